// `pldamp solve`: one collision integrated by a registered solver. The harness calibrates α from
// --e / --alpha-eff with the analytic layer (in double), then hands solvers/ only the physical
// parameters (p, m, k, v0, α).
#include "contact_args.hpp"

#include "pldamp/solvers/registry.hpp"

#include <limits>
#include <map>
#include <sstream>

namespace pldamp::harness {
namespace {

// "e,delta_max,..." -> Want bits; "energy" is both energy_load and energy_unload.
unsigned parse_want(const std::string& list) {
  static const std::map<std::string, unsigned> names{
      {"e", solvers::want_e},           {"delta_max", solvers::want_delta_max},
      {"t_peak", solvers::want_t_peak}, {"tau", solvers::want_tau},
      {"energy", solvers::want_energy}, {"all", solvers::want_all}};
  unsigned want = 0;
  std::istringstream items(list);
  for (std::string item; std::getline(items, item, ',');) {
    const auto found = names.find(item);
    if (found == names.end()) {
      throw InputError("unknown observable in --want, expected e|delta_max|t_peak|tau|energy|all "
                       "(got " +
                       item + ")");
    }
    want |= found->second;
  }
  if (want == 0) {
    throw InputError("--want names no observable (got " + list + ")");
  }
  return want;
}

template <SupportedReal Real>
std::string samples_json(const std::vector<solvers::Sample<Real>>& samples) {
  std::string out = "[";
  for (const auto& s : samples) {
    out += (out.size() > 1 ? ", [" : "[") + format_number(s.t) + ", " + format_number(s.delta) +
           ", " + format_number(s.v) + "]";
  }
  return out + "]";
}

bool runs_in_any_precision(const std::string& solver) {
  const solvers::SolverInfo* info = solvers::find_solver(solver);
  return info != nullptr && info->any_precision; // unknown: solvers::solve names the choices
}

// One collision in precision Real: α calibrated in Real, the solver run in Real.
template <SupportedReal Real>
void solve_in(const SolveArgs& args, std::ostream& out) {
  const analytic::Contact<Real> contact = make_contact<Real>(args.contact);
  const solvers::Problem<Real> problem{contact.p(), contact.m(), contact.k(), contact.v0(),
                                       contact.alpha()};
  const bool any_precision = runs_in_any_precision(args.solver);
  solvers::Options<Real> options;
  if (args.rtol) {
    options.rtol = parse_real<Real>("--rtol", *args.rtol);
  } else if (any_precision) {
    options.rtol = std::numeric_limits<Real>::epsilon(); // the reference: as exact as Real allows
  }
  if (args.atol) {
    options.atol = parse_real<Real>("--atol", *args.atol);
  }
  if (args.dt) {
    options.fixed_step = parse_real<Real>("--dt", *args.dt);
  }
  if (args.horizon) {
    options.horizon = parse_real<Real>("--horizon", *args.horizon);
  }
  for (const std::string& t : args.sample_times) {
    options.sample_times.push_back(parse_real<Real>("--sample-times", t));
  }
  options.want = parse_want(args.want);
  const bool capped = parse_end(args.contact.end) == ContactEnd::force;
  options.end = capped ? solvers::End::force : solvers::End::overlap;
  const long steps_per_contact = parse_integer("--steps-per-contact", args.steps_per_contact);
  if (steps_per_contact < 1 || steps_per_contact > 1000000000) {
    throw InputError("--steps-per-contact must be in [1, 1e9] (got " + args.steps_per_contact +
                     ")");
  }
  options.steps_per_contact = int(steps_per_contact);
  options.max_steps = parse_integer("--max-steps", args.max_steps);

  const solvers::Result<Real> r = solvers::solve(args.solver, problem, options);

  JsonObject o = describe(contact, args.contact);
  o.string("solver", args.solver);
  if (r.fixed_step) { // what a fixed-step run used instead of tolerances
    o.number("dt", r.fixed_step);
  } else {
    o.number("rtol", options.rtol);
    o.number("atol", options.atol);
  }
  o.string("outcome", std::string(solvers::outcome_name(r.outcome)));
  o.number(capped ? "e_cap" : "e", r.e);
  o.number("delta_max", r.delta_max);
  o.number("t_peak", r.t_peak);
  o.number(capped ? "t_cut" : "tau", r.tau);
  o.number("energy_load", r.energy_load);
  o.number("energy_unload", r.energy_unload);
  o.integer("steps", r.steps);
  o.integer("rhs_evals", r.rhs_evals);
  if (r.jacobian_evals > 0) {
    o.integer("jacobian_evals", r.jacobian_evals);
  }
  o.number("wall_seconds", r.wall_seconds);
  if (!options.sample_times.empty()) {
    o.raw("samples", samples_json(r.samples));
  }
  emit(o, args.contact.json, out);
}

} // namespace

void run_solve(const SolveArgs& args, std::ostream& out) {
  if (args.contact.precision != "double" && !runs_in_any_precision(args.solver)) {
    throw InputError("solver " + args.solver +
                     " runs in double precision only; taylor runs in any (got --precision " +
                     args.contact.precision + ")");
  }
  with_precision(args.contact.precision, [&]<SupportedReal Real>() { solve_in<Real>(args, out); });
}

} // namespace pldamp::harness
