// The parametric time-domain solution (MATH.md §2, §3 "Time-domain solution"), all regimes.
//
// In the LSD parameter s (σ = Ω0 s):  x(s) = v0 e^(−zσ) S(s),  δ(s) = A x^q,  v(s) = x'(s),
// t(s) = ∫₀^s A q x^(q−1) ds (time.hpp), elastic force k δ^p, damping force α√(mk) δ^((p−1)/2) v.
// S, C are the regime-free sine and cosine of MATH.md §2 (special.hpp), smooth through z = 1.
// δ(t) for a given t solves t(s) = t by safeguarded Newton (dt/ds = A q x^(q−1) is known).
// Underdamped contacts end at s_end = π/Ω1; overdamped and critical ones never end (s → ∞).
//
// Every t > 0 a type holds gives a finite state (MATH.md §3, "Its ends"): near the onset, where
// s ∝ t^((p+1)/2) underflows first, the series of trajectory_ends.hpp (OnsetSeries); in a decay
// that never returns (p > 1), t(s) in the factored form e^(κσ) G(σ) and δ from ϑ f/G
// (SlowDecay), up to t = ∞; ξ and its powers go through logarithms where they leave the range.
// What truly underflows comes back as 0 (v as ±0).
#pragma once

#include "pldamp/analytic/observables.hpp"
#include "pldamp/analytic/trajectory_ends.hpp"

#include <boost/math/tools/roots.hpp>
#include <boost/math/tools/toms748_solve.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace pldamp::analytic {

template <SupportedReal Real>
struct TrajectoryPoint {
  Real s, t, delta, v, force_elastic, force_damping;
  bool in_contact;
};

template <SupportedReal Real>
struct PhasePoint {
  Real delta, v;
};

template <SupportedReal Real>
class Trajectory {
public:
  explicit Trajectory(const Contact<Real>& c)
      : c_(c), scaled_(c.damping(), c.q()), log_time_scale_(log_time_scale(c)),
        time_scale_(exp_(log_time_scale_)), onset_(c) {
    using std::log;
    if (c.mu() <= 0 && c.q() < 1) {
      slow_.emplace(c.damping(), c.q());
      // The creep's exponents, from p (exact for p = 3/2, 2, 3, 5): δ ∝ (ξ^ν)^(q/ν), ξ =
      // (ξ^ν)^(1/ν).
      delta_power_ = -2 / (c.p() - 1);
      xi_power_ = -(c.p() + 1) / (c.p() - 1);
    }
    log_delta_unit_ = log(c.A()) + c.q() * c.log_L(); // δ = A L^q ξ^q
    delta_unit_ = exp_(log_delta_unit_);
  }

  // LSD functions in physical units (MATH.md §2).
  Real S(const Real& s) const {
    const Real sigma = c_.omega0() * s;
    return sigma * sinc_rf(Real(mu() * sigma * sigma)) / c_.omega0();
  }
  Real C(const Real& s) const {
    const Real sigma = c_.omega0() * s;
    return cos_rf(Real(mu() * sigma * sigma));
  }
  Real x(const Real& s) const {
    const Real sigma = c_.omega0() * s;
    return decayed(sigma) ? Real(0) : Real(c_.L() * scaled_.xi(sigma));
  }
  Real x_dot(const Real& s) const {
    using std::exp;
    const Real sigma = c_.omega0() * s;
    if (decayed(sigma)) {
      return -Real(0);
    }
    if (late_in_decay(sigma)) {
      // e^(−zσ) C = e^(−λσ)(1 − rP), e^(−zσ) S = e^(−λσ) P with P = (1 − e^(−2rσ))/(2r) and
      // z + r = 1/λ: no e^(−zσ) → 0 times cosh → ∞ (MATH.md §3, "Its ends").
      return c_.v0() * exp(-slow_rate() * sigma) * velocity_factor(sigma);
    }
    const Real w = mu() * sigma * sigma;
    return c_.v0() * exp(-z() * sigma) * (cos_rf(w) - z() * sigma * sinc_rf(w));
  }
  Real x_ddot(const Real& s) const {
    using std::exp;
    const Real sigma = c_.omega0() * s;
    if (decayed(sigma)) {
      return Real(0);
    }
    if (late_in_decay(sigma)) {
      // e^(−zσ)(−2z C + (2z² − 1) S) = e^(−λσ)(P/λ² − 2z), as in x_dot with (z + r)² = 1/λ².
      return c_.v0() * c_.omega0() * exp(-slow_rate() * sigma) * acceleration_factor(sigma);
    }
    const Real w = mu() * sigma * sigma;
    return c_.v0() * c_.omega0() * exp(-z() * sigma) *
           (-2 * z() * cos_rf(w) + (2 * z() * z() - 1) * sigma * sinc_rf(w));
  }

