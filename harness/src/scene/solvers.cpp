// [[solver]]: pldamp's registered solvers and external programs, their sweeps expanded into
// configurations; and what every entry naming a solver shares (base_config, check_config).
#include "scene/reader.hpp"

#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace pldamp::harness {

std::string SolverConfig::label() const {
  std::string out = name;
  if (precision != "double") {
    out += " " + precision;
  }
  if (rtol) {
    out += fmt::format(" rtol={:g}", *rtol);
  }
  if (atol) {
    out += fmt::format(" atol={:g}", *atol);
  }
  if (steps_per_contact) {
    out += fmt::format(" n={}", *steps_per_contact);
  }
  if (dt) {
    out += fmt::format(" dt={:g}", *dt);
  }
  if (end) {
    out += " end=" + std::string(name_of(contact_ends, *end));
  }
  if (every_phase != 0) {
    out += " phases=every";
  } else if (onset_phases > 1) {
    out += fmt::format(" phases={}", onset_phases);
  }
  if (tau_as != TauAs::first_step_out) {
    out += " tau=" + std::string(name_of(tau_as_names, tau_as));
  }
  return out;
}

bool SolverConfig::fixed_step() const {
  if (external()) {
    return steps_per_contact.has_value() || dt.has_value();
  }
  const solvers::SolverInfo* info = solvers::find_solver(name);
  return info != nullptr && info->fixed_step;
}

std::string SolverConfig::line() const {
  SolverConfig unswept = *this;
  unswept.rtol.reset();
  unswept.steps_per_contact.reset();
  unswept.dt.reset();
  return unswept.label();
}

