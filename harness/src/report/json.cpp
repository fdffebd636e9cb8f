// report.json, one function per section (common/report_schema.hpp gives its layout and every key).
#include "report/sections.hpp"

#include "common/files.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <utility>

namespace pldamp::harness {

using nlohmann::ordered_json;
using schema::number_or_null;
namespace key = schema::key;
namespace word = schema::word;

namespace {

// fnv1a of a text, in hex: a name for what a scene computes.
std::string fingerprint(std::string_view text) {
  return fmt::format("{:016x}", fnv1a(text));
}

ordered_json config_json(const SolverConfig& config) {
  ordered_json c{
      {key::label, config.label()}, {key::solver, config.name}, {key::precision, config.precision}};
  c[key::rtol] = number_or_null(config.rtol);
  c[key::atol] = number_or_null(config.atol);
  c[key::steps_per_contact] =
      config.steps_per_contact ? ordered_json(*config.steps_per_contact) : ordered_json(nullptr);
  if (config.external()) { // its program is not part of what is computed: external_solvers
    c[key::dt] = number_or_null(config.dt);
    c[key::options] =
        config.options.empty() ? ordered_json::object() : ordered_json::parse(config.options);
  }
  return c;
}

ordered_json scene_json(const Plan& plan) {
  ordered_json scene;
  scene[key::end] = name_of(contact_ends, plan.scene.end);
  for (const Observable* observable : plan.observables) {
    scene[key::observables].push_back(observable->key);
  }
  scene[key::grid] = {{key::p, plan.scene.p},
                      {key::v0, plan.scene.v0},
                      {key::m, plan.scene.m},
                      {key::k, plan.scene.k}};
  if (!plan.scene.damping_exponent.empty()) {
    scene[key::grid][key::damping_exponent] = plan.scene.damping_exponent.front();
  }
  for (const MaterialContact& contact : plan.scene.contacts) {
    scene[key::grid][key::contacts].push_back({{key::name, contact.name},
                                               {key::geometry, contact.geometry},
                                               {key::R_eff, contact.radius_eff},
                                               {key::E_eff, contact.modulus_eff},
                                               {key::m, contact.m},
                                               {key::k, contact.k},
                                               {key::v0, contact.v0},
                                               {key::rayleigh_time, contact.rayleigh_time}});
  }
  if (!plan.scene.contacts.empty()) { // SI throughout: the contacts' numbers and the records'
    ordered_json units{{key::R_eff, "m"},   {key::E_eff, "Pa"}, {key::m, "kg"},
                       {key::k, "N/m^1.5"}, {key::v0, "m/s"},   {key::rayleigh_time, "s"}};
    for (const Observable* observable : plan.observables) {
      static constexpr std::array<const char*, 5> by_dimension{"", "m", "s", "J", "N"};
      if (const char* unit = by_dimension[static_cast<std::size_t>(observable->dimension)];
          *unit != '\0') {
        units[observable->key] = unit;
      }
    }
    scene[key::grid][key::units] = units;
  }
  for (const Point& point : plan.points) {
    if (point.p == plan.scene.p.front()) {
      scene[key::grid][key::damping].push_back({{key::label, point.damping.label()},
                                                {key::alpha_eff, point.alpha_eff},
                                                {key::overdamped, point.overdamped}});
    }
  }
  for (const SolverConfig& config : plan.configs) {
    scene[key::configs].push_back(config_json(config));
  }
  for (const Claim& claim : plan.scene.claims) {
    scene[key::claims].push_back(claim.name);
  }
  for (const Search& search : plan.scene.searches) {
    scene[key::searches].push_back(search.name);
  }
  // What the scene computes, whatever its name, path, timing or report formats: two reports of
  // one fingerprint can be diffed record by record.
  scene[key::fingerprint] = fingerprint(scene.dump());
  scene[key::name] = plan.scene.name;
  scene[key::path] = plan.scene.path;
  scene[key::repeats] = plan.scene.repeats;
  scene[key::repeat_below] = plan.scene.repeat_below;
  // What the work-precision diagrams and report.md's table show (a choice of presentation: not
  // in the fingerprint; budgets.work_precision has every observable).
  for (const WorkPanel& panel : work_panels(plan)) {
    scene[key::work_precision].push_back(panel.key);
  }
  scene[key::diff] = {{key::error_factor, plan.scene.diff.error_factor},
                      {key::work_factor, plan.scene.diff.work_factor},
                      {key::time_factor, plan.scene.diff.time_factor},
                      {key::time_floor, plan.scene.diff.time_floor}};
  return scene;
}

// Each external solver line's program and what it said of itself (none: an empty object).
ordered_json external_solvers_json(const RunReport& report) {
  const Plan& plan = report.plan;
  ordered_json external = ordered_json::object();
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    if (plan.configs[c].external() && c < report.totals.external.size()) {
      external[plan.configs[c].line()] = {{key::command, plan.configs[c].command},
                                          {key::handshake, report.totals.external[c]}};
    }
  }
  return external;
}

ordered_json trajectories_json(const std::vector<TrajectoryCheck>& trajectories) {
  ordered_json checks = ordered_json::array();
  for (const TrajectoryCheck& check : trajectories) {
    ordered_json c{{key::label, check.label}, {key::file, check.file}, {key::inputs, check.inputs}};
    if (!check.failure.empty()) {
      c[key::failure] = check.failure;
    }
    for (const TrajectoryRow& row : check.rows) {
      ordered_json r{{key::value, number_or_null(row.value)},
                     {key::truth, number_or_null(row.truth)},
                     {key::rel_error, number_or_null(row.judgement.relative_error)},
                     {key::rel_sampling, number_or_null(row.judgement.relative_sampling)}};
      r[key::verdict] = row.judgement.explained ? ordered_json(verdict_name(row.judgement))
                                                : ordered_json(nullptr);
      if (!row.judgement.explained) {
        r[key::why] = row.judgement.why_not;
      }
      c[row.key] = r;
    }
    c[key::notes] = check.notes;
    checks.push_back(c);
  }
  return checks;
}

// "holds", "fails", or "partial": holds on some cells only, the others without a value.
const char* verdict_word(const Judgement& j) {
  return j.partial() ? word::partial : j.holds ? word::holds : word::fails;
}

// A judgement's cells counted, and each cell without a value with why.
void cells_json(const Judgement& j, ordered_json& into) {
  into[key::cells] = j.cells;
  into[key::failed_cells] = j.failed_cells;
  into[key::missing_cells] = j.missing_cells;
  ordered_json listed = ordered_json::array();
  for (const CellWithoutValue& c : j.without_value) {
    listed.push_back({{key::cell, c.cell}, {key::why, c.why}, {key::failed, c.failed}});
  }
  into[key::without_value] = listed;
}

ordered_json claim_json(const Verdict& v) {
  ordered_json claim{{key::name, v.name},
                     {key::verdict, verdict_word(v)},
                     {key::expect, v.expect_holds ? word::holds : word::fails},
                     {key::kind, v.kind},
                     {key::where, v.where},
                     {key::quote, v.quote},
                     {key::figure, v.figure},
                     {key::measured, number_or_null(v.measured)},
                     {key::bound, v.bound},
                     {key::margin, number_or_null(v.margin)},
                     {key::meaning, v.meaning},
                     {key::worse, v.worse_when_lower ? word::lower : word::higher},
                     {key::worst, v.worst},
                     {key::grid, v.grid},
                     {key::note, v.note},
                     {key::observable, v.observable},
                     {key::solver, v.config},
                     {key::supported, number_or_null(v.supported)},
                     {key::allow_missing, v.allow_missing}};
  cells_json(v, claim);
  if (v.denser) {
    claim[key::denser] = {{key::verdict, verdict_word(*v.denser)},
                          {key::measured, number_or_null(v.denser->measured)},
                          {key::margin, number_or_null(v.denser->margin)},
                          {key::worst, v.denser->worst},
                          {key::grid, v.denser->grid},
                          {key::note, v.denser->note}};
    cells_json(*v.denser, claim[key::denser]);
  }
  if (!v.orders.empty()) {
    claim[key::orders] = ordered_json::array();
    for (const MeasuredOrder& o : v.orders) {
      claim[key::orders].push_back({{key::p, o.p},
                                    {key::order, number_or_null(o.order)},
                                    {key::coefficient, o.coefficient}});
    }
  }
  return claim;
}

ordered_json search_json(const SearchResult& search) {
  ordered_json groups = ordered_json::array();
  for (const SearchGroup& group : search.groups) {
    groups.push_back({{key::group, group.group},
                      {key::loosest, number_or_null(group.loosest)},
                      {key::failing, number_or_null(group.failing)},
                      {key::measured, number_or_null(group.measured)},
                      {key::worst, group.worst},
                      {key::worst_onset_phase, number_or_null(group.worst_onset_phase)},
                      {key::failing_measured, number_or_null(group.failing_measured)},
                      {key::failing_onset_phase, number_or_null(group.failing_onset_phase)},
                      {key::trials, group.trials},
                      {key::scanned, group.scanned},
                      {key::onset_phases, group.onset_phases},
                      {key::every_phase, group.every_phase},
                      {key::solver_runs, group.solver_runs},
                      {key::note, group.note}});
  }
  return {{key::name, search.name},
          {key::where, search.where},
          {key::quote, search.quote},
          {key::solver, search.line},
          {key::parameter, search.parameter},
          {key::observable, search.observable},
          {key::measured, search.measure},
          {key::bound, search.bound},
          {key::solver_runs, search.solver_runs},
          {key::groups, groups}};
}

ordered_json figure_json(const Figure& figure) {
  ordered_json series = ordered_json::array();
  for (const Series& line : figure.series) {
    series.push_back({{key::title, line.title},
                      {key::closed_form, line.closed_form},
                      {key::points, line.points}});
  }
  ordered_json out{{key::kind, figure.kind},
                   {key::title, figure.title},
                   {key::x, figure.x_label},
                   {key::y, figure.y_label},
                   {key::max_deviation, figure.failure.empty() ? ordered_json(figure.deviation)
                                                               : ordered_json(nullptr)},
                   {key::deviation_of, figure.deviation_of},
                   {key::series, series}};
  if (!figure.failure.empty()) {
    out[key::failure] = figure.failure;
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
    out[key::table] = rows;
  }
  return out;
}

// Every section; the records' an empty array when `with_records` is false (the writer streams
// them in its place).
ordered_json report_sections(const RunReport& report, bool with_records) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  ordered_json out;
  out[key::schema] = schema::version;
  if (report.made != nullptr) {
    out[key::run] = {{key::build, report.made->build},
                     {key::date, report.made->date},
                     {key::host, report.made->host},
                     {key::command, report.made->command},
                     {key::scene_checksum, report.made->scene_checksum}};
  }
  out[key::scene] = scene_json(plan);
  out[key::totals] = {{key::rhs_evals, report.totals.rhs_evals},
                      {key::solver_runs, report.totals.solver_runs},
                      {key::wall_seconds, report.totals.wall_seconds},
                      {key::failed_records, budgets.failed_records}};
  if (ordered_json external = external_solvers_json(report); !external.empty()) {
    out[key::external_solvers] = std::move(external);
  }
  if (report.trajectories != nullptr && !report.trajectories->empty()) {
    out[key::trajectories] = trajectories_json(*report.trajectories);
  }
  out[key::claims] = ordered_json::array();
  for (const Verdict& v : budgets.claims) {
    out[key::claims].push_back(claim_json(v));
  }
  out[key::searches] = ordered_json::array();
  for (const SearchResult& search : budgets.searches) {
    out[key::searches].push_back(search_json(search));
  }
  out[key::budgets] = budgets_json(report);
  out[key::records] = with_records ? records_json(report) : ordered_json::array();
  ordered_json figures = ordered_json::array();
  for (const Figure& figure : report.figures) {
    figures.push_back(figure_json(figure));
  }
  out[key::figures] = figures;
  return out;
}

} // namespace

ordered_json report_json(const RunReport& report) {
  return report_sections(report, true);
}

void write_report_json(const RunReport& report, const TextSink& put, int jobs) {
  const ordered_json json = report_sections(report, false);
  bool first_section = true;
  put("{");
  for (const auto& [name, value] : json.items()) {
    put(first_section ? "\n " : ",\n ");
    first_section = false;
    put(ordered_json(name).dump());
    put(": ");
    if (name == key::records) { // one line each, made and written one at a time
      put("[");
      put_record_lines(report.records, jobs, put, [&](const Record& record, std::size_t i) {
        return (i == 0 ? "\n  " : ",\n  ") + record_json(report.plan, record).dump();
      });
      put(report.records.empty() ? "]" : "\n ]");
      continue;
    }
    // Indented one level deeper: a JSON text holds no raw line break but between its values.
    std::string text;
    for (const char c : value.dump(1)) {
      text += c;
      if (c == '\n') {
        text += ' ';
      }
    }
    put(text);
  }
  put("\n}\n");
}

std::string report_json_text(const RunReport& report) {
  return gather_text([&report](const TextSink& put) { write_report_json(report, put); });
}

} // namespace pldamp::harness
