// The pieces of `pldamp diff` (judge/diff.hpp): the output grammar (findings gathered into
// groups, one line each; diff_findings.cpp), what two scenes do not share (diff.cpp), and the
// comparators of records (diff_records.cpp), budgets (diff_budgets.cpp), and claims and searches
// (diff_claims.cpp). Reports are read through common/report_schema.hpp: its keys, and its defensive
// readers for everything read_report did not check.
#pragma once

#include "common/report_schema.hpp"
#include "judge/diff.hpp"
#include "judge/match_by_key.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

namespace pldamp::harness::diff {

using nlohmann::json;
// A report read through its schema: its keys and words, and its defensive readers.
namespace key = schema::key;
namespace word = schema::word;
using schema::array_in;
using schema::member_or_null;
using schema::number_in;
using schema::string_in;

// A number of a report as diff reads it: a number, null, or absent (missing, or of another type).
struct Number {
  enum class State : std::uint8_t { absent, null, number };
  State state = State::absent;
  double value = 0;
  static Number in(const json& object, std::string_view key);
  std::optional<double> number() const {
    return state == State::number ? std::optional(value) : std::nullopt;
  }
};

// The fields of a record diff compares per observable, in the order of their names (the order a
// line lists them in).
inline constexpr std::array observed_fields{key::error, key::phase_spread, key::reference,
                                            key::rel_error, key::value};
inline constexpr std::size_t rel_error_field = 3;
static_assert(std::string_view(observed_fields[rel_error_field]) == key::rel_error);

// What diff keeps of a record, and no more: a nightly report holds 38 640 records, and two such
// reports as JSON trees took 560 MB.
struct RecordFacts {
  std::string key;
  // Its identity fields, each none when missing or of another type.
  std::optional<std::string> config, damping;
  std::optional<double> p, v0, m, k;
  std::string outcome, failure;
  bool failed = false;
  struct Observed {
    std::string name;
    std::array<Number, observed_fields.size()> fields;
  };
  std::vector<Observed> observed; // by name
  Number rhs_evals, steps;
  // Its time, fastest and slowest of the repeats: the thread's CPU time where the record has one
  // (pldamp's solvers), else the wall time (an external program's own).
  std::optional<double> seconds, seconds_slowest;
  bool cpu = false;

