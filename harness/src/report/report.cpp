#include "report/report.hpp"

#include "common/files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

namespace pldamp::harness {

using nlohmann::ordered_json;

ordered_json number_or_null(const std::optional<double>& x) {
  return x && std::isfinite(*x) ? ordered_json(*x) : ordered_json(nullptr);
}

namespace {

// 64-bit FNV-1a of a text, in hex: a name for what a scene computes, not a security measure.
std::string fingerprint(std::string_view text) {
  std::uint64_t hash = 14695981039346656037ULL;
  for (const char c : text) {
    hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  }
  return fmt::format("{:016x}", hash);
}

} // namespace

std::string short_number(const std::optional<double>& x, int digits) {
  if (!x) {
    return "–";
  }
  if (std::isinf(*x)) {
    return "inf";
  }
  return fmt::format("{:.{}g}", *x, digits + 1);
}

std::string record_key(const Plan& plan, const Record& record) {
  const Cell& cell = plan.cells[record.cell];
  const Point& point = plan.points[cell.point];
  return plan.configs[record.config].label() + " | p=" + to_string_full(point.p) + " " +
         point.damping.label() + " v0=" + to_string_full(cell.v0) + " m=" + to_string_full(cell.m) +
         " k=" + to_string_full(cell.k);
}

namespace {

// The damping points' columns: returning contacts by α_eff, then those that do not return (the
// seed's sinh branch) apart.
std::vector<std::size_t> damping_columns(const Plan& plan) {
  std::vector<std::size_t> columns(plan.scene.damping.size());
  std::iota(columns.begin(), columns.end(), 0);
  const auto alpha_eff = [&](std::size_t d) { return plan.points[d].alpha_eff; };
  std::stable_sort(columns.begin(), columns.end(), [&](std::size_t a, std::size_t b) {
    const bool over_a = plan.points[a].overdamped, over_b = plan.points[b].overdamped;
    return over_a != over_b ? !over_a : alpha_eff(a) < alpha_eff(b);
  });
  return columns;
}

} // namespace

MapTable map_table(const Plan& plan, const std::function<std::string(std::size_t point)>& cell) {
  const std::vector<std::size_t> columns = damping_columns(plan);
  const std::size_t dampings = plan.scene.damping.size();
  // No return (α_eff ≥ 1 for the seed's dashpot; beyond it, what the reference solve found).
  const auto overdamped = [&](std::size_t d) { return plan.points[d].overdamped; };
  const auto starts_overdamped = [&](std::size_t c) {
    return overdamped(columns[c]) && (c == 0 || !overdamped(columns[c - 1]));
  };
  MapTable table;
  table.header.emplace_back("p \\ α_eff");
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (starts_overdamped(c)) {
      table.header.emplace_back("overdamped:");
    }
    const Point& point = plan.points[columns[c]];
    table.header.push_back(short_number(point.alpha_eff, 3) + " (" + point.damping.label() + ")");
  }
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    std::vector<std::string> row{to_string_full(plan.scene.p[i])};
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (starts_overdamped(c)) {
        row.emplace_back();
      }
      row.push_back(cell(i * dampings + columns[c]));
    }
    table.rows.push_back(row);
  }
  return table;
}

double mean_analytic_seconds(const Plan& plan) {
  double sum = 0;
  for (const Cell& cell : plan.cells) {
    sum += plan.points[cell.point].analytic_seconds;
  }
  return plan.cells.empty() ? 0 : sum / double(plan.cells.size());
}

std::string step_steps_text(const Plan& plan, const StepSweep& sweep, const StepsNeeded& needed) {
  if (!needed.returns) {
    return "no return";
  }
  if (!needed.steps) {
    return fmt::format("> {}", *plan.configs[sweep.configs.back()].steps_per_contact);
  }
  return (needed.within_sweep && !needed.from_sweep ? "" : "≤ ") +
         fmt::format("{:.0f}", *needed.steps);
}

MapTable step_points_table(const Plan& plan, const StepSweep& sweep) {
  return map_table(plan, [&](std::size_t point) {
    std::string text;
    for (const StepsNeeded& needed : sweep.by_point[point]) {
      text += (text.empty() ? "" : " / ") + step_steps_text(plan, sweep, needed);
    }
    return text;
  });
}

std::string step_study_description(const StepStudy& study) {
  int phases = 0;
  bool from_sweep = false;
  for (const StepSweep& sweep : study.sweeps) {
    phases = std::max(phases, sweep.onset_phases);
    from_sweep = from_sweep || sweep.onset_phases == 0;
  }
  return fmt::format(
      "Steps per contact is (π δ_u/v0)/Δt, the `steps_per_contact` a scene and `pldamp solve` "
      "set (δ_u the undamped peak overlap); τ/Δt, each answer's true contact duration per step, "
      "is in report.json beside it. Each (p, damping) point's answer is that of a [[search]] over "
      "the sweep's range (judge/search.hpp): scanned from the finest step, 8 values a decade, then "
      "bisected at the first failure, each value's error the worst over 8 onset phases, the answer "
      "checked at twice as many and sought again there until it moves by less than 1 % (up to {} "
      "phases here){}. Per p, the worst over the grid's dampings. The order is the slope of the "
      "worst error in e against Δt over the finest half of the sweep.",
      phases,
      from_sweep ? "; an external program's answer is read off its sweep (≤: the coarsest sweep "
                   "value from which every finer one held)"
                 : "");
}
std::string phase_spread_text(const StepSweep& sweep, std::size_t e, std::size_t p_index) {
  const std::optional<double>& coarsest = sweep.points[e][p_index].front().spread;
  const std::optional<double>& finest = sweep.points[e][p_index].back().spread;
  return coarsest || finest ? short_number(coarsest) + " → " + short_number(finest) : "–";
}

