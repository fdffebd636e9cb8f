// Every input keeps the precision of the run on every path (issue: `solve --damping-exponent
// --e 0.3` in quad once returned the double nearest 0.3). Each command and path is run in every
// precision with e = 0.3, which no binary type holds exactly: what comes back must be 0.3 to the
// precision's own epsilon (a trip through double would leave 1.1e-17 relative), judged in the
// precision itself. And `observables --damping-exponent`, once silently the seed's answer, gives
// the reference solve's.
#include "cli_run.hpp"
#include "fixtures.hpp"
#include "sampled_trajectories.hpp"
#include "support.hpp"

#include "common/input.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

namespace pldamp::harness {
namespace {

using testing::CliRun;
using testing::raw_number;
using testing::run;

// |value − 0.3| / 0.3 in units of Real's epsilon, both in Real.
template <SupportedReal Real>
double epsilons_from_three_tenths(const std::string& printed) {
  using std::abs;
  const Real three_tenths = parse_real<Real>("0.3", "0.3");
  const Real value = parse_real<Real>("printed", printed);
  return static_cast<double>(abs(value - three_tenths) / three_tenths /
                             std::numeric_limits<Real>::epsilon());
}

std::vector<std::string> with_precision_option(std::vector<std::string> args,
                                               std::string_view precision) {
  args.insert(args.end(), {"--precision", std::string(precision), "--json"});
  return args;
}

// One command and path: its output's `key` must be 0.3 within `bound` epsilons of every
// precision it runs in.
struct PathCase {
  std::string name;
  std::vector<std::string> args;
  std::string key;
  double bound; // in epsilons of the run's precision
  // The truth of a reference solve is float128 whatever the precision, its own error up to ~1e-33
  // (its error_estimate): allowed beside the bound. None in 50 digits, where it is refused.
  double truth_error = 0;
};

TEST(PrecisionPaths, ThreeTenthsComesBackInEveryPrecisionOnEveryPath) {
  const std::vector<PathCase> cases{
      {"calibrate, closed form", {"calibrate", "--p", "2.5", "--e", "0.3"}, "e", 0},
      {"calibrate --code (e the code gives)",
       {"calibrate", "--code", "lammps-coeff-restitution", "--p", "1.5", "--e", "0.3"},
       "e_given",
       16},
      {"observables, closed forms",
       {"observables", "--p", "2.5", "--e", "0.3", "--v0", "0.4"},
       "e",
       16},
      {"observables, force end (e_cap inverted numerically)",
       {"observables", "--p", "2.5", "--e", "0.3", "--v0", "0.4", "--end", "force"},
       "e_cap",
       16},
      {"observables, reference solve",
       {"observables", "--p", "2.5", "--e", "0.3", "--v0", "0.4", "--damping-exponent", "0.75"},
       "e",
       16,
       1e-33},
      {"solve taylor, the seed's damping",
       {"solve", "--solver", "taylor", "--p", "2.5", "--e", "0.3", "--v0", "0.4"},
       "e",
       64},
      {"solve taylor, a stated damping exponent",
       {"solve", "--solver", "taylor", "--p", "2.5", "--e", "0.3", "--v0", "0.4",
        "--damping-exponent", "0.75"},
       "e",
       64},
  };
  for (const PathCase& c : cases) {
    for_each_precision([&]<SupportedReal Real>() {
      if (std::is_same_v<Real, bin50> && c.truth_error > 0) {
        return;
      }
      const std::string precision(precision_name<Real>());
      const CliRun r = run(with_precision_option(c.args, precision));
      ASSERT_EQ(r.code, 0) << c.name << " in " << precision << ": " << r.err;
      const std::string printed = raw_number(r.out, c.key);
      EXPECT_LE(epsilons_from_three_tenths<Real>(printed),
                c.bound + c.truth_error / pldamp::testing::eps<Real>())
          << c.name << " in " << precision << ": " << c.key << " = " << printed;
    });
  }
}

// `check` judges against the closed forms in float128 whatever the file: its inputs are parsed
// there, so the truth of e = 0.3 is float128's 0.3 (through a double it would be 1.1e-17 off).
TEST(PrecisionPaths, CheckParsesItsInputsInTheTruthsPrecision) {
  const auto contact = analytic::Contact<double>::from_e(2.5, 0.3, 0.4);
  const std::string file = testing::write_file(
      "precision.csv", testing::csv_of(testing::sampled_contact(contact, 80, 0.3, true, false)));
  const CliRun r = run({"check", file, "--p", "2.5", "--e", "0.3", "--v0", "0.4", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string e = r.out.substr(r.out.find("\"e\": {"));
  EXPECT_LE(epsilons_from_three_tenths<Exact>(testing::raw_number(e, "truth")), 16) << e;
}

// The α a solve prints is the α it ran with, in its own precision; a double solve prints double
// digits (once α_eff came out with float128's 36).
TEST(PrecisionPaths, ADoubleSolvePrintsDoubles) {
  const CliRun r = run({"solve", "--solver", "cvode-bdf", "--p", "2.5", "--e", "0.3", "--v0", "0.4",
                        "--damping-exponent", "0.75", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* key : {"alpha", "alpha_eff", "e", "p", "damping_exponent"}) {
    const std::string printed = raw_number(r.out, key);
    EXPECT_EQ(to_string_full(std::stod(printed)), printed) << key;
  }
}

// `solve` runs at the α `calibrate` prints (and `run` sends, external_checks_test.cpp), to the
// last digit, in every precision, from e and from α_eff.
TEST(PrecisionPaths, SolveRunsAtTheAlphaCalibratePrints) {
  for_each_precision([&]<SupportedReal Real>() {
    const std::string precision(precision_name<Real>());
    for (const char* e : {"0.1", "0.3", "0.7", "0.9"}) {
      const CliRun calibrated =
          run({"calibrate", "--p", "1.5", "--e", e, "--precision", precision, "--json"});
      const CliRun solved = run({"solve", "--solver", "taylor", "--p", "1.5", "--e", e, "--v0", "1",
                                 "--want", "delta_max", "--precision", precision, "--json"});
      ASSERT_EQ(calibrated.code, 0) << calibrated.err;
      ASSERT_EQ(solved.code, 0) << solved.err;
      EXPECT_EQ(raw_number(solved.out, "alpha"), raw_number(calibrated.out, "alpha"))
          << "e = " << e << " in " << precision;
    }
  });
}

// The α a user's C++ gets from the library (Contact::from_e) is the one `calibrate` prints, bit
// for bit, at both ends, in every precision (issue 48: calibrated in double, 10 of 18 came one
// ulp off the command line's float128 rounded once).
TEST(PrecisionPaths, LibraryAlphaIsCalibratesAlpha) {
  for_each_precision([&]<SupportedReal Real>() {
    const std::string precision(precision_name<Real>());
    for (const char* p : {"1", "1.5", "2", "2.5", "3", "4"}) {
      for (const char* e : {"0.05", "0.3", "0.61", "0.9", "0.999"}) {
        for (const char* end : {"overlap", "force"}) {
          const CliRun calibrated = run(
              {"calibrate", "--p", p, "--e", e, "--end", end, "--precision", precision, "--json"});
          ASSERT_EQ(calibrated.code, 0) << calibrated.err;
          const auto library = analytic::Contact<Real>::from_e(
              parse_real<Real>("p", p), parse_real<Real>("e", e), Real(1), Real(1), Real(1),
              std::string_view(end) == "force" ? analytic::ContactEnd::force
                                               : analytic::ContactEnd::overlap);
          EXPECT_EQ(to_string_full(library.alpha()), raw_number(calibrated.out, "alpha"))
              << "p " << p << " e " << e << " " << end << " in " << precision;
          EXPECT_EQ(to_string_full(library.alpha_eff()), raw_number(calibrated.out, "alpha_eff"))
              << "p " << p << " e " << e << " " << end << " in " << precision;
        }
      }
    }
  });
}

// `observables --damping-exponent B`: the truth of that dashpot, which depends on v0 (MATH.md
// §12.1), from the reference solve: the viscoelastic Hertz contact at α = 0.3 gives e = 0.714 at
// v0 = 1 (issue 27's figure, from `solve --solver taylor`), not the seed's 0.6536, and another e
// at v0 = 0.1. Checked against taylor run through `solve` in quad at the same α.
TEST(PrecisionPaths, ObservablesWithADampingExponentAnswersFromTheReferenceSolve) {
  const CliRun seed = run({"observables", "--p", "1.5", "--alpha", "0.3", "--v0", "1", "--json"});
  ASSERT_EQ(seed.code, 0) << seed.err;
  EXPECT_EQ(nlohmann::json::parse(seed.out)["method"], "closed forms");
  std::vector<double> restitutions;
  for (const auto& [v0, m, k] :
       {std::tuple{"0.1", "1", "1"}, std::tuple{"1", "1", "1"}, std::tuple{"1", "2", "3"}}) {
    const CliRun r = run({"observables", "--p", "1.5", "--damping-exponent", "0.5", "--alpha",
                          "0.3", "--v0", v0, "--m", m, "--k", k, "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto got = nlohmann::json::parse(r.out);
    EXPECT_EQ(got["method"], "reference solve");
    EXPECT_NE(got["e"].get<double>(), nlohmann::json::parse(seed.out)["e"].get<double>());
    const CliRun solved = run({"solve", "--solver", "taylor", "--precision", "quad", "--p", "1.5",
                               "--damping-exponent", "0.5", "--alpha", "0.3", "--v0", v0, "--m", m,
                               "--k", k, "--json"});
    ASSERT_EQ(solved.code, 0) << solved.err;
    const auto want = nlohmann::json::parse(solved.out);
    for (const char* key : {"e", "delta_max", "t_peak", "tau", "energy_load", "energy_unload"}) {
      EXPECT_NEAR(got[key].get<double>(), want[key].get<double>(),
                  4e-16 * std::abs(want[key].get<double>()))
          << key << " at v0 = " << v0;
      ASSERT_TRUE(got["error_estimate"].contains(key)) << key;
      EXPECT_LT(got["error_estimate"][key].get<double>(), 1e-30) << key;
    }
    EXPECT_NEAR(got["tau_ratio"].get<double>(),
                got["tau"].get<double>() / got["tau0"].get<double>(), 1e-15);
    // The peak forces too: the total normal force's from the solve, the spring's k δ_max^p.
    for (const char* key : {"normal_force_max", "t_normal_force_max"}) {
      EXPECT_NEAR(got[key].get<double>(), want[key].get<double>(),
                  4e-16 * std::abs(want[key].get<double>()))
          << key << " at v0 = " << v0;
      EXPECT_LT(got["error_estimate"][key].get<double>(), 1e-30) << key;
    }
    EXPECT_NEAR(got["spring_force_max"].get<double>(),
                std::stod(k) * std::pow(want["delta_max"].get<double>(), 1.5),
                4e-16 * got["spring_force_max"].get<double>());
    EXPECT_LT(got["spring_force_max"].get<double>(), got["normal_force_max"].get<double>());
    restitutions.push_back(got["e"].get<double>());
  }
  EXPECT_NEAR(restitutions[1], 0.714, 5e-4);
  EXPECT_GT(restitutions[0], restitutions[1]); // less damping at lower speed: α_eff ∝ v0^(1/5)

  // The force end adds the capped restitution and the cut from the force-end reference solve.
  const CliRun capped = run({"observables", "--p", "1.5", "--damping-exponent", "0.5", "--e", "0.5",
                             "--v0", "1", "--end", "force", "--json"});
  ASSERT_EQ(capped.code, 0) << capped.err;
  const auto x = nlohmann::json::parse(capped.out);
  EXPECT_NEAR(x["e_cap"].get<double>(), 0.5, 1e-15);
  EXPECT_LT(x["e"].get<double>(), 0.5);
  EXPECT_LT(x["t_cut"].get<double>(), x["tau"].get<double>());

  // An overdamped contact the solve sees no exit of within its horizon: no e = 0, τ = ∞ (with δ^½
  // it creeps back later: at α_eff 250 τ = 1.06e4, at 300 beyond the horizon), but one line.
  const CliRun creeping = run({"observables", "--p", "1.5", "--damping-exponent", "0.5",
                               "--alpha-eff", "300", "--v0", "1", "--precision", "quad"});
  EXPECT_EQ(creeping.code, 2);
  EXPECT_EQ(creeping.out, "");
  EXPECT_NE(creeping.err.find("saw no exit within its horizon"), std::string::npos) << creeping.err;
  EXPECT_EQ(std::count(creeping.err.begin(), creeping.err.end(), '\n'), 1) << creeping.err;

  // The seed's own exponent, stated, has closed forms.
  const CliRun stated = run({"observables", "--p", "1.5", "--damping-exponent", "0.25", "--alpha",
                             "0.3", "--v0", "1", "--json"});
  ASSERT_EQ(stated.code, 0) << stated.err;
  EXPECT_EQ(nlohmann::json::parse(stated.out)["method"], "closed forms");
  EXPECT_EQ(nlohmann::json::parse(stated.out)["e"], nlohmann::json::parse(seed.out)["e"]);

  // 50 digits: refused, with the reason and what to do instead.
  const CliRun wide = run({"observables", "--p", "1.5", "--damping-exponent", "0.5", "--alpha",
                           "0.3", "--v0", "1", "--precision", "50"});
  EXPECT_EQ(wide.code, 2);
  EXPECT_NE(wide.err.find("it has no 50-digit truth"), std::string::npos) << wide.err;
}

} // namespace
} // namespace pldamp::harness
