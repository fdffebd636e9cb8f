// SUNDIALS CVODE (cvode-bdf, cvode-adams): the tests of every error-controlled solver, and how a
// SUNDIALS return flag is reported (solvers/src/sundials.hpp).
#include "every_solver.hpp"
#include "sundials.hpp"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>

#include <stdexcept>
#include <string>

namespace pldamp::solvers::testing {
namespace {

INSTANTIATE_TEST_SUITE_P(Cvode, EverySolver, ::testing::ValuesIn(family("cvode-")), test_name);

// A flag is named by its module's XGetReturnFlagName, the linear solver interface's flags by
// theirs; a number only where the module has no name for it.
TEST(SundialsFlags, AreNamedByTheirModule) {
  using namespace detail::sundials;
  using pldamp::testing::message_of;
  EXPECT_EQ(flag_name(CV_TOO_MUCH_WORK, CVodeGetReturnFlagName), "CV_TOO_MUCH_WORK");
  EXPECT_EQ(flag_name(CV_ERR_FAILURE, CVodeGetReturnFlagName), "CV_ERR_FAILURE");
  EXPECT_EQ(flag_name(CVLS_MEM_NULL, CVodeGetLinReturnFlagName), "CVLS_MEM_NULL");
  EXPECT_EQ(flag_name(ARK_TOO_MUCH_WORK, ERKStepGetReturnFlagName), "ARK_TOO_MUCH_WORK");
  EXPECT_EQ(flag_name(ARK_CONV_FAILURE, ARKStepGetReturnFlagName), "ARK_CONV_FAILURE");
  EXPECT_EQ(flag_name(ARKLS_ILL_INPUT, ARKStepGetLinReturnFlagName), "ARKLS_ILL_INPUT");
  EXPECT_EQ(flag_name(-12345, CVodeGetReturnFlagName), "code -12345");
  EXPECT_EQ(flag_name(-1, nullptr), "code -1"); // SUNContext_Create's: no module to name it
  EXPECT_EQ(message_of<std::runtime_error>(
                [] { check(CV_MEM_NULL, "CVodeGetNumSteps", CVodeGetReturnFlagName); }),
            "CVodeGetNumSteps failed with CV_MEM_NULL");
  EXPECT_EQ(
      message_of<std::runtime_error>([] { check(CV_WARNING, "CVode", CVodeGetReturnFlagName); }),
      "no exception"); // positive flags are not failures
  LastMessage last(CVodeGetReturnFlagName);
  EXPECT_EQ(message_of<std::runtime_error>([&] { last.check(CV_ILL_INPUT, "CVodeSVtolerances"); }),
            "CVodeSVtolerances failed with CV_ILL_INPUT");
  LastMessage::keep(CV_TOO_MUCH_WORK, "CVODE", "CVode", const_cast<char*>("mxstep steps taken"),
                    &last);
  EXPECT_EQ(message_of<std::runtime_error>([&] { last.check_step(CV_TOO_MUCH_WORK, "CVode"); }),
            "CVode failed with CV_TOO_MUCH_WORK: CVode: mxstep steps taken");
}

} // namespace
} // namespace pldamp::solvers::testing