std::string unrepresentable_note(const Plan& plan) {
  std::string lines;
  for (const Point& point : plan.points) {
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const AnalyticCheck& check = point.analytic[o];
      if (!check.representable) {
        const std::string key(plan.observables[o]->key);
        lines += fmt::format(
            "p={} {}: {} is not representable in double{}\n", to_string_full(point.p),
            point.damping.label(), key,
            check.log_error ? "; ln " + key + " errs " + short_number(check.log_error) : "");
      }
    }
  }
  return lines;
}

namespace {

bool any_overdamped(const Plan& plan) {
  return std::any_of(plan.points.begin(), plan.points.end(),
                     [](const Point& point) { return point.overdamped; });
}

// A table in Markdown.
std::string markdown_table(const MapTable& table) {
  std::string out = "|";
  for (const std::string& head : table.header) {
    out += " " + head + " |";
  }
  out += "\n|";
  for (std::size_t c = 0; c < table.header.size(); ++c) {
    out += "---|";
  }
  for (const std::vector<std::string>& row : table.rows) {
    out += "\n|";
    for (const std::string& entry : row) {
      out += " " + entry + " |";
    }
  }
  return out + "\n";
}

// The † footnote under the analytic map, one line per observable out of double's range.
std::string analytic_footnote(const Plan& plan) {
  const std::string lines = unrepresentable_note(plan);
  if (lines.empty()) {
    return "";
  }
  std::string out = "\n† an observable out of double's range (it under- or overflows there; not an "
                    "error of the closed form):\n\n";
  std::istringstream each(lines);
  for (std::string line; std::getline(each, line);) {
    out += "- " + line + "\n";
  }
  return out;
}

// A map as a Markdown table.
std::string markdown_map(const Plan& plan,
                         const std::function<std::string(std::size_t point)>& cell) {
  return markdown_table(map_table(plan, cell));
}

ordered_json step_study_json(const Plan& plan, const StepStudy& study) {
  auto needed_json = [](const std::array<StepsNeeded, 3>& needed) {
    ordered_json out = ordered_json::array();
    for (std::size_t t = 0; t < step_targets.size(); ++t) {
      out.push_back({{"target", step_targets[t]},
                     {"steps_per_contact", number_or_null(needed[t].steps)},
                     {"tau_over_dt", number_or_null(needed[t].tau_over_dt)},
                     {"within_sweep", needed[t].within_sweep},
                     {"returns", needed[t].returns},
                     {"from_sweep", needed[t].from_sweep}});
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
      per_p.push_back({{"p", plan.scene.p[i]},
                       {"order_e", number_or_null(sweep.order[i])},
                       {"needed", needed_json(sweep.needed[i])},
                       {"dt_over_tau_and_worst_rel", points}});
    }
    ordered_json per_point = ordered_json::array();
    for (std::size_t pi = 0; pi < sweep.by_point.size(); ++pi) {
      per_point.push_back({{"p", plan.points[pi].p},
                           {"damping", plan.points[pi].damping.label()},
                           {"needed", needed_json(sweep.by_point[pi])}});
    }
    sweeps.push_back({{"line", sweep.line},
                      {"onset_phases", sweep.onset_phases},
                      {"solver_runs", sweep.solver_runs},
                      {"per_p", per_p},
                      {"per_point", per_point}});
  }
  return {{"dt_crit_over_tau0", study.dt_crit_over_tau0},
          {"dt_tangent_over_tau0", study.dt_tangent_over_tau0},
          {"sweeps", sweeps}};
}

std::string step_study_markdown(const Plan& plan, const StepStudy& study) {
  std::string out = "\n## Time-step study: steps per contact for e within 1 %, 0.1 %, 0.01 %\n\n" +
                    step_study_description(study) + "\n";
  for (const StepSweep& sweep : study.sweeps) {
    out += fmt::format("\n### {}\n\n| p | order in e | 1 % | 0.1 % | 0.01 % | spread of e over "
                       "onset phases, coarsest → finest step |\n|---|---|---|---|---|---|\n",
                       sweep.line);
    const std::size_t e = study.e;
    for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
      out +=
          fmt::format("| {} | {} |", to_string_full(plan.scene.p[i]), short_number(sweep.order[i]));
      for (std::size_t t = 0; t < step_targets.size(); ++t) {
        out += fmt::format(" {} |", step_steps_text(plan, sweep, sweep.needed[i][t]));
      }
      out += fmt::format(" {} |\n", phase_spread_text(sweep, e, i));
    }
    out += "\nPer point, steps per contact for 1 % / 0.1 % / 0.01 %:\n\n" +
           markdown_table(step_points_table(plan, sweep)) + "\n";
  }
  out += "\nThe seed's Δt_crit and the tangent-stiffness bound (MATH.md §6), as steps per undamped "
         "contact τ0/Δt:";
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    out += fmt::format(" p = {}: {:.3g} and {:.3g};", to_string_full(plan.scene.p[i]),
                       1 / study.dt_crit_over_tau0[i], 1 / study.dt_tangent_over_tau0[i]);
  }
  out.back() = '.';
  return out + "\n";
}

} // namespace

