// Regime-free elementary functions and log|Γ(x+iy)|, in any SupportedReal.
//
// sinc_rf(w)  = Σ (−w)ⁿ/(2n+1)!  = sin(√w)/√w | 1 | sinh(√−w)/√−w   (w > 0 | 0 | < 0)
// cos_rf(w)   = Σ (−w)ⁿ/(2n)!    = cos(√w)    | 1 | cosh(√−w)
// atan_rf(w)  = Σ (−w)ⁿ/(2n+1)   = atan(√w)/√w | 1 | atanh(√−w)/√−w   (w > −1)
// These carry the LSD solution through critical damping without dividing by √μ (MATH.md §2, §3):
// with w = μ·σ², σ·sinc_rf(w) = sin(√μσ)/√μ stays exact as μ → 0 from either side.
//
// log_abs_gamma(x, y) = ln|Γ(x + iy)| for x > 0 (MATH.md §3, the closed-form τ) = ln Γ(x) plus
// log_abs_gamma_ratio(x, y): the recurrence |Γ(w)| = |Γ(w + N)| / Π|w + j| shifts x past the
// Stirling radius of the type, then the Stirling series with Bernoulli numbers (Boost.Math
// bernoulli_b2n) is summed, both as differences against the real axis (see below).
#pragma once

#include "pldamp/core/real_types.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/bernoulli.hpp>
#include <boost/math/special_functions/gamma.hpp>

#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

