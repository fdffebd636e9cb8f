#include "scene/scene.hpp"

#include "common/observables.hpp"

#include "pldamp/analytic/conventions.hpp"
#include "pldamp/core/domain.hpp"
#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string_view>

namespace pldamp::harness {
namespace {

std::string shortest(double x) {
  return to_string_full(x);
}

// Reports problems at the line of the node they concern.
class Reader {
public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const toml::node& at, const std::string& what) const {
    fail_at(at.source().begin.line, what);
  }
  [[noreturn]] void fail_at(std::size_t line, const std::string& what) const {
    throw SceneError(path_ + ":" + std::to_string(line) + ": " + what);
  }

  // Every key of `table` must be one of `allowed`.
  void only(const toml::table& table, std::initializer_list<std::string_view> allowed,
            const std::string& where) const {
    only(table, std::vector<std::string_view>(allowed), where);
  }
  void only(const toml::table& table, const std::vector<std::string_view>& allowed,
            const std::string& where) const {
    for (const auto& [key, node] : table) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end()) {
        std::string names;
        for (const std::string_view name : allowed) {
          if (!names.empty()) {
            names += '|';
          }
          names.append(name);
        }
        fail(node, "unknown key in " + where + ", expected " + names + " (got " +
                       std::string(key.str()) + ")");
      }
    }
  }

  double number(const toml::node& node, const std::string& what) const {
    if (const auto value = node.value<double>();
        value && (node.is_floating_point() || node.is_integer())) {
      if (!std::isfinite(*value)) {
        fail(node, what + " must be finite (got " + shortest(*value) + ")");
      }
      return *value;
    }
    fail(node, what + " must be a number (got " + type_of(node) + ")");
  }
  // A number or a non-empty list of numbers.
  std::vector<double> numbers(const toml::node& node, const std::string& what) const {
    std::vector<double> out;
    if (const toml::array* list = node.as_array()) {
      for (const toml::node& item : *list) {
        out.push_back(number(item, what));
      }
      if (out.empty()) {
        fail(node, what + " is an empty list");
      }
      return out;
    }
    return {number(node, what)};
  }
  std::string string(const toml::node& node, const std::string& what) const {
    if (const auto value = node.value<std::string>(); value && node.is_string()) {
      return *value;
    }
    fail(node, what + " must be a string (got " + type_of(node) + ")");
  }
  std::vector<std::string> strings(const toml::node& node, const std::string& what) const {
    std::vector<std::string> out;
    if (const toml::array* list = node.as_array()) {
      for (const toml::node& item : *list) {
        out.push_back(string(item, what));
      }
      return out;
    }
    return {string(node, what)};
  }
  // The entries of an array of tables, [[key]].
  const toml::array& entries(const toml::node& node, const std::string& key) const {
    if (const toml::array* list = node.as_array()) {
      return *list;
    }
    fail(node, key + " must be an array of tables ([[" + key + "]])");
  }
  const toml::table& table(const toml::node& node, const std::string& what) const {
    if (const toml::table* t = node.as_table()) {
      return *t;
    }
    fail(node, what + " must be a table (got " + type_of(node) + ")");
  }

  // Checks a condition on a value read from `node`.
  void require(bool ok, const toml::node& node, const std::string& what, double value) const {
    if (!ok) {
      fail(node, what + " (got " + shortest(value) + ")");
    }
  }

private:
  static std::string type_of(const toml::node& node) {
    std::ostringstream out;
    out << node.type();
    return out.str();
  }
  std::string path_;
};

unsigned read_want(const Reader& reader, const toml::node& node) {
  unsigned want = 0;
  const std::vector<std::string> words = reader.strings(node, "want");
  try {
    want = parse_want(words, "want", false);
  } catch (const std::invalid_argument& e) {
    reader.fail(node, e.what());
  }
  if (want == 0) {
    reader.fail(node, "want names no observable");
  }
  return want;
}

// [report] work_precision: observables the scene wants, or the worst of all, each once.
std::vector<std::string> read_work_precision(const Reader& reader, const toml::node& node,
                                             unsigned want) {
  const std::vector<const Observable*> wanted = observables_of(want);
  std::string words;
  for (const Observable* observable : wanted) {
    words += std::string(observable->key) + "|";
  }
  words += worst_of_all_key;
  const std::vector<std::string> keys = reader.strings(node, "work_precision");
  if (keys.empty()) {
    reader.fail(node, "work_precision names nothing, expected some of " + words);
  }
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::string& key = keys[i];
    if (key != worst_of_all_key &&
        std::none_of(wanted.begin(), wanted.end(),
                     [&](const Observable* observable) { return observable->key == key; })) {
      reader.fail(node, "work_precision names an observable the scene does not want, expected " +
                            words + " (got " + key + ")");
    }
    if (std::find(keys.begin(), keys.begin() + std::ptrdiff_t(i), key) !=
        keys.begin() + std::ptrdiff_t(i)) {
      reader.fail(node, "work_precision names " + key + " twice");
    }
  }
  return keys;
}

// The solver (under `key`: name in [[solver]], solver in [[claim]] and [[figure]]), precision and
// atol of an entry; tolerances and steps are the caller's.
SolverConfig base_config(const Reader& reader, const toml::table& entry, const char* key,
                         const std::string& where, const toml::node& at) {
  SolverConfig config;
  const toml::node* name = entry.get(key);
  if (name == nullptr) {
    reader.fail(at, where + " needs " + key);
  }
  config.name = reader.string(*name, "solver name");
  const solvers::SolverInfo* info = solvers::find_solver(config.name);
  if (info == nullptr) {
    reader.fail(*name, "unknown solver, expected " + solvers::solver_names() + " (got " +
                           config.name + ")");
  }
  if (const toml::node* precision = entry.get("precision")) {
    config.precision = reader.string(*precision, "precision");
    if (precision_bit(config.precision) == 0) {
      reader.fail(*precision, unknown_precision(config.precision));
    }
    if (!info->runs_in(config.precision)) {
      reader.fail(*precision, solvers::precision_refusal(*info, config.precision));
    }
  }
  if (const toml::node* phases = entry.get("onset_phases")) {
    const double n = reader.number(*phases, "onset_phases");
    reader.require(n >= 1 && n <= 1000 && n == std::floor(n), *phases,
                   "onset_phases must be an integer in [1, 1000]", n);
    if (!info->fixed_step) {
      reader.fail(*phases, "onset_phases is for fixed-step solvers (got " + config.name + ")");
    }
    config.onset_phases = static_cast<int>(n);
  }
  if (const toml::node* atol = entry.get("atol")) {
    config.atol = reader.number(*atol, "atol");
    reader.require(*config.atol > 0, *atol, "atol must be > 0", *config.atol);
    reader.require(info->takes_atol, *atol,
                   config.name + (info->fixed_step ? " takes a fixed step and no atol"
                                                   : " controls its error relative to each state "
                                                     "and takes no atol"),
                   *config.atol);
  }
  return config;
}

