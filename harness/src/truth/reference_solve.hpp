// The truth where no closed form exists (MATH.md §12.2): a contact whose dashpot is δ^β δ' with
// β ≠ (p−1)/2 is solved by taylor in Exact (float128) at its epsilon, once per (p, β, α_eff) at
// v0 = m = k = 1, and scaled to every cell like the closed forms (MATH.md §7, §12.1): in the units
// δ_u, δ_u/v0, ½mv0² the contact depends on p, β and the group
//     α_eff = α δ_u^(β − (p−1)/2) / √(2(p+1))
// alone, which is α_eff of MATH.md §1 for the seed's β (and then free of v0).
//
// taylor is independent of the closed forms (solvers/ never uses the map) and, given the seed's β
// explicitly, reproduces them within 5e-33 (tests/solvers/damping_exponent_test.cpp). Each truth
// also carries its own error estimate: the same solve in cpp_bin_float_50 against it.
#pragma once

#include "truth/plan.hpp"

#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <vector>

namespace pldamp::harness {

// δ_u at v0 = m = k = 1: ((p+1)/2)^(1/(p+1)).
Exact unit_overlap(double p);

// The group of a contact (above): α δ_u^(β − (p−1)/2) / √(2(p+1)).
Exact group_of(double p, double beta, const Exact& alpha, const Exact& delta_u);

// The α that has α_eff `group` at the overlap scale δ_u.
Exact alpha_of(double p, double beta, const Exact& group, const Exact& delta_u);

// taylor in Exact at its epsilon for (p, β, α_eff) at v0 = m = k = 1, every observable, the
// horizon 10⁴ δ_u/v0 (ten times the solvers' default, so that a solver's no_exit is judged against
// a truth that looked further). Computed once per process and key; thread-safe.
const solvers::Result<Exact>& reference_solve(double p, double beta, const Exact& group,
                                              solvers::End end);

// The group whose restitution (at `end`) is `e`, by TOMS 748 on reference_solve; none when no
// group gives it (e.g. e below what a dashpot that never lets go allows).
std::optional<Exact> group_for_e(double p, double beta, double e, solvers::End end);

// Per observable (plan order): |float128 − 50 digits| / |50 digits| of the reference solve.
std::vector<std::optional<double>>
truth_error_estimate(const std::vector<const Observable*>& observables, double p, double beta,
                     const Exact& group, solvers::End end);

} // namespace pldamp::harness
