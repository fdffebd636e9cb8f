// Gauss–Jacobi rules for ∫_{−1}^{1} (1 + t)^β f(t) dt, β > −1, in any SupportedReal.
//
// The time integral t(s) = ∫ A q x^(q−1) ds has the endpoint weight s^(q−1) (MATH.md §3, §8): a
// Gauss–Jacobi rule carries that weight exactly, so the remaining factor is analytic and the rule
// converges geometrically (β = 0 gives Gauss–Legendre for the interior panels).
//
// Nodes: Newton on P_n^(0,β) from the three-term recurrence (A&S 22.7.1) and its derivative
// (A&S 22.8.1), started at the asymptotic zeros θ_i = π(i − ¼)/(n + (β+1)/2). Weights are
// ∝ 1/((1 − t²) P_n'(t)²) (A&S 25.4.33), normalised to the exact zeroth moment 2^(β+1)/(β+1).
// The recurrence loses up to ~80 ulps in the weights, so rules are built in a wider type
// (cpp_bin_float_50, or 100 digits for cpp_bin_float_50 itself) and rounded once. They are built
// once per (type, β, n) and cached per thread.
#pragma once

#include "pldamp/core/real_types.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace pldamp::analytic {

template <class Real> // a SupportedReal, or the wider type a rule is built in
struct JacobiRule {
  std::vector<Real> nodes;   // in (−1, 1), decreasing
  std::vector<Real> weights; // positive, Σ = 2^(β+1)/(β+1)
};

// Node count for the working precision. The rules are applied to pieces whose nearest
// singularity maps to a Bernstein ellipse of parameter ρ ≥ 4 (see time.hpp), where an n-point
// rule errs by about ρ^(−2n): n = digits·ln2/(2 ln 4) = digits/4, plus 2 for the constant.
template <SupportedReal Real>
constexpr int quadrature_order() {
  return std::numeric_limits<Real>::digits / 4 + 2;
}

// The same for a piece whose singularities lie beyond the ellipse ρ (MATH.md §3, "The time
// integral"): ρ^(−2n) ≤ 2^(−digits) for n = ⌈digits·ln2 / (2 ln ρ)⌉, plus 1. ρ is taken at most
// largest_ellipse: beyond it the entire factor e^(−νzσ), bounded on the interval but not on a
// wider ellipse, decides the count (on ρ = 8 it grows at most 13-fold over a piece with
// |ν|(1 + z)·width ≤ 1, which the added node covers: 8^(−2) = 1/64).
inline constexpr double largest_ellipse = 8;
template <SupportedReal Real>
int quadrature_order(double rho) {
  assert(rho > 1);
  const double digits = std::numeric_limits<Real>::digits;
  return static_cast<int>(std::ceil(digits * std::numbers::ln2 /
                                    (2 * std::log(std::min(rho, largest_ellipse))))) +
         1;
}

namespace detail {

// The type a rule for Real is built in: at least 50 digits, wider than Real.
template <SupportedReal Real>
using RuleBuildType = std::conditional_t<std::is_same_v<Real, bin50>,
                                         boost::multiprecision::cpp_bin_float_100, bin50>;

// P_n^(0,β)(t) and P_{n−1}^(0,β)(t).
template <class Real>
std::pair<Real, Real> jacobi_pair(int n, const Real& beta, const Real& t) {
  Real previous(1);
  Real current = ((beta + 2) * t - beta) / 2;
  for (int j = 2; j <= n; ++j) {
    const Real s = Real(2 * j) + beta;
    const Real next = ((s - 1) * (s * (s - 2) * t - beta * beta) * current -
                       2 * Real(j - 1) * (Real(j - 1) + beta) * s * previous) /
                      (2 * Real(j) * (Real(j) + beta) * (s - 2));
    previous = current;
    current = next;
  }
  return {current, previous};
}

// d/dt P_n from (2n+β)(1 − t²) P_n' = n[−β − (2n+β)t] P_n + 2n(n+β) P_{n−1}.
template <class Real>
Real jacobi_derivative(int n, const Real& beta, const Real& t, const Real& pn, const Real& pn1) {
  const Real s = Real(2 * n) + beta;
  return (Real(n) * (-beta - s * t) * pn + 2 * Real(n) * (Real(n) + beta) * pn1) /
         (s * (1 - t * t));
}

template <class Real>
JacobiRule<Real> build_jacobi_rule(int n, const Real& beta) {
  using std::abs;
  using std::cos;
  using std::pow;
  const Real pi = boost::math::constants::pi<Real>();
  const Real eps = std::numeric_limits<Real>::epsilon();
  JacobiRule<Real> rule;
  rule.nodes.resize(n);
  rule.weights.resize(n);
  Real sum(0);
  for (int i = 0; i < n; ++i) {
    Real t = cos(pi * (Real(i + 1) - Real(1) / 4) / (Real(n) + (beta + 1) / 2));
    Real derivative(0);
    for (int iteration = 0; iteration < 100; ++iteration) {
      const auto [pn, pn1] = jacobi_pair(n, beta, t);
      derivative = jacobi_derivative(n, beta, t, pn, pn1);
      const Real step = pn / derivative;
      t -= step;
      if (abs(step) <= 2 * eps) {
        break;
      }
    }
    const auto [pn, pn1] = jacobi_pair(n, beta, t);
    derivative = jacobi_derivative(n, beta, t, pn, pn1);
    rule.nodes[i] = t;
    rule.weights[i] = 1 / ((1 - t * t) * derivative * derivative);
    sum += rule.weights[i];
    if (!(abs(t) < 1) || (i > 0 && !(t < rule.nodes[i - 1]))) {
      throw std::logic_error("Gauss-Jacobi: Newton did not isolate the zeros");
    }
  }
  const Real moment0 = pow(Real(2), beta + 1) / (beta + 1);
  for (Real& w : rule.weights) {
    w *= moment0 / sum;
  }
  return rule;
}

} // namespace detail

// The n-point rule for weight (1 + t)^β, built on first use in this thread and kept.
template <SupportedReal Real>
const JacobiRule<Real>& jacobi_rule(const Real& beta, int n = quadrature_order<Real>()) {
  // The callers' weights: ν = q − 1 ∈ (−1, 0] with q = 2/(p+1), p ∈ [1, 1000], and 0.
  assert(n >= 1 && beta > -1 && beta <= 0);
  thread_local std::map<std::pair<int, Real>, JacobiRule<Real>> cache;
  const auto key = std::make_pair(n, beta);
  auto found = cache.find(key);
  if (found == cache.end()) {
    using Wide = detail::RuleBuildType<Real>;
    const JacobiRule<Wide> wide = detail::build_jacobi_rule(n, Wide(beta));
    JacobiRule<Real> rule;
    for (std::size_t i = 0; i < wide.nodes.size(); ++i) {
      rule.nodes.push_back(wide.nodes[i].template convert_to<Real>());
      rule.weights.push_back(wide.weights[i].template convert_to<Real>());
    }
    found = cache.emplace(key, std::move(rule)).first;
  }
  return found->second;
}

} // namespace pldamp::analytic
