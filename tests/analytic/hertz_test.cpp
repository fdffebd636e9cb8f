// The Hertz contact from materials (MATH.md §13) in every precision: against mpmath at 60 digits
// (data/reference/hertz.py beside its hertz.csv, computed straight from Johnson 1985 §4.2, and the
// Rayleigh time of Li, Xu & Thornton 2005) and
// against hand-derived closed values for two equal spheres.
#include "analytic/reference.hpp"
#include "support.hpp"

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <random>
#include <string>

namespace pldamp::analytic {
namespace {

using pldamp::testing::CsvTable;
using pldamp::testing::eps;
using pldamp::testing::relative_error;

template <class Real>
class HertzTest : public ::testing::Test {};
TYPED_TEST_SUITE(HertzTest, pldamp::testing::AllReals);

// Each type starts from its own rounding of the decimal inputs: a few roundings apart at most
// (m carries R³, k a square root and the compliance sum).
TYPED_TEST(HertzTest, MatchesMpmathFromJohnson) {
  using Real = TypeParam;
  const CsvTable table(PLDAMP_DATA_DIR "/reference/hertz.csv");
  auto real = [&](const CsvTable::Row& row, const char* column) {
    return Real(bin50(table.cell(row, column)));
  };
  for (const CsvTable::Row& row : table.rows()) {
    const std::string where = "line " + std::to_string(row.line);
    const Sphere<Real> first{.radius = real(row, "R1"),
                             .young = real(row, "E1"),
                             .poisson = real(row, "nu1"),
                             .density = real(row, "rho1")};
    HertzContact<Real> h;
    if (table.cell(row, "geometry") == "sphere-sphere") {
      h = hertz_contact(first, Sphere<Real>{.radius = real(row, "R2"),
                                            .young = real(row, "E2"),
                                            .poisson = real(row, "nu2"),
                                            .density = real(row, "rho2")});
    } else {
      Wall<Real> wall;
      if (!table.cell(row, "E2").empty()) {
        wall = {.young = real(row, "E2"), .poisson = real(row, "nu2")};
      }
      h = hertz_contact(first, wall);
    }
    EXPECT_EQ(h.p, Real(3) / 2) << where;
    EXPECT_LE(relative_error(h.m, bin50(table.cell(row, "m"))), 8 * eps<Real>()) << where;
    EXPECT_LE(relative_error(h.radius, bin50(table.cell(row, "R_eff"))), 4 * eps<Real>()) << where;
    EXPECT_LE(relative_error(h.modulus, bin50(table.cell(row, "E_eff"))), 8 * eps<Real>()) << where;
    EXPECT_LE(relative_error(h.k, bin50(table.cell(row, "k"))), 12 * eps<Real>()) << where;
    EXPECT_LE(relative_error(rayleigh_time(first), bin50(table.cell(row, "t_rayleigh1"))),
              12 * eps<Real>())
        << where;
  }
  EXPECT_EQ(table.rows().size(), 4u);
}

// Narrower than float128, a contact is derived in float128 and rounded once (hertz.hpp), as the
// command line and a scene's [[contact]] derive it: each of m*, k, R*, E* is the 50-digit value
// rounded once, over random materials (a new user's own double derivation of k came one ulp off
// the command line's).
TYPED_TEST(HertzTest, NarrowerTypesRoundTheWideDerivationOnce) {
  using Real = TypeParam;
  if constexpr (std::numeric_limits<Real>::digits <
                std::numeric_limits<CalibrationReal<Real>>::digits) {
    std::mt19937_64 random(48);
    std::uniform_real_distribution<double> unit(0, 1);
    const auto sphere = [&] {
      return Sphere<Real>{.radius = Real(1e-4 * std::exp(6 * unit(random))),
                          .young = Real(1e7 * std::exp(11 * unit(random))),
                          .poisson = Real(-0.9 + 1.39 * unit(random)),
                          .density = Real(500 + 19000 * unit(random))};
    };
    const auto wide = [](const Sphere<Real>& s) {
      return Sphere<bin50>{bin50(s.radius), bin50(s.young), bin50(s.poisson), bin50(s.density)};
    };
    for (int i = 0; i < 2000; ++i) {
      const Sphere<Real> a = sphere(), b = sphere();
      const HertzContact<Real> narrow =
          i % 2 == 0 ? hertz_contact(a, b) : hertz_contact(a, Wall<Real>{b.young, b.poisson});
      const HertzContact<bin50> exact =
          i % 2 == 0 ? hertz_contact(wide(a), wide(b))
                     : hertz_contact(wide(a), Wall<bin50>{bin50(b.young), bin50(b.poisson)});
      ASSERT_EQ(narrow.m, static_cast<Real>(exact.m)) << i;
      ASSERT_EQ(narrow.k, static_cast<Real>(exact.k)) << i;
      ASSERT_EQ(narrow.radius, static_cast<Real>(exact.radius)) << i;
      ASSERT_EQ(narrow.modulus, static_cast<Real>(exact.modulus)) << i;
    }
  }
}

// Two equal spheres (R = 1/100, E = 7e10, ν = 3/10, ρ = 2700) by hand: m_i = 4/3 π 10⁻⁶ 2700 =
// 9π/2500, m* = m_i/2 = 9π/5000; R* = R/2 = 1/200; E* = E/(2 (1 − ν²)) = 7e10/1.82;
// k = 4/3 E* √(1/200).
TYPED_TEST(HertzTest, EqualSpheresByHand) {
  using Real = TypeParam;
  const Sphere<Real> aluminium{.radius = Real(1) / 100,
                               .young = Real(70000000000),
                               .poisson = Real(3) / 10,
                               .density = Real(2700)};
  const HertzContact<Real> h = hertz_contact(aluminium, aluminium);
  using std::sqrt;
  const bin50 pi = boost::math::constants::pi<bin50>();
  const bin50 modulus = bin50(70000000000) / (bin50(182) / 100);
  EXPECT_LE(relative_error(h.m, 9 * pi / 5000), 8 * eps<Real>());
  EXPECT_LE(relative_error(h.radius, bin50(1) / 200), 2 * eps<Real>());
  EXPECT_LE(relative_error(h.modulus, modulus), 8 * eps<Real>());
  EXPECT_LE(relative_error(h.k, bin50(4) / 3 * modulus * sqrt(bin50(1) / 200)), 12 * eps<Real>());
  // A sphere on a rigid wall: the sphere's own mass and radius, its own compliance only.
  const HertzContact<Real> on_rigid = hertz_contact(aluminium, Wall<Real>{});
  // (the mass formed as a contact's is: in float128 for a narrower type, rounded once)
  using Wide = CalibrationReal<Real>;
  EXPECT_EQ(on_rigid.m, static_cast<Real>(sphere_mass(
                            Sphere<Wide>{Wide(aluminium.radius), Wide(aluminium.young),
                                         Wide(aluminium.poisson), Wide(aluminium.density)})));
  EXPECT_EQ(on_rigid.radius, aluminium.radius);
  EXPECT_LE(relative_error(on_rigid.modulus, 2 * modulus), 8 * eps<Real>());
}

} // namespace
} // namespace pldamp::analytic
