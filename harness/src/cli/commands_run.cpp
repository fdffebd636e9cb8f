// `pldamp run`, `merge` and `diff`: their flags parsed into numbers, and one call each
// (pipeline/pipeline.hpp: run_scene, merge_shards; judge/diff.hpp: diff_files).
#include "cli/commands.hpp"
#include "common/input.hpp"
#include "judge/diff.hpp"
#include "pipeline/pipeline.hpp"
#include "run/shard.hpp"

#include <fmt/format.h>

#include <utility>

namespace pldamp::harness {

namespace {

// A count in [1, 1e12], written as an integer or as --help writes defaults ("1e6").
long count_in_range(const char* flag, const std::string& text) {
  const long value = parse_whole(flag, text);
  if (value < 1 || value > 1000000000000L) {
    throw InputError(std::string(flag) + " must be in [1, 1e12] (got " + text + ")");
  }
  return value;
}

std::optional<int> jobs_of(const std::optional<std::string>& text) {
  if (!text) {
    return std::nullopt;
  }
  const long jobs = parse_integer("--jobs", *text);
  if (jobs < 1 || jobs > 1024) {
    throw InputError("--jobs must be in [1, 1024] (got " + *text + ")");
  }
  return static_cast<int>(jobs);
}

// "K/N" of --shard: 1 ≤ K ≤ N ≤ 1e6.
ShardIndex shard_of(const std::string& text) {
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
  return {.index = static_cast<std::size_t>(k), .count = static_cast<std::size_t>(n)};
}

} // namespace

int run_command(const RunArgs& args, std::ostream& out, std::ostream& err,
                Distribution* distribution, std::ostream* progress) {
  RunOptions options{.scene = args.scene,
                     .out = args.out,
                     .jobs = jobs_of(args.jobs),
                     .max_steps = std::nullopt,
                     .max_runs = std::nullopt,
                     .max_seconds = std::nullopt,
                     .strict = args.strict,
                     .shard = std::nullopt,
                     .progress = progress};
  if (args.shard) {
    options.shard = shard_of(*args.shard);
  }
  if (args.max_steps) {
    options.max_steps = count_in_range("--max-steps", *args.max_steps);
  }
  if (args.max_runs) {
    options.max_runs = count_in_range("--max-runs", *args.max_runs);
  }
  if (args.max_seconds) {
    const double seconds = parse_real<double>("--max-seconds", *args.max_seconds);
    if (!(seconds > 0 && seconds <= 86400)) {
      throw InputError("--max-seconds must be in (0, 86400] (got " + *args.max_seconds + ")");
    }
    options.max_seconds = seconds;
  }
  return run_scene(options, out, err, distribution);
}

int merge_command(const MergeArgs& args, std::ostream& out, std::ostream& err) {
  return merge_shards(
      {.shards = args.shards, .out = args.out, .jobs = jobs_of(args.jobs), .strict = args.strict},
      out, err);
}

int diff_command(const DiffArgs& args, std::ostream& out) {
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
    DiffOptions exact;
    exact.verbose = args.verbose;
    exact.exact = true;
    return diff_files(args.old_path, args.new_path, exact, out);
  }
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
  DiffOptions options;
  options.allow_scene_change = args.allow_scene_change;
  options.verbose = args.verbose;
  options.error_factor = threshold("--error-factor", args.error_factor, 1, false);
  options.work_factor = threshold("--work-factor", args.work_factor, 1, false);
  options.time_factor = threshold("--time-factor", args.time_factor, 1, false);
  options.time_floor = threshold("--time-floor", args.time_floor, 0, true);
  return diff_files(args.old_path, args.new_path, options, out);
}

} // namespace pldamp::harness
