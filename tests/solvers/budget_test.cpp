// Every solve bounded and checked before it leaves solvers/ (problem.hpp, Outcome): the budgets
// (steps, wall time, a stop request), the invariants that turn an impossible answer into
// `unstable`, and the inputs that once crashed, hung or answered wrongly.
#include "collision.hpp"
#include "every_solver.hpp"

#include <atomic>
#include <chrono>
#include <stdexcept>

namespace pldamp::solvers::testing {
namespace {

const auto hertz = Contact<double>::from_e(1.5, 0.5, 1.0);

TEST(Invariants, AStepBeyondStabilityIsUnstableNotANumber) {
  // Once: e = 323.8 (verlet-predicted, dem-verlet at Δt = 10), e = 1.87 (arkode-dp5, Δt = 5),
  // δ_max = −1.7e15 (arkode-erk8, Δt = 3), all with outcome exited or no_exit.
  for (const auto& [solver, dt] :
       std::vector<std::pair<std::string, double>>{{"verlet-predicted", 10},
                                                   {"dem-verlet", 10},
                                                   {"dem-leapfrog", 10},
                                                   {"dem-symplectic-euler", 10},
                                                   {"arkode-dp5", 5},
                                                   {"arkode-erk8", 3}}) {
    Options<double> options;
    options.fixed_step = dt;
    const Result<double> r = solve(solver, problem_of(hertz), options);
    EXPECT_EQ(r.outcome, Outcome::unstable) << solver;
    EXPECT_FALSE(r.invariant.empty()) << solver;
    EXPECT_FALSE(r.e || r.delta_max || r.tau) << solver << ": nothing is filled";
  }
}

TEST(Invariants, AnImplicitStepThatCannotConvergeIsUnstableNotAnException) {
  Options<double> options;
  options.fixed_step = 10;
  const Result<double> r = solve("arkode-dirk", problem_of(hertz), options);
  EXPECT_EQ(r.outcome, Outcome::unstable);
  // The flag named (ARKStepGetReturnFlagName), then ARKODE's own message.
  EXPECT_EQ(r.invariant.rfind("ARKStepEvolve failed with ARK_CONV_FAILURE: ARKODE: At t = ", 0), 0u)
      << r.invariant;
}

// A failing SUNDIALS integrator names its flag, not a number: an absolute tolerance at the bottom
// of its range (ε² of the energy scale ½mv0²) under heavy damping fails the error test on the
// first step, in CVODE (both methods) and ERKStep alike.
TEST(Invariants, AFailingSundialsIntegratorNamesItsFlag) {
  Options<double> options;
  options.rtol = 1e-3;
  options.atol = 1e-31;
  const Problem<double> heavily_damped{.p = 1.5, .m = 1, .k = 1, .v0 = 1, .alpha = 1e4};
  for (const auto& [solver, failure] : std::vector<std::pair<std::string, std::string>>{
           {"cvode-bdf", "CVode failed with CV_ERR_FAILURE: CVode: At t = 0 and h = "},
           {"cvode-adams", "CVode failed with CV_ERR_FAILURE: CVode: At t = 0 and h = "},
           {"arkode-dp5", "ERKStepEvolve failed with ARK_ERR_FAILURE: ARKODE: At t = "}}) {
    const Result<double> r = solve(solver, heavily_damped, options);
    EXPECT_EQ(r.outcome, Outcome::unstable) << solver;
    EXPECT_EQ(r.invariant.rfind(failure, 0), 0u) << solver << ": " << r.invariant;
  }
}

// An event is recorded only while pending (collision.cpp asserts it; every method looks first):
// an exit before the peak is the method's bug. Where assertions are compiled in (CI's sanitizer
// build) it stops the program; elsewhere it is not checked.
TEST(InvariantsDeathTest, AnEventOutOfOrderFailsTheAssertion) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  detail::Collision collision(problem_of(hertz), Options<double>{});
  EXPECT_FALSE(collision.pending(EventKind::exit));
  EXPECT_DEBUG_DEATH(collision.record(EventKind::exit, 1.0, {0.0, -0.5, 0.0}), "pending\\(kind\\)");
}

TEST(Invariants, StableStepsKeepTheirAnswer) {
  // At 10 steps per contact no scheme gains more energy than its truncation: not unstable.
  for (const std::string solver : {"verlet-predicted", "dem-verlet", "dem-leapfrog"}) {
    for (const double p : {1.0, 1.5, 3.0}) {
      Options<double> options;
      options.steps_per_contact = 10;
      const Result<double> r =
          solve(solver, problem_of(Contact<double>::from_alpha(p, 0.0, 1.0)), options);
      EXPECT_EQ(r.outcome, Outcome::exited) << solver << " p=" << p << " " << r.invariant;
      EXPECT_NEAR(*r.e, 1.0, 3e-3) << solver << " p=" << p;
    }
  }
}

TEST(Invariants, ACoastingStretchNoLongerOverflowsIntoNoExit) {
  // p = 50, e ≈ 1: the force vanishes well before the exit, odeint's step grew to the horizon
  // and its stages overflowed |δ|^p; NaN errors were accepted and the answer was no_exit, e = 0.
  const auto c = Contact<double>::from_e(50.0, 0.999999, 1.0);
  for (const std::string solver : {"odeint-rkf78", "odeint-bs", "cvode-bdf", "arkode-dp5"}) {
    const Result<double> r = solve(solver, problem_of(c), Options<double>{});
    ASSERT_EQ(r.outcome, Outcome::exited) << solver;
    EXPECT_NEAR(*r.e, 0.999999, 2e-6) << solver;
  }
}

TEST(Budget, TheWallClockEndsASolveAsTimeLimit) {
  Options<double> options;
  options.fixed_step = 1e-9; // ~3e9 steps: far beyond any patience
  options.max_steps = std::numeric_limits<long>::max();
  options.max_seconds = 0.05;
  const auto start = std::chrono::steady_clock::now();
  const Result<double> r = solve("dem-verlet", problem_of(hertz), options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.outcome, Outcome::time_limit);
  EXPECT_LT(seconds, 5.0); // generous: the point is that it ends
  EXPECT_GT(r.steps, 0);
}

// A lane of a batch is charged its share of the batch's time (SharedClock): eight lanes that
// never end, each allowed 0.1 s, run together for about 0.8 s, not 0.1 s (each lane alone would
// have had its 0.1 s), and all end time_limit within 5 % of each other's steps (their clocks
// started as each lane was set up, a few µs apart; a scheduler's pause between two lanes' setup
// under the sanitizers' load made it 2.5 % once), in each batched scheme.
TEST(Budget, ABatchedLaneIsChargedItsShareOfTheBatchsTime) {
  for (const char* name : {"dem-verlet", "verlet-predicted"}) {
    Options<double> options;
    options.fixed_step = 1e-9; // ~3e9 steps: far beyond any patience
    options.max_steps = std::numeric_limits<long>::max();
    options.max_seconds = 0.1;
    const std::vector<Problem<double>> problems(8, problem_of(hertz));
    const std::vector<Options<double>> lanes(8, options);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<Result<double>> r = solve_batch(name, problems, lanes);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GT(seconds, 0.5) << name;  // 8 × 0.1 s, less the last interval's 256 steps
    EXPECT_LT(seconds, 10.0) << name; // generous: the point is that it ends
    for (const Result<double>& lane : r) {
      EXPECT_EQ(lane.outcome, Outcome::time_limit) << name;
      EXPECT_NEAR(double(lane.steps), double(r[0].steps), 0.05 * double(r[0].steps)) << name;
    }
  }
}

TEST(Budget, AStopRequestEndsEverySolverAsTimeLimit) {
  std::atomic<bool> stop{true};
  for (const SolverInfo& info : registry()) {
    Options<double> options;
    options.stop = &stop;
    const Result<double> r = solve(info.name, problem_of(hertz), options);
    EXPECT_EQ(r.outcome, Outcome::time_limit) << info.name;
  }
}

TEST(Budget, TheForceEndWithoutDampingIsTheOverlapEnd) {
  // taylor looked for a sign change of the spring force, which no step reaches (no step crosses
  // δ = 0): no_exit in double, a hang in 50 digits. The truth is e_cap = 1.
  const Problem<bin50> undamped{bin50(3) / 2, bin50(1), bin50(1), bin50(1), bin50(0)};
  Options<bin50> options;
  options.rtol = std::numeric_limits<bin50>::epsilon();
  options.end = End::force;
  const Result<bin50> r = solve("taylor", undamped, options);
  ASSERT_EQ(r.outcome, Outcome::exited);
  EXPECT_LT(abs(*r.e - 1), bin50(1e-45));
  for (const SolverInfo& info : registry()) {
    Options<double> d;
    d.end = End::force;
    const Result<double> rd =
        solve(info.name, problem_of(Contact<double>::from_alpha(1.5, 0.0, 1.0)), d);
    EXPECT_EQ(rd.outcome, Outcome::exited) << info.name;
  }
}

} // namespace
} // namespace pldamp::solvers::testing
