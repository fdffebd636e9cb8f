// Running a plan: every (cell, configuration) solved once for its values, `repeats` times for its
// wall time (the minimum), on `jobs` threads; a fixed-step scheme's contacts in batches (its
// onset phases, the cells of one configuration). Results land in plan order whatever the threads
// and the batches do, so reports are deterministic (except times).
#pragma once

#include "run/workers.hpp"
#include "truth/plan.hpp"

#include <algorithm>
#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

struct Record {
  std::size_t cell = 0, config = 0;
  std::optional<solvers::Outcome> outcome; // none: the solver threw
  // Why the record failed beyond its outcome: the solver's message when it threw, the invariant
  // an unstable answer broke, or a no_exit where the truth returns before the solver's horizon.
  std::string failure;
  long steps = 0, rhs_evals = 0; // per collision (the mean over onset phases)
  // Per collision, the mean over onset phases of the fastest of the repeats (what a report
  // compares: the least disturbed by other load) and of the slowest (its spread).
  double wall_seconds = 0, wall_seconds_slowest = 0;
  // The same of the solving thread's CPU time (CLOCK_THREAD_CPUTIME_ID), which other processes
  // on the machine disturb far less: the time `pldamp diff` judges. None for an external solver
  // (its work is done in its own process: its wall time is what it reports).
  std::optional<double> cpu_seconds, cpu_seconds_slowest;
  // α exactly as the solver received it (alpha_as_received, truth/plan.hpp): as a double, which is
  // what a double solver and an external program get, and in full digits where the configuration
  // runs wider than double (empty otherwise).
  double alpha = 0;
  std::string alpha_digits;
  int phases = 1;           // onset phases run (fixed-step configurations)
  long runs = 0;            // solver runs made, onset phases and repeats included
  std::optional<double> dt; // the fixed step a fixed-step run used
  // Per observable (Plan::observables): the value and the reference (rounded to double for the
  // report), the signed error value − reference and its absolute and relative size, computed in
  // Exact (the signed error tells an overshoot from an undershoot). The relative error
  // of a reference 0 (e of a contact that never returns) is the absolute one; of an infinite
  // reference (its τ) 0 when the value is infinite too. A solver's no_exit where the contact does
  // return (just below critical damping) leaves τ unresolved and compares e absolutely.
  // Over several onset phases: the phase with the largest relative error, and the spread of the
  // values over the phases relative to the reference.
  std::vector<std::optional<double>> value, reference, error, abs_error, rel_error, spread;
  // Per observable, the onset phase (a fraction of a step, k/n) whose error is the one kept.
  std::vector<std::optional<double>> worst_phase;
  // An external solver's record it does not run (docs/external.md "Your code in the loop"): why.
  // Such a record is neither failed nor counted in budgets and costs.
  std::string skip_reason;
  // How the truth of an external solver whose dashpot is not the point's was found (the
  // reference solve of its own β, MATH.md §12.2), or why it has none.
  std::string note;
  // An external solver with a replica ([[solver]] replica): per observable, the largest over the
  // onset phases of |value − replica's value| / |replica's value| (absolute where that is 0).
  std::vector<std::optional<double>> replica_difference;
  bool skipped() const { return !skip_reason.empty(); }
  // Failed: the solver threw, ran out of its budget (step_limit, time_limit), gave an impossible
  // answer (unstable), gave up before a return the truth has in its horizon, or returned a
  // non-finite error.
  bool failed() const;
  // The outcome's name, or "error" when the solver threw.
  std::string_view outcome_name() const;
};

// The times (wall or CPU) of a solve's repeats: the fastest is the one reported (timing noise only
// ever adds), the slowest shows how noisy the machine was.
struct RepeatTimes {
  double fastest = std::numeric_limits<double>::infinity(), slowest = 0;
  void add(double seconds) {
    fastest = std::min(fastest, seconds);
    slowest = std::max(slowest, seconds);
  }
};

struct RunTotals {
  long rhs_evals = 0;   // over one run of each collision (repeats time only)
  long solver_runs = 0; // repeats included
  double wall_seconds = 0;
  // Per configuration: what an external solver said of itself in its handshake
  // (ExternalFacts::describe); empty for pldamp's own solvers.
  std::vector<std::string> external;
};

using Progress = std::function<void(std::size_t done, std::size_t total)>;

// A request to stop the run (a signal handler sets it, lock-free): workers take no new record and
// the solves in flight end within 256 steps, as time_limit. Whoever installs the handler clears
// it first (pipeline/watch.cpp: StopOnSignals).
std::atomic<bool>& stop_requested();
// The signal that asked for the stop, here or on another rank (0: none known): a run stopped by
// SIGTERM on any rank exits 143 on every rank, by SIGINT 130 (distribution.cpp passes it on).
std::atomic<int>& stop_signal();

// Every solver run this process starts (the grid's, its repeats, the onset-phase refinement, and
// the claims', searches' and time-step study's solves), counted as it starts; and the most it may
// start (`[limits] max_runs`, --max-runs): one past it asks the run to stop (stop_requested) and
// solver_run_limit_reached() says why. The plan's estimate is held to the limit before anything
// is built (judge/plan_size.hpp); this holds the guard whatever the estimate says.
void count_solver_runs(long runs);
long solver_runs_made();
// Starts counting again from 0, with `most` the limit (0: none).
void limit_solver_runs(long most);
bool solver_run_limit_reached();

// The lanes of one batch (solvers::solve_batch) when a fixed-step configuration's records are
// solved together: 16 contacts (docs/performance.md, "Batch mode", the cells of a scene).
inline constexpr std::size_t default_batch_lanes = 16;

// Runs every record of the plan (an external solver runs each phase once, whatever the repeats:
// its wall time is what it reports); `progress` (if set) is called from the workers, serialised,
// once per record. The records of pldamp's fixed-step schemes in double are solved in batches of
// up to `batch_lanes` contacts of one configuration, p and β (their onset phases, several cells):
// the same records bit for bit as one at a time (batch_lanes = 1), but for their times.
// Throws ProtocolError (run/external.hpp) before any record when an external solver cannot be
// started or speaks another protocol.
// Shared among MPI ranks when `workers` are (run/workers.hpp): rank r solves every N-th cell from
// r, and every rank returns every record.
std::vector<Record> run_plan(const Plan& plan, const Workers& workers, RunTotals& totals,
                             const Progress& progress = {},
                             std::size_t batch_lanes = default_batch_lanes);

// run_plan in parts, for a process that solves only some of a plan's cells (a shard of a job
// array, an MPI rank's share): the external programs are started once, then any cells' records
// are solved, with the same values as run_plan gives them.
class PlanRunner {
public:
  // Starts every external program and reads its handshake: ProtocolError (run/external.hpp)
  // before any record when one cannot be started or speaks another protocol.
  PlanRunner(const Plan& plan, int jobs, std::size_t batch_lanes = default_batch_lanes);
  ~PlanRunner();
  PlanRunner(const PlanRunner&) = delete;
  PlanRunner& operator=(const PlanRunner&) = delete;

  // The records of `cells`, each cell's configurations in order (run_plan's order for all cells);
  // `progress` counts them.
  std::vector<Record> run_cells(std::span<const std::size_t> cells, const Progress& progress = {});
  // Per configuration: what its external program said of itself (RunTotals::external).
  const std::vector<std::string>& external() const { return external_; }

private:
  struct Programs;
  const Plan& plan_;
  int jobs_;
  std::size_t batch_lanes_;
  std::unique_ptr<Programs> programs_;
  std::vector<std::string> external_;
};

} // namespace pldamp::harness
