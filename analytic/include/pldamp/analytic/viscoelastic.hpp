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
//
// Müller & Pöschel, PRE 84, 021302 (2011), resummed the complete series (all h_k of Schwager &
// Pöschel 2008) into a [3/6] Padé approximant in v* = √X, printed to six significant digits.
// That series is of the contact that ends when the force vanishes (Schwager & Pöschel's "delayed
// recovery"), not at ξ = 0: the two ends agree through X² and part at X^(5/2), and the Padé
// follows pldamp's force-end truth to 6e-8 at α_eff = 0.01 where it misses the overlap-end truth
// by 2e-5 (MATH.md §12.5). Each approximation therefore names the end it describes.
#pragma once

#include "pldamp/analytic/contact.hpp"
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

// The [3/6] Padé approximant of Müller & Pöschel (2011) in v* = √X: numerator and denominator
// coefficients, lowest power first, as published. The coefficients are built from integers so that
// the six published digits are the only rounding, in any precision (MATH.md §12.5).
template <SupportedReal Real>
std::array<Real, 4> muller_poschel_2011_numerator() {
  return {Real(1), Real(107232) / 100000, Real(574198) / 1000000, Real(141552) / 1000000};
}

template <SupportedReal Real>
std::array<Real, 7> muller_poschel_2011_denominator() {
  return {Real(1),
          Real(107232) / 100000,
          Real(172765) / 100000,
          Real(137842) / 100000,
          Real(119449) / 100000,
          Real(467273) / 1000000,
          Real(235585) / 1000000};
}

// e(α_eff) by the 2011 Padé: N(v*)/D(v*) with v* = √X, both by Horner.
template <SupportedReal Real>
Real muller_poschel_2011_pade(const Real& alpha_eff) {
  using std::sqrt;
  const Real v_star = sqrt(viscoelastic_variable(alpha_eff));
  auto horner = [&v_star](const auto& coefficients) {
    Real sum = 0;
    for (auto c = coefficients.rbegin(); c != coefficients.rend(); ++c) {
      sum = sum * v_star + *c;
    }
    return sum;
  };
  return horner(muller_poschel_2011_numerator<Real>()) /
         horner(muller_poschel_2011_denominator<Real>());
}

// A published approximation of e(α_eff) for viscoelastic Hertz, for the report's table, and the
// contact end its authors' e is defined at.
struct Approximation {
  std::string_view name, source;
  ContactEnd end;
  double (*e)(double alpha_eff);
};

inline const std::array<Approximation, 3> published_approximations{{
    {"Ramírez 1999, first order",
     "Ramírez, Pöschel, Brilliantov & Schwager, PRE 60, 4465 (1999): "
     "1 - C1 X",
     ContactEnd::overlap, [](double z) { return ramirez_1999_series(z, 1); }},
    {"Ramírez 1999, second order",
     "Ramírez, Pöschel, Brilliantov & Schwager, PRE 60, 4465 (1999): 1 - C1 X + C2 X^2, "
     "C2 = 3/5 C1^2",
     ContactEnd::overlap, [](double z) { return ramirez_1999_series(z, 2); }},
    {"Müller & Pöschel 2011, Padé [3/6]",
     "Müller & Pöschel, PRE 84, 021302 (2011): the [3/6] Padé approximant of the complete series "
     "in sqrt(X)",
     ContactEnd::force, [](double z) { return muller_poschel_2011_pade(z); }},
}};

} // namespace pldamp::analytic
