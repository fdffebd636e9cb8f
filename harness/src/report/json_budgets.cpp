// report.json's budgets and records (common/report_schema.hpp gives their layout and every key).
#include "report/sections.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string>
#include <utility>

namespace pldamp::harness {

using nlohmann::ordered_json;
using schema::number_or_null;
namespace key = schema::key;

namespace {

// A time for report.json: 4 significant digits, which the noise of timing never reaches (the
// full 17 of a mean over onset phases are bytes of nothing, in every record).
double timing(double seconds) {
  return std::isfinite(seconds) ? std::stod(fmt::format("{:.4g}", seconds)) : seconds;
}

// Per observable of the plan, a value each: {"e": ..., "tau": ...}.
ordered_json per_observable(const Plan& plan, const std::vector<std::optional<double>>& values) {
  ordered_json out;
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    out[plan.observables[o]->key] = number_or_null(values[o]);
  }
  return out;
}

ordered_json step_study_json(const Plan& plan, const StepStudy& study) {
  auto needed_json = [](const std::array<StepsNeeded, 3>& needed) {
    ordered_json out = ordered_json::array();
    for (std::size_t t = 0; t < step_targets.size(); ++t) {
      out.push_back({{key::target, step_targets[t]},
                     {key::steps_per_contact, number_or_null(needed[t].steps)},
                     {key::tau_over_dt, number_or_null(needed[t].tau_over_dt)},
                     {key::within_sweep, needed[t].within_sweep},
                     {key::returns, needed[t].returns},
                     {key::from_sweep, needed[t].from_sweep}});
    }
    return out;
  };
  ordered_json sweeps = ordered_json::array();
  for (const StepSweep& sweep : study.sweeps) {
    ordered_json per_p = ordered_json::array();
    for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
      ordered_json points;
      for (std::size_t o = 0; o < plan.observables.size(); ++o) {
        ordered_json xy = ordered_json::array();
        for (const StepPoint& point : sweep.points[o][i]) {
          xy.push_back({point.dt_over_tau, number_or_null(point.error)});
        }
        points[plan.observables[o]->key] = xy;
      }
      per_p.push_back({{key::p, plan.scene.p[i]},
                       {key::order_e, number_or_null(sweep.order[i])},
                       {key::needed, needed_json(sweep.needed[i])},
                       {key::dt_over_tau_and_worst_rel, points}});
    }
    ordered_json per_point = ordered_json::array();
    for (std::size_t pi = 0; pi < sweep.by_point.size(); ++pi) {
      per_point.push_back({{key::p, plan.points[pi].p},
                           {key::damping, plan.points[pi].damping.label()},
                           {key::needed, needed_json(sweep.by_point[pi])}});
    }
    sweeps.push_back({{key::line, sweep.line},
                      {key::onset_phases, sweep.onset_phases},
                      {key::solver_runs, sweep.solver_runs},
                      {key::per_p, per_p},
                      {key::per_point, per_point}});
  }
  return {{key::dt_crit_over_tau0, study.dt_crit_over_tau0},
          {key::dt_tangent_over_tau0, study.dt_tangent_over_tau0},
          {key::sweeps, sweeps}};
}

// The analytic layer in double against the truth, per point; a solved point's truth is the
// reference solve, with its own error estimate.
ordered_json analytic_json(const Plan& plan) {
  ordered_json analytic = ordered_json::array();
  for (const Point& point : plan.points) {
    ordered_json errors, logs = ordered_json::object();
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const AnalyticCheck& check = point.analytic[o];
      errors[plan.observables[o]->key] = number_or_null(check.error);
      if (check.log_error) {
        logs[plan.observables[o]->key] = number_or_null(check.log_error);
      }
    }
    analytic.push_back({{key::p, point.p},
                        {key::damping, point.damping.label()},
                        {key::alpha_eff, number_or_null(point.alpha_eff)},
                        {key::max_rel, errors},
                        {key::not_representable, not_representable(plan, point)},
                        {key::log_rel, logs},
                        {key::seconds, point.analytic_seconds}});
    if (point.solved) {
      // MATH.md §12.2: no closed form; the truth is the float128 reference solve, and this its
      // own error estimate (a second solve at another order), per observable.
      ordered_json estimate = ordered_json::object();
      for (std::size_t o = 0; o < plan.observables.size() && o < point.truth_error.size(); ++o) {
        estimate[plan.observables[o]->key] = number_or_null(point.truth_error[o]);
      }
      analytic.back()[key::truth] = "reference solve";
      analytic.back()[key::truth_error] = estimate;
      if (!point.no_truth.empty()) {
        analytic.back()[key::no_truth] = point.no_truth;
      }
    }
  }
  return analytic;
}

} // namespace

