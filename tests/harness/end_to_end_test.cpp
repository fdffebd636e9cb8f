// End to end (ctest label end-to-end): the shipped quick and paper scenes through the command
// line, every report file written, Table II and the seed's six figures reproduced.
#include "fixtures.hpp"

#include <nlohmann/json.hpp>

#include <sstream>

#include <gtest/gtest.h>

namespace pldamp::harness {
namespace {

using namespace testing;

TEST(EndToEnd, QuickSceneWritesEveryReportWithItsPlots) {
  if (!PLDAMP_WITH_QUAD) {
    GTEST_SKIP() << "the shipped scenes run taylor in quad, which this build does not have";
  }
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
  // Per p: time and rhs evaluations in double, time in extended precision; a map per solver.
  EXPECT_EQ(plots, 3u * 3u + 5u);
  EXPECT_NE(html.str().find("seed Table II"), std::string::npos);
  EXPECT_EQ(html.str().find("nan"), std::string::npos);
  // The cost against the closed forms: a multiple in every work point and table.
  for (const auto& work : report["budgets"]["work_precision"]) {
    EXPECT_GT(work["x_analytic"].get<double>(), 1.0) << work["config"];
    EXPECT_NEAR(work["x_analytic"].get<double>(),
                work["seconds"].get<double>() / work["analytic_seconds"].get<double>(), 1e-9);
  }
  for (const auto& point : report["budgets"]["analytic_double"]) {
    EXPECT_LT(point["seconds"].get<double>(), 1e-4) << point["damping"];
    EXPECT_TRUE(point["not_representable"].empty()) << point["damping"]; // quick stays in range
  }
  std::ifstream md_file(out / "report.md");
  std::stringstream md;
  md << md_file.rdbuf();
  for (const std::string& page : {md.str(), html.str()}) {
    EXPECT_NE(page.find("How to read this report."), std::string::npos);
    EXPECT_NE(page.find("× analytic"), std::string::npos);
  }
}

TEST(EndToEnd, PaperSceneReproducesTableTwoAndTheSixFigures) {
  if (!PLDAMP_WITH_QUAD) {
    GTEST_SKIP() << "the shipped scenes run taylor in quad, which this build does not have";
  }
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
