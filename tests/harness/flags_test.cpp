// Every flag a command accepts changes its answer, or is documented here as not changing it (issue
// 27: `observables --damping-exponent` was listed in --help, accepted, and ignored). For each
// command, every option its --help lists must have a row below: a base invocation and one with
// the flag turned, whose outputs must differ (or, for a row with a reason, must not). A new flag
// without a row fails the test, so the table keeps up with the command line.
#include "cli_run.hpp"
#include "fixtures.hpp"
#include "sampled_trajectories.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

using testing::CliRun;
using testing::run;
using testing::scratch;
using testing::write_file;
namespace fs = std::filesystem;

using Args = std::vector<std::string>;

// What a run shows a user, wall-clock times left out (they differ from run to run by nature).
std::string shown(const CliRun& r) {
  std::string out = std::to_string(r.code) + "\n" + r.err + "\n";
  const nlohmann::json parsed = nlohmann::json::parse(r.out, nullptr, false);
  if (parsed.is_object()) {
    nlohmann::json without = parsed;
    without.erase("wall_seconds");
    return out + without.dump();
  }
  return out + r.out;
}

// A run's report as its reader sees it: exit code, then report.json without times.
std::string shown_report(const CliRun& r, const fs::path& folder) {
  std::string out = std::to_string(r.code) + "\n";
  std::ifstream in(folder / "report.json");
  if (!in) {
    return out + "no report in " + folder.string();
  }
  nlohmann::json report = nlohmann::json::parse(in);
  report.erase("totals");
  for (nlohmann::json& record : report["records"]) {
    for (const char* time :
         {"wall_seconds", "wall_seconds_slowest", "cpu_seconds", "cpu_seconds_slowest"}) {
      record.erase(time);
    }
  }
  report["budgets"].erase("cost");
  report["budgets"].erase("work_precision");
  report["budgets"].erase("analytic_double");
  return out + report["records"].dump() + report["claims"].dump();
}

struct Row {
  std::string flag;
  Args base, turned;
  std::string same_because; // empty: the output must change
};

void check_rows(const std::string& command, const std::vector<Row>& rows,
                const std::function<std::string(const Args&)>& output) {
  const std::set<std::string> listed = testing::help_options(command);
  std::set<std::string> covered;
  for (const Row& row : rows) {
    covered.insert(row.flag);
    EXPECT_TRUE(listed.count(row.flag)) << command << " " << row.flag << " is not in --help";
    const std::string base = output(row.base), turned = output(row.turned);
    if (row.same_because.empty()) {
      EXPECT_NE(base, turned) << command << " " << row.flag << " changed nothing:\n" << base;
    } else {
      EXPECT_EQ(base, turned) << command << " " << row.flag << " (" << row.same_because << ")";
    }
  }
  for (const std::string& flag : listed) {
    EXPECT_TRUE(covered.count(flag)) << command << " " << flag << " has no row in flags_test.cpp";
  }
}

