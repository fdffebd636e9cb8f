// The claim kinds judged on grids of their own (judge/claims.hpp), each with a claim that holds
// and one that fails, their measured values against independent computations, the denser grid,
// and `run --strict` with expect = "fails".
#include "common/parallel.hpp"
#include "fake_solver.hpp"
#include "judge/claims.hpp"
#include "judge/solve.hpp"

#include "pldamp/analytic/observables.hpp"
#include "pldamp/analytic/seed.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

namespace pldamp::harness {
namespace {

using testing::run;
using testing::write_file;

const std::string claims_scene = R"(name = "claims"
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
)";

// The scene's one claim, judged.
Verdict judged(const std::string& claim) {
  const Scene scene = parse_scene(claims_scene + "[[claim]]\n" + claim, "claims.toml");
  return judge_on_grid(scene, scene.claims.front());
}

// τ/τ0 − 1/√(1 − z²) over 1/√(1 − z²), in 50 digits (the judge computes in float128).
double gap_in_bin50(double p, double z) {
  const auto c = analytic::Contact<bin50>::from_alpha_eff(bin50(p), bin50(z), bin50(1));
  const bin50 curve = analytic::seed::evaluate(analytic::seed::Formula::tau_ratio_curve, c);
  return static_cast<double>((analytic::duration_ratio(c) - curve) / curve);
}

TEST(Claims, RelationLowerBoundHoldsWithItsSmallestGapAndTies) {
  const Verdict v = judged(R"(name = "lower"
kind = "relation"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
relation = "lower_bound"
p = [1.0, 1.5, 3.0]
alpha_eff = [0.0, 0.1, 0.5]
)");
  EXPECT_TRUE(v.holds);
  EXPECT_EQ(v.failed_cells, 0);
  // Equal at p = 1 (every cell) and at α_eff = 0; the smallest gap elsewhere is at p = 1.5, 0.1.
  EXPECT_EQ(v.worst, "p = 1.5, alpha_eff = 0.1");
  ASSERT_TRUE(v.margin);
  EXPECT_NEAR(*v.margin, gap_in_bin50(1.5, 0.1), 1e-20);
  EXPECT_NE(v.note.find("equal within 1e-25 at 5 of 9 cells: p = 1 (every cell); p = 1.5, 3 at "
                        "alpha_eff = 0"),
            std::string::npos)
      << v.note;
}

TEST(Claims, RelationUpperBoundFailsWhereCrossedMost) {
  const Verdict v = judged(R"(name = "upper"
kind = "relation"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
relation = "upper_bound"
p = [1.5, 3.0]
alpha_eff = [0.1, 0.5]
)");
  EXPECT_FALSE(v.holds);
  EXPECT_EQ(v.worst, "p = 3, alpha_eff = 0.5");
  EXPECT_NEAR(v.measured, -gap_in_bin50(3.0, 0.5), 1e-20);
}

TEST(Claims, RelationOfASolverHoldsAtItsAccuracyAndFailsBelowIt) {
  const std::string claim = R"(name = "table II"
kind = "relation"
solver = "arkode-dp5"
rtol = 1e-10
quantity = "e"
formula = "seed_restitution"
relation = "equal_within"
absolute = true
v0 = [0.1, 10.0]
)";
  const Verdict loose = judged(claim + "tolerance = 1e-6\n");
  EXPECT_TRUE(loose.holds);
  EXPECT_GT(loose.measured, 1e-14); // a real solve, not the closed form
  EXPECT_LT(loose.measured, 1e-7);
  const Verdict tight = judged(claim + "tolerance = 1e-15\n");
  EXPECT_FALSE(tight.holds);
  EXPECT_EQ(tight.measured, loose.measured);
}

TEST(Claims, RelationSaysHowAWrongFormulaIsWrong) {
  const Verdict v = judged(R"(name = "unloading"
kind = "relation"
of = "truth"
quantity = "energy_unload"
formula = "seed_energy_unload"
relation = "equal_within"
tolerance = 1e-3
e = [0.5]
)");
  EXPECT_FALSE(v.holds);
  // |truth / formula − 1| with the formula −0.45814 KE0 and the truth 0.30028 KE0 (seed_test.cpp
  // has both from mpmath).
  EXPECT_NEAR(v.measured, 0.30028316962711574 / 0.45813687319742549 + 1, 1e-12);
  EXPECT_NE(v.note.find("formula / energy_unload from -1.526"), std::string::npos) << v.note;
}

