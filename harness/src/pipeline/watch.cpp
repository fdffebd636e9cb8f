// How a run is watched and stopped (pipeline/parts.hpp): its progress, its signals, its threads.
#include "common/input.hpp"
#include "common/parallel.hpp"
#include "judge/plan_size.hpp"
#include "pipeline/parts.hpp"
#include "pipeline/pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <thread>

#include <unistd.h>

namespace pldamp::harness {

std::string time_left_text(double elapsed_seconds, std::size_t done, std::size_t total) {
  if (done < 16 || done * 100 < total) {
    return "time left not known yet";
  }
  return fmt::format("about {:.0f} s left", elapsed_seconds / double(done) * double(total - done));
}

namespace {

// Progress on stderr: a bar redrawn in place on a terminal; otherwise (a CI log) a line every
// 5 s with the rate so far and the time left at that rate.
class ProgressLines {
public:
  ProgressLines(std::ostream& to, bool terminal) : to_(&to), terminal_(terminal) {}

  void operator()(std::size_t done, std::size_t total) {
    if (terminal_) {
      constexpr int width = 40;
      const int filled = static_cast<int>(width * done / total);
      *to_ << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
           << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << done << "/"
           << total << ", " << left(done, total) << "  " << (done == total ? "\n" : "")
           << std::flush;
      return;
    }
    const double elapsed = seconds_since(start_);
    if (elapsed - last_ < (last_ == 0 ? 1 : 5) || done == total) {
      return;
    }
    last_ = elapsed;
    *to_ << fmt::format("{:.0f} s: {}/{} records, {}\n", elapsed, done, total, left(done, total))
         << std::flush;
  }

private:
  std::string left(std::size_t done, std::size_t total) const {
    return time_left_text(seconds_since(start_), done, total);
  }
  static double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }
  std::ostream* to_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double last_ = 0;
};

// SIGINT and SIGTERM: the handler only records the signal and asks the run to stop.
std::atomic<int> caught_signal{0};

extern "C" void on_stop_signal(int signal) {
  caught_signal.store(signal);
  stop_signal().store(signal);
  stop_requested().store(true);
}

} // namespace

int stopped_elsewhere_code() {
  const int signal = stop_signal().load();
  return 128 + (signal > 0 ? signal : SIGINT);
}

StopOnSignals::StopOnSignals() {
  caught_signal = 0;
  stop_signal() = 0;
  stop_requested() = false;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous_int_);
  sigaction(SIGTERM, &action, &previous_term_);
}

StopOnSignals::~StopOnSignals() {
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
}

std::optional<int> StopOnSignals::exit_code() const {
  const int signal = caught_signal.load();
  return signal != 0 ? std::optional<int>(128 + signal) : std::nullopt;
}

void SolverRunLimit::refuse_if_passed(const std::string& folder) const {
  if (solver_run_limit_reached()) {
    throw InputError(fmt::format(
        "the run started more than {} solver runs, its limit ([limits] max_runs, --max-runs), "
        "where the plan counted about {:.0f}: stopped, no report written, {} left as it was; "
        "raise the limit or shrink the scene",
        scene_.limits.max_runs, planned_runs(scene_), one_line(folder)));
  }
}

long judged_solver_runs(long before, const Workers& workers) {
  const long mine = solver_runs_made() - before;
  if (!workers.shared()) {
    return mine;
  }
  long all = 0;
  for (const std::string& rank : workers.ranks->all_gather(std::to_string(mine))) {
    all += std::stol(rank);
  }
  return all;
}

Progress progress_on(std::ostream* to) {
  if (to == nullptr) {
    return [](std::size_t, std::size_t) {};
  }
  return Progress{ProgressLines(*to, to == &std::cerr && isatty(STDERR_FILENO) == 1)};
}

int jobs_or_cores(const std::optional<int>& jobs, int ranks_on_node) {
  if (jobs) {
    return *jobs;
  }
  const int cores = all_cores();
  if (cores >= static_cast<int>(std::thread::hardware_concurrency())) {
    return std::min(1024, std::max(1, cores / std::max(ranks_on_node, 1)));
  }
  return std::min(1024, cores);
}

} // namespace pldamp::harness
