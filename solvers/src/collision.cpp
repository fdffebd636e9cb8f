#include "collision.hpp"

#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace pldamp::solvers::detail {

template <SupportedReal Real>
BasicCollision<Real>::BasicCollision(const Problem<Real>& problem, const Options<Real>& options)
    : ode_(problem), options_(options),
      horizon_(options.horizon.value_or(default_horizon_time_scales * ode_.time_scale())),
      sample_times_(options.sample_times) {
  validate_against(problem, options_);
  std::sort(sample_times_.begin(), sample_times_.end());
  // An "exit" at a speed within the tolerances (of v, and of δ per time unit) is an overdamped
  // overlap that decayed into the integration noise and crossed 0 there: not a return the solver
  // can tell from none (so e below ~10 rtol reads as no exit). Capped at 1e-3 v0 so that a loose
  // tolerance does not hide a real return. Fixed per collision; the exit approach asks per step.
  using std::min;
  const State atol = absolute_tolerances();
  exit_speed_noise_ = min(10 * (atol[1] + atol[0] / ode_.time_scale()), ode_.v0() / 1000);
  settled_energy_ = ode_.mechanical_energy(Real(0), exit_speed_noise_ / 10);
}

template <SupportedReal Real>
bool BasicCollision<Real>::settled(const State& y) const {
  using std::max;
  // pending(exit): the overlap's peak, hence the force's, is behind. The kinetic energy first:
  // while it alone is above the threshold the spring's power need not be taken.
  return pending(EventKind::exit) && next_sample_ == sample_times_.size() &&
         ode_.m() * y[1] * y[1] / 2 < settled_energy_ &&
         ode_.mechanical_energy(max(y[0], Real(0)), y[1]) < settled_energy_;
}

template <SupportedReal Real>
StateOf<Real> BasicCollision<Real>::absolute_tolerances() const {
  if (options_.atol) {
    return {*options_.atol, *options_.atol, *options_.atol};
  }
  // rtol times each state's natural scale, chosen so that what is measured from it is measured
  // relative to itself (otherwise the absolute part dominates the whole contact):
  // - δ: δ_u. τ is its root, where its slope is e v0.
  // - v: 1e-3 v0. The exit speed e v0 is measured relative to itself down to e ~ 0.01; v crosses
  //   0 only at the peak, with slope −kδ^p/m ≠ 0, so the small floor costs a few steps there.
  // - W: the dashpot's work scale c δ_u^a v0 · δ_u (its force at δ_u, v0 over δ_u), at least
  //   1e-3 KE0: the dissipated (1 − e²) KE0 is small when e → 1, and so is c. Holding W to
  //   1e-3 KE0 instead cost 60% more CVODE steps for the same budget.
  using std::max;
  const Real rtol = options_.rtol;
  const Real delta_u = ode_.delta_scale();
  const Real dashpot_work =
      ode_.damping_coefficient() * ode_.dashpot_factor(delta_u) * delta_u * ode_.v0();
  return {rtol * delta_u, rtol * ode_.v0() / 1000,
          rtol * max(dashpot_work, ode_.energy_scale() / 1000)};
}

template <SupportedReal Real>
Real BasicCollision<Real>::jacobian_floor() const {
  // 1e-3 δ_u: the Newton iterations of a step leaving δ = 0 start from the step's start, where the
  // true ∂|δ|^a/∂δ is infinite, and must reach stage overlaps ~ v0 h. A floor at √ε δ_u (the
  // exact derivative almost everywhere) made arkode-dirk's fixed-step Newton fail in 44 of 72
  // runs (p = 1.25 ... 2.5, e = 0.9 ... 0.01, Δt = 0.2 ... 0.005); 1e-3 δ_u in none.
  return ode_.delta_scale() / 1000;
}

template <SupportedReal Real>
Real BasicCollision<Real>::event_value(EventKind kind, const State& y) const {
  if (kind == EventKind::force_peak) {
    return ode_.force_rate_sign(y[0], y[1]);
  }
  if (kind == EventKind::peak) {
    return y[1];
  }
  return options_.end == End::overlap ? y[0] : ode_.force_sign(y[0], y[1]);
}

