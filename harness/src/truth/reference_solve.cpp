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

// α of the group at overlap scale δ_u (MATH.md §12.1), in Real.
template <SupportedReal Real>
Real alpha_in(double p, double beta, const Real& group, const Real& delta_u) {
  using std::pow;
  using std::sqrt;
  const Real p_real(p);
  return group * sqrt(2 * (p_real + 1)) / pow(delta_u, Real(beta) - (p_real - 1) / 2);
}

template <SupportedReal Real>
solvers::Result<Real> solve_at_unit_scale(double p, double beta, const Real& group,
                                          solvers::End end) {
  using std::exp;
  using std::log;
  const Real p_real(p);
  const Real delta_u = exp(log((p_real + 1) / 2) / (p_real + 1));
  const solvers::Problem<Real> problem{
      p_real, Real(1), Real(1), Real(1), alpha_in(p, beta, group, delta_u), Real(beta)};
  solvers::Options<Real> options;
  options.rtol = std::numeric_limits<Real>::epsilon();
  options.end = end;
  options.horizon = 10000 * delta_u; // δ_u / v0 with v0 = 1
  options.max_seconds = 600;
  return solvers::solve("taylor", problem, options);
}

} // namespace

Exact unit_overlap(double p) {
  const Exact p_exact(p);
  return exp(log((p_exact + 1) / 2) / (p_exact + 1));
}

Exact group_of(double p, double beta, const Exact& alpha, const Exact& delta_u) {
  const Exact p_exact(p);
  return alpha * pow(delta_u, Exact(beta) - (p_exact - 1) / 2) / sqrt(2 * (p_exact + 1));
}

Exact alpha_of(double p, double beta, const Exact& group, const Exact& delta_u) {
  return alpha_in(p, beta, group, delta_u);
}

const solvers::Result<Exact>& reference_solve(double p, double beta, const Exact& group,
                                              solvers::End end) {
  using Key = std::tuple<double, double, Exact, solvers::End>;
  static std::mutex mutex;
  static std::map<Key, std::unique_ptr<const solvers::Result<Exact>>> cache;
  const Key key{p, beta, group, end};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto found = cache.find(key); found != cache.end()) {
      return *found->second;
    }
  }
  auto result = std::make_unique<const solvers::Result<Exact>>(
      solve_at_unit_scale<Exact>(p, beta, group, end));
  const std::lock_guard<std::mutex> lock(mutex);
  // Entries are never dropped: callers hold references (a run has a few thousand at most).
  return *cache.emplace(key, std::move(result)).first->second;
}

std::optional<Exact> group_for_e(double p, double beta, double e, solvers::End end) {
  // e falls as the group grows (more damping); 0 once the contact no longer returns.
  const Exact target(e);
  auto restitution = [&](const Exact& group) {
    const solvers::Result<Exact>& r = reference_solve(p, beta, group, end);
    return r.e ? *r.e : Exact(0);
  };
  if (e >= 1) {
    return Exact(0);
  }
  Exact low(0), high = Exact(1) / 8;
  Exact e_high = restitution(high);
  for (int i = 0; i < 40 && e_high > target; ++i) {
    low = high;
    high *= 2;
    e_high = restitution(high);
  }
  if (e_high > target) {
    return std::nullopt;
  }
  std::uintmax_t iterations = 100;
  const auto [lo, hi] = boost::math::tools::toms748_solve(
      [&](const Exact& group) { return Exact(restitution(group) - target); }, low, high,
      Exact(restitution(low) - target), Exact(e_high - target),
      boost::math::tools::eps_tolerance<Exact>(std::numeric_limits<Exact>::digits - 4), iterations);
  return (lo + hi) / 2;
}

std::vector<std::optional<double>>
truth_error_estimate(const std::vector<const Observable*>& observables, double p, double beta,
                     const Exact& group, solvers::End end) {
  using Wide = bin50;
  const solvers::Result<Exact>& truth = reference_solve(p, beta, group, end);
  const solvers::Result<Wide> wide = solve_at_unit_scale<Wide>(p, beta, Wide(group), end);
  std::vector<std::optional<double>> out;
  for (const Observable* observable : observables) {
    const std::optional<Exact> value = observable->measured(truth);
    const std::optional<Wide> exact = observable->measured(wide);
    std::optional<double> error;
    if (value && exact && isfinite(*exact) && isfinite(*value)) {
      const Wide difference = abs(Wide(*value) - *exact);
      error = static_cast<double>(*exact == 0 ? difference : difference / abs(*exact));
    } else if (value && exact && *value == Exact(*exact)) {
      error = 0.0; // both infinite (no return)
    }
    out.push_back(error);
  }
  return out;
}

} // namespace pldamp::harness
