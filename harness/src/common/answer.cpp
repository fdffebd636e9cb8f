#include "common/answer.hpp"

namespace pldamp::harness {
namespace {

bool is_exact_number(const Answer& value) {
  return value.is_number_float() || (value.is_binary() && value.get_binary().has_subtype() &&
                                     value.get_binary().subtype() == exact_number_subtype);
}

std::string digits_of(const Answer& value) {
  if (value.is_number_float()) {
    return format_number(value.get<double>());
  }
  const auto& bytes = value.get_binary();
  return std::string(bytes.begin(), bytes.end());
}

// JSON with ", " and ": " between items; exact numbers bare, infinities as null.
void write_json(const Answer& value, std::string& out) {
  if (is_exact_number(value)) {
    const std::string digits = digits_of(value);
    out += digits == "inf" || digits == "-inf" ? "null" : digits;
  } else if (value.is_object()) {
    out += '{';
    const char* separator = "";
    for (const auto& [key, item] : value.items()) {
      out += separator + Answer(key).dump() + ": ";
      write_json(item, out);
      separator = ", ";
    }
    out += '}';
  } else if (value.is_array()) {
    out += '[';
    const char* separator = "";
    for (const Answer& item : value) {
      out += separator;
      write_json(item, out);
      separator = ", ";
    }
    out += ']';
  } else {
    out += value.dump(); // strings escaped, integers, booleans, null
  }
}

} // namespace

std::optional<std::string> exact_digits(const Answer& value) {
  if (!is_exact_number(value)) {
    return std::nullopt;
  }
  return digits_of(value);
}

std::string answer_json(const Answer& answer) {
  std::string out;
  write_json(answer, out);
  return out;
}

std::string answer_text(const Answer& answer) {
  std::string out;
  // A "units" object (a contact from materials) is shown beside the numbers it names.
  const Answer* units = nullptr;
  if (const auto found = answer.find("units"); found != answer.end() && found->is_object()) {
    units = &*found;
  }
  for (const auto& [key, value] : answer.items()) {
    if (units != nullptr && key == "units") {
      continue;
    }
    std::string shown;
    if (is_exact_number(value)) {
      shown = digits_of(value);
    } else if (value.is_string()) {
      shown = value.get<std::string>();
    } else {
      write_json(value, shown);
    }
    if (units != nullptr && units->contains(key)) {
      shown += ' ';
      shown += (*units)[key].get_ref<const std::string&>();
    }
    out += key + std::string(key.size() < 16 ? 16 - key.size() : 1, ' ') + shown + "\n";
  }
  return out;
}

} // namespace pldamp::harness
