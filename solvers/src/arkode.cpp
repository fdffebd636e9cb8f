// arkode-dp5, arkode-erk8 (ERKStep) and arkode-dirk (ARKStep, implicit), stepped one step at a
// time by run_one_step_method, which finds the events on each step.
//
// - arkode-dp5: Dormand–Prince 5(4), the method of MATLAB's ode45 that the seed used.
// - arkode-erk8: Fehlberg 8(7), 13 stages. Debian's SUNDIALS 6.4.1 treats any table whose last
//   node is c = 1 as first-same-as-last and reuses that stage as the next step's first, which is
//   wrong for this table (its last stage is not at y_{n+1}): measured here, Fehlberg then runs at
//   order ~7 instead of 8, and ARKODE_VERNER_8_5_6 at 3 instead of 6. We pass the table with one
//   stage appended that *is* FSAL: node 1, A-row = b, weight 0. The step is unchanged, the reused
//   derivative is now f(t_{n+1}, y_{n+1}), and the fixed-step order test (tests/solvers) guards it.
// - arkode-dirk: Kværnø's ESDIRK 7(4)5, L-stable, order 5, Newton on a dense 3x3 system with the
//   floored analytic Jacobian (contact_ode.hpp), for heavy damping. (The order-4 SDIRK 5(3)4 needed
//   ~1000 steps at rtol 1e-10 and missed 1e-7 in e = 0.1; this one takes ~300 and meets it.)
//
// Where is the solution inside a step? ARKODE's Hermite interpolant has degree min(5, order − 1),
// below the accuracy of an 8th-order step; an event located on it would limit arkode-erk8. So the
// explicit methods evaluate the solution at t by repeating the step from the step's start with
// h = t − t_start (the method's own full-order value); the DIRK uses the interpolant, of degree 4
// for its order 5.
#include "methods.hpp"
#include "sundials.hpp"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_butcher_dirk.h>
#include <arkode/arkode_butcher_erk.h>
#include <arkode/arkode_erkstep.h>

#include <vector>

namespace pldamp::solvers::detail {
namespace {

using namespace sundials;

struct TableFree {
  void operator()(ARKodeButcherTable table) const noexcept { ARKodeButcherTable_Free(table); }
};
using ButcherTable = std::unique_ptr<ARKodeButcherTableMem, TableFree>;

// The table with a first-same-as-last stage appended (see the top of this file).
ButcherTable with_fsal_stage(ARKodeButcherTable table) {
  const int s = table->stages;
  std::vector<double> c(s + 1), A((s + 1) * (s + 1), 0.0), b(s + 1, 0.0), d(s + 1, 0.0);
  for (int i = 0; i < s; ++i) {
    c[i] = table->c[i];
    b[i] = table->b[i];
    d[i] = table->d[i];
    for (int j = 0; j < s; ++j) {
      A[i * (s + 1) + j] = table->A[i][j];
    }
    A[s * (s + 1) + i] = table->b[i];
  }
  c[s] = 1;
  return ButcherTable(check_created(
      ARKodeButcherTable_Create(s + 1, table->q, table->p, c.data(), A.data(), b.data(), d.data()),
      "ARKodeButcherTable_Create"));
}

ButcherTable explicit_table(ArkodeMethod method) {
  if (method == ArkodeMethod::dormand_prince_5) {
    return ButcherTable(check_created(ARKodeButcherTable_LoadERK(ARKODE_DORMAND_PRINCE_7_4_5),
                                      "ARKodeButcherTable_LoadERK"));
  }
  const ButcherTable fehlberg(check_created(ARKodeButcherTable_LoadERK(ARKODE_FEHLBERG_13_7_8),
                                            "ARKodeButcherTable_LoadERK"));
  return with_fsal_stage(fehlberg.get());
}

// Stages up to the last one with a nonzero weight: an appended FSAL stage (weight 0) only serves
// the next step and is not evaluated when a step is repeated.
std::size_t weighted_stages(ARKodeButcherTable table) {
  std::size_t n = static_cast<std::size_t>(table->stages);
  while (n > 1 && table->b[n - 1] == 0) {
    --n;
  }
  return n;
}

// Settings shared by both steppers, given their Set* functions (ERKStep and ARKStep mirror each
// other's API).
template <class Api>
void configure(void* memory, const LastMessage& last, Collision& collision, N_Vector atol) {
  const Options<double>& options = collision.options();
  last.check(Api::tolerances(memory, options.rtol, atol), "SVtolerances");
  last.check(Api::user_data(memory, &collision), "SetUserData");
  last.check(Api::stop_time(memory, collision.horizon()), "SetStopTime");
  last.check(Api::max_steps(memory, options.max_steps), "SetMaxNumSteps");
  last.check(Api::fixed_step(memory, options.fixed_step.value_or(0.0)), "SetFixedStep");
  // SetFixedStep leaves its h as the next initial step; 0 asks for the estimate again, so that a
  // collision's result never depends on the one before it.
  if (!options.fixed_step) {
    last.check(Api::initial_step(memory, 0.0), "SetInitStep");
  }
}

struct ErkApi {
  static constexpr auto tolerances = ERKStepSVtolerances;
  static constexpr auto user_data = ERKStepSetUserData;
  static constexpr auto stop_time = ERKStepSetStopTime;
  static constexpr auto max_steps = ERKStepSetMaxNumSteps;
  static constexpr auto fixed_step = ERKStepSetFixedStep;
  static constexpr auto initial_step = ERKStepSetInitStep;
};
struct ArkApi {
  static constexpr auto tolerances = ARKStepSVtolerances;
  static constexpr auto user_data = ARKStepSetUserData;
  static constexpr auto stop_time = ARKStepSetStopTime;
  static constexpr auto max_steps = ARKStepSetMaxNumSteps;
  static constexpr auto fixed_step = ARKStepSetFixedStep;
  static constexpr auto initial_step = ARKStepSetInitStep;
};

// One thread-local ERKStep per table, re-initialised per collision.
class ExplicitStepper final : public OneStepMethod {
public:
  explicit ExplicitStepper(ArkodeMethod method)
      : table_(explicit_table(method)),
        memory_(check_created(ERKStepCreate(sundials::rhs, 0, y_.get(), context_.get()),
                              "ERKStepCreate")),
        stages_(weighted_stages(table_.get())), fehlberg_(method == ArkodeMethod::fehlberg_8) {
    last_.check(ERKStepSetErrHandlerFn(memory_.get(), LastMessage::keep, &last_),
                "ERKStepSetErrHandlerFn");
    last_.check(ERKStepSetTable(memory_.get(), table_.get()), "ERKStepSetTable");
  }