template <SupportedReal Real>
bool BasicCollision<Real>::pending(EventKind kind) const {
  switch (kind) {
  case EventKind::force_peak:
    return (options_.want & want_normal_force) != 0 && !peak_found_;
  case EventKind::peak:
    return !peak_found_;
  case EventKind::exit:
    break;
  }
  return peak_found_ && !exit_found_;
}

template <SupportedReal Real>
void BasicCollision<Real>::offer_normal_force(const Real& t, const Real& force) {
  if (!normal_force_ || force > *normal_force_) {
    normal_force_ = force;
    t_normal_force_ = t;
  }
}

template <SupportedReal Real>
void BasicCollision<Real>::offer_onset_force() {
  if ((options_.want & want_normal_force) != 0 && ode_.damping_exponent() == 0) {
    offer_normal_force(Real(0), Real(ode_.damping_coefficient() * ode_.v0()));
  }
}

template <SupportedReal Real>
bool BasicCollision<Real>::record(EventKind kind, const Real& t, const State& y) {
  assert(pending(kind)); // every caller looks first: an event is found once, in its order
  if (kind == EventKind::force_peak) {
    offer_normal_force(t, ode_.total_force(y[0], y[1]));
    return false;
  }
  if (kind == EventKind::peak) {
    events_.push_back({kind, t});
    peak_found_ = true;
    t_peak_ = t;
    delta_max_ = y[0];
    work_peak_ = y[2];
    // Peak quantities alone: nothing after the peak is needed.
    return (options_.want & (want_e | want_tau | want_energy)) == 0;
  }
  using std::abs;
  if (abs(y[1]) <= exit_speed_noise()) {
    return false;
  }
  events_.push_back({kind, t});
  exit_found_ = true;
  tau_ = t;
  exit_speed_ = abs(y[1]);
  work_exit_ = y[2];
  exit_overlap_ = y[0];
  return true;
}

template <SupportedReal Real>
std::optional<Outcome> BasicCollision<Real>::out_of_budget(long steps, bool every_call) const {
  if (steps >= options_.max_steps) {
    return Outcome::step_limit;
  }
  if (every_call || steps % 256 == 0) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (elapsed > options_.max_seconds || (options_.stop != nullptr && options_.stop->load())) {
      return Outcome::time_limit;
    }
  }
  return std::nullopt;
}

