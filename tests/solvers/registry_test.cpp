// The registry and the solver interface: names, traits, validation with messages, independence
// of successive calls, the work counters and the step limit, for every registered solver.
#include "every_solver.hpp"

#include <limits>
#include <stdexcept>

namespace pldamp::solvers::testing {
namespace {

TEST(Registry, ListsEverySolverOnceAndRejectsUnknownNames) {
  const std::vector<std::string> expected{"cvode-bdf",
                                          "cvode-adams",
                                          "arkode-dp5",
                                          "arkode-erk8",
                                          "arkode-dirk",
                                          "odeint-rkf78",
                                          "odeint-bs",
                                          "taylor",
                                          "verlet-predicted",
                                          "dem-verlet",
                                          "dem-symplectic-euler",
                                          "dem-leapfrog"};
  std::vector<std::string> names;
  for (const SolverInfo& info : registry()) {
    names.emplace_back(info.name);
  }
  EXPECT_EQ(names, expected);
  const auto c = Contact<double>::from_e(1.5, 0.5, 1.0);
  try {
    solve("ode45", problem_of(c), Options<double>{});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown solver, expected cvode-bdf|cvode-adams|arkode-dp5|arkode-erk8|"
              "arkode-dirk|odeint-rkf78|odeint-bs|taylor|verlet-predicted|dem-verlet|dem-"
              "symplectic-euler|dem-leapfrog (got ode45)");
  }
}

TEST(Registry, TraitsSayHowEachSolverIsDriven) {
  for (const SolverInfo& info : registry()) {
    const std::string name(info.name);
    EXPECT_EQ(info.precisions, name == "taylor" ? every_precision : precision_bit<double>())
        << name;
    EXPECT_EQ(info.fixed_step, name == "verlet-predicted" || name.rfind("dem-", 0) == 0) << name;
    EXPECT_EQ(info.takes_rtol(), !info.fixed_step) << name;
    EXPECT_EQ(info.takes_atol, !info.fixed_step && name != "taylor") << name;
    EXPECT_EQ(info.takes_fixed_step, name.rfind("arkode-", 0) == 0) << name;
    EXPECT_EQ(info.default_tolerance,
              name == "taylor" ? DefaultTolerance::epsilon : DefaultTolerance::standard)
        << name;
    EXPECT_EQ(info.default_rtol<double>(),
              name == "taylor" ? std::numeric_limits<double>::epsilon() : 1e-8)
        << name;
  }
  EXPECT_EQ(solver_names([](const SolverInfo& info) { return info.fixed_step; }),
            "verlet-predicted|dem-verlet|dem-symplectic-euler|dem-leapfrog");
  EXPECT_EQ(&solver_named("odeint-bs"), find_solver("odeint-bs"));
  EXPECT_EQ(find_solver("ode45"), nullptr);
}

TEST(Registry, EveryErrorControlledSolverIsInATestedFamily) {
  // Each family file instantiates the EverySolver tests (every_solver.hpp) for its solvers.
  for (const SolverInfo& info : registry()) {
    const bool tested = std::any_of(
        std::begin(tested_families), std::end(tested_families),
        [&](std::string_view prefix) { return info.name.substr(0, prefix.size()) == prefix; });
    EXPECT_TRUE(info.fixed_step || tested) << info.name;
  }
}

TEST(Registry, OptionsASolverDoesNotTakeAreRefused) {
  const Problem<double> problem{1.5, 1, 1, 1, 0.5};
  auto message = [&](const std::string& name, const Options<double>& options) {
    try {
      solve(name, problem, options);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  Options<double> atol;
  atol.atol = 1e-12;
  EXPECT_EQ(message("taylor", atol),
            "taylor controls its error relative to each state and takes no atol (got 1e-12)");
  EXPECT_EQ(message("verlet-predicted", atol),
            "verlet-predicted takes a fixed step and no atol (got 1e-12)");
  Options<double> dt;
  dt.fixed_step = 0.01;
  EXPECT_EQ(message("cvode-bdf", dt),
            "cvode-bdf has no fixed-step mode and takes no dt (got 0.01)");
  EXPECT_EQ(message("odeint-bs", dt),
            "odeint-bs has no fixed-step mode and takes no dt (got 0.01)");
  EXPECT_EQ(solve("arkode-dp5", problem, dt).fixed_step, 0.01);
  EXPECT_EQ(solve("verlet-predicted", problem, dt).fixed_step, 0.01);
}

TEST(Registry, OnlyTaylorRunsInOtherPrecisions) {
  const Problem<long double> problem{1.5L, 1, 1, 1, 0.5L};
  try {
    solve("cvode-bdf", problem, Options<long double>{});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "solver cvode-bdf runs in double precision only; taylor runs in any (got long)");
  }
  EXPECT_EQ(solve("taylor", problem, Options<long double>{}).outcome, Outcome::exited);
}

TEST(Validation, BadProblemsAndOptionsNameTheParameter) {
  auto message = [](const Problem<double>& problem, const Options<double>& options) {
    try {
      solve("cvode-bdf", problem, options);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  const Problem<double> good{1.5, 1, 1, 1, 0.5};
  Options<double> options;
  EXPECT_EQ(message({0.5, 1, 1, 1, 0.5}, options), "p must be in [1, 1000] (got 0.5)");
  EXPECT_EQ(message({1.5, 1, 1, 0, 0.5}, options), "v0 must be in [1e-30, 1e30] (got 0)");
  EXPECT_EQ(message({1.5, 1e300, 1e-300, 1, 0.5}, options),
            "m must be in [1e-30, 1e30] (got 1e+300)");
  EXPECT_EQ(message({1.5, 1, 1, 1, -1}, options), "alpha must be in [0, 1e8] (got -1)");
  EXPECT_EQ(message({1.5, 1, NAN, 1, 0.5}, options), "k must be finite (got nan)");
  options.rtol = 0;
  EXPECT_EQ(message(good, options), "rtol must be > 0 (got 0)");
  options.rtol = 1e-16; // below double's epsilon: CVODE would stop "too much accuracy"
  EXPECT_EQ(message(good, options),
            "rtol must be >= 2.220446049250313e-16, the epsilon of double (got 1e-16)");
  options.rtol = 1e-8;
  options.atol = -1;
  EXPECT_EQ(message(good, options), "atol must be > 0 (got -1)");
  options.atol = 1e300; // δ_max was −338
  EXPECT_EQ(message(good, options).rfind("atol must be in [2.46", 0), 0u);
  options.atol = 1e-300; // CVODE's error test failed at t = 0
  EXPECT_EQ(message(good, options).rfind("atol must be in [2.46", 0), 0u);
  options.atol.reset();
  options.horizon = 1e-300;
  EXPECT_EQ(message(good, options).rfind("horizon must be in [", 0), 0u);
  options.horizon.reset();
  options.atol.reset();
  options.sample_times = {-1};
  EXPECT_EQ(message(good, options), "sample time must be >= 0 (got -1)");
}

TEST(Registry, ResultsDoNotDependOnThePreviousCall) {
  // The SUNDIALS workspaces are kept per thread and re-initialised: nothing may leak from one
  // collision into the next (a fixed step used to linger as the next initial step).
  const auto c = Contact<double>::from_e(2.0, 0.3, 1.0);
  for (const SolverInfo& info : registry()) {
    const Result<double> first = solve(info.name, problem_of(c), Options<double>{});
    Options<double> other;
    if (info.fixed_step || info.takes_fixed_step) {
      other.fixed_step = 0.05;
    }
    other.end = End::force;
    other.rtol = 1e-4;
    solve(info.name, problem_of(Contact<double>::from_e(1.5, 0.9, 3.0)), other);
    const Result<double> again = solve(info.name, problem_of(c), Options<double>{});
    EXPECT_EQ(*first.e, *again.e) << info.name;
    EXPECT_EQ(*first.tau, *again.tau) << info.name;
    EXPECT_EQ(first.rhs_evals, again.rhs_evals) << info.name;
  }
}

TEST(Registry, WorkCountsJacobiansOfTheImplicitMethodsOnly) {
  const auto c = Contact<double>::from_e(1.5, 0.5, 1.0);
  for (const SolverInfo& info : registry()) {
    const Result<double> r = solve(info.name, problem_of(c), Options<double>{});
    const std::string name(info.name);
    const bool implicit = name.rfind("cvode", 0) == 0 || name == "arkode-dirk";
    EXPECT_EQ(r.jacobian_evals > 0, implicit) << name;
    if (name.rfind("dem-", 0) == 0) {
      // One force per step in contact; none in the step that reaches it, nor the one leaving.
      EXPECT_GE(r.rhs_evals, r.steps - 2) << name;
      EXPECT_LE(r.rhs_evals, r.steps) << name;
    } else {
      EXPECT_GT(r.rhs_evals, r.steps) << name; // at least one evaluation per step and the start
    }
  }
}

TEST(StepLimit, IsAnOutcomeNotAnError) {
  const auto c = Contact<double>::from_e(1.5, 0.5, 1.0);
  Options<double> options;
  options.max_steps = 2; // taylor's whole contact is four steps at p = 1.5, e = 0.5
  for (const SolverInfo& info : registry()) {
    const Result<double> r = solve(info.name, problem_of(c), options);
    EXPECT_EQ(r.outcome, Outcome::step_limit) << info.name;
    EXPECT_LE(r.steps, 2) << info.name;
  }
}

} // namespace
} // namespace pldamp::solvers::testing
