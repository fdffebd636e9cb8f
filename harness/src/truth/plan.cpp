#include "truth/plan.hpp"

#include "truth/reference_solve.hpp"

#include "common/input.hpp"
#include "common/parallel.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

namespace pldamp::harness {
namespace {

using analytic::Contact;
using analytic::ContactEnd;

// The closed forms of the plan's observables at `c`, at every contact end the plan uses.
template <SupportedReal Real>
analytic::Observables<Real> closed_forms(const Contact<Real>& c, const Plan& plan) {
  unsigned want = 0;
  for (const solvers::End end : plan.ends) {
    want |= analytic_want_of(plan.scene.want, end);
  }
  return analytic::observables(c, want);
}

// The plan's observables from the closed forms, in its order; e and tau are e_cap and t_cut under
// the force end.
template <SupportedReal Real>
std::vector<std::optional<Real>> values_of(const analytic::Observables<Real>& closed,
                                           const Plan& plan, solvers::End end) {
  std::vector<std::optional<Real>> out;
  for (const Observable* observable : plan.observables) {
    out.push_back(observable->exact(closed, end));
  }
  return out;
}

double relative(const Exact& value, const Exact& exact) {
  return static_cast<double>(abs((value - exact) / exact));
}

// The analytic layer in double at α against the exact closed forms (AnalyticCheck).
std::vector<AnalyticCheck> check_in_double(const Plan& plan, double p, double alpha,
                                           const analytic::Observables<Exact>& exact) {
  const analytic::Observables<double> in_double =
      closed_forms(Contact<double>::from_alpha(p, alpha, 1.0), plan);
  const Exact smallest(std::numeric_limits<double>::min()),
      largest(std::numeric_limits<double>::max());
  std::vector<AnalyticCheck> checks;
  for (const Observable* observable : plan.observables) {
    AnalyticCheck check;
    check.value = observable->exact(in_double, plan.scene.end);
    const std::optional<Exact> truth = observable->exact(exact, plan.scene.end);
    if (check.value && truth && isfinite(*truth) && *truth != 0) {
      check.representable = abs(*truth) >= smallest && abs(*truth) <= largest;
      if (check.representable) {
        check.error = relative(Exact(*check.value), *truth);
      } else if (plan.scene.end == solvers::End::overlap) {
        const std::optional<double> log_double = observable->exact_log(in_double);
        const std::optional<Exact> log_exact = observable->exact_log(exact);
        if (log_double && log_exact) {
          check.log_error = relative(Exact(*log_double), *log_exact);
        }
      }
    }
    checks.push_back(check);
  }
  return checks;
}

// The closed forms' cost per cell in double: the contact from α and the wanted bundle, timed over
// batches of at least 100 µs, the fastest batch (timing noise only ever adds).
double time_in_double(const Plan& plan, double p, double alpha) {
  using clock = std::chrono::steady_clock;
  double fastest = std::numeric_limits<double>::infinity();
  for (int batch = 0; batch < 3; ++batch) {
    const auto start = clock::now();
    long evaluations = 0;
    do {
      const auto closed = closed_forms(Contact<double>::from_alpha(p, alpha, 1.0), plan);
      asm volatile("" : : "g"(&closed) : "memory"); // keep the work: it has no other use
      ++evaluations;
    } while (clock::now() - start < std::chrono::microseconds(100));
    fastest = std::min(fastest, std::chrono::duration<double>(clock::now() - start).count() /
                                    double(evaluations));
  }
  return fastest;
}

// α as a solver in `precision` receives it, back in Exact.
Exact rounded_alpha(const Exact& alpha, const std::string& precision) {
  Exact rounded = alpha;
  with_precision(precision,
                 [&]<SupportedReal Real>() { rounded = Exact(alpha_as_received<Real>(alpha)); });
  return rounded;
}

// A point whose truth is a reference solve (β ≠ (p − 1)/2; MATH.md §12.2): its α_eff from the
// scene's (given, or the one whose e is the target), every end's observables at v0 = m = k = 1,
// and their error estimate.
Point solved_point(const Plan& plan, const std::set<std::string>& precisions, double p, double beta,
                   const Damping& damping) {
  Point point{p, damping, 0, 0, false, 0, {}, {}, 0, beta, true, {}, {}};
  point.analytic.assign(plan.observables.size(), AnalyticCheck{});
  std::optional<Exact> group = Exact(damping.value);
  if (damping.kind == Damping::Kind::e) {
    group = group_for_e(p, beta, damping.value, plan.scene.end);
  } else if (damping.kind == Damping::Kind::alpha) { // at the scene's one cell (scene.cpp)
    const std::array scales = cell_scales(Exact(p), Exact(plan.scene.v0.front()),
                                          Exact(plan.scene.m.front()), Exact(plan.scene.k.front()));
    group = group_of(p, beta, Exact(damping.value),
                     unit_overlap(p) * scales[std::size_t(Dimension::length)]);
  }
  if (!group) {
    point.no_truth =
        fmt::format("no alpha_eff gives e = {} at p = {}, beta = {}", to_string_full(damping.value),
                    to_string_full(p), to_string_full(beta));
    point.alpha_eff = std::numeric_limits<double>::quiet_NaN();
    point.log_duration = std::numeric_limits<Exact>::infinity();
    for (const solvers::End config_end : plan.ends) {
      for (const std::string& precision : precisions) {
        point.reference[{precision, config_end}].assign(plan.observables.size(), std::nullopt);
      }
    }
    return point;
  }
  point.group = *group;
  point.alpha_eff = static_cast<double>(*group);
  point.alpha = alpha_of(p, beta, *group, unit_overlap(p));
  const solvers::Result<Exact>& overlap = reference_solve(p, beta, *group, solvers::End::overlap);
  point.overdamped = overlap.outcome == solvers::Outcome::no_exit;
  point.log_duration = overlap.tau && isfinite(*overlap.tau)
                           ? log(*overlap.tau)
                           : std::numeric_limits<Exact>::infinity();
  for (const solvers::End config_end : plan.ends) {
    const solvers::Result<Exact>& truth = reference_solve(p, beta, *group, config_end);
    std::vector<std::optional<Exact>> values;
    for (const Observable* observable : plan.observables) {
      values.push_back(solvers::failing(truth.outcome) ? std::nullopt
                                                       : observable->measured(truth));
    }
    if (solvers::failing(truth.outcome)) {
      point.no_truth = "the reference solve " + reference_failure(truth);
    } else if (truth.outcome == solvers::Outcome::no_exit) {
      // With a damping exponent of its own an overdamped overlap can creep back to 0 after the
      // horizon (observables.cpp): its no_exit is no e = 0, τ = ∞ to judge a solver by.
      point.no_truth = fmt::format("the reference solve saw no exit within its horizon ({} "
                                   "delta_u/v0); the contact may still return later",
                                   to_string_full(truth.horizon / unit_overlap(Exact(p))));
      std::fill(values.begin(), values.end(), std::nullopt);
    }
    for (const std::string& precision : precisions) {
      point.reference[{precision, config_end}] = values;
    }
  }
  point.truth_error = truth_error_estimate(plan.observables, p, beta, *group, plan.scene.end);
  return point;
}

} // namespace

std::string alpha_precision(const SolverConfig& config) {
  std::string out;
  with_precision(config.precision, [&]<SupportedReal Real>() {
    const bool wider = std::numeric_limits<Real>::digits > std::numeric_limits<Exact>::digits;
    out = wider ? std::string(precision_name<Exact>()) : config.precision;
  });
  return out;
}

Contact<Exact> seed_contact(const Exact& p, Damping::Kind kind, const Exact& value,
                            ContactEnd end) {
  switch (kind) {
  case Damping::Kind::e:
    return Contact<Exact>::from_e(p, value, Exact(1), Exact(1), Exact(1), end);
  case Damping::Kind::alpha: // α_eff = α/√(2(p + 1)) at this p (MATH.md §3), as --alpha
    return Contact<Exact>::from_alpha(p, value, Exact(1));
  case Damping::Kind::alpha_eff:
    break;
  }
  return Contact<Exact>::from_alpha_eff(p, value, Exact(1));
}

std::vector<SolverConfig> plan_configs(const Scene& scene) {
  std::vector<SolverConfig> configs = scene.configs;
  for (const Claim& claim : scene.claims) {
    const BoundClaim* bound = claim.on_plan();
    if (bound != nullptr &&
        std::find(configs.begin(), configs.end(), bound->config) == configs.end()) {
      configs.push_back(bound->config);
    }
  }
  return configs;
}

Plan make_plan(const Scene& scene, int jobs, const PointMap& map_points) {
  Plan plan;
  plan.scene = scene;
  plan.observables = observables_of(scene.want);
  plan.configs = plan_configs(scene);
  std::set<std::string> precisions;
  std::set<solvers::End> ends{scene.end};
  for (const SolverConfig& config : plan.configs) {
    precisions.insert(alpha_precision(config));
    ends.insert(end_of(scene, config));
  }
  plan.ends.assign(ends.begin(), ends.end());
  const ContactEnd end = scene.end == solvers::End::force ? ContactEnd::force : ContactEnd::overlap;
  std::vector<std::optional<double>> exponents(scene.damping_exponent.begin(),
                                               scene.damping_exponent.end());
  if (exponents.empty()) {
    exponents.push_back(std::nullopt);
  }
  struct PointOf {
    double p;
    std::optional<double> beta;
    Damping damping;
  };
  std::vector<PointOf> wanted;
  for (const double p : scene.p) {
    for (const std::optional<double>& beta : exponents) {
      for (const Damping& damping : scene.damping) {
        wanted.push_back({p, beta, damping});
      }
    }
  }
  // Each point alone (its truths, its closed forms in double), on `jobs` threads, in plan order:
  // a viscoelastic map's float128 reference solves are most of its plan.
  const auto point_at = [&](std::size_t i) -> Point {
    const auto& [p, beta, damping] = wanted[i];
    if (beta && *beta != (p - 1) / 2) {
      return solved_point(plan, precisions, p, *beta, damping);
    }
    Point point{p, damping, 0, 0, false, 0, {}, {}, 0, beta, false, {}, {}};
    const Contact<Exact> calibrated =
        seed_contact(Exact(p), damping.kind, Exact(damping.value), end);
    // α given: the one typed, not its round trip through α_eff
    point.alpha = damping.kind == Damping::Kind::alpha ? Exact(damping.value) : calibrated.alpha();
    point.alpha_eff = static_cast<double>(calibrated.alpha_eff());
    point.overdamped = calibrated.alpha_eff() >= 1;
    point.log_duration = *analytic::observables(calibrated, analytic::want_tau).log_tau;
    // The closed forms at α as each precision receives it; the double one also judges the
    // analytic layer in double.
    const double alpha = static_cast<double>(point.alpha);
    std::optional<analytic::Observables<Exact>> at_double_alpha;
    for (const std::string& precision : precisions) {
      const Exact rounded = rounded_alpha(point.alpha, precision);
      const analytic::Observables<Exact> closed = closed_forms(
          rounded == point.alpha ? calibrated
                                 : Contact<Exact>::from_alpha(Exact(p), rounded, Exact(1)),
          plan);
      for (const solvers::End config_end : plan.ends) {
        point.reference[{precision, config_end}] = values_of(closed, plan, config_end);
      }
      if (rounded == Exact(alpha)) {
        at_double_alpha = closed;
      }
    }
    if (!at_double_alpha) {
      at_double_alpha =
          closed_forms(Contact<Exact>::from_alpha(Exact(p), Exact(alpha), Exact(1)), plan);
    }
    // The analytic layer's own budget and cost: the same point in double against Exact.
    point.analytic = check_in_double(plan, p, alpha, *at_double_alpha);
    point.analytic_seconds = time_in_double(plan, p, alpha);
    return point;
  };
  plan.points = map_points ? map_points(wanted.size(), point_at)
                           : map_indices<Point>(wanted.size(), jobs, point_at);
  if (plan.points.size() != wanted.size()) {
    throw InternalError("a point map returned " + std::to_string(plan.points.size()) + " of " +
                        std::to_string(wanted.size()) + " points");
  }
  // Each point's cells (their Exact scales: 7 s on one thread for a 2·10^6-cell map), on `jobs`
  // threads, in plan order.
  const std::vector<CellScale> scales_wanted = scene_scales(scene);
  plan.cells.resize(plan.points.size() * scales_wanted.size());
  for_each_index(plan.points.size(), jobs, [&](std::size_t i) {
    const Point& point = plan.points[i];
    for (std::size_t j = 0; j < scales_wanted.size(); ++j) {
      const auto [v0, m, k] = scales_wanted[j];
      const std::array<Exact, 5> scales =
          cell_scales(Exact(point.p), Exact(v0), Exact(m), Exact(k));
      // MATH.md §12.1: the same α_eff at this cell's δ_u = unit δ_u × length.
      const Exact alpha =
          point.solved ? alpha_of(point.p, *point.beta, point.group,
                                  unit_overlap(point.p) * scales[std::size_t(Dimension::length)])
                       : point.alpha;
      plan.cells[i * scales_wanted.size() + j] = {i, v0, m, k, alpha, scales};
    }
  });
  return plan;
}

std::optional<Exact> reference_at(const Plan& plan, const Cell& cell, std::size_t observable,
                                  const SolverConfig& config) {
  const std::optional<Exact>& unit = plan.points[cell.point].reference.at(
      {alpha_precision(config), end_of(plan.scene, config)})[observable];
  if (!unit) {
    return std::nullopt;
  }
  return *unit * cell.scale(plan.observables[observable]->dimension);
}

} // namespace pldamp::harness
