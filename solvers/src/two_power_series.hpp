// The contact-point series for any damping exponent β (MATH.md §12.3): the entry and exit of
//     δ'' + γ δ^β δ' + κ δ^p = 0,   κ = (p+1)/2,                                             (1)
// the taylor solver's scaled equation (contact_series.hpp) with the dashpot δ^β of MATH.md §12.
//
// For the seed's β = (p−1)/2 one variable x = u^a s^b resolves the branch point at δ = 0. In
// general the dashpot and the spring bring two powers of s that need not be commensurate: near a
// contact point passed at speed u, with s the time from it (backward at the exit),
//     δ = u s Y(x1, x2),   x1 = σ γ u^β s^(β+1),   x2 = κ u^(p−1) s^(p+1),   σ = ±1,
// where σ = +1 at the entry and −1 at the exit (time reversal turns the dashpot's sign), and
//     Y = Σ c_ij x1^i x2^j,   c_00 = 1,   λ_ij = 1 + i (β+1) + j (p+1)
// (each term of Y is u s^λ_ij up to constants). With d/ds (s x1^i x2^j) = λ_ij x1^i x2^j,
//     dδ/ds = u Z,   Z = Σ λ_ij c_ij x1^i x2^j,   d²δ/ds² = (u/s) Σ λ_ij (λ_ij − 1) c_ij …,
//     σγ δ^β dδ/ds = (u/s) x1 E Z,   κ δ^p = (u/s) x2 P,   E = Y^β,  P = Y^p,
// and (1) divided by u/s, term by term, is the recurrence
//     c_ij λ_ij (λ_ij − 1) = −(E Z)_(i−1, j) − P_(i, j−1).                                    (2)
// The coefficients depend on (p, β) alone: γ, κ, u and σ enter only through x1 and x2, so one
// table serves the entry, the exit and every damping of a (p, β) (cached, table_for). The work
// from s = 0, ∫ 2γ δ^β (dδ/ds)² ds = 2γ u² ∫ u^β σ'^β E Z² dσ', is with M = E Z²
//     W = 2σ u² W̃,   W̃ = Σ M_ij x1^(i+1) x2^j / ((i+1)(β+1) + j(p+1))                  (3)
// (∫₀^s u^β σ'^β x1^i x2^j dσ' = x1^(i+1) x2^j / (σγ ((i+1)(β+1) + j(p+1)))).
// E and P follow by the power recurrence under the Euler operator of total degree n = i + j
// (x1 ∂1 + x2 ∂2 applied to E = Y^β: Y D E = β E D Y), as power_coefficient in one variable.
//
// Truncation: total degree i + j ≤ D. A product or power over the triangle costs
// C(D + 4, 4) ≈ D⁴/24 operations, which is why the table is cached, and why D is the Taylor
// order (not twice it, as for the one-variable series): its reach is then ~ε^(1/D) ≈ e^−2 of the
// radius, and the Taylor steps take over from there.
#pragma once

#include "contact_series.hpp"
#include "stored_tables.hpp"

#include "pldamp/core/real_types.hpp"
#include "pldamp/solvers/contact_ode.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

namespace pldamp::solvers::detail {

// Coefficients over the triangle i + j ≤ degree, row by row in i.
class Triangle {
public:
  explicit Triangle(int degree) : degree_(degree) {}
  int degree() const { return degree_; }
  std::size_t size() const { return static_cast<std::size_t>((degree_ + 1) * (degree_ + 2) / 2); }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(i * (degree_ + 1) - i * (i - 1) / 2 + j);
  }

private:
  int degree_;
};

template <class Real>
struct TwoPowerTable {
  Real p, beta;
  Triangle shape;            // Y and Z: i + j ≤ D
  Triangle work_shape;       // W̃: i + j ≤ D + 1 (i ≥ 1)
  std::vector<Real> y, z, w; // c_ij, λ_ij c_ij, and W̃'s coefficients
  // The same rounded to double, for a Real wider than long double: the searches that only decide
  // where to stop (the reach, the entry's end) and locate's first Newton steps run on it.
  std::shared_ptr<const TwoPowerTable<double>> coarse;
};

// Whether a series in Real searches in double first (soft-float arithmetic is ~30 times slower).
template <class Real>
inline constexpr bool searches_in_double =
    std::numeric_limits<Real>::digits > std::numeric_limits<long double>::digits;

