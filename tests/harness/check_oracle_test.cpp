// `pldamp check` as a unit-test oracle: --tolerance and its exit status, and a file that
// contradicts its arguments refused (judge/trajectory.hpp: contradiction(); MATH.md §10.2).
#include "cli/commands.hpp"
#include "cli_run.hpp"
#include "fixtures.hpp"
#include "judge/trajectory.hpp"
#include "judge/trajectory_check.hpp"
#include "sampled_trajectories.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace pldamp::harness {
namespace {

using testing::CliRun;
using testing::csv_of;
using testing::dem_dump;
using testing::DemLoop;
using testing::run;
using testing::sampled_contact;
using testing::write_file;

TrajectoryObservables measured(const TrajectoryColumns& c,
                               const analytic::Contact<double>& contact) {
  ExtractOptions options{.v0 = contact.v0()};
  options.force_jumps_at_contact = contact.p() == 1 && contact.alpha() > 0;
  return extract_observables(c, options);
}

// The smallest factor s > 1 for which stating the field times s (`up`) or over s is refused.
double refused_from(const TrajectoryObservables& x, const StatedContact& right,
                    double StatedContact::*field, bool up) {
  double lo = 1, hi = 1e6;
  for (int i = 0; i < 50; ++i) {
    const double mid = std::sqrt(lo * hi);
    StatedContact stated = right;
    stated.*field = up ? right.*field * mid : right.*field / mid;
    (contradiction(x, stated) ? hi : lo) = mid;
  }
  return hi;
}

// Every file a correct code could write for the contact: the closed-form trajectory with and
// without v and F, at 17 and at 6 digits, and the dumps of two DEM loops (velocity Verlet, the
// force half a step from the state; symplectic Euler, a step behind it), with and without F.
std::vector<std::pair<std::string, TrajectoryColumns>>
files_of(const analytic::Contact<double>& contact, int n, double phase) {
  std::vector<std::pair<std::string, TrajectoryColumns>> files;
  for (const bool v : {false, true}) {
    for (const bool f : {false, true}) {
      const TrajectoryColumns c = sampled_contact(contact, n, phase, v, f);
      const std::string name = std::string("closed form") + (v ? " v" : "") + (f ? " F" : "");
      files.emplace_back(name, c);
      files.emplace_back(name + " 6 digits", parse_trajectory_csv(csv_of(c, 6), "six.csv"));
    }
  }
  for (const DemLoop loop : {DemLoop::verlet, DemLoop::symplectic_euler}) {
    const std::string name = loop == DemLoop::verlet ? "verlet" : "euler";
    files.emplace_back(name + " F", dem_dump(contact, n, phase, loop));
    files.emplace_back(name, dem_dump(contact, n, phase, loop));
    files.back().second.force.reset();
  }
  return files;
}

// No correct file is refused: p 1 to 3, e 0.1 to 0.9, 10 to 160 samples per contact, three
// phases of the sample grid. And what is refused: any other v0 (the approach is free flight), a
// k or m off by the factor each sampling resolves, and a forgotten --m or --k at any sampling.
TEST(CheckConsistency, NoCorrectFileIsRefusedAndAWrongArgumentIs) {
  std::map<int, double> worst; // samples per contact: the largest factor of k or m let through
  for (const double p : {1.0, 1.5, 2.0, 3.0}) {
    for (const double e : {0.1, 0.5, 0.9}) {
      const auto contact = analytic::Contact<double>::from_e(p, e, 1.0);
      const StatedContact right{.p = p, .m = 1, .k = 1, .v0 = 1};
      for (const int n : {10, 20, 40, 160}) {
        for (const double phase : {0.1, 0.5, 0.85}) {
          for (const auto& [name, c] : files_of(contact, n, phase)) {
            const TrajectoryObservables x = measured(c, contact);
            const std::string where =
                fmt::format("p {} e {} n {} phase {} {}", p, e, n, phase, name);
            const std::optional<std::string> why = contradiction(x, right);
            EXPECT_FALSE(why) << where << ": " << *why;
            for (const bool up : {false, true}) {
              for (const auto field : {&StatedContact::k, &StatedContact::m}) {
                worst[n] = std::max(worst[n], refused_from(x, right, field, up));
              }
              StatedContact speed = right;
              speed.v0 = up ? 1.001 : 1 / 1.001;
              EXPECT_TRUE(contradiction(x, speed)) << where;
            }
            StatedContact forgotten = right;
            forgotten.k = 7e9;
            EXPECT_TRUE(contradiction(x, forgotten)) << where;
            forgotten.m = 1e-2; // k/m and m both wrong
            EXPECT_TRUE(contradiction(x, forgotten)) << where;
          }
        }
      }
    }
  }
  for (const auto& [n, factor] : worst) {
    std::cout << n << " samples per contact: k or m refused when off by a factor " << factor
              << "\n";
  }
  // Measured: 10.8, 5.4, 2.9, 1.5.
  EXPECT_LT(worst[10], 12);
  EXPECT_LT(worst[20], 6);
  EXPECT_LT(worst[40], 3);
  EXPECT_LT(worst[160], 1.6);
}

// The CSV reader keeps each column's precision; a cell is known to half a unit in it.
TEST(CheckConsistency, TheFilesDigitsAreRead) {
  EXPECT_EQ(significant_digits("0.0480886"), 6);
  EXPECT_EQ(significant_digits("-1.50"), 3);
  EXPECT_EQ(significant_digits("7e9"), 1);
  EXPECT_EQ(significant_digits("+0.000123e-4"), 3);
  EXPECT_EQ(significant_digits("0"), 0);
  EXPECT_EQ(resolution_of(6), 5e-6);
  EXPECT_EQ(resolution_of(0), 0.5);
  EXPECT_EQ(resolution_of(17), std::numeric_limits<double>::epsilon());
  const TrajectoryColumns c =
      parse_trajectory_csv("t,delta,F\n0,-0.5,0\n0.25,0.125,1.5\n0.5,0.25,2.25\n", "d.csv");
  EXPECT_EQ(c.digits.t, 2);
  EXPECT_EQ(c.digits.delta, 3);
  EXPECT_EQ(c.digits.force, 3);
  EXPECT_EQ(TrajectoryColumns{}.digits.delta, 17); // built in code: a double's
}

// A contact at p = 1.5, e = 0.5, v0 = 2, m = 0.01, k = 7e9 (a bead), sampled 100 times, written
// to a file.
std::string bead_file(const std::string& name, bool with_v, bool with_force) {
  const auto contact = analytic::Contact<double>::from_e(1.5, 0.5, 2, 0.01, 7e9);
  return write_file(name, csv_of(sampled_contact(contact, 100, 0.3, with_v, with_force)));
}

CliRun check_bead(const std::string& path, std::vector<std::string> arguments) {
  std::vector<std::string> all{"check", path, "--p", "1.5", "--e", "0.5"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  return run(all);
}

// What a user who forgot --m or --k, or typed another v0, sees: not errors of -100 % but one
// line naming the disagreement, by how much, and what to give (exit 2).
TEST(CheckCli, AFileThatContradictsItsArgumentsIsRefusedWithWhatToGive) {
  const std::string with_f = bead_file("bead_f.csv", true, true);
  const CliRun right = check_bead(with_f, {"--v0", "2", "--m", "0.01", "--k", "7e9", "--json"});
  ASSERT_EQ(right.code, 0) << right.err;
  for (const char* key : {"e", "delta_max", "t_peak", "tau"}) {
    EXPECT_EQ(nlohmann::json::parse(right.out)[key]["verdict"], "explained by sampling") << key;
  }
  const auto refused = [](const CliRun& r, const std::string& begins, const std::string& ends) {
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(r.out.empty());
    EXPECT_EQ(r.err.rfind("error: " + begins, 0), 0u) << r.err;
    EXPECT_NE(r.err.find(ends), std::string::npos) << r.err;
    EXPECT_EQ(r.err.back(), '\n');
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  };
  // F / δ_max^p is k itself: 7e9 to the digits printed.
  refused(check_bead(with_f, {"--v0", "2"}),
          "the file's force at the peak is 7e+09 delta^1.5, not k delta^p with k = 1 (a factor "
          "7e+09 where its sampling, digits and rows about the peak allow",
          "give --k, or check --p (got --k 1)");
  refused(check_bead(with_f, {"--v0", "2", "--k", "7e9"}),
          "the file's force at the peak is 0.01 times its deceleration there, not m = 1 times",
          "give --m (got --m 1)");
  refused(check_bead(with_f, {"--v0", "2", "--k", "3.5e9", "--m", "0.01"}),
          "the file's force at the peak is 7e+09 delta^1.5, not k delta^p with k = 3.5e+09 (a "
          "factor 2 where",
          "(got --k 3.5e+09)");
  // Without F the file fixes k/m only: 7e11, to the reading of δ'' between 100 samples (0.8 %
  // off without v, on δ's parabola).
  for (const auto& [file, arguments, stated] :
       {std::tuple{bead_file("bead_v.csv", true, false), std::vector<std::string>{"--v0", "2"},
                   std::string("1 (")},
        std::tuple{bead_file("bead.csv", false, false),
                   std::vector<std::string>{"--v0", "2", "--k", "7e9"}, std::string("7e+09 (")}}) {
    const CliRun r = check_bead(file, arguments);
    refused(r, "the file's deceleration at the peak is ", "give --m and --k, whose ratio it fixes");
    const std::size_t is = r.err.find("peak is ") + 8;
    EXPECT_NEAR(std::stod(r.err.substr(is)), 7e11, 1e-2 * 7e11) << r.err;
    EXPECT_NE(r.err.find(" delta^1.5, not (k/m) delta^p with k/m = " + stated), std::string::npos)
        << r.err;
  }
  // Another v0: read from v before contact, or from delta's slope there.
  refused(check_bead(with_f, {"--v0", "1", "--m", "0.01", "--k", "7e9"}),
          "the file's incoming speed is 2 (v on the last row before contact), not --v0 1: a "
          "factor 2 where its sampling and digits allow 1",
          "give --v0 2 (got --v0 1)");
  refused(
      check_bead(bead_file("bead.csv", false, false), {"--v0", "2.5", "--m", "0.01", "--k", "7e9"}),
      "the file's incoming speed is 2 (delta's slope on the two rows before contact), not "
      "--v0 2.5",
      "give --v0 2 (got --v0 2.5)");
  // v of the wrong sign (not d(delta)/dt).
  TrajectoryColumns flipped =
      sampled_contact(analytic::Contact<double>::from_e(1.5, 0.5, 1.0), 50, 0.3, true, false);
  for (double& v : *flipped.v) {
    v = -v;
  }
  refused(run({"check", write_file("flipped.csv", csv_of(flipped)), "--p", "1.5", "--e", "0.5",
               "--v0", "1"}),
          "the file's incoming speed is -1 (v on the last row before contact), not --v0 1: of "
          "the opposite sign; v must be d(delta)/dt, > 0 while loading (got --v0 1)",
          "(got --v0 1)");
}

// The shipped trajectories and a scene's entry go through the same refusal.
TEST(CheckScene, AContradictingFileFailsItsEntryWithTheReason) {
  const std::string file = bead_file("scene_bead.csv", true, true);
  const std::string text = "[grid]\np = 1.5\ne = 0.5\nv0 = 2.0\n[[trajectory]]\nfile = \"" + file +
                           "\"\np = 1.5\ne = 0.5\nv0 = 2.0\n";
  const Scene scene = parse_scene(text, "/x/s.toml");
  const TrajectoryCheck checked = check_trajectory(scene.trajectories[0], scene.end);
  EXPECT_EQ(checked.failure.rfind("the file's force at the peak is 7e+09 delta^1.5", 0), 0u)
      << checked.failure;
  EXPECT_TRUE(checked.rows.empty());
  for (const char* shipped : {"hertz_taylor_every_0.1.csv", "hertz_dem_verlet_50.csv"}) {
    const CliRun r = run({"check", std::string(PLDAMP_DATA_DIR) + "/trajectories/" + shipped, "--p",
                          "1.5", "--e", "0.5", "--v0", "1"});
    EXPECT_EQ(r.code, 0) << shipped << ": " << r.err;
  }
}

} // namespace
} // namespace pldamp::harness

