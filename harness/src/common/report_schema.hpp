// report.json's schema, in one place: its version, every key it holds, a record's identity (its
// key and the fields it is read back from), and the helpers that write and read it. Every writer
// (report/: JSON, and CSV's columns, which are named as report.json's fields) and every reader
// (`pldamp diff`, and whatever else reads a report) spells a key through here, never as a string
// literal of its own.
//
// report.json, schema 3 (docs/run.md "Reports"; `?`: only when there is something to say):
//   schema        2
//   run?          build, date, host, command [argv], scene_checksum (what made the report:
//                 common/provenance.hpp; a reader takes a report without it as before)
//   scene         end, observables, grid {p, v0, m, k, damping_exponent?, contacts? [{name,
//                 geometry, R_eff, E_eff, m, k, v0 [], rayleigh_time}], units? {KEY: SI unit},
//                 damping [{label, alpha_eff, overdamped}]}, configs [{label, solver, precision,
//                 rtol, atol, steps_per_contact, dt?, options?}], claims [name], searches [name],
//                 fingerprint (of all the above), name, path, repeats, repeat_below,
//                 work_precision [observable or "worst"], diff {error_factor, work_factor,
//                 time_factor, time_floor}
//   totals        rhs_evals, solver_runs, wall_seconds, failed_records
//   external_solvers?  {solver line: {command, handshake}}
//   trajectories? [{label, file, inputs, failure?, OBSERVABLE: {value, truth, rel_error,
//                 rel_sampling, verdict, why?}, notes}]
//   claims        [{name, verdict, expect, kind, where, quote, figure, measured, bound, margin,
//                 meaning, worse, worst, grid, note, observable, solver, supported, allow_missing,
//                 cells, failed_cells, missing_cells, without_value [{cell, why, failed}],
//                 denser? {verdict, measured, margin, worst, grid, note, cells, ...},
//                 orders? [{p, order, coefficient}]}]
//   searches      [{name, where, quote, solver, parameter, observable, measured, bound,
//                 solver_runs, groups [{group, loosest, failing, measured, worst,
//                 worst_onset_phase, failing_measured, failing_onset_phase, trials, scanned,
//                 onset_phases, every_phase, solver_runs, note}]}]
//   budgets       points_order, worst [{config, observable, max_abs, max_rel, worst_cell,
//                 max_phase_spread?}], maps [{config, observable, max_rel [per point]}],
//                 analytic_double [{p, damping, alpha_eff, max_rel {OBSERVABLE}, not_representable,
//                 log_rel, seconds, truth?, truth_error?, no_truth?}], cost_per_cell [{config,
//                 underdamped and overdamped {cells, rhs_evals, steps, seconds, seconds_slowest}}],
//                 work_precision [{config, solver, p, seconds, rhs_evals, analytic_seconds,
//                 x_analytic, max_rel, cells, skipped_cells, cells_without, by_observable
//                 {OBSERVABLE: {max_rel, cells_without}}}], step_study? {dt_crit_over_tau0,
//                 dt_tangent_over_tau0, sweeps [{line, onset_phases, solver_runs, per_p [{p,
//                 order_e, needed [{target, steps_per_contact, tau_over_dt, within_sweep, returns,
//                 from_sweep}], dt_over_tau_and_worst_rel}], per_point [{p, damping, needed}]}]}
//   records       [{key, config, precision, p, damping, alpha_eff, alpha, v0, m, k, contact?,
//                 outcome, failed, steps, rhs_evals, wall_seconds, wall_seconds_slowest,
//                 cpu_seconds?, cpu_seconds_slowest?, alpha_digits?, dt?, value, reference,
//                 error, rel_error, phase_spread? {OBSERVABLE}, phases?, failure?, skipped?,
//                 note?, replica_difference?}], one record per line
//   figures       [{kind, title, x, y, max_deviation, deviation_of, series [{title, closed_form,
//                 points}], failure?, table?}]
// A work-precision point is extended compatibly: schema 2 had config, solver, p, seconds,
// rhs_evals, analytic_seconds, x_analytic and max_rel (the worst of all observables); cells,
// skipped_cells, cells_without and by_observable came later, and a reader takes a point without
// them as before (nothing of them to check).
#pragma once

#include "common/record_consistency.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <functional>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pldamp::harness::schema {

// The version of report.json. 2: scene fingerprints and diff thresholds, records' reference and
// signed error, cost per regime, searches. 3: records' CPU time (what diff judges), no abs_error
// (|error|), one record per line.
inline constexpr int version = 3;

