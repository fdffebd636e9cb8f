// A Hertz contact from materials (MATH.md §13): two elastic spheres, or a sphere on a wall, give
// the reduced mass m*, the effective radius R*, the effective modulus E* and the stiffness k = 4/3
// E* √R* of the force law k δ^(3/2) (Johnson, Contact Mechanics, 1985, §4.2). The inputs are
// validated by the caller (the harness names its options); these are the formulas.
#pragma once

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <optional>

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

// Two spheres: m* = m1 m2/(m1 + m2), 1/R* = 1/R1 + 1/R2, 1/E* = Σ (1 − ν_i²)/E_i.
template <class Real>
HertzContact<Real> hertz_contact(const Sphere<Real>& a, const Sphere<Real>& b) {
  const Real ma = sphere_mass(a), mb = sphere_mass(b);
  return hertz_from<Real>(ma * mb / (ma + mb), a.radius * b.radius / (a.radius + b.radius),
                          Real(1) /
                              (compliance(a.young, a.poisson) + compliance(b.young, b.poisson)));
}

// A sphere on a wall: the wall's radius and mass are infinite, so R* = R1 and m* = m1; a rigid
// wall adds no compliance.
template <class Real>
HertzContact<Real> hertz_contact(const Sphere<Real>& a, const Wall<Real>& wall) {
  Real wall_compliance(0);
  if (wall.young) {
    wall_compliance = compliance(*wall.young, wall.poisson.value_or(Real(0)));
  }
  return hertz_from<Real>(sphere_mass(a), a.radius,
                          Real(1) / (compliance(a.young, a.poisson) + wall_compliance));
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
