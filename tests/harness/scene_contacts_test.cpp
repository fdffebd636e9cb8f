// A scene's [[contact]]s from materials (MATH.md §13, scene/contacts.cpp): each contact's m* and k
// as the command line derives them, its cells its own speeds (never one contact's m with
// another's k), the truth in SI units against Hertz's formulas written out by hand, claims over
// the contacts' cells, and every bad contact refused at its line before any work.
#include "cli/commands.hpp"
#include "fixtures.hpp"
#include "judge/trajectory_check.hpp"
#include "sampled_trajectories.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>

namespace pldamp::harness {
namespace {

using namespace testing;

// Two equal aluminium spheres (hertz.csv, line 3) at 1 and 2 m/s, and a rubber-like sphere on a
// rigid wall (line 6) at 2 m/s.
const std::string two_contacts = R"(name = "contacts"
want = ["e", "delta_max", "tau", "normal_force"]

[[contact]]
name = "aluminium pair"
geometry = "sphere-sphere"
radius = 0.01
young = 7e10
poisson = 0.3
density = 2700
v0 = [1.0, 2.0]

[[contact]]
name = "soft on rigid"
geometry = "sphere-wall"
radius = 0.02
young = 1e7
poisson = -0.5
density = 1000
v0 = 2.0

[grid]
e = [1.0, 0.5]

[[solver]]
name = "cvode-bdf"
rtol = 1e-11

[[claim]]
name = "cvode-bdf: delta_max within 1e-8 at e = 0.5"
observable = "delta_max"
solver = "cvode-bdf"
rtol = 1e-11
bound_rel = 1e-8
e = [0.5]
)";

TEST(SceneContacts, EachContactIsItsMassAndStiffnessAtItsOwnSpeeds) {
  const Scene scene = load_scene(write_file("contacts.toml", two_contacts));
  ASSERT_EQ(scene.contacts.size(), 2u);
  EXPECT_EQ(scene.p, std::vector<double>{1.5});
  // Derived in float128 and rounded once: mpmath's values (hertz.csv) to double's rounding.
  EXPECT_LE(relative(scene.contacts[0].m, 0.005654866776461627829232758089903105191555), 1.2e-16);
  EXPECT_LE(relative(scene.contacts[0].k, 3626188621.469474484106894164640251483512), 1.2e-16);
  EXPECT_LE(relative(scene.contacts[1].m, 0.0335103216382911278769348627549813640981), 1.2e-16);
  EXPECT_LE(relative(scene.contacts[1].k, 2514157.444218835642314113287483907695235), 1.2e-16);
  EXPECT_LE(relative(scene.contacts[0].rayleigh_time, 0.00001074926843199936423344437853407245417),
            1.2e-16);
  EXPECT_EQ(scene.contacts[1].radius_eff, 0.02);
  // The command line derives the same doubles (float128, rounded once).
  const CliRun cli =
      run({"observables", "--geometry", "sphere-sphere", "--radius", "0.01", "--young", "7e10",
           "--poisson", "0.3", "--density", "2700", "--e", "0.5", "--v0", "1", "--json"});
  ASSERT_EQ(cli.code, 0) << cli.err;
  const nlohmann::json answer = nlohmann::json::parse(cli.out);
  EXPECT_EQ(answer["m"].get<double>(), scene.contacts[0].m);
  EXPECT_EQ(answer["k"].get<double>(), scene.contacts[0].k);
  // Three cells per damping, each contact's m and k at its speeds: not the 2 × 2 × 2 of a product.
  const std::vector<CellScale> scales = scene_scales(scene);
  ASSERT_EQ(scales.size(), 3u);
  EXPECT_EQ(scales[0].v0, 1.0);
  EXPECT_EQ(scales[1].v0, 2.0);
  EXPECT_EQ(scales[2].v0, 2.0);
  EXPECT_EQ(scales[1].m, scene.contacts[0].m);
  EXPECT_EQ(scales[2].k, scene.contacts[1].k);
  const Plan plan = make_plan(scene);
  EXPECT_EQ(plan.cells.size(), 6u);
  for (const Cell& cell : plan.cells) {
    EXPECT_NE(contact_of(scene, cell.m, cell.k), nullptr);
  }
}

// report.json and report.md name each contact and its units; the truth at e = 1 is Hertz's, from
// energy and a Beta function (MATH.md §13), not the closed forms: δ_max = (5 m v0²/(4 k))^(2/5),
// F_max = k δ_max^(3/2), τ = 2 (δ_max/v0) (2/5) B(2/5, 1/2). The claim's own e is judged over
// the contacts' cells.
TEST(SceneContacts, RunReportsEachContactInSIUnits) {
  const std::string path = write_file("contacts-run.toml", two_contacts);
  const fs::path out = scratch() / "contacts-run";
  fs::remove_all(out);
  const CliRun r = run({"run", path, "--strict", "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream json_file(out / "report.json");
  const auto report = nlohmann::json::parse(json_file);
  const auto& grid = report["scene"]["grid"];
  ASSERT_EQ(grid["contacts"].size(), 2u);
  EXPECT_EQ(grid["contacts"][1]["name"], "soft on rigid");
  EXPECT_EQ(grid["contacts"][0]["v0"], nlohmann::json::array({1.0, 2.0}));
  EXPECT_EQ(grid["units"]["delta_max"], "m");
  EXPECT_EQ(grid["units"]["tau"], "s");
  EXPECT_EQ(grid["units"]["normal_force_max"], "N");
  EXPECT_EQ(grid["units"]["k"], "N/m^1.5");
  const double beta = 3.6790939804058;                 // B(2/5, 1/2), mpmath
  const double two_fifths_beta_twice = 2 * 0.4 * beta; // τ v0/δ_max
  int checked = 0;
  for (const auto& record : report["records"]) {
    ASSERT_TRUE(record.contains("contact")) << record["key"];
    if (record["damping"] != "e=1") {
      continue;
    }
    const double m = record["m"], k = record["k"], v0 = record["v0"];
    const double delta_max = std::pow(5 * m * v0 * v0 / (4 * k), 0.4);
    EXPECT_LE(relative(record["reference"]["delta_max"], delta_max), 1e-14) << record["key"];
    EXPECT_LE(relative(record["reference"]["normal_force_max"], k * std::pow(delta_max, 1.5)),
              1e-14)
        << record["key"];
    EXPECT_LE(relative(record["reference"]["tau"], two_fifths_beta_twice * delta_max / v0), 1e-13)
        << record["key"];
    ++checked;
  }
  EXPECT_EQ(checked, 3);
  const auto& claim = report["claims"][0];
  EXPECT_EQ(claim["verdict"], "holds");
  EXPECT_EQ(claim["cells"], 3);
  std::ifstream md_file(out / "report.md");
  const std::string md((std::istreambuf_iterator<char>(md_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(md.find("## Contacts from materials"), std::string::npos);
  EXPECT_NE(md.find("| aluminium pair | sphere-sphere | 0.005 |"), std::string::npos);
  EXPECT_NE(md.find("| soft on rigid | 2 | e=1 |"), std::string::npos);
  // report.csv names each row's contact as report.json names its record's (issue 50: it had no
  // such column), rows and records in one order.
  std::ifstream csv(out / "report.csv");
  std::string header;
  ASSERT_TRUE(std::getline(csv, header));
  std::vector<std::string> columns;
  for (std::size_t from = 0; from <= header.size();) {
    const std::size_t comma = std::min(header.find(',', from), header.size());
    columns.push_back(header.substr(from, comma - from));
    from = comma + 1;
  }
  const auto at = std::find(columns.begin(), columns.end(), "contact");
  ASSERT_NE(at, columns.end()) << header;
  const auto column = static_cast<std::size_t>(at - columns.begin());
  std::size_t rows = 0;
  for (std::string row; std::getline(csv, row); ++rows) {
    std::vector<std::string> fields;
    for (std::size_t from = 0; from <= row.size();) { // no field of these rows holds a comma
      const std::size_t comma = std::min(row.find(',', from), row.size());
      fields.push_back(row.substr(from, comma - from));
      from = comma + 1;
    }
    ASSERT_EQ(fields.size(), columns.size()) << row;
    ASSERT_LT(rows, report["records"].size());
    EXPECT_EQ(fields[column], report["records"][rows]["contact"].get<std::string>()) << row;
  }
  EXPECT_EQ(rows, report["records"].size());
}

TEST(SceneContacts, ABadContactIsRefusedAtItsLine) {
  const std::string contact = R"([[contact]]
name = "c"
geometry = "sphere-wall"
radius = 0.01
young = 7e10
poisson = 0.3
density = 2700
v0 = 1.0
)";
  const std::string rest = R"(
[grid]
e = [0.5]
[[solver]]
name = "cvode-bdf"
rtol = 1e-8
)";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = contact;
    text.replace(text.find(from), from.size(), to);
    return text + rest;
  };
  const std::vector<std::pair<std::string, std::string>> cases{
      {with("poisson = 0.3", "poisson = 0.5"),
       "6: [[contact]] c: poisson must be in (-1, 0.5) (got 0.5)"},
      {with("radius = 0.01", "radius = -0.01"),
       "4: [[contact]] c: radius must be a finite number > 0 (got -0.01)"},
      {with("radius = 0.01", "radius = [0.01, 0.02]"),
       "4: [[contact]] c: radius takes one value (the sphere's; the wall has none) (got radius "
       "0.01,0.02)"},
      // A wall's mistakes at their key's line (issue 50: the entry's, line 1, before).
      {with("young = 7e10", "young = [7e10, 2e11]"),
       "5: [[contact]] c: an elastic wall takes a second young and a second poisson (got young "
       "7e+10,2e+11 poisson 0.3)"},
      {with("poisson = 0.3", "poisson = [0.3, 0.25]"),
       "6: [[contact]] c: an elastic wall takes a second young and a second poisson (got young "
       "7e+10 poisson 0.3,0.25)"},
      {with("sphere-wall", "sphere-plane"),
       "3: [[contact]] c: unknown geometry, expected sphere-sphere|sphere-wall (got sphere-plane)"},
      {with("density = 2700\n", ""), "1: [[contact]] needs density"},
      {with("v0 = 1.0", "v0 = 0.0"), "8: v0 must be in [1e-30, 1e30] (got 0)"},
      {contact + with("", ""), "9: [[contact]] names c twice"},
      {with("v0 = 1.0\n", "v0 = 1.0\nmass = 2\n"),
       "9: unknown key in [[contact]], expected "
       "name|geometry|radius|young|poisson|density|v0 (got mass)"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path =
        write_file("bad-contact" + std::to_string(i) + ".toml", cases[i].first);
    const CliRun r = run({"run", path, "--out", (scratch() / "bad-contact-out").string()});
    EXPECT_EQ(r.code, 2) << i;
    EXPECT_EQ(r.err, path + ":" + cases[i].second + "\n") << i;
  }
  // The grid's and a claim's scales are the contacts'.
  const std::string grid_v0 = contact + "\n[grid]\ne = [0.5]\nv0 = [1.0]\n[[solver]]\nname = "
                                        "\"cvode-bdf\"\n";
  const std::string path = write_file("bad-contact-grid.toml", grid_v0);
  const CliRun r = run({"run", path, "--out", (scratch() / "bad-contact-out").string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, path +
                       ":12: [grid] v0: a scene with [[contact]] takes p = 1.5, v0, m and k from "
                       "its contacts\n");
  const std::string claim_k = contact + rest +
                              "[[claim]]\nname = \"x\"\nobservable = \"e\"\nsolver = "
                              "\"cvode-bdf\"\nbound_rel = 1e-6\nk = [2.0]\n";
  const std::string claim_path = write_file("bad-contact-claim.toml", claim_k);
  const CliRun c = run({"run", claim_path, "--out", (scratch() / "bad-contact-out").string()});
  EXPECT_EQ(c.code, 2);
  EXPECT_EQ(c.err, claim_path +
                       ":20: k: a scene with [[contact]] takes p = 1.5, v0, m and k from its "
                       "contacts (a claim or search may choose e, alpha or alpha_eff)\n");
}

// A [[trajectory]] names a [[contact]] for its p, m and k: what `pldamp check` gives for the same
// file from the same materials, row for row.
TEST(SceneContacts, ATrajectoryTakesItsContactFromTheScene) {
  // The steel contact's closed-form trajectory, sampled 200 times a contact (m* and k as the
  // scene derives them: read back below).
  const double m = 4.0 / 3 * std::numbers::pi * 0.005 * 0.005 * 0.005 * 7850;
  const double k = 4.0 / 3 * 2.1e11 / (1 - 0.29 * 0.29) * std::sqrt(0.005);
  const std::string file = write_file(
      "steel.csv",
      testing::csv_of(testing::sampled_contact(
          analytic::Contact<double>::from_e(1.5, 0.5, 1.0, m, k), 200, 0.3, true, false)));
  const std::string contact = R"([[contact]]
name = "steel"
geometry = "sphere-wall"
radius = 0.005
young = 2.1e11
poisson = 0.29
density = 7850
v0 = 1.0
[grid]
e = [0.5]
[[trajectory]]
contact = "steel"
e = 0.5
v0 = 1.0
file = ")" + file + "\"\n";
  const Scene scene = parse_scene(contact, "/x/s.toml");
  ASSERT_EQ(scene.trajectories.size(), 1u);
  EXPECT_EQ(scene.trajectories[0].p, 1.5);
  EXPECT_EQ(scene.trajectories[0].m, scene.contacts[0].m);
  EXPECT_EQ(scene.trajectories[0].k, scene.contacts[0].k);
  const TrajectoryCheck checked = check_trajectory(scene.trajectories[0], scene.end);
  ASSERT_TRUE(checked.failure.empty()) << checked.failure;
  const CliRun cli =
      run({"check", file, "--geometry", "sphere-wall", "--radius", "0.005", "--young", "2.1e11",
           "--poisson", "0.29", "--density", "7850", "--e", "0.5", "--v0", "1", "--json"});
  ASSERT_EQ(cli.code, 0) << cli.err;
  const nlohmann::json json = nlohmann::json::parse(cli.out);
  ASSERT_FALSE(checked.rows.empty());
  for (const TrajectoryRow& row : checked.rows) {
    ASSERT_TRUE(row.truth) << row.key;
    // check's truth is formed in float128 from the materials themselves, the scene's from its
    // contact's m* and k rounded to double: a rounding apart.
    EXPECT_LE(relative(*row.truth, json[row.key]["truth"].get<double>()), 4e-16) << row.key;
  }
  for (const auto& [entry, message] : std::vector<std::pair<std::string, std::string>>{
           {"contact = \"iron\"", "12: [[trajectory]] contact names no [[contact]] of the scene "
                                  "(got iron)"},
           {"contact = \"steel\"\nk = 2.0", "13: [[trajectory]] k is the contact's (steel): give "
                                            "one or the other"}}) {
    std::string text = contact;
    text.replace(text.find("contact = \"steel\""), 17, entry);
    try {
      parse_scene(text, "/x/s.toml");
      ADD_FAILURE() << entry;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), "/x/s.toml:" + message);
    }
  }
}

} // namespace
} // namespace pldamp::harness
