// Trajectory files for the `pldamp check` tests, made here: the closed-form trajectory sampled
// (the truth, between samples), and a DEM loop's own dump (a code with a first-order error).
#pragma once

#include "judge/trajectory.hpp"

#include "pldamp/analytic.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

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

// The same file as sampled_contact's, fast enough for millions of rows per contact (at_time
// solves for each row's time by Newton on a quadrature, some 4 µs): δ and v exact at nodes, and
// between two nodes the quintic Hermite interpolants through δ, v, δ'' and through v, δ'', δ'''
// at both (the derivatives from the law, exact given δ and v). Such an interpolant errs by at
// most |f⁽⁶⁾| Δ⁶/46080 on a node interval Δ. Inside, f⁽⁶⁾ ~ ω⁶ δ_max with ω τ ≈ π: nodes every
// τ/1000 leave 1e−20. Towards the contact's start and end the law's δ^β (β = (p − 1)/2) makes
// δ'' ≈ −c v0^β d^β and so δ⁽⁶⁾ grow like d^(β−4) at a distance d from the end (p = 1.5:
// d^(−3.75)): nodes every d/64 there keep the error below 1e−17 d, a tenth of an ulp of δ ≈ v0 d.
inline TrajectoryColumns finely_sampled_contact(const analytic::Contact<double>& contact, int n,
                                                double phase) {
  const analytic::Trajectory<double> exact(contact);
  const double tau = *analytic::observables(contact, analytic::want_tau).tau;
  const double e = *analytic::observables(contact, analytic::want_e).e;
  const double p = contact.p(), m = contact.m(), k = contact.k(), v0 = contact.v0();
  const double beta = (p - 1) / 2, damping = contact.alpha() * std::sqrt(m * k);
  const double h = tau / n;
  const ForceLaw law{p, m, k, contact.alpha()};
  struct Node {
    double t, delta, v, a, jerk; // δ, δ', δ'', δ'''
  };
  const auto node_at = [&](double t) {
    const auto at = exact.at_time(t);
    const double d = at.delta, v = at.v;
    const double a = -(k * std::pow(d, p) + damping * std::pow(d, beta) * v) / m;
    const double jerk =
        -(p * k * std::pow(d, p - 1) * v +
          damping * (beta * std::pow(d, beta - 1) * v * v + std::pow(d, beta) * a)) /
        m;
    return Node{t, d, v, a, jerk};
  };
  // The rows inside (0, τ), and nodes from the first of them to the last.
  int first_in = 0;
  while ((first_in - phase) * h <= 0) {
    ++first_in;
  }
  int last_in = first_in;
  while ((last_in + 1 - phase) * h < tau) {
    ++last_in;
  }
  const double t_a = (first_in - phase) * h, t_b = (last_in - phase) * h;
  std::vector<Node> nodes{node_at(t_a)};
  for (double t = t_a; t < t_b;) {
    t = std::min(t + std::min(tau / 1000, std::min(t, tau - t) / 64), t_b);
    nodes.push_back(node_at(t));
  }
  TrajectoryColumns c;
  c.v.emplace();
  c.force.emplace();
  std::size_t at = 0; // the node interval [at, at + 1] holding the row
  for (int i = -1; i <= n + 2; ++i) {
    const double t = (i - phase) * h;
    double delta = v0 * t;
    double v = v0;
    if (t >= tau) {
      delta = -e * v0 * (t - tau);
      v = -e * v0;
    } else if (t > 0) {
      while (at + 2 < nodes.size() && nodes[at + 1].t <= t) {
        ++at;
      }
      const Node& l = nodes[at];
      const Node& r = nodes[std::min(at + 1, nodes.size() - 1)];
      if (t <= l.t || t >= r.t) { // a node itself
        const Node& x = t <= l.t ? l : r;
        delta = x.delta;
        v = x.v;
      } else {
        const double w = r.t - l.t, s = (t - l.t) / w, s2 = s * s, s3 = s2 * s;
        const double h0 = 1 - s3 * (10 - 15 * s + 6 * s2), h1 = s - s3 * (6 - 8 * s + 3 * s2),
                     h2 = (s2 - s3 * (3 - 3 * s + s2)) / 2, h3 = s3 * (10 - 15 * s + 6 * s2),
                     h4 = -s3 * (4 - 7 * s + 3 * s2), h5 = s3 * (1 - 2 * s + s2) / 2;
        delta = h0 * l.delta + w * h1 * l.v + w * w * h2 * l.a + h3 * r.delta + w * h4 * r.v +
                w * w * h5 * r.a;
        v = h0 * l.v + w * h1 * l.a + w * w * h2 * l.jerk + h3 * r.v + w * h4 * r.a +
            w * w * h5 * r.jerk;
      }
    }
    c.t.push_back(t);
    c.delta.push_back(delta);
    c.v->push_back(v);
    c.force->push_back(law(delta, v));
  }
  return c;
}

// x as a file written with `digits` significant digits reads it: the double nearest m·10^−k, m
// the integer nearest x·10^k with `digits` digits. With 10^|k| exact (|k| ≤ 22) and |m| < 2^53
// (digits ≤ 15) that is one correctly rounded division or product, several times faster than
// printing and parsing (a test rounds some 10^8 cells); elsewhere it prints and parses. `k` is
// the previous cell's, kept by the caller: a column's next cell mostly has the same exponent.
inline double rounded_to(double x, int digits, int& k) {
  static const std::array<double, 23> powers = [] {
    std::array<double, 23> p{};
    p[0] = 1;
    for (std::size_t i = 1; i < p.size(); ++i) {
      p[i] = p[i - 1] * 10;
    }
    return p;
  }();
  if (x == 0 || !std::isfinite(x)) {
    return x;
  }
  for (int attempt = 0; attempt < 4 && std::abs(k) <= 22 && digits <= 15; ++attempt) {
    const double scale = powers[static_cast<std::size_t>(std::abs(k))];
    const double scaled = k >= 0 ? x * scale : x / scale;
    if (std::abs(scaled) >= powers[static_cast<std::size_t>(digits)]) {
      --k; // one digit too many
    } else if (std::abs(scaled) < powers[static_cast<std::size_t>(digits - 1)]) {
      ++k; // one too few
    } else {
      // x·10^k was rounded before m is: the remainder, exact by fma, puts m right near a half.
      double m = std::nearbyint(scaled);
      const double remainder = k >= 0 ? std::fma(x, scale, -m) : std::fma(-m, scale, x) / scale;
      m += remainder > 0.5 ? 1 : (remainder < -0.5 ? -1 : 0);
      return k >= 0 ? m / scale : m * scale;
    }
    if (attempt == 1) { // not a neighbour's exponent: from the logarithm
      k = digits - 1 - static_cast<int>(std::floor(std::log10(std::abs(x))));
    }
  }
  std::array<char, 64> text{};
  const auto written =
      std::to_chars(text.data(), text.data() + text.size(), x, std::chars_format::general, digits);
  std::from_chars(text.data(), written.ptr, x);
  return x;
}

// The columns as a file written with `digits` significant digits reads them: each cell the
// double nearest its decimal to that many digits, each column's precision `digits`.
inline TrajectoryColumns rounded(TrajectoryColumns c, int digits) {
  const auto round_all = [&](std::vector<double>& column) {
    int k = 0;
    for (double& x : column) {
      x = rounded_to(x, digits, k);
    }
  };
  round_all(c.t);
  round_all(c.delta);
  if (c.v) {
    round_all(*c.v);
  }
  if (c.force) {
    round_all(*c.force);
  }
  c.digits = {.t = digits, .delta = digits, .v = digits, .force = digits};
  return c;
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
