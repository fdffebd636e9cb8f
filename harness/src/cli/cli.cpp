#include "pldamp/harness/cli.hpp"

#include "ask/ask.hpp"
#include "cli/commands.hpp"
#include "common/input.hpp"
#include "common/observables.hpp"
#include "common/provenance.hpp"
#include "judge/trajectory.hpp"
#include "scene/scene.hpp"

#include "pldamp/analytic/conventions.hpp"
#include "pldamp/solvers/registry.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

// "double | long | quad | 50"
std::string precision_choices() {
  std::string choices = precision_names();
  for (std::size_t at = choices.find('|'); at != std::string::npos;
       at = choices.find('|', at + 3)) {
    choices.replace(at, 1, " | ");
  }
  return choices;
}

// A contact from materials (MATH.md §13, ask/materials.hpp): in place of --m, --k and --p.
void add_material_options(CLI::App& command, ContactArgs& a) {
  command.add_option("--geometry", a.geometry,
                     "a Hertz contact from materials: sphere-sphere | sphere-wall (SI units)");
  // Lists are split by list_items (common/input.hpp), not by CLI11, which drops an empty item.
  command.add_option("--radius", a.radius, "with --geometry: R1[,R2] > 0 [m]");
  command.add_option("--young", a.young,
                     "with --geometry: E1[,E2] > 0 [Pa] (wall: rigid without E2)");
  command.add_option("--poisson", a.poisson, "with --geometry: nu1[,nu2] in (-1, 0.5)");
  command.add_option("--density", a.density, "with --geometry: rho1[,rho2] > 0 [kg/m^3]");
}

void add_contact_options(CLI::App& command, ContactArgs& a, bool calibrate_only) {
  CLI::Option* p = command.add_option("--p", a.p, "force-law exponent, p >= 1");
  command.add_option("--e", a.e, "coefficient of restitution in (0, 1] under --end");
  command.add_option("--end", a.end, "contact end: overlap (delta = 0) or force (F = 0)");
  command.add_option("--precision", a.precision, precision_choices());
  command.add_flag("--json", a.json, "one JSON object instead of key/value lines");
  p->description("force-law exponent, p >= 1 (1.5 under --geometry)");
  add_material_options(command, a);
  if (calibrate_only) {
    return;
  }
  command.add_option("--alpha", a.alpha, "damping coefficient alpha >= 0");
  command.add_option("--alpha-eff", a.alpha_eff, "effective damping ratio alpha_eff >= 0");
  command.add_option("--damping-exponent", a.damping_exponent,
                     "beta of the dashpot d^beta d' in [0, p] (default (p-1)/2, the seed's)");
  command.add_option("--v0", a.v0, "impact velocity > 0")->required();
  command.add_option("--m", a.m, "reduced mass > 0 (default 1)");
  command.add_option("--k", a.k, "stiffness > 0 (default 1)");
}

// After parsing: every option given, as typed, for settle() (ask/ask.hpp), which checks the
// materials against --m, --k and --p and splits the lists.
void record_given(const CLI::App& command, ContactArgs& a) {
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() > 0 && !option->get_lnames().empty()) {
      a.given.push_back("--" + option->get_lnames().front() + " " +
                        CLI::detail::join(option->results(), ","));
    }
  }
}

