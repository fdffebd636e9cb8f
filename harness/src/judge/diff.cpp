#include "judge/diff_parts.hpp"

#include "common/input.hpp"
#include "judge/bounded_queue.hpp"
#include "judge/diff_exact.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <future>
#include <optional>
#include <variant>

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

// What diff settles before the records: the thresholds, what the two scenes do not share, the
// lines said first, and whether the reports may be compared at all.
struct Setup {
  DiffThresholds thresholds;
  diff::SceneChange change;
  std::vector<std::string> lines; // BUILD, then SCENE
  std::optional<InputError> refusal;
};

Setup setup_of(const json& old_report, const json& new_report, const DiffOptions& options) {
  using diff::member_or_null;
  using diff::string_in;
  namespace key = diff::key;
  Setup setup{.thresholds = diff::thresholds_of(new_report, options),
              .change = diff::scene_change(old_report, new_report),
              .lines = {},
              .refusal = std::nullopt};
  const json& was = member_or_null(old_report, key::scene);
  const json& now = member_or_null(new_report, key::scene);
  const std::string old_print = string_in(was, key::fingerprint);
  const std::string new_print = string_in(now, key::fingerprint);
  if (old_print != new_print) {
    if (!options.allow_scene_change) {
      setup.refusal = InputError(fmt::format(
          "the two reports come from different scenes ({} configurations, observables, grid "
          "values, claims, searches or contact ends added, removed or changed); "
          "--allow-scene-change compares what they share (got {} {}, now {} {})",
          setup.change.lines.size(), string_in(was, key::name),
          old_print.empty() ? "unknown" : old_print, string_in(now, key::name),
          new_print.empty() ? "unknown" : new_print));
    }
    setup.lines = setup.change.lines;
  }
  // Another build may compute other values: said first, judged as the rest is.
  const std::string old_build = string_in(member_or_null(old_report, key::run), key::build);
  const std::string new_build = string_in(member_or_null(new_report, key::run), key::build);
  if (old_build != new_build) {
    setup.lines.insert(setup.lines.begin(),
                       fmt::format("BUILD {} -> {}", old_build.empty() ? "unknown" : old_build,
                                   new_build.empty() ? "unknown" : new_build));
  }
  return setup;
}

// One diff, fed as the reports are read: the claims and the setup from everything but the
// records (all of which comes before them in pldamp's layout, but the figures, which diff does
// not read), then the records of both as they come, then the budgets.
class Comparison {
public:
  Comparison(json old_report, json new_report, const DiffOptions& options)
      : options_(options), old_(std::move(old_report)), new_(std::move(new_report)),
        setup_(setup_of(old_, new_, options)), findings_(options.verbose),
        records_(findings_, setup_.change, diff::Noise(new_), setup_.thresholds) {
    if (!setup_.refusal) {
      diff::compare_claims(findings_, old_, new_, setup_.change, setup_.thresholds);
    }
  }
  Comparison(const Comparison&) = delete;
  Comparison& operator=(const Comparison&) = delete;

  // The next record of each report (none where it has ended). Records of reports that may not
  // be compared are read (a damaged one is still refused as such) and dropped.
  void take(std::optional<diff::RecordFacts> was, std::optional<diff::RecordFacts> now) {
    if (!setup_.refusal) {
      records_.take(std::move(was), std::move(now));
    }
  }

  DiffResult finish() {
    if (setup_.refusal) {
      throw *setup_.refusal;
    }
    DiffResult result;
    result.thresholds = setup_.thresholds;
    result.lines = setup_.lines;
    records_.finish();
    diff::compare_budgets(findings_, old_, new_, records_.new_largest(), setup_.change,
                          setup_.thresholds);
    result.records_held = records_.most_waiting();
    findings_.write(result, options_.verbose);
    result.lines.push_back(fmt::format("{} regression{}, {} change{}", result.regressions,
                                       result.regressions == 1 ? "" : "s", result.changes,
                                       result.changes == 1 ? "" : "s"));
    return result;
  }

private:
  DiffOptions options_;
  json old_, new_;
  Setup setup_;
  diff::Findings findings_;
  diff::RecordComparison records_;
};

