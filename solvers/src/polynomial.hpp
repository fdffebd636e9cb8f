// Polynomials given by their coefficients c_0 ... c_n (a Taylor step, a local series): evaluation,
// and the first sign change in an interval by Descartes' rule of signs with bisection (the
// Vincent–Collins–Akritas method, as heyoka isolates events on its Taylor polynomials), polished
// by Boost's TOMS 748 to full precision. Any SupportedReal.
#pragma once

#include <boost/math/tools/toms748_solve.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace pldamp::solvers::detail {

// Σ c_i x^i by Horner's rule.
template <class Real>
Real horner(std::span<const Real> c, const Real& x) {
  Real sum = c.back();
  for (std::size_t i = c.size() - 1; i-- > 0;) {
    sum = sum * x + c[i];
  }
  return sum;
}

// x^e for x ≥ 0, with the exponents whose power is exact or correctly rounded done so: √x for
// e = ½ (the viscoelastic dashpot's, and the seed's δ^β at p = 2), x for e = 1, 1 for e = 0.
// Correctly rounded where pow is within an ulp, and cheaper (a double pow is ~20 ns, a square
// root a few).
template <class Real>
Real power_of(const Real& x, const Real& e) {
  using std::pow;
  using std::sqrt;
  if (e == Real(1) / 2) {
    return sqrt(x);
  }
  if (e == 1) {
    return x;
  }
  if (e == 0) {
    return Real(1);
  }
  return pow(x, e);
}

// A sum of products in two lanes, a += x0 y0 and b += x1 y1 (and a lone last term into a), added
// at the end: in double one SSE2 register (GCC's vector extension), in any other T two values,
// with the same roundings either way.
template <class T>
struct TwoLanes {
  T a = T(0), b = T(0);
  void add(const T& x0, const T& x1, const T& y0, const T& y1) {
    a += x0 * y0;
    b += x1 * y1;
  }
  void add(const T& x0, const T& y0) { a += x0 * y0; }
  T sum() const { return a + b; }
};
template <>
struct TwoLanes<double> {
  using Pair = double __attribute__((vector_size(16)));
  Pair lanes{0, 0};
  void add(double x0, double x1, double y0, double y1) { lanes += Pair{x0, x1} * Pair{y0, y1}; }
  void add(double x0, double y0) { lanes[0] += x0 * y0; }
  double sum() const { return lanes[0] + lanes[1]; }
};

// Two polynomials of one length and their derivatives at one x, by Horner's rule in one pass: four
// independent chains instead of two after two (Newton's iteration at the exit evaluates Y and Z
// together).
template <class Real>
void horner_pair_with_derivative(std::span<const Real> a, std::span<const Real> b, const Real& x,
                                 std::array<Real, 2>& value, std::array<Real, 2>& slope) {
  value = {a.back(), b.back()};
  slope = {Real(0), Real(0)};
  for (std::size_t i = a.size() - 1; i-- > 0;) {
    slope[0] = slope[0] * x + value[0];
    slope[1] = slope[1] * x + value[1];
    value[0] = value[0] * x + a[i];
    value[1] = value[1] * x + b[i];
  }
}

namespace polynomial_detail {

// a(x) -> a(x + 1) in place: n(n+1)/2 additions (repeated synthetic division).
template <class Real>
void shift_by_one(std::vector<Real>& a) {
  const std::size_t n = a.size() - 1;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = n; j-- > i;) {
      a[j] += a[j + 1];
    }
  }
}

// Descartes' bound on the roots of a in (0, 1): the sign variations of the coefficients of
// (x + 1)^n a(1 / (x + 1)), which maps (0, 1) onto (0, ∞). It is exact when it is 0 or 1, and
// otherwise exceeds the root count by an even number.
template <class Real>
int roots_bound_01(const std::vector<Real>& a) {
  thread_local std::vector<Real> b; // its allocation kept: a step's peak search calls this
  b.assign(a.rbegin(), a.rend());
  shift_by_one(b);
  int variations = 0;
  int last_sign = 0;
  for (const Real& coefficient : b) {
    const int sign = coefficient > 0 ? 1 : (coefficient < 0 ? -1 : 0);
    if (sign != 0) {
      variations += (last_sign != 0 && sign != last_sign) ? 1 : 0;
      last_sign = sign;
    }
  }
  return variations;
}

// No root in [0, 1] when |a_0| > Σ_{i≥1} |a_i| (a cheap exclusion that settles almost every step
// far from an event in O(n)).
template <class Real>
bool excludes_roots_01(const std::vector<Real>& a) {
  using std::abs;
  Real rest = Real(0);
  for (std::size_t i = 1; i < a.size(); ++i) {
    rest += abs(a[i]);
  }
  return abs(a[0]) > rest;
}

} // namespace polynomial_detail

// Where p(t) = 0 exactly: the sign of p just after t (that of its first nonzero Taylor coefficient
// at t, found by shifting the polynomial to t) and whether p changes sign at t (odd multiplicity).
template <class Real>
std::pair<int, bool> sign_after_zero(std::span<const Real> c, const Real& t) {
  std::vector<Real> shifted(c.begin(), c.end());
  const std::size_t n = shifted.size() - 1;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = n; j-- > i;) {
      shifted[j] += t * shifted[j + 1];
    }
  }
  for (std::size_t k = 1; k <= n; ++k) {
    if (shifted[k] != 0) {
      return {shifted[k] > 0 ? 1 : -1, k % 2 == 1};
    }
  }
  return {0, false};
}

