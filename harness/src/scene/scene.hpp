// A scene: what one `pldamp run` computes (DESIGN.md "Scenes"). Read from TOML by toml++; every
// problem with the file is reported as `file:line: message` before any work starts.
//
//     name = "quick"
//     end  = "overlap"                      # or "force"
//     want = ["e", "delta_max", "t_peak", "tau", "energy"]
//     [grid]      p, e and/or alpha_eff, v0, m (default [1]), k (default [1]): numbers or lists
//     [[solver]]  name; rtol (number or list; a reference solver without it: its precision's
//                 epsilon); atol; precision (double|long|quad|50, where the solver runs in it);
//                 steps_per_contact (fixed-step solvers, list); end (overlap|force, or both
//                 as a list: the contact-end rule when not the scene's); onset_phases (an
//                 integer n: fixed-step runs at the onset phases k/n, the worst reported)
//     [[claim]]   name, observable, solver, rtol, atol, precision, bound (max abs error); or
//                 name, observable = "e", convention (a DEM code's), limit_damping, bound
//     [[figure]]  kind (figures.hpp), solver, rtol, atol, p, e, alpha_eff: the seed's figures
//     [report]    formats = ["json", "csv", "md", "html"]
//     [timing]    repeats = 3   (wall time of a run: the minimum over repeats)
//     [limits]    max_steps = 1000000, max_seconds = 30 (each solve's budget: a solve that spends
//                 it is a failed record, step_limit or time_limit, and the run goes on);
//                 max_runs = 1000000 (a larger plan is refused before any work)
#pragma once

#include "common/input.hpp"
#include "common/names.hpp"

#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// A bad scene: the message is "file:line: what".
struct SceneError : InputError {
  using InputError::InputError;
};

// The damping of a grid point: a target restitution (under the scene's end) or α_eff.
struct Damping {
  enum class Kind { e, alpha_eff };
  Kind kind;
  double value;
  std::string label() const; // "e=0.5", "z=1.5"
};

// One solver configuration: a point of a solver entry's sweep.
struct SolverConfig {
  std::string name;
  std::string precision = "double";
  std::optional<double> rtol; // none: the solver's default (a reference: its precision's epsilon)
  std::optional<double> atol;
  std::optional<int> steps_per_contact; // fixed-step solvers
  std::optional<solvers::End> end;      // the contact-end rule, when not the scene's
  int onset_phases = 1; // fixed-step solvers: evenly spaced onset phases k/n, worst reported
  // "cvode-bdf rtol=1e-08", "taylor quad", "dem-verlet n=50 end=force phases=16"
  std::string label() const;
  // The label without its sweep value (rtol, steps per contact): the line of a work-precision
  // plot, the sweep of a time-step study.
  std::string line() const;
  bool operator==(const SolverConfig&) const = default;
};

// A claim on a solver configuration's error, or on what a DEM code's calibration gives.
struct Claim {
  std::string name;
  std::string observable; // a key of the observable table the scene wants
  SolverConfig config;    // the solver's claims
  // A DEM code's convention (analytic/conventions.hpp): the claim is that the e it really gives
  // for each target e of the grid is within the bound (closed forms, no solver).
  std::optional<std::string> convention;
  bool limit_damping = false; // the convention's optional force cap switched on
  double bound;               // on the largest absolute error over the grid
};

// The seed's figures (judge/figures.hpp).
enum class FigureKind {
  alpha_vs_e,
  force_history,
  delta_max_vs_e,
  tau_ratio,
  phase_portrait,
  f_of_p
};
inline constexpr NameTable<FigureKind, 6> figure_kinds{
    {{FigureKind::alpha_vs_e, "alpha_vs_e"},
     {FigureKind::force_history, "force_history"},
     {FigureKind::delta_max_vs_e, "delta_max_vs_e"},
     {FigureKind::tau_ratio, "tau_ratio"},
     {FigureKind::phase_portrait, "phase_portrait"},
     {FigureKind::f_of_p, "f_of_p"}}};

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

// "overlap", "force".
inline constexpr NameTable<solvers::End, 2> contact_ends{
    {{solvers::End::overlap, "overlap"}, {solvers::End::force, "force"}}};

// What one run may spend ([limits]; `pldamp run --max-steps/--max-seconds/--max-runs`).
struct Limits {
  long max_steps = 1000000; // per solve
  double max_seconds = 30;  // per solve, wall clock
  long max_runs = 1000000;  // solver runs of the plan (onset phases and repeats included)
};

struct Scene {
  std::string path, name;
  solvers::End end = solvers::End::overlap;
  unsigned want = solvers::want_all;
  std::vector<double> p, v0, m, k;
  std::vector<Damping> damping;
  std::vector<SolverConfig> configs; // every sweep expanded, in file order
  std::vector<Claim> claims;
  std::vector<FigureSpec> figures;
  std::vector<ReportFormat> formats{ReportFormat::json, ReportFormat::csv, ReportFormat::md,
                                    ReportFormat::html};
  int repeats = 1;
  Limits limits;
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
