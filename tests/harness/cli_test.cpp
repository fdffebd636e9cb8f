// The CLI contract of DESIGN.md, run in-process: JSON keys and digits, the force end, and every
// kind of bad input producing one "error: <what> (got <value>)" line and exit code 2.
#include "pldamp/analytic.hpp"
#include "pldamp/harness/cli.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

struct CliRun {
  int code;
  std::string out, err;
};

CliRun run(std::vector<std::string> args) {
  args.insert(args.begin(), "pldamp");
  std::vector<const char*> argv;
  for (const std::string& a : args) {
    argv.push_back(a.c_str());
  }
  std::ostringstream out, err;
  const int code = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {code, out.str(), err.str()};
}

TEST(Cli, ObservablesJsonCarriesTheContractKeys) {
  const CliRun r = run({"observables", "--p", "1.5", "--e", "0.5", "--v0", "2", "--m", "0.01",
                        "--k", "7e9", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  for (const char* key : {"p", "m", "k", "v0", "alpha", "alpha_eff", "e", "delta_max", "t_peak",
                          "tau", "force_max", "energy_load", "energy_unload", "dt_crit"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_FALSE(json.contains("e_cap"));
  const auto c = analytic::Contact<double>::from_e(1.5, 0.5, 2, 0.01, 7e9);
  EXPECT_EQ(json["delta_max"].get<double>(), analytic::delta_max(c)); // shortest round trip
  EXPECT_EQ(json["tau"].get<double>(), analytic::contact_duration(c));
}

#if PLDAMP_WITH_QUAD
TEST(Cli, QuadPrintsThirtySixDigits) {
  const CliRun r = run(
      {"observables", "--p", "1.5", "--e", "0.5", "--v0", "2", "--precision", "quad", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string key = "\"tau\": ";
  const auto at = r.out.find(key);
  ASSERT_NE(at, std::string::npos);
  std::string number = r.out.substr(at + key.size());
  number = number.substr(0, number.find_first_of(",}"));
  const std::string mantissa = number.substr(0, number.find('e'));
  int digits = 0;
  for (char ch : mantissa) {
    digits += (ch >= '0' && ch <= '9') ? 1 : 0;
  }
  EXPECT_EQ(digits, 36) << number;
  const auto c = analytic::Contact<quad>::from_e(quad(3) / 2, quad(1) / 2, quad(2));
  EXPECT_EQ(quad(number), analytic::contact_duration(c));
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

TEST(Cli, TextOutputAndShowcase) {
  const CliRun text = run({"observables", "--p", "2", "--e", "0.5", "--v0", "1"});
  ASSERT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("delta_max"), std::string::npos);
  const CliRun showcase = run({"showcase"});
  ASSERT_EQ(showcase.code, 0);
  EXPECT_NE(showcase.out.find("2.5"), std::string::npos);
  EXPECT_EQ(run({"--help"}).code, 0);
}

struct BadInput {
  std::vector<std::string> args;
  std::string message;
};

TEST(Cli, BadInputIsOneLineAndExitTwo) {
  const std::vector<BadInput> cases = {
      {{"observables", "--p", "0.5", "--e", "0.5", "--v0", "1"}, "p must be >= 1 (got 0.5)"},
      {{"observables", "--p", "2", "--e", "1.5", "--v0", "1"}, "e must be in (0, 1] (got 1.5)"},
      {{"observables", "--p", "2", "--e", "0", "--v0", "1"}, "e must be in (0, 1] (got 0)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "0"}, "v0 must be > 0 (got 0)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--m", "-3"},
       "m must be > 0 (got -3)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--k", "inf"},
       "k must be finite (got inf)"},
      {{"observables", "--p", "nan", "--e", "0.5", "--v0", "1"}, "p must be finite (got nan)"},
      {{"observables", "--p", "2", "--alpha", "-1", "--v0", "1"}, "alpha must be >= 0 (got -1)"},
      {{"observables", "--p", "2x", "--e", "0.5", "--v0", "1"}, "--p is not a number (got 2x)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--precision", "float"},
       "unknown precision, expected double|long|quad|50 (got float)"},
      {{"observables", "--p", "2", "--e", "0.5", "--v0", "1", "--frobnicate"},
       "unknown argument (got --frobnicate)"},
      {{"observables", "--p", "2", "--e", "0.5"}, "--v0 is required (got nothing)"},
      {{"observables", "--p", "2", "--v0", "1"},
       "give exactly one of --e, --alpha, --alpha-eff (got 0)"},
      {{"calibrate", "--p", "2", "--e", "0.5", "--end", "sideways"},
       "unknown contact end, expected overlap|force (got sideways)"},
      {{"launch"}, "unknown command, expected calibrate|observables|showcase (got launch)"},
  };
  for (const BadInput& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.message;
    EXPECT_EQ(r.err, "error: " + c.message + "\n");
    EXPECT_TRUE(r.out.empty());
  }
  for (const char* precision : {"long", "quad", "50"}) {
    const CliRun r =
        run({"observables", "--p", "0.5", "--e", "0.5", "--v0", "1", "--precision", precision});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "error: p must be >= 1 (got 0.5)\n") << precision;
  }
}

} // namespace
} // namespace pldamp::harness