  static RecordFacts of(const json& record); // a record read_report checked
  std::optional<schema::RecordId> id() const;
  const Observed* find(const std::string& name) const;
};

// A report as diff reads it: everything but its records as read_report's tree, and its records'
// facts, in order.
struct Report {
  json rest;
  std::vector<RecordFacts> records;
};

// A record's facts on one line, each number in its shortest round-trip form and a zero with its
// sign: how tests tell whether two readers read the same (== cannot tell -0 from 0).
std::string describe(const RecordFacts& facts);

// A report.json in the layout pldamp writes (report_json_text: a record per line) read fast, its
// records parsed by simdjson (judge/diff_read.cpp); none when the input is in another layout, or
// anything in it is not as the general reader (schema::read_report, then RecordFacts::of) would
// read it, which then reads it and says what is wrong. Reads `in` to its end either way.
std::optional<Report> read_record_lines(std::istream& in, const std::string& path,
                                        const ReportLimits& limits = {});

// The same a record at a time, for a reader that holds none of them: `at_records` (if any) is
// given everything before the records, checked as read_report checks a report (its records
// empty), when the records begin; each record's line is handed to `each` (the line, its length
// without the comma, and its index; the line's buffer has room for simdjson's padding), which
// returns the hash of the record's key, or none when it doubts the line. Returns the text outside
// the records checked whole, or none when read_record_lines would: the caller then drops
// whatever it was handed, and the general reader reads the report again.
using HeadSink = std::function<void(json&& head)>;
using RecordLineSink = std::function<std::optional<std::size_t>(
    std::string& line, std::size_t length, std::size_t index)>;
std::optional<json> read_report_lines(std::istream& in, const std::string& path,
                                      const ReportLimits& limits, const HeadSink& at_records,
                                      const RecordLineSink& each);
// The report at `path`, opened to be read (InputError naming it when it cannot be).
std::ifstream open_report(const std::string& path);

// A stream put back at `start` (where its report begins) for the general reader, after the fast
// one declined it; InputError when it cannot be.
void read_again(std::istream& in, std::istream::pos_type start, const std::string& path);

// read_report_lines with each record read as read_record_lines reads it, its facts handed over.
std::optional<json> stream_record_lines(std::istream& in, const std::string& path,
                                        const ReportLimits& limits, const HeadSink& at_records,
                                        const std::function<void(RecordFacts&&)>& each);

enum class Severity { regression, change };

// One thing that changed. Findings of one kind (`what`), owner (a configuration, claim or
// search) and subject (an observable, a field) make a group, one line of output.
struct Finding {
  Severity severity = Severity::regression;
  std::string what{}, owner{}, subject{}, unit{};
  double rank = 0; // larger: worse (the group shows its largest)
  // worst: "old -> new", cell: where, detail: a verbose line
  std::string worst{}, cell{}, detail{};
};

// Findings gathered into groups; each group remembers its worst member.
class Findings {
public:
  // `keep_details`: each finding's line kept for --verbose (which then holds one per finding);
  // without it a group holds its worst finding and a count, whatever the reports' size.
  explicit Findings(bool keep_details = true) : keep_details_(keep_details) {}
  void add(Finding finding);
  // Each group's line, regressions first, and with `verbose` every finding under its group.
  void write(DiffResult& result, bool verbose) const;

private:
  struct Group {
    Finding worst;
    long count;
    std::vector<std::string> details;
  };
  bool keep_details_;
  std::vector<Group> groups_;
  std::map<std::tuple<Severity, std::string, std::string, std::string>, std::size_t> index_;
};

// A field of an output line as text a script can split: one line (common/input.hpp: a name with
// a line break cannot forge a line of its own) and, unless kept (a verbose line's record key),
// the field separator " | " written " / ".
std::string field_text(std::string_view text, bool keep_separators = false);
// "3e-06" and " (x100)": a number as the lines show it, and the factor from one to another.
std::string number_text(double x);
std::string factor_text(double before, double after);

// 16 ε of a record's precision: below it a tenfold change is rounding, not a regression.
double precision_noise(const std::string& precision);

// Noise per configuration label: 16 ε of its precision (double where unknown).
class Noise {
public:
  explicit Noise(const json& report);
  double of(const std::string& label) const;

private:
  std::map<std::string, double> by_label_;
};

// An error (or a claim's error-like measurement) from `before` to `after`: grown more than the
// factor above the noise, or vanished to 0 from above it, is a regression; fallen by more than
// the factor, a change. Else nothing.
void compare_error(Findings& findings, const Finding& base, double before, double after,
                   double noise, double factor);

// Numbers that were there and are not (regressions), and nulls that became numbers (changes):
// one finding for a subject (an observable, a count), however many of its fields went. Each
// field: its name, its value before, and the number it holds now (none: null or missing).
struct FieldNow {
  std::string_view field;
  Number before;
  std::optional<double> after;
};
void compare_fields(Findings& findings, const Finding& base, const std::string& subject,
                    const std::vector<FieldNow>& fields);
// The same of JSON: `was` and `now` map a subject to its fields' values; none for a subject the
// new scene removed.
void compare_numbers(Findings& findings, const Finding& base, const json& was, const json& now,
                     const std::set<std::string>& removed = {});

// One field of an object as compare_numbers reads it: {subject: {field: value}}.
json field_of(const json& object, const std::string& subject, const std::string& field);

// What one scene has that the other lacks: configurations, grid values, claims.
struct SceneChange {
  std::vector<std::string> lines;
  std::set<std::string> removed_configs, removed_claims, removed_observables;
  std::map<std::string, std::set<std::string>> removed_values; // axis -> values as text
};
SceneChange scene_change(const json& old_report, const json& new_report);

// Per observable, the largest relative error of some records (an observable a record has, even
// as null, is there).
using LargestErrors = std::map<std::string, std::optional<double>>;
// What the budgets of the new report are held to of its records: the largest errors per
// configuration (budgets.worst) and per configuration and p (a work-precision point).
struct RecordsLargest {
  std::map<std::string, LargestErrors> by_config;
  std::map<std::pair<std::string, std::optional<double>>, LargestErrors> by_config_and_p;
  void take(const RecordFacts& record);
};

// A configuration's time on each night: the sums of its records' fastest and slowest repeats.
struct TimeSums {
  double before = 0, before_slowest = 0, after = 0, after_slowest = 0;
  long records = 0;
  bool cpu = true; // every record timed by its thread's CPU clock, on both nights
};

// The comparator of records (errors, numbers, outcomes, work, time), fed the records of both
// reports as they are read, paired by key (judge/match_by_key.hpp).
class RecordComparison {
public:
  RecordComparison(Findings& findings, const SceneChange& change, Noise noise,
                   const DiffThresholds& t);
  // The next record of each report (none where it has ended).
  void take(std::optional<RecordFacts> was, std::optional<RecordFacts> now);
  // After the last record of each: old records without a new one (gone), and each
  // configuration's time.
  void finish();
  const RecordsLargest& new_largest() const { return new_largest_; }
  // The most records that waited at once for the other report's record of their key.
  std::size_t most_waiting() const { return matched_.most_waiting(); }

private:
  void compare(const RecordFacts& was, const RecordFacts& now);
  Findings& findings_;
  const SceneChange& change_;
  Noise noise_;
  DiffThresholds t_;
  MatchByKey<RecordFacts> matched_;
  std::map<std::string, TimeSums> time_; // per configuration
  std::vector<std::string> time_order_;  // its configurations in the old report's order
  RecordsLargest new_largest_;
};

// The other comparators: budgets (budgets.worst, work-precision points and the analytic layer,
// each also against the new report's own records), claims and searches.
void compare_budgets(Findings& findings, const json& old_report, const json& new_report,
                     const RecordsLargest& new_records, const SceneChange& change,
                     const DiffThresholds& t);
void compare_claims(Findings& findings, const json& old_report, const json& new_report,
                    const SceneChange& change, const DiffThresholds& t);

} // namespace pldamp::harness::diff
