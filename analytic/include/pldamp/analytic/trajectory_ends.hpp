// The two ends of the time-domain solution (MATH.md §3 "Time-domain solution" and "Its ends"),
// where the parametric solution of trajectory.hpp cannot be used as it stands.
//
// OnsetSeries, at small t: δ = v0 t Y(χ), v = v0 Z(χ) with χ = Ω0 v0^((p−1)/2) t^((p+1)/2),
// Y = Σ c_j χ^j, Z = Σ (1 + jb) c_j χ^j, b = (p+1)/2, from the equation of motion itself (the
// contact-point series of MATH.md §9 in physical units). The map's parameter is σ ≈ √q χ ∝ t^b,
// which leaves the range of the type long before t does (t = 1e−300 is σ ≈ 1e−375 at p = 3/2);
// the series needs no σ. It keeps c_0…c_3 and is used while the first two neglected terms of Z
// (the larger series) stay below ε/4.
//
// SlowDecay, a contact that never returns (α_eff ≥ 1) with p > 1: ξ = e^(−λσ) P(σ) exactly, with
// r = √(z² − 1), λ = 1/(z + r) the slow rate and P = σ·exprel(−2rσ) (σ at z = 1, → 1/(2r) late),
// so ξ^ν = e^(κσ) f(σ), κ = −νλ, f = P^ν, and I(σ) = e^(κσ) G(σ) with
//     G(σ) = ∫₀^σ e^(−κ(σ−u)) f(u) du.
// G is O(1/κ), smooth, and computed without any exponent of size κσ: by Gauss–Legendre pieces
// summed forward into a table, G(σ_{j+1}) = e^(−κw) G(σ_j) + ∫ over the piece, up to σ_late, and
// beyond by the integration-by-parts series G = (f/κ) Φ + Δ e^(−κ(σ − σ_late)),
//     Φ = Σ_{n≤N} (−1)^n f^(n)/(f κ^n),    Δ = G_table(σ_late) − (f/κ)Φ at σ_late,
// whose error is at most the largest first neglected term over [σ_late, σ] times I(σ) − I(σ_late):
// σ_late is where the two first neglected terms fall below ε/4 (the constant Δ is whatever the
// series misses of the start of the decay; it is exact by construction at σ_late). At the solution
// of e^(κσ) G(σ) = ϑ = t/T, ξ^ν = ϑ f/G, so δ = A L^q (ϑ f/G)^(q/ν) is formed by one power of a
// number known to a few ε: its error is |q/ν| = 2/(p−1) times that, the conditioning of the creep
// δ ∝ t^(−2/(p−1)) itself, where the exponent λσ of e^(−qλσ) would cost ε·qλσ (thousands of ε).
//
// A SlowDecay builds its table up to σ_late once, when made (a few dozen pieces that widen away
// from σ = 0).
#pragma once

#include "pldamp/analytic/contact.hpp"
#include "pldamp/analytic/quadrature.hpp"
#include "pldamp/analytic/time.hpp"

#include <boost/math/special_functions/expm1.hpp>
#include <boost/math/tools/roots.hpp>
#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace pldamp::analytic {

// exprel(x) = (e^x − 1)/x, 1 at x = 0: σ·exprel(−2rσ) = (1 − e^(−2rσ))/(2r) without 0/0 at r = 0.
template <SupportedReal Real>
Real exprel(const Real& x) {
  return x == 0 ? Real(1) : Real(boost::math::expm1(x) / x);
}

// P(σ) = e^(λσ) ξ(σ) = (1 − e^(−2rσ))/(2r) of a decay that never returns (r = √−μ ≥ 0); σ at
// r = 0 (critical damping).
template <SupportedReal Real>
Real slow_mode_P(const Real& r, const Real& sigma) {
  return r == 0 ? sigma : Real(-boost::math::expm1(Real(-2 * r * sigma)) / (2 * r));
}

// ---- the onset -------------------------------------------------------------------------------

template <SupportedReal Real>
class OnsetSeries {
public:
  static constexpr int kept = 4; // c_0 … c_3

