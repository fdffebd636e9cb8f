// The time-step study: what a DEM user can quote about a fixed-step scheme. For every sweep of a
// fixed-step configuration over steps per contact (the configurations sharing a
// SolverConfig::line), per p: the worst error of e, δ_max and τ over the grid's cells (and their
// onset phases) against Δt/τ, the observed order in e, and the steps per contact τ/Δt needed for
// e within 1 %, 0.1 % and 0.01 %, worst over the cells and onset phases (log-log interpolation
// between the sweep's points). τ is each cell's true contact duration under the configuration's
// end rule (t_cut when capped), so the study needs τ among the scene's observables.
#pragma once

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

// The steps per contact (τ/Δt) needed for a target, worst over cells.
struct StepsNeeded {
  std::optional<double> steps; // none: not reached in the sweep
  bool within_sweep = true;    // false: reached already at the coarsest step (an upper bound)
};

struct StepSweep {
  std::string line;                 // the configurations' common label
  std::vector<std::size_t> configs; // coarse to fine
  // points[o][p][k]: observable o (its index in Plan::observables), p index, configuration k.
  std::vector<std::vector<std::vector<StepPoint>>> points;
  std::vector<std::optional<double>> order;       // per p: observed order in e
  std::vector<std::array<StepsNeeded, 3>> needed; // per p, per step_targets
};

struct StepStudy {
  std::vector<StepSweep> sweeps;
  std::size_t e = 0; // the index of e in Plan::observables
  // The undamped contact duration's share of the critical steps, per p (MATH.md §6): the seed's
  // Δt_crit/τ0 and the tangent-stiffness bound's.
  std::vector<double> dt_crit_over_tau0, dt_tangent_over_tau0;
};

// Empty (no sweeps) when the plan has no fixed-step sweep or does not compare τ.
StepStudy make_step_study(const Plan& plan, const std::vector<Record>& records);

} // namespace pldamp::harness
