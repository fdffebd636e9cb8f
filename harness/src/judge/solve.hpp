// One solver run outside a plan, for the figures and the claims judged on grids of their own
// (judge/figures.hpp, judge/claims.hpp): double precision, the configuration's tolerances, the
// scene's limits; a run whose outcome carries no answer throws with what happened.
#pragma once

#include "scene/scene.hpp"

#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

// What to solve: p, α, v0, m, k (the physical parameters of solvers::Problem).
struct Inputs {
  double p, alpha, v0 = 1, m = 1, k = 1;
};

// Solves once, whatever the outcome. A fixed step, when given, replaces the configuration's steps
// per contact; the contact begins at `onset_phase` of a step (fixed-step solvers).
solvers::Result<double> solve_unchecked(const SolverConfig& config, const Inputs& in, unsigned want,
                                        const Limits& limits, std::vector<double> sample_times = {},
                                        std::optional<double> fixed_step = std::nullopt,
                                        double onset_phase = 0);

// Solves once; throws std::runtime_error on step_limit, time_limit or unstable.
solvers::Result<double> solve_once(const SolverConfig& config, const Inputs& in, unsigned want,
                                   const Limits& limits, std::vector<double> sample_times = {});

// One value of a run (e.g. &Result::tau); a run that ended without it (no exit where τ was
// wanted) throws, naming it.
double solved_value(const SolverConfig& config, const Inputs& in, unsigned want,
                    std::optional<double> solvers::Result<double>::*value, const char* name,
                    const Limits& limits);

// The largest Δt at which a fixed-step scheme's contact ends with no energy gained (e <= 1) at
// every onset phase (the supremum of e over the phases, run/phase_supremum.hpp, from 8 sampled):
// scanned up from τ/1000 by factors 1.5 to 50 τ, then bisected twelve times (to 1.5^(1/4096)).
// Used by the stability claim and `pldamp timestep`.
struct StableStep {
  double dt = 0;      // 0: unstable even at τ/1000
  bool below = false; // still stable at 50 τ: dt is a lower bound
  std::string limit;  // a budget spent on the way ("step_limit at dt = ..."): no verdict
};
StableStep largest_stable_dt(const SolverConfig& config, const Inputs& in, const Limits& limits,
                             double tau);

// α for which the solver returns with restitution e: TOMS 748 on α ↦ e_solver(α) − e over
// [0, α at α_eff = 1), where e falls from 1 to 0 (the seed's "bisection on the ODE solver").
// `in.alpha` is ignored.
double alpha_by_bisection(const SolverConfig& config, Inputs in, double e, const Limits& limits);

} // namespace pldamp::harness
