// What every stage of the harness uses for input and output: the two kinds of error the CLI turns
// into exit codes, and parsing and printing numbers in any SupportedReal.
//
// Numbers print with enough digits to round-trip in their own precision: shortest round-trip
// (std::to_chars) for double and long double, max_digits10 (36 for float128) for the Boost types.
// A NaN is never printed; it is an internal error (exit 3), so a bug can't pass as a number.
#pragma once

#include "pldamp/core/real_types.hpp"
#include "pldamp/core/validate.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// Bad input: the message is "<what> (got <value>)"; the CLI prints it after "error: ", exit 2.
struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A result that should be finite was NaN: exit 3.
struct InternalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline constexpr const char* nan_result = "a result evaluated to NaN";

template <SupportedReal Real>
std::string format_number(const Real& value) {
  using std::isnan;
  if (isnan(value)) {
    throw InternalError(nan_result);
  }
  return to_string_full(value); // "inf" for infinities (JSON answers write null)
}

// The length of the well-formed UTF-8 sequence `text` begins with (1 to 4), or 0 when its first
// byte does not begin one (RFC 3629: no overlong form, no surrogate, nothing above U+10FFFF).
inline std::size_t utf8_sequence(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) {
    return 1;
  }
  const std::size_t n = lead >= 0xc2 && lead <= 0xdf   ? 2
                        : lead >= 0xe0 && lead <= 0xef ? 3
                        : lead >= 0xf0 && lead <= 0xf4 ? 4
                                                       : 0;
  if (n == 0 || text.size() < n) {
    return 0;
  }
  for (std::size_t i = 1; i < n; ++i) {
    if ((byte(i) & 0xc0) != 0x80) {
      return 0;
    }
  }
  const unsigned char second = byte(1);
  if ((lead == 0xe0 && second < 0xa0) || (lead == 0xed && second > 0x9f) ||
      (lead == 0xf0 && second < 0x90) || (lead == 0xf4 && second > 0x8f)) {
    return 0;
  }
  return n;
}

// Whether `text` is UTF-8 throughout (what a JSON writer takes: nlohmann's throws otherwise).
inline bool valid_utf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence(text.substr(i));
    if (n == 0) {
      return false;
    }
    i += n;
  }
  return true;
}

// The code point of one well-formed UTF-8 sequence (utf8_sequence's length).
inline char32_t code_point(std::string_view sequence) {
  const auto byte = [&](std::size_t i) {
    return static_cast<char32_t>(static_cast<unsigned char>(sequence[i]));
  };
  switch (sequence.size()) {
  case 1:
    return byte(0);
  case 2:
    return (byte(0) & 0x1f) << 6 | (byte(1) & 0x3f);
  case 3:
    return (byte(0) & 0x0f) << 12 | (byte(1) & 0x3f) << 6 | (byte(2) & 0x3f);
  default:
    return (byte(0) & 0x07) << 18 | (byte(1) & 0x3f) << 12 | (byte(2) & 0x3f) << 6 |
           (byte(3) & 0x3f);
  }
}

// Characters that change what a terminal shows without showing themselves: the C1 controls and
// the bidirectional marks, embeddings, overrides and isolates (U+202E in a solver's name turned
// the rest of its line around).
inline bool hidden(char32_t point) {
  return (point >= 0x80 && point <= 0x9f) || point == 0x200e || point == 0x200f ||
         (point >= 0x202a && point <= 0x202e) || (point >= 0x2066 && point <= 0x2069);
}

// A text as one line of output: control characters and bytes that are not UTF-8 shown escaped
// (\n, \t, \xNN; the hidden characters above as \uNNNN), so that a newline typed into an option or
// a scene's name cannot start a line of its own, a NUL cannot end the line early, and a UTF-16 or
// binary file's bytes cannot reach a terminal raw (or a JSON writer, which refuses text that is not
// UTF-8).
inline std::string one_line(std::string_view text) {
  static constexpr char hex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    const auto byte = static_cast<unsigned char>(c);
    const std::size_t n = utf8_sequence(text.substr(i));
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7f || n == 0) {
      out += {'\\', 'x', hex[byte >> 4], hex[byte & 0xf]};
    } else if (const char32_t point = code_point(text.substr(i, n)); hidden(point)) {
      out += "\\u" + std::string{hex[(point >> 12) & 0xf], hex[(point >> 8) & 0xf],
                                 hex[(point >> 4) & 0xf], hex[point & 0xf]};
      i += n;
      continue;
    } else {
      out.append(text.substr(i, n));
      i += n;
      continue;
    }
    ++i;
  }
  return out;
}

// one_line, cut to at most `limit` bytes (a whole character last, then "..."): a text from
// outside (a program's reply, a file's cell) quoted in a message or kept in a report.
inline std::string one_line(std::string_view text, std::size_t limit) {
  // Each byte becomes at most 4 (\xNN): what lies beyond 4·limit bytes is never shown.
  std::string out = one_line(text.substr(0, std::min(text.size(), 4 * limit + 4)));
  if (out.size() <= limit && text.size() <= 4 * limit + 4) {
    return out;
  }
  std::size_t cut = limit > 3 ? limit - 3 : 0;
  while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xc0) == 0x80) {
    --cut; // not inside a character
  }
  return out.substr(0, cut) + "...";
}

