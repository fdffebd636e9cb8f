// The parameter domain every layer accepts (docs/accuracy.md "Domain"): one definition, checked by
// the analytic contact, the solvers' Problem, the command line and the scenes alike. Outside it the
// answer is a refusal naming the range, never a computation that overflows, hangs or silently
// loses its digits:
// - p ≤ 1000: the Gauss–Jacobi rules of the time quadrature (weight exponent q − 1 = −(p−1)/(p+1))
//   fail to isolate their nodes as q → 0 (p = 1e18 aborted); at p = 1e4 double still agreed with
//   quad to 2e-13, and no contact law in use goes beyond p ~ 10.
// - m, k, v0 in [1e-30, 1e30]: every scale derived from them (δ_u, δ_u/v0, ½mv0², k δ_u^p) then
//   stays far inside double's range, in which the solvers compute (m = 1e300, k = 1e-300 made the
//   time scale 1e300 and CVODE crawl).
// - α_eff ≤ 1e6 (α ≤ 1e8 where α_eff is not formed, in the solvers): 1 − α_eff² stays finite, and
//   the overdamped peak (σ ~ ln(2z)/z) is still resolved by the quadrature's pieces (α = 1e300
//   made μ = −∞ and the piece width 0).
#pragma once

#include "pldamp/core/validate.hpp"

#include <cstdlib>
#include <string>
#include <type_traits>

namespace pldamp::domain {

inline constexpr double p_max = 1000;
inline constexpr double alpha_eff_max = 1e6;
inline constexpr double alpha_max = 1e8;

template <SupportedReal Real>
void require_p(const Real& p) {
  require_finite("p", p);
  require(p >= 1 && p <= Real(p_max), "p must be in [1, 1000]", p);
}

// The Real nearest the decimal `text`, as a user's "1e-30" is read in that precision: Real(1e-30)
// is the double nearest it, 8e−18 above the long double nearest, which refused --v0 1e-30 in
// every precision but double.
template <SupportedReal Real>
Real nearest_to_decimal(const char* text) {
  if constexpr (std::is_same_v<Real, double>) {
    return std::strtod(text, nullptr);
  } else if constexpr (std::is_floating_point_v<Real>) {
    return std::strtold(text, nullptr);
  } else {
    return Real(text);
  }
}

// m, k or v0.
template <SupportedReal Real>
void require_scale(const std::string& name, const Real& value) {
  static const Real least = nearest_to_decimal<Real>("1e-30"),
                    most = nearest_to_decimal<Real>("1e30");
  require_finite(name, value);
  require(
      value >= least && value <= most, [&] { return name + " must be in [1e-30, 1e30]"; }, value);
}

template <SupportedReal Real>
void require_alpha_eff(const Real& z) {
  require_finite("alpha_eff", z);
  require(z >= 0 && z <= Real(alpha_eff_max), "alpha_eff must be in [0, 1e6]", z);
}

template <SupportedReal Real>
void require_alpha(const Real& alpha) {
  require_finite("alpha", alpha);
  require(alpha >= 0 && alpha <= Real(alpha_max), "alpha must be in [0, 1e8]", alpha);
}

// β of the dashpot δ^β δ' (MATH.md §12), in [0, p]: β < 0 is a dashpot force that grows without
// bound as the overlap closes; β > p one that vanishes faster than the spring's, so that the force
// cut of a capped contact (k δ^(p−β) + c δ' = 0) has no meaning near δ = 0.
template <SupportedReal Real>
void require_damping_exponent(const Real& beta, const Real& p) {
  require_finite("damping exponent", beta);
  require(
      beta >= 0 && beta <= p,
      [&] { return "damping exponent must be in [0, p] = [0, " + to_string_full(p) + "]"; }, beta);
}

} // namespace pldamp::domain
