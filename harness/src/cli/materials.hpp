// A contact from materials (MATH.md §13): --geometry sphere-sphere|sphere-wall with --radius,
// --young, --poisson, --density (one value per body, or one for both spheres) in place of --m,
// --k and --p. The options are checked once here, the numbers parsed in the run's precision, and
// m, k, p = 3/2 derived by analytic/hertz.hpp; every command that takes a contact uses this.
#pragma once

#include "cli/commands.hpp"
#include "common/answer.hpp"

#include "pldamp/analytic/hertz.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

inline const std::vector<std::string>& material_option_names() {
  static const std::vector<std::string> names{"--radius", "--young", "--poisson", "--density"};
  return names;
}

// "a,b" as typed.
inline std::string typed_list(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& value : list) {
    out += (out.empty() ? "" : ",") + value;
  }
  return out;
}

// The material lists in the order of material_option_names().
inline std::vector<const std::vector<std::string>*> material_lists(const ContactArgs& a) {
  return {&a.radius, &a.young, &a.poisson, &a.density};
}

// Checks what is precision-free, once the command line is parsed: materials only with
// --geometry and never with --m or --k, each list of a length the geometry takes, --p absent or
// 3/2 (then set to 3/2). `mass_options_given` lists "--m 2" and the like as typed. Without
// --geometry, --p is required.
inline void settle_materials(ContactArgs& a, const std::vector<std::string>& mass_options_given) {
  const auto lists = material_lists(a);
  const auto& names = material_option_names();
  if (!a.geometry) {
    for (std::size_t i = 0; i < lists.size(); ++i) {
      if (!lists[i]->empty()) {
        throw InputError(names[i] + " goes with --geometry sphere-sphere|sphere-wall (got " +
                         names[i] + " " + lists[i]->front() + ")");
      }
    }
    if (a.p.empty()) {
      throw InputError("--p is required (got nothing)");
    }
    return;
  }
  const bool wall = *a.geometry == "sphere-wall";
  if (!wall && *a.geometry != "sphere-sphere") {
    throw InputError("unknown --geometry, expected sphere-sphere|sphere-wall (got " + *a.geometry +
                     ")");
  }
  if (!mass_options_given.empty()) {
    throw InputError("--m and --k are derived from the materials under --geometry, give one or "
                     "the other (got " +
                     mass_options_given.front() + ")");
  }
  for (std::size_t i = 0; i < lists.size(); ++i) {
    // A wall has no radius or density; its modulus and ratio are optional (rigid without).
    const bool wall_optional = wall && (names[i] == "--young" || names[i] == "--poisson");
    const std::size_t most = wall && !wall_optional ? 1 : 2;
    const std::size_t least = 1;
    if (lists[i]->size() < least || lists[i]->size() > most) {
      const std::string typed = typed_list(*lists[i]);
      throw InputError(names[i] + " takes " +
                       (most == 1 ? std::string("one value (the sphere's") +
                                        (wall ? "; the wall has none" : "") + ")"
                        : wall ? std::string("the sphere's value, then the wall's if elastic")
                               : std::string("R1[,R2]-style values: one for both spheres, "
                                             "or one each")) +
                       " (got " + (typed.empty() ? "nothing" : names[i] + " " + typed) + ")");
    }
  }
  if (wall && a.young.size() != a.poisson.size()) {
    throw InputError("an elastic wall takes a second --young and a second --poisson (got --young " +
                     typed_list(a.young) + " --poisson " + typed_list(a.poisson) + ")");
  }
  if (a.p.empty()) {
    a.p = "1.5";
  } else if (parse_real<double>("--p", a.p) != 1.5) {
    throw InputError("a contact from materials is Hertz's, p = 1.5 (got --p " + a.p + ")");
  }
}

// One material number, parsed in Real and checked in its range.
template <SupportedReal Real>
Real material_number(const std::string& option, const std::string& text) {
  using std::isfinite;
  const Real value = parse_real<Real>(option, text);
  bool ok = static_cast<bool>(isfinite(value)) && value > 0;
  std::string range = "a finite number > 0";
  if (option == "--poisson") {
    ok = value > -1 && value < Real(1) / 2;
    range = "in (-1, 0.5)";
  }
  if (!ok) {
    throw InputError(option + " must be " + range + " (got " + text + ")");
  }
  return value;
}

