// A DEM code's unit test of its Hertz–Tsuji impact against pldamp's closed forms (docs/api.md):
// e, δ_max and τ within a tolerance that tightens with the step (the loop is first order in Δt),
// where an approximate formula would have allowed 2 %.
#include "dem_loop.hpp"

#include <pldamp/analytic.hpp>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace {

using pldamp::analytic::Contact;

double relative(double got, double want) {
  return std::abs(got / want - 1);
}

// Two spheres of 5 mm at 1 m/s, m* = 2.05 g (steel), k = 5.7e9 N/m^1.5, e = 0.7.
constexpr double m = 2.0546e-3, k = 5.7e9, v0 = 1.0, e = 0.7;

TEST(HertzTsujiImpact, TheLoopConvergesToTheClosedForms) {
  const Contact<double> contact = Contact<double>::from_e(1.5, e, v0, m, k);
  const double tau = pldamp::analytic::contact_duration(contact);
  const double delta_max = pldamp::analytic::delta_max(contact);
  double previous = 1;
  for (const int steps : {100, 1000, 10000}) {
    const Measured got = dem_impact(m, k, contact.alpha(), v0, tau / steps);
    const double worst = std::max({relative(got.e, pldamp::analytic::restitution(contact)),
                                   relative(got.delta_max, delta_max), relative(got.tau, tau)});
    // Measured 1.8e-3, 1.7e-4, 1.6e-5 (τ, the exit interpolated within its step); an α 1 % off
    // moves e by 3.6e-3, ten times this bound at 10⁴ steps.
    EXPECT_LT(worst, 0.3 / steps) << steps << " steps per contact";
    EXPECT_LT(worst, previous / 5) << steps << " steps per contact"; // first order, or better
    previous = worst;
  }
}

// The closed forms in any precision: 50 digits agree with double to double's rounding.
TEST(HertzTsujiImpact, FiftyDigitsAgreeWithDouble) {
  using Digits50 = boost::multiprecision::cpp_bin_float_50;
  const Contact<Digits50> precise = Contact<Digits50>::from_e(
      Digits50(3) / 2, Digits50(7) / 10, Digits50(1), Digits50(m), Digits50(k));
  const Contact<double> contact = Contact<double>::from_e(1.5, e, v0, m, k);
  EXPECT_LT(relative(pldamp::analytic::contact_duration(contact),
                     static_cast<double>(pldamp::analytic::contact_duration(precise))),
            1e-14);
}

} // namespace
