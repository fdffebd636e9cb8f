// Taylor arithmetic (the automatic-differentiation recurrences) and the local series of the contact
// equation where the overlap vanishes: the entry (t = 0) and the exit (t = τ) of a contact, where
// δ^((p−1)/2) has a branch point (MATH.md §8) that no Taylor step in t can start from or cross.
//
// The taylor solver integrates the physical equation in the units of its own energy balance,
// δ_u (k δ_u^(p+1)/(p+1) = m v0²/2), T = δ_u / v0 and KE0 = m v0²/2 (MATH.md §7). Only units
// change, not variables: time stays the independent variable and δ the overlap. There
//     δ'' + γ δ^a δ' + κ δ^p = 0,   a = (p−1)/2,  b = a + 1 = (p+1)/2,  κ = b,  γ = α √b,   (1)
// with δ(0) = 0, δ'(0) = 1, and the dissipated work W' = 2γ δ^a δ'² (in units of KE0).
//
// The series. Near a point s = 0 where δ = 0 and dδ/ds = u > 0 (forward time at the entry, with γ
// as in (1); backward time s = τ − t at the exit, where the time-reversed equation has −γ), put
//     δ = u s Y(x),   x = u^a s^b,   Y(x) = Σ_j c_j x^j,   c_0 = 1.
// Then, with d/ds (s x^j) = (1 + j b) x^j and E = Y^a,
//     dδ/ds = u Z(x),                                   Z = Σ c_j (1 + j b) x^j,
//     d²δ/ds² = (u / s) Σ c_j j b (1 + j b) x^j,
//     δ^a dδ/ds = u^(a+1) s^a E Z = (u / s) x E Z,      δ^p = u^p s^p E² Y = (u / s) x² E² Y,
// and (1) divided by u / s, power by power of x, is the recurrence
//     c_j j b (1 + j b) = −γ (E Z)_{j−1} − κ (E² Y)_{j−2}.                                   (2)
// The coefficients depend on (p, γ) only; u enters through x alone. E = Y^a follows by the power
// recurrence below. The work from s = 0 is ∫ 2γ δ^a (dδ/ds)² ds = 2γ u² ∫ u^a s^a E Z² ds, and
// since ∫_0^s u^a σ^a x(σ)^j dσ = x^(j+1) / (b (j + 1)),
//     W(s) = 2γ u² Σ_j M_j x^(j+1) / (b (j + 1)),   M = E Z².                               (3)
// For p = 1 (a = 0, b = 1) the series is the ordinary Taylor series in s; for odd p it is one in
// s^b with b integer; otherwise it resolves the branch point exactly.
#pragma once

#include "polynomial.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace pldamp::solvers::detail {

// (f g)_n = Σ_{j=0}^{n} f_j g_{n−j}: the n-th Taylor coefficient of a product.
// Summed in four interleaved partial sums: one running sum is a chain of dependent additions
// (4 cycles each in double), four let the terms overlap; the sum is as accurate either way.
template <class Real>
Real product_coefficient(const std::vector<Real>& f, const std::vector<Real>& g, std::size_t n) {
  Real s0 = f[0] * g[n], s1 = Real(0), s2 = Real(0), s3 = Real(0);
  std::size_t j = 1;
  for (; j + 3 <= n; j += 4) {
    s0 += f[j] * g[n - j];
    s1 += f[j + 1] * g[n - j - 1];
    s2 += f[j + 2] * g[n - j - 2];
    s3 += f[j + 3] * g[n - j - 3];
  }
  for (; j <= n; ++j) {
    s1 += f[j] * g[n - j];
  }
  return (s0 + s1) + (s2 + s3);
}

