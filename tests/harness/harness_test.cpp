// The harness (issue 5): scene errors and their messages, the plan's skip rule (counted rhs
// evaluations), the reference scaling, budget arithmetic on hand-made records, diff catching
// injected regressions, and an end-to-end run of data/scenes/quick.toml.
#include "budget.hpp"
#include "cli_run.hpp"
#include "plan.hpp"
#include "report.hpp"
#include "run.hpp"
#include "scene.hpp"

#include "cli_run.hpp"
#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / "pldamp-harness-test";
  fs::create_directories(dir);
  return dir;
}

std::string write_file(const std::string& name, const std::string& text) {
  const fs::path path = scratch() / name;
  std::ofstream(path) << text;
  return path.string();
}

using testing::CliRun;
using testing::run;

const std::string valid_scene = R"(name = "t"
want = ["e", "delta_max", "t_peak", "tau", "energy"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-6
)";

struct BadScene {
  std::string text;
  std::string message; // after "path:"
};

TEST(Scene, EveryErrorNamesFileAndLineBeforeAnyWork) {
  const std::vector<BadScene> cases{
      {"colour = 1\n" + valid_scene,
       "1: unknown key in the scene, expected name|end|want|grid|solver|claim|figure|report|"
       "timing (got colour)"},
      {R"(name = "t"
[grid]
p = ["one"]
e = [0.5]
v0 = [1.0]
)",
       "3: p must be a number (got string)"},
      {R"([grid]
p = []
e = [0.5]
v0 = [1.0]
)",
       "2: p is an empty list"},
      {R"([grid]
p = [1.5, 0.5]
e = [0.5]
v0 = [1.0]
)",
       "2: p must be >= 1 (got 0.5)"},
      {R"([grid]
p = [1.5]
e = [1.5]
v0 = [1.0]
)",
       "3: e must be in (0, 1] (got 1.5)"},
      {R"([grid]
p = [1.5]
v0 = [1.0]
)",
       "1: [grid] needs e or alpha_eff"},
      {valid_scene + "[[solver]]\nname = \"ode45\"\nrtol = 1e-6\n",
       "11: unknown solver, expected cvode-bdf|cvode-adams|arkode-dp5|arkode-erk8|arkode-dirk|"
       "odeint-rkf78|odeint-bs|taylor|verlet (got ode45)"},
      {valid_scene + "[[solver]]\nname = \"verlet\"\nrtol = 1e-6\n",
       "12: verlet takes a fixed step: give steps_per_contact (got rtol)"},
      {valid_scene + "[[solver]]\nname = \"cvode-adams\"\nrtol = 1e-6\nprecision = \"quad\"\n",
       "13: solver cvode-adams runs in double precision only; taylor runs in any (got quad)"},
      {valid_scene + "[[solver]]\nname = \"cvode-adams\"\nrtl = 1e-6\n",
       "12: unknown key in [[solver]], expected name|rtol|atol|precision|steps_per_contact (got "
       "rtl)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"force_max\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-6\nbound = 1e-5\n",
       "12: claim observable must be one the scene wants: "
       "e|delta_max|t_peak|tau|energy_load|energy_unload (got force_max)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-6\nbound = -1\n",
       "15: bound must be > 0 (got -1)"},
      {"end = \"sideways\"\n" + valid_scene,
       "1: unknown contact end, expected overlap|force (got sideways)"},
      {valid_scene + "[timing]\nrepeats = 0\n",
       "11: repeats must be an integer in [1, 100] (got 0)"},
      {valid_scene + "[[claim]]\nname = \"no solver\"\nobservable = \"e\"\nbound = 1e-5\n",
       "10: [[claim]] needs solver"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"verlet\"\n"
                     "bound = 1e-2\n",
       "10: [[claim]] needs the steps_per_contact of its solver"},
      {"name = \"t\"\n[grid\n", "2: Error while parsing table header: expected ']', saw '\\n'"},
      {valid_scene + "[[figure]]\nkind = \"fig7\"\nsolver = \"arkode-dp5\"\n",
       "11: unknown figure, expected alpha_vs_e|force_history|delta_max_vs_e|tau_ratio|"
       "phase_portrait|f_of_p (got fig7)"},
      {valid_scene + "[[figure]]\nkind = \"tau_ratio\"\nsolver = \"arkode-dp5\"\nrtol = 1e-8\n"
                     "p = [1.5]\nalpha_eff = [0.5, 1.0]\n",
       "15: alpha_eff must be in [0, 1) (a return) (got 1)"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = write_file("bad" + std::to_string(i) + ".toml", cases[i].text);
    try {
      load_scene(path);
      ADD_FAILURE() << "no error for case " << i;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), path + ":" + cases[i].message) << "case " << i;
    }
    // Through the command line: the one line on stderr, exit 2, no report written.
    const fs::path out = scratch() / ("out" + std::to_string(i));
    fs::remove_all(out);
    const CliRun r = run({"run", path, "--out", out.string()});
    EXPECT_EQ(r.code, 2) << "case " << i;
    EXPECT_EQ(r.err, path + ":" + cases[i].message + "\n") << "case " << i;
    EXPECT_FALSE(fs::exists(out)) << "case " << i;
  }
  const CliRun missing = run({"run", (scratch() / "no-such.toml").string()});
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("no-such.toml:0: cannot read the scene"), std::string::npos)
      << missing.err;
}

