#include "judge/diff.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>

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

namespace {

using nlohmann::json;

// A member that is a number, else none (diff reads everything but the checked fields this way:
// a field a report lacks or holds as null is simply absent).
std::optional<double> number_in(const json& object, std::string_view key) {
  if (!object.is_object()) {
    return std::nullopt;
  }
  const auto found = object.find(key);
  return found != object.end() && found->is_number() ? std::optional(found->get<double>())
                                                     : std::nullopt;
}

std::string string_in(const json& object, std::string_view key) {
  if (!object.is_object()) {
    return "";
  }
  const auto found = object.find(key);
  return found != object.end() && found->is_string() ? found->get<std::string>() : "";
}

const json& member_or_null(const json& object, std::string_view key) {
  static const json null;
  if (!object.is_object()) {
    return null;
  }
  const auto found = object.find(key);
  return found != object.end() ? *found : null;
}

// The elements of an array member (none when it is not one).
const json& array_in(const json& object, std::string_view key) {
  static const json empty = json::array();
  const json& found = member_or_null(object, key);
  return found.is_array() ? found : empty;
}

std::string number_text(double x) {
  return fmt::format("{:.3g}", x);
}

std::string factor_text(double before, double after) {
  if (before == 0) {
    return "";
  }
  return fmt::format(" (x{:.3g})", after / before);
}

// A field of an output line as text a script can split: one line (common/input.hpp: a name with
// a line break cannot forge a line of its own) and, unless kept (a verbose line's record key),
// the field separator " | " written " / ".
std::string field_text(std::string_view text, bool keep_separators = false) {
  std::string out = one_line(text);
  for (std::size_t at = out.find(" | "); !keep_separators && at != std::string::npos;
       at = out.find(" | ", at + 3)) {
    out.replace(at, 3, " / ");
  }
  return out;
}

enum class Severity { regression, change };

// Findings gathered into groups of one kind, owner (a configuration, claim, search) and subject
// (an observable, a field); each group remembers its worst member.
class Findings {
public:
  struct Finding {
    Severity severity;
    std::string what, owner, subject, unit;
    double rank = 0;                 // larger: worse (the group shows its largest)
    std::string worst, cell, detail; // worst: "old -> new", cell: where, detail: a verbose line
  };

  void add(Finding finding) {
    const std::string key = fmt::format("{}\x1f{}\x1f{}\x1f{}", int(finding.severity), finding.what,
                                        finding.owner, finding.subject);
    const auto [at, fresh] = index_.try_emplace(key, groups_.size());
    if (fresh) {
      groups_.push_back({finding, 0, {}});
    }
    Group& group = groups_[at->second];
    ++group.count;
    if (finding.rank > group.worst.rank) {
      group.worst = finding;
    }
    group.details.push_back(finding.detail);
  }

