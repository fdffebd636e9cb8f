// The CLI contract (docs/design.md §7), run in-process: JSON keys and digits, the force end, and
// every kind of bad input producing one "error: <what> (got <value>)" line and exit code 2.
#include "cli_run.hpp"
#include "fixtures.hpp"
#include "pldamp/analytic.hpp"

#include "cli/commands.hpp"
#include "common/files.hpp"
#include "pipeline/pipeline.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace pldamp::harness {
namespace {

using testing::CliRun;
using testing::run;

TEST(Cli, ObservablesJsonCarriesTheContractKeys) {
  const CliRun r = run({"observables", "--p", "1.5", "--e", "0.5", "--v0", "2", "--m", "0.01",
                        "--k", "7e9", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  for (const char* key : {"p", "m", "k", "v0", "alpha", "alpha_eff", "e", "delta_max", "t_peak",
                          "tau", "spring_force_max", "normal_force_max", "t_normal_force_max",
                          "energy_load", "energy_unload", "dt_crit"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_FALSE(json.contains("e_cap"));
  const auto c = analytic::Contact<double>::from_e(1.5, 0.5, 2, 0.01, 7e9);
  EXPECT_EQ(json["delta_max"].get<double>(), analytic::delta_max(c)); // shortest round trip
  EXPECT_EQ(json["tau"].get<double>(), analytic::contact_duration(c));
  EXPECT_NEAR(json["log_tau"].get<double>(), std::log(json["tau"].get<double>()), 1e-15);
  // Just below critical damping τ overflows double: null, while ln τ is still given.
  const CliRun edge =
      run({"observables", "--p", "3", "--alpha-eff", "0.999999", "--v0", "1", "--json"});
  ASSERT_EQ(edge.code, 0) << edge.err;
  const auto at_edge = nlohmann::json::parse(edge.out);
  EXPECT_TRUE(at_edge["tau"].is_null());
  EXPECT_GT(at_edge["log_tau"].get<double>(), 709.8); // beyond ln(DBL_MAX)
  EXPECT_EQ(at_edge["e"].get<double>(), 0.0);
  EXPECT_LT(at_edge["log_e"].get<double>(), -2000.0);
}

#if PLDAMP_WITH_QUAD
using testing::raw_number;

TEST(Cli, QuadPrintsThirtySixDigits) {
  const CliRun r = run(
      {"observables", "--p", "1.5", "--e", "0.5", "--v0", "2", "--precision", "quad", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string number = raw_number(r.out, "tau");
  const std::string mantissa = number.substr(0, number.find('e'));
  int digits = 0;
  for (char ch : mantissa) {
    digits += (ch >= '0' && ch <= '9') ? 1 : 0;
  }
  EXPECT_EQ(digits, 36) << number;
  const auto c = analytic::Contact<quad>::from_e(quad(3) / 2, quad(1) / 2, quad(2));
  EXPECT_EQ(quad(number), analytic::contact_duration(c));
}

TEST(Cli, TaylorSolvesInQuadToItsEpsilon) {
  const CliRun r = run({"solve", "--solver", "taylor", "--precision", "quad", "--p", "2.5", "--e",
                        "0.3", "--v0", "0.4", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = analytic::Contact<quad>::from_e(quad(5) / 2, quad(3) / 10, quad(2) / 5);
  const auto x = analytic::observables(c);
  for (const auto& [key, want] :
       {std::pair{"e", *x.e}, std::pair{"delta_max", *x.delta_max}, std::pair{"tau", *x.tau},
        std::pair{"energy_unload", *x.energy_unload}}) {
    const quad got(raw_number(r.out, key));
    EXPECT_LT(static_cast<double>(abs(got - want) / want), 1e-30) << key;
  }
  EXPECT_EQ(raw_number(r.out, "rtol"), "1.92592994438723585305597794258492732e-34"); // ε of quad
  EXPECT_EQ(raw_number(r.out, "outcome"), "\"exited\"");
}
#endif

TEST(Cli, OverdampedTauIsNullAndForceEndAddsTheCut) {
  const CliRun r = run(
      {"observables", "--p", "2", "--alpha-eff", "1.5", "--v0", "1", "--end", "force", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_TRUE(json["tau"].is_null());
  EXPECT_EQ(json["e"].get<double>(), 0.0);
  const auto d = analytic::damping_from_alpha_eff(1.5);
  EXPECT_EQ(json["e_cap"].get<double>(), analytic::capped_restitution(d));
  EXPECT_GT(json["t_cut"].get<double>(), json["t_peak"].get<double>());
}

// A damping whose square underflows double (MATH.md §3, "Vanishing damping"): G and the normal
// force's peak were formed through μ/z² and μr² ~ 1/z², which overflowed, and the answer had
// normal_force_max 0 at t 0 and energy_load 0. Every observable is the undamped one but the
// losses, KE0 π α_eff (a subnormal at denorm_min, rounded once), at both ends.
TEST(Cli, VanishingDampingKeepsTheForcePeakAndTheLoadingLoss) {
  const auto observables = [](const char* alpha_eff) {
    const CliRun r = run({"observables", "--p", "1.5", "--alpha-eff", alpha_eff, "--v0", "1",
                          "--end", "force", "--json"});
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const auto undamped = observables("0");
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(undamped["normal_force_max"].get<double>(), 1.1433, 1e-4);
  EXPECT_NEAR(undamped["t_normal_force_max"].get<double>(), 1.609, 1e-3);
  for (const char* alpha_eff : {"1e-200", "1e-160", "5e-324"}) {
    const auto tiny = observables(alpha_eff);
    for (const char* key : {"normal_force_max", "t_normal_force_max", "spring_force_max", "t_peak",
                            "delta_max", "tau", "t_cut", "e", "e_cap"}) {
      const double want = undamped[key].get<double>();
      EXPECT_NEAR(tiny[key].get<double>(), want, 4 * eps * want) << key << " at " << alpha_eff;
    }
    const double loss = M_PI / 2 * std::strtod(alpha_eff, nullptr); // KE0 π α_eff (stod: ERANGE)
    for (const char* key : {"energy_load", "energy_unload"}) {
      const double got = tiny[key].get<double>();
      EXPECT_NEAR(got, loss, std::max(4 * eps * loss, std::numeric_limits<double>::denorm_min()))
          << key << " at " << alpha_eff;
    }
  }
}

TEST(Cli, CalibrateBothEnds) {
  const CliRun overlap = run({"calibrate", "--p", "1.5", "--e", "0.5", "--json"});
  ASSERT_EQ(overlap.code, 0) << overlap.err;
  const auto a = nlohmann::json::parse(overlap.out);
  const double xi = -std::log(0.5) / std::sqrt(M_PI * M_PI + std::log(0.5) * std::log(0.5));
  EXPECT_NEAR(a["alpha"].get<double>(), std::sqrt(5.0) * xi, 1e-15);

  const CliRun force = run({"calibrate", "--p", "1.5", "--e", "0.5", "--end", "force", "--json"});
  ASSERT_EQ(force.code, 0) << force.err;
  const auto b = nlohmann::json::parse(force.out);
  const auto d = analytic::damping_from_alpha_eff(b["alpha_eff"].get<double>());
  EXPECT_NEAR(analytic::capped_restitution(d), 0.5, 1e-15);
  EXPECT_LT(b["e_uncapped"].get<double>(), 0.5);
}

// α and α_eff are one damping: both the root in 80 digits rounded once, so in double α_eff is
// the float128 answer rounded (at e = 1e−10, force end, it was 1.7e−7 off while α was right).
TEST(Cli, CalibrateRoundsAlphaEffOnceAsAlpha) {
  for (const char* end : {"force", "overlap"}) {
    for (const char* e : {"0.5", "1e-4", "1e-10"}) {
      const CliRun fast = run({"calibrate", "--p", "1.5", "--e", e, "--end", end, "--json"});
      const CliRun wide =
          run({"calibrate", "--p", "1.5", "--e", e, "--end", end, "--json", "--precision", "quad"});
      ASSERT_EQ(fast.code, 0) << fast.err;
      ASSERT_EQ(wide.code, 0) << wide.err;
      const auto a = nlohmann::json::parse(fast.out);
      // The quad number as text, rounded to double by strtod (correctly rounded).
      const std::string text = wide.out.substr(wide.out.find("\"alpha_eff\": ") + 13);
      const double rounded = std::strtod(text.c_str(), nullptr);
      EXPECT_EQ(a["alpha_eff"].get<double>(), rounded) << end << " e=" << e;
      EXPECT_NEAR(a["alpha_eff"].get<double>() * std::sqrt(5.0), a["alpha"].get<double>(),
                  4e-16 * a["alpha"].get<double>())
          << end << " e=" << e;
    }
  }
}

// A velocity-dependent model (MATH.md §12.4): the α that gives e at --v0 is checked by solving
// that α with taylor through `solve --damping-exponent` (an independent path: --alpha, no
// inversion), e falls with the speed for the viscoelastic dashpot (more damping at higher
// α_eff ∝ v0^(1/5)), and at p = 1 mass_velocity is the seed's linear dashpot: the reference
// solve's calibration equals the closed form's.
TEST(Cli, CalibrateAVelocityDependentCodeAndItsRestitutionAtOtherSpeeds) {
  const CliRun viscoelastic =
      run({"calibrate", "--code", "lammps-hertz-history", "--p", "1.5", "--e", "0.9", "--v0", "2",
           "--m", "3", "--k", "5", "--reff", "4", "--speeds", "0.2,2,20", "--json"});
  ASSERT_EQ(viscoelastic.code, 0) << viscoelastic.err;
  const auto a = nlohmann::json::parse(viscoelastic.out);
  const double alpha = a["alpha"].get<double>();
  EXPECT_NEAR(a["entry"].get<double>(), alpha * std::sqrt(5.0 / 3.0) / 2, 1e-15);
  const auto curve = a["e_of_v0"];
  ASSERT_EQ(curve.size(), 3U);
  EXPECT_NEAR(curve[1]["e"].get<double>(), 0.9, 1e-15);
  EXPECT_GT(curve[0]["e"].get<double>(), 0.9);
  EXPECT_LT(curve[2]["e"].get<double>(), 0.9);
  // α_eff ∝ v0^(2(β − (p−1)/2)/(p+1)) = v0^(1/5).
  EXPECT_NEAR(curve[2]["alpha_eff"].get<double>() / curve[1]["alpha_eff"].get<double>(),
              std::pow(10.0, 0.2), 1e-14);
  for (const int at : {0, 2}) {
    const std::string v0 = curve[at]["v0"].dump();
    const CliRun solved = run({"solve", "--solver", "taylor", "--p", "1.5", "--damping-exponent",
                               "0.5", "--alpha", a["alpha"].dump(), "--v0", v0, "--m", "3", "--k",
                               "5", "--precision", "quad", "--json"});
    ASSERT_EQ(solved.code, 0) << solved.err;
    const auto x = nlohmann::json::parse(solved.out);
    EXPECT_NEAR(x["e"].get<double>(), curve[at]["e"].get<double>(), 1e-15) << v0;
  }

  const CliRun linear =
      run({"calibrate", "--code", "lammps-mass-velocity", "--p", "1", "--e", "0.3", "--json"});
  ASSERT_EQ(linear.code, 0) << linear.err;
  const CliRun closed = run({"calibrate", "--p", "1", "--e", "0.3", "--json"});
  ASSERT_EQ(closed.code, 0) << closed.err;
  const auto linear_json = nlohmann::json::parse(linear.out); // outlives the loop below
  EXPECT_NEAR(linear_json["alpha"].get<double>(),
              nlohmann::json::parse(closed.out)["alpha"].get<double>(), 1e-15);
  for (const auto& point : linear_json["e_of_v0"]) {
    EXPECT_NEAR(point["e"].get<double>(), 0.3, 1e-15); // the seed's e does not depend on v0
  }

  // Damping beyond what the reference solve resolves: no e (it answered 0 at 1e20, the solve's
  // horizon taken for no return) and refused at once (1e30 took 140 s to end step_limit), by the
  // first group on the way up in steps of 8 that does not return.
  const CliRun beyond = run({"calibrate", "--code", "lammps-hertz-history", "--p", "1.5", "--e",
                             "0.9", "--v0", "1", "--speeds", "1e30"});
  EXPECT_EQ(beyond.code, 2);
  EXPECT_EQ(beyond.err, "error: at v0 = 1e+30 (alpha_eff 42186.8) no e: the reference solve at "
                        "alpha_eff 512 saw no return within its horizon of 10^4 delta_u/v0, and "
                        "more damping returns later; ask at lower damping (got --speeds 1e+30)\n");

  // An e below what the reference solve resolves is refused by the first group that does not
  // return (it took 45 s, then failed naming a --speeds never given); a code's formula that
  // divides by 0 is refused naming --e (not "alpha_eff must be finite (got inf)").
  const CliRun tiny = run(
      {"calibrate", "--code", "lammps-hertz-history", "--p", "1.5", "--e", "1e-30", "--v0", "1"});
  EXPECT_EQ(tiny.code, 2);
  EXPECT_EQ(tiny.err.rfind("error: no damping gives e = 1e-30 with lammps-hertz-history that the "
                           "reference solve resolves",
                           0),
            0u)
      << tiny.err;
  EXPECT_NE(tiny.err.find("(got --e 1e-30)"), std::string::npos) << tiny.err;
  for (const char* command : {"calibrate", "timestep"}) {
    std::vector<std::string> args{command, "--code", "yade-hertz-mindlin", "--p", "1.5",
                                  "--e",   "1e-50"};
    if (std::string(command) == "timestep") {
      args.insert(args.end(), {"--scheme", "dem-verlet"});
    }
    const CliRun divided = run(args);
    EXPECT_EQ(divided.err,
              "error: yade-hertz-mindlin's formula sets no finite alpha at this e (the "
              "code itself divides by 0 there) (got --e 1e-50)\n");
  }

  const CliRun wrong_p =
      run({"calibrate", "--code", "lammps-viscoelastic", "--p", "1", "--e", "0.5"});
  EXPECT_EQ(wrong_p.code, 2);
  EXPECT_EQ(wrong_p.err,
            "error: lammps-viscoelastic is a hertz model: p must be 1.5 (got --p 1)\n");
}

// --damping-exponent on solve: stated as the seed's (p − 1)/2 it calibrates --e to the closed
// form's α (through the reference solve), and out of [0, p] it is refused.
TEST(Cli, SolveTakesADampingExponent) {
  const CliRun stated =
      run({"solve", "--solver", "taylor", "--p", "2", "--e", "0.4", "--damping-exponent", "0.5",
           "--v0", "1", "--precision", "quad", "--json"});
  ASSERT_EQ(stated.code, 0) << stated.err;
  const CliRun seed = run({"solve", "--solver", "taylor", "--p", "2", "--e", "0.4", "--v0", "1",
                           "--precision", "quad", "--json"});
  ASSERT_EQ(seed.code, 0) << seed.err;
  const auto a = nlohmann::json::parse(stated.out), b = nlohmann::json::parse(seed.out);
  EXPECT_EQ(a["damping_exponent"].get<double>(), 0.5);
  EXPECT_EQ(b["damping_exponent"].get<double>(), 0.5);
  EXPECT_NEAR(a["alpha"].get<double>(), b["alpha"].get<double>(), 1e-15);
  EXPECT_NEAR(a["e"].get<double>(), 0.4, 1e-16);
  const CliRun refused = run({"solve", "--solver", "taylor", "--p", "1.5", "--e", "0.4",
                              "--damping-exponent", "-0.5", "--v0", "1"});
  EXPECT_EQ(refused.code, 2);
  EXPECT_EQ(refused.err, "error: damping exponent must be in [0, p] = [0, 1.5] (got -0.5)\n");
}

TEST(Cli, CalibrateForACodeSaysWhatItGivesAndWhatToEnter) {
  const CliRun tsuji =
      run({"calibrate", "--code", "lammps-tsuji", "--p", "1.5", "--e", "0.5", "--json"});
  ASSERT_EQ(tsuji.code, 0) << tsuji.err;
  const auto a = nlohmann::json::parse(tsuji.out);
  const analytic::Convention& convention = *analytic::find_convention("lammps-tsuji");
  EXPECT_EQ(a["alpha"].get<double>(), analytic::tsuji_polynomial(0.5));
  EXPECT_NEAR(a["e_given"].get<double>(), 0.616076, 1e-6);
  EXPECT_EQ(a["end"], "overlap");
  // Entering e_to_enter gives the target back.
  const double entry = a["e_to_enter"].get<double>();
  EXPECT_NEAR(analytic::e_given(1.5, analytic::alpha_set(convention, 1.5, entry), false), 0.5,
              1e-14);
  EXPECT_NE(a["source"].get<std::string>().find("gran_sub_mod_damping.cpp"), std::string::npos);

  const CliRun chrono =
      run({"calibrate", "--code", "chrono", "--p", "1.5", "--e", "0.1", "--json"});
  ASSERT_EQ(chrono.code, 0) << chrono.err;
  const auto b = nlohmann::json::parse(chrono.out);
  EXPECT_EQ(b["end"], "force");
  EXPECT_TRUE(b["e_to_enter"].is_null()); // a capped code calibrated at the overlap end: ≥ e^-2
  EXPECT_GT(b["e_reachable_from"].get<double>(), std::exp(-2.0));

  const CliRun limited = run(
      {"calibrate", "--code", "liggghts", "--p", "1", "--e", "0.5", "--limit-damping", "--json"});
  ASSERT_EQ(limited.code, 0) << limited.err;
  const auto c = nlohmann::json::parse(limited.out);
  EXPECT_EQ(c["end"], "force");
  EXPECT_NEAR(c["e_given"].get<double>(),
              analytic::capped_restitution(analytic::damping_from_e(0.5)), 1e-15);
}

TEST(Cli, TextOutputAndShowcase) {
  const CliRun text = run({"observables", "--p", "2", "--e", "0.5", "--v0", "1"});
  ASSERT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("delta_max"), std::string::npos);
  const CliRun showcase = run({"showcase"});
  ASSERT_EQ(showcase.code, 0);
  EXPECT_NE(showcase.out.find("2.5"), std::string::npos);
  EXPECT_EQ(run({"--help"}).code, 0);
}

TEST(Cli, SolveReportsTheMeasuredObservablesAndTheWork) {
  const CliRun r = run({"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1",
                        "--rtol", "1e-10", "--atol", "1e-13", "--want", "e,tau", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  for (const char* key : {"p", "m", "k", "v0", "alpha", "alpha_eff", "e", "tau", "solver", "rtol",
                          "atol", "steps", "rhs_evals", "wall_seconds", "outcome"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  for (const char* key : {"delta_max", "t_peak", "energy_load", "samples"}) { // not wanted
    EXPECT_FALSE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["outcome"], "exited");
  EXPECT_EQ(json["solver"], "cvode-bdf");
  EXPECT_NEAR(json["e"].get<double>(), 0.5, 1e-7);
  const auto c = analytic::Contact<double>::from_e(1.5, 0.5, 1);
  EXPECT_NEAR(json["tau"].get<double>(), analytic::contact_duration(c), 1e-7);
  EXPECT_GT(json["rhs_evals"].get<long>(), json["steps"].get<long>());
}

TEST(Cli, SolveForceEndOverdampedAndSamples) {
  const CliRun capped = run({"solve", "--solver", "arkode-dp5", "--p", "2.5", "--alpha-eff", "0.7",
                             "--v0", "1", "--end", "force", "--rtol", "1e-10", "--json"});
  ASSERT_EQ(capped.code, 0) << capped.err;
  const auto a = nlohmann::json::parse(capped.out);
  EXPECT_NEAR(a["e_cap"].get<double>(),
              analytic::capped_restitution(analytic::damping_from_alpha_eff(0.7)), 1e-8);
  EXPECT_TRUE(a.contains("t_cut") && !a.contains("e"));

  const CliRun over = run({"solve", "--solver", "odeint-bs", "--p", "1.5", "--alpha-eff", "1.5",
                           "--v0", "1", "--json"});
  ASSERT_EQ(over.code, 0) << over.err;
  const auto b = nlohmann::json::parse(over.out);
  EXPECT_EQ(b["outcome"], "no_exit");
  EXPECT_EQ(b["e"].get<double>(), 0.0);
  EXPECT_TRUE(b["tau"].is_null());

  const CliRun sampled = run({"solve", "--solver", "verlet-predicted", "--p", "1", "--e", "0.5",
                              "--v0", "1", "--dt", "1e-3", "--sample-times", "0,0.5,1", "--json"});
  ASSERT_EQ(sampled.code, 0) << sampled.err;
  EXPECT_EQ(nlohmann::json::parse(sampled.out)["dt"].get<double>(), 1e-3);
  EXPECT_FALSE(nlohmann::json::parse(sampled.out).contains("rtol")); // a fixed step has none
  const auto samples = nlohmann::json::parse(sampled.out)["samples"];
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples[0][1].get<double>(), 0.0);
  EXPECT_EQ(samples[0][2].get<double>(), 1.0);
  const analytic::Trajectory<double> exact(analytic::Contact<double>::from_e(1.0, 0.5, 1.0));
  EXPECT_NEAR(samples[2][1].get<double>(), exact.at_time(1.0).delta, 1e-6);
}

struct BadInput {
  std::vector<std::string> args;
  std::string message;
};

TEST(Cli, BadInputIsOneLineAndExitTwo) {
  const std::vector<BadInput> cases = {
      {{"observables", "--p", "0.5", "--e", "0.5", "--v0", "1"},
       "p must be in [1, 1000] (got 0.5)"},
      {{"observables", "--p", "2", "--e", "1.5", "--v0", "1"}, "e must be in (0, 1] (got 1.5)"},
      {{"observables", "--p", "2", "--e", "0", "--v0", "1"}, "e must be in (0, 1] (got 0)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "0"},
       "v0 must be in [1e-30, 1e30] (got 0)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--m", "-3"},
       "m must be in [1e-30, 1e30] (got -3)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--k", "inf"},
       "k must be finite (got inf)"},
      {{"observables", "--p", "nan", "--e", "0.5", "--v0", "1"}, "p must be finite (got nan)"},
      {{"observables", "--p", "2", "--alpha", "-1", "--v0", "1"},
       "alpha must be in [0, 1e8] (got -1)"},
      {{"observables", "--p", "2x", "--e", "0.5", "--v0", "1"}, "--p is not a number (got 2x)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--precision", "float"},
       "unknown precision, expected " + precision_names() + " (got float)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--frobnicate"},
       "unknown option --frobnicate for observables (got --frobnicate)"},
      {{"observables", "--p", "2", "--e", "0.5"}, "--v0 is required (got nothing)"},
      // A typo is named, with the option meant, before what it leaves missing (a new user read
      // "--v0 is required" for --vo, and "unknown argument" without a suggestion).
      {{"observables", "--p", "2", "--e", "0.5", "--vo", "1"},
       "unknown option --vo for observables; did you mean --v0? (got --vo)"},
      {{"timestep", "--schem", "dem-verlet", "--p", "1.5", "--e", "0.5"},
       "unknown option --schem for timestep; did you mean --scheme? (got --schem)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--precison=quad"},
       "unknown option --precison for observables; did you mean --precision? (got "
       "--precison=quad)"},
      // Given twice: once CLI11's "At Most 1 required but received 2", or, for a list, the last
      // value kept silently.
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "0.5", "--v0", "0.6"},
       "--v0 is given 2 times: give it once (a list's items comma-separated) (got --v0 0.5 --v0 "
       "0.6)"},
      {{"observables", "--geometry", "sphere-sphere", "--radius", "0.01", "--young", "7e10",
        "--poisson", "0.3", "--poisson", "0.2", "--density", "2700", "--e", "0.5", "--v0", "1"},
       "--poisson is given 2 times: give it once (a list's items comma-separated) (got "
       "--poisson 0.3 --poisson 0.2)"},
      {{"observables", "--p", "2", "--v0", "1"},
       "give exactly one of --e, --alpha, --alpha-eff (got 0)"},
      {{"calibrate", "--p", "2", "--e", "0.5", "--end", "sideways"},
       "unknown contact end, expected overlap|force (got sideways)"},
      {{"launch"},
       "unknown command, expected "
       "calibrate|observables|solve|timestep|run|merge|diff|check|showcase "
       "(got "
       "launch)"},
      {{"solve", "--solver", "ode45", "--p", "1.5", "--e", "0.5", "--v0", "1"},
       "unknown solver, expected cvode-bdf|cvode-adams|arkode-dp5|arkode-erk8|arkode-dirk|"
       "odeint-rkf78|odeint-bs|taylor|verlet-predicted|dem-verlet|dem-symplectic-euler|dem-"
       "leapfrog (got ode45)"},
      {{"solve", "--p", "1.5", "--e", "0.5", "--v0", "1"}, "--solver is required (got nothing)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--rtol", "0"},
       "rtol must be > 0 (got 0)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--rtol", "-1"},
       "rtol must be > 0 (got -1)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--rtol", "2"},
       "rtol must be < 1 (got 2)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--atol", "0"},
       "atol must be > 0 (got 0)"},
      {{"solve", "--solver", "verlet-predicted", "--p", "1.5", "--e", "0.5", "--v0", "1", "--dt",
        "-1e-3"},
       "dt must be > 0 (got -0.001)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--want",
        "e,speed"},
       "unknown observable in --want, expected e|delta_max|t_peak|tau|energy|normal_force|all (got "
       "speed)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--sample-times",
        "1,-2"},
       "sample time must be >= 0 (got -2)"},
      {{"solve", "--solver", "verlet-predicted", "--p", "1.5", "--e", "0.5", "--v0", "1",
        "--steps-per-contact", "abc"},
       "--steps-per-contact is not an integer (got abc)"},
      {{"solve", "--solver", "verlet-predicted", "--p", "1.5", "--e", "0.5", "--v0", "1",
        "--steps-per-contact", "0"},
       "--steps-per-contact must be in [1, 1e9] (got 0)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--max-steps",
        "-3"},
       "max steps must be >= 1 (got -3)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--horizon",
        "0"},
       "horizon must be > 0 (got 0)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "0.9", "--e", "0.5", "--v0", "1"},
       "p must be in [1, 1000] (got 0.9)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--precision",
        "long"},
       "solver cvode-bdf runs in double precision only; taylor runs in any (got --precision "
       "long)"},
      {{"solve", "--solver", "taylor", "--p", "1.5", "--e", "0.5", "--v0", "1", "--atol", "1e-9"},
       "taylor controls its error relative to each state and takes no atol (got 1e-09)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--dt", "0.1"},
       "cvode-bdf has no fixed-step mode and takes no dt (got 0.1)"},
      {{"calibrate", "--code", "lammps", "--p", "1.5", "--e", "0.5"},
       "unknown --code, expected lammps-tsuji|lammps-tsuji-2026|lammps-coeff-restitution|liggghts|"
       "mercurydpm|chrono|yade|yade-viscel|yade-hertz-mindlin|lammps-viscoelastic|lammps-hertz-"
       "history|"
       "lammps-mass-velocity (got lammps)"},
      {{"calibrate", "--code", "lammps-tsuji", "--p", "2", "--e", "0.5"},
       "lammps-tsuji has a Hertz model only: p must be 1.5 (got 2)"},
      {{"calibrate", "--code", "chrono", "--p", "1.5", "--e", "0.5", "--limit-damping"},
       "chrono always caps the force: --limit-damping is a LAMMPS and LIGGGHTS option (got "
       "--limit-damping)"},
      {{"calibrate", "--p", "1.5", "--e", "0.5", "--limit-damping"},
       "--limit-damping goes with --code (got --limit-damping alone)"},
      {{"solve", "--solver", "dem-verlet", "--p", "1.5", "--e", "0.5", "--v0", "1", "--onset-phase",
        "1"},
       "onset phase must be in [0, 1) (got 1)"},
      {{"solve", "--solver", "cvode-bdf", "--p", "1.5", "--e", "0.5", "--v0", "1", "--onset-phase",
        "0.5"},
       "cvode-bdf controls its error and has no onset phase (got 0.5)"},
      {{"solve", "--solver", "verlet-predicted", "--p", "1.5", "--e", "0.5", "--v0", "1", "--rtol",
        "1e-8"},
       "verlet-predicted takes a fixed step and no rtol (got --rtol 1e-8)"},
      // With the step given too: the refusal must not ask for what is there.
      {{"solve", "--solver", "dem-verlet", "--p", "1.5", "--e", "0.5", "--v0", "1",
        "--steps-per-contact", "50", "--rtol", "1e-8"},
       "dem-verlet takes a fixed step and no rtol (got --rtol 1e-8)"},
  };
  for (const BadInput& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.message;
    EXPECT_EQ(r.err, "error: " + c.message + "\n");
    EXPECT_TRUE(r.out.empty());
  }
  for_each_precision([]<class Real>() {
    const std::string precision(precision_name<Real>());
    const CliRun r =
        run({"observables", "--p", "0.5", "--e", "0.5", "--v0", "1", "--precision", precision});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "error: p must be in [1, 1000] (got 0.5)\n") << precision;
  });
}

