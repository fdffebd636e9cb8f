// From the records to the reports (pipeline/parts.hpp), for a run and a merge alike.
#include "common/input.hpp"
#include "common/provenance.hpp"
#include "judge/claims.hpp"
#include "judge/figures.hpp"
#include "judge/search.hpp"
#include "judge/trajectory_check.hpp"
#include "pipeline/parts.hpp"
#include "report/report.hpp"

#include <fmt/format.h>

#include <vector>

namespace pldamp::harness {

int report_records(const Plan& plan, RecordRange records, const RunTotals& totals,
                   const Workers& workers, int jobs, const std::string& folder, bool strict,
                   const StopOnSignals& signals, const SolverRunLimit& limit, std::ostream& out,
                   std::ostream& err) {
  const Scene& scene = plan.scene;
  const long solves_before = solver_runs_made();
  const Budgets budgets = make_budgets(plan, records, workers);
  if (workers.shared()) {
    workers.ranks->shared_work_done(false);
  }
  const long judged = judged_solver_runs(solves_before, workers);
  limit.refuse_if_passed(folder);
  const std::vector<Figure> figures = make_figures(scene, jobs);
  std::vector<TrajectoryCheck> trajectories;
  for (const TrajectorySpec& spec : scene.trajectories) {
    trajectories.push_back(check_trajectory(spec, scene.end));
  }
  const Provenance made = provenance_of(scene.text);
  const RunReport report{plan, records, budgets, totals, figures, &trajectories, &made};
  if (const std::optional<int> code = signals.exit_code()) {
    err << "stopped by a signal: no report written, " << one_line(folder) << " left as it was\n";
    return *code;
  }
  if (stop_requested()) { // under MPI: a signal on another rank, in the shared work
    err << "stopped by a signal on another rank: no report written, " << one_line(folder)
        << " left as it was\n";
    return stopped_elsewhere_code();
  }
  const WrittenReports files = write_reports(report, folder, jobs);
  out << one_line(scene.name) << ": " << plan.cells.size() << " cells x " << plan.configs.size()
      << " solver configurations, " << totals.solver_runs << " solver runs, " << totals.rhs_evals
      << " rhs evaluations in " << totals.wall_seconds << " s; " << budgets.failed_records
      << " failed\n";
  if (judged > 0) { // what the plan line counts beside the grid's runs
    out << fmt::format("{}: {} more solves for the claims, searches and time-step study, {} in "
                       "all\n",
                       one_line(scene.name), judged, totals.solver_runs + judged);
  }
  long unexpected = 0;
  for (const Verdict& v : budgets.claims) {
    unexpected += v.unexpected() ? 1 : 0;
    out << "claim " << one_line(v.name) << ": " << verdict_text(v)
        << (v.unexpected() ? (v.expect_holds ? " (UNEXPECTED)" : " (UNEXPECTED: pinned as fails)")
                           : (v.holds ? "" : " (expected)"))
        << fmt::format(" (measured {:.4g}, bound {:.4g}", v.measured, v.bound)
        << (v.worst.empty() ? "" : "; worst at " + one_line(v.worst)) << ")";
    if (v.denser && verdict_text(*v.denser) != verdict_text(v)) {
      out << "; on the denser grid it " << verdict_text(*v.denser);
    }
    out << "\n";
  }
  for (const SearchResult& search : budgets.searches) {
    for (const SearchGroup& group : search.groups) {
      out << "search " << one_line(search.name) << ", " << one_line(group.group) << ": "
          << (group.loosest ? fmt::format("{} = {:.3g}", search.parameter, *group.loosest)
                            : std::string("none in the range"))
          << (group.failing ? fmt::format(" (breaks at {:.3g})", *group.failing) : "")
          << fmt::format(", {} solver runs", group.solver_runs)
          << (group.note.empty() ? "" : "; " + one_line(group.note)) << "\n";
    }
  }
  for (const Figure& figure : figures) {
    if (!figure.failure.empty()) {
      out << "figure " << one_line(figure.title) << " failed: " << one_line(figure.failure) << "\n";
    }
  }
  for (const std::string& file : files.written) {
    out << "report: " << one_line(file) << "\n";
  }
  if (!files.failures.empty()) {
    throw InputError(files.failures.front() + "; " + what_is_on_disk(files, folder));
  }
  if (strict && unexpected > 0) {
    err << "--strict: " << unexpected << " claim"
        << (unexpected == 1 ? "'s verdict is" : "s' verdicts are") << " not the one expected\n";
    return 1;
  }
  return 0;
}

} // namespace pldamp::harness