template <SupportedReal Real>
std::string BasicCollision<Real>::violated_invariant() const {
  using std::isfinite;
  using std::max;
  using std::sqrt;
  if (peak_found_ && !(isfinite(delta_max_) && delta_max_ >= 0 && isfinite(t_peak_))) {
    return "delta_max " + to_string_full(delta_max_);
  }
  if (!exit_found_) {
    return {};
  }
  if (!(isfinite(exit_speed_) && isfinite(tau_) && isfinite(work_exit_))) {
    return "exit state not finite";
  }
  const Real e = exit_speed_ / ode_.v0();
  if (options_.fixed_step) {
    // No tolerance is asked of a fixed step; a stable second-order step can still gain energy by
    // its truncation, ~(ωΔt)² relative with ω² = k p δ_max^(p−1)/m the contact's stiffest
    // linearised frequency (at α = 0, 10 steps per contact: e = 1.002 at p = 1, 1.0013 at
    // p = 1.5). More than (ωΔt)²/8, or a quarter whatever the step, is the scheme's instability
    // (Δt = 10 gave e = 324; arkode-dp5 at Δt = 5, e = 1.87).
    const Real omega_squared = ode_.k() * ode_.p() * ode_.dashpot_factor(delta_max_) *
                               ode_.dashpot_factor(delta_max_) / ode_.m();
    const Real step = *options_.fixed_step;
    const Real allowance = std::min(Real(omega_squared * step * step / 8), Real(1) / 4);
    return e > 1 + allowance ? "energy gained: e = " + to_string_full(e) : std::string();
  }
  // Error control: e and the energy balance ½mv0² = ½mv² + kδ^(p+1)/(p+1) + W (at the force
  // end δ > 0 at the cut) hold to the tolerance asked, with room for its global accumulation:
  // CVODE's balance was off by up to 400 rtol at rtol 1e-12 (stress scene), so 1e4 tol, and at
  // most √tol, where a loose tolerance would otherwise excuse anything.
  Real tolerance = options_.rtol;
  if (options_.atol) {
    const Real atol = *options_.atol;
    tolerance = max(max(tolerance, Real(atol / ode_.delta_scale())),
                    max(Real(atol / ode_.v0()), Real(atol / ode_.energy_scale())));
  }
  using std::min;
  const Real allowance = min(Real(10000 * tolerance), Real(sqrt(tolerance))) +
                         1000 * std::numeric_limits<Real>::epsilon();
  if (e > 1 + allowance) {
    return "energy gained: e = " + to_string_full(e);
  }
  if (with_work()) {
    const Real left = ode_.mechanical_energy(exit_overlap_, exit_speed_) + work_exit_;
    const Real imbalance = (left - ode_.energy_scale()) / ode_.energy_scale();
    using std::abs;
    if (!(abs(imbalance) <= allowance)) {
      return "energy balance off by " + to_string_full(imbalance) + " of m v0^2/2";
    }
  }
  return {};
}

template <SupportedReal Real>
Result<Real> BasicCollision<Real>::finish(Outcome outcome, long steps, const std::string& reason) {
  Result<Real> r;
  r.outcome = outcome;
  if (outcome == Outcome::unstable) {
    r.invariant = reason.empty() ? "the state is no longer finite" : reason;
  } else {
    r.invariant = violated_invariant();
  }
  if (!r.invariant.empty()) {
    r.outcome = outcome = Outcome::unstable;
    peak_found_ = exit_found_ = false; // nothing below is filled
  }
  const unsigned want = options_.want;
  if (r.invariant.empty() && normal_force_ && (want & want_normal_force)) {
    r.normal_force_max = normal_force_;
    r.t_normal_force_max = t_normal_force_;
  }
  if (peak_found_) {
    if (want & want_delta_max) {
      r.delta_max = delta_max_;
    }
    if (want & want_t_peak) {
      r.t_peak = t_peak_;
    }
    if (want & want_energy) {
      r.energy_load = work_peak_;
    }
  }
  if (exit_found_) {
    if (want & want_e) {
      r.e = exit_speed_ / ode_.v0();
    }
    if (want & want_tau) {
      r.tau = tau_;
    }
    if (want & want_energy) {
      r.energy_unload = work_exit_ - work_peak_;
    }
  } else if (outcome == Outcome::no_exit) {
    // No return before the horizon: the body never leaves (e = 0, τ = ∞); the unloading work is
    // left unset, as it has not been measured to the end.
    if (want & want_e) {
      r.e = Real(0);
    }
    if (want & want_tau) {
      r.tau = std::numeric_limits<Real>::infinity();
    }
  }
  r.fixed_step = options_.fixed_step;
  r.horizon = horizon_;
  r.steps = steps;
  r.rhs_evals = rhs_evals_;
  r.jacobian_evals = jacobian_evals_;
  r.events = std::move(events_);
  r.samples = std::move(samples_);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return r;
}

#define PLDAMP_INSTANTIATE(Real, name) template class BasicCollision<Real>;
PLDAMP_FOR_EACH_PRECISION(PLDAMP_INSTANTIATE)
#undef PLDAMP_INSTANTIATE

