// diff's claims and searches: a verdict that left the expected one, a measured value that moved
// the wrong way or disappeared, a search that no longer finds a value.
#include "judge/diff_parts.hpp"

#include <cmath>
#include <utility>

namespace pldamp::harness::diff {

namespace {

// Searches: the loosest setting found per group.
void compare_searches(Findings& findings, const json& old_report, const json& new_report) {
  const auto search_and_group = [](const json& search, const json& group) {
    return std::pair(string_in(search, key::name), string_in(group, key::group));
  };
  std::map<std::pair<std::string, std::string>, const json*> found_now;
  for (const json& search : array_in(new_report, key::searches)) {
    for (const json& group : array_in(search, key::groups)) {
      found_now[search_and_group(search, group)] = &group;
    }
  }
  for (const json& search : array_in(old_report, key::searches)) {
    for (const json& group : array_in(search, key::groups)) {
      const std::optional<double> before = number_in(group, key::loosest);
      const auto found = found_now.find(search_and_group(search, group));
      if (!before || found == found_now.end()) {
        continue;
      }
      const std::optional<double> after = number_in(*found->second, key::loosest);
      if (after == before) {
        continue;
      }
      const std::string name = string_in(search, key::name);
      const std::string worst =
          number_text(*before) + " -> " + (after ? number_text(*after) : "none found");
      findings.add({.severity = after ? Severity::change : Severity::regression,
                    .what = after ? "search_moved" : "search_lost",
                    .owner = name,
                    .subject = string_in(group, key::group),
                    .unit = "search",
                    .rank = 1,
                    .worst = worst,
                    .detail = name + " " + string_in(group, key::group) + ": " + worst});
    }
  }
}

} // namespace

void compare_claims(Findings& findings, const json& old_report, const json& new_report,
                    const SceneChange& change, const DiffThresholds& t) {
  // A claim regresses when its verdict leaves the expected one: one that held now fails, or one
  // pinned as failing (expect = "fails") now holds. Reports before the claim kinds have no
  // expect: they expected every claim to hold.
  const auto expected = [](const json& claim) {
    return claim.value(key::expect, std::string(word::holds));
  };
  std::map<std::string, const json*> now;
  for (const json& claim : new_report.at(key::claims)) {
    now[claim.at(key::name).get<std::string>()] = &claim;
  }
  for (const json& claim : old_report.at(key::claims)) {
    const std::string name = claim.at(key::name).get<std::string>();
    const std::string was = claim.at(key::verdict).get<std::string>();
    const auto found = now.find(name);
    Finding base{.severity = Severity::regression,
                 .what = "claim",
                 .owner = name,
                 .subject = key::verdict,
                 .unit = "claim",
                 .rank = 1,
                 .detail = name};
    if (found == now.end()) {
      if (was == expected(claim) && !change.removed_claims.contains(name)) {
        base.what = "claim_gone";
        base.worst = (was == word::holds ? "held" : "failed") + std::string(" -> missing");
        findings.add(base);
      }
      continue;
    }
    const json& is = *found->second;
    const std::string verdict = is.at(key::verdict).get<std::string>();
    if (was == expected(claim) && verdict != expected(is)) {
      base.what = "claim_flipped";
      // "partial": holds on some cells only, the others without a value (allow_missing).
      base.worst = was != word::holds         ? "failed as pinned, now holds"
                   : verdict == word::partial ? "held, now holds on some cells only"
                                              : "held, now fails";
      findings.add(base);
    }
    // Its measured value: an error-like one ("worse": "higher") like an error; an order, gap or
    // ratio ("lower") when it fell by more than 10 %.
    base.subject = key::measured;
    const std::optional<double> before = number_in(claim, key::measured);
    const std::optional<double> after = number_in(is, key::measured);
    if (before && !after) {
      compare_numbers(findings, base, field_of(claim, key::measured, key::measured),
                      field_of(is, key::measured, key::measured));
    } else if (before && after && *before != *after) {
      if (string_in(is, key::worse) == word::lower) {
        Finding f = base;
        f.worst = number_text(*before) + " -> " + number_text(*after);
        f.detail += ": " + f.worst;
        const bool fell = *after < *before - 0.1 * std::abs(*before);
        f.severity = fell ? Severity::regression : Severity::change;
        f.what = fell ? "claim_measured_worsened" : "claim_measured_changed";
        findings.add(f);
      } else {
        base.what = "claim_measured";
        compare_error(findings, base, *before, *after, 0, t.error_factor);
      }
    }
  }
  compare_searches(findings, old_report, new_report);
}

} // namespace pldamp::harness::diff