Args with(Args args, const Args& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// A contact from materials (ask/materials.hpp): two aluminium spheres, each material turned.
std::vector<Row> material_rows(const Args& head, const Args& tail) {
  const Args aluminium{"--geometry", "sphere-sphere", "--radius", "0.01",      "--young",
                       "7e10",       "--poisson",     "0.3",      "--density", "2700"};
  auto turned = [&](const std::string& flag, const std::string& value) {
    Args args = aluminium;
    for (std::size_t i = 0; i + 1 < args.size(); ++i) {
      if (args[i] == flag) {
        args[i + 1] = value;
      }
    }
    return with(with(head, args), tail);
  };
  const Args base = with(with(head, aluminium), tail);
  return {{"--geometry", base, turned("--geometry", "sphere-wall"), ""},
          {"--radius", base, turned("--radius", "0.01,0.02"), ""},
          {"--young", base, turned("--young", "7e10,2e11"), ""},
          {"--poisson", base, turned("--poisson", "0.2"), ""},
          {"--density", base, turned("--density", "2700,7800"), ""}};
}

std::vector<Row> joined(std::vector<Row> rows, const std::vector<Row>& more) {
  rows.insert(rows.end(), more.begin(), more.end());
  return rows;
}

TEST(Flags, EveryCalibrateFlagChangesItsAnswer) {
  const Args seed{"calibrate", "--p", "1.5", "--e", "0.5"};
  const Args tsuji = with(seed, {"--code", "lammps-tsuji"});
  const Args viscoelastic{"calibrate", "--code", "lammps-hertz-history", "--p", "1.5",
                          "--e",       "0.9"};
  check_rows("calibrate",
             joined(material_rows({"calibrate", "--code", "lammps-hertz-history", "--e", "0.9"},
                                  {"--v0", "1", "--json"}),
                    {{"--p", seed, {"calibrate", "--p", "2", "--e", "0.5"}, ""},
                     {"--e", seed, {"calibrate", "--p", "1.5", "--e", "0.6"}, ""},
                     {"--end", seed, with(seed, {"--end", "force"}), ""},
                     {"--precision", seed, with(seed, {"--precision", "quad"}), ""},
                     {"--json", seed, with(seed, {"--json"}), ""},
                     {"--code", seed, tsuji, ""},
                     {"--limit-damping", tsuji, with(tsuji, {"--limit-damping"}), ""},
                     {"--v0", viscoelastic, with(viscoelastic, {"--v0", "2"}), ""},
                     {"--m", viscoelastic, with(viscoelastic, {"--m", "2"}), ""},
                     {"--k", viscoelastic, with(viscoelastic, {"--k", "3"}), ""},
                     {"--speeds", viscoelastic, with(viscoelastic, {"--speeds", "1,3"}), ""},
                     {"--reff", viscoelastic, with(viscoelastic, {"--reff", "4"}), ""}}),
             [](const Args& args) { return shown(run(args)); });
  // Without a velocity-dependent code they would change nothing: refused.
  for (const char* flag : {"--v0", "--m", "--k", "--reff"}) {
    EXPECT_EQ(run(with(seed, {flag, "2"})).code, 2) << flag;
  }
  EXPECT_EQ(run(with({"calibrate", "--e", "0.5", "--geometry", "sphere-wall"},
                     {"--radius", "1", "--young", "1", "--poisson", "0", "--density", "1"}))
                .code,
            2);
}

TEST(Flags, EveryObservablesFlagChangesItsAnswer) {
  const Args base{"observables", "--p", "1.5", "--e", "0.5", "--v0", "1"};
  const Args by_alpha{"observables", "--p", "1.5", "--alpha", "0.3", "--v0", "1"};
  const Args by_group{"observables", "--p", "1.5", "--alpha-eff", "0.2", "--v0", "1"};
  check_rows(
      "observables",
      joined(
          material_rows({"observables"}, {"--e", "0.5", "--v0", "1", "--json"}),
          {{"--p", base, {"observables", "--p", "2", "--e", "0.5", "--v0", "1"}, ""},
           {"--e", base, {"observables", "--p", "1.5", "--e", "0.6", "--v0", "1"}, ""},
           {"--alpha", by_alpha, {"observables", "--p", "1.5", "--alpha", "0.4", "--v0", "1"}, ""},
           {"--alpha-eff",
            by_group,
            {"observables", "--p", "1.5", "--alpha-eff", "0.3", "--v0", "1"},
            ""},
           {"--damping-exponent", by_alpha, with(by_alpha, {"--damping-exponent", "0.5"}), ""},
           {"--end", base, with(base, {"--end", "force"}), ""},
           {"--precision", base, with(base, {"--precision", "quad"}), ""},
           {"--json", base, with(base, {"--json"}), ""},
           {"--v0", base, {"observables", "--p", "1.5", "--e", "0.5", "--v0", "2"}, ""},
           {"--m", base, with(base, {"--m", "2"}), ""},
           {"--k", base, with(base, {"--k", "3"}), ""}}),
      [](const Args& args) { return shown(run(args)); });
}

TEST(Flags, EverySolveFlagChangesItsAnswer) {
  const Args cvode{"solve", "--solver", "cvode-bdf", "--p", "1.5",
                   "--e",   "0.5",      "--v0",      "1",   "--json"};
  const Args by_alpha{"solve",   "--solver", "cvode-bdf", "--p", "1.5",
                      "--alpha", "0.3",      "--v0",      "1",   "--json"};
  const Args by_group{"solve",       "--solver", "cvode-bdf", "--p", "1.5",
                      "--alpha-eff", "0.2",      "--v0",      "1",   "--json"};
  const Args taylor{"solve", "--solver", "taylor", "--p", "1.5",
                    "--e",   "0.5",      "--v0",   "1",   "--json"};
  const Args dem{"solve", "--solver", "dem-verlet", "--p", "1.5",
                 "--e",   "0.5",      "--v0",       "1",   "--json"};
  auto set = [](Args args, const std::string& flag, const std::string& value) {
    for (std::size_t i = 0; i + 1 < args.size(); ++i) {
      if (args[i] == flag) {
        args[i + 1] = value;
      }
    }
    return args;
  };
  check_rows(
      "solve",
      joined(
          material_rows({"solve", "--solver", "cvode-bdf"}, {"--e", "0.5", "--v0", "1", "--json"}),
          {{"--solver", cvode, set(cvode, "--solver", "arkode-dp5"), ""},
           {"--p", cvode, set(cvode, "--p", "2"), ""},
           {"--e", cvode, set(cvode, "--e", "0.6"), ""},
           {"--alpha", by_alpha, set(by_alpha, "--alpha", "0.4"), ""},
           {"--alpha-eff", by_group, set(by_group, "--alpha-eff", "0.3"), ""},
           {"--damping-exponent", by_alpha, with(by_alpha, {"--damping-exponent", "0.5"}), ""},
           {"--end", cvode, with(cvode, {"--end", "force"}), ""},
           {"--precision", taylor, with(taylor, {"--precision", "quad"}), ""},
           {"--json", Args(cvode.begin(), cvode.end() - 1), cvode, ""},
           {"--v0", cvode, set(cvode, "--v0", "2"), ""},
           {"--m", cvode, with(cvode, {"--m", "2"}), ""},
           {"--k", cvode, with(cvode, {"--k", "3"}), ""},
           {"--rtol", cvode, with(cvode, {"--rtol", "1e-4"}), ""},
           {"--atol", cvode, with(cvode, {"--atol", "1e-4"}), ""},
           {"--want", cvode, with(cvode, {"--want", "e"}), ""},
           {"--dt", dem, with(dem, {"--dt", "0.05"}), ""},
           {"--steps-per-contact", dem, with(dem, {"--steps-per-contact", "20"}), ""},
           {"--onset-phase", dem, with(dem, {"--onset-phase", "0.5"}), ""},
           {"--tau-as", dem, with(dem, {"--tau-as", "crossing"}), ""},
           {"--horizon", cvode, with(cvode, {"--horizon", "2"}), ""},
           {"--sample-times", cvode, with(cvode, {"--sample-times", "1"}), ""},
           {"--max-steps", cvode, with(cvode, {"--max-steps", "3"}), ""},
           {"--max-seconds", taylor, with(taylor, {"--max-seconds", "1e-9"}), ""},
           {"--repeats", taylor, with(taylor, {"--repeats", "5"}),
            "every solve gives the same answer; only wall_seconds, the fastest, changes"}}),
      [](const Args& args) { return shown(run(args)); });
  for (const char* repeats : {"0", "1001", "2.5", "x"}) {
    const CliRun refused = run(with(taylor, {"--repeats", repeats}));
    EXPECT_EQ(refused.code, 2) << repeats;
    EXPECT_NE(refused.err.find("--repeats"), std::string::npos) << refused.err;
  }
}

TEST(Flags, EveryTimestepFlagChangesItsAnswer) {
  const Args by_alpha{"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--alpha", "0.3"};
  const Args by_group{"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--alpha-eff", "0.2"};
  const Args one{"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--e", "0.5"};
  check_rows(
      "timestep",
      joined(material_rows({"timestep", "--scheme", "dem-verlet"}, {"--e", "0.5", "--v0", "1"}),
             {{"--scheme", one, {"timestep", "--scheme", "verlet", "--p", "1.5", "--e", "0.5"}, ""},
              {"--p", one, {"timestep", "--scheme", "dem-verlet", "--p", "2", "--e", "0.5"}, ""},
              {"--e", one, {"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--e", "0.9"}, ""},
              {"--alpha",
               by_alpha,
               {"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--alpha", "0.4"},
               ""},
              {"--alpha-eff",
               by_group,
               {"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--alpha-eff", "0.3"},
               ""},
              {"--end", one, with(one, {"--end", "force", "--observables", "e"}), ""},
              {"--json", one, with(one, {"--json"}), ""},
              {"--v0", one, with(one, {"--v0", "2"}), ""},
              {"--m", one, with(one, {"--m", "2"}), ""},
              {"--k", one, with(one, {"--k", "3"}), ""},
              {"--tolerance", one, with(one, {"--tolerance", "0.001"}), ""},
              {"--observables", one, with(one, {"--observables", "e"}), ""},
              {"--tau-as", one, with(one, {"--tau-as", "steps-in-contact"}), ""},
              {"--code", one, with(one, {"--code", "liggghts"}), ""}}),
      [](const Args& args) { return shown(run(args)); });
}

TEST(Flags, EveryCheckFlagChangesItsAnswer) {
  // The closed-form trajectory of Hertz e = 0.5 sampled 40 times per contact, with v.
  const std::string file =
      write_file("flags.csv", testing::csv_of(testing::sampled(1.5, 0.5, 40, 0.3, true, false)));
  const Args base{"check", file, "--p", "1.5", "--e", "0.5", "--v0", "1"};
  const Args by_alpha{"check", file, "--p", "1.5", "--alpha", "0.48176925776458657", "--v0", "1"};
  const Args by_group{"check", file, "--p", "1.5", "--alpha-eff", "0.2154537619662468",
                      "--v0",  "1"};
  check_rows(
      "check",
      joined(
          material_rows({"check", file}, {"--e", "0.5", "--v0", "1"}),
          {{"--p", base, {"check", file, "--p", "1.6", "--e", "0.5", "--v0", "1"}, ""},
           {"--e", base, {"check", file, "--p", "1.5", "--e", "0.6", "--v0", "1"}, ""},
           {"--alpha", by_alpha, {"check", file, "--p", "1.5", "--alpha", "0.5", "--v0", "1"}, ""},
           {"--alpha-eff",
            by_group,
            {"check", file, "--p", "1.5", "--alpha-eff", "0.22", "--v0", "1"},
            ""},
           {"--end", base, with(base, {"--end", "force"}), ""},
           {"--json", base, with(base, {"--json"}), ""},
           {"--v0", base, {"check", file, "--p", "1.5", "--e", "0.5", "--v0", "1.5"}, ""},
           {"--m", base, with(base, {"--m", "2"}), ""},
           {"--k", base, with(base, {"--k", "3"}), ""},
           {"--tolerance", base, with(base, {"--tolerance", "1e-12"}), ""}}),
      [](const Args& args) { return shown(run(args)); });
}

// A scene of two cells whose claim fails (--strict exits 1), for run's and merge's flags.
const std::string scene_with_failing_claim = R"(name = "flags"
want = ["e"]
[grid]
p = [1.5]
e = [0.5, 0.9]
v0 = [1.0]
[[solver]]
name = "taylor"
[[claim]]
name = "taylor e within 1e-30"
observable = "e"
solver = "taylor"
bound = 1e-30
)";

