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

// Each scene is refused with its one line, by load_scene and through `pldamp run` (exit 2, the
// line on stderr, no report written). `prefix` names the scratch files.
void expect_refused_before_any_work(const std::vector<BadScene>& cases, const std::string& prefix) {
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = write_file(prefix + std::to_string(i) + ".toml", cases[i].text);
    try {
      load_scene(path);
      ADD_FAILURE() << "no error for case " << i;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), path + ":" + cases[i].message) << "case " << i;
    }
    // Through the command line: the one line on stderr, exit 2, no report written.
    const fs::path out = scratch() / (prefix + "-out" + std::to_string(i));
    fs::remove_all(out);
    const CliRun r = run({"run", path, "--out", out.string()});
    EXPECT_EQ(r.code, 2) << "case " << i;
    EXPECT_EQ(r.err, path + ":" + cases[i].message + "\n") << "case " << i;
    EXPECT_FALSE(fs::exists(out)) << "case " << i;
  }
}

TEST(Scene, EveryErrorNamesFileAndLineBeforeAnyWork) {
  const std::vector<BadScene> cases{
      {"colour = 1\n" + valid_scene, "1: unknown key in the scene, expected "
                                     "name|end|want|contact|grid|solver|claim|search|figure|"
                                     "trajectory|report|timing|limits|diff (got colour)"},
      {R"(name = "t"
[grid]
p = ["one"]
e = [0.5]
v0 = [1.0]
)",
       "3: p must be a number (got string)"},
      {R"(name = "t"
[grid]
p = [1.5]
e = [0.5]
v0 = [9223372036854775807]
)",
       "5: v0 is an integer beyond 2^53, which no double holds exactly: write it as a float (got "
       "9223372036854775807)"},
      // Decimal only, as on the command line: TOML's other bases read 0x10 as 16 m/s.
      {"name = \"t\"\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [0x10]\n",
       "5: v0 must be written in decimal (got 0x10)"},
      {"name = \"t\"\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [0o17]\n",
       "5: v0 must be written in decimal (got 0o17)"},
      {"name = \"t\"\n[grid]\np = [0b1]\ne = [0.5]\nv0 = [1.0]\n",
       "3: p must be written in decimal (got 0b1)"},
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
       "name|rtol|atol|precision|steps_per_contact|end|onset_phases|tau_as (got rtl)"},
      {valid_scene + "[[solver]]\nname = \"dem-verlet\"\nonset_phases = 2.5\n",
       "12: onset_phases must be an integer in [1, 1000] (got 2.5)"},
      {valid_scene + "[[solver]]\nname = \"cvode-adams\"\nrtol = 1e-6\nonset_phases = 4\n",
       "13: onset_phases is for fixed-step solvers (got cvode-adams)"},
      {valid_scene + "[[solver]]\nname = \"dem-verlet\"\nend = [\"overlap\", \"sideways\"]\n",
       "12: unknown contact end, expected overlap|force (got sideways)"},
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nconvention = \"lammps\"\n"
                     "bound = 1e-3\n",
       "13: unknown convention, expected lammps-tsuji|lammps-tsuji-2026|lammps-coeff-restitution|"
       "liggghts|mercurydpm|chrono|yade|yade-viscel|yade-hertz-mindlin (got lammps)"},
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
      // A claim's or search's name is its identity in reports and diff.
      {valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = \"cvode-bdf\"\n"
                     "rtol = 1e-8\nbound = 1e-5\n[[claim]]\nname = \"c\"\nobservable = \"e\"\n"
                     "solver = \"cvode-bdf\"\nrtol = 1e-8\nbound = 1e-6\n",
       "17: [[claim]] c is named twice"},
  };
  expect_refused_before_any_work(cases, "bad");
  const CliRun missing = run({"run", (scratch() / "no-such.toml").string()});
  EXPECT_EQ(missing.code, 2);
  EXPECT_EQ(missing.err, "error: cannot read the scene: No such file or directory (got " +
                             (scratch() / "no-such.toml").string() + ")\n");
}