// Levenshtein distance, for the option nearest a mistyped one.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// What a command's words say before CLI11 judges them: an option it does not take (named, with
// the nearest it takes: a typo once read "--v0 is required"), or one given twice (CLI11 said
// "At Most 1 required but received 2", or kept the last value of a list such as --poisson).
void refuse_unknown_or_repeated_options(const CLI::App& command,
                                        const std::vector<std::string>& words) {
  std::vector<std::string> names{"--help"};
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) {
      names.push_back("--" + name);
    }
  }
  std::map<std::string, std::vector<std::string>> given;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (words[i].rfind("--", 0) != 0 || words[i] == "--") {
      continue;
    }
    const std::string name = words[i].substr(0, words[i].find('='));
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string nearest;
      std::size_t best = 3; // at most two edits away, or no suggestion
      for (const std::string& candidate : names) {
        if (const std::size_t d = edit_distance(name, candidate); d < best) {
          best = d;
          nearest = candidate;
        }
      }
      throw InputError("unknown option " + name + " for " + command.get_name() +
                       (nearest.empty() ? "" : "; did you mean " + nearest + "?") + " (got " +
                       words[i] + ")");
    }
    const bool has_value = words[i].find('=') == std::string::npos && i + 1 < words.size() &&
                           words[i + 1].rfind("--", 0) != 0;
    given[name].push_back(has_value ? name + " " + words[i + 1] : words[i]);
  }
  for (const auto& [name, uses] : given) {
    if (uses.size() > 1) {
      std::string all;
      for (const std::string& use : uses) {
        all += (all.empty() ? "" : " ") + use;
      }
      throw InputError(name + " is given " + std::to_string(uses.size()) +
                       " times: give it once (a list's items comma-separated) (got " + all + ")");
    }
  }
}

// CLI11's own errors, rewritten to the contract's one line "<what> (got <value>)".
std::string describe(const CLI::ParseError& e, const CLI::App& app,
                     const std::vector<std::string>& arguments) {
  const std::string what = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    std::string extras;
    for (const CLI::App* level = &app; level != nullptr;) {
      for (const std::string& extra : level->remaining()) {
        extras += (extras.empty() ? "" : " ") + extra;
      }
      const auto subs = level->get_subcommands();
      level = subs.empty() ? nullptr : subs.front();
    }
    return "unknown argument (got " + (extras.empty() ? what : extras) + ")";
  }
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
    return what + " (got nothing)";
  }
  return what + " (got " + CLI::detail::join(arguments, " ") + ")";
}

