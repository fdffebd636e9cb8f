// How a stepping code can time a contact besides τ, the time of its first step position out of
// contact (docs/MATH.md §5.1): the step positions at which the contact force acted, counted (a
// code's n Δt), and the linear interpolation of the crossing of the quantity that ended the
// contact (the overlap; under End::force the total normal force, unless the overlap ended it)
// between the last of them and the first position out. The fixed-step schemes (dem.cpp,
// dem_batch.cpp, verlet.cpp, verlet_batch.cpp) call it at every position, in the same order on
// the same values, so that a batch lane's Result is still its scalar solve's bit for bit.
#pragma once

#include "pldamp/solvers/problem.hpp"

#include <optional>

namespace pldamp::solvers::detail {

class StepTiming {
public:
  // A position (t, δ) at which the contact force acted, F the total normal force there.
  void acted(double t, double delta, double normal_force) {
    ++acting_;
    t_ = t;
    delta_ = delta;
    force_ = normal_force;
  }
  // The first position out of contact: δ ≤ 0, or (under End::force, δ > 0) a total normal force
  // F ≤ 0. The crossing of whichever ended the contact; none acted: the position itself.
  void ended(double t, double delta, double normal_force) {
    if (acting_ == 0) {
      crossing_ = t;
    } else if (delta > 0) {
      crossing_ = t_ + (t - t_) * (force_ / (force_ - normal_force));
    } else {
      crossing_ = t_ + (t - t_) * (delta_ / (delta_ - delta));
    }
  }
  // Into a result whose contact ended (τ filled).
  void fill(Result<double>& result) const {
    if (result.tau && crossing_) {
      result.steps_in_contact = acting_;
      result.tau_crossing = *crossing_;
    }
  }

private:
  long acting_ = 0;
  double t_ = 0, delta_ = 0, force_ = 0; // the last position that acted
  std::optional<double> crossing_;
};

} // namespace pldamp::solvers::detail