// What a run into folder a shows, and whether it wrote folder b instead.
std::function<std::string(const Args&)> report_in(const fs::path& a, const fs::path& b) {
  return [a, b](const Args& args) {
    fs::remove_all(a);
    fs::remove_all(b);
    const CliRun r = run(args);
    return shown_report(r, a) + "|b:" + (fs::exists(b / "report.json") ? "report" : "none");
  };
}

TEST(Flags, EveryRunFlagChangesItsReport) {
  const std::string scene = write_file("flags-run.toml", scene_with_failing_claim);
  const fs::path a = scratch() / "flags-run-a", b = scratch() / "flags-run-b";
  const Args base{"run", scene, "--out", a.string()};
  check_rows("run",
             {{"--out", base, {"run", scene, "--out", b.string()}, ""},
              {"--jobs", base, with(base, {"--jobs", "1"}),
               "threads share the records out; each record is the same solve"},
              {"--max-steps", base, with(base, {"--max-steps", "1"}), ""},
              {"--max-seconds", base, with(base, {"--max-seconds", "1e-9"}), ""},
              {"--max-runs", base, with(base, {"--max-runs", "1"}), ""},
              {"--strict", base, with(base, {"--strict"}), ""},
              {"--shard", base, with(base, {"--shard", "1/2"}), ""}},
             report_in(a, b));
}