namespace {

// The graded approach to the exit for methods blind to its branch point. A step of size h ending
// at distance d before a singularity (τ − t)^b errs by ~ (h/d)^(q+1) |binom(b, q+1)| d^b for a
// method of order q; |binom(b, q+1)| ~ 1e-3 for b ~ 1...2, q = 8. Steps of at most κ times the
// time left, κ = (1e3 rtol)^(1/(q+1)), so keep each step's error near rtol · d^b, and the
// distances fall geometrically: ~ ln(d_0/d_end)/κ steps (about 30 at rtol 1e-10, q = 8). κ is
// capped at 0.2: at 0.5 (rtol ≥ 1e-6) the estimate failed and e erred by 1.5e-4 at rtol 1e-6.
struct ExitApproach {
  double kappa = 0;         // 0: the method's own error control sees the exit
  double series_switch = 0; // the exit series takes over once its parameter is below this

  ExitApproach(const OneStepMethod& method, const Collision& collision) {
    const int order = method.graded_exit_order();
    const Options<double>& options = collision.options();
    if (order > 0 && options.end == End::overlap) {
      kappa = std::min(0.2, std::pow(1e3 * options.rtol, 1.0 / (order + 1)));
      // The series errs by O(ε³) (contact_ode.hpp): ε ≤ (rtol/10)^(1/3).
      series_switch = std::cbrt(options.rtol / 10);
    }
  }
  bool active() const { return kappa > 0; }
};

} // namespace

Result<double> run_one_step_method(OneStepMethod& method, Collision& collision) {
  State y = collision.initial_state();
  double t = 0;
  collision.offer_onset_force();
  collision.sample_through(t, [&](double) { return y; });
  const double horizon = collision.horizon();
  const ExitApproach approach(method, collision);
  for (;;) {
    if (const auto spent = collision.out_of_budget(method.steps())) {
      return collision.finish(*spent, method.steps());
    }
    // Only while a return can still be told from the noise: once a critical or overdamped
    // overlap has decayed into it, δ hovers about 0 and the cap κ δ/|v| would creep (odeint-rkf78
    // ran into its step limit at p = 1, z = 1).
    const bool unloading =
        !collision.pending(EventKind::peak) && y[0] > 0 && -y[1] > collision.exit_speed_noise();
    if (approach.active() && unloading) {
      method.limit_next_step(approach.kappa * y[0] / -y[1]);
    }
    double t_from = t;
    State y_from = y;
    try {
      t = method.step(horizon, y);
    } catch (const StepFailed& failure) {
      return collision.finish(Outcome::unstable, method.steps(), failure.what());
    }
    if (Collision::diverged(y)) {
      return collision.finish(Outcome::unstable, method.steps());
    }
    for (const EventKind kind : {EventKind::force_peak, EventKind::peak, EventKind::exit}) {
      if (!collision.pending(kind)) {
        continue;
      }
      const double g_from = collision.event_value(kind, y_from);
      const double g_to = collision.event_value(kind, y);
      if (!(g_from > 0 && g_to <= 0)) {
        continue;
      }
      double t_event = t;
      if (g_to < 0) {
        // 50 bits of the event time: its error then adds ~1e-15 relative to any observable.
        auto g = [&](double s) { return collision.event_value(kind, method.state_at(s)); };
        std::uintmax_t iterations = 100;
        const auto [lo, hi] = boost::math::tools::toms748_solve(
            g, t_from, t, g_from, g_to, boost::math::tools::eps_tolerance<double>(50), iterations);
        t_event = lo + (hi - lo) / 2;
      }
      const State y_event = t_event == t ? y : method.state_at(t_event);
      collision.sample_through(t_event, [&](double s) { return method.state_at(s); });
      if (collision.record(kind, t_event, y_event)) {
        return collision.finish(kind == EventKind::peak ? Outcome::peak : Outcome::exited,
                                method.steps());
      }
      if (kind != EventKind::force_peak) {
        // The next event lies beyond this one. Not so the overlap's peak after the force's: they
        // coincide without damping (both where v = 0), and v there may round either way.
        t_from = t_event;
        y_from = y_event;
      }
    }
    collision.sample_through(t, [&](double s) { return method.state_at(s); });
    if (approach.active() && collision.pending(EventKind::exit) && y[1] < 0 && y[0] > 0 &&
        collision.ode().exit_series_parameter(y[0], y[1]) <= approach.series_switch) {
      const auto stretch = collision.ode().exit_stretch(y[0], y[1]);
      const double t_exit = t + stretch.duration;
      const State y_exit{0, stretch.exit_velocity,
                         y[2] + (collision.with_work() ? stretch.work : 0)};
      collision.sample_through(t_exit, [&](double s) { // linear across this short stretch
        const double f = (s - t) / stretch.duration;
        return State{y[0] * (1 - f), y[1] + f * (y_exit[1] - y[1]), y[2] + f * (y_exit[2] - y[2])};
      });
      const bool exited = collision.record(EventKind::exit, t_exit, y_exit); // not if noise
      return collision.finish(exited ? Outcome::exited : Outcome::no_exit, method.steps());
    }
    if (t >= horizon || collision.settled(y)) {
      return collision.finish(Outcome::no_exit, method.steps());
    }
  }
}

} // namespace pldamp::solvers::detail