  Real s_peak() const { return peak_phase(c_.damping()) / c_.omega0(); }
  // π/Ω1 when underdamped, +∞ otherwise.
  Real s_end() const { return scaled_.sigma_end() / c_.omega0(); }

  // t(s) for 0 ≤ s ≤ s_end (+∞ at s = +∞ when the contact never ends).
  Real time_at_parameter(const Real& s) const {
    using std::exp;
    using std::isfinite;
    using std::log;
    require_parameter(s);
    const Real sigma = c_.omega0() * s;
    if (!slow_ || sigma <= scaled_.piece_width()) {
      return time_scale_ * scaled_(sigma);
    }
    if (!isfinite(sigma)) {
      return sigma;
    }
    // T e^(κσ) G(σ): the rounding of κσ is t's own condition number, d ln t/d ln s ≈ κσ.
    const Real g = slow_->G(sigma);
    const Real t = time_scale_ * exp(slow_->rate() * sigma) * g;
    return isfinite(t) && t >= std::numeric_limits<Real>::min()
               ? t
               : Real(exp(log_time_scale_ + slow_->rate() * sigma + log(g)));
  }

  TrajectoryPoint<Real> at_parameter(const Real& s) const {
    require_parameter(s);
    return point(s, time_at_parameter(s));
  }

  // The state at physical time t ≥ 0. After an underdamped contact ends (t ≥ τ) the point is the
  // exit state: δ = 0, v = −e·v0, in_contact = false.
  TrajectoryPoint<Real> at_time(const Real& t) const {
    using std::log;
    require_finite("t", t);
    require(t >= 0, "t must be >= 0", t);
    if (t == 0) {
      return point(Real(0), Real(0));
    }
    const Real log_t = log(t);
    if (onset_.covers(log_t)) {
      return onset_point(t, log_t);
    }
    if (mu() > 0) {
      return underdamped_at(t);
    }
    if (slow_) {
      const Real log_theta = log_t - log_time_scale_;
      const auto [sigma, g] = slow_->solve(Real(t / time_scale_), log_theta);
      return decay_point(sigma, t, DecayTime{log_theta, g});
    }
    // p = 1: t = T σ, and s = t itself (dt/ds = A q x^(q−1) = 1), finite where σ = Ω0 s is not.
    TrajectoryPoint<Real> out = decay_point(Real(t / time_scale_), t, std::nullopt);
    out.s = t;
    return out;
  }

  std::vector<TrajectoryPoint<Real>> at_times(const std::vector<Real>& times) const {
    std::vector<TrajectoryPoint<Real>> out;
    out.reserve(times.size());
    for (const Real& t : times) {
      out.push_back(at_time(t));
    }
    return out;
  }

  // n ≥ 2 samples of (δ, v), uniform in s: loading and unloading up to s_end; when the contact
  // never ends, up to 20 decay lengths of the slow mode e^(−(z − √(z²−1))σ) past the peak.
  std::vector<PhasePoint<Real>> phase_portrait(int n) const {
    using std::sqrt;
    require(n >= 2, "phase portrait needs n >= 2", Real(n));
    Real sigma_stop = scaled_.sigma_end();
    if (!(sigma_stop < std::numeric_limits<Real>::infinity())) {
      sigma_stop = peak_phase(c_.damping()) + 20 / slow_rate();
    }
    std::vector<PhasePoint<Real>> out;
    out.reserve(n);
    for (int i = 0; i < n; ++i) {
      const Real s = sigma_stop * Real(i) / Real(n - 1) / c_.omega0();
      const TrajectoryPoint<Real> at = point(s, Real(0));
      out.push_back({at.delta, at.v});
    }
    return out;
  }

private:
  template <class T>
  static T exp_(const T& value) {
    using std::exp;
    return exp(value);
  }
  const Real& z() const { return c_.alpha_eff(); }
  const Real& mu() const { return c_.mu(); }

