// External solvers over the pldamp-solver protocol (run/external.hpp), against a test double
// (adapters/fake_adapter.py) that behaves, or misbehaves in one way per mode.
#include "fake_solver.hpp"
#include "judge/claims.hpp"
#include "report/sections.hpp"
#include "run/answers.hpp"
#include "run/external.hpp"

#include "pldamp/solvers/registry.hpp"

#include <boost/math/constants/constants.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace pldamp::harness {
namespace {

using testing::Ran;
using testing::run;
using testing::run_scene_text;
using testing::scene_with;
using testing::scratch;
using testing::write_file;

double p_of(const Ran& ran, const Record& record) {
  return ran.plan.points[ran.plan.cells[record.cell].point].p;
}

// A fresh state file for the modes that remember (crash_once, hang_once, record).
std::string fresh_state(const std::string& name) {
  const std::string path = (scratch() / name).string();
  std::filesystem::remove(path);
  return path;
}

TEST(External, AnIndependentTruthAgreesToRoundingAndOtherExponentsAreSkippedNotFailed) {
  const Ran ran = run_scene_text(scene_with("good"));
  ASSERT_EQ(ran.records.size(), 8u);
  for (const Record& record : ran.records) {
    if (p_of(ran, record) == 1) {
      // The fake answers with the linear oscillator's closed forms in Python's double: pldamp's
      // float128 truth of the seed's p = 1 must agree to a few ulps.
      EXPECT_FALSE(record.failed()) << record.failure;
      EXPECT_FALSE(record.skipped());
      for (const auto& error : record.rel_error) {
        ASSERT_TRUE(error.has_value());
        EXPECT_LT(*error, 1e-14);
      }
    } else {
      EXPECT_TRUE(record.skipped());
      EXPECT_FALSE(record.failed());
      EXPECT_EQ(record.skip_reason, "unsupported: p = 1 only");
      EXPECT_EQ(record.outcome_name(), "skipped");
    }
  }
  const Budgets budgets = make_budgets(ran.plan, ran.records);
  EXPECT_EQ(budgets.failed_records, 0);
  EXPECT_EQ(budgets.cost[0].underdamped.cells, 4); // the skipped records cost nothing
  const RunTotals totals{0, 0, 0, {"fake good"}};
  const std::vector<Figure> figures;
  const MapTable table = external_table({ran.plan, ran.records, budgets, totals, figures});
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(table.rows[0], (std::vector<std::string>{
                               "fake", "python3 " PLDAMP_TEST_ADAPTERS "/fake_adapter.py good",
                               "fake good", "4", "4 (unsupported: p = 1 only)", "0", "0", "–"}));
}

TEST(External, EveryProblemCarriesTheProtocolsKeys) {
  const std::string state = fresh_state("problems.jsonl");
  const Ran ran = run_scene_text(scene_with(
      "record", "steps_per_contact = [40]\nonset_phases = 2\noptions = { seed = 7 }\n", state));
  std::ifstream in(state);
  std::string line;
  std::vector<nlohmann::json> problems;
  while (std::getline(in, line)) {
    problems.push_back(nlohmann::json::parse(line));
  }
  // p = 1: 4 cells × 2 onset phases; p = 1.5: 4 cells, each skipped at its first phase.
  ASSERT_EQ(problems.size(), 12u);
  std::vector<long> ids;
  for (const nlohmann::json& problem : problems) {
    ids.push_back(problem["id"]);
    const double p = problem["p"], m = problem["m"], k = problem["k"], v0 = problem["v0"];
    EXPECT_EQ(problem["damping_exponent"].get<double>(), (p - 1) / 2);
    EXPECT_EQ(problem["end"], "overlap");
    EXPECT_EQ(problem["want"], nlohmann::json({"e", "delta_max", "t_peak", "tau"}));
    EXPECT_EQ(problem["steps_per_contact"], 40);
    const double delta_u = std::pow((p + 1) / 2 * m * v0 * v0 / k, 1 / (p + 1)); // undamped peak
    EXPECT_NEAR(problem["dt"].get<double>(),
                boost::math::constants::pi<double>() * delta_u / v0 / 40, 1e-17);
    const double phase = problem["onset_phase"];
    EXPECT_TRUE(phase == 0 || phase == 0.5) << phase;
    EXPECT_EQ(problem["options"], nlohmann::json({{"seed", 7}}));
    EXPECT_GT(problem["alpha"].get<double>(), 0);
  }
  std::sort(ids.begin(), ids.end());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    EXPECT_EQ(ids[i], long(i)); // every id once (the configuration's one program numbers them)
  }
  EXPECT_EQ(ran.plan.configs.front().label(), "fake n=40 phases=2");
}

