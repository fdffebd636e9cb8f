#include "pldamp/solvers/registry.hpp"

#include "methods.hpp"

#include <array>
#include <stdexcept>
#include <string>
#include <tuple>

namespace pldamp::solvers {
namespace {

using detail::ArkodeMethod;
using detail::CvodeMethod;
using detail::DemScheme;
using detail::OdeintMethod;

template <SupportedReal Real>
using SolveFn = Result<Real> (*)(const Problem<Real>&, const Options<Real>&);

// One entry point per precision; nullptr where the solver does not run.
template <class... Reals>
std::tuple<SolveFn<Reals>...> entry_points_of(RealList<Reals...>);
using EntryPoints = decltype(entry_points_of(Precisions{}));

// A solver family's double entry point with its method fixed.
template <auto solve_family, auto method>
Result<double> with_method(const Problem<double>& problem, const Options<double>& options) {
  return solve_family(method, problem, options);
}

using BatchFn = std::vector<Result<double>> (*)(std::span<const Problem<double>>,
                                                std::span<const Options<double>>);

// The DEM batch path with its scheme fixed.
template <DemScheme scheme>
std::vector<Result<double>> dem_batch(std::span<const Problem<double>> problems,
                                      std::span<const Options<double>> options) {
  return detail::solve_dem_batch(scheme, problems, options);
}

struct Entry {
  SolverInfo info;
  EntryPoints solve;
  BatchFn batch = nullptr; // several contacts stepped together (SolverInfo::batched)
};

// The entry point and the precision set are filled together, so the set says where it runs.
constexpr Entry in_double(SolverInfo info, SolveFn<double> solve) {
  Entry entry{info, {}};
  std::get<SolveFn<double>>(entry.solve) = solve;
  entry.info.precisions = precision_bit<double>();
  return entry;
}

// A solver solve_batch steps in lanes (the DEM schemes, dem_batch.cpp; verlet-predicted,
// verlet_batch.cpp).
constexpr Entry batched(Entry entry, BatchFn batch) {
  entry.info.batched = true;
  entry.batch = batch;
  return entry;
}

constexpr Entry taylor_in_every_precision(SolverInfo info) {
  Entry entry{info, {}};
  for_each_precision([&]<class Real>() {
    std::get<SolveFn<Real>>(entry.solve) = detail::solve_taylor<Real>;
    entry.info.precisions |= precision_bit<Real>();
  });
  return entry;
}

using enum DefaultTolerance;

// name, method, fixed_step, takes_atol, takes_fixed_step, default tolerance
constexpr std::array entries{
    in_double({"cvode-bdf", "SUNDIALS CVODE, BDF orders 1-5, Newton with analytic Jacobian", false,
               true, false, standard},
              with_method<detail::solve_cvode, CvodeMethod::bdf>),
    in_double({"cvode-adams", "SUNDIALS CVODE, Adams-Moulton orders 1-12, Newton", false, true,
               false, standard},
              with_method<detail::solve_cvode, CvodeMethod::adams>),
    in_double({"arkode-dp5", "SUNDIALS ARKODE ERKStep, Dormand-Prince 5(4) (ode45)", false, true,
               true, standard},
              with_method<detail::solve_arkode, ArkodeMethod::dormand_prince_5>),
    in_double({"arkode-erk8", "SUNDIALS ARKODE ERKStep, Fehlberg 8(7), FSAL-corrected table", false,
               true, true, standard},
              with_method<detail::solve_arkode, ArkodeMethod::fehlberg_8>),
    in_double({"arkode-dirk", "SUNDIALS ARKODE ARKStep, Kvaerno ESDIRK 7(4)5, Newton", false, true,
               true, standard},
              with_method<detail::solve_arkode, ArkodeMethod::esdirk_5>),
    in_double({"odeint-rkf78", "Boost.Odeint controlled Runge-Kutta-Fehlberg 7(8)", false, true,
               false, standard},
              with_method<detail::solve_odeint, OdeintMethod::fehlberg_78>),
    in_double({"odeint-bs", "Boost.Odeint Bulirsch-Stoer with dense output", false, true, false,
               standard},
              with_method<detail::solve_odeint, OdeintMethod::bulirsch_stoer>),
    taylor_in_every_precision({"taylor",
                               "adaptive Taylor series, order and step after Jorba-Zou, "
                               "contact-point series at entry and exit; double, long, quad or 50 "
                               "digits",
                               false, false, false, epsilon}),
    batched(in_double(
                {"verlet-predicted",
                 "velocity Verlet, the dashpot fed the predicted full-step velocity (second order; "
                 "no DEM code runs it)",
                 true, false, false, standard},
                detail::solve_verlet),
            detail::solve_verlet_batch),
    batched(in_double({"dem-verlet",
                       "velocity Verlet as LAMMPS, LIGGGHTS and MercuryDPM run it: the force from "
                       "x_{n+1} and v_{n+1/2}",
                       true, false, false, standard},
                      with_method<detail::solve_dem, DemScheme::verlet>),
            dem_batch<DemScheme::verlet>),
    batched(
        in_double({"dem-symplectic-euler",
                   "semi-implicit Euler as Project Chrono's SMC runs it: the force from (x_n, v_n)",
                   true, false, false, standard},
                  with_method<detail::solve_dem, DemScheme::symplectic_euler>),
        dem_batch<DemScheme::symplectic_euler>),
    batched(
        in_double({"dem-leapfrog",
                   "leapfrog as YADE's NewtonIntegrator runs it: the force from x_n and v_{n-1/2}",
                   true, false, false, standard},
                  with_method<detail::solve_dem, DemScheme::leapfrog>),
        dem_batch<DemScheme::leapfrog>),
};

constexpr auto infos = [] {
  std::array<SolverInfo, entries.size()> out{};
  for (std::size_t i = 0; i < entries.size(); ++i) {
    out[i] = entries[i].info;
  }
  return out;
}();

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

const SolverInfo& solver_named(std::string_view name) {
  return infos[static_cast<std::size_t>(&entry_named(name) - entries.data())];
}

std::string solver_names() {
  return solver_names([](const SolverInfo&) { return true; });
}

std::string precision_refusal(const SolverInfo& info, const std::string& got) {
  const std::string any =
      solver_names([](const SolverInfo& other) { return other.precisions == every_precision; });
  return "solver " + std::string(info.name) + " runs in " + precision_names(info.precisions) +
         " precision only" + (any.empty() ? "" : "; " + any + " runs in any") + " (got " + got +
         ")";
}

template <SupportedReal Real>
void check_solver_options(const SolverInfo& info, const Options<Real>& options) {
  const std::string name(info.name);
  if ((info.precisions & precision_bit<Real>()) == 0) {
    throw std::invalid_argument(precision_refusal(info, std::string(precision_name<Real>())));
  }
  if (options.atol && !info.takes_atol) {
    require(false,
            name + (info.fixed_step
                        ? " takes a fixed step and no atol"
                        : " controls its error relative to each state and takes no atol"),
            *options.atol);
  }
  if (options.fixed_step && !info.fixed_step && !info.takes_fixed_step) {
    require(false, name + " has no fixed-step mode and takes no dt", *options.fixed_step);
  }
  if (options.onset_phase != 0 && !info.fixed_step) {
    require(false, name + " controls its error and has no onset phase", options.onset_phase);
  }
}

template <SupportedReal Real>
Result<Real> solve(std::string_view name, const Problem<Real>& problem,
                   const Options<Real>& options) {
  const Entry& entry = entry_named(name);
  check_solver_options(entry.info, options);
  return std::get<SolveFn<Real>>(entry.solve)(problem, options);
}

std::vector<Result<double>> solve_batch(std::string_view name,
                                        std::span<const Problem<double>> problems,
                                        std::span<const Options<double>> options) {
  if (problems.size() != options.size()) {
    throw std::invalid_argument("solve_batch: " + std::to_string(problems.size()) +
                                " problems and " + std::to_string(options.size()) + " options");
  }
  const Entry& entry = entry_named(name);
  for (const Options<double>& lane : options) {
    check_solver_options(entry.info, lane);
  }
  if (entry.batch != nullptr && !problems.empty()) {
    return entry.batch(problems, options);
  }
  std::vector<Result<double>> results;
  results.reserve(problems.size());
  for (std::size_t i = 0; i < problems.size(); ++i) {
    results.push_back(std::get<SolveFn<double>>(entry.solve)(problems[i], options[i]));
  }
  return results;
}

#define PLDAMP_INSTANTIATE(Real, name)                                                             \
  template void check_solver_options(const SolverInfo&, const Options<Real>&);                     \
  template Result<Real> solve(std::string_view, const Problem<Real>&, const Options<Real>&);
PLDAMP_FOR_EACH_PRECISION(PLDAMP_INSTANTIATE)
#undef PLDAMP_INSTANTIATE

} // namespace pldamp::solvers
