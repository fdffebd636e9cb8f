// The solvers behind the registry (registry.cpp maps names to these).
#pragma once

#include "pldamp/solvers/problem.hpp"

#include <span>
#include <vector>

namespace pldamp::solvers::detail {

enum class CvodeMethod { bdf, adams };
enum class ArkodeMethod { dormand_prince_5, fehlberg_8, esdirk_5 };
enum class OdeintMethod { fehlberg_78, bulirsch_stoer };
// The stepping loops of DEM codes (dem.cpp): LAMMPS/LIGGGHTS/MercuryDPM, Chrono SMC, YADE.
enum class DemScheme { verlet, symplectic_euler, leapfrog };

Result<double> solve_cvode(CvodeMethod method, const Problem<double>& problem,
                           const Options<double>& options);
Result<double> solve_arkode(ArkodeMethod method, const Problem<double>& problem,
                            const Options<double>& options);
Result<double> solve_odeint(OdeintMethod method, const Problem<double>& problem,
                            const Options<double>& options);
Result<double> solve_verlet(const Problem<double>& problem, const Options<double>& options);
// solve_verlet for every problems[i] with options[i], stepped together (verlet_batch.cpp).
std::vector<Result<double>> solve_verlet_batch(std::span<const Problem<double>> problems,
                                               std::span<const Options<double>> options);
Result<double> solve_dem(DemScheme scheme, const Problem<double>& problem,
                         const Options<double>& options);
// solve_dem for every problems[i] with options[i], the lanes stepped together (dem_batch.cpp);
// each Result is bit for bit solve_dem's but for wall_seconds, the batch's divided among its lanes.
std::vector<Result<double>> solve_dem_batch(DemScheme scheme,
                                            std::span<const Problem<double>> problems,
                                            std::span<const Options<double>> options);
// Instantiated for every SupportedReal.
template <SupportedReal Real>
Result<Real> solve_taylor(const Problem<Real>& problem, const Options<Real>& options);

} // namespace pldamp::solvers::detail
