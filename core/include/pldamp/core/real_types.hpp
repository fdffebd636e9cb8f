// The real types pldamp supports, in one place (convention 1 of DESIGN.md).
//
// double and long double always; boost::multiprecision::float128 when PLDAMP_WITH_QUAD is on
// (the default; it needs GCC's __float128 and -std=gnu++20), and cpp_bin_float_50 always.
// Every analytic template is written against `SupportedReal` and tested on each of them.
#pragma once

#include <boost/multiprecision/cpp_bin_float.hpp>

#include <concepts>
#include <limits>
#include <string_view>
#include <type_traits>

#if PLDAMP_WITH_QUAD
#include <boost/multiprecision/float128.hpp>
#endif

namespace pldamp {

using bin50 = boost::multiprecision::cpp_bin_float_50;
#if PLDAMP_WITH_QUAD
using quad = boost::multiprecision::float128;
#endif

template <class T>
concept SupportedReal = std::same_as<T, double> || std::same_as<T, long double> ||
#if PLDAMP_WITH_QUAD
    std::same_as<T, quad> ||
#endif
    std::same_as<T, bin50>;

// Name used by the CLI (`--precision`) and in reports.
template <SupportedReal Real>
constexpr std::string_view precision_name() {
  if constexpr (std::same_as<Real, double>) {
    return "double";
  } else if constexpr (std::same_as<Real, long double>) {
    return "long";
  } else if constexpr (std::same_as<Real, bin50>) {
    return "50";
  } else {
    return "quad";
  }
}

// Significant decimal digits that round-trip the type (36 for float128).
template <SupportedReal Real>
constexpr int round_trip_digits() {
  return std::numeric_limits<Real>::max_digits10;
}

} // namespace pldamp
