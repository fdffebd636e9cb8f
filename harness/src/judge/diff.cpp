#include "judge/diff_parts.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <exception>
#include <future>

namespace pldamp::harness {
namespace diff {

namespace {

DiffThresholds thresholds_of(const json& new_report, const DiffOptions& options) {
  DiffThresholds t;
  const json& table = member_or_null(member_or_null(new_report, key::scene), key::diff);
  const auto take = [&](double& into, std::string_view name, const std::optional<double>& flag,
                        double least) {
    // The scene parser's ranges: a factor above 1, a floor of at least 0.
    if (const std::optional<double> scene = number_in(table, name);
        scene && (least > 0 ? *scene > least : *scene >= least) && *scene <= 1e6) {
      into = *scene;
    }
    if (flag) {
      into = *flag;
    }
  };
  take(t.error_factor, key::error_factor, options.error_factor, 1);
  take(t.work_factor, key::work_factor, options.work_factor, 1);
  take(t.time_factor, key::time_factor, options.time_factor, 1);
  take(t.time_floor, key::time_floor, options.time_floor, 0);
  return t;
}

// The labels of a list: each item's `name` member, or (no name) the items themselves, numbers in
// their shortest form.
std::set<std::string> labels(const json& list, std::string_view name) {
  std::set<std::string> out;
  for (const json& item : list.is_array() ? list : json::array()) {
    if (!name.empty()) {
      out.insert(string_in(item, name));
    } else if (item.is_number()) {
      out.insert(to_string_full(item.get<double>()));
    } else if (item.is_string()) {
      out.insert(item.get<std::string>());
    }
  }
  return out;
}

} // namespace

SceneChange scene_change(const json& old_report, const json& new_report) {
  SceneChange change;
  const json& was = member_or_null(old_report, key::scene);
  const json& now = member_or_null(new_report, key::scene);
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
  change.removed_configs =
      compare("configuration", labels(member_or_null(was, key::configs), key::label),
              labels(member_or_null(now, key::configs), key::label));
  change.removed_observables =
      compare("observable", labels(member_or_null(was, key::observables), ""),
              labels(member_or_null(now, key::observables), ""));
  const json& old_grid = member_or_null(was, key::grid);
  const json& new_grid = member_or_null(now, key::grid);
  for (const char* axis : {key::p, key::v0, key::m, key::k}) {
    change.removed_values[axis] = compare(axis, labels(member_or_null(old_grid, axis), ""),
                                          labels(member_or_null(new_grid, axis), ""));
  }
  change.removed_values[key::damping] =
      compare(key::damping, labels(member_or_null(old_grid, key::damping), key::label),
              labels(member_or_null(new_grid, key::damping), key::label));
  change.removed_claims = compare("claim", labels(array_in(old_report, key::claims), key::name),
                                  labels(array_in(new_report, key::claims), key::name));
  compare("search", labels(member_or_null(was, key::searches), ""),
          labels(member_or_null(now, key::searches), ""));
  const std::string old_end = string_in(was, key::end), new_end = string_in(now, key::end);
  if (old_end != new_end) {
    change.lines.push_back(fmt::format("SCENE changed end | {} -> {}", old_end, new_end));
  }
  return change;
}

} // namespace diff

namespace {

using diff::json;

// A report read whole (read_report's tree) as diff reads it: its records' facts beside the rest.
diff::Report facts_of(const json& report) {
  diff::Report out{.rest = json::object(), .records = {}};
  for (const auto& [name, value] : report.items()) {
    if (name == diff::key::records) {
      for (const json& record : value) {
        out.records.push_back(diff::RecordFacts::of(record));
      }
    } else {
      out.rest[name] = value;
    }
  }
  return out;
}

// A report streamed (read_report of a stream): its records' facts taken one record at a time.
// One in pldamp's layout is read fast (diff::read_record_lines); any other, or one the fast reader
// doubts, is read again from the start (a stream it cannot go back in is read by this reader
// alone).
diff::Report facts_of(std::istream& in, const std::string& path, const ReportLimits& limits) {
  const auto not_a_report = [&] { return InputError("not a JSON report (got " + path + ")"); };
  // Its first bytes: '{' after a little white space, or it is not a report.
  for (std::size_t blank = 0;; ++blank) {
    const int c = in.peek();
    if (c == '{') {
      break;
    }
    if (blank == limits.leading_space || !(c == ' ' || c == '\n' || c == '\t' || c == '\r')) {
      throw not_a_report();
    }
    in.get();
  }
  if (const std::istream::pos_type start = in.tellg(); start != std::istream::pos_type(-1)) {
    if (std::optional<diff::Report> fast = diff::read_record_lines(in, path, limits)) {
      return std::move(*fast);
    }
    in.clear();
    // Another layout is read whole by the general reader, whose tree of the text outside the
    // records is not bounded line by line: such a file is read up to limits.rest bytes.
    if (!in.seekg(0, std::ios::end) || in.tellg() - start > std::streamoff(limits.rest)) {
      throw InputError(fmt::format("{}: not in the layout pldamp writes (a record a line) and "
                                   "larger than {} MiB: diff reads such a report up to that size",
                                   path, double(limits.rest) / (1 << 20)));
    }
    if (!in.seekg(start)) {
      throw InputError("cannot read " + path + " again");
    }
  }
  diff::Report out;
  out.rest = schema::read_report(
      in, path, [&](json&& record) { out.records.push_back(diff::RecordFacts::of(record)); },
      limits.values);
  return out;
}

DiffResult diff_facts(const diff::Report& old_facts, const diff::Report& new_facts,
                      const DiffOptions& options) {
  using diff::member_or_null;
  using diff::string_in;
  namespace key = diff::key;
  DiffResult result;
  const json& old_report = old_facts.rest;
  const json& new_report = new_facts.rest;
  result.thresholds = diff::thresholds_of(new_report, options);
  const diff::SceneChange change = diff::scene_change(old_report, new_report);
  const std::string old_print = string_in(member_or_null(old_report, key::scene), key::fingerprint);
  const std::string new_print = string_in(member_or_null(new_report, key::scene), key::fingerprint);
  if (old_print != new_print) {
    if (!options.allow_scene_change) {
      const json& was = member_or_null(old_report, key::scene);
      const json& now = member_or_null(new_report, key::scene);
      throw InputError(fmt::format(
          "the two reports come from different scenes ({} configurations, observables, grid "
          "values, claims, searches or contact ends added, removed or changed); "
          "--allow-scene-change compares what they share (got {} {}, now {} {})",
          change.lines.size(), string_in(was, key::name), old_print.empty() ? "unknown" : old_print,
          string_in(now, key::name), new_print.empty() ? "unknown" : new_print));
    }
    result.lines = change.lines;
  }
  // Another build may compute other values: said first, judged as the rest is.
  const std::string old_build = string_in(member_or_null(old_report, key::run), key::build);
  const std::string new_build = string_in(member_or_null(new_report, key::run), key::build);
  if (old_build != new_build) {
    result.lines.insert(result.lines.begin(),
                        fmt::format("BUILD {} -> {}", old_build.empty() ? "unknown" : old_build,
                                    new_build.empty() ? "unknown" : new_build));
  }
  diff::Findings findings;
  diff::compare_claims(findings, old_report, new_report, change, result.thresholds);
  diff::compare_records(findings, old_facts, new_facts, change, result.thresholds);
  diff::compare_budgets(findings, old_report, new_facts, change, result.thresholds);
  findings.write(result, options.verbose);
  result.lines.push_back(fmt::format("{} regression{}, {} change{}", result.regressions,
                                     result.regressions == 1 ? "" : "s", result.changes,
                                     result.changes == 1 ? "" : "s"));
  return result;
}

} // namespace

DiffResult diff_reports(const json& old_report, const json& new_report,
                        const DiffOptions& options) {
  return diff_facts(facts_of(old_report), facts_of(new_report), options);
}

DiffResult diff_reports(std::istream& old_report, const std::string& old_path,
                        std::istream& new_report, const std::string& new_path,
                        const DiffOptions& options, const ReportLimits& limits) {
  // The two read at once, a thread each: reading is most of diff's time. The old report's error,
  // if both are bad, is the one said (as when read one after the other).
  std::future<diff::Report> old_facts =
      std::async(std::launch::async, [&] { return facts_of(old_report, old_path, limits); });
  std::exception_ptr new_failed;
  diff::Report new_facts;
  try {
    new_facts = facts_of(new_report, new_path, limits);
  } catch (...) {
    new_failed = std::current_exception();
  }
  const diff::Report old_read = old_facts.get();
  if (new_failed) {
    std::rethrow_exception(new_failed);
  }
  return diff_facts(old_read, new_facts, options);
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
