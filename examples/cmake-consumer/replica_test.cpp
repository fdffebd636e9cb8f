// The code's loop against pldamp's own integrators (pldamp::solvers, docs/api.md): `dem-verlet`
// is the same velocity-Verlet loop with the force from the half-step velocity, so the two agree
// to rounding; `cvode-bdf` integrates the equation to its tolerance without any closed form.
#include "dem_loop.hpp"

#include <pldamp/analytic.hpp>
#include <pldamp/solvers/registry.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr double m = 2.0546e-3, k = 5.7e9, v0 = 1.0;

TEST(Replica, TheCodesLoopIsPldampsDemVerletAndCvodeFindsTheClosedForm) {
  const auto contact = pldamp::analytic::Contact<double>::from_e(1.5, 0.7, v0, m, k);
  const double tau = pldamp::analytic::contact_duration(contact);
  const pldamp::solvers::Problem<double> problem{1.5, m, k, v0, contact.alpha()};
  pldamp::solvers::Options<double> fixed;
  fixed.fixed_step = tau / 200;
  const auto replica = pldamp::solvers::solve<double>("dem-verlet", problem, fixed);
  const Measured mine = dem_impact(m, k, contact.alpha(), v0, tau / 200);
  ASSERT_TRUE(replica.e && replica.delta_max);
  EXPECT_LT(std::abs(mine.e / *replica.e - 1), 1e-12);
  EXPECT_LT(std::abs(mine.delta_max / *replica.delta_max - 1), 1e-12);

  pldamp::solvers::Options<double> tight;
  tight.rtol = 1e-10;
  const auto cvode = pldamp::solvers::solve<double>("cvode-bdf", problem, tight);
  ASSERT_TRUE(cvode.e);
  EXPECT_LT(std::abs(*cvode.e / pldamp::analytic::restitution(contact) - 1), 1e-7);
}

} // namespace
