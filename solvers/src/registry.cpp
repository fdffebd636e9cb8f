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
    Entry{
        {"cvode-bdf", "SUNDIALS CVODE, BDF orders 1-5, Newton with analytic Jacobian", true, false},
        with_method<detail::solve_cvode, CvodeMethod::bdf>},
    Entry{{"cvode-adams", "SUNDIALS CVODE, Adams-Moulton orders 1-12, Newton", true, false},
          with_method<detail::solve_cvode, CvodeMethod::adams>},
    Entry{{"arkode-dp5", "SUNDIALS ARKODE ERKStep, Dormand-Prince 5(4) (ode45)", true, false},
          with_method<detail::solve_arkode, ArkodeMethod::dormand_prince_5>},
    Entry{{"arkode-erk8", "SUNDIALS ARKODE ERKStep, Fehlberg 8(7), FSAL-corrected table", true,
           false},
          with_method<detail::solve_arkode, ArkodeMethod::fehlberg_8>},
    Entry{{"arkode-dirk", "SUNDIALS ARKODE ARKStep, Kvaerno ESDIRK 7(4)5, Newton", true, false},
          with_method<detail::solve_arkode, ArkodeMethod::esdirk_5>},
    Entry{{"odeint-rkf78", "Boost.Odeint controlled Runge-Kutta-Fehlberg 7(8)", true, false},
          with_method<detail::solve_odeint, OdeintMethod::fehlberg_78>},
    Entry{{"odeint-bs", "Boost.Odeint Bulirsch-Stoer with dense output", true, false},
          with_method<detail::solve_odeint, OdeintMethod::bulirsch_stoer>},
    Entry{{"taylor",
           "adaptive Taylor series, order and step after Jorba-Zou, contact-point series at "
           "entry and exit; double, long, quad or 50 digits",
           true, true},
          detail::solve_taylor<double>},
    Entry{{"verlet", "velocity Verlet, fixed step, as DEM codes step a contact", false, false},
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

const SolverInfo* find_solver(std::string_view name) {
  for (const SolverInfo& info : infos) {
    if (info.name == name) {
      return &info;
    }
  }
  return nullptr;
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

namespace {

const Entry& entry_named(std::string_view name) {
  for (const Entry& entry : entries) {
    if (entry.info.name == name) {
      return entry;
    }
  }
  throw std::invalid_argument("unknown solver, expected " + solver_names() + " (got " +
                              std::string(name) + ")");
}

} // namespace

Result<double> solve(std::string_view name, const Problem<double>& problem,
                     const Options<double>& options) {
  return entry_named(name).solve(problem, options);
}

template <SupportedReal Real>
requires(!std::same_as<Real, double>) Result<Real> solve(std::string_view name,
                                                         const Problem<Real>& problem,
                                                         const Options<Real>& options) {
  if (!entry_named(name).info.any_precision) {
    throw std::invalid_argument("solver " + std::string(name) + " runs in double only (taylor " +
                                "runs in any precision); got " +
                                std::string(precision_name<Real>()));
  }
  return detail::solve_taylor(problem, options);
}

template Result<long double> solve(std::string_view, const Problem<long double>&,
                                   const Options<long double>&);
#if PLDAMP_WITH_QUAD
template Result<quad> solve(std::string_view, const Problem<quad>&, const Options<quad>&);
#endif
template Result<bin50> solve(std::string_view, const Problem<bin50>&, const Options<bin50>&);

} // namespace pldamp::solvers