// Every file a command reads must be a regular file, refused before it is opened otherwise: a
// FIFO without a writer blocked `check`, `run` and `diff` for ever, and /dev/zero never ends.
// The domain's bounds are the decimals as every precision reads them: --v0 1e-30 was refused in
// long, quad and 50 digits (the bound was the double nearest 1e-30, above theirs). A hex float
// is refused in every precision (three of four read it).
TEST(Cli, EveryPrecisionReadsTheSameNumbers) {
  for (const char* precision : {"double", "long", "quad", "50"}) {
    for (const char* bound : {"1e-30", "1e30"}) {
      const CliRun at =
          run({"observables", "--p", "1.5", "--e", "0.5", "--v0", bound, "--precision", precision});
      EXPECT_EQ(at.code, 0) << precision << " " << bound << ": " << at.err;
    }
    const CliRun hex =
        run({"observables", "--p", "1.5", "--e", "0x1p-1", "--v0", "1", "--precision", precision});
    EXPECT_EQ(hex.code, 2) << precision;
    EXPECT_EQ(hex.err, "error: --e is not a number in decimal (got 0x1p-1)\n") << precision;
    // A number the precision cannot hold is named as typed, not as the inf or 0 it became.
    const std::string beyond = std::string(precision) == "double" ? "1e400" : "1e-99999";
    const CliRun far = run({"observables", "--p", "1.5", "--e", "0.5", "--v0", beyond.c_str(),
                            "--precision", precision});
    EXPECT_EQ(far.code, 2) << precision;
    if (std::string(precision) != "50") { // cpp_bin_float_50 holds 1e-99999
      EXPECT_EQ(far.err, "error: --v0 is beyond what precision " + std::string(precision) +
                             " holds (got " + beyond + ")\n");
    }
  }
}

