// A run's reports (DESIGN.md "Reports"), written into one folder:
//   report.json  complete (schema, scene, totals, claims, budgets, records); the input of diff
//   report.csv   one row per cell and solver configuration
//   report.md    worst errors per observable and configuration, claim verdicts, the analytic
//                layer's own budget; fit for a CI log
//   report.html  self-contained: the tables and inline SVG plots drawn by gnuplot (error maps
//                over p × α_eff, work-precision diagrams, the claim table); without gnuplot the
//                plots are skipped and the page says so
#pragma once

#include "judge/budget.hpp"
#include "judge/diff.hpp"
#include "judge/figures.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pldamp::harness {

// A number for a table: `digits` + 1 significant digits, "inf", or "–" when absent.
std::string short_number(const std::optional<double>& x, int digits = 2);

struct RunReport {
  const Plan& plan;
  const std::vector<Record>& records;
  const Budgets& budgets;
  const RunTotals& totals;
  const std::vector<Figure>& figures;
};

nlohmann::ordered_json report_json(const RunReport& report);
std::string report_csv(const RunReport& report);
std::string report_markdown(const RunReport& report);
// `gnuplot` is the program to draw with; empty or missing: no plots.
std::string report_html(const RunReport& report, const std::string& gnuplot);

// Creates `folder` if needed; throws InputError if it cannot (checked before a run's work).
void create_report_folder(const std::string& folder);

// Writes the scene's formats into `folder` (created if needed); returns the files written.
std::vector<std::string> write_reports(const RunReport& report, const std::string& folder);

// A record's identity across runs: "configuration | p=.. damping v0=.. m=.. k=.." (diff's key).
std::string record_key(const Plan& plan, const Record& record);

} // namespace pldamp::harness
