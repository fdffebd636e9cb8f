// What every stage of the harness uses for input and output: the two kinds of error the CLI turns
// into exit codes, and parsing and printing numbers in any SupportedReal.
//
// Numbers print with enough digits to round-trip in their own precision: shortest round-trip
// (std::to_chars) for double and long double, max_digits10 (36 for float128) for the Boost types.
// A NaN is never printed; it is an internal error (exit 3), so a bug can't pass as a number.
#pragma once

#include "pldamp/core/real_types.hpp"
#include "pldamp/core/validate.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace pldamp::harness {

// Bad input: the message is "<what> (got <value>)"; the CLI prints it after "error: ", exit 2.
struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A result that should be finite was NaN: exit 3.
struct InternalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <SupportedReal Real>
std::string format_number(const Real& value) {
  using std::isnan;
  if (isnan(value)) {
    throw InternalError("a result evaluated to NaN");
  }
  return to_string_full(value); // "inf" for infinities (JSON answers write null)
}

// A text as one line of output: control characters shown escaped (\n, \t, \xNN), so that a
// newline typed into an option or a scene's name cannot start a line of its own.
inline std::string one_line(std::string_view text) {
  static constexpr char hex[] = "0123456789abcdef";
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7f) {
      out += {'\\', 'x', hex[byte >> 4], hex[byte & 0xf]};
    } else {
      out += c;
    }
  }
  return out;
}

// Parses the whole of `text` as a Real, rounding once into the target type (so "0.1" is the
// float128 nearest 0.1, not the double one). "nan"/"inf" parse; validation rejects them later.
template <SupportedReal Real>
Real parse_real(const std::string& option, const std::string& text) {
  const std::string what = option + " is not a number";
  // strtod and the multiprecision parsers skip leading blanks: "\t1" is not a number as typed.
  if (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) {
    throw InputError(what + " (got " + text + ")");
  }
  if constexpr (std::is_floating_point_v<Real>) {
    char* end = nullptr;
    const Real value = std::is_same_v<Real, double> ? Real(std::strtod(text.c_str(), &end))
                                                    : Real(std::strtold(text.c_str(), &end));
    if (text.empty() || end != text.c_str() + text.size()) {
      throw InputError(what + " (got " + text + ")");
    }
    return value;
  } else {
    try {
      return Real(text);
    } catch (const std::exception&) {
      throw InputError(what + " (got " + text + ")");
    }
  }
}

// Parses the whole of `text` as a decimal integer.
inline long parse_integer(const std::string& option, const std::string& text) {
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    throw InputError(option + " is not an integer (got " + text + ")");
  }
  return value;
}

} // namespace pldamp::harness
