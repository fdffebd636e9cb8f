// The plan of a scene: its cells (grid points), its solver configurations (the sweeps, plus any
// claim configuration not among them), the observables to compare, and the reference truth.
//
// Reference truth is the analytic layer in the Exact precision (float128; docs/design.md §3) or,
// for a damping exponent other than the seed's, taylor in Exact (reference_solve.hpp), computed
// once per (p, damping) at v0 = m = k = 1 and scaled to each cell by the observable's dimension:
// lengths by (m v0²/k)^(1/(p+1)), times by that over v0, energies by m v0² (MATH.md §7; e is
// scale-free). Only the wanted observables are computed, so no time quadrature runs unless t_peak
// or τ is wanted. The reference is built from α rounded to the precision the solver receives (the
// double solvers get α as a double), so that this rounding is not charged to them. The analytic
// layer's own budget (double against Exact) and its cost per cell are computed alongside, from the
// same (p, damping).
#pragma once

#include "common/observables.hpp"
#include "scene/scene.hpp"

#include "pldamp/analytic/contact.hpp"
#include "pldamp/core/real_types.hpp"

#include <array>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

// The precision of the truth and of every error computed against it: float128, or 50 digits in
// a build without it.
using Exact = NarrowestWithDigits10<30>;

struct Cell {
  std::size_t point; // index into Plan::points: its (p, damping)
  double v0, m, k;
  // α at this cell, in Exact: the point's for the seed's β; for another β the one that gives the
  // point's α_eff at this cell's δ_u (MATH.md §12.1).
  Exact alpha;
  // MATH.md §7, from the unit reference, per Dimension: 1, lengths × (m v0²/k)^(1/(p+1)), times
  // × that / v0, energies × m v0², forces × k (length)^p (computed once here, not per record).
  std::array<Exact, 5> scales;
  const Exact& scale(Dimension dimension) const {
    return scales[static_cast<std::size_t>(dimension)];
  }
};

// The analytic layer's own accuracy for one observable: its double value and relative error, or,
// where the exact value lies outside double's normal range (e ~ e^-2221, τ beyond 1.8e308 just
// below critical damping), not representable in double, and then the relative error of its
// logarithm where the observable has one (ln e, ln τ).
struct AnalyticCheck {
  std::optional<double> value, error;
  bool representable = true;
  std::optional<double> log_error;
};

// The reference values at one (p, damping), v0 = m = k = 1.
struct Point {
  double p;
  Damping damping;
  double alpha_eff; // the damping as α_eff (computed for a target e)
  Exact alpha;      // calibrated in Exact
  bool overdamped;  // α_eff ≥ 1: no return
  // ln τ at the overlap end (+∞ when overdamped): a solver's no_exit is an answer only where the
  // contact returns after its horizon (the force end's cut comes no later than this).
  Exact log_duration;
  // Per α precision (alpha_precision) and contact end: the observables in plan order, in Exact.
  std::map<std::pair<std::string, solvers::End>, std::vector<std::optional<Exact>>> reference;
  // The analytic layer in double against Exact, per observable (plan order).
  std::vector<AnalyticCheck> analytic;
  // What the closed forms cost in double for the observables wanted, per cell (contact and
  // bundle): the yardstick for the solvers' cost (a solver's "× analytic"). 0 where there are none.
  double analytic_seconds = 0;
  // β when the scene states one (damping_exponent); none: the seed's (p − 1)/2.
  std::optional<double> beta;
  // The truth is a reference solve (β ≠ (p − 1)/2, reference_solve.hpp), not the closed forms:
  // α_eff is the group of MATH.md §12.1, `alpha` its value at v0 = m = k = 1, and truth_error
  // the truth's own error estimate per observable (plan order, the scene's end): a second
  // float128 solve at another order against it (truth_error_estimate).
  bool solved = false;
  std::vector<std::optional<double>> truth_error;
  // Why the point has no truth (the reference solve failed, or no α_eff gives the target e).
  std::string no_truth;
  // A solved point's α_eff in Exact (alpha_eff is its double, for display): every cell's α and
  // every truth are formed from this one, not from its rounding.
  Exact group = 0;
};