namespace scene_reading {
namespace {

// A registered solver's name, or "unknown solver, expected ... (got name)".
const solvers::SolverInfo& registered(const Reader& reader, const toml::node& node,
                                      const std::string& name) {
  const solvers::SolverInfo* info = solvers::find_solver(name);
  if (info == nullptr) {
    reader.unknown(node, "solver", solvers::solver_names(), name);
  }
  return *info;
}

// onset_phases (fixed steps: the runs at onset phases k/n, the worst reported), none when absent.
std::optional<int> read_onset_phases(const Reader& reader, const toml::table& entry) {
  const toml::node* node = entry.get("onset_phases");
  if (node == nullptr) {
    return std::nullopt;
  }
  return static_cast<int>(reader.integer_in(*node, "onset_phases", 1, 1000));
}

std::optional<double> read_atol(const Reader& reader, const toml::table& entry) {
  const toml::node* node = entry.get("atol");
  return node ? std::optional(reader.number_in(*node, "atol", Range::above(0))) : std::nullopt;
}

} // namespace

int check_steps(const Reader& reader, const toml::node& node, double n) {
  return static_cast<int>(reader.check_integer(node, "steps_per_contact", n, 1, 1000000000));
}

int read_steps(const Reader& reader, const toml::node& node) {
  return check_steps(reader, node, reader.number(node, "steps_per_contact"));
}

SolverConfig base_config(const Reader& reader, const toml::table& entry, const char* key,
                         const std::string& where, const toml::node& at) {
  SolverConfig config;
  const toml::node* name = entry.get(key);
  if (name == nullptr) {
    reader.fail(at, where + " needs " + key);
  }
  config.name = reader.string(*name, "solver name");
  const solvers::SolverInfo& info = registered(reader, *name, config.name);
  if (const toml::node* precision = entry.get("precision")) {
    config.precision = reader.string(*precision, "precision");
    if (precision_bit(config.precision) == 0) {
      reader.fail(*precision, unknown_precision(config.precision));
    }
    if (!info.runs_in(config.precision)) {
      reader.fail(*precision, solvers::precision_refusal(info, config.precision));
    }
  }
  if (const std::optional<int> phases = read_onset_phases(reader, entry)) {
    if (!info.fixed_step) {
      reader.fail(*entry.get("onset_phases"),
                  "onset_phases is for fixed-step solvers (got " + config.name + ")");
    }
    config.onset_phases = *phases;
  }
  if (const toml::node* tau_as = entry.get("tau_as")) {
    const TauAs as = reader.choice(*tau_as, tau_as_names, "tau_as");
    if (!info.fixed_step) {
      reader.fail(*tau_as, "tau_as is for fixed-step solvers, whose contact time is counted on "
                           "steps (got " +
                               config.name + ")");
    }
    config.tau_as = as;
  }
  if ((config.atol = read_atol(reader, entry))) {
    reader.require(info.takes_atol, *entry.get("atol"),
                   config.name + (info.fixed_step ? " takes a fixed step and no atol"
                                                  : " controls its error relative to each state "
                                                    "and takes no atol"),
                   *config.atol);
  }
  return config;
}

void refuse_untaken_step_keys(const Reader& reader, const toml::table& entry,
                              const solvers::SolverInfo& info,
                              std::string_view fixed_step_instead) {
  if (const toml::node* rtol = entry.get("rtol"); rtol != nullptr && !info.takes_rtol()) {
    reader.fail(*rtol, fmt::format("rtol has no effect on fixed-step solver {}; {}", info.name,
                                   fixed_step_instead));
  }
  if (const toml::node* steps = entry.get("steps_per_contact");
      steps != nullptr && !info.fixed_step) {
    reader.fail(*steps, fmt::format("steps_per_contact has no effect on error-controlled solver "
                                    "{}; set rtol",
                                    info.name));
  }
}

// A configuration's tolerances against the precision it runs in (rtol >= its epsilon) and, for a
// literal atol, against the natural scales of every grid cell: the solvers' own checks
// (solvers::validate_against), before any work.
void check_config(const Reader& reader, const toml::node& node, const Scene& scene,
                  const SolverConfig& config) {
  try {
    with_precision(config.precision, [&]<SupportedReal Real>() {
      solvers::Options<Real> options;
      if (config.rtol) {
        options.rtol = Real(*config.rtol);
      }
      options.want = scene.want;
      options.validate();
      if (!config.atol) {
        return;
      }
      options.atol = Real(*config.atol);
      for (const double p : scene.p) {
        for (const CellScale& cell : scene_scales(scene)) {
          solvers::validate_against(
              solvers::Problem<Real>{Real(p), Real(cell.m), Real(cell.k), Real(cell.v0), Real(0)},
              options);
        }
      }
    });
  } catch (const std::invalid_argument& e) {
    reader.fail(node, config.label() + ": " + e.what());
  }
}

namespace {

// A configuration into the scene, unless it has it already (from this entry's lists or an earlier
// entry, its end the scene's by default or by name): the same runs twice would add nothing.
void add_config(const Reader& reader, const toml::node& node, Scene& scene,
                const SolverConfig& config) {
  const auto same_runs = [&](const SolverConfig& other) {
    SolverConfig unended = other;
    unended.end = config.end;
    return unended == config && end_of(scene, other) == end_of(scene, config);
  };
  if (std::any_of(scene.configs.begin(), scene.configs.end(), same_runs)) {
    reader.fail(node, config.label() + " is a configuration the scene has already");
  }
  scene.configs.push_back(config);
}

// An external solver's sweep (steps_per_contact, dt or rtol, at most one) from `entry` into
// configurations based on `base`; none: one configuration, the program's own default.
std::vector<SolverConfig> external_sweep(const Reader& reader, const toml::table& entry,
                                         const toml::node& item, const SolverConfig& base) {
  std::vector<SolverConfig> configs;
  int keys = 0;
  if (const toml::node* steps = entry.get("steps_per_contact")) {
    ++keys;
    for (const double n : reader.numbers(*steps, "steps_per_contact")) {
      configs.push_back(base);
      configs.back().steps_per_contact = check_steps(reader, *steps, n);
    }
  }
  if (const toml::node* dt = entry.get("dt")) {
    ++keys;
    for (const double value : reader.numbers(*dt, "dt")) {
      reader.check_in(*dt, "dt", value, Range::above(0));
      configs.push_back(base);
      configs.back().dt = value;
    }
  }
  if (const toml::node* rtol = entry.get("rtol")) {
    ++keys;
    for (const double value : reader.numbers(*rtol, "rtol")) {
      reader.check_in(*rtol, "rtol", value, rtol_range);
      configs.push_back(base);
      configs.back().rtol = value;
    }
  }
  if (keys > 1) {
    reader.fail(item, "an external solver sweeps one of steps_per_contact, dt and rtol");
  }
  if (keys == 0) {
    configs.push_back(base);
  }
  if (base.onset_phases > 1 && !configs.front().fixed_step()) {
    reader.fail(*entry.get("onset_phases"), "onset_phases needs steps_per_contact or dt");
  }
  return configs;
}

// The program of a command, so that a scene runs from anywhere: a relative path ("./prog",
// "../x/prog") is the scene file's folder's; a bare name is the file of that name beside the
// scene when there is one, else found on PATH. A resolved path keeps a '/' ("./prog"), so that
// it is not looked up on PATH. Messages name the program as typed.
std::string resolved_program(const std::string& typed, const Scene& scene) {
  const std::filesystem::path program(typed);
  const std::filesystem::path folder = std::filesystem::path(scene.path).parent_path();
  const bool bare = typed.find('/') == std::string::npos;
  std::error_code ignored;
  if (program.is_relative() &&
      (!bare || std::filesystem::is_regular_file(folder / program, ignored))) {
    std::string resolved = (folder / program).lexically_normal().string();
    return resolved.find('/') == std::string::npos ? "./" + resolved : resolved;
  }
  return typed;
}

// [[solver]] with a command: a program speaking the protocol of run/external.hpp.
void read_external_solver(const Reader& reader, const toml::table& entry, const toml::node& item,
                          Scene& scene) {
  reader.only(entry, {scene_keys::external_solver}, "[[solver]] with a command");
  SolverConfig base;
  const toml::node* command = entry.get("command");
  base.command = reader.strings(*command, "command");
  if (base.command.empty() ||
      std::any_of(base.command.begin(), base.command.end(),
                  [](const std::string& arg) { return arg.find('\0') != std::string::npos; }) ||
      base.command.front().empty()) {
    reader.fail(*command, "command must be a non-empty list of strings, the program first");
  }
  base.program = base.command.front();
  base.command.front() = resolved_program(base.program, scene);
  const toml::node* label = entry.get("label");
  if (label == nullptr) {
    reader.fail(item, "[[solver]] with a command needs a label");
  }
  base.name = reader.string(*label, "label");
  if (base.name.empty() || base.name.size() > 100 ||
      std::any_of(base.name.begin(), base.name.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; })) {
    reader.fail(*label, "label must be 1 to 100 printable characters");
  }
  if (solvers::find_solver(base.name) != nullptr) {
    reader.fail(*label, "label names a registered solver (got " + base.name + ")");
  }
  if (std::any_of(scene.configs.begin(), scene.configs.end(),
                  [&](const SolverConfig& other) { return other.name == base.name; })) {
    reader.fail(*label, "another [[solver]] has this label (got " + base.name + ")");
  }
  if (const toml::node* precision = entry.get("precision")) {
    if (reader.string(*precision, "precision") != "double") {
      reader.fail(*precision, "an external solver answers in double (got " +
                                  reader.string(*precision, "precision") + ")");
    }
  }
  if (const toml::node* options = entry.get("options")) {
    std::ostringstream json;
    json << toml::json_formatter{reader.table(*options, "options")};
    base.options = nlohmann::json::parse(json.str()).dump();
  }
  base.atol = read_atol(reader, entry);
  base.onset_phases = read_onset_phases(reader, entry).value_or(base.onset_phases);
  if (const toml::node* replica = entry.get("replica")) {
    base.replica = reader.string(*replica, "replica");
    const solvers::SolverInfo& info = registered(reader, *replica, base.replica);
    const bool stepped = entry.get("steps_per_contact") != nullptr || entry.get("dt") != nullptr;
    if (info.fixed_step != stepped || (base.atol && !info.takes_atol)) {
      reader.fail(*replica, "the replica must take what the program is given (" +
                                std::string(stepped ? "steps_per_contact or dt" : "rtol") +
                                ") (got " + base.replica + ")");
    }
  }
  for (const std::optional<solvers::End>& end : read_ends(reader, entry)) {
    base.end = end;
    const toml::node* swept = entry.get("steps_per_contact") ? entry.get("steps_per_contact")
                              : entry.get("dt")              ? entry.get("dt")
                                                             : entry.get("rtol");
    for (const SolverConfig& config : external_sweep(reader, entry, item, base)) {
      add_config(reader, swept ? *swept : item, scene, config);
    }
  }
}

} // namespace

