// What DEM codes set for a target restitution, and what they really give (MATH.md §5).
//
// Each code turns the restitution e a user enters into the damping coefficient α of MATH.md §1
// by its own formula, and ends a contact by its own rule: when the overlap returns to 0, or, with
// a force cap, when the total normal force reaches 0 (§4). Through the closed forms each choice
// has an exact consequence: the e the code really gives, and the e a user should enter to get
// the target. The formulas, read from each code's source (docs/MATH.md §5 cites the lines):
//
//   lammps-tsuji              α = T(e) = 1.2728 − 4.2783e + 11.087e² − 22.348e³ + 27.467e⁴
//                                 − 18.022e⁵ + 4.8218e⁶ (Marshall 2009's fit; Hertz only)
//   lammps-tsuji-2026         α = √2 T(e), the 2026 correction (PR #5113)
//   lammps-coeff-restitution  α = 2 ξ_L (hooke), √5 ξ_L (hertz): exact at the overlap end
//   liggghts                  the same; `limitForce` caps the force
//   mercurydpm                the same, never capped
//   chrono                    √5 ξ_L (Hertz), always capped (ChSystemSMC)
//   yade                      2 ξ_L (ViscElPhys, linear), √5 ξ_L (Mindlin, Hertz); always capped
//                             (YADE's Mindlin before it took Thornton et al. 2013's fit)
//   yade-viscel               2 ξ_L (ViscElMat tc, en; YADE 2023.02a); always capped
//   yade-hertz-mindlin        √6 β_T(e), β_T(e) = √(1/(1 − (1+e)² exp A(e)) − 1) with A Thornton
//                             et al. (2013)'s (B6) fit, a degree-10 polynomial (YADE 2023.02a's
//                             Ip2_FrictMat_FrictMat_MindlinPhys en); always capped
//
// with ξ_L = −ln e / √(π² + ln² e). LAMMPS's `limit_damping` is the cap for the lammps-*
// conventions, LIGGGHTS's `limitForce` for liggghts.
#pragma once

#include "pldamp/analytic/contact.hpp"

#include <boost/math/tools/toms748_solve.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace pldamp::analytic {

enum class Code {
  lammps_tsuji,
  lammps_tsuji_2026,
  lammps_coeff_restitution,
  liggghts,
  mercurydpm,
  chrono,
  yade,
  yade_viscel,
  yade_hertz_mindlin,
};

// Whether a code ends a contact at the force cut.
enum class Cap { never, optional, always };

struct Convention {
  Code code;
  std::string_view name; // the CLI's --code and a scene's `convention`
  bool linear, hertz;    // the models it has: p = 1 (Hooke), p = 3/2 (Hertz)
  Cap cap;
  std::string_view source; // where the formula is read
};

