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

// ---- Reading over a wider spacing than the rows' (MATH.md §10.2) -----------------------------

// The relative rounding of each column (resolution_of its digits): a cell y is known to ρ |y|.
struct Resolution {
  double t, y, slope;
};

// Every stride-th row of a curve about one of its rows, as a curve of its own: rows
// anchor + j·stride for j from −before to after, those in [lo, hi]. A derivative read off rows
// closer than their digits resolve is their rounding (4 ε y/h² on a second difference); read off
// every s-th row it is the same reading at an s times wider spacing.
struct Strided {
  std::vector<double> t, y, slope;
  std::size_t at = 0; // the anchor's index among them
  Curve curve() const { return {t, y, slope.empty() ? nullptr : &slope}; }
};
Strided strided(const Curve& curve, std::size_t anchor, std::size_t stride, std::size_t before,
                std::size_t after, std::size_t lo, std::size_t hi);

// How far readings off `rows` move when each cell they read moves by its half unit (ρ |cell|,
// MATH.md §10.2), the moves summed: the readings' rounding to first order, whatever weights the
// interpolant gives the cells (a parabola's slope at its rows' ends weighs them 4/H, a Hermite
// extrapolated a row past its piece more). `read(rows)` gives N values; infinite where a move
// made one not finite (a time moved past its neighbour's).
template <std::size_t N, class Read>
std::array<double, N> moved_by_rounding(const Strided& rows, const Resolution& r,
                                        const Read& read) {
  const std::array<double, N> base = read(rows);
  std::array<double, N> moved{};
  for (const auto& [column, resolution] : {std::pair{&Strided::t, r.t}, std::pair{&Strided::y, r.y},
                                           std::pair{&Strided::slope, r.slope}}) {
    for (std::size_t j = 0; j < (rows.*column).size(); ++j) {
      Strided nudged = rows;
      (nudged.*column)[j] += resolution * std::abs((rows.*column)[j]);
      const std::array<double, N> now = read(nudged);
      for (std::size_t k = 0; k < N; ++k) {
        moved[k] += std::abs(now[k] - base[k]);
      }
    }
  }
  for (double& m : moved) {
    m = std::isfinite(m) ? m : std::numeric_limits<double>::infinity();
  }
  return moved;
}

// A reading at one spacing: its value, its estimate (§10.1's comparisons with the other readings
// at that spacing) and a bound on how far the cells' rounding moves it.
struct Reading {
  double value = 0, estimate = 0, rounding = 0;
  std::size_t stride = 1; // of the rows it was read off
  // Set by at_resolving_stride: how far the reading moved from the one a stride narrower, and to
  // the one a stride wider; and how far rounding alone can move those comparisons.
  double change_from_narrower = 0, change_to_wider = 0, changes_rounding = 0;

  // Two readings each off by up to the bound may differ by twice it through rounding alone.
  double compared_rounding() const { return std::max(changes_rounding, 2 * rounding); }
  bool within_rounding() const {
    return std::max({estimate, change_from_narrower, change_to_wider}) <= compared_rounding();
  }
  // The comparisons' spread, but no less than their rounding (readings off by it may agree by
  // accident, hiding that much of the truncation the spread is meant to show), and the reading's
  // own rounding. The narrower reading errs by about the change between two strides or less; the
  // wider by 4/3 of it where its truncation is second order in the spacing, twice where first:
  // twice is counted (once was seen 1.07-fold short: t_peak, p = 3, e = 0.1, 9 digits, 10^5
  // rows).
  double error() const {
    return std::max({estimate, change_to_wider, 2 * change_from_narrower, compared_rounding()}) +
           rounding;
  }
};

// The §10.1 estimates cover the closed form's errors from 40 rows per contact on; below, they
// can miss several-fold (e at p = 1, e = 0.1, off 20 rows written with 6 digits and read at
// stride 2, as if off 10: by 1.6). The widest stride for them keeps 40 rows of contact or more.
inline std::size_t widest_keeping_40_rows(std::size_t contact_rows) {
  return std::max<std::size_t>(1, contact_rows / 40);
}

// The stride a derivative is read at (MATH.md §10.2): 1, doubled while the reading's comparisons
// are within what rounding alone makes of them (the truncation they are meant to show is below
// the rounding, which halves or quarters at each doubling) and while `largest` allows; of the
// strides tried, the one whose error() is least. Past stride 1 each reading is also compared with
// the ones a stride before and after it, which differ from it by truncation even where its own
// comparisons are blind to that (e_cap at the force cut without v, p = 1.5, 12 digits, 10^6
// rows: δ'' = 0 there and the slopes compared err alike; the reading drifted by 5.6e−5 over
// doublings its comparisons put at 1e−10). At a spacing the digits resolve, stride 1: the reading
// as it was. `read(s)` gives the reading at stride s, or none.
template <class Read>
std::optional<Reading> at_resolving_stride(const Read& read, std::size_t largest) {
  std::vector<Reading> tried;
  if (const std::optional<Reading> first = read(std::size_t(1))) {
    tried.push_back(*first);
  }
  for (std::size_t stride = 2;
       stride <= largest && (tried.empty() || tried.back().within_rounding()); stride *= 2) {
    std::optional<Reading> next = read(stride);
    if (!next) {
      continue;
    }
    if (!tried.empty() && tried.back().stride == stride / 2) {
      Reading& narrower = tried.back();
      const double change = std::abs(next->value - narrower.value);
      narrower.change_to_wider = change;
      next->change_from_narrower = change;
      for (Reading* r : {&narrower, &*next}) {
        r->changes_rounding = std::max(r->changes_rounding, narrower.rounding + next->rounding);
      }
    }
    tried.push_back(*next);
  }
  if (tried.empty()) {
    return std::nullopt;
  }
  return *std::min_element(tried.begin(), tried.end(), [](const Reading& a, const Reading& b) {
    return a.error() < b.error();
  });
}

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