// Two reports read whole: their records fed a pair at a time, as they would stream.
DiffResult diff_facts(diff::Report old_facts, diff::Report new_facts, const DiffOptions& options) {
  Comparison comparison(std::move(old_facts.rest), std::move(new_facts.rest), options);
  const std::size_t held = old_facts.records.size() + new_facts.records.size();
  const std::size_t count = std::max(old_facts.records.size(), new_facts.records.size());
  const auto at = [](std::vector<diff::RecordFacts>& records, std::size_t i) {
    return i < records.size() ? std::optional(std::move(records[i])) : std::nullopt;
  };
  for (std::size_t i = 0; i < count; ++i) {
    comparison.take(at(old_facts.records, i), at(new_facts.records, i));
  }
  DiffResult result = comparison.finish();
  result.records_held = held;
  return result;
}

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

// A report's first bytes: '{' after a little white space, or it is not a report. Returns where
// the '{' stands (-1 in a stream that cannot tell).
std::istream::pos_type report_start(std::istream& in, const std::string& path,
                                    const ReportLimits& limits) {
  for (std::size_t blank = 0;; ++blank) {
    const int c = in.peek();
    if (c == '{') {
      return in.tellg();
    }
    if (blank == limits.leading_space || !(c == ' ' || c == '\n' || c == '\t' || c == '\r')) {
      throw InputError("not a JSON report (got " + path + ")");
    }
    in.get();
  }
}

