// Reports and diff: a figure that fails is reported beside the others without losing the run,
// only the formats asked are written, and regressions injected into a report are each found,
// one line each.
#include "fake_solver.hpp"
#include "fixtures.hpp"

#include "common/report_schema.hpp"
#include "judge/diff.hpp"
#include "report/report.hpp"
#include "report/sections.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <sstream>

namespace pldamp::harness {
namespace {

using namespace testing;

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
  const RunTotals totals{400, 4, 1.0, {}};
  const fs::path out = scratch() / "failed-figure";
  fs::remove_all(out);
  const WrittenReports files = write_reports({plan, h.records, b, totals, figures}, out.string());
  EXPECT_TRUE(files.failures.empty());
  EXPECT_EQ(files.written, (std::vector<std::string>{(out / "report.json").string(),
                                                     (out / "report.md").string()}));
  EXPECT_FALSE(fs::exists(out / "report.html"));
  const auto json = nlohmann::json::parse(read_file(out / "report.json"));
  EXPECT_EQ(json["figures"][0]["failure"], "p must be in [1, 1000] (got 0.5)");
  EXPECT_TRUE(json["figures"][0]["max_deviation"].is_null());
  EXPECT_FALSE(json["figures"][1].contains("failure"));
  EXPECT_NE(read_file(out / "report.md").find("failed: p must be in [1, 1000] (got 0.5)"),
            std::string::npos);
}

nlohmann::json hand_made_report() {
  const HandMade h = hand_made();
  const Budgets b = make_budgets(h.plan, h.records);
  const RunTotals totals{400, 4, 1.0, {}};
  return report_json({h.plan, h.records, b, totals, {}});
}

// The lines of a diff that start with `prefix`.
std::vector<std::string> lines_starting(const DiffResult& result, std::string_view prefix) {
  std::vector<std::string> out;
  for (const std::string& line : result.lines) {
    if (line.rfind(prefix, 0) == 0) {
      out.push_back(line);
    }
  }
  return out;
}

// The section of a Markdown report that starts with `heading`, up to the next "## ".
std::string section(const std::string& markdown, const std::string& heading) {
  const std::size_t start = markdown.find(heading);
  if (start == std::string::npos) {
    return "";
  }
  return markdown.substr(start, markdown.find("\n## ", start + 1) - start);
}

// A figure's solves keep the scene's [limits] (and so `run --max-steps`), as every other solve
// of a run does: a step limit that cuts the solve fails the figure, with why.
TEST(Figures, EachSolveKeepsTheScenesLimits) {
  Scene scene;
  // τ's figure: its solves run the whole contact (δ_max's end at the peak, one step after the
  // entry series).
  FigureSpec figure{FigureKind::tau_ratio, {}, {1.5}, {}, {0.5}};
  figure.config.name = "taylor";
  scene.figures = {figure};
  EXPECT_TRUE(make_figures(scene).at(0).failure.empty());
  scene.limits.max_steps = 1;
  const std::string failure = make_figures(scene).at(0).failure;
  EXPECT_EQ(failure.rfind("taylor ended as step_limit at p = 1.5, alpha = ", 0), 0u) << failure;
}

TEST(WorkPrecision, TheReportsShowEachChosenObservablesOwnError) {
  HandMade h = energy_worse_than_e(); // e within 4e-9, energy_unload off by 5e-2
  const RunTotals totals{600, 3, 1.0, {}};
  {
    const Budgets b = make_budgets(h.plan, h.records);
    const nlohmann::ordered_json json = report_json({h.plan, h.records, b, totals, {}});
    EXPECT_EQ(json.at("scene").at("work_precision"), nlohmann::ordered_json({"e", "worst"}));
    const auto& point = json.at("budgets").at("work_precision").at(0);
    EXPECT_EQ(point.at("config"), "cvode-bdf rtol=1e-08");
    EXPECT_EQ(point.at("max_rel").get<double>(), 5e-2); // the worst of all, as schema 2 had it
    EXPECT_EQ(point.at("cells"), 3);
    EXPECT_EQ(point.at("skipped_cells"), 0);
    EXPECT_EQ(point.at("cells_without"), 0);
    const auto& e = point.at("by_observable").at("e");
    EXPECT_EQ(e.at("max_rel").get<double>(), 4e-9);
    EXPECT_EQ(e.at("cells_without"), 1);
    EXPECT_EQ(point.at("by_observable").at("energy_unload").at("max_rel").get<double>(), 5e-2);

    // report.md's table: cost (rhs_evals 200, 2000 µs per cell), then e's error with its cell
    // without, then the worst of all.
    const std::string table = section(report_markdown({h.plan, h.records, b, totals, {}}),
                                      "## Work precision: cost against error, per p");
    EXPECT_NE(table.find("| p | configuration | rhs_evals / cell | µs / cell | × analytic | e | "
                         "worst of all observables |"),
              std::string::npos)
        << table;
    const std::size_t row = table.find("| 2 | cvode-bdf rtol=1e-08 | 200 | 2000 | ");
    ASSERT_NE(row, std::string::npos) << table;
    const std::string line = table.substr(row, table.find('\n', row) - row);
    EXPECT_TRUE(line.ends_with(" | 4e-09 (1 of 3 cells without) | 0.05 |")) << line;
    // report.html: the same table, folded under the plots.
    EXPECT_NE(report_html({h.plan, h.records, b, totals, {}}, "")
                  .find("<td>4e-09 (1 of 3 cells without)</td><td>0.05</td>"),
              std::string::npos);
  }
  // The scene's choice, in its order.
  h.plan.scene.work_precision = {"energy_unload", "e"};
  const Budgets b = make_budgets(h.plan, h.records);
  EXPECT_EQ(report_json({h.plan, h.records, b, totals, {}}).at("scene").at("work_precision"),
            nlohmann::ordered_json({"energy_unload", "e"}));
  const std::string table = section(report_markdown({h.plan, h.records, b, totals, {}}),
                                    "## Work precision: cost against error, per p");
  EXPECT_NE(table.find("| × analytic | energy_unload | e |\n"), std::string::npos) << table;
  EXPECT_NE(table.find(" | 0.05 | 4e-09 (1 of 3 cells without) |\n"), std::string::npos) << table;
  // A key the plan does not compare (a scene made in code; load_scene refuses it) is refused.
  h.plan.scene.work_precision = {"tau"};
  EXPECT_THROW(work_panels(h.plan), InputError);
}

std::size_t plots_in(const std::string& html) {
  std::size_t plots = 0;
  for (std::size_t at = html.find("<svg"); at != std::string::npos;
       at = html.find("<svg", at + 1)) {
    ++plots;
  }
  return plots;
}

// report.html's plots are drawn side by side (a gnuplot process each, `jobs` at a time): the page
// is the one whose plots are drawn one by one where it asks for them (one thread), byte for byte,
// every plot in its place; the formats are written on
// threads too, listed in the scene's order, and one that cannot be written (a folder in its
// place) leaves the others written.
TEST(Report, PlotsAndFormatsMadeOnThreadsGiveTheSamePagesInTheSameOrder) {
  const HandMade h = hand_made();
  Plan plan = h.plan;
  const Budgets b = make_budgets(plan, h.records);
  const RunTotals totals{400, 4, 1.0, {}};
  const RunReport report{plan, h.records, b, totals, {}};
  const std::string alone = report_html(report, "gnuplot", 1);
  const std::size_t plots = plots_in(alone);
  EXPECT_GE(plots, 2u); // work-precision: time and rhs evaluations
  EXPECT_EQ(plots, plots_in(report_html(report, "gnuplot", 4)));
  EXPECT_EQ(report_html(report, "gnuplot", 4), alone);
  EXPECT_EQ(plots_in(report_html(report, "", 4)), 0u); // no gnuplot: tables only

  plan.scene.formats = {ReportFormat::html, ReportFormat::md, ReportFormat::json,
                        ReportFormat::csv};
  const fs::path out = scratch() / "formats-on-threads";
  fs::remove_all(out);
  const WrittenReports files = write_reports({plan, h.records, b, totals, {}}, out.string(), 3);
  EXPECT_TRUE(files.failures.empty());
  // In the scene's order, report.json last (the file a nightly diffs is new only if all are).
  EXPECT_EQ(files.written, (std::vector<std::string>{
                               (out / "report.html").string(), (out / "report.md").string(),
                               (out / "report.json").string(), (out / "report.csv").string()}));
  EXPECT_EQ(read_file(out / "report.html"), alone);
  EXPECT_EQ(read_file(out / "report.json"), report_json_text({plan, h.records, b, totals, {}}));
}

// The files in a folder, by name.
std::vector<std::string> names_in(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// A report set is a set: whichever format fails (a full disk, a file-size limit, an error), every
// file of the folder is the previous run's, and no temporary is left (a 1 MiB tmpfs once left
// report.csv, .md and .html new beside the old report.json). The same for a target that is a
// directory, found before anything is renamed.
TEST(Report, AFormatThatCannotBeWrittenLeavesEveryFileAsItWas) {
  const HandMade h = hand_made();
  Plan plan = h.plan;
  plan.scene.formats = {ReportFormat::json, ReportFormat::csv, ReportFormat::md,
                        ReportFormat::html};
  const Budgets b = make_budgets(plan, h.records);
  const RunReport before{plan, h.records, b, RunTotals{400, 4, 1.0, {}}, {}};
  const RunReport after{plan, h.records, b, RunTotals{800, 8, 2.0, {}}, {}};
  const fs::path out = scratch() / "report-set";
  const std::vector<std::string> names{"report.csv", "report.html", "report.json", "report.md"};
  for (const std::string& failing : names) {
    fs::remove_all(out);
    ASSERT_TRUE(write_reports(before, out.string()).failures.empty());
    std::map<std::string, std::string> old;
    for (const std::string& name : names) {
      old[name] = read_file(out / name);
    }
    const WrittenReports files = write_reports(after, out.string(), 2, [&](const fs::path& path) {
      if (path.filename() == failing) {
        throw InputError("cannot write " + path.string() + " (File too large)");
      }
    });
    ASSERT_EQ(files.failures.size(), 1u) << failing;
    EXPECT_EQ(files.failures[0], "cannot write " + (out / failing).string() + " (File too large)");
    EXPECT_TRUE(files.written.empty()) << failing;
    EXPECT_EQ(files.kept.size(), 4u) << failing;
    EXPECT_EQ(names_in(out), names) << failing; // no temporary left beside them
    for (const std::string& name : names) {
      EXPECT_EQ(read_file(out / name), old[name]) << name << " after " << failing << " failed";
    }
  }
  // A report.md that is a directory: refused before any rename, the others as they were.
  fs::remove_all(out);
  ASSERT_TRUE(write_reports(before, out.string()).failures.empty());
  const std::string json = read_file(out / "report.json");
  fs::remove(out / "report.md");
  fs::create_directories(out / "report.md");
  const WrittenReports files = write_reports(after, out.string(), 2);
  ASSERT_EQ(files.failures.size(), 1u);
  EXPECT_EQ(files.failures[0],
            "cannot write " + (out / "report.md").string() + " (Is a directory)");
  EXPECT_TRUE(files.written.empty());
  EXPECT_EQ(read_file(out / "report.json"), json);
  // And the set written whole once it can be.
  fs::remove(out / "report.md");
  const WrittenReports whole = write_reports(after, out.string(), 2);
  EXPECT_TRUE(whole.failures.empty());
  EXPECT_EQ(read_file(out / "report.json"), report_json_text(after));
}

TEST(Diff, AWorkPointMustBeItsRecordsLargestAndAReportBeforeThemStillReads) {
  const HandMade h = energy_worse_than_e();
  const Budgets b = make_budgets(h.plan, h.records);
  const RunTotals totals{600, 3, 1.0, {}};
  const nlohmann::json report = report_json({h.plan, h.records, b, totals, {}});
  EXPECT_EQ(diff_reports(report, report).regressions, 0);
  // e's point showing the energy's error (the worst of all, as every point did before).
  nlohmann::json wrong = report;
  wrong["budgets"]["work_precision"][0]["by_observable"]["e"]["max_rel"] = 5e-2;
  EXPECT_EQ(lines_starting(diff_reports(report, wrong), "REGRESSION"),
            (std::vector<std::string>{
                "REGRESSION work_precision_inconsistent | cvode-bdf rtol=1e-08 | e | 1 point | "
                "point 0.05, its records' largest 4e-09 at p=2"}));
  // A schema-2 report written before the points had observables: read, compared both ways.
  nlohmann::json before = report;
  for (auto& point : before["budgets"]["work_precision"]) {
    for (const char* key : {"cells", "skipped_cells", "cells_without", "by_observable"}) {
      point.erase(key);
    }
  }
  EXPECT_NO_THROW(schema::read_report(before.dump(), "before.json"));
  for (const auto& [old_report, new_report] :
       {std::pair<const nlohmann::json*, const nlohmann::json*>{&before, &report},
        {&report, &before}}) {
    const DiffResult result = diff_reports(*old_report, *new_report);
    EXPECT_EQ(result.regressions, 0);
    EXPECT_EQ(result.changes, 0);
  }
}

TEST(ReportJson, EachRecordOnALineOfItsOwnAndNoAbsError) {
  const HandMade h = hand_made();
  const Budgets b = make_budgets(h.plan, h.records);
  const RunReport report{h.plan, h.records, b, RunTotals{400, 4, 1.0, {}}, {}};
  const std::string text = report_json_text(report);
  EXPECT_EQ(nlohmann::json::parse(text), nlohmann::json(report_json(report)));
  std::istringstream lines(text);
  std::size_t record_lines = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("  {\"key\":", 0) == 0) {
      ++record_lines;
      const auto record = nlohmann::json::parse(line.substr(0, line.find_last_of('}') + 1));
      EXPECT_FALSE(record.contains("abs_error"));
      EXPECT_EQ(record["cpu_seconds"], record["wall_seconds"]); // as the fixture has them
      EXPECT_EQ(record["error"]["e"], h.records[record_lines - 1].error[0]);
    }
  }
  EXPECT_EQ(record_lines, h.records.size());
  // Written as made: with records enough for several pieces, none holds more than its block of
  // records, and the text on 3 threads is the text on one, in JSON as in CSV.
  std::vector<Record> many;
  while (many.size() < 3 * record_lines_per_piece + 17) {
    many.insert(many.end(), h.records.begin(), h.records.end());
  }
  const RunReport large{h.plan, many, b, RunTotals{400, 4, 1.0, {}}, {}};
  const auto count = [](std::string_view piece, std::string_view marker) {
    std::size_t n = 0;
    for (std::size_t at = piece.find(marker); at != std::string_view::npos;
         at = piece.find(marker, at + 1)) {
      ++n;
    }
    return n;
  };
  // What marks a record in each format: its key in JSON, its line in CSV.
  using Writer = void (*)(const RunReport&, const TextSink&, int);
  for (const auto& [write, marker] :
       {std::pair<Writer, std::string_view>{write_report_json, "{\"key\":"},
        std::pair<Writer, std::string_view>{write_report_csv, "\n"}}) {
    std::string serial, threaded;
    write(
        large, [&](std::string_view piece) { serial += piece; }, 1);
    std::size_t pieces = 0;
    write(
        large,
        [&](std::string_view piece) {
          ++pieces;
          threaded += piece;
          EXPECT_LE(count(piece, marker), record_lines_per_piece + 1);
        },
        3);
    EXPECT_EQ(threaded, serial);
    EXPECT_GT(pieces, 3u);
  }
  const std::string large_text =
      gather_text([&](const TextSink& put) { write_report_json(large, put, 3); });
  EXPECT_EQ(nlohmann::json::parse(large_text)["records"].size(), many.size());
  EXPECT_EQ(std::ranges::count(report_csv(large), '\n'), 1 + static_cast<long>(many.size()));
}

