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

#include "double_double.hpp"
#include "polynomial.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
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
  TwoLanes<Real> plain, by_degree;
  std::size_t j = 0;
  for (; j + 2 <= n; j += 2) {
    plain.add(f[n - j], f[n - j - 1], u[j], u[j + 1]);
    by_degree.add(f[n - j], f[n - j - 1], weighted[j], weighted[j + 1]);
  }
  for (; j < n; ++j) {
    plain.add(f[n - j], u[j]);
    by_degree.add(f[n - j], weighted[j]);
  }
  return (a * Real(n) * plain.sum() - (a + 1) * by_degree.sum()) / (Real(n) * f[0]);
}

enum class NewtonStep { left_the_domain, moving, converged };

// Newton's method at the exit starts from the straight line on the polynomials' first half
// (locate(), TwoPowerView::newton): within the reach their terms fall from 1 to ε, so the half
// left out is ~√ε and the truncated root lies that close to the whole one's. The whole polynomials
// take over after a step below ∛ε in both u and s (quadratic convergence has then reached the
// truncation) or after the sixth, and converge in one (newton_step).
template <class Real>
bool whole_from_now(const Real& u_before, const Real& u, const Real& s_before, const Real& s,
                    int iteration) {
  using std::abs;
  using std::cbrt;
  static const Real below = cbrt(std::numeric_limits<Real>::epsilon());
  return (abs(u - u_before) <= below * u && abs(s - s_before) <= below * s) || iteration == 5;
}

// One Newton step of a series' locate() on (u, s) for the residuals (f1, f2) with the Jacobian
// [[j11, j12], [j21, j22]] (columns ∂/∂u, ∂/∂s): converged when both moved by at most ε^(2/3)
// relative, left_the_domain when u or s is no longer positive. A step η that small puts the new
// point within ~(K/2) η² = (K/2) ε^(4/3) of the root (Kantorovich; K the residuals' relative
// curvature over their slope, of order 1 within the reach): below ε for K up to 2 ε^(−1/3), 3e5
// in double (MATH.md §9, "The contact point in t"). Waiting for a step of 4ε instead cost a
// whole-series iteration that moved nothing but rounding.
template <class Real>
NewtonStep newton_step(Real& u, Real& s, const Real& f1, const Real& f2, const Real& j11,
                       const Real& j12, const Real& j21, const Real& j22) {
  using std::abs;
  using std::cbrt;
  static const Real below = [] {
    const Real third = cbrt(std::numeric_limits<Real>::epsilon());
    return third * third;
  }();
  const Real det = j11 * j22 - j12 * j21;
  const Real du = (f2 * j12 - f1 * j22) / det, ds = (f1 * j21 - f2 * j11) / det;
  u += du;
  s += ds;
  if (!(u > 0 && s > 0)) {
    return NewtonStep::left_the_domain;
  }
  return abs(du) <= below * u && abs(ds) <= below * s ? NewtonStep::converged : NewtonStep::moving;
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
  // Its work alone, and δ and dδ/ds alone (work 0): a series may sum fewer terms for them (the
  // normal force's rate, searched for its peak on the entry stretch, needs no work).
  virtual Real work_at(const Real& u, const Real& s) const { return at(u, s).work; }
  virtual Point motion_at(const Real& u, const Real& s) const { return at(u, s); }
  // Where the entry series stops for speed u: its reach, and not past the time at which dδ/ds has
  // fallen to `fraction` of u (for odd p the series converges everywhere and would otherwise run
  // past the peak and round the whole contact). With `before_force_peak`, a series whose values
  // are dear (two_power_series.hpp) also stops before the normal force's peak, so that the steps,
  // not its values, locate that peak in every collision.
  virtual Real entry_end(const Real& u, const Real& fraction, bool before_force_peak) const = 0;
  // Whether (u, s) lies within the reach (the terms left out below the tolerance).
  virtual bool within_reach(const Real& u, const Real& s) const = 0;
  // The speed u at δ = 0 and the distance s to it of a state (delta, rate = dδ/ds), if that
  // contact point lies within the reach; none otherwise (an overdamped overlap decaying for
  // ever, or a state still too far from the exit).
  virtual std::optional<Contact> locate(const Real& delta, const Real& rate) const = 0;
};

