// A Hertz contact from materials (MATH.md §13): two elastic spheres, or a sphere on a wall, give
// the reduced mass m*, the effective radius R*, the effective modulus E* and the stiffness k = 4/3
// E* √R* of the force law k δ^(3/2) (Johnson, Contact Mechanics, 1985, §4.2). The inputs are
// validated by the caller (the harness names its options); these are the formulas. A contact in
// a type narrower than float128 is derived in float128 (CalibrationReal) and rounded once, as the
// command line and a scene's [[contact]] derive it: the same m* and k to the last bit.
#pragma once

#include "pldamp/analytic/contact.hpp"

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <optional>
#include <type_traits>

namespace pldamp::analytic {

// An elastic sphere: radius [m], Young's modulus [Pa], Poisson's ratio, density [kg/m³].
template <class Real>
struct Sphere {
  Real radius, young, poisson, density;
};

// A flat wall of infinite mass: rigid without a modulus, else elastic.
template <class Real>
struct Wall {
  std::optional<Real> young, poisson;
};

// What a Hertz contact hands the oscillator: m δ'' + ... + k δ^p = 0 with p = 3/2.
template <class Real>
struct HertzContact {
  Real m;       // reduced mass m* [kg]
  Real k;       // 4/3 E* √R* [N/m^1.5]
  Real p;       // 3/2
  Real radius;  // R* [m]
  Real modulus; // E* [Pa]
};

// m = 4/3 π R³ ρ (MATH.md §13).
template <class Real>
Real sphere_mass(const Sphere<Real>& s) {
  return Real(4) / 3 * boost::math::constants::pi<Real>() * s.radius * s.radius * s.radius *
         s.density;
}

// (1 − ν²)/E, one body's share of 1/E* (MATH.md §13).
template <class Real>
Real compliance(const Real& young, const Real& poisson) {
  return (Real(1) - poisson * poisson) / young;
}

// k = 4/3 E* √R* (MATH.md §13; Johnson 1985, §4.2).
template <class Real>
HertzContact<Real> hertz_from(const Real& m, const Real& radius, const Real& modulus) {
  using std::sqrt;
  return {.m = m,
          .k = Real(4) / 3 * modulus * sqrt(radius),
          .p = Real(3) / 2,
          .radius = radius,
          .modulus = modulus};
}

namespace detail {

// Two spheres: m* = m1 m2/(m1 + m2), 1/R* = 1/R1 + 1/R2, 1/E* = Σ (1 − ν_i²)/E_i.
template <class Real>
HertzContact<Real> two_spheres(const Sphere<Real>& a, const Sphere<Real>& b) {
  const Real ma = sphere_mass(a), mb = sphere_mass(b);
  return hertz_from<Real>(ma * mb / (ma + mb), a.radius * b.radius / (a.radius + b.radius),
                          Real(1) /
                              (compliance(a.young, a.poisson) + compliance(b.young, b.poisson)));
}

// A sphere on a wall: the wall's radius and mass are infinite, so R* = R1 and m* = m1; a rigid
// wall adds no compliance.
template <class Real>
HertzContact<Real> sphere_on_wall(const Sphere<Real>& a, const Wall<Real>& wall) {
  Real wall_compliance(0);
  if (wall.young) {
    wall_compliance = compliance(*wall.young, wall.poisson.value_or(Real(0)));
  }
  return hertz_from<Real>(sphere_mass(a), a.radius,
                          Real(1) / (compliance(a.young, a.poisson) + wall_compliance));
}

// Whether Real derives its contacts in a wider type (float128, or 50 digits without it).
template <class Real>
constexpr bool derived_wider() {
  if constexpr (SupportedReal<Real>) {
    return std::numeric_limits<Real>::digits < std::numeric_limits<CalibrationReal<Real>>::digits;
  } else {
    return false;
  }
}

template <class Wide, class Real>
Sphere<Wide> widened(const Sphere<Real>& s) { // exact: Wide holds every Real
  return {Wide(s.radius), Wide(s.young), Wide(s.poisson), Wide(s.density)};
}

template <class Real, class Wide>
HertzContact<Real> rounded(const HertzContact<Wide>& w) {
  return {static_cast<Real>(w.m), static_cast<Real>(w.k), static_cast<Real>(w.p),
          static_cast<Real>(w.radius), static_cast<Real>(w.modulus)};
}

} // namespace detail

template <class Real>
HertzContact<Real> hertz_contact(const Sphere<Real>& a, const Sphere<Real>& b) {
  if constexpr (detail::derived_wider<Real>()) {
    using Wide = CalibrationReal<Real>;
    return detail::rounded<Real>(
        detail::two_spheres(detail::widened<Wide>(a), detail::widened<Wide>(b)));
  } else {
    return detail::two_spheres(a, b);
  }
}

template <class Real>
HertzContact<Real> hertz_contact(const Sphere<Real>& a, const Wall<Real>& wall) {
  if constexpr (detail::derived_wider<Real>()) {
    using Wide = CalibrationReal<Real>;
    Wall<Wide> wide_wall;
    if (wall.young) {
      wide_wall.young = Wide(*wall.young);
    }
    if (wall.poisson) {
      wide_wall.poisson = Wide(*wall.poisson);
    }
    return detail::rounded<Real>(detail::sphere_on_wall(detail::widened<Wide>(a), wide_wall));
  } else {
    return detail::sphere_on_wall(a, wall);
  }
}

// The Rayleigh time of a sphere, π R √(ρ/G) / (0.1631 ν + 0.8766) with G = E/(2(1 + ν)): the
// time a Rayleigh surface wave takes to cross half of it, the step DEM codes size from the
// materials (a fraction of it; MATH.md §13; Li, Xu & Thornton, Powder Technology 160, 2005, 219,
// and YADE's RayleighWaveTimeStep). The fit's coefficients are built in Real.
template <class Real>
Real rayleigh_time(const Sphere<Real>& s) {
  using std::sqrt;
  const Real shear = s.young / (2 * (Real(1) + s.poisson));
  return boost::math::constants::pi<Real>() * s.radius * sqrt(s.density / shear) /
         (Real(1631) / 10000 * s.poisson + Real(8766) / 10000);
}

} // namespace pldamp::analytic
