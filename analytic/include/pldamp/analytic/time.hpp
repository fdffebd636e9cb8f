// Physical time along the LSD solution (MATH.md §3 "Time-domain solution", §2).
//
// In σ = Ω0 s and ξ = x/L = e^(−zσ) σ sinc_rf(μσ²), t(s) = (A q L^ν / Ω0) · I(σ) with
//     I(σ) = ∫₀^σ ξ(σ')^ν dσ',   ν = q − 1 ∈ (−1, 0].
// ξ vanishes like σ at σ = 0 and, when underdamped, like (σ_end − σ) at σ_end = π/√μ, so ξ^ν has
// integrable endpoint singularities there. I is summed over pieces of width ≤ h:
//   - the piece touching σ = 0 by Gauss–Jacobi with weight σ^ν (the rest is analytic),
//   - interior pieces by Gauss–Legendre,
//   - within one piece of σ_end, by Gauss–Jacobi with weight (σ_end − σ)^ν, using
//     sin(√μσ) = sin(√μ(σ_end−σ)); at σ_end itself, I_end in closed form.
// h keeps every piece's nearest singularity (the other endpoint zero of ξ; the complex zeros
// ±iπ/√−μ of sinh when overdamped) at least one piece-width away, i.e. a Bernstein ellipse ρ ≥ 4
// for which quadrature_order() points suffice, and the factor e^(−νzσ) varies by at most e per
// piece. The piece touching σ = 0 reaches σ_end/2 when underdamped, so t_peak (σ_peak ≤ π/2 /√μ)
// is one piece, whose node count follows from its own ellipse (left_piece_order): 10 to 12
// evaluations in double, 20 to 24 in float128, the truncation error below the result's rounding.
//
// The closed form (MATH.md §3, "Contact duration"), with c = −ν z/√μ and a = (1+q)/2:
//     I_end = μ^(−q/2) · π e^(cπ/2) Γ(q) / (2^ν |Γ(a + ic/2)|²),
// evaluated in logarithms because it overflows near z = 1.
#pragma once

#include "pldamp/analytic/contact.hpp"
#include "pldamp/analytic/quadrature.hpp"
#include "pldamp/analytic/special.hpp"

#include <boost/math/special_functions/expm1.hpp>
#include <boost/math/special_functions/log1p.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