TEST(Diff, AReportStreamedIsReadAsAWholeOneAndAnotherSchemaIsOneLine) {
  const nlohmann::json report = hand_made_report();
  std::istringstream in(report.dump());
  std::vector<nlohmann::json> handed;
  const nlohmann::json rest = schema::read_report(
      in, "r.json", [&](nlohmann::json&& record) { handed.push_back(std::move(record)); });
  EXPECT_EQ(nlohmann::json(handed), report["records"]);
  EXPECT_EQ(rest["records"], nlohmann::json::array());
  EXPECT_EQ(rest["claims"], report["claims"]);
  // Diffed from streams as from trees.
  nlohmann::json worse = report;
  set_rel_error(worse["records"][0], "delta_max", 3e-4);
  worse["records"][2]["failed"] = true;
  std::istringstream old_text(report.dump()), new_text(worse.dump());
  DiffOptions verbose;
  verbose.verbose = true;
  EXPECT_EQ(diff_reports(old_text, "old.json", new_text, "new.json", verbose).lines,
            diff_reports(report, worse, verbose).lines);
  // Another schema: its one line, and none of its records handed over.
  nlohmann::json older = report;
  older["schema"] = 2;
  std::istringstream older_text(older.dump());
  handed.clear();
  try {
    schema::read_report(older_text, "older.json",
                        [&](nlohmann::json&& record) { handed.push_back(std::move(record)); });
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "older.json: report schema 2 is not 3");
  }
  EXPECT_TRUE(handed.empty());
  // A damaged record: named by its place, as read_report of a text names it.
  nlohmann::json damaged = report;
  damaged["records"][1]["rel_error"]["e"] = -1;
  std::istringstream damaged_text(damaged.dump());
  try {
    schema::read_report(damaged_text, "d.json", [](nlohmann::json&&) {});
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "d.json: records[1].rel_error.e must be null or a number >= 0 (got -1)");
  }
}

