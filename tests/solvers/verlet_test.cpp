// verlet, the fixed-step velocity Verlet: its order, its default step, and what it does at the
// seed's critical step (MATH.md §6).
#include "every_solver.hpp"

namespace pldamp::solvers::testing {
namespace {

TEST(FixedStep, VerletIsSecondOrderInThePeakOverlap) {
  for (double n : {100.0, 200.0, 400.0}) {
    EXPECT_NEAR(observed_order("verlet-predicted", 1, want_delta_max, n), 2.0, 0.1) << n;
    EXPECT_NEAR(observed_order("verlet-predicted", 5, want_delta_max, n), 2.0, 0.1) << n;
    // For 1 < p < 3 the branch point at contact (force ~ t^((p−1)/2)) caps it at (p+1)/2.
    EXPECT_NEAR(observed_order("verlet-predicted", 1.5, want_delta_max, n), 1.25, 0.1) << n;
  }
}

TEST(FixedStep, VerletAtTheSeedsCriticalStepGainsEnergy) {
  // MATH.md §6 (ii): the seed's Δt_crit is about half the contact, and velocity Verlet run at it
  // returns the body faster than it came (e ≈ 3 undamped, Hertz).
  const auto c = Contact<double>::from_alpha(1.5, 0.0, 1.0);
  Options<double> options;
  options.fixed_step = analytic::dt_crit_seed(c);
  // That is energy gained beyond a stable step's truncation: the answer is called unstable.
  const Result<double> r = solve("verlet-predicted", problem_of(c), options);
  EXPECT_EQ(r.steps, 2);
  EXPECT_EQ(r.outcome, Outcome::unstable);
  EXPECT_FALSE(r.e);
  ASSERT_EQ(r.invariant.rfind("energy gained: e = ", 0), 0u) << r.invariant;
  const double e = std::stod(r.invariant.substr(std::string("energy gained: e = ").size()));
  EXPECT_GT(e, 2.5);
  EXPECT_LT(e, 3.5);
}

TEST(FixedStep, VerletDefaultsToFiftyStepsPerContactTimeScale) {
  const auto c = Contact<double>::from_e(1.0, 0.5, 1.0);
  const Result<double> r = solve("verlet-predicted", problem_of(c), Options<double>{});
  // p = 1: the contact lasts π/Ω1 = π/(Ω0 √μ), a little over the π/Ω0 the step is based on.
  EXPECT_NEAR(double(r.steps), 50 / std::sqrt(c.mu()), 1.5);
  EXPECT_DOUBLE_EQ(*r.fixed_step, M_PI / 50); // π δ_u/v0 / 50 with δ_u/v0 = 1/Ω0 = 1
  EXPECT_EQ(r.rhs_evals, r.steps + 1);
  EXPECT_LT(rel(*r.e, 0.5), 0.05);
}

} // namespace

TEST(FixedStep, VerletStopsASettledContactWithTheSameAnswer) {
  // Collision::settled, looked at every 64 steps: an overdamped contact whose energy can no
  // longer carry an exit above the noise ends no_exit there, not at the horizon 1000 δ_u/v0
  // (318,000 steps at 1000 per contact). A sample at the horizon keeps the run going to it.
  for (double p : {1.0, 1.25}) {
    const auto c = Contact<double>::from_alpha_eff(p, 4.0, 1.0);
    Options<double> options;
    options.steps_per_contact = 1000;
    const Result<double> settled = solve("verlet-predicted", problem_of(c), options);
    options.sample_times = {settled.horizon};
    const Result<double> full = solve("verlet-predicted", problem_of(c), options);
    ASSERT_EQ(settled.outcome, Outcome::no_exit) << p;
    ASSERT_EQ(full.outcome, Outcome::no_exit) << p;
    EXPECT_EQ(*settled.e, 0.0) << p;
    EXPECT_EQ(*settled.delta_max, *full.delta_max) << p; // the same steps up to the peak
    EXPECT_EQ(*settled.energy_load, *full.energy_load) << p;
    EXPECT_EQ(settled.steps % 64, 0) << p;
    EXPECT_LT(settled.steps, full.steps / 2) << p;
  }
}

} // namespace pldamp::solvers::testing
