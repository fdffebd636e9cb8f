// A validated contact m δ'' + α√(mk) δ^((p−1)/2) δ' + k δ^p = 0, δ(0) = 0, δ'(0) = v0, with the
// derived constants of MATH.md §1 and the calibrations of §3 (overlap end) and §4 (force end).
//
// The damping is stored as the pair (z, μ) = (α_eff, 1 − z²) with μ formed where it is exact:
// from e, μ = π²/(π² + ln²e) (no cancellation as e → 0); from z, μ = (1 − z)(1 + z) (one rounding,
// 1 − z is exact near z = 1). Everything downstream reads μ, never 1 − z².
#pragma once

#include "pldamp/analytic/special.hpp"
#include "pldamp/core/domain.hpp"
#include "pldamp/core/real_types.hpp"
#include "pldamp/core/validate.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/math/tools/roots.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

namespace pldamp::analytic {

enum class ContactEnd { overlap, force };

// Damping as the LSD sees it: z = α_eff and μ = 1 − z², kept separately for accuracy.
template <SupportedReal Real>
struct Damping {
  Real z;
  Real mu;
};

// ---- Calibration at the overlap end (MATH.md §3) -------------------------------------------

// From ln e (≤ 0): ξ_L = −ln e / √(π² + ln²e), μ = π² / (π² + ln²e).
template <SupportedReal Real>
Damping<Real> damping_from_log_e(const Real& log_e) {
  using std::sqrt;
  const Real pi = boost::math::constants::pi<Real>();
  const Real d2 = pi * pi + log_e * log_e;
  // 0 − ln e, not −ln e: e = 1 gives α_eff = +0, not −0 (which reports printed as "-0" and a
  // code's adapter refused as a negative α).
  return {(Real(0) - log_e) / sqrt(d2), pi * pi / d2};
}

template <SupportedReal Real>
Damping<Real> damping_from_e(const Real& e) {
  using std::log;
  require_finite("e", e);
  require(e > 0 && e <= 1, "e must be in (0, 1]", e);
  return damping_from_log_e(Real(log(e)));
}

// For e = 1 − ε with ε tiny, ln e = log1p(−ε) keeps the digits that 1 − ε would lose.
template <SupportedReal Real>
Damping<Real> damping_from_one_minus_e(const Real& one_minus_e) {
  using std::log1p;
  require_finite("1 - e", one_minus_e);
  require(one_minus_e >= 0 && one_minus_e < 1, "1 - e must be in [0, 1)", one_minus_e);
  return damping_from_log_e(Real(log1p(-one_minus_e)));
}

template <SupportedReal Real>
Damping<Real> damping_from_alpha_eff(const Real& z) {
  domain::require_alpha_eff(z);
  return {z, (1 - z) * (1 + z)};
}

// ln e = −π z/√μ for z < 1; −∞ (no return in finite time) for z ≥ 1.
template <SupportedReal Real>
Real log_restitution(const Damping<Real>& d) {
  using std::sqrt;
  if (d.mu <= 0) {
    return -std::numeric_limits<Real>::infinity();
  }
  return -boost::math::constants::pi<Real>() * d.z / sqrt(d.mu);
}

template <SupportedReal Real>
Real restitution(const Damping<Real>& d) {
  using std::exp;
  return d.mu <= 0 ? Real(0) : Real(exp(log_restitution(d)));
}

// f(p) = √(2(p+1)): α = f(p)·α_eff.
template <SupportedReal Real>
Real alpha_per_alpha_eff(const Real& p) {
  using std::sqrt;
  return sqrt(2 * (p + 1));
}

// ---- Peak and force-capped end (MATH.md §3 "Peak", §4) ---------------------------------------

// Overdamped beyond |μ|/z² ≥ 1/16 (z ≥ 1.033), the peak phase in the form that keeps its digits:
// tanh(rσ) = r/z at the peak (r = √−μ) and r/z = tanh(asinh r), so σ_peak = asinh(r)/r. The
// regime-free atan_rf(μ/z²) = atanh(r/z)/(r/z) is the same number, but r/z → 1 − 1/(2z²) and
// atanh there carries the rounding of its argument as ε·2z²: 4e−5 relative in δ_max at
// z = 10⁶ in double, 7e13 ε in float128 (found by a hostile trial; MATH.md §3 "Peak").
template <SupportedReal Real>
bool far_overdamped(const Damping<Real>& d) {
  return d.mu < 0 && -d.mu >= d.z * d.z / 16;
}
template <SupportedReal Real>
Real far_overdamped_peak_phase(const Damping<Real>& d) {
  using std::asinh;
  using std::sqrt;
  const Real r = sqrt(-d.mu); // −μ = (z − 1)(z + 1), formed without cancellation
  return asinh(r) / r;
}

// G = z Ω0 s_peak (MATH.md §3): z·atan2(√μ, z)/√μ while μ > ¼, atan_rf(μ/z²) near critical damping
// (analytic through z = 1), z·asinh(r)/r far overdamped (above). Not atan_rf(μ/z²) as z → 0: z²
// underflows (below √min, 1.5e-154 in double; subnormal, it holds a few bits) and μ/z² overflows,
// and atan_rf(∞) = 0 made G, E_load and the normal force's peak 0 there. z multiplies last: a
// subnormal z is rounded once. 0 at z = 0.
template <SupportedReal Real>
Real peak_exponent(const Damping<Real>& d) {
  using std::atan2;
  using std::sqrt;
  if (d.mu > Real(1) / 4) {
    const Real root_mu = sqrt(d.mu);
    return d.z * Real(atan2(root_mu, d.z) / root_mu);
  }
  if (far_overdamped(d)) {
    return d.z * far_overdamped_peak_phase(d);
  }
  return atan_rf(Real(d.mu / (d.z * d.z)));
}

// σ_peak = Ω0 s_peak: atan2(√μ, z)/√μ while μ > ¼ (finite as z → 0, where G/z is 0/0),
// asinh(r)/r far overdamped, G/z between.
template <SupportedReal Real>
Real peak_phase(const Damping<Real>& d) {
  using std::atan2;
  using std::sqrt;
  if (d.mu > Real(1) / 4) {
    const Real root_mu = sqrt(d.mu);
    return atan2(root_mu, d.z) / root_mu;
  }
  if (far_overdamped(d)) {
    return far_overdamped_peak_phase(d);
  }
  return peak_exponent(d) / d.z;
}

// The capped contact ends where the total force, ∝ x''(s), first vanishes after the peak (§4):
// tan(√μσ_c) = 2z√μ/(2z² − 1), i.e. cos(√μσ_c) = 2z² − 1 = cos(2 acos z). With cos θ_p = z,
// sin θ_p = √μ at the peak angle θ_p = √μ σ_peak this is exactly
//     σ_c = 2 σ_peak,
// and the exit speed x'(s_c)/v0 = e^(−2G) [cos 2θ_p − (z/√μ) sin 2θ_p] = −e^(−2G) (z² + μ), so
//     e_cap = e^(−2G) = (x_max/L)²,
// for every z (the overdamped case follows by continuation to cosh/sinh). This is MATH.md §4's
// e_cap in a form without cancellation; the tests check it against §4's angle formulas.
template <SupportedReal Real>
Real capped_cut_phase(const Damping<Real>& d) {
  return 2 * peak_phase(d);
}

template <SupportedReal Real>
Real capped_restitution(const Damping<Real>& d) {
  using std::exp;
  return exp(-2 * peak_exponent(d));
}

// The peak of the total normal force F = k δ^p + α√(mk) δ^((p−1)/2) δ' (MATH.md §3, "Peak
// normal force"). With r = S/C (S = sin(√μσ)/√μ, C = cos(√μσ), regime-free), F = k δ^p
// (1 − 2z² + 2z/r), and dF/ds = 0 is a quadratic in r. It is solved for u = z r, which stays in
// [0, 1] for every z (r ~ 1/z as z → 0, and μr² overflowed below z = 1e-154 in double, which
// made the peak σ = 0 and F_max = 0):
//     P(u) = a u² + b u + c0 = 0,
//     a = 4z² − 3 − (1 − q)(1 − 2z²),  b = (2 − q)(1 − 4z²),  c0 = 2(1 − q) z².
// P(0) = c0 ≥ 0 and P(1) = −2 < 0 (u = 1 is the overlap's peak, x' = 0), so exactly one root lies
// in (0, 1): the force peaks before the overlap does. Both roots are formed without cancellation
// (t = −(b + sgn(b)√D)/2, roots t/a and c0/t); c0 may underflow, the root in (0, 1) is then −b/a.
// For p = 1 (c0 = 0) and z ≥ ½ the root is u = 0: the force is largest at the onset, F = c v0 (the
// dashpot's jump). Then σ_F = atan(√μ r)/√μ = atan2(√μ u, z)/√μ while μ > ¼ (as σ_peak), and
// r·atan_rf(μr²) beyond, and F_max = k δ_F^p (1 − 2z² + 2z²/u).
template <SupportedReal Real>
struct NormalForcePeak {
  Real sigma;        // Ω0 s at the peak: 0 at the onset, σ_peak for z = 0
  Real scaled_ratio; // u = z r = zS/C there: 0 at the onset, 1 for z = 0 (the overlap's peak)
};

template <SupportedReal Real>
NormalForcePeak<Real> normal_force_peak(const Damping<Real>& d, const Real& q,
                                        const Real& one_minus_q) {
  using std::atan2;
  using std::sqrt;
  const Real z = d.z;
  if (z == 0) {
    return {peak_phase(d), Real(1)};
  }
  const Real z2 = z * z;
  const Real a = 4 * z2 - 3 - one_minus_q * (1 - 2 * z2);
  const Real b = (2 - q) * (1 - 4 * z2);
  const Real c0 = 2 * one_minus_q * z2; // from (p − 1)/(p + 1): 0 at p = 1 + 2^−52 from 1 − q
  const Real root_d = sqrt(b * b - 4 * a * c0); // ≥ 0: a root exists (above)
  const Real t = -(b + (b < 0 ? -root_d : root_d)) / 2;
  Real u(0);
  for (const Real& candidate :
       {a != 0 ? Real(t / a) : Real(-1), t != 0 ? Real(c0 / t) : Real(-1)}) {
    if (candidate > 0 && candidate < 1) {
      u = candidate;
    }
  }
  if (d.mu > Real(1) / 4) {
    const Real root_mu = sqrt(d.mu);
    return {Real(atan2(root_mu * u, z) / root_mu), u};
  }
  // z ≥ √3/2 here: r = u/z neither over- nor underflows. σ = atan(√μ r)/√μ, regime-free.
  const Real r = u / z;
  return {r * atan_rf(Real(d.mu * r * r)), u};
}

// e_cap falls only like 1/(2z)² (G ≈ ln 2z): below its value at the domain's largest α_eff no
// damping reaches it. Said so, not as the bracket's α_eff out of range (it said "alpha_eff must be
// in [0, 1e6] (got 1048576)", a number the user never gave).
template <SupportedReal Real>
void require_reachable_e_cap(const Real& e_cap) {
  require_finite("e", e_cap);
  require(e_cap > 0 && e_cap <= 1, "e must be in (0, 1]", e_cap);
  const Real least = capped_restitution(damping_from_alpha_eff(Real(domain::alpha_eff_max)));
  require(e_cap >= least,
          "e at the force end must be >= " + to_string_full(least) +
              ", what the largest alpha_eff, 1e6, gives",
          e_cap);
}

// Numeric inverse of the monotone e_cap(z) = e^(−2G(z)): TOMS 748 on G(z) = −½ ln e_cap,
// bracketed by doubling z (G grows like ln z when overdamped).
template <SupportedReal Real>
Damping<Real> damping_from_e_cap(const Real& e_cap) {
  using std::log;
  require_reachable_e_cap(e_cap);
  if (e_cap == 1) {
    return {Real(0), Real(1)};
  }
  const Real target = -log(e_cap) / 2;
  auto residual = [&](const Real& z) { return peak_exponent(damping_from_alpha_eff(z)) - target; };
  const Real most = Real(domain::alpha_eff_max);
  Real lo(0);
  Real hi(1);
  while (residual(hi) < 0) {
    if (hi == most) { // e_cap within a rounding of the least reachable: that least is its α_eff
      return damping_from_alpha_eff(most);
    }
    lo = hi;
    hi = 2 * hi < most ? Real(2 * hi) : most;
  }
  boost::math::tools::eps_tolerance<Real> converged(std::numeric_limits<Real>::digits - 2);
  std::uintmax_t max_iterations = 400;
  const auto [a, b] =
      boost::math::tools::toms748_solve(residual, lo, hi, converged, max_iterations);
  return damping_from_alpha_eff(Real((a + b) / 2));
}

// ---- The contact -----------------------------------------------------------------------------

// The type a calibration is formed in before it is rounded once to Real: the narrowest with 30
// digits (float128 where the build has it), or Real itself when that is as wide (MATH.md §3
// "One α"). A double contact from e then holds the α `pldamp calibrate` prints, bit for bit.
template <SupportedReal Real>
using CalibrationReal = std::conditional_t<(std::numeric_limits<Real>::digits <
                                            std::numeric_limits<NarrowestWithDigits10<30>>::digits),
                                           NarrowestWithDigits10<30>, Real>;

namespace detail {
// x rounded once to Real when every number within `slack` of x rounds to the same Real (rounding
// is monotone, so both ends agreeing decides the whole interval); none when the interval holds a
// rounding boundary.
template <SupportedReal Real, class Wide>
std::optional<Real> rounding_decided(const Wide& x, const Wide& slack) {
  const Real low = static_cast<Real>(x - slack), high = static_cast<Real>(x + slack);
  return low == high ? std::optional<Real>(low) : std::nullopt;
}
} // namespace detail

template <SupportedReal Real>
class Contact {
public:
  // α as given (alpha() returns it, not its round trip through α_eff); α_eff = α/√(2(p+1)) in Real.
  static Contact from_alpha(const Real& p, const Real& alpha, const Real& v0,
                            const Real& m = Real(1), const Real& k = Real(1)) {
    domain::require_p(p);
    domain::require_alpha(alpha);
    return Contact(p, damping_from_alpha_eff(Real(alpha / alpha_per_alpha_eff(p))), alpha, v0, m,
                   k);
  }
  // α_eff as given; α = √(2(p+1)) α_eff formed in CalibrationReal and rounded once.
  static Contact from_alpha_eff(const Real& p, const Real& z, const Real& v0,
                                const Real& m = Real(1), const Real& k = Real(1)) {
    domain::require_p(p);
    const Damping<Real> d = damping_from_alpha_eff(z);
    return Contact(p, d, alpha_of(p, d.z), v0, m, k);
  }
  // e is the restitution the contact really gives under `end`: at the overlap end the closed-form
  // inverse of §3, at the force end the numeric inverse of e_cap (§4). Calibrated in
  // CalibrationReal and rounded once: α_eff, μ and α are each within half an ulp of the exact.
  static Contact from_e(const Real& p, const Real& e, const Real& v0, const Real& m = Real(1),
                        const Real& k = Real(1), ContactEnd end = ContactEnd::overlap) {
    domain::require_p(p);
    // Refused in Real first, so that the message quotes e as the caller's type prints it.
    if (end == ContactEnd::overlap) {
      require_finite("e", e);
      require(e > 0 && e <= 1, "e must be in (0, 1]", e);
    } else {
      require_reachable_e_cap(e);
    }
    if constexpr (std::is_same_v<Real, double> && std::numeric_limits<long double>::digits >= 64) {
      // The overlap end's closed form in long double first (30 ns against 0.9 µs in float128):
      // its α_eff, μ and α are within a few ulps of long double (log, sqrt, a division, a
      // product), 2^-11 of a double's. Where the interval of 32 such ulps about each rounds to one
      // double, that double is also the float128 value's rounding; else (about 3 % of e) float128
      // decides. Tested against the float128 path over 10^5 random (p, e).
      if (end == ContactEnd::overlap) {
        using std::fabs;
        const Damping<long double> quick = damping_from_e(static_cast<long double>(e));
        const long double alpha = quick.z * alpha_per_alpha_eff(static_cast<long double>(p));
        const long double ulps = 32 * std::numeric_limits<long double>::epsilon();
        const auto z = detail::rounding_decided<double>(quick.z, ulps * fabs(quick.z));
        const auto mu = detail::rounding_decided<double>(quick.mu, ulps * fabs(quick.mu));
        const auto a = detail::rounding_decided<double>(alpha, ulps * fabs(alpha));
        if (z && mu && a) {
          return Contact(p, Damping<Real>{*z, *mu}, *a, v0, m, k);
        }
      }
    }
    return calibrated_wide(p, e, v0, m, k, end);
  }
  static Contact from_damping(const Real& p, const Damping<Real>& d, const Real& v0,
                              const Real& m = Real(1), const Real& k = Real(1)) {
    domain::require_p(p);
    return Contact(p, d, alpha_of(p, d.z), v0, m, k);
  }

