#include "truth/reference_solve.hpp"

#include "pldamp/solvers/registry.hpp"

#include <boost/math/tools/toms748_solve.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>

namespace pldamp::harness {
namespace {

// The reference solve of a group at v0 = m = k = 1: taylor at ε. The error estimate's second
// solve (truth_error_estimate) passes its other tolerance and its α nudged by a few ulps.
template <TruthReal T>
solvers::Result<T> solve_at_unit_scale(const T& p, const T& beta, const T& group, solvers::End end,
                                       long max_steps = solvers::Options<T>{}.max_steps,
                                       const T& rtol = std::numeric_limits<T>::epsilon(),
                                       const T& alpha_factor = T(1)) {
  const T delta_u = unit_overlap(p);
  const solvers::Problem<T> problem{
      p, T(1), T(1), T(1), T(alpha_of(p, beta, group, delta_u) * alpha_factor), beta};
  solvers::Options<T> options;
  options.rtol = rtol;
  options.end = end;
  options.horizon = 10000 * delta_u; // δ_u / v0 with v0 = 1
  options.max_seconds = 600;
  options.max_steps = max_steps;
  return solvers::solve("taylor", problem, options);
}

// e = 1 needs no damping; e falls as the group grows (more damping), to 0 once the contact no
// longer returns.
template <TruthReal T>
T restitution_at(const T& p, const T& beta, const T& group, solvers::End end) {
  const solvers::Result<T>& r = reference_solve(p, beta, group, end);
  return r.e ? *r.e : T(0);
}

// A contact the solve saw return: a stated β's no_exit carries no e a target can be met with
// (its e is where the horizon cut it), the seed's β's is the closed form's decay.
template <class T>
bool returned(const solvers::Result<T>& r, const Exact& p, const Exact& beta) {
  return r.e.has_value() && !solvers::failing(r.outcome) &&
         (r.outcome != solvers::Outcome::no_exit || beta == (p - 1) / 2);
}

// Groups low < high with e(low) ≥ target ≥ e(high), and those e.
template <class T>
struct Bracket {
  T low, high, e_low, e_high;
};

// The bracket grows from [0, 1/8] by doubling the group until e falls to the target (undamped,
// e(0) = 1 exactly: no solve at the low end). `restitution(group)` is e, or none where the solve
// saw no return within its horizon (or its budget), which ends the search: e there is not 0 but
// beyond what the solve resolves, and a target below every e resolved has no group (it took 45 s
// to be bracketed against such "zeros" at e = 1e-30, then failed elsewhere).
template <class T, class Restitution>
std::optional<Bracket<T>> doubling_bracket(const T& target, Restitution&& restitution) {
  Bracket<T> bracket{T(0), T(1) / 8, T(1), T(0)};
  std::optional<T> e_high = restitution(bracket.high);
  for (int i = 0; i < 40 && e_high && *e_high > target; ++i) {
    bracket.low = bracket.high;
    bracket.e_low = *e_high;
    bracket.high *= 2;
    e_high = restitution(bracket.high);
  }
  if (!e_high || *e_high > target) {
    return std::nullopt;
  }
  bracket.e_high = *e_high;
  return bracket;
}

// The group of `e` from double taylor solves (20 µs each, against 3 to 5 ms in Exact), to about
// 1e-13, or none (a contact the double solve sees no return of). Only a first guess: Exact
// brackets it and decides.
std::optional<double> double_group_for_e(const Exact& p, const Exact& beta, const Exact& e,
                                         solvers::End end) {
  const Exact delta_u = unit_overlap(p);
  solvers::Options<double> options;
  options.rtol = 1e-15;
  options.end = end;
  options.horizon = static_cast<double>(10000 * delta_u);
  options.want = solvers::want_e;
  const double target = static_cast<double>(e);
  const auto restitution = [&](double group) -> std::optional<double> {
    const solvers::Problem<double> problem{
        static_cast<double>(p),
        1.0,
        1.0,
        1.0,
        static_cast<double>(alpha_of(p, beta, Exact(group), delta_u)),
        static_cast<double>(beta)};
    const solvers::Result<double> r = solvers::solve("taylor", problem, options);
    if (!returned(r, p, beta)) {
      return std::nullopt;
    }
    return *r.e;
  };
  const std::optional<Bracket<double>> bracket = doubling_bracket(target, restitution);
  if (!bracket) {
    return std::nullopt;
  }
  std::uintmax_t iterations = 100;
  bool failed = false;
  const auto [lo, hi] = boost::math::tools::toms748_solve(
      [&](double group) {
        const std::optional<double> at = restitution(group);
        failed = failed || !at;
        return at ? *at - target : -target;
      },
      bracket->low, bracket->high, bracket->e_low - target, bracket->e_high - target,
      boost::math::tools::eps_tolerance<double>(44), iterations);
  if (failed) {
    return std::nullopt;
  }
  return (lo + hi) / 2;
}

// In Exact the group is bracketed within 1e-13 of the double one (widened a thousandfold at a time
// to 1e-4 if it is not there: the double group is within 1e-16 of it at e = 0.61), which TOMS 748
// closes in a few solves: 4 against 12 Exact solves from the doubling search below, which remains
// for what the double solves cannot guess.
std::optional<std::pair<Exact, Exact>> bracket_near(const Exact& p, const Exact& beta,
                                                    const Exact& e, solvers::End end) {
  const std::optional<double> guess = double_group_for_e(p, beta, e, end);
  if (!guess || *guess <= 0) {
    return std::nullopt;
  }
  for (const double width : {1e-13, 1e-10, 1e-7, 1e-4}) {
    const Exact low = Exact(*guess) * (1 - Exact(width)), high = Exact(*guess) * (1 + Exact(width));
    const solvers::Result<Exact>& at_low = reference_solve(p, beta, low, end);
    const solvers::Result<Exact>& at_high = reference_solve(p, beta, high, end);
    if (!returned(at_low, p, beta) || !returned(at_high, p, beta)) {
      return std::nullopt;
    }
    if (*at_low.e >= e && *at_high.e <= e) {
      return std::pair{low, high};
    }
  }
  return std::nullopt;
}

std::optional<Exact> exact_group_for_e(const Exact& p, const Exact& beta, const Exact& e,
                                       solvers::End end) {
  if (e >= 1) {
    return Exact(0);
  }
  // TOMS 748 on a bracket [low, high] with e(low) ≥ e ≥ e(high).
  const auto closed = [&](const Exact& low, const Exact& high, const Exact& e_low,
                          const Exact& e_high) {
    std::uintmax_t iterations = 100;
    const auto [lo, hi] = boost::math::tools::toms748_solve(
        [&](const Exact& group) { return Exact(restitution_at(p, beta, group, end) - e); }, low,
        high, Exact(e_low - e), Exact(e_high - e),
        boost::math::tools::eps_tolerance<Exact>(std::numeric_limits<Exact>::digits - 4),
        iterations);
    // The end of the last bracket that meets e the closer, rather than its midpoint: both are
    // solved already, and the truth is the solve at the group returned.
    return abs(restitution_at(p, beta, lo, end) - e) <= abs(restitution_at(p, beta, hi, end) - e)
               ? lo
               : hi;
  };
  if (const auto near = bracket_near(p, beta, e, end)) {
    return closed(near->first, near->second, restitution_at(p, beta, near->first, end),
                  restitution_at(p, beta, near->second, end));
  }
  const std::optional<Bracket<Exact>> bracket =
      doubling_bracket(e, [&](const Exact& group) -> std::optional<Exact> {
        const solvers::Result<Exact>& r = reference_solve(p, beta, group, end);
        return returned(r, p, beta) ? r.e : std::nullopt;
      });
  if (!bracket) {
    return std::nullopt;
  }
  return closed(bracket->low, bracket->high, bracket->e_low, bracket->e_high);
}

} // namespace

template <TruthReal T>
T unit_overlap(const T& p) {
  using std::exp;
  using std::log;
  return exp(log((p + 1) / 2) / (p + 1));
}

template <TruthReal T>
std::array<T, 5> cell_scales(const T& p, const T& v0, const T& m, const T& k) {
  using std::exp;
  using std::log;
  const T log_length = log(m * v0 * v0 / k) / (p + 1);
  const T length = exp(log_length);
  return {T(1), length, T(length / v0), T(m * v0 * v0), T(k * exp(p * log_length))};
}

template <TruthReal T>
T group_of(const T& p, const T& beta, const T& alpha, const T& delta_u) {
  using std::pow;
  using std::sqrt;
  return alpha * pow(delta_u, beta - (p - 1) / 2) / sqrt(2 * (p + 1));
}

template <TruthReal T>
T alpha_of(const T& p, const T& beta, const T& group, const T& delta_u) {
  using std::pow;
  using std::sqrt;
  return group * sqrt(2 * (p + 1)) / pow(delta_u, beta - (p - 1) / 2);
}

template <TruthReal T>
const solvers::Result<T>& reference_solve(const T& p, const T& beta, const T& group,
                                          solvers::End end) {
  using Key = std::tuple<T, T, T, solvers::End>;
  static std::mutex mutex;
  static std::map<Key, std::unique_ptr<const solvers::Result<T>>> cache;
  const Key key{p, beta, group, end};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto found = cache.find(key); found != cache.end()) {
      return *found->second;
    }
  }
  auto result =
      std::make_unique<const solvers::Result<T>>(solve_at_unit_scale(p, beta, group, end));
  const std::lock_guard<std::mutex> lock(mutex);
  // Entries are never dropped: callers hold references (a run has a few thousand at most).
  return *cache.emplace(key, std::move(result)).first->second;
}

