// A contact from materials on the command line (MATH.md §13, ask/materials.hpp): m, k and p = 3/2
// derived once and used by observables, solve and check, with R*, E* and the units answered, and
// every bad material input one line and exit 2.
#include "cli_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

using testing::CliRun;
using testing::raw_number;
using testing::relative;
using testing::run;

const std::vector<std::string> aluminium{"--geometry", "sphere-sphere", "--radius",  "0.01",
                                         "--young",    "7e10",          "--poisson", "0.3",
                                         "--density",  "2700"};

std::vector<std::string> with(std::vector<std::string> head, const std::vector<std::string>& a,
                              const std::vector<std::string>& tail) {
  head.insert(head.end(), a.begin(), a.end());
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

// Two equal aluminium spheres, against mpmath (data/reference/hertz.csv, line 3): m* = 9π/5000 kg,
// R* = 5 mm, E* = 7e10/1.82 Pa, k = 4/3 E* √R*; and the same observables as --m and --k given
// those digits.
TEST(Materials, ObservablesDeriveMassStiffnessAndUnits) {
  const CliRun r = run(with({"observables"}, aluminium, {"--e", "0.5", "--v0", "1", "--json"}));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["p"].get<double>(), 1.5);
  EXPECT_LE(relative(json["m"].get<double>(), 0.005654866776461627829232758089903105191555), 4e-16);
  EXPECT_LE(relative(json["k"].get<double>(), 3626188621.469474484106894164640251483512), 8e-16);
  EXPECT_EQ(json["R_eff"].get<double>(), 0.005);
  EXPECT_LE(relative(json["E_eff"].get<double>(), 38461538461.53846153846153846153846153846),
            4e-16);
  EXPECT_EQ(json["geometry"], "sphere-sphere");
  const auto& units = json["units"];
  EXPECT_EQ(units["m"], "kg");
  EXPECT_EQ(units["k"], "N/m^1.5");
  EXPECT_EQ(units["v0"], "m/s");
  EXPECT_EQ(units["R_eff"], "m");
  EXPECT_EQ(units["E_eff"], "Pa");
  EXPECT_EQ(units["delta_max"], "m");
  EXPECT_EQ(units["tau"], "s");
  EXPECT_EQ(units["energy_load"], "J");
  EXPECT_EQ(units["normal_force_max"], "N");
  EXPECT_FALSE(units.contains("e")); // dimensionless
  // The same contact by --m, --k: the same observables, digit for digit.
  const CliRun by_mk = run({"observables", "--p", "1.5", "--m", raw_number(r.out, "m"), "--k",
                            raw_number(r.out, "k"), "--e", "0.5", "--v0", "1", "--json"});
  ASSERT_EQ(by_mk.code, 0) << by_mk.err;
  const auto plain = nlohmann::json::parse(by_mk.out);
  for (const char* key : {"delta_max", "t_peak", "tau", "normal_force_max", "energy_load"}) {
    EXPECT_EQ(raw_number(r.out, key), raw_number(by_mk.out, key)) << key;
  }
  EXPECT_FALSE(plain.contains("units"));
  // δ_max of the undamped Hertz contact, by hand: (5/4 m v0²/k)^(2/5) (MATH.md §13).
  const CliRun undamped =
      run(with({"observables"}, aluminium, {"--alpha", "0", "--v0", "1", "--json"}));
  ASSERT_EQ(undamped.code, 0) << undamped.err;
  const auto u = nlohmann::json::parse(undamped.out);
  EXPECT_LE(relative(u["delta_max"].get<double>(),
                     std::pow(1.25 * u["m"].get<double>() / u["k"].get<double>(), 0.4)),
            1e-14);
}