namespace two_power_detail {

// λ_ij = 1 + i (β+1) + j (p+1), with b1 = β + 1 and b2 = p + 1: the same operations wherever a
// table is made (build, or from stored coefficients), so that its Z is the same bit for bit.
template <class Real>
Real exponent(const Real& b1, const Real& b2, int i, int j) {
  return 1 + Real(i) * b1 + Real(j) * b2;
}

// (f g)_ij = Σ_{k ≤ i, l ≤ j} f_kl g_(i−k)(j−l).
template <class Real>
Real product(const Triangle& t, const std::vector<Real>& f, const std::vector<Real>& g, int i,
             int j) {
  Real sum = Real(0);
  for (int k = 0; k <= i; ++k) {
    for (int l = 0; l <= j; ++l) {
      sum += f[t.index(k, l)] * g[t.index(i - k, j - l)];
    }
  }
  return sum;
}

// The (i, j) coefficient (i + j = n ≥ 1) of u = f^a, f_00 = 1, from the lower ones:
//     n u_ij = Σ_{(k,l) < (i,j)} (a (n − k − l) − (k + l)) f_(i−k)(j−l) u_kl
//            = a n Σ f_(i−k)(j−l) u_kl − (a + 1) Σ f_(i−k)(j−l) (k + l) u_kl,
// the second form with `weighted` = (k + l) u_kl kept beside u: two products a term instead of
// three and two integer conversions (the table's build in float128 is these sums).
template <class Real>
Real power(const Triangle& t, const std::vector<Real>& f, const std::vector<Real>& u,
           const std::vector<Real>& weighted, const Real& a, int i, int j) {
  const int n = i + j;
  Real plain = Real(0), by_degree = Real(0);
  for (int k = 0; k <= i; ++k) {
    for (int l = 0; l <= j; ++l) {
      if (k == i && l == j) {
        continue;
      }
      const Real& factor = f[t.index(i - k, j - l)];
      plain += factor * u[t.index(k, l)];
      by_degree += factor * weighted[t.index(k, l)];
    }
  }
  return (a * Real(n) * plain - (a + 1) * by_degree) / Real(n);
}

template <class Real>
std::shared_ptr<TwoPowerTable<Real>> build(const Real& p, const Real& beta, int degree) {
  auto table = std::make_shared<TwoPowerTable<Real>>(
      TwoPowerTable<Real>{p, beta, Triangle(degree), Triangle(degree + 1), {}, {}, {}, nullptr});
  const Triangle& t = table->shape;
  const std::size_t n = t.size();
  std::vector<Real> c(n, Real(0)), e(n, Real(0)), power_p(n, Real(0)), z(n, Real(0)),
      ez(n, Real(0)), m(n, Real(0)), weighted_e(n, Real(0)), weighted_p(n, Real(0));
  c[0] = e[0] = power_p[0] = Real(1);
  const Real b1 = beta + 1, b2 = p + 1;
  for (int total = 0; total <= degree; ++total) {
    for (int i = 0; i <= total; ++i) {
      const int j = total - i;
      const std::size_t ij = t.index(i, j);
      const Real lambda = exponent(b1, b2, i, j);
      if (total > 0) {
        Real rhs = Real(0);
        if (i > 0) {
          rhs -= ez[t.index(i - 1, j)];
        }
        if (j > 0) {
          rhs -= power_p[t.index(i, j - 1)];
        }
        c[ij] = rhs / (lambda * (lambda - 1)); // (2)
        e[ij] = power(t, c, e, weighted_e, beta, i, j);
        power_p[ij] = power(t, c, power_p, weighted_p, p, i, j);
        weighted_e[ij] = Real(total) * e[ij];
        weighted_p[ij] = Real(total) * power_p[ij];
      }
      z[ij] = lambda * c[ij];
      ez[ij] = product(t, e, z, i, j);
      m[ij] = product(t, ez, z, i, j);
    }
  }
  const Triangle& tw = table->work_shape;
  table->w.assign(tw.size(), Real(0));
  for (int i = 0; i <= degree; ++i) {
    for (int j = 0; i + j <= degree; ++j) {
      table->w[tw.index(i + 1, j)] = m[t.index(i, j)] / (Real(i + 1) * b1 + Real(j) * b2); // (3)
    }
  }
  table->y = std::move(c);
  table->z = std::move(z);
  return table;
}

// The table to a lower degree, from a wider one: each coefficient of total degree n is made from
// those below n alone, by the same operations in the same order whatever the degree, so this is
// build(p, β, degree) bit for bit (damping_exponent_test) at a copy's cost.
template <class Real>
std::shared_ptr<TwoPowerTable<Real>> prefix(const TwoPowerTable<Real>& wide, int degree) {
  auto table = std::make_shared<TwoPowerTable<Real>>(TwoPowerTable<Real>{
      wide.p, wide.beta, Triangle(degree), Triangle(degree + 1), {}, {}, {}, nullptr});
  const std::pair<const Triangle*, std::vector<Real>*> parts[] = {
      {&table->shape, &table->y}, {&table->shape, &table->z}, {&table->work_shape, &table->w}};
  const std::vector<Real>* wide_parts[] = {&wide.y, &wide.z, &wide.w};
  const Triangle* wide_shapes[] = {&wide.shape, &wide.shape, &wide.work_shape};
  for (std::size_t part = 0; part < 3; ++part) {
    const Triangle& shape = *parts[part].first;
    std::vector<Real>& out = *parts[part].second;
    out.assign(shape.size(), Real(0));
    for (int i = 0; i <= shape.degree(); ++i) {
      for (int j = 0; i + j <= shape.degree(); ++j) {
        out[shape.index(i, j)] = (*wide_parts[part])[wide_shapes[part]->index(i, j)];
      }
    }
  }
  return table;
}

// A table kept in the source (stored_tables.hpp) for this (p, β), if Real is float128 and one is:
// the stored coefficients of Y and W̃, and Z made from Y as build makes it.
template <class Real>
std::shared_ptr<TwoPowerTable<Real>> from_stored(const Real& p, const Real& beta) {
#if PLDAMP_WITH_QUAD
  if constexpr (std::same_as<Real, quad> && std::endian::native == std::endian::little) {
    const auto value = [](std::span<const std::uint64_t> words, std::size_t k) {
      return quad(std::bit_cast<__float128>(std::array{words[2 * k], words[2 * k + 1]}));
    };
    for (const StoredTable& stored : stored_tables) {
      if (value(stored.p, 0) != p || value(stored.beta, 0) != beta) {
        continue;
      }
      auto table = std::make_shared<TwoPowerTable<Real>>(TwoPowerTable<Real>{
          p, beta, Triangle(stored.degree), Triangle(stored.degree + 1), {}, {}, {}, nullptr});
      const Triangle& t = table->shape;
      if (stored.y.size() != 2 * t.size() || stored.w.size() != 2 * table->work_shape.size()) {
        return nullptr; // not this build's layout: build instead
      }
      const Real b1 = beta + 1, b2 = p + 1;
      table->y.resize(t.size());
      table->z.resize(t.size());
      for (int i = 0; i <= t.degree(); ++i) {
        for (int j = 0; i + j <= t.degree(); ++j) {
          const std::size_t ij = t.index(i, j);
          table->y[ij] = value(stored.y, ij);
          table->z[ij] = exponent(b1, b2, i, j) * table->y[ij];
        }
      }
      table->w.resize(table->work_shape.size());
      for (std::size_t k = 0; k < table->w.size(); ++k) {
        table->w[k] = value(stored.w, k);
      }
      return table;
    }
  }
#endif
  static_cast<void>(p);
  static_cast<void>(beta);
  return nullptr;
}

} // namespace two_power_detail

