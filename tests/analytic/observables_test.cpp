// Every observable against the cpp_bin_float_50 reference table and live cpp_bin_float_50, and
// the identities of MATH.md §3, §6, §7.
#include "reference.hpp"
#include "support.hpp"

#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/math/special_functions/beta.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pldamp::analytic {
namespace {

using pldamp::testing::eps;
using pldamp::testing::relative_error;

template <class Real>
class ObservablesTest : public ::testing::Test {};
TYPED_TEST_SUITE(ObservablesTest, pldamp::testing::FastReals);

// The accuracy the issue asks of each type over z ∈ [0, 0.999] ∪ [1, 10]: double 1e−14
// (1e−13 within 1e−6 of z = 1), long double 1e−17, float128 1e−32. In the band 0.999 < z < 1,
// outside that domain, e and τ are exponentials of arguments up to ~10⁴·π and the rounded input
// μ = (1 − z)(1 + z) carries a condition number of the same size (|d ln v/d ln μ| ≈ |ln v|/2):
// there the bound grows with |ln v|/16.
template <SupportedReal Real>
double tolerance(double z, const bin50& value) {
  using std::abs;
  using std::log;
  double base = 1e-14;
  if constexpr (std::is_same_v<Real, long double>) {
    base = 1e-17;
  } else if constexpr (!std::is_same_v<Real, double>) {
    base = 1e-32;
  }
  if (std::abs(z - 1) <= 1e-6) {
    base *= 10;
  }
  if (z > 0.999 && z < 1 && value != 0) {
    base *= std::max(1.0, std::abs(static_cast<double>(log(abs(value)))) / 16);
  }
  return base;
}

// The part of the table that the type can represent: values that over- or underflow it must come
// out as inf or (near) zero.
template <SupportedReal Real>
void expect_matches(const std::optional<Real>& got, const bin50& want, double z,
                    const std::string& where) {
  using std::abs;
  ASSERT_TRUE(got.has_value()) << where;
  ASSERT_FALSE(boost::math::isnan(*got)) << where;
  const bin50 largest(std::numeric_limits<Real>::max());
  const bin50 smallest(std::numeric_limits<Real>::min());
  if (boost::multiprecision::isinf(want) || abs(want) > largest) {
    EXPECT_TRUE(boost::math::isinf(*got)) << where;
  } else if (want != 0 && abs(want) < smallest * 1024) {
    EXPECT_LE(abs(bin50(*got)), smallest * 1024) << where;
  } else if (want == 0) {
    EXPECT_EQ(*got, Real(0)) << where;
  } else {
    EXPECT_LE(relative_error(*got, want), tolerance<Real>(z, want)) << where;
  }
}

TYPED_TEST(ObservablesTest, MatchReferenceTable) {
  using Real = TypeParam;
  const auto rows = pldamp::testing::read_reference();
  ASSERT_GT(rows.size(), 250u);
  for (const auto& row : rows) {
    const auto got = pldamp::testing::as_map(observables(row.template contact<Real>()));
    for (const auto& [name, want] : row.expected) {
      const std::string where = name + " at p=" + std::to_string(row.p) + " " + row.input + "=" +
                                pldamp::to_string_full(row.value) + " v0=" + std::to_string(row.v0);
      expect_matches(got.at(name), want, row.z(), where);
    }
  }
}

// The peak of the total normal force and its time (MATH.md §3, "Peak normal force") against
// data/reference/normal_force_peak.csv: mpmath's maximum of F along the parametric solution,
// found by root-finding on dF/ds and timed by tanh-sinh quadrature (normal_force_peak.py beside
// it), independent of the closed form's quadratic. p = 1 with z ≥ ½ peaks at the onset.
TYPED_TEST(ObservablesTest, NormalForcePeakMatchesAnIndependentMaximum) {
  using Real = TypeParam;
  std::ifstream in(PLDAMP_DATA_DIR "/reference/normal_force_peak.csv");
  ASSERT_TRUE(in) << "cannot open normal_force_peak.csv";
  int rows = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'p') {
      continue;
    }
    std::stringstream cells(line);
    std::string p, z, force, time;
    std::getline(cells, p, ',');
    std::getline(cells, z, ',');
    std::getline(cells, force, ',');
    std::getline(cells, time, ',');
    const Contact<Real> c =
        Contact<Real>::from_alpha_eff(Real(bin50(p)), Real(bin50(z)), Real(1), Real(1), Real(1));
    const std::string where = "p = " + p + ", alpha_eff = " + z;
    const auto x = observables(c, want_normal_force | want_spring_force_max | want_t_peak);
    expect_matches(x.normal_force_max, bin50(force), std::stod(z), where + ": F");
    expect_matches(x.t_normal_force_max, bin50(time), std::stod(z), where + ": t");
    // The total force at the overlap's peak is the spring's: the peak is never below it, and
    // comes before the overlap's (at it only undamped).
    EXPECT_GE(*x.normal_force_max,
              *x.spring_force_max * (1 - 4 * std::numeric_limits<Real>::epsilon()))
        << where;
    EXPECT_LT(*x.t_normal_force_max, *x.t_peak) << where;
    ++rows;
  }
  EXPECT_EQ(rows, 60);
  // Undamped, the force peaks with the overlap: k δ_max^p at t_peak.
  const Contact<Real> undamped = Contact<Real>::from_alpha_eff(Real(3) / 2, Real(0), Real(2));
  const auto x = observables(undamped, want_normal_force | want_spring_force_max | want_t_peak);
  EXPECT_EQ(*x.normal_force_max, *x.spring_force_max);
  EXPECT_LE(relative_error(*x.t_normal_force_max, *x.t_peak), 4 * eps<Real>());
}

