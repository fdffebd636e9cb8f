// Reports and diff: a figure that fails is reported beside the others without losing the run,
// only the formats asked are written, and regressions injected into a report are each found,
// one line each.
#include "fixtures.hpp"

#include "report/report.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <sstream>

namespace pldamp::harness {
namespace {

using namespace testing;

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Figures, OneThatFailsIsReportedAndTheOthersStand) {
  Scene scene;
  FigureSpec good{FigureKind::delta_max_vs_e, {}, {1.5}, {0.5, 0.9}, {}};
  good.config.name = "taylor";
  FigureSpec bad = good; // p < 1 reaches the solver, which refuses it
  bad.p = {0.5};
  scene.figures = {bad, good};
  const std::vector<Figure> figures = make_figures(scene);
  ASSERT_EQ(figures.size(), 2u);
  EXPECT_EQ(figures[0].failure, "p must be in [1, 1000] (got 0.5)");
  EXPECT_TRUE(figures[0].series.empty());
  EXPECT_TRUE(figures[1].failure.empty());
  EXPECT_LT(figures[1].deviation, 1e-12);

  // Written with a run's records: the failure in every format, the good figure drawn.
  const HandMade h = hand_made();
  Plan plan = h.plan;
  plan.scene.formats = {ReportFormat::json, ReportFormat::md};
  const Budgets b = make_budgets(plan, h.records);
  const RunTotals totals{400, 4, 1.0};
  const fs::path out = scratch() / "failed-figure";
  fs::remove_all(out);
  const WrittenReports files = write_reports({plan, h.records, b, totals, figures}, out.string());
  EXPECT_TRUE(files.failures.empty());
  EXPECT_EQ(files.written, (std::vector<std::string>{(out / "report.json").string(),
                                                     (out / "report.md").string()}));
  EXPECT_FALSE(fs::exists(out / "report.html"));
  const auto json = nlohmann::json::parse(read(out / "report.json"));
  EXPECT_EQ(json["figures"][0]["failure"], "p must be in [1, 1000] (got 0.5)");
  EXPECT_TRUE(json["figures"][0]["max_deviation"].is_null());
  EXPECT_FALSE(json["figures"][1].contains("failure"));
  EXPECT_NE(read(out / "report.md").find("failed: p must be in [1, 1000] (got 0.5)"),
            std::string::npos);
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

  // A claim pinned as failing regresses when it holds, and a pinned one that still fails does
  // not; a report before the claim kinds (no expect) counts as expecting holds.
  nlohmann::json pinned = old_report;
  pinned["claims"][0]["verdict"] = "fails";
  pinned["claims"][0]["expect"] = "fails";
  EXPECT_TRUE(regressions(pinned, pinned).empty());
  nlohmann::json now_holds = pinned;
  now_holds["claims"][0]["verdict"] = "holds";
  EXPECT_EQ(regressions(pinned, now_holds),
            std::vector<std::string>{"claim flipped: tight failed as pinned, now holds"});
  nlohmann::json before = old_report;
  before["claims"][0].erase("expect");
  EXPECT_EQ(regressions(before, worse).front(), "claim flipped: tight held, now fails");
  nlohmann::json hostile = old_report;
  hostile["claims"][0]["expect"] = 7;
  EXPECT_THROW(read_report(hostile.dump(), "hostile.json"), InputError);

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

} // namespace
} // namespace pldamp::harness