void check_rtol(const Reader& reader, const toml::node& node, double rtol) {
  reader.require(rtol > 0 && rtol < 1, node, "rtol must be in (0, 1)", rtol);
}

int steps_per_contact(const Reader& reader, const toml::node& node, double n) {
  reader.require(n >= 1 && n <= 1e9 && n == std::floor(n), node,
                 "steps_per_contact must be an integer in [1, 1e9]", n);
  return static_cast<int>(n);
}

// The contact ends of an entry's `end` key (a word or a list), none when absent.
std::vector<std::optional<solvers::End>> read_ends(const Reader& reader, const toml::table& entry) {
  const toml::node* node = entry.get("end");
  if (node == nullptr) {
    return {std::nullopt};
  }
  std::vector<std::optional<solvers::End>> ends;
  for (const std::string& name : reader.strings(*node, "end")) {
    const std::optional<solvers::End> end = value_named(contact_ends, name);
    if (!end) {
      reader.fail(*node, "unknown contact end, expected " + names_of(contact_ends) + " (got " +
                             name + ")");
    }
    ends.push_back(end);
  }
  if (ends.empty()) {
    reader.fail(*node, "end is an empty list");
  }
  return ends;
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
        for (const double v0 : scene.v0) {
          for (const double m : scene.m) {
            for (const double k : scene.k) {
              solvers::validate_against(
                  solvers::Problem<Real>{Real(p), Real(m), Real(k), Real(v0), Real(0)}, options);
            }
          }
        }
      }
    });
  } catch (const std::invalid_argument& e) {
    reader.fail(node, config.label() + ": " + e.what());
  }
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
      configs.back().steps_per_contact = steps_per_contact(reader, *steps, n);
    }
  }
  if (const toml::node* dt = entry.get("dt")) {
    ++keys;
    for (const double value : reader.numbers(*dt, "dt")) {
      reader.require(value > 0, *dt, "dt must be > 0", value);
      configs.push_back(base);
      configs.back().dt = value;
    }
  }
  if (const toml::node* rtol = entry.get("rtol")) {
    ++keys;
    for (const double value : reader.numbers(*rtol, "rtol")) {
      check_rtol(reader, *rtol, value);
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

// [[solver]] with a command: a program speaking the protocol of run/external.hpp.
void read_external_solver(const Reader& reader, const toml::table& entry, const toml::node& item,
                          Scene& scene) {
  reader.only(entry,
              {"command", "label", "options", "replica", "rtol", "atol", "steps_per_contact", "dt",
               "end", "onset_phases", "precision"},
              "[[solver]] with a command");
  SolverConfig base;
  const toml::node* command = entry.get("command");
  base.command = reader.strings(*command, "command");
  if (base.command.empty() ||
      std::any_of(base.command.begin(), base.command.end(),
                  [](const std::string& arg) { return arg.find('\0') != std::string::npos; }) ||
      base.command.front().empty()) {
    reader.fail(*command, "command must be a non-empty list of strings, the program first");
  }
  // The program, so that a scene runs from anywhere: a relative path ("./prog", "../x/prog") is
  // the scene file's folder's; a bare name is the file of that name beside the scene when there
  // is one, else found on PATH. A resolved path keeps a '/' ("./prog"), so that it is not
  // looked up on PATH. Messages name the program as typed.
  base.program = base.command.front();
  const std::filesystem::path program(base.program);
  const std::filesystem::path folder = std::filesystem::path(scene.path).parent_path();
  const bool bare = base.program.find('/') == std::string::npos;
  std::error_code ignored;
  if (program.is_relative() &&
      (!bare || std::filesystem::is_regular_file(folder / program, ignored))) {
    std::string resolved = (folder / program).lexically_normal().string();
    base.command.front() = resolved.find('/') == std::string::npos ? "./" + resolved : resolved;
  }
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
  if (const toml::node* atol = entry.get("atol")) {
    base.atol = reader.number(*atol, "atol");
    reader.require(*base.atol > 0, *atol, "atol must be > 0", *base.atol);
  }
  if (const toml::node* phases = entry.get("onset_phases")) {
    const double n = reader.number(*phases, "onset_phases");
    reader.require(n >= 1 && n <= 1000 && n == std::floor(n), *phases,
                   "onset_phases must be an integer in [1, 1000]", n);
    base.onset_phases = static_cast<int>(n);
  }
  if (const toml::node* replica = entry.get("replica")) {
    base.replica = reader.string(*replica, "replica");
    const solvers::SolverInfo* info = solvers::find_solver(base.replica);
    if (info == nullptr) {
      reader.fail(*replica, "unknown solver, expected " + solvers::solver_names() + " (got " +
                                base.replica + ")");
    }
    const bool stepped = entry.get("steps_per_contact") != nullptr || entry.get("dt") != nullptr;
    if (info->fixed_step != stepped || (base.atol && !info->takes_atol)) {
      reader.fail(*replica, "the replica must take what the program is given (" +
                                std::string(stepped ? "steps_per_contact or dt" : "rtol") +
                                ") (got " + base.replica + ")");
    }
  }
  for (const std::optional<solvers::End>& end : read_ends(reader, entry)) {
    base.end = end;
    for (const SolverConfig& config : external_sweep(reader, entry, item, base)) {
      scene.configs.push_back(config);
    }
  }
}

void read_solvers(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "solver")) {
    const toml::table& entry = reader.table(item, "[[solver]]");
    if (entry.get("command") != nullptr) {
      read_external_solver(reader, entry, item, scene);
      continue;
    }
    reader.only(entry,
                {"name", "rtol", "atol", "precision", "steps_per_contact", "end", "onset_phases"},
                "[[solver]]");
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
          config.steps_per_contact = steps_per_contact(reader, *steps, n);
          check_config(reader, item, scene, config);
          scene.configs.push_back(config);
        }
        continue;
      }
      if (const toml::node* rtol = entry.get("rtol")) {
        for (const double value : reader.numbers(*rtol, "rtol")) {
          check_rtol(reader, *rtol, value);
          SolverConfig config = base;
          config.rtol = value;
          check_config(reader, *rtol, scene, config);
          scene.configs.push_back(config);
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
      scene.configs.push_back(config);
    }
  }
}

