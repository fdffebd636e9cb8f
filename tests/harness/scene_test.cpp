// Scenes: every error names its file and line before any work; sweeps expand into
// configurations.
#include "fixtures.hpp"

#include <gtest/gtest.h>

namespace pldamp::harness {
namespace {

using namespace testing;

struct BadScene {
  std::string text;
  std::string message; // after "path:"
};

TEST(Scene, EveryErrorNamesFileAndLineBeforeAnyWork) {
  const std::vector<BadScene> cases{
      {"colour = 1\n" + valid_scene, "1: unknown key in the scene, expected "
                                     "name|end|want|grid|solver|claim|search|figure|trajectory|"
                                     "report|timing|limits|diff (got colour)"},
      {R"(name = "t"
[grid]
p = ["one"]
e = [0.5]
v0 = [1.0]
)",
       "3: p must be a number (got string)"},
      {R"([grid]
p = []
e = [0.5]
v0 = [1.0]
)",
       "2: p is an empty list"},
      {R"([grid]
p = [1.5, 0.5]
e = [0.5]
v0 = [1.0]
)",
       "2: p must be in [1, 1000] (got 0.5)"},
      {R"([grid]
p = [1.5]
e = [1.5]
v0 = [1.0]
)",
       "3: e must be in (0, 1] (got 1.5)"},
      {R"([grid]
p = [1.5]
v0 = [1.0]
)",
       "1: [grid] needs e, alpha or alpha_eff"},
      {"[grid]\np = 1.5\nalpha = [0.3, -0.1]\nv0 = 1.0\n",
       "3: alpha must be in [0, 1e8] (got -0.1)"},
      {"[grid]\np = 1.5\nalpha = [0.3, \"x\"]\nv0 = 1.0\n",
       "3: alpha must be a number (got string)"},
      // Beyond the seed α_eff depends on δ_u: α is converted at the one cell there is.
      {"[grid]\np = 1.5\ndamping_exponent = 0.5\nalpha = 0.3\nv0 = [1.0, 2.0]\n",
       "4: alpha with damping_exponent 0.5 at p = 1.5 needs one v0, m and k: the contact's "
       "alpha_eff depends on them (give alpha_eff, or one cell)"},
      {valid_scene + "[[solver]]\nname = \"ode45\"\nrtol = 1e-6\n",
       "11: unknown solver, expected cvode-bdf|cvode-adams|arkode-dp5|arkode-erk8|arkode-dirk|"
       "odeint-rkf78|odeint-bs|taylor|verlet-predicted|dem-verlet|dem-symplectic-euler|dem-"
       "leapfrog (got ode45)"},
      {valid_scene + "[[solver]]\nname = \"verlet-predicted\"\nrtol = 1e-6\n",
       "12: verlet-predicted takes a fixed step and no rtol: give steps_per_contact (got rtol)"},
      {valid_scene + "[[solver]]\nname = \"cvode-adams\"\nrtol = 1e-6\nprecision = \"long\"\n",
       "13: solver cvode-adams runs in double precision only; taylor runs in any (got long)"},
      {valid_scene + "[[solver]]\nname = \"taylor\"\nprecision = \"float\"\n",
       "12: unknown precision, expected " + precision_names() + " (got float)"},
      {valid_scene + "[[solver]]\nname = \"taylor\"\natol = 1e-12\n",
       "12: taylor controls its error relative to each state and takes no atol (got 1e-12)"},
      {valid_scene + "[[solver]]\nname = \"verlet-predicted\"\natol = 1e-12\n",
       "12: verlet-predicted takes a fixed step and no atol (got 1e-12)"},
      // Tolerances the solver could not meet, or that let any answer through, before any work.
      {valid_scene + "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-17\n",
       "12: cvode-bdf rtol=1e-17: rtol must be >= 2.220446049250313e-16, the epsilon of double "
       "(got 1e-17)"},
      {valid_scene + "[[solver]]\nname = \"arkode-dp5\"\nrtol = 1e-6\natol = 1e300\n",
       "12: arkode-dp5 rtol=1e-06 atol=1e+300: atol must be in [2.465190328815662e-32, 0.5), "
       "epsilon^2 times and once the smallest natural scale of the state (delta_u, v0, "
       "m v0^2/2) (got 1e+300)"},
      {valid_scene + "[report]\nformats = []\n",
       "11: formats names no report format, expected some of json|csv|md|html"},
      {valid_scene + "[report]\nwork_precision = []\n",
       "11: work_precision names nothing, expected some of "
       "e|delta_max|t_peak|tau|energy_load|energy_unload|worst"},
      {valid_scene + "[report]\nwork_precision = [\"e\", \"energy\"]\n", // a want word
       "11: work_precision names an observable the scene does not want, expected "
       "e|delta_max|t_peak|tau|energy_load|energy_unload|worst (got energy)"},
      {valid_scene + "[report]\nwork_precision = [\"e\", \"normal_force_max\"]\n",
       "11: work_precision names an observable the scene does not want, expected "
       "e|delta_max|t_peak|tau|energy_load|energy_unload|worst (got normal_force_max)"},
      {valid_scene + "[report]\nwork_precision = [\"worst\", \"e\", \"worst\"]\n",
       "11: work_precision names worst twice"},
      {valid_scene + "[report]\nwork_precision = [\"e\", 1]\n",
       "11: work_precision must be a string (got integer)"},
      {valid_scene + "[limits]\nmax_steps = 0\n",
       "11: max_steps must be an integer in [1, 1e12] (got 0)"},
      {valid_scene + "[limits]\nmax_seconds = -1\n",
       "11: max_seconds must be in (0, 86400] (got -1)"},
      {valid_scene +
           [] {
             std::string key = "a"; // a.a.a...: 40 parts
             for (int i = 1; i < 40; ++i) {
               key += ".a";
             }
             return key + " = 1\n";
           }(),
       "10: nested deeper than 32 levels (arrays, inline tables or dotted keys)"},
      {valid_scene + "x = " + std::string(40, '[') + std::string(40, ']') + "\n",
       "10: nested deeper than 32 levels (arrays, inline tables or dotted keys)"},
      {valid_scene + "name\xc3\x9f = 1\n",
       "10: a character beyond ASCII outside a comment (in a string, write it as \\uXXXX)"},
      {valid_scene + "# a comment may say \xc3\x9f\nx = \"\xc3\x9f\"\n",
       "11: a character beyond ASCII outside a comment (in a string, write it as \\uXXXX)"},
      {valid_scene + "[[solver]]\nname = \"cvode-adams\"\nrtl = 1e-6\n",
       "12: unknown key in [[solver]], expected "
       "name|rtol|atol|precision|steps_per_contact|end|onset_phases (got rtl)"},
      {valid_scene + "[[solver]]\nname = \"dem-verlet\"\nonset_phases = 2.5\n",
       "12: onset_phases must be an integer in [1, 1000] (got 2.5)"},
      {valid_scene + "[[solver]]\nname = \"cvode-adams\"\nrtol = 1e-6\nonset_phases = 4\n",
       "13: onset_phases is for fixed-step solvers (got cvode-adams)"},
      {valid_scene + "[[solver]]\nname = \"dem-verlet\"\nend = [\"overlap\", \"sideways\"]\n",
       "12: unknown contact end, expected overlap|force (got sideways)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nconvention = \"lammps\"\n"
                     "bound = 1e-3\n",
       "13: unknown convention, expected lammps-tsuji|lammps-tsuji-2026|lammps-coeff-restitution|"
       "liggghts|mercurydpm|chrono|yade (got lammps)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"force_max\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-6\nbound = 1e-5\n",
       "12: claim observable must be one the scene wants: "
       "e|delta_max|t_peak|tau|energy_load|energy_unload (got force_max)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-6\nbound = -1\n",
       "15: bound must be > 0 (got -1)"},
      {"end = \"sideways\"\n" + valid_scene,
       "1: unknown contact end, expected overlap|force (got sideways)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-6\nbound = 1e-5\nbound_rel = 1e-3\n",
       "15: [[claim]] needs one of bound (absolute error) and bound_rel (relative error)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-6\nbound_rel = 1e-3\nquantile = 0\n",
       "16: quantile must be in (0, 1] (got 0)"},
      {valid_scene + "[diff]\nerror_factor = 1\n", "11: error_factor must be in (1, 1e6] (got 1)"},
      {valid_scene + "[diff]\ntime_floor = -1\n",
       "11: time_floor must be in [0, 86400] seconds (got -1)"},
      {valid_scene + "[[search]]\nname = \"s\"\nsolver = \"verlet-predicted\"\nparameter = "
                     "\"rtol\"\nrange = [1e-8, 1e-3]\nobservable = \"e\"\nbound = 1e-3\n",
       "13: verlet-predicted takes a fixed step: search steps_per_contact or dt (got rtol)"},
      {valid_scene + "[[search]]\nname = \"s\"\nsolver = \"cvode-bdf\"\nparameter = \"rtol\"\n"
                     "range = [1e-8]\nobservable = \"e\"\nbound = 1e-3\n",
       "14: range must be [from, to], two different values of rtol in (0, 1)"},
      {valid_scene + "[[search]]\nname = \"s\"\nsolver = \"cvode-bdf\"\nparameter = \"rtol\"\n"
                     "range = [1e-8, 1e-3]\nobservable = \"e\"\n",
       "10: [[search]] needs one of bound (absolute error) and bound_rel (relative error)"},
      {valid_scene + "[[search]]\nname = \"s\"\nsolver = \"cvode-bdf\"\nparameter = \"rtol\"\n"
                     "range = [1e-8, 1e-3]\nobservable = \"e\"\nbound = 1e-3\nrtol = 1e-6\n",
       "17: [[search]] sets rtol per trial: give its range, not a value"},
      {valid_scene + "[timing]\nrepeats = 0\n",
       "11: repeats must be an integer in [1, 100] (got 0)"},
      {valid_scene + "[[claim]]\nname = \"no solver\"\nobservable = \"e\"\nbound = 1e-5\n",
       "10: [[claim]] needs solver"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"verlet-predicted\"\n"
                     "bound = 1e-2\n",
       "10: [[claim]] needs the steps_per_contact of its solver"},
      {"name = \"t\"\n[grid\n", "2: Error while parsing table header: expected ']', saw '\\n'"},
      {valid_scene + "[[figure]]\nkind = \"fig7\"\nsolver = \"arkode-dp5\"\n",
       "11: unknown figure, expected alpha_vs_e|force_history|delta_max_vs_e|tau_ratio|"
       "phase_portrait|f_of_p|restitution_approximations (got fig7)"},
      {"[grid]\np = [1.0, 2.0]\ndamping_exponent = 1.5\ne = 0.5\nv0 = 1.0\n",
       "3: damping exponent must be in [0, p] = [0, 1] (got 1.5) at p = 1"},
      {"[grid]\np = 1.5\ndamping_exponent = [0.25, 0.5]\ne = 0.5\nv0 = 1.0\n",
       "3: damping_exponent must be one number, as a scene's maps are p x damping (got 2 values)"},
      {valid_scene + "[[figure]]\nkind = \"restitution_approximations\"\np = 1.5\n"
                     "alpha_eff = [1.0, 0.1]\n",
       "13: alpha_eff must be [from, to] with 0 < from < to <= 10"},
      {valid_scene + "[[figure]]\nkind = \"tau_ratio\"\nsolver = \"arkode-dp5\"\nrtol = 1e-8\n"
                     "p = [1.5]\nalpha_eff = [0.5, 1.0]\n",
       "15: alpha_eff must be in [0, 1) (a return) (got 1)"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = write_file("bad" + std::to_string(i) + ".toml", cases[i].text);
    try {
      load_scene(path);
      ADD_FAILURE() << "no error for case " << i;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), path + ":" + cases[i].message) << "case " << i;
    }
    // Through the command line: the one line on stderr, exit 2, no report written.
    const fs::path out = scratch() / ("out" + std::to_string(i));
    fs::remove_all(out);
    const CliRun r = run({"run", path, "--out", out.string()});
    EXPECT_EQ(r.code, 2) << "case " << i;
    EXPECT_EQ(r.err, path + ":" + cases[i].message + "\n") << "case " << i;
    EXPECT_FALSE(fs::exists(out)) << "case " << i;
  }
  const CliRun missing = run({"run", (scratch() / "no-such.toml").string()});
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("no-such.toml:0: cannot read the scene"), std::string::npos)
      << missing.err;
}

