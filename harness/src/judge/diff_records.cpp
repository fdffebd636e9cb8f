// diff's records: each old record against the new one of its key (errors, numbers, outcomes,
// work), and each configuration's time.
#include "judge/diff_parts.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pldamp::harness::diff {

RecordFacts RecordFacts::of(const json& record) {
  RecordFacts facts;
  facts.key = record.at(key::key).get<std::string>();
  for (auto [field, into] :
       {std::pair{key::config, &facts.config}, {key::damping, &facts.damping}}) {
    if (const json& text = member_or_null(record, field); text.is_string()) {
      *into = text.get<std::string>();
    }
  }
  facts.p = number_in(record, key::p);
  facts.v0 = number_in(record, key::v0);
  facts.m = number_in(record, key::m);
  facts.k = number_in(record, key::k);
  facts.outcome = record.at(key::outcome).get<std::string>();
  facts.failure = string_in(record, key::failure);
  facts.failed = record.at(key::failed).get<bool>();
  for (std::size_t f = 0; f < observed_fields.size(); ++f) {
    const json& values = member_or_null(record, observed_fields[f]);
    if (!values.is_object()) {
      continue;
    }
    for (const auto& item : values.items()) {
      // Not a structured binding: Clang 14 (the fuzz build) lets no lambda capture one.
      const std::string& name = item.key();
      auto at = std::find_if(facts.observed.begin(), facts.observed.end(),
                             [&](const Observed& o) { return o.name == name; });
      if (at == facts.observed.end()) {
        facts.observed.push_back({.name = name, .fields = {}});
        at = facts.observed.end() - 1;
      }
      at->fields[f] = Number::in(values, name);
    }
  }
  std::sort(facts.observed.begin(), facts.observed.end(),
            [](const Observed& a, const Observed& b) { return a.name < b.name; });
  facts.rhs_evals = Number::in(record, key::rhs_evals);
  facts.steps = Number::in(record, key::steps);
  facts.cpu = number_in(record, key::cpu_seconds).has_value();
  facts.seconds = number_in(record, facts.cpu ? key::cpu_seconds : key::wall_seconds);
  facts.seconds_slowest =
      number_in(record, facts.cpu ? key::cpu_seconds_slowest : key::wall_seconds_slowest);
  return facts;
}

std::optional<schema::RecordId> RecordFacts::id() const {
  if (!config || !damping || !p || !v0 || !m || !k) {
    return std::nullopt;
  }
  return schema::RecordId{
      .config = *config, .p = *p, .damping = *damping, .v0 = *v0, .m = *m, .k = *k};
}

const RecordFacts::Observed* RecordFacts::find(const std::string& name) const {
  const auto at =
      std::lower_bound(observed.begin(), observed.end(), name,
                       [](const Observed& o, const std::string& n) { return o.name < n; });
  return at != observed.end() && at->name == name ? &*at : nullptr;
}