// A claim on a DEM code's calibration: the e it gives for the grid's target e (needs them, and a
// p the code has a model for).
void read_convention_claim(const Reader& reader, const toml::table& entry, const toml::node& item,
                           const toml::node& node, Scene& scene, Claim& claim) {
  reader.only(entry,
              {"name", "kind", "where", "quote", "figure", "expect", "observable", "convention",
               "limit_damping", "bound", "bound_rel", "quantile", "p", "e", "denser"},
              "[[claim]]");
  const std::string name = reader.string(node, "convention");
  const analytic::Convention* convention = analytic::find_convention(name);
  if (convention == nullptr) {
    reader.fail(node, "unknown convention, expected " + analytic::convention_names() + " (got " +
                          name + ")");
  }
  if (claim.observable != "e") {
    reader.fail(*entry.get("observable"),
                "a convention's claim is about the e it gives: observable must be e (got " +
                    claim.observable + ")");
  }
  if (const toml::node* limit = entry.get("limit_damping")) {
    if (!limit->is_boolean()) {
      reader.fail(*limit, "limit_damping must be true or false");
    }
    claim.limit_damping = *limit->value<bool>();
  }
  const bool targets = std::any_of(claim.grid.damping.begin(), claim.grid.damping.end(),
                                   [](const Damping& d) { return d.kind == Damping::Kind::e; });
  const bool models = std::any_of(claim.grid.p.begin(), claim.grid.p.end(), [&](double p) {
    return (convention->linear && p == 1) || (convention->hertz && p == 1.5);
  });
  if (!targets || !models) {
    reader.fail(item, "[[claim]] " + claim.name + " needs target e and a p " + name +
                          " has a model for (" + (convention->linear ? "1 or 1.5" : "1.5") + ")");
  }
  claim.convention = name;
  scene.claims.push_back(claim);
}

// A keyword of a NameTable, or the one-line refusal naming the choices.
template <class Enum, std::size_t N>
Enum keyword(const Reader& reader, const toml::node& node, const NameTable<Enum, N>& table,
             const std::string& what) {
  const std::string name = reader.string(node, what);
  const std::optional<Enum> value = value_named(table, name);
  if (!value) {
    reader.fail(node, "unknown " + what + ", expected " + names_of(table) + " (got " + name + ")");
  }
  return *value;
}

bool boolean(const Reader& reader, const toml::node& node, const std::string& what) {
  if (!node.is_boolean()) {
    reader.fail(node, what + " must be true or false");
  }
  return *node.value<bool>();
}

constexpr std::array grid_keys{"p", "e", "alpha", "alpha_eff", "v0", "m", "k"};

// The grid lists of a [grid] or a claim (p, e, alpha, alpha_eff, v0, m, k) that `table` has,
// each value checked against the domain (core/domain.hpp); the others stay as they are in `grid`.
// e, alpha and alpha_eff replace its damping together.
void read_grid_lists(const Reader& reader, const toml::table& table, ClaimGrid& grid) {
  auto list = [&](const char* key, std::vector<double>& into, auto&& check) {
    if (const toml::node* at = table.get(key)) {
      into = reader.numbers(*at, key);
      for (const double value : into) {
        try {
          check(value);
        } catch (const std::invalid_argument& e) {
          reader.fail(*at, e.what());
        }
      }
    }
  };
  list("p", grid.p, [](double p) { domain::require_p(p); });
  list("v0", grid.v0, [](double x) { domain::require_scale("v0", x); });
  list("m", grid.m, [](double x) { domain::require_scale("m", x); });
  list("k", grid.k, [](double x) { domain::require_scale("k", x); });
  std::vector<double> es, alphas, zs;
  list("e", es, [](double x) { require(x > 0 && x <= 1, "e must be in (0, 1]", x); });
  list("alpha", alphas, [](double a) { domain::require_alpha(a); });
  list("alpha_eff", zs, [](double z) { domain::require_alpha_eff(z); });
  if (!es.empty() || !alphas.empty() || !zs.empty()) {
    grid.damping.clear();
    for (const auto& [kind, values] :
         {std::pair{Damping::Kind::e, &es}, std::pair{Damping::Kind::alpha, &alphas},
          std::pair{Damping::Kind::alpha_eff, &zs}}) {
      for (const double value : *values) {
        grid.damping.push_back({kind, value});
      }
    }
  }
}

// A bound on an error: `bound` (absolute) or `bound_rel` (relative), one of them, and the
// quantile of the cells it holds over (default 1: every cell).
void read_error_bound(const Reader& reader, const toml::table& entry, const toml::node& item,
                      const std::string& where, double& bound, bool& relative, double& quantile) {
  const toml::node* absolute = entry.get("bound");
  const toml::node* rel = entry.get("bound_rel");
  if ((absolute == nullptr) == (rel == nullptr)) {
    reader.fail(absolute != nullptr ? *absolute : item,
                where + " needs one of bound (absolute error) and bound_rel (relative error)");
  }
  relative = rel != nullptr;
  const toml::node& node = relative ? *rel : *absolute;
  bound = reader.number(node, relative ? "bound_rel" : "bound");
  reader.require(bound > 0, node, std::string(relative ? "bound_rel" : "bound") + " must be > 0",
                 bound);
  if (const toml::node* q = entry.get("quantile")) {
    quantile = reader.number(*q, "quantile");
    reader.require(quantile > 0 && quantile <= 1, *q, "quantile must be in (0, 1]", quantile);
  }
}

void read_trajectories(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "trajectory")) {
    const toml::table& entry = reader.table(item, "[[trajectory]]");
    reader.only(entry, {"file", "label", "p", "e", "alpha", "alpha_eff", "v0", "m", "k", "end"},
                "[[trajectory]]");
    TrajectorySpec spec;
    for (const char* key : {"file", "p", "v0"}) {
      if (entry.get(key) == nullptr) {
        reader.fail(item, std::string("[[trajectory]] needs ") + key);
      }
    }
    const std::string file = reader.string(*entry.get("file"), "file");
    spec.file =
        (std::filesystem::path(scene.path).parent_path() / file).lexically_normal().string();
    if (!std::filesystem::is_regular_file(spec.file)) {
      reader.fail(*entry.get("file"), "no such trajectory file (got " + spec.file + ")");
    }
    spec.label = entry.get("label") ? reader.string(*entry.get("label"), "label") : file;
    int dampings = 0;
    for (const char* key : {"e", "alpha", "alpha_eff"}) {
      if (const toml::node* value = entry.get(key)) {
        ++dampings;
        spec.damping_key = key;
        spec.damping = reader.number(*value, key);
      }
    }
    if (dampings != 1) {
      reader.fail(item, "[[trajectory]] needs exactly one of e, alpha and alpha_eff");
    }
    try {
      spec.p = reader.number(*entry.get("p"), "p");
      domain::require_p(spec.p);
      spec.v0 = reader.number(*entry.get("v0"), "v0");
      for (auto [key, value] :
           {std::pair{"v0", &spec.v0}, std::pair{"m", &spec.m}, std::pair{"k", &spec.k}}) {
        if (const toml::node* given = entry.get(key)) {
          *value = reader.number(*given, key);
        }
        domain::require_scale(key, *value);
      }
      if (spec.damping_key == "alpha") {
        domain::require_alpha(spec.damping);
      } else if (spec.damping_key == "alpha_eff") {
        domain::require_alpha_eff(spec.damping);
      } else {
        require(spec.damping > 0 && spec.damping <= 1, "e must be in (0, 1]", spec.damping);
      }
    } catch (const std::invalid_argument& e) {
      reader.fail(item, e.what());
    }
    const std::vector<std::optional<solvers::End>> ends = read_ends(reader, entry);
    if (ends.size() != 1) {
      reader.fail(*entry.get("end"), "a trajectory's end is one contact end (got a list)");
    }
    spec.end = ends.front();
    scene.trajectories.push_back(spec);
  }
}

