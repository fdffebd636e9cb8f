// What the harness tests share: a scratch folder, scene files written into it, a valid scene to
// vary, and a plan with records made by hand (for budgets and diff).
#pragma once

#include "cli_run.hpp"
#include "judge/budget.hpp"
#include "run/run.hpp"
#include "scene/scene.hpp"
#include "truth/plan.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace pldamp::harness::testing {

namespace fs = std::filesystem;

// One folder per test process: ctest runs each test case as a process of its own, in parallel, and
// two writing hand.toml into one folder read each other's half-written file. It is removed when
// the process ends (by its creator alone, never by a forked child): left behind, a CI run's
// 2 000 test processes left 8.8 GB in /tmp over a day.
inline fs::path scratch() {
  struct Folder {
    pid_t owner = ::getpid();
    fs::path path = fs::temp_directory_path() / ("pldamp-harness-test-" + std::to_string(owner));
    Folder(const Folder&) = delete;
    Folder& operator=(const Folder&) = delete;
    Folder() = default;
    ~Folder() {
      if (::getpid() == owner) {
        std::error_code ignored;
        fs::remove_all(path, ignored);
      }
    }
  };
  static const Folder folder;
  fs::create_directories(folder.path);
  return folder.path;
}

inline std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
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

// Observable `o` of `r` measured as run.cpp measures a value against its truth: the value
// `reference` + `error`, its error and its relative error (the absolute one against a reference
// 0), consistent as a record's numbers must be (common/record_consistency.hpp). A reference that
// is a power of 2 keeps the relative error exact.
inline void measure(Record& r, std::size_t o, double reference, double error) {
  r.value[o] = reference + error;
  r.reference[o] = reference;
  r.error[o] = error;
  r.abs_error[o] = std::abs(error);
  r.rel_error[o] = reference == 0 ? std::abs(error) : std::abs(error) / std::abs(reference);
}
// A record of a report given the relative error `rel_error` in `observable`, as a run would write
// it: its error (of the sign it had) and its value moved with it, against the same reference.
// Changed alone, the relative error no longer agrees with them, and diff refuses the report.
inline void set_rel_error(nlohmann::json& record, const std::string& observable, double rel_error) {
  const double reference = record["reference"][observable];
  const double error = std::copysign(rel_error * (reference == 0 ? 1 : std::abs(reference)),
                                     record["error"][observable].get<double>());
  record["value"][observable] = reference + error;
  record["error"][observable] = error;
  record["rel_error"][observable] = rel_error;
}

// The record line `index` (0-based) of a report in pldamp's layout (a record a line), without its
// comma.
inline std::string record_line(const std::string& text, std::size_t index) {
  std::istringstream in(text);
  std::size_t record = 0;
  for (std::string l; std::getline(in, l);) {
    if (l.rfind("  {\"key\":", 0) == 0 && record++ == index) {
      return l.substr(2, l.size() - 2 - (l.ends_with(",") ? 1 : 0));
    }
  }
  return "";
}

// The text with its record line `index` (0-based) replaced by `line`.
inline std::string with_record_line(const std::string& text, std::size_t index,
                                    const std::string& line) {
  std::istringstream in(text);
  std::string out;
  std::size_t record = 0;
  for (std::string l; std::getline(in, l);) {
    if (l.rfind("  {\"key\":", 0) == 0 && record++ == index) {
      l = "  " + line + (l.ends_with(",") ? "," : "");
    }
    out += l + "\n";
  }
  return out;
}

// The text with its record lines replaced by `lines`, in their order (commas as pldamp writes).
inline std::string with_records(const std::string& text, const std::vector<std::string>& lines) {
  std::istringstream in(text);
  std::string out;
  bool replaced = false;
  for (std::string l; std::getline(in, l);) {
    if (l.rfind("  {\"key\":", 0) != 0) {
      out += l + "\n";
    } else if (!replaced) {
      replaced = true;
      for (std::size_t i = 0; i < lines.size(); ++i) {
        out += "  " + lines[i] + (i + 1 < lines.size() ? ",\n" : "\n");
      }
    }
  }
  return out;
}

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
  // cells: (e=0.5, v0=1), (e=0.5, v0=10), (z=2, v0=1), (z=2, v0=10); the last two overdamped,
  // no_exit with e = 0 against a truth 0.
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
    r.value = r.reference = r.error = r.abs_error = r.rel_error =
        r.spread = {std::nullopt, std::nullopt};
    measure(r, 0, cell < 2 ? 0.5 : 0.0, abs_e[cell]);
    measure(r, 1, 1.0, rel_dm[cell]);
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
    r.value = r.reference = r.error = r.abs_error = r.rel_error =
        r.spread = {std::nullopt, std::nullopt, std::nullopt};
    if (rel_e[cell]) {
      measure(r, 0, 0.5, *rel_e[cell] * 0.5);
    } else {
      r.reference[0] = 0.5; // a truth, and no value to compare with it
    }
    measure(r, 1, 1.0, rel_load[cell]);
    measure(r, 2, 0.25, rel_unload[cell] * 0.25);
    h.records.push_back(r);
  }
  return h;
}

} // namespace pldamp::harness::testing
