// A scene: what one `pldamp run` computes (DESIGN.md "Scenes"). Read from TOML by toml++; every
// problem with the file is reported as `file:line: message` before any work starts.
//
//     name = "quick"
//     end  = "overlap"                      # or "force"
//     want = ["e", "delta_max", "t_peak", "tau", "energy"]
//     [grid]      p, e, alpha and/or alpha_eff, v0, m (default [1]), k (default [1]): numbers or
//                 lists
//     [[solver]]  an external program instead of name: command = [argv...] (a relative program path
//                 is the scene file's folder's, a bare name the file beside the scene if there is
//                 one, else PATH's), label, options = {...} (passed through), replica
//                 (pldamp's solver of the same scheme, compared on every problem), and
//                 rtol, atol, steps_per_contact or dt (lists), end, onset_phases as below
//     [[solver]]  name; rtol (number or list; a reference solver without it: its precision's
//                 epsilon); atol; precision (double|long|quad|50, where the solver runs in it);
//                 steps_per_contact (fixed-step solvers, list); end (overlap|force, or both
//                 as a list: the contact-end rule when not the scene's); onset_phases (an
//                 integer n: fixed-step runs at the onset phases k/n, the worst reported)
//     [[claim]]   name; kind (default bound); where, quote (the source's section and words);
//                 figure (a [[figure]] kind that shows it); expect = "holds" | "fails" (pins a
//                 known-false claim); then by kind:
//                 bound: observable, solver, rtol, atol, precision, bound (max abs error); or
//                   observable = "e", convention (a DEM code's), limit_damping, bound
//                 relation: quantity, of = "truth" | solver (rtol, atol), formula, relation
//                   (lower_bound|upper_bound|equal_within), tolerance, absolute
//                 asymptotic: quantity, of | solver, formula, order, range = [from, to], points
//                 recovered_parameter: solver, rtol, atol, bound (relative, on alpha)
//                 stability: solver (fixed-step), formula = "seed_dt_crit", fraction (of
//                   it, default 1: DEM practice runs a fraction of a critical step)
//                 and for all, a grid of its own (p, e, alpha_eff, v0, m, k; each
//                 defaults to [grid]'s) and denser = true (also judged ten times denser)
//                 bound claims: bound (absolute error) or bound_rel (relative), and quantile
//                 (over the cells, nearest rank; default 1, the worst); a grid of their own too
//                 (solved for the claim alone; a convention's: p and e), denser = true, and
//                 allow_missing = true (cells without a value allowed: "holds on M of N cells")
//     [[search]]  name, where, quote; solver, precision, atol (and rtol or steps_per_contact,
//                 whichever is not searched); parameter = rtol | steps_per_contact | dt; range =
//                 [from, to] (either order); observable; bound or bound_rel; quantile; group_by = p
//                 | damping | point | all (default p); a grid of its own (p, e, alpha_eff, v0, m,
//                 k; each defaults to [grid]'s); onset_phases (fixed steps; default 8); end
//     [[trajectory]] file (a CSV of t, delta and optionally v, F; the scene's folder's), label, p,
//                 e or alpha or alpha_eff, v0, m, k (default 1), end: checked as `pldamp check`
//     [[figure]]  kind (figures.hpp), solver, rtol, atol, p, e, alpha_eff: the seed's figures
//     [report]    formats = ["json", "csv", "md", "html"]; work_precision = ["e", "worst"] (the
//                 series of the work-precision diagrams and of report.md's table: observables the
//                 scene wants, and "worst", the largest error of any; default: e and worst)
//     [timing]    repeats = 3   (wall time of a run: the minimum over repeats)
//     [diff]      error_factor = 10, work_factor = 1.5, time_factor = 2, time_floor = 0.005:
//                 when `pldamp diff` calls a change a regression (judge/diff.hpp)
//     [limits]    max_steps = 1000000, max_seconds = 30 (each solve's budget: a solve that spends
//                 it is a failed record, step_limit or time_limit, and the run goes on);
//                 max_runs = 1000000 (a larger plan is refused before any work)
#pragma once

#include "common/input.hpp"
#include "common/names.hpp"

#include "pldamp/analytic/seed.hpp"
#include "pldamp/solvers/problem.hpp"

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// A bad scene: the message is "file:line: what".
struct SceneError : InputError {
  using InputError::InputError;
};

