// The solver registry: names (the CLI's `--solver` and the scenes' `name`) mapped to integrators
// of the physical equation, all behind Problem / Options / Result (problem.hpp).
#pragma once

#include "pldamp/solvers/problem.hpp"

#include <concepts>
#include <span>
#include <string>
#include <string_view>

namespace pldamp::solvers {

struct SolverInfo {
  std::string_view name;
  std::string_view method;
  bool adaptive;      // false: fixed step (rtol and atol are ignored)
  bool any_precision; // runs in every SupportedReal, not only double
};

// Every registered solver, in a stable order.
std::span<const SolverInfo> registry();

// The registered solver of that name, or nullptr.
const SolverInfo* find_solver(std::string_view name);

// "cvode-bdf|cvode-adams|...", for messages and help.
std::string solver_names();

// Integrates `problem` with the named solver. Throws std::invalid_argument for an unknown name or
// invalid problem/options, std::runtime_error when the integrator itself fails.
Result<double> solve(std::string_view name, const Problem<double>& problem,
                     const Options<double>& options);

// The same in another precision, for the solvers marked any_precision (taylor); any other name
// throws std::invalid_argument. Instantiated for long double, float128 and cpp_bin_float_50.
template <SupportedReal Real>
requires(!std::same_as<Real, double>) Result<Real> solve(std::string_view name,
                                                         const Problem<Real>& problem,
                                                         const Options<Real>& options);

} // namespace pldamp::solvers