TEST(Claims, AsymptoticMeasuresTheFirstOrderOfTheDurationRatio) {
  const std::string claim = R"(name = "limit"
kind = "asymptotic"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
p = [1.0, 2.0]
)";
  const Verdict linear = judged(claim + "order = 1\n");
  EXPECT_TRUE(linear.holds);
  ASSERT_EQ(linear.orders.size(), 2u);
  EXPECT_FALSE(linear.orders[0].order); // p = 1: equal over the whole range
  ASSERT_TRUE(linear.orders[1].order);
  EXPECT_NEAR(*linear.orders[1].order, 1.0, 5e-3);
  // The coefficient of α_eff is (π/2)(p − 1)/(p + 1), MATH.md §3, up to the z² term at 1e-4.
  EXPECT_NEAR(linear.orders[1].coefficient, analytic::duration_ratio_slope(2.0), 1e-4);
  const Verdict limit = judged(claim + "order = 3\n");
  EXPECT_FALSE(limit.holds);
  EXPECT_EQ(limit.worst, "p = 2");
  EXPECT_NEAR(*limit.margin, -2.0, 5e-3);
}

TEST(Claims, AsymptoticOfASolverCountsOnlyDifferencesBeyondItsOwnError) {
  // The duration ratio of a fixed-step scheme against the seed's curve: the scheme's error in τ
  // (about 1e-5 at 20000 steps per contact) hides the curve's first-order gap at the small α_eff,
  // so those points are equal to the solver's accuracy and the order comes from the others. Held
  // to a tolerance the scheme does not have (10 rtol, rtol defaulting to 1e-8), the solver's own
  // error was read as the gap and the measured order fell to about 0.
  const std::string claim = R"(name = "limit of a scheme"
kind = "asymptotic"
solver = "dem-verlet"
steps_per_contact = 20000
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
p = [2.0]
order = 1
range = [1e-4, 1e-1]
points = 7
)";
  const Verdict v = judged(claim);
  ASSERT_EQ(v.orders.size(), 1u);
  ASSERT_TRUE(v.orders[0].order) << v.note;
  EXPECT_NEAR(*v.orders[0].order, 1.0, 0.1) << v.note;
  EXPECT_TRUE(v.holds) << v.note;
  // At 50 steps per contact the scheme's error hides the gap everywhere: no order can be
  // measured, and the claim is not judged as holding.
  const std::string coarse = std::string(claim).replace(claim.find("20000"), 5, "50");
  const Verdict hidden = judged(coarse);
  EXPECT_TRUE(hidden.orders.empty()) << hidden.note;
  EXPECT_FALSE(hidden.holds);
  EXPECT_EQ(hidden.missing_cells, 1) << hidden.note;
}

TEST(Claims, RecoveredParameterHoldsAtTheSolversAccuracyNotBeyond) {
  const std::string claim = R"(name = "fig 1"
kind = "recovered_parameter"
solver = "arkode-dp5"
rtol = 1e-10
p = [1.0, 2.0]
e = [0.2, 0.9]
)";
  const Verdict loose = judged(claim + "bound = 1e-3\n");
  EXPECT_TRUE(loose.holds);
  EXPECT_GT(loose.measured, 1e-13);
  EXPECT_LT(loose.measured, 1e-6);
  const Verdict tight = judged(claim + "bound = 1e-14\n");
  EXPECT_FALSE(tight.holds);
}

TEST(Claims, StabilityOfVelocityVerletAgainstTheSeedsCriticalStep) {
  const std::string claim = R"(name = "dt_crit"
kind = "stability"
solver = "dem-verlet"
formula = "seed_dt_crit"
p = [1.0, 2.0]
e = [0.5]
)";
  const Verdict full = judged(claim);
  EXPECT_FALSE(full.holds); // the seed's step gains energy (MATH.md §11.6)
  EXPECT_GT(full.measured, 0.2);
  EXPECT_LT(full.measured, 1.0);
  EXPECT_NE(full.note.find("unstable (no return, or energy gained) in 2 of 2 cells"),
            std::string::npos)
      << full.note;
  // A fifth of it, as DEM practice runs: stable, and the ratio scales by exactly 5.
  const Verdict fifth = judged(claim + "fraction = 0.2\n");
  EXPECT_TRUE(fifth.holds);
  EXPECT_NEAR(fifth.measured, 5 * full.measured, 1e-12);
  EXPECT_NE(fifth.note.find("e off by up to"), std::string::npos) << fifth.note;
}