void read_solvers(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "solver")) {
    const toml::table& entry = reader.table(item, "[[solver]]");
    if (entry.get("command") != nullptr) {
      read_external_solver(reader, entry, item, scene);
      continue;
    }
    reader.only(entry, {scene_keys::solver}, "[[solver]]");
    const SolverConfig first = base_config(reader, entry, "name", "[[solver]]", item);
    const solvers::SolverInfo& info = solvers::solver_named(first.name);
    const bool fixed_step = info.fixed_step;
    for (const std::optional<solvers::End>& end : read_ends(reader, entry)) {
      SolverConfig base = first;
      base.end = end;
      if (fixed_step && entry.get("rtol") != nullptr) {
        reader.fail(*entry.get("rtol"),
                    base.name +
                        " takes a fixed step and no rtol: give steps_per_contact (got rtol)");
      }
      if (const toml::node* steps = entry.get("steps_per_contact")) {
        if (!fixed_step) {
          reader.fail(*steps,
                      "steps_per_contact is for fixed-step solvers (got " + base.name + ")");
        }
        for (const double n : reader.numbers(*steps, "steps_per_contact")) {
          SolverConfig config = base;
          config.steps_per_contact = check_steps(reader, *steps, n);
          check_config(reader, item, scene, config);
          add_config(reader, *steps, scene, config);
        }
        continue;
      }
      if (const toml::node* rtol = entry.get("rtol")) {
        for (const double value : reader.numbers(*rtol, "rtol")) {
          reader.check_in(*rtol, "rtol", value, rtol_range);
          SolverConfig config = base;
          config.rtol = value;
          check_config(reader, *rtol, scene, config);
          add_config(reader, *rtol, scene, config);
        }
        continue;
      }
      if (info.default_tolerance != solvers::DefaultTolerance::epsilon && !fixed_step) {
        reader.fail(item, "[[solver]] " + base.name + " needs rtol (a number or a list)");
      }
      SolverConfig config = base;
      if (fixed_step) {
        config.steps_per_contact = 50;
      }
      check_config(reader, item, scene, config);
      add_config(reader, item, scene, config);
    }
  }
}

} // namespace scene_reading
} // namespace pldamp::harness
