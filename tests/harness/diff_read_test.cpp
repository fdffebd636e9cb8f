// diff's fast reader (judge/diff_read.cpp) against the general one (schema::read_report, then
// RecordFacts::of): on pldamp's layout, odd records included, both read the same facts; on any
// other layout, or a damaged report, the fast one declines and diff says what the general reader
// says. tests/fuzz/report_fuzz.cpp compares the two on arbitrary bytes.
#include "fixtures.hpp"

#include "common/report_schema.hpp"
#include "judge/diff.hpp"
#include "judge/diff_parts.hpp"
#include "report/report.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <sstream>
#include <streambuf>

namespace pldamp::harness {
namespace {

using namespace testing;

std::string report_text() {
  const HandMade h = hand_made();
  const Budgets b = make_budgets(h.plan, h.records);
  return report_json_text({h.plan, h.records, b, RunTotals{400, 4, 1.0, {}}, {}});
}

// What the general reader makes of a text (its message when it refuses it).
struct General {
  diff::Report report;
  std::string error;
};
General general(const std::string& text) {
  General out;
  std::istringstream in(text);
  try {
    out.report.rest = schema::read_report(in, "r.json", [&](nlohmann::json&& record) {
      out.report.records.push_back(diff::RecordFacts::of(record));
    });
  } catch (const InputError& e) {
    out.error = e.what();
  }
  return out;
}

// Every record's facts, a line each (diff::describe tells -0 from 0).
std::vector<std::string> described(const diff::Report& report) {
  std::vector<std::string> out;
  for (const diff::RecordFacts& record : report.records) {
    out.push_back(diff::describe(record));
  }
  return out;
}

std::optional<diff::Report> fast(const std::string& text) {
  std::istringstream in(text);
  return diff::read_record_lines(in, "r.json");
}

TEST(DiffReader, ReadsPldampsLayoutAsTheGeneralReaderDoesOddRecordsIncluded) {
  const std::string text = report_text();
  {
    const General g = general(text);
    ASSERT_EQ(g.error, "");
    ASSERT_GE(g.report.records.size(), 3u);
    const std::optional<diff::Report> f = fast(text);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(described(*f), described(g.report));
    EXPECT_EQ(f->rest, g.report.rest);
  }
  // Records read_report accepts, each in the place of the second: escapes and non-ASCII text, a
  // negative zero, integers beyond 2^53 and 2^64 where a field is not a count, identity fields of
  // the wrong type, null and string numbers, counts and times at their bounds, a wall time alone,
  // unknown members, a deep value; numbers at the edges of what agrees (subnormals, an error
  // below the value's rounding, τ = ∞ written as null, e compared absolutely on a late return,
  // several phases, a replica's difference).
  const std::vector<std::string> odd = {
      R"({"key":"a \"quoted\" \u00e9 key\\","outcome":"exited","failed":false,"rel_error":{"e":null,"tau":0},"p":-0,"v0":"fast","value":{"e":-0.0,"tau":2,"t_peak":"x"},"reference":{"tau":2},"error":{"tau":0},"steps":12,"rhs_evals":null})",
      R"({"key":"k","outcome":"exited","failed":false,"rel_error":{"e":1},"value":{"e":2},"reference":{"e":1},"error":{"e":1},"config":"c","steps":-0,"rhs_evals":9007199254740992,"cpu_seconds":0,"cpu_seconds_slowest":null,"wall_seconds":-0.0,"wall_seconds_slowest":1e-300})",
      R"({"key":"k","outcome":"exited","failed":true,"rel_error":{},"v0":18446744073709551615,"p":9007199254740993,"m":1e308,"k":123456789012345678901234567890})",
      R"({"key":"k","outcome":"exited","failed":false,"rel_error":{"e":1e-300,"tau":0.6666666666666666},"value":{"e":1,"tau":5},"reference":{"e":1,"tau":3},"error":{"e":1e-300,"tau":2},"precision":"long","steps":0})",
      R"({"key":"k","outcome":"no_exit","failed":true,"rel_error":{"e":0.5},"value":{"e":0},"reference":{"e":0.5},"error":{"e":-0.5},"wall_seconds":0.5,"wall_seconds_slowest":0.75,"damping":7,"config":null,"failure":"why"})",
      R"({"key":"k","outcome":"exited","failed":false,"rel_error":{"e":2.5},"value":{"e":3.5},"error":{"e":2.5},"cpu_seconds":1,"wall_seconds":3,"extra":[[[[{"a":[1,2,{"b":null,"c":{}}],"d":{"a":1}}]]]],"phase_spread":[1],"reference":{"e":1,"tau":true}})",
      R"({"failed":false,"rel_error":{"e":3},"outcome":"exited","key":"fields in another order","p":1.5,"v0":2,"m":3,"k":4,"damping":"e=0.5","config":"taylor","value":{"e":4},"reference":{"e":1},"error":{"e":3}})",
      R"({"key":"zeros","outcome":"exited","failed":false,"rel_error":{"e":0.0,"tau":-0.0,"t_peak":0,"delta_max":5e-324,"energy_load":2e-323},"value":{"e":0.5,"tau":1,"t_peak":1,"delta_max":1,"energy_load":0.25},"reference":{"e":0.5,"tau":1,"t_peak":1,"delta_max":1,"energy_load":0.25},"error":{"e":-0.0,"tau":-0,"t_peak":-0e0,"delta_max":4.9e-325,"energy_load":5e-324},"p":-0.0})",
      R"({"key":"never ends","outcome":"no_exit","failed":false,"rel_error":{"e":0,"tau":0},"value":{"e":0,"tau":null},"reference":{"e":0,"tau":null},"error":{"e":0,"tau":0}})",
      R"({"key":"phases","outcome":"exited","failed":false,"phases":16,"rel_error":{"e":0.5},"value":{"e":0},"reference":{"e":0.5},"error":{"e":-0.5},"phase_spread":{"e":0.5},"replica_difference":{"e":0,"tau":null}})",
  };
  for (const std::string& record : odd) {
    SCOPED_TRACE(record);
    const std::string edited = with_record_line(text, 1, record);
    const General g = general(edited);
    ASSERT_EQ(g.error, "");
    const std::optional<diff::Report> f = fast(edited);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(described(*f), described(g.report));
    EXPECT_EQ(f->rest, g.report.rest);
  }
  // Spot checks of the facts themselves, against values known independently of both readers.
  const std::optional<diff::Report> f = fast(with_record_line(text, 1, odd[2]));
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->records[1].v0, 18446744073709551616.0);
  EXPECT_EQ(f->records[1].p, 9007199254740992.0); // 2^53 + 1 rounds to even
  EXPECT_EQ(f->records[1].k, 1.2345678901234568e29);
  const std::optional<diff::Report> bounds = fast(with_record_line(text, 1, odd[1]));
  ASSERT_TRUE(bounds.has_value());
  EXPECT_EQ(diff::describe(bounds->records[1]),
            R"(key="k" config="c" damping=none p=none v0=none m=none k=none outcome="exited" )"
            R"(failure="" failed=false rhs_evals=9007199254740992 steps=0 cpu=true seconds=0 )"
            R"(slowest=none "e": 1 absent 1 1 2)");
  const std::optional<diff::Report> zeros = fast(with_record_line(text, 1, odd[7]));
  ASSERT_TRUE(zeros.has_value());
  EXPECT_EQ(diff::describe(zeros->records[1]),
            R"(key="zeros" config=none damping=none p=-0 v0=none m=none k=none outcome="exited" )"
            R"(failure="" failed=false rhs_evals=absent steps=absent cpu=false seconds=none )"
            R"(slowest=none "delta_max": 0 absent 1 5e-324 1 "e": -0 absent 0.5 0 0.5 )"
            R"("energy_load": 5e-324 absent 0.25 2e-323 0.25 "t_peak": -0 absent 1 0 1 )"
            R"("tau": 0 absent 1 -0 1)");
  const std::optional<diff::Report> g = fast(with_record_line(text, 1, odd[4]));
  ASSERT_TRUE(g.has_value());
  EXPECT_FALSE(g->records[1].cpu);
  EXPECT_EQ(g->records[1].seconds, 0.5);
  EXPECT_EQ(g->records[1].seconds_slowest, 0.75);
  EXPECT_EQ(g->records[1].failure, "why");
  EXPECT_FALSE(g->records[1].config.has_value());
}

