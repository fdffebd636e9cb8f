// `pldamp run SCENE.toml [--out DIR] [--jobs N]` and `pldamp diff OLD.json NEW.json [--verbose]`.
#include "cli/commands.hpp"
#include "common/files.hpp"
#include "common/parallel.hpp"
#include "common/report_schema.hpp"
#include "judge/claims.hpp"
#include "judge/diff.hpp"
#include "judge/diff_exact.hpp"
#include "judge/step_study.hpp"
#include "report/report.hpp"
#include "run/record_check.hpp"
#include "run/record_store.hpp"
#include "run/shard.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>
#include <type_traits>
#include <unistd.h>
#include <variant>

namespace pldamp::harness {

std::string time_left_text(double elapsed_seconds, std::size_t done, std::size_t total) {
  if (done < 16 || done * 100 < total) {
    return "time left not known yet";
  }
  return fmt::format("about {:.0f} s left", elapsed_seconds / double(done) * double(total - done));
}

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
                << total << ", " << left(done, total) << "  " << (done == total ? "\n" : "")
                << std::flush;
      return;
    }
    const double elapsed = seconds_since(start_);
    if (elapsed - last_ < (last_ == 0 ? 1 : 5) || done == total) {
      return;
    }
    last_ = elapsed;
    std::cerr << fmt::format("{:.0f} s: {}/{} records, {}\n", elapsed, done, total,
                             left(done, total))
              << std::flush;
  }

private:
  std::string left(std::size_t done, std::size_t total) const {
    return time_left_text(seconds_since(start_), done, total);
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
  stop_signal().store(signal);
  stop_requested().store(true);
}

// 128 + the signal that stopped the run on another rank (SIGINT's when it is not known).
int stopped_elsewhere_code() {
  const int signal = stop_signal().load();
  return 128 + (signal > 0 ? signal : SIGINT);
}

