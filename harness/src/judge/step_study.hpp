// The time-step study: what a DEM user can quote about a fixed-step scheme. For every sweep of a
// fixed-step configuration over steps per contact (the configurations sharing a
// SolverConfig::line), per p: the worst error of e, δ_max and τ over the grid's cells (and their
// onset phases) against Δt/τ, and the observed order in e; and, per (p, damping) point, the steps
// per contact needed for e within 1 %, 0.1 % and 0.01 %.
//
// One name per quantity: steps per contact is always (π δ_u/v0) ÷ Δt, the parameter a scene and
// `solve --steps-per-contact` set (δ_u the undamped peak overlap); the true contact duration per
// step, τ ÷ Δt, is called tau_over_dt (τ under the configuration's end rule: t_cut when capped).
//
// The steps needed are the answers of [[search]]'s engine (judge/search.hpp) over the sweep's
// range, one search per point, each trial the worst over every onset phase (sought from 8): the
// same question asked as a [[search]] gets the same answer. An external program is not searched
// (each run can cost milliseconds): its answer is read off its sweep, the coarsest sweep value from
// which every finer one holds (an upper bound, `from_sweep`).
#pragma once

#include "run/record_store.hpp"
#include "run/run.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

inline constexpr std::array<double, 3> step_targets{1e-2, 1e-3, 1e-4};

// A point of a sweep at one p: the mean Δt/τ over the cells and the worst relative error.
struct StepPoint {
  double dt_over_tau = 0;
  std::optional<double> error;
  std::optional<double> spread; // the largest spread over onset phases (several phases run)
};

// The steps per contact needed for a target.
struct StepsNeeded {
  std::optional<double> steps; // none: not reached at the sweep's finest step
  bool within_sweep = true;    // false: held at the coarsest step already (an upper bound)
  bool from_sweep = false;     // read off the sweep's points (external programs): an upper bound
  std::optional<double> tau_over_dt; // τ/Δt at those steps (per point; none for a worst)
  bool returns = true; // false: the point does not return (overdamped) or has no truth: no answer
};

struct StepSweep {
  std::string line;                 // the configurations' common label
  std::vector<std::size_t> configs; // coarse to fine
  // points[o][p][k]: observable o (its index in Plan::observables), p index, configuration k.
  std::vector<std::vector<std::vector<StepPoint>>> points;
  std::vector<std::optional<double>> order;       // per p: observed order in e
  std::vector<std::array<StepsNeeded, 3>> needed; // per p, per step_targets: worst over points
  // by_point[point index of the plan][target]: each (p, damping) point's own answer.
  std::vector<std::array<StepsNeeded, 3>> by_point;
  int onset_phases = 0; // the phases the searches took their worst over (0: from the sweep)
  long solver_runs = 0; // the searches' solves
};

struct StepStudy {
  std::vector<StepSweep> sweeps;
  std::size_t e = 0; // the index of e in Plan::observables
  // The undamped contact duration's share of the critical steps, per p (MATH.md §6): the seed's
  // Δt_crit/τ0 and the tangent-stiffness bound's.
  std::vector<double> dt_crit_over_tau0, dt_tangent_over_tau0;
};

// Empty (no sweeps) when the plan has no fixed-step sweep or does not compare e and τ. The
// searches run on the workers' threads, shared among their ranks (run/workers.hpp). Under MPI
// every rank calls it, rank 0 with the run's records: the others' study, made without them, is
// not the run's (the sweeps' points, an external program's answers) and is not reported.
StepStudy make_step_study(const Plan& plan, RecordRange records, const Workers& workers);

// The solver runs the study's searches are estimated to cost (the plan's size).
double step_study_runs_estimate(const Scene& scene);

} // namespace pldamp::harness