TEST(Diff, SameReportHasNothingToSay) {
  const nlohmann::json report = hand_made_report();
  const DiffResult same = diff_reports(report, report);
  EXPECT_EQ(same.lines, std::vector<std::string>{"0 regressions, 0 changes"});
  EXPECT_EQ(same.regressions, 0);
  EXPECT_EQ(report["scene"]["fingerprint"].get<std::string>().size(), 16u);
}

TEST(Diff, EachInjectedRegressionIsOneGroupedLine) {
  const nlohmann::json old_report = hand_made_report();
  nlohmann::json worse = old_report;
  // Records: (e=0.5, v0=1), (e=0.5, v0=10), (z=2, v0=1), (z=2, v0=10), all cvode-bdf rtol=1e-08.
  set_rel_error(worse["records"][0], "delta_max", 3e-4); // 100x
  set_rel_error(worse["records"][1], "delta_max", 9e-6); // 9x: not a regression
  worse["records"][2]["failed"] = true;
  worse["records"][2]["outcome"] = "step_limit";
  worse["claims"][0]["verdict"] = "fails";
  worse["records"].erase(3);
  // A reference that disappeared, and with it the error, as a run writes a value without a truth.
  for (const char* field : {"reference", "error", "rel_error"}) {
    worse["records"][0][field]["e"] = nullptr;
  }
  worse["records"][0]["rhs_evals"] = 160;         // 100 -> 160: more than 1.5x
  worse["records"][1]["rhs_evals"] = 210;         // 200 -> 210: listed, not a regression
  worse["budgets"]["worst"][1]["max_rel"] = 1e-9; // delta_max's budget: was 7e-6
  worse["budgets"]["analytic_double"][0]["max_rel"]["e"] = 5.5e-12;
  worse["claims"][0]["measured"] = 0;
  const DiffResult result = diff_reports(old_report, worse);
  const std::string config = "cvode-bdf rtol=1e-08";
  const double analytic_e = old_report["budgets"]["analytic_double"][0]["max_rel"]["e"];
  const std::string analytic_grew =
      fmt::format("{:.3g} -> 5.5e-12{} at p=2 e=0.5", analytic_e,
                  analytic_e > 0 ? fmt::format(" (x{:.3g})", 5.5e-12 / analytic_e) : "");
  EXPECT_EQ(
      lines_starting(result, "REGRESSION"),
      (std::vector<std::string>{
          "REGRESSION claim_flipped | tight | verdict | 1 claim | held, now fails",
          "REGRESSION claim_measured_vanished | tight | measured | 1 claim | 0.00025 -> 0 (x0)",
          "REGRESSION number_lost | " + config +
              " | e | 1 record | error 0.0001, reference 0.5, rel_error 0.0002 -> null at p=2 "
              "e=0.5 v0=1 m=1 k=1",
          "REGRESSION error_grew | " + config +
              " | delta_max | 1 record | 3e-06 -> 0.0003 (x100) at p=2 e=0.5 v0=1 m=1 k=1",
          "REGRESSION work_grew | " + config +
              " | rhs_evals | 1 record | 100 -> 160 (x1.6) at p=2 e=0.5 v0=1 m=1 k=1",
          "REGRESSION now_fails | " + config +
              " | outcome | 1 record | no_exit -> step_limit at p=2 z=2 v0=1 m=1 k=1",
          "REGRESSION record_gone | " + config +
              " | record | 1 record | present -> missing at p=2 z=2 v0=10 m=1 k=1",
          "REGRESSION budget_inconsistent | " + config +
              " | delta_max | 1 budget | budget 1e-09, its records' largest 0.0003",
          "REGRESSION work_precision_inconsistent | " + config +
              " | delta_max | 1 point | point 7e-06, its records' largest 0.0003 at p=2",
          "REGRESSION analytic_grew | closed forms in double | e | 1 point | " + analytic_grew}));
  EXPECT_EQ(lines_starting(result, "CHANGE"),
            (std::vector<std::string>{
                "CHANGE work_changed | " + config +
                    " | rhs_evals | 1 record | 200 -> 210 (x1.05) at p=2 e=0.5 v0=10 m=1 k=1",
                "CHANGE budget_fell | " + config +
                    " | delta_max | 1 budget | 7e-06 -> 1e-09 (x0.000143)"}));
  EXPECT_EQ(result.lines.back(), "10 regressions, 2 changes");
  EXPECT_EQ(regressions(old_report, worse), lines_starting(result, "REGRESSION"));

  // Grouped: two records of one configuration and observable are one line, with the worse; every
  // record under it with --verbose.
  nlohmann::json twice = old_report;
  set_rel_error(twice["records"][0], "delta_max", 3e-4); // 100x
  set_rel_error(twice["records"][1], "delta_max", 1e-3); // 1000x
  twice["budgets"]["worst"][1]["max_rel"] = 1e-3;
  twice["budgets"]["work_precision"][0]["by_observable"]["delta_max"]["max_rel"] = 1e-3;
  DiffOptions verbose;
  verbose.verbose = true;
  EXPECT_EQ(
      diff_reports(old_report, twice, verbose).lines,
      (std::vector<std::string>{
          "REGRESSION error_grew | " + config +
              " | delta_max | 2 records | 1e-06 -> 0.001 (x1e+03) at p=2 e=0.5 "
              "v0=10 m=1 k=1",
          "  " + config + " | p=2 e=0.5 v0=1 m=1 k=1: 3e-06 -> 0.0003 (x100)",
          "  " + config + " | p=2 e=0.5 v0=10 m=1 k=1: 1e-06 -> 0.001 (x1e+03)",
          "REGRESSION budget_grew | " + config + " | delta_max | 1 budget | 7e-06 -> 0.001 (x143)",
          "  " + config + " delta_max: 7e-06 -> 0.001 (x143)", "2 regressions, 0 changes"}));
}

