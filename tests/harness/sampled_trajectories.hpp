// Trajectory files for the `pldamp check` tests, made here: the closed-form trajectory sampled
// (the truth, between samples), and a DEM loop's own dump (a code with a first-order error).
#pragma once

#include "judge/trajectory.hpp"

#include "pldamp/analytic.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace pldamp::harness::testing {

// The closed-form trajectory of `contact` sampled every τ/n from −(1 + φ)τ/n: free flight at v0
// before contact and at −e v0 after it; F by the model's force law.
inline TrajectoryColumns sampled_contact(const analytic::Contact<double>& contact, int n,
                                         double phase, bool with_v, bool with_force) {
  const analytic::Trajectory<double> exact(contact);
  const double tau = *analytic::observables(contact, analytic::want_tau).tau;
  const double e = *analytic::observables(contact, analytic::want_e).e;
  const double v0 = contact.v0();
  const double h = tau / n;
  const ForceLaw law{contact.p(), contact.m(), contact.k(), contact.alpha()};
  TrajectoryColumns c;
  c.v.emplace();
  c.force.emplace();
  for (int i = -1; i <= n + 2; ++i) {
    const double t = (i - phase) * h;
    double delta = v0 * t;
    double v = v0;
    if (t >= tau) {
      delta = -e * v0 * (t - tau);
      v = -e * v0;
    } else if (t > 0) {
      const auto at = exact.at_time(t);
      delta = at.delta;
      v = at.v;
    }
    c.t.push_back(t);
    c.delta.push_back(delta);
    c.v->push_back(v);
    c.force->push_back(law(delta, v));
  }
  if (!with_v) {
    c.v.reset();
  }
  if (!with_force) {
    c.force.reset();
  }
  return c;
}

// The same at p, e with v0 = m = k = 1.
inline TrajectoryColumns sampled(double p, double e, int n, double phase, bool with_v,
                                 bool with_force) {
  return sampled_contact(analytic::Contact<double>::from_e(p, e, 1.0), n, phase, with_v,
                         with_force);
}

// How a DEM loop steps: velocity Verlet as LAMMPS (half kick, drift, the force from the new
// overlap and the half-step velocity, half kick) or symplectic Euler as Project Chrono (the force
// from the state, then v, then δ with the new v: the force a full step behind the state dumped).
enum class DemLoop { verlet, symplectic_euler };

// A DEM loop's dump: the state after every step and the force the step applied, from three steps
// before contact to three after it; Δt = (π δ_u/v0)/steps.
inline TrajectoryColumns dem_dump(const analytic::Contact<double>& contact, int steps, double phase,
                                  DemLoop loop = DemLoop::verlet) {
  const double p = contact.p(), m = contact.m(), k = contact.k(), v0 = contact.v0();
  const double damping = contact.alpha() * std::sqrt(m * k);
  const double delta_u = std::pow((p + 1) / 2 * m * v0 * v0 / k, 1 / (p + 1));
  const double dt = std::numbers::pi * delta_u / v0 / steps;
  const auto force_at = [&](double delta, double v) {
    return delta > 0 ? k * std::pow(delta, p) + damping * std::pow(delta, (p - 1) / 2) * v : 0;
  };
  TrajectoryColumns out;
  out.v.emplace();
  out.force.emplace();
  double t = (phase - 3) * dt, delta = v0 * t, v = v0, force = 0;
  const auto dump = [&] {
    out.t.push_back(t);
    out.delta.push_back(delta);
    out.v->push_back(v);
    out.force->push_back(force);
  };
  dump();
  bool touched = false;
  for (int after = 0; after < 3 && out.t.size() < 1000000;) {
    if (loop == DemLoop::verlet) {
      v -= dt / 2 * force / m;
      delta += dt * v;
      force = force_at(delta, v);
      v -= dt / 2 * force / m;
    } else {
      force = force_at(delta, v);
      v -= dt * force / m;
      delta += dt * v;
    }
    t += dt;
    dump();
    touched = touched || delta > 0;
    after += touched && delta <= 0 ? 1 : 0;
  }
  return out;
}

// The columns as a CSV file's text, every number to `digits` significant digits.
inline std::string csv_of(const TrajectoryColumns& c, int digits = 17) {
  std::ostringstream csv;
  csv.precision(digits);
  csv << "t,delta" << (c.v ? ",v" : "") << (c.force ? ",F" : "") << "\n";
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    csv << c.t[i] << "," << c.delta[i];
    if (c.v) {
      csv << "," << (*c.v)[i];
    }
    if (c.force) {
      csv << "," << (*c.force)[i];
    }
    csv << "\n";
  }
  return csv.str();
}

} // namespace pldamp::harness::testing
