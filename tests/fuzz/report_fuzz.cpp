// libFuzzer target: pldamp::harness::schema::read_report (common/report_schema.hpp), the reader of
// a report.json, on arbitrary bytes; when it accepts them, `regressions` between that report and
// itself and between it and a small valid report, both ways (what `pldamp diff OLD NEW` computes).
// An InputError (an std::invalid_argument) is the answer to bad input; any other exception escapes
// and aborts, and libFuzzer reports it with a crash, a hang (-timeout), a leak or an ASan/UBSan
// report. And diff's fast reader (judge/diff_read.cpp) on the same bytes: when it reads them, the
// general reader must read the same facts, and when it refuses them (too many values outside the
// records), say the same; and read_report of the bytes as a text and as a stream must agree
// (anything else aborts). Each with diff's limit of values kept, and with a small one.
//
// Build (Clang; float128 off, Clang has no GCC quadmath.h) and run, from the source tree:
//   CC=clang CXX=clang++ cmake -S . -B /tmp/build-fuzz -DPLDAMP_FUZZ=ON -DPLDAMP_WITH_QUAD=OFF \
//       -DPLDAMP_BUILD_TESTS=OFF -DPLDAMP_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
//   cmake --build /tmp/build-fuzz --target fuzz             # scene_fuzz and report_fuzz
//   tests/fuzz/run.sh /tmp/build-fuzz 60      # both, 60 s each, on a copy of tests/fuzz/corpus
//   F=/tmp/build-fuzz/tests/fuzz/report_fuzz; mkdir -p /tmp/report-corpus
//   $F -dict=tests/fuzz/report.dict /tmp/report-corpus tests/fuzz/corpus/report   # until Ctrl-C
//   $F tests/fuzz/corpus/report/crash-...                  # replays one input
#include "common/report_schema.hpp"
#include "judge/diff.hpp"
#include "judge/diff_parts.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace {

// A valid report (in a build with or without float128) with keys of records in corpus/report,
// so that a fuzzed report's records are found, gone, newly failed or grown against it, and a
// work-precision point checked against its records; each record consistent in itself
// (common/record_consistency.hpp). (Its schema must be schema::version: a report
// read_report refuses is compared with nothing.)
constexpr std::string_view other_text = R"({
  "schema": 3,
  "claims": [{"name": "seed Table II", "verdict": "holds"},
             {"name": "too tight", "verdict": "fails"}],
  "records": [
    {"key": "cvode-bdf rtol=1e-06 | p=1 e=0.9 v0=0.1 m=1 k=1", "precision": "double",
     "config": "cvode-bdf rtol=1e-06", "p": 1, "outcome": "exited", "failed": false,
     "value": {"e": 0.5000005, "delta_max": 0.25000005, "tau": 3},
     "reference": {"e": 0.5, "delta_max": 0.25, "tau": null},
     "error": {"e": 5e-07, "delta_max": 5e-08, "tau": null},
     "rel_error": {"e": 1e-06, "delta_max": 2e-07, "tau": null}},
    {"key": "taylor long | p=1.5 e=0.5 v0=1 m=1 k=1", "precision": "long",
     "outcome": "exited", "failed": false, "value": {"e": 0.5, "tau": 2},
     "reference": {"e": 0.5, "tau": 2}, "error": {"e": 5e-20, "tau": 0},
     "rel_error": {"e": 1e-19, "tau": 0}},
    {"key": "dem-verlet n=1 end=overlap phases=2 | p=1.5 z=1 v0=1 m=1 k=1",
     "precision": "double", "outcome": "exited", "failed": false, "phases": 2,
     "value": {"e": 0.55}, "reference": {"e": 0.5}, "error": {"e": 0.05},
     "rel_error": {"e": 0.1}},
    {"key": "verlet-predicted n=1000 | p=2.5 z=2 v0=10 m=1 k=1", "outcome": "no_exit",
     "failed": true, "rel_error": {}}
  ],
  "budgets": {"work_precision": [
    {"config": "cvode-bdf rtol=1e-06", "p": 1, "max_rel": 1e-06, "cells": 1, "skipped_cells": 0,
     "cells_without": 0, "by_observable": {"e": {"max_rel": 1e-06, "cells_without": 0},
                                           "tau": {"max_rel": null, "cells_without": 1}}}
  ]}
})";

// Refused, it would be compared with nothing, every run silently: that happened from schema 3 on
// until this check.
const nlohmann::json& other_report() {
  static const nlohmann::json report = [] {
    try {
      return pldamp::harness::schema::read_report(other_text, "other.json");
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "report_fuzz's own report is refused: %s\n", e.what());
      std::abort();
    }
  }();
  return report;
}