inline constexpr std::array<Convention, 9> conventions{{
    {Code::lammps_tsuji, "lammps-tsuji", false, true, Cap::optional,
     "LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp (GranSubModDampingTsuji::init, released "
     "versions): damp = T(e); the pair force adds -damp*sqrt(meff*Fnormal/delta)*vnnr "
     "(granular_model.cpp), limit_damping clips the total normal force at 0"},
    {Code::lammps_tsuji_2026, "lammps-tsuji-2026", false, true, Cap::optional,
     "LAMMPS gran_sub_mod_damping.cpp after PR #5113 (2026): damp = T(e) * MY_SQRT2"},
    {Code::lammps_coeff_restitution, "lammps-coeff-restitution", true, true, Cap::optional,
     "LAMMPS gran_sub_mod_damping.cpp (GranSubModDampingCoeffRestitution::init, PR #4068): "
     "hooke -2 ln e/sqrt(pi^2+ln^2 e), hertz sqrt(3/2)*2*sqrt(5/6) times that"},
    {Code::liggghts, "liggghts", true, true, Cap::optional,
     "LIGGGHTS 3.8.0 src/normal_model_hertz.h L231-261 (gamman = -2 sqrt(5/6) beta sqrt(Sn "
     "meff), limitForce), normal_model_hooke.h L274-291"},
    {Code::mercurydpm, "mercurydpm", true, true, Cap::never,
     "MercuryDPM Kernel/Species/NormalForceSpecies/HertzianViscoelasticNormalSpecies.cc "
     "(dissipation = sqrt(5 ln^2 e/(ln^2 e+pi^2))), LinearViscoelasticNormalSpecies.cc; "
     "HertzianViscoelasticInteraction.cc applies the force unclamped"},
    {Code::chrono, "chrono", false, true, Cap::always,
     "Project Chrono src/chrono/physics/ChContactSMC.cpp (Hertz: gn = -2 sqrt(5/6) beta "
     "sqrt(Sn m_eff); if (forceN < 0) forceN = 0)"},
    {Code::yade, "yade", true, true, Cap::always,
     "YADE pkg/dem/HertzMindlin.cpp (alpha from en, normal force set to 0 when attractive), "
     "pkg/dem/ViscoelasticPM.cpp (cn = -2 massR ln(en)/tc; normal force 0 when Fn+Fv < 0)"},
    {Code::yade_viscel, "yade-viscel", true, false, Cap::always,
     "YADE 2023.02a (Debian 12) pkg/dem/ViscoelasticPM.cpp: ViscElMat(tc, en) gives kn = massR "
     "(pi^2+ln^2 en)/tc^2, cn = -2 massR ln(en)/tc; Law2_ScGeom_ViscElPhys_Basic sets the normal "
     "force to 0 when kn*delta + cn*vn < 0 (adapters/yade measures both)"},
    {Code::yade_hertz_mindlin, "yade-hertz-mindlin", false, true, Cap::always,
     "YADE 2023.02a (Debian 12) pkg/dem/HertzMindlin.cpp: Ip2_FrictMat_FrictMat_MindlinPhys(en) "
     "sets betan = sqrt(1/(1-(1+en)^2 exp(A(en)))-1), A Thornton et al. 2013's (B6) fit; "
     "Law2_ScGeom_MindlinPhys_Mindlin cn = 2 betan sqrt(mbar kn), kn = 3/2 kno sqrt(uN), the "
     "normal force 0 when attractive (adapters/yade measures both)"},
}};

// The convention of that name, or nullptr.
inline const Convention* find_convention(std::string_view name) {
  for (const Convention& c : conventions) {
    if (c.name == name) {
      return &c;
    }
  }
  return nullptr;
}

// "lammps-tsuji|...|yade", for messages.
inline std::string convention_names() {
  std::string names;
  for (const Convention& c : conventions) {
    names += names.empty() ? "" : "|";
    names += c.name;
  }
  return names;
}

// Whether a contact under this convention ends at the force cut (`limit` is LAMMPS's
// limit_damping or LIGGGHTS's limitForce, for the codes where it is an option).
inline bool capped(const Convention& c, bool limit) {
  return c.cap == Cap::always || (c.cap == Cap::optional && limit);
}

// T(e), the fit of Marshall (2009) to Tsuji's curve that LAMMPS's `tsuji` damping evaluates.
template <SupportedReal Real>
Real tsuji_polynomial(const Real& e) {
  const Real c[] = {Real(12728) / 10000, Real(-42783) / 10000, Real(11087) / 1000,
                    Real(-22348) / 1000, Real(27467) / 1000,   Real(-18022) / 1000,
                    Real(48218) / 10000};
  Real sum(0);
  for (int i = 6; i >= 0; --i) {
    sum = sum * e + c[i];
  }
  return sum;
}