solvers::Result<Exact> reference_solve_within(const Exact& p, const Exact& beta, const Exact& group,
                                              solvers::End end, long max_steps) {
  return solve_at_unit_scale(p, beta, group, end, max_steps);
}

template <TruthReal T>
std::optional<T> group_for_e(const T& p, const T& beta, const T& e, solvers::End end) {
  if constexpr (std::is_same_v<T, Exact>) {
    return exact_group_for_e(p, beta, e, end);
  } else {
    using std::abs;
    // Newton from the float128 group g0, with the slope de/dg from two float128 solves at
    // g0 (1 ± h): its relative error O(h²) = 1e-16 leaves each step's error 1e-16 of the last
    // (1e-34 after the float128 answer, 1e-50 after one step), so two or three 50-digit solves
    // reach ε.
    const std::optional<Exact> start = exact_group_for_e(Exact(p), Exact(beta), Exact(e), end);
    if (!start || *start == 0) {
      return start ? std::optional<T>(T(0)) : std::nullopt;
    }
    const Exact h = Exact(1) / 100000000;
    const Exact slope = (restitution_at(Exact(p), Exact(beta), Exact(*start * (1 + h)), end) -
                         restitution_at(Exact(p), Exact(beta), Exact(*start * (1 - h)), end)) /
                        (2 * h * *start);
    T group(*start);
    for (int step = 0; step < 6; ++step) {
      const T correction = (restitution_at(p, beta, group, end) - e) / T(slope);
      group -= correction;
      if (abs(correction) <= 4 * std::numeric_limits<T>::epsilon() * group) {
        return group;
      }
    }
    return group; // six steps: the last correction was already below 1e-16 of the first
  }
}

