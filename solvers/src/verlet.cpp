// verlet-predicted: fixed-step velocity Verlet (kick, drift, force, kick),
//
//     v_half = v + a Δt/2,   δ += v_half Δt,   a = F(δ, v + a Δt)/m,   v = v_half + a Δt/2,
//
// whose dashpot sees the full-step velocity predicted as v + a Δt. That keeps it second order
// where the force is smooth; the DEM codes (dem.cpp) feed the dashpot the half-step velocity
// v_half and are first order in everything. It is the better scheme at the same cost, and not
// what any code we know runs. The contact ends at the first step whose new overlap is ≤ 0 (or,
// with End::force, whose computed force is ≤ 0): there no contact force acts, so the body leaves
// with v_half of that step, and τ is that step's time. Both are first order in Δt by design.
//
// Between steps (the peak, samples) the trajectory is the cubic Hermite interpolant of (δ, v) at
// the two ends: the peak time where v interpolated linearly vanishes, δ_max the cubic there; both
// are second order. The dissipated work is the trapezoidal sum of the dashpot power c δ^a v².
// The onset phase φ puts the first step position at t = φ Δt, δ = v0 φ Δt (free flight before);
// φ = 0 starts on the moment of contact, with the force evaluated there.
#include "collision.hpp"
#include "hermite.hpp"
#include "methods.hpp"
#include "step_timing.hpp"

#include <boost/math/constants/constants.hpp>

namespace pldamp::solvers::detail {

Result<double> solve_verlet(const Problem<double>& problem, const Options<double>& options) {
  Options<double> stepped = options; // the step is reported in the result
  stepped.fixed_step = options.fixed_step.value_or(boost::math::constants::pi<double>() *
                                                   ContactOde<double>(problem).time_scale() /
                                                   options.steps_per_contact);
  Collision collision(problem, stepped);
  const double dt = *stepped.fixed_step;
  const bool force_end = options.end == End::force;
  // The first step position, φ of a step after the moment of contact.
  double t = options.onset_phase * dt;
  State y = collision.initial_state();
  y[0] = t * y[1];
  collision.sample_through(t, [&](double s) { return State{s * y[1], y[1], 0.0}; });
  double a = collision.rhs(y)[1];
  // The normal force is read off the step positions, as a stepping code would: −m a there.
  auto offer_force = [&](double at) {
    if (collision.pending(EventKind::force_peak)) {
      collision.offer_normal_force(at, -collision.ode().m() * a);
    }
  };
  offer_force(t);
  StepTiming timing;
  if (y[0] > 0) {
    timing.acted(t, y[0], -collision.ode().m() * a);
  }
  auto dashpot_power = [&](double delta, double v) {
    const auto& ode = collision.ode();
    return collision.with_work() ? ode.damping_coefficient() * ode.dashpot_factor(delta) * v * v
                                 : 0.0;
  };
  double power = dashpot_power(y[0], y[1]);
  long steps = 0;
  for (;;) {
    if (const auto spent =
            collision.budget_due(steps) ? collision.out_of_budget(steps) : std::nullopt) {
      return collision.finish(*spent, steps);
    }
    const State y_old = y;
    const double t_old = t;
    const double v_half = y[1] + a * dt / 2;
    const double delta = y[0] + v_half * dt;
    const State f = collision.rhs({delta, y[1] + a * dt, y[2]});
    a = f[1];
    t = (double(++steps) + options.onset_phase) * dt;
    offer_force(t);
    const double v = v_half + a * dt / 2;
    const double power_new = dashpot_power(delta, v);
    y = {delta, v, y[2] + dt / 2 * (power + power_new)};
    power = power_new;
    if (Collision::diverged(y)) {
      return collision.finish(Outcome::unstable, steps);
    }
    auto between = [&](double s) { return interpolate((s - t_old) / dt, dt, y_old, y); };
    if (collision.pending(EventKind::peak) && y_old[1] > 0 && y[1] <= 0) {
      const double t_peak = t_old + dt * y_old[1] / (y_old[1] - y[1]);
      collision.sample_through(t_peak, between);
      if (collision.record(EventKind::peak, t_peak, between(t_peak))) {
        return collision.finish(Outcome::peak, steps);
      }
    }
    const bool contact_lost =
        collision.pending(EventKind::exit) &&
        (force_end ? collision.ode().force_sign(delta, v_half) <= 0 : delta <= 0);
    if (contact_lost) {
      y[1] = v_half; // no contact force, hence no dashpot work, on the step that loses it
      y[2] = y_old[2];
      timing.ended(t, delta, delta > 0 ? collision.ode().total_force(delta, v_half) : 0.0);
    } else {
      timing.acted(t, delta, -collision.ode().m() * a);
    }
    collision.sample_through(t, between);
    if (contact_lost) {
      const bool exited = collision.record(EventKind::exit, t, y); // not if tolerance noise
      Result<double> result = collision.finish(exited ? Outcome::exited : Outcome::no_exit, steps);
      timing.fill(result);
      return result;
    }
    // Settled (Collision::settled): looked at every 64 steps, as the energy costs a power.
    if (t >= collision.horizon() || (steps % 64 == 0 && collision.settled(y))) {
      return collision.finish(Outcome::no_exit, steps);
    }
  }
}

} // namespace pldamp::solvers::detail
