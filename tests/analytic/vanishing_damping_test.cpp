// Vanishing damping (MATH.md §3, "Vanishing damping"): every observable, at both ends, at
// α_eff = 10^−k down to each type's smallest value (its denorm_min where it has subnormals) and at
// 0, in ε (epsilon.hpp) against 50 digits at the same α_eff; 50 digits itself, below 1e−60,
// against the undamped values and the first-order terms derived there. z² underflows below √min
// (1.5e−154 in double, 1e−2466 in long double and float128): G and the normal force's peak were
// formed through μ/z² and μr² and came out 0 there (E_load = 0, F_max = 0, t_F = 0).
#include "epsilon.hpp"
#include "reference.hpp"
#include "support.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::analytic {
namespace {

using pldamp::testing::eps;
using pldamp::testing::EpsilonErrors;
using pldamp::testing::ExpectedEpsilon;

template <class Real>
class VanishingDampingTest : public ::testing::Test {};
TYPED_TEST_SUITE(VanishingDampingTest, pldamp::testing::FastReals);

// The p of the scan: linear (no time quadrature), Hertz, 5/2 and 10 (ν = q − 1 = −9/11).
const std::vector<double> vanishing_ps{1, 1.5, 2.5, 10};

// −log10 of x > 0, rounded down, for x anywhere in the range of any type.
long decades_below_one(const bin50& x) {
  using std::floor;
  using std::log10;
  return static_cast<long>(floor(-log10(x)));
}

// α_eff = 10^−k in Real from k = `first` down to the type's smallest value, in steps of
// max(1, k/3) decades up to 30 steps over the whole range, and every k within two decades of √min
// (where z² leaves the normal range), of min and of the smallest; then denorm_min (min for a type
// without subnormals).
template <SupportedReal Real>
std::vector<Real> vanishing_dampings(long first) {
  using std::pow;
  using std::sqrt;
  const Real tiniest = std::numeric_limits<Real>::denorm_min() > 0
                           ? std::numeric_limits<Real>::denorm_min()
                           : std::numeric_limits<Real>::min(); // cpp_bin_float's denorm_min is 0
  const long last = decades_below_one(bin50(tiniest));
  std::set<long> ks;
  for (long k = first; k <= last; k += std::max(1L, std::min(last / 30, k / 3))) {
    ks.insert(k);
  }
  for (const Real& edge :
       {Real(sqrt(std::numeric_limits<Real>::min())), std::numeric_limits<Real>::min(), tiniest}) {
    const long centre = decades_below_one(bin50(edge));
    for (long k = centre - 2; k <= std::min(centre + 2, last); ++k) {
      ks.insert(k);
    }
  }
  std::vector<Real> zs;
  for (long k : ks) {
    const Real z(pow(bin50(10), -k));
    if (k >= first && z > 0) {
      zs.push_back(z);
    }
  }
  zs.push_back(tiniest);
  return zs;
}

// The two regions: z² in the type's normal range, and z² below it (z = 0 included).
template <SupportedReal Real>
std::string_view vanishing_region(const Real& z) {
  const bin50 wide(z);
  return wide * wide >= bin50(std::numeric_limits<Real>::min()) ? "z^2 normal" : "z^2 underflows";
}

// |got − want| in ε of max(|want|, min): relative for a normal value, in ulps of a subnormal's
// spacing below (E_load ≈ KE0 π z is subnormal when z is).
template <SupportedReal Real>
void record_vanishing(EpsilonErrors<Real>& errors, std::string_view region,
                      const std::string& observable, const std::optional<Real>& got,
                      const bin50& want, const std::string& row) {
  using std::abs;
  ASSERT_TRUE(got.has_value()) << observable << " at " << row;
  if (boost::multiprecision::isinf(want)) { // τ and ln e at α_eff = 1
    errors.record_error(region, observable, *got == Real(want) ? 0 : INFINITY, row);
    return;
  }
  const bin50 floor(std::numeric_limits<Real>::min());
  const bin50 scale = abs(want) > floor ? bin50(abs(want)) : floor;
  const bin50 error = abs(bin50(*got) - want) / scale;
  errors.record_error(
      region, observable,
      boost::math::isnan(*got) ? INFINITY : static_cast<double>(error) / eps<Real>(), row);
}

std::string vanishing_row(double p, const bin50& z) {
  return "p=" + to_string_full(p) + " alpha_eff=" + z.str(6, std::ios_base::scientific);
}

// The errors expected over the scan, in ε of each type: twice the measured max and RMS, rounded
// up (measured in the comments; `observables_test --gtest_filter='*VanishingDamping*'` prints
// them). Before z² was kept out of G and the normal force's peak, "z^2 underflows" measured
// 4.5e15 ε in double (E_load, F_max and t_F were 0), 9.2e18 in long double, 5.2e33 in float128
// and 1.9e50 in 50 digits; before A^p was formed directly, F_max at p = 10 measured 6.5 ε in
// float128; before lgamma took 100 digits, t_c in 50 digits measured 11.5 ε at p = 1.
constexpr ExpectedEpsilon vanishing_errors[] = {
    {"double", "z^2 normal", "*", 4, 2},     // measured 1.77, 0.726
    {"double", "z^2 underflows", "*", 3, 2}, // measured 1.17, 0.707
    {"long", "z^2 normal", "*", 5, 2},       // measured 2.47, 0.93
    {"long", "z^2 underflows", "*", 4, 2},   // measured 1.83, 1
    {"quad", "z^2 normal", "*", 5, 2},       // measured 2.35, 0.855
    {"quad", "z^2 underflows", "*", 4, 2},   // measured 1.79, 0.94
    {"50", "z^2 normal", "*", 8, 6},         // measured 3.82, 2.91 (t_c: quadrature against τ0)
    {"50", "z^2 underflows", "*", 8, 6},     // measured 3.79, 2.85
};

TYPED_TEST(VanishingDampingTest, EveryObservableMatchesFiftyDigitsDownToTheSmallestAlphaEff) {
  using Real = TypeParam;
  EpsilonErrors<Real> errors;
  for (double p : vanishing_ps) {
    std::vector<Real> zs = vanishing_dampings<Real>(0);
    zs.push_back(Real(0));
    for (const Real& z : zs) {
      const auto got =
          pldamp::testing::as_map(observables(Contact<Real>::from_alpha_eff(Real(p), z, Real(1))));
      const auto want = pldamp::testing::as_map(
          observables(Contact<bin50>::from_alpha_eff(bin50(p), bin50(z), bin50(1))));
      const std::string row = vanishing_row(p, bin50(z));
      for (const auto& [name, value] : want) {
        record_vanishing(errors, vanishing_region(z), name, got.at(name), *value, row);
      }
    }
  }
  errors.check(vanishing_errors);
}

// 50 digits below α_eff = 1e−60, where z·(anything of size 1) is below its ε: every observable is
// its undamped value but the three that vanish with z, ln e = −π z and E_load = E_unload =
// KE0 π z (relative errors O(z)), and t_c, which the cut's distance to the end, 2z, moves by
// T (2z)^q/q, far more than z (MATH.md §3, "Vanishing damping"; §4).
TEST(VanishingDampingFiftyDigits, EveryObservableMatchesItsSmallDampingLimit) {
  using boost::math::constants::pi;
  EpsilonErrors<bin50> errors;
  for (double p : vanishing_ps) {
    const Contact<bin50> undamped = Contact<bin50>::from_alpha_eff(bin50(p), bin50(0), bin50(1));
    const auto limit = pldamp::testing::as_map(observables(undamped));
    const bin50 q = undamped.q();
    const bin50 time_scale = exp(log_time_scale(undamped));
    std::vector<bin50> zs = vanishing_dampings<bin50>(61);
    zs.push_back(bin50(0));
    for (const bin50& z : zs) {
      const Contact<bin50> c = Contact<bin50>::from_alpha_eff(bin50(p), z, bin50(1));
      std::map<std::string, bin50> want;
      for (const auto& [name, value] : limit) {
        want[name] = *value;
      }
      want["log_e"] = -pi<bin50>() * z;
      want["energy_load"] = c.ke0() * pi<bin50>() * z;
      want["energy_unload"] = c.ke0() * pi<bin50>() * z;
      want["t_cut"] = *limit.at("tau") - time_scale * pow(2 * z, q) / q;
      const auto got = pldamp::testing::as_map(observables(c));
      const std::string row = vanishing_row(p, z);
      for (const auto& [name, value] : want) {
        record_vanishing(errors, vanishing_region(z), name, got.at(name), value, row);
      }
    }
  }
  errors.check(vanishing_errors);
}

} // namespace
} // namespace pldamp::analytic
