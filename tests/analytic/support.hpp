// Shared pieces of the analytic tests: the typed real-type lists and error measures.
#pragma once

#include "pldamp/analytic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

namespace pldamp::testing {

#if PLDAMP_WITH_QUAD
using AllReals = ::testing::Types<double, long double, quad, bin50>;
using FastReals = ::testing::Types<double, long double, quad>;
#else
using AllReals = ::testing::Types<double, long double, bin50>;
using FastReals = ::testing::Types<double, long double>;
#endif

template <SupportedReal Real>
double eps() {
  return static_cast<double>(std::numeric_limits<Real>::epsilon());
}

// |got − want| / |want| in the wider type, as a double for the report.
template <class Got, class Want>
double relative_error(const Got& got, const Want& want) {
  using std::abs;
  const bin50 g(got);
  const bin50 w(want);
  return static_cast<double>(w == 0 ? abs(g) : abs(g - w) / abs(w));
}

// For test reports (std::to_string would print 1e-15 as 0.000000).
inline std::string scientific(double x) {
  std::ostringstream out;
  out << std::scientific << std::setprecision(2) << x;
  return out.str();
}

} // namespace pldamp::testing