ordered_json report_json(const RunReport& report) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  ordered_json out;
  out["schema"] = schema::version;
  ordered_json scene;
  scene["end"] = plan.scene.end == solvers::End::force ? "force" : "overlap";
  for (const Observable* observable : plan.observables) {
    scene["observables"].push_back(observable->key);
  }
  scene["grid"] = {
      {"p", plan.scene.p}, {"v0", plan.scene.v0}, {"m", plan.scene.m}, {"k", plan.scene.k}};
  if (!plan.scene.damping_exponent.empty()) {
    scene["grid"]["damping_exponent"] = plan.scene.damping_exponent.front();
  }
  for (const Point& point : plan.points) {
    if (point.p == plan.scene.p.front()) {
      scene["grid"]["damping"].push_back({{"label", point.damping.label()},
                                          {"alpha_eff", point.alpha_eff},
                                          {"overdamped", point.overdamped}});
    }
  }
  for (const SolverConfig& config : plan.configs) {
    ordered_json c{
        {"label", config.label()}, {"solver", config.name}, {"precision", config.precision}};
    c["rtol"] = number_or_null(config.rtol);
    c["atol"] = number_or_null(config.atol);
    c["steps_per_contact"] =
        config.steps_per_contact ? ordered_json(*config.steps_per_contact) : ordered_json(nullptr);
    if (config.external()) { // its program is not part of what is computed: external_solvers
      c["dt"] = number_or_null(config.dt);
      c["options"] =
          config.options.empty() ? ordered_json::object() : ordered_json::parse(config.options);
    }
    scene["configs"].push_back(c);
  }
  for (const Claim& claim : plan.scene.claims) {
    scene["claims"].push_back(claim.name);
  }
  for (const Search& search : plan.scene.searches) {
    scene["searches"].push_back(search.name);
  }
  // What the scene computes, whatever its name, path, timing or report formats: two reports of
  // one fingerprint can be diffed record by record.
  scene["fingerprint"] = fingerprint(scene.dump());
  scene["name"] = plan.scene.name;
  scene["path"] = plan.scene.path;
  scene["repeats"] = plan.scene.repeats;
  // What the work-precision diagrams and report.md's table show (a choice of presentation: not
  // in the fingerprint; budgets.work_precision has every observable).
  for (const WorkPanel& panel : work_panels(plan)) {
    scene["work_precision"].push_back(panel.key);
  }
  scene["diff"] = {{"error_factor", plan.scene.diff.error_factor},
                   {"work_factor", plan.scene.diff.work_factor},
                   {"time_factor", plan.scene.diff.time_factor},
                   {"time_floor", plan.scene.diff.time_floor}};
  out["scene"] = scene;
  out["totals"] = {{"rhs_evals", report.totals.rhs_evals},
                   {"solver_runs", report.totals.solver_runs},
                   {"wall_seconds", report.totals.wall_seconds},
                   {"failed_records", budgets.failed_records}};
  ordered_json external = ordered_json::object();
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    if (plan.configs[c].external() && c < report.totals.external.size()) {
      external[plan.configs[c].line()] = {{"command", plan.configs[c].command},
                                          {"handshake", report.totals.external[c]}};
    }
  }
  if (!external.empty()) {
    out["external_solvers"] = external;
  }
  if (report.trajectories != nullptr && !report.trajectories->empty()) {
    ordered_json checks = ordered_json::array();
    for (const TrajectoryCheck& check : *report.trajectories) {
      ordered_json c{{"label", check.label}, {"file", check.file}, {"inputs", check.inputs}};
      if (!check.failure.empty()) {
        c["failure"] = check.failure;
      }
      for (const TrajectoryRow& row : check.rows) {
        ordered_json r{{"value", number_or_null(row.value)},
                       {"truth", number_or_null(row.truth)},
                       {"rel_error", number_or_null(row.judgement.relative_error)},
                       {"rel_sampling", number_or_null(row.judgement.relative_sampling)}};
        r["verdict"] = row.judgement.explained ? ordered_json(verdict_name(row.judgement))
                                               : ordered_json(nullptr);
        if (!row.judgement.explained) {
          r["why"] = row.judgement.why_not;
        }
        c[row.key] = r;
      }
      c["notes"] = check.notes;
      checks.push_back(c);
    }
    out["trajectories"] = checks;
  }
  out["claims"] = ordered_json::array();
  // "holds", "fails", or "partial": holds on some cells only, the others without a value.
  const auto verdict_word = [](const Judgement& j) {
    return j.partial() ? "partial" : j.holds ? "holds" : "fails";
  };
  const auto cells_json = [](const Judgement& j, ordered_json& into) {
    into["cells"] = j.cells;
    into["failed_cells"] = j.failed_cells;
    into["missing_cells"] = j.missing_cells;
    ordered_json listed = ordered_json::array();
    for (const CellWithoutValue& c : j.without_value) {
      listed.push_back({{"cell", c.cell}, {"why", c.why}, {"failed", c.failed}});
    }
    into["without_value"] = listed;
  };
  for (const Verdict& v : budgets.claims) {
    ordered_json claim{{"name", v.name},
                       {"verdict", verdict_word(v)},
                       {"expect", v.expect_holds ? "holds" : "fails"},
                       {"kind", v.kind},
                       {"where", v.where},
                       {"quote", v.quote},
                       {"figure", v.figure},
                       {"measured", number_or_null(v.measured)},
                       {"bound", v.bound},
                       {"margin", number_or_null(v.margin)},
                       {"meaning", v.meaning},
                       {"worse", v.worse_when_lower ? "lower" : "higher"},
                       {"worst", v.worst},
                       {"grid", v.grid},
                       {"note", v.note},
                       {"observable", v.observable},
                       {"solver", v.config},
                       {"supported", number_or_null(v.supported)},
                       {"allow_missing", v.allow_missing}};
    cells_json(v, claim);
    if (v.denser) {
      claim["denser"] = {{"verdict", verdict_word(*v.denser)},
                         {"measured", number_or_null(v.denser->measured)},
                         {"margin", number_or_null(v.denser->margin)},
                         {"worst", v.denser->worst},
                         {"grid", v.denser->grid},
                         {"note", v.denser->note}};
      cells_json(*v.denser, claim["denser"]);
    }
    if (!v.orders.empty()) {
      claim["orders"] = ordered_json::array();
      for (const MeasuredOrder& o : v.orders) {
        claim["orders"].push_back(
            {{"p", o.p}, {"order", number_or_null(o.order)}, {"coefficient", o.coefficient}});
      }
    }
    out["claims"].push_back(claim);
  }
  out["searches"] = ordered_json::array();
  for (const SearchResult& search : budgets.searches) {
    ordered_json groups = ordered_json::array();
    for (const SearchGroup& group : search.groups) {
      groups.push_back({{"group", group.group},
                        {"loosest", number_or_null(group.loosest)},
                        {"failing", number_or_null(group.failing)},
                        {"measured", number_or_null(group.measured)},
                        {"worst", group.worst},
                        {"trials", group.trials},
                        {"scanned", group.scanned},
                        {"onset_phases", group.onset_phases},
                        {"phases_checked", group.phases_checked},
                        {"solver_runs", group.solver_runs},
                        {"note", group.note}});
    }
    out["searches"].push_back({{"name", search.name},
                               {"where", search.where},
                               {"quote", search.quote},
                               {"solver", search.line},
                               {"parameter", search.parameter},
                               {"observable", search.observable},
                               {"measured", search.measure},
                               {"bound", search.bound},
                               {"solver_runs", search.solver_runs},
                               {"groups", groups}});
  }
  ordered_json worst = ordered_json::array(), maps = ordered_json::array(),
               cost = ordered_json::array();
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const std::string label = plan.configs[c].label();
    ordered_json regimes{{"config", label}};
    for (const auto& [name, regime] : {std::pair{"underdamped", &budgets.cost[c].underdamped},
                                       std::pair{"overdamped", &budgets.cost[c].overdamped}}) {
      regimes[name] = {{"cells", regime->cells},
                       {"rhs_evals", regime->rhs_evals},
                       {"steps", regime->steps},
                       {"seconds", regime->seconds},
                       {"seconds_slowest", regime->seconds_slowest}};
    }
    cost.push_back(regimes);
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      worst.push_back({{"config", label},
                       {"observable", plan.observables[o]->key},
                       {"max_abs", number_or_null(budgets.worst[c][o].abs)},
                       {"max_rel", number_or_null(budgets.worst[c][o].rel)},
                       {"worst_cell", budgets.worst[c][o].cell}});
      if (plan.configs[c].onset_phases > 1) {
        worst.back()["max_phase_spread"] = number_or_null(budgets.worst[c][o].spread);
      }
      ordered_json map = ordered_json::array();
      for (std::size_t i = 0; i < plan.points.size(); ++i) {
        map.push_back(number_or_null(budgets.map[c][o][i]));
      }
      maps.push_back(
          {{"config", label}, {"observable", plan.observables[o]->key}, {"max_rel", map}});
    }
  }
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
    analytic.push_back({{"p", point.p},
                        {"damping", point.damping.label()},
                        {"alpha_eff", number_or_null(point.alpha_eff)},
                        {"max_rel", errors},
                        {"not_representable", not_representable(plan, point)},
                        {"log_rel", logs},
                        {"seconds", point.analytic_seconds}});
    if (point.solved) {
      // MATH.md §12.2: no closed form; the truth is the float128 reference solve, and this its
      // own error estimate (the same solve in 50 digits), per observable.
      ordered_json estimate = ordered_json::object();
      for (std::size_t o = 0; o < plan.observables.size() && o < point.truth_error.size(); ++o) {
        estimate[plan.observables[o]->key] = number_or_null(point.truth_error[o]);
      }
      analytic.back()["truth"] = "reference solve";
      analytic.back()["truth_error"] = estimate;
      if (!point.no_truth.empty()) {
        analytic.back()["no_truth"] = point.no_truth;
      }
    }
  }
  out["budgets"] = {{"points_order", "p-major: point = p index × dampings + damping index"},
                    {"worst", worst},
                    {"maps", maps},
                    {"analytic_double", analytic},
                    {"cost_per_cell", cost},
                    {"work_precision", work_precision_json(report)}};
  if (!budgets.steps.sweeps.empty()) {
    out["budgets"]["step_study"] = step_study_json(plan, budgets.steps);
  }
  ordered_json records = ordered_json::array();
  for (const Record& record : report.records) {
    const Cell& cell = plan.cells[record.cell];
    const Point& point = plan.points[cell.point];
    ordered_json r{{"key", record_key(plan, record)},
                   {"config", plan.configs[record.config].label()},
                   {"precision", plan.configs[record.config].precision},
                   {"p", point.p},
                   {"damping", point.damping.label()},
                   {"alpha_eff", point.alpha_eff},
                   {"alpha", record.alpha},
                   {"v0", cell.v0},
                   {"m", cell.m},
                   {"k", cell.k},
                   {"outcome", record.outcome_name()},
                   {"failed", record.failed()},
                   {"steps", record.steps},
                   {"rhs_evals", record.rhs_evals},
                   {"wall_seconds", record.wall_seconds},
                   {"wall_seconds_slowest", record.wall_seconds_slowest}};
    if (!record.alpha_digits.empty()) {
      r["alpha_digits"] = record.alpha_digits; // α in the configuration's wider precision
    }
    if (record.dt) {
      r["dt"] = *record.dt;
    }
    const std::pair<const char*, const std::vector<std::optional<double>>*> columns[] = {
        {"value", &record.value},         {"reference", &record.reference},
        {"error", &record.error},         {"abs_error", &record.abs_error},
        {"rel_error", &record.rel_error}, {"phase_spread", &record.spread}};
    for (const auto& [field, column] : columns) {
      if (column == &record.spread && record.phases == 1) {
        continue; // one phase: no spread
      }
      ordered_json values;
      for (std::size_t o = 0; o < plan.observables.size(); ++o) {
        values[plan.observables[o]->key] = number_or_null((*column)[o]);
      }
      r[field] = values;
    }
    if (record.phases > 1) {
      r["phases"] = record.phases;
    }
    if (!record.failure.empty()) {
      r["failure"] = record.failure;
    }
    if (record.skipped()) {
      r["skipped"] = record.skip_reason;
    }
    if (!record.note.empty()) {
      r["note"] = record.note;
    }
    if (!record.replica_difference.empty()) {
      ordered_json differences;
      for (std::size_t o = 0; o < plan.observables.size(); ++o) {
        differences[plan.observables[o]->key] = number_or_null(record.replica_difference[o]);
      }
      r["replica_difference"] = differences;
    }
    records.push_back(r);
  }
  out["records"] = records;
  ordered_json figures = ordered_json::array();
  for (const Figure& figure : report.figures) {
    ordered_json series = ordered_json::array();
    for (const Series& line : figure.series) {
      series.push_back(
          {{"title", line.title}, {"closed_form", line.closed_form}, {"points", line.points}});
    }
    figures.push_back({{"kind", figure.kind},
                       {"title", figure.title},
                       {"x", figure.x_label},
                       {"y", figure.y_label},
                       {"max_deviation", figure.failure.empty() ? ordered_json(figure.deviation)
                                                                : ordered_json(nullptr)},
                       {"deviation_of", figure.deviation_of},
                       {"series", series}});
    if (!figure.failure.empty()) {
      figures.back()["failure"] = figure.failure;
    }
    if (!figure.table_header.empty()) {
      ordered_json rows = ordered_json::array();
      for (const std::vector<std::string>& row : figure.table_rows) {
        ordered_json entry = ordered_json::object();
        for (std::size_t i = 0; i < row.size() && i < figure.table_header.size(); ++i) {
          entry[figure.table_header[i]] = row[i];
        }
        rows.push_back(entry);
      }
      figures.back()["table"] = rows;
    }
  }
  out["figures"] = figures;
  return out;
}

