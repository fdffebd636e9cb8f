#include "judge/budget.hpp"

#include "judge/claims.hpp"

#include "pldamp/analytic/conventions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace pldamp::harness {
namespace {

void raise(std::optional<double>& slot, const std::optional<double>& value) {
  if (value && (!slot || *value > *slot || std::isnan(*value))) {
    slot = std::isnan(*value) ? std::numeric_limits<double>::infinity() : *value;
  }
}

// The claim's measurement over its cells' errors (`where` names each cell): the largest, or the
// quantile it asks for (nearest rank), and the cell it comes from; then what its cells without a
// value make of it.
void conclude_errors(Judgement& j, const ErrorBound& bound, bool allow_missing,
                     const std::vector<double>& errors, const std::vector<std::string>& where) {
  j.measured = std::numeric_limits<double>::infinity();
  if (!errors.empty()) {
    const std::size_t at = nearest_rank(errors, bound.quantile);
    if (!std::isnan(errors[at])) {
      j.measured = errors[at];
    }
    j.worst = where[at];
  }
  j.holds = j.measured <= bound.bound;
  if (j.measured > 0 && std::isfinite(j.measured)) {
    j.margin = bound.bound / j.measured;
  }
  conclude_without_value(j, allow_missing);
}

// A DEM code's calibration, by the closed forms: |e it gives − target| (relative: over the
// target) over the grid's targets (and the p it has a model for).
Judgement judge_convention(const ConventionClaim& claim, const ClaimGrid& grid) {
  const analytic::Convention& convention = *analytic::find_convention(claim.convention);
  Judgement j;
  j.grid = grid_text(grid);
  const bool cut = analytic::capped(convention, claim.limit_damping);
  std::vector<double> errors;
  std::vector<std::string> where;
  for (const double p : grid.p) {
    for (const Damping& damping : grid.damping) {
      const bool model = (convention.linear && p == 1) || (convention.hertz && p == 1.5);
      if (!model || damping.kind != Damping::Kind::e) {
        continue;
      }
      const Exact target(damping.value);
      const Exact given =
          analytic::e_given(Exact(p), analytic::alpha_set(convention, Exact(p), target), cut);
      const Exact error = abs(given - target);
      errors.push_back(static_cast<double>(claim.error.relative ? error / target : error));
      where.push_back(fmt::format("p = {:g}, {}", p, damping_text(damping)));
    }
  }
  j.cells = static_cast<long>(errors.size());
  conclude_errors(j, claim.error, false, errors, where);
  return j;
}

// Why a record that did not fail gives a claim no value of an observable.
std::string why_no_value(const Plan& plan, const Record& record, std::size_t observable) {
  const std::string_view key = plan.observables[observable]->key;
  if (record.skipped()) {
    return "skipped: " + record.skip_reason;
  }
  if (!record.value[observable]) {
    return fmt::format("no {} in the answer ({})", key, record.outcome_name());
  }
  if (!record.reference[observable]) {
    const Point& point = plan.points[plan.cells[record.cell].point];
    return !point.no_truth.empty() ? "no truth: " + point.no_truth
           : !record.note.empty()  ? record.note
                                   : fmt::format("no reference {} at this contact end", key);
  }
  return fmt::format("{} unresolved: {} where the contact returns beyond the solver's horizon", key,
                     record.outcome_name());
}

// A bound on a configuration's error over a plan's records: every record of it is a cell of the
// claim, judged on its error, or without a value (failed, skipped, not measured, no truth).
Judgement judge_records(const Plan& plan, RecordRange records, const BoundClaim& claim) {
  Judgement j;
  j.grid = grid_text(scene_grid(plan.scene));
  const auto config = static_cast<std::size_t>(
      std::find(plan.configs.begin(), plan.configs.end(), claim.config) - plan.configs.begin());
  const auto observable = static_cast<std::size_t>(
      std::find_if(plan.observables.begin(), plan.observables.end(),
                   [&](const Observable* o) { return o->key == claim.observable; }) -
      plan.observables.begin());
  std::vector<double> errors;
  std::vector<std::string> where;
  for (const Record& record : records) {
    if (record.config != config) {
      continue;
    }
    ++j.cells;
    const std::string cell = cell_text(plan, plan.cells[record.cell]);
    const std::optional<double>& error =
        (claim.error.relative ? record.rel_error : record.abs_error)[observable];
    if (record.failed()) {
      add_without_value(j, cell,
                        std::string(record.outcome_name()) +
                            (record.failure.empty() ? "" : ": " + record.failure),
                        true);
    } else if (!error) {
      add_without_value(j, cell, why_no_value(plan, record, observable), false);
    }
    if (error) {
      errors.push_back(*error);
      where.push_back(cell);
    }
  }
  conclude_errors(j, claim.error, claim.allow_missing, errors, where);
  return j;
}

// A bound claim on a grid of its own: its configuration alone solved over the grid's cells (a
// plan of its own, as a search's), then judged on those records.
Judgement judge_own_grid(const Scene& scene, const BoundClaim& claim, const ClaimGrid& grid,
                         const Workers& workers) {
  Scene cells = with_cells(scene, grid);
  cells.damping = grid.damping;
  cells.configs = {claim.config};
  cells.claims.clear();
  cells.searches.clear();
  cells.figures.clear();
  cells.trajectories.clear();
  cells.repeats = 1;
  const Plan plan = make_plan(cells);
  RunTotals totals;
  const std::vector<Record> records = run_plan(plan, workers, totals);
  Judgement j = judge_records(plan, records, claim);
  j.grid = grid_text(grid);
  return j;
}

Verdict judge_bound(const Plan& plan, RecordRange records, const Claim& claim,
                    const Workers& workers) {
  Verdict verdict = verdict_of(claim);
  const ClaimGrid of_scene = scene_grid(plan.scene);
  const ConventionClaim* convention = std::get_if<ConventionClaim>(&claim.kind);
  const BoundClaim* bound = std::get_if<BoundClaim>(&claim.kind);
  const bool own_grid = convention ? convention->own_grid : bound->own_grid;
  const ClaimGrid& grid = own_grid ? claim.grid : of_scene;
  const auto judge_over = [&](const ClaimGrid& cells, bool the_plans) {
    return convention  ? judge_convention(*convention, cells)
           : the_plans ? judge_records(plan, records, *bound)
                       : judge_own_grid(plan.scene, *bound, cells, workers);
  };
  static_cast<Judgement&>(verdict) = judge_over(grid, !own_grid);
  if (verdict.measured > 0 && std::isfinite(verdict.measured)) {
    verdict.supported = std::pow(10.0, std::ceil(std::log10(verdict.measured)));
  }
  if (claim.denser) {
    verdict.denser = judge_over(denser_grid(grid), false);
  }
  return verdict;
}

} // namespace

