// Speed of the closed forms (issue targets, double: e, α(e), δ_max ≤ 50 ns; τ ≤ 300 ns; the bundle
// e, δ_max, t_peak, τ, energies ≤ 2 µs; float128 bundle ≤ 300 µs).
// Run: build/bench/analytic_bench
#include "pldamp/analytic.hpp"

#include <benchmark/benchmark.h>

#include <string>
#include <utility>
#include <vector>

namespace {

using namespace pldamp;
using namespace pldamp::analytic;

template <SupportedReal Real>
Contact<Real> hertz() {
  return Contact<Real>::from_e(Real(3) / 2, Real(1) / 2, Real(2), Real(1) / 100, Real(7000000000));
}

void restitution_double(benchmark::State& state) {
  const auto c = hertz<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(restitution(c));
  }
}
BENCHMARK(restitution_double);

void alpha_from_e_double(benchmark::State& state) {
  double e = 0.5;
  for (auto _ : state) {
    benchmark::DoNotOptimize(e);
    benchmark::DoNotOptimize(damping_from_e(e).z * alpha_per_alpha_eff(1.5));
  }
}
BENCHMARK(alpha_from_e_double);

// The loop the Python module's observables over an array runs (python/module.cpp), written in
// C++: a contact from each α, its observables with want_e, and α, α_eff and e stored. The module's
// target is at most twice this per element (bench/python_vectorised.py compares the two).
void restitutions_over_an_array(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<double> alpha(n), e(n), alpha_out(n), alpha_eff(n);
  for (std::size_t i = 0; i < n; ++i) {
    alpha[i] = 2.0 * double(i) / double(n); // 0 to 2: under- and overdamped (α_eff ≥ 1 from √5)
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const Contact<double> c = Contact<double>::from_alpha(1.5, alpha[i], 1.0, 1.0, 1.0);
      const Observables<double> o = observables(c, want_e);
      alpha_out[i] = c.alpha();
      alpha_eff[i] = c.alpha_eff();
      e[i] = *o.e;
    }
    benchmark::DoNotOptimize(e.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}
BENCHMARK(restitutions_over_an_array)->Arg(1000000)->Unit(benchmark::kMillisecond);

void delta_max_double(benchmark::State& state) {
  const auto c = hertz<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(delta_max(c));
  }
}
BENCHMARK(delta_max_double);

void tau_double(benchmark::State& state) {
  const auto c = hertz<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(contact_duration(c));
  }
}
BENCHMARK(tau_double);

void t_peak_double(benchmark::State& state) {
  const auto c = hertz<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(t_peak(c));
  }
}
BENCHMARK(t_peak_double);

constexpr unsigned bundle = want_e | want_delta_max | want_t_peak | want_tau | want_energy;

template <SupportedReal Real>
void bundle_of(benchmark::State& state) {
  const auto c = hertz<Real>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(observables(c, bundle));
  }
}
BENCHMARK(bundle_of<double>)->Name("bundle_double");
#if PLDAMP_WITH_QUAD
BENCHMARK(bundle_of<quad>)->Name("bundle_quad")->Unit(benchmark::kMicrosecond);
#endif
BENCHMARK(bundle_of<bin50>)->Name("bundle_bin50")->Unit(benchmark::kMicrosecond);

// Near z = 1 the exponent of τ is summed in a wider type (observables.hpp): what that costs.
template <SupportedReal Real>
void bundle_near_critical(benchmark::State& state) {
  const auto c = Contact<Real>::from_alpha_eff(Real(3) / 2, Real(999) / 1000, Real(2));
  for (auto _ : state) {
    benchmark::DoNotOptimize(observables(c, bundle));
  }
}
BENCHMARK(bundle_near_critical<double>)->Name("bundle_double_z0.999");
#if PLDAMP_WITH_QUAD
BENCHMARK(bundle_near_critical<quad>)->Name("bundle_quad_z0.999")->Unit(benchmark::kMicrosecond);
#endif

// Each observable of the bundle alone (observables(c, bit)), in double and float128: what a
// scene that asks for one pays. `observable/all/*` is every observable (want_all).
template <SupportedReal Real>
void observable_of(benchmark::State& state, unsigned want) {
  const auto c = hertz<Real>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(observables(c, want));
  }
}
const int observables_registered = [] {
  const std::pair<const char*, unsigned> wants[] = {
      {"e", want_e},
      {"delta_max", want_delta_max},
      {"t_peak", want_t_peak},
      {"tau", want_tau},
      {"energy", want_energy},
      {"spring_force_max", want_spring_force_max},
      {"dt_crit", want_dt_crit},
      {"capped", want_capped},
      {"normal_force", want_normal_force},
      {"all", want_all},
  };
  for (const auto& [name, want] : wants) {
    benchmark::RegisterBenchmark((std::string("observable/") + name + "/double").c_str(),
                                 observable_of<double>, want);
#if PLDAMP_WITH_QUAD
    benchmark::RegisterBenchmark((std::string("observable/") + name + "/quad").c_str(),
                                 observable_of<quad>, want)
        ->Unit(benchmark::kMicrosecond);
#endif
  }
  return 0;
}();

// Building a contact (validation, A, Ω0, ln L) is paid once per cell. From e it is calibrated in
// float128 and rounded once (MATH.md §3 "One α"): at the overlap end a closed form, at the force
// end a TOMS 748 root.
void contact_from_e_double(benchmark::State& state) {
  const auto end = state.range(0) == 0 ? ContactEnd::overlap : ContactEnd::force;
  double e = 0.5;
  for (auto _ : state) {
    benchmark::DoNotOptimize(e);
    benchmark::DoNotOptimize(Contact<double>::from_e(1.5, e, 2.0, 0.01, 7e9, end));
  }
  state.SetLabel(state.range(0) == 0 ? "overlap end" : "force end");
}
BENCHMARK(contact_from_e_double)->Arg(0)->Arg(1);

// The time-domain solution (trajectory.hpp): a Trajectory made (for a decay that never returns,
// its SlowDecay table) and asked for δ, v at 1000 times, 2^−60 to 2^60 (onset series, the map, the
// late form): what pldamp.trajectory does per call. Arg 0 returns (α_eff 0.5), 1 never does (2).
template <SupportedReal Real>
void trajectory_at_times(benchmark::State& state) {
  const Real alpha_eff = state.range(0) == 0 ? Real(1) / 2 : Real(2);
  const Contact<Real> c = Contact<Real>::from_alpha_eff(Real(3) / 2, alpha_eff, Real(1));
  std::vector<Real> times;
  for (int i = 0; i < 1000; ++i) {
    using std::exp2;
    times.push_back(Real(exp2(Real(-60) + Real(120) * Real(i) / Real(999))));
  }
  for (auto _ : state) {
    const Trajectory<Real> path(c);
    Real sum(0);
    for (const Real& t : times) {
      const TrajectoryPoint<Real> at = path.at_time(t);
      sum += at.delta + at.v;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * 1000);
}
BENCHMARK(trajectory_at_times<double>)
    ->Name("trajectory_1000_times_double")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMicrosecond);
#if PLDAMP_WITH_QUAD
BENCHMARK(trajectory_at_times<quad>)
    ->Name("trajectory_1000_times_quad")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
#endif

} // namespace