// The n-th (n ≥ 1) Taylor coefficient of u = f^a for constant a, from u_0 ... u_{n−1}: u = f^a
// gives f u' = a f' u, whose coefficient of order n − 1 solves to
//     u_n = (1 / (n f_0)) Σ_{j=0}^{n−1} (a (n − j) − j) f_{n−j} u_j.
// It divides by f_0: the expansion point must not be a zero of f (the branch point).
template <class Real>
Real power_coefficient(const std::vector<Real>& f, const std::vector<Real>& u, const Real& a,
                       std::size_t n) {
  // a (n − j) − j = a n − (a + 1) j; four partial sums as in product_coefficient.
  const Real an = a * Real(n), a1 = a + 1;
  auto term = [&](std::size_t j) { return (an - a1 * Real(j)) * f[n - j] * u[j]; };
  Real s0 = Real(0), s1 = Real(0), s2 = Real(0), s3 = Real(0);
  std::size_t j = 0;
  for (; j + 4 <= n; j += 4) {
    s0 += term(j);
    s1 += term(j + 1);
    s2 += term(j + 2);
    s3 += term(j + 3);
  }
  for (; j < n; ++j) {
    s0 += term(j);
  }
  return ((s0 + s1) + (s2 + s3)) / (Real(n) * f[0]);
}

// power_coefficient with weighted[j] = j u_j kept beside u: the sum split as
//     Σ (a n − (a + 1) j) f_{n−j} u_j = a n Σ f_{n−j} u_j − (a + 1) Σ f_{n−j} j u_j,
// two products a term instead of three and an integer conversion (a series built in float128 is
// these sums).
template <class Real>
Real power_coefficient(const std::vector<Real>& f, const std::vector<Real>& u,
                       const std::vector<Real>& weighted, const Real& a, std::size_t n) {
  Real plain0 = Real(0), plain1 = Real(0), by_degree0 = Real(0), by_degree1 = Real(0);
  std::size_t j = 0;
  for (; j + 2 <= n; j += 2) {
    plain0 += f[n - j] * u[j];
    by_degree0 += f[n - j] * weighted[j];
    plain1 += f[n - j - 1] * u[j + 1];
    by_degree1 += f[n - j - 1] * weighted[j + 1];
  }
  for (; j < n; ++j) {
    plain0 += f[n - j] * u[j];
    by_degree0 += f[n - j] * weighted[j];
  }
  return (a * Real(n) * (plain0 + plain1) - (a + 1) * (by_degree0 + by_degree1)) / (Real(n) * f[0]);
}

enum class NewtonStep { left_the_domain, moving, converged };

// One Newton step of a series' locate() on (u, s) for the residuals (f1, f2) with the Jacobian
// [[j11, j12], [j21, j22]] (columns ∂/∂u, ∂/∂s): converged when both moved by at most 4ε
// relative; left_the_domain when u or s is no longer positive.
template <class Real>
NewtonStep newton_step(Real& u, Real& s, const Real& f1, const Real& f2, const Real& j11,
                       const Real& j12, const Real& j21, const Real& j22) {
  using std::abs;
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real det = j11 * j22 - j12 * j21;
  const Real du = (f2 * j12 - f1 * j22) / det, ds = (f1 * j21 - f2 * j11) / det;
  u += du;
  s += ds;
  if (!(u > 0 && s > 0)) {
    return NewtonStep::left_the_domain;
  }
  return abs(du) <= 4 * eps * u && abs(ds) <= 4 * eps * s ? NewtonStep::converged
                                                          : NewtonStep::moving;
}

// What the taylor solver asks of a series at a contact point (this one for the seed's damping
// exponent, two_power_series.hpp's for any other): the state at time s from the point, where the
// series stops at the entry, whether a state lies within its reach, and the contact point behind a
// state near the exit.
template <class Real>
class ContactSeries {
public:
  virtual ~ContactSeries() = default;

  struct Point {
    Real delta, rate, work; // δ, dδ/ds and the work done since s = 0
  };
  struct Contact {
    Real u, s;
  };
  // The state at time s from a contact point passed at speed u.
  virtual Point at(const Real& u, const Real& s) const = 0;
  // Its work alone (a series may sum it alone for less).
  virtual Real work_at(const Real& u, const Real& s) const { return at(u, s).work; }
  // Where the entry series stops for speed u: its reach, and not past the time at which dδ/ds has
  // fallen to `fraction` of u (for odd p the series converges everywhere and would otherwise run
  // past the peak and round the whole contact).
  virtual Real entry_end(const Real& u, const Real& fraction) const = 0;
  // Whether (u, s) lies within the reach (the terms left out below the tolerance).
  virtual bool within_reach(const Real& u, const Real& s) const = 0;
  // The speed u at δ = 0 and the distance s to it of a state (delta, rate = dδ/ds), if that
  // contact point lies within the reach; none otherwise (an overdamped overlap decaying for
  // ever, or a state still too far from the exit).
  virtual std::optional<Contact> locate(const Real& delta, const Real& rate) const = 0;
};