// The table of (p, β) to total degree D, made once per process: taken from the source where it is
// kept there (stored_tables.hpp: float128, the viscoelastic (3/2, 1/2)), else built (25 ms in
// float128 at D = 40), and shared by every solve of that (p, β) in that precision (a scene's
// truths differ in γ only). A lower degree is cut from a wider table (the truth's error estimate
// solves again one order lower: MATH.md §12.2).
template <class Real>
std::shared_ptr<const TwoPowerTable<Real>> table_for(const Real& p, const Real& beta, int degree) {
  static std::mutex mutex;
  static std::map<std::tuple<Real, Real, int>, std::shared_ptr<const TwoPowerTable<Real>>> cache;
  const std::tuple<Real, Real, int> key{p, beta, degree};
  std::shared_ptr<const TwoPowerTable<Real>> wider;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto found = cache.find(key); found != cache.end()) {
      return found->second;
    }
    // The least degree above this one of the same (p, β), if any.
    const auto above = cache.upper_bound(key);
    if (above != cache.end() && std::get<0>(above->first) == p &&
        std::get<1>(above->first) == beta) {
      wider = above->second;
    }
  }
  // Outside the lock: other keys proceed.
  std::shared_ptr<TwoPowerTable<Real>> table;
  if (wider) {
    table = two_power_detail::prefix(*wider, degree);
  } else if (auto stored = two_power_detail::from_stored(p, beta);
             stored && stored->shape.degree() >= degree) {
    table = stored->shape.degree() == degree ? std::move(stored)
                                             : two_power_detail::prefix(*stored, degree);
  } else {
    table = two_power_detail::build(p, beta, degree);
  }
  if constexpr (searches_in_double<Real>) {
    const auto rounded = [](const std::vector<Real>& c) {
      return std::vector<double>(c.begin(), c.end());
    };
    table->coarse = std::make_shared<const TwoPowerTable<double>>(TwoPowerTable<double>{
        static_cast<double>(p), static_cast<double>(beta), table->shape, table->work_shape,
        rounded(table->y), rounded(table->z), rounded(table->w), nullptr});
  }
  const std::lock_guard<std::mutex> lock(mutex);
  if (cache.size() >= 64) {
    cache.clear(); // a sweep over many (p, β): rebuild rather than grow without bound
  }
  cache.emplace(key, table);
  return table;
}

// A table with a damping (σγ) and κ: what the series computes, in the table's type T. The
// series in Real uses one over its table and, where searches_in_double, one over the table's
// double copy for what only decides where to stop.
template <class T>
class TwoPowerView {
public:
  TwoPowerView(const TwoPowerTable<T>* table, const T& damping, const T& kappa, const T& tail_limit)
      : table_(table), damping_(damping), kappa_(kappa), tail_limit_(tail_limit) {}