// Every key a scene accepts takes effect: a key that would not change the run is refused with
// why, from the solver's traits (solvers/registry.hpp), the claim's kind or the figure's.
TEST(Scene, AKeyWithoutEffectIsRefusedWithWhy) {
  const std::string claim = "[[claim]]\nname = \"c\"\nobservable = \"e\"\n"; // lines 10-12
  const std::string relation = "[[claim]]\nname = \"c\"\nkind = \"relation\"\n";
  const std::string truth = "of = \"truth\"\nquantity = \"e\"\nformula = \"seed_restitution\"\n"
                            "relation = \"equal_within\"\ntolerance = 1e-20\n"; // lines 13-17
  const std::string asymptotic = "[[claim]]\nname = \"c\"\nkind = \"asymptotic\"\nof = "
                                 "\"truth\"\nquantity = \"tau_ratio\"\nformula = "
                                 "\"seed_tau_ratio_curve\"\norder = 1\n"; // lines 10-16
  const std::string figure = "[[figure]]\nkind = ";
  // An external solver swept by steps per contact (lines 10-13), then a claim on it (14-19).
  const std::string external = "[[solver]]\ncommand = [\"./code\"]\nlabel = \"code\"\n"
                               "steps_per_contact = [50, 100]\n[[claim]]\nname = \"c\"\n"
                               "observable = \"e\"\nsolver = \"code\"\n";
  const std::vector<BadScene> cases{
      // The sweep key a solver's traits say it ignores, in a claim of every kind that takes one.
      {valid_scene + claim +
           "solver = \"dem-verlet\"\nsteps_per_contact = 50\nrtol = 1e-3\n"
           "bound = 1e-2\n",
       "15: rtol has no effect on fixed-step solver dem-verlet; set steps_per_contact"},
      {valid_scene + claim +
           "solver = \"cvode-bdf\"\nrtol = 1e-6\nsteps_per_contact = 50\n"
           "bound = 1e-2\n",
       "15: steps_per_contact has no effect on error-controlled solver cvode-bdf; set rtol"},
      {valid_scene + relation +
           "solver = \"dem-verlet\"\nrtol = 1e-3\nquantity = \"e\"\n"
           "formula = \"seed_restitution\"\nrelation = \"equal_within\"\n"
           "tolerance = 1e-2\n",
       "14: rtol has no effect on fixed-step solver dem-verlet; set steps_per_contact"},
      {valid_scene + "[[claim]]\nname = \"c\"\nkind = \"recovered_parameter\"\nsolver = "
                     "\"taylor\"\nsteps_per_contact = 50\nbound = 1e-3\n",
       "14: steps_per_contact has no effect on error-controlled solver taylor; set rtol"},
      // The truth (the closed forms) takes no solver's settings.
      {valid_scene + relation + truth + "atol = 1e-9\n",
       "18: atol has no effect on the truth (of = \"truth\", the closed forms): it is a solver's "
       "setting"},
      {valid_scene + asymptotic + "steps_per_contact = 50\n",
       "17: steps_per_contact has no effect on the truth (of = \"truth\", the closed forms): it "
       "is a solver's setting"},
      // A figure: rtol beside a fixed step, the list its kind is not drawn over, a second value
      // where it is drawn at one, a tolerance the solver cannot meet.
      {valid_scene + figure +
           "\"alpha_vs_e\"\nsolver = \"dem-verlet\"\nrtol = 1e-3\np = 1.5\n"
           "e = 0.5\n",
       "13: rtol has no effect on fixed-step solver dem-verlet; a figure runs it at 50 steps per "
       "contact"},
      {valid_scene + figure +
           "\"tau_ratio\"\nsolver = \"arkode-dp5\"\np = 1.5\n"
           "alpha_eff = 0.5\ne = 0.5\n",
       "15: e has no effect on figure tau_ratio: it is drawn against alpha_eff"},
      {valid_scene + figure +
           "\"delta_max_vs_e\"\nsolver = \"arkode-dp5\"\np = 1.5\ne = 0.5\n"
           "alpha_eff = 0.5\n",
       "15: alpha_eff has no effect on figure delta_max_vs_e: it is drawn at target e"},
      {valid_scene + figure +
           "\"force_history\"\nsolver = \"arkode-dp5\"\np = 1.5\n"
           "e = [0.5, 0.7]\n",
       "14: figure force_history is drawn at one e (got 2 values)"},
      {valid_scene + figure +
           "\"f_of_p\"\nsolver = \"arkode-dp5\"\np = [1.0, 2.0]\n"
           "e = [0.5, 0.7]\n",
       "14: figure f_of_p is drawn at one e (got 2 values)"},
      {valid_scene + figure +
           "\"phase_portrait\"\nsolver = \"arkode-dp5\"\np = [1.5, 2.0]\n"
           "e = [0.5, 0.7]\n",
       "13: figure phase_portrait is drawn at one p (got 2 values)"},
      {valid_scene + figure +
           "\"alpha_vs_e\"\nsolver = \"taylor\"\nrtol = 1e-20\np = 1.5\n"
           "e = 0.5\n",
       "10: taylor rtol=1e-20: rtol must be >= 2.220446049250313e-16, the epsilon of double (got "
       "1e-20)"},
      // A claim on an external solver takes its [[solver]]'s configuration at a value of its
      // sweep: what it cannot change is refused.
      {valid_scene + external + "steps_per_contact = 50\natol = 1e-9\nbound = 1e-2\n",
       "19: atol has no effect on external solver code: a claim takes its configuration from its "
       "[[solver]] (set atol there)"},
      {valid_scene + external + "steps_per_contact = 50\nonset_phases = 4\nbound = 1e-2\n",
       "19: onset_phases has no effect on external solver code: a claim takes its configuration "
       "from its [[solver]] (set onset_phases there)"},
      {valid_scene + external + "steps_per_contact = 50\nprecision = \"double\"\nbound = 1e-2\n",
       "19: precision has no effect on external solver code: it answers in double"},
      {valid_scene + external + "steps_per_contact = 50\nrtol = 1e-6\nbound = 1e-2\n",
       "19: rtol has no effect on external solver code, which sweeps steps_per_contact: name its "
       "configuration by steps_per_contact"},
      {valid_scene + "[[solver]]\ncommand = [\"./code\"]\nlabel = \"code\"\nrtol = [1e-6]\n" +
           claim + "solver = \"code\"\nrtol = 1e-6\nsteps_per_contact = 50\nbound = 1e-2\n",
       "19: steps_per_contact has no effect on external solver code, which sweeps rtol: name its "
       "configuration by rtol"},
      {valid_scene + "[[solver]]\ncommand = [\"./code\"]\nlabel = \"code\"\n" + claim +
           "solver = \"code\"\nrtol = 1e-6\nsteps_per_contact = 50\nbound = 1e-2\n",
       "18: a claim on external solver code gives at most one of rtol and steps_per_contact, as "
       "a [[solver]] sweeps one"},
      {valid_scene + "[[solver]]\ncommand = [\"./code\"]\nlabel = \"code\"\ndt = [0.1, 0.01]\n" +
           claim + "solver = \"code\"\nbound = 1e-2\n",
       "17: a claim cannot name a configuration of external solver code, which sweeps dt: it "
       "names one by rtol or steps_per_contact"},
      // A convention whose code has no force cap to switch, or always caps.
      {valid_scene + claim + "convention = \"mercurydpm\"\nlimit_damping = true\nbound = 1e-3\n",
       "14: limit_damping has no effect on convention mercurydpm, which never caps the force"},
      {valid_scene + claim + "convention = \"chrono\"\nlimit_damping = false\nbound = 1e-3\n",
       "14: limit_damping has no effect on convention chrono, which always caps the force"},
      // An asymptotic claim is judged at one v0, m and k, and refined in p only.
      {valid_scene + asymptotic + "v0 = [1.0, 2.0]\n",
       "17: an asymptotic claim is judged at one v0 (got 2 values)"},
      {valid_scene + asymptotic + "denser = true\n",
       "17: denser has no effect on an asymptotic claim with one p: its grid is refined in p"},
      {valid_scene + claim + "solver = \"cvode-bdf\"\nrtol = 1e-6\nbound = 1e-2\ndenser = true\n",
       "16: denser has no effect: the claim's grid has one value in every list, nothing to "
       "refine"},
      // A search's dt range says its upper end, and its ends must keep the scan finite.
      {valid_scene + "[[search]]\nname = \"s\"\nsolver = \"dem-verlet\"\nparameter = \"dt\"\n"
                     "range = [1e-3, 1e300]\nobservable = \"e\"\nbound = 1e-3\n",
       "14: range must be [from, to], two different values of dt in (0, 1e300)"},
      {valid_scene + "[[search]]\nname = \"s\"\nsolver = \"dem-verlet\"\nparameter = \"dt\"\n"
                     "range = [1e-10, 1e299]\nobservable = \"e\"\nbound = 1e-3\n",
       "14: range must have its ends within a factor 1e300 of each other (got inf)"},
      // A word said twice adds nothing.
      {valid_scene + "[report]\nformats = [\"json\", \"md\", \"json\"]\n",
       "11: formats names json twice"},
      {"want = [\"e\", \"tau\", \"e\"]\n" + valid_scene.substr(valid_scene.find("[grid]")),
       "1: want names e twice"},
      // A value said twice: a cell, a figure's point or a configuration twice.
      {"[grid]\np = [1.5, 2.0, 1.5]\ne = 0.5\nv0 = 1.0\n[[solver]]\nname = \"taylor\"\n",
       "2: p names 1.5 twice"},
      {valid_scene + claim +
           "solver = \"cvode-bdf\"\nrtol = 1e-6\nbound = 1e-2\n"
           "v0 = [1.0, 0.1, 1.0]\n",
       "16: v0 names 1 twice"},
      {valid_scene + figure +
           "\"alpha_vs_e\"\nsolver = \"arkode-dp5\"\np = 1.5\n"
           "e = [0.5, 0.5]\n",
       "14: e names 0.5 twice"},
      {valid_scene + "[[solver]]\nname = \"cvode-bdf\"\nrtol = [1e-8, 1e-6]\n",
       "12: cvode-bdf rtol=1e-06 is a configuration the scene has already"},
      {valid_scene + "[[solver]]\nname = \"dem-verlet\"\nend = [\"force\", \"force\"]\n",
       "10: dem-verlet n=50 end=force is a configuration the scene has already"},
      {valid_scene + "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-6\nend = \"overlap\"\n",
       "12: cvode-bdf rtol=1e-06 end=overlap is a configuration the scene has already"},
      {valid_scene + "[[solver]]\ncommand = [\"./code\"]\nlabel = \"code\"\n"
                     "steps_per_contact = [50, 100, 50]\n",
       "13: code n=50 is a configuration the scene has already"},
      // Repeats time pldamp's own configurations; an external program runs once.
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[solver]]\ncommand = [\"./code\"]\nlabel = "
       "\"code\"\n[timing]\nrepeats = 2\n",
       "9: repeats has no effect: the scene runs none of pldamp's solvers on its grid (an "
       "external program runs once; claims on grids of their own and searches solve once)"},
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[solver]]\nname = \"taylor\"\n[timing]\n"
       "repeat_below = 1e-3\n",
       "8: repeat_below has no effect with repeats = 1"},
      // A limit where nothing it limits runs: an external program is given no step limit, and
      // a trajectory is judged by the closed forms.
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[solver]]\ncommand = [\"./code\"]\nlabel = "
       "\"code\"\n[limits]\nmax_steps = 100\n",
       "9: max_steps has no effect: the scene runs none of pldamp's solvers (an external program "
       "is given no step limit)"},
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[trajectory]]\nfile = \"no-effect.csv\"\n"
       "p = 1.5\ne = 0.5\nv0 = 1.0\n[limits]\nmax_seconds = 5\n",
       "11: max_seconds has no effect: the scene solves nothing (its claims and trajectories are "
       "judged by the closed forms)"},
      // The work-precision diagrams are drawn from records.
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n" + relation + truth +
           "[report]\nwork_precision = \"e\"\n",
       "14: work_precision has no effect: the scene has no records to draw (no [[solver]], no "
       "bound claim on its grid)"},
      // pldamp diff compares records (their errors, work and time), claims and searches.
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[trajectory]]\nfile = \"no-effect.csv\"\n"
       "p = 1.5\ne = 0.5\nv0 = 1.0\n[diff]\nerror_factor = 5\n",
       "11: error_factor has no effect: the scene has no records, claims or searches for pldamp "
       "diff to compare (it compares no trajectory)"},
      {"[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n" + relation + truth + "[diff]\ntime_factor = 3\n",
       "14: time_factor has no effect: the scene has no records for pldamp diff to compare (no "
       "[[solver]], no bound claim on its grid)"},
  };
  write_file("no-effect.csv", "t,delta\n0,0\n");
  expect_refused_before_any_work(cases, "no-effect");
}

