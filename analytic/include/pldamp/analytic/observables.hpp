// The closed-form observables of MATH.md §3 (e, δ_max, the spring force there, the peak normal
// force and its time, t_peak, energies, τ, τ0, τ/τ0),
// §4 (e_cap and the cut time t_c) and §6 (the seed's Δt_crit and the tangent-stiffness bound),
// singly or as a bundle that computes only what is asked.
//
// G and σ_peak are in contact.hpp, beside e_cap = e^(−2G) which they also give. Powers of L go
// through ln L so nothing over- or underflows before the final exp.
#pragma once

#include "pldamp/analytic/contact.hpp"
#include "pldamp/analytic/time.hpp"

#include <boost/math/special_functions/expm1.hpp>
#include <boost/math/special_functions/trigamma.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>

namespace pldamp::analytic {

// ---- single observables ---------------------------------------------------------------------

template <SupportedReal Real>
Real restitution(const Contact<Real>& c) {
  return restitution(c.damping());
}

template <SupportedReal Real>
Real log_delta_max(const Contact<Real>& c) {
  using std::log;
  return log(c.A()) + c.q() * (c.log_L() - peak_exponent(c.damping()));
}

template <SupportedReal Real>
Real delta_max(const Contact<Real>& c) {
  using std::exp;
  return c.A() * exp(c.q() * (c.log_L() - peak_exponent(c.damping())));
}

// A^p = ((p+1)/2)^(p/(p+1)), whose logarithm is formed directly: p·ln A would carry the rounding
// of A p-fold (5 ε at p = 10) into the forces k δ^p.
template <SupportedReal Real>
Real log_A_to_the_p(const Contact<Real>& c) {
  using std::log;
  return c.p() / (c.p() + 1) * log((c.p() + 1) / 2);
}

// The spring (elastic) force k δ^p, largest at δ_max: k A^p e^(pq(ln L − G)). Not the largest
// force: the total normal force peaks earlier and higher (normal_force_max).
template <SupportedReal Real>
Real spring_force_max(const Contact<Real>& c) {
  using std::exp;
  return c.k() * exp(log_A_to_the_p(c) + c.p() * c.q() * (c.log_L() - peak_exponent(c.damping())));
}

// The peak of the total normal force k δ^p + α√(mk) δ^((p−1)/2) δ' (MATH.md §3, "Peak normal
// force"): k δ_F^p (1 − 2z² + 2z²/u) at σ_F (contact.hpp, normal_force_peak; u = z r), with
// δ_F^p = A^p (L ξ_F)^(pq) formed by pow, not through ln L: pq = 2p/(p+1) < 2 keeps L^(pq) within
// range over the domain's scales, and exp(pq ln L) would cost |pq ln L| ulps (1.2e-14 in double
// at v0 = 1e-6). At the onset (p = 1, z ≥ ½) the dashpot's c v0 = 2z k L.
template <SupportedReal Real>
Real normal_force_max(const Contact<Real>& c) {
  using std::exp;
  using std::pow;
  const Damping<Real>& d = c.damping();
  const NormalForcePeak<Real> peak = normal_force_peak(d, c.q(), c.one_minus_q());
  if (peak.scaled_ratio == 0) {
    return 2 * d.z * c.k() * c.L();
  }
  if (d.z == 0) {
    return spring_force_max(c);
  }
  const Real xi =
      exp(-d.z * peak.sigma) * peak.sigma * sinc_rf(Real(d.mu * peak.sigma * peak.sigma));
  const Real pq = c.p() * c.q();
  return c.k() * exp(log_A_to_the_p(c)) * pow(c.L(), pq) * pow(xi, pq) *
         (1 - 2 * d.z * d.z + 2 * d.z * d.z / peak.scaled_ratio);
}

// The time of that peak, t = T·I(σ_F) (time.hpp); 0 at the onset.
template <SupportedReal Real>
Real t_normal_force_max(const Contact<Real>& c) {
  using std::exp;
  const ScaledTime<Real> scaled(c.damping(), c.q());
  return exp(log_time_scale(c)) *
         scaled(normal_force_peak(c.damping(), c.q(), c.one_minus_q()).sigma);
}

// ln of the time scale T = A q L^ν / Ω0 with t = T·I(σ) (time.hpp).
template <SupportedReal Real>
Real log_time_scale(const Contact<Real>& c) {
  using std::log;
  return log(c.A() * c.q() / c.omega0()) + c.nu() * c.log_L();
}

template <SupportedReal Real>
Real t_peak(const Contact<Real>& c) {
  using std::exp;
  const ScaledTime<Real> scaled(c.damping(), c.q());
  return exp(log_time_scale(c)) * scaled(peak_phase(c.damping()));
}

// E_load = KE0 (1 − e^(−2G)), by expm1 so it keeps its digits as z → 0.
template <SupportedReal Real>
Real energy_load(const Contact<Real>& c) {
  return -c.ke0() * boost::math::expm1(Real(-2 * peak_exponent(c.damping())));
}

// E_unload = KE0 (e^(−2G) − e²) = −KE0 e^(−2G) expm1(2(G + ln e)), where
// G + ln e = −z·atan2(√μ, −z)/√μ (the unloading phase angle, no cancellation as z → 0);
// KE0 e^(−2G) when z ≥ 1 (all remaining energy, as t → ∞).
template <SupportedReal Real>
Real energy_unload(const Contact<Real>& c) {
  using std::atan2;
  using std::exp;
  using std::sqrt;
  const Damping<Real>& d = c.damping();
  const Real remaining = c.ke0() * exp(-2 * peak_exponent(d));
  if (d.mu <= 0) {
    return remaining;
  }
  const Real root_mu = sqrt(d.mu);
  const Real g_plus_log_e = -d.z * atan2(root_mu, -d.z) / root_mu;
  return -remaining * boost::math::expm1(Real(2 * g_plus_log_e));
}

namespace detail {

// Near z = 1, ln τ and ln(τ/τ0) grow like π c with c = (1 − q) z/√μ, and one ulp of a logarithm
// of size 50 is already 1e−14 of τ in double (1e−32 in float128). Once c > 5/2 (an exponent above
// about 8) they are therefore summed in a wider type: long double for double (x87: 11 more bits),
// cpp_bin_float_50 for long double and float128 (long double as it was: ε·ln τ, 350 ε at p = 2,
// z = 1 − 1e−6, 1100 ε at p = 1000, found by an accuracy hunt). cpp_bin_float_50 meets its bounds
// as it is.
template <SupportedReal Real>
struct DurationWidening {
  using type = Real;
};
template <>
struct DurationWidening<long double> {
  using type = bin50;
};
template <>
struct DurationWidening<double> {
  using type =
      std::conditional_t<(std::numeric_limits<long double>::digits > 53), long double, double>;
};
#if PLDAMP_WITH_QUAD
template <>
struct DurationWidening<quad> {
  using type = bin50;
};
#endif

template <SupportedReal Real>
using DurationWide = typename DurationWidening<Real>::type;

template <SupportedReal Real>
bool widen_duration_exponent(const Contact<Real>& c) {
  using std::sqrt;
  return -c.nu() * c.alpha_eff() > Real(5) / 2 * sqrt(c.mu());
}

template <SupportedReal Real, class Wide>
Real narrowed(const Wide& value) {
  if constexpr (std::is_floating_point_v<Wide>) {
    return static_cast<Real>(value);
  } else {
    return value.template convert_to<Real>();
  }
}

template <SupportedReal Real>
struct Duration {
  Real tau, ratio, log_tau; // τ, τ/τ0 and ln τ
};

// τ, τ/τ0 and ln τ from ln τ0 and one ln(τ/τ0), which is summed in the wider type when it is
// large (it needs no Γ but the ratio of special.hpp, cheap in any type); +∞ for z ≥ 1. ln τ stays
// finite where τ itself overflows the type (near z = 1).
template <SupportedReal Real>
Duration<Real> duration_and_ratio(const Contact<Real>& c, const Real& log_tau0) {
  using std::exp;
  if (c.mu() <= 0) {
    const Real inf = std::numeric_limits<Real>::infinity();
    return {inf, inf, inf};
  }
  if constexpr (!std::is_same_v<DurationWide<Real>, Real>) {
    if (widen_duration_exponent(c)) {
      using W = DurationWide<Real>;
      const W log_ratio =
          log_duration_ratio(Damping<W>{W(c.alpha_eff()), W(c.mu())}, W(2 / (W(c.p()) + 1)),
                             W((W(c.p()) - 1) / (W(c.p()) + 1)));
      const W log_tau = W(log_tau0) + log_ratio;
      return {narrowed<Real>(exp(log_tau)), narrowed<Real>(exp(log_ratio)),
              narrowed<Real>(log_tau)};
    }
  }
  const Real log_ratio = log_duration_ratio(c.damping(), c.q(), c.one_minus_q());
  return {exp(log_tau0 + log_ratio), exp(log_ratio), log_tau0 + log_ratio};
}

} // namespace detail

// ln τ0 = ln T + ln B(q/2, ½).
template <SupportedReal Real>
Real log_undamped_duration(const Contact<Real>& c) {
  return log_time_scale(c) + log_undamped_scaled_duration(c.q());
}

// τ0 = (2A/((p+1)Ω0)) L^(q−1) B(1/(p+1), ½).
template <SupportedReal Real>
Real undamped_duration(const Contact<Real>& c) {
  using std::exp;
  return exp(log_undamped_duration(c));
}

// τ in closed form (MATH.md §3), as τ0·(τ/τ0); +∞ for z ≥ 1.
template <SupportedReal Real>
Real contact_duration(const Contact<Real>& c) {
  return detail::duration_and_ratio(c, log_undamped_duration(c)).tau;
}

template <SupportedReal Real>
Real duration_ratio(const Contact<Real>& c) {
  return detail::duration_and_ratio(c, Real(0)).ratio;
}

// Small damping (MATH.md §3): ln(τ/τ0) = s1·z + s2·z² + O(z³) with s1 = (π/2)(1 − q), the first
// order that makes τ/τ0 grow linearly in α_eff for p > 1, and s2 = q/2 + (1 − q)²ψ'(a)/4,
// a = (1 + q)/2. So τ/τ0 = 1 + s1·z + (s2 + s1²/2)·z² + O(z³).
template <SupportedReal Real>
Real duration_ratio_slope(const Real& p) {
  return boost::math::constants::half_pi<Real>() * ((p - 1) / (p + 1)); // 1 − q
}

// The z² coefficient of τ/τ0 itself: s2 + s1²/2.
template <SupportedReal Real>
Real duration_ratio_curvature(const Real& p) {
  const Real q = 2 / (p + 1);
  const Real s1 = duration_ratio_slope(p);
  const Real one_minus_q = (p - 1) / (p + 1);
  return q / 2 + one_minus_q * one_minus_q * boost::math::trigamma((1 + q) / 2) / 4 + s1 * s1 / 2;
}

template <SupportedReal Real>
Real capped_restitution(const Contact<Real>& c) {
  return capped_restitution(c.damping());
}

// I(σ_c) for the cut at σ_c = 2σ_peak. Near the end of an underdamped contact dt/ds is infinite,
// so there the cut's distance to the end, σ_end − 2σ_peak = 2·atan2(z, √μ)/√μ, is formed directly
// rather than by subtracting (at z = 0 it is exactly 0 and t_c = τ).
template <SupportedReal Real>
Real scaled_cut_time(const Damping<Real>& d, const ScaledTime<Real>& scaled) {
  using std::atan2;
  using std::sqrt;
  if (d.mu > Real(1) / 4) {
    const Real root_mu = sqrt(d.mu);
    return scaled.before_end(Real(2 * atan2(d.z, root_mu) / root_mu));
  }
  return scaled(capped_cut_phase(d));
}

// t_c = T·I(σ_c): the time at which the total force of a capped contact reaches zero.
template <SupportedReal Real>
Real cut_time(const Contact<Real>& c) {
  using std::exp;
  const ScaledTime<Real> scaled(c.damping(), c.q());
  return exp(log_time_scale(c)) * scaled_cut_time(c.damping(), scaled);
}

// The seed's Δt_crit = (4/(p+1)) A Ω0⁻¹ L^(−(p−1)/(p+1)) = 2T (MATH.md §6).
template <SupportedReal Real>
Real dt_crit_seed(const Contact<Real>& c) {
  using std::exp;
  return 2 * exp(log_time_scale(c));
}

// Central-difference bound with the tangent stiffness at the undamped peak δ0 = A L^q:
// 2 / (Ω0 √(p δ0^(p−1))) (MATH.md §6). (p − 1) ln δ0 = (1 − q)(ln((p + 1)/2) + 2 ln L), since
// A^(p+1) = (p + 1)/2 and (p − 1) q = 2(1 − q): from the rounded A, (p − 1) ln A carried A's
// rounding p-fold (p/8 ε at p = 1000).
template <SupportedReal Real>
Real dt_crit_tangent(const Contact<Real>& c) {
  using std::exp;
  using std::log;
  const Real p_minus_1_log_delta0 = c.one_minus_q() * (log((c.p() + 1) / 2) + 2 * c.log_L());
  return 2 / c.omega0() * exp(-(log(c.p()) + p_minus_1_log_delta0) / 2);
}

// ---- the bundle -----------------------------------------------------------------------------

enum Want : unsigned {
  want_e = 1u << 0,
  want_delta_max = 1u << 1,
  want_t_peak = 1u << 2,
  want_tau = 1u << 3, // τ, ln τ, τ0, τ/τ0
  want_energy = 1u << 4,
  want_spring_force_max = 1u << 5,
  want_dt_crit = 1u << 6,      // seed and tangent bounds
  want_capped = 1u << 7,       // e_cap, t_cut
  want_normal_force = 1u << 8, // the peak normal force and its time
  want_all = (1u << 9) - 1,
};

template <SupportedReal Real>
struct Observables {
  std::optional<Real> e, log_e, delta_max, spring_force_max, normal_force_max, t_normal_force_max,
      t_peak, tau, log_tau, tau0, tau_ratio, energy_load, energy_unload, dt_crit, dt_tangent, e_cap,
      t_cut;
};

// Computes exactly the observables in `want`; the rest stay empty.
template <SupportedReal Real>
Observables<Real> observables(const Contact<Real>& c, unsigned want = want_all) {
  using std::exp;
  Observables<Real> out;
  if (want & want_e) {
    out.log_e = log_restitution(c.damping());
    out.e = restitution(c.damping());
  }
  if (want & want_delta_max) {
    out.delta_max = delta_max(c);
  }
  if (want & want_spring_force_max) {
    out.spring_force_max = spring_force_max(c);
  }
  if (want & want_normal_force) {
    out.normal_force_max = normal_force_max(c);
  }
  if (want & (want_t_peak | want_capped | want_normal_force)) {
    const ScaledTime<Real> scaled(c.damping(), c.q());
    const Real scale = exp(log_time_scale(c));
    if (want & want_normal_force) {
      out.t_normal_force_max =
          scale * scaled(normal_force_peak(c.damping(), c.q(), c.one_minus_q()).sigma);
    }
    if (want & want_t_peak) {
      out.t_peak = scale * scaled(peak_phase(c.damping()));
    }
    if (want & want_capped) {
      out.e_cap = capped_restitution(c.damping());
      out.t_cut = scale * scaled_cut_time(c.damping(), scaled);
    }
  }
  if (want & want_tau) {
    const Real log_tau0 = log_undamped_duration(c);
    out.tau0 = exp(log_tau0);
    const detail::Duration<Real> duration = detail::duration_and_ratio(c, log_tau0);
    out.tau = duration.tau;
    out.tau_ratio = duration.ratio;
    out.log_tau = duration.log_tau;
  }
  if (want & want_energy) {
    out.energy_load = energy_load(c);
    out.energy_unload = energy_unload(c);
  }
  if (want & want_dt_crit) {
    out.dt_crit = dt_crit_seed(c);
    out.dt_tangent = dt_crit_tangent(c);
  }
  return out;
}

} // namespace pldamp::analytic
