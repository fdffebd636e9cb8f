#include "truth/plan.hpp"

#include "pldamp/analytic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace pldamp::harness {
namespace {

using analytic::Contact;
using analytic::ContactEnd;

// The observables of `c` in the plan's order; e and tau are e_cap and t_cut under the force end.
template <SupportedReal Real>
std::vector<std::optional<Real>> observe(const Contact<Real>& c, const Plan& plan) {
  const solvers::End end = plan.scene.end;
  const analytic::Observables<Real> closed =
      analytic::observables(c, analytic_want_of(plan.scene.want, end));
  std::vector<std::optional<Real>> out;
  for (const Observable* observable : plan.observables) {
    out.push_back(observable->exact(closed, end));
  }
  return out;
}

template <SupportedReal Real>
Contact<Real> contact_of(const Point& point, ContactEnd end) {
  const Real p(point.p);
  return point.damping.kind == Damping::Kind::e
             ? Contact<Real>::from_e(p, Real(point.damping.value), Real(1), Real(1), Real(1), end)
             : Contact<Real>::from_alpha_eff(p, Real(point.damping.value), Real(1));
}

// α as a solver in `precision` receives it, back in Exact.
Exact rounded_alpha(const Exact& alpha, const std::string& precision) {
  Exact rounded = alpha;
  with_precision(precision,
                 [&]<SupportedReal Real>() { rounded = Exact(static_cast<Real>(alpha)); });
  return rounded;
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

Plan make_plan(const Scene& scene) {
  Plan plan;
  plan.scene = scene;
  plan.observables = observables_of(scene.want);
  plan.configs = scene.configs;
  for (const Claim& claim : scene.claims) {
    if (std::find(plan.configs.begin(), plan.configs.end(), claim.config) == plan.configs.end()) {
      plan.configs.push_back(claim.config);
    }
  }
  std::set<std::string> precisions;
  for (const SolverConfig& config : plan.configs) {
    precisions.insert(alpha_precision(config));
  }
  const ContactEnd end = scene.end == solvers::End::force ? ContactEnd::force : ContactEnd::overlap;
  for (const double p : scene.p) {
    for (const Damping& damping : scene.damping) {
      Point point{p, damping, 0, 0, false, {}, {}, {}};
      const Contact<Exact> calibrated = contact_of<Exact>(point, end);
      point.alpha = calibrated.alpha();
      point.alpha_eff = static_cast<double>(calibrated.alpha_eff());
      point.overdamped = calibrated.alpha_eff() >= 1;
      for (const std::string& precision : precisions) {
        const Exact alpha = rounded_alpha(point.alpha, precision);
        point.reference[precision] =
            alpha == point.alpha
                ? observe(calibrated, plan)
                : observe(Contact<Exact>::from_alpha(Exact(p), alpha, Exact(1)), plan);
      }
      // The analytic layer's own budget: the same point in double against Exact.
      const std::vector<std::optional<Exact>>& exact = point.reference.count("double")
                                                           ? point.reference.at("double")
                                                           : observe(calibrated, plan);
      const auto in_double =
          observe(Contact<double>::from_alpha(p, static_cast<double>(point.alpha), 1.0), plan);
      for (std::size_t i = 0; i < in_double.size(); ++i) {
        point.analytic_double.push_back(in_double[i]);
        std::optional<double> error;
        if (in_double[i] && exact[i] && isfinite(*exact[i]) && *exact[i] != 0) {
          error = static_cast<double>(abs((Exact(*in_double[i]) - *exact[i]) / *exact[i]));
        }
        point.analytic_error.push_back(error);
      }
      plan.points.push_back(std::move(point));
    }
  }
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    for (const double v0 : scene.v0) {
      for (const double m : scene.m) {
        for (const double k : scene.k) {
          const Exact length =
              exp(log(Exact(m) * Exact(v0) * Exact(v0) / Exact(k)) / (Exact(plan.points[i].p) + 1));
          plan.cells.push_back(
              {i, v0, m, k, {Exact(1), length, length / Exact(v0), Exact(m) * v0 * v0}});
        }
      }
    }
  }
  return plan;
}

std::optional<Exact> reference_at(const Plan& plan, const Cell& cell, std::size_t observable,
                                  const std::string& alpha_precision) {
  const std::optional<Exact>& unit =
      plan.points[cell.point].reference.at(alpha_precision)[observable];
  if (!unit) {
    return std::nullopt;
  }
  return *unit * cell.scale(plan.observables[observable]->dimension);
}

} // namespace pldamp::harness
