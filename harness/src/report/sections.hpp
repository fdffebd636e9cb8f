// What the report's formats share: report.json's sections that live apart (json_budgets.cpp,
// work_precision.cpp), and the table model (tables.cpp): every table and note is built once here
// and written by report.md (markdown.cpp) and report.html (html.cpp) alike.
#pragma once

#include "common/report_schema.hpp"
#include "report/report.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// report.json's budgets (worst, maps, the analytic layer, cost, work precision, the time-step
// study) and records (json_budgets.cpp); work_precision_json: budgets.work_precision, one point
// per configuration and p with every observable's error and the worst of all
// (work_precision.cpp).
nlohmann::ordered_json budgets_json(const RunReport& report);
nlohmann::ordered_json records_json(const RunReport& report);
nlohmann::ordered_json record_json(const Plan& plan, const Record& record); // one of them
nlohmann::ordered_json work_precision_json(const RunReport& report);

// Each record's text (`line(record, index)`), made on `jobs` threads a block of records each and
// handed to `put` in plan order, a block a piece: report.json's and report.csv's records, which
// were most of a 10^6-record merge's time on one thread.
void put_record_lines(RecordRange records, int jobs, const TextSink& put,
                      const std::function<std::string(const Record&, std::size_t)>& line);
inline constexpr std::size_t record_lines_per_piece = 512;

// A record's identity (schema.hpp): its configuration's label and its cell.
schema::RecordId record_id(const Plan& plan, const Record& record);

// The paragraph that opens report.md and report.html.
inline constexpr std::string_view how_to_read =
    "A cell is one point of the scene's grid: p, a damping (a target e, or alpha_eff), v0, m and "
    "k. Each solver configuration (a solver at one tolerance, precision or step count) solves "
    "every cell once, and its values are compared with the closed forms, computed in float128 "
    "from the damping coefficient exactly as the solver received it (for a damping exponent "
    "other than the seed's, with the reference solve: taylor in float128, whose own error "
    "estimate, a second solve at another order, is in report.json). Errors are relative unless "
    "a column says otherwise; a dash is an observable not asked for or not produced, inf an "
    "answer that should have been finite. A claim is judged over a grid (the scene's, or its "
    "own) into a verdict, the cell where it comes closest to failing, and a margin; what its "
    "measured value and margin are depends on its kind and is said in its line below the "
    "claim table (for a bound on a solver's error: its largest absolute error, the bound "
    "divided by that). A failing claim is a finding: pinned with expect = \"fails\", it is "
    "expected; `run --strict` fails on any verdict other than the expected one. '× analytic' "
    "is a configuration's time per cell as a multiple of the closed forms' time for the same "
    "observables in double. Every record (one cell, one configuration) is in report.json and "
    "report.csv; `pldamp diff OLD.json NEW.json` lists what regressed between two runs.";

// A number for a table: `digits` + 1 significant digits, "inf", or "–" when absent.
std::string short_number(const std::optional<double>& x, int digits = 2);

// A table of text: a header and its rows.
struct MapTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};
// A table over p (rows) × damping (columns), underdamped by α_eff, then the overdamped (sinh
// branch) columns after an empty separator column; `cell` gives each point's text.
MapTable map_table(const Plan& plan, const std::function<std::string(std::size_t point)>& cell);

// "230", "≤ 10" (reached at the coarsest step, or read off an external program's sweep), "> 5000"
// (not reached at the finest): the steps per contact a sweep needs for a target.
std::string step_steps_text(const Plan& plan, const StepSweep& sweep, const StepsNeeded& needed);
// The per-point answers of a sweep, p × damping, "41 / 380 / > 5000".
MapTable step_points_table(const Plan& plan, const StepSweep& sweep);
// How the time-step study's numbers are found and named (report.md and report.html).
std::string step_study_description(const StepStudy& study);

// The spread of e over onset phases at a sweep's coarsest and finest step, "3.1e-02 → 2e-05".
std::string phase_spread_text(const StepSweep& sweep, std::size_t e, std::size_t p_index);

// The closed forms' mean cost per cell in double over the grid.
double mean_analytic_seconds(const Plan& plan);

// One line per observable out of double's range at a point, with its logarithm's error.
std::string unrepresentable_note(const Plan& plan);

// A claim as the reports show it, in the table's order: an unexpected verdict first, then the
// failing claims, then those that hold.
struct ClaimRow {
  std::string name, kind, subject, where, quote, figure, verdict, worst, measured, bound, margin,
      denser, grid, note, meaning;
  std::string without_value; // "Without a value: CELL (why); ..." (empty: none)
  bool holds = false, unexpected = false;
};
std::vector<ClaimRow> claim_rows(const RunReport& report);

// The budget tables, one row per configuration: its worst relative error per observable and
// the cell of its largest; its cost per cell (rhs evaluations by regime, the time of the fastest
// repeat, the slowest's excess over it, the multiple of the closed forms' time).
MapTable error_table(const RunReport& report);
MapTable cost_table(const RunReport& report);
// The searches' answers, one row per group, and what they searched.
MapTable search_table(const RunReport& report);
std::string search_table_note(const RunReport& report);
// The scene's trajectories checked, one row per file and observable (a failed file: one row).
MapTable trajectory_table(const RunReport& report);
// External solvers, one row per solver line: its program, what it said of itself, and its records
// run, skipped (and why), failed, and measured without a truth (and why). Empty: none in the run.
MapTable external_table(const RunReport& report);
// What the two tables' columns mean, a paragraph under them.
std::string budget_table_note(const Plan& plan);

// A scene's contacts from materials (contacts.cpp): one row per contact (its R*, E*, m*, k, speeds
// and Rayleigh time), and one per cell of a contact with its closed forms in SI units and each
// configuration's largest relative error there; empty without contacts.
MapTable contacts_table(const RunReport& report);
MapTable contact_truth_table(const RunReport& report);
std::string contacts_note(const RunReport& report);

// Work precision (work_precision.cpp): the table of report.md (and report.html), one row per p
// and configuration, its cost and the error of each series work_panels chooses, with the cells
// without a value counted; what its columns mean.
MapTable work_precision_table(const RunReport& report);
std::string work_precision_note(const Plan& plan);

} // namespace pldamp::harness
