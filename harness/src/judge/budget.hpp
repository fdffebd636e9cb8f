// Error budgets, work-precision points and claim verdicts from a run's records.
#pragma once

#include "judge/step_study.hpp"
#include "run/run.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct Worst {
  std::optional<double> abs, rel; // largest over the records (none: the observable never came)
  std::optional<double> spread;   // largest spread over onset phases (several phases run)
};

// What a solver configuration costs and achieves at one p: mean wall time and rhs_evals per
// cell, and the largest relative error of any observable in any cell.
struct WorkPoint {
  double p = 0, seconds = 0, rhs_evals = 0;
  double analytic_seconds = 0; // the closed forms' cost per cell in double, over the same cells
  std::optional<double> error;
};

// What a configuration costs as a multiple of the closed forms for the same cells and
// observables: the mean over p of its time per cell, over the same mean of the closed forms'.
double times_analytic(const std::vector<WorkPoint>& work);

struct Verdict {
  std::string name, observable, config;
  bool holds = false;
  double measured = 0, bound = 0;
  std::optional<double> margin;    // bound / measured
  std::optional<double> supported; // the tightest power of ten at or above the measurement
  long failed_cells = 0;           // cells where the claim's solver failed (the claim then fails)
};

struct Budgets {
  // worst[config][observable] over every cell.
  std::vector<std::vector<Worst>> worst;
  // map[config][observable][point]: the largest relative error over the cells of each
  // (p, damping) point (their v0, m, k).
  std::vector<std::vector<std::vector<std::optional<double>>>> map;
  // work[config]: one point per p, in the scene's order.
  std::vector<std::vector<WorkPoint>> work;
  std::vector<Verdict> claims;
  StepStudy steps; // the time-step study of fixed-step sweeps (empty without one)
  long failed_records = 0;
};

Budgets make_budgets(const Plan& plan, const std::vector<Record>& records);

// The largest of the values present (NaN counts as infinite); none if none is.
std::optional<double> largest(const std::vector<std::optional<double>>& values);
// The analytic layer's largest relative error in double at a point, over the observables
// representable in double (none: no such observable).
std::optional<double> analytic_worst(const Point& point);
// The keys of the observables not representable in double at a point (AnalyticCheck).
std::vector<std::string> not_representable(const Plan& plan, const Point& point);
// A configuration's largest relative error of any observable at one (p, damping) point.
std::optional<double> worst_at(const Budgets& budgets, std::size_t config, std::size_t point);
// Whether a configuration is the last (tightest) of its solver's sweep, the one the reports map.
bool last_of_its_solver(const Plan& plan, std::size_t config);

} // namespace pldamp::harness