TEST(Scene, SweepsExpandIntoConfigurations) {
  const std::string path = write_file("sweeps.toml", valid_scene + R"([[solver]]
name = "taylor"
precision = "quad"
[[solver]]
name = "verlet"
steps_per_contact = [50, 200]
[[solver]]
name = "arkode-dp5"
rtol = [1e-6, 1e-10]
atol = 1e-13
)");
  const Scene scene = load_scene(path);
  // A claim on a configuration the sweeps already run adds no configuration to the plan.
  const std::string with_claim = write_file("sweeps-claim.toml", valid_scene + R"([[solver]]
name = "verlet"
steps_per_contact = [50, 200]
[[claim]]
name = "DEM at 200 steps"
observable = "e"
solver = "verlet"
steps_per_contact = 200
bound = 1e-2
)");
  const Plan plan = make_plan(load_scene(with_claim));
  ASSERT_EQ(plan.configs.size(), 3u);
  EXPECT_EQ(plan.scene.claims[0].config, plan.configs[2]);
  const CliRun no_folder = run({"run", with_claim, "--out", "/proc/pldamp-report"});
  EXPECT_EQ(no_folder.code, 2);
  EXPECT_EQ(no_folder.err.rfind("error: cannot create the report folder", 0), 0u) << no_folder.err;
  const CliRun no_jobs = run({"run", with_claim, "--jobs", "0"});
  EXPECT_EQ(no_jobs.code, 2);
  EXPECT_EQ(no_jobs.err, "error: --jobs must be in [1, 1024] (got 0)\n");
  std::vector<std::string> labels;
  for (const SolverConfig& config : scene.configs) {
    labels.push_back(config.label());
  }
  EXPECT_EQ(labels, (std::vector<std::string>{"cvode-bdf rtol=1e-06", "taylor quad", "verlet n=50",
                                              "verlet n=200", "arkode-dp5 rtol=1e-06 atol=1e-13",
                                              "arkode-dp5 rtol=1e-10 atol=1e-13"}));
}

// The same scene wanting everything and wanting δ_max only, with every registered solver (two
// tolerances each; verlet two step counts).
std::string skip_scene(const std::string& want) {
  std::string scene = "want = [" + want + R"(]
[grid]
p = [1.0, 1.5, 2.5]
e = [0.9, 0.5, 0.1]
alpha_eff = [1.5]
v0 = [1.0]
)";
  for (const solvers::SolverInfo& info : solvers::registry()) {
    scene += "[[solver]]\nname = \"" + std::string(info.name) + "\"\n" +
             (info.name == "taylor" ? ""
              : info.adaptive       ? "rtol = [1e-6, 1e-10]\n"
                                    : "steps_per_contact = [50, 1000]\n");
  }
  return scene;
}