void add_without_value(Judgement& j, const std::string& cell, const std::string& why, bool failed) {
  ++(failed ? j.failed_cells : j.missing_cells);
  constexpr std::size_t listed = 20;
  if (j.without_value.size() < listed) {
    j.without_value.push_back({cell, why, failed});
  }
}

void conclude_without_value(Judgement& j, bool allow_missing) {
  const auto first = [&](bool failed) {
    const auto found = std::find_if(j.without_value.begin(), j.without_value.end(),
                                    [&](const CellWithoutValue& c) { return c.failed == failed; });
    return found == j.without_value.end() ? std::string() : found->cell + ": " + found->why;
  };
  const auto add_note = [&](const std::string& text) {
    j.note += (j.note.empty() ? "" : "; ") + text;
  };
  if (j.failed_cells > 0) {
    j.holds = false;
    add_note(fmt::format("no answer at {} of {} cells (first: {})", j.failed_cells, j.cells,
                         first(true)));
  }
  if (j.missing_cells > 0) {
    j.holds = j.holds && allow_missing;
    add_note(fmt::format("no value at {} of {} cells{} (first: {})", j.missing_cells, j.cells,
                         allow_missing ? ", allowed (allow_missing): judged on the others" : "",
                         first(false)));
  }
}

std::string verdict_text(const Judgement& j) {
  if (j.partial()) {
    return fmt::format("holds on {} of {} cells", j.cells - j.missing_cells, j.cells);
  }
  const long without = j.failed_cells + j.missing_cells;
  if (!j.holds && without > 0) {
    return fmt::format("fails ({} of {} cells without a value)", without, j.cells);
  }
  return j.holds ? "holds" : "fails";
}

