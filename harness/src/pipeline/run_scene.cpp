// `pldamp run`: a scene's plan solved (serially, in a shard of a job array, or on MPI ranks) and
// judged into its reports (pipeline/pipeline.hpp).
#include "common/files.hpp"
#include "common/input.hpp"
#include "common/provenance.hpp"
#include "judge/plan_size.hpp"
#include "pipeline/parts.hpp"
#include "pipeline/pipeline.hpp"
#include "run/record_store.hpp"
#include "run/shard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

namespace pldamp::harness {

namespace {

// The scene of `pldamp run` with the command line's limits in place, checked.
Scene scene_with_limits(const RunOptions& args) {
  Scene scene = load_scene(args.scene); // every scene error before any work
  // As [limits] in the scene (scene.cpp, read_limits): a limit on nothing that runs is refused.
  const bool own_solves = solves_with_pldamp(scene);
  if (args.max_steps && !own_solves) {
    throw InputError(fmt::format("--max-steps has no effect: the scene runs none of pldamp's "
                                 "solvers (an external program is given no step limit) (got {})",
                                 *args.max_steps));
  }
  if (args.max_seconds && !own_solves && scene.configs.empty()) {
    throw InputError(fmt::format("--max-seconds has no effect: the scene solves nothing (its "
                                 "claims and trajectories are judged by the closed forms) (got {})",
                                 *args.max_seconds));
  }
  scene.limits.max_steps = args.max_steps.value_or(scene.limits.max_steps);
  scene.limits.max_runs = args.max_runs.value_or(scene.limits.max_runs);
  scene.limits.max_seconds = args.max_seconds.value_or(scene.limits.max_seconds);
  return scene;
}

// A shard's records into its folder, and one line saying so.
int write_shard_run(const RunOptions& args, const Plan& plan, std::size_t index, std::size_t count,
                    int jobs, const Progress& progress, const StopOnSignals& signals,
                    const SolverRunLimit& limit, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  ShardHeader h;
  PlanRunner runner(plan, jobs);
  h.totals.external = runner.external();
  const std::vector<std::size_t> cells = shard_cells(plan.cells.size(), index, count);
  RecordStore records(cells.size() * plan.configs.size(), args.out);
  solve_into(plan, runner, cells, records, jobs, progress);
  limit.refuse_if_passed(args.out);
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

int run_scene(const RunOptions& args, std::ostream& out, std::ostream& err,
              Distribution* distribution) {
  if (distribution == nullptr && !args.shard) {
    refuse_tasks_that_are_not_ranks("run");
  }
  const bool distributed = distribution != nullptr && distribution->size() > 1;
  const bool prints = !distributed || distribution->rank() == 0;
  const std::optional<ShardIndex>& shard = args.shard;
  if (shard && distribution != nullptr) {
    throw InputError(fmt::format("--shard is for job arrays without MPI: under mpirun the ranks "
                                 "share the cells themselves (got --shard {}/{})",
                                 shard->index, shard->count));
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
    jobs = jobs_or_cores(args.jobs, distributed ? distribution->ranks_on_node() : 1);
    scene = scene_with_limits(args);
    const double shares = shard ? double(shard->count) : distributed ? distribution->size() : 1;
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
  const SolverRunLimit limit(*scene);
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
  const Progress progress = progress_on(args.progress);
  if (shard) {
    return write_shard_run(args, *plan, shard->index, shard->count, jobs, progress, signals, limit,
                           out, err);
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
        const long solves_before = solver_runs_made();
        const Workers workers(jobs, distribution);
        make_budgets(*plan, none, workers);
        distribution->shared_work_done(false);
        judged_solver_runs(solves_before, workers); // rank 0 counts every rank's
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
  limit.refuse_if_passed(args.out);
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
                        tail_jobs, args.out, args.strict, signals, limit, out, err);
}

} // namespace pldamp::harness