// The external [[solver]] a [[claim]]'s `solver` names by its label, or nullptr.
const SolverConfig* external_named(const Reader& reader, const toml::table& entry,
                                   const Scene& scene) {
  const toml::node* solver = entry.get("solver");
  if (solver == nullptr) {
    return nullptr;
  }
  const std::string name = reader.string(*solver, "solver");
  for (const SolverConfig& config : scene.configs) {
    if (config.external() && config.name == name) {
      return &config;
    }
  }
  return nullptr;
}

// The scene with a grid's cells (p, v0, m, k), against which a claim's solver is checked.
Scene with_cells(const Scene& scene, const ClaimGrid& grid) {
  Scene cells = scene;
  cells.p = grid.p;
  cells.v0 = grid.v0;
  cells.m = grid.m;
  cells.k = grid.k;
  return cells;
}

// The solver of a claim of the new kinds, in double (the seed's own runs were double): name,
// rtol (error-controlled) or steps_per_contact (fixed-step; stability needs none), atol.
SolverConfig claim_solver(const Reader& reader, const toml::table& entry, const toml::node& item,
                          const Scene& scene, ClaimKind kind) {
  SolverConfig config = base_config(reader, entry, "solver", "[[claim]]", item);
  const solvers::SolverInfo& info = solvers::solver_named(config.name);
  if (kind == ClaimKind::stability) {
    if (!info.fixed_step) {
      reader.fail(*entry.get("solver"), "a stability claim is about a fixed-step scheme (got " +
                                            config.name + ", which controls its error)");
    }
    return config;
  }
  if (info.fixed_step) {
    const toml::node* steps = entry.get("steps_per_contact");
    config.steps_per_contact =
        steps ? steps_per_contact(reader, *steps, reader.number(*steps, "steps_per_contact")) : 50;
  } else if (const toml::node* rtol = entry.get("rtol")) {
    config.rtol = reader.number(*rtol, "rtol");
    check_rtol(reader, *rtol, *config.rtol);
  } else if (info.default_tolerance != solvers::DefaultTolerance::epsilon) {
    reader.fail(item, "[[claim]] needs the rtol of its solver");
  }
  check_config(reader, item, scene, config);
  return config;
}

// relation, asymptotic, recovered_parameter, stability: a claim judged on a grid of its own.
void read_grid_claim(const Reader& reader, const toml::table& entry, const toml::node& item,
                     Scene& scene, Claim& claim) {
  static constexpr std::array common{"name",   "kind", "where", "quote", "figure", "expect",
                                     "denser", "p",    "v0",    "m",     "k"};
  std::vector<std::string_view> allowed(common.begin(), common.end());
  auto allow = [&](std::initializer_list<std::string_view> keys) {
    allowed.insert(allowed.end(), keys.begin(), keys.end());
  };
  auto need = [&](const char* key) -> const toml::node& {
    if (entry.get(key) == nullptr) {
      reader.fail(item, "[[claim]] " + claim.name + " (" +
                            std::string(name_of(claim_kinds, claim.kind)) + ") needs " + key);
    }
    return *entry.get(key);
  };
  auto formula = [&]() {
    const toml::node& node = need("formula");
    const std::string name = reader.string(node, "formula");
    const analytic::seed::FormulaInfo* found = analytic::seed::find_formula(name);
    if (found == nullptr) {
      std::string names;
      for (const analytic::seed::FormulaInfo& info : analytic::seed::formulas) {
        names += (names.empty() ? "" : "|") + std::string(info.name);
      }
      reader.fail(node, "unknown formula, expected " + names + " (got " + name + ")");
    }
    claim.formula = found->formula;
  };
  const bool solver = entry.get("solver") != nullptr;
  auto truth_or_solver = [&]() {
    allow({"quantity", "formula", "of", "solver", "rtol", "atol", "steps_per_contact"});
    claim.quantity = keyword(reader, need("quantity"), quantities, "quantity");
    formula();
    if (const toml::node* of = entry.get("of")) {
      if (reader.string(*of, "of") != "truth" || solver) {
        reader.fail(*of, "of = \"truth\" (the closed forms) or a solver = NAME, not both");
      }
      claim.of_truth = true;
    } else if (!solver) {
      reader.fail(item, "[[claim]] " + claim.name + " needs of = \"truth\" or a solver");
    }
  };
  switch (claim.kind) {
  case ClaimKind::relation: {
    truth_or_solver();
    allow({"relation", "tolerance", "absolute", "e", "alpha_eff"});
    claim.relation = keyword(reader, need("relation"), relations, "relation");
    // The truth's own accuracy in float128 when no tolerance is given.
    claim.bound = 1e-25;
    if (const toml::node* tolerance = entry.get("tolerance")) {
      claim.bound = reader.number(*tolerance, "tolerance");
      reader.require(claim.bound >= 0 && claim.bound < 1e300, *tolerance, "tolerance must be >= 0",
                     claim.bound);
    } else if (!claim.of_truth || claim.relation == Relation::equal_within) {
      need("tolerance");
    }
    if (const toml::node* absolute = entry.get("absolute")) {
      claim.absolute = boolean(reader, *absolute, "absolute");
    }
    break;
  }
  case ClaimKind::asymptotic: {
    truth_or_solver();
    allow({"order", "range", "points"});
    claim.bound = reader.number(need("order"), "order");
    reader.require(claim.bound > 0 && claim.bound <= 20, need("order"), "order must be in (0, 20]",
                   claim.bound);
    if (const toml::node* range = entry.get("range")) {
      const std::vector<double> ends = reader.numbers(*range, "range");
      if (ends.size() != 2 || !(ends[0] > 0 && ends[1] < 1 && ends[1] >= 100 * ends[0])) {
        reader.fail(*range, "range must be [from, to] in alpha_eff with 0 < from, to < 1 and at "
                            "least two decades (to >= 100 from)");
      }
      claim.range = {ends[0], ends[1]};
    }
    if (const toml::node* points = entry.get("points")) {
      const double n = reader.number(*points, "points");
      reader.require(n >= 3 && n <= 1000 && n == std::floor(n), *points,
                     "points must be an integer in [3, 1000]", n);
      claim.points = static_cast<int>(n);
    }
    break;
  }
  case ClaimKind::recovered_parameter:
    allow({"solver", "rtol", "atol", "steps_per_contact", "bound", "e"});
    claim.bound = reader.number(need("bound"), "bound");
    reader.require(claim.bound > 0, need("bound"), "bound must be > 0", claim.bound);
    need("solver");
    break;
  case ClaimKind::stability:
    allow({"solver", "formula", "fraction", "e", "alpha_eff"});
    formula();
    if (const toml::node* fraction = entry.get("fraction")) {
      claim.fraction = reader.number(*fraction, "fraction");
      reader.require(claim.fraction > 0 && claim.fraction <= 10, *fraction,
                     "fraction must be in (0, 10]", claim.fraction);
    }
    if (claim.formula != analytic::seed::Formula::dt_crit) {
      reader.fail(*entry.get("formula"), "a stability claim compares with a time step: formula "
                                         "must be seed_dt_crit");
    }
    claim.bound = 1;
    need("solver");
    break;
  case ClaimKind::bound:
    break;
  }
  reader.only(entry, allowed, "[[claim]] of kind " + std::string(name_of(claim_kinds, claim.kind)));
  claim.grid = ClaimGrid{scene.p, scene.v0, scene.m, scene.k, scene.damping};
  read_grid_lists(reader, entry, claim.grid);
  if (solver || claim.kind == ClaimKind::recovered_parameter ||
      claim.kind == ClaimKind::stability) {
    // The solver's tolerances are checked against the claim's own cells.
    claim.config = claim_solver(reader, entry, item, with_cells(scene, claim.grid), claim.kind);
  }
  const bool targets =
      std::all_of(claim.grid.damping.begin(), claim.grid.damping.end(),
                  [](const Damping& d) { return d.kind == Damping::Kind::e && d.value < 1; });
  if (claim.kind == ClaimKind::recovered_parameter && !targets) {
    reader.fail(item, "[[claim]] " + claim.name +
                          " recovers alpha for target e: its grid needs "
                          "e in (0, 1), not alpha or alpha_eff");
  }
  if (const toml::node* denser = entry.get("denser")) {
    claim.denser = boolean(reader, *denser, "denser");
  }
  scene.claims.push_back(claim);
}