namespace pldamp::analytic {

namespace detail {

// Sums Σ_{n≥0} termₙ with term₀ = 1 and termₙ = termₙ₋₁ · ratio(n) until a term is below ε of
// the sum. Callers use it only for |w| ≤ 1/4 (sinc, cos) or 1/16 (atan), where the ratio is small.
template <SupportedReal Real, class Ratio>
Real power_series(Ratio ratio) {
  using std::abs;
  const Real eps = std::numeric_limits<Real>::epsilon();
  Real term(1);
  Real sum(1);
  for (int n = 1; n < 1000; ++n) {
    term *= ratio(n);
    sum += term;
    if (abs(term) <= eps * abs(sum)) {
      break;
    }
  }
  return sum;
}

} // namespace detail

template <SupportedReal Real>
Real sinc_rf(const Real& w) {
  using std::abs;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  // Below |w| = 1/4 the closed forms lose digits to the division; the series converges like
  // (w/6)(w/20)... and needs about digits/3 terms there.
  if (abs(w) < Real(1) / 4) {
    return detail::power_series<Real>([&](int n) { return -w / Real((2 * n) * (2 * n + 1)); });
  }
  if (w > 0) {
    const Real r = sqrt(w);
    return sin(r) / r;
  }
  const Real r = sqrt(-w);
  return sinh(r) / r;
}

template <SupportedReal Real>
Real cos_rf(const Real& w) {
  using std::cos;
  using std::cosh;
  using std::sqrt;
  // No division here: cos(√w) is accurate for any w ≥ 0, so no series is needed.
  return w >= 0 ? Real(cos(sqrt(w))) : Real(cosh(sqrt(-w)));
}

template <SupportedReal Real>
Real atan_rf(const Real& w) {
  using std::abs;
  using std::atan;
  using std::atanh;
  using std::sqrt;
  // The series ratio is −w(2n−1)/(2n+1); at |w| < 1/16 it needs about digits/1.2 terms.
  if (abs(w) < Real(1) / 16) {
    return detail::power_series<Real>(
        [&](int n) { return -w * Real(2 * n - 1) / Real(2 * n + 1); });
  }
  if (w > 0) {
    const Real r = sqrt(w);
    return atan(r) / r;
  }
  const Real r = sqrt(-w);
  return atanh(r) / r;
}

// |w| above which the Stirling series of the type reaches ε: its smallest term is about
// e^(−2π|w|), so |w| ≥ digits·ln2/(2π), plus one for the terms before the smallest.
template <SupportedReal Real>
Real stirling_radius() {
  using boost::math::constants::ln_two;
  using boost::math::constants::two_pi;
  return Real(std::numeric_limits<Real>::digits) * ln_two<Real>() / two_pi<Real>() + 1;
}

// B_2k / (2k(2k−1)), k = 1, 2, …: Stirling's coefficients, computed once per type. For |w| ≥
// stirling_radius the terms decrease until k ≈ π|w| and reach ε well before, so π·radius + 4
// coefficients always suffice. (A table, because bernoulli_b2n costs ~17 ns a call in double.)
template <SupportedReal Real>
const std::vector<Real>& stirling_coefficients() {
  static const std::vector<Real> table = [] {
    const int count = static_cast<int>(boost::math::constants::pi<double>() *
                                       static_cast<double>(stirling_radius<Real>())) +
                      4;
    std::vector<Real> coefficients;
    for (int k = 1; k <= count; ++k) {
      coefficients.push_back(boost::math::bernoulli_b2n<Real>(k) / Real((2 * k) * (2 * k - 1)));
    }
    return coefficients;
  }();
  return table;
}

// ln|Γ(x + iy) / Γ(x)|, x > 0, formed without either Γ: both logs can be ~40 while their
// difference is small, and subtracting them would cost digits. With u = x + N ≥ stirling_radius,
//   ln|Γ(x+iy)/Γ(x)| = Stirling(u + iy) − Stirling(u) − ½ ln Π_{j<N} (1 + y²/(x+j)²),
//   Stirling(u + iy) − Stirling(u) = (u − ½)·½ log1p(y²/u²) − y·atan2(y, u)
//                                    + Σ_k B_2k/(2k(2k−1)) · (Re (u+iy)^−(2k−1) − u^−(2k−1)),
// where the −w and ½ ln 2π terms of Stirling's series cancel exactly. Every piece is of the size
// of the result, or a product of factors ≥ 1.
template <SupportedReal Real>
Real log_abs_gamma_ratio(const Real& x, const Real& y) {
  using std::abs;
  using std::atan2;
  using std::log1p;
  if (y == 0) {
    return Real(0);
  }
  const Real y2 = y * y;
  const Real r_min = stirling_radius<Real>();
  // Π (1 + δ_j), δ_j = y²/(x+j)², carried as its excess over 1 (excess' = excess + δ + excess·δ,
  // all terms ≥ 0) so that a tiny y is not rounded away by 1 + δ; moved into a log sum whenever
  // it grows past 1/ε (no overflow for any y).
  const Real flush = 1 / std::numeric_limits<Real>::epsilon();
  Real u = x;
  Real excess(0);
  Real log_product(0);
  while (u < r_min) {
    const Real delta = y2 / (u * u);
    excess += delta + excess * delta;
    if (excess > flush) {
      log_product += log1p(excess);
      excess = 0;
    }
    u += 1;
  }
  log_product += log1p(excess);

  Real result = (u - Real(1) / 2) * log1p(y2 / (u * u)) / 2 - y * atan2(y, u);

  // Series: Σ_k B_2k/(2k(2k−1)) · u^−m · Re D_m with m = 2k − 1, t = y/u and
  // D_m = (1 + it)^−m − 1 = (w^−m − u^−m)·u^m. Subtracting the powers would cancel when y ≪ u;
  // instead D runs its own recurrence, D_{m+2} = D_m·Q + (Q − 1), Q = (1 + it)^−2, with
  // Q − 1 = (t² − 2it)·Q and D_1 = −(t² + it)/(1 + t²): no step subtracts nearly equal numbers.
  // Convergence is judged on the bound |D_m| ≤ min(2, m|t|), since Re D_m can pass near zero.
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real t = y / u;
  const Real t2 = t * t;
  const Real one_plus_t2 = 1 + t2;
  const Real q_re = (1 - t2) / (one_plus_t2 * one_plus_t2);
  const Real q_im = -2 * t / (one_plus_t2 * one_plus_t2);
  const Real qm1_re = t2 * q_re + 2 * t * q_im;
  const Real qm1_im = t2 * q_im - 2 * t * q_re;
  Real d_re = -t2 / one_plus_t2;
  Real d_im = -t / one_plus_t2;
  const Real inverse_u2 = 1 / (u * u);
  Real real_power = 1 / u; // u^−m
  Real previous = std::numeric_limits<Real>::infinity();
  const std::vector<Real>& coefficients = stirling_coefficients<Real>();
  for (int k = 1; k <= static_cast<int>(coefficients.size()); ++k) {
    const Real& coefficient = coefficients[k - 1];
    const Real bound = abs(coefficient) * real_power;
    if (bound >= previous) {
      break; // asymptotic series: stop at its smallest term
    }
    result += coefficient * real_power * d_re;
    const Real spread = Real(2 * k - 1) * abs(t);
    if (bound * (spread < 2 ? spread : Real(2)) <= eps * abs(result)) {
      break;
    }
    previous = bound;
    real_power *= inverse_u2;
    const Real next_re = d_re * q_re - d_im * q_im + qm1_re;
    d_im = d_re * q_im + d_im * q_re + qm1_im;
    d_re = next_re;
  }
  return result - log_product / 2;
}

// ln Γ(x), x > 0: the C library's lgamma for the built-in types, Boost.Math's for float128, both
// accurate to a few ulps. In 50 digits Boost.Math's lgamma errs by up to 20 ε (13 ε at x = 3/4,
// 20 ε at 3/2), which τ0 carried: at p = 3 the closed-form τ0, which t_c is at α_eff = 0, stood
// 17 ε from the quadrature that gives t_c just above 0. So 50 digits take it from 100 digits,
// rounded once.
template <SupportedReal Real>
Real log_gamma(const Real& x) {
  if constexpr (std::is_floating_point_v<Real>) {
    return std::lgamma(x);
  } else if constexpr (std::is_same_v<Real, bin50>) {
    using Wide = boost::multiprecision::cpp_bin_float_100;
    return static_cast<Real>(boost::math::lgamma(Wide(x)));
  } else {
    return boost::math::lgamma(x);
  }
}

template <SupportedReal Real>
Real log_abs_gamma(const Real& x, const Real& y) {
  return log_gamma(x) + log_abs_gamma_ratio(x, y);
}

} // namespace pldamp::analytic