  void require_parameter(const Real& s) const {
    require(s >= 0 && s <= s_end(), "s must be in [0, s_end]", s);
  }

  // σ = +∞ (s = +∞, or Ω0 s beyond the type) of a contact that never returns: at rest at 0.
  bool decayed(const Real& sigma) const {
    return mu() <= 0 && !(sigma < std::numeric_limits<Real>::infinity());
  }

  // Overdamped and past rσ = 1, where e^(−zσ) cosh(rσ) would be 0·∞ far enough on: the decay's
  // slow-mode form instead (time.hpp's ξ does the same).
  bool late_in_decay(const Real& sigma) const {
    using std::sqrt;
    return mu() < 0 && sqrt(-mu()) * sigma > 1;
  }
  // λ = z − r = 1/(z + r), the slow rate (z = 1: 1).
  Real slow_rate() const {
    using std::sqrt;
    return 1 / (z() + sqrt(-mu()));
  }
  Real decay_P(const Real& sigma) const {
    using std::sqrt;
    return slow_mode_P(Real(sqrt(-mu())), sigma);
  }

  // 1 − P/λ (x' = v0 e^(−λσ)(1 − P/λ)) and P/λ² − 2z (x'' likewise), each in the form that
  // cancels less: with y = e^(−2rσ) and P = (1 − y)/(2r), u − wP = w(y − y0)/(2r) for
  // (w, u, y0) = (1/λ, 1, λ²) and (1/λ², 2z, λ⁴), since 2rλ − 1 = −λ² and 4zrλ² − 1 = −λ⁴. Both
  // forms vanish only at true zeros (the peak, the force's cut), but heavily overdamped
  // P → 1/(2r) ≈ λ and 1 − P/λ cancels all along the decay (300-fold at α_eff = 10), while near
  // critical damping 2r → 0 and the y-form cancels instead.
  Real velocity_factor(const Real& sigma) const {
    const Real lambda = slow_rate();
    return least_cancelling(sigma, Real(1 / lambda), Real(1), Real(lambda * lambda));
  }
  Real acceleration_factor(const Real& sigma) const {
    const Real lambda2 = slow_rate() * slow_rate();
    return -least_cancelling(sigma, Real(1 / lambda2), Real(2 * z()), Real(lambda2 * lambda2));
  }
  Real least_cancelling(const Real& sigma, const Real& w, const Real& u, const Real& y0) const {
    using std::abs;
    using std::exp;
    using std::max;
    using std::sqrt;
    const Real wp = w * decay_P(sigma);
    const Real p_form = u - wp;
    const Real r = sqrt(-mu());
    if (r == 0) {
      return p_form;
    }
    const Real y = exp(-2 * r * sigma);
    const Real y_form = w * (y - y0) / (2 * r);
    // Each form's rounding, relative: its operands' size over its value.
    return max(y, y0) / abs(y - y0) < max(u, wp) / abs(p_form) ? y_form : p_form;
  }

  // The underdamped inversion of t(s) (MATH.md §3), and the exit state from τ on.
  TrajectoryPoint<Real> underdamped_at(const Real& t) const {
    using std::exp;
    using std::log;
    const Real target = t / time_scale_;
    Real lo(0);
    Real hi = scaled_.sigma_end();
    const Real i_hi = scaled_.total();
    std::uintmax_t iterations = 200;
    const int digits = std::numeric_limits<Real>::digits - 2;
    if (target >= i_hi) {
      return exit_point(t);
    }
    // In the last piece, solve for the distance ρ to the end: δ ∝ ρ^q there, and a σ near
    // σ_end would keep only the absolute precision of σ_end.
    const Real last = scaled_.piece_width() < hi / 2 ? scaled_.piece_width() : Real(hi / 2);
    const Real i_last = scaled_.before_end(last);
    if (target > i_last) {
      return unloading_at(Real(i_hi - target), last, t);
    }
    hi -= last;
    auto residual = [&](const Real& sigma) {
      return std::make_pair(Real(scaled_(sigma) - target), scaled_.integrand(sigma));
    };
    // Early on I ≈ σ^q/q: from there rather than from the middle, which a small target would
    // leave by many bisections.
    const Real early = exp((log(target) + log(c_.q())) / c_.q());
    const Real guess = early < hi / 2 ? early : Real(hi / 2);
    Real sigma =
        boost::math::tools::newton_raphson_iterate(residual, guess, lo, hi, digits, iterations);
    using std::abs;
    if (!(abs(scaled_(sigma) - target) <=
          Real(64) * std::numeric_limits<Real>::epsilon() * target)) {
      // Newton did not settle on the root: TOMS 748 on the bracket, which always does.
      auto value = [&](const Real& x) { return Real(scaled_(x) - target); };
      std::uintmax_t more = 400;
      const auto [a, b] = boost::math::tools::toms748_solve(
          value, lo, hi, boost::math::tools::eps_tolerance<Real>(digits), more);
      sigma = a + (b - a) / 2;
    }
    return point(Real(sigma / c_.omega0()), t);
  }

