#include "judge/trajectory_check.hpp"

#include "common/input.hpp"
#include "common/observables.hpp"

#include <fmt/format.h>

namespace pldamp::harness {

CheckedTrajectory check_trajectory_file(const analytic::Contact<Exact>& contact, solvers::End end,
                                        const std::string& path) {
  CheckedTrajectory c{contact, end, load_trajectory(path), {}, {}};
  ExtractOptions options;
  options.v0 = double(c.contact.v0());
  options.end = c.end;
  options.force_law = ForceLaw{double(c.contact.p()), double(c.contact.m()), double(c.contact.k()),
                               double(c.contact.alpha())};
  options.force_jumps_at_contact = c.contact.p() == 1 && c.contact.alpha() > 0;
  c.x = extract_observables(c.columns, options);
  const StatedContact stated{.p = options.force_law->p,
                             .m = options.force_law->m,
                             .k = options.force_law->k,
                             .v0 = options.v0};
  if (const std::optional<std::string> why = contradiction(c.x, stated)) {
    throw InputError(*why);
  }
  const unsigned want = solvers::want_e | solvers::want_delta_max | solvers::want_t_peak |
                        solvers::want_tau | solvers::want_normal_force;
  const analytic::Observables<Exact> closed =
      analytic::observables(c.contact, analytic_want_of(want, c.end));
  const std::array<const Extracted*, checked_keys.size()> measured_of{
      &c.x.e,   &c.x.delta_max,        &c.x.t_peak,
      &c.x.tau, &c.x.normal_force_max, &c.x.t_normal_force_max};
  for (std::size_t i = 0; i < checked_keys.size(); ++i) {
    const char* key = checked_keys[i];
    const Extracted* measured = measured_of[i];
    const Observable* observable = find_observable(key);
    const std::optional<Exact> truth = observable->exact(closed, c.end);
    c.rows.push_back({observable, *measured, truth, judge_extracted(*measured, truth), {}, {}});
  }
  return c;
}

TrajectoryCheck check_trajectory(const TrajectorySpec& spec, solvers::End scene_end) {
  TrajectoryCheck out{spec.label, spec.file, "", "", {}, {}};
  const solvers::End end = spec.end.value_or(scene_end);
  out.inputs = fmt::format("p = {:g}, {} = {:g}, v0 = {:g}, m = {:g}, k = {:g}, end {}", spec.p,
                           spec.damping_key, spec.damping, spec.v0, spec.m, spec.k,
                           end == solvers::End::force ? "force" : "overlap");
  // The scene's decimal (its shortest text) in Exact, as `pldamp check` reads a flag: a double's
  // binary value would differ from 0.3 beyond Exact's digits.
  const auto exact = [](const char* name, double x) {
    return parse_real<Exact>(name, to_string_full(x));
  };
  try {
    const Exact p = exact("p", spec.p), damping = exact(spec.damping_key.c_str(), spec.damping),
                v0 = exact("v0", spec.v0), m = exact("m", spec.m), k = exact("k", spec.k);
    const analytic::Contact<Exact> contact =
        spec.damping_key == "e"
            ? analytic::Contact<Exact>::from_e(p, damping, v0, m, k,
                                               end == solvers::End::force
                                                   ? analytic::ContactEnd::force
                                                   : analytic::ContactEnd::overlap)
        : spec.damping_key == "alpha"
            ? analytic::Contact<Exact>::from_alpha(p, damping, v0, m, k)
            : analytic::Contact<Exact>::from_alpha_eff(p, damping, v0, m, k);
    const CheckedTrajectory checked = check_trajectory_file(contact, end, spec.file);
    for (const CheckedRow& row : checked.rows) {
      out.rows.push_back({std::string(row.observable->key_at(end)), row.measured.value,
                          row.measured.value ? std::optional(row.measured.sampling) : std::nullopt,
                          row.truth ? std::optional(static_cast<double>(*row.truth)) : std::nullopt,
                          row.judgement});
    }
    out.notes = checked.x.notes;
  } catch (const InputError& e) { // this file only: the run goes on
    out.failure = e.what();
  }
  return out;
}

} // namespace pldamp::harness
