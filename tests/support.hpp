// Shared pieces of the tests: the typed real-type lists (from core's one list) and error measures.
#pragma once

#include "pldamp/analytic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
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

// The largest relative error over many checks, and which one it was.
struct Worst {
  double error = 0;
  std::string where;
  template <class Got, class Want>
  void check(const std::optional<Got>& got, const std::optional<Want>& want, const char* name,
             const std::string& label) {
    ASSERT_TRUE(got.has_value()) << name << " missing at " << label;
    ASSERT_TRUE(want.has_value()) << name << " at " << label;
    const double err = relative_error(*got, *want);
    if (!(err <= error)) { // NaN too
      error = std::isnan(err) ? INFINITY : err;
      where = std::string(name) + " at " + label;
    }
  }
  // e, δ_max, t_peak, τ, the energy split and the normal force's peak of a solver's result
  // against another result or the closed forms (anything with those eight members).
  template <class Got, class Want>
  void check_observables(const Got& got, const Want& want, const std::string& label) {
    check(got.e, want.e, "e", label);
    check(got.delta_max, want.delta_max, "delta_max", label);
    check(got.t_peak, want.t_peak, "t_peak", label);
    check(got.tau, want.tau, "tau", label);
    check(got.energy_load, want.energy_load, "energy_load", label);
    check(got.energy_unload, want.energy_unload, "energy_unload", label);
    check(got.normal_force_max, want.normal_force_max, "normal_force_max", label);
    check(got.t_normal_force_max, want.t_normal_force_max, "t_normal_force_max", label);
  }
};

// The message of the Exception a call throws, or "no exception" (any other exception propagates
// and fails the test).
template <class Exception = std::invalid_argument, class Call>
std::string message_of(Call&& call) {
  try {
    call();
  } catch (const Exception& error) {
    return error.what();
  }
  return "no exception";
}

// For test reports (std::to_string would print 1e-15 as 0.000000).
inline std::string scientific(double x) {
  std::ostringstream out;
  out << std::scientific << std::setprecision(2) << x;
  return out.str();
}

} // namespace pldamp::testing
