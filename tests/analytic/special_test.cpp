// log|Γ(x+iy)| against exact identities and Boost's lgamma; the regime-free functions across
// their series switch; Gauss–Jacobi rules against exact moments.
#include "support.hpp"

#include <boost/math/special_functions/trigamma.hpp>

namespace pldamp::analytic {
namespace {

using pldamp::testing::eps;
using pldamp::testing::relative_error;

template <class Real>
class SpecialTest : public ::testing::Test {};
TYPED_TEST_SUITE(SpecialTest, pldamp::testing::AllReals);

// |Γ(½ + iy)|² = π / cosh(πy) and |Γ(1 + iy)|² = πy / sinh(πy) (DLMF 5.4.3, 5.4.4).
TYPED_TEST(SpecialTest, LogAbsGammaMatchesReflectionIdentities) {
  using Real = TypeParam;
  using std::abs;
  using std::log;
  const Real pi = boost::math::constants::pi<Real>();
  for (const Real& y : {Real(1) / 10, Real(1), Real(5), Real(30), Real(250)}) {
    // ln cosh x = x − ln 2 + log1p(e^(−2x)), ln sinh x = x − ln 2 + log1p(−e^(−2x)): no overflow.
    using std::exp;
    using std::log1p;
    const Real x = pi * y;
    const Real ln2 = boost::math::constants::ln_two<Real>();
    const Real half = (log(pi) - (x - ln2 + log1p(exp(-2 * x)))) / 2;
    const Real one = (log(pi * y) - (x - ln2 + log1p(-exp(-2 * x)))) / 2;
    // Absolute error: the result enters an exponential. y·arg(w) is of size πy/2, so the
    // bound scales with y.
    const Real tolerance = Real(32 * eps<Real>()) * (1 + y);
    EXPECT_LE(abs(log_abs_gamma(Real(1) / 2, y) - half), tolerance) << "y = " << y;
    EXPECT_LE(abs(log_abs_gamma(Real(1), y) - one), tolerance) << "y = " << y;
  }
}

// ln Γ(½) = ½ ln π, ln Γ(1) = ln Γ(2) = 0, and ln Γ(x + 1) − ln Γ(x) = ln x. (Boost's lgamma in
// 50 digits errs by up to ~16 ulps, hence 32.)
TYPED_TEST(SpecialTest, LogGammaIdentities) {
  using Real = TypeParam;
  using std::abs;
  using std::log;
  const Real pi = boost::math::constants::pi<Real>();
  EXPECT_LE(relative_error(log_gamma(Real(1) / 2), Real(log(pi) / 2)), 32 * eps<Real>());
  EXPECT_EQ(log_gamma(Real(1)), Real(0));
  EXPECT_EQ(log_gamma(Real(2)), Real(0));
  for (const Real& x : {Real(2) / 11, Real(9) / 10, Real(37) / 10}) {
    EXPECT_LE(abs(log_gamma(Real(x + 1)) - log_gamma(x) - log(x)), Real(32 * eps<Real>()) * 4);
  }
}

// Near the real axis ln|Γ(x+iy)/Γ(x)| = −(y²/2) ψ'(x) + O(y⁴): the ratio must keep its digits
// where ln|Γ(x+iy)| and ln Γ(x) agree to many places (the regime of τ at small damping).
TYPED_TEST(SpecialTest, LogAbsGammaRatioNearTheRealAxis) {
  using Real = TypeParam;
  using std::sqrt;
  const Real y = sqrt(Real(std::numeric_limits<Real>::epsilon()));
  for (const Real& x : {Real(2) / 11, Real(59) / 100, Real(1)}) {
    const Real expected = -y * y / 2 * boost::math::trigamma(x);
    // The O(y⁴) remainder is ~ε² relative to y²: the bound is set by rounding alone.
    EXPECT_LE(relative_error(log_abs_gamma_ratio(x, y), expected), 16 * eps<Real>()) << x;
  }
  EXPECT_EQ(log_abs_gamma_ratio(Real(1) / 2, Real(0)), Real(0));
}

// The series and closed forms must agree where the code switches between them.
TYPED_TEST(SpecialTest, RegimeFreeFunctionsAgreeAcrossSeriesSwitch) {
  using Real = TypeParam;
  using std::atan;
  using std::atanh;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  const Real nudge = 64 * std::numeric_limits<Real>::epsilon();
  for (const Real& w : {Real(1) / 4 - nudge, Real(1) / 4 + nudge}) {
    EXPECT_LE(relative_error(sinc_rf(w), Real(sin(sqrt(w)) / sqrt(w))), 8 * eps<Real>());
    EXPECT_LE(relative_error(sinc_rf(Real(-w)), Real(sinh(sqrt(w)) / sqrt(w))), 8 * eps<Real>());
  }
  for (const Real& w : {Real(1) / 16 - nudge, Real(1) / 16 + nudge}) {
    EXPECT_LE(relative_error(atan_rf(w), Real(atan(sqrt(w)) / sqrt(w))), 8 * eps<Real>());
    EXPECT_LE(relative_error(atan_rf(Real(-w)), Real(atanh(sqrt(w)) / sqrt(w))), 8 * eps<Real>());
  }
  EXPECT_EQ(sinc_rf(Real(0)), Real(1));
  EXPECT_EQ(cos_rf(Real(0)), Real(1));
  EXPECT_EQ(atan_rf(Real(0)), Real(1));
}

// An n-point Gauss–Jacobi rule integrates (1+t)^β·t^j exactly for j < 2n.
TYPED_TEST(SpecialTest, JacobiRuleIntegratesMomentsExactly) {
  using Real = TypeParam;
  using std::pow;
  for (const Real& beta : {Real(0), Real(-1) / 2, Real(-9) / 11}) {
    const JacobiRule<Real>& rule = jacobi_rule(beta);
    ASSERT_EQ(static_cast<int>(rule.nodes.size()), quadrature_order<Real>());
    for (int j = 0; j <= 8; ++j) {
      // ∫(1+t)^β t^j dt with t = u − 1: Σ_i C(j,i) (−1)^(j−i) 2^(β+i+1)/(β+i+1).
      Real exact(0);
      Real binomial(1);
      for (int i = 0; i <= j; ++i) {
        const Real sign = (j - i) % 2 == 0 ? Real(1) : Real(-1);
        exact += sign * binomial * pow(Real(2), beta + i + 1) / (beta + i + 1);
        binomial = binomial * Real(j - i) / Real(i + 1);
      }
      Real sum(0);
      for (std::size_t k = 0; k < rule.nodes.size(); ++k) {
        sum += rule.weights[k] * pow(rule.nodes[k], j);
      }
      // Odd moments vanish for β = 0: measure against the size of the integrand, 2^j.
      using std::abs;
      EXPECT_LE(abs(sum - exact), Real(16 * eps<Real>()) * pow(Real(2), j + 1))
          << "beta " << beta << " j " << j;
    }
  }
}

} // namespace
} // namespace pldamp::analytic
