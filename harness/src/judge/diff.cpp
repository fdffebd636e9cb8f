#include "judge/diff.hpp"

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

} // namespace

std::vector<std::string> regressions(const nlohmann::json& old_report,
                                     const nlohmann::json& new_report) {
  std::vector<std::string> found;
  std::map<std::string, bool> new_claims;
  for (const auto& claim : new_report.at("claims")) {
    new_claims[claim.at("name").get<std::string>()] = claim.at("verdict") == "holds";
  }
  for (const auto& claim : old_report.at("claims")) {
    const std::string name = claim.at("name").get<std::string>();
    const auto now = new_claims.find(name);
    if (claim.at("verdict") == "holds" && (now == new_claims.end() || !now->second)) {
      found.push_back("claim flipped: " + name + " held, now " +
                      (now == new_claims.end() ? "missing" : "fails"));
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