std::size_t nearest_rank(const std::vector<double>& values, double quantile) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto key = [&](std::size_t i) {
    return std::isnan(values[i]) ? std::numeric_limits<double>::infinity() : values[i];
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  const auto rank = static_cast<std::size_t>(std::ceil(quantile * double(values.size())));
  return order[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

std::string cell_text(const Plan& plan, const Cell& cell) {
  const Point& point = plan.points[cell.point];
  if (const MaterialContact* contact = contact_of(plan.scene, cell.m, cell.k)) {
    return fmt::format("{}, {}, v0 = {:g} m/s", contact->name, damping_text(point.damping),
                       cell.v0);
  }
  return fmt::format("p = {:g}, {}, v0 = {:g}, m = {:g}, k = {:g}", point.p,
                     damping_text(point.damping), cell.v0, cell.m, cell.k);
}

std::optional<double> largest(const std::vector<std::optional<double>>& values) {
  std::optional<double> out;
  for (const std::optional<double>& value : values) {
    raise(out, value);
  }
  return out;
}

double times_analytic(const std::vector<WorkPoint>& work) {
  double seconds = 0, analytic = 0;
  for (const WorkPoint& w : work) {
    seconds += w.seconds;
    analytic += w.analytic_seconds;
  }
  return analytic > 0 ? seconds / analytic : std::numeric_limits<double>::infinity();
}

std::optional<double> analytic_worst(const Point& point) {
  std::optional<double> out;
  for (const AnalyticCheck& check : point.analytic) {
    raise(out, check.error);
  }
  return out;
}

std::vector<std::string> not_representable(const Plan& plan, const Point& point) {
  std::vector<std::string> keys;
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    if (!point.analytic[o].representable) {
      keys.emplace_back(plan.observables[o]->key);
    }
  }
  return keys;
}

std::optional<double> worst_at(const Budgets& budgets, std::size_t config, std::size_t point) {
  std::optional<double> out;
  for (const auto& per_observable : budgets.map[config]) {
    raise(out, per_observable[point]);
  }
  return out;
}

std::vector<WorkPanel> work_panels(const Plan& plan) {
  const auto index_of = [&](std::string_view key) -> std::optional<std::size_t> {
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      if (plan.observables[o]->key == key) {
        return o;
      }
    }
    return std::nullopt;
  };
  std::vector<WorkPanel> panels;
  for (const std::string& key : plan.scene.work_precision) {
    const std::optional<std::size_t> observable = index_of(key);
    if (!observable && key != worst_of_all_key) { // load_scene refuses it first
      throw InputError("work_precision names an observable the scene does not want (got " + key +
                       ")");
    }
    panels.push_back({observable, key});
  }
  if (!panels.empty()) {
    return panels;
  }
  if (plan.observables.size() == 1) { // its own worst: the one series, by its name
    return {{0, std::string(plan.observables.front()->key)}};
  }
  if (const std::optional<std::size_t> e = index_of("e")) {
    panels.push_back({e, "e"});
  }
  panels.push_back({std::nullopt, std::string(worst_of_all_key)});
  return panels;
}

const WorkError& error_of(const WorkPoint& point, const WorkPanel& panel) {
  return panel.observable ? point.observables.at(*panel.observable) : point.worst_of_all;
}

bool last_of_its_solver(const Plan& plan, std::size_t config) {
  const std::size_t next = config + 1;
  return next == plan.configs.size() || plan.configs[next].line() != plan.configs[config].line();
}