  const TwoPowerTable<T>& table() const { return *table_; }

  // x1 = σγ (u s)^β s and x2 = κ (u s)^(p−1) s²: two powers instead of four, and one where
  // β = p − 1 (Hertz's spring with the viscoelastic dashpot). Newton's iterations at the exit
  // take these at every step (powers were a seventh of a double viscoelastic collision).
  std::pair<T, T> variables(const T& u, const T& s) const {
    const T p = table_->p, beta = table_->beta;
    const T us = u * s;
    const T damped = power_of(us, beta);
    const T sprung = beta == p - 1 ? damped : power_of(us, p - 1);
    return {damping_ * damped * s, kappa_ * sprung * s * s};
  }

  // Σ_i x1^i (Σ_j c_ij x2^j), Horner's rule in both (the values: its rounding is the smaller).
  // Up to total degree `degree` (the whole triangle by default).
  static T evaluate(const Triangle& t, const std::vector<T>& c, const T& x1, const T& x2,
                    int degree = -1) {
    degree = degree < 0 ? t.degree() : std::min(degree, t.degree());
    T sum = T(0);
    for (int i = degree; i >= 0; --i) {
      const T* coefficients = &c[t.index(i, 0)]; // row i is contiguous
      T row = T(0);
      for (int j = degree - i; j >= 0; --j) {
        row = row * x2 + coefficients[j];
      }
      sum = sum * x1 + row;
    }
    return sum;
  }
  // x^0 … x^degree.
  static void fill_powers(std::vector<T>& powers, const T& x, int degree) {
    powers.resize(static_cast<std::size_t>(degree) + 1);
    T power = T(1);
    for (T& entry : powers) {
      entry = power;
      power *= x;
    }
  }

  // The same where T is soft-float (searches_in_double), for one of the table's polynomials `c`
  // and its double copy: the shells of total degree n ≥ n0 are summed in double, n0 the least for
  // which their rounding, (4D + 8) 2^−53 Σ |c_ij x1^i x2^j| over them (coefficients, powers and
  // sums rounded), is at most tolerance/1024 of the series' unit; the shells below in T. At the
  // entry's end, where every shell counts, n0 is about 0.7 D; at an exit, lower (MATH.md §12.3).
  T value(const Triangle& t, const std::vector<T>& c, const std::vector<double>& coarse,
          const T& x1, const T& x2) const {
    if constexpr (!searches_in_double<T>) {
      return evaluate(t, c, x1, x2);
    } else {
      constexpr int most = 128; // shells kept on the stack; a wider table is summed in T
      const int degree = t.degree();
      if (degree >= most) {
        return evaluate(t, c, x1, x2);
      }
      std::array<double, most> shell{}, size{};
      const double a1 = static_cast<double>(x1), a2 = static_cast<double>(x2);
      double power1 = 1;
      for (int i = 0; i <= degree; ++i, power1 *= a1) {
        double power = power1;
        for (int j = 0; i + j <= degree; ++j, power *= a2) {
          const double term = coarse[t.index(i, j)] * power;
          shell[i + j] += term;
          size[i + j] += std::abs(term);
        }
      }
      const double unit = (4.0 * degree + 8) * std::ldexp(1.0, -53);
      const double allowed = static_cast<double>(tail_limit_) / 128; // tolerance / 1024
      int split = degree + 1;
      double high = 0, high_size = 0;
      while (split > 0 && unit * (high_size + size[split - 1]) <= allowed) {
        --split;
        high += shell[split];
        high_size += size[split];
      }
      return (split > 0 ? evaluate(t, c, x1, x2, split - 1) : T(0)) + T(high);
    }
  }