#if PLDAMP_WITH_QUAD
// float128 against cpp_bin_float_50 computed live, over p ∈ [1, 10], z ∈ [0, 0.999] ∪ [1, 10]
// with z = 1 ± 1e−3, 1e−6, 1e−9, and v0, m, k from 1e−6 to 1e9.
TEST(QuadVersusBin50, AgreeTo1e32) {
  const std::vector<double> ps{1, 1.1, 1.5, 2.7, 6.3, 10};
  const std::vector<double> zs{0, 0.3,      0.8,      0.999,    1 - 1e-6, 1 - 1e-9,
                               1, 1 + 1e-9, 1 + 1e-6, 1 + 1e-3, 2.5,      10};
  const double scales[][3] = {{1, 1, 1}, {1e-6, 1e9, 1e-6}, {1e9, 1e-6, 1e9}, {1e-6, 1e-6, 1e-6}};
  for (double p : ps) {
    for (double z : zs) {
      for (const auto& s : scales) {
        const auto fast = pldamp::testing::as_map(observables(
            Contact<quad>::from_alpha_eff(quad(p), quad(z), quad(s[0]), quad(s[1]), quad(s[2]))));
        const auto wide = pldamp::testing::as_map(observables(Contact<bin50>::from_alpha_eff(
            bin50(p), bin50(z), bin50(s[0]), bin50(s[1]), bin50(s[2]))));
        for (const auto& [name, want] : wide) {
          expect_matches(fast.at(name), *want, z,
                         name + " p=" + std::to_string(p) + " z=" + to_string_full(z));
        }
      }
    }
  }
}
#endif