std::string analytic_convention_names() {
  std::string names = analytic::convention_names();
  std::replace(names.begin(), names.end(), '|', ',');
  return names;
}

} // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
            Distribution* distribution, std::ostream* progress) {
  CLI::App app{"pldamp: closed forms and validation harness for the power-law damped contact "
               "oscillator m d'' + alpha sqrt(mk) d^((p-1)/2) d' + k d^p = 0"};
  app.require_subcommand(1);
  // The build every report names (report.json's run.build): version and commit.
  app.set_version_flag("--version", "pldamp " + std::string(build_id()),
                       "the pldamp version and the commit it was built from");
  remember_command_line(std::vector<std::string>(argv, argv + argc));

  ContactArgs calibrate_args;
  CLI::App* calibrate = app.add_subcommand("calibrate", "alpha for a target restitution e");
  add_contact_options(*calibrate, calibrate_args, true);
  calibrate->add_option("--code", calibrate_args.code,
                        "what a DEM code sets and really gives: " + calibrate_code_names());
  calibrate->add_flag("--limit-damping", calibrate_args.limit_damping,
                      "with --code: LAMMPS limit_damping / LIGGGHTS limitForce (force cap) on");
  calibrate->add_option(
      "--v0", calibrate_args.v0,
      "with a velocity-dependent --code: the speed at which e is set (default 1)");
  calibrate->add_option("--m", calibrate_args.m, "reduced mass > 0 (default 1)");
  calibrate->add_option("--k", calibrate_args.k, "stiffness > 0 (default 1)");
  calibrate->add_option("--speeds", calibrate_args.speeds,
                        "with a velocity-dependent --code: the speeds of the e(v0) curve "
                        "(default v0/10, v0, 10 v0)");
  calibrate->add_option("--reff", calibrate_args.reff,
                        "with a velocity-dependent --code: LAMMPS's effective radius Reff "
                        "(default 1)");

  ContactArgs observables_args;
  CLI::App* observables = app.add_subcommand("observables", "every closed-form observable");
  add_contact_options(*observables, observables_args, false);

  SolveArgs solve_args;
  CLI::App* solve = app.add_subcommand("solve", "integrate one collision with a registered solver");
  add_contact_options(*solve, solve_args.contact, false);
  std::string solver_help = "registered solver:";
  for (const solvers::SolverInfo& info : solvers::registry()) {
    solver_help += "\n  " + std::string(info.name) + ": " + std::string(info.method);
  }
  solve->add_option("--solver", solve_args.solver, solver_help)->required();
  solve->add_option("--rtol", solve_args.rtol,
                    "relative tolerance (default 1e-8; " +
                        solvers::solver_names([](const solvers::SolverInfo& info) {
                          return info.default_tolerance == solvers::DefaultTolerance::epsilon;
                        }) +
                        ": the precision's epsilon)");
  solve->add_option("--atol", solve_args.atol,
                    "absolute tolerance for every state, literal (default: rtol x natural scale)");
  std::string want_list = want_words(false);
  std::replace(want_list.begin(), want_list.end(), '|', ',');
  solve->add_option("--want", solve_args.want, "comma list of " + want_list + " (default: all)");
  const std::string fixed_step_solvers =
      solvers::solver_names([](const solvers::SolverInfo& info) { return info.fixed_step; });
  solve->add_option("--dt", solve_args.dt,
                    "fixed step (" + fixed_step_solvers + "; " +
                        solvers::solver_names(
                            [](const solvers::SolverInfo& info) { return info.takes_fixed_step; }) +
                        " without error control)");
  solve->add_option("--steps-per-contact", solve_args.steps_per_contact,
                    fixed_step_solvers +
                        " without --dt: steps per contact time estimate (default 50)");
  solve->add_option("--onset-phase", solve_args.onset_phase,
                    "fixed-step solvers: the contact begins this fraction of a step before the "
                    "first step position in contact, in [0, 1) (default 0)");
  const std::string tau_as_help =
      "fixed-step solvers: the contact time as the code measures it, " + names_of(tau_as_names) +
      " (default first-step-out: the first step position out of contact, from the touch; "
      "steps-in-contact: n dt; crossing: delta = 0 interpolated)";
  solve->add_option("--tau-as", solve_args.tau_as, tau_as_help);
  solve->add_option("--horizon", solve_args.horizon,
                    "time at which a contact that has not ended is reported no_exit");
  solve->add_option("--sample-times", solve_args.sample_times,
                    "comma list of times to sample, inside the contact solved");
  solve->add_option("--max-steps", solve_args.max_steps, "step limit (default 1e6)");
  solve->add_option("--max-seconds", solve_args.max_seconds,
                    "wall-clock limit of the solve (default 60): outcome time_limit beyond it");
  solve->add_option("--repeats", solve_args.repeats,
                    "solve this many times, in [1, 1000] (default 3): wall_seconds is the fastest "
                    "(the first pays for cold caches and builds taylor's contact-point series)");

  TimestepArgs timestep_args;
  CLI::App* timestep = app.add_subcommand(
      "timestep", "the largest fixed step keeping observables within a tolerance of the closed "
                  "forms from every onset phase (a [[search]] of dt)");
  add_contact_options(*timestep, timestep_args.contact, false);
  // DEM codes step in double with the seed's dashpot: the closed forms are the truth.
  timestep->remove_option(timestep->get_option("--precision"));
  timestep->remove_option(timestep->get_option("--damping-exponent"));
  timestep->get_option("--v0")->required(false)->description("impact velocity > 0 (default 1)");
  timestep->add_option("--scheme", timestep_args.scheme, "fixed-step scheme: " + fixed_step_solvers)
      ->required();
  timestep->add_option("--tolerance", timestep_args.tolerance,
                       "relative error every observable keeps, in (0, 1) (default 0.01)");
  timestep->add_option("--observables", timestep_args.observables,
                       "comma list of the observables judged (default e,delta_max,tau)");
  timestep->add_option("--tau-as", timestep_args.tau_as, tau_as_help);
  timestep->add_option("--code", timestep_args.contact.code,
                       "a DEM code's convention sets alpha from --e (as calibrate --code): " +
                           analytic_convention_names());

  RunArgs run_args;
  CLI::App* run = app.add_subcommand("run", "run a scene: solvers against the closed forms, "
                                            "budgets, claims, reports");
  run->add_option("scene", run_args.scene, "scene file (TOML), e.g. data/scenes/nightly.toml")
      ->required();
  run->add_option("--out", run_args.out, "report folder (default: report)");
  run->add_option("--jobs", run_args.jobs,
                  "parallel solver runs (default: the cores this process may use; under mpirun, "
                  "a rank's own cores, or the node's shared among its ranks)");
  run->add_option("--max-steps", run_args.max_steps,
                  "each solve's step limit (default: the scene's [limits], else 1000000)");
  run->add_option("--max-seconds", run_args.max_seconds,
                  "each solve's wall-clock limit (default: the scene's [limits], else 30)");
  run->add_option("--max-runs", run_args.max_runs,
                  "refuse a plan of more solver runs, a process's share under --shard or mpirun "
                  "(default: the scene's [limits], else 1000000)");
  run->add_flag("--strict", run_args.strict,
                "exit 1 when a claim's verdict is not the one expected (a failing claim, or one "
                "pinned with expect = \"fails\" that now holds)");
  run->add_option("--shard", run_args.shard,
                  "K/N: solve shard K of N of the grid's cells (a job array's task) into --out, "
                  "for `pldamp merge`");

  MergeArgs merge_args;
  CLI::App* merge = app.add_subcommand(
      "merge", "the report of a run made in shards (pldamp run SCENE --shard K/N --out DIR_K)");
  merge->add_option("shards", merge_args.shards, "the shards' --out folders, all N of them")
      ->required();
  merge->add_option("--out", merge_args.out, "report folder (default: report)");
  merge->add_option("--jobs", merge_args.jobs,
                    "threads for the claims, searches and reports (default: the cores)");
  merge->add_flag("--strict", merge_args.strict,
                  "exit 1 when a claim's verdict is not the one expected (as run --strict)");

  DiffArgs diff_args;
  CLI::App* diff = app.add_subcommand(
      "diff", "what changed between two report.json of one scene; exit 1 on a regression, 2 on "
              "bad input or different scenes (docs/ci.md: the output's format)");
  diff->add_option("old", diff_args.old_path, "last night's report.json")->required();
  diff->add_option("new", diff_args.new_path, "tonight's report.json")->required();
  diff->add_option("--error-factor", diff_args.error_factor,
                   "an error grown more than this factor regresses (default: the scene's [diff], "
                   "else 10)");
  diff->add_option("--work-factor", diff_args.work_factor,
                   "rhs_evals or steps grown more than this factor regress (default 1.5)");
  diff->add_option("--time-factor", diff_args.time_factor,
                   "a configuration's time (sum of fastest repeats) grown more than this factor "
                   "regresses (default 2) ...");
  diff->add_option("--time-floor", diff_args.time_floor,
                   "... when it took at least this many seconds before (default 0.005)");
  diff->add_flag("--allow-scene-change", diff_args.allow_scene_change,
                 "compare reports of different scenes on what they share, listing what was added "
                 "and removed");
  diff->add_flag("--verbose", diff_args.verbose, "every record under its group's line");
  diff->add_flag("--exact", diff_args.exact,
                 "the reproducibility check: exit 1 listing every record, claim, search or budget "
                 "that differs by one bit, timings and provenance aside (judge/diff_exact.hpp)");

  CheckArgs check_args;
  CLI::App* check = app.add_subcommand(
      "check", "one contact's time series from a code that cannot be driven (a DEM dump), "
               "measured between its samples and judged against the closed forms");
  check
      ->add_option("trajectory", check_args.trajectory,
                   "CSV file: a header naming the columns " + trajectory_column_names() +
                       ", t and delta required; then rows of numbers, t increasing; lines "
                       "starting with # skipped")
      ->required();
  add_contact_options(*check, check_args.contact, false);
  check->remove_option(check->get_option("--precision")); // the truth is computed in Exact
  // The truth is the seed's closed forms: another dashpot has none (`solve` takes it).
  check->remove_option(check->get_option("--damping-exponent"));
  check->add_option("--tolerance", check_args.tolerance,
                    "judge the file: a relative tolerance T for every observable, or "
                    "NAME=T,... for some (e, delta_max, t_peak, tau; e_cap, t_cut under --end "
                    "force); exit 1 when one is beyond it");

  std::string showcase_precision = "double";
  CLI::App* showcase =
      app.add_subcommand("showcase", "observables for p = 1 ... 3 at e = 0.5, one overdamped case");
  showcase->add_option("--precision", showcase_precision, precision_choices());

  const std::vector<std::string> arguments(argv + 1, argv + argc);
  try {
    if (!arguments.empty() && arguments.front().rfind('-', 0) != 0 &&
        arguments.front() != "calibrate" && arguments.front() != "observables" &&
        arguments.front() != "solve" && arguments.front() != "showcase" &&
        arguments.front() != "run" && arguments.front() != "diff" && arguments.front() != "check" &&
        arguments.front() != "timestep" && arguments.front() != "merge") {
      throw InputError("unknown command, expected "
                       "calibrate|observables|solve|timestep|run|merge|diff|check|showcase (got " +
                       arguments.front() + ")");
    }
    if (!arguments.empty() && arguments.front().rfind('-', 0) != 0) {
      refuse_unknown_or_repeated_options(
          *app.get_subcommand(arguments.front()),
          std::vector<std::string>(arguments.begin() + 1, arguments.end()));
    }
    try {
      app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
      const auto parsed = app.get_subcommands();
      out << (parsed.empty() ? app.help() : parsed.front()->help());
      return 0;
    } catch (const CLI::CallForVersion&) {
      out << "pldamp " << build_id() << "\n";
      return 0;
    } catch (const CLI::CallForAllHelp&) {
      out << app.help("", CLI::AppFormatMode::All);
      return 0;
    } catch (const CLI::ParseError& e) {
      throw InputError(describe(e, app, arguments));
    }
    if (calibrate->parsed()) {
      record_given(*calibrate, calibrate_args);
      settle(Question::calibrate, calibrate_args);
      run_calibrate(calibrate_args, out);
    } else if (observables->parsed()) {
      record_given(*observables, observables_args);
      settle(Question::observables, observables_args);
      run_observables(observables_args, out);
    } else if (solve->parsed()) {
      record_given(*solve, solve_args.contact);
      settle(solve_args);
      run_solve(solve_args, out);
    } else if (timestep->parsed()) {
      record_given(*timestep, timestep_args.contact);
      settle(timestep_args);
      run_timestep(timestep_args, out);
    } else if (showcase->parsed()) {
      run_showcase(showcase_precision, out);
    } else if (run->parsed()) {
      return run_command(run_args, out, err, distribution, progress != nullptr ? progress : &err);
    } else if (merge->parsed()) {
      return merge_command(merge_args, out, err);
    } else if (diff->parsed()) {
      return diff_command(diff_args, out);
    } else if (check->parsed()) {
      record_given(*check, check_args.contact);
      settle(Question::check, check_args.contact);
      return run_check(check_args, out);
    }
  } catch (const SceneError& e) { // already "file:line: message"
    err << one_line(e.what()) << "\n";
    return 2;
  } catch (const InternalError& e) {
    err << "error: internal: " << one_line(e.what()) << "\n";
    return 3;
  } catch (const std::invalid_argument& e) { // InputError and the library's validation
    err << "error: " << one_line(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) { // an integrator that failed; anything unforeseen
    err << "error: internal: " << one_line(e.what()) << "\n";
    return 3;
  } catch (...) {
    err << "error: internal: an unknown exception\n";
    return 3;
  }
  return 0;
}

} // namespace pldamp::harness
