// Boost.Odeint (odeint-rkf78, odeint-bs): the tests of every error-controlled solver.
#include "every_solver.hpp"

namespace pldamp::solvers::testing {
namespace {

INSTANTIATE_TEST_SUITE_P(Odeint, EverySolver, ::testing::ValuesIn(family("odeint-")), test_name);

} // namespace
} // namespace pldamp::solvers::testing
