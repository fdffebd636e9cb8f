// `pldamp timestep`: its flags read into a contact and a question (a DEM code's α from its
// convention, a duration the search can reach), answered by judge/timestep_advice.hpp, and the
// answer written (text or JSON), with the closed forms beside it.
#include "ask/contact.hpp"
#include "ask/materials.hpp"
#include "common/observables.hpp"
#include "common/parallel.hpp"
#include "judge/timestep_advice.hpp"
#include "truth/plan.hpp"

#include "pldamp/analytic/conventions.hpp"
#include "pldamp/solvers/contact_ode.hpp"
#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pldamp::harness {
namespace {

std::vector<std::string> observable_keys(const std::string& list) {
  std::vector<std::string> keys;
  for (const std::string& item : list_items("--observables", list, true)) {
    const auto table = observable_table();
    const auto known = std::find_if(table.begin(), table.end(),
                                    [&](const Observable& o) { return o.key == item; });
    if (known == table.end() || known->solver_want == 0 || known->analytic_want == 0) {
      std::string names;
      for (const Observable& o : table) {
        if (o.solver_want != 0 && o.analytic_want != 0) {
          names.append(names.empty() ? "" : ",").append(o.key);
        }
      }
      throw InputError("unknown observable in --observables, expected a list of " + names +
                       " (got " + item + ")");
    }
    keys.push_back(item);
  }
  if (keys.empty()) {
    throw InputError("--observables names no observable (got " + list + ")");
  }
  return keys;
}

} // namespace

