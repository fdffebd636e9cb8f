// dem-verlet, dem-symplectic-euler, dem-leapfrog: a head-on contact stepped as DEM codes step it,
// each loop written as the code writes it (docs/MATH.md §5 "How the codes step a contact").
//
// In every code the force on the pair is evaluated only while the overlap is positive (their
// contact tests are strict: LAMMPS `rsq < radsum*radsum`, gran_sub_mod_normal.cpp; LIGGGHTS
// pair_gran_base.h L356; Chrono ChContactContainerSMC `distance >= 0` rejected; YADE
// `penetrationDepth < 0` erases the interaction), as k δ^p + c δ^a v with the velocity the code
// holds at that moment, and, where the code caps it, set to 0 when it is attractive. The body
// leaves with the velocity the code holds once no force acts: the contact ends at the first force
// evaluation with no overlap (End::overlap) or, with the cap, with a total force ≤ 0 while
// unloading (End::force; the force stays clipped from then on: with the overlap shrinking at a
// fixed speed its sign cannot come back).
//
// The three loops are one map. Written in the half-step velocities h, all three are
//     a_{n+1} = −F(δ_{n+1}, h_n)/m,   h_{n+1} = h_n + Δt a_{n+1},   δ_{n+2} = δ_{n+1} + Δt h_{n+1},
// velocity Verlet's v_{n+1} being (h_n + h_{n+1})/2 and Chrono's and YADE's stored velocity being
// h itself. They differ only in the velocity they report between contacts of the force (the
// energy measured at the peak), and agree in e, δ_max, t_peak and τ to rounding (tested). The
// dashpot always sees a velocity half a step old: first order in e, δ_max's error O(Δt).
//
// What is reported is what a user of the code can read off: e from the velocity held when the
// contact ends, τ the time of that force evaluation, δ_max and t_peak the largest overlap over
// the step positions and its time (no interpolation), the largest normal force the code
// evaluated and when, the energies by balance at those positions (KE0 − ½ m v² − k δ^(p+1)/(p+1)
// with the code's velocity).
//
// The onset phase φ (Options::onset_phase): a contact begins at t = 0, the first step position
// in contact is at t = φ Δt (free flight before, at v0), as the step grid of a simulation falls
// anywhere relative to the moment two particles touch.
#include "collision.hpp"
#include "methods.hpp"
#include "step_timing.hpp"

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <cmath>

namespace pldamp::solvers::detail {
namespace {

class DemContact {
public:
  DemContact(const Problem<double>& problem, const Options<double>& options)
      : stepped_(with_step(problem, options)), collision_(problem, stepped_),
        dt_(*stepped_.fixed_step), capped_(options.end == End::force),
        t_last_(start_time()), last_{start_overlap(), collision_.ode().v0(), 0.0} {}

  const Options<double>& stepped() const { return stepped_; }
  Collision& collision() { return collision_; }
  double dt() const { return dt_; }

  // The contact force on the overlap coordinate as the code evaluates it at time t and (δ, v):
  // −(k δ^p + c δ^a v), the total normal force pushing the bodies apart; 0 without overlap.
  // Notes when the contact ends there (no overlap, or a capped force ≤ 0 while unloading), and
  // offers the normal force to the collision (the largest is reported).
  double force(double t, double delta, double v) {
    if (delta <= 0) {
      ended_ = touched_;
      if (ended_) {
        timing_.ended(t, delta, 0);
      }
      return 0;
    }
    touched_ = true;
    const double force = collision_.ode().m() * collision_.rhs({delta, v, 0.0})[1];
    if (collision_.pending(EventKind::force_peak)) {
      collision_.offer_normal_force(t, -force);
    }
    if (capped_ && force >= 0) { // the total normal force k δ^p + c δ^a v is ≤ 0: clipped
      ended_ = true;
      timing_.ended(t, delta, -force);
      return 0;
    }
    timing_.acted(t, delta, -force);
    return force;
  }
  const StepTiming& timing() const { return timing_; }
  bool ended() const { return ended_; }

  // The work done on the dashpot by balance, with the velocity the code reports.
  double dissipated(double delta, double v) const {
    const ContactOde<double>& ode = collision_.ode();
    return ode.energy_scale() - ode.mechanical_energy(std::max(delta, 0.0), v);
  }

  // After each step: the step position (t, δ) with the code's velocity. Returns true when the
  // collision is complete (the caller then finishes with the returned outcome).
  bool after_step(double t, double delta, double v, long steps, Outcome& outcome) {
    const State y{delta, v, collision_.with_work() ? dissipated(delta, v) : 0.0};
    // Between step positions, samples follow the straight line (the codes keep no more).
    auto between = [&](double s) {
      const double theta = (s - t_last_) / dt_;
      return State{last_[0] + theta * (y[0] - last_[0]), last_[1] + theta * (y[1] - last_[1]), 0.0};
    };
    if (touched_ && collision_.pending(EventKind::peak) && delta < last_[0]) {
      collision_.sample_through(t_last_, between);
      if (collision_.record(EventKind::peak, t_last_, last_)) {
        outcome = Outcome::peak;
        return true;
      }
    }
    collision_.sample_through(t, between);
    t_last_ = t;
    last_ = y;
    if (ended_ && collision_.pending(EventKind::exit)) {
      outcome = collision_.record(EventKind::exit, t, y) ? Outcome::exited : Outcome::no_exit;
      return true;
    }
    if (t >= collision_.horizon()) {
      outcome = Outcome::no_exit;
      return true;
    }
    if (Collision::diverged(y)) {
      outcome = Outcome::unstable;
      return true;
    }
    if (collision_.budget_due(steps)) {
      if (const auto spent = collision_.out_of_budget(steps)) {
        outcome = *spent;
        return true;
      }
    }
    return false;
  }