// p = 1 is the linear spring-dashpot: τ = π/Ω1, t_peak = atan(Ω1/(ξΩ0))/Ω1,
// δ_max = (v0/Ω0) exp(−ξ/√(1−ξ²) · atan(√(1−ξ²)/ξ)).
TYPED_TEST(ObservablesTest, LinearCaseIsTheTextbook) {
  using Real = TypeParam;
  using std::atan;
  using std::exp;
  using std::sqrt;
  const Real pi = boost::math::constants::pi<Real>();
  for (const Real& xi : {Real(1) / 20, Real(3) / 10, Real(9) / 10}) {
    const Real k(7), m(3), v0(2);
    const Contact<Real> c = Contact<Real>::from_alpha_eff(Real(1), xi, v0, m, k);
    const Real omega0 = sqrt(k / m);
    const Real omega1 = omega0 * sqrt(1 - xi * xi);
    const Real r = sqrt(1 - xi * xi);
    // τ is assembled as exp of a sum of logs of size ~1: a few ulps each.
    EXPECT_LE(relative_error(contact_duration(c), Real(pi / omega1)), 32 * eps<Real>());
    EXPECT_LE(relative_error(t_peak(c), Real(atan(omega1 / (xi * omega0)) / omega1)),
              16 * eps<Real>());
    EXPECT_LE(relative_error(delta_max(c), Real(v0 / omega0 * exp(-xi / r * atan(r / xi)))),
              16 * eps<Real>());
    EXPECT_LE(relative_error(undamped_duration(c), Real(pi / omega0)), 16 * eps<Real>());
  }
}

// E_load + E_unload = KE0(1 − e²); E_load = KE0(1 − e_cap) (the cut is where x'² = e^(−2G)v0²).
TYPED_TEST(ObservablesTest, EnergySplitBalances) {
  using Real = TypeParam;
  for (const Real& p : {Real(1), Real(5) / 2, Real(9)}) {
    for (const Real& z : {Real(0), Real(1) / 1000, Real(1) / 2, Real(99) / 100, Real(1), Real(4)}) {
      const Contact<Real> c = Contact<Real>::from_alpha_eff(p, z, Real(3), Real(2), Real(5));
      const auto x = observables(c);
      using std::expm1;
      const Real loss = z < 1 ? Real(-c.ke0() * expm1(2 * *x.log_e)) : c.ke0(); // KE0(1 − e²)
      EXPECT_LE(relative_error(Real(*x.energy_load + *x.energy_unload), loss), 8 * eps<Real>())
          << "p " << p << " z " << z;
      using std::abs;
      EXPECT_LE(abs(*x.energy_load - c.ke0() * (1 - *x.e_cap)), 8 * eps<Real>() * c.ke0())
          << "p " << p << " z " << z;
    }
  }
}

// MATH.md §7: e is exactly independent of v0; δ_max ∝ v0^q and τ ∝ v0^(q−1).
TYPED_TEST(ObservablesTest, ScalingWithImpactVelocity) {
  using Real = TypeParam;
  using std::pow;
  const Real p = Real(5) / 2;
  const Real z = Real(3) / 10;
  const Contact<Real> unit = Contact<Real>::from_alpha_eff(p, z, Real(1));
  for (const Real& v0 : {Real(1) / 1000000, Real(1) / 1000, Real(1000), Real(1000000)}) {
    const Contact<Real> c = Contact<Real>::from_alpha_eff(p, z, v0);
    EXPECT_EQ(restitution(c), restitution(unit));
    EXPECT_LE(relative_error(delta_max(c), Real(delta_max(unit) * pow(v0, c.q()))),
              64 * eps<Real>());
    EXPECT_LE(
        relative_error(contact_duration(c), Real(contact_duration(unit) * pow(v0, c.q() - 1))),
        64 * eps<Real>());
    EXPECT_LE(relative_error(t_peak(c), Real(t_peak(unit) * pow(v0, c.q() - 1))), 64 * eps<Real>());
  }
}

// τ/τ0 = 1 + (π/2)(p−1)/(p+1)·z + O(z²)  (MATH.md §3, "Small damping").
TYPED_TEST(ObservablesTest, SmallDampingSlope) {
  using Real = TypeParam;
  using std::sqrt;
  const Real z = sqrt(Real(std::numeric_limits<Real>::epsilon())) * 8;
  for (const Real& p : {Real(3) / 2, Real(3), Real(10)}) {
    const Contact<Real> c = Contact<Real>::from_alpha_eff(p, z, Real(1));
    const Real slope = (duration_ratio(c) - 1) / z;
    const Real expected = boost::math::constants::half_pi<Real>() * (p - 1) / (p + 1);
    EXPECT_LE(relative_error(slope, expected), 10 * static_cast<double>(z)) << p;
    EXPECT_LE(relative_error(duration_ratio(c), Real(contact_duration(c) / undamped_duration(c))),
              64 * eps<Real>());
  }
}