  const Real& p() const { return p_; }
  const Real& m() const { return m_; }
  const Real& k() const { return k_; }
  const Real& v0() const { return v0_; }
  const Damping<Real>& damping() const { return damping_; }
  const Real& alpha_eff() const { return damping_.z; } // z
  const Real& mu() const { return damping_.mu; }       // 1 − z²
  const Real& alpha() const { return alpha_; }
  const Real& q() const { return q_; }                     // 2/(p+1)
  const Real& one_minus_q() const { return one_minus_q_; } // (p − 1)/(p + 1), −ν
  Real nu() const { return q_ - 1; }                       // exponent of dt/ds = A q x^(q−1)
  const Real& A() const { return A_; }                     // ((p+1)/2)^(1/(p+1))
  const Real& omega0() const { return omega0_; }           // √(k/m)
  const Real& L() const { return L_; }                     // v0/Ω0
  const Real& log_L() const { return log_L_; }
  Real ke0() const { return m_ * v0_ * v0_ / 2; }

private:
  // from_e's calibration in CalibrationReal, rounded once (what the long double pass agrees with).
  static Contact calibrated_wide(const Real& p, const Real& e, const Real& v0, const Real& m,
                                 const Real& k, ContactEnd end) {
    using Wide = CalibrationReal<Real>;
    const Wide wide_p(p), wide_e(e); // exact: Wide holds every Real
    const Damping<Wide> wide =
        end == ContactEnd::overlap ? damping_from_e(wide_e) : damping_from_e_cap(wide_e);
    return Contact(p, Damping<Real>{static_cast<Real>(wide.z), static_cast<Real>(wide.mu)},
                   static_cast<Real>(wide.z * alpha_per_alpha_eff(wide_p)), v0, m, k);
  }
  static Real alpha_of(const Real& p, const Real& z) {
    using Wide = CalibrationReal<Real>;
    return static_cast<Real>(Wide(z) * alpha_per_alpha_eff(Wide(p)));
  }
  Contact(const Real& p, const Damping<Real>& d, const Real& alpha, const Real& v0, const Real& m,
          const Real& k)
      : p_(p), m_(m), k_(k), v0_(v0), damping_(d), alpha_(alpha) {
    using std::log;
    using std::pow;
    using std::sqrt;
    domain::require_scale("v0", v0);
    domain::require_scale("m", m);
    domain::require_scale("k", k);
    q_ = 2 / (p + 1);
    one_minus_q_ = (p - 1) / (p + 1); // not 1 − q: as p → 1 that keeps only ε/(p − 1) of it
    A_ = pow((p + 1) / 2, 1 / (p + 1));
    omega0_ = sqrt(k / m);
    L_ = v0 * sqrt(m / k);
    // Powers of L are taken as exp(a·ln L), so that L^q·e^(−qG) and the like never form an
    // intermediate that leaves the range of the type for extreme v0, m, k (MATH.md §8).
    log_L_ = log(L_);
  }
  Real p_, m_, k_, v0_;
  Damping<Real> damping_;
  Real alpha_;
  Real q_, one_minus_q_, A_, omega0_, L_, log_L_;
};

} // namespace pldamp::analytic