std::string report_csv(const RunReport& report) {
  const Plan& plan = report.plan;
  std::string out = "solver,precision,rtol,atol,steps_per_contact,p,damping,alpha_eff,alpha,v0,m,k,"
                    "outcome,steps,rhs_evals,wall_seconds,wall_seconds_slowest";
  for (const Observable* observable : plan.observables) {
    const std::string_view name = observable->key;
    out += fmt::format(",{0},{0}_reference,{0}_error,{0}_abs_error,{0}_rel_error", name);
  }
  out += "\n";
  // Numbers in the shortest form that reads back to the same double (0.05, not
  // 0.050000000000000003); an empty field is a value absent.
  const auto number = [](const std::optional<double>& x) {
    return x ? fmt::format("{}", *x) : std::string();
  };
  for (const Record& record : report.records) {
    const SolverConfig& config = plan.configs[record.config];
    const Cell& c = plan.cells[record.cell];
    const Point& point = plan.points[c.point];
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", config.name,
                       config.precision, number(config.rtol), number(config.atol),
                       config.steps_per_contact ? std::to_string(*config.steps_per_contact) : "",
                       point.p, point.damping.label(), point.alpha_eff, record.alpha, c.v0, c.m,
                       c.k, record.outcome_name(), record.steps, record.rhs_evals,
                       record.wall_seconds, record.wall_seconds_slowest);
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      out += fmt::format(",{},{},{},{},{}", number(record.value[o]), number(record.reference[o]),
                         number(record.error[o]), number(record.abs_error[o]),
                         number(record.rel_error[o]));
    }
    out += "\n";
  }
  return out;
}

