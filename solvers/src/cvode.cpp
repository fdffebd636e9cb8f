// cvode-bdf and cvode-adams: SUNDIALS CVODE (variable order BDF 1-5 / Adams-Moulton 1-12, both
// with Newton iterations on a dense 3x3 system and the analytic Jacobian of contact_ode.hpp).
//
// Events use CVODE's own root finding on g = (force rate, v, exit function), all with direction -1
// (falling): the normal force's peak is its rate's sign crossing 0 downward (only while pending:
// wanted, before the overlap's peak); the peak is v crossing 0 downward; the exit is δ (or the
// force sign) reaching 0. At
// t = 0 the overlap is exactly 0; CVODE never reports a root at t0 (it deactivates a component
// that is 0 there until it moves away), and the rising direction of δ is masked anyway, so the
// exit root is the one at the end; the run stops on it, so it is reported exactly once.
#include "methods.hpp"
#include "sundials.hpp"

#include <cvode/cvode.h>

#include <algorithm>
#include <array>
#include <string>

namespace pldamp::solvers::detail {
namespace {

using namespace sundials;

int event_functions(double /*t*/, N_Vector y, double* g, void* user_data) {
  const Collision& collision = *static_cast<Collision*>(user_data);
  const State state = to_state(y);
  g[0] = collision.event_value(EventKind::force_peak, state);
  g[1] = collision.event_value(EventKind::peak, state);
  g[2] = collision.event_value(EventKind::exit, state);
  return 0;
}

struct CvodeWorkspace {
  Context context = make_context();
  Vector y = make_vector(context.get());
  Vector atol = make_vector(context.get());
  DenseNewton newton{y.get(), context.get()};
  Memory<CVodeFree> memory;
  LastMessage last_message{CVodeGetReturnFlagName};

  explicit CvodeWorkspace(int lmm)
      : memory(check_created(CVodeCreate(lmm, context.get()), "CVodeCreate")) {
    void* cvode = memory.get();
    last_message.check(CVodeInit(cvode, sundials::rhs, 0, y.get()), "CVodeInit");
    last_message.check(CVodeSetErrHandlerFn(cvode, LastMessage::keep, &last_message),
                       "CVodeSetErrHandlerFn");
    // The linear solver interface's flags (CVLS_*) have their own names.
    check(CVodeSetLinearSolver(cvode, newton.solver.get(), newton.matrix.get()),
          "CVodeSetLinearSolver", CVodeGetLinReturnFlagName);
    check(CVodeSetJacFn(cvode, sundials::jacobian), "CVodeSetJacFn", CVodeGetLinReturnFlagName);
    last_message.check(CVodeRootInit(cvode, 3, event_functions), "CVodeRootInit");
    std::array<int, 3> falling{-1, -1, -1};
    last_message.check(CVodeSetRootDirection(cvode, falling.data()), "CVodeSetRootDirection");
    last_message.check(CVodeSetNoInactiveRootWarn(cvode), "CVodeSetNoInactiveRootWarn");
  }
};

CvodeWorkspace& workspace(CvodeMethod method) {
  thread_local CvodeWorkspace bdf(CV_BDF);
  thread_local CvodeWorkspace adams(CV_ADAMS);
  return method == CvodeMethod::bdf ? bdf : adams;
}

} // namespace

Result<double> solve_cvode(CvodeMethod method, const Problem<double>& problem,
                           const Options<double>& options) {
  Collision collision(problem, options);
  CvodeWorkspace& w = workspace(method);
  void* cvode = w.memory.get();
  assign(w.y.get(), collision.initial_state());
  assign(w.atol.get(), collision.absolute_tolerances());
  w.last_message.forget();
  w.last_message.check(CVodeReInit(cvode, 0, w.y.get()), "CVodeReInit");
  w.last_message.check(CVodeSVtolerances(cvode, options.rtol, w.atol.get()), "CVodeSVtolerances");
  w.last_message.check(CVodeSetUserData(cvode, &collision), "CVodeSetUserData");
  w.last_message.check(CVodeSetStopTime(cvode, collision.horizon()), "CVodeSetStopTime");
  // At most this many steps per call, so that the budget (steps, wall time, a stop request) is
  // looked at between calls; CV_TOO_MUCH_WORK then means "call again".
  const long steps_per_call = std::min(options.max_steps, 4096L);
  w.last_message.check(CVodeSetMaxNumSteps(cvode, steps_per_call), "CVodeSetMaxNumSteps");

  auto steps = [&] {
    long n = 0;
    w.last_message.check(CVodeGetNumSteps(cvode, &n), "CVodeGetNumSteps");
    return n;
  };
  // Dense output inside the last step: CVODE's Nordsieck interpolant, of the method's order.
  auto state_at = [&](double t) {
    w.last_message.check(CVodeGetDky(cvode, t, 0, w.y.get()), "CVodeGetDky");
    return to_state(w.y.get());
  };
  collision.sample_through(0, [&](double) { return collision.initial_state(); });
  collision.offer_onset_force();
  // Without samples, CVODE runs to the overlap's peak in one call (CV_NORMAL); with them, and
  // once the exit is pending, one step per call, so that each step's samples come off its
  // interpolant and a settled contact (Collision::settled) is seen.
  for (;;) {
    const int mode = options.sample_times.empty() && collision.pending(EventKind::peak)
                         ? CV_NORMAL
                         : CV_ONE_STEP;
    double t = 0;
    const int flag = CVode(cvode, collision.horizon(), w.y.get(), &t, mode);
    if (const auto spent = collision.out_of_budget(steps(), true)) {
      return collision.finish(*spent, steps());
    }
    if (flag == CV_TOO_MUCH_WORK) {
      continue;
    }
    try {
      w.last_message.check_step(flag, "CVode");
    } catch (const StepFailed& failure) {
      return collision.finish(Outcome::unstable, steps(), failure.what());
    }
    const State y = to_state(w.y.get());
    collision.sample_through(t, state_at);
    if (flag == CV_ROOT_RETURN) {
      std::array<int, 3> found{};
      w.last_message.check(CVodeGetRootInfo(cvode, found.data()), "CVodeGetRootInfo");
      for (const EventKind kind : {EventKind::force_peak, EventKind::peak, EventKind::exit}) {
        if (found[static_cast<std::size_t>(kind)] != 0 && collision.pending(kind) &&
            collision.record(kind, t, y)) {
          return collision.finish(kind == EventKind::peak ? Outcome::peak : Outcome::exited,
                                  steps());
        }
      }
    } else if (flag == CV_TSTOP_RETURN || (mode == CV_NORMAL && flag == CV_SUCCESS) ||
               collision.settled(y)) {
      return collision.finish(Outcome::no_exit, steps());
    }
  }
}

} // namespace pldamp::solvers::detail