// Each misbehaviour fails its records with its reason, and the run goes on to the end.
TEST(External, EachMisbehaviourFailsItsRecordsWithAReason) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"bad_json", "the reply is not JSON (got 'e = 0.5')"},
      {"wrong_id", "the reply is for another problem: id 0 expected (got '7')"},
      {"no_outcome", "the reply has no outcome"},
      {"slow_clock", "the reply's wall_seconds 1e+300 is longer than its round trip"},
      {"deep", "the reply nests JSON deeper than 16 levels (got '{\"id\": 0, \"outcome\": "
               "\"error\", \"reason\": \"\\u00e9\\n\\u00e9"},
      {"error", "the program's error: fakecode: lost atoms"},
      {"crash", "the program exited with status 3; its last words on stderr: 'fake: boom'"},
      {"partial", "the program exited with status 0 in the middle of a line ('{\"id\": 0, "
                  "\"outc')"},
      {"hang", "no reply within 0.5 s ([limits] max_seconds); the program was stopped"}};
  for (const auto& [mode, reason] : cases) {
    const Ran ran = run_scene_text(scene_with(mode, "", "", "p = [1]\ne = [0.5]\nv0 = [1, 2]\n"));
    long failed = 0;
    bool reason_seen = false;
    for (const Record& record : ran.records) {
      failed += record.failed() ? 1 : 0;
      reason_seen = reason_seen || record.failure.find(reason) != std::string::npos;
      EXPECT_FALSE(record.outcome.has_value()) << mode;
    }
    EXPECT_EQ(failed, 2) << mode;
    EXPECT_TRUE(reason_seen) << mode << ": " << ran.records.front().failure;
  }
}

// A program that does not read its input: a problem line longer than the pipe's buffer (64 KiB)
// blocked pldamp's write for ever, deaf to max_seconds and to SIGTERM. It fails the record
// within the limit, as a late reply does.
TEST(External, AProgramThatDoesNotReadFailsItsRecordWithinTheLimit) {
  const Ran ran = run_scene_text(
      scene_with("deaf", "options = { padding = \"" + std::string(100000, 'x') + "\" }\n", "",
                 "p = [1]\ne = [0.5]\nv0 = [1]\n"));
  ASSERT_EQ(ran.records.size(), 1u);
  EXPECT_TRUE(ran.records.front().failed());
  EXPECT_EQ(ran.records.front().failure,
            "the program did not read the problem within 0.5 s ([limits] max_seconds); the "
            "program was stopped");
}

TEST(External, ACrashedOrHungProgramIsRestartedForTheNextRecord) {
  for (const std::string mode : {"crash_once", "hang_once"}) {
    const Ran ran = run_scene_text(
        scene_with(mode, "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-8\n", fresh_state(mode)));
    long failed = 0, good = 0;
    for (const Record& record : ran.records) {
      if (ran.plan.configs[record.config].external() && p_of(ran, record) == 1) {
        failed += record.failed() ? 1 : 0;
        good += record.rel_error[0] && *record.rel_error[0] < 1e-14 ? 1 : 0;
      }
    }
    EXPECT_EQ(failed, 1) << mode;
    EXPECT_EQ(good, 3) << mode;
  }
}

