// The commands of the command line, their flags read (cli/cli.cpp): each calls one function of
// the stages below and writes what it returns.
#pragma once

#include "ask/ask.hpp"
#include "judge/trajectory.hpp"
#include "pldamp/harness/distribution.hpp"
#include "scene/scene.hpp"

#include <array>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace pldamp::harness {

// `pldamp run`: a scene, its plan, its reports.
struct RunArgs {
  std::string scene;
  std::string out = "report";
  std::optional<std::string> jobs; // default: the cores
  // The scene's [limits], overridden.
  std::optional<std::string> max_steps, max_seconds, max_runs;
  bool strict = false; // exit 1 when a claim's verdict is not the one expected (a CI gate)
  std::optional<std::string> shard; // "K/N": this run solves shard K of N (merged by merge)
};

// `pldamp merge DIR_1 ... DIR_N --out DIR`: the shards of one run (run with --shard), one
// report, the serial run's but for times.
struct MergeArgs {
  std::vector<std::string> shards;
  std::string out = "report";
  std::optional<std::string> jobs;
  bool strict = false;
};

// The questions of ask/ask.hpp, answered and written as text or, with --json, one JSON line.
void run_calibrate(const ContactArgs& args, std::ostream& out);
void run_observables(const ContactArgs& args, std::ostream& out);
void run_solve(const SolveArgs& args, std::ostream& out);
void run_timestep(const TimestepArgs& args, std::ostream& out);
void run_showcase(const std::string& precision, std::ostream& out);
// The commands of pipeline/pipeline.hpp and judge/diff.hpp, their flags parsed (cli/
// commands_run.cpp): run_scene, merge_shards and diff_files' exit codes.
int run_command(const RunArgs& args, std::ostream& out, std::ostream& err,
                Distribution* distribution = nullptr, std::ostream* progress = nullptr);
int merge_command(const MergeArgs& args, std::ostream& out, std::ostream& err);

struct DiffArgs {
  std::string old_path, new_path;
  std::optional<std::string> error_factor, work_factor, time_factor, time_floor;
  bool allow_scene_change = false, verbose = false;
  bool exact = false; // judge/diff_exact.hpp: every value to the last bit, timings aside
};
// Returns the exit code: 1 if NEW regressed against OLD (or differs from it, --exact), else 0.
int diff_command(const DiffArgs& args, std::ostream& out);

// `pldamp check TRAJECTORY.csv`: one contact's time series against the closed forms
// (judge/trajectory.hpp). The contact options without --precision and --damping-exponent: the
// truth is the seed's closed forms, in Exact.
struct CheckArgs {
  std::string trajectory;
  ContactArgs contact;
  // One relative tolerance for every observable, or "e=1e-3,tau=1e-2": judged, exit 1 on a fail.
  std::optional<std::string> tolerance;
};
// Returns the exit code: 0, or 1 when an observable judged under --tolerance fails. A file that
// contradicts its arguments (judge/trajectory.hpp: contradiction()) is an InputError.
int run_check(const CheckArgs& args, std::ostream& out);

} // namespace pldamp::harness