template <class Real>
class ContactPointSeries final : public ContactSeries<Real> {
public:
  using typename ContactSeries<Real>::Point;
  using typename ContactSeries<Real>::Contact;

  // The series of (1) with damping `gamma` (γ at the entry, −γ at the exit) to x^terms, its work
  // (3) with the physical `dissipation` 2γ (if `with_work`), and its reach: the largest x at which
  // the terms left out stay below `tolerance` relative.
  ContactPointSeries(const Real& p, const Real& gamma, const Real& dissipation,
                     const Real& tolerance, int terms, bool with_work)
      : a_((p - 1) / 2), b_((p + 1) / 2), dissipation_(dissipation) {
    const std::size_t n = static_cast<std::size_t>(terms) + 1;
    // E = Y^a, E Z, Y^p = E² Y (its own power recurrence: one pass instead of two products) and
    // M = (E Z) Z.
    std::vector<Real> c(n), e(n), ez(n), yp(n), z(n), m(n), weighted_e(n), weighted_yp(n);
    const Real& kappa = b_;
    c[0] = e[0] = yp[0] = Real(1);
    for (std::size_t j = 0; j < n; ++j) {
      if (j > 0) {
        const Real jb = Real(j) * b_;
        Real rhs = -gamma * ez[j - 1];
        if (j >= 2) {
          rhs -= kappa * yp[j - 2];
        }
        c[j] = rhs / (jb * (1 + jb)); // (2)
        e[j] = power_coefficient(c, e, weighted_e, a_, j);
        yp[j] = power_coefficient(c, yp, weighted_yp, p, j);
        weighted_e[j] = Real(j) * e[j];
        weighted_yp[j] = Real(j) * yp[j];
      }
      z[j] = c[j] * (1 + Real(j) * b_);
      ez[j] = product_coefficient(e, z, j);
      if (with_work) {
        m[j] = product_coefficient(ez, z, j);
      }
    }
    y_ = std::move(c);
    z_ = std::move(z);
    // (3) as a polynomial in x: w_{j+1} = M_j / (b (j + 1)); zero without work.
    w_.assign(n + 1, Real(0));
    for (std::size_t j = 0; j < n; ++j) {
      w_[j + 1] = m[j] / (b_ * Real(j + 1));
    }
    reach_ = reach_of(tolerance);
  }

  Real a() const { return a_; }
  Real b() const { return b_; }
  // The series is used for x = u^a s^b ≤ reach() only.
  Real reach() const { return reach_; }
  Real x_of(const Real& u, const Real& s) const {
    using std::pow;
    return pow(u * s, a_) * s; // u^a s^(a+1), one power
  }
  // The s at which x reaches `x` for speed u.
  Real s_of(const Real& u, const Real& x) const {
    using std::pow;
    return pow(x / pow(u, a_), 1 / b_);
  }

  Point at(const Real& u, const Real& s) const override {
    const Real x = x_of(u, s);
    return {u * s * horner<Real>(y_, x), u * horner<Real>(z_, x),
            dissipation_ * u * u * horner<Real>(w_, x)};
  }
  Real entry_end(const Real& u, const Real& fraction) const override {
    // The first x within the reach at which dδ/ds has fallen to `fraction` of u, if any.
    std::vector<Real> shifted = z_;
    shifted[0] -= fraction;
    return s_of(u, first_sign_change<Real>(shifted, reach_).value_or(reach_));
  }
  bool within_reach(const Real& u, const Real& s) const override { return x_of(u, s) <= reach_; }