// The spheres of --geometry (two for sphere-sphere, one against a wall), in Real. Call
// settle_materials first.
template <SupportedReal Real>
std::vector<analytic::Sphere<Real>> spheres_of(const ContactArgs& a) {
  auto body = [&](std::size_t i) {
    auto value = [&](const char* option, const std::vector<std::string>& list) {
      return material_number<Real>(option, list[std::min(i, list.size() - 1)]);
    };
    return analytic::Sphere<Real>{.radius = value("--radius", a.radius),
                                  .young = value("--young", a.young),
                                  .poisson = value("--poisson", a.poisson),
                                  .density = value("--density", a.density)};
  };
  if (!a.geometry) {
    return {};
  }
  if (*a.geometry == "sphere-sphere") {
    return {body(0), body(1)};
  }
  return {body(0)};
}

// The Hertz contact of --geometry, in Real; none without it. Call settle_materials first.
template <SupportedReal Real>
std::optional<analytic::HertzContact<Real>> hertz_of(const ContactArgs& a) {
  if (!a.geometry) {
    return std::nullopt;
  }
  const std::vector<analytic::Sphere<Real>> spheres = spheres_of<Real>(a);
  analytic::HertzContact<Real> hertz;
  if (spheres.size() == 2) {
    hertz = analytic::hertz_contact(spheres[0], spheres[1]);
  } else {
    analytic::Wall<Real> wall;
    if (a.young.size() == 2) {
      wall = {.young = material_number<Real>("--young", a.young[1]),
              .poisson = material_number<Real>("--poisson", a.poisson[1])};
    }
    hertz = analytic::hertz_contact(spheres[0], wall);
  }
  // R³ or E beyond the type: inf, or inf/inf = NaN in m*; said so here, not as a NaN later.
  using std::isfinite;
  if (!isfinite(hertz.m) || !isfinite(hertz.k)) {
    throw InputError("the materials give a mass or stiffness beyond " +
                     std::string(precision_name<Real>()) + " (got --radius " +
                     typed_list(a.radius) + " --young " + typed_list(a.young) + " --density " +
                     typed_list(a.density) + ")");
  }
  return hertz;
}

// m and k of the contact: derived from the materials, or --m and --k as typed.
template <SupportedReal Real>
std::pair<Real, Real> mass_and_stiffness(const ContactArgs& a) {
  if (const auto hertz = hertz_of<Real>(a)) {
    return {hertz->m, hertz->k};
  }
  return {parse_real<Real>("--m", a.m), parse_real<Real>("--k", a.k)};
}

// The materials' part of an answer: the geometry, R* and E*.
template <SupportedReal Real>
void describe_materials(const ContactArgs& a, Answer& o) {
  if (const auto hertz = hertz_of<Real>(a)) {
    o["geometry"] = *a.geometry;
    o["R_eff"] = exact_number(hertz->radius);
    o["E_eff"] = exact_number(hertz->modulus);
  }
}

// The SI unit of each key of an answer that has one, for a contact from materials (whose inputs
// are SI: m, s, N, J, kg, Pa); a key not here is dimensionless or a count. α of the seed's
// damping exponent is dimensionless (MATH.md §13).
inline void add_units(Answer& o) {
  static const std::vector<std::pair<std::string, std::string>> units{{"m", "kg"},
                                                                      {"k", "N/m^1.5"},
                                                                      {"v0", "m/s"},
                                                                      {"R_eff", "m"},
                                                                      {"E_eff", "Pa"},
                                                                      {"delta_max", "m"},
                                                                      {"spring_force_max", "N"},
                                                                      {"normal_force_max", "N"},
                                                                      {"t_normal_force_max", "s"},
                                                                      {"t_peak", "s"},
                                                                      {"tau", "s"},
                                                                      {"tau0", "s"},
                                                                      {"energy_load", "J"},
                                                                      {"energy_unload", "J"},
                                                                      {"dt_crit", "s"},
                                                                      {"dt_tangent", "s"},
                                                                      {"t_cut", "s"},
                                                                      {"dt", "s"},
                                                                      {"dt_failing", "s"},
                                                                      {"dt_crit_seed", "s"},
                                                                      {"dt_stability", "s"},
                                                                      {"t_hertz", "s"},
                                                                      {"t_rayleigh", "s"},
                                                                      {"range", "[s, s]"},
                                                                      {"wall_seconds", "s"},
                                                                      {"samples", "[s, m, m/s]"}};
  Answer table = Answer::object();
  for (const auto& [key, unit] : units) {
    if (o.contains(key)) {
      table[key] = unit;
    }
  }
  o["units"] = table;
}

} // namespace pldamp::harness