namespace pldamp::solvers {

template <SupportedReal Real>
void validate_against(const Problem<Real>& problem, const Options<Real>& options) {
  options.validate();
  const ContactOde<Real> ode(problem);
  using std::min;
  const Real epsilon = std::numeric_limits<Real>::epsilon();
  const Real time_scale = ode.time_scale();
  if (options.atol) {
    // atol applies literally to δ, v and W (problem.hpp): at or above the smallest of their
    // natural scales it lets any answer through (atol 1e300 gave δ_max = −338); far below it the
    // first steps out of δ = 0 cannot meet it (at scale 1, CVODE and ARKODE's error tests failed
    // at t = 0 from atol 1e-60, and met 1e-30): the floor is ε² times that scale.
    const bool with_work = (options.want & want_energy) != 0;
    const Real scale =
        min(min(ode.delta_scale(), ode.v0()), with_work ? ode.energy_scale() : ode.v0());
    const Real floor = epsilon * epsilon * scale;
    require(
        *options.atol < scale && *options.atol >= floor,
        [&] {
          return "atol must be in [" + to_string_full(floor) + ", " + to_string_full(scale) +
                 "), epsilon^2 times and once the smallest natural scale of the state (delta_u, " +
                 "v0" + (with_work ? ", m v0^2/2" : "") + ")";
        },
        *options.atol);
  }
  // The horizon: at least ε of the time scale (CVODE refused a stop time of 1e-300 as behind
  // t = 0), at most 1e9 of it (an overdamped contact's steps then grew to 1e133 and CVODE's
  // corrector failed; the default is 1000).
  const Real horizon = options.horizon.value_or(default_horizon_time_scales * time_scale);
  require(
      horizon >= epsilon * time_scale && horizon <= 1000000000 * time_scale,
      [&] {
        return "horizon must be in [" + to_string_full(Real(epsilon * time_scale)) + ", " +
               to_string_full(Real(1000000000 * time_scale)) +
               "], epsilon and 1e9 times the time scale delta_u/v0";
      },
      horizon);
  // A fixed step below ε of the time scale does not advance time; one beyond the horizon never
  // sees the contact at all.
  if (options.fixed_step) {
    require(
        *options.fixed_step >= epsilon * time_scale && *options.fixed_step < horizon,
        [&] {
          return "dt must be in [" + to_string_full(Real(epsilon * time_scale)) + ", " +
                 to_string_full(horizon) + "), epsilon times the time scale delta_u/v0 and the " +
                 "horizon";
        },
        *options.fixed_step);
  }
}

#define PLDAMP_INSTANTIATE(Real, name)                                                             \
  template void validate_against(const Problem<Real>&, const Options<Real>&);
PLDAMP_FOR_EACH_PRECISION(PLDAMP_INSTANTIATE)
#undef PLDAMP_INSTANTIATE

} // namespace pldamp::solvers
