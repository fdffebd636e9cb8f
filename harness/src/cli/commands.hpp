// The analytic subcommands (calibrate, observables, showcase), behind a precision dispatch.
#pragma once

#include "judge/trajectory.hpp"
#include "pldamp/harness/distribution.hpp"
#include "scene/scene.hpp"

#include <array>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace pldamp::harness {

// Options as typed by the user; numbers are parsed later, in the precision asked for.
struct ContactArgs {
  std::string p;
  std::optional<std::string> e, alpha, alpha_eff;
  std::string v0 = "1", m = "1", k = "1";
  // A contact from materials (MATH.md §13, cli/materials.hpp): sphere-sphere|sphere-wall and one
  // value per body (or one for both spheres), in place of --m, --k and --p.
  std::optional<std::string> geometry;
  std::vector<std::string> radius, young, poisson, density;
  std::string precision = "double";
  std::string end = "overlap";
  bool json = false;
  std::optional<std::string> damping_exponent; // β of δ^β δ' (MATH.md §12); none: (p − 1)/2
  std::optional<std::string> code;             // calibrate: a DEM code's convention
  bool limit_damping = false;                  // calibrate --code: its optional force cap on
  // calibrate --code for a velocity-dependent model (MATH.md §12.4): where e(v0) is asked, and
  // the effective radius that LAMMPS's damping entry is divided by.
  std::vector<std::string> speeds;
  std::string reff = "1";
  // calibrate: the options above that only a velocity-dependent --code takes, as given ("--v0 3";
  // the seed's α is scale-free: without such a code they would be ignored, so they are refused).
  std::vector<std::string> speed_options_given;
};

// `pldamp solve`: the contact options plus the solver's.
struct SolveArgs {
  ContactArgs contact;
  std::string solver;
  std::optional<std::string> rtol; // default 1e-8; taylor: the precision's epsilon
  std::optional<std::string> atol, dt, horizon;
  std::string want = "e,delta_max,t_peak,tau,energy,normal_force";
  std::vector<std::string> sample_times;
  std::optional<std::string> steps_per_contact; // fixed-step solvers without --dt (default 50)
  std::optional<std::string> onset_phase;       // fixed-step solvers, in [0, 1)
  std::optional<std::string> tau_as;            // fixed-step solvers: how τ is counted
  std::string max_steps = "1000000";
  std::string max_seconds = "60";
  std::string repeats = "3"; // wall_seconds: the fastest of this many solves
};

// `pldamp timestep`: the contact options plus the question's.
struct TimestepArgs {
  ContactArgs contact; // --code: a DEM code's convention sets α from --e
  std::string scheme;
  std::string tolerance = "0.01";
  std::string observables = "e,delta_max,tau";
  std::string tau_as = "first-step-out"; // the contact time as the user's code measures it
};

// --tau-as's word (common/tau_as.hpp), or InputError naming the choices.
TauAs parse_tau_as(const std::string& word);

void run_timestep(const TimestepArgs& args, std::ostream& out);

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

void run_calibrate(const ContactArgs& args, std::ostream& out);
// "lammps-tsuji|...|lammps-mass-velocity": every --code calibrate takes (the DEM conventions of
// analytic/conventions.hpp, then LAMMPS's velocity-dependent models), for its help and errors.
std::string calibrate_code_names();
void run_observables(const ContactArgs& args, std::ostream& out);
void run_showcase(const std::string& precision, std::ostream& out);
void run_solve(const SolveArgs& args, std::ostream& out);
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