// The keys of report.json, each spelled here once (the layout above says where each stands).
namespace key {
// The top level.
inline constexpr const char* schema = "schema";
inline constexpr const char* run = "run";
inline constexpr const char* scene = "scene";
inline constexpr const char* totals = "totals";
inline constexpr const char* external_solvers = "external_solvers";
inline constexpr const char* trajectories = "trajectories";
inline constexpr const char* claims = "claims";
inline constexpr const char* searches = "searches";
inline constexpr const char* budgets = "budgets";
inline constexpr const char* records = "records";
inline constexpr const char* figures = "figures";
// run (what made the report: common/provenance.hpp); its command line is `command`
inline constexpr const char* build = "build";
inline constexpr const char* date = "date";
inline constexpr const char* host = "host";
inline constexpr const char* scene_checksum = "scene_checksum";
// scene
inline constexpr const char* end = "end";
inline constexpr const char* observables = "observables";
inline constexpr const char* grid = "grid";
inline constexpr const char* p = "p";
inline constexpr const char* v0 = "v0";
inline constexpr const char* m = "m";
inline constexpr const char* k = "k";
inline constexpr const char* damping_exponent = "damping_exponent";
inline constexpr const char* contacts = "contacts";
inline constexpr const char* contact = "contact";
inline constexpr const char* geometry = "geometry";
inline constexpr const char* R_eff = "R_eff";
inline constexpr const char* E_eff = "E_eff";
inline constexpr const char* rayleigh_time = "rayleigh_time";
inline constexpr const char* units = "units";
inline constexpr const char* damping = "damping";
inline constexpr const char* label = "label";
inline constexpr const char* alpha_eff = "alpha_eff";
inline constexpr const char* overdamped = "overdamped";
inline constexpr const char* configs = "configs";
inline constexpr const char* solver = "solver";
inline constexpr const char* precision = "precision";
inline constexpr const char* rtol = "rtol";
inline constexpr const char* atol = "atol";
inline constexpr const char* steps_per_contact = "steps_per_contact";
inline constexpr const char* dt = "dt";
inline constexpr const char* options = "options";
inline constexpr const char* fingerprint = "fingerprint";
inline constexpr const char* name = "name";
inline constexpr const char* path = "path";
inline constexpr const char* repeats = "repeats";
inline constexpr const char* repeat_below = "repeat_below";
inline constexpr const char* work_precision = "work_precision";
inline constexpr const char* diff = "diff";
inline constexpr const char* error_factor = "error_factor";
inline constexpr const char* work_factor = "work_factor";
inline constexpr const char* time_factor = "time_factor";
inline constexpr const char* time_floor = "time_floor";
// totals, external_solvers
inline constexpr const char* rhs_evals = "rhs_evals";
inline constexpr const char* solver_runs = "solver_runs";
inline constexpr const char* wall_seconds = "wall_seconds";
inline constexpr const char* failed_records = "failed_records";
inline constexpr const char* command = "command";
inline constexpr const char* handshake = "handshake";
// trajectories
inline constexpr const char* file = "file";
inline constexpr const char* inputs = "inputs";
inline constexpr const char* failure = "failure";
inline constexpr const char* value = "value";
inline constexpr const char* truth = "truth";
inline constexpr const char* rel_error = "rel_error";
inline constexpr const char* rel_sampling = "rel_sampling";
inline constexpr const char* verdict = "verdict";
inline constexpr const char* why = "why";
inline constexpr const char* notes = "notes";
// claims
inline constexpr const char* expect = "expect";
inline constexpr const char* kind = "kind";
inline constexpr const char* where = "where";
inline constexpr const char* quote = "quote";
inline constexpr const char* figure = "figure";
inline constexpr const char* measured = "measured";
inline constexpr const char* bound = "bound";
inline constexpr const char* margin = "margin";
inline constexpr const char* meaning = "meaning";
inline constexpr const char* worse = "worse";
inline constexpr const char* worst = "worst";
inline constexpr const char* note = "note";
inline constexpr const char* observable = "observable";
inline constexpr const char* supported = "supported";
inline constexpr const char* allow_missing = "allow_missing";
inline constexpr const char* cells = "cells";
inline constexpr const char* failed_cells = "failed_cells";
inline constexpr const char* missing_cells = "missing_cells";
inline constexpr const char* without_value = "without_value";
inline constexpr const char* cell = "cell";
inline constexpr const char* failed = "failed";
inline constexpr const char* denser = "denser";
inline constexpr const char* orders = "orders";
inline constexpr const char* order = "order";
inline constexpr const char* coefficient = "coefficient";
// searches
inline constexpr const char* parameter = "parameter";
inline constexpr const char* groups = "groups";
inline constexpr const char* group = "group";
inline constexpr const char* loosest = "loosest";
inline constexpr const char* failing = "failing";
inline constexpr const char* trials = "trials";
inline constexpr const char* scanned = "scanned";
inline constexpr const char* onset_phases = "onset_phases";
inline constexpr const char* every_phase = "every_phase";
inline constexpr const char* worst_onset_phase = "worst_onset_phase";
inline constexpr const char* failing_measured = "failing_measured";
inline constexpr const char* failing_onset_phase = "failing_onset_phase";
// budgets
inline constexpr const char* points_order = "points_order";
inline constexpr const char* config = "config";
inline constexpr const char* max_abs = "max_abs";
inline constexpr const char* max_rel = "max_rel";
inline constexpr const char* worst_cell = "worst_cell";
inline constexpr const char* max_phase_spread = "max_phase_spread";
inline constexpr const char* maps = "maps";
inline constexpr const char* analytic_double = "analytic_double";
inline constexpr const char* not_representable = "not_representable";
inline constexpr const char* log_rel = "log_rel";
inline constexpr const char* seconds = "seconds";
inline constexpr const char* truth_error = "truth_error";
inline constexpr const char* no_truth = "no_truth";
inline constexpr const char* cost_per_cell = "cost_per_cell";
inline constexpr const char* underdamped = "underdamped";
inline constexpr const char* steps = "steps";
inline constexpr const char* seconds_slowest = "seconds_slowest";
inline constexpr const char* analytic_seconds = "analytic_seconds";
inline constexpr const char* x_analytic = "x_analytic";
inline constexpr const char* skipped_cells = "skipped_cells";
inline constexpr const char* cells_without = "cells_without";
inline constexpr const char* by_observable = "by_observable";
inline constexpr const char* step_study = "step_study";
inline constexpr const char* dt_crit_over_tau0 = "dt_crit_over_tau0";
inline constexpr const char* dt_tangent_over_tau0 = "dt_tangent_over_tau0";
inline constexpr const char* sweeps = "sweeps";
inline constexpr const char* line = "line";
inline constexpr const char* per_p = "per_p";
inline constexpr const char* per_point = "per_point";
inline constexpr const char* order_e = "order_e";
inline constexpr const char* needed = "needed";
inline constexpr const char* dt_over_tau_and_worst_rel = "dt_over_tau_and_worst_rel";
inline constexpr const char* target = "target";
inline constexpr const char* tau_over_dt = "tau_over_dt";
inline constexpr const char* within_sweep = "within_sweep";
inline constexpr const char* returns = "returns";
inline constexpr const char* from_sweep = "from_sweep";
// records
inline constexpr const char* key = "key";
inline constexpr const char* alpha = "alpha";
inline constexpr const char* outcome = "outcome";
inline constexpr const char* wall_seconds_slowest = "wall_seconds_slowest";
inline constexpr const char* cpu_seconds = "cpu_seconds";
inline constexpr const char* cpu_seconds_slowest = "cpu_seconds_slowest";
inline constexpr const char* alpha_digits = "alpha_digits";
inline constexpr const char* reference = "reference";
inline constexpr const char* error = "error";
inline constexpr const char* abs_error = "abs_error";
inline constexpr const char* phase_spread = "phase_spread";
inline constexpr const char* phases = "phases";
inline constexpr const char* skipped = "skipped";
inline constexpr const char* replica_difference = "replica_difference";
// figures
inline constexpr const char* title = "title";
inline constexpr const char* x = "x";
inline constexpr const char* y = "y";
inline constexpr const char* max_deviation = "max_deviation";
inline constexpr const char* deviation_of = "deviation_of";
inline constexpr const char* series = "series";
inline constexpr const char* closed_form = "closed_form";
inline constexpr const char* points = "points";
inline constexpr const char* table = "table";
} // namespace key