template <SupportedReal Real>
std::optional<Real> restitution_at(const Real& p, const Real& z) {
  return observables(Contact<Real>::from_alpha_eff(p, z, Real(1)), want_e).e;
}

// ln e and ln τ stay finite and accurate where e and τ leave the type's range (near z = 1, where
// e ~ e^(−2221) underflows and, for p ≥ 2, τ overflows double), and equal ln of them elsewhere.
TYPED_TEST(ObservablesTest, LogarithmsOfRestitutionAndDuration) {
  using Real = TypeParam;
  using std::log;
  for (const Real& p : {Real(1), Real(2), Real(3)}) {
    const Contact<Real> c = Contact<Real>::from_alpha(p, Real(1) / 2, Real(3));
    const Observables<Real> x = observables(c, want_e | want_tau);
    EXPECT_LE(relative_error(*x.log_e, Real(log(*x.e))), 8 * eps<Real>()) << p;
    EXPECT_LE(relative_error(*x.log_tau, Real(log(*x.tau))), 8 * eps<Real>()) << p;
    const Real z = 1 - Real(1) / 1000000;
    const Observables<Real> near = observables(Contact<Real>::from_alpha_eff(p, z, Real(1)));
    const Observables<bin50> exact =
        observables(Contact<bin50>::from_alpha_eff(bin50(p), bin50(z), bin50(1)));
    EXPECT_LE(relative_error(*near.log_e, *exact.log_e), 8 * eps<Real>()) << p;
    EXPECT_LE(relative_error(*near.log_tau, *exact.log_tau), 8 * eps<Real>()) << p;
  }
  const bool underflows =
      *restitution_at(Real(2), Real(1) - Real(1) / 1000000) == 0; // e^(−2221), double only
  EXPECT_EQ(underflows, (std::is_same_v<Real, double>));
}

// The seed's Δt_crit and the tangent bound at p = 3/2, v0 = Ω0 = 1 (MATH.md §6: 1.749, 1.597),
// and Δt_crit/τ0 = 2/B(1/(p+1), ½) for every p.
TYPED_TEST(ObservablesTest, CriticalTimeSteps) {
  using Real = TypeParam;
  const Contact<Real> hertz = Contact<Real>::from_alpha_eff(Real(3) / 2, Real(0), Real(1));
  EXPECT_NEAR(static_cast<double>(dt_crit_seed(hertz)), 1.749, 5e-4);
  EXPECT_NEAR(static_cast<double>(dt_crit_tangent(hertz)), 1.597, 5e-4);
  for (const Real& p : {Real(1), Real(2), Real(6)}) {
    const Contact<Real> c =
        Contact<Real>::from_alpha_eff(p, Real(1) / 5, Real(3), Real(2), Real(7));
    const Real beta = boost::math::beta(Real(1) / (p + 1), Real(1) / 2);
    EXPECT_LE(relative_error(Real(dt_crit_seed(c) / undamped_duration(c)), Real(2 / beta)),
              64 * eps<Real>());
  }
}