  // The contact point behind a state near it: the speed u at δ = 0 and the distance s to it, such
  // that δ(s) = delta and dδ/ds = rate. Newton's method on the two equations
  //     F1 = u s Y(x) − δ,   F2 = u Z(x) − rate,   x = u^a s^b   (∂x/∂u = a x/u, ∂x/∂s = b x/s)
  // from u = rate, s = δ / rate (the straight line), converging quadratically. None if it does not
  // converge to a point inside the reach: then the state is not near a return to δ = 0 (an
  // overdamped overlap decaying for ever, or still too far from the exit).
  std::optional<Contact> locate(const Real& delta, const Real& rate) const override {
    if (!(delta > 0 && rate > 0)) {
      return std::nullopt;
    }
    Real u = rate, s = delta / rate;
    for (int iteration = 0; iteration < 40; ++iteration) {
      const Real x = x_of(u, s);
      if (!(x <= reach_)) {
        return std::nullopt;
      }
      Real y, dy, z, dz;
      horner_with_derivative<Real>(y_, x, y, dy);
      horner_with_derivative<Real>(z_, x, z, dz);
      const Real f1 = u * s * y - delta, f2 = u * z - rate;
      const Real j11 = s * (y + a_ * x * dy), j12 = u * z;
      const Real j21 = z + a_ * x * dz, j22 = u * b_ * x * dz / s;
      const NewtonStep step = newton_step(u, s, f1, f2, j11, j12, j21, j22);
      if (step == NewtonStep::left_the_domain) {
        return std::nullopt;
      }
      if (step == NewtonStep::converged) {
        if (!(x_of(u, s) <= reach_)) {
          return std::nullopt;
        }
        return Contact{u, s};
      }
    }
    return std::nullopt;
  }

private:
  // The coefficients of a series with radius R in x grow like R^-j; an estimate of 1/R is the
  // largest |c_j|^(1/j) over the upper half of the terms (the lower ones still carry the
  // function's own scale). The terms left out at x = r R add up to ~ r^(J+1) / (1 − r), so
  // r = (tolerance / 4)^(1/(J+1)) keeps them below the tolerance. With J = twice the Taylor
  // order (1 − ½ ln tolerance), r ≈ e^-1: the series covers a third of its radius.
  // Where the solution is entire (p = 1, odd p) R is large and the terms can grow far beyond
  // their sum (e^(γ s) summed from alternating terms): the reach is then cut back until no sum
  // exceeds its value more than 16-fold, so that rounding stays within ~16 J ε (at γ = 2, p = 1
  // the energy balance of the series lost 6 digits at the radius-based reach).
  Real reach_of(const Real& tolerance) const {
    using std::abs;
    using std::exp;
    using std::log;
    const std::size_t terms = y_.size() - 1;
    // max |c_j|^(1/j) as max ln|c_j| / j: one logarithm per term instead of a power.
    Real log_inverse_radius = -std::numeric_limits<Real>::infinity();
    for (std::size_t j = (terms + 1) / 2; j <= terms; ++j) {
      for (const std::vector<Real>* coefficients : {&y_, &z_}) {
        const Real magnitude = abs((*coefficients)[j]);
        if (magnitude > 0) {
          log_inverse_radius = std::max(log_inverse_radius, Real(log(magnitude) / Real(j)));
        }
      }
    }
    const Real log_r = log(tolerance / 4) / Real(terms + 1);
    Real reach = log_inverse_radius > -std::numeric_limits<Real>::infinity()
                     ? Real(exp(log_r - log_inverse_radius))
                     : Real(1);
    for (int shrink = 0; shrink < 200 && cancels(reach); ++shrink) {
      reach *= Real(7) / 8;
    }
    return reach;
  }
  bool cancels(const Real& x) const {
    using std::abs;
    for (const std::vector<Real>* coefficients : {&y_, &z_, &w_}) {
      Real sum = Real(0), magnitude = Real(0), power = Real(1);
      for (const Real& coefficient : *coefficients) {
        sum += coefficient * power;
        magnitude += abs(coefficient * power);
        power *= x;
      }
      if (magnitude > 16 * abs(sum)) {
        return true;
      }
    }
    return false;
  }

  Real a_, b_, dissipation_;
  std::vector<Real> y_, z_, w_; // δ / (u s), dδ/ds / u, W / (2γ u²) as polynomials in x
  Real reach_;
};

} // namespace pldamp::solvers::detail
