// Printing and parsing numbers in any SupportedReal, and a small ordered JSON object writer.
//
// Numbers print with enough digits to round-trip in their own precision: shortest round-trip
// (std::to_chars) for double and long double, max_digits10 (36 for float128) for the Boost types.
// JSON has no infinity: an infinite value (τ when z ≥ 1) is `null`. A NaN is never printed; it is
// an internal error (exit 3), so a bug can't pass as a number.
#pragma once

#include "pldamp/core/real_types.hpp"
#include "pldamp/core/validate.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
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

template <SupportedReal Real>
std::string format_number(const Real& value) {
  using std::isnan;
  if (isnan(value)) {
    throw InternalError("a result evaluated to NaN");
  }
  return to_string_full(value); // "inf" for infinities; JsonObject writes them as null
}

// Parses the whole of `text` as a Real, rounding once into the target type (so "0.1" is the
// float128 nearest 0.1, not the double one). "nan"/"inf" parse; validation rejects them later.
template <SupportedReal Real>
Real parse_real(const std::string& option, const std::string& text) {
  const std::string what = option + " is not a number";
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

// An object whose keys keep their insertion order; values are pre-formatted JSON.
class JsonObject {
public:
  template <SupportedReal Real>
  void number(const std::string& key, const Real& value) {
    fields_.emplace_back(key, format_number(value));
  }
  template <SupportedReal Real>
  void number(const std::string& key, const std::optional<Real>& value) {
    if (value) {
      number(key, *value);
    }
  }
  void integer(const std::string& key, long value) {
    fields_.emplace_back(key, std::to_string(value));
  }
  // A value already written as JSON (an array, say).
  void raw(const std::string& key, const std::string& json_value) {
    fields_.emplace_back(key, json_value);
  }
  void string(const std::string& key, const std::string& value) {
    fields_.emplace_back(key, "\"" + value + "\""); // values are identifiers: nothing to escape
  }
  // JSON has no infinity: ±inf is written as null.
  std::string json() const {
    std::string out = "{";
    for (std::size_t i = 0; i < fields_.size(); ++i) {
      const std::string& value = fields_[i].second;
      out += (i ? ", \"" : "\"") + fields_[i].first +
             "\": " + (value == "inf" || value == "-inf" ? "null" : value);
    }
    return out + "}";
  }
  // "key  value" lines for people (strings unquoted, infinities as inf).
  std::string text() const {
    std::string out;
    for (const auto& [key, value] : fields_) {
      std::string shown = value;
      if (shown.size() >= 2 && shown.front() == '"') {
        shown = shown.substr(1, shown.size() - 2);
      }
      out += key + std::string(key.size() < 16 ? 16 - key.size() : 1, ' ') + shown + "\n";
    }
    return out;
  }

private:
  std::vector<std::pair<std::string, std::string>> fields_;
};

} // namespace pldamp::harness