// The closed-form τ and the Gauss–Jacobi t_peak against an independent tanh-sinh quadrature of
// (A q/Ω1)(v0/Ω1)^ν ∫ e^(cθ) sin^ν θ dθ (MATH.md §3), which meets the endpoint singularities with
// its double-exponential clustering instead of an exact weight.
TEST(IndependentQuadrature, DurationAndPeakTime) {
  using Real = double;
  boost::math::quadrature::tanh_sinh<Real> integrator;
  for (const Real& p : {1.5, 2.0, 3.0, 5.0}) {
    for (const Real& z : {0.1, 0.5, 0.9}) {
      const Contact<Real> c = Contact<Real>::from_alpha_eff(p, z, 2.0, 3.0, 5.0);
      const Real nu = c.nu();
      const Real root_mu = std::sqrt(c.mu());
      const Real cc = -nu * z / root_mu;
      const Real omega1 = c.omega0() * root_mu;
      const Real scale = c.A() * c.q() / omega1 * std::pow(c.v0() / omega1, nu);
      // Two-argument form: the second argument is the distance to the nearer endpoint, so
      // sin θ keeps its digits at both ends.
      const Real pi = boost::math::constants::pi<Real>();
      auto integrand = [&](Real theta, Real complement) {
        const Real s = theta < pi / 2 ? std::sin(theta) : std::sin(complement);
        return std::exp(cc * theta) * std::pow(s, nu);
      };
      EXPECT_LE(
          relative_error(contact_duration(c), scale * integrator.integrate(integrand, 0.0, pi)),
          1e-13)
          << "p " << p << " z " << z;
      const Real theta_peak = std::atan2(root_mu, z);
      auto rising = [&](Real theta) {
        return std::exp(cc * theta) * std::pow(std::sin(theta), nu);
      };
      EXPECT_LE(relative_error(t_peak(c), scale * integrator.integrate(rising, 0.0, theta_peak)),
                1e-13)
          << "p " << p << " z " << z;
    }
  }
}

// t_peak in double: 1e−15 relative with at most 64 integrand evaluations (the seed used 2000).
TEST(PeakTimeQuadrature, AtMost64EvaluationsFor1e15) {
  for (double p = 1; p <= 10; p += 0.75) {
    for (double z : {0.0, 0.01, 0.3, 0.7071, 0.9, 0.999, 1 - 1e-9, 1.0, 1 + 1e-6, 1.5, 4.0, 10.0}) {
      const Damping<double> d = damping_from_alpha_eff(z);
      const double q = 2 / (p + 1);
      const ScaledTime<double> fast(d, q);
      const double got = fast(peak_phase(d));
      EXPECT_LE(fast.evaluations(), 64u) << "p " << p << " z " << z;
      const ScaledTime<bin50> wide(damping_from_alpha_eff(bin50(z)), bin50(q)); // the same q
      const bin50 want = wide(peak_phase(damping_from_alpha_eff(bin50(z))));
      EXPECT_LE(relative_error(got, want), 1e-15) << "p " << p << " z " << z;
    }
  }
}

// Nothing in the domain evaluates to NaN, in any branch.
TEST(Domain, NoNaNAnywhere) {
  for (double p = 1; p <= 10; p += 0.5) {
    for (double z = 0; z <= 10; z += z < 0.9 ? 0.1 : (z < 1.1 ? 0.01 : 0.5)) {
      for (double v0 : {1e-6, 1.0, 1e9}) {
        const auto x = pldamp::testing::as_map(
            observables(Contact<double>::from_alpha_eff(p, z, v0, 1e-3, 1e6), want_all));
        for (const auto& [name, value] : x) {
          ASSERT_TRUE(value.has_value()) << name;
          EXPECT_FALSE(std::isnan(*value)) << name << " p " << p << " z " << z << " v0 " << v0;
        }
      }
    }
  }
}

TEST(Bundle, ComputesOnlyWhatIsAsked) {
  const auto c = Contact<double>::from_e(1.5, 0.5, 1.0);
  const auto x = observables(c, want_delta_max | want_e);
  EXPECT_TRUE(x.delta_max && x.e && x.log_e);
  EXPECT_FALSE(x.t_peak || x.tau || x.energy_load || x.e_cap || x.t_cut || x.dt_crit);
  EXPECT_EQ(*x.delta_max, delta_max(c));
}

} // namespace
} // namespace pldamp::analytic
