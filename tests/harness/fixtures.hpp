// What the harness tests share: a scratch folder, scene files written into it, a valid scene to
// vary, and a plan with records made by hand (for budgets and diff).
#pragma once

#include "cli_run.hpp"
#include "judge/budget.hpp"
#include "run/run.hpp"
#include "scene/scene.hpp"
#include "truth/plan.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace pldamp::harness::testing {

namespace fs = std::filesystem;

// One folder per test process: ctest runs each test case as a process of its own, in parallel, and
// two writing hand.toml into one folder read each other's half-written file.
inline fs::path scratch() {
  const fs::path dir =
      fs::temp_directory_path() / ("pldamp-harness-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

inline std::string write_file(const std::string& name, const std::string& text) {
  const fs::path path = scratch() / name;
  std::ofstream(path) << text;
  return path.string();
}

inline const std::string valid_scene = R"(name = "t"
want = ["e", "delta_max", "t_peak", "tau", "energy"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-6
)";

// A plan of 1 p × 2 dampings × 2 v0 and one configuration, with records made by hand.
struct HandMade {
  Plan plan;
  std::vector<Record> records;
};
inline HandMade hand_made() {
  const std::string path = write_file("hand.toml", R"(want = ["e", "delta_max"]
[grid]
p = [2.0]
e = [0.5]
alpha_eff = [2.0]
v0 = [1.0, 10.0]
[[claim]]
name = "tight"
observable = "e"
solver = "cvode-bdf"
rtol = 1e-8
bound = 3e-4
)");
  HandMade h{make_plan(load_scene(path)), {}};
  // cells: (e=0.5, v0=1), (e=0.5, v0=10), (z=2, v0=1), (z=2, v0=10)
  const double abs_e[] = {1e-4, 2.5e-4, 0, 0};
  const double rel_dm[] = {3e-6, 1e-6, 7e-6, 2e-6};
  const double seconds[] = {1e-3, 3e-3, 2e-3, 6e-3};
  for (std::size_t cell = 0; cell < 4; ++cell) {
    Record r;
    r.cell = cell;
    r.config = 0;
    r.outcome = cell < 2 ? solvers::Outcome::exited : solvers::Outcome::no_exit;
    r.rhs_evals = long(100 * (cell + 1));
    r.wall_seconds = seconds[cell];
    r.wall_seconds_slowest = 1.5 * seconds[cell];
    r.cpu_seconds = seconds[cell];
    r.cpu_seconds_slowest = 1.2 * seconds[cell];
    r.value = {0.5, 1.0};
    r.reference = {0.5 - abs_e[cell], 1.0 - rel_dm[cell]};
    r.error = {abs_e[cell], rel_dm[cell]};
    r.abs_error = {abs_e[cell], rel_dm[cell]};
    r.rel_error = {cell < 2 ? abs_e[cell] / 0.5 : 0.0, rel_dm[cell]};
    r.spread = {std::nullopt, std::nullopt};
    h.records.push_back(r);
  }
  return h;
}

// A plan of p = 2, e = 0.5, v0 in {0.1, 1, 10}, wanting e and the energies (e, energy_load,
// energy_unload), one configuration, with records made by hand: e within 4e-9, the energy of the
// unloading (computed by balance, ill-conditioned) off by 5e-2, and the third cell without e (an
// answer that left it out).
inline HandMade energy_worse_than_e() {
  const std::string path = write_file("energy.toml", R"(want = ["e", "energy"]
[grid]
p = [2.0]
e = [0.5]
v0 = [0.1, 1.0, 10.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-8
)");
  HandMade h{make_plan(load_scene(path)), {}};
  const std::optional<double> rel_e[] = {1e-9, 4e-9, std::nullopt};
  const double rel_load[] = {2e-9, 1e-9, 1e-9}, rel_unload[] = {3e-3, 5e-2, 1e-3};
  for (std::size_t cell = 0; cell < 3; ++cell) {
    Record r;
    r.cell = cell;
    r.config = 0;
    r.outcome = solvers::Outcome::exited;
    r.rhs_evals = long(100 * (cell + 1));
    r.wall_seconds = 1e-3 * double(cell + 1);
    r.wall_seconds_slowest = r.wall_seconds;
    r.value = {rel_e[cell] ? std::optional(0.5) : std::nullopt, 1.0, 0.25};
    r.reference = {0.5, 1.0, 0.25};
    r.rel_error = {rel_e[cell], rel_load[cell], rel_unload[cell]};
    r.abs_error = {rel_e[cell] ? std::optional(*rel_e[cell] * 0.5) : std::nullopt, rel_load[cell],
                   rel_unload[cell] * 0.25};
    r.error = r.abs_error;
    r.spread = {std::nullopt, std::nullopt, std::nullopt};
    h.records.push_back(r);
  }
  return h;
}

} // namespace pldamp::harness::testing