TEST(DiffReader, OtherLayoutsAndDamagedReportsAreLeftToTheGeneralReader) {
  const std::string text = report_text();
  const nlohmann::json tree = nlohmann::json::parse(text);
  struct Case {
    std::string name, text, error; // error: the general reader's message, "" when it reads it
  };
  // A "records" line inside another member, the top level's records empty.
  std::string nested = text;
  nested.erase(nested.rfind("\n \"records\": [\n"));
  nested += "\n \"records\": []\n}\n";
  nested.insert(nested.find("\n \"scene\": {"),
                "\n \"junk\": {\"x\": 1,\n \"records\": [\n  {\"key\":\"k\",\"outcome\":\"exited\","
                "\"failed\":false,\"rel_error\":{}}\n ]},");
  std::string trailing_comma = text;
  trailing_comma.replace(trailing_comma.rfind("}\n ]"), 3, "},\n ");
  std::string two_on_a_line = text;
  two_on_a_line.replace(two_on_a_line.find("},\n  {\"key\""), 5, "}, ");
  std::string older = text;
  older.replace(older.find("\"schema\": 3"), 11, "\"schema\": 2");
  // A NUL ends nlohmann's input (simdjson refuses it): after a record, and after a whole report.
  std::string nul_after_record = with_record_line(
      text, 0,
      std::string(R"({"key":"k","outcome":"exited","failed":false,"rel_error":{}})") + '\0' +
          " garbage ]]] {{");
  const std::string nul_between =
      std::string(R"({"schema":3,"claims":[],"records":[]})") + '\0' + "{\n \"records\": [\n  " +
      R"({"key":"k1","outcome":"exited","failed":false,"rel_error":{"e":1}})" + "\n ]\n}\n";
  // A top-level member named twice: the tree keeps the last one, the records handed over were the
  // first one's (read before the schema, or dropped as another schema's).
  const std::string record = R"({"key":"k","outcome":"exited","failed":false,"rel_error":{}})";
  const std::string records_twice = "{\n \"claims\": [],\n \"records\": [\n  " + record +
                                    "\n ],\n \"schema\": 3,\n \"re\\u0063ords\": []\n}\n";
  const std::string schema_twice = "{\n \"schema\": 2,\n \"claims\": [],\n \"records\": [\n  " +
                                   record + "\n ],\n \"schema\": 3\n}\n";
  std::string crlf;
  for (const char c : text) {
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  }
  // A record line twice: diff compared one of them, and never saw the other.
  std::string record_twice = with_record_line(text, 2, record_line(text, 1));
  std::string claim_twice = text;
  claim_twice.replace(claim_twice.find("\"verdict\":"), 10, "\"name\": \"x\", \"verdict\":");
  const std::string key_of_1 = nlohmann::json::parse(record_line(text, 1))["key"];
  const auto damaged = [&](const std::string& fields) {
    return with_record_line(
        text, 1, R"({"key":"k","outcome":"exited","failed":false,"rel_error":{})" + fields + "}");
  };
  // A key named twice 1000 levels down: the message says where in its first 200 characters.
  std::string deep_where = "r.json: records[1].x";
  while (deep_where.size() <= 200 + 8) { // "r.json: " is not part of the place
    deep_where += "[0]";
  }
  const std::string deep = std::string(1000, '[') + R"({"a":1,"a":2})" + std::string(1000, ']');
  const std::vector<Case> cases = {
      {"pretty-printed", tree.dump(2), ""},
      {"on one line", tree.dump(), ""},
      {"CRLF line ends", crlf, ""},
      {"two records on a line", two_on_a_line, ""},
      {"records nested in another member", nested, ""},
      {"damaged record",
       with_record_line(text, 1,
                        R"({"key":"k","outcome":"exited","failed":false,"rel_error":{"e":-1}})"),
       "r.json: records[1].rel_error.e must be null or a number >= 0 (got -1)"},
      {"failed not a boolean",
       with_record_line(text, 0, R"({"key":"k","outcome":"exited","failed":0,"rel_error":{}})"),
       "r.json: records[0].failed must be true or false (got 0)"},
      {"another schema", older, "r.json: report schema 2 is not 3"},
      {"a NUL after a record", nul_after_record, "not a JSON report (got r.json)"},
      // nlohmann's lexer ends its input at a NUL: a NUL and what follows it were accepted where
      // any other text after the report is refused.
      {"a NUL after a whole report", nul_between, "not a JSON report (got r.json)"},
      {"a NUL after pldamp's report", text + '\0', "not a JSON report (got r.json)"},
      {"a NUL and text after it", text + '\0' + "}}", "not a JSON report (got r.json)"},
      {"records named twice", records_twice, "r.json: the report names records twice"},
      {"schema named twice", schema_twice, "r.json: the report names schema twice"},
      {"a trailing comma", trailing_comma, "not a JSON report (got r.json)"},
      {"cut short", text.substr(0, text.size() / 2), "not a JSON report (got r.json)"},
      // A key named twice, which nlohmann reads as its last value.
      {"a record's field named twice", damaged(R"(,"rel_error":{"e":1})"),
       "r.json: records[1] names rel_error twice"},
      {"an observable named twice", damaged(R"(,"error":{"e":1,"tau":2,"e":3})"),
       "r.json: records[1].error names e twice"},
      {"a key named twice deep in a record", damaged(R"(,"x":[0,{"y":[{"a\n":1,"a\n":2}]}])"),
       "r.json: records[1].x[1].y[0] names a\\n twice"},
      {"a key named twice under an observed field", damaged(R"(,"value":[{"a":1,"a":2}])"),
       "r.json: records[1].value[0] names a twice"},
      {"a key named twice 1000 levels down", damaged(",\"x\":" + deep),
       deep_where + "... names a twice"},
      {"a key named twice outside the records", claim_twice, "r.json: claims[0] names name twice"},
      {"a record line twice", record_twice,
       "r.json: records[2] has the key of records[1] (" + key_of_1 + ")"},
      // Counts and times diff compares, impossible: "-5" became "CHANGE 120 -> -5", 1.5 was shown
      // as 2, and a negative or textual time left the time unjudged.
      {"a negative count", damaged(R"(,"rhs_evals":-5)"),
       "r.json: records[1].rhs_evals must be null or a whole number from 0 to 2^53 (got -5)"},
      {"a count with a fraction", damaged(R"(,"steps":1.5)"),
       "r.json: records[1].steps must be null or a whole number from 0 to 2^53 (got 1.5)"},
      {"a count as a float", damaged(R"(,"steps":120.0)"),
       "r.json: records[1].steps must be null or a whole number from 0 to 2^53 (got 120.0)"},
      {"the least integer as a count", damaged(R"(,"rhs_evals":-9223372036854775808)"),
       "r.json: records[1].rhs_evals must be null or a whole number from 0 to 2^53 (got "
       "-9223372036854775808)"},
      {"a count beyond 2^53", damaged(R"(,"rhs_evals":9007199254740993)"),
       "r.json: records[1].rhs_evals must be null or a whole number from 0 to 2^53 (got "
       "9007199254740993)"},
      {"a count as text", damaged(R"(,"steps":"12")"),
       "r.json: records[1].steps must be null or a whole number from 0 to 2^53 (got \"12\")"},
      {"a negative time", damaged(R"(,"cpu_seconds":-1e-9)"),
       "r.json: records[1].cpu_seconds must be null or a number >= 0 (got -1e-09)"},
      {"a time as text", damaged(R"(,"cpu_seconds":"fast")"),
       "r.json: records[1].cpu_seconds must be null or a number >= 0 (got \"fast\")"},
      {"a slowest time negative", damaged(R"(,"wall_seconds":1,"wall_seconds_slowest":-2)"),
       "r.json: records[1].wall_seconds_slowest must be null or a number >= 0 (got -2)"},
      {"not JSON in a record",
       with_record_line(text, 0,
                        R"({"key":"k","outcome":"exited","failed":false,"rel_error":{}})"
                        "x"),
       "not a JSON report (got r.json)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const General g = general(c.text);
    EXPECT_EQ(g.error, c.error);
    const std::optional<diff::Report> f = fast(c.text);
    if (!c.error.empty()) {
      EXPECT_FALSE(f.has_value());
      // diff of a stream says what the general reader says.
      std::istringstream old_text(c.text), new_text(text);
      try {
        (void)diff_reports(old_text, "r.json", new_text, "new.json");
        ADD_FAILURE() << "read";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), c.error);
      }
    } else if (f) { // read fast only when it reads the same
      EXPECT_EQ(described(*f), described(g.report));
      EXPECT_EQ(f->rest, g.report.rest);
    }
  }
}

