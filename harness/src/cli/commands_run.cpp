// `pldamp run SCENE.toml [--out DIR] [--jobs N]` and `pldamp diff OLD.json NEW.json`.
#include "cli/commands.hpp"
#include "report/report.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace pldamp::harness {
namespace {

// A one-line progress bar, redrawn in place (only when stderr is a terminal).
void draw_progress(std::size_t done, std::size_t total) {
  constexpr int width = 40;
  const int filled = static_cast<int>(width * done / total);
  std::cerr << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << done << "/"
            << total << (done == total ? "\n" : "") << std::flush;
}

// The report at `path`, read whole and checked (judge/diff.hpp).
nlohmann::json read_report_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) {
    throw InputError("cannot read report (got " + path + ")");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return read_report(text.str(), path);
}

} // namespace

void run_scene(const RunArgs& args, std::ostream& out, std::ostream& err) {
  const Scene scene = load_scene(args.scene); // every scene error before any work
  const long jobs = args.jobs
                        ? parse_integer("--jobs", *args.jobs)
                        : static_cast<long>(std::max(1u, std::thread::hardware_concurrency()));
  if (jobs < 1 || jobs > 1024) {
    throw InputError("--jobs must be in [1, 1024] (got " + std::to_string(jobs) + ")");
  }
  create_report_folder(args.out); // a folder that cannot be written fails before the work
  const Plan plan = make_plan(scene);
  const bool terminal = &err == &std::cerr && isatty(STDERR_FILENO) == 1;
  RunTotals totals;
  const std::vector<Record> records =
      run_plan(plan, static_cast<int>(jobs), totals, terminal ? Progress(draw_progress) : nullptr);
  const Budgets budgets = make_budgets(plan, records);
  const std::vector<Figure> figures = make_figures(scene);
  const RunReport report{plan, records, budgets, totals, figures};
  const std::vector<std::string> written = write_reports(report, args.out);
  out << scene.name << ": " << plan.cells.size() << " cells x " << plan.configs.size()
      << " solver configurations, " << totals.solver_runs << " solver runs, " << totals.rhs_evals
      << " rhs evaluations in " << totals.wall_seconds << " s; " << budgets.failed_records
      << " failed\n";
  for (const Verdict& v : budgets.claims) {
    out << "claim " << v.name << ": " << (v.holds ? "holds" : "fails") << " (measured "
        << v.measured << ", bound " << v.bound << ")\n";
  }
  for (const Figure& figure : figures) {
    if (!figure.failure.empty()) {
      out << "figure " << figure.title << " failed: " << figure.failure << "\n";
    }
  }
  for (const std::string& file : written) {
    out << "report: " << file << "\n";
  }
}

int run_diff(const std::string& old_path, const std::string& new_path, std::ostream& out) {
  const nlohmann::json old_report = read_report_file(old_path);
  const nlohmann::json new_report = read_report_file(new_path);
  const std::vector<std::string> found = regressions(old_report, new_report);
  for (const std::string& line : found) {
    out << line << "\n";
  }
  out << found.size() << " regression" << (found.size() == 1 ? "" : "s") << "\n";
  return found.empty() ? 0 : 1;
}

} // namespace pldamp::harness