// A value's own refusal names its line once (a [[trajectory]]'s was caught by the domain checks
// and prefixed again with the entry's line); the domain's own refusals name the entry. Figures
// check p as [grid] does (core/domain.hpp), a relation's tolerance says the range it checks, and a
// search's observable is refused with the observables the scene wants, as a claim's is.
TEST(Scene, RefusalsOfTrajectoriesFiguresAndTolerances) {
  const std::string file = write_file("refusals.csv", "t,delta\n0,0\n");
  const auto refusal = [](const std::string& text) {
    const std::string path = write_file("refusals.toml", text);
    try {
      load_scene(path);
    } catch (const SceneError& e) {
      return std::string(e.what()).substr(path.size() + 1);
    }
    return std::string("no error");
  };
  const std::string trajectory =
      "[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[trajectory]]\nfile = \"refusals.csv\"\np = 1.5\n"
      "e = 0.5\n";
  EXPECT_EQ(refusal(trajectory + "v0 = \"x\"\n"), "9: v0 must be a number (got string)");
  EXPECT_EQ(refusal(trajectory + "v0 = 0.0\n"), "5: v0 must be in [1e-30, 1e30] (got 0)");
  EXPECT_EQ(refusal(valid_scene + "[[figure]]\nkind = \"alpha_vs_e\"\nsolver = \"arkode-dp5\"\n"
                                  "p = [1.5, 1001.0]\ne = 0.5\n"),
            "13: p must be in [1, 1000] (got 1001)");
  const std::string relation = valid_scene + "[[claim]]\nname = \"c\"\nkind = \"relation\"\n"
                                             "of = \"truth\"\nquantity = \"e\"\nformula = "
                                             "\"seed_restitution\"\nrelation = \"equal_within\"\n";
  EXPECT_EQ(refusal(relation + "tolerance = -1\n"), "17: tolerance must be in [0, 1e300) (got -1)");
  EXPECT_EQ(refusal(relation + "tolerance = 1e300\n"),
            "17: tolerance must be in [0, 1e300) (got 1e+300)");
  EXPECT_EQ(refusal(relation + "tolerance = 0.5\n"), "no error");
  // A search's observable is refused as a claim's is, naming those the scene wants.
  EXPECT_EQ(refusal("want = [\"e\", \"tau\"]\n" + valid_scene.substr(valid_scene.find("[grid]")) +
                    "[[search]]\nname = \"s\"\nsolver = \"cvode-bdf\"\nparameter = \"rtol\"\n"
                    "range = [1e-8, 1e-3]\nobservable = \"delta_max\"\nbound = 1e-3\n"),
            "14: search observable must be one the scene wants: e|tau (got delta_max)");
}