namespace pldamp::analytic {

// ln(τ/τ0) = −(q/2) ln μ + cπ/2 − 2 ln|Γ(a + ic/2)/Γ(a)|  (MATH.md §3); +∞ for z ≥ 1. This is
// the part of ln τ that grows like πc as z → 1. c = (1 − q) z/√μ from 1 − q = (p − 1)/(p + 1) as
// given: 1 − q formed from q keeps only ε/(p − 1) of it as p → 1, and near critical damping πc
// carries that into τ (5.6e6 ε at p = 1 + 2^−52, z = 1 − 1e−14).
template <SupportedReal Real>
Real log_duration_ratio(const Damping<Real>& d, const Real& q, const Real& one_minus_q) {
  using std::log;
  using std::sqrt;
  if (d.mu <= 0) {
    return std::numeric_limits<Real>::infinity();
  }
  const Real c = one_minus_q * d.z / sqrt(d.mu);
  const Real a = (1 + q) / 2;
  return -q * log(d.mu) / 2 + c * boost::math::constants::pi<Real>() / 2 -
         2 * log_abs_gamma_ratio(a, Real(c / 2));
}

// ln B(q/2, ½) = ln Γ(q/2) + ½ ln π − ln Γ((1+q)/2): the undamped I_end, τ0 in units of T.
template <SupportedReal Real>
Real log_undamped_scaled_duration(const Real& q) {
  using std::log;
  return log_gamma(Real(q / 2)) + log(boost::math::constants::pi<Real>()) / 2 -
         log_gamma(Real((1 + q) / 2));
}

// ln I_end = ln B(q/2, ½) + ln(τ/τ0); by Legendre's duplication formula this is the closed form
// above, ln[μ^(−q/2) π e^(cπ/2) Γ(q) / (2^ν |Γ(a + ic/2)|²)].
template <SupportedReal Real>
Real log_scaled_duration(const Damping<Real>& d, const Real& q) {
  return log_undamped_scaled_duration(q) + log_duration_ratio(d, q, Real(1 - q));
}

namespace detail {

// The type a power that decides a result's last digits is formed in: cpp_bin_float_50's own pow
// and exp lose tens to thousands of ε (pow(x, 4/5) near x = 3e−8: 75 ε; exp(−1e4): 5400 ε, its
// argument reduction keeping no guard digits), so for it they are formed in 100 digits and
// rounded once. The IEEE types' pow and exp are right to an ulp as they are.
template <SupportedReal Real>
struct PowerWidening {
  using type = Real;
};
template <>
struct PowerWidening<bin50> {
  using type = boost::multiprecision::cpp_bin_float_100;
};
template <SupportedReal Real>
using PowerWide = typename PowerWidening<Real>::type;

template <SupportedReal Real, class Wide>
Real narrowed_power(const Wide& value) {
  if constexpr (std::is_same_v<Wide, Real>) {
    return value;
  } else {
    return value.template convert_to<Real>();
  }
}

// x^y formed in PowerWide<Real>.
template <SupportedReal Real>
Real wide_pow(const Real& x, const Real& y) {
  using std::pow;
  using W = PowerWide<Real>;
  return narrowed_power<Real>(W(pow(W(x), W(y))));
}

} // namespace detail

// x^power for x > 0 when x is a normal number; else exp(power·ln x), all that a subnormal or a
// value beyond the type's range can give (pow(0, power < 0) = +∞). log_x() gives ln x, known
// where x is not.
template <SupportedReal Real, class LogX>
Real power_of(const Real& x, LogX log_x, const Real& power) {
  using std::exp;
  using std::isfinite;
  using std::pow;
  if (x >= std::numeric_limits<Real>::min() && isfinite(x)) {
    return pow(x, power);
  }
  return exp(power * Real(log_x()));
}

template <SupportedReal Real>
class ScaledTime {
public:
  ScaledTime(const Damping<Real>& d, const Real& q) : d_(d), q_(q), nu_(q - 1) {
    assert(q > 0 && q <= 1); // q = 2/(p + 1) of a Contact, whose p ∈ [1, 1000]
    using std::abs;
    using std::min;
    using std::sqrt;
    const Real pi = boost::math::constants::pi<Real>();
    sigma_end_ = d.mu > 0 ? Real(pi / sqrt(d.mu)) : std::numeric_limits<Real>::infinity();
    // Piece width: 2 (ρ = 4 for a singularity one width beyond a piece touching the other
    // end, when underdamped with σ_end ≥ π); 1/√|μ| keeps the overdamped zeros of sinh at
    // ±iπ/√−μ beyond ρ = 4; 1/(|ν|(1+z)) bounds the growth of e^(−νzσ) per piece.
    h_ = Real(2);
    if (d.mu < 0) {
      h_ = min(h_, Real(1 / sqrt(-d.mu)));
    }
    const Real rate = abs(nu_) * (1 + d.z);
    if (rate * h_ > 1) {
      h_ = 1 / rate;
    }
    // The piece touching σ = 0 may reach further when underdamped: up to σ_end/2 its nearest
    // singularity, the zero of sin at σ_end, lies at least a piece-width beyond it (ρ ≥ 3 + √8),
    // and within 1/rate e^(−νzσ) still varies by at most e. So σ_peak ≤ σ_end/2 (and the normal
    // force's peak before it) is one Gauss–Jacobi piece: half the evaluations of two pieces.
    left_reach_ = h_;
    if (d.mu > 0) {
      const Real half_contact = sigma_end_ / 2;
      const Real left = rate > 0 && rate * half_contact > 1 ? Real(1 / rate) : half_contact;
      left_reach_ = std::max(h_, left);
    }
  }

  const Real& sigma_end() const { return sigma_end_; }
  // Integrand evaluations made by the quadratures of this object so far (cost accounting).
  std::size_t evaluations() const { return evaluations_; }

