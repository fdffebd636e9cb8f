// What every thread of a run shares to be stopped (run/run.hpp): the stop request a signal or the
// solver-run limit raises, the signal that raised it, and the count of solver runs started.
#include "run/run.hpp"

#include <atomic>

namespace pldamp::harness {

std::atomic<bool>& stop_requested() {
  static std::atomic<bool> stop{false};
  static_assert(std::atomic<bool>::is_always_lock_free);
  return stop;
}

std::atomic<int>& stop_signal() {
  static std::atomic<int> signal{0};
  static_assert(std::atomic<int>::is_always_lock_free);
  return signal;
}

namespace {
std::atomic<long> solver_runs_started{0};
std::atomic<long> solver_run_limit{0};
std::atomic<bool> solver_run_limit_passed{false};
} // namespace

void count_solver_runs(long runs) {
  const long made = solver_runs_started.fetch_add(runs) + runs;
  const long most = solver_run_limit.load();
  if (most > 0 && made > most && !solver_run_limit_passed.exchange(true)) {
    stop_requested() = true;
  }
}

long solver_runs_made() {
  return solver_runs_started.load();
}

void limit_solver_runs(long most) {
  solver_runs_started = 0;
  solver_run_limit = most;
  solver_run_limit_passed = false;
}

bool solver_run_limit_reached() {
  return solver_run_limit_passed.load();
}

} // namespace pldamp::harness
