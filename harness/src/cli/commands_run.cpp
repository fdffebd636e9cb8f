// `pldamp run SCENE.toml [--out DIR] [--jobs N]` and `pldamp diff OLD.json NEW.json [--verbose]`.
#include "cli/commands.hpp"
#include "common/files.hpp"
#include "common/report_schema.hpp"
#include "judge/claims.hpp"
#include "judge/diff.hpp"
#include "judge/step_study.hpp"
#include "report/report.hpp"
#include "run/parallel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <type_traits>
#include <unistd.h>
#include <variant>

namespace pldamp::harness {
namespace {

// Progress on stderr: a bar redrawn in place on a terminal; otherwise (a CI log) a line every
// 5 s with the rate so far and the time left at that rate.
class ProgressLines {
public:
  explicit ProgressLines(bool terminal) : terminal_(terminal) {}

  void operator()(std::size_t done, std::size_t total) {
    if (terminal_) {
      constexpr int width = 40;
      const int filled = static_cast<int>(width * done / total);
      std::cerr << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
                << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << done << "/"
                << total << fmt::format(", about {:.0f} s left  ", left(done, total))
                << (done == total ? "\n" : "") << std::flush;
      return;
    }
    const double elapsed = seconds_since(start_);
    if (elapsed - last_ < (last_ == 0 ? 1 : 5) || done == total) {
      return;
    }
    last_ = elapsed;
    std::cerr << fmt::format("{:.0f} s: {}/{} records, about {:.0f} s left\n", elapsed, done, total,
                             left(done, total))
              << std::flush;
  }

private:
  double left(std::size_t done, std::size_t total) const {
    return seconds_since(start_) / double(done) * double(total - done);
  }
  static double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }
  bool terminal_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double last_ = 0;
};

// SIGINT and SIGTERM during a run: the handler only records the signal and asks the run to stop
// (run/run.hpp); the previous handlers come back when the run is over.
std::atomic<int> caught_signal{0};

extern "C" void on_stop_signal(int signal) {
  caught_signal.store(signal);
  stop_requested().store(true);
}

class StopOnSignals {
public:
  StopOnSignals() {
    caught_signal = 0;
    stop_requested() = false;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
  }
  ~StopOnSignals() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
  }
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

  // 128 + the signal once one came (the shell's convention: 130 for SIGINT, 143 for SIGTERM).
  std::optional<int> exit_code() const {
    const int signal = caught_signal.load();
    return signal != 0 ? std::optional<int>(128 + signal) : std::nullopt;
  }

private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

// The grid's cells, counted before any is built (as a double: a hostile grid overflows long).
double grid_cells(const Scene& scene) {
  const double scales = scene.contacts.empty() ? double(scene.v0.size()) * double(scene.m.size()) *
                                                     double(scene.k.size())
                                               : double(scene_scales(scene).size());
  return double(scene.p.size()) * double(scene.damping.size()) * scales;
}

double claim_grid_cells(const ClaimGrid& grid) {
  const double scales = grid.scales.empty()
                            ? double(grid.v0.size()) * double(grid.m.size()) * double(grid.k.size())
                            : double(grid.scales.size());
  return double(grid.p.size()) * double(grid.damping.size()) * scales;
}

// The solver runs of a claim judged on cells of its own, at what each costs per cell
// (claims.hpp): a bound on a solver over a grid of its own, or ten times denser, solved for it
// alone; a solve or two per cell of a solver's relation (a closed-form evaluation, of about a
// solve's cost, for the truth's), a bisection (about 20 solves) for a recovered α, a scan and
// bisection (about 40) for a largest stable step.
double claim_runs(const Claim& claim) {
  const auto over = [&](auto&& cells) {
    return cells(claim.grid) + (claim.denser ? cells(denser_grid(claim.grid)) : 0);
  };
  const auto solves_over = [&](double solves) { return solves * over(claim_grid_cells); };
  // τ(α)/τ(0) of a solver: two solves.
  const auto solves_of = [](const MeasuredQuantity& of) {
    return of.solver && of.quantity == Quantity::tau_ratio ? 2.0 : 1.0;
  };
  return std::visit(
      [&](const auto& stated) -> double {
        using Kind = std::decay_t<decltype(stated)>;
        if constexpr (std::is_same_v<Kind, BoundClaim>) {
          return stated.config.onset_phases *
                 ((stated.own_grid ? claim_grid_cells(claim.grid) : 0) +
                  (claim.denser ? claim_grid_cells(denser_grid(claim.grid)) : 0));
        } else if constexpr (std::is_same_v<Kind, ConventionClaim>) {
          return 0; // closed forms
        } else if constexpr (std::is_same_v<Kind, RelationClaim>) {
          return solves_over(solves_of(stated.of));
        } else if constexpr (std::is_same_v<Kind, AsymptoticClaim>) {
          return solves_of(stated.of) *
                 over([&](const ClaimGrid& grid) { return double(grid.p.size()) * stated.points; });
        } else if constexpr (std::is_same_v<Kind, RecoveredParameterClaim>) {
          return solves_over(20);
        } else {
          return solves_over(40);
        }
      },
      claim.kind);
}

// The solver runs a scene asks for: cells × (each configuration's onset phases) × repeats, claim
// configurations included; and the claims judged on grids of their own (claim_runs).
double planned_runs(const Scene& scene) {
  // Per cell: each configuration at each onset phase, pldamp's own solvers once per timing repeat
  // (an external program answers once: run.cpp).
  double per_cell = 0;
  for (const SolverConfig& config : scene.configs) {
    per_cell += config.onset_phases * (config.external() ? 1 : scene.repeats);
  }
  double claim_solves = 0;
  for (const Claim& claim : scene.claims) { // a configuration of its own, as make_plan adds it
    const BoundClaim* bound = claim.on_plan();
    const bool own = bound != nullptr && std::find(scene.configs.begin(), scene.configs.end(),
                                                   bound->config) == scene.configs.end();
    per_cell +=
        own ? bound->config.onset_phases * (bound->config.external() ? 1 : scene.repeats) : 0;
    claim_solves += claim_runs(claim);
  }
  double search_runs = 0;
  for (const Search& search : scene.searches) {
    search_runs += search_runs_estimate(search);
  }
  search_runs += step_study_runs_estimate(scene); // the time-step study's searches
  return grid_cells(scene) * per_cell + claim_solves + search_runs;
}

// The report at `path`, opened to be read (common/report_schema.hpp checks it as it is read).
std::ifstream open_report(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) {
    throw InputError("cannot read report (got " + path + ")");
  }
  return in;
}

} // namespace