  // The grid point before the first one in contact: (φ − 1)Δt, in free flight towards contact.
  double start_time() const { return (stepped_.onset_phase - 1) * dt_; }
  double start_overlap() const { return collision_.ode().v0() * start_time(); }

private:
  static Options<double> with_step(const Problem<double>& problem, const Options<double>& options) {
    Options<double> stepped = options; // the step is reported in the result
    stepped.fixed_step = options.fixed_step.value_or(boost::math::constants::pi<double>() *
                                                     ContactOde<double>(problem).time_scale() /
                                                     options.steps_per_contact);
    return stepped;
  }

  Options<double> stepped_;
  Collision collision_;
  double dt_;
  bool capped_;
  bool touched_ = false, ended_ = false;
  StepTiming timing_;
  double t_last_; // the last step position and the code's state there
  State last_;
};

} // namespace

Result<double> solve_dem(DemScheme scheme, const Problem<double>& problem,
                         const Options<double>& options) {
  DemContact contact(problem, options);
  Collision& collision = contact.collision();
  const double dt = contact.dt(), m = collision.ode().m();
  double t = contact.start_time();
  double delta = contact.start_overlap(), v = collision.ode().v0();
  long steps = 0;
  if (const auto spent = collision.out_of_budget(steps)) { // the loops look after each step
    return collision.finish(*spent, steps);
  }
  Outcome outcome = Outcome::step_limit;
  switch (scheme) {
  case DemScheme::verlet: {
    // LAMMPS Verlet::run (src/verlet.cpp): modify->initial_integrate, force->pair->compute,
    // modify->final_integrate; FixNVESphere (src/fix_nve_sphere.cpp): initial_integrate
    // `v += dtfm*f; x += dtv*v`, final_integrate `v += dtfm*f`, dtfm = dt/2/m. LIGGGHTS 3.8.0 the
    // same (verlet.cpp L293-373, fix_nve_sphere.cpp L167-175, L235-238); MercuryDPM
    // DPMBase::computeOneTimeStep with BaseParticle::integrateBeforeForceComputation
    // (`accelerate(F/m dt/2); move(v dt)`) and integrateAfterForceComputation. The pair force
    // reads the velocity between the two kicks: v_{n+1/2}.
    double f = 0; // the force of the last evaluation (free flight before contact)
    do {
      v += dt / 2 * f / m;                 // initial_integrate: half kick
      delta += dt * v;                     //                    drift
      f = contact.force(t + dt, delta, v); // pair compute at (x_{n+1}, v_{n+1/2})
      v += dt / 2 * f / m;                 // final_integrate: half kick
      t += dt;
    } while (!contact.after_step(t, delta, v, ++steps, outcome));
    break;
  }
  case DemScheme::symplectic_euler:
    // Chrono's ChSystemSMC with its default ChTimestepperEulerImplicitLinearized
    // (ChTimestepperImplicit.cpp, OnAdvance: solve M v_{n+1} = M v_n + dt f, then X += V*dt): the
    // SMC contact contributes no Jacobian (ChContactSMC::CreateJacobians is disabled), so the step
    // is v_{n+1} = v_n + dt F(x_n, v_n)/m, x_{n+1} = x_n + dt v_{n+1}, the force computed at
    // collision time from the state at the start of the step (ChContactSMC::Reset).
    do {
      const double f = contact.force(t, delta, v); // ComputeCollisions: F(x_n, v_n)
      if (contact.ended()) {
        break; // no force from here on: the body leaves with v_n
      }
      v += dt * f / m; // v_{n+1}
      delta += dt * v; // x_{n+1}
      t += dt;
    } while (!contact.after_step(t, delta, v, ++steps, outcome));
    break;
  case DemScheme::leapfrog:
    // YADE's engine loop (core/Scene.cpp): InteractionLoop computes the contact force from the
    // positions x_n and the stored velocity state->vel = v_{n−1/2}, then NewtonIntegrator
    // (pkg/dem/NewtonIntegrator.cpp) `state->vel += dt*linAccel` (v_{n+1/2}) and
    // leapfrogTranslate `state->pos += state->vel*dt` (x_{n+1}); its Cundall damping off.
    do {
      const double f = contact.force(t, delta, v); // InteractionLoop: F(x_n, v_{n−1/2})
      if (contact.ended()) {
        break;
      }
      v += dt * f / m; // NewtonIntegrator: v_{n+1/2}
      delta += dt * v; // leapfrogTranslate: x_{n+1}
      t += dt;
    } while (!contact.after_step(t, delta, v, ++steps, outcome));
    break;
  }
  if (contact.ended() && collision.pending(EventKind::exit)) {
    // The force evaluation at the start of a step found the contact over (Chrono, YADE).
    contact.after_step(t, delta, v, steps, outcome);
  }
  Result<double> result = collision.finish(outcome, steps);
  contact.timing().fill(result);
  return result;
}

} // namespace pldamp::solvers::detail