std::vector<ClaimRow> claim_rows(const RunReport& report) {
  const std::vector<Verdict>& claims = report.budgets.claims;
  std::vector<std::size_t> order(claims.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = i;
  }
  // An unexpected verdict first, then the failing claims, then those that hold.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    auto rank = [&](const Verdict& v) { return v.unexpected() ? 0 : v.holds ? 2 : 1; };
    return rank(claims[a]) < rank(claims[b]);
  });
  std::vector<ClaimRow> rows;
  for (const std::size_t i : order) {
    const Verdict& v = claims[i];
    ClaimRow row;
    row.name = v.name;
    row.kind = v.kind;
    row.subject = v.observable + ", " + v.config;
    row.where = v.where.empty() ? "–" : v.where;
    row.quote = v.quote;
    row.figure = v.figure;
    row.holds = v.holds;
    row.unexpected = v.unexpected();
    row.verdict =
        verdict_text(v) + (v.unexpected()
                               ? (v.expect_holds ? ", unexpected" : ", unexpected: pinned as fails")
                               : (v.holds ? "" : " (expected)"));
    row.worst = v.worst.empty() ? "–" : v.worst;
    row.measured = short_number(v.measured, 3);
    row.bound = short_number(v.bound);
    row.margin = short_number(v.margin);
    row.denser =
        !v.denser ? "–"
        : v.denser->holds == v.holds
            ? verdict_text(*v.denser) + ", unchanged (" + short_number(v.denser->measured, 3) + ")"
            : verdict_text(*v.denser) + ": CHANGED (" + short_number(v.denser->measured, 3) +
                  " at " + v.denser->worst + ")";
    row.grid = v.grid + (v.denser ? "; denser: " + v.denser->grid : "");
    row.note = v.note;
    // Every cell without a value that the verdict keeps (the first 20), with why.
    for (const Judgement* j :
         {static_cast<const Judgement*>(&v), v.denser ? &*v.denser : nullptr}) {
      if (j == nullptr || j->without_value.empty()) {
        continue;
      }
      std::string listed;
      for (const CellWithoutValue& c : j->without_value) {
        listed += (listed.empty() ? "" : "; ") + c.cell + " (" + c.why + ")";
      }
      const long more = j->failed_cells + j->missing_cells - long(j->without_value.size());
      row.without_value +=
          fmt::format("{}Without a value{}: {}{}.", row.without_value.empty() ? "" : " ",
                      j == &v ? "" : " on the denser grid", listed,
                      more > 0 ? fmt::format("; and {} more", more) : "");
    }
    row.meaning = v.meaning;
    rows.push_back(row);
  }
  return rows;
}