// The first t in (0, h] where the polynomial Σ c_i t^i changes sign (a crossing, not a touch), or
// none. Intervals are halved until Descartes' rule isolates a single root (a(x) on [lo, lo + w]
// becomes a(lo + w x) on [0, 1]: the left half scales coefficient i by 2^-i, the right half is
// the left shifted by one) or excludes all; the isolated root is then polished by TOMS 748 on
// the original polynomial to all but 2 bits. Descartes counts roots inside an interval only, so
// an exact zero at an end is judged by its multiplicity.
template <class Real>
std::optional<Real> first_sign_change(std::span<const Real> c, const Real& h) {
  using polynomial_detail::excludes_roots_01;
  using polynomial_detail::roots_bound_01;
  using polynomial_detail::shift_by_one;

  auto value_at = [&](const Real& t) { return horner(c, t); };
  auto sign = [](const Real& x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
  // Horner's rule evaluates p(t) to within 2 n ε Σ |c_i| |t|^i; a value below that has no
  // reliable sign (near a double root, say, a bracket end there would let TOMS 748 converge on a
  // rounding-noise "crossing").
  auto noise_at = [&](const Real& t) {
    using std::abs;
    Real sum = Real(0), power = Real(1);
    for (const Real& coefficient : c) {
      sum += abs(coefficient) * power;
      power *= abs(t);
    }
    return 2 * Real(c.size()) * std::numeric_limits<Real>::epsilon() * sum;
  };
  auto significant = [&](const Real& t, const Real& f) {
    using std::abs;
    return abs(f) > noise_at(t);
  };
  // Moves an end whose value is within the noise to the point nearest it, on the way towards the
  // other end (halving the distance), whose sign is significant; false if there is none.
  auto significant_end = [&](Real& end, Real& f_end, const Real& other) {
    if (significant(end, f_end)) {
      return true;
    }
    bool found = false;
    Real step = (other - end) / 2;
    Real best = end, f_best = f_end;
    for (int k = 0; k < 60; ++k, step /= 2) {
      const Real t = end + step;
      const Real f = value_at(t);
      if (!significant(t, f)) {
        if (found) {
          break;
        }
        continue;
      }
      found = true;
      best = t;
      f_best = f;
    }
    end = best;
    f_end = f_best;
    return found;
  };
  // The single crossing inside [lo, hi] that Descartes isolated, bracketed by ends whose signs are
  // significant.
  auto polish = [&](Real lo, Real hi) -> std::optional<Real> {
    Real f_lo = value_at(lo), f_hi = value_at(hi);
    if (!significant_end(lo, f_lo, hi) || !significant_end(hi, f_hi, lo)) {
      return std::nullopt;
    }
    if (sign(f_lo) == sign(f_hi)) {
      return std::nullopt; // an even number of crossings, or one within the noise
    }
    std::uintmax_t iterations = 200;
    const auto bracket = boost::math::tools::toms748_solve(
        value_at, lo, hi, f_lo, f_hi,
        boost::math::tools::eps_tolerance<Real>(std::numeric_limits<Real>::digits - 2), iterations);
    return bracket.first + (bracket.second - bracket.first) / 2;
  };

  // The exclusion test first, without a copy: it settles almost every step.
  {
    using std::abs;
    Real rest = Real(0), power = h;
    for (std::size_t i = 1; i < c.size(); ++i, power *= h) {
      rest += abs(c[i]) * power;
    }
    if (abs(c[0]) > rest) {
      return std::nullopt;
    }
  }
  // a(x) = p(h x) on [0, 1].
  std::vector<Real> a(c.begin(), c.end());
  Real power = Real(1);
  for (Real& coefficient : a) {
    coefficient *= power;
    power *= h;
  }
  // Depth-first, left half first, so that the first root is found first. 2^-60 of h is below the
  // resolution of double; deeper ties (multiple roots) are settled by the signs at the ends.
  struct Interval {
    std::vector<Real> coefficients;
    Real lo, width;
    int depth;
  };
  std::vector<Interval> stack;
  stack.push_back({std::move(a), Real(0), Real(1), 0});
  while (!stack.empty()) {
    Interval piece = std::move(stack.back());
    stack.pop_back();
    if (excludes_roots_01(piece.coefficients)) {
      continue;
    }
    const int bound = roots_bound_01(piece.coefficients);
    const Real lo = h * piece.lo, hi = h * (piece.lo + piece.width);
    if (bound == 1 || piece.depth == 60) {
      if (const auto root = polish(lo, hi)) {
        return root;
      }
    }
    if (bound <= 1 || piece.depth == 60) {
      // Nothing (more) inside; a zero exactly at the right end counts if p crosses there.
      if (value_at(hi) == 0 && sign_after_zero(c, hi).second) {
        return hi;
      }
      continue;
    }
    std::vector<Real> left = std::move(piece.coefficients);
    Real scale = Real(1);
    for (Real& coefficient : left) {
      coefficient *= scale;
      scale /= 2;
    }
    std::vector<Real> right = left;
    shift_by_one(right);
    const Real half = piece.width / 2;
    stack.push_back({std::move(right), piece.lo + half, half, piece.depth + 1});
    stack.push_back({std::move(left), piece.lo, half, piece.depth + 1});
  }
  return std::nullopt;
}

} // namespace pldamp::solvers::detail
