// A curve known only at samples, y(t) with optionally its tabulated slope, interpolated locally
// (MATH.md §10): where it crosses 0, its slope, its largest value about a sample, each with a
// lower-order partner whose difference is the sampling estimate. What the curves are (overlap,
// speed, force) is judge/trajectory.cpp's business; nothing here knows the contact.
#pragma once

#include "judge/trajectory.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace pldamp::harness::sampled {

// Rounding: no estimate is below a few ulps of the quantity it is on.
inline double floored(double sampling, double scale) {
  return std::max(sampling, 4 * std::numeric_limits<double>::epsilon() * std::abs(scale));
}

// The parabola through three samples, in Newton form around its first two nodes.
struct Quadratic {
  double t0, t1, y0, d01, d012;
  Quadratic(double ta, double ya, double tb, double yb, double tc, double yc)
      : t0(ta), t1(tb), y0(ya), d01((yb - ya) / (tb - ta)),
        d012(((yc - yb) / (tc - tb) - (yb - ya) / (tb - ta)) / (tc - ta)) {}
  double operator()(double t) const { return y0 + (t - t0) * (d01 + d012 * (t - t1)); }
  double slope(double t) const { return d01 + d012 * (2 * t - t0 - t1); }
  // Where the slope vanishes (d012 ≠ 0).
  double vertex() const { return (t0 + t1) / 2 - d01 / (2 * d012); }
};

// The cubic Hermite interpolant on [ta, ta + h] of values and slopes at both ends, as a cubic in
// s = (t − ta)/h.
struct Hermite {
  double ta, h;
  std::array<double, 4> c; // c0 + c1 s + c2 s² + c3 s³
  Hermite(double t_a, double t_b, double ya, double yb, double ma, double mb)
      : ta(t_a), h(t_b - t_a), c{ya, h * ma, 3 * (yb - ya) - h * (2 * ma + mb),
                                 2 * (ya - yb) + h * (ma + mb)} {}
  double at_s(double s) const { return c[0] + s * (c[1] + s * (c[2] + s * c[3])); }
  double operator()(double t) const { return at_s((t - ta) / h); }
  double slope(double t) const {
    const double s = (t - ta) / h;
    return (c[1] + s * (2 * c[2] + s * 3 * c[3])) / h;
  }
};

// A local interpolant of a sampled curve: the cubic Hermite on [near, near + 1] when the slopes
// are tabulated, else a parabola through three samples; and its lower-order partner for the
// slope, the straight line through the tabulated slopes at near and near + 1, or the secant
// through those two samples.
struct Interpolant {
  std::optional<Hermite> cubic;
  std::optional<Quadratic> parabola;
  std::size_t near = 0;

  double operator()(double x) const {
    assert(cubic.has_value() != parabola.has_value()); // Curve::interpolant makes one of them
    return cubic ? (*cubic)(x) : (*parabola)(x);
  }
};

// A sampled curve y(t), t strictly increasing, at least 3 samples, with optionally its tabulated
// slope (extract_observables checks the columns before it builds one).
struct Curve {
  const std::vector<double>& t;
  const std::vector<double>& y;
  const std::vector<double>* slope;

  std::size_t size() const { return t.size(); }
  Hermite hermite(std::size_t a) const {
    assert(slope != nullptr && a + 1 < size());
    return {t[a], t[a + 1], y[a], y[a + 1], (*slope)[a], (*slope)[a + 1]};
  }
  Quadratic quadratic(std::size_t first) const {
    assert(first + 2 < size());
    return {t[first], y[first], t[first + 1], y[first + 1], t[first + 2], y[first + 2]};
  }
  // The Hermite on [near, near + 1], else the parabola through `first` and the two samples after
  // it (near being one of its two intervals).
  Interpolant interpolant(std::size_t near, std::size_t first) const {
    if (slope != nullptr) {
      return {hermite(near), std::nullopt, near};
    }
    return {std::nullopt, quadratic(first), near};
  }
  // The interpolant across [a, a + 1]; the parabola takes the sample beyond the interval on
  // `inside_side` (−1 before, +1 after), or on the other side where there is none.
  Interpolant across(std::size_t a, int inside_side) const {
    assert(a + 1 < size() && size() >= 3);
    std::size_t first = a >= 1 ? a - 1 : a;
    if (inside_side > 0 || a == 0) {
      first = a + 2 < size() ? a : a - 1;
    }
    return interpolant(a, first);
  }
  // y = 0 between samples a and a + 1 (opposite sides of 0), on the interpolant across the
  // interval or, `one_sided`, on `local`, the contact side's, where it changes sign in the
  // interval. The sampling estimate is the largest distance to the crossing of the straight line
  // and of the other interpolant (MATH.md §10); a zero beyond the interval that may be clamped
  // (`clamped`) widens it to the whole interval, unless `local` placed the crossing.
  Extracted crossing(std::size_t a, const std::optional<Interpolant>& local, bool one_sided,
                     int inside_side, bool clamped) const;
  // dy/dt at x by an interpolant, and by its lower-order partner.
  std::pair<double, double> slopes(double x, const Interpolant& by) const;
};

// The vertex of the parabola through samples first .. first + 2, when it is concave; clamped to
// their span.
std::optional<std::pair<double, double>> vertex_of(const Curve& curve, std::size_t first);

// The largest value of the cubic Hermite pieces on both sides of sample i, and where.
std::pair<double, double> hermite_peak(const Curve& curve, std::size_t i);

// The largest value of the cubic through samples from .. from + 3, and where: its slope's root
// in their span that is a maximum (the cubic is unimodal there about a sampled maximum), else
// the largest of the samples.
std::pair<double, double> cubic_peak(const Curve& curve, std::size_t from);

} // namespace pldamp::harness::sampled