  // χ's units: Ω0 v0^a t^b with a = (p−1)/2, b = (p+1)/2 = 1/q; α = 2z/√q.
  explicit OnsetSeries(const Contact<Real>& c)
      : a_((c.p() - 1) / 2), b_((c.p() + 1) / 2), v0_(c.v0()) {
    using std::abs;
    using std::log;
    using std::pow;
    log_chi_unit_ = log(c.omega0()) + a_ * log(c.v0());
    const Real alpha = c.alpha();
    // c_j j b (1 + j b) = −α (E Z)_(j−1) − (E² Y)_(j−2), E = Y^a, Z_j = (1 + j b) c_j (MATH.md
    // §3 "Its ends"): each order needs the earlier ones only.
    constexpr int size = kept + 2;
    std::array<Real, size> e{}, w{}; // E = Y^a and E² (their orders known so far)
    c_[0] = Real(1);
    e[0] = Real(1);
    w[0] = Real(1);
    for (int j = 1; j < size; ++j) {
      Real ez(0), w_y(0);
      for (int i = 0; i <= j - 1; ++i) {
        ez += e[i] * (1 + Real(j - 1 - i) * b_) * c_[j - 1 - i];
      }
      for (int i = 0; i <= j - 2; ++i) {
        w_y += w[i] * c_[j - 2 - i];
      }
      c_[j] = -(alpha * ez + w_y) / (Real(j) * b_ * (1 + Real(j) * b_));
      // Power rule for E = Y^a (Y_0 = 1): j E_j = Σ_{i=1..j} (a i − (j − i)) c_i E_(j−i).
      Real sum(0);
      for (int i = 1; i <= j; ++i) {
        sum += (a_ * Real(i) - Real(j - i)) * c_[i] * e[j - i];
      }
      e[j] = sum / Real(j);
      w[j] = Real(0);
      for (int i = 0; i <= j; ++i) {
        w[j] += e[i] * e[j - i];
      }
    }
    // The switch: each of the two first neglected terms of Z below ε/8, so that together they
    // are below ε/4 of Z ≈ 1.
    const Real eighth_eps = std::numeric_limits<Real>::epsilon() / 8;
    log_chi_switch_ = std::numeric_limits<Real>::infinity();
    for (int j = kept; j < size; ++j) {
      const Real coefficient = abs((1 + Real(j) * b_) * c_[j]);
      if (coefficient > 0) {
        log_chi_switch_ = std::min(log_chi_switch_, Real(log(eighth_eps / coefficient) / j));
      }
    }
  }

  const Real& coefficient(int j) const { return c_[static_cast<std::size_t>(j)]; }
  // ln χ at t.
  Real log_chi(const Real& log_t) const { return log_chi_unit_ + b_ * log_t; }
  bool covers(const Real& log_t) const { return log_chi(log_t) <= log_chi_switch_; }

  struct State {
    Real delta, v;
    Real log_delta; // ln δ, where δ itself may underflow
  };

  // δ and v at t > 0 (t and its logarithm).
  State at(const Real& t, const Real& log_t) const {
    using boost::math::log1p;
    using std::exp;
    using std::log;
    const Real chi = exp(log_chi(log_t)); // 0 once it underflows: the corrections are then below ε
    Real y_excess(0), z_excess(0), power(1);
    for (int j = 1; j < kept; ++j) {
      power *= chi;
      y_excess += c_[j] * power;
      z_excess += (1 + Real(j) * b_) * c_[j] * power;
    }
    const Real scale = v0_ * (1 + y_excess);
    return {scale * t, v0_ * (1 + z_excess), Real(log(v0_) + log_t + log1p(y_excess))};
  }

private:
  Real a_, b_, v0_, log_chi_unit_, log_chi_switch_;
  std::array<Real, kept + 2> c_{};
};

// ---- the slow decay --------------------------------------------------------------------------

template <SupportedReal Real>
class SlowDecay {
public:
  // The damping must be critical or over (μ ≤ 0) and q < 1 (p > 1).
  SlowDecay(const Damping<Real>& d, const Real& q) : scaled_(d, q), nu_(q - 1) {
    using std::abs;
    using std::min;
    using std::sqrt;
    assert(d.mu <= 0 && q < 1);
    r_ = sqrt(-d.mu);
    lambda_ = 1 / (d.z + r_); // z − r without cancellation: (z − r)(z + r) = z² + μ = 1
    kappa_ = -nu_ * lambda_;
    // A piece [σ_j, σ_j + w] keeps P's zero at 0 at least w away (w ≤ σ_j: ρ ≥ 3 + √8), its
    // zeros ±iπ/r beyond the Bernstein ellipse ρ = 4 (w ≤ 3/r: ρ = 4.2) and e^(−κ(b−u)) within
    // e² (w ≤ 2/κ), so quadrature_order() points reach ε (as in time.hpp). Few and wide pieces
    // matter here: each step of the table multiplies the rounding carried by e^(−κw) and adds its
    // own, so the table's error is about ε/(1 − e^(−κw)).
    widest_ = 2 / kappa_;
    if (r_ > 0) {
      widest_ = min(widest_, Real(3 / r_));
    }
    find_late_switch(peak_phase(d));
  }