  // ξ(σ) = x/L.
  Real xi(const Real& sigma) const {
    using std::exp;
    using std::sqrt;
    if (d_.mu < 0) {
      // Overdamped and late: the two decaying modes e^(−(z∓r)σ)/(2r), r = √(z² − 1) < z, which
      // stay finite where e^(−zσ) underflows and sinh(rσ) overflows (their product was NaN).
      const Real r = sqrt(-d_.mu);
      if (r * sigma > 1) {
        return (exp(-(d_.z - r) * sigma) - exp(-(d_.z + r) * sigma)) / (2 * r);
      }
    }
    return exp(-d_.z * sigma) * sigma * sinc_rf(Real(d_.mu * sigma * sigma));
  }
  // ln ξ(σ), finite where ξ itself underflows (late in a decay, or near critical damping where
  // e^(−zσ) leaves the range before the contact ends).
  Real log_xi(const Real& sigma) const {
    using std::log;
    using std::sqrt;
    if (d_.mu < 0) {
      const Real r = sqrt(-d_.mu);
      if (r * sigma > 1) {
        using boost::math::log1p;
        return -(d_.z - r) * sigma + log1p(-exp_(-2 * r * sigma)) - log(2 * r);
      }
    }
    return -d_.z * sigma + log(sigma * sinc_rf(Real(d_.mu * sigma * sigma)));
  }
  // dI/dσ = ξ^ν, through ln ξ where ξ is not a normal number (pow(0, ν < 0) would be +∞).
  Real integrand(const Real& sigma) const {
    return nu_ == 0 ? Real(1)
                    : power_of(
                          xi(sigma), [&] { return log_xi(sigma); }, nu_);
  }
  // ξ(σ_end − ρ) from the distance ρ to the end of an underdamped contact, exact for small ρ:
  // sin(√μσ)/√μ = ρ sinc_rf(μρ²).
  Real xi_before_end(const Real& rho) const {
    using std::exp;
    return exp(-d_.z * (sigma_end_ - rho)) * rho * sinc_rf(Real(d_.mu * rho * rho));
  }
  Real log_xi_before_end(const Real& rho) const {
    using std::log;
    return -d_.z * (sigma_end_ - rho) + log(rho * sinc_rf(Real(d_.mu * rho * rho)));
  }
  Real integrand_before_end(const Real& rho) const {
    return nu_ == 0 ? Real(1)
                    : power_of(
                          xi_before_end(rho), [&] { return log_xi_before_end(rho); }, nu_);
  }
  // Width of the quadrature pieces; within one width of σ_end, positions are best given as ρ.
  const Real& piece_width() const { return h_; }

  // I_end = I(σ_end), in closed form (+∞ when z ≥ 1).
  Real total() const {
    using std::exp;
    return exp(log_scaled_duration(d_, q_));
  }

  // I(σ), 0 ≤ σ ≤ σ_end.
  Real operator()(const Real& sigma) const {
    if (nu_ == 0) {
      return sigma; // p = 1: dt/ds = 1
    }
    if (sigma <= 0) {
      return Real(0);
    }
    if (sigma <= left_reach_) {
      return left_piece(sigma);
    }
    if (sigma_end_ - sigma < h_) {
      return before_end(Real(sigma_end_ - sigma));
    }
    return from_start(sigma);
  }

  // I(σ_end − ρ) for an underdamped contact, given the distance ρ ≥ 0 to the end directly (a
  // rounding of σ near σ_end would cost digits: dI/dσ is infinite there).
  // ∫ over the last ρ before σ_end of ξ^ν, 0 < ρ ≤ piece_width(): what is left of the contact's
  // time, in units of T, at ρ from its end (one end-weighted piece).
  Real to_end(const Real& rho) const { return nu_ == 0 ? rho : tail(rho); }
  const Real& nu() const { return nu_; }

  Real before_end(const Real& rho) const {
    if (nu_ == 0) {
      return sigma_end_ - rho;
    }
    if (rho <= 0) {
      return total();
    }
    if (rho >= h_) {
      return from_start(Real(sigma_end_ - rho));
    }
    // Within the last piece [σ_end − h, σ_end]. Sums always run forward from 0 (the integrand
    // grows steeply towards the end, so I_end minus a tail would cancel); the remainder is
    // ∫_ρ^h in ρ' = σ_end − σ', by Gauss–Legendre while the singularity at ρ' = 0 is at least half
    // the interval away, else as a difference of two end-weighted pieces (ρ < h/3, so the smaller
    // is at most 3^−(ν+1) of the larger: under one digit lost).
    const Real base = sigma_end_ - h_;
    const Real head = from_start(base);
    if (2 * rho >= h_ - rho) {
      return head + panels(base, Real(sigma_end_ - rho));
    }
    return head + tail(h_) - tail(rho);
  }

private:
  template <class T>
  static T exp_(const T& value) {
    using std::exp;
    return exp(value);
  }

  Real from_start(const Real& sigma) const {
    const Real first = sigma < h_ ? sigma : h_;
    return left_piece(first) + panels(first, sigma);
  }

  // Σ over a Jacobi rule on [0, b] of b^(ν+1)·(1+t)^ν-weighted f(σ = b(1+t)/2) / 2^(ν+1).
  template <class Smooth>
  Real jacobi_piece(const Real& b, Smooth smooth) const {
    using std::pow;
    const JacobiRule<Real>& rule = jacobi_rule(nu_);
    evaluations_ += rule.nodes.size();
    Real sum(0);
    for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
      sum += rule.weights[i] * smooth(b * (1 + rule.nodes[i]) / 2);
    }
    return pow(b / 2, nu_ + 1) * sum;
  }