// The items of a list as typed, its tokens split at commas: the one rule for every list of the
// command line (and so of Python's keywords). No empty item ("0.01,", ",0.01" and "1,,2" were
// read as "0.01" and "1,2"); where `distinct` (a set of observables, times or speeds, not a pair
// of bodies' radii), no item twice as typed (numbers are compared as values where parsed).
inline std::vector<std::string> list_items(const std::string& option,
                                           const std::vector<std::string>& tokens, bool distinct) {
  std::vector<std::string> items;
  for (const std::string& token : tokens) {
    for (std::size_t from = 0;;) {
      const std::size_t comma = token.find(',', from);
      std::string item = token.substr(from, comma == std::string::npos ? comma : comma - from);
      if (item.empty()) {
        throw InputError(option + " has an empty item (got " + one_line(token, 200) + ")");
      }
      if (distinct && std::find(items.begin(), items.end(), item) != items.end()) {
        throw InputError(option + " names " + one_line(item, 200) + " twice (got " +
                         one_line(token, 200) + ")");
      }
      items.push_back(std::move(item));
      if (comma == std::string::npos) {
        break;
      }
      from = comma + 1;
    }
  }
  return items;
}
inline std::vector<std::string> list_items(const std::string& option, const std::string& text,
                                           bool distinct) {
  return list_items(option, std::vector<std::string>{text}, distinct);
}

// Beyond the type's range the number read is not the one typed: 1e400 read as inf and 1e-400 as
// 0 were refused as "(got inf)" and "(got 0)", values the user never gave.
template <SupportedReal Real>
void refuse_out_of_range(const std::string& option, const std::string& text, const Real& value) {
  using std::isinf;
  if (!isinf(value) && value != 0) { // the common case, and a parse pays for it every time
    return;
  }
  const std::string mantissa = text.substr(0, text.find_first_of("eE"));
  const bool infinity_typed = text.find_first_of("iI") != std::string::npos;
  const bool nonzero_typed = mantissa.find_first_of("123456789") != std::string::npos;
  if ((isinf(value) && !infinity_typed) || (value == 0 && nonzero_typed)) {
    throw InputError(option + " is beyond what precision " + std::string(precision_name<Real>()) +
                     " holds" + " (got " + text + ")");
  }
}

// Parses the whole of `text` as a Real, rounding once into the target type (so "0.1" is the
// float128 nearest 0.1, not the double one). "nan"/"inf" parse; validation rejects them later.
template <SupportedReal Real>
Real parse_real(const std::string& option, const std::string& text) {
  // Made only when refused: a number is parsed a dozen times an answer.
  const auto what = [&] { return option + " is not a number"; };
  // strtod and the multiprecision parsers skip leading blanks: "\t1" is not a number as typed.
  if (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) {
    throw InputError(what() + " (got " + text + ")");
  }
  // Decimal only, as in scenes and CSV files: strtod and float128 read 0x1p-1, cpp_bin_float
  // does not, so a hex float was a number in three precisions of four.
  const std::size_t digits = text.find_first_not_of("+-");
  if (digits != std::string::npos &&
      (text.compare(digits, 2, "0x") == 0 || text.compare(digits, 2, "0X") == 0)) {
    throw InputError(what() + " in decimal (got " + text + ")");
  }
  if constexpr (std::is_floating_point_v<Real>) {
    char* end = nullptr;
    const Real value = std::is_same_v<Real, double> ? Real(std::strtod(text.c_str(), &end))
                                                    : Real(std::strtold(text.c_str(), &end));
    if (text.empty() || end != text.c_str() + text.size()) {
      throw InputError(what() + " (got " + text + ")");
    }
    refuse_out_of_range(option, text, value);
    return value;
  } else {
    Real value;
    try {
      value = Real(text);
    } catch (const std::exception&) {
      throw InputError(what() + " (got " + text + ")");
    }
    refuse_out_of_range(option, text, value);
    return value;
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

// Parses the whole of `text` as a whole number: a decimal integer, or a number in the form help
// texts write defaults in ("1e6") whose value is whole and within long's range.
inline long parse_whole(const std::string& option, const std::string& text) {
  try {
    return parse_integer(option, text);
  } catch (const InputError&) {
    double value = 0;
    try {
      value = parse_real<double>(option, text);
    } catch (const InputError&) {
      throw InputError(option + " is not a whole number (got " + text + ")");
    }
    // 2^63 is the first double beyond long's range.
    if (!(value == std::floor(value) && std::abs(value) < 9223372036854775808.0)) {
      throw InputError(option + " is not a whole number (got " + text + ")");
    }
    return static_cast<long>(value);
  }
}

} // namespace pldamp::harness
