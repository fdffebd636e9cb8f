// The published approximations of the restitution of viscoelastic spheres (MATH.md §12.5), as
// functions of the group α_eff of MATH.md §12.1, so that the harness can measure them against the
// reference solve.
//
// The model (Brilliantov, Spahn, Hertzsch & Pöschel, PRE 53, 5382 (1996)):
//     m ξ'' + ρ (ξ^(3/2) + (3/2) A ξ^(1/2) ξ') = 0,   ρ = 2 Y √R_eff / (3 (1 − ν²)),
// pldamp's p = 3/2, β = 1/2 with k = ρ and α √(m k) = (3/2) A ρ. Its restitution depends on the
// impact speed v through one variable (Schwager & Pöschel's notation, PRE 78, 051304 (2008))
//     X = β_SP v^(1/5),   β_SP = (3/2) A (ρ/m)^(2/5),
// and with δ_u = ((5/4) m v²/ρ)^(2/5) the group α_eff = α δ_u^(1/4) / √5 is
//     α_eff = (3/2) A (ρ/m)^(2/5) v^(1/5) (5/4)^(1/10) / √5,   so   X = √5 (4/5)^(1/10) α_eff.
//
// Ramírez, Pöschel, Brilliantov & Schwager, PRE 60, 4465 (1999), derived the series
//     e = 1 − C1 X + C2 X² ∓ …,   C1 = √π Γ(3/5) / (2^(1/5) 5^(2/5) Γ(21/10)) = 1.15344…,
//                                 C2 = (3/5) C1² = 0.79826…,
// γ1 = C1 X / v^(1/5) and γ2 = C2 X² / v^(2/5) in their ε = 1 − γ1 v^(1/5) + γ2 v^(2/5). pldamp's
// reference solve reproduces C1 to 1e−12 and C2 to 1e−6 (tests/solvers/damping_exponent_test.cpp),
// which is what fixes the (3/2) in X: the series is of the dashpot
// (3/2) A ρ ξ^(1/2) ξ'.
#pragma once

#include "pldamp/core/real_types.hpp"
#include "pldamp/core/validate.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/gamma.hpp>

#include <array>
#include <cmath>
#include <string_view>

namespace pldamp::analytic {

// X of Schwager & Pöschel from the group α_eff: √5 (4/5)^(1/10) α_eff.
template <SupportedReal Real>
Real viscoelastic_variable(const Real& alpha_eff) {
  using std::pow;
  using std::sqrt;
  require_finite("alpha_eff", alpha_eff);
  require(alpha_eff >= 0, "alpha_eff must be >= 0", alpha_eff);
  return sqrt(Real(5)) * pow(Real(4) / 5, Real(1) / 10) * alpha_eff;
}

// C1 of Ramírez et al. (1999), in closed form.
template <SupportedReal Real>
Real ramirez_c1() {
  using boost::math::tgamma;
  using std::pow;
  using std::sqrt;
  const Real pi = boost::math::constants::pi<Real>();
  return sqrt(pi) * tgamma(Real(3) / 5) /
         (pow(Real(2), Real(1) / 5) * pow(Real(5), Real(2) / 5) * tgamma(Real(21) / 10));
}

// C2 = (3/5) C1² of Ramírez et al. (1999).
template <SupportedReal Real>
Real ramirez_c2() {
  const Real c1 = ramirez_c1<Real>();
  return Real(3) / 5 * c1 * c1;
}

// The 1999 series to first (1 − C1 X) or second order (+ C2 X²), the order published in closed
// form.
template <SupportedReal Real>
Real ramirez_1999_series(const Real& alpha_eff, int order) {
  require(order == 1 || order == 2, "the 1999 series has orders 1 and 2", Real(order));
  const Real x = viscoelastic_variable(alpha_eff);
  return order == 1 ? 1 - ramirez_c1<Real>() * x
                    : 1 - ramirez_c1<Real>() * x + ramirez_c2<Real>() * x * x;
}

// A published approximation of e(α_eff) for viscoelastic Hertz, for the report's table.
struct Approximation {
  std::string_view name, source;
  double (*e)(double alpha_eff);
};

inline const std::array<Approximation, 2> published_approximations{{
    {"Ramírez 1999, first order",
     "Ramírez, Pöschel, Brilliantov & Schwager, PRE 60, 4465 (1999): "
     "1 - C1 X",
     [](double z) { return ramirez_1999_series(z, 1); }},
    {"Ramírez 1999, second order",
     "Ramírez, Pöschel, Brilliantov & Schwager, PRE 60, 4465 (1999): 1 - C1 X + C2 X^2, "
     "C2 = 3/5 C1^2",
     [](double z) { return ramirez_1999_series(z, 2); }},
}};

} // namespace pldamp::analytic