  void write(DiffResult& result, bool verbose) const {
    for (const Severity severity : {Severity::regression, Severity::change}) {
      for (const Group& group : groups_) {
        if (group.worst.severity != severity) {
          continue;
        }
        const Finding& f = group.worst;
        (severity == Severity::regression ? result.regressions : result.changes) += 1;
        result.lines.push_back(fmt::format(
            "{} {} | {} | {} | {} {}{} | {}{}",
            severity == Severity::regression ? "REGRESSION" : "CHANGE", f.what, field_text(f.owner),
            field_text(f.subject), group.count, f.unit, group.count == 1 ? "" : "s",
            field_text(f.worst), f.cell.empty() ? "" : " at " + field_text(f.cell)));
        if (verbose) {
          for (const std::string& detail : group.details) {
            result.lines.push_back("  " + field_text(detail, true));
          }
        }
      }
    }
  }

private:
  struct Group {
    Finding worst;
    long count;
    std::vector<std::string> details;
  };
  std::vector<Group> groups_;
  std::map<std::string, std::size_t> index_;
};

DiffThresholds thresholds_of(const json& new_report, const DiffOptions& options) {
  DiffThresholds t;
  const json& table = member_or_null(member_or_null(new_report, "scene"), "diff");
  const auto take = [&](double& into, std::string_view key, const std::optional<double>& flag,
                        double least) {
    // The scene parser's ranges: a factor above 1, a floor of at least 0.
    if (const std::optional<double> scene = number_in(table, key);
        scene && (least > 0 ? *scene > least : *scene >= least) && *scene <= 1e6) {
      into = *scene;
    }
    if (flag) {
      into = *flag;
    }
  };
  take(t.error_factor, "error_factor", options.error_factor, 1);
  take(t.work_factor, "work_factor", options.work_factor, 1);
  take(t.time_factor, "time_factor", options.time_factor, 1);
  take(t.time_floor, "time_floor", options.time_floor, 0);
  return t;
}

// What one scene has that the other lacks: configurations, grid values, claims.
struct SceneChange {
  std::vector<std::string> lines;
  std::set<std::string> removed_configs, removed_claims, removed_observables;
  std::map<std::string, std::set<std::string>> removed_values; // axis -> values as text
};

// The labels of a list: each item's `key` member, or (no key) the items themselves, numbers in
// their shortest form.
std::set<std::string> labels(const json& list, std::string_view key) {
  std::set<std::string> out;
  for (const json& item : list.is_array() ? list : json::array()) {
    if (!key.empty()) {
      out.insert(string_in(item, key));
    } else if (item.is_number()) {
      out.insert(to_string_full(item.get<double>()));
    } else if (item.is_string()) {
      out.insert(item.get<std::string>());
    }
  }
  return out;
}

SceneChange scene_change(const json& old_report, const json& new_report) {
  SceneChange change;
  const json& was = member_or_null(old_report, "scene");
  const json& now = member_or_null(new_report, "scene");
  const auto compare = [&](std::string_view what, const std::set<std::string>& before,
                           const std::set<std::string>& after) -> std::set<std::string> {
    std::set<std::string> removed;
    for (const std::string& label : after) {
      if (!before.contains(label)) {
        change.lines.push_back(fmt::format("SCENE added {} | {}", what, field_text(label)));
      }
    }
    for (const std::string& label : before) {
      if (!after.contains(label)) {
        change.lines.push_back(fmt::format("SCENE removed {} | {}", what, field_text(label)));
        removed.insert(label);
      }
    }
    return removed;
  };
  change.removed_configs = compare("configuration", labels(member_or_null(was, "configs"), "label"),
                                   labels(member_or_null(now, "configs"), "label"));
  change.removed_observables = compare("observable", labels(member_or_null(was, "observables"), ""),
                                       labels(member_or_null(now, "observables"), ""));
  const json& old_grid = member_or_null(was, "grid");
  const json& new_grid = member_or_null(now, "grid");
  for (const char* axis : {"p", "v0", "m", "k"}) {
    change.removed_values[axis] = compare(axis, labels(member_or_null(old_grid, axis), ""),
                                          labels(member_or_null(new_grid, axis), ""));
  }
  change.removed_values["damping"] =
      compare("damping", labels(member_or_null(old_grid, "damping"), "label"),
              labels(member_or_null(new_grid, "damping"), "label"));
  change.removed_claims = compare("claim", labels(array_in(old_report, "claims"), "name"),
                                  labels(array_in(new_report, "claims"), "name"));
  compare("search", labels(member_or_null(was, "searches"), ""),
          labels(member_or_null(now, "searches"), ""));
  const std::string old_end = string_in(was, "end"), new_end = string_in(now, "end");
  if (old_end != new_end) {
    change.lines.push_back(fmt::format("SCENE changed end | {} -> {}", old_end, new_end));
  }
  return change;
}

// Whether a record of the old report is outside the new scene (its configuration or one of its
// cell's values removed).
bool outside(const SceneChange& change, const json& record) {
  if (change.removed_configs.contains(string_in(record, "config"))) {
    return true;
  }
  for (const char* axis : {"p", "v0", "m", "k"}) {
    const std::optional<double> value = number_in(record, axis);
    if (value && change.removed_values.at(axis).contains(to_string_full(*value))) {
      return true;
    }
  }
  return change.removed_values.at("damping").contains(string_in(record, "damping"));
}

// Noise per configuration label: 16 ε of its precision (double where unknown).
class Noise {
public:
  explicit Noise(const json& report) {
    for (const json& config : array_in(member_or_null(report, "scene"), "configs")) {
      by_label_[string_in(config, "label")] = precision_noise(string_in(config, "precision"));
    }
  }
  double of(const std::string& label) const {
    const auto found = by_label_.find(label);
    return found != by_label_.end() ? found->second : precision_noise("double");
  }

private:
  std::map<std::string, double> by_label_;
};

// An error (or a claim's error-like measurement) from `before` to `after`: grown more than the
// factor above the noise, or vanished to 0 from above it, is a regression; fallen by more than
// the factor, a change. Else nothing.
void compare_error(Findings& findings, const Findings::Finding& base, double before, double after,
                   double noise, double factor) {
  Findings::Finding f = base;
  f.worst = number_text(before) + " -> " + number_text(after) + factor_text(before, after);
  f.detail += ": " + f.worst;
  if (after > noise && after > factor * before) {
    f.severity = Severity::regression;
    f.what = base.what + "_grew";
    f.rank = before > 0 ? after / before : std::numeric_limits<double>::infinity();
    findings.add(f);
  } else if (after == 0 && before > noise) {
    f.severity = Severity::regression;
    f.what = base.what + "_vanished";
    f.rank = before;
    findings.add(f);
  } else if (before > noise && after * factor < before) {
    f.severity = Severity::change;
    f.what = base.what + "_fell";
    f.rank = after > 0 ? before / after : std::numeric_limits<double>::infinity();
    findings.add(f);
  }
}

// Numbers that were there and are not (regressions), and nulls that became numbers (changes).
// `was` and `now` map a subject (an observable, a count) to its fields' values; one finding per
// subject, however many of its fields went, but none for a subject the new scene removed.
void compare_numbers(Findings& findings, const Findings::Finding& base, const json& was,
                     const json& now, const std::set<std::string>& removed = {}) {
  if (!was.is_object()) {
    return;
  }
  for (const auto& [name, fields] : was.items()) {
    if (removed.contains(name) || !fields.is_object()) {
      continue;
    }
    std::string lost, appeared;
    for (const auto& [field, value] : fields.items()) {
      const std::optional<double> after = number_in(member_or_null(now, name), field);
      if (value.is_number() && !after) {
        lost += fmt::format("{}{} {}", lost.empty() ? "" : ", ", field,
                            number_text(value.get<double>()));
      } else if (value.is_null() && after) {
        appeared +=
            fmt::format("{}{} {}", appeared.empty() ? "" : ", ", field, number_text(*after));
      }
    }
    Findings::Finding f = base;
    f.subject = name;
    if (!lost.empty()) {
      f.severity = Severity::regression;
      f.what = "number_lost";
      f.worst = lost + " -> null";
      f.rank = 1;
    } else if (!appeared.empty()) {
      f.severity = Severity::change;
      f.what = "number_appeared";
      f.worst = "null -> " + appeared;
    } else {
      continue;
    }
    f.detail += ": " + f.worst;
    findings.add(f);
  }
}

// One field of an object as compare_numbers reads it: {subject: {field: value}}.
json field_of(const json& object, const std::string& subject, const std::string& field) {
  return json{{subject, {{field, member_or_null(object, field)}}}};
}

void compare_records(Findings& findings, const json& old_report, const json& new_report,
                     const SceneChange& change, const DiffThresholds& t) {
  std::map<std::string, const json*> new_records;
  for (const json& record : new_report.at("records")) {
    new_records[record.at("key").get<std::string>()] = &record;
  }
  const Noise noise(new_report);
  struct Time {
    double before = 0, after = 0;
    long records = 0;
  };
  std::map<std::string, Time> time; // per configuration, in the old report's order
  std::vector<std::string> time_order;
  for (const json& old_record : old_report.at("records")) {
    const std::string key = old_record.at("key").get<std::string>();
    const std::size_t bar = key.find(" | ");
    const std::string config = key.substr(0, bar);
    const std::string cell = bar == std::string::npos ? key : key.substr(bar + 3);
    Findings::Finding base{Severity::regression, "", config, "", "record", 0, "", cell, key};
    const auto found = new_records.find(key);
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
    const bool failed_before = old_record.at("failed").get<bool>();
    const bool failed_now = now.at("failed").get<bool>();
    if (failed_now && !failed_before) {
      base.what = "now_fails";
      base.subject = "outcome";
      base.worst = old_record.at("outcome").get<std::string>() + " -> " +
                   now.at("outcome").get<std::string>();
      base.detail +=
          ": " + base.worst +
          (string_in(now, "failure").empty() ? "" : " (" + string_in(now, "failure") + ")");
      base.rank = 1;
      findings.add(base);
      continue;
    }
    if (failed_before) {
      if (!failed_now) {
        base.severity = Severity::change;
        base.what = "now_passes";
        base.subject = "outcome";
        base.worst = old_record.at("outcome").get<std::string>() + " -> " +
                     now.at("outcome").get<std::string>();
        findings.add(base);
      }
      continue;
    }
    // Numbers lost or appeared: one finding per observable of the record, however many of its
    // fields (value, reference, error, ...) went.
    json fields_before = json::object(), fields_now = json::object();
    for (const char* field :
         {"value", "reference", "error", "abs_error", "rel_error", "phase_spread"}) {
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
    const json& old_errors = old_record.at("rel_error");
    for (const auto& [name, was] : old_errors.items()) {
      const std::optional<double> is = number_in(now.at("rel_error"), name);
      if (was.is_number() && is) {
        Findings::Finding f = base;
        f.what = "error";
        f.subject = name;
        compare_error(findings, f, was.get<double>(), *is, noise.of(config), t.error_factor);
      }
    }
    for (const char* field : {"rhs_evals", "steps"}) {
      const std::optional<double> before = number_in(old_record, field);
      const std::optional<double> after = number_in(now, field);
      if (before && !after) {
        compare_numbers(findings, base, field_of(old_record, field, field),
                        field_of(now, field, field));
      } else if (before && after && *before != *after) {
        Findings::Finding f = base;
        f.subject = field;
        f.worst = fmt::format("{:.0f} -> {:.0f}{}", *before, *after, factor_text(*before, *after));
        f.detail += ": " + f.worst;
        const bool grew = *after > t.work_factor * *before;
        f.severity = grew ? Severity::regression : Severity::change;
        f.what = grew ? "work_grew" : "work_changed";
        f.rank = *before > 0 ? std::abs(std::log(*after / *before))
                             : std::numeric_limits<double>::infinity();
        findings.add(f);
      }
    }
    const std::optional<double> before = number_in(old_record, "wall_seconds");
    const std::optional<double> after = number_in(now, "wall_seconds");
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
      findings.add({ratio > 1 ? Severity::regression : Severity::change,
                    ratio > 1 ? "time_grew" : "time_fell", config, "wall_seconds", "configuration",
                    ratio, worst, "", config + ": " + worst});
    }
  }
}

// budgets.work_precision: each point's error per observable is the largest of its records' at
// its configuration and p (a point that shows another observable's error, or a stale one, is a
// bug). A point without by_observable (a report before it) has nothing to check.
void compare_work_points(Findings& findings, const json& new_report) {
  namespace key = work_precision_key;
  const auto point_key = [](const json& object, std::string_view config, std::string_view p) {
    const std::optional<double> at = number_in(object, p);
    return string_in(object, config) + "\x1f" + (at ? to_string_full(*at) : "?");
  };
  std::map<std::string, std::map<std::string, std::optional<double>>> largest;
  for (const json& record : new_report.at("records")) {
    auto& of = largest[point_key(record, "config", "p")];
    for (const auto& [name, error] : record.at("rel_error").items()) {
      std::optional<double>& slot = of[name];
      if (error.is_number() && (!slot || error.get<double>() > *slot)) {
        slot = error.get<double>();
      }
    }
  }
  for (const json& point : array_in(member_or_null(new_report, "budgets"), "work_precision")) {
    const json& by_observable = member_or_null(point, key::by_observable);
    if (!by_observable.is_object()) {
      continue;
    }
    const auto records = largest.find(point_key(point, key::config, key::p));
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
        findings.add({Severity::regression, "work_precision_inconsistent",
                      string_in(point, key::config), name, "point", 1, worst, cell,
                      worst + " at " + cell});
      }
    }
  }
}

