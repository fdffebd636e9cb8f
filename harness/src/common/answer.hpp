// The answers of `calibrate`, `observables` and `solve`: an nlohmann::ordered_json object, so the
// keys keep their order and every string is escaped by nlohmann, whose numbers are printed by
// format_number in their own precision (36 digits for float128).
//
// nlohmann's numbers are doubles: a double travels in the tree as one (printed by the writers
// below in its shortest round-trip digits, format_number's, never by nlohmann's dump), a wider
// number as a binary value of subtype exact_number_subtype holding its decimal digits.
// answer_json prints either bare, an infinity as null (JSON has none: τ when α_eff ≥ 1), and
// answer_text as the digits or "inf".
#pragma once

#include "common/input.hpp"

#include <nlohmann/json.hpp>

#include <cassert>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

namespace pldamp::harness {

using Answer = nlohmann::ordered_json;

inline constexpr std::uint64_t exact_number_subtype = 0x45; // 'E'

template <SupportedReal Real>
Answer exact_number(const Real& value) {
  if constexpr (std::is_same_v<Real, double>) {
    if (std::isnan(value)) { // format_number's refusal, without its digits (a tenth of an answer)
      throw InternalError(nan_result);
    }
    return Answer(value); // no digits held: a Python answer takes the double itself
  } else {
    const std::string digits = format_number(value); // throws InternalError for NaN
    return Answer::binary(Answer::binary_t::container_type(digits.begin(), digits.end()),
                          exact_number_subtype);
  }
}

// An empty answer with room for a command's keys: an answer grows to 30 or so, and each growth
// moved every key and value (a tenth of `observables`' C++ time).
inline Answer answer_object() {
  Answer answer = Answer::object();
  answer.get_ref<Answer::object_t&>().reserve(40);
  return answer;
}

// The digits of an exact number ("0.5", "inf"), a double's included; none for any other value.
std::optional<std::string> exact_digits(const Answer& value);

// Adds key: value to an answer that has no such key yet, without looking for it (answer[key]
// compares the key with every key before it: a fifth of what `solve` adds to its solve).
inline void append(Answer& answer, std::string_view key, Answer value) {
  assert(!answer.contains(key));
  answer.get_ref<Answer::object_t&>().emplace_back(std::string(key), std::move(value));
}

// append's key: value, if there is a value.
template <SupportedReal Real>
void append_number(Answer& answer, std::string_view key, const std::optional<Real>& value) {
  if (value) {
    append(answer, key, exact_number(*value));
  }
}

// Sets answer[key] to the value, if there is one.
template <SupportedReal Real>
void put_number(Answer& answer, const std::string& key, const std::optional<Real>& value) {
  if (value) {
    answer[key] = exact_number(*value);
  }
}

// {"key": value, ...} on one line.
std::string answer_json(const Answer& answer);
// "key             value" lines for people: strings unquoted, infinities as inf.
std::string answer_text(const Answer& answer);

} // namespace pldamp::harness