TEST(Diff, ThresholdsComeFromTheSceneAndFlagsOverrideThem) {
  const nlohmann::json old_report = hand_made_report();
  nlohmann::json nine = old_report;
  set_rel_error(nine["records"][1], "delta_max", 9e-6); // 9x
  nine["budgets"]["worst"][1]["max_rel"] = 9e-6;
  nine["budgets"]["work_precision"][0]["by_observable"]["delta_max"]["max_rel"] = 9e-6;
  EXPECT_EQ(diff_reports(old_report, nine).regressions, 0);
  nine["scene"]["diff"]["error_factor"] = 5;                // the new report's [diff]
  EXPECT_EQ(diff_reports(old_report, nine).regressions, 1); // the record (its budget grew 1.3x)
  DiffOptions flags;
  flags.error_factor = 20;
  EXPECT_EQ(diff_reports(old_report, nine, flags).regressions, 0);

  // Time: a configuration's sum of fastest repeats on its thread's CPU clock, judged above the
  // floor only, against the larger of time_factor and the two nights' spread (slowest over
  // fastest: 1.2 on each night here, x1.44 in all).
  nlohmann::json slower = old_report;
  for (auto& record : slower["records"]) {
    record["cpu_seconds"] = 3 * record["cpu_seconds"].get<double>(); // 12 ms -> 36 ms
    record["cpu_seconds_slowest"] = 3 * record["cpu_seconds_slowest"].get<double>();
  }
  const DiffResult slow = diff_reports(old_report, slower);
  EXPECT_EQ(slow.lines, (std::vector<std::string>{
                            "REGRESSION time_grew | cvode-bdf rtol=1e-08 | cpu_seconds | 1 "
                            "configuration | 0.012 s -> 0.036 s (x3, noise x1.44) over 4 records",
                            "1 regression, 0 changes"}));
  flags = {};
  flags.time_floor = 0.02;
  EXPECT_EQ(diff_reports(old_report, slower, flags).regressions, 0);
  flags = {};
  flags.time_factor = 4;
  EXPECT_EQ(diff_reports(old_report, slower, flags).regressions, 0);
  // The same 3x on a night whose repeats spread 2.6x: within the noise of both (x3.12), no finding.
  nlohmann::json noisy = slower;
  for (auto& record : noisy["records"]) {
    record["cpu_seconds_slowest"] = 2.6 * record["cpu_seconds"].get<double>();
  }
  EXPECT_EQ(diff_reports(old_report, noisy).lines,
            std::vector<std::string>{"0 regressions, 0 changes"});
  // Records without a CPU time (an external program's): their wall time, spread 1.5 each night.
  nlohmann::json walls = old_report;
  for (auto& record : walls["records"]) {
    record.erase("cpu_seconds");
    record.erase("cpu_seconds_slowest");
  }
  nlohmann::json slower_walls = walls;
  for (auto& record : slower_walls["records"]) {
    record["wall_seconds"] = 3 * record["wall_seconds"].get<double>();
    record["wall_seconds_slowest"] = 3 * record["wall_seconds_slowest"].get<double>();
  }
  EXPECT_EQ(diff_reports(walls, slower_walls).lines,
            (std::vector<std::string>{
                "REGRESSION time_grew | cvode-bdf rtol=1e-08 | wall_seconds | 1 configuration | "
                "0.012 s -> 0.036 s (x3, noise x2.25) over 4 records",
                "1 regression, 0 changes"}));
}

