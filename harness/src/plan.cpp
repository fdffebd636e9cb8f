#include "plan.hpp"

#include "pldamp/analytic.hpp"

#include <cmath>
#include <set>

namespace pldamp::harness {
namespace {

using analytic::Contact;
using analytic::ContactEnd;

// The analytic Want bits behind the scene's observables.
unsigned analytic_want(const Scene& scene) {
  const bool capped = scene.end == solvers::End::force;
  unsigned want = 0;
  if (scene.want & solvers::want_e) {
    want |= capped ? analytic::want_capped : analytic::want_e;
  }
  if (scene.want & solvers::want_delta_max) {
    want |= analytic::want_delta_max;
  }
  if (scene.want & solvers::want_t_peak) {
    want |= analytic::want_t_peak;
  }
  if (scene.want & solvers::want_tau) {
    want |= capped ? analytic::want_capped : analytic::want_tau;
  }
  if (scene.want & solvers::want_energy) {
    want |= analytic::want_energy;
  }
  return want;
}

// The observables of `c` in the plan's order; e and tau are e_cap and t_cut under the force end.
template <SupportedReal Real>
std::vector<std::optional<Real>> observe(const Contact<Real>& c, const Plan& plan) {
  const bool capped = plan.scene.end == solvers::End::force;
  const analytic::Observables<Real> x = analytic::observables(c, analytic_want(plan.scene));
  std::vector<std::optional<Real>> out;
  for (const std::string& name : plan.observables) {
    if (name == "e") {
      out.push_back(capped ? x.e_cap : x.e);
    } else if (name == "delta_max") {
      out.push_back(x.delta_max);
    } else if (name == "t_peak") {
      out.push_back(x.t_peak);
    } else if (name == "tau") {
      out.push_back(capped ? x.t_cut : x.tau);
    } else if (name == "energy_load") {
      out.push_back(x.energy_load);
    } else { // energy_unload: the analytic layer splits the energy of the full contact only
      out.push_back(capped ? std::nullopt : x.energy_unload);
    }
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

quad rounded_alpha(const quad& alpha, const std::string& precision) {
  if (precision == "double") {
    return quad(static_cast<double>(alpha));
  }
  if (precision == "long") {
    return quad(static_cast<long double>(alpha));
  }
  return alpha;
}

} // namespace

std::string alpha_precision(const SolverConfig& config) {
  return config.precision == "50" ? "quad" : config.precision;
}

Plan make_plan(const Scene& scene) {
  Plan plan;
  plan.scene = scene;
  plan.observables = observable_names(scene.want);
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
      const Contact<quad> calibrated = contact_of<quad>(point, end);
      point.alpha = calibrated.alpha();
      point.alpha_eff = static_cast<double>(calibrated.alpha_eff());
      point.overdamped = calibrated.alpha_eff() >= 1;
      for (const std::string& precision : precisions) {
        const quad alpha = rounded_alpha(point.alpha, precision);
        point.reference[precision] =
            alpha == point.alpha
                ? observe(calibrated, plan)
                : observe(Contact<quad>::from_alpha(quad(p), alpha, quad(1)), plan);
      }
      // The analytic layer's own budget: the same point in double against float128.
      const std::vector<std::optional<quad>>& exact = point.reference.count("double")
                                                          ? point.reference.at("double")
                                                          : observe(calibrated, plan);
      const auto in_double =
          observe(Contact<double>::from_alpha(p, static_cast<double>(point.alpha), 1.0), plan);
      for (std::size_t i = 0; i < in_double.size(); ++i) {
        point.analytic_double.push_back(in_double[i]);
        std::optional<double> error;
        if (in_double[i] && exact[i] && isfinite(*exact[i]) && *exact[i] != 0) {
          error = static_cast<double>(abs((quad(*in_double[i]) - *exact[i]) / *exact[i]));
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
          const quad length =
              exp(log(quad(m) * quad(v0) * quad(v0) / quad(k)) / (quad(plan.points[i].p) + 1));
          plan.cells.push_back({i, v0, m, k, length, length / quad(v0), quad(m) * v0 * v0});
        }
      }
    }
  }
  return plan;
}

std::optional<quad> reference_at(const Plan& plan, const Cell& cell, std::size_t observable,
                                 const std::string& alpha_precision) {
  const Point& point = plan.points[cell.point];
  const std::optional<quad>& unit = point.reference.at(alpha_precision)[observable];
  if (!unit) {
    return std::nullopt;
  }
  const std::string& name = plan.observables[observable];
  if (name == "delta_max") {
    return *unit * cell.length_scale;
  }
  if (name == "t_peak" || name == "tau") {
    return *unit * cell.time_scale;
  }
  if (name == "energy_load" || name == "energy_unload") {
    return *unit * cell.energy_scale;
  }
  return unit; // e
}

} // namespace pldamp::harness
