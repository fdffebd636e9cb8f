// `pldamp diff --exact OLD NEW`: the reproducibility check (serial against MPI, this machine
// against that one, before and after a refactor). Unlike the regression gate (judge/diff.hpp),
// which rightly lets a value change while its error does not grow, it asks whether two reports
// computed the same: every record, claim, search, budget, figure and the totals, to the last bit,
// but for what timing decides (times, the repeats' runs, × analytic) and what made the report
// (`run`, the scene's path). Both reports are read as streams side by side, a record of each at a
// time, matched by key (a record gone or added is named alone; only records out of step wait for
// their match), so its memory does not grow with the reports: 23 MB for two reports of a 10^6-run
// map (docs/scaling.md, "Diff at size").
//
// Output: a line per difference, then a summary.
//   DIFFERS record | <key> | <path>: <old> -> <new>          (the first three paths of a record)
//   DIFFERS record | <key> | only in <old|new>
//   DIFFERS <claims|searches|budgets|figures|totals|...> | <name or part> | <path>: <old> -> <new>
//   <N> differences (<r> records, <o> other) | identical but for timings and provenance
// Exit 0 when identical, 1 when anything differs, 2 on bad input (as diff).
#pragma once

#include "judge/diff.hpp"

#include <istream>
#include <string>
#include <vector>

namespace pldamp::harness {

struct ExactResult {
  std::vector<std::string> lines; // summary last
  long differences = 0;
};

// `verbose` lists every differing record; otherwise the first 20 and a count of the rest.
ExactResult diff_exact(std::istream& old_report, const std::string& old_path,
                       std::istream& new_report, const std::string& new_path, bool verbose,
                       const ReportLimits& limits = {});

} // namespace pldamp::harness
