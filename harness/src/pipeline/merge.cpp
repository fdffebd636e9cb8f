// `pldamp merge`: a job array's shards (run_scene with a Shard) held to one another and to their
// scene, then judged into the report the serial run writes (pipeline/pipeline.hpp).
#include "common/files.hpp"
#include "common/input.hpp"
#include "common/provenance.hpp"
#include "judge/plan_size.hpp"
#include "pipeline/parts.hpp"
#include "pipeline/pipeline.hpp"
#include "run/record_check.hpp"
#include "run/record_store.hpp"
#include "run/shard.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace pldamp::harness {

int merge_shards(const MergeOptions& args, std::ostream& out, std::ostream& err) {
  refuse_tasks_that_are_not_ranks("merge");
  const int jobs = jobs_or_cores(args.jobs, 1);
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
  const SolverRunLimit limit(scene); // the judging's solves, which merge makes
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
  return report_records(plan, records, totals, jobs, jobs, args.out, args.strict, signals, limit,
                        out, err);
}

} // namespace pldamp::harness
