// diff's budgets: budgets.worst and the analytic layer against the old report's, and budgets.worst
// and the work-precision points against the new report's own records.
#include "judge/diff_parts.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <optional>
#include <utility>

namespace pldamp::harness::diff {

namespace {

// Where a configuration's work-precision point or a record stands: its configuration and p.
std::pair<std::string, std::optional<double>> config_and_p(const json& object) {
  return {string_in(object, key::config), number_in(object, key::p)};
}
std::pair<std::string, std::optional<double>> config_and_p(const RecordFacts& record) {
  return {record.config.value_or(""), record.p};
}

// budgets.work_precision: each point's error per observable is the largest of its records' at
// its configuration and p (a point that shows another observable's error, or a stale one, is a
// bug). A point without by_observable (a report before it) has nothing to check.
void compare_work_points(Findings& findings, const json& new_report,
                         const RecordsLargest& new_records) {
  const auto& largest = new_records.by_config_and_p;
  for (const json& point :
       array_in(member_or_null(new_report, key::budgets), key::work_precision)) {
    const json& by_observable = member_or_null(point, key::by_observable);
    if (!by_observable.is_object()) {
      continue;
    }
    const auto records = largest.find(config_and_p(point));
    for (const auto& [name, entry] : by_observable.items()) {
      const std::optional<double> shown = number_in(entry, key::max_rel);
      if (!shown) {
        continue; // none, or not finite: as budgets.worst, nothing to compare
      }
      const std::optional<double> measured =
          records == largest.end() || !records->second.contains(name) ? std::nullopt
                                                                      : records->second.at(name);
      if (measured != shown) {
        const std::optional<double> p = number_in(point, key::p);
        const std::string worst =
            fmt::format("point {}, its records' largest {}", number_text(*shown),
                        measured ? number_text(*measured) : "none");
        const std::string cell = "p=" + (p ? to_string_full(*p) : "?");
        findings.add({.severity = Severity::regression,
                      .what = "work_precision_inconsistent",
                      .owner = string_in(point, key::config),
                      .subject = name,
                      .unit = "point",
                      .rank = 1,
                      .worst = worst,
                      .cell = cell,
                      .detail = worst + " at " + cell});
      }
    }
  }
}

// The analytic layer in double against the truth, per (p, damping) and observable.
void compare_analytic(Findings& findings, const json& old_budgets, const json& new_budgets,
                      const SceneChange& change, const DiffThresholds& t) {
  const auto point_of = [](const json& point) {
    return std::pair(number_in(point, key::p), string_in(point, key::damping));
  };
  std::map<std::pair<std::optional<double>, std::string>, const json*> points;
  for (const json& point : array_in(new_budgets, key::analytic_double)) {
    points[point_of(point)] = &point;
  }
  const double double_noise = precision_noise("double");
  for (const json& point : array_in(old_budgets, key::analytic_double)) {
    const auto found = points.find(point_of(point));
    if (found == points.end()) {
      continue; // a point outside the new grid: listed as a SCENE change
    }
    const json& was = member_or_null(point, key::max_rel);
    const json& is = member_or_null(*found->second, key::max_rel);
    const std::optional<double> p = number_in(point, key::p);
    const std::string cell =
        fmt::format("p={} {}", p ? to_string_full(*p) : "?", string_in(point, key::damping));
    const Finding base{.severity = Severity::regression,
                       .what = "analytic",
                       .owner = "closed forms in double",
                       .unit = "point",
                       .rank = 1,
                       .cell = cell,
                       .detail = "closed forms in double | " + cell};
    if (!was.is_object()) {
      continue;
    }
    json fields_before = json::object(), fields_now = json::object();
    for (const auto& [name, value] : was.items()) {
      fields_before[name][key::max_rel] = value;
      fields_now[name][key::max_rel] = member_or_null(is, name);
    }
    compare_numbers(findings, base, fields_before, fields_now, change.removed_observables);
    for (const auto& [name, value] : was.items()) {
      const std::optional<double> after = number_in(is, name);
      if (value.is_number() && after) {
        Finding f = base;
        f.subject = name;
        compare_error(findings, f, value.get<double>(), *after, double_noise, t.error_factor);
      }
    }
  }
}

} // namespace

void RecordsLargest::take(const RecordFacts& record) {
  LargestErrors& per_config = by_config[record.config.value_or("")];
  LargestErrors& per_point = by_config_and_p[config_and_p(record)];
  for (const RecordFacts::Observed& observed : record.observed) {
    const Number& error = observed.fields[rel_error_field];
    if (error.state == Number::State::absent) {
      continue;
    }
    for (LargestErrors* largest : {&per_config, &per_point}) {
      std::optional<double>& slot = (*largest)[observed.name];
      if (error.state == Number::State::number && (!slot || error.value > *slot)) {
        slot = error.value;
      }
    }
  }
}

// budgets.worst: each configuration's largest error per observable, against the old report's,
// and against the new report's own records (a budget that no longer matches them is a bug).
void compare_budgets(Findings& findings, const json& old_report, const json& new_report,
                     const RecordsLargest& new_records, const SceneChange& change,
                     const DiffThresholds& t) {
  const Noise noise(new_report);
  const auto config_and_observable = [](const json& entry) {
    return std::pair(string_in(entry, key::config), string_in(entry, key::observable));
  };
  const json& old_budgets = member_or_null(old_report, key::budgets);
  const json& new_budgets = member_or_null(new_report, key::budgets);
  std::map<std::pair<std::string, std::string>, const json*> now;
  for (const json& entry : array_in(new_budgets, key::worst)) {
    now[config_and_observable(entry)] = &entry;
  }
  for (const json& entry : array_in(old_budgets, key::worst)) {
    const auto [config, observable] = config_and_observable(entry);
    const Finding base{.severity = Severity::regression,
                       .what = "budget",
                       .owner = config,
                       .subject = observable,
                       .unit = "budget",
                       .rank = 1,
                       .detail = config + " " + observable};
    const auto found = now.find(config_and_observable(entry));
    if (found == now.end()) {
      if (!change.removed_configs.contains(config) &&
          !change.removed_observables.contains(observable)) {
        compare_numbers(findings, base, field_of(entry, observable, key::max_rel), json::object());
      }
      continue;
    }
    compare_numbers(findings, base, field_of(entry, observable, key::max_rel),
                    field_of(*found->second, observable, key::max_rel));
    const std::optional<double> before = number_in(entry, key::max_rel);
    const std::optional<double> after = number_in(*found->second, key::max_rel);
    if (before && after) {
      compare_error(findings, base, *before, *after, noise.of(config), t.error_factor);
    }
  }
  // Consistency: a budget's number is the largest of its records' relative errors.
  const auto& largest = new_records.by_config;
  for (const json& entry : array_in(new_budgets, key::worst)) {
    const std::optional<double> budget = number_in(entry, key::max_rel);
    const auto [config, observable] = config_and_observable(entry);
    const auto records = largest.find(config);
    if (!budget || records == largest.end() || !records->second.contains(observable)) {
      continue;
    }
    const std::optional<double>& measured = records->second.at(observable);
    if (measured != budget) {
      const std::string worst =
          fmt::format("budget {}, its records' largest {}", number_text(*budget),
                      measured ? number_text(*measured) : "none");
      findings.add({.severity = Severity::regression,
                    .what = "budget_inconsistent",
                    .owner = config,
                    .subject = observable,
                    .unit = "budget",
                    .rank = 1,
                    .worst = worst,
                    .detail = worst});
    }
  }
  compare_work_points(findings, new_report, new_records);
  compare_analytic(findings, old_budgets, new_budgets, change, t);
}

} // namespace pldamp::harness::diff