TEST(Cli, WhatIsNotARegularFileIsRefusedBeforeItIsRead) {
  const std::filesystem::path fifo = testing::scratch() / "no-writer.fifo";
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string report = testing::scratch() / "no-such-report.json";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"check", fifo, "--p", "1.5", "--e", "0.5", "--v0", "1"},
       "error: cannot read the trajectory: a FIFO (a named pipe), not a regular file (got " +
           fifo.string() + ")"},
      {{"check", "/dev/zero", "--p", "1.5", "--e", "0.5", "--v0", "1"},
       "error: cannot read the trajectory: a character device, not a regular file (got "
       "/dev/zero)"},
      {{"run", fifo},
       "error: cannot read the scene: a FIFO (a named pipe), not a regular file (got " +
           fifo.string() + ")"},
      {{"run", "/dev/zero"},
       "error: cannot read the scene: a character device, not a regular file (got /dev/zero)"},
      {{"diff", fifo, report},
       "error: cannot read report: a FIFO (a named pipe), not a regular file (got " +
           fifo.string() + ")"},
      {{"diff", "/dev/zero", fifo},
       "error: cannot read report: a character device, not a regular file (got /dev/zero)"},
      {{"diff", "/dev/null", "/dev/null"},
       "error: cannot read report: a character device, not a regular file (got /dev/null)"}};
  for (const auto& [args, says] : cases) {
    const CliRun ran = run(args);
    EXPECT_EQ(ran.code, 2) << args[0];
    EXPECT_EQ(ran.err, says + "\n");
  }
  std::filesystem::remove(fifo);
}