int run_scene(const RunArgs& args, std::ostream& out, std::ostream& err) {
  Scene scene = load_scene(args.scene); // every scene error before any work
  const long jobs =
      args.jobs ? parse_integer("--jobs", *args.jobs) : static_cast<long>(all_cores());
  if (jobs < 1 || jobs > 1024) {
    throw InputError("--jobs must be in [1, 1024] (got " + std::to_string(jobs) + ")");
  }
  auto limit = [](const char* flag, const std::optional<std::string>& text, long& into) {
    if (text) {
      into = parse_integer(flag, *text);
      if (into < 1 || into > 1000000000000L) {
        throw InputError(std::string(flag) + " must be in [1, 1e12] (got " + *text + ")");
      }
    }
  };
  // As [limits] in the scene (scene.cpp, read_limits): a limit on nothing that runs is refused.
  const bool own_solves = solves_with_pldamp(scene);
  if (args.max_steps && !own_solves) {
    throw InputError("--max-steps has no effect: the scene runs none of pldamp's solvers (an "
                     "external program is given no step limit) (got " +
                     *args.max_steps + ")");
  }
  if (args.max_seconds && !own_solves && scene.configs.empty()) {
    throw InputError("--max-seconds has no effect: the scene solves nothing (its claims and "
                     "trajectories are judged by the closed forms) (got " +
                     *args.max_seconds + ")");
  }
  limit("--max-steps", args.max_steps, scene.limits.max_steps);
  limit("--max-runs", args.max_runs, scene.limits.max_runs);
  if (args.max_seconds) {
    const double seconds = parse_real<double>("--max-seconds", *args.max_seconds);
    if (!(seconds > 0 && seconds <= 86400)) {
      throw InputError("--max-seconds must be in (0, 86400] (got " + *args.max_seconds + ")");
    }
    scene.limits.max_seconds = seconds;
  }
  // The plan's size, refused beyond the limit before anything is built, else printed first.
  const double runs = planned_runs(scene);
  const double cells = grid_cells(scene);
  const double configs = double(scene.configs.size() + scene.claims.size());
  const double megabytes =
      (cells * configs *
           (sizeof(Record) + 4 * sizeof(std::optional<double>) * observable_table().size()) +
       cells * sizeof(Cell)) /
      1e6;
  if (runs > double(scene.limits.max_runs)) {
    throw InputError(fmt::format("the plan has {:.0f} solver runs, above the limit of {}: shrink "
                                 "the grid, or raise the limit with --max-runs or [limits] "
                                 "max_runs (got {})",
                                 runs, scene.limits.max_runs, args.scene));
  }
  require_writable_folder(args.out); // a folder that cannot be written fails before the work
  const auto grid_claims =
      std::count_if(scene.claims.begin(), scene.claims.end(), [](const Claim& c) {
        const BoundClaim* bound = std::get_if<BoundClaim>(&c.kind);
        const ConventionClaim* convention = std::get_if<ConventionClaim>(&c.kind);
        return bound ? bound->own_grid || c.denser : !convention || convention->own_grid;
      });
  // With repeats, an upper bound: a run of repeat_below or more is not repeated.
  out << fmt::format("{}: {:.0f} cells x {:.0f} solver configurations{}: {}{:.0f} solver runs "
                     "(onset phases, repeats{} included), about {:.3g} MB of records\n",
                     scene.name, cells, double(scene.configs.size()),
                     grid_claims > 0 ? fmt::format(", {} claims on grids of their own", grid_claims)
                                     : "",
                     scene.repeats > 1 ? "at most " : "", runs,
                     grid_claims > 0 || !scene.searches.empty()
                         ? " and the claims' and searches' solves, estimated"
                         : "",
                     megabytes)
      << std::flush;
  const StopOnSignals signals;
  const Plan plan = make_plan(scene);
  const bool terminal = &err == &std::cerr && isatty(STDERR_FILENO) == 1;
  RunTotals totals;
  const std::vector<Record> records =
      run_plan(plan, static_cast<int>(jobs), totals, Progress(ProgressLines(terminal)));
  if (const std::optional<int> code = signals.exit_code()) {
    err << "stopped by a signal: no report written, " << args.out << " left as it was\n";
    return *code;
  }
  const Budgets budgets = make_budgets(plan, records, static_cast<int>(jobs));
  const std::vector<Figure> figures = make_figures(scene, static_cast<int>(jobs));
  std::vector<TrajectoryCheck> trajectories;
  for (const TrajectorySpec& spec : scene.trajectories) {
    trajectories.push_back(check_trajectory(spec, scene.end));
  }
  const RunReport report{plan, records, budgets, totals, figures, &trajectories};
  if (const std::optional<int> code = signals.exit_code()) {
    err << "stopped by a signal: no report written, " << args.out << " left as it was\n";
    return *code;
  }
  const WrittenReports files = write_reports(report, args.out, static_cast<int>(jobs));
  out << scene.name << ": " << plan.cells.size() << " cells x " << plan.configs.size()
      << " solver configurations, " << totals.solver_runs << " solver runs, " << totals.rhs_evals
      << " rhs evaluations in " << totals.wall_seconds << " s; " << budgets.failed_records
      << " failed\n";
  long unexpected = 0;
  for (const Verdict& v : budgets.claims) {
    unexpected += v.unexpected() ? 1 : 0;
    out << "claim " << v.name << ": " << verdict_text(v)
        << (v.unexpected() ? (v.expect_holds ? " (UNEXPECTED)" : " (UNEXPECTED: pinned as fails)")
                           : (v.holds ? "" : " (expected)"))
        << fmt::format(" (measured {:.4g}, bound {:.4g}", v.measured, v.bound)
        << (v.worst.empty() ? "" : "; worst at " + v.worst) << ")";
    if (v.denser && verdict_text(*v.denser) != verdict_text(v)) {
      out << "; on the denser grid it " << verdict_text(*v.denser);
    }
    out << "\n";
  }
  for (const SearchResult& search : budgets.searches) {
    for (const SearchGroup& group : search.groups) {
      out << "search " << search.name << ", " << group.group << ": "
          << (group.loosest ? fmt::format("{} = {:.3g}", search.parameter, *group.loosest)
                            : std::string("none in the range"))
          << (group.failing ? fmt::format(" (breaks at {:.3g})", *group.failing) : "")
          << fmt::format(", {} solver runs", group.solver_runs)
          << (group.note.empty() ? "" : "; " + group.note) << "\n";
    }
  }
  for (const Figure& figure : figures) {
    if (!figure.failure.empty()) {
      out << "figure " << figure.title << " failed: " << figure.failure << "\n";
    }
  }
  for (const std::string& file : files.written) {
    out << "report: " << file << "\n";
  }
  if (!files.failures.empty()) {
    throw InputError(files.failures.front() +
                     (files.written.empty() ? "" : "; the other formats were written"));
  }
  if (args.strict && unexpected > 0) {
    err << "--strict: " << unexpected << " claim"
        << (unexpected == 1 ? "'s verdict is" : "s' verdicts are") << " not the one expected\n";
    return 1;
  }
  return 0;
}