// The words of a claim's verdict and expect ("partial": holds on some cells only, the others
// without a value) and of its "worse" (which way its measured value worsens).
namespace word {
inline constexpr const char* holds = "holds";
inline constexpr const char* fails = "fails";
inline constexpr const char* partial = "partial";
inline constexpr const char* lower = "lower";
inline constexpr const char* higher = "higher";
} // namespace word

// A record's identity across runs: its configuration and its cell, as a record's fields hold
// them (config, p, damping, v0, m, k). Its key is made of them; a reader takes them back from
// the fields, never by splitting the key (a configuration's label may hold " | ").
struct RecordId {
  std::string config; // the configuration's label
  double p = 0;
  std::string damping; // the damping's label, "e=0.5", "z=2"
  double v0 = 0, m = 0, k = 0;
};
// "p=2 e=0.5 v0=1 m=1 k=1": numbers in their shortest round-trip form.
std::string cell_text(const RecordId& id);
// "CONFIGURATION | CELL": a record's key.
std::string record_key(const RecordId& id);
// From a record's fields; none when one is missing or of another type.
std::optional<RecordId> read_record_id(const nlohmann::json& record);

// A number for report.json: null when absent or not finite (JSON has no inf or NaN).
nlohmann::ordered_json number_or_null(const std::optional<double>& x);

