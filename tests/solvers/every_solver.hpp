// What every error-controlled solver must do, as value-parameterised tests over solver names
// (GoogleTest's abstract-test pattern): the tests are defined once in every_solver.cpp and each
// family's file (cvode_test.cpp, arkode_test.cpp, odeint_test.cpp, taylor_test.cpp) instantiates
// them for its solvers. Also the helpers the solver tests share.
#pragma once

#include "support.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::solvers::testing {

using analytic::Contact;

inline Problem<double> problem_of(const Contact<double>& c) {
  return {c.p(), c.m(), c.k(), c.v0(), c.alpha()};
}

inline double rel(double got, double want) {
  return std::abs(got - want) / std::abs(want);
}

// The largest relative error of any observable the result carries.
inline double worst_error(const Result<double>& r, const Contact<double>& c,
                          std::string* which = nullptr) {
  const auto x = analytic::observables(c);
  double worst = 0;
  auto check = [&](const std::optional<double>& got, const std::optional<double>& want,
                   const char* name) {
    if (got && want && std::isfinite(*want) && *want != 0) { // e = 0, τ = ∞: tested apart
      const double err = rel(*got, *want);
      if (err > worst || std::isnan(err)) {
        worst = std::isnan(err) ? INFINITY : err;
        if (which) {
          *which = name;
        }
      }
    }
  };
  check(r.e, x.e, "e");
  check(r.delta_max, x.delta_max, "delta_max");
  check(r.t_peak, x.t_peak, "t_peak");
  check(r.tau, x.tau, "tau");
  check(r.energy_load, x.energy_load, "energy_load");
  check(r.energy_unload, x.energy_unload, "energy_unload");
  check(r.normal_force_max, x.normal_force_max, "normal_force_max");
  check(r.t_normal_force_max, x.t_normal_force_max, "t_normal_force_max");
  return worst;
}

struct Case {
  double p, e, v0, m, k;
};

inline std::vector<Case> issue_grid() {
  std::vector<Case> cases;
  for (double p : {1.0, 1.5, 2.0, 3.0, 5.0}) {
    for (double e : {0.9, 0.5, 0.1, 0.01}) {
      for (double v0 : {1e-3, 1.0, 1e3}) {
        cases.push_back({p, e, v0, 1, 1});
      }
      cases.push_back({p, e, 0.5, 1.2e-5, 7e9}); // a 1 mm glass bead at 0.5 m/s, Hertz units
    }
  }
  return cases;
}

class EverySolver : public ::testing::TestWithParam<std::string> {};

// The registered error-controlled solvers whose names start with `family` ("cvode-", "taylor").
inline std::vector<std::string> family(std::string_view prefix) {
  std::vector<std::string> names;
  for (const SolverInfo& info : registry()) {
    if (!info.fixed_step && info.name.substr(0, prefix.size()) == prefix) {
      names.emplace_back(info.name);
    }
  }
  return names;
}

// The families that instantiate EverySolver; registry_test checks they cover every solver.
inline constexpr std::string_view tested_families[] = {"cvode-", "arkode-", "odeint-", "taylor"};

// A test name from a solver name ("cvode-bdf" -> "cvode_bdf").
inline std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

// log2 of the error ratio in e (or δ_max) between fixed steps τ/steps and τ/(2 steps): the
// observed order, over a smooth contact at p = 5 (the spring δ^5 and the dashpot δ² are
// polynomials, so no branch point lowers it) or the given p.
double observed_order(const std::string& solver, double p, unsigned want, double steps);

} // namespace pldamp::solvers::testing