  struct Euler {
    T value, d1, d2; // Σ c x1^i x2^j, Σ i c …, Σ j c …
  };
  // Two polynomials of the triangle (Y and Z in Newton's iteration) and their Euler derivatives
  // x1 ∂/∂x1 and x2 ∂/∂x2 at once, up to total degree `degree` (the whole triangle by default).
  // Each row is a dot product with the powers of x2 and with j x2^j, in two lanes (TwoLanes):
  // by Horner's rule every term waited for the last, and Newton's iterations were a fifth of a
  // double viscoelastic collision. WithSizes: also Σ |c x1^i x2^j| of each into `sizes` (for the
  // cancellation guard; x2 = κ (us)^(p−1) s² > 0, so its powers are their own sizes).
  template <bool WithSizes = false>
  static std::array<Euler, 2> euler_pair_of(const Triangle& t, const std::vector<T>& a,
                                            const std::vector<T>& b, const T& x1, const T& x2,
                                            int degree = -1, std::array<T, 2>* sizes = nullptr) {
    using std::abs;
    degree = degree < 0 ? t.degree() : std::min(degree, t.degree());
    thread_local std::vector<T> powers, weighted; // x2^j and j x2^j
    fill_powers(powers, x2, degree);
    weighted.resize(powers.size());
    for (std::size_t j = 0; j < powers.size(); ++j) {
      weighted[j] = T(static_cast<int>(j)) * powers[j];
    }
    std::array<Euler, 2> sum{Euler{T(0), T(0), T(0)}, Euler{T(0), T(0), T(0)}};
    std::array<T, 2> size_sum{T(0), T(0)};
    T power1 = T(1);
    for (int i = 0; i <= degree; ++i, power1 *= x1) {
      const T *row_a = &a[t.index(i, 0)], *row_b = &b[t.index(i, 0)]; // rows are contiguous
      // The four dot products in one pass over the row (each coefficient loaded once).
      TwoLanes<T> value_a, value_b, d2_a, d2_b, size_a, size_b;
      const std::size_t last = static_cast<std::size_t>(degree - i);
      std::size_t j = 0;
      for (; j + 1 <= last; j += 2) {
        value_a.add(row_a[j], row_a[j + 1], powers[j], powers[j + 1]);
        value_b.add(row_b[j], row_b[j + 1], powers[j], powers[j + 1]);
        d2_a.add(row_a[j], row_a[j + 1], weighted[j], weighted[j + 1]);
        d2_b.add(row_b[j], row_b[j + 1], weighted[j], weighted[j + 1]);
        if constexpr (WithSizes) {
          size_a.add(abs(row_a[j]), abs(row_a[j + 1]), powers[j], powers[j + 1]);
          size_b.add(abs(row_b[j]), abs(row_b[j + 1]), powers[j], powers[j + 1]);
        }
      }
      if (j == last) {
        value_a.add(row_a[j], powers[j]);
        value_b.add(row_b[j], powers[j]);
        d2_a.add(row_a[j], weighted[j]);
        d2_b.add(row_b[j], weighted[j]);
        if constexpr (WithSizes) {
          size_a.add(abs(row_a[j]), powers[j]);
          size_b.add(abs(row_b[j]), powers[j]);
        }
      }
      const T rows[2][2]{{value_a.sum(), d2_a.sum()}, {value_b.sum(), d2_b.sum()}};
      for (int k = 0; k < 2; ++k) {
        const T scaled = power1 * rows[k][0];
        sum[k].value += scaled;
        sum[k].d1 += T(i) * scaled;
        sum[k].d2 += power1 * rows[k][1];
      }
      if constexpr (WithSizes) {
        size_sum[0] += abs(power1) * size_a.sum();
        size_sum[1] += abs(power1) * size_b.sum();
      }
    }
    if constexpr (WithSizes) {
      *sizes = size_sum;
    }
    return sum;
  }

  // A threshold: decided in double where T is soft-float, by the view of the table's double copy.
  bool within_reach(const T& u, const T& s) const {
    if constexpr (searches_in_double<T>) {
      return TwoPowerView<double>(table_->coarse.get(), static_cast<double>(damping_),
                                  static_cast<double>(kappa_), static_cast<double>(tail_limit_))
          .within_reach(static_cast<double>(u), static_cast<double>(s));
    } else {
      const auto [x1, x2] = variables(u, s);
      return tail(x1, x2) <= tail_limit_;
    }
  }

  // dδ/ds over u: Z alone.
  T rate_over_u(const T& u, const T& s) const {
    const auto [x1, x2] = variables(u, s);
    return evaluate(table_->shape, table_->z, x1, x2);
  }