TEST(Diff, ADifferentSceneIsRefusedUnlessAllowedThenWhatChangedIsListed) {
  const nlohmann::json old_report = hand_made_report();
  nlohmann::json other = old_report;
  other["scene"]["fingerprint"] = "0123456789abcdef";
  other["scene"]["grid"]["v0"] = {1.0, 5.0};
  other["scene"]["configs"][0]["label"] = "cvode-bdf rtol=1e-10";
  nlohmann::json kept = nlohmann::json::array();
  for (auto record : other["records"]) {
    if (record["v0"] == 1.0) {
      kept.push_back(record);
    }
  }
  other["records"] = kept;
  other["scene"]["configs"].push_back(old_report["scene"]["configs"][0]);
  other["budgets"]["worst"][0]["max_rel"] = 2e-4; // e over the records kept
  other["budgets"]["work_precision"][0]["by_observable"]["e"]["max_rel"] = 2e-4;
  EXPECT_THROW(diff_reports(old_report, other), InputError);
  DiffOptions allow;
  allow.allow_scene_change = true;
  // The v0 = 10 records are outside the new scene: listed as a removed value, not as gone.
  EXPECT_EQ(diff_reports(old_report, other, allow).lines,
            (std::vector<std::string>{"SCENE added configuration | cvode-bdf rtol=1e-10",
                                      "SCENE added v0 | 5", "SCENE removed v0 | 10",
                                      "0 regressions, 0 changes"}));
}

