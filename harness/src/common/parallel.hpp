// Independent pieces of work on `jobs` threads (the grid's records, the claims' cells, the
// searches' groups, the step study's points), each result in its own slot by index: the thread
// count changes when a piece runs, never what it computes or where its result lands, so a report
// does not depend on --jobs (docs/design.md §3). One job runs everything on the calling thread in
// index order, which nested work (a search's trials inside a parallel step study) uses.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

#include <sched.h>

namespace pldamp::harness {

// The threads a run uses unless told (--jobs): every core this process may run on (its CPU
// affinity: mpirun binds a rank to its cores, Slurm a task to its allocation).
inline int all_cores() {
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0 && CPU_COUNT(&allowed) > 0) {
    return CPU_COUNT(&allowed);
  }
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// body(i) for every i in [0, count), on up to `jobs` threads (the caller's among them; fewer when
// the system gives no more, as under `ulimit -v` with many jobs: it aborted the process). An
// exception ends no other piece; the first by index is rethrown once all have ended, as a serial
// loop would have thrown it.
template <class Body>
void for_each_index(std::size_t count, int jobs, Body&& body) {
  std::vector<std::exception_ptr> thrown(count);
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        body(i);
      } catch (...) {
        thrown[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> workers;
  const std::size_t threads =
      std::min<std::size_t>(count, static_cast<std::size_t>(std::max(jobs, 1)));
  for (std::size_t j = 1; j < threads; ++j) {
    try {
      workers.emplace_back(work);
    } catch (const std::system_error&) { // no thread to be had (a process or memory limit): the
      break;                             // threads started and the caller's do the work
    }
  }
  work();
  for (std::thread& worker : workers) {
    worker.join();
  }
  for (const std::exception_ptr& e : thrown) {
    if (e) {
      std::rethrow_exception(e);
    }
  }
}

// f(i) for every i in [0, count), in index order (for_each_index); T default-constructible.
template <class T, class F>
std::vector<T> map_indices(std::size_t count, int jobs, F&& f) {
  std::vector<T> out(count);
  for_each_index(count, jobs, [&](std::size_t i) { out[i] = f(i); });
  return out;
}

} // namespace pldamp::harness
