#include "judge/solve.hpp"

#include "common/input.hpp"
#include "run/phase_supremum.hpp"
#include "run/run.hpp"

#include "pldamp/analytic/contact.hpp"
#include "pldamp/solvers/registry.hpp"

#include <boost/math/tools/toms748_solve.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <limits>
#include <stdexcept>

namespace pldamp::harness {
namespace {

std::string where(const Inputs& in) {
  return " at p = " + to_string_full(in.p) + ", alpha = " + to_string_full(in.alpha) +
         (in.v0 != 1 ? ", v0 = " + to_string_full(in.v0) : "") +
         (in.m != 1 ? ", m = " + to_string_full(in.m) : "") +
         (in.k != 1 ? ", k = " + to_string_full(in.k) : "");
}

} // namespace

solvers::Result<double> solve_unchecked(const SolverConfig& config, const Inputs& in, unsigned want,
                                        const Limits& limits, std::vector<double> sample_times,
                                        std::optional<double> fixed_step, double onset_phase) {
  solvers::Options<double> options;
  options.rtol =
      config.rtol.value_or(solvers::solver_named(config.name).template default_rtol<double>());
  options.atol = config.atol;
  options.want = want;
  options.max_steps = limits.max_steps;
  options.max_seconds = limits.max_seconds;
  options.stop = &stop_requested(); // a signal ends these solves too (pipeline/watch.cpp)
  options.fixed_step = fixed_step;
  options.onset_phase = onset_phase;
  if (config.steps_per_contact && !fixed_step) {
    options.steps_per_contact = *config.steps_per_contact;
  }
  options.sample_times = std::move(sample_times);
  count_solver_runs(1); // a claim's solves count toward the run's (run/run.hpp)
  return solvers::solve(config.name, solvers::Problem<double>{in.p, in.m, in.k, in.v0, in.alpha},
                        options);
}

solvers::Result<double> solve_once(const SolverConfig& config, const Inputs& in, unsigned want,
                                   const Limits& limits, std::vector<double> sample_times) {
  const solvers::Result<double> r =
      solve_unchecked(config, in, want, limits, std::move(sample_times));
  if (solvers::failing(r.outcome)) {
    throw std::runtime_error(config.label() + " ended as " +
                             std::string(solvers::outcome_name(r.outcome)) + where(in));
  }
  return r;
}

double solved_value(const SolverConfig& config, const Inputs& in, unsigned want,
                    std::optional<double> solvers::Result<double>::*value, const char* name,
                    const Limits& limits) {
  const solvers::Result<double> r = solve_once(config, in, want, limits);
  if (!(r.*value)) {
    throw std::runtime_error(config.label() + " gave no " + name + where(in) + " (" +
                             std::string(solvers::outcome_name(r.outcome)) + ")");
  }
  return *(r.*value);
}

double alpha_by_bisection(const SolverConfig& config, Inputs in, double e, const Limits& limits) {
  const double critical = analytic::Contact<double>::from_alpha_eff(in.p, 1.0, 1.0).alpha();
  auto gap = [&](double alpha) {
    in.alpha = alpha;
    return solved_value(config, in, solvers::want_e, &solvers::Result<double>::e, "e", limits) - e;
  };
  std::uintmax_t iterations = 100;
  const auto [lo, hi] =
      boost::math::tools::toms748_solve(gap, 0.0, critical * (1 - 1e-9), 1 - e, -e,
                                        boost::math::tools::eps_tolerance<double>(40), iterations);
  return lo + (hi - lo) / 2;
}

StableStep largest_stable_dt(const SolverConfig& config, const Inputs& in, const Limits& limits,
                             double tau) {
  StableStep found;
  // Stable: the contact ends, with no energy gained, from every onset phase. A budget spent is no
  // verdict at all.
  auto stable = [&](double dt) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    auto evaluate = [&](double phase) {
      const solvers::Result<double> r =
          solve_unchecked(config, in, solvers::want_e, limits, {}, dt, phase);
      if (r.outcome == solvers::Outcome::step_limit || r.outcome == solvers::Outcome::time_limit) {
        found.limit = fmt::format("{} at dt = {:.4g}, onset phase {:.17g}",
                                  solvers::outcome_name(r.outcome), dt, phase);
      }
      const bool returned = r.outcome == solvers::Outcome::exited && r.e;
      return PhasePoint{
          .phase = phase, .piece = piece_of(r, phase), .scores = {returned ? *r.e : inf}};
    };
    std::vector<PhasePoint> points;
    for (const double phase : sampled_phases(8)) {
      points.push_back(evaluate(phase));
      if (!(points.back().scores.front() <= 1)) {
        return false;
      }
    }
    // Sought no further than an e above 1; a worst not resolved within the budget is no verdict.
    if (!refine_to_supremum(points, evaluate, 4000, 1.0)) {
      found.limit = fmt::format("the worst onset phase not resolved at dt = {:.4g}", dt);
      return false;
    }
    return std::all_of(points.begin(), points.end(),
                       [](const PhasePoint& p) { return p.scores.front() <= 1; });
  };
  double lo = tau / 1000, hi = lo;
  if (!stable(lo)) {
    lo = 0;
  } else {
    while (hi < 50 * tau && stable(hi)) {
      lo = hi;
      hi *= 1.5;
    }
    if (hi < 50 * tau) {
      for (int i = 0; i < 12; ++i) {
        const double mid = std::sqrt(lo * hi);
        (stable(mid) ? lo : hi) = mid;
      }
    } else {
      found.below = true;
    }
  }
  found.dt = lo;
  return found;
}

} // namespace pldamp::harness
