// SUNDIALS CVODE (cvode-bdf, cvode-adams): the tests of every error-controlled solver.
#include "every_solver.hpp"

namespace pldamp::solvers::testing {
namespace {

INSTANTIATE_TEST_SUITE_P(Cvode, EverySolver, ::testing::ValuesIn(family("cvode-")), test_name);

} // namespace
} // namespace pldamp::solvers::testing