Budgets make_budgets(const Plan& plan, RecordRange records, const Workers& workers) {
  Budgets budgets;
  const std::size_t configs = plan.configs.size(), observables = plan.observables.size();
  budgets.worst.assign(configs, std::vector<Worst>(observables));
  budgets.map.assign(configs,
                     std::vector<std::vector<std::optional<double>>>(
                         observables, std::vector<std::optional<double>>(plan.points.size())));
  // Work per configuration and p: sums, then means.
  const std::vector<double>& ps = plan.scene.p;
  std::vector<std::vector<long>> counts(configs, std::vector<long>(ps.size(), 0));
  budgets.work.assign(configs, std::vector<WorkPoint>(ps.size()));
  budgets.cost.assign(configs, Cost{});
  for (std::size_t c = 0; c < configs; ++c) {
    for (std::size_t i = 0; i < ps.size(); ++i) {
      budgets.work[c][i].p = ps[i];
      budgets.work[c][i].observables.resize(observables);
    }
  }
  for (const Record& record : records) {
    budgets.failed_records += record.failed() ? 1 : 0;
    const Cell& cell = plan.cells[record.cell];
    const double p = plan.points[cell.point].p;
    const auto p_index = static_cast<std::size_t>(std::find(ps.begin(), ps.end(), p) - ps.begin());
    WorkPoint& work = budgets.work[record.config][p_index];
    ++work.cells;
    bool any_error = false;
    for (std::size_t o = 0; o < observables; ++o) {
      const std::optional<double> error =
          record.skipped() || o >= record.rel_error.size() ? std::nullopt : record.rel_error[o];
      WorkError& of = work.observables[o];
      of.cells_without += error ? 0 : 1;
      raise(of.error, error);
      raise(work.worst_of_all.error, error);
      any_error = any_error || error.has_value();
    }
    work.worst_of_all.cells_without += any_error ? 0 : 1;
    if (record.skipped()) {
      ++work.skipped_cells;
      continue; // not run: no error, no cost
    }
    work.seconds += record.wall_seconds;
    work.analytic_seconds += plan.points[cell.point].analytic_seconds;
    work.rhs_evals += double(record.rhs_evals);
    ++counts[record.config][p_index];
    Cost& cost = budgets.cost[record.config];
    RegimeCost& regime = plan.points[cell.point].overdamped ? cost.overdamped : cost.underdamped;
    ++regime.cells;
    regime.rhs_evals += double(record.rhs_evals);
    regime.steps += double(record.steps);
    regime.seconds += record.wall_seconds;
    regime.seconds_slowest += record.wall_seconds_slowest;
    for (std::size_t o = 0; o < observables; ++o) {
      Worst& worst = budgets.worst[record.config][o];
      raise(worst.abs, record.abs_error[o]);
      const std::optional<double> before = worst.rel;
      raise(worst.rel, record.rel_error[o]);
      if (worst.rel != before || (worst.cell.empty() && worst.rel)) {
        worst.cell = cell_text(plan, cell);
      }
      raise(worst.spread, record.spread[o]);
      raise(budgets.map[record.config][o][cell.point], record.rel_error[o]);
    }
  }
  for (Cost& cost : budgets.cost) {
    for (RegimeCost* regime : {&cost.underdamped, &cost.overdamped}) {
      if (regime->cells > 0) {
        const double cells = double(regime->cells);
        regime->rhs_evals /= cells;
        regime->steps /= cells;
        regime->seconds /= cells;
        regime->seconds_slowest /= cells;
      }
    }
  }
  for (std::size_t c = 0; c < configs; ++c) {
    for (std::size_t i = 0; i < ps.size(); ++i) {
      if (counts[c][i] > 0) {
        budgets.work[c][i].seconds /= double(counts[c][i]);
        budgets.work[c][i].analytic_seconds /= double(counts[c][i]);
        budgets.work[c][i].rhs_evals /= double(counts[c][i]);
      }
    }
  }
  for (const Claim& claim : plan.scene.claims) {
    budgets.claims.push_back(claim.claim_kind() == ClaimKind::bound
                                 ? judge_bound(plan, records, claim, workers)
                                 : judge_on_grid(plan.scene, claim, workers));
  }
  for (const Search& search : plan.scene.searches) {
    budgets.searches.push_back(run_search(plan.scene, search, workers));
  }
  budgets.steps = make_step_study(plan, records, workers);
  return budgets;
}

} // namespace pldamp::harness