// The recurrence (2) of the series, its power rules and products, over whole arrays of one
// arithmetic: extend() fills orders [from, to) from the orders below.
template <class T>
struct SeriesTerms {
  // E = Y^a, E Z, Y^p = E² Y (its own power recurrence: one pass instead of two products),
  // M = (E Z) Z, and j E_j, j (Y^p)_j for the two-product power rule.
  std::vector<T> c, e, ez, yp, z, m, weighted_e, weighted_yp;
  explicit SeriesTerms(std::size_t n)
      : c(n), e(n), ez(n), yp(n), z(n), m(n), weighted_e(n), weighted_yp(n) {}
  template <class Other, class Convert>
  void assign(const SeriesTerms<Other>& other, std::size_t from, std::size_t to, Convert convert) {
    for (std::size_t j = from; j < to; ++j) {
      c[j] = convert(other.c[j]);
      e[j] = convert(other.e[j]);
      ez[j] = convert(other.ez[j]);
      yp[j] = convert(other.yp[j]);
      z[j] = convert(other.z[j]);
      m[j] = convert(other.m[j]);
      weighted_e[j] = convert(other.weighted_e[j]);
      weighted_yp[j] = convert(other.weighted_yp[j]);
    }
  }
};
template <class T>
struct Parameters {
  T a, b, p, gamma; // κ = b
};

template <class T>
void extend(SeriesTerms<T>& s, const Parameters<T>& k, std::size_t from, std::size_t to,
            bool with_work) {
  for (std::size_t j = from; j < to; ++j) {
    if (j == 0) {
      s.c[0] = s.e[0] = s.yp[0] = T(1);
      s.weighted_e[0] = s.weighted_yp[0] = T(0);
    } else {
      const T jb = T(j) * k.b;
      T rhs = -k.gamma * s.ez[j - 1];
      if (j >= 2) {
        rhs = rhs - k.b * s.yp[j - 2];
      }
      s.c[j] = rhs / (jb * (1 + jb)); // (2)
      s.e[j] = power_coefficient(s.c, s.e, s.weighted_e, k.a, j);
      s.yp[j] = power_coefficient(s.c, s.yp, s.weighted_yp, k.p, j);
      s.weighted_e[j] = T(j) * s.e[j];
      s.weighted_yp[j] = T(j) * s.yp[j];
    }
    s.z[j] = s.c[j] * (1 + T(j) * k.b);
    s.ez[j] = product_coefficient(s.e, s.z, j);
    s.m[j] = with_work ? product_coefficient(s.ez, s.z, j) : T(0);
  }
}

// Converting to and from the tiers' arithmetic.
template <class T, class Real>
T narrowed(const Real& x) {
  if constexpr (std::is_same_v<T, double>) {
    return static_cast<double>(x);
  } else {
    return T::from(x);
  }
}
template <class Real, class T>
Real widened(const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    return Real(x);
  } else {
    return x.template to<Real>();
  }
}

// Orders [from, to) of `s` summed in T, from the orders below rounded to it, written back.
template <class T, class Real>
void extend_in(SeriesTerms<Real>& s, const Parameters<Real>& k, std::size_t from, std::size_t to,
               bool with_work) {
  if (from >= to) {
    return;
  }
  SeriesTerms<T> tier(to);
  tier.assign(s, 0, from, [](const Real& x) { return narrowed<T>(x); });
  extend(tier,
         Parameters<T>{narrowed<T>(k.a), narrowed<T>(k.b), narrowed<T>(k.p), narrowed<T>(k.gamma)},
         from, to, with_work);
  s.assign(tier, from, to, [](const T& x) { return widened<Real>(x); });
}

template <class Real>
class ContactPointSeries final : public ContactSeries<Real> {
public:
  using typename ContactSeries<Real>::Point;
  using typename ContactSeries<Real>::Contact;

  // How the high orders are summed wider than double-double: in cheaper tiers kept where the
  // bound allows (the solver's), or (for the tests) never, or always whatever the bound says.
  enum class Tiers { by_bound, never, always };

