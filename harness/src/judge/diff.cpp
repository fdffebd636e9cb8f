#include "judge/diff.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <limits>
#include <map>

namespace pldamp::harness {
namespace {

// 16 ε of a record's precision: below it a tenfold change is rounding, not a regression.
double precision_noise(const std::string& precision) {
  double epsilon = 0;
  with_precision(precision, [&]<SupportedReal Real>() {
    epsilon = static_cast<double>(std::numeric_limits<Real>::epsilon());
  });
  return 16 * epsilon;
}

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
  if (!report.is_object() || !report.contains("schema") || !report.contains("records") ||
      !report.contains("claims")) {
    throw InputError("not a pldamp report.json (got " + path + ")");
  }
  if (report.at("schema") != report_schema) {
    throw InputError(path + ": report schema " + shown(report.at("schema")) + " is not " +
                     std::to_string(report_schema));
  }
  const auto is_string = [](const nlohmann::json& j) { return j.is_string(); };
  const auto is_object = [](const nlohmann::json& j) { return j.is_object(); };
  const auto is_array = [](const nlohmann::json& j) { return j.is_array(); };
  expect(report.at("claims"), is_array, path, "claims", "an array");
  expect(report.at("records"), is_array, path, "records", "an array");
  std::size_t i = 0;
  for (const nlohmann::json& claim : report.at("claims")) {
    const std::string where = "claims[" + std::to_string(i++) + "]";
    expect(claim, is_object, path, where, "an object");
    expect(member(claim, "name", path, where), is_string, path, where + ".name", "a string");
    expect(member(claim, "verdict", path, where), is_string, path, where + ".verdict", "a string");
    if (claim.contains("expect")) { // reports before the claim kinds have none
      expect(
          claim.at("expect"), [](const nlohmann::json& j) { return j == "holds" || j == "fails"; },
          path, where + ".expect", "holds or fails");
    }
  }
  i = 0;
  for (const nlohmann::json& record : report.at("records")) {
    const std::string where = "records[" + std::to_string(i++) + "]";
    expect(record, is_object, path, where, "an object");
    expect(member(record, "key", path, where), is_string, path, where + ".key", "a string");
    expect(member(record, "outcome", path, where), is_string, path, where + ".outcome", "a string");
    expect(
        member(record, "failed", path, where),
        [](const nlohmann::json& j) { return j.is_boolean(); }, path, where + ".failed",
        "true or false");
    const nlohmann::json& errors = member(record, "rel_error", path, where);
    expect(errors, is_object, path, where + ".rel_error", "an object");
    for (const auto& [name, error] : errors.items()) {
      expect(
          error,
          [](const nlohmann::json& j) {
            return j.is_null() || (j.is_number() && !(j.get<double>() < 0));
          },
          path, where + ".rel_error." + name, "null or a number >= 0");
    }
    if (const auto precision = record.find("precision"); precision != record.end()) {
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
          path, where + ".precision", "one of " + precision_names());
    }
  }
  return report;
}

std::vector<std::string> regressions(const nlohmann::json& old_report,
                                     const nlohmann::json& new_report) {
  std::vector<std::string> found;
  // A claim regresses when its verdict leaves the expected one: one that held now fails, or one
  // pinned as failing (expect = "fails", reports since the claim kinds) now holds.
  auto expected = [](const nlohmann::json& claim) {
    return claim.value("expect", std::string("holds"));
  };
  std::map<std::string, const nlohmann::json*> new_claims;
  for (const auto& claim : new_report.at("claims")) {
    new_claims[claim.at("name").get<std::string>()] = &claim;
  }
  for (const auto& claim : old_report.at("claims")) {
    const std::string name = claim.at("name").get<std::string>();
    const std::string was = claim.at("verdict").get<std::string>();
    if (was != expected(claim)) {
      continue;
    }
    const auto now = new_claims.find(name);
    if (now == new_claims.end()) {
      found.push_back("claim flipped: " + name + " " + (was == "holds" ? "held" : "failed") +
                      ", now missing");
      continue;
    }
    const std::string is = now->second->at("verdict").get<std::string>();
    if (is != expected(*now->second)) {
      found.push_back("claim flipped: " + name +
                      (was == "holds" ? " held, now fails" : " failed as pinned, now holds"));
    }
  }
  std::map<std::string, const nlohmann::json*> new_records;
  for (const auto& record : new_report.at("records")) {
    new_records[record.at("key").get<std::string>()] = &record;
  }
  for (const auto& old_record : old_report.at("records")) {
    const std::string key = old_record.at("key").get<std::string>();
    const auto found_new = new_records.find(key);
    if (found_new == new_records.end()) {
      found.push_back("record gone: " + key);
      continue;
    }
    const nlohmann::json& now = *found_new->second;
    if (now.at("failed").get<bool>() && !old_record.at("failed").get<bool>()) {
      found.push_back("now fails: " + key + " (" + now.at("outcome").get<std::string>() + ")");
      continue;
    }
    const double noise = precision_noise(now.value("precision", "double"));
    for (const auto& [name, was] : old_record.at("rel_error").items()) {
      const auto& is = now.at("rel_error").contains(name) ? now.at("rel_error").at(name)
                                                          : nlohmann::json(nullptr);
      if (!was.is_number() || !is.is_number()) {
        continue;
      }
      const double before = was.get<double>(), after = is.get<double>();
      if (after > noise && after > 10 * before) {
        found.push_back(
            fmt::format("error grew: {} {} {:.3g} -> {:.3g}", key, name, before, after));
      }
    }
  }
  return found;
}

} // namespace pldamp::harness