// One rule for every list of the command line: no empty item, no item twice where the list is a
// set, and every item used ("--radius 0.01," and "--speeds 1,,2" were read as if the comma were not
// there, "--observables e,e" merged, a sample time past the solve dropped).
TEST(Cli, EveryListTakesEachItemOnceAndUsesIt) {
  const std::vector<std::string> glass{
      "--geometry", "sphere-sphere", "--young", "63e9", "--poisson",
      "0.2",        "--density",     "2500",    "--e",  "0.5"};
  const auto with_glass = [&](std::vector<std::string> args) {
    args.insert(args.end(), glass.begin(), glass.end());
    return args;
  };
  const auto solve = [](const std::vector<std::string>& more) {
    std::vector<std::string> args{"solve", "--solver", "taylor", "--p", "1.5",
                                  "--e",   "0.5",      "--v0",   "1"};
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {with_glass({"observables", "--v0", "1", "--radius", "0.01,"}),
       "--radius has an empty item (got 0.01,)"},
      {with_glass({"observables", "--v0", "1", "--radius", ",0.01"}),
       "--radius has an empty item (got ,0.01)"},
      {with_glass({"observables", "--v0", "1", "--radius", "0.01,,0.02"}),
       "--radius has an empty item (got 0.01,,0.02)"},
      {{"observables", "--v0", "1", "--e", "0.5", "--geometry", "sphere-sphere", "--radius", "0.01",
        "--young", "7e10,", "--poisson", "0.2", "--density", "2500"},
       "--young has an empty item (got 7e10,)"},
      {{"calibrate", "--code", "lammps-hertz-history", "--p", "1.5", "--e", "0.9", "--speeds",
        "1,,2"},
       "--speeds has an empty item (got 1,,2)"},
      {{"calibrate", "--code", "lammps-hertz-history", "--p", "1.5", "--e", "0.9", "--speeds",
        "1,1.0"},
       "--speeds names one speed twice (got 1.0)"},
      {solve({"--want", "e,"}), "--want has an empty item (got e,)"},
      {solve({"--want", "e,e"}), "--want names e twice (got e,e)"},
      {solve({"--sample-times", "0.1,"}), "--sample-times has an empty item (got 0.1,)"},
      {solve({"--sample-times", "0.1,1e-1"}), "--sample-times names one time twice (got 1e-1)"},
      {solve({"--want", "delta_max", "--sample-times", "0.5,3.0"}),
       "--sample-times 3 lies outside the contact solved (outcome peak, at the peak: --want asks "
       "for nothing later): samples are taken inside it (got 3)"},
      {solve({"--sample-times", "0.5,9"}),
       "--sample-times 9 lies outside the contact solved (outcome exited): samples are taken "
       "inside it (got 9)"},
      {{"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--e", "0.5", "--observables", "e,"},
       "--observables has an empty item (got e,)"},
      {{"timestep", "--scheme", "dem-verlet", "--p", "1.5", "--e", "0.5", "--observables", "e,e"},
       "--observables names e twice (got e,e)"}};
  for (const auto& [args, says] : cases) {
    const CliRun ran = run(args);
    EXPECT_EQ(ran.code, 2) << says;
    EXPECT_EQ(ran.err, "error: " + says + "\n");
  }
  // Two equal bodies repeat a value: a pair, not a set.
  const CliRun pair = run(with_glass({"observables", "--v0", "1", "--radius", "0.01,0.01"}));
  const CliRun one = run(with_glass({"observables", "--v0", "1", "--radius", "0.01"}));
  EXPECT_EQ(pair.code, 0) << pair.err;
  EXPECT_EQ(pair.out, one.out);
  // Every sample asked inside the contact is answered.
  const CliRun sampled = run(solve({"--sample-times", "0.5,3.0", "--json"}));
  ASSERT_EQ(sampled.code, 0) << sampled.err;
  EXPECT_EQ(nlohmann::json::parse(sampled.out)["samples"].size(), 2u);
}

