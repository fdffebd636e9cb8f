// taylor: an adaptive Taylor-series integrator of the physical equation, in any precision (double,
// long double, float128, cpp_bin_float_50); the harness's numerical reference.
//
// The equation is (1) of contact_series.hpp: MATH.md §1 in the units δ_u, T = δ_u/v0, KE0 of its
// own energy balance, state (δ, v, W), time the independent variable, with the damping exponent
// β of MATH.md §12 (the seed's (p−1)/2 unless the problem states one). Nothing here uses the
// paper's map or a closed form.
//
// A step from (δ, v, W) at t computes the Taylor coefficients of the solution to order N by the
// automatic-differentiation recurrences (contact_series.hpp):
//     u = δ^β (power, by way of g: MATH.md §9),  q = δ^(p−β) (u δ for the seed's β, a power
//     otherwise),  f = u q = δ^p,
//     g = u v = δ^β v,  P = g v = δ^β v²,
//     δ_{n+1} = v_n / (n+1),   v_{n+1} = −(γ g_n + κ f_n) / (n+1),   W_{n+1} = 2γ P_n / (n+1),
// O(N²) operations per step. Order and step follow Jorba & Zou (2005), as heyoka does:
// - N = ⌈1 − ½ ln ε⌉ for the tolerance ε (rtol): the cost per unit time, ~N² / h with h ~ ρ e^−2,
//   is least there when the step keeps the truncation error at ε.
// - ρ, the radius of convergence, is estimated from the last two coefficients of each state,
//   relative to its scale s: ρ = min (s / |x_n|)^(1/n), n ∈ {N−1, N} (two orders, as one can
//   vanish by accident). Relative (s = |δ| for δ; see step_size for v and W), so that the exit
//   speed e v0 is measured to ε relative even for e = 1e-3. atol is not used: no state needs an
//   absolute floor, physical units included.
// - h = ρ e^−2 e^(−0.7/(N−1)). With |x_n| ~ ρ^−n the first term left out is then ~ e^(−2N) ~ ε,
//   and the sum of all of them stays below ε; e^(−0.7/(N−1)) is Jorba & Zou's correction for the
//   estimate of ρ from two coefficients only.
//
// The branch points at δ = 0. The radius of convergence at t is at most the distance to the entry
// (t) or to the exit (τ − t), so the steps would shrink geometrically at both ends and no step
// can start at δ = 0, where the power recurrence divides by δ. Both ends are therefore left to
// the series of contact_series.hpp, in the variable x ~ t^b that resolves the branch point (for
// a stated β, two_power_series.hpp's, in the two variables x1 ~ t^(β+1), x2 ~ t^(p+1)):
// - entry: the series with u = 1 gives the state at t1 = x1^(1/b), x1 the series' reach (its
//   truncation below ε), and before the loading has lost seven eighths of the impact speed
//   (v ≥ ⅛), so that the peak is found by the steps. (Stopping at v = ½ left a step more than
//   the reach needed at p = 1.5 and 2: a fifth of a double collision.) The two-variable series
//   also stops before the normal force's peak where that is wanted (its values are dear: the
//   steps find the peak on their polynomials) and is taken three degrees above the order
//   (taylor_degrees.hpp: summed once per (p, β, γ), it reaches a step further).
// - exit: after each step while unloading, the time-reversed series is tried: Newton finds the
//   exit speed u and the time s to the exit from the step's (δ, v); it answers when x = u^a s^b
//   lies within its reach. Then τ = t + s, e = u and the remaining work W(s) are exact to ε.
//   No step approaches δ = 0 (a step that would cross it is halved).
// The state is carried as a compensated sum (advance), so that rounding does not build up over the
// slow creep before a heavily damped exit.
//
// Events. The peak (v = 0) and, with the force end, the cut (k δ^(p−β) + c v = 0, MATH.md §4; here
// κ q + γ v, whose coefficients the recurrences give) are located on each step's polynomial:
// Descartes' rule with bisection isolates the first crossing, TOMS 748 polishes it
// (polynomial.hpp). The state at an event is the polynomial's value. The normal force's peak
// (its rate's sign, ContactOde::force_rate_sign, falling through 0) is a function of the state,
// not a polynomial: it is bracketed by its sign at the ends of the entry stretch and of each step
// before the overlap's peak, and located by TOMS 748 on the series' or the step's state.
//
// Work: rhs_evals counts the orders of the recurrences computed (N per step, plus the terms of
// each series built); order n costs about n products, so this undercounts the arithmetic of
// high orders: compare wall time across methods. The series' terms are counted whether or not the
// thread's cache held them (contact_series), so that a run's count does not depend on what the
// thread ran before it.
#include "collision.hpp"
#include "contact_series.hpp"
#include "double_double.hpp"
#include "methods.hpp"
#include "polynomial.hpp"
#include "taylor_degrees.hpp"
#include "two_power_series.hpp"

#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

namespace pldamp::solvers::detail {
namespace {

template <SupportedReal Real>
class TaylorContact {
public:
  using Scaled = StateOf<Real>; // (δ, v, W) in units δ_u, v0, KE0

