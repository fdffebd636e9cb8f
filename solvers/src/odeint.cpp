// odeint-rkf78 and odeint-bs: Boost.Odeint's controlled Runge–Kutta–Fehlberg 7(8) and its
// Bulirsch–Stoer extrapolation method with dense output (interpolation error controlled too).
//
// Odeint has no events: run_one_step_method brackets them by the sign of their functions at the
// ends of each step and locates them with Boost.Math's TOMS 748 on the step's dense output. For
// Bulirsch–Stoer that is its own interpolant; for RKF78, which has none, it is the RKF78 step from
// the step's start repeated with the shorter h (the method's own full-order value, 12 evaluations
// as the start's derivative is kept).
//
// Odeint takes one absolute tolerance for all states. The states are therefore integrated scaled,
// u_i = y_i / s_i with s_i = atol_i / atol, which gives each state its own absolute tolerance
// atol_i (collision.hpp; all equal, s = 1, for a literal atol, as ode45 takes it). The error norm
// is Odeint's max_i |err_i| / (atol + rtol |u_i|) (factor_x = 1, factor_dxdt = 0), as ode45's.
#include "collision.hpp"
#include "methods.hpp"

// Odeint's controlled stepper copies a default-constructed RKF78 whose std::array scratch states
// are not yet written; GCC 12 flags the copy (a false positive inside Boost 1.74).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <boost/numeric/odeint.hpp>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>

namespace pldamp::solvers::detail {
namespace {

namespace odeint = boost::numeric::odeint;

// The contact ODE in scaled states u = y / scale.
struct ScaledSystem {
  Collision* collision;
  State scale;

  State physical(const State& u) const {
    return {u[0] * scale[0], u[1] * scale[1], u[2] * scale[2]};
  }
  State initial() const {
    const State y0 = collision->initial_state();
    return {y0[0] / scale[0], y0[1] / scale[1], y0[2] / scale[2]};
  }
  void operator()(const State& u, State& dudt, double /*t*/) const {
    const State f = collision->rhs(physical(u));
    for (std::size_t i = 0; i < 3; ++i) {
      dudt[i] = f[i] / scale[i];
    }
  }
};

double absolute_tolerance(const Collision& collision) {
  return collision.options().atol.value_or(collision.options().rtol);
}

// Scales that turn Odeint's one atol into the per-state ones: u_i = y_i / (atol_i / atol).
ScaledSystem scaled_system(Collision& collision) {
  const State atol = collision.absolute_tolerances();
  const double common = absolute_tolerance(collision);
  return {&collision, {atol[0] / common, atol[1] / common, atol[2] / common}};
}

// A first trial step. RKF78's error estimate cannot see the branch point at contact (see
// collision.hpp), so it would accept any first step: start small and let it grow.
double first_step(const Collision& collision) {
  return collision.ode().time_scale() * 1e-6;
}

class Fehlberg78 final : public OneStepMethod {
public:
  explicit Fehlberg78(Collision& collision)
      : system_(scaled_system(collision)),
        controlled_(Controlled::error_checker_type(absolute_tolerance(collision),
                                                   collision.options().rtol, 1, 0)),
        dt_(first_step(collision)), u_(system_.initial()) {
    system_(u_, dudt_, t_);
  }

  double step(double t_stop, State& y) override {
    u_start_ = u_;
    dudt_start_ = dudt_;
    t_start_ = t_;
    // A step of a coasting stretch (p = 50: no force left) grows towards the horizon and its
    // stages overflow |δ|^p far beyond the exit; NaN errors compare false with the tolerance, so
    // odeint accepts such a step. Retried from its start with half the size, up to 64 times.
    for (int halvings = 0;;) {
      dt_ = std::min(dt_, t_stop - t_);
      const double tried = dt_;
      if (controlled_.try_step(system_, u_, dudt_start_, t_, dt_) == odeint::success) {
        if (!Collision::diverged(system_.physical(u_)) || ++halvings > 64) {
          break;
        }
        u_ = u_start_;
        t_ = t_start_;
        dt_ = tried / 2;
      }
    }
    ++steps_;
    system_(u_, dudt_, t_); // the next step's first stage, also the start of its dense output
    y = system_.physical(u_);
    return t_;
  }

  State state_at(double t) override {
    State u{};
    controlled_.stepper().do_step(system_, u_start_, dudt_start_, t_start_, u, t - t_start_);
    return system_.physical(u);
  }

  long steps() const override { return steps_; }
  int graded_exit_order() const override { return 8; }
  void limit_next_step(double h_max) override { dt_ = std::min(dt_, h_max); }

private:
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<State>>;
  ScaledSystem system_;
  Controlled controlled_;
  double dt_;
  double t_ = 0, t_start_ = 0;
  State u_{}, dudt_{}, u_start_{}, dudt_start_{};
  long steps_ = 0;
};

class BulirschStoer final : public OneStepMethod {
public:
  explicit BulirschStoer(Collision& collision)
      : system_(scaled_system(collision)),
        stepper_(absolute_tolerance(collision), collision.options().rtol, 1, 0, 0, true) {
    stepper_.initialize(system_.initial(), 0.0, first_step(collision));
  }

  // Odeint's dense-output steppers choose their own step; the driver treats a step ending past
  // t_stop as reaching it.
  double step(double /*t_stop*/, State& y) override {
    stepper_.do_step(system_);
    ++steps_;
    y = system_.physical(stepper_.current_state());
    return stepper_.current_time();
  }

  State state_at(double t) override {
    State u{};
    stepper_.calc_state(t, u);
    return system_.physical(u);
  }

  long steps() const override { return steps_; }

private:
  ScaledSystem system_;
  odeint::bulirsch_stoer_dense_out<State> stepper_;
  long steps_ = 0;
};

} // namespace

Result<double> solve_odeint(OdeintMethod method, const Problem<double>& problem,
                            const Options<double>& options) {
  Collision collision(problem, options);
  if (method == OdeintMethod::fehlberg_78) {
    Fehlberg78 stepper(collision);
    return run_one_step_method(stepper, collision);
  }
  BulirschStoer stepper(collision);
  return run_one_step_method(stepper, collision);
}

} // namespace pldamp::solvers::detail