// A bound claim's grid (the scene's, or its own lists), denser and allow_missing.
void read_bound_grid(const Reader& reader, const toml::table& entry, const Scene& scene,
                     Claim& claim) {
  claim.grid = ClaimGrid{scene.p, scene.v0, scene.m, scene.k, scene.damping};
  read_grid_lists(reader, entry, claim.grid);
  claim.own_grid = std::any_of(grid_keys.begin(), grid_keys.end(),
                               [&](const char* key) { return entry.get(key) != nullptr; });
  if (const toml::node* denser = entry.get("denser")) {
    claim.denser = boolean(reader, *denser, "denser");
  }
  if (const toml::node* allow = entry.get("allow_missing")) {
    claim.allow_missing = boolean(reader, *allow, "allow_missing");
  }
}

void read_claims(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "claim")) {
    const toml::table& entry = reader.table(item, "[[claim]]");
    Claim claim;
    if (entry.get("name") == nullptr) {
      reader.fail(item, "[[claim]] needs name");
    }
    claim.name = reader.string(*entry.get("name"), "claim name");
    if (const toml::node* kind = entry.get("kind")) {
      claim.kind = keyword(reader, *kind, claim_kinds, "claim kind");
    }
    for (const char* key : {"where", "quote"}) {
      if (const toml::node* text = entry.get(key)) {
        (key[0] == 'w' ? claim.where : claim.quote) = reader.string(*text, key);
      }
    }
    if (const toml::node* figure = entry.get("figure")) {
      claim.figure =
          std::string(name_of(figure_kinds, keyword(reader, *figure, figure_kinds, "figure")));
    }
    if (const toml::node* expect = entry.get("expect")) {
      const std::string word = reader.string(*expect, "expect");
      if (word != "holds" && word != "fails") {
        reader.fail(*expect, "expect must be holds or fails (got " + word + ")");
      }
      claim.expect_holds = word == "holds";
    }
    if (claim.kind != ClaimKind::bound) {
      read_grid_claim(reader, entry, item, scene, claim);
      continue;
    }
    if (entry.get("observable") == nullptr) {
      reader.fail(item, "[[claim]] needs observable");
    }
    claim.observable = reader.string(*entry.get("observable"), "observable");
    read_error_bound(reader, entry, item, "[[claim]]", claim.bound, claim.relative, claim.quantile);
    read_bound_grid(reader, entry, scene, claim);
    if (const toml::node* convention = entry.get("convention")) {
      read_convention_claim(reader, entry, item, *convention, scene, claim);
      continue;
    }
    std::vector<std::string_view> allowed{
        "name",         "kind",         "where", "quote",     "figure",    "expect",
        "observable",   "solver",       "rtol",  "atol",      "precision", "steps_per_contact",
        "end",          "onset_phases", "bound", "bound_rel", "quantile",  "denser",
        "allow_missing"};
    allowed.insert(allowed.end(), grid_keys.begin(), grid_keys.end());
    reader.only(entry, allowed, "[[claim]]");
    const SolverConfig* external = external_named(reader, entry, scene);
    if (external != nullptr) {
      claim.config = *external;
      claim.config.rtol.reset();
      claim.config.steps_per_contact.reset();
      claim.config.dt.reset();
    } else {
      claim.config = base_config(reader, entry, "solver", "[[claim]]", item);
    }
    const std::vector<std::optional<solvers::End>> ends = read_ends(reader, entry);
    if (ends.size() != 1) {
      reader.fail(*entry.get("end"), "a claim's end is one contact end (got a list)");
    }
    claim.config.end = ends.front();
    const std::vector<const Observable*> wanted = observables_of(scene.want);
    if (std::none_of(wanted.begin(), wanted.end(), [&](const Observable* observable) {
          return observable->key == claim.observable;
        })) {
      std::string names;
      for (const Observable* observable : wanted) {
        names += names.empty() ? "" : "|";
        names += observable->key;
      }
      reader.fail(*entry.get("observable"), "claim observable must be one the scene wants: " +
                                                names + " (got " + claim.observable + ")");
    }
    if (external != nullptr) {
      // The claim names one configuration of the external solver's sweep.
      const bool swept = external->steps_per_contact || external->rtol;
      const char* key = external->steps_per_contact ? "steps_per_contact" : "rtol";
      const toml::node* value = entry.get(key);
      if (swept && value == nullptr) {
        reader.fail(item, std::string("[[claim]] needs the ") + key + " of its solver");
      }
      if (value != nullptr && external->steps_per_contact) {
        claim.config.steps_per_contact =
            steps_per_contact(reader, *value, reader.number(*value, key));
      } else if (value != nullptr) {
        claim.config.rtol = reader.number(*value, key);
        check_rtol(reader, *value, *claim.config.rtol);
      }
      scene.claims.push_back(claim);
      continue;
    }
    const solvers::SolverInfo& info = solvers::solver_named(claim.config.name);
    const bool fixed_step = info.fixed_step;
    if (const toml::node* rtol = entry.get(fixed_step ? "steps_per_contact" : "rtol")) {
      const double value = reader.number(*rtol, fixed_step ? "steps_per_contact" : "rtol");
      if (fixed_step) {
        claim.config.steps_per_contact = steps_per_contact(reader, *rtol, value);
      } else {
        check_rtol(reader, *rtol, value);
        claim.config.rtol = value;
      }
    } else if (info.default_tolerance != solvers::DefaultTolerance::epsilon || fixed_step) {
      reader.fail(item, std::string("[[claim]] needs the ") +
                            (fixed_step ? "steps_per_contact" : "rtol") + " of its solver");
    }
    check_config(reader, item, with_cells(scene, claim.grid), claim.config);
    scene.claims.push_back(claim);
  }
}

