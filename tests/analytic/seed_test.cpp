// The seed's formulas as printed (analytic/seed.hpp): those that are right equal pldamp's closed
// forms; the printed unloading energy is wrong as MATH.md §3 says; each agrees between float128
// and cpp_bin_float_50. And the small-damping coefficients of τ/τ0 (MATH.md §3, §11.4) against
// the closed-form τ.
#include "epsilon.hpp"
#include "reference.hpp"
#include "support.hpp"

#include "pldamp/analytic/seed.hpp"

#include <vector>

namespace pldamp::analytic {
namespace {

using pldamp::testing::eps;
using pldamp::testing::relative_error;
using seed::Formula;

template <class Real>
class SeedTest : public ::testing::Test {};
TYPED_TEST_SUITE(SeedTest, pldamp::testing::FastReals);

// Every contact of these tests: p, α_eff and v0, m, k away from 1 (the formulas carry units).
template <SupportedReal Real>
std::vector<Contact<Real>> contacts() {
  std::vector<Contact<Real>> out;
  for (const Real& p : {Real(1), Real(3) / 2, Real(2), Real(7)}) {
    for (const Real& z : {Real(1) / 10, Real(1) / 2, Real(9) / 10}) {
      out.push_back(Contact<Real>::from_alpha_eff(p, z, Real(3), Real(2), Real(7)));
    }
  }
  return out;
}

TYPED_TEST(SeedTest, PrintedFormulasThatAreRightEqualTheClosedForms) {
  using Real = TypeParam;
  const double tolerance = 256 * eps<Real>();
  for (const Contact<Real>& c : contacts<Real>()) {
    const std::string where = "p=" + to_string_full(c.p()) + " z=" + to_string_full(c.alpha_eff());
    EXPECT_LE(relative_error(seed::evaluate(Formula::restitution, c), restitution(c)), tolerance)
        << where;
    EXPECT_LE(relative_error(seed::evaluate(Formula::delta_max, c), delta_max(c)), tolerance)
        << where;
    EXPECT_LE(relative_error(seed::evaluate(Formula::energy_load, c), energy_load(c)), tolerance)
        << where;
    EXPECT_LE(relative_error(seed::evaluate(Formula::dt_crit, c), dt_crit_seed(c)), tolerance)
        << where;
    EXPECT_LE(relative_error(seed::evaluate(Formula::undamped_duration, c), undamped_duration(c)),
              tolerance)
        << where;
    EXPECT_LE(
        relative_error(seed::evaluate(Formula::universal_factor, c), alpha_per_alpha_eff(c.p())),
        tolerance)
        << where;
    // α(e) of the seed's calibration inverts e(α_eff): the contact's own α.
    EXPECT_LE(relative_error(seed::alpha_of_e(c.p(), restitution(c)), c.alpha()), tolerance)
        << where;
    // Fig. 4's curve is τ/τ0 at p = 1 only.
    const Real ratio = duration_ratio(c);
    if (c.p() == 1) {
      EXPECT_LE(relative_error(seed::evaluate(Formula::tau_ratio_curve, c), ratio), tolerance);
    } else {
      EXPECT_GT(ratio, seed::evaluate(Formula::tau_ratio_curve, c) * (1 + Real(1) / 100)) << where;
    }
  }
}

TYPED_TEST(SeedTest, PrintedUnloadingEnergyIsNegative) {
  using Real = TypeParam;
  for (const Contact<Real>& c : contacts<Real>()) {
    const Real printed = seed::evaluate(Formula::energy_unload, c);
    EXPECT_LT(printed, 0) << to_string_full(c.alpha_eff());
    EXPECT_GT(energy_unload(c), 0);
    // The right split closes the energy balance; the printed one does not come near.
    const Real lost = c.ke0() * (1 - restitution(c) * restitution(c));
    EXPECT_LE(relative_error(Real(energy_load(c) + energy_unload(c)), lost), 64 * eps<Real>());
    EXPECT_GT(abs(energy_load(c) + printed - lost), lost / 10);
  }
  // e = 0.5 (MATH.md §3), by mpmath at 40 digits:
  //   z = -ln e/sqrt(pi^2 + ln^2 e), r = sqrt(1 - z^2)
  //   e^2/(exp(-2 z/r (pi - atan(r/z))) - 1) = -0.45813687319742549515...
  //   exp(-2 z/r atan(r/z)) - e^2 = 0.30028316962711574200...
  const Contact<Real> half = Contact<Real>::from_e(Real(3) / 2, Real(1) / 2, Real(1));
  EXPECT_LE(relative_error(Real(seed::evaluate(Formula::energy_unload, half) / half.ke0()),
                           bin50("-0.45813687319742549515065085239893448")),
            64 * eps<Real>());
  EXPECT_LE(relative_error(Real(energy_unload(half) / half.ke0()),
                           bin50("0.30028316962711574200963321739765470")),
            64 * eps<Real>());
}

// ln(τ/τ0) = s1 z + s2 z² + O(z³): τ/τ0 − 1 − s1 z − (s2 + s1²/2) z² is O(z³) against the
// closed-form τ, at z where z³ is far above the type's ε and z⁴ far below z³.
TYPED_TEST(SeedTest, SmallDampingCoefficientsOfTheDurationRatio) {
  using Real = TypeParam;
  using std::abs;
  using std::cbrt;
  const Real z = cbrt(Real(std::numeric_limits<Real>::epsilon())) * 16;
  for (const Real& p : {Real(1), Real(3) / 2, Real(3), Real(10)}) {
    const Contact<Real> c = Contact<Real>::from_alpha_eff(p, z, Real(1));
    const Real s1 = duration_ratio_slope(p), s2 = duration_ratio_curvature(p);
    const Real residual = duration_ratio(c) - 1 - s1 * z - s2 * z * z;
    EXPECT_LE(static_cast<double>(abs(residual) / (z * z * z)), 2.0) << to_string_full(p);
    if (p == 1) {
      EXPECT_EQ(s1, Real(0));
      EXPECT_LE(relative_error(s2, Real(1) / 2), 4 * eps<Real>()); // 1/√(1 − z²) = 1 + z²/2 + …
    }
  }
  // The values MATH.md §3 quotes for the first order.
  EXPECT_NEAR(static_cast<double>(duration_ratio_slope(Real(3) / 2)), 0.314159, 1e-6);
  EXPECT_NEAR(static_cast<double>(duration_ratio_slope(Real(2))), 0.523599, 1e-6);
  EXPECT_NEAR(static_cast<double>(duration_ratio_slope(Real(3))), 0.785398, 1e-6);
}

#if PLDAMP_WITH_QUAD
// The seed's formulas in float128 against cpp_bin_float_50, in float128's ε, measured (the test
// prints them: `conventions_test --gtest_filter='SeedQuad*'`) and set to twice the measured max
// and RMS, rounded up. The small-damping coefficients depend on p alone (region p_only).
constexpr pldamp::testing::ExpectedEpsilon seed_errors[] = {
    {"quad", "z<0.99", "*", 5, 3}, // measured 2.08, 1.5
    {"quad", "p_only", "*", 2, 1}, // measured 0.78, 0.445
};

TEST(SeedQuadVersusBin50, AgreeInEpsilon) {
  pldamp::testing::EpsilonErrors<quad> errors;
  for (const double p : {1.0, 1.5, 2.7, 10.0}) {
    for (const double z : {0.0, 0.05, 0.5, 0.95}) {
      const auto fast = Contact<quad>::from_alpha_eff(quad(p), quad(z), quad(3), quad(2), quad(7));
      const auto wide =
          Contact<bin50>::from_alpha_eff(bin50(p), bin50(z), bin50(3), bin50(2), bin50(7));
      const std::string where = "p=" + to_string_full(p) + " z=" + to_string_full(z);
      for (const seed::FormulaInfo& info : seed::formulas) {
        if (z == 0 && info.formula == Formula::energy_unload) {
          continue; // as printed it divides by zero there
        }
        errors.record(pldamp::testing::damping_region(z), info.name,
                      seed::evaluate(info.formula, fast), seed::evaluate(info.formula, wide),
                      where);
      }
    }
    const std::string where = "p=" + to_string_full(p);
    errors.record("p_only", "duration_ratio_slope", duration_ratio_slope(quad(p)),
                  duration_ratio_slope(bin50(p)), where);
    errors.record("p_only", "duration_ratio_curvature", duration_ratio_curvature(quad(p)),
                  duration_ratio_curvature(bin50(p)), where);
  }
  errors.check(seed_errors);
}
#endif

} // namespace
} // namespace pldamp::analytic
