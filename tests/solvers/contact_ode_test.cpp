// The physical equation behind every solver (contact_ode.hpp): its Jacobian at contact and its
// exit series against the analytic trajectory.
#include "every_solver.hpp"

#include "pldamp/solvers/contact_ode.hpp"

#include <limits>

namespace pldamp::solvers::testing {
namespace {

TEST(ContactOde, JacobianIsFiniteAtContactAndMatchesDifferencesAway) {
  for (double p : {1.0, 1.2, 1.5, 2.0, 2.9, 3.0, 5.0}) {
    const ContactOde<double> ode({p, 2.0, 3.0, 1.5, 0.8});
    const double floor = 1e-8;
    for (double delta : {0.0, -1e-3, 1e-12}) {
      const auto J = ode.jacobian(delta, -0.7, true, floor);
      for (const auto& row : J) {
        for (double x : row) {
          EXPECT_TRUE(std::isfinite(x)) << "p=" << p << " delta=" << delta;
        }
      }
    }
    const double delta = 0.3, v = -0.7, h = 1e-6;
    const auto J = ode.jacobian(delta, v, true, floor);
    const auto plus = ode.rhs(delta + h, v, true), minus = ode.rhs(delta - h, v, true);
    const auto vplus = ode.rhs(delta, v + h, true), vminus = ode.rhs(delta, v - h, true);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(J[i][0], (plus[i] - minus[i]) / (2 * h), 1e-7) << "p=" << p << " row " << i;
      EXPECT_NEAR(J[i][1], (vplus[i] - vminus[i]) / (2 * h), 1e-7) << "p=" << p << " row " << i;
    }
  }
}

TEST(ContactOde, ExitSeriesCompletesTheAnalyticTrajectory) {
  for (double p : {1.0, 1.5, 2.0, 3.0}) {
    for (double e : {0.9, 0.3, 0.05}) {
      const auto c = Contact<double>::from_e(p, e, 1.0);
      const ContactOde<double> ode(problem_of(c));
      const analytic::Trajectory<double> exact(c);
      const double tau = analytic::contact_duration(c);
      // The point of the exact trajectory where the series parameter is 1e-3 (bisection in time):
      // the series then errs by ~1e-9 relative, and by 1e-3 times less at ε = 1e-4.
      for (double epsilon : {1e-3, 1e-4}) {
        double lo = exact.time_at_parameter(exact.s_peak()), hi = tau;
        for (int i = 0; i < 200 && hi - lo > 1e-15 * tau; ++i) {
          const double mid = (lo + hi) / 2;
          const auto at = exact.at_time(mid);
          (ode.exit_series_parameter(at.delta, at.v) > epsilon ? lo : hi) = mid;
        }
        const auto at = exact.at_time(lo);
        const auto stretch = ode.exit_stretch(at.delta, at.v);
        const double bound = 10 * epsilon * epsilon * epsilon;
        EXPECT_LT(rel(lo + stretch.duration, tau), bound) << "p=" << p << " e=" << e;
        EXPECT_LT(rel(-stretch.exit_velocity, e), bound) << "p=" << p << " e=" << e;
      }
    }
  }
}

} // namespace
} // namespace pldamp::solvers::testing
