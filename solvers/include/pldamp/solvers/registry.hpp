// The solver registry: names (the CLI's `--solver` and the scenes' `name`) mapped to integrators
// of the physical equation, all behind Problem / Options / Result (problem.hpp), and to their
// traits. Code above solvers/ asks the traits (SolverInfo), never a name.
#pragma once

#include "pldamp/solvers/problem.hpp"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::solvers {

// What a solver runs at when it is given no rtol.
enum class DefaultTolerance {
  standard, // standard_rtol (1e-8)
  epsilon,  // the epsilon of the precision it runs in: a reference, as exact as its type allows
};

struct SolverInfo {
  std::string_view name;
  std::string_view method; // one line, for help and docs
  // A fixed-step scheme: it steps a fixed Δt (Options::fixed_step, or one from
  // steps_per_contact) and takes no tolerance. Otherwise the error is controlled by rtol.
  bool fixed_step;
  // Beside rtol, an absolute tolerance (false: the error is controlled relative to each state).
  bool takes_atol;
  // An error-controlled solver that can also run at a fixed step Options::fixed_step without
  // error control (for convergence-order tests).
  bool takes_fixed_step;
  DefaultTolerance default_tolerance;
  // The precisions it runs in (derived from the entry points it is registered with).
  PrecisionSet precisions = 0;
  // solve_batch steps several contacts of it together (SIMD lanes); otherwise one by one.
  bool batched = false;

  bool takes_rtol() const { return !fixed_step; }
  bool runs_in(std::string_view precision) const {
    return (precisions & precision_bit(precision)) != 0;
  }
  // The rtol it runs at when none is given, in the precision it runs in.
  template <SupportedReal Real>
  Real default_rtol() const {
    return default_tolerance == DefaultTolerance::epsilon ? std::numeric_limits<Real>::epsilon()
                                                          : standard_rtol<Real>();
  }
};

// Every registered solver, in a stable order.
std::span<const SolverInfo> registry();

// The registered solver of that name, or nullptr.
const SolverInfo* find_solver(std::string_view name);

// The registered solver of that name; throws std::invalid_argument "unknown solver, expected
// cvode-bdf|...|verlet (got NAME)" otherwise.
const SolverInfo& solver_named(std::string_view name);

// "cvode-bdf|cvode-adams|...", for messages and help; with a predicate, the names it accepts.
std::string solver_names();
template <class Predicate>
std::string solver_names(Predicate&& accept) {
  std::string names;
  for (const SolverInfo& info : registry()) {
    if (accept(info)) {
      names += names.empty() ? "" : "|";
      names += info.name;
    }
  }
  return names;
}

// Why a solver refuses a precision: "solver cvode-bdf runs in double precision only; taylor runs
// in any (got <got>)".
std::string precision_refusal(const SolverInfo& info, const std::string& got);

// Throws std::invalid_argument unless the named solver runs in Real and takes the options given:
// no atol for a solver controlled relative to each state, no fixed step for one without a
// fixed-step mode.
template <SupportedReal Real>
void check_solver_options(const SolverInfo& info, const Options<Real>& options);

// Integrates `problem` with the named solver in precision Real (instantiated for every
// SupportedReal). Throws std::invalid_argument for an unknown name, a precision the solver does
// not run in, an option it does not take, or an invalid problem or options; std::runtime_error
// when the integrator itself fails.
template <SupportedReal Real>
Result<Real> solve(std::string_view name, const Problem<Real>& problem,
                   const Options<Real>& options);

// Integrates problems[i] with options[i] for every i with the named solver in double; the
// Result of each is bit for bit what solve() returns for it, but for wall_seconds: a batched
// solver (SolverInfo::batched: the DEM schemes and verlet-predicted) steps the contacts together,
// and each Result's wall_seconds is then the batch's divided among its lanes. Lanes are stepped
// together when they share p and the damping exponent and ask for no samples (the onset phases of
// one cell, or cells of one p); any other lane is solved alone. Throws as solve() does, for the
// first lane that would throw.
std::vector<Result<double>> solve_batch(std::string_view name,
                                        std::span<const Problem<double>> problems,
                                        std::span<const Options<double>> options);

} // namespace pldamp::solvers
