// Validation messages, the calibrations of MATH.md §3 and §4, and their identities.
#include "support.hpp"

#include <cmath>
#include <random>
#include <string>

namespace pldamp::analytic {
namespace {

using pldamp::testing::eps;
using pldamp::testing::message_of;
using pldamp::testing::relative_error;

template <class Real>
class ContactTest : public ::testing::Test {};
TYPED_TEST_SUITE(ContactTest, pldamp::testing::AllReals);

TYPED_TEST(ContactTest, BadInputNamesTheParameterAndValue) {
  using Real = TypeParam;
  using C = Contact<Real>;
  const Real one(1);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  EXPECT_EQ(message_of([&] { C::from_e(Real(1) / 2, one / 2, one); }),
            "p must be in [1, 1000] (got 0.5)");
  EXPECT_EQ(message_of([&] { C::from_e(Real(1001), one / 2, one); }),
            "p must be in [1, 1000] (got 1001)");
  EXPECT_EQ(message_of([&] { C::from_e(nan, one / 2, one); }), "p must be finite (got nan)");
  EXPECT_EQ(message_of([&] { C::from_e(one, Real(0), one); }), "e must be in (0, 1] (got 0)");
  EXPECT_EQ(message_of([&] { C::from_e(one, Real(2), one); }), "e must be in (0, 1] (got 2)");
  EXPECT_EQ(message_of([&] { C::from_e(one, one / 2, Real(-1)); }),
            "v0 must be in [1e-30, 1e30] (got -1)");
  EXPECT_EQ(message_of([&] { C::from_e(one, one / 2, one, Real(-2)); }),
            "m must be in [1e-30, 1e30] (got -2)");
  EXPECT_EQ(message_of([&] { C::from_e(one, one / 2, one, nan); }), "m must be finite (got nan)");
  EXPECT_EQ(message_of([&] { C::from_e(one, one / 2, one, one, inf); }),
            "k must be finite (got inf)");
  EXPECT_EQ(message_of([&] { C::from_e(one, one / 2, one, one, Real(0)); }),
            "k must be in [1e-30, 1e30] (got 0)");
  EXPECT_EQ(message_of([&] { C::from_alpha(one, Real(-1), one); }),
            "alpha must be in [0, 1e8] (got -1)");
  EXPECT_EQ(message_of([&] { C::from_alpha_eff(one, Real(-1), one); }),
            "alpha_eff must be in [0, 1e6] (got -1)");
  EXPECT_EQ(message_of([&] { C::from_alpha_eff(one, nan, one); }),
            "alpha_eff must be finite (got nan)");
  EXPECT_EQ(message_of([&] { C::from_e(one, Real(0), one, one, one, ContactEnd::force); }),
            "e must be in (0, 1] (got 0)");
  // Below what α_eff = 1e6 gives at the force end, e_cap = e^(−2G) with G = 1e6 asinh(r)/r
  // (about 1/(4e12)): refused as such, not as the root bracket's α_eff 2^20 out of range.
  const Real e_cap_least = capped_restitution(damping_from_alpha_eff(Real(1000000)));
  EXPECT_LE(relative_error(e_cap_least, Real(Real(1) / 4000000000000)), Real(1) / 10000);
  EXPECT_EQ(message_of([&] {
              C::from_e(one, Real(1) / 100000000000000, one, one, one, ContactEnd::force);
            }),
            "e at the force end must be >= " + to_string_full(e_cap_least) +
                ", what the largest alpha_eff, 1e6, gives (got " +
                to_string_full(Real(1) / 100000000000000) + ")");
  // Just above it the root lies between 2^19 and 1e6, the bracket's end.
  EXPECT_GT(
      C::from_e(one, Real(e_cap_least * (1 + Real(1) / 1000)), one, one, one, ContactEnd::force)
          .alpha_eff(),
      Real(524288));
}

// ξ_L = −ln e/√(π² + ln²e); α = √(2(p+1)) ξ_L, which for p = 3/2 is Antypov–Elliott's √5 ξ_L.
TYPED_TEST(ContactTest, CalibrationIsTheUniversalFormula) {
  using Real = TypeParam;
  using std::log;
  using std::sqrt;
  const Real pi = boost::math::constants::pi<Real>();
  for (const Real& e :
       {Real(999) / 1000, Real(9) / 10, Real(1) / 2, Real(1) / 10, Real(1) / 1000}) {
    const Real xi = -log(e) / sqrt(pi * pi + log(e) * log(e));
    const Real hertz = Contact<Real>::from_e(Real(3) / 2, e, Real(1)).alpha();
    EXPECT_LE(relative_error(hertz, Real(sqrt(Real(5)) * xi)), 8 * eps<Real>()) << e;
    for (const Real& p : {Real(1), Real(2), Real(7)}) {
      const Real alpha = Contact<Real>::from_e(p, e, Real(1)).alpha();
      EXPECT_LE(relative_error(alpha, Real(sqrt(2 * (p + 1)) * xi)), 8 * eps<Real>()) << e;
    }
  }
  EXPECT_EQ(Contact<Real>::from_e(Real(2), Real(1), Real(1)).alpha(), Real(0));
  // +0, not −0: e = 1 printed as alpha "-0" and was refused by an adapter as negative.
  using std::signbit;
  EXPECT_FALSE(signbit(Contact<Real>::from_e(Real(3) / 2, Real(1), Real(1)).alpha()));
  EXPECT_FALSE(signbit(damping_from_e(Real(1)).z));
}

// One α everywhere (MATH.md §3 "One α"): a contact narrower than the calibration type holds α,
// α_eff and μ correctly rounded from the 50-digit calibration, at both ends, so the α a user's
// code gets from the library is the one `pldamp calibrate` prints (precision_paths_test.cpp).
// Calibrated in double, 10 of 18 (p, e) came one ulp off.
TYPED_TEST(ContactTest, CalibrationFromERoundsTheWideOneOnce) {
  using Real = TypeParam;
  if constexpr (std::numeric_limits<Real>::digits <
                std::numeric_limits<CalibrationReal<Real>>::digits) {
    int cases = 0;
    for (const Real& p :
         {Real(1), Real(5) / 4, Real(3) / 2, Real(2), Real(5) / 2, Real(3), Real(7)}) {
      for (const Real& e :
           {Real(1) / 1000, Real(1) / 20, Real(1) / 10, Real(3) / 10, Real(1) / 2, Real(61) / 100,
            Real(7) / 10, Real(9) / 10, Real(99) / 100, Real(999999) / 1000000}) {
        for (const ContactEnd end : {ContactEnd::overlap, ContactEnd::force}) {
          const Contact<Real> narrow = Contact<Real>::from_e(p, e, Real(1), Real(1), Real(1), end);
          const Contact<bin50> wide =
              Contact<bin50>::from_e(bin50(p), bin50(e), bin50(1), bin50(1), bin50(1), end);
          EXPECT_EQ(narrow.alpha(), static_cast<Real>(wide.alpha())) << "p " << p << " e " << e;
          EXPECT_EQ(narrow.alpha_eff(), static_cast<Real>(wide.alpha_eff()))
              << "p " << p << " e " << e;
          EXPECT_EQ(narrow.mu(), static_cast<Real>(wide.mu())) << "p " << p << " e " << e;
          ++cases;
        }
      }
    }
    EXPECT_EQ(cases, 140);
    // From α_eff, α is formed wide and rounded once too.
    const Real z = Real(3) / 10;
    EXPECT_EQ(Contact<Real>::from_alpha_eff(Real(3) / 2, z, Real(1)).alpha(),
              static_cast<Real>(bin50(z) * sqrt(bin50(5))));
  }
  // From α, α is the one given, not its round trip through α_eff.
  EXPECT_EQ(Contact<Real>::from_alpha(Real(3) / 2, Real(7) / 10, Real(1)).alpha(), Real(7) / 10);
}

// α and α_eff of a contact do not depend on its scales, to the bit, from e at both ends and from
// α_eff (MATH.md §7): the harness's answers read them off the contact they describe instead of
// calibrating a second, unit-scaled one (ask/contact.hpp).
TYPED_TEST(ContactTest, DampingIsScaleFreeToTheBit) {
  using Real = TypeParam;
  using C = Contact<Real>;
  const Real scales[][3] = {{Real(42) / 100, Real(3), Real(1) / 7},
                            {Real(1e-6), Real(2.7e-5), Real(4.5e8)},
                            {Real(1e6), Real(1e-9), Real(1e12)}};
  for (const Real& p : {Real(1), Real(3) / 2, Real(13) / 5, Real(7)}) {
    for (const Real& e : {Real(61) / 100, Real(1) / 1000, Real(999999) / 1000000}) {
      for (const ContactEnd end : {ContactEnd::overlap, ContactEnd::force}) {
        const C unit = C::from_e(p, e, Real(1), Real(1), Real(1), end);
        for (const auto& [v0, m, k] : scales) {
          const C scaled = C::from_e(p, e, v0, m, k, end);
          EXPECT_EQ(scaled.alpha(), unit.alpha()) << p << ' ' << e;
          EXPECT_EQ(scaled.alpha_eff(), unit.alpha_eff()) << p << ' ' << e;
          EXPECT_EQ(scaled.mu(), unit.mu()) << p << ' ' << e;
        }
      }
      const Real z = Real(1) - e; // an α_eff over (0, 1)
      EXPECT_EQ(C::from_alpha_eff(p, z, scales[1][0], scales[1][1], scales[1][2]).alpha(),
                C::from_alpha_eff(p, z, Real(1)).alpha());
    }
  }
}

// Contact<double>::from_e decides the rounding in long double where it can (contact.hpp): over
// 10^5 random (p, e), e spread over [1e-12, 1] in log and near 1, it must give exactly what the
// float128 calibration rounded once gives, which itself is tested against 50 digits above.
TEST(ContactFromE, TheLongDoublePassRoundsAsFloat128Does) {
  if constexpr (std::numeric_limits<CalibrationReal<double>>::digits >= 113) {
    using Wide = CalibrationReal<double>;
    std::mt19937_64 random(20261129);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int i = 0; i < 100000; ++i) {
      const double p = 1 + 9 * unit(random);
      const double e = i % 4 == 0 ? 1 - std::exp(-36 * unit(random)) // near 1: 1 − e down to 2e-16
                                  : std::exp(-27.6 * unit(random));  // 1e-12 to 1
      const Contact<double> c = Contact<double>::from_e(p, e, 1.0);
      const Contact<Wide> w = Contact<Wide>::from_e(Wide(p), Wide(e), Wide(1));
      ASSERT_EQ(c.alpha(), static_cast<double>(w.alpha())) << "p " << p << " e " << e;
      ASSERT_EQ(c.alpha_eff(), static_cast<double>(w.alpha_eff())) << "p " << p << " e " << e;
      ASSERT_EQ(c.mu(), static_cast<double>(w.mu())) << "p " << p << " e " << e;
    }
  }
}

// e → α → e. The condition number of e(z) is |ln e|·(1/μ): bounds scale with it.
TYPED_TEST(ContactTest, RestitutionRoundTripsThroughAlpha) {
  using Real = TypeParam;
  using std::log;
  for (const Real& e :
       {Real(999) / 1000, Real(9) / 10, Real(1) / 2, Real(1) / 10, Real(1) / 100, Real(1) / 1000}) {
    for (const Real& p : {Real(1), Real(3) / 2, Real(3)}) {
      const Contact<Real> from_e = Contact<Real>::from_e(p, e, Real(1));
      const Contact<Real> from_alpha = Contact<Real>::from_alpha(p, from_e.alpha(), Real(1));
      const double condition = 1 + static_cast<double>(-log(e) / from_e.mu());
      EXPECT_LE(relative_error(restitution(from_alpha.damping()), e), 8 * eps<Real>() * condition)
          << "e " << e << " p " << p;
      EXPECT_LE(relative_error(restitution(from_e.damping()), e), 16 * eps<Real>());
    }
  }
}

TYPED_TEST(ContactTest, NoReturnAtOrBeyondCriticalDamping) {
  using Real = TypeParam;
  for (const Real& z : {Real(1), Real(3) / 2, Real(10)}) {
    EXPECT_EQ(restitution(damping_from_alpha_eff(z)), Real(0));
    EXPECT_GT(capped_restitution(damping_from_alpha_eff(z)), Real(0));
  }
}

// MATH.md §4's angle formulas, evaluated directly, against e_cap = e^(−2G) (contact.hpp).
TYPED_TEST(ContactTest, CappedRestitutionMatchesTheAngleForm) {
  using Real = TypeParam;
  using std::abs;
  using std::atan;
  using std::atanh;
  using std::cos;
  using std::cosh;
  using std::exp;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  const Real pi = boost::math::constants::pi<Real>();
  for (const Real& z :
       {Real(1) / 10, Real(1) / 2, Real(7) / 10, Real(9) / 10, Real(3) / 2, Real(3)}) {
    Real expected;
    if (z < 1) {
      const Real r = sqrt(1 - z * z);
      const Real theta = 2 * z * z < 1 ? pi - atan(2 * z * r / (1 - 2 * z * z))
                                       : atan(2 * z * r / (2 * z * z - 1));
      expected = exp(-z * theta / r) * abs(cos(theta) - z / r * sin(theta));
    } else {
      const Real g = sqrt(z * z - 1);
      const Real u = atanh(2 * z * g / (2 * z * z - 1));
      expected = exp(-z * u / g) * abs(cosh(u) - z / g * sinh(u));
    }
    // The angle form cancels for large z (its two terms grow like z²): the bound does too.
    EXPECT_LE(relative_error(capped_restitution(damping_from_alpha_eff(z)), expected),
              64 * eps<Real>() * static_cast<double>(1 + z * z))
        << "z = " << z;
  }
  EXPECT_LE(relative_error(capped_restitution(damping_from_alpha_eff(Real(1))), exp(Real(-2))),
            4 * eps<Real>());
}

// MATH.md §4's table: z from e = 0.1/0.3/0.5/0.7/0.9 and z = 1.5, to 5 digits.
TEST(CappedTable, MatchesMath) {
  const std::pair<double, double> table[] = {
      {0.1, 0.25273}, {0.3, 0.39714}, {0.5, 0.55028}, {0.7, 0.71820}, {0.9, 0.90203}};
  for (const auto& [e, e_cap] : table) {
    EXPECT_NEAR(capped_restitution(damping_from_e(e)), e_cap, 0.5e-5) << "e = " << e;
  }
  EXPECT_NEAR(capped_restitution(damping_from_alpha_eff(1.5)), 0.075588, 0.5e-6);
}

TYPED_TEST(ContactTest, CappedCalibrationInvertsMonotonically) {
  using Real = TypeParam;
  Real previous_z(-1);
  for (const Real& target : {Real(1), Real(9) / 10, Real(55) / 100, Real(1) / 5, Real(135) / 1000,
                             Real(1) / 20, Real(1) / 1000}) {
    const Damping<Real> d = damping_from_e_cap(target);
    // z is found to 4 ulps; e_cap = e^(−2G) amplifies that by about |ln e_cap|.
    using std::log;
    EXPECT_LE(relative_error(capped_restitution(d), target),
              32 * eps<Real>() * (1 + static_cast<double>(-log(target))))
        << target;
    EXPECT_GT(d.z, previous_z) << target;
    previous_z = d.z;
  }
  const Contact<Real> hertz =
      Contact<Real>::from_e(Real(3) / 2, Real(1) / 2, Real(1), Real(1), Real(1), ContactEnd::force);
  EXPECT_LE(relative_error(capped_restitution(hertz), Real(1) / 2), 16 * eps<Real>());
}

} // namespace
} // namespace pldamp::analytic
