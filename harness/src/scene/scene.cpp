// The scene file: read, guarded for toml++, its top-level keys and the small tables ([report],
// [limits], [diff], [timing]); each of the others has a file of its own (reader.hpp).
#include "scene/reader.hpp"

#include "common/files.hpp"
#include "common/observables.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <type_traits>
#include <variant>

namespace pldamp::harness {
namespace {

using namespace scene_reading;

unsigned read_want(const Reader& reader, const toml::node& node) {
  unsigned want = 0;
  const std::vector<std::string> words = reader.strings(node, "want");
  refuse_repeated(reader, node, "want", words);
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
  for (const std::string& key : keys) {
    if (key != worst_of_all_key &&
        std::none_of(wanted.begin(), wanted.end(),
                     [&](const Observable* observable) { return observable->key == key; })) {
      reader.fail(node, "work_precision names an observable the scene does not want, expected " +
                            words + " (got " + key + ")");
    }
  }
  refuse_repeated(reader, node, "work_precision", keys);
  return keys;
}

// Whether the run makes records: the configurations of its [[solver]]s and of the bound claims
// judged on its grid, solved on every cell (truth/plan.hpp).
bool has_records(const Scene& scene) {
  return !scene.configs.empty() ||
         std::any_of(scene.claims.begin(), scene.claims.end(),
                     [](const Claim& claim) { return claim.on_plan() != nullptr; });
}

// [report]: the formats written, and the series of the work-precision diagrams.
void read_report(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& table = reader.table(node, "[report]");
  reader.only(table, {scene_keys::report}, "[report]");
  if (const toml::node* formats = table.get("formats")) {
    scene.formats.clear();
    const std::vector<std::string> names = reader.strings(*formats, "formats");
    for (const std::string& name : names) {
      scene.formats.push_back(reader.choice_of(*formats, name, report_formats, "report format"));
    }
    if (scene.formats.empty()) {
      reader.fail(*formats,
                  "formats names no report format, expected some of " + names_of(report_formats));
    }
    refuse_repeated(reader, *formats, "formats", names);
  }
  if (const toml::node* series = table.get("work_precision")) {
    scene.work_precision = read_work_precision(reader, *series, scene.want);
    if (!has_records(scene)) {
      reader.fail(*series, "work_precision has no effect: the scene has no records to draw (no "
                           "[[solver]], no bound claim on its grid)");
    }
  }
}

bool own_solver(const SolverConfig& config) {
  return !config.external();
}

// [limits]: each limit refused where nothing it limits runs (max_steps: pldamp's solvers, for an
// external program is given no step limit; max_seconds: any solve, an external program's reply
// included).
void read_limits(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& table = reader.table(node, "[limits]");
  reader.only(table, {scene_keys::limits}, "[limits]");
  for (auto [key, into] : {std::pair{"max_steps", &scene.limits.max_steps},
                           std::pair{"max_runs", &scene.limits.max_runs}}) {
    if (const toml::node* limit = table.get(key)) {
      *into = reader.integer_in(*limit, key, 1, 1000000000000);
    }
  }
  if (const toml::node* limit = table.get("max_seconds")) {
    scene.limits.max_seconds =
        reader.number_in(*limit, "max_seconds", Range::open_closed(0, 86400));
  }
  const bool own = solves_with_pldamp(scene);
  if (const toml::node* limit = table.get("max_steps"); limit != nullptr && !own) {
    reader.fail(*limit, "max_steps has no effect: the scene runs none of pldamp's solvers (an "
                        "external program is given no step limit)");
  }
  if (const toml::node* limit = table.get("max_seconds");
      limit != nullptr && !own && scene.configs.empty()) {
    reader.fail(*limit, "max_seconds has no effect: the scene solves nothing (its claims and "
                        "trajectories are judged by the closed forms)");
  }
}

// [diff]: what `pldamp diff` compares of the scene's reports: errors (of records, claims and
// searches), and the work and time of records (judge/diff.cpp); not trajectories nor figures.
void read_diff(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& table = reader.table(node, "[diff]");
  reader.only(table, {scene_keys::diff}, "[diff]");
  for (auto [key, into] : {std::pair{"error_factor", &scene.diff.error_factor},
                           std::pair{"work_factor", &scene.diff.work_factor},
                           std::pair{"time_factor", &scene.diff.time_factor}}) {
    if (const toml::node* factor = table.get(key)) {
      *into = reader.number_in(*factor, key, Range::open_closed(1, 1e6));
    }
  }
  if (const toml::node* floor = table.get("time_floor")) {
    scene.diff.time_floor =
        reader.number_in(*floor, "time_floor", Range::closed(0, 86400).with_unit(" seconds"));
  }
  const bool records = has_records(scene);
  for (const char* key : {"work_factor", "time_factor", "time_floor"}) {
    if (const toml::node* threshold = table.get(key); threshold != nullptr && !records) {
      reader.fail(*threshold, std::string(key) +
                                  " has no effect: the scene has no records for pldamp diff to "
                                  "compare (no [[solver]], no bound claim on its grid)");
    }
  }
  if (const toml::node* factor = table.get("error_factor");
      factor != nullptr && !records && scene.claims.empty() && scene.searches.empty()) {
    reader.fail(*factor, "error_factor has no effect: the scene has no records, claims or "
                         "searches for pldamp diff to compare (it compares no trajectory)");
  }
}

// [timing] repeats: the records of pldamp's own configurations on the scene's grid, of its
// [[solver]]s and of the bound claims judged from them, are repeated (run/run.cpp); not an
// external program's, nor the solves of claims on grids of their own and of searches; nor a run
// that took repeat_below seconds of CPU or more.
void read_timing(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& table = reader.table(node, "[timing]");
  reader.only(table, {scene_keys::timing}, "[timing]");
  if (const toml::node* repeats = table.get("repeats")) {
    scene.repeats = static_cast<int>(reader.integer_in(*repeats, "repeats", 1, 100));
    const bool timed =
        std::any_of(scene.configs.begin(), scene.configs.end(), own_solver) ||
        std::any_of(scene.claims.begin(), scene.claims.end(), [](const Claim& claim) {
          return claim.on_plan() != nullptr && own_solver(claim.on_plan()->config);
        });
    if (scene.repeats > 1 && !timed) {
      reader.fail(*repeats, "repeats has no effect: the scene runs none of pldamp's solvers on "
                            "its grid (an external program runs once; claims on grids of their "
                            "own and searches solve once)");
    }
  }
  if (const toml::node* below = table.get("repeat_below")) {
    scene.repeat_below = reader.number_in(*below, "repeat_below", Range::above(0));
    if (scene.repeats == 1) {
      reader.fail(*below, "repeat_below has no effect with repeats = 1");
    }
  }
}

} // namespace

bool solves_with_pldamp(const Scene& scene) {
  const bool claims = std::any_of(scene.claims.begin(), scene.claims.end(), [](const Claim& c) {
    return std::visit(
        [](const auto& stated) {
          using Stated = std::decay_t<decltype(stated)>;
          if constexpr (std::is_same_v<Stated, BoundClaim>) {
            return own_solver(stated.config);
          } else if constexpr (std::is_same_v<Stated, ConventionClaim>) {
            return false; // the closed forms
          } else if constexpr (requires { stated.of; }) {
            return stated.of.solver.has_value();
          } else {
            return true; // recovered_parameter, stability
          }
        },
        c.kind);
  });
  const bool figures =
      std::any_of(scene.figures.begin(), scene.figures.end(), [](const FigureSpec& figure) {
        return figure.kind != FigureKind::restitution_approximations;
      });
  return claims || figures || !scene.searches.empty() ||
         std::any_of(scene.configs.begin(), scene.configs.end(), own_solver);
}

Scene load_scene(const std::string& path) {
  if (const std::optional<std::string> why = unreadable_file(path)) {
    // Not "file:line: message": there is no line (it read "PATH:0: ..."); the one-line error.
    throw InputError("cannot read the scene: " + *why + " (got " + path + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError("cannot read the scene: " + std::string(std::strerror(errno)) + " (got " +
                     path + ")");
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
  reader.only(root, {scene_keys::top_level}, "the scene");
  Scene scene;
  scene.path = path;
  scene.text = text;
  scene.name = root.get("name") ? reader.string(*root.get("name"), "name") : path;
  if (const toml::node* end = root.get("end")) {
    scene.end = reader.choice_of(*end, reader.string(*end, "end"), contact_ends, "contact end");
  }
  if (const toml::node* want = root.get("want")) {
    scene.want = read_want(reader, *want);
  }
  if (const toml::node* contacts = root.get("contact")) {
    read_contacts(reader, *contacts, scene);
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
    read_report(reader, *report, scene);
  }
  if (const toml::node* limits = root.get("limits")) {
    read_limits(reader, *limits, scene);
  }
  if (const toml::node* diff = root.get("diff")) {
    read_diff(reader, *diff, scene);
  }
  if (const toml::node* timing = root.get("timing")) {
    read_timing(reader, *timing, scene);
  }
  return scene;
}

} // namespace pldamp::harness
