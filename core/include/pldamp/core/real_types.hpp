// The real types pldamp supports, in one list (docs/design.md §8, convention 1).
//
// PLDAMP_FOR_EACH_PRECISION is that list: double, long double, boost::multiprecision::float128
// when PLDAMP_WITH_QUAD is on (the default; it needs GCC's __float128 and -std=gnu++20), and
// cpp_bin_float_50, narrowest first, each with the name the CLI (`--precision`), scenes and
// reports use. Everything else is derived from it: the SupportedReal concept, the `Precisions`
// type list (typed tests iterate it), for_each_precision and with_precision (runtime dispatch by
// name), precision_names() for messages, and the explicit instantiations of the compiled
// templates (`PLDAMP_FOR_EACH_PRECISION(INSTANTIATE)` in each .cpp). Adding a precision is one
// line here (docs/design.md "Adding a precision").
#pragma once

#include <boost/multiprecision/cpp_bin_float.hpp>

#include <concepts>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#if PLDAMP_WITH_QUAD
#include <boost/multiprecision/float128.hpp>
#endif

namespace pldamp {

using bin50 = boost::multiprecision::cpp_bin_float_50;
#if PLDAMP_WITH_QUAD
using quad = boost::multiprecision::float128;
#define PLDAMP_IF_QUAD(...) __VA_ARGS__
#else
#define PLDAMP_IF_QUAD(...)
#endif

// X(type, "name") for every supported precision, narrowest first.
#define PLDAMP_FOR_EACH_PRECISION(X)                                                               \
  X(double, "double")                                                                              \
  X(long double, "long")                                                                           \
  PLDAMP_IF_QUAD(X(::pldamp::quad, "quad"))                                                        \
  X(::pldamp::bin50, "50")

template <class... Reals>
struct RealList {};

namespace detail {

template <class List>
struct DropFirst;
template <class First, class... Rest>
struct DropFirst<RealList<First, Rest...>> {
  using type = RealList<Rest...>;
};

template <class T, class List>
inline constexpr bool in_list = false;
template <class T, class... Reals>
inline constexpr bool in_list<T, RealList<Reals...>> = (std::same_as<T, Reals> || ...);

template <class T>
inline constexpr std::string_view precision_label{};

#define PLDAMP_DETAIL_LIST_ENTRY(type, name) , type
#define PLDAMP_DETAIL_LABEL(type, name)                                                            \
  template <>                                                                                      \
  inline constexpr std::string_view precision_label<type> = name;
PLDAMP_FOR_EACH_PRECISION(PLDAMP_DETAIL_LABEL)
#undef PLDAMP_DETAIL_LABEL

} // namespace detail

// The supported types as a list, narrowest first.
using Precisions =
    detail::DropFirst<RealList<void PLDAMP_FOR_EACH_PRECISION(PLDAMP_DETAIL_LIST_ENTRY)>>::type;
#undef PLDAMP_DETAIL_LIST_ENTRY

template <class T>
concept SupportedReal = detail::in_list<T, Precisions>;

// Name used by the CLI (`--precision`), scenes and reports.
template <SupportedReal Real>
constexpr std::string_view precision_name() {
  return detail::precision_label<Real>;
}

// Significant decimal digits that round-trip the type (36 for float128).
template <SupportedReal Real>
constexpr int round_trip_digits() {
  return std::numeric_limits<Real>::max_digits10;
}

// Calls body.template operator()<Real>() for every supported Real, narrowest first.
template <class Body>
constexpr void for_each_precision(Body&& body) {
  [&]<class... Reals>(RealList<Reals...>) {
    (body.template operator()<Reals>(), ...);
  }(Precisions{});
}

// "double|long|quad|50", for messages and help.
inline std::string precision_names() {
  std::string names;
  for_each_precision([&]<class Real>() {
    names += names.empty() ? "" : "|";
    names += precision_name<Real>();
  });
  return names;
}

// The message for a precision name not in the list.
inline std::string unknown_precision(std::string_view name) {
  const std::string expected =
      ", expected " + precision_names() + " (got " + std::string(name) + ")";
#if !PLDAMP_WITH_QUAD
  if (name == "quad") {
    return "precision quad is not in this build (PLDAMP_WITH_QUAD=OFF)" + expected;
  }
#endif
  return "unknown precision" + expected;
}

// Calls body.template operator()<Real>() for the precision named `name`; throws
// std::invalid_argument(unknown_precision(name)) otherwise.
template <class Body>
void with_precision(std::string_view name, Body&& body) {
  bool found = false;
  for_each_precision([&]<class Real>() {
    if (!found && precision_name<Real>() == name) {
      found = true;
      body.template operator()<Real>();
    }
  });
  if (!found) {
    throw std::invalid_argument(unknown_precision(name));
  }
}

namespace detail {
template <int Digits10, class List>
struct NarrowestWith; // none: no supported type is that precise
template <int Digits10, class First, class... Rest>
struct NarrowestWith<Digits10, RealList<First, Rest...>>
    : std::conditional_t<(std::numeric_limits<First>::digits10 >= Digits10),
                         std::type_identity<First>, NarrowestWith<Digits10, RealList<Rest...>>> {};
} // namespace detail

// The narrowest supported type with at least Digits10 significant decimal digits (for a truth to
// 30 digits: float128, or cpp_bin_float_50 in a build without it).
template <int Digits10>
using NarrowestWithDigits10 = typename detail::NarrowestWith<Digits10, Precisions>::type;

// A set of precisions as bits, bit i for the i-th of Precisions.
using PrecisionSet = unsigned;

template <SupportedReal Real>
constexpr PrecisionSet precision_bit() {
  PrecisionSet bit = 0, next = 1;
  for_each_precision([&]<class Other>() {
    bit |= std::same_as<Real, Other> ? next : 0;
    next <<= 1;
  });
  return bit;
}

inline constexpr PrecisionSet every_precision = [] {
  PrecisionSet all = 0;
  for_each_precision([&]<class Real>() { all |= precision_bit<Real>(); });
  return all;
}();

// The names in `set`, "double|quad".
inline std::string precision_names(PrecisionSet set) {
  std::string names;
  for_each_precision([&]<class Real>() {
    if (set & precision_bit<Real>()) {
      names += names.empty() ? "" : "|";
      names += precision_name<Real>();
    }
  });
  return names;
}

// The bit of the precision named `name`; 0 for an unknown name.
inline PrecisionSet precision_bit(std::string_view name) {
  PrecisionSet bit = 0;
  for_each_precision(
      [&]<class Real>() { bit |= precision_name<Real>() == name ? precision_bit<Real>() : 0; });
  return bit;
}

} // namespace pldamp
