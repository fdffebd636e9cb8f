#include "common/report_schema.hpp"

#include "common/input.hpp"

#include <cmath>
#include <initializer_list>
#include <set>

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

// `value`, at `where`, must be an object whose members `names` are strings.
void expect_strings(const nlohmann::json& value, std::initializer_list<const char*> names,
                    const std::string& path, const std::string& where) {
  expect(
      value, [](const nlohmann::json& j) { return j.is_object(); }, path, where, "an object");
  for (const char* name : names) {
    expect(
        member(value, name, path, where), [](const nlohmann::json& j) { return j.is_string(); },
        path, where + "." + name, "a string");
  }
}

// The claims as read_report checks them.
void check_claims(const nlohmann::json& claims, const std::string& path) {
  std::size_t i = 0;
  for (const nlohmann::json& claim : claims) {
    const std::string where = std::string(key::claims) + "[" + std::to_string(i++) + "]";
    expect_strings(claim, {key::name, key::verdict}, path, where);
    if (claim.contains(key::expect)) { // reports before the claim kinds have none
      expect(
          claim.at(key::expect),
          [](const nlohmann::json& j) { return j == word::holds || j == word::fails; }, path,
          where + "." + key::expect, "holds or fails");
    }
  }
}

} // namespace

bool known_precision(std::string_view name) {
  bool known = false;
  for_each_precision([&]<class Real>() { known = known || precision_name<Real>() == name; });
  return known;
}

void check_record(const nlohmann::json& record, const std::string& path, const std::string& where) {
  expect_strings(record, {key::key, key::outcome}, path, where);
  expect(
      member(record, key::failed, path, where),
      [](const nlohmann::json& j) { return j.is_boolean(); }, path, where + "." + key::failed,
      "true or false");
  const std::string errors_at = where + "." + key::rel_error;
  const nlohmann::json& errors = member(record, key::rel_error, path, where);
  expect(
      errors, [](const nlohmann::json& j) { return j.is_object(); }, path, errors_at, "an object");
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
          return j.is_string() && known_precision(j.get<std::string>());
        },
        path, where + "." + key::precision, "one of " + precision_names());
  }
}

namespace {

// read_report, of any input nlohmann::json::parse takes: every record of the schema's version is
// checked and handed to `each` as soon as it is read, and not kept (one record in memory at a
// time); a record read before the schema's version is known is kept until it is.
template <class Input>
nlohmann::json read_report_from(Input&& input, const std::string& path, const RecordSink& each) {
  using event = nlohmann::json::parse_event_t;
  std::string section;         // the top-level member being read
  std::optional<bool> ours;    // whether its schema is this version's (none: not yet read)
  bool in_records = false;     // inside the top-level records array
  std::size_t read = 0;        // records handed over
  bool claims_checked = false; // as soon as they are read (before the records, as pldamp writes)
  std::set<std::string> named; // of schema, claims and records: each once
  const auto take = [&](nlohmann::json&& record) {
    check_record(record, path, std::string(key::records) + "[" + std::to_string(read++) + "]");
    each(std::move(record));
  };
  const nlohmann::json::parser_callback_t callback = [&](int depth, event e,
                                                         nlohmann::json& parsed) {
    if (depth == 1) {
      if (e == event::key) {
        section = parsed.get<std::string>();
        // Named twice, the tree would keep the last one while the records handed over (or
        // dropped, or the claims checked) were the first one's: refused.
        if ((section == key::schema || section == key::claims || section == key::records) &&
            !named.insert(section).second) {
          throw InputError(path + ": the report names " + section + " twice");
        }
      } else if (e == event::value && section == key::schema) {
        ours = parsed == version;
      } else if (e == event::array_end && section == key::claims && ours == true) {
        check_claims(parsed, path);
        claims_checked = true;
      }
      in_records = section == key::records && e == event::array_start;
      return true;
    }
    const bool element = depth == 2 && in_records &&
                         (e == event::object_end || e == event::array_end || e == event::value);
    if (!element || !ours) {
      return true; // a record before the schema: kept in the tree, handed over at the end
    }
    if (*ours) {
      take(std::move(parsed));
    }
    return false; // of another schema: refused at the end, its records never kept
  };
  nlohmann::json report = nlohmann::json::parse(std::forward<Input>(input), callback, false);
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
  const auto is_array = [](const nlohmann::json& j) { return j.is_array(); };
  expect(report.at(key::claims), is_array, path, key::claims, "an array");
  expect(report.at(key::records), is_array, path, key::records, "an array");
  if (!claims_checked) {
    check_claims(report.at(key::claims), path);
  }
  for (nlohmann::json& record : report.at(key::records)) {
    take(std::move(record));
  }
  report.at(key::records) = nlohmann::json::array();
  return report;
}

} // namespace

nlohmann::json read_report(std::string_view text, const std::string& path) {
  nlohmann::json records = nlohmann::json::array();
  nlohmann::json report = read_report_from(
      text, path, [&](nlohmann::json&& record) { records.push_back(std::move(record)); });
  report.at(key::records) = std::move(records);
  return report;
}

nlohmann::json read_report(std::istream& in, const std::string& path, const RecordSink& each) {
  return read_report_from(in, path, each);
}

} // namespace pldamp::harness::schema
