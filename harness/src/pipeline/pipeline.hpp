// A scene through every stage to its reports (`pldamp run`), and a job array's shards merged into
// the report the serial run writes (`pldamp merge`): what those commands call once cli/ has
// parsed their flags. The last stage (docs/design.md §3): it alone chains scene/ → truth/ → run/
// → judge/ → report/, under MPI too (a Distribution, src/mpi/).
#pragma once

#include "pldamp/harness/distribution.hpp"

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace pldamp::harness {

// This process runs shard `index` (1-based) of `count`, merged by merge_shards.
struct ShardIndex {
  std::size_t index = 1, count = 1;
};

struct RunOptions {
  std::string scene; // the scene file's path
  std::string out = "report";
  // Threads; none: every core this process may use (shared among a node's ranks when unbound).
  std::optional<int> jobs;
  // The scene's [limits], overridden.
  std::optional<long> max_steps, max_runs;
  std::optional<double> max_seconds;
  bool strict = false; // exit 1 when a claim's verdict is not the one expected (a CI gate)
  std::optional<ShardIndex> shard;
  std::ostream* progress = nullptr; // where the progress lines go (none without)
};

// Returns the exit code: 0; 1 under --strict when a claim's verdict is not the one expected (a
// failing claim is otherwise a finding, not an error); or 128 + the signal that stopped the run
// (no report written then). With a distribution of more than one rank (an MPI job), the ranks
// share the plan's cells and rank 0 writes the report; the others print nothing unless they
// alone fail.
int run_scene(const RunOptions& options, std::ostream& out, std::ostream& err,
              Distribution* distribution = nullptr);

// The shards of one run (run_scene with a ShardIndex, every one of them), one report: the serial
// run's but for times.
struct MergeOptions {
  std::vector<std::string> shards; // their folders
  std::string out = "report";
  std::optional<int> jobs;
  bool strict = false;
};
int merge_shards(const MergeOptions& options, std::ostream& out, std::ostream& err);

// A run's progress line's time left at the rate so far, once the rate means something: at least
// 1 % of the records and 16 of them ("time left not known yet" before; a 10^6-run map's first
// line said "1/400000 records, about 486584 s left").
std::string time_left_text(double elapsed_seconds, std::size_t done, std::size_t total);

} // namespace pldamp::harness