  TaylorContact(const Problem<Real>& problem, const Options<Real>& options)
      : collision_(problem, options), order_(taylor_order(static_cast<double>(options.rtol))),
        exact_orders_(orders_in<DoubleDouble>(order_)), double_orders_(orders_in<double>(order_)),
        p_(problem.p), a_(undamped_or_seed(problem) ? (problem.p - 1) / 2 : problem.beta()),
        kappa_((problem.p + 1) / 2), gamma_(gamma_of(problem, collision_.ode().delta_scale())),
        general_(!undamped_or_seed(problem)), entry_(contact_series(+1)) {
    using std::exp;
    const std::size_t n = static_cast<std::size_t>(order_) + 1;
    for (std::vector<Real>* series : own_arrays()) {
      *series = recycled_arrays().take();
      series->assign(n, Real(0));
    }
    for (std::size_t i = 1; i < n; ++i) {
      inverse_[i] = 1 / Real(i);
    }
    if (exact_orders_ < order_) {
      middle_.assign(inverse_);
      low_.assign(inverse_);
    }
    safety_ = exp(Real(-2) - Real(7) / 10 / Real(order_ - 1));
    const ContactOde<Real>& ode = collision_.ode();
    time_unit_ = ode.time_scale();
    units_ = {ode.delta_scale(), ode.v0(), ode.energy_scale()};
    horizon_ = collision_.horizon() / time_unit_;
    collision_.count_rhs_evals(series_terms());
  }

  TaylorContact(const TaylorContact&) = delete;
  TaylorContact& operator=(const TaylorContact&) = delete;
  ~TaylorContact() {
    for (std::vector<Real>* series : own_arrays()) {
      recycled_arrays().give(std::move(*series));
    }
  }

  Result<Real> run();

private:
  // The coefficient arrays' allocations, kept per thread from one solve to the next: ten of them
  // were 3 % of a double collision.
  class RecycledArrays {
  public:
    std::vector<Real> take() {
      if (free_.empty()) {
        return {};
      }
      std::vector<Real> taken = std::move(free_.back());
      free_.pop_back();
      return taken;
    }
    void give(std::vector<Real>&& array) {
      if (free_.size() < 64) {
        free_.push_back(std::move(array));
      }
    }

  private:
    std::vector<std::vector<Real>> free_;
  };
  static RecycledArrays& recycled_arrays() {
    thread_local RecycledArrays arrays;
    return arrays;
  }
  std::array<std::vector<Real>*, 10> own_arrays() {
    return {&d_, &v_, &w_, &u_, &q_, &f_, &g_, &power_, &cut_, &inverse_};
  }

  // The one-variable series and the seed's recurrences (u = δ^((p−1)/2), q = u δ) serve the seed's
  // β and an undamped contact, whose equation does not involve β (stated, the two-variable series
  // lost 5 digits there in quad at p = 1: the energy balance was off by 1.8e-29).
  static bool undamped_or_seed(const Problem<Real>& problem) {
    return !problem.damping_exponent.has_value() || problem.alpha == 0;
  }
  // γ of the scaled equation: α √κ δ_u^(β − (p−1)/2) (MATH.md §12.1; the seed's β: α √κ).
  static Real gamma_of(const Problem<Real>& problem, const Real& delta_u) {
    using std::pow;
    using std::sqrt;
    const Real gamma = problem.alpha * sqrt((problem.p + 1) / 2);
    const Real excess = problem.beta() - (problem.p - 1) / 2;
    return excess == 0 ? gamma : gamma * pow(delta_u, excess);
  }
  // The series at a contact point: `sign` +1 the entry, −1 the exit. The seed's exponent has the
  // one-variable series (contact_series.hpp), a stated one the two-variable series
  // (two_power_series.hpp), even when it equals (p − 1)/2: that is how the general path is
  // checked against the closed forms.
  std::shared_ptr<const ContactSeries<Real>> build_series(int sign) const {
    const Real tolerance = collision_.options().rtol;
    if (general_) {
      const int degree = sign > 0 ? entry_degree(order_) : order_;
      return std::make_shared<TwoPowerSeries<Real>>(table_for(p_, a_, degree), sign, gamma_, kappa_,
                                                    tolerance);
    }
    return std::make_shared<ContactPointSeries<Real>>(p_, Real(sign) * gamma_, 2 * gamma_,
                                                      tolerance, series_terms(), with_work());
  }
  // A series with where the entry stretch ends and the scaled state there (for the entry's: the
  // same for every collision that shares the series).
  struct SeriesAndEnd {
    std::shared_ptr<const ContactSeries<Real>> series;
    Real entry_end;
    Scaled at_end;
  };
  // The series depend on (p, β, γ, the tolerance, the work) alone, not on v0, m or k, which the
  // units absorb: the cells of a grid that share p and α share them. Building one is most of a
  // double collision's cost (two series of 2N terms against a few steps of N), so each thread
  // keeps the last few it built.
  SeriesAndEnd contact_series(int sign) const {
    struct Key {
      Real p, beta, gamma, tolerance;
      int sign;
      bool general, work, force_peak;
      bool operator==(const Key&) const = default;
    };
    static constexpr std::size_t kept = 16;
    thread_local std::vector<std::pair<Key, SeriesAndEnd>> cache;
    thread_local std::size_t next_evicted = 0;
    // The entry's stretch ends before the normal force's peak where that is wanted (entry_end).
    const bool force_peak = sign > 0 && collision_.pending(EventKind::force_peak);
    const Key key{p_,   a_,       gamma_,      collision_.options().rtol,
                  sign, general_, with_work(), force_peak};
    for (const auto& [cached_key, cached] : cache) {
      if (cached_key == key) {
        return cached;
      }
    }
    SeriesAndEnd built{build_series(sign), Real(0), {}};
    if (sign > 0) {
      built.entry_end = built.series->entry_end(Real(1), Real(1) / 8, force_peak);
      const auto point = built.series->at(Real(1), built.entry_end);
      built.at_end = {point.delta, point.rate, point.work};
    }
    if (cache.size() < kept) {
      cache.emplace_back(key, built);
    } else {
      cache[next_evicted] = {key, built};
      next_evicted = (next_evicted + 1) % kept;
    }
    return built;
  }

