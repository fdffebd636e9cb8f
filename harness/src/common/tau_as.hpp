// The contact time as a user's code measures it (`--tau-as`, a scene's `tau_as`; docs/MATH.md
// §5.1). A fixed-step run reports three (solvers::Result): τ, the time of its first step position
// out of contact (counted from the exact touch); the steps at which the contact force acted times
// Δt; and the interpolated crossing of δ = 0 (F = 0 under the force end). Each is compared with
// the same closed-form τ (t_cut).
#pragma once

#include "common/names.hpp"

#include "pldamp/solvers/problem.hpp"

namespace pldamp::harness {

enum class TauAs { first_step_out, steps_in_contact, crossing };
inline constexpr NameTable<TauAs, 3> tau_as_names{{{TauAs::first_step_out, "first-step-out"},
                                                   {TauAs::steps_in_contact, "steps-in-contact"},
                                                   {TauAs::crossing, "crossing"}}};

// result.tau replaced by the contact time `as` counts it. A run without the fixed-step counts
// (an error-controlled solver, an external program) is left as it is: the scene reader refuses
// tau_as for those.
template <class Real>
void time_contact_as(solvers::Result<Real>& result, TauAs as) {
  if (!result.tau || !result.steps_in_contact || !result.fixed_step) {
    return;
  }
  switch (as) {
  case TauAs::first_step_out:
    break;
  case TauAs::steps_in_contact:
    result.tau = Real(*result.steps_in_contact) * *result.fixed_step;
    break;
  case TauAs::crossing:
    result.tau = result.tau_crossing;
    break;
  }
}

} // namespace pldamp::harness