TEST(Diff, AClaimRegressesWhenItsVerdictLeavesTheExpectedOne) {
  // A claim pinned as failing regresses when it holds, and a pinned one that still fails does
  // not; a report before the claim kinds (no expect) counts as expecting holds.
  const nlohmann::json old_report = hand_made_report();
  nlohmann::json pinned = old_report;
  pinned["claims"][0]["verdict"] = "fails";
  pinned["claims"][0]["expect"] = "fails";
  EXPECT_TRUE(regressions(pinned, pinned).empty());
  nlohmann::json now_holds = pinned;
  now_holds["claims"][0]["verdict"] = "holds";
  EXPECT_EQ(
      regressions(pinned, now_holds),
      std::vector<std::string>{
          "REGRESSION claim_flipped | tight | verdict | 1 claim | failed as pinned, now holds"});
  nlohmann::json before = old_report;
  before["claims"][0].erase("expect");
  nlohmann::json fails = old_report;
  fails["claims"][0]["verdict"] = "fails";
  EXPECT_EQ(regressions(before, fails),
            std::vector<std::string>{"REGRESSION claim_flipped | tight | verdict | 1 claim | held, "
                                     "now fails"});
  // Holding on some cells only (the others without a value, allow_missing) is not holding.
  nlohmann::json partial = old_report;
  partial["claims"][0]["verdict"] = "partial";
  EXPECT_EQ(regressions(old_report, partial),
            std::vector<std::string>{"REGRESSION claim_flipped | tight | verdict | 1 claim | held, "
                                     "now holds on some cells only"});
  EXPECT_TRUE(regressions(partial, old_report).empty());
  nlohmann::json hostile = old_report;
  hostile["claims"][0]["expect"] = 7;
  EXPECT_THROW(schema::read_report(hostile.dump(), "hostile.json"), InputError);
}

