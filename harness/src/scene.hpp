// A scene: what one `pldamp run` computes (DESIGN.md "Scenes"). Read from TOML by toml++; every
// problem with the file is reported as `file:line: message` before any work starts.
//
//     name = "quick"
//     end  = "overlap"                      # or "force"
//     want = ["e", "delta_max", "t_peak", "tau", "energy"]
//     [grid]      p, e and/or alpha_eff, v0, m (default [1]), k (default [1]): numbers or lists
//     [[solver]]  name; rtol (number or list; taylor: its precision's epsilon if absent); atol;
//                 precision (taylor: double|long|quad|50); steps_per_contact (verlet, list)
//     [[claim]]   name, observable, solver, rtol, atol, precision, bound (max abs error)
//     [[figure]]  kind (figures.hpp), solver, rtol, atol, p, e, alpha_eff: the seed's figures
//     [report]    formats = ["json", "csv", "md", "html"]
//     [timing]    repeats = 3   (wall time of a run: the minimum over repeats)
#pragma once

#include "format.hpp"

#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <string>
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
  std::optional<double> rtol; // none: taylor at its precision's epsilon
  std::optional<double> atol;
  std::optional<int> steps_per_contact; // verlet
  std::string label() const;            // "cvode-bdf rtol=1e-08", "taylor quad", "verlet n=50"
  bool operator==(const SolverConfig&) const = default;
};

struct Claim {
  std::string name;
  std::string observable; // e, delta_max, t_peak, tau, energy_load, energy_unload
  SolverConfig config;
  double bound; // on the largest absolute error over the grid
};

// A figure of the seed (figures.hpp): its kind, the solver behind its points, its lists.
struct FigureSpec {
  std::string kind;
  SolverConfig config;
  std::vector<double> p, e, alpha_eff;
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
  std::vector<std::string> formats{"json", "csv", "md", "html"};
  int repeats = 1;
};

// Reads and validates a scene; throws SceneError.
Scene load_scene(const std::string& path);

// The observables a Want bit set names, as reported (energy is energy_load and energy_unload).
std::vector<std::string> observable_names(unsigned want);

} // namespace pldamp::harness