int run_diff(const DiffArgs& args, std::ostream& out) {
  DiffOptions options;
  options.allow_scene_change = args.allow_scene_change;
  options.verbose = args.verbose;
  const auto threshold = [](const char* flag, const std::optional<std::string>& text, double least,
                            bool inclusive) -> std::optional<double> {
    if (!text) {
      return std::nullopt;
    }
    const double value = parse_real<double>(flag, *text);
    if (!(inclusive ? value >= least : value > least) || !(value <= 1e6)) {
      throw InputError(fmt::format("{} must be in {}{}, 1e6] (got {})", flag, inclusive ? "[" : "(",
                                   least, *text));
    }
    return value;
  };
  options.error_factor = threshold("--error-factor", args.error_factor, 1, false);
  options.work_factor = threshold("--work-factor", args.work_factor, 1, false);
  options.time_factor = threshold("--time-factor", args.time_factor, 1, false);
  options.time_floor = threshold("--time-floor", args.time_floor, 0, true);
  std::ifstream old_report = open_report(args.old_path);
  std::ifstream new_report = open_report(args.new_path);
  const DiffResult result =
      diff_reports(old_report, args.old_path, new_report, args.new_path, options);
  for (const std::string& line : result.lines) {
    out << line << "\n";
  }
  return result.regressions > 0 ? 1 : 0;
}

} // namespace pldamp::harness
