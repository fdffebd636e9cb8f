// What run_scene and merge_shards share (pipeline/pipeline.hpp): how a run is watched and
// stopped, its threads, and everything from its records to its reports.
#pragma once

#include "judge/budget.hpp"
#include "run/run.hpp"
#include "run/workers.hpp"
#include "scene/scene.hpp"
#include "truth/plan.hpp"

#include <csignal>
#include <optional>
#include <ostream>
#include <string>

namespace pldamp::harness {

// SIGINT and SIGTERM while this lives: the handler only records the signal and asks the run to
// stop (run/run.hpp); the previous handlers come back when it ends.
class StopOnSignals {
public:
  StopOnSignals();
  ~StopOnSignals();
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

  // 128 + the signal once one came (the shell's convention: 130 for SIGINT, 143 for SIGTERM).
  std::optional<int> exit_code() const;

private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

// 128 + the signal that stopped the run on another rank (SIGINT's when it is not known).
int stopped_elsewhere_code();

// Progress on `to`: a bar redrawn in place on a terminal; otherwise (a CI log, Python's stderr) a
// line every 5 s with the rate so far and the time left at that rate. None without a stream.
Progress progress_on(std::ostream* to);

// The scene's [limits] max_runs held to every solver run this process starts (run/run.hpp) while
// this lives; the count starts from 0 and no limit is left behind for what runs next in the
// process (the Python module, the tests' in-process runs).
class SolverRunLimit {
public:
  explicit SolverRunLimit(const Scene& scene) : scene_(scene) {
    limit_solver_runs(scene.limits.max_runs);
  }
  ~SolverRunLimit() { limit_solver_runs(0); }
  SolverRunLimit(const SolverRunLimit&) = delete;
  SolverRunLimit& operator=(const SolverRunLimit&) = delete;
  // Once past the limit: an InputError saying so and what the plan counted, `folder` left as it
  // was.
  void refuse_if_passed(const std::string& folder) const;

private:
  const Scene& scene_;
};

// The solves the judging made (claims, searches, time-step study): this process's since
// `before`, or, under MPI, every rank's (each rank calls it once, after the shared work).
long judged_solver_runs(long before, const Workers& workers);

// `jobs`, or every core this process may use: the cores it is bound to (mpirun binds each of a
// few ranks to a core, Slurm a task to its --cpus-per-task), or, unbound, the machine's cores
// shared among the `ranks_on_node`.
int jobs_or_cores(const std::optional<int>& jobs, int ranks_on_node);

// From the records on: budgets, claims, figures, trajectories, the reports in `folder` and the
// summary on `out`. Under MPI (`workers` shared) every rank judges the claims, searches and step
// study with rank 0 (make_budgets, run/workers.hpp); rank 0 alone then goes on, on `jobs`
// threads. Returns the exit code, as run_scene.
int report_records(const Plan& plan, RecordRange records, const RunTotals& totals,
                   const Workers& workers, int jobs, const std::string& folder, bool strict,
                   const StopOnSignals& signals, const SolverRunLimit& limit, std::ostream& out,
                   std::ostream& err);

} // namespace pldamp::harness
