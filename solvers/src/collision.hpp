// What every solver shares: the bookkeeping of one collision (events -> Result), the right-hand
// side with its evaluation counter, and the loop that drives any one-step method with dense output
// and finds events on it.
#pragma once

#include "pldamp/core/real_types.hpp"
#include "pldamp/solvers/contact_ode.hpp"
#include "pldamp/solvers/problem.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pldamp::solvers::detail {

// An integrator that cannot take its next step (a Newton iteration that does not converge, an
// error test failing down to the smallest step): the solve ends as `unstable`, with this message
// as its reason, not as an exception out of the solver.
struct StepFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <SupportedReal Real>
using StateOf = std::array<Real, 3>; // δ, v, W (W frozen at 0 when energy is not wanted)
using State = StateOf<double>;

// One collision's bookkeeping in physical units, in any precision (the Taylor reference runs in
// quad; the other solvers use Collision, the double one).
template <SupportedReal Real>
class BasicCollision {
public:
  using State = StateOf<Real>;

  BasicCollision(const Problem<Real>& problem, const Options<Real>& options);

  const ContactOde<Real>& ode() const { return ode_; }
  const Options<Real>& options() const { return options_; }
  bool with_work() const { return (options_.want & want_energy) != 0; }
  Real horizon() const { return horizon_; }
  State initial_state() const { return {Real(0), ode_.v0(), Real(0)}; }
  // Per-state absolute tolerances: literal `atol` for all, or rtol times each natural scale.
  State absolute_tolerances() const;
  // The δ-floor below which implicit methods' Jacobians are frozen (contact_ode.hpp).
  Real jacobian_floor() const;

  // Counts one evaluation.
  State rhs(const State& y) {
    ++rhs_evals_;
    return ode_.rhs(y[0], y[1], with_work());
  }
  // Counts one evaluation (an implicit method's Newton matrix; about one rhs in cost).
  std::array<State, 3> jacobian(const State& y) {
    ++jacobian_evals_;
    return ode_.jacobian(y[0], y[1], with_work(), jacobian_floor());
  }
  // Counts work done outside rhs() (the Taylor recurrences, in rhs-evaluation units).
  void count_rhs_evals(long n) { rhs_evals_ += n; }

  // Event functions, positive before the event and falling through 0 at it: the sign of dF/dt
  // (ContactOde::force_rate_sign) for the normal force's peak; v for the overlap's peak; δ or the
  // sign of the total force (MATH.md §4) for the exit.
  Real event_value(EventKind kind, const State& y) const;
  // An event still to be found: the normal force's peak while wanted and the overlap still
  // loads (every maximum of F lies there: while unloading F < k δ^p < k δ_max^p); the overlap's
  // peak until found; the exit once that peak is behind.
  bool pending(EventKind kind) const;
  // Records an event; returns true when the run is complete. An exit at a speed at or below
  // exit_speed_noise() is not one. A force peak is offered (below) and never ends the run.
  bool record(EventKind kind, const Real& t, const State& y);
  // A value of the total normal force at time t: the largest offered is the one reported.
  void offer_normal_force(const Real& t, const Real& force);
  // The onset, for the methods that integrate the ODE: with β = 0 the dashpot's c v0 acts at once
  // and can be the largest force (p = 1 with α_eff ≥ ½; MATH.md §3); offered when wanted.
  void offer_onset_force();
  Real exit_speed_noise() const { return exit_speed_noise_; }
  // True once the contact can no longer end above the noise, so that integrating on to the
  // horizon would only confirm `no_exit`: the peaks and every sample behind, the exit pending,
  // and the mechanical energy ½mv² + kδ^(p+1)/(p+1) below that of a tenth of the noise speed. The
  // dashpot only takes energy out (its power c δ^β v² ≥ 0, any β), so any later exit, at δ = 0
  // or where a capped force vanishes, comes at a speed ≤ √(2E/m) < exit_speed_noise() / 10: one
  // record() refuses whatever the integrator's error (the factor 10 is its margin). No
  // transformation of the paper's is used: only that the energy is a Lyapunov function.
  // A critical or overdamped contact gets there by δ_u/v0 times tens (p = 1) to thousands
  // (p = 1.5) instead of the 1000 of the horizon, and before its state reaches subnormal numbers.
  bool settled(const State& y) const;

