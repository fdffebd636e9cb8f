#include "judge/budget.hpp"

#include "judge/claims.hpp"

#include "pldamp/analytic/conventions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <thread>

namespace pldamp::harness {
namespace {

void raise(std::optional<double>& slot, const std::optional<double>& value) {
  if (value && (!slot || *value > *slot || std::isnan(*value))) {
    slot = std::isnan(*value) ? std::numeric_limits<double>::infinity() : *value;
  }
}

void conclude(Verdict& verdict, const std::optional<double>& measured, const Scene& scene) {
  verdict.grid = grid_text(ClaimGrid{scene.p, scene.v0, scene.m, scene.k, scene.damping});
  verdict.measured = measured.value_or(std::numeric_limits<double>::infinity());
  verdict.holds = verdict.failed_cells == 0 && verdict.measured <= verdict.bound;
  if (verdict.measured > 0 && std::isfinite(verdict.measured)) {
    verdict.margin = verdict.bound / verdict.measured;
    verdict.supported = std::pow(10.0, std::ceil(std::log10(verdict.measured)));
  }
}

// The claim's measurement over its cells' errors (`where` names each cell): the largest, or the
// quantile it asks for (nearest rank), and the cell it comes from.
void conclude_errors(Verdict& verdict, const Claim& claim, const std::vector<double>& errors,
                     const std::vector<std::string>& where, const Scene& scene) {
  std::optional<double> measured;
  if (!errors.empty()) {
    const std::size_t at = nearest_rank(errors, claim.quantile);
    measured = std::isnan(errors[at]) ? std::numeric_limits<double>::infinity() : errors[at];
    verdict.worst = where[at];
  }
  conclude(verdict, measured, scene);
}

// A DEM code's calibration, by the closed forms: |e it gives − target| (relative: over the
// target) over the grid's targets (and the p it has a model for).
Verdict judge_convention(const Plan& plan, const Claim& claim) {
  const analytic::Convention& convention = *analytic::find_convention(*claim.convention);
  Verdict verdict = verdict_of(claim);
  const bool cut = analytic::capped(convention, claim.limit_damping);
  std::vector<double> errors;
  std::vector<std::string> where;
  for (const Point& point : plan.points) {
    const bool model = (convention.linear && point.p == 1) || (convention.hertz && point.p == 1.5);
    if (!model || point.damping.kind != Damping::Kind::e) {
      continue;
    }
    const Exact p(point.p), target(point.damping.value);
    const Exact given = analytic::e_given(p, analytic::alpha_set(convention, p, target), cut);
    const Exact error = abs(given - target);
    errors.push_back(static_cast<double>(claim.relative ? error / target : error));
    where.push_back(fmt::format("p = {:g}, {}", point.p, damping_text(point.damping)));
  }
  conclude_errors(verdict, claim, errors, where, plan.scene);
  return verdict;
}

Verdict judge(const Plan& plan, const std::vector<Record>& records, const Claim& claim) {
  if (claim.convention) {
    return judge_convention(plan, claim);
  }
  Verdict verdict = verdict_of(claim);
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
    if (record.failed()) {
      ++verdict.failed_cells;
    }
    const std::optional<double>& error =
        (claim.relative ? record.rel_error : record.abs_error)[observable];
    if (error) {
      errors.push_back(*error);
      where.push_back(cell_text(plan, plan.cells[record.cell]));
    }
  }
  conclude_errors(verdict, claim, errors, where, plan.scene);
  return verdict;
}

} // namespace

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

bool last_of_its_solver(const Plan& plan, std::size_t config) {
  const std::size_t next = config + 1;
  return next == plan.configs.size() || plan.configs[next].line() != plan.configs[config].line();
}

Budgets make_budgets(const Plan& plan, const std::vector<Record>& records) {
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
    }
  }
  for (const Record& record : records) {
    budgets.failed_records += record.failed() ? 1 : 0;
    if (record.skipped()) {
      continue; // not run: no error, no cost
    }
    const Cell& cell = plan.cells[record.cell];
    const double p = plan.points[cell.point].p;
    const auto p_index = static_cast<std::size_t>(std::find(ps.begin(), ps.end(), p) - ps.begin());
    WorkPoint& work = budgets.work[record.config][p_index];
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
      raise(work.error, record.rel_error[o]);
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
    budgets.claims.push_back(claim.kind == ClaimKind::bound ? judge(plan, records, claim)
                                                            : judge_on_grid(plan.scene, claim));
  }
  const int jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (const Search& search : plan.scene.searches) {
    budgets.searches.push_back(run_search(plan.scene, search, jobs));
  }
  budgets.steps = make_step_study(plan, records);
  return budgets;
}

} // namespace pldamp::harness