// β_T(e), the damping ratio YADE's Ip2_FrictMat_FrictMat_MindlinPhys sets for a restitution en:
// Thornton, Cummins and Cleary (2013), eq. (B6), a fit of the Hertz contact with a δ^¼ dashpot
// ended at the force cut, β = √(1/(1 − (1+e)² exp A(e)) − 1), A(e) = e (h1 + e (h2 + … e h10)).
// It is positive on (0, 1] (1 − (1+e)² exp A > 0 there; at e = 1 it is 0.0045, not 0).
template <SupportedReal Real>
Real thornton_damping_ratio(const Real& e) {
  using std::exp;
  using std::sqrt;
  const Real h[] = {Real(-6918798) / 1000000, Real(-1641105) / 100000, Real(1468049) / 10000,
                    Real(-7964559) / 10000,   Real(2928711) / 1000,    Real(-7206864) / 1000,
                    Real(1149429) / 100,      Real(-1134218) / 100,    Real(6276757) / 1000,
                    Real(-1489915) / 1000};
  Real sum(0);
  for (int i = 9; i >= 0; --i) {
    sum = sum * e + h[i];
  }
  const Real a = e * sum;
  return sqrt(Real(1) / (Real(1) - (Real(1) + e) * (Real(1) + e) * exp(a)) - Real(1));
}

// Throws std::invalid_argument unless the code has a model with exponent p (Hooke, Hertz).
template <SupportedReal Real>
void require_model(const Convention& c, const Real& p) {
  const bool linear = p == 1, hertz = p == Real(3) / 2;
  if (!((c.linear && linear) || (c.hertz && hertz))) {
    const bool both = c.linear && c.hertz;
    require(false,
            std::string(c.name) + " has " +
                (both       ? "a linear (p = 1) and a Hertz (p = 1.5) model"
                 : c.linear ? "a linear model only"
                            : "a Hertz model only") +
                ": p must be " +
                (both       ? "1 or 1.5"
                 : c.linear ? "1"
                            : "1.5"),
            p);
  }
}

// The α the code sets for the e a user enters.
template <SupportedReal Real>
Real alpha_set(const Convention& c, const Real& p, const Real& e_entered) {
  using std::sqrt;
  require_model(c, p);
  require_finite("e", e_entered);
  require(e_entered > 0 && e_entered <= 1, "e must be in (0, 1]", e_entered);
  switch (c.code) {
  case Code::lammps_tsuji:
    return tsuji_polynomial(e_entered);
  case Code::lammps_tsuji_2026:
    return sqrt(Real(2)) * tsuji_polynomial(e_entered);
  case Code::yade_hertz_mindlin: // cn = 2 β √(m · 3/2 k δ^½): α = 2 √(3/2) β = √6 β
    return sqrt(Real(6)) * thornton_damping_ratio(e_entered);
  default: // the exact overlap-end calibration, α = √(2(p+1)) ξ_L: 2 ξ_L, √5 ξ_L
    return alpha_per_alpha_eff(p) * damping_from_e(e_entered).z;
  }
}

// The restitution a contact with α really has under the code's end rule (MATH.md §3, §4).
template <SupportedReal Real>
Real e_given(const Real& p, const Real& alpha, bool capped_end) {
  const Damping<Real> d = damping_from_alpha_eff(Real(alpha / alpha_per_alpha_eff(p)));
  return capped_end ? capped_restitution(d) : restitution(d);
}

// The e a user should enter so that the code gives `target`; none when no entry reaches it (a
// capped code calibrated at the overlap end gives at least e^-2 = 0.1353 however small the entry).
template <SupportedReal Real>
std::optional<Real> e_to_enter(const Convention& c, const Real& p, const Real& target, bool limit) {
  require_finite("e", target);
  require(target > 0 && target <= 1, "e must be in (0, 1]", target);
  const bool cut = capped(c, limit);
  auto given = [&](const Real& entered) { return e_given(p, alpha_set(c, p, entered), cut); };
  // e_given grows with the entry (more restitution asked, less damping set); it is bracketed
  // between its values at the smallest entry and at e = 1.
  const Real smallest = Real(1) / 1000000;
  const Real low = given(smallest), high = given(Real(1));
  if (target < low || target > high) {
    return std::nullopt;
  }
  if (target == high) {
    return Real(1);
  }
  std::uintmax_t iterations = 200;
  const auto [lo, hi] = boost::math::tools::toms748_solve(
      [&](const Real& entered) { return Real(given(entered) - target); }, smallest, Real(1),
      Real(low - target), Real(high - target),
      boost::math::tools::eps_tolerance<Real>(std::numeric_limits<Real>::digits - 3), iterations);
  return (lo + hi) / 2;
}

} // namespace pldamp::analytic
