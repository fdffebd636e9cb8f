// A scene: what one `pldamp run` computes (docs/design.md §3). Read from TOML by toml++; every
// problem with the file is reported as `file:line: message` before any work starts. What a scene
// may say (every table and key, its type, range and default) is docs/scenes.md; scene/keys.hpp
// lists the keys of each table, and tests/harness/scene_docs_test.cpp holds the two together.
#pragma once

#include "common/input.hpp"
#include "common/names.hpp"
#include "common/tau_as.hpp"

#include "pldamp/analytic/seed.hpp"
#include "pldamp/solvers/problem.hpp"

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
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
  // Fixed-step solvers: the observables (solvers::Want bits) whose worst over every onset phase is
  // sought from the onset_phases sampled (run/phase_supremum.hpp); searches set it to theirs. 0:
  // the worst over the samples (a reported sweep).
  unsigned every_phase = 0;
  // The seeking may stop once one of their errors passes this (a search's bound: the value fails).
  double every_phase_enough = std::numeric_limits<double>::infinity();
  TauAs tau_as = TauAs::first_step_out; // the contact time as the user's code measures it
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

// What a claim states (judge/claims.hpp says how each is judged), by its `kind`:
//   bound                a solver configuration's error of an observable over the cells
//                        (BoundClaim), or a DEM code's calibration by `convention`
//                        (ConventionClaim)
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
// The scales of a grid's cells: v0, m, k.
struct CellScale {
  double v0, m, k;
};

struct ClaimGrid {
  std::vector<double> p, v0, m, k;
  std::vector<Damping> damping;
  // A scene's [[contact]]s: their cells' (v0, m, k), in place of the product v0 × m × k (which
  // would pair one contact's m with another's k); empty otherwise.
  std::vector<CellScale> scales{};
};

// The (v0, m, k) of a grid's cells: its contacts', or v0 × m × k.
std::vector<CellScale> grid_scales(const ClaimGrid& grid);

struct Scene;
// The scene's grid (with its contacts' scales), to start a claim's or a search's from.
ClaimGrid scene_grid(const Scene& scene);
// The scene with a grid's cells (p, v0, m, k, or the contacts'): what a claim or a search solves
// on its own, and against which a solver's tolerances are checked.
Scene with_cells(const Scene& scene, const ClaimGrid& grid);

// A bound on an error over cells: on the absolute error (`bound`) or the relative one
// (`bound_rel`), over the cells' `quantile` (nearest rank; 1: the worst cell).
struct ErrorBound {
  double bound = 0;
  bool relative = false;
  double quantile = 1;
};

// kind = "bound": a solver configuration's error of an observable the scene wants.
struct BoundClaim {
  static constexpr ClaimKind claim_kind = ClaimKind::bound;
  std::string observable;
  SolverConfig config;
  ErrorBound error;
  // The claim names a grid of its own (p, e, alpha, alpha_eff, v0, m, k): its configuration is
  // solved over it for the claim alone; else the plan's records on the scene's grid are judged.
  bool own_grid = false;
  // Cells without a value (skipped, not measured, no truth) allowed: the claim then holds on the
  // others ("holds on M of N cells", which `run --strict` counts as unexpected).
  bool allow_missing = false;
};

// kind = "bound" with a `convention` (analytic/conventions.hpp): the e a DEM code really gives
// for each target e of the cells is within the bound (closed forms, no solver).
struct ConventionClaim {
  static constexpr ClaimKind claim_kind = ClaimKind::bound;
  std::string convention;
  bool limit_damping = false; // the convention's optional force cap switched on
  ErrorBound error;
  bool own_grid = false; // p or e of its own
};

// The quantity a relation or asymptotic claim measures, and whose it is.
struct MeasuredQuantity {
  Quantity quantity = Quantity::e;
  std::optional<SolverConfig> solver; // none: the truth's (of = "truth")
};

// kind = "relation": the quantity against a formula of analytic/seed.hpp, cell by cell.
struct RelationClaim {
  static constexpr ClaimKind claim_kind = ClaimKind::relation;
  MeasuredQuantity of;
  analytic::seed::Formula formula = analytic::seed::Formula::tau_ratio_curve;
  Relation relation = Relation::equal_within;
  // equal_within: how far apart the two sides may be; a lower or upper bound: how far it may be
  // crossed (relative; default 1e-25, the truth's rounding in float128).
  double tolerance = 0;
  bool absolute = false; // |a − f| ≤ tolerance rather than |a/f − 1| ≤ tolerance
};