  void start(Collision& collision) {
    collision_ = &collision;
    t_ = 0;
    y_now_ = collision.initial_state();
    assign(y_.get(), y_now_);
    assign(atol_.get(), collision.absolute_tolerances());
    last_.forget();
    last_.check(ERKStepReInit(memory_.get(), sundials::rhs, 0, y_.get()), "ERKStepReInit");
    configure<ErkApi>(memory_.get(), last_, collision, atol_.get());
    last_.check(ERKStepSetMaxStep(memory_.get(), 0), "ERKStepSetMaxStep"); // no limit
  }

  double step(double t_stop, State& y) override {
    t_start_ = t_;
    y_start_ = y_now_;
    const int flag = ERKStepEvolve(memory_.get(), t_stop, y_.get(), &t_, ARK_ONE_STEP);
    last_.check_step(flag, "ERKStepEvolve");
    y = y_now_ = to_state(y_.get());
    return t_;
  }

  // The step from the last step's start, repeated with h = t − t_start.
  State state_at(double t) override {
    const double h = t - t_start_;
    for (std::size_t i = 0; i < stages_.size(); ++i) {
      State y = y_start_;
      for (std::size_t j = 0; j < i; ++j) {
        const double a = table_->A[i][j];
        for (std::size_t n = 0; n < 3; ++n) {
          y[n] += h * a * stages_[j][n];
        }
      }
      stages_[i] = collision_->rhs(y);
    }
    State y = y_start_;
    for (std::size_t i = 0; i < stages_.size(); ++i) {
      for (std::size_t n = 0; n < 3; ++n) {
        y[n] += h * table_->b[i] * stages_[i][n];
      }
    }
    return y;
  }

  long steps() const override {
    long n = 0;
    last_.check(ERKStepGetNumSteps(memory_.get(), &n), "ERKStepGetNumSteps");
    return n;
  }