std::string budget_table_note(const Plan& plan) {
  return fmt::format(
      "Worst cell: where the configuration's largest relative error is (its observable in "
      "brackets). rhs_evals / cell: the mean right-hand-side and Jacobian evaluations per "
      "collision{}. µs / cell: the mean over the cells of each record's fastest repeat{}. "
      "× analytic: the time per cell as a multiple of the closed forms' for the same observables "
      "in double ({} µs per cell).",
      any_overdamped(plan) ? ", underdamped and overdamped cells apart (an overdamped contact "
                             "never returns: its solve runs to the horizon)"
                           : "",
      plan.scene.repeats > 1 ? "; slowest repeat: how much slower the slowest was (the noise of "
                               "the machine)"
                             : "",
      short_number(mean_analytic_seconds(plan) * 1e6, 2));
}

MapTable search_table(const RunReport& report) {
  MapTable table;
  table.header = {
      "search", "group",       "loosest value", "first value beyond", "measured there", "bound",
      "trials", "solver runs", "note"};
  for (const SearchResult& search : report.budgets.searches) {
    for (const SearchGroup& group : search.groups) {
      table.rows.push_back(
          {search.name, group.group,
           group.loosest ? fmt::format("{} = {:.3g}", search.parameter, *group.loosest)
                         : "none in the range",
           group.failing ? fmt::format("{:.3g}", *group.failing) : "–",
           short_number(group.measured, 2) + (group.worst.empty() ? "" : " at " + group.worst),
           short_number(search.bound), std::to_string(group.trials),
           std::to_string(group.solver_runs), group.note.empty() ? "–" : group.note});
    }
  }
  return table;
}

std::string search_table_note(const RunReport& report) {
  std::string out;
  for (const SearchResult& search : report.budgets.searches) {
    out += fmt::format(
        "{}{}: {} of {}, keeping {} at most {:g}{}.", out.empty() ? "" : " ", search.name,
        search.parameter, search.line, search.measure, search.bound,
        search.quote.empty() ? "" : fmt::format(" (\"{}\", {})", search.quote, search.where));
  }
  return out + (out.empty()
                    ? ""
                    : " By bisection on the parameter's logarithm, assuming the error grows "
                      "as it loosens: the loosest value kept the bound, the next one "
                      "tried broke it.");
}

MapTable trajectory_table(const RunReport& report) {
  MapTable table{{"trajectory", "inputs", "observable", "measured", "truth", "rel error",
                  "sampling (rel)", "verdict"},
                 {}};
  if (report.trajectories == nullptr) {
    return table;
  }
  for (const TrajectoryCheck& check : *report.trajectories) {
    if (!check.failure.empty()) {
      table.rows.push_back(
          {check.label, check.inputs, "–", "failed: " + check.failure, "", "", "", ""});
      continue;
    }
    for (const TrajectoryRow& row : check.rows) {
      table.rows.push_back(
          {check.label, check.inputs, row.key, row.value ? short_number(row.value, 9) : "missing",
           short_number(row.truth, 9), short_number(row.judgement.relative_error),
           short_number(row.judgement.relative_sampling),
           row.judgement.explained ? verdict_name(row.judgement) : row.judgement.why_not});
    }
  }
  return table;
}