// Whether process `pid` has ended: gone from /proc, or a zombie (dead, left for its parent to
// reap: an orphan's new parent, init, may never do so in a container).
bool ended(long pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  const std::string text((std::istreambuf_iterator<char>(stat)), {});
  const std::size_t name_end = text.rfind(')'); // "PID (NAME) STATE ...", NAME may hold ')'
  return text.empty() || (name_end != std::string::npos && text.substr(name_end, 3) == ") Z");
}

// The pids fake_adapter.py's fork modes append to their state file: the program's and its
// sleeping child's, a line each time one forks.
std::vector<long> forked_pids(const std::string& state) {
  std::ifstream in(state);
  std::vector<long> pids;
  for (long pid = 0; in >> pid;) {
    pids.push_back(pid);
  }
  return pids;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A program that forks a child which sleeps an hour on its pipes. Whether the program answers
// (fork_stay) or exits without a word (fork_exit on its first problem, fork_handshake before its
// handshake), no process of it is left after the run: each ran in its own process group, stopped
// as a whole. And a program that exits fails at once, though its child holds its output open:
// each record waited max_seconds ("no reply within 5 s"), the handshake 30 s ("no handshake
// within 30 s"), and the children slept on as orphans.
TEST(External, NoProcessOfAProgramOutlivesTheRun) {
  const auto scene = [](const std::string& mode, const std::string& state) {
    return "name = \"forks\"\nwant = [\"e\"]\n[grid]\np = [1]\ne = [0.5]\nv0 = [1, 2]\n"
           "[limits]\nmax_seconds = 5\n" +
           testing::fake_solver(mode, state);
  };
  const auto expect_all_ended = [](const std::string& state, std::size_t processes) {
    const std::vector<long> pids = forked_pids(state);
    EXPECT_EQ(pids.size(), processes) << state;
    for (const long pid : pids) {
      EXPECT_TRUE(ended(pid)) << "process " << pid << " of " << state << " still runs";
    }
  };
  const std::string staying = fresh_state("fork_stay.pids");
  for (const Record& record : run_scene_text(scene("fork_stay", staying)).records) {
    EXPECT_FALSE(record.failed()) << record.failure;
  }
  expect_all_ended(staying, 2);

  const std::string exiting = fresh_state("fork_exit.pids");
  auto start = std::chrono::steady_clock::now();
  const Ran ran = run_scene_text(scene("fork_exit", exiting));
  const double both_records = seconds_since(start);
  ASSERT_EQ(ran.records.size(), 2u);
  for (const Record& record : ran.records) {
    EXPECT_EQ(record.failure, "the program exited with status 0"); // restarted for the second
  }
  EXPECT_LT(both_records, 2.0) << "each record waited for the child, not the program";
  expect_all_ended(exiting, 4);

  const std::string before_handshake = fresh_state("fork_handshake.pids");
  start = std::chrono::steady_clock::now();
  try {
    run_scene_text(scene("fork_handshake", before_handshake));
    ADD_FAILURE() << "a program without a handshake ran";
  } catch (const ProtocolError& e) {
    EXPECT_EQ(std::string(e.what()),
              "[[solver]] fake: the program exited with status 0 before its handshake");
  }
  EXPECT_LT(seconds_since(start), 2.0) << "the handshake waited for the child";
  expect_all_ended(before_handshake, 2);
}

// A program runs in a process group of its own, so a terminal's Ctrl-C reaches pldamp alone: the
// run's stop (its SIGINT handler's flag) ends the wait for a reply at once, and the program with
// it, where the wait went on to max_seconds (60 s here).
TEST(External, AStoppedRunStopsWaitingForTheProgram) {
  const std::string text = "name = \"stopped\"\nwant = [\"e\"]\n[grid]\np = [1]\ne = [0.5]\n"
                           "v0 = [1]\n[limits]\nmax_seconds = 60\n" +
                           testing::fake_solver("hang");
  std::thread stopper([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    stop_requested() = true;
  });
  const auto start = std::chrono::steady_clock::now();
  const Ran ran = run_scene_text(text);
  const double seconds = seconds_since(start);
  stopper.join();
  stop_requested() = false;
  ASSERT_EQ(ran.records.size(), 1u);
  EXPECT_EQ(ran.records[0].failure, "pldamp was stopped by a signal; the program was stopped");
  EXPECT_LT(seconds, 2.0);
}

TEST(External, AWrongProtocolOrNoProgramStopsTheRunBeforeAnyWork) {
  EXPECT_THROW(run_scene_text(scene_with("wrong_version")), ProtocolError);
  EXPECT_THROW(run_scene_text(scene_with("no_handshake")), ProtocolError);
  const std::string missing = "name = \"x\"\n[grid]\np = [1]\ne = [0.5]\nv0 = [1]\n"
                              "[[solver]]\ncommand = [\"./no-such-adapter\"]\nlabel = \"none\"\n";
  try {
    run_scene_text(missing);
    FAIL() << "a missing program was started";
  } catch (const ProtocolError& e) {
    // The program as typed, and where it was looked for.
    EXPECT_NE(std::string(e.what()).find(
                  "[[solver]] none: cannot start ./no-such-adapter (from the scene's folder: " +
                  (scratch() / "no-such-adapter").string() + ", not found or not executable)"),
              std::string::npos)
        << e.what();
  }
  const std::string path = write_file("wrong_version.toml", scene_with("wrong_version"));
  const auto cli = run({"run", path, "--out", (scratch() / "wrong_version").string()});
  EXPECT_EQ(cli.code, 2);
  EXPECT_NE(cli.err.find("speaks another protocol; pldamp speaks pldamp-solver version 1"),
            std::string::npos)
      << cli.err;
  EXPECT_FALSE(std::filesystem::exists(scratch() / "wrong_version" / "report.json"));
}

TEST(External, RunsLimitsAndThePlansSizeCountWhatAProgramIsGiven) {
  // An external program is given no step limit, so --max-steps on a scene of programs only is
  // refused, as [limits] max_steps is; --max-seconds limits its replies and is taken.
  const std::string programs = write_file("programs.toml", scene_with("good"));
  const std::string out = (scratch() / "programs").string();
  const auto steps = run({"run", programs, "--out", out, "--max-steps", "100"});
  EXPECT_EQ(steps.code, 2);
  EXPECT_EQ(steps.err, "error: --max-steps has no effect: the scene runs none of pldamp's solvers "
                       "(an external program is given no step limit) (got 100)\n");
  EXPECT_EQ(run({"run", programs, "--out", out, "--max-seconds", "5", "--max-runs", "1"}).err,
            "error: the plan has 8 solver runs, above the limit of 1: shrink the grid, raise "
            "the limit with --max-runs or [limits] max_runs, or share it with --shard or mpirun "
            "(got " +
                programs + ")\n");
  // Timing repeats apply to pldamp's own solvers: 8 cells x (3 repeats + the program once).
  const std::string mixed = write_file(
      "mixed.toml",
      scene_with("good", "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-8\n[timing]\nrepeats = 3\n"));
  EXPECT_NE(run({"run", mixed, "--out", out, "--max-runs", "1"})
                .err.find("the plan has 32 solver runs, above the limit of 1"),
            std::string::npos);
}

TEST(External, AnUnavailableCodeIsSkippedWithItsReason) {
  const Ran ran = run_scene_text(scene_with("unavailable"));
  for (const Record& record : ran.records) {
    EXPECT_TRUE(record.skipped());
    EXPECT_FALSE(record.failed());
    EXPECT_EQ(record.skip_reason, "unavailable: fakecode not found on PATH");
  }
  // An empty reason is said to be missing ("unavailable: unavailable" before).
  for (const Record& record : run_scene_text(scene_with("unavailable_silently")).records) {
    EXPECT_EQ(record.skip_reason, "unavailable: (no reason given)");
  }
}

// A code whose dashpot is not the point's is judged against the reference solve of its own β at
// α as it received it (MATH.md §12.2): here taylor in Exact with β = 1/2, run directly.
TEST(External, ADashpotNotTheSeedsIsJudgedAgainstTheReferenceSolveOfItsOwnExponent) {
  const Ran ran = run_scene_text(scene_with("beta"));
  int judged = 0;
  for (const Record& record : ran.records) {
    if (p_of(ran, record) != 1) {
      continue;
    }
    EXPECT_FALSE(record.failed());
    EXPECT_TRUE(record.value[0].has_value());
    ASSERT_TRUE(record.reference[0].has_value());
    EXPECT_TRUE(record.rel_error[0].has_value());
    EXPECT_EQ(record.note, "truth by reference solve: it damps as delta^0.5 delta'");
    const Cell& cell = ran.plan.cells[record.cell];
    ASSERT_EQ(ran.plan.observables[0]->key, "e");
    solvers::Options<Exact> options;
    options.rtol = std::numeric_limits<Exact>::epsilon();
    const solvers::Result<Exact> direct = solvers::solve(
        "taylor",
        solvers::Problem<Exact>{Exact(1), Exact(cell.m), Exact(cell.k), Exact(cell.v0),
                                Exact(static_cast<double>(cell.alpha)), Exact(1) / 2},
        options);
    EXPECT_LT(std::abs(*record.reference[0] - static_cast<double>(*direct.e)),
              1e-15 * static_cast<double>(*direct.e));
    ++judged;
  }
  EXPECT_GT(judged, 0);
}

TEST(External, ABoundClaimNamesAnExternalConfigurationByItsLabel) {
  const std::string claim = "steps_per_contact = [20, 40]\n"
                            "[[claim]]\nname = \"fake e\"\nobservable = \"e\"\nsolver = "
                            "\"fake\"\nsteps_per_contact = 40\nbound = 1e-12\n";
  const Ran ran = run_scene_text(scene_with("good", claim));
  const Budgets budgets = make_budgets(ran.plan, ran.records);
  ASSERT_EQ(budgets.claims.size(), 1u);
  EXPECT_EQ(ran.plan.configs.size(), 2u); // the claim's configuration is one of the sweep's
  // The fake ignores the step (exact at p = 1) and skips p = 1.5: the claim names 8 cells and
  // has a value at 4 only, so it does not hold.
  const Verdict& v = budgets.claims[0];
  EXPECT_FALSE(v.holds);
  EXPECT_EQ(v.cells, 8);
  EXPECT_EQ(v.missing_cells, 4);
  EXPECT_EQ(v.failed_cells, 0);
  EXPECT_LT(v.measured, 1e-15);
  ASSERT_EQ(v.without_value.size(), 4u);
  EXPECT_EQ(v.without_value[0].cell, "p = 1.5, e = 0.3, v0 = 1, m = 1, k = 1");
  EXPECT_EQ(v.without_value[0].why, "skipped: unsupported: p = 1 only");
  EXPECT_EQ(verdict_text(v), "fails (4 of 8 cells without a value)");
  // Allowed, it holds on the cells it has, which is still not the verdict expected.
  const Ran allowed = run_scene_text(scene_with("good", claim + "allow_missing = true\n"));
  const Verdict partial = make_budgets(allowed.plan, allowed.records).claims[0];
  EXPECT_TRUE(partial.holds);
  EXPECT_TRUE(partial.partial());
  EXPECT_TRUE(partial.unexpected());
  EXPECT_EQ(verdict_text(partial), "holds on 4 of 8 cells");
}

TEST(External, AReplicaRunsBesideTheProgramOnEveryProblem) {
  // The fake is exact, so its difference from dem-verlet is dem-verlet's own error, which a
  // dem-verlet configuration of the same steps measures against the truth.
  const Ran ran = run_scene_text(
      scene_with("good",
                 "steps_per_contact = [300]\nonset_phases = 3\nreplica = \"dem-verlet\"\n"
                 "[[solver]]\nname = \"dem-verlet\"\nsteps_per_contact = [300]\n"
                 "onset_phases = 3\n",
                 "", "p = [1]\ne = [0.3, 0.8]\nv0 = [1]\n"));
  ASSERT_EQ(ran.plan.configs.size(), 2u);
  for (const Record& fake : ran.records) {
    if (fake.config != 0) {
      continue;
    }
    const Record& dem = ran.records[fake.cell * 2 + 1];
    ASSERT_EQ(fake.replica_difference.size(), 4u);
    for (std::size_t o = 0; o < 4; ++o) {
      ASSERT_TRUE(fake.replica_difference[o] && dem.rel_error[o]);
      EXPECT_GT(*dem.rel_error[o], 1e-6); // a real difference, not rounding
      EXPECT_NEAR(*fake.replica_difference[o] / *dem.rel_error[o], 1, 0.02) << o;
    }
  }
}

TEST(External, SceneMistakesAreRefusedWithTheirLine) {
  const auto refused = [](const std::string& solver, const std::string& expected) {
    const std::string text =
        "name = \"x\"\n[grid]\np = [1]\ne = [0.5]\nv0 = [1]\n[[solver]]\n" + solver;
    try {
      parse_scene(text, "x.toml");
      ADD_FAILURE() << "accepted: " << solver;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused("command = [\"a\"]\n", "x.toml:6: [[solver]] with a command needs a label");
  refused("command = []\nlabel = \"a\"\n", "command must be a non-empty list of strings");
  refused("command = [\"\"]\nlabel = \"a\"\n", "command must be a non-empty list of strings");
  refused("command = [\"a\"]\nlabel = \"taylor\"\n", "label names a registered solver");
  refused("command = [\"a\"]\nlabel = \"a\\u0001b\"\n", "label must be 1 to 100 printable");
  refused("command = [\"a\"]\nlabel = \"a\"\nprecision = \"quad\"\n",
          "an external solver answers in double (got quad)");
  refused("command = [\"a\"]\nlabel = \"a\"\nrtol = 1e-6\nsteps_per_contact = 20\n",
          "an external solver sweeps one of steps_per_contact, dt and rtol");
  refused("command = [\"a\"]\nlabel = \"a\"\nonset_phases = 4\n",
          "onset_phases needs steps_per_contact or dt");
  refused("command = [\"a\"]\nlabel = \"a\"\ndt = -1\n", "dt must be > 0");
  refused("command = [\"a\"]\nlabel = \"a\"\nname = \"taylor\"\n", "unknown key in [[solver]]");
  refused("command = [\"a\"]\nlabel = \"a\"\nreplica = \"nope\"\n", "unknown solver, expected");
  refused("command = [\"a\"]\nlabel = \"a\"\nsteps_per_contact = 20\nreplica = \"cvode-bdf\"\n",
          "the replica must take what the program is given (steps_per_contact or dt)");
  refused("command = [\"a\"]\nlabel = \"a\"\n[[solver]]\ncommand = [\"b\"]\nlabel = \"a\"\n",
          "another [[solver]] has this label (got a)");
}

TEST(External, ARelativeProgramIsTheScenesFolders) {
  const Scene scene = parse_scene(
      "[grid]\np = [1]\ne = [0.5]\nv0 = [1]\n[[solver]]\ncommand = [\"../adapters/x\", "
      "\"--flag\"]\nlabel = \"x\"\n[[solver]]\ncommand = [\"python3\"]\nlabel = \"y\"\n",
      "data/scenes/s.toml");
  EXPECT_EQ(scene.configs[0].command,
            (std::vector<std::string>{"data/adapters/x", "--flag"}));         // beside the scene
  EXPECT_EQ(scene.configs[1].command, (std::vector<std::string>{"python3"})); // on PATH
}

} // namespace
} // namespace pldamp::harness