// A stream that cannot seek (a pipe): read by the general reader alone, the same diff.
class Unseekable : public std::streambuf {
public:
  explicit Unseekable(std::string text) : text_(std::move(text)) {
    setg(text_.data(), text_.data(), text_.data() + text_.size());
  }

private:
  std::string text_;
};

TEST(DiffReader, DiffOfStreamsEqualsDiffOfTreesSeekableOrNot) {
  const std::string text = report_text();
  nlohmann::json worse = nlohmann::json::parse(text);
  set_rel_error(worse["records"][0], "delta_max", 3e-4);
  worse["records"][2]["failed"] = true;
  DiffOptions verbose;
  verbose.verbose = true;
  const DiffResult trees = diff_reports(nlohmann::json::parse(text), worse, verbose);
  ASSERT_GE(trees.regressions, 2);
  std::istringstream old_text(text), new_text(worse.dump());
  EXPECT_EQ(diff_reports(old_text, "old.json", new_text, "new.json", verbose).lines, trees.lines);
  Unseekable old_buffer(text), new_buffer(worse.dump());
  std::istream old_stream(&old_buffer), new_stream(&new_buffer);
  ASSERT_EQ(old_stream.tellg(), std::istream::pos_type(-1));
  EXPECT_EQ(diff_reports(old_stream, "old.json", new_stream, "new.json", verbose).lines,
            trees.lines);
}

