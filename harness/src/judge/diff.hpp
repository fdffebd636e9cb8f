// `pldamp diff OLD.json NEW.json`: what changed between two runs of one scene, and what of it is a
// regression (docs/ci.md gives the output's grammar for CI scripts).
//
// Compared, record by record (same key: configuration and cell):
//   errors      rel_error grown more than error_factor above the precision's noise (16 ε), or
//               fallen to exactly 0 from above it (a value compared with itself): regressions;
//               fallen by more than error_factor: a change
//   numbers     a value, reference, error or spread that was a number and is now null or
//               missing: a regression (a reference that silently disappears)
//   outcomes    a record that now fails, or is gone: regressions
//   work        rhs_evals and steps, deterministic: any change listed, growth above work_factor
//               a regression
//   time        per configuration, the sum of its records' fastest repeats: above time_factor a
//               regression when the old sum is at least time_floor seconds (below it: noise)
// and beyond the records: budgets.worst and the analytic layer's own budget like errors, a
// budget or a work-precision point (per observable) that no longer matches its records
// (inconsistent), a claim whose verdict left the
// expected one, a claim's measured value that moved the wrong way (more than error_factor for an
// error, 10 % for an order, gap or ratio) or disappeared, a search that no longer finds a value.
//
// Output: one line per group (kind of finding, configuration, observable), then a summary.
//   BUILD <old build> -> <new build>    (first, when the reports' run.build differ or one has none)
//   REGRESSION <what> | <configuration, claim or search> | <subject> | <n> <unit>(s) | <worst>
//              [at <cell>]          (the cell for records and the closed forms' points only)
//   CHANGE <what> | ...                                   (the same fields; not a regression)
//   SCENE <added|removed> <configuration|observable|p|v0|m|k|damping|claim|search> | <label>
//   SCENE changed end | <old> -> <new>
//   <N> regressions, <M> changes
// A field's control characters are escaped (\n, \xNN) and a " | " inside it is written " / ", so
// that a name from a scene can neither add a line nor shift the fields; --verbose adds each
// finding under its group's line, indented by two spaces (a record's key keeps its " | ").
// Exit: 0 no regression, 1 regressions, 2 bad input (not a report, a record inconsistent in
// itself, a different scene without --allow-scene-change). A record is judged by its rel_error,
// so each is first held to itself as read_report checks it (common/record_consistency.hpp): a
// rel_error its error, value and reference contradict is refused, not trusted.
#pragma once

#include "common/report_schema.hpp"
#include "scene/scene.hpp"

#include <nlohmann/json.hpp>

#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// The thresholds (scene/scene.hpp, DiffThresholds) come from the new report's scene (its [diff]
// table, written into report.json), each overridden by its flag.
struct DiffOptions {
  std::optional<double> error_factor, work_factor, time_factor, time_floor; // flags
  bool allow_scene_change = false; // compare what two different scenes share
  bool verbose = false;            // every record under its group's line
  // diff_files: the reproducibility check of judge/diff_exact.hpp instead (every value to the
  // last bit; the thresholds and scene changes above mean nothing to it).
  bool exact = false;
};

struct DiffResult {
  std::vector<std::string> lines; // the output, summary last
  long regressions = 0, changes = 0;
  DiffThresholds thresholds; // as applied
  // The most records diff held at once: all of both reports' when it read them whole (another
  // layout than pldamp's, or streams it cannot read again), and when it streamed them only those
  // waiting for the other report's record of their key (none for two reports in one order).
  std::size_t records_held = 0;
};

// Compares two reports, each as schema::read_report (common/report_schema.hpp) checked it. Throws
// InputError when they come from different scenes (their fingerprints differ) and
// `allow_scene_change` is off.
DiffResult diff_reports(const nlohmann::json& old_report, const nlohmann::json& new_report,
                        const DiffOptions& options = {});

// What diff reads of a report stream, whatever it holds: a report begins with '{' after at most
// `leading_space` bytes of white space (what does not is refused by its first bytes: 1 GB of
// blanks read for 36 s and grew to 3.2 GB before, /dev/zero without end); a line of pldamp's
// layout is at most `line` bytes (a record is about 1.2 KB, the scene's longest string 6 MiB
// escaped: a longer line is left to the general reader, never held whole); its text outside the
// records at most `rest` bytes (the nightly's is 1.2 MB), and a report in another layout
// (reformatted by another program) at most `rest` bytes in all; that text's tree at most `values`
// JSON values and keys (schema::read_report; records read before the schema count too), up to
// about 100 bytes each where their text may take 3: the nightly's rest holds 62 614, a map of
// 10^4 points of its 47 configurations would hold about 4.2 million. A report at both limits
// takes about 1 GB (docs/design.md §5). Beyond them, the report is refused with one line.
struct ReportLimits {
  std::size_t leading_space = 4096;
  std::size_t line = std::size_t{16} << 20;
  std::size_t rest = std::size_t{128} << 20;
  std::size_t values = schema::max_kept_values;
};

// The same of two reports read from streams (report.json files), each checked as
// schema::read_report checks it. Two in pldamp's layout are compared as they are read, a record
// of each at a time on a thread each, matched by key (only records out of step wait for their
// match): diff's memory does not grow with them (24 MB for two reports of a 10^6-run map, where
// keeping every record's facts took 770 MB; docs/scaling.md, "Diff at size"). Any other layout,
// or a stream that cannot be read again should the fast reader doubt it, is read whole, each
// record's facts kept.
DiffResult diff_reports(std::istream& old_report, const std::string& old_path,
                        std::istream& new_report, const std::string& new_path,
                        const DiffOptions& options = {}, const ReportLimits& limits = {});

// `pldamp diff OLD NEW`: the two report files compared, the lines written to `out`; returns the
// exit code, 1 when NEW regressed against OLD (with `exact`: differs from it), else 0.
// InputError when either cannot be read or is not a report.
int diff_files(const std::string& old_path, const std::string& new_path, const DiffOptions& options,
               std::ostream& out);

// The REGRESSION lines of diff_reports, scene changes allowed.
std::vector<std::string> regressions(const nlohmann::json& old_report,
                                     const nlohmann::json& new_report);

} // namespace pldamp::harness