namespace pldamp::harness {
namespace {

// The closed-form values at p, e under `end` (v0 = m = k = 1), in double: the truth of a check.
std::map<std::string, double> truth_at(double p, double e, solvers::End end) {
  const auto c = analytic::Contact<Exact>::from_e(Exact(p), Exact(e), Exact(1));
  const auto x = analytic::observables(c);
  const bool capped = end == solvers::End::force;
  return {{"e", double(capped ? *x.e_cap : *x.e)},
          {"delta_max", double(*x.delta_max)},
          {"t_peak", double(*x.t_peak)},
          {"tau", double(capped ? *x.t_cut : *x.tau)},
          {"normal_force_max", double(*x.normal_force_max)},
          {"t_normal_force_max", double(*x.t_normal_force_max)}};
}

// A velocity-Verlet loop at 50 steps per contact, judged under --tolerance: the observables
// whose |rel error| (computed here from the extraction and the closed forms) exceeds it fail,
// named, exit 1; within it, exit 0. Per observable, only those named are judged.
TEST(CheckCli, ToleranceJudgesEachObservableAndExitsOneOnAFailure) {
  const auto contact = analytic::Contact<double>::from_e(1.5, 0.5, 1.0);
  const TrajectoryColumns dump = dem_dump(contact, 50, 0.3);
  const std::string path = write_file("verlet50.csv", csv_of(dump));
  const TrajectoryObservables x = measured(dump, contact);
  const std::map<std::string, double> truth = truth_at(1.5, 0.5, solvers::End::overlap);
  std::map<std::string, double> rel, rel_sampling;
  for (const auto& [key, value] :
       {std::pair{"e", &x.e}, std::pair{"delta_max", &x.delta_max}, std::pair{"t_peak", &x.t_peak},
        std::pair{"tau", &x.tau}, std::pair{"normal_force_max", &x.normal_force_max},
        std::pair{"t_normal_force_max", &x.t_normal_force_max}}) {
    rel[key] = std::abs(*value->value - truth.at(key)) / truth.at(key);
    rel_sampling[key] = value->sampling / truth.at(key);
    EXPECT_GT(rel[key], 1e-4) << key; // the loop's first-order errors
    EXPECT_LT(rel[key], 3e-2) << key;
  }
  const auto check = [&](const std::string& tolerance, bool json) {
    std::vector<std::string> args{"check", path,   "--p", "1.5",         "--e",
                                  "0.5",   "--v0", "1",   "--tolerance", tolerance};
    if (json) {
      args.push_back("--json");
    }
    return run(args);
  };
  double largest = 0;
  for (const auto& [key, value] : rel) {
    largest = std::max({largest, value, rel_sampling[key]});
  }
  const CliRun pass = check(fmt::format("{}", 1.5 * largest), true);
  ASSERT_EQ(pass.code, 0) << pass.err;
  const auto passed = nlohmann::json::parse(pass.out);
  EXPECT_EQ(passed["passed"], true);
  for (const auto& [key, value] : rel) {
    EXPECT_EQ(passed[key]["pass"], true) << key;
    EXPECT_EQ(passed[key]["tolerance"].get<double>(), 1.5 * largest) << key;
  }
  EXPECT_EQ(check(fmt::format("{}", 1.5 * largest), false)
                .out.substr(check(fmt::format("{}", 1.5 * largest), false).out.rfind("passed")),
            "passed: every judged observable is within its tolerance\n");

  // Between the errors: the larger ones fail, by name.
  std::vector<double> sorted;
  for (const auto& [key, value] : rel) {
    sorted.push_back(value);
  }
  std::sort(sorted.begin(), sorted.end());
  const double between = std::sqrt(sorted[1] * sorted[2]);
  std::string failing;
  for (const char* key :
       {"e", "delta_max", "t_peak", "tau", "normal_force_max", "t_normal_force_max"}) {
    if (rel[key] > between || rel_sampling[key] > between) {
      failing += (failing.empty() ? "" : ", ") + std::string(key);
    }
  }
  const CliRun fail = check(fmt::format("{}", between), false);
  EXPECT_EQ(fail.code, 1) << fail.err;
  EXPECT_TRUE(fail.err.empty()) << fail.err;
  EXPECT_EQ(fail.out.substr(fail.out.rfind("FAILED")), "FAILED: " + failing + "\n") << fail.out;
  const auto failed = nlohmann::json::parse(check(fmt::format("{}", between), true).out);
  EXPECT_EQ(failed["passed"], false);
  for (const auto& [key, value] : rel) {
    const bool fails = value > between || rel_sampling[key] > between;
    EXPECT_EQ(failed[key]["pass"], !fails) << key;
    EXPECT_EQ(failed[key].contains("failure"), fails) << key;
  }

  // Per observable: e passes, tau fails, the others are not judged.
  const CliRun some =
      check(fmt::format("e={},tau={}", 2 * (rel["e"] + rel_sampling["e"]), rel["tau"] / 2), true);
  EXPECT_EQ(some.code, 1);
  const auto judged = nlohmann::json::parse(some.out);
  EXPECT_EQ(judged["e"]["pass"], true);
  EXPECT_EQ(judged["tau"]["pass"], false);
  EXPECT_EQ(judged["tau"]["failure"],
            fmt::format("|rel error| {:.3g} > {:.3g}", rel["tau"], rel["tau"] / 2));
  EXPECT_FALSE(judged["delta_max"].contains("pass"));
  EXPECT_FALSE(judged["t_peak"].contains("tolerance"));
  // Without --tolerance: measured, exit 0, no verdict keys.
  const CliRun plain = run({"check", path, "--p", "1.5", "--e", "0.5", "--v0", "1", "--json"});
  EXPECT_EQ(plain.code, 0);
  EXPECT_FALSE(nlohmann::json::parse(plain.out).contains("passed"));
}

// A judged observable the file cannot give fails with the reason; so does one whose sampling
// estimate alone exceeds the tolerance (the file cannot resolve it: adding the estimate instead
// would let a coarse file pass any tolerance).
TEST(CheckCli, ToleranceFailsWhatTheFileCannotShow) {
  const std::string open =
      write_file("open.csv", "t,delta\n-0.1,-0.1\n0.1,0.0995\n0.2,0.19\n0.3,0.27\n0.4,0.33\n");
  const CliRun missing =
      run({"check", open, "--p", "1.5", "--e", "0.5", "--v0", "1", "--tolerance", "tau=0.5"});
  EXPECT_EQ(missing.code, 1);
  EXPECT_EQ(missing.out.substr(missing.out.rfind("\ntau ")),
            fmt::format("\n{:<18} {:>9}  FAIL: the contact does not end within the series\nFAILED: "
                        "tau\n",
                        "tau", 0.5))
      << missing.out;

  const auto contact = analytic::Contact<double>::from_e(1.5, 0.5, 1.0);
  const TrajectoryColumns coarse = sampled_contact(contact, 20, 0.3, false, false);
  const TrajectoryObservables x = measured(coarse, contact);
  const double truth = truth_at(1.5, 0.5, solvers::End::overlap).at("e");
  const double rel = std::abs(*x.e.value - truth) / truth;
  const double rel_sampling = x.e.sampling / truth;
  ASSERT_LT(10 * rel, rel_sampling); // the closed form's samples: within the estimate
  const double tolerance = std::sqrt(rel * rel_sampling);
  const CliRun unresolved =
      run({"check", write_file("coarse.csv", csv_of(coarse)), "--p", "1.5", "--e", "0.5", "--v0",
           "1", "--tolerance", fmt::format("e={}", tolerance), "--json"});
  EXPECT_EQ(unresolved.code, 1) << unresolved.err;
  const auto o = nlohmann::json::parse(unresolved.out);
  EXPECT_EQ(o["e"]["failure"],
            fmt::format("its sampling estimate {:.3g} > {:.3g}: the file cannot resolve the "
                        "tolerance, dump more often",
                        rel_sampling, tolerance));
}

TEST(CheckCli, ABadToleranceIsRefusedBeforeTheFileIsRead) {
  const std::string expected =
      "e|delta_max|t_peak|tau|normal_force_max|t_normal_force_max=T,... with T > 0";
  for (const auto& [tolerance, message] : std::vector<std::pair<std::string, std::string>>{
           {"0", "a tolerance must be a relative one in (0, 1) (got 0)"},
           {"-1e-3", "a tolerance must be a relative one in (0, 1) (got -1e-3)"},
           {"inf", "a tolerance must be a relative one in (0, 1) (got inf)"},
           {"nan", "a tolerance must be a relative one in (0, 1) (got nan)"},
           {"1", "a tolerance must be a relative one in (0, 1) (got 1)"},
           {"tau=2", "a tolerance must be a relative one in (0, 1) (got tau=2)"},
           {"abc", "--tolerance takes a relative tolerance T or " + expected + " (got abc)"},
           {"", "--tolerance takes a relative tolerance T or " + expected + " (got )"},
           {"e=", "--tolerance takes a relative tolerance T or " + expected + " (got e=)"},
           {"e=1e-3,",
            "--tolerance takes a relative tolerance T or " + expected + " (got e=1e-3,)"},
           {"e=0", "a tolerance must be a relative one in (0, 1) (got e=0)"},
           {"speed=1e-3", "unknown observable in --tolerance, expected "
                          "e|delta_max|t_peak|tau|normal_force_max|t_normal_force_max (got speed)"},
           {"e_cap=1e-3", "unknown observable in --tolerance, expected "
                          "e|delta_max|t_peak|tau|normal_force_max|t_normal_force_max (got e_cap)"},
           {"e=1e-3,tau", "--tolerance takes a relative tolerance T or " + expected + " (got tau)"},
           {"e=1e-3,e=1e-2", "--tolerance names an observable twice (got e)"}}) {
    const CliRun r = run({"check", "/no/such.csv", "--p", "1.5", "--e", "0.5", "--v0", "1",
                          "--tolerance", tolerance});
    EXPECT_EQ(r.code, 2) << tolerance;
    EXPECT_EQ(r.err, "error: " + message + "\n");
  }
  // Under --end force the names are the force end's.
  const CliRun force = run({"check", "/no/such.csv", "--p", "1.5", "--e", "0.5", "--v0", "1",
                            "--end", "force", "--tolerance", "e=1e-3"});
  EXPECT_EQ(force.err,
            "error: unknown observable in --tolerance, expected "
            "e_cap|delta_max|t_peak|t_cut|normal_force_max|t_normal_force_max (got e)\n");
}

} // namespace
} // namespace pldamp::harness

namespace pldamp::harness {
namespace {

// A series starting in contact, its peak on its second row: the curvature there is read from the
// rows there are (once, a parabola "one row before" was read from row −1).
TEST(CheckConsistency, APeakOnTheSecondRowOfASeriesInContactIsReadFromItsRows) {
  TrajectoryColumns c; // δ = 1 − (t − 0.1)², in contact from its first row
  for (int i = 0; i <= 6; ++i) {
    const double t = 0.1 * i;
    c.t.push_back(t);
    c.delta.push_back(1 - (t - 0.1) * (t - 0.1));
  }
  const TrajectoryObservables x = extract_observables(c, {.v0 = 1});
  ASSERT_TRUE(x.peak_acceleration.value);
  EXPECT_NEAR(*x.peak_acceleration.value, -2, 1e-12);
  EXPECT_LT(x.peak_acceleration.sampling, 1e-10); // one parabola: the rows agree (ASan: in range)
  EXPECT_FALSE(x.incoming_speed.value);
  EXPECT_EQ(x.incoming_speed.missing, "the series starts in contact");
}

} // namespace
} // namespace pldamp::harness