// budgets.worst: each configuration's largest error per observable, against the old report's,
// and against the new report's own records (a budget that no longer matches them is a bug).
void compare_budgets(Findings& findings, const json& old_report, const json& new_report,
                     const SceneChange& change, const DiffThresholds& t) {
  const Noise noise(new_report);
  const auto entry_key = [](const json& entry) {
    return string_in(entry, "config") + "\x1f" + string_in(entry, "observable");
  };
  const json& old_budgets = member_or_null(old_report, "budgets");
  const json& new_budgets = member_or_null(new_report, "budgets");
  std::map<std::string, const json*> now;
  for (const json& entry : array_in(new_budgets, "worst")) {
    now[entry_key(entry)] = &entry;
  }
  for (const json& entry : array_in(old_budgets, "worst")) {
    const std::string config = string_in(entry, "config");
    const std::string observable = string_in(entry, "observable");
    Findings::Finding base{
        Severity::regression,     "budget", config, observable, "budget", 1, "", "",
        config + " " + observable};
    const auto found = now.find(entry_key(entry));
    if (found == now.end()) {
      if (!change.removed_configs.contains(config) &&
          !change.removed_observables.contains(observable)) {
        compare_numbers(findings, base, field_of(entry, observable, "max_rel"), json::object());
      }
      continue;
    }
    compare_numbers(findings, base, field_of(entry, observable, "max_rel"),
                    field_of(*found->second, observable, "max_rel"));
    const std::optional<double> before = number_in(entry, "max_rel");
    const std::optional<double> after = number_in(*found->second, "max_rel");
    if (before && after) {
      compare_error(findings, base, *before, *after, noise.of(config), t.error_factor);
    }
  }
  // Consistency: a budget's number is the largest of its records' relative errors.
  std::map<std::string, std::optional<double>> largest;
  for (const json& record : new_report.at("records")) {
    for (const auto& [name, error] : record.at("rel_error").items()) {
      std::optional<double>& slot = largest[string_in(record, "config") + "\x1f" + name];
      if (error.is_number() && (!slot || error.get<double>() > *slot)) {
        slot = error.get<double>();
      }
    }
  }
  for (const json& entry : array_in(new_budgets, "worst")) {
    const std::optional<double> budget = number_in(entry, "max_rel");
    const auto records = largest.find(entry_key(entry));
    if (!budget || records == largest.end()) {
      continue;
    }
    if (records->second != budget) {
      const std::string worst =
          fmt::format("budget {}, its records' largest {}", number_text(*budget),
                      records->second ? number_text(*records->second) : "none");
      findings.add({Severity::regression, "budget_inconsistent", string_in(entry, "config"),
                    string_in(entry, "observable"), "budget", 1, worst, "", worst});
    }
  }
  compare_work_points(findings, new_report);
  // The analytic layer in double against the truth, per (p, damping) and observable.
  const auto point_key = [](const json& point) {
    const std::optional<double> p = number_in(point, "p");
    return fmt::format("p={} {}", p ? to_string_full(*p) : "?", string_in(point, "damping"));
  };
  std::map<std::string, const json*> points;
  for (const json& point : array_in(new_budgets, "analytic_double")) {
    points[point_key(point)] = &point;
  }
  const double double_noise = precision_noise("double");
  for (const json& point : array_in(old_budgets, "analytic_double")) {
    const std::string key = point_key(point);
    const auto found = points.find(key);
    if (found == points.end()) {
      continue; // a point outside the new grid: listed as a SCENE change
    }
    const json& was = member_or_null(point, "max_rel");
    const json& is = member_or_null(*found->second, "max_rel");
    Findings::Finding base{Severity::regression,
                           "analytic",
                           "closed forms in double",
                           "",
                           "point",
                           1,
                           "",
                           key,
                           "closed forms in double | " + key};
    if (!was.is_object()) {
      continue;
    }
    json fields_before = json::object(), fields_now = json::object();
    for (const auto& [name, value] : was.items()) {
      fields_before[name]["max_rel"] = value;
      fields_now[name]["max_rel"] = member_or_null(is, name);
    }
    compare_numbers(findings, base, fields_before, fields_now, change.removed_observables);
    for (const auto& [name, value] : was.items()) {
      const std::optional<double> after = number_in(is, name);
      if (value.is_number() && after) {
        Findings::Finding f = base;
        f.subject = name;
        compare_error(findings, f, value.get<double>(), *after, double_noise, t.error_factor);
      }
    }
  }
}