  // The state at the distance ρ ≤ `last` from σ_end at which the time left, to_end(ρ), is
  // `left` (in units of T; MATH.md §3 "Its ends"). Near the end to_end(ρ) = (ρ^q/q) g0 (1 + O(ρ)),
  // g0 = e^(−νzσ_end): ρ ∝ left^(1/q), which for large p leaves the type while t is far from τ
  // (p = 1000 at t = 0.99τ: ρ ≈ 1e−1000), and a Newton step in ρ itself could not find
  // ρ = 1e−81 (p = 80) from a linear guess: δ came out 0.029 for 0.0118, at p = 1000 wrong by
  // 63-fold. So ρ is solved for in ln ρ, where ln to_end(ρ) is nearly linear (slope q); and where
  // ρ is below ε/(16(1 + z)), whatever the type holds, the exit form: with ρ^q = q·left/g0,
  // δ = A L^q (e^(−zσ_end) ρ)^q = A L^q q·left·e (q − ν = 1), i.e. δ = e v0 (τ − t), and
  // v = −e v0, each to 1 + O(ρ).
  TrajectoryPoint<Real> unloading_at(const Real& left, const Real& last, const Real& t) const {
    using std::exp;
    using std::isfinite;
    using std::log;
    if (scaled_.nu() == 0) { // p = 1: to_end(ρ) = ρ
      return point_before_end(std::min(left, last), t);
    }
    const Real q = c_.q();
    const Real sigma_end = scaled_.sigma_end();
    const Real log_g0 = -scaled_.nu() * z() * sigma_end;
    const Real log_rho0 = (log(Real(q * left)) - log_g0) / q;
    const Real eps = std::numeric_limits<Real>::epsilon();
    if (log_rho0 < log(Real(eps / (16 * (1 + z()))))) {
      const Real e = exp(-z() * sigma_end);
      const Real log_delta = log_delta_unit_ + log(q) + log(left) - z() * sigma_end;
      Real delta = delta_unit_ * q * left * e;
      if (!(isfinite(delta) && delta >= std::numeric_limits<Real>::min())) {
        delta = exp(log_delta);
      }
      TrajectoryPoint<Real> out{
          Real(sigma_end / c_.omega0()), t, delta, Real(-e * c_.v0()), Real(0), Real(0), true};
      add_forces(out, log_delta);
      return out;
    }
    // F(λ) = ln to_end(e^λ) − ln left, increasing; bracketed around λ0 (F ≈ q(λ − λ0) plus the
    // slow drift of g over the piece), its top at ln last.
    const Real log_left = log(left);
    const Real log_last = log(last);
    auto residual = [&](const Real& lambda) {
      return Real(log(scaled_.to_end(Real(exp(lambda)))) - log_left);
    };
    Real lo = log_rho0 - 1, hi = log_rho0 + 1 < log_last ? Real(log_rho0 + 1) : log_last;
    for (int step = 0; step < 64 && residual(lo) > 0; ++step) {
      lo -= Real(1 << std::min(step, 20)) / q;
    }
    for (int step = 0; step < 64 && hi < log_last && residual(hi) < 0; ++step) {
      hi = std::min(Real(hi + Real(1 << std::min(step, 20)) / q), log_last);
    }
    if (!(residual(hi) > 0)) { // left rounds to all of the last piece's time
      return point_before_end(last, t);
    }
    // TOMS 748 in λ to a few digits, then Newton in ρ itself inside that bracket: λ's own
    // tolerance would leave ρ only ε·|ln ρ| relative.
    const int digits = std::numeric_limits<Real>::digits - 2;
    std::uintmax_t iterations = 200;
    const auto [a, b] = boost::math::tools::toms748_solve(
        residual, lo, hi, boost::math::tools::eps_tolerance<Real>(digits / 4), iterations);
    auto in_rho = [&](const Real& rho) {
      return std::make_pair(Real(scaled_.to_end(rho) - left),
                            Real(scaled_.integrand_before_end(rho)));
    };
    const Real rho_lo = exp(std::min(a, b)), rho_hi = exp(std::max(a, b));
    if (!(rho_lo < rho_hi)) {
      return point_before_end(rho_lo, t);
    }
    iterations = 200;
    const Real rho = boost::math::tools::newton_raphson_iterate(
        in_rho, Real(rho_lo + (rho_hi - rho_lo) / 2), rho_lo, rho_hi, digits, iterations);
    return point_before_end(rho, t);
  }