TEST(Materials, TextOutputNamesUnits) {
  const CliRun r = run(with({"observables"}, aluminium, {"--e", "0.5", "--v0", "1"}));
  ASSERT_EQ(r.code, 0) << r.err;
  // "m               <digits> kg": m* = 9π/5000 kg (hertz.csv), its unit beside it.
  const auto at = r.out.find("\nm               ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string line = r.out.substr(at + 1, r.out.find('\n', at + 1) - at - 1);
  ASSERT_EQ(line.substr(line.size() - 3), " kg") << line;
  EXPECT_LE(relative(std::stod(line.substr(16)), 0.005654866776461627829232758089903105191555),
            4e-16);
  EXPECT_NE(r.out.find("\nR_eff           0.005 m\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nE_eff           "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" N/m^1.5\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\ne               0.5\n"), std::string::npos) << r.out; // no unit
  EXPECT_EQ(r.out.find("units"), std::string::npos) << r.out;
}

// A sphere on a wall: the sphere's own mass and radius; a rigid wall (no second E) adds no
// compliance, so E* = E/(1 − ν²); an elastic one adds its own (hertz.csv, line 5).
TEST(Materials, SphereOnAWall) {
  const CliRun rigid =
      run({"observables", "--geometry", "sphere-wall", "--radius", "0.02", "--young", "1e7",
           "--poisson", "-0.5", "--density", "1000", "--e", "0.9", "--v0", "2", "--json"});
  ASSERT_EQ(rigid.code, 0) << rigid.err;
  const auto json = nlohmann::json::parse(rigid.out);
  EXPECT_LE(relative(json["m"].get<double>(), 0.0335103216382911278769348627549813640981), 4e-16);
  EXPECT_EQ(json["R_eff"].get<double>(), 0.02);
  EXPECT_LE(relative(json["E_eff"].get<double>(), 1e7 / 0.75), 4e-16);
  EXPECT_LE(relative(json["k"].get<double>(), 2514157.444218835642314113287483907695235), 8e-16);
  const CliRun elastic = run({"observables", "--geometry", "sphere-wall", "--radius", "0.002",
                              "--young", "6.3e10,2.1e11", "--poisson", "0.22,0.29", "--density",
                              "2500", "--e", "0.9", "--v0", "2", "--json"});
  ASSERT_EQ(elastic.code, 0) << elastic.err;
  const auto e = nlohmann::json::parse(elastic.out);
  EXPECT_LE(relative(e["k"].get<double>(), 3063181749.553272413682177290270101254548), 8e-16);
  EXPECT_LE(relative(e["m"].get<double>(), 0.00008377580409572781969233715688745341024526), 4e-16);
}

// solve integrates the derived contact: the same digits as --m/--k, in every key but the time.
TEST(Materials, SolveTakesMaterials) {
  const std::vector<std::string> tail{"--e", "0.5", "--v0", "1", "--solver", "cvode-bdf", "--json"};
  const CliRun r = run(with({"solve"}, aluminium, tail));
  ASSERT_EQ(r.code, 0) << r.err;
  const CliRun by_mk = run(
      with({"solve", "--p", "1.5", "--m", raw_number(r.out, "m"), "--k", raw_number(r.out, "k")},
           {}, tail));
  ASSERT_EQ(by_mk.code, 0) << by_mk.err;
  for (const char* key : {"alpha", "e", "delta_max", "t_peak", "tau", "steps"}) {
    EXPECT_EQ(raw_number(r.out, key), raw_number(by_mk.out, key)) << key;
  }
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["units"]["tau"], "s");
  EXPECT_EQ(json["units"]["wall_seconds"], "s");
  // A stated damping exponent goes through the reference solve's calibration: materials too.
  const CliRun beta = run(with({"solve"}, aluminium,
                               {"--alpha", "0.1", "--damping-exponent", "1", "--v0", "1",
                                "--solver", "cvode-bdf", "--json"}));
  ASSERT_EQ(beta.code, 0) << beta.err;
  EXPECT_EQ(raw_number(beta.out, "m"), raw_number(r.out, "m"));
  EXPECT_EQ(nlohmann::json::parse(beta.out)["units"]["m"], "kg");
}