// What a file or a scene says reaches the terminal escaped: a NUL in a CSV cut the error line at
// it, a UTF-16 CSV printed raw bytes, and a scene name with control characters reached stdout.
TEST(Cli, TextFromFilesIsShownEscaped) {
  using namespace std::string_literals;
  const std::string nul = testing::write_file("nul.csv", "t,delta\n0,0\n1,\0x\n"s);
  const CliRun with_nul = run({"check", nul, "--p", "1.5", "--e", "0.5", "--v0", "1"});
  EXPECT_EQ(with_nul.err, "error: " + nul + ":3: delta is not a number (got \\x00x)\n");
  const std::string utf16 = testing::write_file("utf16.csv", "\xff\xfet\0,\0d\0e\0l\0t\0a\0\n\0"s);
  const CliRun with_utf16 = run({"check", utf16, "--p", "1.5", "--e", "0.5", "--v0", "1"});
  EXPECT_NE(with_utf16.err.find("(got \\xff\\xfet\\x00)"), std::string::npos) << with_utf16.err;
  const std::string scene = testing::write_file(
      "bell.toml",
      "name = \"a\\u0007b\\nreport: /etc/passwd\\u202e\"\nwant = [\"e\"]\n[grid]\np = [1]\n"
      "e = [0.5]\nv0 = [1]\n[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-6\n"
      "[[claim]]\nname = \"c\\u001b]0;x\\u0007|y\"\nobservable = \"e\"\n"
      "solver = \"cvode-bdf\"\nrtol = 1e-6\nbound = 1e-3\n"
      "[report]\nformats = [\"json\", \"md\", \"html\"]\n");
  const std::string out = (testing::scratch() / "bell\nout").string();
  const CliRun ran = run({"run", scene, "--out", out});
  ASSERT_EQ(ran.code, 0) << ran.err;
  EXPECT_EQ(ran.out.find('\a'), std::string::npos) << ran.out;
  EXPECT_EQ(ran.out.find("\nreport: /etc/passwd"), std::string::npos) << ran.out;
  EXPECT_NE(ran.out.find("a\\x07b\\nreport: /etc/passwd\\u202e: 1 cells"), std::string::npos)
      << ran.out;
  EXPECT_NE(ran.out.find("report: " + testing::scratch().string() + "/bell\\nout/report.json"),
            std::string::npos)
      << ran.out;
  // The report files a person opens hold them escaped too (an ESC reached report.md's claims and
  // report.html's <title> raw).
  for (const char* file : {"report.md", "report.html"}) {
    std::ifstream in(std::filesystem::path(out) / file, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_FALSE(text.empty()) << file;
    EXPECT_EQ(std::count_if(text.begin(), text.end(),
                            [](char c) {
                              const auto byte = static_cast<unsigned char>(c);
                              return (byte < 0x20 && c != '\n' && c != '\t') || byte == 0x7f;
                            }),
              0)
        << file;
    // Nor a right-to-left override (U+202E turned report.html's title around).
    EXPECT_EQ(text.find("\xe2\x80\xae"), std::string::npos) << file;
  }
  EXPECT_EQ(ran.out.find("\xe2\x80\xae"), std::string::npos) << ran.out;
}

} // namespace
} // namespace pldamp::harness