  // Records the requested samples with times up to t (inclusive), in order.
  template <class StateAt>
  void sample_through(const Real& t, StateAt&& state_at) {
    while (next_sample_ < sample_times_.size() && sample_times_[next_sample_] <= t) {
      const Real ts = sample_times_[next_sample_++];
      const State y = state_at(ts);
      samples_.push_back({ts, y[0], y[1]});
    }
  }

  // A state that is no longer finite (a step beyond stability overflowed): the caller then
  // finishes with Outcome::unstable.
  static bool diverged(const State& y) {
    using std::isfinite;
    return !(isfinite(y[0]) && isfinite(y[1]) && isfinite(y[2]));
  }

  // The outcome that ends the solve before step `steps` + 1 when its budget is spent: step_limit
  // at max_steps; time_limit past max_seconds or on a stop request, looked at every 256 steps (a
  // clock read costs ~20 ns, a DEM code's step ~60 ns) or, with `every_call`, at each call.
  std::optional<Outcome> out_of_budget(long steps, bool every_call = false) const;
  // Whether out_of_budget(steps) can say anything: a fixed-step loop asks after every step, and
  // the call with its std::optional through memory was 40 % of a scalar DEM solve.
  bool budget_due(long steps) const { return steps >= options_.max_steps || steps % 256 == 0; }
  // A lane of a batch (batch_lanes.hpp, SharedClock): `others`, the time the batch spent on the
  // other lanes, is not this solve's, and max_seconds does not count it.
  void discount_time(std::chrono::steady_clock::duration others) { start_ += others; }

  // The Result, after the invariants every answer must satisfy (problem.hpp, Outcome::unstable):
  // an answer that breaks one is returned as `unstable`, its values dropped.
  // `reason`: why an `unstable` outcome came (default: a state no longer finite).
  Result<Real> finish(Outcome outcome, long steps, const std::string& reason = {});

private:
  ContactOde<Real> ode_;
  Options<Real> options_;
  Real horizon_;
  Real exit_speed_noise_ = 0; // set in the constructor
  Real settled_energy_ = 0;   // settled()'s threshold, set in the constructor
  long rhs_evals_ = 0, jacobian_evals_ = 0;
  std::vector<Real> sample_times_; // sorted
  std::size_t next_sample_ = 0;
  std::vector<Sample<Real>> samples_;
  std::vector<Event<Real>> events_;
  bool peak_found_ = false, exit_found_ = false;
  std::optional<Real> normal_force_, t_normal_force_; // the largest offered, and when
  Real t_peak_ = 0, delta_max_ = 0, work_peak_ = 0;
  Real tau_ = 0, exit_speed_ = 0, work_exit_ = 0, exit_overlap_ = 0;
  // Why the answer is impossible, or empty (finish).
  std::string violated_invariant() const;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

using Collision = BasicCollision<double>;

// A one-step method that can evaluate its solution anywhere in its last step [t_prev, t] to its
// own order of accuracy (a dense output, or the method's step repeated with a shorter h).
class OneStepMethod {
public:
  virtual ~OneStepMethod() = default;
  // Takes one accepted step, not beyond t_stop; returns the new time and leaves the state in y.
  virtual double step(double t_stop, State& y) = 0;
  virtual State state_at(double t) = 0;
  virtual long steps() const = 0;
  // Fehlberg pairs estimate their error from the stages at c = 0 and c = 1 only (b − b̂ vanishes
  // elsewhere) and so accept steps that straddle the branch point at the exit: at rtol 1e-10
  // their e was off by 1e-5 at p = 1.5. Such a method returns its order here; the driver then
  // caps its steps near the exit and ends the contact with the exit series (contact_ode.hpp).
  virtual int graded_exit_order() const { return 0; }
  virtual void limit_next_step(double /*h_max*/) {}
};

// Steps until the collision is complete, the horizon or the step limit. Each step's events are
// bracketed by a sign change of their event function and located by TOMS 748 on state_at.
Result<double> run_one_step_method(OneStepMethod& method, Collision& collision);

} // namespace pldamp::solvers::detail