namespace {

// Whether a record of the old report is outside the new scene (its configuration or one of its
// cell's values removed).
bool outside(const SceneChange& change, const RecordFacts& record) {
  if (change.removed_configs.contains(record.config.value_or(""))) {
    return true;
  }
  for (const auto& [axis, value] : {std::pair{key::p, record.p}, std::pair{key::v0, record.v0},
                                    std::pair{key::m, record.m}, std::pair{key::k, record.k}}) {
    if (value && change.removed_values.at(axis).contains(to_string_full(*value))) {
      return true;
    }
  }
  return change.removed_values.at(key::damping).contains(record.damping.value_or(""));
}

// A record's work (rhs_evals, steps), deterministic: any change listed, growth above the factor a
// regression.
void compare_work(Findings& findings, const Finding& base, const RecordFacts& was,
                  const RecordFacts& now, double work_factor) {
  for (const auto& [field, before_number, after_number] :
       {std::tuple{key::rhs_evals, was.rhs_evals, now.rhs_evals},
        std::tuple{key::steps, was.steps, now.steps}}) {
    const std::optional<double> before = before_number.number();
    const std::optional<double> after = after_number.number();
    if (before && !after) {
      compare_fields(findings, base, field,
                     {{.field = field, .before = before_number, .after = std::nullopt}});
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

// Time per configuration: the ratio of the sums of the fastest repeats, judged above the floor
// against the larger of time_factor and the noise of both nights (each night's slowest over its
// fastest: a ratio within what the repeats of one night already differ by is no finding).
void compare_time(Findings& findings, const std::string& config, const TimeSums& sums,
                  const DiffThresholds& t) {
  if (sums.before < t.time_floor || sums.before <= 0 || sums.after <= 0) {
    return;
  }
  const double ratio = sums.after / sums.before;
  const double noise = std::max(1.0, sums.before_slowest / sums.before) *
                       std::max(1.0, sums.after_slowest / sums.after);
  const double factor = std::max(t.time_factor, noise);
  if (ratio > factor || ratio * factor < 1) {
    const std::string worst =
        fmt::format("{:.3g} s -> {:.3g} s (x{:.3g}, noise x{:.3g}) over {} records", sums.before,
                    sums.after, ratio, noise, sums.records);
    findings.add({.severity = ratio > 1 ? Severity::regression : Severity::change,
                  .what = ratio > 1 ? "time_grew" : "time_fell",
                  .owner = config,
                  .subject = sums.cpu ? key::cpu_seconds : key::wall_seconds,
                  .unit = "configuration",
                  .rank = ratio,
                  .worst = worst,
                  .detail = config + ": " + worst});
  }
}

// What every finding about an old record says: its configuration and cell as its fields hold
// them, never split out of its key (a label may hold " | "); a record without them (not one
// pldamp wrote) is named by its key.
Finding base_finding(const RecordFacts& old_record) {
  const std::optional<schema::RecordId> id = old_record.id();
  return {.severity = Severity::regression,
          .owner = id ? id->config : old_record.key,
          .unit = "record",
          .cell = id ? schema::cell_text(*id) : "",
          .detail = old_record.key};
}

} // namespace

RecordComparison::RecordComparison(Findings& findings, const SceneChange& change, Noise noise,
                                   const DiffThresholds& t)
    : findings_(findings), change_(change), noise_(std::move(noise)), t_(t) {}

void RecordComparison::take(std::optional<RecordFacts> was, std::optional<RecordFacts> now) {
  if (now) {
    new_largest_.take(*now);
  }
  const std::string was_key = was ? was->key : "", now_key = now ? now->key : "";
  matched_.take(std::move(was), was_key, std::move(now), now_key,
                [&](const RecordFacts& a, const RecordFacts& b) { compare(a, b); });
}

void RecordComparison::finish() {
  for (const RecordFacts* old_record : matched_.only_in_old()) {
    if (outside(change_, *old_record)) {
      continue;
    }
    Finding base = base_finding(*old_record);
    base.what = "record_gone";
    base.subject = "record";
    base.worst = "present -> missing";
    base.rank = 1;
    findings_.add(base);
  }
  for (const std::string& config : time_order_) {
    compare_time(findings_, config, time_.at(config), t_);
  }
}

void RecordComparison::compare(const RecordFacts& old_record, const RecordFacts& now) {
  Finding base = base_finding(old_record);
  const std::string& config = base.owner;
  const auto outcomes = [&] { return old_record.outcome + " -> " + now.outcome; };
  if (now.failed && !old_record.failed) {
    base.what = "now_fails";
    base.subject = key::outcome;
    base.worst = outcomes();
    base.detail += ": " + base.worst + (now.failure.empty() ? "" : " (" + now.failure + ")");
    base.rank = 1;
    findings_.add(base);
    return;
  }
  if (old_record.failed) {
    if (!now.failed) {
      base.severity = Severity::change;
      base.what = "now_passes";
      base.subject = key::outcome;
      base.worst = outcomes();
      findings_.add(base);
    }
    return;
  }
  // Numbers lost or appeared: one finding per observable of the record, however many of its
  // fields (value, reference, error, ...) went.
  for (const RecordFacts::Observed& was : old_record.observed) {
    if (change_.removed_observables.contains(was.name)) {
      continue;
    }
    const RecordFacts::Observed* is = now.find(was.name);
    std::vector<FieldNow> fields;
    for (std::size_t f = 0; f < observed_fields.size(); ++f) {
      if (was.fields[f].state != Number::State::absent) {
        fields.push_back({.field = observed_fields[f],
                          .before = was.fields[f],
                          .after = is != nullptr ? is->fields[f].number() : std::nullopt});
      }
    }
    compare_fields(findings_, base, was.name, fields);
  }
  for (const RecordFacts::Observed& was : old_record.observed) {
    const Number& before = was.fields[rel_error_field];
    const RecordFacts::Observed* is = now.find(was.name);
    const std::optional<double> after =
        is != nullptr ? is->fields[rel_error_field].number() : std::nullopt;
    if (before.state == Number::State::number && after) {
      Finding f = base;
      f.what = "error";
      f.subject = was.name;
      compare_error(findings_, f, before.value, *after, noise_.of(config), t_.error_factor);
    }
  }
  compare_work(findings_, base, old_record, now, t_.work_factor);
  if (old_record.seconds && now.seconds) {
    const auto [at, fresh] = time_.try_emplace(config);
    if (fresh) {
      time_order_.push_back(config);
    }
    TimeSums& sums = at->second;
    sums.before += *old_record.seconds;
    sums.before_slowest += old_record.seconds_slowest.value_or(*old_record.seconds);
    sums.after += *now.seconds;
    sums.after_slowest += now.seconds_slowest.value_or(*now.seconds);
    sums.cpu = sums.cpu && old_record.cpu && now.cpu;
    ++sums.records;
  }
}

} // namespace pldamp::harness::diff
