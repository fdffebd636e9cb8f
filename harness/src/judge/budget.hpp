// Error budgets, work-precision points and claim verdicts from a run's records.
#pragma once

#include "common/parallel.hpp"
#include "judge/search.hpp"
#include "judge/step_study.hpp"
#include "run/record_store.hpp"
#include "run/run.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct Worst {
  std::optional<double> abs, rel; // largest over the records (none: the observable never came)
  std::optional<double> spread;   // largest spread over onset phases (several phases run)
  std::string cell;               // where the largest relative error is (cell_text)
};

// What a configuration costs per cell, underdamped and overdamped cells apart (an overdamped
// contact never returns: its solve runs to the horizon, a different amount of work).
struct RegimeCost {
  long cells = 0;
  double rhs_evals = 0, steps = 0; // per cell, deterministic
  // Per cell: the mean of each record's fastest repeat, and of its slowest (the spread).
  double seconds = 0, seconds_slowest = 0;
};
struct Cost {
  RegimeCost underdamped, overdamped;
};

// A work-precision point's error: the largest relative error over the cells that gave one, and
// how many cells gave none (failed, skipped, not measured, no truth): counted, never dropped.
struct WorkError {
  std::optional<double> error;
  long cells_without = 0;
};

// What a solver configuration costs and achieves at one p: mean wall time and rhs_evals per
// cell run, and per observable its largest relative error over the cells; and the worst of all
// observables (its cells_without: the cells without a value of any observable). One ill-
// conditioned observable (an energy by balance) dominates the worst of all: a user reads the
// observable they care about (issue 27, part 10).
struct WorkPoint {
  double p = 0, seconds = 0, rhs_evals = 0;
  double analytic_seconds = 0; // the closed forms' cost per cell in double, over the same cells
  long cells = 0;              // the configuration's records at this p, skipped ones included
  long skipped_cells = 0;      // not run: no cost, no error (counted in cells_without)
  std::vector<WorkError> observables; // Plan::observables' order
  WorkError worst_of_all;
};

// A series of the work-precision diagrams and table: one observable's errors, or the worst of
// all (`observable` none; its key worst_of_all_key).
struct WorkPanel {
  std::optional<std::size_t> observable; // into Plan::observables
  std::string key;
};
// The scene's [report] work_precision, in its order; by default e (when wanted) and the worst
// of all, or the one observable a scene wants alone.
std::vector<WorkPanel> work_panels(const Plan& plan);
const WorkError& error_of(const WorkPoint& point, const WorkPanel& panel);

// What a configuration costs as a multiple of the closed forms for the same cells and
// observables: the mean over p of its time per cell, over the same mean of the closed forms'.
double times_analytic(const std::vector<WorkPoint>& work);

// A cell of a claim that gave it no value, and why.
struct CellWithoutValue {
  std::string cell, why;
  bool failed = false; // the solve failed (else the value is missing: skipped, not measured)
};

// A claim judged over one grid. What `measured` and `margin` mean depends on the claim's kind
// (claims.hpp, verdict_of). A claim holds only on every cell it names
// (conclude_without_value).
struct Judgement {
  bool holds = false;
  double measured = 0;
  std::optional<double> margin;
  std::string worst;     // the cell where the claim comes closest to failing, or fails worst
  std::string grid;      // what it was judged over, "p in {1, 2} x e in [0.1, 0.99] (10): 20 cells"
  std::string note;      // what else the kind measured (ties, per-p orders, e at the Δt bound)
  long cells = 0;        // the cells it names
  long failed_cells = 0; // cells without an answer (the solver failed): the claim then fails
  // Cells without a value, not failed (a record skipped, a value the solver did not give, no
  // truth): the claim fails, unless it allows them (allow_missing) and then holds on the others.
  long missing_cells = 0;
  std::vector<CellWithoutValue> without_value; // the failed and missing cells (the first 20)
  // Holds on only some of its cells (the others without a value, as the claim allows).
  bool partial() const { return holds && missing_cells > 0; }
};

// A claim's cell without a value, counted in `j` (failed: the solve failed; else missing) and
// listed with why (the first 20).
void add_without_value(Judgement& j, const std::string& cell, const std::string& why, bool failed);

// What the cells without a value make of a judgement: a failed one fails it, a missing one too
// unless `allow_missing`; the note counts them and names the first.
void conclude_without_value(Judgement& j, bool allow_missing);

// "holds", "fails", "holds on 8 of 9 cells", "fails (1 of 9 cells without a value)".
std::string verdict_text(const Judgement& j);

// The order in α_eff at which an asymptotic claim's two sides agree, per p, and the coefficient
// of that leading term (|difference| ≈ coefficient · α_eff^round(order)).
struct MeasuredOrder {
  double p = 0;
  std::optional<double> order; // none: equal within the tolerance over the whole range
  double coefficient = 0;
};

struct Verdict : Judgement {
  std::string name, kind, observable, config, where, quote, figure;
  std::string meaning; // what measured and margin are for this kind (claims.hpp)
  bool expect_holds = true;
  bool allow_missing = false; // cells without a value allowed: "holds on M of N cells"
  // Whether a lower measurement is the worse one (an order, a gap, a ratio of steps), not a
  // higher one (an error): how `pldamp diff` reads a change of it.
  bool worse_when_lower = false;
  double bound = 0;
  std::optional<double> supported; // bound: the tightest power of ten at or above the measurement
  std::optional<Judgement> denser; // the same claim on a grid ten times denser
  std::vector<MeasuredOrder> orders;
  // A verdict other than the one expected (expect = "fails" pins a known-false claim), or one
  // that holds on only some of its cells: what `run --strict` exits 1 on.
  bool unexpected() const { return holds != expect_holds || partial(); }
};

struct Budgets {
  // worst[config][observable] over every cell.
  std::vector<std::vector<Worst>> worst;
  // map[config][observable][point]: the largest relative error over the cells of each
  // (p, damping) point (their v0, m, k).
  std::vector<std::vector<std::vector<std::optional<double>>>> map;
  // work[config]: one point per p, in the scene's order.
  std::vector<std::vector<WorkPoint>> work;
  std::vector<Cost> cost; // cost[config]
  std::vector<Verdict> claims;
  std::vector<SearchResult> searches;
  StepStudy steps; // the time-step study of fixed-step sweeps (empty without one)
  long failed_records = 0;
};

// The claims, searches and step study solve on the workers' threads (--jobs), and under MPI on
// every rank (run/workers.hpp): every rank calls it, rank 0 with the run's records, the others
// with none (their budgets are not the run's). Nothing in rank 0's budgets depends on the number
// of threads or ranks (common/parallel.hpp).
Budgets make_budgets(const Plan& plan, RecordRange records, const Workers& workers = all_cores());

// The index of the `quantile` of `values` by nearest rank (the ⌈q·n⌉-th smallest; NaN counts as
// the largest; q = 1: the largest). `values` must not be empty.
std::size_t nearest_rank(const std::vector<double>& values, double quantile);

// A cell as reports name it: "p = 1.5, e = 0.5, v0 = 1, m = 1, k = 1".
std::string cell_text(const Plan& plan, const Cell& cell);

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