// A report read whole, its records' facts taken one record at a time. One in pldamp's layout is
// read fast (diff::read_record_lines); any other, or one the fast reader doubts, is read again
// from the start (a stream it cannot go back in is read by this reader alone).
diff::Report facts_of(std::istream& in, const std::string& path, const ReportLimits& limits) {
  if (const std::istream::pos_type start = report_start(in, path, limits);
      start != std::istream::pos_type(-1)) {
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

// Two reports read whole, a thread each: reading is most of diff's time. The old report's error,
// if both are bad, is the one said (as when read one after the other).
DiffResult diff_read_whole(std::istream& old_report, const std::string& old_path,
                           std::istream& new_report, const std::string& new_path,
                           const DiffOptions& options, const ReportLimits& limits) {
  std::future<diff::Report> old_facts =
      std::async(std::launch::async, [&] { return facts_of(old_report, old_path, limits); });
  std::exception_ptr new_failed;
  diff::Report new_facts;
  try {
    new_facts = facts_of(new_report, new_path, limits);
  } catch (...) {
    new_failed = std::current_exception();
  }
  diff::Report old_read = old_facts.get();
  if (new_failed) {
    std::rethrow_exception(new_failed);
  }
  return diff_facts(std::move(old_read), std::move(new_facts), options);
}

// What a report's reading thread hands over: everything before its records, then each record's
// facts; or Doubted, when the fast reader declines the report.
using StreamItem = std::variant<json, diff::RecordFacts>;
using StreamQueue = diff::BoundedQueue<StreamItem>;
using diff::Doubted;
using diff::doubted;

// The reading of a report in pldamp's layout, a record at a time into a queue.
diff::SideBySide<StreamItem>::Read stream_of(std::istream& in, const std::string& path,
                                             const ReportLimits& limits) {
  return [&in, &path, &limits](StreamQueue& queue) {
    if (!diff::stream_record_lines(
            in, path, limits, [&](json&& head) { queue.push(StreamItem(std::move(head))); },
            [&](diff::RecordFacts&& facts) { queue.push(StreamItem(std::move(facts))); })) {
      throw Doubted{};
    }
  };
}

// Two reports in pldamp's layout compared as they are read, a record of each at a time: the
// memory of `pldamp diff` does not grow with the reports (docs/scaling.md, "Diff at size"). None
// when either is not in that layout, or the fast reader doubts it: both are then read whole.
std::optional<DiffResult> diff_streamed(std::istream& old_report, const std::string& old_path,
                                        std::istream& new_report, const std::string& new_path,
                                        const DiffOptions& options, const ReportLimits& limits) {
  diff::SideBySide<StreamItem> reading(stream_of(old_report, old_path, limits),
                                       stream_of(new_report, new_path, limits));
  StreamQueue& old_queue = reading.old_queue();
  StreamQueue& new_queue = reading.new_queue();
  std::exception_ptr old_failed, new_failed, failed;
  const auto take = [](StreamQueue& queue, std::exception_ptr& failure) {
    std::optional<StreamItem> item;
    if (!failure) {
      try {
        item = queue.pop();
      } catch (...) {
        failure = std::current_exception();
      }
    }
    return item;
  };
  std::optional<Comparison> comparison;
  try {
    // Each stream's first item is its head, the next ones its records. After a failure of the
    // new report, the old one is read on, unjudged: its own error, if it has one, is said first.
    std::optional<StreamItem> old_item = take(old_queue, old_failed);
    std::optional<StreamItem> new_item = take(new_queue, new_failed);
    if (old_item && new_item) {
      comparison.emplace(std::get<json>(std::move(*old_item)), std::get<json>(std::move(*new_item)),
                         options);
    }
    while (!old_failed) {
      old_item = take(old_queue, old_failed);
      new_item = take(new_queue, new_failed);
      if (!old_item && !new_item) {
        break;
      }
      if (comparison && !new_failed) {
        const auto facts = [](std::optional<StreamItem>& item) {
          return item ? std::optional(std::get<diff::RecordFacts>(std::move(*item))) : std::nullopt;
        };
        comparison->take(facts(old_item), facts(new_item));
      }
    }
  } catch (...) {
    failed = std::current_exception();
  }
  reading.stop();
  if (failed) {
    std::rethrow_exception(failed);
  }
  if (old_failed && !doubted(old_failed)) {
    std::rethrow_exception(old_failed);
  }
  if ((old_failed && doubted(old_failed)) || (new_failed && doubted(new_failed))) {
    return std::nullopt;
  }
  if (new_failed) {
    std::rethrow_exception(new_failed);
  }
  return comparison->finish();
}

} // namespace

DiffResult diff_reports(const json& old_report, const json& new_report,
                        const DiffOptions& options) {
  return diff_facts(facts_of(old_report), facts_of(new_report), options);
}

DiffResult diff_reports(std::istream& old_report, const std::string& old_path,
                        std::istream& new_report, const std::string& new_path,
                        const DiffOptions& options, const ReportLimits& limits) {
  // Streamed when both can be read again from their start should the fast reader doubt them.
  const std::istream::pos_type unknown(-1);
  const std::istream::pos_type old_start = report_start(old_report, old_path, limits);
  std::istream::pos_type new_start = unknown;
  try {
    new_start = report_start(new_report, new_path, limits);
  } catch (const InputError&) {
    // Not a report: said once the old one is read, whose own error, if any, comes first.
  }
  if (old_start != unknown && new_start != unknown) {
    if (std::optional<DiffResult> streamed =
            diff_streamed(old_report, old_path, new_report, new_path, options, limits)) {
      return std::move(*streamed);
    }
    diff::read_again(old_report, old_start, old_path);
    diff::read_again(new_report, new_start, new_path);
  }
  return diff_read_whole(old_report, old_path, new_report, new_path, options, limits);
}

int diff_files(const std::string& old_path, const std::string& new_path, const DiffOptions& options,
               std::ostream& out) {
  std::ifstream old_report = diff::open_report(old_path);
  std::ifstream new_report = diff::open_report(new_path);
  const auto put = [&](const std::vector<std::string>& lines) {
    for (const std::string& line : lines) {
      out << line << "\n";
    }
  };
  if (options.exact) {
    const ExactResult result =
        diff_exact(old_report, old_path, new_report, new_path, options.verbose);
    put(result.lines);
    return result.differences > 0 ? 1 : 0;
  }
  const DiffResult result = diff_reports(old_report, old_path, new_report, new_path, options);
  put(result.lines);
  return result.regressions > 0 ? 1 : 0;
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
