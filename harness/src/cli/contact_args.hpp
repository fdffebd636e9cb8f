// Contact options as the user typed them, turned into an analytic::Contact in the precision asked
// for; shared by the analytic commands and `solve` (which calibrates α from e or α_eff here, in
// the harness, so that solvers/ never sees a closed form).
#pragma once

#include "cli/commands.hpp"
#include "common/answer.hpp"

#include "pldamp/analytic.hpp"

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
  const Real m = parse_real<Real>("--m", a.m);
  const Real k = parse_real<Real>("--k", a.k);
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

inline void emit(const Answer& answer, bool json, std::ostream& out) {
  out << (json ? answer_json(answer) + "\n" : answer_text(answer));
}

// The physical parameters and damping of a contact, the head of every analytic answer.
template <SupportedReal Real>
Answer describe(const analytic::Contact<Real>& c, const ContactArgs& a) {
  Answer o;
  o["precision"] = precision_name<Real>();
  o["end"] = a.end;
  o["p"] = exact_number(c.p());
  o["m"] = exact_number(c.m());
  o["k"] = exact_number(c.k());
  o["v0"] = exact_number(c.v0());
  o["alpha"] = exact_number(c.alpha());
  o["alpha_eff"] = exact_number(c.alpha_eff());
  return o;
}

} // namespace pldamp::harness