  // ∫₀^b ξ^ν with the weight σ^ν taken exactly: ξ^ν = σ^ν g(σ), g = (e^(−zσ) sinc_rf(μσ²))^ν,
  // as (b^q/q)(1 + the rule's mean of g − 1): the rounded weights then touch only g − 1, which is
  // O(b) near the onset, where t ≈ T σ^q/q must be right to the last bits for σ(t) to be (the
  // rule's own Σ w_i = 2^q/q carried 7 ε of float128 into t there).
  Real left_piece(const Real& b) const {
    using std::log;
    const JacobiRule<Real>& rule = jacobi_rule(nu_, left_piece_order(b));
    evaluations_ += rule.nodes.size();
    Real sum(0);
    for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
      const Real sigma = b * (1 + rule.nodes[i]) / 2;
      sum += rule.weights[i] *
             boost::math::expm1(
                 Real(nu_ * (log(sinc_rf(Real(d_.mu * sigma * sigma))) - d_.z * sigma)));
    }
    return detail::wide_pow(b, q_) / q_ * (1 + sum * q_ / detail::wide_pow(Real(2), q_));
  }

  // Nodes for a piece whose nearest singularity on the real axis lies a half-widths from its
  // centre: the ellipse through it is ρ = a + √(a² − 1), capped at largest_ellipse (MATH.md §3,
  // "The time integral"). Overdamped, the zeros ±iπ/√−μ of sinh lie beyond ρ = 12 of any piece
  // (their widths are at most 1/√−μ), so only the real ones count: ξ's zero at σ = 0 and, when
  // underdamped, the zero of sin at σ_end.
  static int order_for(const Real& a) {
    if (!(a < Real((largest_ellipse + 1 / largest_ellipse) / 2))) {
      return quadrature_order<Real>(largest_ellipse);
    }
    const double near = static_cast<double>(a);
    return quadrature_order<Real>(near + std::sqrt((near - 1) * (near + 1)));
  }
  // [0, b]: its own singularity is the weight's; underdamped, b ≤ σ_end/2 puts σ_end at a ≥ 3.
  // t_peak at e = 0.5 is a = 3.6: 10 nodes in double and 21 in float128 instead of 15 and 30.
  int left_piece_order(const Real& b) const {
    return order_for(d_.mu > 0 ? Real((2 * sigma_end_ - b) / b)
                               : std::numeric_limits<Real>::infinity());
  }

  // ∫ over the last ρ ≤ h before σ_end of ξ^ν; with ρ' = σ_end − σ, ξ = e^(−zσ) ρ' sinc_rf(μρ'²).
  Real tail(const Real& rho) const {
    using std::exp;
    using std::log;
    return jacobi_piece(rho, [&](const Real& r) {
      const Real sinc = sinc_rf(Real(d_.mu * r * r));
      return power_of(
          Real(exp(-d_.z * (sigma_end_ - r)) * sinc),
          [&] { return Real(-d_.z * (sigma_end_ - r) + log(sinc)); }, nu_);
    });
  }

  // ∫_a^b ξ^ν by Gauss–Legendre on ⌈(b − a)/h⌉ equal panels.
  Real panels(const Real& a, const Real& b) const {
    using std::ceil;
    if (!(b > a)) {
      return Real(0);
    }
    const Real count_real = ceil((b - a) / h_);
    const long count = static_cast<long>(count_real);
    const Real width = (b - a) / count_real;
    // The first panel is nearest σ = 0, the last nearest σ_end: one order for all, the worse's.
    const Real from_onset = 2 * a / width + 1;
    const JacobiRule<Real>& rule = jacobi_rule(
        Real(0), order_for(d_.mu > 0 ? std::min(from_onset, Real(2 * (sigma_end_ - b) / width + 1))
                                     : from_onset));
    evaluations_ += rule.nodes.size() * static_cast<std::size_t>(count);
    Real total_sum(0);
    for (long j = 0; j < count; ++j) {
      const Real mid = a + width * (Real(j) + Real(1) / 2);
      Real sum(0);
      for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
        sum += rule.weights[i] * integrand(Real(mid + width * rule.nodes[i] / 2));
      }
      total_sum += sum * width / 2;
    }
    return total_sum;
  }

  Damping<Real> d_;
  Real q_, nu_, sigma_end_, h_, left_reach_;
  mutable std::size_t evaluations_ = 0;
};

} // namespace pldamp::analytic