TEST(Materials, TimestepTakesMaterials) {
  // The step for the aluminium pair is the step for its derived m and k at p = 3/2: the materials
  // are not accepted and then ignored.
  const std::vector<std::string> tail{"--scheme", "dem-verlet", "--e",   "0.5",
                                      "--v0",     "1",          "--json"};
  const CliRun r = run(with({"timestep"}, aluminium, tail));
  ASSERT_EQ(r.code, 0) << r.err;
  const CliRun by_mk = run(
      with({"timestep", "--p", "1.5", "--m", raw_number(r.out, "m"), "--k", raw_number(r.out, "k")},
           {}, tail));
  ASSERT_EQ(by_mk.code, 0) << by_mk.err;
  for (const char* key : {"alpha", "dt", "tau_over_dt", "worst_error", "dt_stability"}) {
    EXPECT_EQ(raw_number(r.out, key), raw_number(by_mk.out, key)) << key;
  }
  const auto json = nlohmann::json::parse(r.out);
  for (const char* key :
       {"dt", "dt_failing", "dt_crit_seed", "dt_stability", "tau", "t_hertz", "t_rayleigh"}) {
    EXPECT_EQ(json["units"][key], "s") << key;
  }
  // The step as a fraction of the elastic Hertz contact time and of the Rayleigh time, against
  // mpmath (hertz.csv, line 3: t_H from energy and a Beta function, not the closed form used here).
  const double hertz_time = 0.00006092333496870261957091895764236901108;
  const double rayleigh_time = 0.00001074926843199936423344437853407245417;
  EXPECT_LE(relative(json["t_hertz"].get<double>(), hertz_time), 1e-14);
  EXPECT_LE(relative(json["t_rayleigh"].get<double>(), rayleigh_time), 4e-16);
  const double dt = json["dt"].get<double>();
  EXPECT_LE(relative(json["dt_over_t_hertz"].get<double>(), dt / hertz_time), 1e-14);
  EXPECT_LE(relative(json["dt_over_t_rayleigh"].get<double>(), dt / rayleigh_time), 1e-15);
  EXPECT_FALSE(nlohmann::json::parse(by_mk.out).contains("t_hertz")); // no materials, no Hertz
  const CliRun mixed = run(with({"timestep", "--m", "2"}, aluminium, tail));
  EXPECT_EQ(mixed.code, 2);
  EXPECT_EQ(mixed.err, "error: --m and --k are derived from the materials under --geometry, give "
                       "one or the other (got --m 2)\n");
}

// A velocity-dependent code's calibration depends on m, k and LAMMPS's Reff: from materials they
// are m*, k and R*, the same entry as typed by hand; the seed's codes do not depend on the
// contact, so materials are refused there as --m is.
TEST(Materials, CalibrateTakesMaterialsForAVelocityDependentCode) {
  const std::vector<std::string> tail{"--code", "lammps-hertz-history", "--e", "0.9", "--v0", "2",
                                      "--json"};
  const CliRun r = run(with({"calibrate"}, aluminium, tail));
  ASSERT_EQ(r.code, 0) << r.err;
  const CliRun by_hand = run(with({"calibrate", "--p", "1.5", "--m", raw_number(r.out, "m"), "--k",
                                   raw_number(r.out, "k"), "--reff", "0.005"},
                                  {}, tail));
  ASSERT_EQ(by_hand.code, 0) << by_hand.err;
  for (const char* key : {"alpha", "alpha_eff", "entry"}) {
    EXPECT_EQ(raw_number(r.out, key), raw_number(by_hand.out, key)) << key;
  }
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["R_eff"].get<double>(), 0.005);
  EXPECT_EQ(json["units"]["v0"], "m/s");
  // α √(m k) δ^(1/2) δ' is a force in N: √(m k) in kg s^-1 m^-1/4 (k in N/m^1.5), δ^(1/2) δ' in
  // m^3/2 s^-1, so α is in m^-1/4; the entry α √(k/m)/√R* then in m^-1 s^-1.
  EXPECT_EQ(json["units"]["alpha"], "m^-0.25");
  EXPECT_EQ(json["units"]["entry"], "m^-1/s");
  const CliRun seed =
      run(with({"calibrate", "--code", "lammps-tsuji", "--e", "0.9"}, aluminium, {}));
  EXPECT_EQ(seed.code, 2);
  EXPECT_EQ(seed.err,
            "error: --geometry goes with a velocity-dependent --code "
            "(lammps-viscoelastic|lammps-hertz-history|lammps-mass-velocity): the seed's "
            "alpha for an e does not depend on v0, m or k (got --geometry sphere-sphere)\n");
  const CliRun reff = run(with({"calibrate", "--reff", "0.005"}, aluminium, tail));
  EXPECT_EQ(reff.code, 2);
  EXPECT_EQ(reff.err, "error: --reff is R* under --geometry, derived from the radii (got --reff "
                      "0.005)\n");
}

