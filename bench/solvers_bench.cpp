// One collision (p = 1.5, e = 0.5, v0 = m = k = 1, every observable) per registered solver at
// rtol 1e-6 and 1e-10 (fixed-step schemes: 50 and 1000 steps per contact). Counters: rhs_evals
// and steps per collision, ns_per_step, the worst relative error of e, δ_max, t_peak, τ and the
// energies against the closed forms, and x_analytic, the time as a multiple of the analytic
// layer's bundle of the same observables (measured here, in double).
#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using pldamp::analytic::Contact;
namespace solvers = pldamp::solvers;

const Contact<double>& contact() {
  static const Contact<double> c = Contact<double>::from_e(1.5, 0.5, 1.0);
  return c;
}

// Seconds per analytic bundle (e, δ_max, t_peak, τ, energies), the best of 5 batches.
double analytic_bundle_seconds() {
  static const double seconds = [] {
    using namespace pldamp::analytic;
    constexpr unsigned bundle = want_e | want_delta_max | want_t_peak | want_tau | want_energy;
    double best = INFINITY;
    for (int batch = 0; batch < 5; ++batch) {
      const auto start = std::chrono::steady_clock::now();
      for (int i = 0; i < 2000; ++i) {
        benchmark::DoNotOptimize(observables(contact(), bundle));
      }
      const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
      best = std::min(best, took.count() / 2000);
    }
    return best;
  }();
  return seconds;
}

double worst_error(const solvers::Result<double>& r) {
  const auto x = pldamp::analytic::observables(contact());
  double worst = 0;
  auto check = [&](const std::optional<double>& got, const std::optional<double>& want) {
    worst = std::max(worst, std::abs(*got - *want) / std::abs(*want));
  };
  check(r.e, x.e);
  check(r.delta_max, x.delta_max);
  check(r.t_peak, x.t_peak);
  check(r.tau, x.tau);
  check(r.energy_load, x.energy_load);
  check(r.energy_unload, x.energy_unload);
  return worst;
}

void collision(benchmark::State& state, const std::string& name, double rtol, int steps) {
  const Contact<double>& c = contact();
  const solvers::Problem<double> problem{c.p(), c.m(), c.k(), c.v0(), c.alpha()};
  solvers::Options<double> options;
  options.rtol = rtol;
  options.steps_per_contact = steps;
  solvers::Result<double> r;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    r = solvers::solve(name, problem, options);
    benchmark::DoNotOptimize(r);
  }
  const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
  state.counters["rhs_evals"] = double(r.rhs_evals);
  state.counters["steps"] = double(r.steps);
  state.counters["error"] = worst_error(r);
  state.counters["x_analytic"] =
      took.count() / double(state.iterations()) / analytic_bundle_seconds();
  state.counters["ns_per_step"] = took.count() * 1e9 / double(state.iterations()) / double(r.steps);
}

// What a batch's lanes hold: the onset phases k/n of one contact (e = 0.5, v0 = m = k = 1), as
// the harness runs a record's phases (16 as in data/scenes/dem.toml); 16 cells of one p (e 0.9 to
// 0.3, v0 0.1 and 10, m 1 and 1e-3, k = 1e5), as it runs the cells of one configuration; or those
// cells with the last 4 overdamped (α_eff = 1.5), which run until they settle, 10 to 100 times
// longer: the lanes that finish early leave the batch (compact_lanes).
enum class LaneSet { phases, cells, cells_overdamped };

std::vector<solvers::Problem<double>> lane_problems(LaneSet set, double p) {
  std::vector<solvers::Problem<double>> problems;
  for (int lane = 0; lane < 16; ++lane) {
    Contact<double> c = Contact<double>::from_e(p, 0.5, 1.0);
    if (set != LaneSet::phases) {
      const double v0 = lane % 2 == 0 ? 0.1 : 10.0, m = lane / 2 % 2 == 0 ? 1.0 : 1e-3;
      c = set == LaneSet::cells_overdamped && lane >= 12
              ? Contact<double>::from_alpha_eff(p, 1.5, v0, m, 1e5)
              : Contact<double>::from_e(p, 0.9 - 0.2 * (lane / 4), v0, m, 1e5);
    }
    problems.push_back({c.p(), c.m(), c.k(), c.v0(), c.alpha()});
  }
  return problems;
}

// Throughput of the batch path against the scalar one on the same 16 lanes (LaneSet), every
// observable, `steps` per contact. `batch` false: solve() per lane; true: one solve_batch.
// Counters: contacts per second of this core (items_per_second) and ns per lane-step.
void lanes(benchmark::State& state, const std::string& name, LaneSet set, double p, int steps,
           bool batch) {
  const std::vector<solvers::Problem<double>> problems = lane_problems(set, p);
  std::vector<solvers::Options<double>> options(problems.size());
  for (std::size_t lane = 0; lane < options.size(); ++lane) {
    options[lane].onset_phase = set == LaneSet::phases ? double(lane) / 16 : 0.0;
    options[lane].steps_per_contact = steps;
  }
  long lane_steps = 0;
  for (auto _ : state) {
    lane_steps = 0;
    if (batch) {
      const std::vector<solvers::Result<double>> r = solvers::solve_batch(name, problems, options);
      for (const solvers::Result<double>& one : r) {
        lane_steps += one.steps;
      }
      benchmark::DoNotOptimize(r);
    } else {
      for (std::size_t i = 0; i < problems.size(); ++i) {
        const solvers::Result<double> r = solvers::solve(name, problems[i], options[i]);
        lane_steps += r.steps;
        benchmark::DoNotOptimize(r);
      }
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(problems.size()));
  state.counters["ns_per_lane_step"] =
      benchmark::Counter(double(lane_steps) * double(state.iterations()) * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

const int registered = [] {
  for (const solvers::SolverInfo& info : solvers::registry()) {
    const std::string name(info.name);
    if (!info.fixed_step) {
      for (const double rtol : {1e-6, 1e-10}) {
        benchmark::RegisterBenchmark((name + "/rtol:" + (rtol > 1e-8 ? "1e-6" : "1e-10")).c_str(),
                                     collision, name, rtol, 50)
            ->Unit(benchmark::kMicrosecond);
      }
    } else {
      for (const int steps : {50, 1000}) {
        benchmark::RegisterBenchmark((name + "/steps:" + std::to_string(steps)).c_str(), collision,
                                     name, 1e-6, steps)
            ->Unit(benchmark::kMicrosecond);
      }
    }
  }
  const std::pair<LaneSet, const char*> sets[] = {{LaneSet::phases, "phases"},
                                                  {LaneSet::cells, "cells"},
                                                  {LaneSet::cells_overdamped, "cells_overdamped"}};
  for (const auto& [set, set_name] : sets) {
    for (const char* name :
         {"dem-verlet", "dem-symplectic-euler", "dem-leapfrog", "verlet-predicted"}) {
      for (const double p : {1.0, 1.5, 2.0, 3.0}) {
        for (const int steps : {50, 1000}) {
          for (const bool batch : {false, true}) {
            std::ostringstream label;
            label << set_name << "/" << name << "/p:" << p << "/lanes:16/steps:" << steps << "/"
                  << (batch ? "batch" : "scalar");
            benchmark::RegisterBenchmark(label.str().c_str(), lanes, name, set, p, steps, batch)
                ->Unit(benchmark::kMicrosecond);
          }
        }
      }
    }
  }
  return 0;
}();

} // namespace