// kind = "asymptotic": the order in α_eff at which the quantity and a formula agree.
struct AsymptoticClaim {
  static constexpr ClaimKind claim_kind = ClaimKind::asymptotic;
  MeasuredQuantity of;
  analytic::seed::Formula formula = analytic::seed::Formula::tau_ratio_curve;
  double order = 0;                        // the order the claim implies
  std::array<double, 2> range{1e-4, 1e-2}; // α_eff from, to (log-spaced)
  int points = 9;                          // over the range, per p
};

// kind = "recovered_parameter": α found by bisection on a solver's e for each target e.
struct RecoveredParameterClaim {
  static constexpr ClaimKind claim_kind = ClaimKind::recovered_parameter;
  SolverConfig config;
  double bound = 0; // on the largest relative error of α against the seed's α(e)
};

// kind = "stability": a fixed-step scheme's largest stable Δt against a fraction of a formula's.
struct StabilityClaim {
  static constexpr ClaimKind claim_kind = ClaimKind::stability;
  SolverConfig config;
  analytic::seed::Formula formula = analytic::seed::Formula::dt_crit;
  double fraction = 1; // DEM practice runs a fraction of a critical step
};

struct Claim {
  std::string name;
  std::string where, quote;          // the source's section and its words (shown in reports)
  std::optional<std::string> figure; // the kind of the scene's figure that shows it
  bool expect_holds = true;          // expect = "fails": a known-false claim, pinned
  ClaimGrid grid;                    // its own lists, else the scene's
  bool denser = false;               // also judged on a grid ten times denser
  std::variant<BoundClaim, ConventionClaim, RelationClaim, AsymptoticClaim, RecoveredParameterClaim,
               StabilityClaim>
      kind;

  ClaimKind claim_kind() const {
    return std::visit([](const auto& stated) { return stated.claim_kind; }, kind);
  }
  // The bound claim judged from the plan's records (a solver's error over the scene's grid), or
  // nullptr.
  const BoundClaim* on_plan() const {
    const BoundClaim* bound = std::get_if<BoundClaim>(&kind);
    return bound != nullptr && !bound->own_grid ? bound : nullptr;
  }
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
  // `pldamp timestep`: more observables the bound holds for; a trial's error is then the largest
  // over `observable` and these (a [[search]] has none).
  std::vector<std::string> more_observables{};
  double bound = 0;
  bool relative = false; // bound_rel: on the relative error
  double quantile = 1;   // over the group's cells (1: the worst)
  SearchGroups group_by = SearchGroups::p;
  ClaimGrid grid;
  // steps_per_contact and dt: the onset phases k/n each trial samples before seeking its worst
  // over every phase (judge/search.hpp, run/phase_supremum.hpp).
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

// [[contact]]: two bodies from materials (MATH.md §13), a Hertz contact (p = 3/2) whose m* and k
// are derived in float128 (or 50 digits) and rounded to double once, met at each of `v0` (the
// relative normal speed). A scene with contacts takes its cells from them: p = 1.5 and per contact
// its m, k and each of its v0, in place of [grid]'s v0 × m × k. Units are SI.
struct MaterialContact {
  std::string name, geometry;
  double radius_eff = 0, modulus_eff = 0; // R* [m], E* [Pa]
  double m = 0, k = 0;                    // m* [kg], 4/3 E* √R* [N/m^1.5]
  double rayleigh_time = 0;               // the smaller sphere's [s]
  std::vector<double> v0;                 // [m/s]
};

struct Scene {
  std::string path, name;
  std::string text; // the file as read (a shard carries it: `pldamp merge` plans it again)
  solvers::End end = solvers::End::overlap;
  unsigned want = solvers::want_all;
  // With contacts: p = {1.5}, and v0, m, k each contact's values in order (what scene_scales
  // pairs up; a product of them is not the scene's cells).
  std::vector<double> p, v0, m, k;
  std::vector<MaterialContact> contacts;
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
  // A run that took at least this many seconds on its thread's CPU clock is not repeated: its own
  // length averages the noise a repeat is there to remove (run/run.cpp).
  double repeat_below = 1e-3;
  Limits limits;
  DiffThresholds diff;
};

// The (v0, m, k) of the scene's cells, per p and damping: [grid]'s v0 × m × k, or each contact's
// m and k at each of its v0.
std::vector<CellScale> scene_scales(const Scene& scene);

// The [[contact]] whose m and k a cell has, or nullptr (a scene without contacts).
const MaterialContact* contact_of(const Scene& scene, double m, double k);

// The contact-end rule a configuration runs under: its own, or the scene's.
inline solvers::End end_of(const Scene& scene, const SolverConfig& config) {
  return config.end.value_or(scene.end);
}

// Whether the run solves with pldamp's own solvers: a [[solver]], a claim's solver, a search, a
// figure's solver (restitution_approximations is the reference solve's, within limits of its own).
// A step limit has no effect otherwise (an external program is given none).
bool solves_with_pldamp(const Scene& scene);

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