namespace pldamp::harness {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::run;

// Every report names what made it (issue 49): `pldamp --version` prints the build, report.json's
// `run` holds it with the date, host, command line and the scene text's checksum, report.md and
// report.html say it in their first lines, and diff says when two reports come from two builds.
TEST(Cli, EveryReportNamesTheBuildAndTheCommandThatMadeIt) {
  const CliRun version = run({"--version"});
  EXPECT_EQ(version.code, 0);
  ASSERT_EQ(version.out.rfind("pldamp 0.", 0), 0u) << version.out;
  const std::string build = version.out.substr(7, version.out.size() - 8);
  EXPECT_NE(build.find('+'), std::string::npos) << build; // VERSION+COMMIT

  const std::string scene = testing::write_file("made.toml", testing::valid_scene);
  const fs::path out = testing::scratch() / "made";
  fs::remove_all(out);
  const CliRun ran = run({"run", scene, "--out", out.string(), "--jobs", "1"});
  ASSERT_EQ(ran.code, 0) << ran.err;
  const auto report = nlohmann::json::parse(testing::read_file(out / "report.json"));
  const nlohmann::json& made = report.at("run");
  EXPECT_EQ(made.at("build"), build);
  EXPECT_EQ(made.at("command"),
            (nlohmann::json{"pldamp", "run", scene, "--out", out.string(), "--jobs", "1"}));
  EXPECT_EQ(made.at("scene_checksum"), fmt::format("{:016x}", fnv1a(testing::read_file(scene))));
  const std::string date = made.at("date");
  EXPECT_EQ(date.size(), 20u) << date; // 2026-11-29T02:13:30Z
  EXPECT_EQ(date.substr(0, 2), "20");
  EXPECT_EQ(date.back(), 'Z');
  EXPECT_FALSE(made.at("host").get<std::string>().empty());
  const std::string line = "pldamp " + build + " on " + made.at("host").get<std::string>() + ", " +
                           date + ": pldamp run " + scene;
  EXPECT_NE(testing::read_file(out / "report.md").find("Made by " + line), std::string::npos);
  EXPECT_NE(testing::read_file(out / "report.html").find("Made by <code>" + line),
            std::string::npos);

  // The same report as another build's: diff says so first, and judges the rest as before.
  nlohmann::json other = report;
  other["run"]["build"] = "0.0.9+0123456789ab";
  std::ofstream(testing::scratch() / "other-build.json") << other.dump(1);
  const CliRun diff = run(
      {"diff", (testing::scratch() / "other-build.json").string(), (out / "report.json").string()});
  EXPECT_EQ(diff.code, 0) << diff.err;
  EXPECT_EQ(diff.out.rfind("BUILD 0.0.9+0123456789ab -> " + build + "\n", 0), 0u) << diff.out;
  EXPECT_NE(diff.out.find("0 regressions, 0 changes"), std::string::npos) << diff.out;
  const CliRun same = run({"diff", (out / "report.json").string(), (out / "report.json").string()});
  EXPECT_EQ(same.out.find("BUILD"), std::string::npos) << same.out;
}

// diff --exact, the reproducibility check (issue 49): two runs of one scene on other thread
// counts are identical but for timings and provenance (exit 0); one bit of one value, a budget,
// a record gone, each listed (exit 1); the gate's thresholds refused beside it.
TEST(Cli, DiffExactFindsOneBitAndNothingElse) {
  std::string text = testing::valid_scene;
  text.replace(text.find("p = [1.5]"), 9, "p = [1.5, 2.0, 2.5]");
  const std::string scene = testing::write_file("exact.toml", text);
  const fs::path base = testing::scratch() / "exact";
  fs::remove_all(base);
  for (const char* jobs : {"1", "2"}) {
    const CliRun ran = run({"run", scene, "--out", (base / jobs).string(), "--jobs", jobs});
    ASSERT_EQ(ran.code, 0) << ran.err;
  }
  const std::string one = (base / "1" / "report.json").string();
  const std::string two = (base / "2" / "report.json").string();
  const CliRun same = run({"diff", "--exact", one, two});
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_EQ(same.out, "0 differences: identical but for timings and provenance\n");

  nlohmann::json edited = nlohmann::json::parse(testing::read_file(two));
  std::size_t which = 0;
  while (!edited["records"][which]["value"]["e"].is_number()) { // the last is erased below
    ASSERT_LT(which + 2, edited["records"].size());
    ++which;
  }
  nlohmann::json& record = edited["records"][which];
  const double e = record["value"]["e"];
  record["value"]["e"] = std::nextafter(e, 2.0); // one bit
  const std::string key = record["key"];
  edited["budgets"]["worst"][0]["max_abs"] = 123.0;
  const std::string last = edited["records"].back()["key"];
  edited["records"].erase(edited["records"].size() - 1);
  const fs::path changed = base / "changed.json";
  std::ofstream(changed) << edited.dump(1);
  const CliRun differs = run({"diff", "--exact", one, changed.string()});
  EXPECT_EQ(differs.code, 1) << differs.err;
  EXPECT_NE(differs.out.find(fmt::format("DIFFERS record | {} | value.e: {} -> {}\n", key,
                                         nlohmann::json(e).dump(),
                                         nlohmann::json(std::nextafter(e, 2.0)).dump())),
            std::string::npos)
      << differs.out;
  EXPECT_NE(differs.out.find("DIFFERS record | " + last + " | only in old\n"), std::string::npos)
      << differs.out;
  EXPECT_NE(differs.out.find("DIFFERS budgets | worst | [0].max_abs: "), std::string::npos)
      << differs.out;
  EXPECT_NE(differs.out.find("3 differences (2 records, 1 other)\n"), std::string::npos)
      << differs.out;
  // A record gone from the middle is named alone: the records after it are matched by their
  // keys, not their places (each of them differed before).
  const std::string two_text = testing::read_file(two);
  std::vector<std::string> lines;
  for (std::size_t i = 0; !testing::record_line(two_text, i).empty(); ++i) {
    lines.push_back(testing::record_line(two_text, i));
  }
  ASSERT_GE(lines.size(), 3u);
  const std::string middle = nlohmann::json::parse(lines[1])["key"];
  lines.erase(lines.begin() + 1);
  const fs::path gone = base / "gone.json";
  std::ofstream(gone) << testing::with_records(two_text, lines);
  const CliRun alone = run({"diff", "--exact", one, gone.string()});
  EXPECT_EQ(alone.code, 1) << alone.err;
  EXPECT_EQ(alone.out, "DIFFERS record | " + middle + " | only in old\n" +
                           "1 difference (1 record, 0 other)\n");
  const CliRun gate = run({"diff", "--exact", "--time-factor", "3", one, two});
  EXPECT_EQ(gate.code, 2);
  EXPECT_EQ(gate.err, "error: --time-factor goes with the regression gate, not --exact, which "
                      "compares every value to the last bit (got --time-factor with --exact)\n");
}

// A run's progress says the time left only once the rate means something (issue 49: the first
// line of a 10^6-run map said "1/400000 records, about 486584 s left").
TEST(Cli, ProgressEstimatesTheTimeLeftOnlyFromEnoughRecords) {
  EXPECT_EQ(time_left_text(1.0, 1, 400000), "time left not known yet");
  EXPECT_EQ(time_left_text(1.0, 3999, 400000), "time left not known yet");
  EXPECT_EQ(time_left_text(10.0, 4000, 400000), "about 990 s left");
  EXPECT_EQ(time_left_text(1.0, 15, 20), "time left not known yet");
  EXPECT_EQ(time_left_text(2.0, 16, 20), "about 0 s left");
}

} // namespace
} // namespace pldamp::harness