TEST(Diff, ANameCannotForgeALineOrShiftTheFields) {
  const nlohmann::json old_report = hand_made_report();
  nlohmann::json forged = old_report;
  forged["claims"][0]["verdict"] = "fails";
  nlohmann::json before = old_report;
  for (nlohmann::json* report : {&before, &forged}) {
    (*report)["claims"][0]["name"] = "x | y\nREGRESSION forged | z";
  }
  EXPECT_EQ(diff_reports(before, forged).lines,
            (std::vector<std::string>{"REGRESSION claim_flipped | x / y\\nREGRESSION forged / z | "
                                      "verdict | 1 claim | held, now fails",
                                      "1 regression, 0 changes"}));
  // A contact end or a search changed is a scene change, and says so.
  nlohmann::json force = old_report;
  force["scene"]["fingerprint"] = "0123456789abcdef";
  force["scene"]["end"] = "force";
  force["scene"]["searches"] = {"loosest rtol"};
  DiffOptions allow;
  allow.allow_scene_change = true;
  const std::vector<std::string> lines = diff_reports(old_report, force, allow).lines;
  EXPECT_EQ(std::vector<std::string>(lines.begin(), lines.begin() + 2),
            (std::vector<std::string>{"SCENE added search | loosest rtol",
                                      "SCENE changed end | overlap -> force"}));
}

// The reports in `format` of a run of the fake program labelled `label` (TOML string contents) at
// p = 1, e = 0.3 and the `v0` line, written into the scratch folder `name`.
fs::path reports_of_a_labelled_program(const std::string& label, const std::string& v0,
                                       ReportFormat format, const std::string& name) {
  std::string scene = testing::scene_with("good", "", "", "p = [1]\ne = [0.3]\n" + v0 + "\n");
  scene.replace(scene.find("label = \"fake\""), 14, "label = \"" + label + "\"");
  const testing::Ran ran = testing::run_scene_text(scene);
  Plan plan = ran.plan;
  plan.scene.formats = {format};
  const Budgets b = make_budgets(plan, ran.records);
  const RunTotals totals{0, 0, 0, {"fake good"}};
  const std::vector<Figure> figures;
  const fs::path out = scratch() / name;
  fs::remove_all(out);
  const auto written = write_reports({plan, ran.records, b, totals, figures}, out.string());
  EXPECT_TRUE(written.failures.empty());
  return out;
}

