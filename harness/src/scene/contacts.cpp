// [[contact]]: a scene's contacts from materials (MATH.md §13), by the command line's rules
// (common/materials.hpp), and the cells they make.
#include "common/materials.hpp"
#include "scene/reader.hpp"

#include "pldamp/core/domain.hpp"

#include <algorithm>

namespace pldamp::harness {

std::vector<CellScale> scene_scales(const Scene& scene) {
  std::vector<CellScale> scales;
  for (const MaterialContact& contact : scene.contacts) {
    for (const double v0 : contact.v0) {
      scales.push_back({v0, contact.m, contact.k});
    }
  }
  return scene.contacts.empty() ? grid_scales(ClaimGrid{{}, scene.v0, scene.m, scene.k, {}})
                                : scales;
}

std::vector<CellScale> grid_scales(const ClaimGrid& grid) {
  if (!grid.scales.empty()) {
    return grid.scales;
  }
  std::vector<CellScale> scales;
  for (const double v0 : grid.v0) {
    for (const double m : grid.m) {
      for (const double k : grid.k) {
        scales.push_back({v0, m, k});
      }
    }
  }
  return scales;
}

const MaterialContact* contact_of(const Scene& scene, double m, double k) {
  const auto found = std::find_if(
      scene.contacts.begin(), scene.contacts.end(),
      [&](const MaterialContact& contact) { return contact.m == m && contact.k == k; });
  return found == scene.contacts.end() ? nullptr : &*found;
}

namespace scene_reading {
namespace {

// The float128 of the truth (truth/plan.hpp's Exact): m and k are rounded to double once.
using Derived = NarrowestWithDigits10<30>;

// A material key: a number, or a list of one per body, as the text the command line would take
// (shortest round trip: the double the scene's number is).
std::vector<std::string> material_texts(const Reader& reader, const toml::table& entry,
                                        const char* key) {
  std::vector<std::string> texts;
  if (const toml::node* node = entry.get(key)) {
    for (const double value : reader.numbers(*node, key)) {
      texts.push_back(to_string_full(value));
    }
  }
  return texts;
}

} // namespace

void read_contacts(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "contact")) {
    const toml::table& entry = reader.table(item, "[[contact]]");
    reader.only(entry, {scene_keys::contact}, "[[contact]]");
    for (const char* key : {"name", "geometry", "radius", "young", "poisson", "density", "v0"}) {
      if (entry.get(key) == nullptr) {
        reader.fail(item, std::string("[[contact]] needs ") + key);
      }
    }
    MaterialContact contact;
    contact.name = reader.string(*entry.get("name"), "name");
    const MaterialInput input{
        reader.string(*entry.get("geometry"), "geometry"), material_texts(reader, entry, "radius"),
        material_texts(reader, entry, "young"), material_texts(reader, entry, "poisson"),
        material_texts(reader, entry, "density")};
    contact.geometry = input.geometry;
    try {
      check_material_shape(input, MaterialNames::keys());
      const analytic::HertzContact<Derived> hertz = hertz_of<Derived>(input, MaterialNames::keys());
      contact.m = static_cast<double>(hertz.m);
      contact.k = static_cast<double>(hertz.k);
      contact.radius_eff = static_cast<double>(hertz.radius);
      contact.modulus_eff = static_cast<double>(hertz.modulus);
      contact.rayleigh_time =
          static_cast<double>(rayleigh_time_of<Derived>(input, MaterialNames::keys()));
      // Within double's range: m* and k are what the solvers get.
      domain::require_scale("m", contact.m);
      domain::require_scale("k", contact.k);
    } catch (const std::invalid_argument& e) {
      // At the line of the key the message names ("poisson must be ...", "unknown geometry"),
      // or, for a wall given one of its two elastic constants, the one given (its second value
      // is the mistake or the other's is missing: the line names both); else the entry's.
      const std::string what = e.what();
      const toml::node* at = &item;
      for (const char* key : {"geometry", "radius", "young", "poisson", "density"}) {
        if (what.rfind(std::string(key) + " ", 0) == 0 ||
            what.rfind("unknown " + std::string(key) + ",", 0) == 0) {
          at = entry.get(key);
        }
      }
      if (what.rfind("an elastic wall", 0) == 0) {
        at = input.young.size() > input.poisson.size() ? entry.get("young") : entry.get("poisson");
      }
      reader.fail(*at, "[[contact]] " + contact.name + ": " + what);
    }
    const toml::node& speeds = *entry.get("v0");
    contact.v0 = reader.numbers(speeds, "v0");
    for (const double v0 : contact.v0) {
      reader.within_domain(speeds, [&] { domain::require_scale("v0", v0); });
    }
    refuse_repeated(reader, speeds, "v0", contact.v0);
    for (const MaterialContact& other : scene.contacts) {
      if (other.name == contact.name) {
        reader.fail(item, "[[contact]] names " + contact.name + " twice");
      }
      if (other.m == contact.m && other.k == contact.k) { // one cell would be two contacts
        reader.fail(item, "[[contact]] " + contact.name + " has the m and k of " + other.name +
                              ": give the two as one contact with both speeds");
      }
    }
    scene.contacts.push_back(contact);
  }
  scene.p = {1.5};
  scene.v0.clear();
  scene.m.clear();
  scene.k.clear();
  for (const MaterialContact& contact : scene.contacts) {
    scene.v0.insert(scene.v0.end(), contact.v0.begin(), contact.v0.end());
    scene.m.push_back(contact.m);
    scene.k.push_back(contact.k);
  }
}

} // namespace scene_reading
} // namespace pldamp::harness