  // The series of (1) with damping `gamma` (γ at the entry, −γ at the exit) to x^terms, its work
  // (3) with the physical `dissipation` 2γ (if `with_work`), and its reach: the largest x at which
  // the terms left out stay below `tolerance` relative.
  ContactPointSeries(const Real& p, const Real& gamma, const Real& dissipation,
                     const Real& tolerance, int terms, bool with_work,
                     Tiers tiers = Tiers::by_bound)
      : a_((p - 1) / 2), b_((p + 1) / 2), dissipation_(dissipation) {
    const std::size_t n = static_cast<std::size_t>(terms) + 1;
    const Parameters<Real> exact{a_, b_, p, gamma};
    SeriesTerms<Real> built(n);
    std::size_t exact_to = 0;
    if constexpr (std::numeric_limits<Real>::digits > 106) {
      // Wider than double-double the high orders are summed in it and in double, and kept only if
      // the running bound says they moved the series by at most tolerance/1024 (MATH.md §9,
      // "Tiered series"); else again with the tiers starting later, else all in Real.
      for (const double cancellation : {1e3, 1e9}) {
        if (tiers == Tiers::never) {
          break;
        }
        const TierStarts starts = tier_starts(tolerance, n, cancellation);
        extend(built, exact, exact_to, starts.double_double, with_work);
        exact_to = starts.double_double;
        extend_in<DoubleDouble>(built, exact, starts.double_double, starts.plain_double, with_work);
        extend_in<double>(built, exact, starts.plain_double, n, with_work);
        adopt(built, tolerance, with_work);
        tier_bound_ = tier_error(built, exact, starts, with_work);
        if (tier_bound_ <= tolerance / 1024 || tiers == Tiers::always) {
          tiered_ = true;
          return;
        }
      }
    }
    extend(built, exact, exact_to, n, with_work);
    adopt(built, tolerance, with_work);
  }

  // Whether the high orders were kept from the cheaper arithmetic (else rebuilt in Real), and the
  // bound of the last tiered build tried on how far that moved Y, Z or W at the reach.
  bool tiered() const { return tiered_; }
  const Real& tier_bound() const { return tier_bound_; }
  // The polynomials in x of δ/(u s), (dδ/ds)/u and W/(2γ u²) (at() sums them).
  const std::vector<Real>& overlap_polynomial() const { return y_; }
  const std::vector<Real>& rate_polynomial() const { return z_; }
  const std::vector<Real>& work_polynomial() const { return w_; }

  Real a() const { return a_; }
  Real b() const { return b_; }
  const Real& dissipation() const { return dissipation_; }
  // The series is used for x = u^a s^b ≤ reach() only.
  Real reach() const { return reach_; }
  Real x_of(const Real& u, const Real& s) const {
    return power_of(u * s, a_) * s; // u^a s^(a+1), one power
  }
  // The s at which x reaches `x` for speed u.
  Real s_of(const Real& u, const Real& x) const {
    using std::pow;
    return pow(x / pow(u, a_), 1 / b_);
  }