  T entry_end(const T& u, const T& fraction, bool before_force_peak) const {
    using std::sqrt;
    // The reach: the largest s whose last two shells stay below the limit (they grow with s),
    // by bisection in log s; then cut back while the sums cancel (rounding ~16 D ε at most).
    T low = T(1), high = T(1);
    if (within_reach(u, low)) {
      for (int i = 0; i < 64 && within_reach(u, high); ++i) {
        high *= 2;
      }
      if (within_reach(u, high)) {
        low = high; // entire and slowly growing: the cancellation guard decides
      }
    } else {
      for (int i = 0; i < 400 && !within_reach(u, low); ++i) {
        low /= 2;
      }
    }
    for (int i = 0; i < 30 && high > low * (1 + T(1) / 1000000); ++i) {
      const T middle = sqrt(low * high);
      (within_reach(u, middle) ? low : high) = middle;
    }
    // The last s before the guard trips, to the reach's precision: back by eighths until it
    // holds, then bisected (the eighths alone left up to an eighth of the stretch unused: at
    // p = 1.5, β = ½, α = 0.05 in float128, a step more).
    T s = low;
    if (cancels(u, s)) {
      T tripped = s;
      for (int shrink = 0; shrink < 200 && cancels(u, s); ++shrink) {
        tripped = s;
        s *= T(7) / 8;
      }
      for (int i = 0; i < 30 && tripped > s * (1 + T(1) / 1000000); ++i) {
        const T middle = sqrt(s * tripped);
        (cancels(u, middle) ? tripped : s) = middle;
      }
    }
    // Not past dδ/ds = fraction u: dδ/ds = u Z falls monotonically while loading.
    if (rate_over_u(u, s) < fraction) {
      T before = T(0), after = s;
      for (int i = 0; i < 40; ++i) {
        const T middle = (before + after) / 2;
        (rate_over_u(u, middle) >= fraction ? before : after) = middle;
      }
      s = before;
    }
    // Not past the normal force's peak, if wanted: a split point, not the peak itself, so a rough
    // bracket will do (twelve halvings) as long as the force still rises where the stretch ends.
    // Where it falls from the onset on (β = 0) the halvings find no rise and the stretch stays.
    // The rate's sign is the event function's: that of (1) as a ContactOde (m = 1, k = κ, c = σγ)
    // on the series' δ = u s Y and dδ/ds = u Z.
    const auto ode =
        solvers::ContactOde<T>::from_coefficients(table_->p, T(1), kappa_, damping_, table_->beta);
    const auto rising_at = [&](const T& at) {
      const auto [x1, x2] = variables(u, at);
      return ode.force_rate_sign(u * at * evaluate(table_->shape, table_->y, x1, x2),
                                 u * evaluate(table_->shape, table_->z, x1, x2)) > 0;
    };
    if (before_force_peak && !rising_at(s)) {
      T rising = s;
      for (int i = 0; i < 64 && !rising_at(rising); ++i) {
        rising /= 2;
      }
      if (rising_at(rising)) {
        T falling = s;
        for (int i = 0; i < 12; ++i) {
          const T middle = (rising + falling) / 2;
          (rising_at(middle) ? rising : falling) = middle;
        }
        s = rising;
      }
    }
    return s;
  }

  enum class Newton { converged, failed, out_of_reach };
  // Newton's method on F1 = u s Y − δ, F2 = u Z − rate from (u, s). With D_k = x_k ∂/∂x_k and
  // ∂x1/∂u = β x1/u, ∂x1/∂s = (β+1) x1/s, ∂x2/∂u = (p−1) x2/u, ∂x2/∂s = (p+1) x2/s:
  //     ∂F1/∂u = s (Y + β D1Y + (p−1) D2Y),   ∂F1/∂s = u Z,
  //     ∂F2/∂u = Z + β D1Z + (p−1) D2Z,       ∂F2/∂s = (u/s) ((β+1) D1Z + (p+1) D2Z).
  // Converged as newton_step says, within the reach. From `far` (the straight line), the first
  // iterations take the polynomials to half their degree, a quarter of the terms (whole_from_now:
  // five whole iterations from the straight line were a fifth of a double viscoelastic
  // collision).
  // Where T is not soft-float, the whole iterations also take the sizes of Y's and Z's terms, and
  // `motion_cancels` (if given) says at convergence whether either sum cancels more than 16-fold
  // (cancels()' guard for Y and Z, at the last iteration's point: a step of at most ε^(2/3) from
  // the answer, which cannot move a 16-fold threshold); it stays empty otherwise.
  Newton newton(const T& delta, const T& rate, T& u, T& s, bool far,
                std::optional<bool>* motion_cancels = nullptr) const {
    const T beta = table_->beta, p = table_->p;
    const int whole = table_->shape.degree();
    int degree = far ? std::max(1, whole / 2) : whole;
    for (int iteration = 0; iteration < 40; ++iteration) {
      // The truncated iterations only choose where the whole ones start: the reach is theirs
      // to judge.
      if (degree == whole && !within_reach(u, s)) {
        return Newton::out_of_reach;
      }
      const auto [x1, x2] = variables(u, s);
      Euler y, z;
      std::array<T, 2> sizes{T(0), T(0)};
      if constexpr (searches_in_double<T>) {
        // The residuals need T's digits; the Jacobian only steers (its rounding to double moves
        // each step by 1e−16 of what is left), so it comes from the double copy.
        const TwoPowerTable<double>& coarse = *table_->coarse;
        const double a1 = static_cast<double>(x1), a2 = static_cast<double>(x2);
        const auto [steer_y, steer_z] =
            TwoPowerView<double>::euler_pair_of(coarse.shape, coarse.y, coarse.z, a1, a2);
        y = {value(table_->shape, table_->y, coarse.y, x1, x2), T(steer_y.d1), T(steer_y.d2)};
        z = {value(table_->shape, table_->z, coarse.z, x1, x2), T(steer_z.d1), T(steer_z.d2)};
      } else {
        const auto both =
            degree == whole
                ? euler_pair_of<true>(table_->shape, table_->y, table_->z, x1, x2, degree, &sizes)
                : euler_pair_of(table_->shape, table_->y, table_->z, x1, x2, degree);
        y = both[0];
        z = both[1];
      }
      const T f1 = u * s * y.value - delta, f2 = u * z.value - rate;
      const T j11 = s * (y.value + beta * y.d1 + (p - 1) * y.d2), j12 = u * z.value;
      const T j21 = z.value + beta * z.d1 + (p - 1) * z.d2;
      const T j22 = u * ((beta + 1) * z.d1 + (p + 1) * z.d2) / s;
      const T u_before = u, s_before = s;
      const NewtonStep step = newton_step(u, s, f1, f2, j11, j12, j21, j22);
      if (degree < whole && step != NewtonStep::left_the_domain) {
        if (whole_from_now(u_before, u, s_before, s, iteration)) {
          degree = whole;
        }
        continue; // never converged on the truncated polynomials
      }
      switch (step) {
      case NewtonStep::left_the_domain:
        return Newton::failed;
      case NewtonStep::converged:
        if (motion_cancels && !searches_in_double<T>) {
          *motion_cancels =
              exceeds_16_fold(sizes[0], y.value) || exceeds_16_fold(sizes[1], z.value);
        }
        return within_reach(u, s) ? Newton::converged : Newton::out_of_reach;
      case NewtonStep::moving:
        break;
      }
    }
    return Newton::failed;
  }