  const Real& rate() const { return kappa_; } // κ

  Real P(const Real& sigma) const { return slow_mode_P(r_, sigma); }
  // f = P^ν; at a single σ (not a quadrature's node) in detail::PowerWide, as the state's
  // ξ^ν = ϑ f/G is: cpp_bin_float_50's own pow loses tens of ε.
  Real f(const Real& sigma) const {
    using std::pow;
    return pow(P(sigma), nu_);
  }
  Real f_at(const Real& sigma) const { return detail::wide_pow(P(sigma), nu_); }

  // G(σ) = e^(−κσ) I(σ), σ > 0.
  Real G(const Real& sigma) const {
    if (sigma >= sigma_late_) {
      return late(sigma);
    }
    if (sigma <= sigmas_.front()) {
      return exp_(-kappa_ * sigma) * scaled_(sigma);
    }
    // The last entry at or below σ: the piece from it to σ is within its width.
    const std::size_t j =
        static_cast<std::size_t>(std::upper_bound(sigmas_.begin(), sigmas_.end(), sigma) -
                                 sigmas_.begin()) -
        1;
    return exp_(-kappa_ * (sigma - sigmas_[j])) * gs_[j] + piece(sigmas_[j], sigma);
  }

  // ln I(σ) = κσ + ln G(σ).
  Real log_I(const Real& sigma) const {
    using std::log;
    return kappa_ * sigma + log(G(sigma));
  }

  // The σ with I(σ) = ϑ = t/T (theta, and log_theta = ln ϑ, finite where ϑ is not), and G there.
  // Up to σ_late the residual is I(σ)/ϑ − 1, whose rounding is a few ε of I: near the onset δ is
  // formed from σ itself, and ln I − ln ϑ would carry ε·|ln ϑ| into it. Beyond, ln I − ln ϑ: δ
  // is then formed from ϑ f/G, in which σ's error barely moves f/G.
  std::pair<Real, Real> solve(const Real& theta, const Real& log_theta) const {
    using std::abs;
    using std::exp;
    using std::isfinite;
    using std::log;
    Real lo(0), hi, guess;
    const bool late_time = log_theta >= log_Is_.back();
    if (late_time) {
      // Beyond σ_late ln I grows like κσ: step out until the bracket holds the root.
      lo = sigma_late_;
      Real step = (log_theta - log_Is_.back()) / kappa_ + widest_;
      while (log_I(Real(sigma_late_ + step)) < log_theta) {
        step *= 2;
      }
      hi = sigma_late_ + step;
      guess = lo + (hi - lo) / 2;
    } else {
      const std::size_t above = static_cast<std::size_t>(
          std::lower_bound(log_Is_.begin(), log_Is_.end(), log_theta) - log_Is_.begin());
      hi = sigmas_[above];
      if (above > 0) {
        lo = sigmas_[above - 1];
        guess = lo + (hi - lo) / 2;
      } else {
        // In the first piece, I ≈ σ^q/q: start there, and halve until below the root for the
        // bracket (σ = 0 itself has ln I = −∞ and an infinite dt/dσ).
        guess = std::min(Real(exp((log_theta + log(q())) / q())), hi);
        lo = guess;
        while (lo > 0 && log_I(lo) >= log_theta) {
          lo /= 2;
        }
      }
    }
    const bool linear = !late_time && isfinite(theta) && theta > 0;
    auto residual = [&](const Real& sigma) {
      const Real g = G(sigma);
      if (linear) {
        const Real growth = exp_(kappa_ * sigma) / theta;
        return std::make_pair(Real(growth * g - 1), Real(growth * f(sigma)));
      }
      return std::make_pair(Real(kappa_ * sigma + log(g) - log_theta), Real(f(sigma) / g));
    };
    const int digits = std::numeric_limits<Real>::digits - 2;
    std::uintmax_t iterations = 100;
    Real sigma =
        boost::math::tools::newton_raphson_iterate(residual, guess, lo, hi, digits, iterations);
    if (!(abs(residual(sigma).first) <=
          Real(64) * std::numeric_limits<Real>::epsilon() * (linear ? 1 : abs(log_theta) + 1))) {
      // Newton did not settle: TOMS 748 on the bracket, which always does.
      auto value = [&](const Real& x) { return residual(x).first; };
      std::uintmax_t more = 400;
      const auto [a, b] = boost::math::tools::toms748_solve(
          value, lo, hi, boost::math::tools::eps_tolerance<Real>(digits), more);
      sigma = a + (b - a) / 2;
    }
    return {sigma, G(sigma)};
  }

private:
  template <class T>
  static T exp_(const T& value) {
    using std::exp;
    return exp(value);
  }
  Real q() const { return nu_ + 1; }