  // At the onset (OnsetSeries): δ and v from the series, s from ξ = (δ/A)^(1/q)/L by the fixed
  // point σ = ξ e^(zσ)/sinc_rf(μσ²) in logarithms (σ ≈ ξ; each step gains a factor zσ ≪ 1).
  TrajectoryPoint<Real> onset_point(const Real& t, const Real& log_t) const {
    using std::exp;
    using std::log;
    const typename OnsetSeries<Real>::State state = onset_.at(t, log_t);
    const Real log_xi = (state.log_delta - log(c_.A())) / c_.q() - c_.log_L();
    Real sigma = exp(log_xi), log_sigma = log_xi;
    for (int step = 0; step < 8; ++step) {
      log_sigma = log_xi + z() * sigma - log(sinc_rf(Real(mu() * sigma * sigma)));
      const Real next = exp(log_sigma);
      if (next == sigma) {
        break;
      }
      sigma = next;
    }
    TrajectoryPoint<Real> out{
        exp(log_sigma - log(c_.omega0())), t, state.delta, state.v, Real(0), Real(0), true};
    add_forces(out, state.log_delta);
    return out;
  }

  // Given ϑ = t/T and G(σ) at the solution of e^(κσ) G(σ) = ϑ (SlowDecay::solve).
  struct DecayTime {
    Real log_theta, g;
  };

  // The state at σ of a contact that never returns (μ ≤ 0). From σ alone, ln ξ = −λσ + ln P and
  // δ = A (L ξ)^q, whose rounding of λσ costs ε·qλσ. Given the time as well and κσ > 1, from
  // ξ^ν = ϑ f/G instead: δ = A L^q (ϑ f/G)^(q/ν), ξ = (ϑ f/G)^(1/ν), one power of a number known to
  // a few ε (MATH.md §3, "Its ends").
  TrajectoryPoint<Real> decay_point(const Real& sigma, const Real& t,
                                    const std::optional<DecayTime>& time) const {
    using std::abs;
    using std::exp;
    using std::isfinite;
    using std::log;
    const Real s = sigma / c_.omega0();
    if (!isfinite(sigma)) { // t/T beyond the type: the decay is over
      return {s, t, Real(0), -Real(0), Real(0), Real(0), true};
    }
    const Real lambda = slow_rate();
    const Real p = decay_P(sigma);
    TrajectoryPoint<Real> out{s, t, Real(0), Real(0), Real(0), Real(0), true};
    // v = v0 e^(−λσ)(1 − P/λ) = v0 ξ (1 − P/λ)/P, of the sign of 1 − P/λ (< 0 past the peak).
    const Real factor = velocity_factor(sigma);
    const Real v_sign = factor < 0 ? Real(-1) : Real(1);
    Real log_delta;
    // ln(v0 |factor|), as a sum: v0 |factor| itself may overflow (factor = 1 − σ at z = 1).
    const Real log_v_unit = log(c_.v0()) + log(abs(factor));
    if (time && slow_->rate() * sigma > 1) {
      // ϑ f/G as t · (f/(G T)): t/T alone can leave the range where the product does not.
      const Real ratio = slow_->f_at(sigma) / time->g;
      const Real log_y = time->log_theta + log(ratio);
      const Real per_time = ratio / time_scale_;
      out.delta = power_of_product(delta_unit_, log_delta_unit_, t, per_time, log_y, delta_power_);
      log_delta = log_delta_unit_ + delta_power_ * log_y;
      out.v = v_sign * power_of_product(Real(c_.v0() * abs(factor) / p), Real(log_v_unit - log(p)),
                                        t, per_time, log_y, xi_power_);
    } else {
      // ξ = e^(−λσ) P and v = v0 e^(−λσ)(1 − P/λ) as products while they are normal numbers.
      const Real decay = exp(-lambda * sigma);
      const Real log_xi = -lambda * sigma + log(p);
      out.delta = power_of_product(delta_unit_, log_delta_unit_, decay, p, log_xi, c_.q());
      log_delta = log_delta_unit_ + c_.q() * log_xi;
      out.v = v_sign * power_of_product(Real(c_.v0() * abs(factor)), log_v_unit, decay, Real(1),
                                        Real(-lambda * sigma), Real(1));
    }
    add_forces(out, log_delta);
    return out;
  }