void read_searches(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "search")) {
    const toml::table& entry = reader.table(item, "[[search]]");
    reader.only(entry, {"name",      "where",        "quote",      "solver",
                        "precision", "atol",         "rtol",       "steps_per_contact",
                        "parameter", "range",        "observable", "bound",
                        "bound_rel", "quantile",     "group_by",   "p",
                        "e",         "alpha_eff",    "v0",         "m",
                        "k",         "onset_phases", "end"},
                "[[search]]");
    Search search;
    for (const char* key : {"name", "parameter", "range", "observable"}) {
      if (entry.get(key) == nullptr) {
        reader.fail(item, std::string("[[search]] needs ") + key);
      }
    }
    search.name = reader.string(*entry.get("name"), "search name");
    for (const char* key : {"where", "quote"}) {
      if (const toml::node* text = entry.get(key)) {
        (key[0] == 'w' ? search.where : search.quote) = reader.string(*text, key);
      }
    }
    search.config = base_config(reader, entry, "solver", "[[search]]", item);
    if (entry.get("onset_phases") != nullptr) { // read (and checked) by base_config
      search.onset_phases = search.config.onset_phases;
    }
    const std::vector<std::optional<solvers::End>> search_ends = read_ends(reader, entry);
    if (search_ends.size() != 1) {
      reader.fail(*entry.get("end"), "a search's end is one contact end (got a list)");
    }
    search.config.end = search_ends.front();
    const solvers::SolverInfo& info = solvers::solver_named(search.config.name);
    search.parameter = keyword(reader, *entry.get("parameter"), search_parameters, "parameter");
    const bool fixed = search.parameter != SearchParameter::rtol;
    if (fixed != info.fixed_step) {
      reader.fail(*entry.get("parameter"),
                  search.config.name +
                      (info.fixed_step ? " takes a fixed step: search steps_per_contact or dt"
                                       : " controls its error: search rtol") +
                      " (got " + std::string(name_of(search_parameters, search.parameter)) + ")");
    }
    for (const char* key : {"rtol", "steps_per_contact"}) {
      if (entry.get(key) != nullptr) {
        reader.fail(*entry.get(key), std::string("[[search]] sets ") + key +
                                         " per trial: give its range, not a value");
      }
    }
    const toml::node& range = *entry.get("range");
    const std::vector<double> ends = reader.numbers(range, "range");
    const auto valid = [&](double x) {
      switch (search.parameter) {
      case SearchParameter::rtol:
        return x > 0 && x < 1;
      case SearchParameter::steps_per_contact:
        return x >= 1 && x <= 1e9 && x == std::floor(x);
      case SearchParameter::dt:
        break;
      }
      return x > 0 && x < 1e300;
    };
    if (ends.size() != 2 || !valid(ends[0]) || !valid(ends[1]) || ends[0] == ends[1]) {
      reader.fail(range,
                  "range must be [from, to], two different values of " +
                      std::string(name_of(search_parameters, search.parameter)) +
                      (search.parameter == SearchParameter::rtol ? " in (0, 1)"
                       : search.parameter == SearchParameter::dt ? " > 0"
                                                                 : ", integers in [1, 1e9]"));
    }
    // Tightest first: the smaller rtol or Δt, the more steps per contact.
    const bool more_is_tighter = search.parameter == SearchParameter::steps_per_contact;
    const double tight = more_is_tighter ? std::max(ends[0], ends[1]) : std::min(ends[0], ends[1]);
    search.range = {tight, ends[0] == tight ? ends[1] : ends[0]};
    search.observable = reader.string(*entry.get("observable"), "observable");
    const std::vector<const Observable*> wanted = observables_of(scene.want);
    if (std::none_of(wanted.begin(), wanted.end(), [&](const Observable* observable) {
          return observable->key == search.observable;
        })) {
      reader.fail(*entry.get("observable"),
                  "search observable must be one the scene wants (got " + search.observable + ")");
    }
    read_error_bound(reader, entry, item, "[[search]]", search.bound, search.relative,
                     search.quantile);
    if (const toml::node* groups = entry.get("group_by")) {
      search.group_by = keyword(reader, *groups, search_groups, "group_by");
    }
    search.grid = ClaimGrid{scene.p, scene.v0, scene.m, scene.k, scene.damping};
    read_grid_lists(reader, entry, search.grid);
    if (search.parameter == SearchParameter::rtol) { // the tightest rtol against the precision
      SolverConfig tightest = search.config;
      tightest.rtol = search.range[0];
      check_config(reader, item, with_cells(scene, search.grid), tightest);
    }
    scene.searches.push_back(search);
  }
}

