// The plan: a peak-only scene stops every solver at the peak (counted rhs evaluations), and the
// references scale exactly across units (MATH.md §7).
#include "fixtures.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>

namespace pldamp::harness {
namespace {

using namespace testing;

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
             (info.fixed_step ? "steps_per_contact = [50, 1000]\n" : "rtol = [1e-6, 1e-10]\n");
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
  ASSERT_EQ(delta_max.observables.size(), 1u);
  EXPECT_EQ(delta_max.observables[0]->key, "delta_max");
  for (const Record& record : peak_records) {
    EXPECT_EQ(record.outcome, solvers::Outcome::peak) << record.config;
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

// A scene's tau_as takes effect: each fixed-step record's tau is the contact time counted that way
// (solve --tau-as gives the three), and e is the same whatever the count; refused for a solver
// that does not step.
TEST(Plan, TauAsCountsTheContactTimeOfEachRecord) {
  auto tau_and_e = [](const std::string& tau_as) {
    const Plan plan = make_plan(load_scene(write_file(
        "tau_as.toml", fmt::format(R"(want = ["e", "tau"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "dem-verlet"
steps_per_contact = [20]
onset_phases = 4
{})",
                                   tau_as.empty() ? "" : "tau_as = \"" + tau_as + "\""))));
    RunTotals totals;
    const Record record = run_plan(plan, 1, totals).front();
    return std::make_pair(*record.value[1], *record.value[0]);
  };
  const auto [out, e] = tau_and_e("");
  EXPECT_EQ(tau_and_e("first-step-out"), std::make_pair(out, e));
  const auto [counted, e_counted] = tau_and_e("steps-in-contact");
  const auto [crossing, e_crossing] = tau_and_e("crossing");
  EXPECT_EQ(e_counted, e);
  EXPECT_EQ(e_crossing, e);
  EXPECT_NE(counted, out);
  EXPECT_NE(crossing, out);
  EXPECT_NE(crossing, counted);
  EXPECT_THROW(load_scene(write_file("tau_as_bdf.toml", R"(want = ["tau"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = [1e-8]
tau_as = "crossing"
)")),
               SceneError);
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
precision = ")" + std::string(precision_name<Exact>()) + R"("
)");
  const Plan plan = make_plan(load_scene(path));
  ASSERT_EQ(plan.cells.size(), 2u);
  for (const Cell& cell : plan.cells) {
    const auto direct = analytic::observables(analytic::Contact<Exact>::from_alpha(
        Exact(5) / 2, plan.points[0].alpha, Exact(cell.v0), Exact(cell.m), Exact(cell.k)));
    const std::vector<std::optional<Exact>> want{direct.e,
                                                 direct.delta_max,
                                                 direct.t_peak,
                                                 direct.tau,
                                                 direct.energy_load,
                                                 direct.energy_unload,
                                                 direct.normal_force_max,
                                                 direct.t_normal_force_max};
    ASSERT_EQ(plan.observables.size(), want.size());
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const Exact got = *reference_at(plan, cell, o, plan.configs[0]);
      EXPECT_LT(static_cast<double>(abs(got - *want[o]) / *want[o]), 1e-31)
          << plan.observables[o]->key << " v0=" << cell.v0;
    }
  }
}

TEST(Plan, TheClosedFormsInDoubleSayWhatDoubleCannotHold) {
  // Just below critical damping e ~ e^-2221 underflows double and, for p = 2, τ overflows it:
  // not an error of the closed forms. Their logarithms are judged instead (the rounding of α to
  // double costs ~5e-11 in ln e there: μ = (1 − z)(1 + z) with 1 − z = 1e-6).
  const std::string path = write_file("edge.toml", R"([grid]
p = [2.0]
alpha_eff = [0.999999, 0.5]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-6
)");
  const Plan plan = make_plan(load_scene(path));
  ASSERT_EQ(plan.points.size(), 2u);
  std::map<std::string, AnalyticCheck> edge, plain;
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    edge[std::string(plan.observables[o]->key)] = plan.points[0].analytic[o];
    plain[std::string(plan.observables[o]->key)] = plan.points[1].analytic[o];
  }
  for (const char* key : {"e", "tau"}) {
    EXPECT_FALSE(edge[key].representable) << key;
    EXPECT_FALSE(edge[key].error) << key;
    ASSERT_TRUE(edge[key].log_error) << key;
    EXPECT_LT(*edge[key].log_error, 1e-9) << key;
  }
  EXPECT_TRUE(edge["delta_max"].representable);
  EXPECT_LT(*edge["delta_max"].error, 1e-12);
  for (const auto& [key, check] : plain) {
    EXPECT_TRUE(check.representable) << key;
    EXPECT_LT(*check.error, 1e-14) << key;
  }
  EXPECT_EQ(not_representable(plan, plan.points[0]), (std::vector<std::string>{"e", "tau"}));
  // The closed forms' cost per cell in double: measured, about a microsecond.
  EXPECT_GT(plan.points[1].analytic_seconds, 0.0);
  EXPECT_LT(plan.points[1].analytic_seconds, 1e-4);
}

} // namespace
} // namespace pldamp::harness

