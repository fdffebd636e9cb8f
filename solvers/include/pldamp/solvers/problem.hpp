// The solver interface (docs/design.md §4): what to integrate (Problem), what to compute
// and how (Options), what came out (Result). Every solver in the registry takes and returns these.
//
// The equation is MATH.md §1 in physical time, with the damping exponent β of MATH.md §12,
//     m δ'' + α √(m k) δ^β δ' + k δ^p = 0,   δ(0) = 0, δ'(0) = v0,
// β = (p−1)/2 unless stated, and nothing in solvers/ knows its closed-form solution: the values
// here are measured.
#pragma once

#include "pldamp/core/domain.hpp"
#include "pldamp/core/real_types.hpp"
#include "pldamp/core/validate.hpp"

#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::solvers {

// Physical parameters. `alpha` is the dimensionless damping coefficient of MATH.md §1; the harness
// turns a target e or α_eff into it.
// `damping_exponent` is β; absent, the seed's (p−1)/2. Stated, even as (p−1)/2, the solvers take
// their general path (taylor's two-variable contact series), which is how that path is checked
// against the closed forms. α then carries the units length^((p−1)/2 − β).
template <SupportedReal Real>
struct Problem {
  Real p, m, k, v0, alpha;
  std::optional<Real> damping_exponent = std::nullopt;

  Real beta() const { return damping_exponent.value_or((p - 1) / 2); }

  void validate() const {
    domain::require_p(p);
    domain::require_scale("m", m);
    domain::require_scale("k", k);
    domain::require_scale("v0", v0);
    domain::require_alpha(alpha);
    if (damping_exponent) {
      domain::require_damping_exponent(*damping_exponent, p);
    }
  }
};

// How a contact ends (MATH.md §4): when the overlap returns to 0, or, as force-capped DEM codes
// do, when the total normal force k δ^p + α√(mk) δ^((p−1)/2) δ' first reaches 0 while unloading.
enum class End { overlap, force };

// Observables a run is asked for (a bit set). Peak quantities alone let a run stop at the peak;
// energy adds the dissipated work as a third state; normal_force the largest total normal force
// k δ^p + c δ^β δ' and its time (it comes before the overlap's peak: a peak quantity).
enum Want : unsigned {
  want_e = 1u << 0,
  want_delta_max = 1u << 1,
  want_t_peak = 1u << 2,
  want_tau = 1u << 3,
  want_energy = 1u << 4,
  want_normal_force = 1u << 5,
  want_all = (1u << 6) - 1,
};

// The relative tolerance of a solve that names none (DefaultTolerance::standard in registry.hpp).
template <SupportedReal Real>
Real standard_rtol() {
  return Real(1) / 100000000;
}

// The default horizon (Options::horizon), in natural time units δ_u/v0.
inline constexpr int default_horizon_time_scales = 1000;

template <SupportedReal Real>
struct Options {
  Real rtol = standard_rtol<Real>();
  // Absolute tolerance applied literally to every state, in physical units, as ode45 does. When
  // absent each state gets rtol times its natural scale (δ: the undamped δ_max; v: 1e-3 v0; W:
  // the dashpot's work scale; see Collision::absolute_tolerances), so a contact in metres
  // (δ ~ 1e-5) is solved as accurately as one in units of 1. taylor controls the error relative
  // to each state and ignores atol.
  std::optional<Real> atol;
  unsigned want = want_all;
  End end = End::overlap;
  // Where a contact that has not ended is given up as `no_exit` (critical and overdamped contacts
  // return only as t → ∞). Default: 1000 natural time units δ_u/v0, about 300 undamped contact
  // durations. For p = 1 an overdamped overlap has then decayed exponentially, by tens of orders
  // of magnitude; for p > 1 the creep is algebraic (δ ~ t^(−2/(p−1))), and a heavily damped
  // contact can return later than that (p = 10, e = 1e-4 at 2100 δ_u/v0): set the horizon
  // accordingly to see such returns. A run stops before the horizon, also as `no_exit`, once its
  // mechanical energy is too small for any later exit to be told from the tolerance noise (the
  // dashpot only dissipates; every sample taken first).
  std::optional<Real> horizon;
  // Times at which to record (t, δ, v); only those inside the contact are recorded.
  std::vector<Real> sample_times;
  // A fixed step instead of error control: arkode-* (for convergence-order tests) and the
  // fixed-step schemes.
  std::optional<Real> fixed_step;
  // Fixed-step schemes without fixed_step: Δt = (π δ_u / v0) / steps_per_contact; π δ_u/v0 is the
  // undamped contact duration for p = 1 and within 20% of it for 1 ≤ p ≤ 5.
  int steps_per_contact = 50;
  // Fixed-step solvers: the contact begins this fraction of a step before the first step position
  // in contact (free flight at v0 until then), in [0, 1); 0 puts a step position exactly at the
  // moment of contact. A simulation's step grid falls anywhere relative to that moment.
  Real onset_phase = 0;
  // The budget of one solve: steps, and wall-clock seconds (checked every few hundred steps).
  // Whichever comes first ends the solve as step_limit or time_limit with what was reached.
  long max_steps = 1000000;
  double max_seconds = 60;
  // Another thread's request to stop (a signal handler's flag): the solve ends as time_limit.
  const std::atomic<bool>* stop = nullptr;

