// Shared pieces of the tests: the typed real-type lists (from core's one list) and error measures.
#pragma once

#include "pldamp/analytic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

namespace pldamp::testing {

namespace detail {
template <class... Reals>
::testing::Types<Reals...> gtest_types(RealList<Reals...>);

// The list without Slow.
template <class Slow, class... Kept>
RealList<Kept...> without(RealList<>, RealList<Kept...>) {
  return {};
}
template <class Slow, class First, class... Rest, class... Kept>
auto without(RealList<First, Rest...>, RealList<Kept...>) {
  if constexpr (std::is_same_v<First, Slow>) {
    return without<Slow>(RealList<Rest...>{}, RealList<Kept...>{});
  } else {
    return without<Slow>(RealList<Rest...>{}, RealList<Kept..., First>{});
  }
}
} // namespace detail

// Every supported precision (core's list), and all but 50 digits (whose loops are slow).
using AllReals = decltype(detail::gtest_types(Precisions{}));
using FastReals = decltype(detail::gtest_types(detail::without<bin50>(Precisions{}, RealList<>{})));

// The reference one step above double and long double: float128, or 50 digits without it.
using Exact = NarrowestWithDigits10<30>;

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