  // Terms of the contact-point series: about twice the order, so that their reach is ~1/e of
  // their radius (contact_series.hpp) and they cover much of the contact in one evaluation.
  // Wider than 106 bits the steps sum most orders in cheaper tiers (lower_tiers) and the series
  // do not: there 1.5 times the order is cheaper (float128 at p = 1.5, instructions counted by
  // callgrind: a first collision 29.2M -> 19.9M, a repeated one 7.7M -> 7.3M). In double twice
  // the order is (a repeated collision 98k instructions, 108k at 1.5 times, 144k at once).
  int series_terms() const {
    return std::numeric_limits<Real>::digits > 106 ? order_ + order_ / 2 : 2 * order_;
  }
  // The exit series, built when a run first needs it (never for peak-only or force-end runs).
  const ContactSeries<Real>& exit_series() {
    if (!exit_) {
      exit_ = contact_series(-1).series;
      collision_.count_rhs_evals(series_terms());
    }
    return *exit_;
  }
  bool with_work() const { return collision_.with_work(); }
  // Without damping the total force is the spring's, k δ^p, and first reaches 0 at δ = 0: the
  // force end is the overlap end, found by the exit series (cut_ = κ δ^b never changes sign
  // within a step, as no step crosses δ = 0).
  bool force_end() const { return collision_.options().end == End::force && gamma_ > 0; }
  std::span<const Real> span_of(const std::vector<Real>& series) const { return series; }

  StateOf<Real> physical(const Scaled& y) const {
    return {units_[0] * y[0], units_[1] * y[1], units_[2] * y[2]};
  }
  template <class ScaledAt>
  void sample_through(const Real& t, ScaledAt&& scaled_at) {
    collision_.sample_through(time_unit_ * t, [&](const Real& physical_t) {
      return physical(scaled_at(physical_t / time_unit_));
    });
  }
  // Records an event at scaled time t; true when the run is complete.
  bool record(EventKind kind, const Real& t, const Scaled& y) {
    return collision_.record(kind, time_unit_ * t, physical(y));
  }

  // The normal force's peak where its rate falls through 0 between scaled times `from` and `to`
  // (`state` gives the scaled state between, `motion` its δ and v alone: the rate needs no W),
  // when wanted and still to be found.
  template <class StateAt, class MotionAt>
  void find_force_peak(const Real& from, const Real& to, StateAt&& state, MotionAt&& motion) {
    if (!collision_.pending(EventKind::force_peak)) {
      return;
    }
    auto rate = [&](const Real& s) {
      return collision_.event_value(EventKind::force_peak, physical(motion(s)));
    };
    // The rate at a step's start is the last step's at its end (`rate_at_end_`): the same point,
    // and the bracket of one step then starts where the last one's ended.
    const Real rate_from =
        rate_at_end_ && rate_at_end_->first == from ? rate_at_end_->second : rate(from);
    const Real rate_to = rate(to);
    rate_at_end_.emplace(to, rate_to);
    if (!(rate_from > 0 && rate_to <= 0)) {
      return;
    }
    Real at = to;
    if (rate_to < 0) {
      std::uintmax_t iterations = 200;
      const auto [lo, hi] = boost::math::tools::toms748_solve(
          rate, from, to, rate_from, rate_to,
          boost::math::tools::eps_tolerance<Real>(std::numeric_limits<Real>::digits - 2),
          iterations);
      at = (lo + hi) / 2;
    }
    record(EventKind::force_peak, at, state(at));
  }