  // Where the solution is entire (p = 1 and β = 0) the terms can grow far beyond their sum: the
  // reach is cut back until no sum exceeds its value more than 16-fold (contact_series.hpp).
  // `work_only`: Y and Z judged already (newton's motion_cancels).
  bool cancels(const T& u, const T& s, bool work_only = false) const {
    using std::abs;
    const auto [x1, x2] = variables(u, s);
    const T a1 = abs(x1);
    const int widest = table_->work_shape.degree();
    thread_local std::vector<T> powers, sizes; // x2^j and |x2|^j
    fill_powers(powers, x2, widest);
    fill_powers(sizes, abs(x2), widest);
    for (const auto& [shape, c] :
         {std::pair{&table_->shape, &table_->y}, std::pair{&table_->shape, &table_->z},
          std::pair{&table_->work_shape, &table_->w}}) {
      if (work_only && c != &table_->w) {
        continue;
      }
      // Σ c x1^i x2^j and Σ |c x1^i x2^j|, each row a dot product in two lanes (a threshold:
      // their rounding does not matter; by Horner's rule this was 8 % of a double viscoelastic
      // collision).
      T sum = T(0), magnitude = T(0), power1 = T(1), size1 = T(1);
      const int degree = shape->degree();
      for (int i = 0; i <= degree; ++i, power1 *= x1, size1 *= a1) {
        const T* row = &(*c)[shape->index(i, 0)];
        TwoLanes<T> row_sum, row_magnitude;
        const std::size_t last = static_cast<std::size_t>(degree - i);
        std::size_t j = 0;
        for (; j + 1 <= last; j += 2) {
          row_sum.add(row[j], row[j + 1], powers[j], powers[j + 1]);
          row_magnitude.add(abs(row[j]), abs(row[j + 1]), sizes[j], sizes[j + 1]);
        }
        if (j == last) {
          row_sum.add(row[j], powers[j]);
          row_magnitude.add(abs(row[j]), sizes[j]);
        }
        sum += power1 * row_sum.sum();
        magnitude += size1 * row_magnitude.sum();
      }
      if (exceeds_16_fold(magnitude, sum)) {
        return true;
      }
    }
    return false;
  }
  // The guard's rule: the terms' sizes add up to more than 16 times their sum.
  static bool exceeds_16_fold(const T& magnitude, const T& sum) {
    using std::abs;
    return magnitude > 16 * abs(sum) && magnitude > 0;
  }

private:
  // The magnitude of the last two shells (i + j = D − 1, D) of Z, the largest of the series:
  // the terms left out are of their order when the shells decrease.
  //     Σ_i |x1|^i (|z_i,D−1−i| |x2|^(D−1−i) + |z_i,D−i| |x2|^(D−i)),
  // both shells in one pass by Horner's rule in |x1| (one dependent chain: shell after shell, two,
  // was 4 % of a double viscoelastic collision, which asks at every step while unloading).
  T tail(const T& x1, const T& x2) const {
    using std::abs;
    const Triangle& t = table_->shape;
    const int degree = t.degree();
    const std::vector<T>& z = table_->z;
    const T a1 = abs(x1), a2 = abs(x2);
    if (degree == 0) {
      return abs(z[0]);
    }
    T sum = abs(z[t.index(degree, 0)]), lower = T(1), upper = a2; // |x2|^(D−1−i), |x2|^(D−i)
    for (int i = degree - 1; i >= 0; --i) {
      sum = sum * a1 +
            (abs(z[t.index(i, degree - 1 - i)]) * lower + abs(z[t.index(i, degree - i)]) * upper);
      lower = upper;
      upper *= a2;
    }
    return sum;
  }

  const TwoPowerTable<T>* table_;
  T damping_, kappa_; // σγ, κ
  T tail_limit_;
};