// What a reader made of the bytes: the report, or its message.
struct Read {
  pldamp::harness::diff::Report report;
  std::string error;
};

// The general reader of a stream (schema::read_report, then RecordFacts::of).
Read general_reading(std::string_view text, std::size_t max_values) {
  Read out;
  std::istringstream in{std::string(text)};
  try {
    out.report.rest = pldamp::harness::schema::read_report(
        in, "fuzz.json",
        [&](nlohmann::json&& record) {
          out.report.records.push_back(pldamp::harness::diff::RecordFacts::of(record));
        },
        max_values);
  } catch (const std::invalid_argument& e) {
    out.error = e.what();
  }
  return out;
}

void fail(const char* what, const std::string& detail = "") {
  std::fprintf(stderr, "%s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
  std::abort();
}

// The fast reader declines, or reads what the general reader reads, or says what it says (of a
// text outside the records beyond `max_values`, which it tells without the general reader).
void fast_reader_agrees(std::string_view text, std::size_t max_values) {
  using pldamp::harness::diff::describe;
  std::istringstream fast_in{std::string(text)};
  std::optional<pldamp::harness::diff::Report> fast;
  std::string fast_error;
  try {
    fast = pldamp::harness::diff::read_record_lines(fast_in, "fuzz.json", {.values = max_values});
  } catch (const std::invalid_argument& e) {
    fast_error = e.what();
  }
  if (!fast && fast_error.empty()) {
    return;
  }
  const Read general = general_reading(text, max_values);
  if (!fast_error.empty()) {
    if (general.error != fast_error) {
      fail("the fast reader refused a report otherwise than the general one", fast_error);
    }
    return;
  }
  if (!general.error.empty()) {
    fail("the fast reader read a report the general one refuses", general.error);
  }
  bool same =
      fast->records.size() == general.report.records.size() && fast->rest == general.report.rest;
  for (std::size_t i = 0; same && i < fast->records.size(); ++i) {
    same = describe(fast->records[i]) == describe(general.report.records[i]);
  }
  if (!same) {
    fail("the fast reader read other facts than the general one");
  }
}

// read_report of a text and of a stream (nlohmann reads each through its own input, and a NUL
// is found by each its own way): the same report, or the same message.
void text_and_stream_agree(std::string_view text, std::size_t max_values) {
  Read whole;
  try {
    const nlohmann::json report =
        pldamp::harness::schema::read_report(text, "fuzz.json", max_values);
    whole.report.rest = report;
    whole.report.rest["records"] = nlohmann::json::array();
    for (const nlohmann::json& record : report.at("records")) {
      whole.report.records.push_back(pldamp::harness::diff::RecordFacts::of(record));
    }
  } catch (const std::invalid_argument& e) {
    whole.error = e.what();
  }
  const Read streamed = general_reading(text, max_values);
  if (whole.error != streamed.error) {
    fail("read_report of a text and of a stream disagree", whole.error + " / " + streamed.error);
  }
  if (!whole.error.empty()) {
    return; // the stream's records read before its error were handed over
  }
  bool same = whole.report.rest == streamed.report.rest &&
              whole.report.records.size() == streamed.report.records.size();
  for (std::size_t i = 0; same && i < whole.report.records.size(); ++i) {
    same = pldamp::harness::diff::describe(whole.report.records[i]) ==
           pldamp::harness::diff::describe(streamed.report.records[i]);
  }
  if (!same) {
    fail("read_report of a text and of a stream read other reports");
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // With the limit of values diff applies, and with one a fuzzed report can reach.
  for (const std::size_t max_values : {pldamp::harness::schema::max_kept_values, std::size_t{40}}) {
    fast_reader_agrees(text, max_values);
    text_and_stream_agree(text, max_values);
  }
  nlohmann::json report;
  try {
    report = pldamp::harness::schema::read_report(text, "fuzz.json");
  } catch (const std::invalid_argument&) {
    return 0; // InputError: a damaged or foreign file, the expected answer
  }
  // read_report checked everything regressions reads: nothing may throw now but InputError.
  try {
    (void)pldamp::harness::regressions(report, report);
  } catch (const std::invalid_argument&) {
  }
  try {
    (void)pldamp::harness::regressions(other_report(), report);
  } catch (const std::invalid_argument&) {
  }
  try {
    (void)pldamp::harness::regressions(report, other_report());
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
