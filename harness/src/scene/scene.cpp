// The scene file: read, guarded for toml++, its top-level keys and the small tables ([report],
// [limits], [diff], [timing]); each of the others has a file of its own (reader.hpp).
#include "scene/reader.hpp"

#include "common/observables.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace pldamp::harness {
namespace {

using namespace scene_reading;

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

// [report]: the formats written, and the series of the work-precision diagrams.
void read_report(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& table = reader.table(node, "[report]");
  reader.only(table, {scene_keys::report}, "[report]");
  if (const toml::node* formats = table.get("formats")) {
    scene.formats.clear();
    for (const std::string& name : reader.strings(*formats, "formats")) {
      scene.formats.push_back(reader.choice_of(*formats, name, report_formats, "report format"));
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
  reader.only(root, {scene_keys::top_level}, "the scene");
  Scene scene;
  scene.path = path;
  scene.name = root.get("name") ? reader.string(*root.get("name"), "name") : path;
  if (const toml::node* end = root.get("end")) {
    scene.end = reader.choice_of(*end, reader.string(*end, "end"), contact_ends, "contact end");
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
    read_report(reader, *report, scene);
  }
  if (const toml::node* limits = root.get("limits")) {
    const toml::table& table = reader.table(*limits, "[limits]");
    reader.only(table, {scene_keys::limits}, "[limits]");
    for (auto [key, into] : {std::pair{"max_steps", &scene.limits.max_steps},
                             std::pair{"max_runs", &scene.limits.max_runs}}) {
      if (const toml::node* node = table.get(key)) {
        *into = reader.integer_in(*node, key, 1, 1000000000000);
      }
    }
    if (const toml::node* node = table.get("max_seconds")) {
      scene.limits.max_seconds =
          reader.number_in(*node, "max_seconds", Range::open_closed(0, 86400));
    }
  }
  if (const toml::node* diff = root.get("diff")) {
    const toml::table& table = reader.table(*diff, "[diff]");
    reader.only(table, {scene_keys::diff}, "[diff]");
    for (auto [key, into] : {std::pair{"error_factor", &scene.diff.error_factor},
                             std::pair{"work_factor", &scene.diff.work_factor},
                             std::pair{"time_factor", &scene.diff.time_factor}}) {
      if (const toml::node* node = table.get(key)) {
        *into = reader.number_in(*node, key, Range::open_closed(1, 1e6));
      }
    }
    if (const toml::node* node = table.get("time_floor")) {
      scene.diff.time_floor =
          reader.number_in(*node, "time_floor", Range::closed(0, 86400).with_unit(" seconds"));
    }
  }
  if (const toml::node* timing = root.get("timing")) {
    const toml::table& table = reader.table(*timing, "[timing]");
    reader.only(table, {scene_keys::timing}, "[timing]");
    if (const toml::node* repeats = table.get("repeats")) {
      scene.repeats = static_cast<int>(reader.integer_in(*repeats, "repeats", 1, 100));
    }
  }
  return scene;
}

} // namespace pldamp::harness