MapTable external_table(const RunReport& report) {
  const Plan& plan = report.plan;
  MapTable table{{"external solver", "program", "says of itself", "run", "skipped", "failed",
                  "truth of its own dashpot", "largest difference from its replica"},
                 {}};
  struct Row {
    long run = 0, failed = 0;
    std::map<std::string, long> skipped, notes; // each reason and how many records it has
    std::optional<double> from_replica;
    std::string where; // the replica and the observable of the largest difference
  };
  std::vector<std::string> lines;
  std::vector<Row> rows;
  for (const Record& record : report.records) {
    const SolverConfig& config = plan.configs[record.config];
    if (!config.external()) {
      continue;
    }
    auto found = std::find(lines.begin(), lines.end(), config.line());
    if (found == lines.end()) {
      lines.push_back(config.line());
      rows.emplace_back();
      std::string program;
      for (const std::string& arg : config.command) {
        program += (program.empty() ? "" : " ") + arg;
      }
      const std::vector<std::string>& said = report.totals.external;
      table.rows.push_back(
          {config.line(), program, record.config < said.size() ? said[record.config] : ""});
      found = lines.end() - 1;
    }
    Row& row = rows[static_cast<std::size_t>(found - lines.begin())];
    if (record.skipped()) {
      ++row.skipped[record.skip_reason];
      continue;
    }
    ++row.run;
    row.failed += record.failed() ? 1 : 0;
    if (!record.note.empty()) {
      ++row.notes[record.note];
    }
    for (std::size_t o = 0; o < record.replica_difference.size(); ++o) {
      const std::optional<double>& difference = record.replica_difference[o];
      if (difference && !(*difference <= row.from_replica.value_or(-1.0))) {
        row.from_replica = difference;
        row.where = config.replica + ", " + std::string(plan.observables[o]->key);
      }
    }
  }
  // "21 (reason)", or with several reasons "28: 21 reason; 7 another".
  const auto counted = [](const std::map<std::string, long>& reasons) {
    long total = 0;
    std::string text;
    for (const auto& [reason, n] : reasons) {
      total += n;
      text += (text.empty() ? "" : "; ") + std::to_string(n) + " " + reason;
    }
    if (reasons.size() == 1) {
      return std::to_string(total) + " (" + reasons.begin()->first + ")";
    }
    return std::to_string(total) + (reasons.empty() ? "" : ": " + text);
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    table.rows[i].push_back(std::to_string(row.run));
    table.rows[i].push_back(counted(row.skipped));
    table.rows[i].push_back(std::to_string(row.failed));
    table.rows[i].push_back(counted(row.notes));
    table.rows[i].push_back(
        row.where.empty() ? "–" : short_number(row.from_replica) + " (" + row.where + ")");
  }
  return table;
}

MapTable error_table(const RunReport& report) {
  const Plan& plan = report.plan;
  MapTable table;
  table.header.emplace_back("configuration");
  for (const Observable* observable : plan.observables) {
    table.header.emplace_back(observable->key);
  }
  table.header.emplace_back("worst cell");
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    std::vector<std::string> row{plan.configs[c].label()};
    std::optional<double> largest_error;
    std::string worst_cell = "–";
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const Worst& worst = report.budgets.worst[c][o];
      row.push_back(short_number(worst.rel));
      if (worst.rel && (!largest_error || *worst.rel > *largest_error)) {
        largest_error = worst.rel;
        worst_cell = fmt::format("{} ({})", worst.cell, plan.observables[o]->key);
      }
    }
    row.push_back(worst_cell);
    table.rows.push_back(row);
  }
  return table;
}

MapTable cost_table(const RunReport& report) {
  const Plan& plan = report.plan;
  const bool overdamped = any_overdamped(plan), repeats = plan.scene.repeats > 1;
  MapTable table;
  table.header = {"configuration",
                  overdamped ? "rhs_evals / cell, underdamped" : "rhs_evals / cell"};
  if (overdamped) {
    table.header.emplace_back("rhs_evals / cell, overdamped");
  }
  table.header.push_back(fmt::format("µs / cell (fastest of {})", plan.scene.repeats));
  if (repeats) {
    table.header.emplace_back("slowest repeat");
  }
  table.header.emplace_back("× analytic");
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const Cost& cost = report.budgets.cost[c];
    const auto per_cell = [](const RegimeCost& regime) {
      return regime.cells > 0 ? short_number(regime.rhs_evals, 3) : std::string("–");
    };
    std::vector<std::string> row{plan.configs[c].label(), per_cell(cost.underdamped)};
    if (overdamped) {
      row.push_back(per_cell(cost.overdamped));
    }
    const double cells = double(cost.underdamped.cells + cost.overdamped.cells);
    const auto mean = [&](double RegimeCost::*seconds) {
      return (cost.underdamped.*seconds * double(cost.underdamped.cells) +
              cost.overdamped.*seconds * double(cost.overdamped.cells)) /
             cells;
    };
    const double fastest = mean(&RegimeCost::seconds), slowest = mean(&RegimeCost::seconds_slowest);
    row.push_back(short_number(fastest * 1e6, 3));
    if (repeats) {
      row.push_back(fastest > 0 ? fmt::format("+{:.0f} %", 100 * (slowest / fastest - 1)) : "–");
    }
    row.push_back(short_number(times_analytic(report.budgets.work[c]), 2));
    table.rows.push_back(row);
  }
  return table;
}

