// The worst over every onset phase (run/phase_supremum.hpp): never below what any phase gives,
// reached at the phase it names, and at a jump of the exit step to the double's resolution.
#include "run/phase_supremum.hpp"

#include "pldamp/analytic/observables.hpp"
#include "pldamp/solvers/registry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

// A dem-verlet contact at a coarse fixed step (p = 1.5, e ≈ 0.5, 25 steps a contact) and the
// relative errors of e, δ_max and τ at one phase against the closed forms.
struct CoarseContact {
  std::string scheme = "dem-verlet";
  double p = 1.5, alpha = 0.48176925776458657, dt = 3.5185315448303163 / 25;
  analytic::Observables<double> truth = analytic::observables(
      analytic::Contact<double>::from_alpha(p, alpha, 1.0), analytic::want_all);

  solvers::Result<double> solve(double phase) const {
    solvers::Options<double> options;
    options.fixed_step = dt;
    options.onset_phase = phase;
    return solvers::solve(scheme, solvers::Problem<double>{p, 1, 1, 1, alpha}, options);
  }
  PhasePoint point(double phase) const {
    const solvers::Result<double> r = solve(phase);
    return {.phase = phase,
            .piece = r.steps,
            .scores = {std::abs(*r.e / *truth.e - 1), std::abs(*r.delta_max / *truth.delta_max - 1),
                       std::abs(*r.tau / *truth.tau - 1)}};
  }
};

TEST(PhaseSupremum, NoPhaseExceedsItAndItsPhaseReachesIt) {
  for (const std::string scheme : {"dem-verlet", "dem-symplectic-euler", "verlet-predicted"}) {
    CoarseContact contact;
    contact.scheme = scheme;
    std::vector<PhasePoint> points;
    for (const double phase : sampled_phases(16)) {
      points.push_back(contact.point(phase));
    }
    int evaluations = 0;
    ASSERT_TRUE(refine_to_supremum(points, [&](double phase) {
      ++evaluations;
      return contact.point(phase);
    }));
    EXPECT_LT(evaluations, 1000) << scheme;
    for (std::size_t s = 0; s < 3; ++s) {
      const PhasePoint* worst = &points.front();
      for (const PhasePoint& point : points) {
        worst = point.scores[s] > worst->scores[s] ? &point : worst;
      }
      // Reached: the phase named gives it again.
      EXPECT_EQ(contact.point(worst->phase).scores[s], worst->scores[s]) << scheme << " " << s;
      // Never exceeded at 20 000 phases (the error at a phase is exact to rounding: a sampled
      // phase may reach the supremum, not pass it by more than a few ulps of its φ).
      double sampled = 0;
      for (int k = 0; k < 20000; ++k) {
        sampled = std::max(sampled, contact.point((k + 0.5) / 20000).scores[s]);
      }
      EXPECT_LE(sampled, worst->scores[s] * (1 + 1e-9)) << scheme << " score " << s;
      EXPECT_GT(worst->scores[s], 0) << scheme;
    }
  }
}

// τ as the first step position out jumps down by a step where the exit step changes; its worst is
// at the jump's upper side, which the refinement brackets to 2^-52 in φ.
TEST(PhaseSupremum, FindsTheJumpOfTheExitStep) {
  const CoarseContact contact;
  std::vector<PhasePoint> points;
  for (const double phase : sampled_phases(8)) {
    points.push_back(contact.point(phase));
  }
  refine_to_supremum(points, [&](double phase) { return contact.point(phase); });
  std::sort(points.begin(), points.end(),
            [](const PhasePoint& a, const PhasePoint& b) { return a.phase < b.phase; });
  int jumps = 0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (points[i].piece != points[i - 1].piece && points[i].phase > 0.5 / 8) {
      ++jumps;
      EXPECT_LE(points[i].phase - points[i - 1].phase, 0x1p-52) << points[i].phase;
      // Across the jump τ falls by one step: the limit from below is a step later.
      const double before = *contact.solve(points[i - 1].phase).tau;
      const double after = *contact.solve(points[i].phase).tau;
      EXPECT_NEAR(before - after, contact.dt, 1e-12);
    }
  }
  EXPECT_GE(jumps, 1);
}

// A budget spent before the supremum is found is said (the caller fails the record rather than
// report a lower bound as the worst); a run that failed at a sampled phase ends the search at once.
TEST(PhaseSupremum, SaysWhenItsBudgetIsSpent) {
  const CoarseContact contact;
  std::vector<PhasePoint> points;
  for (const double phase : sampled_phases(8)) {
    points.push_back(contact.point(phase));
  }
  const std::vector<PhasePoint> sampled = points;
  EXPECT_FALSE(refine_to_supremum(
      points, [&](double phase) { return contact.point(phase); }, 5));
  EXPECT_EQ(points.size(), sampled.size() + 5);
  points = sampled;
  points.front().scores[0] = std::numeric_limits<double>::infinity();
  int evaluations = 0;
  EXPECT_TRUE(refine_to_supremum(points, [&](double phase) {
    ++evaluations;
    return contact.point(phase);
  }));
  EXPECT_EQ(evaluations, 0);
}

} // namespace
} // namespace pldamp::harness
