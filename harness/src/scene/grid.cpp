// [grid], the grid lists of claims and searches, contact ends, and [[trajectory]] (a contact of
// its own).
#include "scene/reader.hpp"

#include "common/input.hpp"

#include "pldamp/core/domain.hpp"

#include <filesystem>
#include <utility>

namespace pldamp::harness {

std::string Damping::label() const {
  return (kind == Kind::e ? "e=" : kind == Kind::alpha ? "alpha=" : "z=") + to_string_full(value);
}

std::string_view Damping::key() const {
  return kind == Kind::e ? "e" : kind == Kind::alpha ? "alpha" : "alpha_eff";
}

ClaimGrid scene_grid(const Scene& scene) {
  ClaimGrid grid{scene.p, scene.v0, scene.m, scene.k, scene.damping};
  if (!scene.contacts.empty()) {
    grid.scales = scene_scales(scene);
  }
  return grid;
}

Scene with_cells(const Scene& scene, const ClaimGrid& grid) {
  Scene cells = scene;
  if (grid.scales.empty()) {
    cells.contacts.clear(); // the grid's own lists: their product
  }
  cells.p = grid.p;
  cells.v0 = grid.v0;
  cells.m = grid.m;
  cells.k = grid.k;
  return cells;
}

namespace scene_reading {

void read_grid_lists(const Reader& reader, const toml::table& table, ClaimGrid& grid) {
  if (!grid.scales.empty()) { // a scene's contacts: only the damping is the entry's to choose
    for (const char* key : {"p", "v0", "m", "k"}) {
      if (const toml::node* at = table.get(key)) {
        reader.fail(*at, std::string(key) +
                             ": a scene with [[contact]] takes p = 1.5, v0, m and k from its "
                             "contacts (a claim or search may choose e, alpha or alpha_eff)");
      }
    }
  }
  auto list = [&](const char* key, std::vector<double>& into, auto&& check) {
    if (const toml::node* at = table.get(key)) {
      into = reader.numbers(*at, key);
      for (const double value : into) {
        reader.within_domain(*at, [&] { check(value); });
      }
      refuse_repeated(reader, *at, key, into); // a cell twice
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

std::vector<std::optional<solvers::End>> read_ends(const Reader& reader, const toml::table& entry) {
  const toml::node* node = entry.get("end");
  if (node == nullptr) {
    return {std::nullopt};
  }
  std::vector<std::optional<solvers::End>> ends;
  for (const std::string& name : reader.strings(*node, "end")) {
    ends.push_back(reader.choice_of(*node, name, contact_ends, "contact end"));
  }
  if (ends.empty()) {
    reader.fail(*node, "end is an empty list");
  }
  return ends;
}

std::optional<solvers::End> read_end(const Reader& reader, const toml::table& entry,
                                     const std::string& what) {
  const std::vector<std::optional<solvers::End>> ends = read_ends(reader, entry);
  if (ends.size() != 1) {
    reader.fail(*entry.get("end"), what + " end is one contact end (got a list)");
  }
  return ends.front();
}

void read_grid(const Reader& reader, const toml::node& node, Scene& scene) {
  const toml::table& grid = reader.table(node, "[grid]");
  reader.only(grid, {scene_keys::grid}, "[grid]");
  const bool contacts = !scene.contacts.empty();
  for (const char* key : {"p", "v0", "m", "k"}) {
    if (contacts && grid.get(key) != nullptr) {
      reader.fail(*grid.get(key), std::string("[grid] ") + key +
                                      ": a scene with [[contact]] takes p = 1.5, v0, m and k "
                                      "from its contacts");
    }
    if (!contacts && grid.get(key) == nullptr &&
        (key == std::string_view("p") || key == std::string_view("v0"))) {
      reader.fail(node, std::string("[grid] needs ") + key);
    }
  }
  if (grid.get("e") == nullptr && grid.get("alpha") == nullptr &&
      grid.get("alpha_eff") == nullptr) {
    reader.fail(node, "[grid] needs e, alpha or alpha_eff");
  }
  ClaimGrid lists{scene.p, {1.0}, {1.0}, {1.0}, {}};
  if (contacts) {
    lists = scene_grid(scene);
  }
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
        const bool one_cell = scene_scales(scene).size() == 1;
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

void read_trajectories(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "trajectory")) {
    const toml::table& entry = reader.table(item, "[[trajectory]]");
    reader.only(entry, {scene_keys::trajectory}, "[[trajectory]]");
    TrajectorySpec spec;
    // A [[contact]] of the scene by name: its p = 1.5, m* and k, in place of p, m and k.
    const MaterialContact* contact = nullptr;
    if (const toml::node* name = entry.get("contact")) {
      const std::string wanted = reader.string(*name, "contact");
      for (const MaterialContact& known : scene.contacts) {
        contact = known.name == wanted ? &known : contact;
      }
      if (contact == nullptr) {
        reader.fail(*name, "[[trajectory]] contact names no [[contact]] of the scene (got " +
                               wanted + ")");
      }
      for (const char* key : {"p", "m", "k"}) {
        if (const toml::node* given = entry.get(key)) {
          reader.fail(*given, std::string("[[trajectory]] ") + key + " is the contact's (" +
                                  contact->name + "): give one or the other");
        }
      }
    }
    for (const char* key : {"file", "p", "v0"}) {
      if (entry.get(key) == nullptr && (contact == nullptr || key == std::string_view("file") ||
                                        key == std::string_view("v0"))) {
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
    // The values' own refusals at their lines, the domain's at the entry's.
    if (contact != nullptr) {
      spec.p = 1.5;
      spec.m = contact->m;
      spec.k = contact->k;
    }
    reader.within_domain(item, [&] {
      if (contact == nullptr) {
        spec.p = reader.number(*entry.get("p"), "p");
      }
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
    });
    spec.end = read_end(reader, entry, "a trajectory's");
    scene.trajectories.push_back(spec);
  }
}

} // namespace scene_reading
} // namespace pldamp::harness