namespace pldamp::harness {
namespace {

// A scene beyond the seed (MATH.md §12): the truth of each point is the float128 reference solve,
// scaled to every cell; a target e is met on it; each truth carries its error estimate; and the
// solvers run the stated exponent (taylor in double within 1e-13 of the truth at three speeds).
TEST(Plan, BeyondTheSeedTheTruthIsTheReferenceSolveScaledToEveryCell) {
  const Plan plan =
      make_plan(load_scene(write_file("beyond.toml", R"(want = ["e", "delta_max", "tau"]
[grid]
p = 1.5
damping_exponent = 0.5
e = [0.5]
alpha_eff = [0.2]
v0 = [0.01, 1.0, 100.0]
m = [2.0]
[[solver]]
name = "taylor"
)")));
  ASSERT_EQ(plan.points.size(), 2u);
  for (const Point& point : plan.points) {
    EXPECT_TRUE(point.solved);
    EXPECT_EQ(point.beta, 0.5);
    EXPECT_TRUE(point.no_truth.empty()) << point.no_truth;
    ASSERT_EQ(point.truth_error.size(), plan.observables.size());
    for (const std::optional<double>& estimate : point.truth_error) {
      ASSERT_TRUE(estimate.has_value());
      EXPECT_LT(*estimate, 1e-30);
    }
  }
  // The target e is met by the reference solve, at every speed (α differs per cell).
  const SolverConfig& taylor = plan.configs.front();
  std::set<double> alphas;
  for (const Cell& cell : plan.cells) {
    alphas.insert(static_cast<double>(cell.alpha));
    if (cell.point == 0) {
      EXPECT_LT(abs(*reference_at(plan, cell, 0, taylor) - Exact(1) / 2), Exact(1e-32));
    }
  }
  EXPECT_EQ(alphas.size(), plan.cells.size());
  RunTotals totals;
  const std::vector<Record> records = run_plan(plan, 2, totals);
  for (const Record& record : records) {
    ASSERT_FALSE(record.failed()) << record.failure;
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      ASSERT_TRUE(record.rel_error[o].has_value());
      EXPECT_LT(*record.rel_error[o], 1e-13) << plan.observables[o]->key;
    }
  }
}

// An overdamped point beyond the seed whose reference solve sees no exit within its horizon has
// no truth, with the reason: the overlap may creep back later (viscoelastic Hertz at α_eff 300
// does, beyond 10⁴ δ_u/v0), so e = 0, τ = ∞ would judge every solver wrongly. α_eff 100, which
// returns at 3.6e3, keeps its truth.
TEST(Plan, BeyondTheSeedANoExitIsNoTruth) {
  const Plan plan = make_plan(load_scene(write_file("creep.toml", R"(want = ["e", "tau"]
[grid]
p = 1.5
damping_exponent = 0.5
alpha_eff = [100.0, 300.0]
v0 = [1.0]
[[solver]]
name = "taylor"
)")));
  ASSERT_EQ(plan.points.size(), 2u);
  const Point& returning = plan.points[0];
  const Point& creeping = plan.points[1];
  EXPECT_TRUE(returning.no_truth.empty()) << returning.no_truth;
  EXPECT_NE(creeping.no_truth.find("saw no exit within its horizon"), std::string::npos)
      << creeping.no_truth;
  const SolverConfig& taylor = plan.configs.front();
  for (const Cell& cell : plan.cells) {
    const bool creeps = cell.point == 1;
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      EXPECT_EQ(reference_at(plan, cell, o, taylor).has_value(), !creeps)
          << plan.observables[o]->key;
    }
  }
}

// [grid] alpha is the equation's α, as the command line's --alpha: at every p its α_eff is
// α/√(2(p + 1)), and the truth of each cell is what `pldamp observables --alpha` answers there.
// The points are computed on threads, each alone: the plan is the same for any --jobs, truths
// of the closed forms and of reference solves (a stated β) alike, bit for bit. (p = 1, β = ½,
// e = 0.9 once threw from the calibration: its bracket solved the undamped contact, whose e is 1
// exactly, and float128 taylor called that solve unstable.)
TEST(Plan, PointsOnThreadsAreTheSerialPoints) {
  Scene scene = parse_scene(R"(want = ["e", "delta_max", "tau"]
[grid]
p = [1.0, 1.5, 2.5]
e = [0.9, 0.3]
alpha_eff = [1.5]
v0 = [1.0]
damping_exponent = [0.5]
[[solver]]
name = "cvode-bdf"
rtol = 1e-8
[[solver]]
name = "taylor"
precision = "quad"
)",
                            "threads.toml");
  for (int variant = 0; variant < 2; ++variant) {
    if (variant == 1) {
      scene.damping_exponent.clear(); // the seed's β: closed forms in every precision
    }
    const Plan serial = make_plan(scene, 1), threaded = make_plan(scene, 3);
    ASSERT_EQ(serial.points.size(), threaded.points.size());
    ASSERT_EQ(serial.cells.size(), threaded.cells.size());
    for (std::size_t i = 0; i < serial.points.size(); ++i) {
      const Point &a = serial.points[i], &b = threaded.points[i];
      EXPECT_EQ(a.p, b.p);
      EXPECT_EQ(a.alpha, b.alpha) << i;
      EXPECT_EQ(a.group, b.group) << i;
      EXPECT_EQ(a.alpha_eff, b.alpha_eff) << i;
      EXPECT_EQ(a.log_duration, b.log_duration) << i;
      EXPECT_EQ(a.reference, b.reference) << i;
      EXPECT_EQ(a.truth_error, b.truth_error) << i;
      EXPECT_EQ(a.no_truth, b.no_truth) << i;
      EXPECT_FALSE(a.reference.empty());
    }
    for (std::size_t c = 0; c < serial.cells.size(); ++c) {
      EXPECT_EQ(serial.cells[c].alpha, threaded.cells[c].alpha) << c;
    }
  }
}

TEST(Plan, GridAlphaIsTheEquationsAlphaAsOnTheCommandLine) {
  const Plan plan = make_plan(load_scene(write_file("alpha.toml", R"([grid]
p = [1.0, 1.5, 3.0]
alpha = [0.3, 2.5]
v0 = [1.0, 2.0]
m = 0.5
[[solver]]
name = "taylor"
)")));
  ASSERT_EQ(plan.points.size(), 6u);
  for (const Point& point : plan.points) {
    ASSERT_EQ(point.damping.kind, Damping::Kind::alpha);
    EXPECT_EQ(point.damping.label(), "alpha=" + to_string_full(point.damping.value));
    EXPECT_EQ(static_cast<double>(point.alpha), point.damping.value);
    EXPECT_DOUBLE_EQ(point.alpha_eff, point.damping.value / std::sqrt(2 * (point.p + 1)));
  }
  EXPECT_TRUE(plan.points[1].overdamped); // p = 1, alpha 2.5: alpha_eff 1.25
  for (const Cell& cell : plan.cells) {
    const Point& point = plan.points[cell.point];
    // The scene's α is a double: its exact decimal, not "0.3" (which quad reads closer).
    const CliRun cli =
        run({"observables", "--p", to_string_full(point.p), "--alpha",
             fmt::format("{:.60g}", point.damping.value), "--v0", to_string_full(cell.v0), "--m",
             "0.5", "--precision", std::string(precision_name<Exact>()), "--json"});
    ASSERT_EQ(cli.code, 0) << cli.err;
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const std::string key(plan.observables[o]->key);
      const std::optional<Exact> got = reference_at(plan, cell, o, plan.configs[0]);
      const std::string number = raw_number(cli.out, key);
      if (number == "null") { // an infinite τ (overdamped)
        using std::isinf;
        EXPECT_TRUE(got && isinf(*got)) << key << " " << point.damping.label();
        continue;
      }
      ASSERT_TRUE(got) << key;
      const Exact want(number);
      const Exact scale = want == 0 ? Exact(1) : abs(want);
      EXPECT_LT(static_cast<double>(abs(*got - want) / scale), 1e-32)
          << key << " p=" << point.p << " " << point.damping.label() << " v0=" << cell.v0;
    }
  }
}

// Beyond the seed, α is converted at the scene's one cell, as `observables --damping-exponent
// --alpha` converts it at its contact: the same α_eff, and the cell gets the α typed.
TEST(Plan, GridAlphaBeyondTheSeedIsConvertedAtItsCell) {
  const Plan plan = make_plan(load_scene(write_file("alpha_beyond.toml", R"(want = ["e"]
[grid]
p = 1.5
damping_exponent = 0.5
alpha = 0.4
v0 = 2.0
m = 0.5
k = 3.0
[[solver]]
name = "taylor"
)")));
  ASSERT_EQ(plan.cells.size(), 1u);
  EXPECT_EQ(static_cast<double>(plan.cells[0].alpha), 0.4);
  const CliRun cli = run({"observables", "--p", "1.5", "--damping-exponent", "0.5", "--alpha",
                          "0.4", "--v0", "2", "--m", "0.5", "--k", "3", "--json"});
  ASSERT_EQ(cli.code, 0) << cli.err;
  EXPECT_DOUBLE_EQ(plan.points[0].alpha_eff, std::stod(raw_number(cli.out, "alpha_eff")));
}

} // namespace
// Every solver run a process starts is counted, and one past the run's limit asks it to stop
// (run/run.hpp): the guard holds whatever the plan's estimate said. 2 cells x 4 onset phases x 3
// repeats: 24 runs.
TEST(Plan, SolverRunsAreCountedAndTheLimitStopsTheRun) {
  const Plan plan = make_plan(load_scene(write_file("counted.toml", R"(want = ["e"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0, 2.0]
[timing]
repeats = 3
[[solver]]
name = "dem-verlet"
steps_per_contact = [20]
onset_phases = 4
)")));
  stop_requested() = false;
  limit_solver_runs(0);
  RunTotals totals;
  (void)run_plan(plan, 1, totals);
  EXPECT_EQ(solver_runs_made(), totals.solver_runs);
  EXPECT_GT(totals.solver_runs, 8); // the repeats counted too
  EXPECT_FALSE(solver_run_limit_reached());
  EXPECT_FALSE(stop_requested());
  limit_solver_runs(totals.solver_runs); // exactly enough
  RunTotals again;
  (void)run_plan(plan, 1, again);
  EXPECT_FALSE(solver_run_limit_reached());
  limit_solver_runs(totals.solver_runs - 1); // one short
  RunTotals stopped;
  (void)run_plan(plan, 1, stopped);
  EXPECT_TRUE(solver_run_limit_reached());
  EXPECT_TRUE(stop_requested());
  stop_requested() = false;
  limit_solver_runs(0);
}

} // namespace pldamp::harness