struct Plan {
  Scene scene;
  std::vector<const Observable*> observables; // compared, in table order
  std::vector<Point> points;
  std::vector<Cell> cells;
  std::vector<SolverConfig> configs; // the scene's, then claim-only ones
  std::vector<solvers::End> ends;    // the contact ends the configurations run under
};

// How make_plan computes its `count` points, point_at(i) each, returned in index order: by
// default on make_plan's `jobs` threads; a run on MPI ranks computes a share on each rank and
// exchanges them (points_on_ranks, pldamp/harness/distribution.hpp), every truth once in the run.
using PointMap = std::function<std::vector<Point>(
    std::size_t count, const std::function<Point(std::size_t)>& point_at)>;

// The plan's configurations: the scene's, then each bound claim's own that the scene lacks, once.
std::vector<SolverConfig> plan_configs(const Scene& scene);

// Expands the scene and computes the references (Exact work, once per point), the points on
// `jobs` threads or by `map_points`: the same plan for any jobs and any map.
Plan make_plan(const Scene& scene, int jobs = 1, const PointMap& map_points = {});

// The Exact reference of an observable (its index in Plan::observables) at a cell, for a
// configuration (α as its precision receives it, its contact end).
std::optional<Exact> reference_at(const Plan& plan, const Cell& cell, std::size_t observable,
                                  const SolverConfig& config);

// The precision α is rounded to for a configuration: its own, or Exact's for a solver running
// wider than the truth (taylor in 50 digits gets the float128 α).
std::string alpha_precision(const SolverConfig& config);

// The seed's contact of a damping (a target e under `end`, α as the command line's --alpha, or
// α_eff) at p, calibrated in Exact at v0 = m = k = 1 (α is scale-free: MATH.md §7): every α of
// the plan comes from here.
analytic::Contact<Exact> seed_contact(const Exact& p, Damping::Kind kind, const Exact& value,
                                      analytic::ContactEnd end);

// α as a solver in Real receives it: the Exact α rounded once to Real (Real no wider than Exact),
// or, wider, exactly the Exact α (alpha_precision).
template <SupportedReal Real>
Real alpha_as_received(const Exact& alpha) {
  return static_cast<Real>(alpha);
}

// The α `pldamp calibrate` and `pldamp solve` use in Real for a target e (or an α_eff): the
// contact's own, calibrated in Exact (analytic::CalibrationReal) and rounded once, so that the
// library, `calibrate`, `solve` and `run` (seed_contact, rounded once) agree to the last bit. A
// Real wider than Exact calibrates in Real (a run gives such a solver the float128 α instead).
template <SupportedReal Real>
Real seed_alpha(const Real& p, Damping::Kind kind, const Real& value, analytic::ContactEnd end) {
  switch (kind) {
  case Damping::Kind::alpha:
    return value;
  case Damping::Kind::e:
    return analytic::Contact<Real>::from_e(p, value, Real(1), Real(1), Real(1), end).alpha();
  case Damping::Kind::alpha_eff:
    break;
  }
  return analytic::Contact<Real>::from_alpha_eff(p, value, Real(1)).alpha();
}

// α_eff as seed_alpha gives α: for a target e (or α) formed in Exact and rounded once to Real; a
// given α_eff as it is. A Real wider than Exact forms it in Real.
template <SupportedReal Real>
Real seed_alpha_eff(const Real& p, Damping::Kind kind, const Real& value,
                    analytic::ContactEnd end) {
  switch (kind) {
  case Damping::Kind::alpha_eff:
    return value;
  case Damping::Kind::e:
    return analytic::Contact<Real>::from_e(p, value, Real(1), Real(1), Real(1), end).alpha_eff();
  case Damping::Kind::alpha:
    break;
  }
  if constexpr (std::numeric_limits<Real>::digits > std::numeric_limits<Exact>::digits) {
    return analytic::Contact<Real>::from_alpha(p, value, Real(1)).alpha_eff();
  } else {
    return static_cast<Real>(seed_contact(Exact(p), kind, Exact(value), end).alpha_eff());
  }
}

} // namespace pldamp::harness
