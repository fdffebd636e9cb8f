// SUNDIALS objects in move-only RAII owners, and one helper that turns return codes into
// exceptions (docs/design.md §8, convention 7). A solver keeps one workspace per thread and
// re-initialises it per collision: creating a context, vectors and a linear solver costs more than
// a whole collision at moderate tolerance.
#pragma once

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cassert>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "collision.hpp"

namespace pldamp::solvers::detail::sundials {

// A module's XGetReturnFlagName (CVodeGetReturnFlagName, ARKStepGetLinReturnFlagName, ...): the
// name of a return flag, in a string the caller frees; "NONE" for a flag the module does not know.
using FlagNamer = char* (*)(long int);

// "CV_TOO_MUCH_WORK": the flag's name by `namer`, or "code -4" where it has none (namer null: a
// call of no module, SUNContext_Create).
inline std::string flag_name(int flag, FlagNamer namer) {
  const std::unique_ptr<char, decltype(&std::free)> name(namer ? namer(flag) : nullptr, &std::free);
  if (name == nullptr || std::string_view(name.get()) == "NONE") {
    return "code " + std::to_string(flag);
  }
  return name.get();
}

// Throws unless a SUNDIALS call succeeded (negative flags are failures), naming the flag.
inline void check(int flag, const char* call, FlagNamer namer) {
  if (flag < 0) {
    throw std::runtime_error(std::string(call) + " failed with " + flag_name(flag, namer));
  }
}

template <class Pointer>
Pointer check_created(Pointer object, const char* call) {
  if (object == nullptr) {
    throw std::runtime_error(std::string(call) + " returned null");
  }
  return object;
}

struct ContextFree {
  void operator()(SUNContext context) const noexcept { SUNContext_Free(&context); }
};
struct VectorFree {
  void operator()(N_Vector vector) const noexcept { N_VDestroy(vector); }
};
struct MatrixFree {
  void operator()(SUNMatrix matrix) const noexcept { SUNMatDestroy(matrix); }
};
struct LinearSolverFree {
  void operator()(SUNLinearSolver solver) const noexcept { SUNLinSolFree(solver); }
};

using Context = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextFree>;
using Vector = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorFree>;
using Matrix = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixFree>;
using LinearSolver = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverFree>;

// An integrator's memory block (void* in SUNDIALS), freed by its own Free(void**).
template <void (*free_memory)(void**)>
struct MemoryFree {
  void operator()(void* memory) const noexcept { free_memory(&memory); }
};
template <void (*free_memory)(void**)>
using Memory = std::unique_ptr<void, MemoryFree<free_memory>>;

inline Context make_context() {
  SUNContext context = nullptr;
  check(SUNContext_Create(nullptr, &context), "SUNContext_Create", nullptr);
  return Context(context);
}

// A zeroed vector of the three states.
inline Vector make_vector(SUNContext context) {
  Vector vector(check_created(N_VNew_Serial(3, context), "N_VNew_Serial"));
  N_VConst(0, vector.get());
  return vector;
}

// Every vector here is make_vector's: serial, of the three states.
inline State to_state(N_Vector y) {
  assert(N_VGetLength(y) == 3);
  const double* data = N_VGetArrayPointer(y);
  return {data[0], data[1], data[2]};
}

inline void assign(N_Vector y, const State& state) {
  assert(N_VGetLength(y) == 3);
  double* data = N_VGetArrayPointer(y);
  for (int i = 0; i < 3; ++i) {
    data[i] = state[static_cast<std::size_t>(i)];
  }
}

// The right-hand side as SUNDIALS calls it; user data is the Collision.
inline int rhs(double /*t*/, N_Vector y, N_Vector ydot, void* user_data) {
  assign(ydot, static_cast<Collision*>(user_data)->rhs(to_state(y)));
  return 0;
}

// The Jacobian of contact_ode.hpp (floored at δ = 0 where it is singular), into a dense matrix.
inline int jacobian(double /*t*/, N_Vector y, N_Vector /*fy*/, SUNMatrix J, void* user_data,
                    N_Vector, N_Vector, N_Vector) {
  const auto jac = static_cast<Collision*>(user_data)->jacobian(to_state(y));
  for (sunindextype i = 0; i < 3; ++i) {
    for (sunindextype j = 0; j < 3; ++j) {
      SM_ELEMENT_D(J, i, j) = jac[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    }
  }
  return 0;
}

// SUNDIALS reports through a handler; keep the last message for the exception instead of letting
// the library print to stderr. A failure names its flag by the integrator's namer:
// "CVode failed with CV_CONV_FAILURE: CVode: At t = ..., the corrector convergence failed ...".
struct LastMessage {
  FlagNamer namer;
  std::string text;

  explicit LastMessage(FlagNamer integrator_namer) : namer(integrator_namer) {}

  // A workspace serves collision after collision: each forgets the one before's message, which
  // would otherwise be attached to a later, unrelated failure.
  void forget() { text.clear(); }

  static void keep(int /*code*/, const char* /*module*/, const char* function, char* message,
                   void* self) {
    static_cast<LastMessage*>(self)->text = std::string(function) + ": " + message;
  }
  std::string failure(int flag, const char* call) const {
    return std::string(call) + " failed with " + flag_name(flag, namer) +
           (text.empty() ? "" : ": " + text);
  }
  void check(int flag, const char* call) const {
    if (flag < 0) {
      throw std::runtime_error(failure(flag, call));
    }
  }
  // A failure of the integration itself (not of its set-up): StepFailed (collision.hpp).
  void check_step(int flag, const char* call) const {
    if (flag < 0) {
      throw StepFailed(failure(flag, call));
    }
  }
};

// A dense 3×3 Newton solver: the matrix and its LU solver.
struct DenseNewton {
  Matrix matrix;
  LinearSolver solver;
  DenseNewton(N_Vector y, SUNContext context)
      : matrix(check_created(SUNDenseMatrix(3, 3, context), "SUNDenseMatrix")),
        solver(check_created(SUNLinSol_Dense(y, matrix.get(), context), "SUNLinSol_Dense")) {}
};

} // namespace pldamp::solvers::detail::sundials
