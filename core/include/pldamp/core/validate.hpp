// Validation at the API boundary (docs/design.md §8, convention 4): every public entry point checks
// its arguments and throws std::invalid_argument whose message names the parameter and prints the
// offending value at full precision, e.g. "p must be >= 1 (got 0.5)". The CLI prints that message
// after "error: " and exits 2.
#pragma once

#include "pldamp/core/real_types.hpp"

#include <cassert>
#include <charconv>
#include <cmath>
#include <concepts>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace pldamp {

template <SupportedReal Real>
std::string to_string_full(const Real& value) {
  using std::isnan;
  if (isnan(value)) {
    return "nan";
  }
  if constexpr (std::is_floating_point_v<Real>) { // shortest round trip: 0.9, not
                                                  // 0.90000000000000002
    char buffer[64]; // a long double's shortest round trip takes at most 29
    const std::to_chars_result written = std::to_chars(buffer, buffer + sizeof buffer, value);
    assert(written.ec == std::errc{});
    return std::string(buffer, written.ptr);
  } else {
    std::ostringstream out;
    out << std::setprecision(round_trip_digits<Real>()) << value;
    return out.str();
  }
}

// Throws "<what> (got <value>)" unless `ok`.
template <SupportedReal Real>
void require(bool ok, const std::string& what, const Real& value) {
  if (!ok) {
    throw std::invalid_argument(what + " (got " + to_string_full(value) + ")");
  }
}

// A literal message: no std::string is made unless it is thrown (a fixed-step contact of 50 steps
// spent a fifth of its time making the messages of the bounds its problem and options keep).
template <SupportedReal Real>
void require(bool ok, const char* what, const Real& value) {
  if (!ok) {
    require(false, std::string(what), value);
  }
}

// The same with the message built only when it is thrown: a solve validates its problem each
// time, and formatting bounds it never breaks cost a tenth of a double taylor collision.
template <SupportedReal Real, std::invocable Message>
void require(bool ok, Message&& what, const Real& value) {
  if (!ok) {
    require(false, std::string(what()), value);
  }
}

template <SupportedReal Real>
void require_finite(const std::string& name, const Real& value) {
  using std::isfinite;
  require(
      static_cast<bool>(isfinite(value)), [&] { return name + " must be finite"; }, value);
}

template <SupportedReal Real>
void require_positive(const std::string& name, const Real& value) {
  require_finite(name, value);
  require(
      value > 0, [&] { return name + " must be > 0"; }, value);
}

} // namespace pldamp
