#include "common/report_schema.hpp"

#include "common/input.hpp"

#include <cmath>

namespace pldamp::harness::schema {

std::string cell_text(const RecordId& id) {
  return "p=" + to_string_full(id.p) + " " + id.damping + " v0=" + to_string_full(id.v0) +
         " m=" + to_string_full(id.m) + " k=" + to_string_full(id.k);
}

std::string record_key(const RecordId& id) {
  return id.config + " | " + cell_text(id);
}

std::optional<RecordId> read_record_id(const nlohmann::json& record) {
  const std::optional<double> p = number_in(record, key::p), v0 = number_in(record, key::v0),
                              m = number_in(record, key::m), k = number_in(record, key::k);
  const nlohmann::json& config = member_or_null(record, key::config);
  const nlohmann::json& damping = member_or_null(record, key::damping);
  if (!p || !v0 || !m || !k || !config.is_string() || !damping.is_string()) {
    return std::nullopt;
  }
  return RecordId{.config = config.get<std::string>(),
                  .p = *p,
                  .damping = damping.get<std::string>(),
                  .v0 = *v0,
                  .m = *m,
                  .k = *k};
}

nlohmann::ordered_json number_or_null(const std::optional<double>& x) {
  return x && std::isfinite(*x) ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
}

const nlohmann::json& member_or_null(const nlohmann::json& object, std::string_view key) {
  static const nlohmann::json null;
  if (!object.is_object()) {
    return null;
  }
  const auto found = object.find(key);
  return found != object.end() ? *found : null;
}

std::optional<double> number_in(const nlohmann::json& object, std::string_view key) {
  const nlohmann::json& found = member_or_null(object, key);
  return found.is_number() ? std::optional(found.get<double>()) : std::nullopt;
}

std::string string_in(const nlohmann::json& object, std::string_view key) {
  const nlohmann::json& found = member_or_null(object, key);
  return found.is_string() ? found.get<std::string>() : "";
}

const nlohmann::json& array_in(const nlohmann::json& object, std::string_view key) {
  static const nlohmann::json empty = nlohmann::json::array();
  const nlohmann::json& found = member_or_null(object, key);
  return found.is_array() ? found : empty;
}

namespace {

// A value for a message: a scalar as written (at most 40 characters), else its type. Never
// dump() a container: it recurses once per level, and 80 000 levels overflowed the stack.
std::string shown(const nlohmann::json& value) {
  if (value.is_structured()) {
    return std::string("an ") + value.type_name();
  }
  return value.dump(-1, ' ', true).substr(0, 40);
}

// `where` in `report` must hold a value `is` accepts; else "PATH: WHERE must be WHAT".
template <class Check>
void expect(const nlohmann::json& value, Check is, const std::string& path,
            const std::string& where, const std::string& what) {
  if (!is(value)) {
    throw InputError(path + ": " + where + " must be " + what + " (got " + shown(value) + ")");
  }
}

const nlohmann::json& member(const nlohmann::json& object, const char* key, const std::string& path,
                             const std::string& where) {
  const auto found = object.find(key);
  if (found == object.end()) {
    throw InputError(path + ": " + where + " has no \"" + key + "\"");
  }
  return *found;
}

} // namespace

nlohmann::json read_report(std::string_view text, const std::string& path) {
  nlohmann::json report = nlohmann::json::parse(text, nullptr, false);
  if (report.is_discarded()) {
    throw InputError("not a JSON report (got " + path + ")");
  }
  if (!report.is_object() || !report.contains(key::schema) || !report.contains(key::records) ||
      !report.contains(key::claims)) {
    throw InputError("not a pldamp report.json (got " + path + ")");
  }
  if (report.at(key::schema) != version) {
    throw InputError(path + ": report schema " + shown(report.at(key::schema)) + " is not " +
                     std::to_string(version));
  }
  const auto is_object = [](const nlohmann::json& j) { return j.is_object(); };
  const auto is_array = [](const nlohmann::json& j) { return j.is_array(); };
  expect(report.at(key::claims), is_array, path, key::claims, "an array");
  expect(report.at(key::records), is_array, path, key::records, "an array");
  // A member of an object at `where` that must be a string.
  const auto expect_string = [&](const nlohmann::json& object, const char* name,
                                 const std::string& where) {
    expect(
        member(object, name, path, where), [](const nlohmann::json& j) { return j.is_string(); },
        path, where + "." + name, "a string");
  };
  std::size_t i = 0;
  for (const nlohmann::json& claim : report.at(key::claims)) {
    const std::string where = std::string(key::claims) + "[" + std::to_string(i++) + "]";
    expect(claim, is_object, path, where, "an object");
    expect_string(claim, key::name, where);
    expect_string(claim, key::verdict, where);
    if (claim.contains(key::expect)) { // reports before the claim kinds have none
      expect(
          claim.at(key::expect),
          [](const nlohmann::json& j) { return j == word::holds || j == word::fails; }, path,
          where + "." + key::expect, "holds or fails");
    }
  }
  i = 0;
  for (const nlohmann::json& record : report.at(key::records)) {
    const std::string where = std::string(key::records) + "[" + std::to_string(i++) + "]";
    expect(record, is_object, path, where, "an object");
    expect_string(record, key::key, where);
    expect_string(record, key::outcome, where);
    expect(
        member(record, key::failed, path, where),
        [](const nlohmann::json& j) { return j.is_boolean(); }, path, where + "." + key::failed,
        "true or false");
    const std::string errors_at = where + "." + key::rel_error;
    const nlohmann::json& errors = member(record, key::rel_error, path, where);
    expect(errors, is_object, path, errors_at, "an object");
    for (const auto& [name, error] : errors.items()) {
      expect(
          error,
          [](const nlohmann::json& j) {
            return j.is_null() || (j.is_number() && !(j.get<double>() < 0));
          },
          path, errors_at + "." + name, "null or a number >= 0");
    }
    if (const auto precision = record.find(key::precision); precision != record.end()) {
      expect(
          *precision,
          [](const nlohmann::json& j) {
            bool known = false;
            if (j.is_string()) {
              for_each_precision([&]<class Real>() {
                known = known || precision_name<Real>() == j.get<std::string>();
              });
            }
            return known;
          },
          path, where + "." + key::precision, "one of " + precision_names());
    }
  }
  return report;
}

} // namespace pldamp::harness::schema
