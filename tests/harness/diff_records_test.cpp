// diff holds each record of a report to itself (common/record_consistency.hpp), as merge holds a
// shard's: a record whose error, value, reference and relative error disagree beyond the rounding
// of their printed digits, whose outcome is unknown, or whose failed flag, values or ranges its
// outcome contradicts is refused with one line naming the file, the record and what is
// inconsistent (exit 2), read fast (pldamp's layout) or by the general reader (another layout).
// Before, diff judged a record by its rel_error alone: an error of 1e300 or 0, a value of 1e300 or
// an outcome "weird" gave "0 regressions, 0 changes", exit 0. A real report is read, and diffs
// cleanly against itself.
#include "fixtures.hpp"

#include "judge/diff.hpp"
#include "judge/diff_parts.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pldamp::harness {
namespace {

using namespace testing;
using nlohmann::ordered_json;

// A real report's text: `pldamp run` of an underdamped and an overdamped point (τ never ends:
// null, beside an error 0) by an error-controlled solver and by a fixed-step one over 4 onset
// phases.
const std::string& real_report() {
  static const std::string text = [] {
    const std::string scene = write_file("held.toml", R"(name = "held to itself"
want = ["e", "delta_max", "t_peak", "tau", "energy"]
[grid]
p = [1.5]
e = [0.5]
alpha_eff = [2.0]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-8
[[solver]]
name = "dem-verlet"
steps_per_contact = [50]
onset_phases = 4
)");
    const fs::path out = scratch() / "held";
    fs::remove_all(out);
    const CliRun ran = run({"run", scene, "--out", out.string()});
    if (ran.code != 0) {
      throw std::runtime_error("the scene did not run: " + ran.err);
    }
    std::ifstream in(out / "report.json");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  return text;
}

// The report's records, as written.
std::vector<ordered_json> records_of(const std::string& text) {
  std::vector<ordered_json> records;
  for (std::size_t i = 0;; ++i) {
    const std::string line = record_line(text, i);
    if (line.empty()) {
      return records;
    }
    records.push_back(ordered_json::parse(line));
  }
}

// The same report in another layout (as another program would reformat it): read by the general
// reader alone.
std::string reformatted(const std::string& text) {
  return ordered_json::parse(text).dump(1);
}

// Kinds of record the cases edit.
bool exited(const ordered_json& r) {
  return r["outcome"] == "exited" && !r.contains("phases") && r["value"]["e"].is_number();
}
bool never_ends(const ordered_json& r) {
  return r["outcome"] == "no_exit" && r["value"]["tau"].is_null() && r["error"]["tau"] == 0;
}
bool several_phases(const ordered_json& r) {
  return r.contains("phases") && r["value"]["e"].is_number();
}

std::string number(const ordered_json& x) {
  return to_string_full(x.get<double>());
}

TEST(DiffHoldsEachRecordToItself, ARealReportIsReadAndDiffsCleanlyAgainstItself) {
  const std::string& text = real_report();
  const std::vector<ordered_json> records = records_of(text);
  ASSERT_EQ(records.size(), 4u);
  // What the refusals below edit, as a run writes it.
  for (const auto& kind : {exited, never_ends, several_phases}) {
    ASSERT_TRUE(std::any_of(records.begin(), records.end(), kind));
  }
  std::istringstream in(text);
  EXPECT_TRUE(diff::read_record_lines(in, "real.json").has_value()) << "read fast, whole";
  const std::string written = write_file("real.json", text);
  const std::string other = write_file("real-reformatted.json", reformatted(text));
  // A value rounded the other way (an ulp away) still agrees with its error: the rounding of its
  // digits is allowed.
  std::size_t at = 0;
  while (!exited(records[at])) {
    ++at;
  }
  ordered_json rounded = records[at];
  rounded["value"]["e"] = std::nextafter(rounded["value"]["e"].get<double>(), 2.0);
  const std::string within =
      write_file("real-rounded.json", with_record_line(text, at, rounded.dump()));
  for (const auto& [old_path, new_path] :
       {std::pair{written, written}, {other, written}, {written, other}, {written, within}}) {
    const CliRun diffed = run({"diff", old_path, new_path});
    EXPECT_EQ(diffed.code, 0) << old_path << " " << new_path << ": " << diffed.err;
    EXPECT_EQ(diffed.out, "0 regressions, 0 changes\n") << old_path << " " << new_path;
  }
}

// One edit of one record, and what diff says of it.
struct Case {
  std::string name;
  std::function<bool(const ordered_json&)> of; // the kind of record edited
  std::function<void(ordered_json&)> edit;
  std::function<std::string(const ordered_json&)> why; // of the record as edited
};

TEST(DiffHoldsEachRecordToItself, AnInconsistentRecordIsRefusedWithOneLineNamingIt) {
  const double epsilon = std::numeric_limits<double>::epsilon();
  const auto error_not_difference = [](const ordered_json& r) {
    return fmt::format("e's error {} is not its value {} minus its reference {}",
                       number(r["error"]["e"]), number(r["value"]["e"]),
                       number(r["reference"]["e"]));
  };
  const auto rel_error_not_quotient = [](const ordered_json& r) {
    return fmt::format("e's rel_error {} is not |error| / |reference| = {}",
                       number(r["rel_error"]["e"]),
                       to_string_full(std::abs(r["error"]["e"].get<double>()) /
                                      std::abs(r["reference"]["e"].get<double>())));
  };
  const std::vector<Case> cases = {
      // The hostile pass's: each was "0 regressions, 0 changes", exit 0.
      {"an error of 1e300", exited, [](ordered_json& r) { r["error"]["e"] = 1e300; },
       error_not_difference},
      {"an error of 0", exited, [](ordered_json& r) { r["error"]["e"] = 0.0; },
       error_not_difference},
      {"a value of 1e300", exited, [](ordered_json& r) { r["value"]["e"] = 1e300; },
       error_not_difference},
      {"an unknown outcome", exited, [](ordered_json& r) { r["outcome"] = "weird"; },
       [](const ordered_json&) { return std::string("unknown outcome \"weird\""); }},
      // The error: value − reference to the rounding of their digits, and no further.
      {"an error of -0", exited, [](ordered_json& r) { r["error"]["e"] = -0.0; },
       error_not_difference},
      {"an error of the least subnormal", exited,
       [](ordered_json& r) { r["error"]["e"] = std::numeric_limits<double>::denorm_min(); },
       error_not_difference},
      {"an error 3 ε |value| away", exited,
       [&](ordered_json& r) {
         r["error"]["e"] =
             r["error"]["e"].get<double>() + 3 * epsilon * std::abs(r["value"]["e"].get<double>());
       },
       error_not_difference},
      {"a reference moved alone", exited,
       [](ordered_json& r) { r["reference"]["e"] = 2 * r["reference"]["e"].get<double>(); },
       error_not_difference},
      // The relative error: |error| / |reference|.
      {"a relative error of 1e300", exited, [](ordered_json& r) { r["rel_error"]["e"] = 1e300; },
       rel_error_not_quotient},
      {"a relative error of 0", exited, [](ordered_json& r) { r["rel_error"]["e"] = 0.0; },
       rel_error_not_quotient},
      {"a relative error 6 ε away", exited,
       [&](ordered_json& r) {
         r["rel_error"]["e"] = r["rel_error"]["e"].get<double>() * (1 + 6 * epsilon);
       },
       rel_error_not_quotient},
      // |error| stands for it only against a reference 0 or infinite, and for e on a late return
      // (no_exit, or one of several phases).
      {"a relative error of |error| on an exited record", exited,
       [](ordered_json& r) { r["rel_error"]["e"] = std::abs(r["error"]["e"].get<double>()); },
       rel_error_not_quotient},
      // What comes with what.
      {"a relative error without an error", exited,
       [](ordered_json& r) { r["error"]["e"] = nullptr; },
       [](const ordered_json& r) {
         return fmt::format("e has a rel_error {} but no error", number(r["rel_error"]["e"]));
       }},
      {"an error without its value", exited, [](ordered_json& r) { r["value"]["e"] = nullptr; },
       [](const ordered_json& r) {
         return fmt::format("e has an error {} without its value, reference and rel_error",
                            number(r["error"]["e"]));
       }},
      {"an error without its relative error", exited,
       [](ordered_json& r) { r["rel_error"]["e"] = nullptr; },
       [](const ordered_json& r) {
         return fmt::format("e has an error {} without its value, reference and rel_error",
                            number(r["error"]["e"]));
       }},
      {"a value and a reference without their error", exited,
       [](ordered_json& r) { r["error"]["e"] = r["rel_error"]["e"] = nullptr; },
       [](const ordered_json& r) {
         return fmt::format("e has a value {} and a reference {} but no error",
                            number(r["value"]["e"]), number(r["reference"]["e"]));
       }},
      // τ = ∞ is null in JSON, its error between two infinities 0.
      {"an error between two infinite τ other than 0", never_ends,
       [](ordered_json& r) { r["error"]["tau"] = 1.0; },
       [](const ordered_json&) {
         return std::string("tau's error 1 is not its value inf minus its reference inf");
       }},
      // The ranges: sizes and times, spreads and a replica's differences are not negative.
      {"a negative size", exited,
       [](ordered_json& r) { // consistent but for its sign
         const double value = -r["value"]["delta_max"].get<double>();
         const double reference = r["reference"]["delta_max"];
         r["value"]["delta_max"] = value;
         r["error"]["delta_max"] = value - reference;
         r["rel_error"]["delta_max"] = std::abs(value - reference) / reference;
       },
       [](const ordered_json& r) {
         return fmt::format("delta_max = {} is impossible (a negative size or time)",
                            number(r["value"]["delta_max"]));
       }},
      {"a negative spread over the phases", several_phases,
       [](ordered_json& r) { r["phase_spread"]["e"] = -0.5; },
       [](const ordered_json&) { return std::string("e's spread -0.5 is negative"); }},
      {"a negative difference from a replica", several_phases,
       [](ordered_json& r) {
         r["replica_difference"] = {{"e", -1e-9}};
       },
       [](const ordered_json&) {
         return std::string("e's difference from its replica is -1e-09");
       }},
      // The outcome: the failed flag it implies, and the values it leaves.
      {"not failed beside a failing outcome", exited,
       [](ordered_json& r) { r["outcome"] = "step_limit"; },
       [](const ordered_json&) {
         return std::string("failed is false beside outcome step_limit");
       }},
      {"not failed beside a failure", exited, [](ordered_json& r) { r["failure"] = "why"; },
       [](const ordered_json&) {
         return std::string("failed is false beside outcome exited and a failure");
       }},
      {"failed when skipped", exited,
       [](ordered_json& r) {
         r["outcome"] = "skipped";
         r["failed"] = true;
       },
       [](const ordered_json&) { return std::string("failed is true beside outcome skipped"); }},
      {"values beside a solver that threw", exited,
       [](ordered_json& r) {
         r["outcome"] = "error";
         r["failed"] = true;
       },
       [](const ordered_json&) { return std::string("values beside outcome error"); }},
      {"values beside an impossible answer", exited,
       [](ordered_json& r) {
         r["outcome"] = "unstable";
         r["failed"] = true;
       },
       [](const ordered_json&) { return std::string("values beside outcome unstable"); }},
      {"e beside the peak", exited, [](ordered_json& r) { r["outcome"] = "peak"; },
       [](const ordered_json&) {
         return std::string("e, tau or energy_unload beside outcome peak");
       }},
      {"an e beside no return", exited, [](ordered_json& r) { r["outcome"] = "no_exit"; },
       [](const ordered_json& r) {
         return fmt::format("e = {} beside outcome no_exit", number(r["value"]["e"]));
       }},
  };
  const std::string& text = real_report();
  const std::vector<ordered_json> records = records_of(text);
  const std::string written = write_file("real.json", text);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto at = std::find_if(records.begin(), records.end(), c.of);
    ASSERT_NE(at, records.end());
    const auto index = static_cast<std::size_t>(at - records.begin());
    ordered_json edited = *at;
    c.edit(edited);
    const std::string edited_text = with_record_line(text, index, edited.dump());
    // In pldamp's layout (the fast reader declines the record, the general one says why) and in
    // another (the general reader alone).
    for (const auto& [name, report] :
         {std::pair{std::string("edited.json"), edited_text},
          {std::string("edited-reformatted.json"), reformatted(edited_text)}}) {
      const std::string path = write_file(name, report);
      const CliRun diffed = run({"diff", written, path});
      EXPECT_EQ(diffed.code, 2) << name << ": " << diffed.out;
      EXPECT_EQ(diffed.out, "") << name;
      EXPECT_EQ(diffed.err, fmt::format("error: {}: records[{}] ({}): {}\n", path, index,
                                        edited["key"].get<std::string>(), c.why(edited)))
          << name;
    }
  }
}

} // namespace
} // namespace pldamp::harness
