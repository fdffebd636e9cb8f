// `pldamp observables`: every closed-form observable of a contact in the precision asked
// (MATH.md §§2–7), or, for a damping exponent other than the seed's, the float128 reference solve
// scaled to the contact with its own error estimate (MATH.md §12).
#include "common/observables.hpp"
#include "ask/contact.hpp"
#include "truth/plan.hpp"
#include "truth/reference_solve.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <map>
#include <string>
#include <vector>

namespace pldamp::harness {

namespace {

// `observables --damping-exponent B` with B ≠ the seed's: no closed form exists (MATH.md §12), so
// the truth is the float128 reference solve (reference_solve.hpp), scaled to the contact
// (MATH.md §7, §12.1) and rounded to Real, with its own error estimate (a second float128 solve,
// MATH.md §12.2). The undamped τ0 and the critical steps do not depend on the damping: closed
// forms. No 50-digit truth is kept for this path: 50 digits are refused.
template <SupportedReal Real>
Answer observables_by_reference_solve(const ContactArgs& args) {
  if constexpr (!std::is_same_v<TruthFor<Real>, Exact>) {
    throw InputError("observables with --damping-exponent answers from the float128 reference "
                     "solve and its error estimate; it has no 50-digit truth (use --precision "
                     "quad, or solve --solver taylor --precision 50, about a second) (got "
                     "--precision " +
                     args.precision + ")");
  } else {
    Answer o = answer_object();
    const Real beta = parse_real<Real>("--damping-exponent", *args.damping_exponent);
    const ExponentContact<Real> contact = contact_with_exponent<Real>(args, beta, o);
    const solvers::Problem<Real>& problem = contact.problem;
    o["damping_exponent"] = exact_number(beta);
    o["method"] = "reference solve";
    const Exact p(problem.p), b(beta);
    const std::array<Exact, 5> scales =
        cell_scales(p, Exact(problem.v0), Exact(problem.m), Exact(problem.k));
    const bool capped = parse_end(args.end) == ContactEnd::force;
    std::vector<solvers::End> ends{solvers::End::overlap};
    if (capped) {
      ends.push_back(solvers::End::force);
    }
    // The truth's values at the contact's scales, by key, and their error estimates.
    std::map<std::string, Exact> values;
    Answer estimates = Answer::object();
    std::map<std::string, double> relative_errors;
    for (const solvers::End end : ends) {
      const solvers::Result<Exact>& truth = reference_solve(p, b, contact.group, end);
      if (solvers::failing(truth.outcome)) {
        throw InputError(fmt::format("the reference solve {} (got alpha_eff {})",
                                     reference_failure(truth), to_string_full(contact.group)));
      }
      // A damping exponent of its own has no closed form for an overdamped contact: the overlap
      // creeps and can come back to 0 after the horizon at a speed the solve never saw (with
      // δ^½ it does, at α_eff 1000 after ~5e4 δ_u/v0), so "no exit" is no e = 0, τ = ∞.
      if (truth.outcome == solvers::Outcome::no_exit) {
        throw InputError(fmt::format(
            "the reference solve saw no exit within its horizon ({} delta_u/v0): an overdamped "
            "contact with this damping exponent may still return later, at a speed below what it "
            "resolves, so no e or tau is given (got alpha_eff {})",
            to_string_full(truth.horizon / unit_overlap(p)), to_string_full(contact.group)));
      }
      const std::vector<const Observable*> observables = observables_of(solvers::want_all);
      const std::vector<std::optional<double>> errors =
          truth_error_estimate(observables, p, b, contact.group, end);
      for (std::size_t i = 0; i < observables.size(); ++i) {
        const Observable& observable = *observables[i];
        if (end == solvers::End::force && observable.key_at(end) == observable.key) {
          continue; // the force end adds e_cap and t_cut; the rest keep the overlap end's meaning
        }
        const std::string key(observable.key_at(end));
        if (const std::optional<Exact> value = observable.measured(truth)) {
          values[key] = *value * scales[std::size_t(observable.dimension)];
        }
        if (errors[i]) {
          estimates[key] = exact_number(*errors[i]);
          relative_errors[key] = *errors[i];
        }
      }
    }
    if (values.contains("e") && values["e"] > 0) {
      values["log_e"] = log(values["e"]);
    }
    const auto undamped = analytic::observables(
        analytic::Contact<Exact>::from_alpha(p, Exact(0), Exact(problem.v0), Exact(problem.m),
                                             Exact(problem.k)),
        analytic::want_tau | analytic::want_dt_crit);
    values["tau0"] = *undamped.tau0;
    values["dt_crit"] = *undamped.dt_crit;
    values["dt_tangent"] = *undamped.dt_tangent;
    if (values.contains("tau")) {
      values["log_tau"] = log(values["tau"]);
      values["tau_ratio"] = values["tau"] / values["tau0"];
    }
    // The spring's force at the peak overlap, k δ_max^p; its relative error p times δ_max's.
    if (values.contains("delta_max")) {
      values["spring_force_max"] = Exact(problem.k) * pow(values["delta_max"], p);
      if (const auto found = relative_errors.find("delta_max"); found != relative_errors.end()) {
        estimates["spring_force_max"] = exact_number(static_cast<double>(p) * found->second);
      }
    }
    for (const char* key :
         {"e", "log_e", "delta_max", "spring_force_max", "normal_force_max", "t_normal_force_max",
          "t_peak", "tau", "log_tau", "tau0", "tau_ratio", "energy_load", "energy_unload",
          "dt_crit", "dt_tangent", "e_cap", "t_cut"}) {
      if (const auto found = values.find(key); found != values.end()) {
        o[key] = exact_number(static_cast<Real>(found->second));
      }
    }
    // What each value's truth may err by (truth_error_estimate: relative; absolute where the value
    // is 0), before the rounding to the precision asked.
    o["error_estimate"] = estimates;
    return with_units(o);
  }
}

} // namespace

Answer observables_answer(const ContactArgs& args) {
  Answer answer;
  with_precision(args.precision, [&]<SupportedReal Real>() {
    // A stated β other than the seed's has no closed form; the seed's own has.
    std::optional<Real> beta;
    if (args.damping_exponent) {
      beta = parse_real<Real>("--damping-exponent", *args.damping_exponent);
      if (*beta != (parse_real<Real>("--p", args.p) - 1) / 2) {
        answer = observables_by_reference_solve<Real>(args);
        return;
      }
    }
    const analytic::Contact<Real> c = make_contact<Real>(args);
    const bool capped = parse_end(args.end) == ContactEnd::force;
    const auto x = analytic::observables(c, analytic::want_all &
                                                ~(capped ? 0u : unsigned(analytic::want_capped)));
    Answer o = describe(c, args);
    append_number(o, "damping_exponent", beta);
    append(o, "method", "closed forms");
    const std::pair<const char*, const std::optional<Real>&> fields[] = {
        {"e", x.e},
        {"log_e", x.log_e},
        {"delta_max", x.delta_max},
        {"spring_force_max", x.spring_force_max},
        {"normal_force_max", x.normal_force_max},
        {"t_normal_force_max", x.t_normal_force_max},
        {"t_peak", x.t_peak},
        {"tau", x.tau},
        {"log_tau", x.log_tau},
        {"tau0", x.tau0},
        {"tau_ratio", x.tau_ratio},
        {"energy_load", x.energy_load},
        {"energy_unload", x.energy_unload},
        {"dt_crit", x.dt_crit},
        {"dt_tangent", x.dt_tangent},
        {"e_cap", x.e_cap},
        {"t_cut", x.t_cut}};
    for (const auto& [key, value] : fields) {
      append_number(o, key, value);
    }
    answer = with_units(o);
  });
  return answer;
}

} // namespace pldamp::harness