// The damping of a grid point: a target restitution (under the scene's end), α (the equation's,
// as the command line's --alpha) or α_eff.
struct Damping {
  enum class Kind { e, alpha, alpha_eff };
  Kind kind;
  double value;
  std::string label() const;    // "e=0.5", "alpha=0.3", "z=1.5"
  std::string_view key() const; // the scene's word: "e", "alpha", "alpha_eff"
};

// One solver configuration: a point of a solver entry's sweep.
struct SolverConfig {
  std::string name;
  std::string precision = "double";
  std::optional<double> rtol; // none: the solver's default (a reference: its precision's epsilon)
  std::optional<double> atol;
  std::optional<int> steps_per_contact; // fixed-step solvers
  std::optional<double> dt;             // fixed-step solvers: a fixed step instead (searches)
  std::optional<solvers::End> end;      // the contact-end rule, when not the scene's
  int onset_phases = 1; // fixed-step solvers: evenly spaced onset phases k/n, worst reported
  // An external solver (run/external.hpp): the program and its arguments, started once per
  // configuration; `name` is then the [[solver]]'s label. `options` is its [[solver]] options
  // table as JSON text, passed through in every problem.
  std::vector<std::string> command;
  std::string program; // the program as the scene typed it (command[0] is it resolved)
  std::string options;
  // pldamp's own solver that replicates the program's scheme (e.g. dem-verlet for LAMMPS): run on
  // every problem beside it, the largest relative difference reported (they should agree to
  // rounding). Empty: none.
  std::string replica;
  bool external() const { return !command.empty(); }
  // Fixed-step: a registered fixed-step scheme, or an external solver swept by steps or dt.
  bool fixed_step() const;
  // "cvode-bdf rtol=1e-08", "taylor quad", "dem-verlet n=50 end=force phases=16"
  std::string label() const;
  // The label without its sweep value (rtol, steps per contact): the line of a work-precision
  // plot, the sweep of a time-step study.
  std::string line() const;
  bool operator==(const SolverConfig&) const = default;
};

// What a claim states (judge/claims.hpp says how each is judged):
//   bound                a solver configuration's largest absolute error of an observable over
//                        the scene's grid (or a DEM code's calibration, by `convention`)
//   relation             a quantity of the truth or of a solver against a named formula of the
//                        inputs: lower_bound, upper_bound or equal_within
//   asymptotic           the order in α_eff at which a quantity and a formula agree as α_eff → 0
//   recovered_parameter  α found by bisection on a solver's e, against the seed's α(e)
//   stability            a fixed-step scheme's largest stable Δt against a named Δt bound
enum class ClaimKind { bound, relation, asymptotic, recovered_parameter, stability };
inline constexpr NameTable<ClaimKind, 5> claim_kinds{
    {{ClaimKind::bound, "bound"},
     {ClaimKind::relation, "relation"},
     {ClaimKind::asymptotic, "asymptotic"},
     {ClaimKind::recovered_parameter, "recovered_parameter"},
     {ClaimKind::stability, "stability"}}};

// What a relation or asymptotic claim measures, of the truth (closed forms in float128) or of a
// solver in double: an observable, or τ(α)/τ(0) (a solver: two solves).
enum class Quantity { e, delta_max, t_peak, tau, tau_ratio, energy_load, energy_unload };
inline constexpr NameTable<Quantity, 7> quantities{{{Quantity::e, "e"},
                                                    {Quantity::delta_max, "delta_max"},
                                                    {Quantity::t_peak, "t_peak"},
                                                    {Quantity::tau, "tau"},
                                                    {Quantity::tau_ratio, "tau_ratio"},
                                                    {Quantity::energy_load, "energy_load"},
                                                    {Quantity::energy_unload, "energy_unload"}}};

enum class Relation { lower_bound, upper_bound, equal_within };
inline constexpr NameTable<Relation, 3> relations{{{Relation::lower_bound, "lower_bound"},
                                                   {Relation::upper_bound, "upper_bound"},
                                                   {Relation::equal_within, "equal_within"}}};

// The cells a claim of the new kinds is judged over: its own lists, else the scene's grid.
struct ClaimGrid {
  std::vector<double> p, v0, m, k;
  std::vector<Damping> damping;
};