// merge's flags over one run in two shards.
TEST(Flags, EveryMergeFlagChangesItsReport) {
  const std::string scene = write_file("flags-merge.toml", scene_with_failing_claim);
  std::vector<std::string> shards;
  for (const char* k : {"1", "2"}) {
    shards.push_back((scratch() / (std::string("flags-merge-shard-") + k)).string());
    ASSERT_EQ(run({"run", scene, "--shard", std::string(k) + "/2", "--out", shards.back()}).code,
              0);
  }
  const fs::path a = scratch() / "flags-merge-a", b = scratch() / "flags-merge-b";
  const Args base{"merge", shards[0], shards[1], "--out", a.string()};
  check_rows("merge",
             {{"--out", base, {"merge", shards[0], shards[1], "--out", b.string()}, ""},
              {"--jobs", base, with(base, {"--jobs", "1"}),
               "threads share the claims and reports out; each is the same computation"},
              {"--strict", base, with(base, {"--strict"}), ""}},
             report_in(a, b));
}

TEST(Flags, EveryDiffFlagChangesItsFindings) {
  // Two reports of one scene: the second with e's error grown 5-fold in one record, its work
  // grown 30 %, its time 50 %; and a third from another scene.
  const std::string scene = write_file("flags-diff.toml", R"(name = "flags"
want = ["e"]
[grid]
p = [1.5]
e = [0.5, 0.9]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-6
)");
  const fs::path folder = scratch() / "flags-diff";
  ASSERT_EQ(run({"run", scene, "--out", folder.string()}).code, 0);
  std::ifstream in(folder / "report.json");
  nlohmann::json old_report = nlohmann::json::parse(in);
  for (nlohmann::json& record : old_report["records"]) {
    record["cpu_seconds"] = 0.01;
    record["cpu_seconds_slowest"] = 0.01;
  }
  nlohmann::json new_report = old_report;
  for (nlohmann::json& record : new_report["records"]) {
    record["cpu_seconds"] = 0.015;
    record["cpu_seconds_slowest"] = 0.015;
    record["rhs_evals"] = static_cast<long>(record["rhs_evals"].get<double>() * 1.3);
  }
  nlohmann::json& grown = new_report["records"][0];
  set_rel_error(grown, "e", grown["rel_error"]["e"].get<double>() * 5);
  nlohmann::json other = old_report;
  other["scene"]["fingerprint"] = "0000000000000000";
  const std::string old_path = write_file("flags-old.json", old_report.dump());
  const std::string new_path = write_file("flags-new.json", new_report.dump());
  const std::string other_path = write_file("flags-other.json", other.dump());
  const Args base{"diff", old_path, new_path};
  check_rows("diff",
             {{"--error-factor", base, with(base, {"--error-factor", "2"}), ""},
              {"--work-factor", base, with(base, {"--work-factor", "1.1"}), ""},
              {"--time-factor", base, with(base, {"--time-factor", "1.2"}), ""},
              {"--time-floor", with(base, {"--time-factor", "1.2"}),
               with(base, {"--time-factor", "1.2", "--time-floor", "1000"}), ""},
              {"--allow-scene-change",
               {"diff", old_path, other_path},
               {"diff", old_path, other_path, "--allow-scene-change"},
               ""},
              {"--verbose", base, with(base, {"--verbose"}), ""},
              {"--exact", base, with(base, {"--exact"}), ""}},
             [](const Args& args) { return shown(run(args)); });
}

TEST(Flags, ShowcasePrecisionChangesItsDigits) {
  check_rows("showcase", {{"--precision", {"showcase"}, {"showcase", "--precision", "quad"}, ""}},
             [](const Args& args) { return shown(run(args)); });
}

} // namespace
} // namespace pldamp::harness