  // unit · (a b)^power (unit = e^log_unit > 0, a, b > 0, ln(a b) = log_y). In an IEEE type, the
  // first of these that stays in range: unit · pow(a b, power) while both are normal numbers
  // (three roundings); pow(a b unit^(1/power), power), rounded once where the result is
  // subnormal or a b leaves the range (through logarithms the exponent's rounding would cost
  // |ln result| ulps there); unit · a^power b^power; logarithms only where all of these leave
  // the range. In cpp_bin_float_50, whose own pow is not right to an ulp: split_power.
  static Real power_of_product(const Real& unit, const Real& log_unit, const Real& a, const Real& b,
                               const Real& log_y, const Real& power) {
    using std::isfinite;
    if constexpr (!std::is_same_v<detail::PowerWide<Real>, Real>) {
      if (unit > 0 && a > 0 && b > 0 && isfinite(unit) && isfinite(a) && isfinite(b)) {
        return split_power(unit, a, b, power);
      }
    }
    return power_in_range(unit, log_unit, a, b, log_y, power);
  }

  // unit · (a b)^power with the binary exponents split off exactly (frexp): the mantissas' power
  // in detail::PowerWide and 2^(e·power) as 2^⌊e·power⌋ 2^frac, exact where e·power is (as for
  // the creep's −2/(p−1) and −(p+1)/(p−1) at p = 3/2, 2, 3, 5). Free of PowerWide's range, which
  // stops 332 binary orders short of cpp_bin_float_50's.
  static Real split_power(const Real& unit, const Real& a, const Real& b, const Real& power) {
    using W = detail::PowerWide<Real>;
    using std::floor;
    using std::frexp;
    using std::ldexp;
    using std::pow;
    int e_unit = 0, e_a = 0, e_b = 0;
    const Real m_unit = frexp(unit, &e_unit), m_a = frexp(a, &e_a), m_b = frexp(b, &e_b);
    const W exponent = W(static_cast<long long>(e_a) + e_b) * W(power);
    const W whole = floor(exponent);
    const W mantissa = W(m_unit) * pow(W(m_a) * W(m_b), W(power)) * pow(W(2), W(exponent - whole));
    // A shift beyond the type's range gives 0 or ∞ however far beyond: clamped to an int.
    const long long limit = std::numeric_limits<int>::max() - 64;
    const W shift = whole + W(e_unit);
    const auto whole_bits = [](const W& x) -> long long {
      if constexpr (std::is_arithmetic_v<W>) {
        return static_cast<long long>(x);
      } else {
        return x.template convert_to<long long>();
      }
    };
    const long long bits = shift > W(limit)    ? limit
                           : shift < W(-limit) ? -limit
                                               : whole_bits(shift);
    return ldexp(detail::narrowed_power<Real>(mantissa), static_cast<int>(bits));
  }