struct Claim {
  std::string name;
  ClaimKind kind = ClaimKind::bound;
  std::string where, quote;          // the source's section and its words (shown in reports)
  std::optional<std::string> figure; // the kind of the scene's figure that shows it
  bool expect_holds = true;          // expect = "fails": a known-false claim, pinned
  std::string observable;            // bound: an observable key the scene wants
  Quantity quantity = Quantity::e;   // relation, asymptotic
  SolverConfig config;               // the solver's claims
  bool of_truth = false; // relation, asymptotic: the closed forms' quantity, not a solver's
  // A DEM code's convention (analytic/conventions.hpp): the claim is that the e it really gives
  // for each target e of the grid is within the bound (closed forms, no solver).
  std::optional<std::string> convention;
  bool limit_damping = false; // the convention's optional force cap switched on
  // relation, asymptotic, stability: the formula of analytic/seed.hpp compared against
  analytic::seed::Formula formula = analytic::seed::Formula::tau_ratio_curve;
  Relation relation = Relation::equal_within;
  bool absolute = false; // equal_within: |a − b| ≤ bound rather than |a/b − 1| ≤ bound
  // bound: on the largest absolute error; relation: equal_within's tolerance, or how far a
  // lower/upper bound may be crossed (relative: rounding); asymptotic: the order the claim
  // implies; recovered_parameter: on the largest relative error of α; stability: 1 (Δt ratio).
  double bound = 0;
  ClaimGrid grid;
  bool denser = false;                     // also judged on a grid ten times denser
  std::array<double, 2> range{1e-4, 1e-2}; // asymptotic: α_eff from, to (log-spaced)
  int points = 9;                          // asymptotic: points over the range, per p
  double fraction = 1; // stability: the bound is this fraction of the formula's Δt
  // bound: on the relative error (bound_rel) rather than the absolute one, and over the cells'
  // `quantile` (nearest rank; 1: the worst cell).
  bool relative = false;
  double quantile = 1;
  // bound: the claim names a grid of its own (p, e, alpha_eff, v0, m, k), solved for it alone;
  // else `grid` is the scene's and its records are judged.
  bool own_grid = false;
  // bound: cells without a value (skipped, not measured, no truth) allowed: the claim then holds
  // on the others ("holds on M of N cells", which `run --strict` counts as unexpected).
  bool allow_missing = false;
  // Judged from the plan's records (a bound on a solver's error over the scene's grid).
  bool on_plan() const { return kind == ClaimKind::bound && !convention && !own_grid; }
};

// The sweep parameter a search loosens.
enum class SearchParameter { rtol, steps_per_contact, dt };
inline constexpr NameTable<SearchParameter, 3> search_parameters{
    {{SearchParameter::rtol, "rtol"},
     {SearchParameter::steps_per_contact, "steps_per_contact"},
     {SearchParameter::dt, "dt"}}};

// How a search splits its grid: one answer per p, per damping, per (p, damping), or one for all.
enum class SearchGroups { p, damping, point, all };
inline constexpr NameTable<SearchGroups, 4> search_groups{{{SearchGroups::p, "p"},
                                                           {SearchGroups::damping, "damping"},
                                                           {SearchGroups::point, "point"},
                                                           {SearchGroups::all, "all"}}};

// [[search]]: the loosest value of a configuration's sweep parameter that keeps a bound on an
// observable's error, per group of cells (judge/search.hpp).
struct Search {
  std::string name, where, quote;
  SolverConfig config; // the parameter searched is set per trial
  SearchParameter parameter = SearchParameter::rtol;
  std::array<double, 2> range{}; // the values searched: tightest, loosest
  std::string observable;
  double bound = 0;
  bool relative = false; // bound_rel: on the relative error
  double quantile = 1;   // over the group's cells (1: the worst)
  SearchGroups group_by = SearchGroups::p;
  ClaimGrid grid;
  // steps_per_contact and dt: the onset phases k/n each trial takes its worst over
  // (judge/search.hpp checks the answer at twice as many).
  int onset_phases = 8;
};

// [[trajectory]]: a contact's time series dumped by a code, checked as `pldamp check` checks it
// (judge/trajectory.hpp) against the closed forms of its inputs.
struct TrajectorySpec {
  std::string label, file; // file: resolved from the scene file's folder
  double p = 1, v0 = 1, m = 1, k = 1;
  std::string damping_key; // e, alpha or alpha_eff
  double damping = 0;
  std::optional<solvers::End> end; // none: the scene's
};

