// The analytic layer's explicit instantiations (pldamp/analytic/instances.hpp), every precision.
#include "pldamp/analytic/instances.hpp"

namespace pldamp::analytic {
#define PLDAMP_ANALYTIC_DEFINE(Real, name) PLDAMP_ANALYTIC_INSTANCES(, Real)
PLDAMP_FOR_EACH_PRECISION(PLDAMP_ANALYTIC_DEFINE)
#undef PLDAMP_ANALYTIC_DEFINE
} // namespace pldamp::analytic