  void compute_coefficients(const Scaled& y);
  template <class T>
  struct Series {
    std::vector<T>&d, &v, &w, &u, &q, &f, &g, &power;
  };
  template <class T>
  struct Constants {
    T gamma, kappa, a, q_exponent, time_scale;
    std::span<const T> inverse; // 1/n to the order
  };
  template <class T>
  void recurrences(Series<T> s, const Constants<T>& c, std::size_t from, std::size_t to) const;
  // How q = δ^(p−β), the spring's factor beside u = δ^β (f = u q = δ^p), is made: u δ for the
  // seed's β; δ itself where p − β = 1 (Hertz's spring with the viscoelastic dashpot: no sum of
  // its own, and f's is u δ's, the sum that u needs anyway); otherwise by its own power rule.
  enum class SpringFactor { seed, overlap, power };
  SpringFactor spring_factor() const {
    return !general_ ? SpringFactor::seed
                     : (p_ - a_ == 1 ? SpringFactor::overlap : SpringFactor::power);
  }
  // recurrences' orders for one way of making q and with or without the work W.
  template <class T, SpringFactor Q, bool Work>
  void orders(Series<T> s, const Constants<T>& c, std::size_t from, std::size_t to) const;
  Series<Real> own_series() { return {d_, v_, w_, u_, q_, f_, g_, power_}; }
  Constants<Real> own_constants(const Real& q_exponent) const {
    return {gamma_, kappa_, a_, q_exponent, Real(1), inverse_};
  }
  void lower_tiers(const Real& q_exponent);
  // Where each order's coefficients are summed (Real wider than 106 bits only; the order itself
  // otherwise): from order n on in T when n ε_T e^(−2n) ≤ ε/1024, the term of order n at the
  // step's end being ~e^(−2n) of the state's (h = ρ e^−2, step_size) and its sums erring by
  // ~n ε_T. In float128 (order 40): 0-7 in float128, 8-25 in double-double, 26-40 in double.
  template <class T>
  static int orders_in(int order) {
    if constexpr (std::numeric_limits<Real>::digits <= 106) {
      return order;
    } else {
      // In logarithms, in double: a threshold, computed once per solve, needs no more.
      const double eps_t = std::is_same_v<T, double> ? std::numeric_limits<double>::epsilon()
                                                     : std::ldexp(1.0, -104); // 4 ulps of 2^-106
      const double bound =
          std::log(static_cast<double>(std::numeric_limits<Real>::epsilon()) / 1024 / eps_t);
      for (int n = 1; n < order; ++n) {
        if (std::log(double(n)) - 2.0 * n <= bound) {
          return n;
        }
      }
      return order;
    }
  }
  // ln ρ from the coefficients at orders top − 1 and top (step_size).
  Real log_radius_of(std::size_t top, bool with_cut = false) const;
  Real step_size(bool with_cut = false) const;
  Scaled state_at(const Real& theta) const {
    return {horner(span_of(d_), theta), horner(span_of(v_), theta),
            with_work() ? horner(span_of(w_), theta) : Real(0)};
  }
  Scaled motion_at(const Real& theta) const {
    return {horner(span_of(d_), theta), horner(span_of(v_), theta), Real(0)};
  }
  // y(t + h) = y + Σ_{n≥1} c_n h^n, the sum compensated (Kahan; TwoSum): the rounding error of
  // y + increment is kept in `carry_` and added back at the next step, so a step costs ~ε of its
  // increment rather than ~ε of the state. Where the increments are small against the state, in
  // the slow creep before the exit of a heavily damped contact, the rounding errors of the steps
  // add up to a shift of the exit time, and the relative error of δ grows as δ → 0: with plain
  // sums e = 1e-3 erred by 37ε in double at p = 2.5.
  void advance(Scaled& y, const Real& h) {
    for (std::size_t i = 0; i < 3; ++i) {
      const std::vector<Real>& c = i == 0 ? d_ : (i == 1 ? v_ : w_);
      Real increment = c[static_cast<std::size_t>(order_)];
      for (std::size_t n = static_cast<std::size_t>(order_) - 1; n > 0; --n) {
        increment = increment * h + c[n];
      }
      increment = increment * h + carry_[i];
      const Real sum = y[i] + increment;
      const Real y_part = sum - increment;
      carry_[i] = (y[i] - y_part) + (increment - (sum - y_part));
      y[i] = sum;
    }
  }
  Scaled entry_state(const Real& t) const {
    const auto point = entry_.series->at(Real(1), t);
    return {point.delta, point.rate, point.work};
  }
  Scaled entry_motion(const Real& t) const {
    const auto point = entry_.series->motion_at(Real(1), t);
    return {point.delta, point.rate, Real(0)};
  }