// The seed's figures (judge/figures.hpp).
enum class FigureKind {
  alpha_vs_e,
  force_history,
  delta_max_vs_e,
  tau_ratio,
  phase_portrait,
  f_of_p,
  restitution_approximations
};
inline constexpr NameTable<FigureKind, 7> figure_kinds{
    {{FigureKind::alpha_vs_e, "alpha_vs_e"},
     {FigureKind::force_history, "force_history"},
     {FigureKind::delta_max_vs_e, "delta_max_vs_e"},
     {FigureKind::tau_ratio, "tau_ratio"},
     {FigureKind::phase_portrait, "phase_portrait"},
     {FigureKind::f_of_p, "f_of_p"},
     {FigureKind::restitution_approximations, "restitution_approximations"}}};

// A figure of the seed: its kind, the solver behind its points, its lists.
struct FigureSpec {
  FigureKind kind;
  SolverConfig config;
  std::vector<double> p, e, alpha_eff;
};

// The report files; each name is the scene's word for it and the file's extension.
enum class ReportFormat { json, csv, md, html };
inline constexpr NameTable<ReportFormat, 4> report_formats{{{ReportFormat::json, "json"},
                                                            {ReportFormat::csv, "csv"},
                                                            {ReportFormat::md, "md"},
                                                            {ReportFormat::html, "html"}}};

// The word for the worst of all observables: in [report] work_precision, in report.json's
// scene.work_precision, and as the report's series.
inline constexpr std::string_view worst_of_all_key = "worst";

// "overlap", "force".
inline constexpr NameTable<solvers::End, 2> contact_ends{
    {{solvers::End::overlap, "overlap"}, {solvers::End::force, "force"}}};

// What one run may spend ([limits]; `pldamp run --max-steps/--max-seconds/--max-runs`).
struct Limits {
  long max_steps = 1000000; // per solve
  double max_seconds = 30;  // per solve, wall clock
  long max_runs = 1000000;  // solver runs of the plan (onset phases and repeats included)
};

// When `pldamp diff` calls a difference a regression ([diff]; its flags override).
struct DiffThresholds {
  double error_factor = 10; // an error grown more than this
  double work_factor = 1.5; // rhs_evals or steps grown more than this
  double time_factor = 2;   // a configuration's time grown more than this ...
  double time_floor = 5e-3; // ... when it took at least this many seconds
};

struct Scene {
  std::string path, name;
  solvers::End end = solvers::End::overlap;
  unsigned want = solvers::want_all;
  std::vector<double> p, v0, m, k;
  std::vector<Damping> damping;
  // β of the dashpot δ^β δ' (MATH.md §12), at most one; empty: the seed's (p − 1)/2.
  std::vector<double> damping_exponent;
  std::vector<SolverConfig> configs; // every sweep expanded, in file order
  std::vector<Claim> claims;
  std::vector<Search> searches;
  std::vector<FigureSpec> figures;
  std::vector<TrajectorySpec> trajectories;
  std::vector<ReportFormat> formats{ReportFormat::json, ReportFormat::csv, ReportFormat::md,
                                    ReportFormat::html};
  // [report] work_precision: observable keys and worst_of_all_key, in the order shown; empty:
  // the default (judge/budget.hpp, work_panels).
  std::vector<std::string> work_precision;
  int repeats = 1;
  Limits limits;
  DiffThresholds diff;
};

// The contact-end rule a configuration runs under: its own, or the scene's.
inline solvers::End end_of(const Scene& scene, const SolverConfig& config) {
  return config.end.value_or(scene.end);
}

// Reads and validates a scene file; throws SceneError.
Scene load_scene(const std::string& path);
// The same from the file's text (`path` names it in messages).
Scene parse_scene(std::string_view text, const std::string& path);

// A scene file larger than this is refused before parsing (the largest shipped is ~3 kB).
inline constexpr std::size_t max_scene_bytes = 1 << 20;
// Arrays, inline tables and dotted keys nested deeper than this (together) are refused before
// parsing: toml++ parses them recursively, and 100 000 levels overflowed the stack.
inline constexpr int max_scene_nesting = 32;

} // namespace pldamp::harness