TEST(Plan, PeakOnlyScenesStopAtThePeak) {
  RunTotals all, peak;
  const Plan everything =
      make_plan(load_scene(write_file("all.toml", skip_scene(R"("e", "delta_max", "t_peak",
                                                                 "tau", "energy")"))));
  const std::vector<Record> all_records = run_plan(everything, 2, all);
  const Plan delta_max =
      make_plan(load_scene(write_file("peak.toml", skip_scene("\"delta_max\""))));
  const std::vector<Record> peak_records = run_plan(delta_max, 2, peak);
  const double ratio = double(peak.rhs_evals) / double(all.rhs_evals);
  EXPECT_LE(ratio, 0.6) << peak.rhs_evals << " / " << all.rhs_evals;
  RecordProperty("rhs_ratio", std::to_string(ratio));
  EXPECT_EQ(delta_max.observables, std::vector<std::string>{"delta_max"});
  for (const Record& record : peak_records) {
    EXPECT_EQ(record.outcome, "peak") << record.config;
  }
  // Stopping at the peak costs no accuracy: each configuration's worst δ_max over the grid stays
  // within 10x of the full runs' (not cell by cell: without W the error control, and so the
  // steps, of most solvers change, and single errors fluctuate by more).
  const Budgets peak_budget = make_budgets(delta_max, peak_records);
  const Budgets all_budget = make_budgets(everything, all_records);
  for (std::size_t c = 0; c < delta_max.configs.size(); ++c) {
    EXPECT_LE(*peak_budget.worst[c][0].rel, std::max(10 * *all_budget.worst[c][1].rel, 1e-14))
        << delta_max.configs[c].label();
  }
}

TEST(Plan, ReferencesScaleExactlyAcrossUnits) {
  // MATH.md §7: the reference at (v0, m, k) is the unit one scaled; against a direct evaluation.
  const std::string path = write_file("scale.toml", R"([grid]
p = [2.5]
e = [0.3]
v0 = [1e-3, 7.0]
m = [2.0]
k = [5e4]
[[solver]]
name = "taylor"
precision = "quad"
)");
  const Plan plan = make_plan(load_scene(path));
  ASSERT_EQ(plan.cells.size(), 2u);
  for (const Cell& cell : plan.cells) {
    const auto direct = analytic::observables(analytic::Contact<quad>::from_alpha(
        quad(5) / 2, plan.points[0].alpha, quad(cell.v0), quad(cell.m), quad(cell.k)));
    const std::vector<std::optional<quad>> want{direct.e,           direct.delta_max,
                                                direct.t_peak,      direct.tau,
                                                direct.energy_load, direct.energy_unload};
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const quad got = *reference_at(plan, cell, o, "quad");
      EXPECT_LT(static_cast<double>(abs(got - *want[o]) / *want[o]), 1e-31)
          << plan.observables[o] << " v0=" << cell.v0;
    }
  }
}

// A plan of 1 p × 2 dampings × 2 v0 and one configuration, with records made by hand.
struct HandMade {
  Plan plan;
  std::vector<Record> records;
};
HandMade hand_made() {
  const std::string path = write_file("hand.toml", R"(want = ["e", "delta_max"]
[grid]
p = [2.0]
e = [0.5]
alpha_eff = [2.0]
v0 = [1.0, 10.0]
[[claim]]
name = "tight"
observable = "e"
solver = "cvode-bdf"
rtol = 1e-8
bound = 3e-4
)");
  HandMade h{make_plan(load_scene(path)), {}};
  // cells: (e=0.5, v0=1), (e=0.5, v0=10), (z=2, v0=1), (z=2, v0=10)
  const double abs_e[] = {1e-4, 2.5e-4, 0, 0};
  const double rel_dm[] = {3e-6, 1e-6, 7e-6, 2e-6};
  const double seconds[] = {1e-3, 3e-3, 2e-3, 6e-3};
  for (std::size_t cell = 0; cell < 4; ++cell) {
    Record r;
    r.cell = cell;
    r.config = 0;
    r.outcome = cell < 2 ? "exited" : "no_exit";
    r.rhs_evals = long(100 * (cell + 1));
    r.wall_seconds = seconds[cell];
    r.value = {0.5, 1.0};
    r.abs_error = {abs_e[cell], rel_dm[cell]};
    r.rel_error = {cell < 2 ? abs_e[cell] / 0.5 : 0.0, rel_dm[cell]};
    h.records.push_back(r);
  }
  return h;
}

TEST(Budgets, ArithmeticOnHandMadeRecords) {
  const HandMade h = hand_made();
  ASSERT_EQ(h.plan.configs.size(), 1u); // the claim's configuration
  const Budgets b = make_budgets(h.plan, h.records);
  EXPECT_EQ(*b.worst[0][0].abs, 2.5e-4);
  EXPECT_EQ(*b.worst[0][0].rel, 5e-4);
  EXPECT_EQ(*b.worst[0][1].rel, 7e-6);
  // Maps: per (p, damping) point, the worst over its v0.
  EXPECT_EQ(*b.map[0][1][0], 3e-6);
  EXPECT_EQ(*b.map[0][1][1], 7e-6);
  // Work at p = 2: the means over the four cells; the error the worst of all observables.
  EXPECT_DOUBLE_EQ(b.work[0][0].seconds, 3e-3);
  EXPECT_DOUBLE_EQ(b.work[0][0].rhs_evals, 250);
  EXPECT_EQ(*b.work[0][0].error, 5e-4);
  // The claim: largest absolute error 2.5e-4 under the bound 3e-4.
  ASSERT_EQ(b.claims.size(), 1u);
  EXPECT_TRUE(b.claims[0].holds);
  EXPECT_EQ(b.claims[0].measured, 2.5e-4);
  EXPECT_DOUBLE_EQ(*b.claims[0].margin, 1.2);
  EXPECT_DOUBLE_EQ(*b.claims[0].supported, 1e-3);
  // A failed cell fails the claim whatever the errors.
  HandMade failing = hand_made();
  failing.records[3].outcome = "step_limit";
  const Budgets f = make_budgets(failing.plan, failing.records);
  EXPECT_FALSE(f.claims[0].holds);
  EXPECT_EQ(f.claims[0].failed_cells, 1);
  EXPECT_EQ(f.failed_records, 1);
}

TEST(Diff, CatchesInjectedRegressions) {
  const HandMade h = hand_made();
  const Budgets b = make_budgets(h.plan, h.records);
  const RunTotals totals{400, 4, 1.0};
  const nlohmann::json old_report = report_json({h.plan, h.records, b, totals, {}});
  EXPECT_TRUE(regressions(old_report, old_report).empty());

  nlohmann::json worse = old_report;
  worse["records"][0]["rel_error"]["delta_max"] = 3e-4; // 100x
  worse["records"][1]["rel_error"]["delta_max"] = 9e-6; // 9x: not a regression
  worse["records"][2]["failed"] = true;
  worse["records"][2]["outcome"] = "step_limit";
  worse["claims"][0]["verdict"] = "fails";
  worse["records"].erase(3);
  const std::vector<std::string> found = regressions(old_report, worse);
  ASSERT_EQ(found.size(), 4u);
  EXPECT_EQ(found[0], "claim flipped: tight held, now fails");
  EXPECT_EQ(found[1].rfind("error grew: cvode-bdf rtol=1e-08 | p=2 e=0.5 v0=1 m=1 k=1 delta_max "
                           "3e-06 -> 0.0003",
                           0),
            0u)
      << found[1];
  EXPECT_EQ(found[2].rfind("now fails: cvode-bdf rtol=1e-08 | p=2 z=2 v0=1", 0), 0u) << found[2];
  EXPECT_EQ(found[3].rfind("record gone: cvode-bdf rtol=1e-08 | p=2 z=2 v0=10", 0), 0u) << found[3];

  // Through the command line: exit 1 with regressions, 0 without, 2 for what is not a report.
  const std::string a = write_file("old.json", old_report.dump());
  const std::string c = write_file("new.json", worse.dump());
  EXPECT_EQ(run({"diff", a, c}).code, 1);
  const CliRun same = run({"diff", a, a});
  EXPECT_EQ(same.code, 0);
  EXPECT_EQ(same.out, "0 regressions\n");
  const CliRun bad = run({"diff", a, write_file("bad.json", "{\"schema\": 1}")});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("not a pldamp report.json"), std::string::npos) << bad.err;
}

TEST(EndToEnd, QuickSceneWritesEveryReportWithItsPlots) {
  const fs::path out = scratch() / "quick";
  fs::remove_all(out);
  const CliRun r =
      run({"run", std::string(PLDAMP_DATA_DIR) + "/scenes/quick.toml", "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("claim seed Table II: holds"), std::string::npos) << r.out;
  for (const char* name : {"report.json", "report.csv", "report.md", "report.html"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  std::ifstream json_file(out / "report.json");
  const nlohmann::ordered_json report = nlohmann::ordered_json::parse(json_file);
  std::vector<std::string> keys;
  for (const auto& [key, value] : report.items()) {
    keys.push_back(key);
  }
  EXPECT_EQ(keys, (std::vector<std::string>{"schema", "scene", "totals", "claims", "budgets",
                                            "records", "figures"}));
  EXPECT_EQ(report["claims"][0]["verdict"], "holds");
  EXPECT_LT(report["claims"][0]["measured"].get<double>(), 1e-5);
  EXPECT_EQ(report["totals"]["failed_records"], 0);
  const std::size_t records = report["records"].size();
  EXPECT_EQ(records, 45u * 13u); // 3 p × 5 dampings × 3 v0, 13 configurations
  // taylor quad is the reference's reference: within 1e-30 everywhere.
  for (const auto& worst : report["budgets"]["worst"]) {
    if (worst["config"] == "taylor quad") {
      EXPECT_LT(worst["max_rel"].get<double>(), 1e-30) << worst["observable"];
    }
  }
  std::ifstream csv_file(out / "report.csv");
  std::size_t lines = 0;
  for (std::string line; std::getline(csv_file, line);) {
    ++lines;
  }
  EXPECT_EQ(lines, records + 1);
  std::ifstream html_file(out / "report.html");
  std::stringstream html;
  html << html_file.rdbuf();
  std::size_t plots = 0;
  for (std::size_t at = html.str().find("<svg"); at != std::string::npos;
       at = html.str().find("<svg", at + 1)) {
    ++plots;
  }
  EXPECT_GE(plots, 2u * 3u + 5u) << "work-precision per p (time, rhs) and a map per solver";
  EXPECT_NE(html.str().find("seed Table II"), std::string::npos);
}

} // namespace
} // namespace pldamp::harness

namespace pldamp::harness {
namespace {

TEST(EndToEnd, PaperSceneReproducesTableTwoAndTheSixFigures) {
  const fs::path out = scratch() / "paper";
  fs::remove_all(out);
  const CliRun r =
      run({"run", std::string(PLDAMP_DATA_DIR) + "/scenes/paper.toml", "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream json_file(out / "report.json");
  const nlohmann::json report = nlohmann::json::parse(json_file);
  EXPECT_EQ(report["claims"][0]["verdict"], "holds");
  // Table II: 5 p x 5 v0 at e = 0.5, every entry 0.50000 within 1e-5 (measured 2e-9).
  std::size_t table = 0;
  for (const auto& record : report["records"]) {
    if (record["config"] == "arkode-dp5 rtol=1e-10 atol=1e-13") {
      EXPECT_NEAR(record["value"]["e"].get<double>(), 0.5, 1e-8) << record["key"];
      ++table;
    }
  }
  EXPECT_EQ(table, 25u);
  // The figures: the seed says "within 0.1%"; the solver and the closed forms agree far closer.
  const std::vector<std::string> kinds{"alpha_vs_e", "force_history",  "delta_max_vs_e",
                                       "tau_ratio",  "phase_portrait", "f_of_p"};
  ASSERT_EQ(report["figures"].size(), kinds.size());
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    const auto& figure = report["figures"][i];
    EXPECT_EQ(figure["kind"], kinds[i]);
    EXPECT_LT(figure["max_deviation"].get<double>(), 1e-5) << kinds[i];
    std::size_t points = 0;
    for (const auto& series : figure["series"]) {
      points += series["closed_form"].get<bool>() ? 0 : series["points"].size();
    }
    EXPECT_GE(points, 8u) << kinds[i];
  }
  std::ifstream html_file(out / "report.html");
  std::stringstream html;
  html << html_file.rdbuf();
  EXPECT_NE(html.str().find("Fig. 6: f(p)"), std::string::npos);
}

} // namespace
} // namespace pldamp::harness