TEST(Claims, DenserGridHasTenTimesTheCells) {
  const ClaimGrid one{{1.0, 2.0, 3.0}, {1.0}, {1.0}, {1.0}, {{Damping::Kind::e, 0.5}}};
  const ClaimGrid dense_one = denser_grid(one);
  EXPECT_EQ(dense_one.p.size(), 21u); // 9 between each pair
  EXPECT_DOUBLE_EQ(dense_one.p[10], 2.0);
  const ClaimGrid two{{1.0, 3.0}, {0.1, 10.0}, {1.0}, {1.0}, {{Damping::Kind::e, 0.5}}};
  const ClaimGrid dense_two = denser_grid(two);
  EXPECT_EQ(dense_two.p.size(), 5u); // 3 between: (3 + 1)² = 16 ≥ 10 cells per grid square
  ASSERT_EQ(dense_two.v0.size(), 5u);
  EXPECT_NEAR(dense_two.v0[2], 1.0, 1e-15); // log-spaced over two decades
  const Verdict v = judged(R"(name = "dense"
kind = "relation"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
relation = "equal_within"
tolerance = 1e-2
p = [1.0, 3.0]
alpha_eff = [0.0, 0.2]
denser = true
)");
  ASSERT_TRUE(v.denser);
  EXPECT_FALSE(v.holds);
  EXPECT_FALSE(v.denser->holds);
  EXPECT_NE(v.denser->grid.find(": 25 cells"), std::string::npos) << v.denser->grid;
}

// [grid] alpha (the equation's α) keeps its kind through the claims' grid text and the denser
// grid, beside e and alpha_eff (it once fell among the alpha_eff).
TEST(Claims, GridAlphaKeepsItsKind) {
  const ClaimGrid mixed{{1.5},
                        {1.0},
                        {1.0},
                        {1.0},
                        {{Damping::Kind::e, 0.5},
                         {Damping::Kind::alpha, 0.2},
                         {Damping::Kind::alpha, 0.4},
                         {Damping::Kind::alpha_eff, 0.1}}};
  EXPECT_EQ(grid_text(mixed),
            "p in {1.5} x e in {0.5} and alpha in {0.2, 0.4} and alpha_eff in {0.1}: 4 cells");
  const ClaimGrid dense = denser_grid(mixed);
  std::vector<double> alphas;
  for (const Damping& d : dense.damping) {
    if (d.kind == Damping::Kind::alpha) {
      alphas.push_back(d.value);
    }
  }
  ASSERT_EQ(alphas.size(), 11u); // 9 between 0.2 and 0.4 (one list varies)
  EXPECT_DOUBLE_EQ(alphas.front(), 0.2);
  EXPECT_DOUBLE_EQ(alphas.back(), 0.4);
  EXPECT_EQ(dense.damping.front().kind, Damping::Kind::e);
  EXPECT_EQ(dense.damping.back().kind, Damping::Kind::alpha_eff);
}