std::vector<std::optional<double>>
truth_error_estimate(const std::vector<const Observable*>& observables, const Exact& p,
                     const Exact& beta, const Exact& group, solvers::End end) {
  // MATH.md §12.2: a second solve in Exact at another order and step sequence (16 ε: one order
  // fewer, other steps and other contact series) with α 4 ulps off (so that what rounding the
  // inputs does shows too); the estimate is twice their difference plus 4 ε of the value.
  const Exact epsilon = std::numeric_limits<Exact>::epsilon();
  const solvers::Result<Exact>& truth = reference_solve(p, beta, group, end);
  const solvers::Result<Exact> second = solve_at_unit_scale(
      p, beta, group, end, solvers::Options<Exact>{}.max_steps, 16 * epsilon, 1 + 4 * epsilon);
  std::vector<std::optional<double>> out;
  for (const Observable* observable : observables) {
    const std::optional<Exact> value = observable->measured(truth);
    const std::optional<Exact> other = observable->measured(second);
    std::optional<double> error;
    if (value && other && isfinite(*value) && isfinite(*other)) {
      const Exact bound = 2 * abs(*value - *other) + 4 * epsilon * abs(*value);
      error = static_cast<double>(*value == 0 ? bound : bound / abs(*value));
    } else if (value && other && *value == *other) {
      error = 0.0; // both infinite (no return)
    }
    out.push_back(error);
  }
  return out;
}

#define PLDAMP_INSTANTIATE_TRUTH(T)                                                                \
  template T unit_overlap(const T&);                                                               \
  template std::array<T, 5> cell_scales(const T&, const T&, const T&, const T&);                   \
  template T group_of(const T&, const T&, const T&, const T&);                                     \
  template T alpha_of(const T&, const T&, const T&, const T&);                                     \
  template const solvers::Result<T>& reference_solve(const T&, const T&, const T&, solvers::End);  \
  template std::optional<T> group_for_e(const T&, const T&, const T&, solvers::End);
PLDAMP_INSTANTIATE_TRUTH(Exact)
#if PLDAMP_WITH_QUAD // without float128, Exact is cpp_bin_float_50 already
PLDAMP_INSTANTIATE_TRUTH(bin50)
#endif
#undef PLDAMP_INSTANTIATE_TRUTH

} // namespace pldamp::harness