std::string report_markdown(const RunReport& report) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  std::ostringstream out;
  out << "# pldamp report: " << plan.scene.name << "\n\n";
  out << "Scene `" << plan.scene.path << "`, end "
      << (plan.scene.end == solvers::End::force ? "force" : "overlap") << ": " << plan.cells.size()
      << " cells × " << plan.configs.size() << " solver configurations, "
      << report.totals.solver_runs << " solver runs, " << report.totals.rhs_evals
      << " rhs evaluations, " << short_number(report.totals.wall_seconds, 3) << " s. "
      << budgets.failed_records << " failed records.\n\n**How to read this report.** "
      << how_to_read << "\n\n";
  if (!budgets.claims.empty()) {
    out << "## Claims\n\n| claim | where | verdict | worst case | measured | bound | margin | ten "
           "times denser |\n|---|---|---|---|---|---|---|---|\n";
    for (const ClaimRow& row : claim_rows(report)) {
      out << "| " << row.name << " | " << row.where << " | **" << row.verdict << "** | "
          << row.worst << " | " << row.measured << " | " << row.bound << " | " << row.margin
          << " | " << row.denser << " |\n";
    }
    out << "\n";
    for (const ClaimRow& row : claim_rows(report)) {
      out << "- **" << row.name << "** (" << row.kind << "; " << row.subject << "). "
          << (row.quote.empty() ? "" : "\"" + row.quote + "\" ") << "Judged over " << row.grid
          << ". Measured: " << row.meaning << "." << (row.note.empty() ? "" : " " + row.note + ".")
          << (row.without_value.empty() ? "" : " " + row.without_value) << "\n";
    }
    out << "\n";
  }
  if (!budgets.searches.empty()) {
    out << "## Searches: the loosest setting that keeps a bound\n\n"
        << markdown_table(search_table(report)) << "\n"
        << search_table_note(report) << "\n\n";
  }
  if (const MapTable external = external_table(report); !external.rows.empty()) {
    out << "## External solvers\n\n" << markdown_table(external) << "\n";
  }
  if (const MapTable checked = trajectory_table(report); !checked.rows.empty()) {
    out << "## Trajectories checked\n\n" << markdown_table(checked) << "\n";
  }
  out << "## Worst relative error over the grid\n\n"
      << markdown_table(error_table(report)) << "\n## Cost per cell\n\n"
      << markdown_table(cost_table(report));
  out << "\n" << budget_table_note(plan) << "\n";
  out << "\n## Work precision: cost against error, per p\n\n"
      << markdown_table(work_precision_table(report)) << "\n"
      << work_precision_note(plan) << "\n";
  if (!budgets.steps.sweeps.empty()) {
    out << step_study_markdown(plan, budgets.steps);
  }
  out << "\n## Worst relative error per p × α_eff, per configuration\n";
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    out << "\n### " << plan.configs[c].label() << "\n\n"
        << markdown_map(
               plan, [&](std::size_t point) { return short_number(worst_at(budgets, c, point)); });
  }
  out << "\n## The analytic layer in double against " << precision_name<Exact>()
      << " (relative error, worst observable)\n\n"
      << markdown_map(plan,
                      [&](std::size_t point) {
                        const Point& at = plan.points[point];
                        return short_number(analytic_worst(at)) +
                               (not_representable(plan, at).empty() ? "" : " †");
                      })
      << analytic_footnote(plan);
  if (!report.figures.empty()) {
    out << "\n## The seed's figures: solver against closed form\n\n| figure | largest deviation "
           "|\n|---|---|\n";
    for (const Figure& figure : report.figures) {
      out << "| " << figure.title << " | "
          << (figure.failure.empty() ? short_number(figure.deviation) + " in " + figure.deviation_of
                                     : "failed: " + figure.failure)
          << " |\n";
    }
    for (const Figure& figure : report.figures) {
      if (figure.table_header.empty()) {
        continue;
      }
      out << "\n"
          << figure.title << "\n\n"
          << markdown_table(MapTable{figure.table_header, figure.table_rows});
    }
  }
  if (budgets.failed_records > 0) {
    out << "\n## Failed records\n\n";
    long shown = 0;
    for (const Record& record : report.records) {
      if (record.failed() && shown++ < 20) {
        out << "- " << record_key(plan, record) << ": " << record.outcome_name()
            << (record.failure.empty() ? "" : " (" + record.failure + ")") << "\n";
      }
    }
  }
  return out.str();
}

WrittenReports write_reports(const RunReport& report, const std::string& folder) {
  namespace fs = std::filesystem;
  require_writable_folder(folder);
  WrittenReports out;
  for (const ReportFormat format : report.plan.scene.formats) {
    const fs::path path =
        fs::path(folder) / ("report." + std::string(name_of(report_formats, format)));
    try {
      switch (format) {
      case ReportFormat::json:
        write_file_atomically(path, report_json(report).dump(1) + "\n");
        break;
      case ReportFormat::csv:
        write_file_atomically(path, report_csv(report));
        break;
      case ReportFormat::md:
        write_file_atomically(path, report_markdown(report));
        break;
      case ReportFormat::html:
        write_file_atomically(path, report_html(report, "gnuplot"));
        break;
      }
      out.written.push_back(path.string());
    } catch (const InputError& e) { // the other formats are still written
      out.failures.push_back(e.what());
    }
  }
  return out;
}

} // namespace pldamp::harness