  // ∫_a^b e^(−κ(b − u)) f(u) du by one Gauss–Legendre rule.
  Real piece(const Real& a, const Real& b) const {
    const JacobiRule<Real>& rule = jacobi_rule(Real(0));
    const Real half = (b - a) / 2;
    Real sum(0);
    for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
      const Real u = a + half * (1 + rule.nodes[i]);
      sum += rule.weights[i] * exp_(-kappa_ * half * (1 - rule.nodes[i])) * f(u);
    }
    return half * sum;
  }

  // The table up to `end`: G at each piece's end from the last, e^(−κw) times it plus the piece
  // (all terms positive: no cancellation, and each step damps the rounding carried).
  void extend_table(const Real& end) {
    using std::log;
    using std::min;
    if (sigmas_.empty()) {
      const Real first = min(scaled_.piece_width(), end);
      sigmas_.push_back(first);
      gs_.push_back(exp_(-kappa_ * first) * scaled_(first));
      log_Is_.push_back(kappa_ * first + log(gs_.back()));
    }
    while (sigmas_.back() < end) {
      const Real a = sigmas_.back();
      const Real b = min(Real(a + min(a, widest_)), end);
      gs_.push_back(exp_(-kappa_ * (b - a)) * gs_.back() + piece(a, b));
      sigmas_.push_back(b);
      log_Is_.push_back(kappa_ * b + log(gs_.back()));
    }
  }

  // t_0 … t_(count−1) of Φ(σ) = Σ t_n, t_n = (−1)^n n! f̂_n with f̂_n the Taylor coefficients of
  // (P(σ + u/κ)/P(σ))^ν in u, i.e. (−1)^n f^(n)/(f κ^n). Stops early (the rest +∞) once a term
  // passes 1: the series is diverging there.
  std::vector<Real> late_terms_at(const Real& sigma, int count) const {
    using std::abs;
    using std::exp;
    const auto size = static_cast<std::size_t>(count);
    std::vector<Real> p_hat(size), f_hat(size), terms(size, std::numeric_limits<Real>::infinity());
    // P(σ + h) = (1 − e^(−2rσ) e^(−2rh))/(2r): P_1 = e^(−2rσ), P_(k+1) = P_k (−2r)/(k + 1), and
    // in u = κh each P_k is divided by κ^k.
    p_hat[0] = P(sigma);
    Real coefficient = exp(-2 * r_ * sigma) / kappa_;
    for (std::size_t k = 1; k < size; ++k) {
      p_hat[k] = coefficient;
      coefficient *= -2 * r_ / (kappa_ * Real(k + 1));
    }
    f_hat[0] = Real(1);
    terms[0] = Real(1);
    Real factorial(1);
    for (std::size_t n = 1; n < size; ++n) {
      // The power rule: n P_0 f_n = Σ_{j=1..n} (ν j − (n − j)) P_j f_(n−j).
      Real sum(0);
      for (std::size_t j = 1; j <= n; ++j) {
        sum += (nu_ * Real(j) - Real(n - j)) * p_hat[j] * f_hat[n - j];
      }
      f_hat[n] = sum / (Real(n) * p_hat[0]);
      factorial *= -Real(n);
      terms[n] = factorial * f_hat[n];
      if (!(abs(terms[n]) <= 1)) {
        terms[n] = std::numeric_limits<Real>::infinity();
        break;
      }
    }
    return terms;
  }

  // G beyond σ_late, F + Δ e^(−κd) with F = (f/κ)Φ, Δ = G_late − F_late and d = σ − σ_late.
  // Overdamped, F is nearly constant and far above G_late (I is still dominated by its start):
  // Δ ≈ −F, and F + Δ e^(−κd) cancels while Δ e^(−κd) is more than half of F. There it is summed
  // as e^(−κd) G_late + F (1 − e^(−κd)) + e^(−κd)(F − F_late), with F − F_late formed from
  // P − P_late = e^(−2rσ_late) d exprel(−2rd) and the differences of the terms, each small there
  // (d is then below ln(2|Δ|/F)/κ); beyond, as it stands (f − f_late would cancel instead).
  Real late(const Real& sigma) const {
    using std::abs;
    const Real d = sigma - sigma_late_;
    const Real decay = exp_(-kappa_ * d);
    const std::vector<Real> terms = late_terms_at(sigma, late_terms_ + 1);
    Real phi(0), phi_step(0);
    for (auto n = terms.size(); n-- > 0;) { // smallest first
      phi += terms[n];
      phi_step += terms[n] - late_phi_terms_[n];
    }
    const Real offset = late_g_ - f_late_ / kappa_ * late_phi_; // Δ
    const Real F = f_at(sigma) / kappa_ * phi;
    if (abs(offset * decay) <= F / 2) {
      return F + offset * decay;
    }
    using boost::math::log1p;
    const Real p_step = exp_(-2 * r_ * sigma_late_) * d * exprel(Real(-2 * r_ * d));
    const Real f_step = f_late_ * boost::math::expm1(Real(nu_ * log1p(p_step / p_late_)));
    const Real F_step = (f_step * phi + f_late_ * phi_step) / kappa_;
    return decay * late_g_ -
           (f_late_ + f_step) / kappa_ * phi * boost::math::expm1(Real(-kappa_ * d)) +
           decay * F_step;
  }

  // The fewest terms N whose two first neglected terms are below ε/4 of Φ at σ; −1 for none.
  // Critically damped t_n = (−ν)_n/(κσ)^n: its smallest term is about e^(−κσ), at n ≈ κσ, so κσ
  // must reach about ln(1/ε), with as many terms; twice that is the most tried.
  static int terms_needed(const std::vector<Real>& terms) {
    using std::abs;
    const Real eta = std::numeric_limits<Real>::epsilon() / 4;
    Real sum(0);
    for (std::size_t n = 0; n + 2 < terms.size(); ++n) {
      sum += terms[n];
      const Real neglected = abs(terms[n + 1]) + abs(terms[n + 2]);
      if (neglected <= eta * abs(sum)) {
        return static_cast<int>(n);
      }
      if (!(abs(terms[n + 2]) < abs(terms[n + 1]) || abs(terms[n + 1]) <= eta)) {
        return -1; // growing while still too large: asymptotic only further out
      }
    }
    return -1;
  }

  // σ_late: from the overlap's peak, the first σ of a (5/4)^k ladder where some N leaves its
  // two first neglected terms below ε/4 of Φ. Each |t_n| falls as σ grows (the Taylor
  // coefficients of P(σ + u)/P(σ) do), so the bound then holds at every later σ.
  void find_late_switch(const Real& sigma_peak) {
    const int most = 2 * (std::numeric_limits<Real>::digits * 7 / 10) + 8;
    Real sigma = std::max(sigma_peak, scaled_.piece_width());
    for (int rung = 0; rung < 100000; ++rung, sigma *= Real(5) / 4) {
      const int needed = terms_needed(late_terms_at(sigma, most + 3));
      if (needed < 0) {
        continue;
      }
      extend_table(sigma);
      late_terms_ = needed;
      sigma_late_ = sigma;
      late_g_ = gs_.back();
      p_late_ = P(sigma);
      f_late_ = f_at(sigma);
      late_phi_terms_ = late_terms_at(sigma, needed + 1);
      late_phi_ = Real(0);
      for (auto n = late_phi_terms_.size(); n-- > 0;) {
        late_phi_ += late_phi_terms_[n];
      }
      return;
    }
    throw std::logic_error("SlowDecay: no late switch found (not reached for p > 1, z >= 1)");
  }

  ScaledTime<Real> scaled_;
  Real nu_, r_, lambda_, kappa_, widest_;
  // At σ_late: G, P, f and the terms of Φ kept.
  Real sigma_late_, late_g_, p_late_, f_late_, late_phi_;
  std::vector<Real> late_phi_terms_;
  int late_terms_ = 0;
  // G at the ends σ_j of the pieces up to σ_late (the last), and ln I there.
  std::vector<Real> sigmas_, gs_, log_Is_;
};

} // namespace pldamp::analytic
