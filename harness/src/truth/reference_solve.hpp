// The truth where no closed form exists (MATH.md §12.2): a contact whose dashpot is δ^β δ' with
// β ≠ (p−1)/2 is solved by taylor at its epsilon, once per (p, β, α_eff) at v0 = m = k = 1, and
// scaled to every cell like the closed forms (MATH.md §7, §12.1): in the units δ_u, δ_u/v0,
// ½mv0² the contact depends on p, β and the group
//     α_eff = α δ_u^(β − (p−1)/2) / √(2(p+1))
// alone, which is α_eff of MATH.md §1 for the seed's β (and then free of v0).
//
// The solve runs in a truth type T: Exact (float128) for answers up to quad, cpp_bin_float_50 for
// answers in 50 digits (TruthFor), so that an input such as e = 0.3 keeps the digits of the
// precision it was given in on every path. taylor is independent of the closed forms (solvers/
// never uses the map) and, given the seed's β explicitly, reproduces them within 5e-33
// (tests/solvers/damping_exponent_test.cpp). Each float128 truth also carries its own error
// estimate, a second float128 solve made to err differently (truth_error_estimate).
#pragma once

#include "truth/plan.hpp"

#include "pldamp/solvers/problem.hpp"

#include <fmt/format.h>

#include <array>
#include <concepts>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace pldamp::harness {

// A type a reference solve runs in: Exact, or cpp_bin_float_50 where that is wider.
template <class T>
concept TruthReal = std::same_as<T, Exact> || std::same_as<T, bin50>;

// The truth type for an answer in Real: Exact, or Real itself where it is wider (50 digits).
template <SupportedReal Real>
using TruthFor =
    std::conditional_t<(std::numeric_limits<Real>::digits > std::numeric_limits<Exact>::digits),
                       Real, Exact>;

// δ_u at v0 = m = k = 1: ((p+1)/2)^(1/(p+1)).
template <TruthReal T>
T unit_overlap(const T& p);

// MATH.md §7 per Dimension at (p, v0, m, k): 1, the length (m v0²/k)^(1/(p+1)) (δ_u divided by
// its unit-scale value), that over v0, m v0², and k length^p (a force k δ^p).
template <TruthReal T>
std::array<T, 5> cell_scales(const T& p, const T& v0, const T& m, const T& k);

// The group of a contact (above): α δ_u^(β − (p−1)/2) / √(2(p+1)).
template <TruthReal T>
T group_of(const T& p, const T& beta, const T& alpha, const T& delta_u);

// The α that has α_eff `group` at the overlap scale δ_u.
template <TruthReal T>
T alpha_of(const T& p, const T& beta, const T& group, const T& delta_u);

// taylor in T at its epsilon for (p, β, α_eff) at v0 = m = k = 1, every observable, the horizon
// 10⁴ δ_u/v0 (ten times the solvers' default, so that a solver's no_exit is judged against a
// truth that looked further). Computed once per process and key; thread-safe.
template <TruthReal T>
const solvers::Result<T>& reference_solve(const T& p, const T& beta, const T& group,
                                          solvers::End end);

// reference_solve in Exact within `max_steps` steps (not kept: a solve cut short is no truth):
// for a question whose damping may be beyond what the solve resolves in reasonable work (an
// impact speed of 1e30 took 140 s to end at the default million steps).
solvers::Result<Exact> reference_solve_within(const Exact& p, const Exact& beta, const Exact& group,
                                              solvers::End end, long max_steps);

// How a reference solve that gave no answer ended, for a message: "ended step_limit (its budget
// ran out after N steps, before the contact ended)", or the invariant an unstable one broke.
template <class T>
std::string reference_failure(const solvers::Result<T>& truth) {
  return fmt::format("ended {} ({})", solvers::outcome_name(truth.outcome),
                     truth.invariant.empty()
                         ? fmt::format("its budget ran out after {} steps, before the contact "
                                       "ended",
                                       truth.steps)
                         : truth.invariant);
}

// The group whose restitution (at `end`) is `e`; none when no group gives it (e.g. e below what a
// dashpot that never lets go allows). In Exact by TOMS 748 on reference_solve, from a bracket
// about the group double solves find (MATH.md §12.2); in 50 digits by Newton steps from the Exact
// group (each a 50-digit solve, about a second; two or three).
template <TruthReal T>
std::optional<T> group_for_e(const T& p, const T& beta, const T& e, solvers::End end);

// A scene's exponents are doubles, held exactly in Exact.
inline Exact unit_overlap(double p) {
  return unit_overlap(Exact(p));
}
inline Exact group_of(double p, double beta, const Exact& alpha, const Exact& delta_u) {
  return group_of(Exact(p), Exact(beta), alpha, delta_u);
}
inline Exact alpha_of(double p, double beta, const Exact& group, const Exact& delta_u) {
  return alpha_of(Exact(p), Exact(beta), group, delta_u);
}
inline const solvers::Result<Exact>& reference_solve(double p, double beta, const Exact& group,
                                                     solvers::End end) {
  return reference_solve(Exact(p), Exact(beta), group, end);
}
inline std::optional<Exact> group_for_e(double p, double beta, double e, solvers::End end) {
  return group_for_e(Exact(p), Exact(beta), Exact(e), end);
}

// Per observable (in the order given), the reference solve's own error estimate (MATH.md §12.2):
// with A the truth and B a second solve at 16 ε (another order, other steps) with α 4 ulps off,
// (2 |A − B| + 4 ε |A|) / |A| (absolute where A = 0). Held against 50 digits and against
// independent mpmath values (tests/harness/reference_solve_test.cpp).
std::vector<std::optional<double>>
truth_error_estimate(const std::vector<const Observable*>& observables, const Exact& p,
                     const Exact& beta, const Exact& group, solvers::End end);
inline std::vector<std::optional<double>>
truth_error_estimate(const std::vector<const Observable*>& observables, double p, double beta,
                     const Exact& group, solvers::End end) {
  return truth_error_estimate(observables, Exact(p), Exact(beta), group, end);
}

} // namespace pldamp::harness