template <class Real>
class TwoPowerSeries final : public ContactSeries<Real> {
public:
  using typename ContactSeries<Real>::Point;
  using typename ContactSeries<Real>::Contact;

  // `sign` σ: +1 at the entry, −1 at the exit; γ ≥ 0 and κ of (1); the terms left out stay below
  // `tolerance` relative.
  TwoPowerSeries(std::shared_ptr<const TwoPowerTable<Real>> table, int sign, const Real& gamma,
                 const Real& kappa, const Real& tolerance)
      : table_(std::move(table)), sign_(sign),
        exact_(table_.get(), Real(sign) * gamma, kappa, tolerance / 8),
        coarse_(table_->coarse.get(), static_cast<double>(Real(sign) * gamma),
                static_cast<double>(kappa), static_cast<double>(tolerance / 8)) {}

  Point at(const Real& u, const Real& s) const override {
    Point point = motion_at(u, s);
    point.work = work_at(u, s);
    return point;
  }

  Point motion_at(const Real& u, const Real& s) const override {
    const auto [x1, x2] = exact_.variables(u, s);
    const TwoPowerTable<Real>& t = *table_;
    return {u * s * polynomial(t.shape, t.y, &TwoPowerTable<double>::y, x1, x2),
            u * polynomial(t.shape, t.z, &TwoPowerTable<double>::z, x1, x2), Real(0)};
  }

  Real work_at(const Real& u, const Real& s) const override {
    const auto [x1, x2] = exact_.variables(u, s);
    return 2 * Real(sign_) * u * u *
           polynomial(table_->work_shape, table_->w, &TwoPowerTable<double>::w, x1, x2);
  }

  bool within_reach(const Real& u, const Real& s) const override {
    return exact_.within_reach(u, s);
  }

  // The search decides where the series hands over to the Taylor steps, not a value: in double
  // where Real is soft-float (a third of a first viscoelastic collision in float128 went to it).
  Real entry_end(const Real& u, const Real& fraction, bool before_force_peak) const override {
    if constexpr (searches_in_double<Real>) {
      return Real(coarse_.entry_end(static_cast<double>(u), static_cast<double>(fraction),
                                    before_force_peak));
    } else {
      return exact_.entry_end(u, fraction, before_force_peak);
    }
  }

  // Newton on (u, s) from the straight line u = rate, s = δ/rate; where Real is soft-float, its
  // first steps in double, so that Real's take over within 1e-16 and converge in one or two
  // (seven from the straight line: half a repeated viscoelastic collision in float128). The
  // answer is Real's Newton's either way: the double steps only choose where it starts.
  std::optional<Contact> locate(const Real& delta, const Real& rate) const override {
    if (!(delta > 0 && rate > 0)) {
      return std::nullopt;
    }
    Real u = rate, s = delta / rate;
    if constexpr (searches_in_double<Real>) {
      double coarse_u = static_cast<double>(u), coarse_s = static_cast<double>(s);
      if (coarse_.newton(static_cast<double>(delta), static_cast<double>(rate), coarse_u, coarse_s,
                         true) == TwoPowerView<double>::Newton::converged) {
        u = Real(coarse_u);
        s = Real(coarse_s);
      }
    }
    std::optional<bool> motion_cancels; // Y's and Z's guard, judged by Newton where it can be
    if (exact_.newton(delta, rate, u, s, !searches_in_double<Real>, &motion_cancels) !=
            TwoPowerView<Real>::Newton::converged ||
        motion_cancels.value_or(false) || cancels(u, s, motion_cancels.has_value())) {
      return std::nullopt;
    }
    return Contact{u, s};
  }

private:
  // One of the table's polynomials at (x1, x2): its high shells in double where Real is
  // soft-float and their rounding allows (TwoPowerView::value).
  Real polynomial(const Triangle& t, const std::vector<Real>& c,
                  std::vector<double> TwoPowerTable<double>::*coarse_member, const Real& x1,
                  const Real& x2) const {
    if constexpr (searches_in_double<Real>) {
      return exact_.value(t, c, table_->coarse.get()->*coarse_member, x1, x2);
    } else {
      return TwoPowerView<Real>::evaluate(t, c, x1, x2);
    }
  }

  // A guard on how far the series is used (more than 16-fold cancellation), not a value: double
  // decides it as well where Real is soft-float.
  bool cancels(const Real& u, const Real& s, bool work_only) const {
    if constexpr (searches_in_double<Real>) {
      return coarse_.cancels(static_cast<double>(u), static_cast<double>(s), work_only);
    } else {
      return exact_.cancels(u, s, work_only);
    }
  }

  std::shared_ptr<const TwoPowerTable<Real>> table_;
  int sign_;
  TwoPowerView<Real> exact_;
  TwoPowerView<double> coarse_; // over table_->coarse (none unless searches_in_double)
};

} // namespace pldamp::solvers::detail
