// Regime-free elementary functions and log|Γ(x+iy)|, in any SupportedReal.
//
// sinc_rf(w)  = Σ (−w)ⁿ/(2n+1)!  = sin(√w)/√w | 1 | sinh(√−w)/√−w   (w > 0 | 0 | < 0)
// cos_rf(w)   = Σ (−w)ⁿ/(2n)!    = cos(√w)    | 1 | cosh(√−w)
// atan_rf(w)  = Σ (−w)ⁿ/(2n+1)   = atan(√w)/√w | 1 | atanh(√−w)/√−w   (w > −1)
// These carry the LSD solution through critical damping without dividing by √μ (MATH.md §2, §3):
// with w = μ·σ², σ·sinc_rf(w) = sin(√μσ)/√μ stays exact as μ → 0 from either side.
//
// log_abs_gamma(x, y) = ln|Γ(x + iy)| for x > 0 (MATH.md §3, the closed-form τ): shift x upward by
// the recurrence |Γ(w)| = |Γ(w + N)| / Π|w + j| until |w| exceeds the Stirling radius of the type,
// then sum the Stirling series with Bernoulli numbers (Boost.Math bernoulli_b2n) until the terms
// drop below ε or start to grow (it is asymptotic).
#pragma once

#include "pldamp/analytic/real_types.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/bernoulli.hpp>
#include <boost/math/special_functions/gamma.hpp>

#include <cmath>
#include <limits>
#include <type_traits>

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

template <SupportedReal Real>
Real log_abs_gamma(const Real& x, const Real& y) {
  using std::abs;
  using std::atan2;
  using std::log;
  using std::sqrt;
  const Real y2 = y * y;
  const Real r_min = stirling_radius<Real>();
  const Real r_min2 = r_min * r_min;

  // Recurrence: ln|Γ(x+iy)| = ln|Γ(u+iy)| − ½ ln Π_{j<N} ((x+j)² + y²), u = x + N. The product is
  // bounded by (r_min² + 1)^N with N ≤ r_min, far inside the range of every type.
  Real u = x;
  Real shift_product(1);
  while (u * u + y2 < r_min2) {
    shift_product *= u * u + y2;
    u += 1;
  }

  // Stirling at w = u + iy, real part:
  //   Re[(w − ½) ln w − w + ½ ln 2π] = (u − ½) ln r − y·arg w − u + ½ ln 2π.
  const Real r2 = u * u + y2;
  const Real arg_w = atan2(y, u);
  Real result = (u - Real(1) / 2) * log(r2) / 2 - y * arg_w - u +
                log(boost::math::constants::two_pi<Real>()) / 2;

  // Σ_k B_2k / (2k(2k−1)) · Re(w^−(2k−1)), with w^−1 = (u − iy)/r² advanced by w^−2 each term.
  // Convergence is judged on the modulus |B_2k| / (2k(2k−1) |w|^(2k−1)): the real part alone can
  // pass near zero for one k and would stop the series early.
  const Real eps = std::numeric_limits<Real>::epsilon();
  Real power_re = u / r2;
  Real power_im = -y / r2;
  const Real step_re = (u * u - y2) / (r2 * r2);
  const Real step_im = -2 * u * y / (r2 * r2);
  const Real inverse_r2 = 1 / r2;
  Real inverse_modulus = sqrt(inverse_r2); // |w|^−(2k−1)
  Real previous = std::numeric_limits<Real>::infinity();
  for (int k = 1; k < 200; ++k) {
    const Real coefficient = boost::math::bernoulli_b2n<Real>(k) / Real((2 * k) * (2 * k - 1));
    const Real bound = abs(coefficient) * inverse_modulus;
    if (bound >= previous) {
      break; // asymptotic series: stop at its smallest term
    }
    result += coefficient * power_re;
    if (bound <= eps * abs(result)) {
      break;
    }
    previous = bound;
    inverse_modulus *= inverse_r2;
    const Real next_re = power_re * step_re - power_im * step_im;
    power_im = power_re * step_im + power_im * step_re;
    power_re = next_re;
  }
  return result - log(shift_product) / 2;
}

// ln Γ(x), x > 0: the C library's lgamma for the built-in types, Boost.Math's for the others. Both
// are accurate to a few ulps, better than the shifted Stirling sum above, whose recurrence
// subtracts logs of size ~40 (a few bits) and is needed only off the real axis.
template <SupportedReal Real>
Real log_gamma(const Real& x) {
  if constexpr (std::is_floating_point_v<Real>) {
    return std::lgamma(x);
  } else {
    return boost::math::lgamma(x);
  }
}

} // namespace pldamp::analytic
