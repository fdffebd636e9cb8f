#include "pldamp/solvers/registry.hpp"

#include "methods.hpp"

#include <array>
#include <stdexcept>

namespace pldamp::solvers {
namespace {

using detail::ArkodeMethod;
using detail::CvodeMethod;
using detail::OdeintMethod;

// A solver family's entry point with its method fixed.
template <auto solve_family, auto method>
Result<double> with_method(const Problem<double>& problem, const Options<double>& options) {
  return solve_family(method, problem, options);
}

struct Entry {
  SolverInfo info;
  Result<double> (*solve)(const Problem<double>&, const Options<double>&);
};

constexpr std::array entries{
    Entry{{"cvode-bdf", "SUNDIALS CVODE, BDF orders 1-5, Newton with analytic Jacobian", true},
          with_method<detail::solve_cvode, CvodeMethod::bdf>},
    Entry{{"cvode-adams", "SUNDIALS CVODE, Adams-Moulton orders 1-12, Newton", true},
          with_method<detail::solve_cvode, CvodeMethod::adams>},
    Entry{{"arkode-dp5", "SUNDIALS ARKODE ERKStep, Dormand-Prince 5(4) (ode45)", true},
          with_method<detail::solve_arkode, ArkodeMethod::dormand_prince_5>},
    Entry{{"arkode-erk8", "SUNDIALS ARKODE ERKStep, Fehlberg 8(7), FSAL-corrected table", true},
          with_method<detail::solve_arkode, ArkodeMethod::fehlberg_8>},
    Entry{{"arkode-dirk", "SUNDIALS ARKODE ARKStep, Kvaerno ESDIRK 7(4)5, Newton", true},
          with_method<detail::solve_arkode, ArkodeMethod::esdirk_5>},
    Entry{{"odeint-rkf78", "Boost.Odeint controlled Runge-Kutta-Fehlberg 7(8)", true},
          with_method<detail::solve_odeint, OdeintMethod::fehlberg_78>},
    Entry{{"odeint-bs", "Boost.Odeint Bulirsch-Stoer with dense output", true},
          with_method<detail::solve_odeint, OdeintMethod::bulirsch_stoer>},
    Entry{{"verlet", "velocity Verlet, fixed step, as DEM codes step a contact", false},
          detail::solve_verlet},
};

constexpr auto infos = [] {
  std::array<SolverInfo, entries.size()> out{};
  for (std::size_t i = 0; i < entries.size(); ++i) {
    out[i] = entries[i].info;
  }
  return out;
}();

} // namespace

std::span<const SolverInfo> registry() {
  return infos;
}

std::string solver_names() {
  std::string names;
  for (const SolverInfo& info : infos) {
    if (!names.empty()) {
      names += '|';
    }
    names += info.name;
  }
  return names;
}

Result<double> solve(std::string_view name, const Problem<double>& problem,
                     const Options<double>& options) {
  for (const Entry& entry : entries) {
    if (entry.info.name == name) {
      return entry.solve(problem, options);
    }
  }
  throw std::invalid_argument("unknown solver, expected " + solver_names() + " (got " +
                              std::string(name) + ")");
}

} // namespace pldamp::solvers
