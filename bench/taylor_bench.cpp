// The Taylor reference's speed against error (issue 31), on one collision with every observable:
// e = 0.61, v0 = 0.42, m = k = 1, at p ∈ {1, 1.5, 2, 3} and the viscoelastic p = 3/2, β = 1/2.
//
// - taylor/<precision>/<case>: taylor at its precision's epsilon (double, long double, float128,
//   cpp_bin_float_50). The series at the contact points depend on (p, β, α) only and are kept per
//   thread (taylor.cpp), so from the second iteration on these time a grid cell whose p and α an
//   earlier cell shared.
// - taylor_cold/<precision>/<case>: the same with a new α at every iteration (64 values around
//   e = 0.61, more than a thread keeps): the cost of a collision whose series are built.
// - adaptive/<solver>/<case>/rtol:<r>: taylor and every SUNDIALS and Odeint configuration in
//   double, at the tolerances where they reach 1e-12.
// Counters: err, the largest relative error of e, δ_max, t_peak and τ against the closed forms in
// float128 for the same α (the double closed forms' own error would blur the picture below
// 1e-14); steps and rhs_evals.
//
//   build/bench/taylor_bench --benchmark_min_time=0.2
//   python3 bench/taylor_speedup.py build/bench/taylor_bench   # taylor against the fastest
//                                                              # other config with err <= 1e-12
#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using pldamp::analytic::Contact;
namespace solvers = pldamp::solvers;

// The reference: float128, or 50 digits in a build without it.
using Exact = pldamp::NarrowestWithDigits10<30>;

struct Case {
  const char* name;
  double p;
  bool viscoelastic; // β = 1/2 instead of the seed's (p − 1)/2
};
constexpr Case cases[] = {
    {"p:1", 1.0, false}, {"p:1.5", 1.5, false},       {"p:2", 2.0, false},
    {"p:3", 3.0, false}, {"viscoelastic", 1.5, true},
};
constexpr double restitution = 0.61, impact_speed = 0.42;

// α for e = 0.61: the seed's closed form, or for the viscoelastic contact, whose e depends on v0,
// the seed's α for the same e (the contact then restitutes with its own e, which the closed forms
// do not give: its errors are against a 50-digit taylor solve).
double alpha_of(const Case& c) {
  return Contact<double>::from_e(c.p, restitution, 1.0).alpha();
}

template <class Real>
solvers::Problem<Real> problem_of(const Case& c, double alpha) {
  solvers::Problem<Real> problem{Real(c.p), Real(1), Real(1), Real(impact_speed), Real(alpha)};
  if (c.viscoelastic) {
    problem.damping_exponent = Real(1) / 2;
  }
  return problem;
}

struct Truth {
  Exact e, delta_max, t_peak, tau;
};
// The exact observables of a case at the α it is run with (α a double, converted exactly).
Truth truth_of(const Case& c) {
  const double alpha = alpha_of(c);
  if (!c.viscoelastic) {
    const auto x = pldamp::analytic::observables(
        Contact<Exact>::from_alpha(Exact(c.p), Exact(alpha), Exact(impact_speed)));
    return {*x.e, *x.delta_max, *x.t_peak, *x.tau};
  }
  using Wide = boost::multiprecision::cpp_bin_float_50;
  solvers::Options<Wide> options;
  options.rtol = std::numeric_limits<Wide>::epsilon();
  const auto r = solvers::solve("taylor", problem_of<Wide>(c, alpha), options);
  return {Exact(*r.e), Exact(*r.delta_max), Exact(*r.t_peak), Exact(*r.tau)};
}

template <class Real>
double worst_error(const solvers::Result<Real>& r, const Truth& truth) {
  auto relative = [](const std::optional<Real>& got, const Exact& want) {
    return got ? static_cast<double>(abs(static_cast<Exact>(*got) - want) / want)
               : std::numeric_limits<double>::infinity();
  };
  return std::max({relative(r.e, truth.e), relative(r.delta_max, truth.delta_max),
                   relative(r.t_peak, truth.t_peak), relative(r.tau, truth.tau)});
}