  Point at(const Real& u, const Real& s) const override {
    Point point = motion_at(u, s);
    point.work = work_at(u, s);
    return point;
  }
  Point motion_at(const Real& u, const Real& s) const override {
    const Real x = x_of(u, s);
    return {u * s * horner<Real>(y_, x), u * horner<Real>(z_, x), Real(0)};
  }
  Real work_at(const Real& u, const Real& s) const override {
    return dissipation_ * u * u * horner<Real>(w_, x_of(u, s));
  }
  // Its values cost 2N terms, about what a step's polynomials do: a force peak within its
  // stretch is found on it (before_force_peak does not apply).
  Real entry_end(const Real& u, const Real& fraction, bool) const override {
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
    // The first iterations on the polynomials' first half (whole_from_now).
    const std::size_t whole = y_.size();
    std::size_t terms = (whole + 1) / 2;
    for (int iteration = 0; iteration < 40; ++iteration) {
      const Real x = x_of(u, s);
      if (!(x <= reach_)) {
        return std::nullopt;
      }
      std::array<Real, 2> value, slope; // Y and Z, and their derivatives in x
      horner_pair_with_derivative<Real>(std::span<const Real>(y_).first(terms),
                                        std::span<const Real>(z_).first(terms), x, value, slope);
      const Real &y = value[0], &z = value[1], &dy = slope[0], &dz = slope[1];
      const Real f1 = u * s * y - delta, f2 = u * z - rate;
      const Real j11 = s * (y + a_ * x * dy), j12 = u * z;
      const Real j21 = z + a_ * x * dz, j22 = u * b_ * x * dz / s;
      const Real u_before = u, s_before = s;
      const NewtonStep step = newton_step(u, s, f1, f2, j11, j12, j21, j22);
      if (step == NewtonStep::left_the_domain) {
        return std::nullopt;
      }
      if (terms < whole) {
        if (whole_from_now(u_before, u, s_before, s, iteration)) {
          terms = whole;
        }
        continue; // never converged on the truncated polynomials
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
  // The series' polynomials from the recurrence's arrays, and their reach.
  void adopt(const SeriesTerms<Real>& built, const Real& tolerance, bool with_work) {
    const std::size_t n = built.c.size();
    y_ = built.c;
    z_ = built.z;
    // (3) as a polynomial in x: w_{j+1} = M_j / (b (j + 1)); zero without work.
    w_.assign(n + 1, Real(0));
    if (with_work) {
      for (std::size_t j = 0; j < n; ++j) {
        w_[j + 1] = built.m[j] / (b_ * Real(j + 1));
      }
    }
    reach_ = reach_of(tolerance);
  }

  // Where the cheaper tiers start. At the reach the term of order j is about (tolerance/4)^(j/n)
  // of the sum (reach_of), and a coefficient summed with unit roundoff u errs by about
  // n u `cancellation` times it, the factor by which the sizes it sums exceed it (a power rule of
  // an alternating series cancels like 2^j): order j goes to a tier once that is below
  // tolerance/1024. In float128 at ε (n = 61) and cancellation 1e3: double-double from order 19,
  // double from 47 (accepted by the bound for 85 of 96 (p, ±γ) in p 1–5, γ 0.01–4; the rest are
  // exits of strong damping, whose series grow like e^(γs), and p = 1).
  struct TierStarts {
    std::size_t double_double, plain_double;
  };
  static TierStarts tier_starts(const Real& tolerance, std::size_t n, double cancellation) {
    const double log_tolerance = std::log(static_cast<double>(tolerance));
    auto start = [&](double unit_roundoff) {
      const double wanted =
          log_tolerance - std::log(1024 * cancellation * double(n) * unit_roundoff);
      const double fraction = std::clamp(wanted / (log_tolerance - std::log(4.0)), 0.0, 1.0);
      return std::min(n, static_cast<std::size_t>(std::ceil(fraction * double(n))));
    };
    const std::size_t dd = std::max<std::size_t>(2, start(tier_roundoff<DoubleDouble>()));
    return {dd, std::max(dd, start(tier_roundoff<double>()))};
  }
  template <class T>
  static constexpr double tier_roundoff() {
    // Double-double's operations are not correctly rounded: 4 ulps of 2^-106 (as taylor.cpp's
    // tiers); float128's own rounding, which the tiers replace, is added where it is used.
    return std::is_same_v<T, double> ? std::numeric_limits<double>::epsilon() / 2
                                     : std::ldexp(1.0, -104);
  }

  // A first-order bound on how far the tiered coefficients lie from those Real would have summed,
  // evaluated as the largest of |ΔY|, |ΔZ| and the work's |ΔW| (in its physical units) at the
  // reach (MATH.md §9, "Tiered series"). Orders below the first tier are the same numbers either
  // way (bound 0); above, every coefficient's bound is what its inputs' bounds carry through the
  // recurrence (|f| b(g) + b(f) |g| term by term) plus its own rounding, (terms + 4) units of
  // its tier and of Real times the sum of the magnitudes it adds: a cancelling sum pays for the
  // sizes of its terms, not of its result. Carried in double, beside the magnitudes.
  Real tier_error(const SeriesTerms<Real>& s, const Parameters<Real>& k, const TierStarts& starts,
                  bool with_work) const {
    const std::size_t n = s.c.size();
    const double real_roundoff = std::ldexp(1.0, -std::numeric_limits<Real>::digits);
    auto unit = [&](std::size_t j) {
      if (j < starts.double_double) {
        return 0.0;
      }
      return real_roundoff +
             (j < starts.plain_double ? tier_roundoff<DoubleDouble>() : tier_roundoff<double>());
    };
    auto magnitudes = [&](const std::vector<Real>& v) {
      std::vector<double> out(n);
      for (std::size_t j = 0; j < n; ++j) {
        out[j] = std::abs(static_cast<double>(v[j]));
      }
      return out;
    };
    const std::vector<double> c = magnitudes(s.c), e = magnitudes(s.e), ez = magnitudes(s.ez),
                              yp = magnitudes(s.yp), z = magnitudes(s.z), m = magnitudes(s.m);
    std::vector<double> bc(n), be(n), bez(n), byp(n), bz(n), bm(n), bw(n + 1);
    const double a = static_cast<double>(k.a), b = static_cast<double>(k.b),
                 p = static_cast<double>(k.p), gamma = std::abs(static_cast<double>(k.gamma));
    // Σ_{i=0}^{j} |f_i| b(g_{j−i}) + b(f_i) |g_{j−i}| and Σ |f_i g_{j−i}|.
    auto product = [&](const std::vector<double>& f, const std::vector<double>& bf,
                       const std::vector<double>& g, const std::vector<double>& bg, std::size_t j,
                       double u) {
      double carried = 0, size = 0;
      for (std::size_t i = 0; i <= j; ++i) {
        carried += f[i] * bg[j - i] + bf[i] * g[j - i];
        size += f[i] * g[j - i];
      }
      return carried + double(j + 4) * u * size;
    };
    // u_j = Y^x by the two-sum power rule (f = c, f_0 = 1): its weights |x j − (x + 1) i|.
    auto power = [&](const std::vector<double>& u_mag, const std::vector<double>& bu, double x,
                     std::size_t j, double u) {
      double carried = 0, size = 0;
      for (std::size_t i = 0; i < j; ++i) {
        const double weight = std::abs(x * double(j) - (x + 1) * double(i));
        carried += weight * (c[j - i] * bu[i] + bc[j - i] * u_mag[i]);
        size += (std::abs(x) * double(j) + std::abs(x + 1) * double(i)) * c[j - i] * u_mag[i];
      }
      return (carried + double(j + 4) * u * size) / double(j);
    };
    for (std::size_t j = starts.double_double; j < n; ++j) {
      const double u = unit(j), jb = double(j) * b;
      const double rhs = gamma * ez[j - 1] + (j >= 2 ? b * yp[j - 2] : 0.0);
      const double rhs_bound = gamma * bez[j - 1] + (j >= 2 ? b * byp[j - 2] : 0.0);
      bc[j] = (rhs_bound + 4 * u * rhs) / (jb * (1 + jb));
      be[j] = power(e, be, a, j, u);
      byp[j] = power(yp, byp, p, j, u);
      bz[j] = bc[j] * (1 + jb) + 2 * u * z[j];
      bez[j] = product(e, be, z, bz, j, u);
      if (with_work) {
        bm[j] = product(ez, bez, z, bz, j, u);
        bw[j + 1] = (bm[j] + 2 * u * m[j]) / (b * double(j + 1));
      }
    }
    const double x = static_cast<double>(reach_);
    auto at_reach = [&](const std::vector<double>& bound) {
      double sum = 0, power_of_x = 1;
      for (const double coefficient : bound) {
        sum += coefficient * power_of_x;
        power_of_x *= x;
      }
      return sum;
    };
    return Real(std::max(
        {at_reach(bc), at_reach(bz), std::abs(static_cast<double>(dissipation_)) * at_reach(bw)}));
  }

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
    // max |c_j|^(1/j) as max ln|c_j| / j: one logarithm per term instead of a power, taken in
    // double where |c_j| is a normal double (an estimate of the radius needs no more; in float128
    // the logarithms were a tenth of building the series).
    auto log_of = [](const Real& magnitude) {
      const double narrow = static_cast<double>(magnitude);
      return std::isnormal(narrow) ? Real(std::log(narrow)) : Real(log(magnitude));
    };
    Real log_inverse_radius = -std::numeric_limits<Real>::infinity();
    for (std::size_t j = (terms + 1) / 2; j <= terms; ++j) {
      for (const std::vector<Real>* coefficients : {&y_, &z_}) {
        const Real magnitude = abs((*coefficients)[j]);
        if (magnitude > 0) {
          log_inverse_radius = std::max(log_inverse_radius, Real(log_of(magnitude) / Real(j)));
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
  // Whether a sum at x exceeds its value more than 16-fold: a threshold, decided in double (terms
  // below double's range count as 0, which cannot tip a sum of size 1/16 or more).
  bool cancels(const Real& x) const {
    const double at = static_cast<double>(x);
    for (const std::vector<Real>* coefficients : {&y_, &z_, &w_}) {
      double sum = 0, magnitude = 0, power = 1;
      for (const Real& coefficient : *coefficients) {
        const double term = static_cast<double>(coefficient) * power;
        sum += term;
        magnitude += std::abs(term);
        power *= at;
      }
      if (magnitude > 16 * std::abs(sum)) {
        return true;
      }
    }
    return false;
  }

  Real a_, b_, dissipation_;
  std::vector<Real> y_, z_, w_; // δ / (u s), dδ/ds / u, W / (2γ u²) as polynomials in x
  Real reach_;
  bool tiered_ = false;
  Real tier_bound_ = Real(0);
};

} // namespace pldamp::solvers::detail
