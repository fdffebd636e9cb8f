// A contact from materials (MATH.md §13): --geometry sphere-sphere|sphere-wall with --radius,
// --young, --poisson, --density (one value per body, or one for both spheres) in place of --m,
// --k and --p. The options are checked once here (by common/materials.hpp's rules, which a
// scene's [[contact]] shares), the numbers parsed in the run's precision, and m, k, p = 3/2
// derived by analytic/hertz.hpp; every command that takes a contact uses this.
#pragma once

#include "ask/ask.hpp"
#include "common/answer.hpp"
#include "common/materials.hpp"

#include "pldamp/analytic/hertz.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

// The materials of the command line, as common/materials.hpp takes them.
inline MaterialInput material_input(const ContactArgs& a) {
  return {a.geometry.value_or(""), a.radius, a.young, a.poisson, a.density};
}

// Checks what is precision-free, once the command line is parsed: materials only with
// --geometry and never with --m or --k, each list of a length the geometry takes, --p absent or
// 3/2 (then set to 3/2). `mass_options_given` lists "--m 2" and the like as typed. Without
// --geometry, --p is required.
inline void settle_materials(ContactArgs& a, const std::vector<std::string>& mass_options_given) {
  const MaterialNames names = MaterialNames::options();
  if (!a.geometry) {
    for (const auto& [name, list] :
         {std::pair{&names.radius, &a.radius}, std::pair{&names.young, &a.young},
          std::pair{&names.poisson, &a.poisson}, std::pair{&names.density, &a.density}}) {
      if (!list->empty()) {
        throw InputError(*name + " goes with --geometry sphere-sphere|sphere-wall (got " + *name +
                         " " + list->front() + ")");
      }
    }
    if (a.p.empty()) {
      throw InputError("--p is required (got nothing)");
    }
    return;
  }
  if (*a.geometry == "sphere-sphere" || *a.geometry == "sphere-wall") {
    if (!mass_options_given.empty()) {
      throw InputError("--m and --k are derived from the materials under --geometry, give one or "
                       "the other (got " +
                       mass_options_given.front() + ")");
    }
  }
  check_material_shape(material_input(a), names);
  if (a.p.empty()) {
    a.p = "1.5";
  } else if (parse_real<double>("--p", a.p) != 1.5) {
    throw InputError("a contact from materials is Hertz's, p = 1.5 (got --p " + a.p + ")");
  }
}

// The Hertz contact of --geometry in Real, none without it: derived in float128 (50 digits where
// Real is wider) and rounded once, as a scene's [[contact]] derives it, so that the command line
// and a scene hand the solvers the same m and k, digit for digit. Call settle_materials first.
template <SupportedReal Real>
std::optional<analytic::HertzContact<Real>> hertz_of(const ContactArgs& a) {
  if (!a.geometry) {
    return std::nullopt;
  }
  using Derived = std::conditional_t<(std::numeric_limits<Real>::digits <
                                      std::numeric_limits<NarrowestWithDigits10<30>>::digits),
                                     NarrowestWithDigits10<30>, Real>;
  const auto wide = hertz_of<Derived>(material_input(a), MaterialNames::options());
  const analytic::HertzContact<Real> hertz{.m = static_cast<Real>(wide.m),
                                           .k = static_cast<Real>(wide.k),
                                           .p = static_cast<Real>(wide.p),
                                           .radius = static_cast<Real>(wide.radius),
                                           .modulus = static_cast<Real>(wide.modulus)};
  require_representable(hertz, material_input(a), MaterialNames::options());
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
                                                                      {"samples", "[s, m, m/s]"},
                                                                      {"e_of_v0", "[{v0: m/s}]"}};
  // Units a command set itself (a velocity-dependent code's α and entry) are kept.
  Answer table = o.contains("units") ? o["units"] : Answer::object();
  for (const auto& [key, unit] : units) {
    if (o.contains(key)) {
      table[key] = unit;
    }
  }
  o["units"] = table;
}

} // namespace pldamp::harness