void count(benchmark::State& state, long steps, long rhs_evals) {
  state.counters["steps"] = double(steps);
  state.counters["rhs_evals"] = double(rhs_evals);
}

template <class Real>
void taylor(benchmark::State& state, const Case& c) {
  solvers::Options<Real> options;
  options.rtol = std::numeric_limits<Real>::epsilon();
  const solvers::Problem<Real> problem = problem_of<Real>(c, alpha_of(c));
  solvers::Result<Real> r;
  for (auto _ : state) {
    r = solvers::solve("taylor", problem, options);
    benchmark::DoNotOptimize(r);
  }
  count(state, r.steps, r.rhs_evals);
  if constexpr (std::numeric_limits<Real>::digits <= std::numeric_limits<Exact>::digits) {
    state.counters["err"] = worst_error(r, truth_of(c));
  }
}

// A new α at every iteration: 64 values of e in [0.6, 0.62].
template <class Real>
void taylor_cold(benchmark::State& state, const Case& c) {
  solvers::Options<Real> options;
  options.rtol = std::numeric_limits<Real>::epsilon();
  std::vector<solvers::Problem<Real>> problems;
  for (int i = 0; i < 64; ++i) {
    const double e = 0.6 + 0.02 * i / 63;
    problems.push_back(problem_of<Real>(c, Contact<double>::from_e(c.p, e, 1.0).alpha()));
  }
  std::size_t next = 0;
  for (auto _ : state) {
    auto r = solvers::solve("taylor", problems[next], options);
    benchmark::DoNotOptimize(r);
    next = (next + 1) % problems.size();
  }
}

void adaptive(benchmark::State& state, const Case& c, const std::string& name, double rtol) {
  solvers::Options<double> options;
  options.rtol = rtol;
  const solvers::Problem<double> problem = problem_of<double>(c, alpha_of(c));
  solvers::Result<double> r;
  for (auto _ : state) {
    r = solvers::solve(name, problem, options);
    benchmark::DoNotOptimize(r);
  }
  count(state, r.steps, r.rhs_evals);
  state.counters["err"] = worst_error(r, truth_of(c));
}

const int registered = [] {
  for (const Case& c : cases) {
    pldamp::for_each_precision([&]<class Real>() {
      const bool wide = std::numeric_limits<Real>::digits > 64; // milliseconds, not microseconds
      const std::string suffix = std::string(pldamp::precision_name<Real>()) + "/" + c.name;
      benchmark::RegisterBenchmark(("taylor/" + suffix).c_str(), taylor<Real>, c)
          ->Unit(wide ? benchmark::kMillisecond : benchmark::kMicrosecond);
      benchmark::RegisterBenchmark(("taylor_cold/" + suffix).c_str(), taylor_cold<Real>, c)
          ->Unit(wide ? benchmark::kMillisecond : benchmark::kMicrosecond);
    });
  }
  const double eps = std::numeric_limits<double>::epsilon();
  const std::pair<const char*, std::vector<double>> sweeps[] = {
      {"taylor", {1e-8, 1e-10, 1e-12, eps}}, {"odeint-bs", {1e-11, 1e-12, 1e-13}},
      {"odeint-rkf78", {1e-13, 1e-14, eps}}, {"arkode-dp5", {1e-13, 1e-14}},
      {"arkode-erk8", {1e-13, 1e-14, eps}},  {"cvode-adams", {1e-13, 1e-14, eps}},
      {"cvode-bdf", {1e-14, eps}},
  };
  for (const Case& c : cases) {
    for (const auto& [name, tolerances] : sweeps) {
      for (const double rtol : tolerances) {
        std::ostringstream label;
        label << "adaptive/" << name << "/" << c.name << "/rtol:";
        if (rtol == eps) {
          label << "eps";
        } else {
          label << rtol;
        }
        benchmark::RegisterBenchmark(label.str().c_str(), adaptive, c, std::string(name), rtol)
            ->Unit(benchmark::kMicrosecond);
      }
    }
  }
  return 0;
}();

} // namespace
