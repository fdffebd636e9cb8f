// Contact options as the user typed them, turned into an analytic::Contact in the precision asked
// for; shared by the analytic commands and `solve` (which calibrates α from e or α_eff here, in
// the harness, so that solvers/ never sees a closed form).
#pragma once

#include "ask/ask.hpp"
#include "ask/materials.hpp"
#include "common/answer.hpp"
#include "truth/plan.hpp"
#include "truth/reference_solve.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/solvers/problem.hpp"

#include <ostream>
#include <string>

namespace pldamp::harness {

using analytic::ContactEnd;

inline ContactEnd parse_end(const std::string& end) {
  if (end == "overlap") {
    return ContactEnd::overlap;
  }
  if (end == "force") {
    return ContactEnd::force;
  }
  throw InputError("unknown contact end, expected overlap|force (got " + end + ")");
}

template <SupportedReal Real>
analytic::Contact<Real> make_contact(const ContactArgs& a) {
  const int given = int(a.e.has_value()) + int(a.alpha.has_value()) + int(a.alpha_eff.has_value());
  if (given != 1) {
    throw InputError("give exactly one of --e, --alpha, --alpha-eff (got " + std::to_string(given) +
                     ")");
  }
  const Real p = parse_real<Real>("--p", a.p);
  const Real v0 = parse_real<Real>("--v0", a.v0);
  const auto [m, k] = mass_and_stiffness<Real>(a);
  if (a.e) {
    return analytic::Contact<Real>::from_e(p, parse_real<Real>("--e", *a.e), v0, m, k,
                                           parse_end(a.end));
  }
  if (a.alpha) {
    return analytic::Contact<Real>::from_alpha(p, parse_real<Real>("--alpha", *a.alpha), v0, m, k);
  }
  return analytic::Contact<Real>::from_alpha_eff(p, parse_real<Real>("--alpha-eff", *a.alpha_eff),
                                                 v0, m, k);
}

// An answer as a front end gets it: with the units of its numbers for a contact from materials
// (one that has E_eff).
inline Answer with_units(Answer answer) {
  if (answer.contains("E_eff")) {
    add_units(answer);
  }
  return answer;
}

// The physical parameters and damping of a contact made by make_contact from `a`, the head of
// every analytic answer. Its α and α_eff are `calibrate`'s and `run`'s (seed_alpha,
// seed_alpha_eff): from e or α_eff they are calibrated in CalibrationReal and rounded once,
// whatever the contact's scales (contact_test's DampingIsScaleFreeToTheBit), so they are read off
// the contact; only α_eff from a stated α is formed again, in float128, and rounded once.
template <SupportedReal Real>
Answer describe(const analytic::Contact<Real>& c, const ContactArgs& a) {
  Answer o = answer_object();
  append(o, "precision", precision_name<Real>());
  append(o, "end", a.end);
  append(o, "p", exact_number(c.p()));
  append(o, "m", exact_number(c.m()));
  append(o, "k", exact_number(c.k()));
  append(o, "v0", exact_number(c.v0()));
  append(o, "alpha", exact_number(c.alpha()));
  append(o, "alpha_eff",
         exact_number(a.alpha ? seed_alpha_eff<Real>(c.p(), Damping::Kind::alpha,
                                                     parse_real<Real>("--alpha", *a.alpha),
                                                     parse_end(a.end))
                              : c.alpha_eff()));
  describe_materials<Real>(a, o);
  return o;
}

// A contact with a stated damping exponent: the problem handed to a solver, and its group.
template <SupportedReal Real>
struct ExponentContact {
  solvers::Problem<Real> problem;
  TruthFor<Real> group; // α_eff as calibrated, before α is rounded to Real
};

// The problem of a stated damping exponent β (MATH.md §12): α from --alpha, or the α that has
// the group --alpha-eff at this contact's δ_u, or the one whose restitution is --e (found on the
// reference solve, reference_solve.hpp). Every input is parsed in Real and the group is formed in
// TruthFor<Real> (float128, or 50 digits for a 50-digit solve), so nothing passes through a
// narrower type. `o` gets the α and α_eff used, in Real.
template <SupportedReal Real>
ExponentContact<Real> contact_with_exponent(const ContactArgs& a, const Real& beta, Answer& o) {
  using Truth = TruthFor<Real>;
  const int given = int(a.e.has_value()) + int(a.alpha.has_value()) + int(a.alpha_eff.has_value());
  if (given != 1) {
    throw InputError("give exactly one of --e, --alpha, --alpha-eff (got " + std::to_string(given) +
                     ")");
  }
  const Real p = parse_real<Real>("--p", a.p);
  const auto [m, k] = mass_and_stiffness<Real>(a);
  solvers::Problem<Real> problem{p, m, k, parse_real<Real>("--v0", a.v0), Real(0), beta};
  domain::require_p(p);
  domain::require_damping_exponent(beta, p);
  problem.validate(); // the scales, before δ_u is formed from them
  const Truth p_truth(p), beta_truth(beta);
  const Truth delta_u =
      unit_overlap(p_truth) * cell_scales(p_truth, Truth(problem.v0), Truth(problem.m),
                                          Truth(problem.k))[std::size_t(Dimension::length)];
  Truth group;
  if (a.alpha) {
    problem.alpha = parse_real<Real>("--alpha", *a.alpha);
    domain::require_alpha(problem.alpha);
    group = group_of(p_truth, beta_truth, Truth(problem.alpha), delta_u);
  } else {
    if (a.alpha_eff) {
      const Real z = parse_real<Real>("--alpha-eff", *a.alpha_eff);
      domain::require_alpha_eff(z);
      group = Truth(z);
    } else {
      const Real e = parse_real<Real>("--e", *a.e);
      require_finite("e", e);
      require(e > 0 && e <= 1, "e must be in (0, 1]", e);
      const std::optional<Truth> found = group_for_e(
          p_truth, beta_truth, Truth(e),
          parse_end(a.end) == ContactEnd::force ? solvers::End::force : solvers::End::overlap);
      if (!found) {
        throw InputError("no alpha_eff gives e = " + *a.e + " at p = " + a.p +
                         " with damping exponent " + *a.damping_exponent + " (got --e " + *a.e +
                         ")");
      }
      group = *found;
    }
    problem.alpha = static_cast<Real>(alpha_of(p_truth, beta_truth, group, delta_u));
    domain::require_alpha(problem.alpha);
  }
  o["precision"] = precision_name<Real>();
  o["end"] = a.end;
  o["p"] = exact_number(p);
  o["m"] = exact_number(problem.m);
  o["k"] = exact_number(problem.k);
  o["v0"] = exact_number(problem.v0);
  o["alpha"] = exact_number(problem.alpha);
  o["alpha_eff"] = exact_number(static_cast<Real>(group));
  describe_materials<Real>(a, o);
  return {problem, group};
}

// A code's formula (MATH.md §5) at an e it cannot take: YADE's Hertz-Mindlin β(e) divides by
// 1 − (1+e)² exp A(e), which rounds to 0 below e ~ 1e-17 in double, and sets an infinite α.
// Refused naming --e, not as "alpha_eff must be finite (got inf)" later.
template <class Real>
void require_finite_alpha_set(const analytic::Convention& convention, const Real& alpha,
                              const std::string& e_typed) {
  using std::isfinite;
  if (!isfinite(alpha)) {
    throw InputError(std::string(convention.name) + "'s formula sets no finite alpha at this e " +
                     "(the code itself divides by 0 there) (got --e " + e_typed + ")");
  }
}

} // namespace pldamp::harness