Answer timestep_answer(const TimestepArgs& args) {
  const solvers::SolverInfo* scheme = solvers::find_solver(args.scheme);
  if (scheme == nullptr || !scheme->fixed_step) {
    throw InputError(
        "--scheme must be a fixed-step scheme, " +
        solvers::solver_names([](const solvers::SolverInfo& info) { return info.fixed_step; }) +
        " (got " + args.scheme + ")");
  }
  const double tolerance = parse_real<double>("--tolerance", args.tolerance);
  if (!(tolerance > 0 && tolerance < 1)) {
    throw InputError("--tolerance must be in (0, 1), a relative error (got " + args.tolerance +
                     ")");
  }
  ContactArgs contact_args = args.contact;
  TimestepQuestion q;
  q.scheme = args.scheme;
  q.tolerance = tolerance;
  q.observables = observable_keys(args.observables);
  q.tau_as = name_of(tau_as_names, parse_tau_as(args.tau_as));
  Answer o = answer_object();
  if (args.contact.code) {
    // A DEM code's convention (calibrate --code): the α its formula sets for the target e, whose
    // contact the code then really integrates; a capped code's contact ends where F = 0.
    const analytic::Convention* convention = analytic::find_convention(*args.contact.code);
    if (convention == nullptr) {
      throw InputError("unknown --code, expected " + analytic::convention_names() + " (got " +
                       *args.contact.code + ")");
    }
    if (!args.contact.e || args.contact.alpha || args.contact.alpha_eff) {
      throw InputError("--code takes the target --e alone (got --code " + *args.contact.code + ")");
    }
    const double p = parse_real<double>("--p", args.contact.p);
    domain::require_p(p);
    const double alpha =
        analytic::alpha_set(*convention, p, parse_real<double>("--e", *args.contact.e));
    require_finite_alpha_set(*convention, alpha, *args.contact.e);
    contact_args.e.reset();
    contact_args.alpha = fmt::format("{:.17g}", alpha);
    contact_args.end = analytic::capped(*convention, false) ? "force" : "overlap";
    o["code"] = convention->name;
    o["e_target"] = exact_number(parse_real<double>("--e", *args.contact.e));
  }
  const analytic::Contact<double> contact = make_contact<double>(contact_args);
  const Answer head = describe(contact, contact_args);
  for (const auto& [key, value] : head.items()) {
    o[key] = value;
  }
  // The contact's duration as the scheme ends it: τ at the overlap end, which a contact at
  // α_eff >= 1 never reaches; at the force end the cut t_cut (MATH.md §4), which every contact
  // reaches (after the peak the dashpot's pull outgrows the spring's push as δ -> 0).
  const bool force_end = parse_end(contact_args.end) == analytic::ContactEnd::force;
  if (!force_end && contact.mu() <= 0) {
    throw InputError("alpha_eff >= 1: the contact does not return, no step keeps its e (got "
                     "alpha_eff " +
                     fmt::format("{}", static_cast<double>(contact.alpha_eff())) + ")");
  }
  const double tau = analytic::contact_duration(contact); // +inf when it never returns
  const double contact_time = force_end ? analytic::cut_time(contact) : tau;
  // Every solve of the search runs to the default horizon (solvers/problem.hpp): a contact that
  // lasts longer (α_eff just below 1, an e of 1e-300) has no step to search. Refused for what it
  // is, not at the first trial with "dt must be in [...]" of a step the user never gave.
  const double time_scale = solvers::ContactOde<double>({contact.p(), contact.m(), contact.k(),
                                                         contact.v0(), contact.alpha()})
                                .time_scale();
  if (!(contact_time < solvers::default_horizon_time_scales * time_scale)) {
    // A duration beyond double's range (α_eff 0.9999999 at p = 3/2: τ ~ e^1400) is said so, not
    // as "lasts inf"; α_eff in full, not rounded to the 1 it is not.
    const std::string lasts = std::isfinite(contact_time)
                                  ? fmt::format("lasts {:.6g} = {:.3g} delta_u/v0", contact_time,
                                                contact_time / time_scale)
                                  : std::string("lasts longer than a double holds");
    throw InputError(fmt::format(
        "the contact {}, beyond the {} delta_u/v0 a fixed-step solve runs to (e = {:.3g}: this "
        "close to critical damping no step is searched) (got alpha_eff {})",
        lasts, solvers::default_horizon_time_scales,
        static_cast<double>(analytic::restitution(contact)),
        static_cast<double>(contact.alpha_eff())));
  }
  q.p = contact.p();
  // The damping as given (a scene's e is calibrated as `solve` and `run` calibrate it); a code's
  // α as its formula sets it.
  if (contact_args.e) {
    q.damping_key = "e";
    q.damping = parse_real<double>("--e", *contact_args.e);
  } else if (contact_args.alpha_eff) {
    q.damping_key = "alpha_eff";
    q.damping = contact.alpha_eff();
  } else {
    q.damping_key = "alpha";
    q.damping = contact.alpha();
  }
  q.v0 = contact.v0();
  q.m = contact.m();
  q.k = contact.k();
  q.end = contact_args.end;
  const TimestepAdvice advice = advise_timestep(q, contact_time);
  const SearchGroup& group = advice.group;

  o["scheme"] = args.scheme;
  o["tolerance"] = exact_number(tolerance);
  Answer observables = Answer::array();
  for (const std::string& key : q.observables) {
    observables.push_back(key);
  }
  o["observables"] = observables;
  o["tau_as"] = q.tau_as;
  o["tau"] = exact_number(tau); // null (inf in text) when the contact never returns
  if (force_end) {
    o["t_cut"] = exact_number(contact_time);
  }
  o["range"] = Answer::array({exact_number(advice.range[0]), exact_number(advice.range[1])});
  put_number(o, "dt", group.loosest);
  put_number(o, "tau_over_dt",
             group.loosest && std::isfinite(tau) ? std::optional<double>(tau / *group.loosest)
                                                 : std::nullopt);
  if (force_end) {
    put_number(o, "t_cut_over_dt",
               group.loosest ? std::optional<double>(contact_time / *group.loosest) : std::nullopt);
  }
  // How tight: the worst error at the answer over every onset phase and the phase it is reached
  // at; the next Δt tried beyond it (within the search's 2 %), a phase where it fails and the
  // error there (the first found beyond the tolerance: the seeking stops there).
  put_number(o, "worst_error", group.measured);
  put_number(o, "worst_onset_phase", group.worst_onset_phase);
  put_number(o, "dt_failing", group.failing);
  put_number(o, "failing_error", group.failing_measured);
  put_number(o, "failing_onset_phase", group.failing_onset_phase);
  o["onset_phases"] = group.onset_phases;
  o["trials"] = group.trials;
  o["solver_runs"] = group.solver_runs;
  // The seed's Δt_crit (MATH.md §6), analytic; and the largest stable Δt measured as the
  // stability claim measures it (judge/solve.hpp: onset phase 0, e <= 1 at the return).
  o["dt_crit_seed"] = exact_number(analytic::dt_crit_seed(contact));
  if (std::find(q.observables.begin(), q.observables.end(), "normal_force_max") !=
          q.observables.end() &&
      group.loosest && group.worst_onset_phase) {
    // The peak force as the code reports it, the largest force it evaluated at a step (at the
    // answer and its worst phase), beside the exact peak it is judged against.
    put_number(o, "normal_force_max_at_worst_phase", advice.normal_force_max_at_worst_phase);
    o["normal_force_max_exact"] =
        exact_number(*analytic::observables(contact, analytic::want_normal_force).normal_force_max);
  }
  const StableStep& stable = advice.stable;
  put_number(o, "dt_stability",
             stable.limit.empty() && stable.dt > 0 ? std::optional<double>(stable.dt)
                                                   : std::nullopt);
  std::string note = group.note;
  if (!stable.limit.empty()) {
    note += (note.empty() ? "" : "; ") + ("stability search: " + stable.limit);
  } else if (stable.below) {
    note += (note.empty() ? "" : "; ") + std::string("stable up to 50 tau: dt_stability is a "
                                                     "lower bound");
  }
  // From materials, the step as DEM users size it (MATH.md §13): a fraction of the elastic Hertz
  // contact time (the closed form at α = 0) and of the Rayleigh time (the smaller sphere's).
  if (contact_args.geometry) {
    const double hertz_time =
        static_cast<double>(analytic::contact_duration(analytic::Contact<Exact>::from_alpha(
            Exact(q.p), Exact(0), Exact(q.v0), Exact(q.m), Exact(q.k))));
    const double rayleigh = static_cast<double>(
        rayleigh_time_of<Exact>(material_input(contact_args), MaterialNames::options()));
    o["t_hertz"] = exact_number(hertz_time);
    o["t_rayleigh"] = exact_number(rayleigh);
    put_number(o, "dt_over_t_hertz",
               group.loosest ? std::optional<double>(*group.loosest / hertz_time) : std::nullopt);
    put_number(o, "dt_over_t_rayleigh",
               group.loosest ? std::optional<double>(*group.loosest / rayleigh) : std::nullopt);
  }
  if (!note.empty()) {
    o["note"] = note;
  }
  return with_units(o);
}

} // namespace pldamp::harness