// Two reports in pldamp's layout are compared as they are read, a record of each at a time: the
// lines are those of the reports read whole, their records in one order or not, gone or added;
// two reports in one order hold no record waiting. Before, diff held every record of both
// (770 MB for a 10^6-run map's report against itself, docs/scaling.md "Diff at size").
TEST(DiffReader, ReportsInPldampsLayoutAreComparedAsTheyAreRead) {
  const std::string text = report_text();
  std::vector<std::string> lines;
  for (std::size_t i = 0; !record_line(text, i).empty(); ++i) {
    lines.push_back(record_line(text, i));
  }
  ASSERT_EQ(lines.size(), 4u);
  nlohmann::json worse_record = nlohmann::json::parse(lines[1]);
  set_rel_error(worse_record, "delta_max", 3e-4);
  std::vector<std::string> worse = lines;
  worse[1] = worse_record.dump();
  const std::vector<std::string> reversed(lines.rbegin(), lines.rend());
  const std::vector<std::string> one_gone{lines[0], lines[2], lines[3]};
  const std::vector<std::string> swapped{lines[1], lines[0], lines[3], lines[2]};
  DiffOptions verbose;
  verbose.verbose = true;
  struct Case {
    std::string name;
    std::vector<std::string> old_lines, new_lines;
    std::size_t held; // when streamed
  };
  // Held when streamed: none in the plan order (each pair compared as it comes), and as many as
  // wait out of step (read one of each in turn: the reversed report's first two of each wait for
  // their matches; a record gone or added holds its neighbours a pair each).
  for (const Case& c : {Case{"itself", lines, lines, 0}, Case{"worse", lines, worse, 0},
                        Case{"better", worse, lines, 0}, Case{"reversed", lines, reversed, 4},
                        Case{"one gone", lines, one_gone, 2}, Case{"one added", one_gone, lines, 2},
                        Case{"swapped", swapped, lines, 2}}) {
    const std::string old_text = with_records(text, c.old_lines);
    const std::string new_text = with_records(text, c.new_lines);
    const DiffResult trees =
        diff_reports(nlohmann::json::parse(old_text), nlohmann::json::parse(new_text), verbose);
    EXPECT_EQ(trees.records_held, c.old_lines.size() + c.new_lines.size()) << c.name;
    std::istringstream old_in(old_text), new_in(new_text);
    const DiffResult streamed = diff_reports(old_in, "old.json", new_in, "new.json", verbose);
    EXPECT_EQ(streamed.lines, trees.lines) << c.name;
    EXPECT_EQ(streamed.records_held, c.held) << c.name;
  }
  // What the cases found, that the comparison above is not of two empty lists.
  std::istringstream old_in(text), new_in(with_records(text, one_gone));
  const DiffResult gone = diff_reports(old_in, "old.json", new_in, "new.json");
  // The record gone, and the new report's budgets held to the records that streamed past.
  ASSERT_EQ(gone.regressions, 3) << ::testing::PrintToString(gone.lines);
  EXPECT_TRUE(gone.lines[0].starts_with("REGRESSION record_gone | ")) << gone.lines[0];
  EXPECT_TRUE(gone.lines[1].starts_with("REGRESSION budget_inconsistent | ")) << gone.lines[1];
  EXPECT_TRUE(gone.lines[2].starts_with("REGRESSION work_precision_inconsistent | "))
      << gone.lines[2];
}

} // namespace
// What cannot be a report is refused by what diff reads first, and nothing it reads is held whole
// beyond its limits (diff.hpp, ReportLimits; small ones here, the command's in Cli tests): blanks
// before the report (1 GB of them took 36 s and 3.2 GB before "not a JSON report"), a line
// longer than the limit, a text outside the records beyond it.
TEST(DiffReader, WhatCannotBeAReportIsRefusedByItsFirstBytesAndHeldWithinBounds) {
  const std::string good = report_text();
  const std::string one_line_report = nlohmann::json::parse(good).dump();
  const ReportLimits limits{
      .leading_space = 64, .line = 4096, .rest = std::max(good.size(), one_line_report.size())};
  const auto diff_of = [&](const std::string& text) -> std::string {
    std::istringstream old_in(text), new_in(good);
    try {
      (void)diff_reports(old_in, "bad.json", new_in, "good.json", {}, limits);
    } catch (const InputError& e) {
      return e.what();
    }
    return "read";
  };
  ASSERT_LT(good.find("\n  {"), limits.line) << "a record line within the limit";
  EXPECT_EQ(diff_of(good), "read");
  EXPECT_EQ(diff_of(std::string(64, ' ') + good), "read");
  EXPECT_EQ(diff_of(std::string(65, ' ') + good), "not a JSON report (got bad.json)");
  EXPECT_EQ(diff_of(std::string(1 << 20, '\0')), "not a JSON report (got bad.json)");
  EXPECT_EQ(diff_of("[" + good + "]"), "not a JSON report (got bad.json)");
  // Blank lines are not kept by the fast reader: a report with 10^4 of them reads, its rest
  // within the limit.
  std::string blank_lines = good;
  blank_lines.insert(2, std::string(10000, '\n'));
  EXPECT_EQ(diff_of(blank_lines), "read");
  // A report on one line: the fast reader stops at the limit; the general reader reads it, as
  // long as it is within the rest's limit in all.
  ASSERT_EQ(one_line_report.find('\n'), std::string::npos);
  ASSERT_GT(one_line_report.size(), limits.line);
  std::istringstream long_line(one_line_report);
  EXPECT_FALSE(diff::read_record_lines(long_line, "r.json", limits));
  EXPECT_EQ(diff_of(one_line_report), "read");
  EXPECT_EQ(diff_of(one_line_report + std::string(limits.rest, ' ')),
            fmt::format("bad.json: not in the layout pldamp writes (a record a line) and larger "
                        "than {} MiB: diff reads such a report up to that size",
                        double(limits.rest) / (1 << 20)));
  // Text outside the records beyond the limit, in pldamp's layout: refused as it is read.
  std::string padded = good;
  for (std::size_t i = 0; i <= limits.rest / 1000; ++i) { // lines within the line's limit
    padded.insert(2, fmt::format(" \"x{}\": \"{}\",\n", i, std::string(1000, 'x')));
  }
  EXPECT_EQ(diff_of(padded), fmt::format("bad.json: its text outside the records is larger than {} "
                                         "MiB: not a report pldamp wrote",
                                         double(limits.rest) / (1 << 20)));
}