class StopOnSignals {
public:
  StopOnSignals() {
    caught_signal = 0;
    stop_signal() = 0;
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

// The solves of a scene's claims judged on grids of their own (claim_runs) and of its searches and
// time-step study, estimated: one process makes them in a shard set (merge), the ranks share them
// under MPI.
double claim_and_search_runs(const Scene& scene) {
  double runs = step_study_runs_estimate(scene); // the time-step study's searches
  for (const Claim& claim : scene.claims) {
    runs += claim_runs(claim);
  }
  for (const Search& search : scene.searches) {
    runs += search_runs_estimate(search);
  }
  return runs;
}

// The solver runs a scene asks for: cells × (each configuration's onset phases) × repeats, claim
// configurations included; and claim_and_search_runs.
double planned_runs(const Scene& scene) {
  // Per cell: each configuration at each onset phase, pldamp's own solvers once per timing repeat
  // (an external program answers once: run.cpp).
  double per_cell = 0;
  for (const SolverConfig& config : scene.configs) {
    per_cell += config.onset_phases * (config.external() ? 1 : scene.repeats);
  }
  for (const Claim& claim : scene.claims) { // a configuration of its own, as make_plan adds it
    const BoundClaim* bound = claim.on_plan();
    const bool own = bound != nullptr && std::find(scene.configs.begin(), scene.configs.end(),
                                                   bound->config) == scene.configs.end();
    per_cell +=
        own ? bound->config.onset_phases * (bound->config.external() ? 1 : scene.repeats) : 0;
  }
  return grid_cells(scene) * per_cell + claim_and_search_runs(scene);
}

// The report at `path`, opened to be read (common/report_schema.hpp checks it as it is read).
std::ifstream open_report(const std::string& path) {
  if (const std::optional<std::string> why = unreadable_file(path)) {
    throw InputError("cannot read report: " + *why + " (got " + one_line(path) + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError("cannot read report (got " + one_line(path) + ")");
  }
  return in;
}

} // namespace

namespace {

// The scene of `pldamp run` with the command line's limits in place, checked.
Scene scene_with_limits(const RunArgs& args) {
  Scene scene = load_scene(args.scene); // every scene error before any work
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
  return scene;
}

// --jobs, or every core this process may use: the cores it is bound to (mpirun binds each of a few
// ranks to a core, Slurm a task to its --cpus-per-task), or, unbound, the machine's cores shared
// among the ranks on its node.
int jobs_of(const std::optional<std::string>& text, int ranks_on_node) {
  long jobs = all_cores();
  if (!text && jobs >= static_cast<long>(std::thread::hardware_concurrency())) {
    jobs = std::max(1L, jobs / std::max(ranks_on_node, 1));
  }
  if (text) {
    jobs = parse_integer("--jobs", *text);
  }
  if (jobs < 1 || jobs > 1024) {
    throw InputError("--jobs must be in [1, 1024] (got " + std::to_string(jobs) + ")");
  }
  return static_cast<int>(jobs);
}

// "K/N" of --shard: 1 ≤ K ≤ N ≤ 1e6.
std::pair<std::size_t, std::size_t> parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto bad = [&] {
    return InputError("--shard must be K/N, this run being shard K of N, with 1 <= K <= N <= "
                      "1000000 (got " +
                      text + ")");
  };
  if (slash == std::string::npos) {
    throw bad();
  }
  long k = 0, n = 0;
  try {
    k = parse_integer("--shard", text.substr(0, slash));
    n = parse_integer("--shard", text.substr(slash + 1));
  } catch (const InputError&) {
    throw bad();
  }
  if (!(k >= 1 && k <= n && n <= static_cast<long>(max_shards))) {
    throw bad();
  }
  return {static_cast<std::size_t>(k), static_cast<std::size_t>(n)};
}

// The plan's size, refused beyond the limit before anything is built. The grid's runs are shared
// among `shares` processes (shards or ranks), and among MPI ranks (`judging_shared`) the claims'
// and searches' solves too (run/workers.hpp), which a shard set's merge makes in one process:
// the limit counts one process's.
void check_plan_size(const Scene& scene, const std::string& scene_path, double shares,
                     bool judging_shared) {
  const double runs = planned_runs(scene);
  const double judging = claim_and_search_runs(scene);
  const double grid_runs = runs - judging;
  // The largest share of the grid: a shard of N holds ceil(cells / N) cells.
  const double cells = grid_cells(scene);
  const double grid_share = cells > 0 ? grid_runs * std::ceil(cells / shares) / cells : 0;
  const double per_process = grid_share + (judging_shared ? judging / shares : judging);
  if (per_process > double(scene.limits.max_runs)) {
    throw InputError(fmt::format(
        "the plan has {:.0f} solver runs{}, above the limit of {}: shrink the grid, raise the "
        "limit with --max-runs or [limits] max_runs{} (got {})",
        runs,
        shares <= 1 ? ""
        : judging_shared
            ? fmt::format(", {:.0f} in the largest share of {:.0f} ranks", per_process, shares)
            : fmt::format(", {:.0f} in one of {:.0f} processes (a share of the grid's {:.0f} and "
                          "the {:.0f} of the claims, searches and time-step study, estimated, "
                          "which one process makes)",
                          per_process, shares, grid_runs, judging),
        scene.limits.max_runs, shares > 1 ? "" : ", or share it with --shard or mpirun",
        scene_path));
  }
}

// The plan's size, printed first.
void print_plan_size(const Scene& scene, std::ostream& out) {
  const double runs = planned_runs(scene);
  const double cells = grid_cells(scene);
  // report.json's size, a record a line: about 500 bytes and 125 more per observable wanted
  // (measured: 875 bytes a record for 3 observables, 1 165 for the nightly's 7). The records live
  // in a file that is unlinked as it is made, not in memory (run/record_store.hpp). It said
  // "about 602 MB of records", an in-memory size no run had since.
  const double megabytes = cells * double(scene.configs.size()) *
                           (500 + 125 * double(observables_of(scene.want).size())) / 1e6;
  const auto grid_claims =
      std::count_if(scene.claims.begin(), scene.claims.end(), [](const Claim& c) {
        const BoundClaim* bound = std::get_if<BoundClaim>(&c.kind);
        const ConventionClaim* convention = std::get_if<ConventionClaim>(&c.kind);
        return bound ? bound->own_grid || c.denser : !convention || convention->own_grid;
      });
  // With repeats, an upper bound: a run of repeat_below or more is not repeated. Not with a
  // search or a time-step study, whose solves are estimated (a fixed-step search's onset phases
  // grow where its answer does not settle).
  const bool searches = !scene.searches.empty() || step_study_runs_estimate(scene) > 0;
  out << fmt::format("{}: {:.0f} cells x {:.0f} solver configurations{}: {}{:.0f} solver runs "
                     "(onset phases, repeats{} included); report.json about {:.3g} MB\n",
                     one_line(scene.name), cells, double(scene.configs.size()),
                     grid_claims > 0 ? fmt::format(", {} claims on grids of their own", grid_claims)
                                     : "",
                     searches            ? "about "
                     : scene.repeats > 1 ? "at most "
                                         : "",
                     runs,
                     grid_claims > 0 || searches
                         ? " and the solves of the claims on grids of their own, the searches and "
                           "the time-step study, estimated"
                         : "",
                     megabytes)
      << std::flush;
}

// From the records on: budgets, claims, figures, trajectories, the reports and the summary.
// Under MPI (`workers` shared) every rank judges the claims, searches and step study with rank 0
// (make_budgets, run/workers.hpp); rank 0 alone then goes on, on `jobs` threads.
int report_records(const Plan& plan, RecordRange records, const RunTotals& totals,
                   const Workers& workers, int jobs, const std::string& folder, bool strict,
                   const StopOnSignals& signals, std::ostream& out, std::ostream& err) {
  const Scene& scene = plan.scene;
  const Budgets budgets = make_budgets(plan, records, workers);
  if (workers.shared()) {
    workers.ranks->shared_work_done(false);
  }
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

// A shard's records into its folder, and one line saying so.
int write_shard_run(const RunArgs& args, const Plan& plan, std::size_t index, std::size_t count,
                    int jobs, const Progress& progress, const StopOnSignals& signals,
                    std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  ShardHeader h;
  PlanRunner runner(plan, jobs);
  h.totals.external = runner.external();
  const std::vector<std::size_t> cells = shard_cells(plan.cells.size(), index, count);
  RecordStore records(cells.size() * plan.configs.size(), args.out);
  solve_into(plan, runner, cells, records, jobs, progress);
  if (const std::optional<int> code = signals.exit_code()) {
    err << "stopped by a signal: no shard written, " << one_line(args.out) << " left as it was\n";
    return *code;
  }
  records.seal();
  add_to_totals(records, h.totals);
  h.totals.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  h.build = build_id();
  h.scene_path = plan.scene.path;
  h.scene_text = plan.scene.text;
  h.max_steps = plan.scene.limits.max_steps;
  h.max_runs = plan.scene.limits.max_runs;
  h.max_seconds = plan.scene.limits.max_seconds;
  h.index = index;
  h.count = count;
  h.cells = plan.cells.size();
  h.configs = plan.configs.size();
  write_shard(args.out, h, records);
  if (std::filesystem::exists(std::filesystem::path(args.out) / "report.json")) {
    err << "note: " << one_line(args.out)
        << " also holds an earlier run's report.json; this shard's "
        << "records are " << shard_file_name << ", the report is merge's\n";
  }
  long failed = 0;
  for (const Record& record : RecordRange(records)) {
    failed += record.failed() ? 1 : 0;
  }
  out << fmt::format("{}: shard {}/{}: {} of {} cells x {} solver configurations, {} solver runs "
                     "in {:.3g} s; {} failed\nshard: {} (pldamp merge {} for the report)\n",
                     one_line(plan.scene.name), index, count, cells.size(), plan.cells.size(),
                     plan.configs.size(), h.totals.solver_runs, h.totals.wall_seconds, failed,
                     one_line((std::filesystem::path(args.out) / shard_file_name).string()),
                     count == 1 ? "this folder" : fmt::format("the {} shards' folders", count));
  return 0;
}

} // namespace

int run_scene(const RunArgs& args, std::ostream& out, std::ostream& err,
              Distribution* distribution) {
  if (distribution == nullptr && !args.shard) {
    refuse_tasks_that_are_not_ranks("run");
  }
  const bool distributed = distribution != nullptr && distribution->size() > 1;
  const bool prints = !distributed || distribution->rank() == 0;
  std::optional<std::pair<std::size_t, std::size_t>> shard;
  if (args.shard) {
    shard = parse_shard(*args.shard);
    if (distribution != nullptr) {
      throw InputError("--shard is for job arrays without MPI: under mpirun the ranks share the "
                       "cells themselves (got --shard " +
                       *args.shard + ")");
    }
  }
  // Everything that can refuse the run, on every rank, before any rank solves anything.
  std::optional<Scene> scene;
  std::optional<Plan> plan;
  std::unique_ptr<PlanRunner> runner;
  std::unique_ptr<RecordStore> store;
  int jobs = 1;
  std::string failure;
  std::exception_ptr thrown; // this rank's failure, of its kind (a scene's error prints as serial)
  try {
    jobs = jobs_of(args.jobs, distributed ? distribution->ranks_on_node() : 1);
    scene = scene_with_limits(args);
    const double shares = shard ? double(shard->second) : distributed ? distribution->size() : 1;
    check_plan_size(*scene, args.scene, shares, distributed && !shard);
    if (prints) {
      // A folder that cannot be written fails before the work (a shard's too: it is written).
      require_writable_folder(args.out, shard ? "shard's folder" : "report folder");
      print_plan_size(*scene, out);
    }
  } catch (const std::exception& e) {
    failure = *e.what() != '\0' ? e.what() : "an error without a message"; // empty: ready
    thrown = std::current_exception();
    if (!distributed) {
      throw;
    }
  }
  // Every rank must run rank 0's scene: a node whose copy of the file at the same path differs
  // (or another --max-steps given to some ranks) would put other cells' answers in the report.
  if (distributed) {
    const std::string mine =
        failure.empty()
            ? fmt::format("{:016x}",
                          fnv1a(fmt::format("{}\n{} {} {}", scene->text, scene->limits.max_steps,
                                            scene->limits.max_runs, scene->limits.max_seconds)))
            : "";
    const std::vector<std::string> read = distribution->all_gather(mine);
    if (!mine.empty() && !read.at(0).empty() && mine != read[0]) {
      failure = "this rank read another scene or other limits than rank 0 (" + args.scene +
                " differs between the nodes, or the ranks were given other flags)";
    }
  }
  // Under MPI, twice: before the plan, whose points the ranks compute together (a collective),
  // and after it, once the external programs were started.
  const auto every_rank_ready = [&] {
    std::string why;
    if (distributed && !distribution->all_ready(failure, why)) {
      if (thrown && why == failure) { // this rank's own, said as a serial run says it
        std::rethrow_exception(thrown);
      }
      if (!why.empty()) {
        throw InputError(why);
      }
      return false;
    }
    return true;
  };
  if (!every_rank_ready()) {
    return 2;
  }
  const StopOnSignals signals;
  try {
    PointMap map_points;
    if (distributed) {
      map_points = [&](std::size_t count, const std::function<Point(std::size_t)>& point_at) {
        return points_on_ranks(*distribution, count, point_at, jobs);
      };
    }
    plan = make_plan(*scene, jobs, map_points);
    if (!shard) {
      runner = std::make_unique<PlanRunner>(*plan, jobs);
    }
    if (!shard && (!distributed || distribution->rank() == 0)) { // where the records land
      store = std::make_unique<RecordStore>(plan->cells.size() * plan->configs.size(), args.out);
    }
  } catch (const std::exception& e) {
    failure = *e.what() != '\0' ? e.what() : "an error without a message"; // empty: ready
    thrown = std::current_exception();
    if (!distributed) {
      throw;
    }
  }
  if (!every_rank_ready()) {
    return 2;
  }
  const bool terminal = &err == &std::cerr && isatty(STDERR_FILENO) == 1;
  const Progress progress{ProgressLines(terminal)};
  if (shard) {
    return write_shard_run(args, *plan, shard->first, shard->second, jobs, progress, signals, out,
                           err);
  }
  // The external programs were started with the runner, before every rank agreed to go on.
  const auto start = std::chrono::steady_clock::now();
  bool stopped_elsewhere = false;
  if (distributed) {
    distribution->run(*plan, *runner, store.get(), progress, stopped_elsewhere);
    // Whether any rank was stopped, on every rank: then none goes on to the shared judging. Each
    // says by which signal (0: by another rank's), and the first rank's signal is every rank's.
    const std::vector<std::string> stops = distribution->all_gather(
        stop_requested() || stopped_elsewhere ? std::to_string(stop_signal().load()) : "");
    const bool stopped =
        std::any_of(stops.begin(), stops.end(), [](auto& s) { return !s.empty(); });
    for (const std::string& said : stops) {
      if (!said.empty() && said != "0" && stop_signal().load() == 0) {
        stop_signal() = std::stoi(said);
      }
    }
    stopped_elsewhere = stopped && !signals.exit_code();
    if (stopped) {
      distribution->shared_work_done(false);
    }
    if (distribution->rank() != 0) {
      if (!stopped) { // the claims, searches and step study with rank 0, which holds the records
        const std::vector<Record> none;
        make_budgets(*plan, none, Workers(jobs, distribution));
        distribution->shared_work_done(false);
      }
      if (const std::optional<int> code = signals.exit_code()) {
        return *code;
      }
      return stopped || stop_requested() ? stopped_elsewhere_code() : 0;
    }
  } else {
    solve_into(*plan, *runner, shard_cells(plan->cells.size(), 1, 1), *store, jobs, progress);
  }
  // Stopped: some records were never solved (a store lacks them), so nothing reads them.
  if (const std::optional<int> code = signals.exit_code()) {
    err << "stopped by a signal: no report written, " << one_line(args.out) << " left as it was\n";
    return *code;
  }
  if (stopped_elsewhere) {
    err << "stopped by a signal on another rank: no report written, " << args.out
        << " left as it was\n";
    return stopped_elsewhere_code();
  }
  store->seal();
  RunTotals totals;
  totals.external = runner->external();
  add_to_totals(*store, totals);
  totals.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Under MPI the ranks judge the claims, searches and step study together, then wait in
  // MPI_Finalize without using their cores: rank 0 makes the figures and the reports on the
  // threads of every rank on its node.
  const int tail_jobs =
      distributed ? std::min(1024, jobs * std::max(distribution->ranks_on_node(), 1)) : jobs;
  return report_records(*plan, *store, totals, Workers(jobs, distributed ? distribution : nullptr),
                        tail_jobs, args.out, args.strict, signals, out, err);
}

int merge_shards(const MergeArgs& args, std::ostream& out, std::ostream& err) {
  refuse_tasks_that_are_not_ranks("merge");
  const int jobs = jobs_of(args.jobs, 1);
  for (const std::string& folder : args.shards) {
    std::error_code error;
    if (std::filesystem::weakly_canonical(args.out, error) ==
        std::filesystem::weakly_canonical(folder, error)) {
      throw InputError("--out must not be one of the shards' folders: a shard's folder holds its "
                       "records only (got " +
                       args.out + ")");
    }
  }
  // The headers first (each file's checksum checked): a set that is not one run's is refused
  // before any record is read. The records then go to the store one shard at a time.
  std::vector<ShardHeader> shards;
  for (const std::string& folder : args.shards) {
    shards.push_back(read_shard_records(folder, {}));
  }
  // One run's shards, every one once: what was run, how it was split, by which build.
  const ShardHeader& first = shards.front();
  std::vector<const std::string*> holder(first.count, nullptr);
  for (std::size_t i = 0; i < shards.size(); ++i) {
    const ShardHeader& h = shards[i];
    const std::string& folder = args.shards[i];
    if (h.build != build_id()) {
      throw InputError(fmt::format("{} was written by pldamp {}, this is pldamp {}: merge with the "
                                   "build that ran the shards (got {})",
                                   folder, h.build, build_id(), folder));
    }
    // The scene's text, not its path: one file typed as ./map.toml or /abs/map.toml, or a copy
    // beside the rerun of a failed task, is the same scene. Of the limits, those that change
    // records (a solve's step and time budgets); --max-runs is a guard on the plan's size and
    // changes none: shards run under different ones merge.
    const auto differ = [&](const std::string& what, const std::string& mine,
                            const std::string& theirs) {
      throw InputError(fmt::format("{} and {} are shards of different runs: {} {} and {} (got {})",
                                   args.shards[0], folder, what, mine, theirs, folder));
    };
    if (h.scene_text != first.scene_text) {
      differ("their scene texts differ, checksums", fmt::format("{:016x}", fnv1a(first.scene_text)),
             fmt::format("{:016x}", fnv1a(h.scene_text)));
    }
    if (h.max_steps != first.max_steps) {
      differ("each solve's step budget (--max-steps, [limits] max_steps) is",
             std::to_string(first.max_steps), std::to_string(h.max_steps));
    }
    if (!(h.max_seconds == first.max_seconds)) {
      differ("each solve's time budget (--max-seconds, [limits] max_seconds) is",
             to_string_full(first.max_seconds), to_string_full(h.max_seconds));
    }
    if (h.count != first.count) {
      throw InputError(fmt::format("{} is shard {}/{} and {} is shard {}/{}: one run's shards "
                                   "share their N (got {})",
                                   args.shards[0], first.index, first.count, folder, h.index,
                                   h.count, folder));
    }
    if (holder[h.index - 1] != nullptr) {
      throw InputError(fmt::format("shard {}/{} is given twice (got {} and {})", h.index, h.count,
                                   *holder[h.index - 1], folder));
    }
    holder[h.index - 1] = &folder;
  }
  std::vector<std::size_t> missing;
  for (std::size_t k = 0; k < holder.size(); ++k) {
    if (holder[k] == nullptr) {
      missing.push_back(k + 1);
    }
  }
  if (!missing.empty()) {
    const std::size_t shown = std::min<std::size_t>(missing.size(), 10);
    throw InputError(fmt::format(
        "the shard set is incomplete: {} of {} given, missing shard{} {}{} (got {} folders)",
        shards.size(), first.count, missing.size() == 1 ? "" : "s",
        fmt::join(missing.begin(), missing.begin() + static_cast<std::ptrdiff_t>(shown), ", "),
        missing.size() > shown ? ", ..." : "", shards.size()));
  }
  Scene scene = parse_scene(first.scene_text, first.scene_path);
  scene.limits.max_steps = first.max_steps;
  // The largest guard of the set: each shard's run passed its own.
  scene.limits.max_runs = std::max_element(shards.begin(), shards.end(),
                                           [](const ShardHeader& a, const ShardHeader& b) {
                                             return a.max_runs < b.max_runs;
                                           })
                              ->max_runs;
  scene.limits.max_seconds = first.max_seconds;
  // Before the plan is made, what the shards' header says is held to their scene and to their
  // files' bytes: a hand-made header (its checksum is easy to recompute) of a 10^7-cell grid with
  // max_runs = 1e12 was planned in full (51 s, 1.27 GB) before its cell count was refused. The
  // records the set holds need at least `least_record_bytes` each, so the plan's cells are
  // bounded by the bytes given; the guard is the one the shards' run passed (scene_with_limits).
  if (grid_cells(scene) != double(first.cells)) {
    throw InputError(
        fmt::format("the shards' scene has {:.0f} cells, their header says {} (got {})",
                    grid_cells(scene), first.cells, args.shards[0]));
  }
  double set_bytes = 0;
  for (const std::string& folder : args.shards) {
    std::error_code error;
    set_bytes +=
        double(std::filesystem::file_size(std::filesystem::path(folder) / shard_file_name, error));
  }
  if (double(first.cells) * double(first.configs) * double(least_record_bytes) > set_bytes) {
    throw InputError(fmt::format("the shards' header says {} cells x {} configurations, more "
                                 "records than their {:.0f} bytes can hold: not a set pldamp "
                                 "wrote (got {})",
                                 first.cells, first.configs, set_bytes, args.shards[0]));
  }
  check_plan_size(scene, first.scene_path, double(first.count), false);
  require_writable_folder(args.out);
  const StopOnSignals signals;
  const Plan plan = make_plan(scene, jobs);
  if (plan.cells.size() != first.cells || plan.configs.size() != first.configs) {
    throw InputError(fmt::format("the shards' scene plans {} cells x {} configurations here, "
                                 "{} x {} where they ran (got {})",
                                 plan.cells.size(), plan.configs.size(), first.cells, first.configs,
                                 args.shards[0]));
  }
  // Every record in its place: shard K holds its cells' records (shard_cells), each whole.
  RecordStore records(plan.cells.size() * plan.configs.size(), args.out);
  RunTotals totals;
  totals.external = first.totals.external;
  for (std::size_t i = 0; i < shards.size(); ++i) {
    const ShardHeader& h = shards[i];
    const std::vector<std::size_t> cells = shard_cells(plan.cells.size(), h.index, h.count);
    std::size_t held = 0;
    read_shard_records(args.shards[i], [&](Record&& record, std::string_view bytes) {
      const std::size_t at = record.cell * plan.configs.size() + record.config;
      if (record.cell >= plan.cells.size() || record.config >= plan.configs.size() ||
          record.cell % h.count != h.index - 1 || records.has(at)) {
        throw InputError(fmt::format("{} holds a record of another shard (cell {}) (got {})",
                                     args.shards[i], record.cell, args.shards[i]));
      }
      if (const std::string why = impossible_record(plan, record); !why.empty()) {
        throw InputError(fmt::format("{} holds a record no run of this plan writes (cell {}, {}): "
                                     "{}; run its shard again (got {})",
                                     args.shards[i], record.cell,
                                     plan.configs[record.config].label(), one_line(why, 300),
                                     args.shards[i]));
      }
      records.put_bytes(at, bytes);
      ++held;
    });
    if (held != cells.size() * plan.configs.size()) {
      throw InputError(fmt::format("{} holds {} records, shard {}/{} of this plan has {}: it is "
                                   "incomplete (got {})",
                                   args.shards[i], held, h.index, h.count,
                                   cells.size() * plan.configs.size(), args.shards[i]));
    }
    totals.wall_seconds += h.totals.wall_seconds;
  }
  records.seal();
  add_to_totals(records, totals);
  return report_records(plan, records, totals, jobs, jobs, args.out, args.strict, signals, out,
                        err);
}

int run_diff(const DiffArgs& args, std::ostream& out) {
  if (args.exact) {
    // The gate's thresholds and scene changes mean nothing to a comparison of every bit.
    for (const auto& [flag, given] : {std::pair{"--error-factor", args.error_factor.has_value()},
                                      std::pair{"--work-factor", args.work_factor.has_value()},
                                      std::pair{"--time-factor", args.time_factor.has_value()},
                                      std::pair{"--time-floor", args.time_floor.has_value()},
                                      std::pair{"--allow-scene-change", args.allow_scene_change}}) {
      if (given) {
        throw InputError(std::string(flag) +
                         " goes with the regression gate, not --exact, which compares every "
                         "value to the last bit (got " +
                         flag + " with --exact)");
      }
    }
    std::ifstream old_report = open_report(args.old_path);
    std::ifstream new_report = open_report(args.new_path);
    const ExactResult result =
        diff_exact(old_report, args.old_path, new_report, args.new_path, args.verbose);
    for (const std::string& line : result.lines) {
      out << line << "\n";
    }
    return result.differences > 0 ? 1 : 0;
  }
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