void compare_claims(Findings& findings, const json& old_report, const json& new_report,
                    const SceneChange& change, const DiffThresholds& t) {
  // A claim regresses when its verdict leaves the expected one: one that held now fails, or one
  // pinned as failing (expect = "fails") now holds. Reports before the claim kinds have no
  // expect: they expected every claim to hold.
  const auto expected = [](const json& claim) {
    return claim.value("expect", std::string("holds"));
  };
  std::map<std::string, const json*> now;
  for (const json& claim : new_report.at("claims")) {
    now[claim.at("name").get<std::string>()] = &claim;
  }
  for (const json& claim : old_report.at("claims")) {
    const std::string name = claim.at("name").get<std::string>();
    const std::string was = claim.at("verdict").get<std::string>();
    const auto found = now.find(name);
    Findings::Finding base{
        Severity::regression, "claim", name, "verdict", "claim", 1, "", "", name};
    if (found == now.end()) {
      if (was == expected(claim) && !change.removed_claims.contains(name)) {
        base.what = "claim_gone";
        base.worst = (was == "holds" ? "held" : "failed") + std::string(" -> missing");
        findings.add(base);
      }
      continue;
    }
    const json& is = *found->second;
    const std::string verdict = is.at("verdict").get<std::string>();
    if (was == expected(claim) && verdict != expected(is)) {
      base.what = "claim_flipped";
      // "partial": holds on some cells only, the others without a value (allow_missing).
      base.worst = was != "holds"         ? "failed as pinned, now holds"
                   : verdict == "partial" ? "held, now holds on some cells only"
                                          : "held, now fails";
      findings.add(base);
    }
    // Its measured value: an error-like one ("worse": "higher") like an error; an order, gap or
    // ratio ("lower") when it fell by more than 10 %.
    base.subject = "measured";
    const std::optional<double> before = number_in(claim, "measured");
    const std::optional<double> after = number_in(is, "measured");
    if (before && !after) {
      compare_numbers(findings, base, field_of(claim, "measured", "measured"),
                      field_of(is, "measured", "measured"));
    } else if (before && after && *before != *after) {
      if (string_in(is, "worse") == "lower") {
        Findings::Finding f = base;
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
  // Searches: the loosest setting found per group.
  const auto search_key = [](const json& search, const json& group) {
    return string_in(search, "name") + "\x1f" + string_in(group, "group");
  };
  std::map<std::string, const json*> found_now;
  for (const json& search : array_in(new_report, "searches")) {
    for (const json& group : array_in(search, "groups")) {
      found_now[search_key(search, group)] = &group;
    }
  }
  for (const json& search : array_in(old_report, "searches")) {
    for (const json& group : array_in(search, "groups")) {
      const std::optional<double> before = number_in(group, "loosest");
      const auto found = found_now.find(search_key(search, group));
      if (!before || found == found_now.end()) {
        continue;
      }
      const std::optional<double> after = number_in(*found->second, "loosest");
      if (after == before) {
        continue;
      }
      const std::string name = string_in(search, "name");
      const std::string worst =
          number_text(*before) + " -> " + (after ? number_text(*after) : "none found");
      findings.add({after ? Severity::change : Severity::regression,
                    after ? "search_moved" : "search_lost", name, string_in(group, "group"),
                    "search", 1, worst, "", name + " " + string_in(group, "group") + ": " + worst});
    }
  }
}

} // namespace

DiffResult diff_reports(const json& old_report, const json& new_report,
                        const DiffOptions& options) {
  DiffResult result;
  result.thresholds = thresholds_of(new_report, options);
  const SceneChange change = scene_change(old_report, new_report);
  const std::string old_print = string_in(member_or_null(old_report, "scene"), "fingerprint");
  const std::string new_print = string_in(member_or_null(new_report, "scene"), "fingerprint");
  if (old_print != new_print) {
    if (!options.allow_scene_change) {
      const json& was = member_or_null(old_report, "scene");
      const json& now = member_or_null(new_report, "scene");
      throw InputError(fmt::format(
          "the two reports come from different scenes ({} configurations, observables, grid "
          "values, claims, searches or contact ends added, removed or changed); "
          "--allow-scene-change compares what they share (got {} {}, now {} {})",
          change.lines.size(), string_in(was, "name"), old_print.empty() ? "unknown" : old_print,
          string_in(now, "name"), new_print.empty() ? "unknown" : new_print));
    }
    result.lines = change.lines;
  }
  Findings findings;
  compare_claims(findings, old_report, new_report, change, result.thresholds);
  compare_records(findings, old_report, new_report, change, result.thresholds);
  compare_budgets(findings, old_report, new_report, change, result.thresholds);
  findings.write(result, options.verbose);
  result.lines.push_back(fmt::format("{} regression{}, {} change{}", result.regressions,
                                     result.regressions == 1 ? "" : "s", result.changes,
                                     result.changes == 1 ? "" : "s"));
  return result;
}

std::vector<std::string> regressions(const json& old_report, const json& new_report) {
  DiffOptions options;
  options.allow_scene_change = true;
  std::vector<std::string> found;
  for (const std::string& line : diff_reports(old_report, new_report, options).lines) {
    if (line.rfind("REGRESSION ", 0) == 0) {
      found.push_back(line);
    }
  }
  return found;
}

} // namespace pldamp::harness
