// diff's records: each old record against the new one of its key (errors, numbers, outcomes,
// work), and each configuration's time.
#include "judge/diff_parts.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace pldamp::harness::diff {

namespace {

// Whether a record of the old report is outside the new scene (its configuration or one of its
// cell's values removed).
bool outside(const SceneChange& change, const json& record) {
  if (change.removed_configs.contains(string_in(record, key::config))) {
    return true;
  }
  for (const char* axis : {key::p, key::v0, key::m, key::k}) {
    const std::optional<double> value = number_in(record, axis);
    if (value && change.removed_values.at(axis).contains(to_string_full(*value))) {
      return true;
    }
  }
  return change.removed_values.at(key::damping).contains(string_in(record, key::damping));
}

// A record's work (rhs_evals, steps), deterministic: any change listed, growth above the factor a
// regression.
void compare_work(Findings& findings, const Finding& base, const json& was, const json& now,
                  double work_factor) {
  for (const char* field : {key::rhs_evals, key::steps}) {
    const std::optional<double> before = number_in(was, field);
    const std::optional<double> after = number_in(now, field);
    if (before && !after) {
      compare_numbers(findings, base, field_of(was, field, field), field_of(now, field, field));
    } else if (before && after && *before != *after) {
      Finding f = base;
      f.subject = field;
      f.worst = fmt::format("{:.0f} -> {:.0f}{}", *before, *after, factor_text(*before, *after));
      f.detail += ": " + f.worst;
      const bool grew = *after > work_factor * *before;
      f.severity = grew ? Severity::regression : Severity::change;
      f.what = grew ? "work_grew" : "work_changed";
      f.rank = *before > 0 ? std::abs(std::log(*after / *before))
                           : std::numeric_limits<double>::infinity();
      findings.add(f);
    }
  }
}

} // namespace

void compare_records(Findings& findings, const json& old_report, const json& new_report,
                     const SceneChange& change, const DiffThresholds& t) {
  std::map<std::string, const json*> new_records;
  for (const json& record : new_report.at(key::records)) {
    new_records[record.at(key::key).get<std::string>()] = &record;
  }
  const Noise noise(new_report);
  struct Time {
    double before = 0, after = 0;
    long records = 0;
  };
  std::map<std::string, Time> time; // per configuration, in the old report's order
  std::vector<std::string> time_order;
  for (const json& old_record : old_report.at(key::records)) {
    const std::string record_key = old_record.at(key::key).get<std::string>();
    // Its configuration and cell as its fields hold them, never split out of its key (a label
    // may hold " | "); a record without them (not one pldamp wrote) is named by its key.
    const std::optional<schema::RecordId> id = schema::read_record_id(old_record);
    const std::string config = id ? id->config : record_key;
    Finding base{.severity = Severity::regression,
                 .owner = config,
                 .unit = "record",
                 .cell = id ? schema::cell_text(*id) : "",
                 .detail = record_key};
    const auto found = new_records.find(record_key);
    if (found == new_records.end()) {
      if (!outside(change, old_record)) {
        base.what = "record_gone";
        base.subject = "record";
        base.worst = "present -> missing";
        base.rank = 1;
        findings.add(base);
      }
      continue;
    }
    const json& now = *found->second;
    const bool failed_before = old_record.at(key::failed).get<bool>();
    const bool failed_now = now.at(key::failed).get<bool>();
    const auto outcomes = [&] {
      return old_record.at(key::outcome).get<std::string>() + " -> " +
             now.at(key::outcome).get<std::string>();
    };
    if (failed_now && !failed_before) {
      base.what = "now_fails";
      base.subject = key::outcome;
      base.worst = outcomes();
      const std::string failure = string_in(now, key::failure);
      base.detail += ": " + base.worst + (failure.empty() ? "" : " (" + failure + ")");
      base.rank = 1;
      findings.add(base);
      continue;
    }
    if (failed_before) {
      if (!failed_now) {
        base.severity = Severity::change;
        base.what = "now_passes";
        base.subject = key::outcome;
        base.worst = outcomes();
        findings.add(base);
      }
      continue;
    }
    // Numbers lost or appeared: one finding per observable of the record, however many of its
    // fields (value, reference, error, ...) went.
    json fields_before = json::object(), fields_now = json::object();
    for (const char* field : {key::value, key::reference, key::error, key::abs_error,
                              key::rel_error, key::phase_spread}) {
      for (const bool before : {true, false}) { // the two may be one object: a report with itself
        const json& values = member_or_null(before ? old_record : now, field);
        if (!values.is_object()) {
          continue;
        }
        json& into = before ? fields_before : fields_now;
        for (const auto& [name, value] : values.items()) {
          into[name][field] = value;
        }
      }
    }
    compare_numbers(findings, base, fields_before, fields_now, change.removed_observables);
    for (const auto& [name, was] : old_record.at(key::rel_error).items()) {
      const std::optional<double> is = number_in(now.at(key::rel_error), name);
      if (was.is_number() && is) {
        Finding f = base;
        f.what = "error";
        f.subject = name;
        compare_error(findings, f, was.get<double>(), *is, noise.of(config), t.error_factor);
      }
    }
    compare_work(findings, base, old_record, now, t.work_factor);
    const std::optional<double> before = number_in(old_record, key::wall_seconds);
    const std::optional<double> after = number_in(now, key::wall_seconds);
    if (before && after) {
      const auto [at, fresh] = time.try_emplace(config);
      if (fresh) {
        time_order.push_back(config);
      }
      at->second.before += *before;
      at->second.after += *after;
      ++at->second.records;
    }
  }
  // Time per configuration: the sum of the fastest repeats, judged above the floor.
  for (const std::string& config : time_order) {
    const Time& sums = time.at(config);
    if (sums.before < t.time_floor || sums.before <= 0) {
      continue;
    }
    const double ratio = sums.after / sums.before;
    if (ratio > t.time_factor || ratio * t.time_factor < 1) {
      const std::string worst = fmt::format("{:.3g} s -> {:.3g} s (x{:.3g}) over {} records",
                                            sums.before, sums.after, ratio, sums.records);
      findings.add({.severity = ratio > 1 ? Severity::regression : Severity::change,
                    .what = ratio > 1 ? "time_grew" : "time_fell",
                    .owner = config,
                    .subject = key::wall_seconds,
                    .unit = "configuration",
                    .rank = ratio,
                    .worst = worst,
                    .detail = config + ": " + worst});
    }
  }
}

} // namespace pldamp::harness::diff