namespace {

// The values and keys of a JSON tree, each counted once, as read_report counts what it keeps.
std::size_t values_and_keys(const nlohmann::json& j) {
  std::size_t count = 1;
  if (j.is_object()) {
    for (const auto& [name, value] : j.items()) {
      count += 1 + values_and_keys(value);
    }
  } else if (j.is_array()) {
    for (const nlohmann::json& item : j) {
      count += values_and_keys(item);
    }
  }
  return count;
}

} // namespace

// nlohmann's callback parser, which read_report used, looked through an object's parent at each
// object's end: 100 000 `{}` in an array outside the records took 1.5 s, 200 000 5.6 s, 400 000
// 22 s (a map of 10^6 points holds such arrays). Read by its own SAX handler, linearly.
TEST(ReportReader, ReadsAnArrayOfManyObjects) {
  // Its time, linear in the objects (20 s for these before, 0.05 s since), is harness_bench's
  // report_objects: a test does not time.
  std::string text = report_text();
  std::string objects = " \"x\": [{}";
  for (int i = 1; i < 300000; ++i) {
    objects += ",{}";
  }
  text.insert(2, objects + "],\n");
  const nlohmann::json report = schema::read_report(text, "r.json");
  EXPECT_EQ(report["x"].size(), 300000u);
}