// [report] work_precision: the series of the work-precision diagrams and table, in the scene's
// order; without it, e and the worst of all, or the one observable a scene wants alone.
TEST(Scene, WorkPrecisionChoosesTheReportsSeries) {
  const auto keys = [](const std::string& text) {
    std::vector<std::string> out;
    for (const WorkPanel& panel : work_panels(make_plan(load_scene(write_file("wp.toml", text))))) {
      out.push_back(panel.key + (panel.observable ? "" : " (all)"));
    }
    return out;
  };
  using Keys = std::vector<std::string>;
  EXPECT_EQ(keys(valid_scene), (Keys{"e", "worst (all)"}));
  EXPECT_EQ(keys(valid_scene + "[report]\nwork_precision = [\"tau\", \"worst\", \"e\"]\n"),
            (Keys{"tau", "worst (all)", "e"}));
  EXPECT_EQ(keys(valid_scene + "[report]\nwork_precision = \"energy_unload\"\n"),
            (Keys{"energy_unload"}));
  const std::string grid = "[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[solver]]\nname = \"taylor\"\n";
  EXPECT_EQ(keys("want = [\"tau\"]\n" + grid), (Keys{"tau"}));
  EXPECT_EQ(keys("want = [\"e\"]\n" + grid), (Keys{"e"}));
  EXPECT_EQ(keys("want = [\"tau\", \"delta_max\"]\n" + grid), (Keys{"worst (all)"}));
}