TEST(Claims, SceneErrorsNameTheLine) {
  auto error_of = [](const std::string& claim) {
    try {
      parse_scene(claims_scene + "[[claim]]\n" + claim, "claims.toml");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of("name = \"x\"\nkind = \"theorem\"\n"),
            "claims.toml:8: unknown claim kind, expected bound|relation|asymptotic|"
            "recovered_parameter|stability (got theorem)");
  EXPECT_NE(error_of("name = \"x\"\nkind = \"relation\"\nof = \"truth\"\nquantity = \"e\"\n"
                     "formula = \"seed_e\"\nrelation = \"lower_bound\"\n")
                .find("unknown formula, expected seed_tau_ratio_curve|"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nkind = \"relation\"\nquantity = \"e\"\n"
                     "formula = \"seed_restitution\"\nrelation = \"lower_bound\"\n")
                .find("needs of = \"truth\" or a solver"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nkind = \"stability\"\nsolver = \"cvode-bdf\"\n"
                     "formula = \"seed_dt_crit\"\n")
                .find("a stability claim is about a fixed-step scheme"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nkind = \"recovered_parameter\"\nsolver = \"arkode-dp5\"\n"
                     "rtol = 1e-8\nbound = 1e-3\nalpha_eff = [0.5]\n")
                .find("of kind recovered_parameter, expected name|"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nkind = \"asymptotic\"\nof = \"truth\"\nquantity = "
                     "\"tau_ratio\"\nformula = \"seed_tau_ratio_curve\"\norder = 2\nrange = "
                     "[1e-3, 1e-2]\n")
                .find("at least two decades"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nkind = \"relation\"\nof = \"truth\"\nquantity = "
                     "\"tau\"\nformula = \"seed_dt_crit\"\nrelation = \"lower_bound\"\n"
                     "figure = \"tau_ratio\"\n")
                .find("links to figure tau_ratio, which the scene does not draw"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nkind = \"relation\"\nof = \"truth\"\nquantity = "
                     "\"tau\"\nformula = \"seed_dt_crit\"\nrelation = \"lower_bound\"\n"
                     "bound = 1\n")
                .find("unknown key in [[claim]] of kind relation"),
            std::string::npos);
  EXPECT_NE(error_of("name = \"x\"\nexpect = \"maybe\"\nobservable = \"e\"\nbound = 1\n")
                .find("expect must be holds or fails (got maybe)"),
            std::string::npos);
  EXPECT_EQ(error_of("name = \"x\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\nrtol = 1e-8\n"
                     "bound = 1\nallow_missing = 1\n"),
            "claims.toml:12: allow_missing must be true or false");
  EXPECT_EQ(error_of("name = \"x\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\nrtol = 1e-8\n"
                     "bound = 1\ne = [1.5]\n"),
            "claims.toml:12: e must be in (0, 1] (got 1.5)");
  EXPECT_NE(error_of("name = \"x\"\nobservable = \"e\"\nconvention = \"lammps-tsuji\"\n"
                     "bound = 1\nv0 = [2.0]\n")
                .find("unknown key in [[claim]], expected name|"),
            std::string::npos);
}

std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Issue 27, 7: a program that answers exited without e at p = 2 and whose handshake skips p = 3
// made a bound claim over p in {1, 2, 3} hold on the one cell it had. A claim holds only on
// every cell it names: the two without a value are counted, listed, and fail it.
TEST(Claims, ABoundClaimFailsOnTheCellsWithoutAValueAndListsThem) {
  const std::string scene = "name = \"gaps\"\nwant = [\"e\"]\n[grid]\np = [1, 2, 3]\ne = [0.5]\n"
                            "v0 = [1]\n" +
                            testing::fake_solver("gaps") +
                            "[[claim]]\nname = \"fake e\"\nobservable = \"e\"\nsolver = "
                            "\"fake\"\nbound = 1e-12\n";
  const std::filesystem::path out = testing::scratch() / "gaps";
  const testing::CliRun r = run({"run", write_file("gaps.toml", scene), "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("claim fake e: fails (2 of 3 cells without a value) (UNEXPECTED)"),
            std::string::npos)
      << r.out;
  const nlohmann::json claim = nlohmann::json::parse(file_text(out / "report.json"))["claims"][0];
  EXPECT_EQ(claim["verdict"], "fails");
  EXPECT_EQ(claim["cells"], 3);
  EXPECT_EQ(claim["missing_cells"], 2);
  EXPECT_EQ(claim["failed_cells"], 0);
  EXPECT_LT(claim["measured"].get<double>(), 1e-15); // p = 1, the cell it has, is exact
  const nlohmann::json listed =
      nlohmann::json::array({{{"cell", "p = 2, e = 0.5, v0 = 1, m = 1, k = 1"},
                              {"why", "no e in the answer (exited)"},
                              {"failed", false}},
                             {{"cell", "p = 3, e = 0.5, v0 = 1, m = 1, k = 1"},
                              {"why", "skipped: it runs p = 1, 2 only"},
                              {"failed", false}}});
  EXPECT_EQ(claim["without_value"], listed);
  const std::string cells = "Without a value: p = 2, e = 0.5, v0 = 1, m = 1, k = 1 (no e in the "
                            "answer (exited)); p = 3, e = 0.5, v0 = 1, m = 1, k = 1 (skipped: it "
                            "runs p = 1, 2 only).";
  for (const char* name : {"report.md", "report.html"}) {
    const std::string text = file_text(out / name);
    EXPECT_NE(text.find("fails (2 of 3 cells without a value), unexpected"), std::string::npos)
        << name;
    EXPECT_NE(text.find(cells), std::string::npos) << name;
  }
  // Allowed by the scene: it holds on 1 of 3 cells, which --strict does not take as expected.
  const std::string allowed = write_file("gaps.toml", scene + "allow_missing = true\n");
  const testing::CliRun partial = run({"run", allowed, "--out", out.string()});
  EXPECT_EQ(partial.code, 0) << partial.err;
  EXPECT_NE(partial.out.find("claim fake e: holds on 1 of 3 cells (UNEXPECTED)"), std::string::npos)
      << partial.out;
  EXPECT_EQ(nlohmann::json::parse(file_text(out / "report.json"))["claims"][0]["verdict"],
            "partial");
  const testing::CliRun strict = run({"run", allowed, "--out", out.string(), "--strict"});
  EXPECT_EQ(strict.code, 1);
  EXPECT_NE(strict.err.find("--strict: 1 claim's verdict is not the one expected"),
            std::string::npos);
}

// "For all p in [1, 2]": a bound claim with a grid of its own is solved for it alone (its
// configuration is not the plan's), each cell's error the one a solve of its own gives, and its
// solves count in the plan's size.
TEST(Claims, ABoundClaimOnAGridOfItsOwnIsSolvedForItAlone) {
  const std::string claim = "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-6\n"
                            "[[claim]]\nname = \"cvode e\"\nobservable = \"e\"\nsolver = "
                            "\"cvode-bdf\"\nrtol = 1e-7\nbound = 1e-4\np = [1.0, 2.0]\n"
                            "e = [0.3, 0.8]\ndenser = true\n";
  const std::string text = "name = \"own\"\nwant = [\"e\"]\n[grid]\np = [1.5]\ne = [0.5]\n"
                           "v0 = [1.0]\n" +
                           claim;
  const Scene scene = parse_scene(text, "own.toml");
  ASSERT_TRUE(std::get<BoundClaim>(scene.claims[0].kind).own_grid);
  const Plan plan = make_plan(scene);
  EXPECT_EQ(plan.configs.size(), 1u); // the claim's rtol = 1e-7 is not run on the scene's grid
  RunTotals totals;
  const Verdict v = make_budgets(plan, run_plan(plan, 2, totals)).claims[0];
  EXPECT_TRUE(v.holds);
  EXPECT_EQ(v.cells, 4);
  EXPECT_EQ(v.grid, "p in {1, 2} x e in {0.3, 0.8}: 4 cells");
  double largest = 0;
  for (const double p : {1.0, 2.0}) {
    for (const double e : {0.3, 0.8}) {
      // The truth at α as a double solver receives it, and a solve of its own.
      const double alpha = static_cast<double>(
          analytic::Contact<Exact>::from_e(Exact(p), Exact(e), Exact(1)).alpha());
      const Exact truth = analytic::restitution(
          analytic::Contact<Exact>::from_alpha(Exact(p), Exact(alpha), Exact(1)));
      const double solved = *solve_once(std::get<BoundClaim>(scene.claims[0].kind).config,
                                        {p, alpha}, solvers::want_e, scene.limits)
                                 .e;
      largest = std::max(largest, static_cast<double>(abs(Exact(solved) - truth)));
    }
  }
  EXPECT_GT(largest, 1e-12); // a solve's error, not rounding
  EXPECT_EQ(v.measured, largest);
  ASSERT_TRUE(v.denser);
  EXPECT_EQ(v.denser->cells, 25); // 2 varied lists: 3 values between neighbours, 5 each
  EXPECT_TRUE(v.denser->holds);
  // 1 cell x 1 configuration, and the claim's 4 + 25 cells.
  const std::string path = write_file("own.toml", text);
  const std::string out = (testing::scratch() / "own").string();
  const testing::CliRun r = run({"run", path, "--out", out, "--max-runs", "29"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("the plan has 30 solver runs, above the limit of 29"), std::string::npos)
      << r.err;
  const testing::CliRun ok = run({"run", path, "--out", out});
  EXPECT_NE(ok.out.find("1 cells x 1 solver configurations, 1 claims on grids of their own: 30 "
                        "solver runs"),
            std::string::npos)
      << ok.out;
}

// A failing claim is a finding (exit 0); --strict exits 1 on a verdict other than the expected
// one, either way round.
TEST(Claims, StrictExitsOneOnAnUnexpectedVerdict) {
  auto scene_with = [](const std::string& expect, double tolerance) {
    return write_file("strict.toml", claims_scene + R"([[claim]]
name = "collapse"
kind = "relation"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
relation = "equal_within"
alpha_eff = [0.2]
p = [3.0]
)" + "tolerance = " + std::to_string(tolerance) +
                                         "\n" + expect);
  };
  const std::string out = (testing::scratch() / "strict-report").string();
  const std::string failing = scene_with("", 1e-2);
  EXPECT_EQ(run({"run", failing, "--out", out}).code, 0);
  const testing::CliRun strict = run({"run", failing, "--out", out, "--strict"});
  EXPECT_EQ(strict.code, 1);
  EXPECT_NE(strict.out.find("claim collapse: fails (UNEXPECTED)"), std::string::npos) << strict.out;
  EXPECT_EQ(run({"run", scene_with("expect = \"fails\"\n", 1e-2), "--out", out, "--strict"}).code,
            0);
  // Pinned as failing, yet it holds: a change of verdict, which is what --strict is for.
  EXPECT_EQ(run({"run", scene_with("expect = \"fails\"\n", 0.5), "--out", out, "--strict"}).code,
            1);
}

// The claims' cells, the searches' groups and the step study's points run on --jobs threads
// (common/parallel.hpp): every result lands in its own slot and is judged in order, so the report
// is the same on one thread as on three, apart from the timings.
TEST(Claims, TheReportDoesNotDependOnTheThreads) {
  const std::string scene = write_file("jobs.toml", R"(name = "jobs"
want = ["e", "tau"]
[grid]
p = [1.5, 2.0]
e = [0.5, 0.9]
v0 = [1.0]
[[solver]]
name = "dem-verlet"
steps_per_contact = [20, 50]
[[claim]]
name = "relation"
kind = "relation"
solver = "arkode-dp5"
rtol = 1e-8
quantity = "e"
formula = "seed_restitution"
relation = "equal_within"
tolerance = 1e-6
absolute = true
p = [1.0, 1.5, 2.0]
e = [0.1, 0.5, 0.9]
denser = true
[[claim]]
name = "asymptotic"
kind = "asymptotic"
solver = "dem-verlet"
steps_per_contact = 2000
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
p = [1.5, 2.0]
order = 1
range = [1e-3, 1e-1]
points = 5
[[claim]]
name = "recovered"
kind = "recovered_parameter"
solver = "arkode-dp5"
rtol = 1e-8
bound = 1e-6
p = [1.0, 2.0]
e = [0.2, 0.9]
[[claim]]
name = "stability"
kind = "stability"
solver = "dem-verlet"
formula = "seed_dt_crit"
p = [1.0, 2.0]
e = [0.5]
[[search]]
name = "rtol"
solver = "arkode-dp5"
atol = 1e-13
parameter = "rtol"
range = [1e-10, 1e-3]
observable = "e"
bound = 1e-6
group_by = "p"
)");
  auto report_on = [&](int jobs) {
    const std::string out = (testing::scratch() / ("jobs-" + std::to_string(jobs))).string();
    const testing::CliRun r = run({"run", scene, "--out", out, "--jobs", std::to_string(jobs)});
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(out + "/report.json");
    nlohmann::json report = nlohmann::json::parse(in);
    for (nlohmann::json& record : report["records"]) {
      for (const char* time :
           {"wall_seconds", "wall_seconds_slowest", "cpu_seconds", "cpu_seconds_slowest"}) {
        record.erase(time);
      }
    }
    return nlohmann::json{{"records", report["records"]},
                          {"claims", report["claims"]},
                          {"searches", report["searches"]},
                          {"step_study", report["budgets"]["step_study"]}};
  };
  const nlohmann::json one = report_on(1);
  ASSERT_EQ(one["claims"].size(), 4u);
  ASSERT_EQ(one["searches"].at(0)["groups"].size(), 2u);
  ASSERT_FALSE(one["step_study"].is_null());
  EXPECT_EQ(one.dump(), report_on(3).dump());
}

// Every piece runs once, its result in its own slot; of the pieces that throw, the first by
// index is the one rethrown (as a serial loop would), after every piece has run.
TEST(Claims, ForEachIndexKeepsTheOrderAndTheFirstException) {
  const std::vector<std::size_t> squares =
      map_indices<std::size_t>(1000, 4, [](std::size_t i) { return i * i; });
  for (std::size_t i = 0; i < squares.size(); ++i) {
    ASSERT_EQ(squares[i], i * i);
  }
  std::vector<int> ran(100, 0);
  try {
    for_each_index(ran.size(), 3, [&](std::size_t i) {
      ++ran[i];
      if (i % 10 == 7) {
        throw std::runtime_error("piece " + std::to_string(i));
      }
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "piece 7");
  }
  EXPECT_EQ(std::count(ran.begin(), ran.end(), 1), 100);
}

} // namespace
} // namespace pldamp::harness