void read_figures(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "figure")) {
    const toml::table& entry = reader.table(item, "[[figure]]");
    reader.only(entry, {"kind", "solver", "rtol", "atol", "p", "e", "alpha_eff"}, "[[figure]]");
    FigureSpec figure;
    if (entry.get("kind") == nullptr) {
      reader.fail(item, "[[figure]] needs a kind");
    }
    const std::string kind = reader.string(*entry.get("kind"), "kind");
    const std::optional<FigureKind> known = value_named(figure_kinds, kind);
    if (!known) {
      reader.fail(*entry.get("kind"),
                  "unknown figure, expected " + names_of(figure_kinds) + " (got " + kind + ")");
    }
    figure.kind = *known;
    if (figure.kind == FigureKind::restitution_approximations) {
      // The published approximations of viscoelastic Hertz against the truth, which is the
      // reference solve (taylor in float128, MATH.md §12.2) over alpha_eff = [from, to].
      reader.only(entry, {"kind", "p", "alpha_eff"}, "[[figure]] restitution_approximations");
      const toml::node* ps = entry.get("p");
      const toml::node* range = entry.get("alpha_eff");
      if (ps == nullptr || range == nullptr) {
        reader.fail(item, "[[figure]] restitution_approximations needs p = 1.5 and alpha_eff = "
                          "[from, to]");
      }
      figure.p = reader.numbers(*ps, "p");
      reader.require(figure.p == std::vector<double>{1.5}, *ps,
                     "the published approximations are of viscoelastic Hertz: p must be 1.5",
                     figure.p.front());
      figure.alpha_eff = reader.numbers(*range, "alpha_eff");
      if (figure.alpha_eff.size() != 2 || !(figure.alpha_eff[0] > 0) ||
          !(figure.alpha_eff[0] < figure.alpha_eff[1]) || !(figure.alpha_eff[1] <= 10)) {
        reader.fail(*range, "alpha_eff must be [from, to] with 0 < from < to <= 10");
      }
      figure.config.name = "taylor";
      figure.config.precision = std::string(precision_name<NarrowestWithDigits10<30>>());
      scene.figures.push_back(figure);
      continue;
    }
    figure.config = base_config(reader, entry, "solver", "[[figure]]", item);
    if (solvers::solver_named(figure.config.name).fixed_step) {
      figure.config.steps_per_contact = 50;
    }
    if (const toml::node* rtol = entry.get("rtol")) {
      figure.config.rtol = reader.number(*rtol, "rtol");
      check_rtol(reader, *rtol, *figure.config.rtol);
    }
    const bool by_alpha_eff = figure.kind == FigureKind::tau_ratio;
    for (const char* key : {"p", by_alpha_eff ? "alpha_eff" : "e"}) {
      if (entry.get(key) == nullptr) {
        reader.fail(item, "[[figure]] " + kind + " needs " + key);
      }
    }
    const toml::node& ps = *entry.get("p");
    figure.p = reader.numbers(ps, "p");
    for (const double p : figure.p) {
      reader.require(p >= 1 && p <= domain::p_max, ps, "p must be in [1, 1000]", p);
    }
    if (const toml::node* es = entry.get("e")) {
      figure.e = reader.numbers(*es, "e");
      for (const double e : figure.e) {
        reader.require(e > 0 && e < 1, *es, "e must be in (0, 1)", e);
      }
    }
    if (const toml::node* zs = entry.get("alpha_eff")) {
      figure.alpha_eff = reader.numbers(*zs, "alpha_eff");
      for (const double z : figure.alpha_eff) {
        reader.require(z >= 0 && z < 1, *zs, "alpha_eff must be in [0, 1) (a return)", z);
      }
    }
    scene.figures.push_back(figure);
  }
}

void read_grid(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& grid = reader.table(node, "[grid]");
  reader.only(grid, {"p", "e", "alpha", "alpha_eff", "v0", "m", "k", "damping_exponent"}, "[grid]");
  for (const char* key : {"p", "v0"}) {
    if (grid.get(key) == nullptr) {
      reader.fail(node, std::string("[grid] needs ") + key);
    }
  }
  if (grid.get("e") == nullptr && grid.get("alpha") == nullptr &&
      grid.get("alpha_eff") == nullptr) {
    reader.fail(node, "[grid] needs e, alpha or alpha_eff");
  }
  ClaimGrid lists{{}, {1.0}, {1.0}, {1.0}, {}};
  read_grid_lists(reader, grid, lists);
  scene.p = lists.p;
  scene.v0 = lists.v0;
  scene.m = lists.m;
  scene.k = lists.k;
  scene.damping = lists.damping;
  if (const toml::node* at = grid.get("damping_exponent")) {
    scene.damping_exponent = reader.numbers(*at, "damping_exponent");
    // One per scene: the maps and tables of a report are p × damping.
    if (scene.damping_exponent.size() != 1) {
      reader.fail(*at,
                  "damping_exponent must be one number, as a scene's maps are p x damping (got " +
                      std::to_string(scene.damping_exponent.size()) + " values)");
    }
    for (const double beta : scene.damping_exponent) {
      for (const double p : scene.p) {
        try {
          domain::require_damping_exponent(beta, p);
        } catch (const std::invalid_argument& e) {
          reader.fail(*at, std::string(e.what()) + " at p = " + to_string_full(p));
        }
        // With another dashpot α_eff depends on δ_u (MATH.md §12.1): α is converted at the one
        // cell there is, as the command line's --alpha is at its contact.
        const bool by_alpha = grid.get("alpha") != nullptr;
        const bool one_cell = scene.v0.size() == 1 && scene.m.size() == 1 && scene.k.size() == 1;
        if (beta != (p - 1) / 2 && by_alpha && !one_cell) {
          reader.fail(*grid.get("alpha"),
                      "alpha with damping_exponent " + to_string_full(beta) +
                          " at p = " + to_string_full(p) +
                          " needs one v0, m and k: the contact's alpha_eff depends on them "
                          "(give alpha_eff, or one cell)");
        }
      }
    }
  }
}

} // namespace

std::string Damping::label() const {
  return (kind == Kind::e ? "e=" : kind == Kind::alpha ? "alpha=" : "z=") + to_string_full(value);
}

std::string_view Damping::key() const {
  return kind == Kind::e ? "e" : kind == Kind::alpha ? "alpha" : "alpha_eff";
}

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
  if (onset_phases > 1) {
    out += fmt::format(" phases={}", onset_phases);
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

namespace {

// Refuses, before toml++ sees the text, what it handles badly (max_scene_nesting):
// - nesting it would recurse into without bound: arrays and inline tables inside each other,
//   table headers and dotted keys with many parts (counted together: a dotted key inside nested
//   arrays is as deep as both);
// - a byte beyond ASCII outside comments: toml++ 3.3.0 reaches __builtin_unreachable on such
//   bytes in keys, after a string's backslash and in its error paths (marzer/tomlplusplus#295,
//   #190), found by tests/fuzz; in a string, \uXXXX says the same.
// A lexical pass that skips strings and comments; a dot between two digits is a number's.
void check_text(const Reader& reader, std::string_view text) {
  int depth = 0, dots = 0;
  std::size_t line = 1;
  auto deeper_than_allowed = [&](int levels) {
    if (levels > max_scene_nesting) {
      reader.fail_at(line, "nested deeper than " + std::to_string(max_scene_nesting) +
                               " levels (arrays, inline tables or dotted keys)");
    }
  };
  auto non_ascii = [](char c) { return static_cast<unsigned char>(c) >= 0x80; };
  const std::string beyond_ascii =
      "a character beyond ASCII outside a comment (in a string, write it as \\uXXXX)";
  auto digit = [&](std::size_t i) { return i < text.size() && text[i] >= '0' && text[i] <= '9'; };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      dots = 0;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') {
        ++i;
      }
    } else if (c == '"' || c == '\'') {
      const bool multiline = text.substr(i, 3) == std::string(3, c);
      const std::string_view close = multiline ? text.substr(i, 3) : text.substr(i, 1);
      i += close.size();
      while (i < text.size() && text.substr(i, close.size()) != close) {
        if (text[i] == '\n') {
          if (!multiline) {
            break; // an unterminated string: toml++ says so
          }
          ++line;
        } else if (non_ascii(text[i])) {
          reader.fail_at(line, beyond_ascii);
        } else if (c == '"' && text[i] == '\\') {
          ++i; // an escaped character
        }
        ++i;
      }
      i += close.size() - 1;
    } else if (non_ascii(c)) {
      reader.fail_at(line, beyond_ascii);
    } else if (c == '[' || c == '{') {
      deeper_than_allowed(++depth + dots);
    } else if (c == ']' || c == '}') {
      depth = std::max(depth - 1, 0);
    } else if (c == '.' && !(i > 0 && digit(i - 1) && digit(i + 1))) {
      deeper_than_allowed(depth + ++dots + 1);
    }
  }
}

} // namespace