ordered_json budgets_json(const RunReport& report) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  ordered_json worst = ordered_json::array(), maps = ordered_json::array(),
               cost = ordered_json::array();
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const std::string label = plan.configs[c].label();
    ordered_json regimes{{key::config, label}};
    for (const auto& [name, regime] : {std::pair{key::underdamped, &budgets.cost[c].underdamped},
                                       std::pair{key::overdamped, &budgets.cost[c].overdamped}}) {
      regimes[name] = {{key::cells, regime->cells},
                       {key::rhs_evals, regime->rhs_evals},
                       {key::steps, regime->steps},
                       {key::seconds, regime->seconds},
                       {key::seconds_slowest, regime->seconds_slowest}};
    }
    cost.push_back(regimes);
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      worst.push_back({{key::config, label},
                       {key::observable, plan.observables[o]->key},
                       {key::max_abs, number_or_null(budgets.worst[c][o].abs)},
                       {key::max_rel, number_or_null(budgets.worst[c][o].rel)},
                       {key::worst_cell, budgets.worst[c][o].cell}});
      if (plan.configs[c].onset_phases > 1) {
        worst.back()[key::max_phase_spread] = number_or_null(budgets.worst[c][o].spread);
      }
      ordered_json map = ordered_json::array();
      for (std::size_t i = 0; i < plan.points.size(); ++i) {
        map.push_back(number_or_null(budgets.map[c][o][i]));
      }
      maps.push_back(
          {{key::config, label}, {key::observable, plan.observables[o]->key}, {key::max_rel, map}});
    }
  }
  ordered_json out{{key::points_order, "p-major: point = p index × dampings + damping index"},
                   {key::worst, worst},
                   {key::maps, maps},
                   {key::analytic_double, analytic_json(plan)},
                   {key::cost_per_cell, cost},
                   {key::work_precision, work_precision_json(report)}};
  if (!budgets.steps.sweeps.empty()) {
    out[key::step_study] = step_study_json(plan, budgets.steps);
  }
  return out;
}

schema::RecordId record_id(const Plan& plan, const Record& record) {
  const Cell& cell = plan.cells[record.cell];
  const Point& point = plan.points[cell.point];
  return {.config = plan.configs[record.config].label(),
          .p = point.p,
          .damping = point.damping.label(),
          .v0 = cell.v0,
          .m = cell.m,
          .k = cell.k};
}

ordered_json record_json(const Plan& plan, const Record& record) {
  const schema::RecordId id = record_id(plan, record);
  const Point& point = plan.points[plan.cells[record.cell].point];
  ordered_json r{{key::key, schema::record_key(id)},
                 {key::config, id.config},
                 {key::precision, plan.configs[record.config].precision},
                 {key::p, id.p},
                 {key::damping, id.damping},
                 {key::alpha_eff, point.alpha_eff},
                 {key::alpha, record.alpha},
                 {key::v0, id.v0},
                 {key::m, id.m},
                 {key::k, id.k},
                 {key::outcome, record.outcome_name()},
                 {key::failed, record.failed()},
                 {key::steps, record.steps},
                 {key::rhs_evals, record.rhs_evals},
                 {key::wall_seconds, timing(record.wall_seconds)},
                 {key::wall_seconds_slowest, timing(record.wall_seconds_slowest)}};
  if (record.cpu_seconds && record.cpu_seconds_slowest) {
    r[key::cpu_seconds] = timing(*record.cpu_seconds);
    r[key::cpu_seconds_slowest] = timing(*record.cpu_seconds_slowest);
  }
  if (!record.alpha_digits.empty()) {
    r[key::alpha_digits] = record.alpha_digits; // α in the configuration's wider precision
  }
  if (const MaterialContact* contact = contact_of(plan.scene, id.m, id.k)) {
    r[key::contact] = contact->name;
  }
  if (record.dt) {
    r[key::dt] = *record.dt;
  }
  // No abs_error: it is |error| exactly (both rounded once from the same Exact difference).
  const std::pair<const char*, const std::vector<std::optional<double>>*> columns[] = {
      {key::value, &record.value},
      {key::reference, &record.reference},
      {key::error, &record.error},
      {key::rel_error, &record.rel_error},
      {key::phase_spread, &record.spread}};
  for (const auto& [field, column] : columns) {
    if (column == &record.spread && record.phases == 1) {
      continue; // one phase: no spread
    }
    r[field] = per_observable(plan, *column);
  }
  if (record.phases > 1) {
    r[key::phases] = record.phases;
  }
  if (!record.failure.empty()) {
    r[key::failure] = record.failure;
  }
  if (record.skipped()) {
    r[key::skipped] = record.skip_reason;
  }
  if (!record.note.empty()) {
    r[key::note] = record.note;
  }
  if (!record.replica_difference.empty()) {
    r[key::replica_difference] = per_observable(plan, record.replica_difference);
  }
  return r;
}

ordered_json records_json(const RunReport& report) {
  ordered_json records = ordered_json::array();
  for (const Record& record : report.records) {
    records.push_back(record_json(report.plan, record));
  }
  return records;
}

} // namespace pldamp::harness