TEST(Scene, SweepsExpandIntoConfigurations) {
  const std::string exact(precision_name<Exact>()); // quad, or 50 digits in a build without it
  const std::string path = write_file("sweeps.toml", valid_scene + R"([[solver]]
name = "taylor"
precision = ")" + exact + R"("
[[solver]]
name = "verlet-predicted"
steps_per_contact = [50, 200]
[[solver]]
name = "arkode-dp5"
rtol = [1e-6, 1e-10]
atol = 1e-13
)");
  const Scene scene = load_scene(path);
  // A claim on a configuration the sweeps already run adds no configuration to the plan.
  const std::string with_claim = write_file("sweeps-claim.toml", valid_scene + R"([[solver]]
name = "verlet-predicted"
steps_per_contact = [50, 200]
[[claim]]
name = "DEM at 200 steps"
observable = "e"
solver = "verlet-predicted"
steps_per_contact = 200
bound = 1e-2
)");
  const Plan plan = make_plan(load_scene(with_claim));
  ASSERT_EQ(plan.configs.size(), 3u);
  EXPECT_EQ(std::get<BoundClaim>(plan.scene.claims[0].kind).config, plan.configs[2]);
  const CliRun no_folder = run({"run", with_claim, "--out", "/proc/pldamp-report"});
  EXPECT_EQ(no_folder.code, 2);
  EXPECT_EQ(no_folder.err.rfind("error: cannot create the report folder", 0), 0u) << no_folder.err;
  const CliRun no_jobs = run({"run", with_claim, "--jobs", "0"});
  EXPECT_EQ(no_jobs.code, 2);
  EXPECT_EQ(no_jobs.err, "error: --jobs must be in [1, 1024] (got 0)\n");
  std::vector<std::string> labels;
  for (const SolverConfig& config : scene.configs) {
    labels.push_back(config.label());
  }
  EXPECT_EQ(labels, (std::vector<std::string>{"cvode-bdf rtol=1e-06", "taylor " + exact,
                                              "verlet-predicted n=50", "verlet-predicted n=200",
                                              "arkode-dp5 rtol=1e-06 atol=1e-13",
                                              "arkode-dp5 rtol=1e-10 atol=1e-13"}));
}

} // namespace
} // namespace pldamp::harness