// The tree of the text outside the records takes up to about 100 bytes a value or key, where its
// text takes 2 (a 100 MB report of zeros took 2 GB): read_report keeps at most so many, and diff
// says the same with either reader. Records read before the schema are kept, and count.
TEST(ReportReader, KeepsAtMostItsLimitOfValuesAndKeysOutsideTheRecords) {
  const std::string text = report_text();
  const nlohmann::json tree = nlohmann::json::parse(text);
  std::size_t in_records = 0;
  for (const nlohmann::json& record : tree["records"]) {
    in_records += values_and_keys(record);
  }
  const std::size_t outside = values_and_keys(tree) - in_records;
  const auto refusal = [](std::size_t limit) {
    return fmt::format("r.json: its text outside the records holds more than {} JSON values and "
                       "keys (records before its schema count too): not a report pldamp wrote",
                       limit);
  };
  const auto read = [](const std::string& report, std::size_t limit) -> std::string {
    try {
      (void)schema::read_report(report, "r.json", limit);
    } catch (const InputError& e) {
      return e.what();
    }
    return "read";
  };
  EXPECT_EQ(read(text, outside), "read");
  EXPECT_EQ(read(text, outside - 1), refusal(outside - 1));
  const std::string sorted = tree.dump(); // records before the schema
  ASSERT_LT(sorted.find("\"records\""), sorted.find("\"schema\""));
  EXPECT_EQ(read(sorted, outside + in_records), "read");
  EXPECT_EQ(read(sorted, outside + in_records - 1), refusal(outside + in_records - 1));
  // diff, of pldamp's layout (the fast reader) and of another (the general one), the schema first.
  for (const std::string& report : {text, nlohmann::ordered_json::parse(text).dump(1)}) {
    for (const std::size_t limit : {outside, outside - 1}) {
      std::istringstream old_in(report), new_in(report);
      std::string said = "read";
      try {
        (void)diff_reports(old_in, "r.json", new_in, "new.json", {}, {.values = limit});
      } catch (const InputError& e) {
        said = e.what();
      }
      EXPECT_EQ(said, limit == outside ? "read" : refusal(limit));
    }
  }
  std::istringstream in(text);
  EXPECT_THROW((void)diff::read_record_lines(in, "r.json", {.values = outside - 1}), InputError)
      << "said by the fast reader itself, never read again";
}

} // namespace pldamp::harness