// The most JSON values and keys read_report keeps of a report's text outside its records (and of
// records read before its schema): its tree takes 32 bytes a number in an array and up to about
// 100 an empty object, where the text takes 2 or 3 (docs/design.md §5: about 800 MB at this
// limit). The nightly's holds 62 614; diff's default (judge/diff.hpp, ReportLimits).
inline constexpr std::size_t max_kept_values = std::size_t{1} << 23;

// A report.json's text, parsed and checked for what a reader needs to trust (schema, claims'
// names, verdicts and expectations, records' keys, outcomes, failed flags, errors, precisions,
// counts and times, each record's numbers against each other and its outcome
// (common/record_consistency.hpp), each record's key once, and no key named twice in an object);
// everything else is read defensively (below). Throws InputError naming `path` and the first thing
// amiss, so a damaged or foreign file is one line, exit 2: among them a text outside the records of
// more than `max_values` JSON values.
nlohmann::json read_report(std::string_view text, const std::string& path,
                           std::size_t max_values = max_kept_values);
// The same of a stream, its records checked one at a time and handed to `each` in order rather
// than kept: the tree returned has an empty records array, and a reader that keeps only what it
// needs of each record never holds them all (`pldamp diff` of two nightly reports).
using RecordSink = std::function<void(nlohmann::json&& record)>;
nlohmann::json read_report(std::istream& in, const std::string& path, const RecordSink& each,
                           std::size_t max_values = max_kept_values);
// Whether `error` is read_report's refusal of more than max_values values, which a reader of the
// text outside the records alone (diff's fast reader) says as the general reader would.
bool too_many_values(const std::exception& error);
// The text of one record (a line of pldamp's layout) read as read_report reads a record: no key
// named twice, then check_record.
nlohmann::json read_record(std::string_view text, const std::string& path,
                           const std::string& where);
// A record as read_report checks it (InputError naming `path` and `where`, e.g. "records[3]"),
// and whether a precision's name is one of this build's.
void check_record(const nlohmann::json& record, const std::string& path, const std::string& where);
bool known_precision(std::string_view name);

// A record's objects of a number per observable, and which of ObservedNumbers' numbers
// (common/record_consistency.hpp) each holds.
inline constexpr std::array<std::pair<const char*, std::optional<double> ObservedNumbers::*>, 6>
    observed_number_fields{{{key::value, &ObservedNumbers::value},
                            {key::reference, &ObservedNumbers::reference},
                            {key::error, &ObservedNumbers::error},
                            {key::rel_error, &ObservedNumbers::rel_error},
                            {key::phase_spread, &ObservedNumbers::spread},
                            {key::replica_difference, &ObservedNumbers::replica_difference}}};
// A record's numbers per observable as check_record judges them, each none where it is null,
// absent or not a number; the keys are views of the record's.
std::vector<ObservedNumbers> observed_in(const nlohmann::json& record);

// Reading defensively: a member of an object (null when the object is not one or lacks it), a
// member that is a number (none otherwise: a field absent or null is simply absent), a string
// ("" otherwise), an array (an empty one otherwise).
const nlohmann::json& member_or_null(const nlohmann::json& object, std::string_view key);
std::optional<double> number_in(const nlohmann::json& object, std::string_view key);
std::string string_in(const nlohmann::json& object, std::string_view key);
const nlohmann::json& array_in(const nlohmann::json& object, std::string_view key);

} // namespace pldamp::harness::schema