TEST(Diff, ASolverLabelHoldingTheFieldSeparatorKeepsItsRecordsApart) {
  // An external solver's label may hold " | " (the scene accepts any label), the separator of a
  // record's key: written, read back from the file and diffed, its records keep the label whole
  // and their cells apart, never the key split at its first " | ".
  const fs::path out = reports_of_a_labelled_program("fake | v2", "v0 = [1, 2]", ReportFormat::json,
                                                     "separator-label");
  const std::string written = read_file(out / "report.json");
  const nlohmann::json old_report = schema::read_report(written, "report.json");
  ASSERT_EQ(old_report["records"].size(), 2u);
  const nlohmann::json& first = old_report["records"][0];
  EXPECT_EQ(first["key"], "fake | v2 | p=1 e=0.3 v0=1 m=1 k=1");
  EXPECT_EQ(first["config"], "fake | v2");
  EXPECT_EQ(first["outcome"], "exited");
  nlohmann::json worse = old_report;
  worse["records"][0]["failed"] = true;
  worse["records"][0]["outcome"] = "step_limit";
  const std::string old_path = write_file("separator-old.json", written);
  const std::string new_path = write_file("separator-new.json", worse.dump());
  const CliRun diffed = run({"diff", old_path, new_path, "--verbose"});
  EXPECT_EQ(diffed.code, 1);
  // The label's " | " is written " / " in its field; the verbose line keeps the key as it is.
  EXPECT_EQ(diffed.out, "REGRESSION now_fails | fake / v2 | outcome | 1 record | exited -> "
                        "step_limit at p=1 e=0.3 v0=1 m=1 k=1\n"
                        "  fake | v2 | p=1 e=0.3 v0=1 m=1 k=1: exited -> step_limit\n"
                        "1 regression, 0 changes\n");
  // The second record, gone: the label whole, its own cell.
  nlohmann::json gone = old_report;
  gone["records"].erase(1);
  EXPECT_EQ(regressions(old_report, gone),
            std::vector<std::string>{"REGRESSION record_gone | fake / v2 | record | 1 record | "
                                     "present -> missing at p=1 e=0.3 v0=2 m=1 k=1"});
}

TEST(Report, ACsvFieldHoldingACommaOrAQuoteIsQuoted) {
  // A label with a comma would shift every later column of its rows; RFC 4180 quotes it.
  const fs::path out = reports_of_a_labelled_program("fake, \\\"v2\\\"", "v0 = [1]",
                                                     ReportFormat::csv, "comma-label");
  std::istringstream csv(read_file(out / "report.csv"));
  std::string header, row;
  ASSERT_TRUE(std::getline(csv, header));
  ASSERT_TRUE(std::getline(csv, row));
  // Split as a CSV reader does: commas outside quotes, "" inside a quoted field is one quote.
  const auto fields = [](const std::string& line) {
    std::vector<std::string> split{""};
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
        split.back() += '"';
        ++i;
      } else if (line[i] == '"') {
        quoted = !quoted;
      } else if (line[i] == ',' && !quoted) {
        split.emplace_back();
      } else {
        split.back() += line[i];
      }
    }
    return split;
  };
  const std::vector<std::string> names = fields(header), values = fields(row);
  ASSERT_EQ(values.size(), names.size());
  EXPECT_EQ(names[0], "solver");
  EXPECT_EQ(values[0], "fake, \"v2\"");
  EXPECT_EQ(names[1], "precision");
  EXPECT_EQ(values[1], "double");
}

TEST(Diff, ThroughTheCommandLine) {
  // Exit 1 with regressions, 0 without, 2 for what is not a report, a different scene or a bad
  // threshold.
  const nlohmann::json old_report = hand_made_report();
  nlohmann::json worse = old_report;
  set_rel_error(worse["records"][0], "delta_max", 3e-4);
  worse["budgets"]["worst"][1]["max_rel"] = 3e-4;
  worse["budgets"]["work_precision"][0]["by_observable"]["delta_max"]["max_rel"] = 3e-4;
  const std::string a = write_file("old.json", old_report.dump());
  const std::string c = write_file("new.json", worse.dump());
  EXPECT_EQ(run({"diff", a, c}).code, 1);
  EXPECT_EQ(run({"diff", a, c, "--error-factor", "1000"}).code, 0);
  const CliRun same = run({"diff", a, a});
  EXPECT_EQ(same.code, 0);
  EXPECT_EQ(same.out, "0 regressions, 0 changes\n");
  const CliRun bad = run({"diff", a, write_file("bad.json", "{\"schema\": 2}")});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("not a pldamp report.json"), std::string::npos) << bad.err;
  nlohmann::json older = old_report;
  older["schema"] = 2;
  const std::string older_path = write_file("older.json", older.dump());
  const CliRun refused = run({"diff", older_path, a});
  EXPECT_EQ(refused.code, 2);
  EXPECT_EQ(refused.out, "");
  EXPECT_EQ(refused.err, "error: " + older_path + ": report schema 2 is not 3\n");
  const CliRun factor = run({"diff", a, a, "--work-factor", "0.5"});
  EXPECT_EQ(factor.code, 2);
  EXPECT_EQ(factor.err, "error: --work-factor must be in (1, 1e6] (got 0.5)\n");
  nlohmann::json other = old_report;
  other["scene"]["fingerprint"] = "0123456789abcdef";
  const CliRun scene = run({"diff", a, write_file("other.json", other.dump())});
  EXPECT_EQ(scene.code, 2);
  EXPECT_NE(scene.err.find("come from different scenes"), std::string::npos) << scene.err;
}
} // namespace
} // namespace pldamp::harness
