// The parametric time-domain solution (MATH.md §2, §3 "Time-domain solution"), all regimes.
//
// In the LSD parameter s (σ = Ω0 s):  x(s) = v0 e^(−zσ) S(s),  δ(s) = A x^q,  v(s) = x'(s),
// t(s) = ∫₀^s A q x^(q−1) ds (time.hpp), elastic force k δ^p, damping force α√(mk) δ^((p−1)/2) v.
// S, C are the regime-free sine and cosine of MATH.md §2 (special.hpp), smooth through z = 1.
// δ(t) for a given t solves t(s) = t by safeguarded Newton (dt/ds = A q x^(q−1) is known).
// Underdamped contacts end at s_end = π/Ω1; overdamped and critical ones never end (s → ∞).
#pragma once

#include "pldamp/analytic/observables.hpp"

#include <boost/math/tools/roots.hpp>
#include <boost/math/tools/toms748_solve.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
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
      : c_(c), scaled_(c.damping(), c.q()), time_scale_(exp_(log_time_scale(c))) {}

  // LSD functions in physical units (MATH.md §2).
  Real S(const Real& s) const {
    const Real sigma = c_.omega0() * s;
    return sigma * sinc_rf(Real(mu() * sigma * sigma)) / c_.omega0();
  }
  Real C(const Real& s) const {
    const Real sigma = c_.omega0() * s;
    return cos_rf(Real(mu() * sigma * sigma));
  }
  Real x(const Real& s) const { return c_.L() * scaled_.xi(c_.omega0() * s); }
  Real x_dot(const Real& s) const {
    using std::exp;
    const Real sigma = c_.omega0() * s;
    const Real w = mu() * sigma * sigma;
    return c_.v0() * exp(-z() * sigma) * (cos_rf(w) - z() * sigma * sinc_rf(w));
  }
  Real x_ddot(const Real& s) const {
    using std::exp;
    const Real sigma = c_.omega0() * s;
    const Real w = mu() * sigma * sigma;
    return c_.v0() * c_.omega0() * exp(-z() * sigma) *
           (-2 * z() * cos_rf(w) + (2 * z() * z() - 1) * sigma * sinc_rf(w));
  }

  Real s_peak() const { return peak_phase(c_.damping()) / c_.omega0(); }
  // π/Ω1 when underdamped, +∞ otherwise.
  Real s_end() const { return scaled_.sigma_end() / c_.omega0(); }

  Real time_at_parameter(const Real& s) const { return time_scale_ * scaled_(c_.omega0() * s); }

  TrajectoryPoint<Real> at_parameter(const Real& s) const { return point(s, time_at_parameter(s)); }

  // The state at physical time t ≥ 0. After an underdamped contact ends (t ≥ τ) the point is the
  // exit state: δ = 0, v = −e·v0, in_contact = false.
  TrajectoryPoint<Real> at_time(const Real& t) const {
    require_finite("t", t);
    require(t >= 0, "t must be >= 0", t);
    if (t == 0) {
      return point(Real(0), Real(0));
    }
    const Real target = t / time_scale_;
    Real lo(0);
    Real hi = scaled_.sigma_end();
    Real i_hi;
    std::uintmax_t iterations = 200;
    const int digits = std::numeric_limits<Real>::digits - 2;
    if (hi < std::numeric_limits<Real>::infinity()) {
      i_hi = scaled_.total();
      if (target >= i_hi) {
        return exit_point(t);
      }
      // In the last piece, solve for the distance ρ to the end: δ ∝ ρ^q there, and a σ near
      // σ_end would keep only the absolute precision of σ_end.
      const Real last = scaled_.piece_width() < hi / 2 ? scaled_.piece_width() : Real(hi / 2);
      const Real i_last = scaled_.before_end(last);
      if (target > i_last) {
        auto residual = [&](const Real& rho) {
          return std::make_pair(Real(scaled_.before_end(rho) - target),
                                Real(-scaled_.integrand_before_end(rho)));
        };
        const Real guess = last * (i_hi - target) / (i_hi - i_last);
        const Real rho = boost::math::tools::newton_raphson_iterate(residual, guess, Real(0), last,
                                                                    digits, iterations);
        return point_before_end(rho, t);
      }
      hi -= last;
      i_hi = i_last;
    } else {
      // Never returns: double σ until I(σ) passes the target, keeping the last σ below it as the
      // bracket's low end. Late in a decay I grows like e^(κσ) (κ = −ν times the slow rate), so
      // Newton from [0, hi] could jump to 0 and stay there: at α_eff 1.9–2.01 it answered the
      // onset, δ = 0 and v = v0, at t ~ 1e6 (found by a user's trial, tests/analytic).
      hi = peak_phase(c_.damping());
      while ((i_hi = scaled_(hi)) < target) {
        lo = hi;
        hi *= 2;
      }
    }
    auto residual = [&](const Real& sigma) {
      return std::make_pair(Real(scaled_(sigma) - target), scaled_.integrand(sigma));
    };
    const Real guess = lo + (hi - lo) / 2;
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
      const Real slow_rate = z() - sqrt(-mu());
      sigma_stop = peak_phase(c_.damping()) + 20 / slow_rate;
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

  TrajectoryPoint<Real> point(const Real& s, const Real& t) const {
    using std::exp;
    using std::sqrt;
    const Real sigma = c_.omega0() * s;
    const Real w = mu() * sigma * sigma;
    const Real r = mu() < 0 ? Real(sqrt(-mu())) : Real(0);
    if (r * sigma > 1) {
      // Overdamped and late: e^(−zσ) cosh(rσ) and e^(−zσ) sinh(rσ)/r as the two decaying modes
      // e^(−(z∓r)σ) (r = √(z² − 1) < z), which neither overflow nor underflow where the factors
      // do (e^(−zσ) → 0 times cosh rσ → ∞ gave NaN at t = 1e10, α_eff = 2).
      const Real slow = exp(-(z() - r) * sigma), fast = exp(-(z() + r) * sigma);
      return assemble(s, t, Real((slow + fast) / 2), Real((slow - fast) / (2 * r)), Real(1));
    }
    return assemble(s, t, cos_rf(w), Real(sigma * sinc_rf(w)), exp(-z() * sigma));
  }

  // The state at σ = σ_end − ρ, from ρ: cos(√μσ) = −cos(√μρ), sin(√μσ)/√μ = ρ sinc_rf(μρ²).
  TrajectoryPoint<Real> point_before_end(const Real& rho, const Real& t) const {
    const Real sigma = scaled_.sigma_end() - rho;
    const Real w = mu() * rho * rho;
    using std::exp;
    return assemble(Real(sigma / c_.omega0()), t, Real(-cos_rf(w)), Real(rho * sinc_rf(w)),
                    exp(-z() * sigma));
  }

  TrajectoryPoint<Real> exit_point(const Real& t) const {
    return {s_end(), t,       Real(0), Real(-restitution(c_.damping()) * c_.v0()),
            Real(0), Real(0), false};
  }

  // From the regime-free cos and sine parts C, S̃ = Ω0 S at σ = Ω0 s and the decay e^(−zσ) (1
  // when the parts carry it already): ξ = x/L = e^(−zσ) S̃, v = x' = v0 e^(−zσ)(C − z S̃),
  // δ = A (L ξ)^q, forces from δ and v.
  TrajectoryPoint<Real> assemble(const Real& s, const Real& t, const Real& cos_part,
                                 const Real& sine_part, const Real& decay) const {
    using std::log;
    using std::sqrt;
    const Real xi = decay * sine_part;
    TrajectoryPoint<Real> out{
        s,       t,       Real(0), Real(c_.v0() * decay * (cos_part - z() * sine_part)),
        Real(0), Real(0), true};
    if (xi > 0) {
      const Real log_delta = log(c_.A()) + c_.q() * (c_.log_L() + log(xi));
      out.delta = exp(log_delta);
      out.force_elastic = c_.k() * exp(c_.p() * log_delta);
      out.force_damping =
          c_.alpha() * sqrt(c_.m() * c_.k()) * exp((c_.p() - 1) / 2 * log_delta) * out.v;
    }
    return out;
  }

  Contact<Real> c_;
  ScaledTime<Real> scaled_;
  Real time_scale_;
};

} // namespace pldamp::analytic