  template <class W>
  static W power_in_range(const W& unit, const W& log_unit, const W& a, const W& b, const W& log_y,
                          const W& power) {
    using std::exp;
    using std::isfinite;
    using std::pow;
    const W min = std::numeric_limits<W>::min();
    const auto normal = [&](const W& x) { return isfinite(x) && x >= min; };
    const auto raise = [&](const W& x) { return power == 1 ? x : W(pow(x, power)); };
    const W y = a * b;
    if (normal(y) && isfinite(unit)) {
      const W raised = raise(y);
      if (normal(raised)) {
        const W product = unit * raised;
        if (isfinite(product)) {
          return product; // subnormal only when the result is
        }
      }
    }
    const W root = exp(log_unit / power); // unit^(1/power)
    for (const W& base : {W(y * root), W(a * (b * root)), W(b * (a * root))}) {
      if (normal(base)) {
        const W raised = raise(base);
        if (isfinite(raised)) {
          return raised;
        }
      }
    }
    if (normal(a) && normal(b) && isfinite(unit)) {
      const W first = raise(a), second = raise(b);
      if (normal(first) && normal(second)) {
        const W product = unit * second * first;
        if (isfinite(product) && product != 0) {
          return product;
        }
      }
    }
    return exp(log_unit + power * log_y);
  }

  TrajectoryPoint<Real> point(const Real& s, const Real& t) const {
    using std::exp;
    using std::sqrt;
    const Real sigma = c_.omega0() * s;
    if (late_in_decay(sigma) || decayed(sigma)) {
      // e^(−zσ) → 0 times cosh rσ → ∞ gave NaN at t = 1e10, α_eff = 2: the slow-mode form.
      return decay_point(sigma, t, std::nullopt);
    }
    const Real w = mu() * sigma * sigma;
    return assemble(s, t, cos_rf(w), Real(sigma * sinc_rf(w)), sigma);
  }

  // The state at σ = σ_end − ρ, from ρ: cos(√μσ) = −cos(√μρ), sin(√μσ)/√μ = ρ sinc_rf(μρ²).
  TrajectoryPoint<Real> point_before_end(const Real& rho, const Real& t) const {
    const Real sigma = scaled_.sigma_end() - rho;
    const Real w = mu() * rho * rho;
    return assemble(Real(sigma / c_.omega0()), t, Real(-cos_rf(w)), Real(rho * sinc_rf(w)), sigma);
  }

  TrajectoryPoint<Real> exit_point(const Real& t) const {
    return {s_end(), t,       Real(0), Real(-restitution(c_.damping()) * c_.v0()),
            Real(0), Real(0), false};
  }

  // From the regime-free cos and sine parts C, S̃ = Ω0 S at σ = Ω0 s: ξ = x/L = e^(−zσ) S̃,
  // v = x' = v0 e^(−zσ)(C − z S̃), δ = A L^q ξ^q, through ln ξ = −zσ + ln S̃ where e^(−zσ) alone
  // underflows (near critical damping, late in the contact).
  TrajectoryPoint<Real> assemble(const Real& s, const Real& t, const Real& cos_part,
                                 const Real& sine_part, const Real& sigma) const {
    using std::exp;
    using std::log;
    const Real decay = exp(-z() * sigma);
    TrajectoryPoint<Real> out{
        s,       t,       Real(0), Real(c_.v0() * decay * (cos_part - z() * sine_part)),
        Real(0), Real(0), true};
    if (sine_part > 0) {
      const Real log_xi = -z() * sigma + log(sine_part);
      out.delta = power_of_product(delta_unit_, log_delta_unit_, decay, sine_part, log_xi, c_.q());
      add_forces(out, Real(log_delta_unit_ + c_.q() * log_xi));
    }
    return out;
  }

  // k δ^p and α√(mk) δ^((p−1)/2) v, through ln δ where δ is not a normal number.
  void add_forces(TrajectoryPoint<Real>& out, const Real& log_delta) const {
    using std::sqrt;
    if (!(out.delta > 0)) {
      return;
    }
    auto log_delta_of = [&] { return log_delta; };
    out.force_elastic = c_.k() * power_of(out.delta, log_delta_of, c_.p());
    out.force_damping = c_.alpha() * sqrt(c_.m() * c_.k()) *
                        power_of(out.delta, log_delta_of, Real((c_.p() - 1) / 2)) * out.v;
  }

  Contact<Real> c_;
  ScaledTime<Real> scaled_;
  Real log_time_scale_, time_scale_;
  OnsetSeries<Real> onset_;
  std::optional<SlowDecay<Real>> slow_; // α_eff ≥ 1 and p > 1
  Real delta_power_ = Real(0), xi_power_ = Real(0), log_delta_unit_, delta_unit_;
};

} // namespace pldamp::analytic
