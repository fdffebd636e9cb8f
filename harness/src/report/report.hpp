// A run's reports (docs/design.md §5), written into one folder:
//   report.json  complete (schema, scene, totals, claims, budgets, records); the input of diff
//   report.csv   one row per cell and solver configuration
//   report.md    worst errors per observable and configuration, claim verdicts, the
//                work-precision table, the analytic layer's own budget; fit for a CI log
//   report.html  self-contained: the tables and inline SVG plots drawn by gnuplot (error maps
//                over p × α_eff, work-precision diagrams, the claim table); without gnuplot the
//                plots are skipped and the page says so
#pragma once

#include "common/files.hpp"
#include "common/provenance.hpp"
#include "judge/budget.hpp"
#include "judge/figures.hpp"
#include "judge/trajectory.hpp"
#include "run/record_store.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct RunReport {
  const Plan& plan;
  RecordRange records;
  const Budgets& budgets;
  const RunTotals& totals;
  const std::vector<Figure>& figures;
  const std::vector<TrajectoryCheck>* trajectories = nullptr; // the scene's [[trajectory]], checked
  const Provenance* made = nullptr; // what made it (report.json's `run`, the pages' first lines)
};

// Each format on its own (json.cpp, csv.cpp, markdown.cpp, html.cpp); common/report_schema.hpp
// gives report.json's layout and keys, report/sections.hpp the tables report.md and report.html
// share.
nlohmann::ordered_json report_json(const RunReport& report);
// report.json's text: each section indented, and each record on one line of its own (a nightly
// report holds 39 480 records: indented, their line breaks and spaces were a tenth of the file;
// one per line, a record is still one grep away).
std::string report_json_text(const RunReport& report);
std::string report_csv(const RunReport& report);
// The same two texts handed to `put` in pieces as they are made, a record at a time: what
// write_reports writes (a merge of 4·10^5 records held 2.6 GB building report.json whole).
// The records' text is made on `jobs` threads (put_record_lines): the same text for any jobs.
void write_report_json(const RunReport& report, const TextSink& put, int jobs = 1);
void write_report_csv(const RunReport& report, const TextSink& put, int jobs = 1);
std::string report_markdown(const RunReport& report);
// `gnuplot` is the program to draw with; empty or missing: no plots. The plots are drawn on up to
// `jobs` threads; the page does not depend on their number.
std::string report_html(const RunReport& report, const std::string& gnuplot, int jobs = 1);

struct WrittenReports {
  std::vector<std::string> written;  // the files now this run's, in the scene's order
  std::vector<std::string> kept;     // the files left as they were (the previous run's, or none)
  std::vector<std::string> failures; // "cannot write PATH (reason)", one per file that failed
};

// After a failed write_reports, exactly what `folder` holds: every file as it was (none was put
// in place unless all could be), or, a rename having failed, which files are this run's.
std::string what_is_on_disk(const WrittenReports& files, const std::string& folder);

// Writes the scene's formats into `folder` (created if needed) as one set: each is written whole
// under a temporary name, and only when all are, they are renamed into place, report.json last
// (common/files.hpp, StagedFile). A format that cannot be written (a full disk, a file-size
// limit, an error) leaves every file as it was. The formats are made on up to `jobs` threads
// (report.json and report.html take a second or more each for a nightly). `before_stage`, for
// tests, is called with each file's path before it is written: what it throws fails that file.
WrittenReports
write_reports(const RunReport& report, const std::string& folder, int jobs = 1,
              const std::function<void(const std::filesystem::path&)>& before_stage = {});

} // namespace pldamp::harness