  int graded_exit_order() const override { return fehlberg_ ? table_->q : 0; }
  void limit_next_step(double h_max) override {
    last_.check(ERKStepSetMaxStep(memory_.get(), h_max), "ERKStepSetMaxStep");
  }

private:
  Context context_ = make_context();
  Vector y_ = make_vector(context_.get());
  Vector atol_ = make_vector(context_.get());
  ButcherTable table_;
  Memory<ERKStepFree> memory_;
  LastMessage last_{ERKStepGetReturnFlagName};
  Collision* collision_ = nullptr;
  std::vector<State> stages_;
  bool fehlberg_;
  double t_ = 0, t_start_ = 0;
  State y_now_{}, y_start_{};
};

class DirkStepper final : public OneStepMethod {
public:
  DirkStepper()
      : memory_(check_created(ARKStepCreate(nullptr, sundials::rhs, 0, y_.get(), context_.get()),
                              "ARKStepCreate")) {
    void* ark = memory_.get();
    last_.check(ARKStepSetErrHandlerFn(ark, LastMessage::keep, &last_), "ARKStepSetErrHandlerFn");
    last_.check(ARKStepSetTableNum(ark, ARKODE_KVAERNO_7_4_5, ARKODE_ERK_NONE),
                "ARKStepSetTableNum");
    // The linear solver interface's flags (ARKLS_*) have their own names.
    check(ARKStepSetLinearSolver(ark, newton_.solver.get(), newton_.matrix.get()),
          "ARKStepSetLinearSolver", ARKStepGetLinReturnFlagName);
    check(ARKStepSetJacFn(ark, sundials::jacobian), "ARKStepSetJacFn", ARKStepGetLinReturnFlagName);
  }

  void start(Collision& collision) {
    assign(y_.get(), collision.initial_state());
    assign(atol_.get(), collision.absolute_tolerances());
    last_.forget();
    last_.check(ARKStepReInit(memory_.get(), nullptr, sundials::rhs, 0, y_.get()), "ARKStepReInit");
    configure<ArkApi>(memory_.get(), last_, collision, atol_.get());
    // A fixed step cannot be cut when Newton stalls: give it more iterations (default 3) and a
    // fresh Jacobian every step instead.
    const bool fixed = collision.options().fixed_step.has_value();
    last_.check(ARKStepSetMaxNonlinIters(memory_.get(), fixed ? 20 : 3), "SetMaxNonlinIters");
    last_.check(ARKStepSetLSetupFrequency(memory_.get(), fixed ? 1 : 0), "SetLSetupFrequency");
    last_.check(ARKStepSetNonlinRDiv(memory_.get(), fixed ? 1e6 : 0), "SetNonlinRDiv");
    // Newton starts from the last step's interpolant extrapolated (not from y_n): 12% fewer rhs
    // and a quarter of the Jacobians at rtol 1e-10.
    last_.check(ARKStepSetPredictorMethod(memory_.get(), 1), "SetPredictorMethod");
  }

  double step(double t_stop, State& y) override {
    double t = 0;
    last_.check_step(ARKStepEvolve(memory_.get(), t_stop, y_.get(), &t, ARK_ONE_STEP),
                     "ARKStepEvolve");
    y = to_state(y_.get());
    return t;
  }

  State state_at(double t) override {
    last_.check(ARKStepGetDky(memory_.get(), t, 0, dense_.get()), "ARKStepGetDky");
    return to_state(dense_.get());
  }

  long steps() const override {
    long n = 0;
    last_.check(ARKStepGetNumSteps(memory_.get(), &n), "ARKStepGetNumSteps");
    return n;
  }

private:
  Context context_ = make_context();
  Vector y_ = make_vector(context_.get());
  Vector atol_ = make_vector(context_.get());
  Vector dense_ = make_vector(context_.get());
  DenseNewton newton_{y_.get(), context_.get()};
  Memory<ARKStepFree> memory_;
  LastMessage last_{ARKStepGetReturnFlagName};
};

template <class Stepper>
Result<double> run(Stepper& stepper, Collision& collision) {
  stepper.start(collision);
  return run_one_step_method(stepper, collision);
}

} // namespace

Result<double> solve_arkode(ArkodeMethod method, const Problem<double>& problem,
                            const Options<double>& options) {
  Collision collision(problem, options);
  switch (method) {
  case ArkodeMethod::dormand_prince_5: {
    thread_local ExplicitStepper stepper(method);
    return run(stepper, collision);
  }
  case ArkodeMethod::fehlberg_8: {
    thread_local ExplicitStepper stepper(method);
    return run(stepper, collision);
  }
  case ArkodeMethod::esdirk_5:
    break;
  }
  thread_local DirkStepper stepper;
  return run(stepper, collision);
}

} // namespace pldamp::solvers::detail