Scene load_scene(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw SceneError(path + ":0: is a directory, not a scene file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw SceneError(path + ":0: cannot read the scene (" + std::strerror(errno) + ")");
  }
  std::string text;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_scene_bytes) {
      throw SceneError(path + ":0: a scene is at most " + std::to_string(max_scene_bytes) +
                       " bytes; this file is larger");
    }
  }
  return parse_scene(text, path);
}

Scene parse_scene(std::string_view text, const std::string& path) {
  const Reader reader(path);
  check_text(reader, text);
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    reader.fail_at(e.source().begin.line, std::string(e.description()));
  }
  reader.only(root,
              {"name", "end", "want", "grid", "solver", "claim", "search", "figure", "trajectory",
               "report", "timing", "limits", "diff"},
              "the scene");
  Scene scene;
  scene.path = path;
  scene.name = root.get("name") ? reader.string(*root.get("name"), "name") : path;
  if (const toml::node* end = root.get("end")) {
    const std::string value = reader.string(*end, "end");
    const std::optional<solvers::End> known = value_named(contact_ends, value);
    if (!known) {
      reader.fail(*end, "unknown contact end, expected " + names_of(contact_ends) + " (got " +
                            value + ")");
    }
    scene.end = *known;
  }
  if (const toml::node* want = root.get("want")) {
    scene.want = read_want(reader, *want);
  }
  if (root.get("grid") == nullptr) {
    reader.fail_at(1, "the scene needs a [grid]");
  }
  read_grid(reader, *root.get("grid"), scene);
  if (const toml::node* entries = root.get("solver")) {
    read_solvers(reader, *entries, scene);
  }
  if (const toml::node* claims = root.get("claim")) {
    read_claims(reader, *claims, scene);
  }
  if (const toml::node* searches = root.get("search")) {
    read_searches(reader, *searches, scene);
  }
  if (const toml::node* figures = root.get("figure")) {
    read_figures(reader, *figures, scene);
  }
  if (const toml::node* trajectories = root.get("trajectory")) {
    read_trajectories(reader, *trajectories, scene);
  }
  for (const Claim& claim : scene.claims) {
    if (claim.figure &&
        std::none_of(scene.figures.begin(), scene.figures.end(), [&](const FigureSpec& figure) {
          return name_of(figure_kinds, figure.kind) == *claim.figure;
        })) {
      reader.fail(*root.get("claim"), "[[claim]] " + claim.name + " links to figure " +
                                          *claim.figure + ", which the scene does not draw");
    }
  }
  if (scene.configs.empty() && scene.claims.empty() && scene.searches.empty() &&
      scene.trajectories.empty()) {
    reader.fail_at(1, "the scene names no [[solver]], [[claim]], [[search]] or [[trajectory]]");
  }
  if (const toml::node* report = root.get("report")) {
    const toml::table& table = reader.table(*report, "[report]");
    reader.only(table, {"formats", "work_precision"}, "[report]");
    if (const toml::node* formats = table.get("formats")) {
      scene.formats.clear();
      for (const std::string& name : reader.strings(*formats, "formats")) {
        const std::optional<ReportFormat> format = value_named(report_formats, name);
        if (!format) {
          reader.fail(*formats, "unknown report format, expected " + names_of(report_formats) +
                                    " (got " + name + ")");
        }
        scene.formats.push_back(*format);
      }
      if (scene.formats.empty()) {
        reader.fail(*formats,
                    "formats names no report format, expected some of " + names_of(report_formats));
      }
    }
    if (const toml::node* series = table.get("work_precision")) {
      scene.work_precision = read_work_precision(reader, *series, scene.want);
    }
  }
  if (const toml::node* limits = root.get("limits")) {
    const toml::table& table = reader.table(*limits, "[limits]");
    reader.only(table, {"max_steps", "max_seconds", "max_runs"}, "[limits]");
    auto count = [&](const char* key, long& into) {
      if (const toml::node* node = table.get(key)) {
        const double n = reader.number(*node, key);
        reader.require(n >= 1 && n <= 1e12 && n == std::floor(n), *node,
                       std::string(key) + " must be an integer in [1, 1e12]", n);
        into = static_cast<long>(n);
      }
    };
    count("max_steps", scene.limits.max_steps);
    count("max_runs", scene.limits.max_runs);
    if (const toml::node* node = table.get("max_seconds")) {
      const double seconds = reader.number(*node, "max_seconds");
      reader.require(seconds > 0 && seconds <= 86400, *node, "max_seconds must be in (0, 86400]",
                     seconds);
      scene.limits.max_seconds = seconds;
    }
  }
  if (const toml::node* diff = root.get("diff")) {
    const toml::table& table = reader.table(*diff, "[diff]");
    reader.only(table, {"error_factor", "work_factor", "time_factor", "time_floor"}, "[diff]");
    auto factor = [&](const char* key, double& into) {
      if (const toml::node* node = table.get(key)) {
        into = reader.number(*node, key);
        reader.require(into > 1 && into <= 1e6, *node, std::string(key) + " must be in (1, 1e6]",
                       into);
      }
    };
    factor("error_factor", scene.diff.error_factor);
    factor("work_factor", scene.diff.work_factor);
    factor("time_factor", scene.diff.time_factor);
    if (const toml::node* node = table.get("time_floor")) {
      scene.diff.time_floor = reader.number(*node, "time_floor");
      reader.require(scene.diff.time_floor >= 0 && scene.diff.time_floor <= 86400, *node,
                     "time_floor must be in [0, 86400] seconds", scene.diff.time_floor);
    }
  }
  if (const toml::node* timing = root.get("timing")) {
    const toml::table& table = reader.table(*timing, "[timing]");
    reader.only(table, {"repeats"}, "[timing]");
    if (const toml::node* repeats = table.get("repeats")) {
      const double n = reader.number(*repeats, "repeats");
      reader.require(n >= 1 && n <= 100 && n == std::floor(n), *repeats,
                     "repeats must be an integer in [1, 100]", n);
      scene.repeats = static_cast<int>(n);
    }
  }
  return scene;
}

} // namespace pldamp::harness