  void validate() const {
    using std::numeric_limits;
    require_positive("rtol", rtol);
    require(rtol < 1, "rtol must be < 1", rtol);
    // Below the working precision's ε no integrator can meet the tolerance (CVODE and ARKODE
    // stop with "too much accuracy requested"; taylor would silently give ε).
    require(
        rtol >= numeric_limits<Real>::epsilon(),
        [] {
          return "rtol must be >= " + to_string_full(Real(numeric_limits<Real>::epsilon())) +
                 ", the epsilon of " + std::string(precision_name<Real>());
        },
        rtol);
    if (atol) {
      require_positive("atol", *atol);
    }
    require(std::isfinite(max_seconds) && max_seconds > 0, "max seconds must be > 0",
            Real(max_seconds));
    if (horizon) {
      require_positive("horizon", *horizon);
    }
    if (fixed_step) {
      require_positive("dt", *fixed_step);
    }
    require(steps_per_contact >= 1, "steps per contact must be >= 1", Real(steps_per_contact));
    require_finite("onset phase", onset_phase);
    require(onset_phase >= 0 && onset_phase < 1, "onset phase must be in [0, 1)", onset_phase);
    require(max_steps >= 1, "max steps must be >= 1", Real(max_steps));
    require(want != 0 && (want & ~unsigned(want_all)) == 0, "want must name an observable",
            Real(want));
    for (const Real& t : sample_times) {
      require_finite("sample time", t);
      require(t >= 0, "sample time must be >= 0", t);
    }
  }
};

// What Options::validate cannot check alone, against the problem's natural scales (δ_u, v0,
// ½mv0², the time δ_u/v0): atol, the fixed step, the horizon. Every solve runs it; scenes run it
// on their grid before any work. Throws std::invalid_argument.
template <SupportedReal Real>
void validate_against(const Problem<Real>& problem, const Options<Real>& options);

enum class Outcome {
  exited,     // the contact ended: everything wanted is filled
  peak,       // stopped at the peak, as asked (only peak quantities were wanted)
  no_exit,    // the horizon came first, or the energy left cannot carry an exit above the noise
              // (critical or overdamped): e = 0, τ = ∞, loading measured
  step_limit, // max_steps came first: whatever was reached is filled
  time_limit, // max_seconds (or a stop request) came first: whatever was reached is filled
  unstable,   // an impossible answer: a state not finite, δ_max < 0, energy gained (e > 1 beyond
              // the solve's accuracy) or an energy balance off by more than the tolerance asked;
              // nothing is filled (collision.hpp, BasicCollision::finish)
};

// An outcome that carries no answer: the budget ran out, or the answer was impossible.
constexpr bool failing(Outcome outcome) {
  return outcome == Outcome::step_limit || outcome == Outcome::time_limit ||
         outcome == Outcome::unstable;
}

constexpr std::string_view outcome_name(Outcome outcome) {
  switch (outcome) {
  case Outcome::exited:
    return "exited";
  case Outcome::peak:
    return "peak";
  case Outcome::no_exit:
    return "no_exit";
  case Outcome::step_limit:
    return "step_limit";
  case Outcome::time_limit:
    return "time_limit";
  case Outcome::unstable:
    break;
  }
  return "unstable";
}

// The outcome outcome_name names `name`; none for any other word (an external program's reply, a
// report's record).
constexpr std::optional<Outcome> outcome_named(std::string_view name) {
  for (const Outcome outcome : {Outcome::exited, Outcome::peak, Outcome::no_exit,
                                Outcome::step_limit, Outcome::time_limit, Outcome::unstable}) {
    if (outcome_name(outcome) == name) {
      return outcome;
    }
  }
  return std::nullopt;
}

// The normal force's peak (dF/dt falling through 0, ContactOde::force_rate_sign), the overlap's
// peak (v = 0) and the exit.
enum class EventKind { force_peak, peak, exit };

template <SupportedReal Real>
struct Event {
  EventKind kind;
  Real t;
};

template <SupportedReal Real>
struct Sample {
  Real t, delta, v;
};

// Only what was wanted (and reached) is filled. Under End::force, e and tau are the capped
// restitution and the cut time. normal_force_max is the largest total normal force
// k δ^p + c δ^β δ' (at the onset, c v0, when the dashpot's jump is the largest), t_normal_force_max
// its time.
template <SupportedReal Real>
struct Result {
  Outcome outcome = Outcome::step_limit;
  std::string invariant; // unstable: the invariant the answer broke, e.g. "energy gained: e = 2.7"
  std::optional<Real> e, delta_max, t_peak, tau, energy_load, energy_unload;
  std::optional<Real> normal_force_max, t_normal_force_max;
  std::optional<Real> fixed_step; // the step of a fixed-step run (or Options::fixed_step)
  // A fixed-step run whose contact ended: the step positions at which the contact force acted,
  // and the linear interpolation between the last of them and τ of the crossing that ended it
  // (δ = 0, or F = 0 under End::force): the contact time as a code may count it (n Δt) or
  // interpolate it, beside τ, its first position out of contact (docs/MATH.md §5.1).
  std::optional<long> steps_in_contact;
  std::optional<Real> tau_crossing;
  Real horizon = 0; // where a contact not yet ended was given up (no_exit)
  long steps = 0;
  long rhs_evals = 0; // every right-hand-side evaluation, Jacobian difference quotients included
  long jacobian_evals = 0; // analytic Jacobians of the implicit methods (each ~ one rhs)
  double wall_seconds = 0;
  std::vector<Event<Real>> events; // in time order; the peak and the exit each at most once
  std::vector<Sample<Real>> samples;
};

} // namespace pldamp::solvers