  BasicCollision<Real> collision_;
  std::optional<std::pair<Real, Real>> rate_at_end_; // find_force_peak's last (time, rate)
  int order_, exact_orders_, double_orders_;         // the tiers (orders_in)
  Real p_, a_, kappa_, gamma_;                       // a_ is β
  bool general_;                                     // a stated β with damping (undamped_or_seed)
  SeriesAndEnd entry_;
  std::shared_ptr<const ContactSeries<Real>> exit_;
  Real safety_, time_unit_, horizon_;
  StateOf<Real> units_;
  Scaled carry_{};                                // the compensated sum's low parts (advance)
  std::vector<Real> inverse_;                     // 1/n
  std::vector<Real> d_, v_, w_;                   // the state's Taylor coefficients
  std::vector<Real> u_, q_, f_, g_, power_, cut_; // δ^β, δ^(p−β), δ^p, δ^β v, δ^β v², κ q + γ v
  // The orders summed below Real, scaled (lower_tiers).
  template <class T>
  struct Tier {
    std::vector<T> d, v, w, u, q, f, g, power;
    std::vector<T> inverse; // 1/n, rounded from Real's
    void assign(const std::vector<Real>& inverse_in_real) {
      const std::size_t n = inverse_in_real.size();
      for (std::vector<T>* series : {&d, &v, &w, &u, &q, &f, &g, &power}) {
        series->assign(n, T(0));
      }
      inverse.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        inverse[i] = narrowed<T>(inverse_in_real[i]);
      }
    }
    Series<T> view() { return {d, v, w, u, q, f, g, power}; }
  };
  Tier<DoubleDouble> middle_;
  Tier<double> low_;
};

template <SupportedReal Real>
void TaylorContact<Real>::compute_coefficients(const Scaled& y) {
  using std::pow;
  const std::size_t order = static_cast<std::size_t>(order_);
  const std::size_t exact = static_cast<std::size_t>(exact_orders_);
  d_[0] = y[0];
  v_[0] = y[1];
  w_[0] = y[2];
  u_[0] = power_of(y[0], a_);
  // q = δ^(p−β): u δ for the seed's β (δ^((p+1)/2), one product), its own power otherwise.
  const Real q_exponent = p_ - a_;
  if (spring_factor() == SpringFactor::power) {
    q_[0] = power_of(y[0], q_exponent);
  } else if (spring_factor() == SpringFactor::overlap) {
    q_[0] = y[0];
  }
  recurrences<Real>(own_series(), own_constants(q_exponent), 0, std::min(order, exact));
  if (exact < order) {
    lower_tiers(q_exponent);
  }
  if (force_end()) {
    for (std::size_t n = 0; n <= order; ++n) {
      cut_[n] = kappa_ * q_[n] + gamma_ * v_[n];
    }
  }
  collision_.count_rhs_evals(order_);
}

// The recurrences of (1) for orders [from, to) in any arithmetic T: u_n, q_n, f_n, g_n, P_n from
// the coefficients below them, then δ, v and W at n + 1. With a time scale H ≠ 1 every series
// holds c_n H^n instead of c_n: products and powers keep their form, and the derivative brings
// a factor H into δ' = v, v' = −(γ g + κ f) and W' = 2γ P.
template <SupportedReal Real>
template <class T>
void TaylorContact<Real>::recurrences(Series<T> s, const Constants<T>& c, std::size_t from,
                                      std::size_t to) const {
  const auto with = [&]<SpringFactor Q>() {
    with_work() ? orders<T, Q, true>(s, c, from, to) : orders<T, Q, false>(s, c, from, to);
  };
  switch (spring_factor()) {
  case SpringFactor::seed:
    with.template operator()<SpringFactor::seed>();
    break;
  case SpringFactor::overlap:
    with.template operator()<SpringFactor::overlap>();
    break;
  case SpringFactor::power:
    with.template operator()<SpringFactor::power>();
    break;
  }
  if (force_end() && to > 0 && from < to) {
    // The cut needs u and q at the top order too.
    s.u[to] = power_coefficient(s.d, s.u, c.a, to);
    switch (spring_factor()) {
    case SpringFactor::seed:
      s.q[to] = product_coefficient(s.u, s.d, to);
      break;
    case SpringFactor::overlap:
      s.q[to] = s.d[to];
      break;
    case SpringFactor::power:
      s.q[to] = power_coefficient(s.d, s.q, c.q_exponent, to);
      break;
    }
  }
}

// Order n in one pass over 1 ≤ j < n (each coefficient read once for all the sums, which are
// independent chains), the terms with a factor of order n added once that factor is known:
// - u = δ^β needs no sum of its own (MATH.md §9): the power rule n δ_0 u_n = Σ_{j<n} (β(n − j) −
//   j) δ_{n−j} u_j, with (n − j) δ_{n−j} = H v_{n−j−1} (δ' = v), is
//   n δ_0 u_n = (β + 1) H g_{n−1} − n S_n,   S_n = Σ_{1≤j≤n} δ_j u_{n−j},
//   and S_n + δ_0 u_n is the seed's q_n = (u δ)_n: one sum gives both.
// - q = δ^(p−β) for a stated β: δ itself where p − β = 1, else the power rule,
//   n δ_0 q_n = Σ_{1≤j≤n} ((p − β + 1) j − n) δ_j q_{n−j}.
// - f = u q (for q = δ, f_n = S_n + u_n δ_0: the sum u's rule made), g = u v, P = g v: Cauchy
//   products.
template <SupportedReal Real>
template <class T, typename TaylorContact<Real>::SpringFactor Q, bool Work>
void TaylorContact<Real>::orders(Series<T> s, const Constants<T>& c, std::size_t from,
                                 std::size_t to) const {
  const T inverse_d0 = T(1) / s.d[0], a1 = c.a + T(1), b1 = c.q_exponent + T(1);
  const std::span<const T> inverse = c.inverse; // 1/n: no division on the chain from u_n to u_n+1
  // β = 0 (the seed's p = 1): u = 1 exactly. The rule below would give u_n as the difference of
  // two roundings of one number, a noise of ε that moved the radius estimate (one float128 step
  // more at p = 1, e = 0.5).
  const bool constant_u = a_ == Real(0);
  for (std::size_t n = from; n < to; ++n) {
    if (n == 0) {
      if constexpr (Q == SpringFactor::seed) {
        s.q[0] = s.u[0] * s.d[0];
      }
      s.f[0] = s.g[0] = T(0);
      if constexpr (Work) {
        s.power[0] = T(0);
      }
    } else {
      // Each sum in two lanes, odd j and even j, added at the end (TwoLanes): in double one SSE2
      // register each, and two dependency chains instead of one.
      TwoLanes<T> du, uq, uv, gv, dq;
      const T order = T(n);
      std::size_t j = 1;
      for (; j + 1 < n; j += 2) {
        const T& u0 = s.u[j];
        const T& u1 = s.u[j + 1];
        du.add(u0, u1, s.d[n - j], s.d[n - j - 1]);
        if constexpr (Q != SpringFactor::overlap) {
          uq.add(u0, u1, s.q[n - j], s.q[n - j - 1]);
        }
        uv.add(u0, u1, s.v[n - j], s.v[n - j - 1]);
        if constexpr (Work) {
          gv.add(s.g[j - 1], s.g[j], s.v[n - j + 1], s.v[n - j]);
        }
        if constexpr (Q == SpringFactor::power) {
          dq.add((b1 * T(j) - order) * s.d[j], (b1 * T(j + 1) - order) * s.d[j + 1], s.q[n - j],
                 s.q[n - j - 1]);
        }
      }
      if (j < n) {
        du.add(s.u[j], s.d[n - j]);
        if constexpr (Q != SpringFactor::overlap) {
          uq.add(s.u[j], s.q[n - j]);
        }
        uv.add(s.u[j], s.v[n - j]);
        if constexpr (Work) {
          gv.add(s.g[j - 1], s.v[n - j + 1]);
        }
        if constexpr (Q == SpringFactor::power) {
          dq.add((b1 * T(j) - order) * s.d[j], s.q[n - j]);
        }
      }
      const T sum = du.sum() + s.d[n] * s.u[0]; // S_n
      s.u[n] = constant_u ? T(0) : (a1 * c.time_scale * s.g[n - 1] * inverse[n] - sum) * inverse_d0;
      if constexpr (Q == SpringFactor::power) {
        s.q[n] = (dq.sum() * inverse[n] + c.q_exponent * s.d[n] * s.q[0]) * inverse_d0;
      } else if constexpr (Q == SpringFactor::overlap) {
        s.q[n] = s.d[n];
      } else {
        s.q[n] = sum + s.u[n] * s.d[0];
      }
      // f_n less u_0 q_n (added below); for q = δ the sum is S_n's.
      s.f[n] = Q == SpringFactor::overlap ? du.sum() + s.u[n] * s.q[0] : uq.sum() + s.u[n] * s.q[0];
      s.g[n] = uv.sum() + s.u[n] * s.v[0];
      if constexpr (Work) {
        s.power[n] = gv.sum() + s.g[n - 1] * s.v[1];
      }
    }
    s.f[n] += s.u[0] * s.q[n];
    s.g[n] += s.u[0] * s.v[n];
    const T step = c.time_scale * inverse[n + 1];
    s.d[n + 1] = s.v[n] * step;
    s.v[n + 1] = -(c.gamma * s.g[n] + c.kappa * s.f[n]) * step;
    if constexpr (Work) {
      s.power[n] += s.g[n] * s.v[0];
      s.w[n + 1] = 2 * c.gamma * s.power[n] * step;
    }
  }
}

// The orders from exact_orders_ on, in double-double and then double (Real wider than 106 bits
// only; orders_in). The series are scaled by H = the radius the exact orders show (step_size's
// estimate), so that every scaled coefficient is of the state's size: unscaled, c_n ~ ρ^−n could
// leave double's range.
template <SupportedReal Real>
void TaylorContact<Real>::lower_tiers(const Real& q_exponent) {
  using std::exp;
  const std::size_t order = static_cast<std::size_t>(order_);
  const std::size_t exact = static_cast<std::size_t>(exact_orders_);
  const std::size_t middle_end = std::min(order, static_cast<std::size_t>(double_orders_));
  const Real log_radius = log_radius_of(exact);
  const Real scale =
      log_radius < std::numeric_limits<Real>::infinity() ? Real(exp(log_radius)) : Real(1);
  using std::abs;
  using std::log;
  if (!(abs(log(scale)) * Real(order) < log(std::numeric_limits<Real>::max()) / 2)) {
    // H^N itself would leave Real's range (no contact in the units of §7 comes near): all in Real.
    recurrences<Real>(own_series(), own_constants(q_exponent), exact, order);
    return;
  }
  // Real -> double-double, scaled: c_n H^n.
  Real power = Real(1);
  const Series<Real> high = own_series();
  Series<DoubleDouble> middle = middle_.view();
  for (std::size_t n = 0; n <= exact; ++n, power *= scale) {
    for (auto [to, from] : {std::pair{&middle.d, &high.d}, std::pair{&middle.v, &high.v},
                            std::pair{&middle.w, &high.w}, std::pair{&middle.u, &high.u},
                            std::pair{&middle.q, &high.q}, std::pair{&middle.f, &high.f},
                            std::pair{&middle.g, &high.g}, std::pair{&middle.power, &high.power}}) {
      (*to)[n] = DoubleDouble::from((*from)[n] * power);
    }
  }
  recurrences<DoubleDouble>(middle,
                            {DoubleDouble::from(gamma_), DoubleDouble::from(kappa_),
                             DoubleDouble::from(a_), DoubleDouble::from(q_exponent),
                             DoubleDouble::from(scale), middle_.inverse},
                            exact, middle_end);
  Series<double> low = low_.view();
  if (middle_end < order) {
    for (std::size_t n = 0; n <= middle_end; ++n) {
      for (auto [to, from] : {std::pair{&low.d, &middle.d}, std::pair{&low.v, &middle.v},
                              std::pair{&low.w, &middle.w}, std::pair{&low.u, &middle.u},
                              std::pair{&low.q, &middle.q}, std::pair{&low.f, &middle.f},
                              std::pair{&low.g, &middle.g}, std::pair{&low.power, &middle.power}}) {
        (*to)[n] = (*from)[n].hi();
      }
    }
    recurrences<double>(low,
                        {static_cast<double>(gamma_), static_cast<double>(kappa_),
                         static_cast<double>(a_), static_cast<double>(q_exponent),
                         static_cast<double>(scale), low_.inverse},
                        middle_end, order);
  }
  // Back, unscaled: c_n = (c_n H^n) / H^n.
  const Real inverse = 1 / scale;
  power = Real(1);
  auto back = [&](std::vector<Real>& to, const std::vector<DoubleDouble>& mid,
                  const std::vector<double>& lo, std::size_t n) {
    to[n] = (n <= middle_end ? mid[n].template to<Real>() : Real(lo[n])) * power;
  };
  for (std::size_t n = 1; n <= order; ++n) {
    power *= inverse;
    if (n <= exact) {
      continue;
    }
    back(d_, middle.d, low.d, n);
    back(v_, middle.v, low.v, n);
    back(w_, middle.w, low.w, n);
    if (force_end()) {
      back(u_, middle.u, low.u, n);
      back(q_, middle.q, low.q, n);
    }
  }
}

template <SupportedReal Real>
Real TaylorContact<Real>::log_radius_of(std::size_t top, bool with_cut) const {
  using std::abs;
  using std::exp;
  using std::log;
  // ρ = min (s / |x_n|)^(1/n), taken as min ln(s / |x_n|) / n: a logarithm per bound, one
  // exponential at the end, instead of a power per bound.
  Real log_rho = std::numeric_limits<Real>::infinity();
  auto bound_by = [&](const std::vector<Real>& x, const Real& scale) {
    for (const std::size_t n : {top - 1, top}) {
      const Real coefficient = abs(x[n]);
      if (scale > 0 && coefficient > 0) {
        log_rho = std::min(log_rho, Real(log(scale / coefficient) * inverse_[n]));
      }
    }
  };
  // δ > 0 inside a contact: its own value is its scale. v and W pass through 0 (at the peak; W at
  // the start), so their scale is their value plus their growth over the radius found from δ:
  // with |v_0| alone the steps would shrink with v towards the peak, a geometric creep that never
  // reaches it at low orders (h ∝ |v_0|^(1/(N−1))).
  bound_by(d_, abs(d_[0]));
  const Real reach = log_rho < std::numeric_limits<Real>::infinity() ? Real(exp(log_rho)) : Real(0);
  bound_by(v_, abs(v_[0]) + abs(v_[1]) * reach);
  if (with_work()) {
    // W must take part: where the solution is entire (p = 1, and odd p away from δ = 0) ρ measures
    // the oscillation of δ and v, and W, an integral of v², oscillates twice as fast; its N-th
    // term is then ~2^N times theirs (the work of p = 1 erred by 6e-27 in quad without this).
    bound_by(w_, abs(w_[0]) + abs(w_[1]) * reach);
  }
  if (with_cut) {
    // The cut's κ δ^(p−β) + γ v, on whose polynomial the force end is found (run()): δ^(p−β) has
    // the exit's branch point at a lower power than δ (δ^½ against δ^3.5 at p = 1.5, β = 1), and
    // a step sized by δ alone left its series 1e-29 off at the step's end near the exit, t_cut
    // 2.2e-31 off in float128 (MATH.md §12.2).
    bound_by(cut_, abs(cut_[0]) + abs(cut_[1]) * reach);
  }
  return log_rho;
}

template <SupportedReal Real>
Real TaylorContact<Real>::step_size(bool with_cut) const {
  using std::exp;
  const Real log_rho = log_radius_of(static_cast<std::size_t>(order_), with_cut);
  return log_rho < std::numeric_limits<Real>::infinity() ? Real(exp(log_rho)) * safety_
                                                         : std::numeric_limits<Real>::infinity();
}

template <SupportedReal Real>
Result<Real> TaylorContact<Real>::run() {
  // Entry: the series up to its reach, and not past v = ⅛ (the peak is the steps').
  Real t = std::min(entry_.entry_end, horizon_);
  Scaled y = t == entry_.entry_end ? entry_.at_end : entry_state(t);
  sample_through(t, [&](const Real& s) { return entry_state(s); });
  // The normal force's peak within the entry stretch (a heavily damped contact's comes early):
  // its rate is > 0 just after the onset unless the onset itself is the peak (β = 0).
  collision_.offer_onset_force();
  if (collision_.pending(EventKind::force_peak)) {
    const Real rate_at_end = collision_.event_value(EventKind::force_peak, physical(y));
    rate_at_end_.emplace(t, rate_at_end);
    Real rising = t;
    for (int halving = 0;
         halving < 64 &&
         !((rising == t ? rate_at_end
                        : collision_.event_value(EventKind::force_peak,
                                                 physical(entry_motion(rising)))) > 0);
         ++halving) {
      rising /= 2;
    }
    if (rising < t) { // else the force still grows at the stretch's end: no peak within it
      find_force_peak(
          rising, t, [&](const Real& s) { return entry_state(s); },
          [&](const Real& s) { return entry_motion(s); });
    }
  }
  long steps = 0;
  while (t < horizon_) {
    // The clock at every step where a step is long (soft-float: tens of µs and more); in double
    // and long double every 256 steps, as the fixed-step solvers (a clock read was 3 % of a
    // double collision of five steps).
    if (const auto spent =
            collision_.out_of_budget(steps, std::numeric_limits<Real>::digits > 64)) {
      return collision_.finish(*spent, steps);
    }
    compute_coefficients(y);
    const Real estimate = step_size();
    const bool to_horizon = estimate >= horizon_ - t;
    Real h = to_horizon ? horizon_ - t : estimate;
    // Never across δ = 0: a step the estimate of ρ let through would end beyond the branch
    // point, where the polynomial means nothing. Also from a step that starts while loading:
    // where the solution is entire (p = 1, undamped) ρ is unbounded, and in 50 digits one step
    // went past the peak and over two zeros of δ (τ = 3π for π).
    if (const auto zero = first_sign_change(span_of(d_), h)) {
      h = *zero / 2;
    }
    // A step in which the cut falls is sized by the cut's own series too (log_radius_of): only
    // there, since elsewhere its error does not reach the answer (and in double it never did: a
    // step count doubled for nothing at β = 1).
    if (force_end() && collision_.pending(EventKind::exit) && first_sign_change(span_of(cut_), h)) {
      h = std::min(h, step_size(true));
    }
    find_force_peak(
        t, t + h, [&](const Real& s) { return state_at(s - t); },
        [&](const Real& s) { return motion_at(s - t); });
    for (const EventKind kind : {EventKind::peak, EventKind::exit}) {
      if (!collision_.pending(kind) || (kind == EventKind::exit && !force_end())) {
        continue;
      }
      const std::vector<Real>& event = kind == EventKind::peak ? v_ : cut_;
      if (const auto theta = first_sign_change(span_of(event), h)) {
        sample_through(t + *theta, [&](const Real& s) { return state_at(s - t); });
        if (record(kind, t + *theta, state_at(*theta))) {
          return collision_.finish(kind == EventKind::peak ? Outcome::peak : Outcome::exited,
                                   steps + 1);
        }
      }
    }
    sample_through(t + h, [&](const Real& s) { return state_at(s - t); });
    advance(y, h);
    t = to_horizon && h == horizon_ - t ? horizon_ : t + h;
    ++steps;
    if (collision_.settled(physical(y))) {
      return collision_.finish(Outcome::no_exit, steps);
    }
    if (!force_end() && !collision_.pending(EventKind::peak) && y[1] < 0) {
      const ContactSeries<Real>& exit = exit_series();
      // The straight-line guesses u ≈ −v, s ≈ δ / −v: Newton only near the reach.
      const auto contact =
          exit.within_reach(-y[1], y[0] / -y[1]) ? exit.locate(y[0], -y[1]) : std::nullopt;
      if (contact && t + contact->s > horizon_) {
        // The series sees a return beyond the horizon; like every solver, give up there.
        return collision_.finish(Outcome::no_exit, steps);
      }
      if (contact) {
        const Real tau = t + contact->s;
        const Real work_exit =
            y[2] + (with_work() ? exit.work_at(contact->u, contact->s) : Real(0));
        sample_through(tau, [&](const Real& s) {
          const auto point = exit.at(contact->u, tau - s);
          return Scaled{point.delta, -point.rate, with_work() ? work_exit - point.work : Real(0)};
        });
        const bool exited = record(EventKind::exit, tau, {Real(0), -contact->u, work_exit});
        return collision_.finish(exited ? Outcome::exited : Outcome::no_exit, steps);
      }
    }
  }
  return collision_.finish(Outcome::no_exit, steps);
}

} // namespace

template <SupportedReal Real>
Result<Real> solve_taylor(const Problem<Real>& problem, const Options<Real>& options) {
  return TaylorContact<Real>(problem, options).run();
}

#define PLDAMP_INSTANTIATE(Real, name)                                                             \
  template Result<Real> solve_taylor(const Problem<Real>&, const Options<Real>&);
PLDAMP_FOR_EACH_PRECISION(PLDAMP_INSTANTIATE)
#undef PLDAMP_INSTANTIATE

} // namespace pldamp::solvers::detail
