// The truth beyond the seed's damping (MATH.md §12.2): the viscoelastic reference solve against
// independent 36-digit values (data/reference/viscoelastic.py: mpmath, another formulation and
// another integrator), and its own error estimate, a second solve in the same precision, bounding
// its error there and against the same solve in 50 digits on every observable.
#include "truth/reference_solve.hpp"

#include "analytic/reference.hpp"

#include "common/observables.hpp"

#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sstream>

namespace pldamp::harness {
namespace {

#if PLDAMP_WITH_QUAD
// Each row of the table: the float128 truth within 1e-28 of it (the budget for the
// viscoelastic truth) and within its own error estimate, on both ends' observables.
TEST(ViscoelasticTruth, MatchesIndependentValuesWithinItsErrorEstimate) {
  const pldamp::testing::CsvTable table(std::string(PLDAMP_DATA_DIR) +
                                        "/reference/viscoelastic.csv");
  ASSERT_GE(table.rows().size(), 15u);
  double worst_error = 0, worst_ratio = 0;
  std::string worst_where;
  for (const auto& row : table.rows()) {
    const auto cell = [&](std::string_view name) { return Exact(table.cell(row, name)); };
    const Exact p = cell("p"), beta = cell("beta"), group = cell("group");
    // The table's A is alpha_of's definition of the group, to the last digits.
    const Exact alpha = alpha_of(p, beta, group, unit_overlap(p));
    EXPECT_LT(abs(alpha - cell("A")) / cell("A"), 1e-32) << "line " << row.line;
    for (const solvers::End end : {solvers::End::overlap, solvers::End::force}) {
      const solvers::Result<Exact>& truth = reference_solve(p, beta, group, end);
      ASSERT_EQ(truth.outcome, solvers::Outcome::exited) << "line " << row.line;
      const std::vector<const Observable*> observables{
          find_observable("e"), find_observable("delta_max"), find_observable("t_peak"),
          find_observable("tau")};
      const std::vector<std::optional<double>> estimates =
          truth_error_estimate(observables, p, beta, group, end);
      for (std::size_t i = 0; i < observables.size(); ++i) {
        const std::string key(observables[i]->key_at(end)); // e_cap and t_cut at the force end
        const std::optional<Exact> value = observables[i]->measured(truth);
        ASSERT_TRUE(value.has_value()) << key << " line " << row.line;
        ASSERT_TRUE(estimates[i].has_value()) << key << " line " << row.line;
        const double error = static_cast<double>(abs(*value - cell(key)) / cell(key));
        const std::string where = key + " at line " + std::to_string(row.line);
        EXPECT_LT(error, 1e-28) << where;
        EXPECT_LE(error, *estimates[i]) << where;
        if (error > worst_error) {
          worst_error = error;
          worst_where = where;
        }
        worst_ratio = std::max(worst_ratio, error / *estimates[i]);
      }
    }
  }
  RecordProperty("worst_relative_error", fmt::format("{:.3g} ({})", worst_error, worst_where));
  RecordProperty("worst_error_over_estimate", fmt::format("{:.3g}", worst_ratio));
}

struct Dashpot {
  double p, beta, alpha;
};

// The viscoelastic contact (light to heavy damping), the dashpots of the solvers' tests, and
// p = 1.5, β = 1, α = 0.1 at the force end: there the float128 solve at its own order found t_cut
// 2.2e-31 off until a step holding the cut was sized by the cut's series too (MATH.md §12.2), and
// only a second solve at another order saw it.
constexpr Dashpot dashpots[] = {{1.5, 0.5, 0.05}, {1.5, 0.5, 0.5}, {1.5, 0.5, 2.0},
                                {1.5, 0.0, 0.3},  {1.0, 0.5, 0.4}, {2.5, 0.3, 1.0},
                                {1.5, 1.0, 0.1},  {1.5, 0.3, 3.0}};

TEST(TruthErrorEstimate, BoundsTheErrorAgainstFiftyDigits) {
  const std::vector<const Observable*> observables = observables_of(solvers::want_all);
  double worst_ratio = 0, widest = 0;
  std::string worst_where;
  for (const Dashpot& point : dashpots) {
    for (const solvers::End end : {solvers::End::overlap, solvers::End::force}) {
      const Exact p(point.p), beta(point.beta);
      const Exact group = group_of(p, beta, Exact(point.alpha), unit_overlap(p));
      const solvers::Result<Exact>& truth = reference_solve(p, beta, group, end);
      // The same contact in 50 digits: the group is what defines it, its α formed anew.
      const bin50 wide_p(p), wide_beta(beta);
      const solvers::Problem<bin50> wide{
          wide_p,   1, 1, 1, alpha_of(wide_p, wide_beta, bin50(group), unit_overlap(wide_p)),
          wide_beta};
      solvers::Options<bin50> options;
      options.rtol = std::numeric_limits<bin50>::epsilon();
      options.end = end;
      const solvers::Result<bin50> exact = solvers::solve("taylor", wide, options);
      ASSERT_EQ(truth.outcome, solvers::Outcome::exited);
      ASSERT_EQ(exact.outcome, solvers::Outcome::exited);
      const std::vector<std::optional<double>> estimates =
          truth_error_estimate(observables, p, beta, group, end);
      ASSERT_EQ(estimates.size(), observables.size());
      for (std::size_t i = 0; i < observables.size(); ++i) {
        const std::optional<Exact> value = observables[i]->measured(truth);
        const std::optional<bin50> reference = observables[i]->measured(exact);
        std::ostringstream where;
        where << "p=" << point.p << " beta=" << point.beta << " alpha=" << point.alpha << ' '
              << observables[i]->key_at(end);
        ASSERT_EQ(value.has_value(), reference.has_value()) << where.str();
        if (!value) {
          continue;
        }
        ASSERT_TRUE(estimates[i].has_value()) << where.str();
        const bin50 error = abs(bin50(*value) - *reference) / abs(*reference);
        const double ratio = static_cast<double>(error) / *estimates[i];
        if (ratio > worst_ratio) {
          worst_ratio = ratio;
          worst_where = where.str();
        }
        widest = std::max(widest, *estimates[i]);
      }
    }
  }
  EXPECT_LE(worst_ratio, 1.0) << worst_where;
  EXPECT_LT(widest, 1e-30); // useful: the reference remains a 30-digit truth
  RecordProperty("worst_error_over_estimate", fmt::format("{:.3g} ({})", worst_ratio, worst_where));
  RecordProperty("widest_estimate", fmt::format("{:.3g}", widest));
}
#endif

// A reference solve without an answer says why in the messages that refuse it (observables, a
// scene's point): a budget that ran out names its steps (its invariant is empty), an unstable
// one the invariant it broke.
TEST(ReferenceFailure, SaysWhyTheSolveGaveNoAnswer) {
  solvers::Result<Exact> budget;
  budget.outcome = solvers::Outcome::step_limit;
  budget.steps = 1000000;
  EXPECT_EQ(reference_failure(budget),
            "ended step_limit (its budget ran out after 1000000 steps, before the contact ended)");
  solvers::Result<Exact> unstable;
  unstable.outcome = solvers::Outcome::unstable;
  unstable.invariant = "energy gained: e = 2.7";
  EXPECT_EQ(reference_failure(unstable), "ended unstable (energy gained: e = 2.7)");
}

} // namespace
} // namespace pldamp::harness