// What the refusals above leave is taken: a claim on an external solver without a sweep names a
// configuration of its own by rtol or steps_per_contact, repeats time a claim's configuration of
// pldamp's, denser refines a grid with a list to refine, error_factor judges a claim's value.
TEST(Scene, TheKeysBesideTheRefusedOnesTakeEffect) {
  const std::string external = "[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[solver]]\ncommand = "
                               "[\"./code\"]\nlabel = \"code\"\n[[claim]]\nname = \"c\"\n"
                               "observable = \"e\"\nsolver = \"code\"\nbound = 1e-2\n";
  const auto claimed = [](const std::string& name, const std::string& text) {
    return std::get<BoundClaim>(load_scene(write_file(name, text)).claims.at(0).kind).config;
  };
  EXPECT_EQ(claimed("steps.toml", external + "steps_per_contact = 50\n").steps_per_contact, 50);
  EXPECT_EQ(claimed("rtol.toml", external + "rtol = 1e-6\n").rtol, 1e-6);
  const SolverConfig own = claimed("own.toml", external);
  EXPECT_FALSE(own.rtol || own.steps_per_contact || own.dt);
  const Scene repeated = load_scene(write_file(
      "repeats.toml", "[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[claim]]\nname = \"c\"\n"
                      "observable = \"e\"\nsolver = \"cvode-bdf\"\nrtol = 1e-6\nbound = 1e-2\n"
                      "[timing]\nrepeats = 2\nrepeat_below = 0.5\n"));
  EXPECT_EQ(repeated.repeats, 2);
  EXPECT_EQ(repeated.repeat_below, 0.5);
  const Scene denser = load_scene(write_file(
      "denser.toml", valid_scene + "[[claim]]\nname = \"c\"\nobservable = \"e\"\nsolver = "
                                   "\"cvode-bdf\"\nrtol = 1e-6\nbound = 1e-2\nv0 = [1.0, 2.0]\n"
                                   "denser = true\n"));
  EXPECT_TRUE(denser.claims.at(0).denser);
  // A claim's measured value is compared by pldamp diff: error_factor takes effect.
  const Scene compared = load_scene(write_file(
      "diff.toml", "[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[claim]]\nname = \"c\"\nkind = "
                   "\"relation\"\nof = \"truth\"\nquantity = \"e\"\nformula = "
                   "\"seed_restitution\"\nrelation = \"equal_within\"\ntolerance = 1e-20\n"
                   "[diff]\nerror_factor = 5\n"));
  EXPECT_EQ(compared.diff.error_factor, 5);
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
