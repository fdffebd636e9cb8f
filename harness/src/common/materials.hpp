// A contact from materials (MATH.md §13), as the command line (--geometry, --radius, ...) and a
// scene's [[contact]] (geometry, radius, ...) both give it: the rules on what each body takes, each
// number's range, and the Hertz contact they make, in one place. The numbers arrive as typed text,
// parsed in the precision asked; `Names` says how the user typed each key ("--radius" on the
// command line, "radius" in a scene), so that a refusal names what was typed.
#pragma once

#include "common/input.hpp"

#include "pldamp/analytic/hertz.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

// The materials as typed: one value per body, or one for both spheres.
struct MaterialInput {
  std::string geometry; // sphere-sphere | sphere-wall
  std::vector<std::string> radius, young, poisson, density;
};

// How each key was typed: the geometry's, then radius, young, poisson, density.
struct MaterialNames {
  std::string geometry, radius, young, poisson, density;
  static MaterialNames options() {
    return {"--geometry", "--radius", "--young", "--poisson", "--density"};
  }
  static MaterialNames keys() { return {"geometry", "radius", "young", "poisson", "density"}; }
};

// "a,b" as typed.
inline std::string typed_list(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& value : list) {
    out += (out.empty() ? "" : ",") + value;
  }
  return out;
}

// Checks what is precision-free: a known geometry, and each list of a length it takes (a sphere
// on a wall: one radius and density; the wall's modulus and ratio optional, both or neither).
inline void check_material_shape(const MaterialInput& in, const MaterialNames& names) {
  const bool wall = in.geometry == "sphere-wall";
  if (!wall && in.geometry != "sphere-sphere") {
    throw InputError("unknown " + names.geometry + ", expected sphere-sphere|sphere-wall (got " +
                     in.geometry + ")");
  }
  const std::array<std::pair<const std::vector<std::string>*, const std::string*>, 4> lists{
      {{&in.radius, &names.radius},
       {&in.young, &names.young},
       {&in.poisson, &names.poisson},
       {&in.density, &names.density}}};
  for (const auto& [list, name] : lists) {
    // A wall has no radius or density; its modulus and ratio are optional (rigid without).
    const bool wall_optional = wall && (list == &in.young || list == &in.poisson);
    const std::size_t most = wall && !wall_optional ? 1 : 2;
    if (list->empty()) {
      throw InputError(*name + " is required with " + names.geometry + " " + in.geometry +
                       " (got nothing)");
    }
    if (list->size() > most) {
      throw InputError(*name + " takes " +
                       (most == 1 ? std::string("one value (the sphere's") +
                                        (wall ? "; the wall has none" : "") + ")"
                        : wall ? std::string("the sphere's value, then the wall's if elastic")
                               : std::string("one value for both spheres, or one each")) +
                       " (got " + *name + " " + typed_list(*list) + ")");
    }
  }
  if (wall && in.young.size() != in.poisson.size()) {
    throw InputError("an elastic wall takes a second " + names.young + " and a second " +
                     names.poisson + " (got " + names.young + " " + typed_list(in.young) + " " +
                     names.poisson + " " + typed_list(in.poisson) + ")");
  }
}

// One material number, parsed in Real and checked in its range: ν in (−1, 1/2), every other > 0
// and finite.
template <SupportedReal Real>
Real material_number(const std::string& name, const std::string& text, bool poisson) {
  using std::isfinite;
  const Real value = parse_real<Real>(name, text);
  const bool ok =
      poisson ? value > -1 && value < Real(1) / 2 : static_cast<bool>(isfinite(value)) && value > 0;
  if (!ok) {
    throw InputError(name + " must be " + (poisson ? "in (-1, 0.5)" : "a finite number > 0") +
                     " (got " + text + ")");
  }
  return value;
}

// The spheres (two for sphere-sphere, one against a wall), in Real. Check the shape first.
template <SupportedReal Real>
std::vector<analytic::Sphere<Real>> spheres_of(const MaterialInput& in,
                                               const MaterialNames& names) {
  auto body = [&](std::size_t i) {
    auto value = [&](const std::string& name, const std::vector<std::string>& list, bool poisson) {
      return material_number<Real>(name, list[std::min(i, list.size() - 1)], poisson);
    };
    return analytic::Sphere<Real>{.radius = value(names.radius, in.radius, false),
                                  .young = value(names.young, in.young, false),
                                  .poisson = value(names.poisson, in.poisson, true),
                                  .density = value(names.density, in.density, false)};
  };
  if (in.geometry == "sphere-sphere") {
    return {body(0), body(1)};
  }
  return {body(0)};
}

// m* and k finite and > 0 in Real: R³ or E beyond the type gives inf (or inf/inf = NaN in m*),
// and a narrower type than they were derived in can round them to 0 or inf; said so here, not as
// a NaN later.
template <SupportedReal Real>
void require_representable(const analytic::HertzContact<Real>& hertz, const MaterialInput& in,
                           const MaterialNames& names) {
  using std::isfinite;
  if (!isfinite(hertz.m) || !isfinite(hertz.k) || !(hertz.m > 0) || !(hertz.k > 0)) {
    throw InputError("the materials give a mass or stiffness beyond " +
                     std::string(precision_name<Real>()) + " (got " + names.radius + " " +
                     typed_list(in.radius) + " " + names.young + " " + typed_list(in.young) + " " +
                     names.density + " " + typed_list(in.density) + ")");
  }
}

// The Hertz contact, in Real. Check the shape first.
template <SupportedReal Real>
analytic::HertzContact<Real> hertz_of(const MaterialInput& in, const MaterialNames& names) {
  const std::vector<analytic::Sphere<Real>> spheres = spheres_of<Real>(in, names);
  analytic::HertzContact<Real> hertz;
  if (spheres.size() == 2) {
    hertz = analytic::hertz_contact(spheres[0], spheres[1]);
  } else {
    analytic::Wall<Real> wall;
    if (in.young.size() == 2) {
      wall = {.young = material_number<Real>(names.young, in.young[1], false),
              .poisson = material_number<Real>(names.poisson, in.poisson[1], true)};
    }
    hertz = analytic::hertz_contact(spheres[0], wall);
  }
  require_representable(hertz, in, names);
  return hertz;
}

// The smallest Rayleigh time of the spheres (MATH.md §13), in Real.
template <SupportedReal Real>
Real rayleigh_time_of(const MaterialInput& in, const MaterialNames& names) {
  Real shortest = std::numeric_limits<Real>::infinity();
  for (const analytic::Sphere<Real>& sphere : spheres_of<Real>(in, names)) {
    shortest = std::min(shortest, analytic::rayleigh_time(sphere));
  }
  return shortest;
}

} // namespace pldamp::harness