TEST(Materials, BadInputIsOneLineAndExitTwo) {
  auto observables = [](std::vector<std::string> materials) {
    return with({"observables"}, materials, {"--e", "0.5", "--v0", "1"});
  };
  auto replaced = [&](const std::string& option, const std::string& value) {
    std::vector<std::string> a = aluminium;
    for (std::size_t i = 0; i + 1 < a.size(); ++i) {
      if (a[i] == option) {
        a[i + 1] = value;
      }
    }
    return observables(a);
  };
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {replaced("--radius", "0"), "--radius must be a finite number > 0 (got 0)"},
      {replaced("--radius", "-1"), "--radius must be a finite number > 0 (got -1)"},
      {replaced("--radius", "0.01,inf"), "--radius must be a finite number > 0 (got inf)"},
      {replaced("--young", "0"), "--young must be a finite number > 0 (got 0)"},
      {replaced("--young", "7e10,-1"), "--young must be a finite number > 0 (got -1)"},
      {replaced("--poisson", "0.5"), "--poisson must be in (-1, 0.5) (got 0.5)"},
      {replaced("--poisson", "-1"), "--poisson must be in (-1, 0.5) (got -1)"},
      {replaced("--poisson", "nan"), "--poisson must be in (-1, 0.5) (got nan)"},
      {replaced("--density", "0"), "--density must be a finite number > 0 (got 0)"},
      {replaced("--density", "2700x"), "--density is not a number (got 2700x)"},
      {replaced("--geometry", "cube-cube"),
       "unknown --geometry, expected sphere-sphere|sphere-wall (got cube-cube)"},
      {replaced("--radius", "1,2,3"),
       "--radius takes one value for both spheres, or one each (got --radius "
       "1,2,3)"},
      {with({"observables", "--m", "2"}, aluminium, {"--e", "0.5", "--v0", "1"}),
       "--m and --k are derived from the materials under --geometry, give one or the other (got "
       "--m 2)"},
      {with({"solve", "--k", "5"}, aluminium, {"--e", "0.5", "--v0", "1", "--solver", "cvode-bdf"}),
       "--m and --k are derived from the materials under --geometry, give one or the other (got "
       "--k 5)"},
      {with({"check", "no-such.csv", "--m", "2"}, aluminium, {"--e", "0.5", "--v0", "1"}),
       "--m and --k are derived from the materials under --geometry, give one or the other (got "
       "--m 2)"},
      {with({"observables", "--p", "2"}, aluminium, {"--e", "0.5", "--v0", "1"}),
       "a contact from materials is Hertz's, p = 1.5 (got --p 2)"},
      // In SI a speed of 1 m/s is no default: Δt and a velocity-dependent e depend on it.
      {with({"timestep", "--scheme", "dem-verlet"}, aluminium, {"--e", "0.5"}),
       "--v0, the relative normal speed in m/s, is required with --geometry (got nothing)"},
      {with({"calibrate", "--code", "lammps-hertz-history"}, aluminium, {"--e", "0.9"}),
       "--v0, the relative normal speed in m/s at which e is set, is required with --geometry "
       "(got nothing)"},
      {observables({"--geometry", "sphere-sphere", "--radius", "0.01", "--young", "7e10",
                    "--poisson", "0.3"}),
       "--density is required with --geometry sphere-sphere (got nothing)"},
      {observables({"--geometry", "sphere-wall", "--radius", "0.01,0.02", "--young", "7e10",
                    "--poisson", "0.3", "--density", "2700"}),
       "--radius takes one value (the sphere's; the wall has none) (got --radius 0.01,0.02)"},
      {observables({"--geometry", "sphere-wall", "--radius", "0.01", "--young", "7e10,2e11",
                    "--poisson", "0.3", "--density", "2700"}),
       "an elastic wall takes a second --young and a second --poisson (got --young 7e10,2e11 "
       "--poisson 0.3)"},
      {observables({"--radius", "0.01"}),
       "--radius goes with --geometry sphere-sphere|sphere-wall (got --radius 0.01)"},
      {{"observables", "--e", "0.5", "--v0", "1"}, "--p is required (got nothing)"},
  };
  for (const auto& [args, message] : cases) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << message;
    EXPECT_EQ(r.err, "error: " + message + "\n");
    EXPECT_EQ(r.out, "");
  }
  // --p 1.5 stated is Hertz's own: accepted.
  EXPECT_EQ(run(with({"observables", "--p", "1.5"}, aluminium, {"--e", "0.5", "--v0", "1"})).code,
            0);
}

} // namespace
} // namespace pldamp::harness
