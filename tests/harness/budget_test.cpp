// Budgets and claims: the arithmetic on records made by hand.
#include "fixtures.hpp"

#include <gtest/gtest.h>

namespace pldamp::harness {
namespace {

using namespace testing;

TEST(Budgets, ArithmeticOnHandMadeRecords) {
  const HandMade h = hand_made();
  ASSERT_EQ(h.plan.configs.size(), 1u); // the claim's configuration
  const Budgets b = make_budgets(h.plan, h.records);
  EXPECT_EQ(*b.worst[0][0].abs, 2.5e-4);
  EXPECT_EQ(*b.worst[0][0].rel, 5e-4);
  EXPECT_EQ(*b.worst[0][1].rel, 7e-6);
  // Maps: per (p, damping) point, the worst over its v0.
  EXPECT_EQ(*b.map[0][1][0], 3e-6);
  EXPECT_EQ(*b.map[0][1][1], 7e-6);
  // Work at p = 2: the means over the four cells; the error the worst of all observables.
  EXPECT_DOUBLE_EQ(b.work[0][0].seconds, 3e-3);
  EXPECT_DOUBLE_EQ(b.work[0][0].rhs_evals, 250);
  EXPECT_EQ(*b.work[0][0].error, 5e-4);
  // The claim: largest absolute error 2.5e-4 under the bound 3e-4.
  ASSERT_EQ(b.claims.size(), 1u);
  EXPECT_TRUE(b.claims[0].holds);
  EXPECT_EQ(b.claims[0].measured, 2.5e-4);
  EXPECT_DOUBLE_EQ(*b.claims[0].margin, 1.2);
  EXPECT_DOUBLE_EQ(*b.claims[0].supported, 1e-3);
  // A failed cell fails the claim whatever the errors.
  HandMade failing = hand_made();
  failing.records[3].outcome = solvers::Outcome::step_limit;
  const Budgets f = make_budgets(failing.plan, failing.records);
  EXPECT_FALSE(f.claims[0].holds);
  EXPECT_EQ(f.claims[0].failed_cells, 1);
  EXPECT_EQ(f.failed_records, 1);
}

} // namespace
} // namespace pldamp::harness
