// What an external solver's answers and handshake are held to (run/answers.hpp): the invariants
// of pldamp's own solvers, the settings it says it honours; where its program is found; and the
// α it is sent, which `pldamp calibrate` gives to the last bit.
#include "fake_solver.hpp"
#include "run/answers.hpp"
#include "run/external.hpp"

#include "pldamp/solvers/registry.hpp"

#include <boost/math/constants/constants.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

namespace pldamp::harness {
namespace {

using namespace testing; // the fake adapter's scenes, run, scratch, write_file

// Each impossible answer makes its record unstable, with the invariant it breaks and nothing
// measured kept; the answer's work is kept (the exchange stayed in step).
TEST(ExternalChecks, AnImpossibleAnswerIsUnstableWithItsReason) {
  const std::string grid = "p = [1]\ne = [0.5]\nv0 = [1, 2]\n";
  const std::string with_energy = "\"e\", \"delta_max\", \"t_peak\", \"tau\", \"energy\"";
  struct Case {
    std::string mode, extra, want, reason;
  };
  const std::vector<Case> cases{
      {"above_one", "", "", "impossible answer: energy gained: e = 1.3 (allowed up to 1 + 0.001)"},
      {"negative", "", "", "impossible answer: e = -0.5: negative"},
      {"negative_delta", "", "", "impossible answer: delta_max = -0.1: negative"},
      {"peak", "", "",
       "impossible answer: outcome peak, but the problem wants what comes after the peak (e, tau "
       "or energy_unload)"},
      {"gained", "", with_energy,
       "impossible answer: energy gained: energy_load = -0.1 (m v0^2/2 = 0.5)"},
      {"imbalance", "rtol = [1e-10]\n", with_energy,
       "impossible answer: energy balance off by 0.1"},
      // What no damping allows (answers.cpp): these were accepted as `exited`.
      {"dmax_huge", "", "",
       "impossible answer: energy gained: delta_max = 1e+308 above the undamped peak delta_u = 1 "
       "(allowed up to 1.00100000000022"},
      {"tpeak_zero", "", "",
       "impossible answer: t_peak = 0: not positive (the contact begins at v0 > 0)"},
      {"tpeak_after_tau", "", "", " not after t_peak = "},
      {"tau_tiny", "", "", "impossible answer: tau = 5e-324 not after t_peak = "},
      {"fast_compression", "", "", ": compressed faster than v0 (allowed up to 1 + 0.001 times)"},
      {"fast_return", "", "", ": in and out faster than v0 (allowed down to 1 - 0.001 times)"}};
  for (const Case& c : cases) {
    const std::string scene = c.want.empty() ? scene_with(c.mode, c.extra, "", grid)
                                             : scene_with(c.mode, c.extra, "", grid, c.want);
    const Ran ran = run_scene_text(scene);
    ASSERT_EQ(ran.records.size(), 2u);
    bool reason_seen = false;
    for (const Record& record : ran.records) {
      EXPECT_TRUE(record.failed()) << c.mode;
      EXPECT_EQ(record.outcome_name(), "unstable") << c.mode;
      EXPECT_EQ(record.steps, 1) << c.mode;
      for (const std::optional<double>& value : record.value) {
        EXPECT_FALSE(value.has_value()) << c.mode;
      }
      reason_seen = reason_seen || record.failure.find(c.reason) != std::string::npos;
    }
    EXPECT_TRUE(reason_seen) << c.mode << ": " << ran.records.front().failure;
  }
  // The same answers without the lie pass, energies and balance included, at rtol 1e-12.
  const Ran good = run_scene_text(scene_with("good", "rtol = [1e-12]\n", "", grid, with_energy));
  for (const Record& record : good.records) {
    EXPECT_FALSE(record.failed()) << record.failure;
    for (const std::optional<double>& error : record.rel_error) {
      ASSERT_TRUE(error.has_value());
      EXPECT_LT(*error, 1e-13);
    }
  }
}

// A fixed step's allowance (ωΔt)²/8 with ω² = k p δ_u^(p−1)/m and Δt = π δ_u/(v0 n) is, since
// k δ_u^(p+1) = (p+1) m v0²/2, p (p+1) π² / (16 n²) whatever the scales.
// Whatever a program writes is read within bounds: nesting refused before any tree is built (a
// reply 10^5 arrays deep crashed `pldamp run`, and Python with it), every text it says kept to
// one line of at most max_reply_text characters, each handshake list at most max_reply_items.
TEST(ExternalChecks, WhatAProgramSaysIsReadWithinBounds) {
  const auto nested = [](int depth) {
    return std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']');
  };
  const auto reply = [](const std::string& fields) {
    return R"({"id": 3, "outcome": "exited", )" + fields + "}";
  };
  const auto message_of = [&](const std::string& line) -> std::string {
    try {
      (void)read_reply(line, 3);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "read";
  };
  for (const int depth : {16, 17, 100000}) { // the reply object itself is level 1
    const std::string what = message_of(reply(R"("e": )" + nested(depth)));
    EXPECT_EQ(what.find("nests JSON deeper than 16 levels") != std::string::npos, depth > 15)
        << depth << ": " << what;
    EXPECT_LE(what.size(), 200u) << depth;
  }
  EXPECT_EQ(message_of(reply(R"("e": 0.5)")), "read");
  // A key twice (the last one won: "id" twice answered another problem); a NUL, where nlohmann's
  // parser stopped; an array of 3·10^5 objects, read in linear time (24 s before).
  EXPECT_EQ(message_of(R"({"id": 5, "id": 3, "outcome": "exited"})"),
            R"(the reply names id twice (got '{"id": 5, "id": 3, "outcome": "exited"}'))");
  EXPECT_EQ(
      message_of(reply(R"("e": 0.5)") + std::string(2, '\0')).rfind("the reply is not JSON", 0),
      0u);
  std::string objects;
  for (int i = 0; i < 300000; ++i) {
    objects += i == 0 ? "{}" : ",{}";
  }
  EXPECT_EQ(message_of(reply(R"("x": [)" + objects + "]")), "read");
  // Counts a report can sum over its records in 64 bits (INT64_MAX wrapped a total).
  EXPECT_EQ(message_of(reply(R"("steps": 1e12)")), "read");
  EXPECT_EQ(message_of(reply(R"("steps": 1000000000001)")),
            "the reply's steps must be a whole number up to 1e+12 (got 1000000000001)");
  // A reason of 10^5 characters, with newlines and a two-byte character at every cut: kept as one
  // line of whole characters.
  std::string reason;
  for (int i = 0; i < 50000; ++i) {
    reason += R"(\u00e9\n)"; // JSON's escapes: é and a newline
  }
  try {
    (void)read_reply(R"({"id": 3, "outcome": "error", "reason": ")" + reason + "\"}", 3);
    ADD_FAILURE() << "an error outcome fails its record";
  } catch (const ReportedError& e) {
    const std::string what = e.what();
    EXPECT_LE(what.size(), std::string("the program's error: ").size() + max_reply_text) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
    EXPECT_TRUE(what.ends_with("\xc3\xa9\\n...") || what.ends_with("\\n\xc3\xa9...") ||
                what.ends_with("\\...") || what.ends_with("\\n..."))
        << what.substr(what.size() - 12);
    EXPECT_EQ(one_line(what), what) << "whole UTF-8 characters only";
  }
  // The handshake: nesting, a long name, long lists.
  const std::string hello = R"({"protocol": "pldamp-solver", "version": 1, )";
  const auto handshake_error = [&](const std::string& fields) -> std::string {
    try {
      (void)read_handshake(hello + fields + "}", "[[solver]] x");
    } catch (const ProtocolError& e) {
      return e.what();
    }
    return "read";
  };
  EXPECT_NE(handshake_error(R"("solver": "s", "x": )" + nested(100000))
                .find("[[solver]] x: its handshake nests JSON deeper than 16 levels"),
            std::string::npos);
  EXPECT_EQ(
      read_handshake(hello + R"("solver": ")" + std::string(5000, 's') + "\"}", "x").solver.size(),
      max_reply_text);
  for (const auto& [fields, says] : std::vector<std::pair<std::string, std::string>>{
           {R"("solver": "s", "version": 2)", "[[solver]] x: its handshake names version twice"},
           {R"("solver": "")", "[[solver]] x: its handshake's solver names nothing"},
           {R"("solver": "s", "damping_exponent": 1e10)",
            "[[solver]] x: damping_exponent must be a number in [0, 1000] or \"seed\" (got "
            "'10000000000.0')"},
           {R"("solver": "s", "p": [])", "[[solver]] x: its handshake's p is an empty list"},
           {R"("solver": "s", "ends": [])", "[[solver]] x: its handshake's ends is an empty list"},
           {R"("solver": "s", "honours": ["dt", "speed"])",
            "[[solver]] x: unknown setting in its handshake's honours, expected "
            "steps_per_contact|dt|onset_phase|rtol|atol|options.KEY (got 'speed')"}}) {
    EXPECT_EQ(handshake_error(fields).rfind(says, 0), 0u) << handshake_error(fields);
  }
  std::string many = "[1";
  for (std::size_t i = 1; i <= max_reply_items; ++i) {
    many += ", 1";
  }
  EXPECT_EQ(handshake_error(R"("solver": "s", "p": )" + many + "]"),
            "[[solver]] x: its handshake's p lists 1001 items, more than 1000");
  std::string settings = R"(["dt")";
  for (std::size_t i = 1; i <= max_reply_items; ++i) {
    settings += R"(, "dt")";
  }
  EXPECT_EQ(handshake_error(R"("solver": "s", "honours": )" + settings + "]"),
            "[[solver]] x: its handshake's honours lists 1001 items, more than 1000");
}

TEST(ExternalChecks, TheAllowanceIsPldampsOwnAndScaleFree) {
  const double pi = boost::math::constants::pi<double>();
  SolverConfig fixed;
  fixed.command = {"x"};
  for (const double p : {1.0, 1.5, 2.5}) {
    for (const int n : {2, 20, 50}) {
      fixed.steps_per_contact = n;
      const double expected = std::min(p * (p + 1) * pi * pi / (16.0 * n * n), 0.25);
      const solvers::Problem<double> problem{p, 2, 3, 0.5, 0.4};
      EXPECT_NEAR(answer_allowance(fixed, problem), expected, 1e-14 * expected) << p << " " << n;
    }
  }
  const solvers::Problem<double> unit{1.5, 1, 1, 1, 0.4};
  const double eps = 1000 * std::numeric_limits<double>::epsilon();
  SolverConfig controlled;
  controlled.command = {"x"};
  EXPECT_DOUBLE_EQ(answer_allowance(controlled, unit), 1e-3 + eps); // its default: rtol 1e-6
  controlled.rtol = 1e-12;
  EXPECT_DOUBLE_EQ(answer_allowance(controlled, unit), 1e-8 + eps);
  controlled.atol = 1e-6; // over ½ m v0² = 0.5: 2e-6, √ of it the smaller
  EXPECT_DOUBLE_EQ(answer_allowance(controlled, unit), std::sqrt(2e-6) + eps);
  // At the edge: e within the allowance is possible, beyond it energy was gained.
  fixed.steps_per_contact = 20;
  const double allowance = answer_allowance(fixed, unit);
  solvers::Result<double> answer;
  answer.outcome = solvers::Outcome::exited;
  solvers::Options<double> options;
  options.want = solvers::want_e;
  answer.e = 1 + 0.99 * allowance;
  EXPECT_EQ(impossible_answer(answer, fixed, unit, options), "");
  answer.e = 1 + 1.01 * allowance;
  EXPECT_EQ(impossible_answer(answer, fixed, unit, options).substr(0, 18), "energy gained: e =");
  // peak answers a problem that wants peak quantities only; no_exit is e = 0; exited is finite.
  answer = {};
  answer.outcome = solvers::Outcome::peak;
  answer.delta_max = 1;
  options.want = solvers::want_delta_max | solvers::want_t_peak;
  EXPECT_EQ(impossible_answer(answer, fixed, unit, options), "");
  answer.outcome = solvers::Outcome::no_exit;
  answer.e = 0.1;
  EXPECT_EQ(impossible_answer(answer, fixed, unit, options),
            "no_exit with e = 0.1 (no return is e = 0)");
  answer.outcome = solvers::Outcome::exited;
  answer.e.reset();
  answer.tau = std::numeric_limits<double>::infinity();
  EXPECT_EQ(impossible_answer(answer, fixed, unit, options), "exited with tau = inf");
}

// What no damping ≥ 0 allows (answers.cpp derives each bound), at a fixed step and under error
// control: each bound refuses an answer just beyond it and takes an honest coarse one just within
// it. Off the unit scales: m = 2, k = 3, v0 = 0.5, p = 1.5.
TEST(ExternalChecks, NoDampingAllowsWhatTheUndampedContactCannotDo) {
  const solvers::Problem<double> problem{1.5, 2, 3, 0.5, 0.4};
  const double v0 = problem.v0;
  // k δ_u^(p+1)/(p+1) = m v0²/2.
  const double delta_u =
      std::pow((problem.p + 1) * problem.m * v0 * v0 / (2 * problem.k), 1 / (problem.p + 1));
  SolverConfig fixed;
  fixed.command = {"x"};
  fixed.steps_per_contact = 20;
  SolverConfig controlled;
  controlled.command = {"x"};
  controlled.rtol = 1e-6;
  const double dt = boost::math::constants::pi<double>() * delta_u / v0 / 20;
  solvers::Options<double> overlap_end;
  solvers::Options<double> force_end;
  force_end.end = solvers::End::force;
  const auto verdict = [&](const SolverConfig& config, std::optional<double> delta_max,
                           std::optional<double> t_peak, std::optional<double> tau,
                           const solvers::Options<double>& options) {
    solvers::Result<double> answer;
    answer.outcome = solvers::Outcome::exited;
    answer.delta_max = delta_max;
    answer.t_peak = t_peak;
    answer.tau = tau;
    return impossible_answer(answer, config, problem, options);
  };
  const auto starts = [](const std::string& text, const std::string& prefix) {
    return text.rfind(prefix, 0) == 0;
  };
  for (const SolverConfig* config : {&fixed, &controlled}) {
    const double a = answer_allowance(*config, problem);
    const bool stepped = config == &fixed;
    SCOPED_TRACE(stepped ? "fixed step" : "error control");
    EXPECT_NEAR(a,
                stepped ? std::min(1.5 * 2.5 * std::pow(boost::math::constants::pi<double>(), 2) /
                                       (16.0 * 20 * 20),
                                   0.25)
                        : 1e-3 + 1000 * std::numeric_limits<double>::epsilon(),
                1e-15);
    // 0 < δ_max ≤ (1 + a)(δ_u + v0 Δt): the undamped peak, a step's onset beyond it.
    const double most = (1 + a) * (delta_u + (stepped ? v0 * dt : 0));
    EXPECT_EQ(verdict(*config, 0.0, {}, {}, overlap_end),
              "delta_max = 0: not positive (the contact begins at v0 > 0)");
    EXPECT_EQ(verdict(*config, 1e-300, {}, {}, overlap_end), "");
    EXPECT_TRUE(starts(verdict(*config, most * (1 + 1e-9), {}, {}, overlap_end),
                       "energy gained: delta_max = "))
        << verdict(*config, most * (1 + 1e-9), {}, {}, overlap_end);
    EXPECT_EQ(verdict(*config, most * (1 - 1e-9), {}, {}, overlap_end), "");
    EXPECT_TRUE(starts(verdict(*config, 1e308, {}, {}, force_end),
                       "energy gained: delta_max = 1e+308 above the undamped peak delta_u = "));
    // t_peak > 0, and δ_max ≤ v0 t_peak (1 + a).
    EXPECT_EQ(verdict(*config, {}, 0.0, {}, overlap_end),
              "t_peak = 0: not positive (the contact begins at v0 > 0)");
    const double fastest = delta_u / (v0 * (1 + a)); // the shortest t_peak of δ_max = δ_u
    EXPECT_TRUE(starts(verdict(*config, delta_u, fastest * (1 - 1e-9), {}, overlap_end),
                       "delta_max = " + to_string_full(delta_u) + " above v0 t_peak = "));
    EXPECT_NE(verdict(*config, delta_u, fastest * (1 - 1e-9), {}, force_end), "");
    EXPECT_EQ(verdict(*config, delta_u, fastest * (1 + 1e-9), {}, overlap_end), "");
    // The force peaks at or before the overlap, within the contact; its peak is finite.
    {
      solvers::Result<double> answer;
      answer.outcome = solvers::Outcome::exited;
      answer.t_peak = 1.5;
      answer.tau = 3.2;
      answer.t_normal_force_max = 1e6;
      EXPECT_TRUE(starts(impossible_answer(answer, *config, problem, overlap_end),
                         "t_normal_force_max = 1e+06 after t_peak = 1.5"));
      answer.t_peak.reset();
      EXPECT_EQ(impossible_answer(answer, *config, problem, overlap_end),
                "t_normal_force_max = 1e+06 not before tau = 3.2");
      answer.t_normal_force_max = 1.5;
      EXPECT_EQ(impossible_answer(answer, *config, problem, overlap_end), "");
      answer.normal_force_max = std::numeric_limits<double>::infinity();
      EXPECT_EQ(impossible_answer(answer, *config, problem, overlap_end),
                "normal_force_max = inf: not finite");
    }
    // τ > t_peak (at either end), and τ > 0.
    EXPECT_EQ(verdict(*config, {}, 1.5, 1.5, force_end),
              "tau = 1.5 not after t_peak = 1.5: a contact ends after its peak");
    EXPECT_EQ(verdict(*config, {}, 1.5, 5e-324, overlap_end),
              "tau = 5e-324 not after t_peak = 1.5: a contact ends after its peak");
    EXPECT_EQ(verdict(*config, {}, 1.5, std::nextafter(1.5, 2.0), overlap_end), "");
    EXPECT_EQ(verdict(*config, {}, {}, 0.0, overlap_end),
              "tau = 0: not positive (the contact begins at v0 > 0)");
    // At the overlap end τ ≥ 2 δ_max/v0 (1 − a); the force end's cut may come sooner.
    const double shortest = 2 * delta_u / v0 * (1 - a);
    EXPECT_TRUE(starts(verdict(*config, delta_u, {}, shortest * (1 - 1e-9), overlap_end), "tau = "))
        << verdict(*config, delta_u, {}, shortest * (1 - 1e-9), overlap_end);
    EXPECT_NE(verdict(*config, delta_u, {}, shortest * (1 - 1e-9), overlap_end)
                  .find(" below 2 delta_max/v0 = " + to_string_full(2 * delta_u / v0) +
                        ": in and out faster than v0"),
              std::string::npos);
    EXPECT_EQ(verdict(*config, delta_u, {}, shortest * (1 + 1e-9), overlap_end), "");
    EXPECT_EQ(verdict(*config, delta_u, {}, 0.5 * shortest, force_end), "");
    // With t_peak given too, and a no_exit's infinite τ, which bounds nothing.
    EXPECT_NE(verdict(*config, delta_u, fastest * 1.01, shortest * (1 - 1e-9), overlap_end), "");
    EXPECT_EQ(verdict(*config, delta_u, fastest * 1.01, shortest * (1 + 1e-9), overlap_end), "");
    solvers::Result<double> no_exit;
    no_exit.outcome = solvers::Outcome::no_exit;
    no_exit.delta_max = delta_u;
    no_exit.t_peak = fastest * 1.01;
    no_exit.tau = std::numeric_limits<double>::infinity();
    EXPECT_EQ(impossible_answer(no_exit, *config, problem, overlap_end), "");
  }
}

// pldamp's own solvers, run as a program would be (each fixed-step scheme at 2 to 50 steps per
// contact and onset phases up to a step, each error-controlled one at rtol 1e-2 to 1e-12, p from
// 1 to 30, undamped to overdamped, both ends), never give an answer the checks call impossible:
// the allowances are honest for coarse schemes. (δ_max (1 + a) alone refused dem-verlet at 4
// steps per contact, answers.cpp.)
TEST(ExternalChecks, PldampsOwnSolversNeverGiveAnImpossibleAnswer) {
  long judged = 0;
  for (const solvers::SolverInfo& info : solvers::registry()) {
    if (!info.runs_in("double")) {
      continue;
    }
    for (const double p : {1.0, 1.5, 3.0, 30.0}) {
      for (const double alpha : {0.0, 0.3, 1.5, 4.0}) {
        const solvers::Problem<double> problem{p, 2, 3, 0.5, alpha};
        for (const solvers::End end : {solvers::End::overlap, solvers::End::force}) {
          const auto judge = [&](const SolverConfig& config, solvers::Options<double> options) {
            options.end = end;
            if (info.fixed_step || options.fixed_step) {
              // A coarse fixed step's dashpot work can come out negative, and pldamp's own schemes
              // are not held to its sign (Shards.ARecordAsItsOwnSolverWroteItIsMerged).
              options.want &= ~solvers::want_energy;
            }
            const solvers::Result<double> answer = solvers::solve(info.name, problem, options);
            if (answer.outcome == solvers::Outcome::unstable) {
              return; // its own invariant refused it: not an answer
            }
            EXPECT_EQ(impossible_answer(answer, config, problem, options), "")
                << info.name << " p = " << p << " alpha = " << alpha
                << " steps = " << config.steps_per_contact.value_or(0)
                << " rtol = " << config.rtol.value_or(0) << " phase = " << options.onset_phase;
            ++judged;
          };
          for (const int steps : {2, 3, 4, 6, 10, 50}) {
            SolverConfig config;
            config.command = {"x"};
            solvers::Options<double> options;
            if (info.fixed_step) {
              config.steps_per_contact = steps;
              options.steps_per_contact = steps;
              for (const double phase : {0.0, 0.5, 0.9999}) {
                options.onset_phase = phase;
                judge(config, options);
              }
            } else if (info.takes_fixed_step) {
              config.steps_per_contact = steps;
              config.dt = step_of(config, problem); // sent as dt, as a program is
              config.steps_per_contact.reset();
              options.fixed_step = config.dt;
              judge(config, options);
            }
          }
          if (!info.fixed_step) {
            for (const double rtol : {1e-2, 1e-4, 1e-8, 1e-12}) {
              SolverConfig config;
              config.command = {"x"};
              config.rtol = rtol;
              solvers::Options<double> options;
              options.rtol = rtol;
              judge(config, options);
            }
          }
        }
      }
    }
  }
  EXPECT_GT(judged, 2000);
}

TEST(ExternalChecks, ASettingTheProgramDoesNotHonourIsRefusedBeforeAnyWork) {
  const std::string declared = "(its handshake honours steps_per_contact, onset_phase)";
  const std::vector<std::pair<std::string, std::string>> refused{
      {"rtol = [1e-6]\n", "sets rtol, which its program does not honour " + declared},
      {"dt = [0.01]\n", "sets dt, which its program does not honour"},
      {"steps_per_contact = [20]\natol = 1e-9\n", "sets atol, which"},
      {"steps_per_contact = [20]\noptions = { seed = 7, newton_off = true }\n",
       "sets options.newton_off, options.seed, which its program does not honour"}};
  for (const auto& [settings, message] : refused) {
    try {
      run_scene_text(scene_with("honours", settings));
      ADD_FAILURE() << "accepted: " << settings;
    } catch (const ProtocolError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  // What it honours runs, and the report says what it declared.
  const Ran ran =
      run_scene_text(scene_with("honours", "steps_per_contact = [20]\nonset_phases = 2\n"));
  long judged = 0;
  for (const Record& record : ran.records) {
    EXPECT_FALSE(record.failed()) << record.failure;
    judged += record.rel_error[0] ? 1 : 0;
  }
  EXPECT_EQ(judged, 4); // p = 1; p = 1.5 skipped
  const std::string path = write_file("honours.toml", scene_with("honours", "rtol = [1e-6]\n"));
  const fs::path out = scratch() / "honours";
  const auto refused_run = run({"run", path, "--out", out.string()});
  EXPECT_EQ(refused_run.code, 2);
  EXPECT_NE(refused_run.err.find("error: [[solver]] fake"), std::string::npos) << refused_run.err;
  EXPECT_FALSE(fs::exists(out / "report.json"));
  const auto ran_cli =
      run({"run", write_file("honoured.toml", scene_with("honours", "steps_per_contact = [20]\n")),
           "--out", out.string()});
  ASSERT_EQ(ran_cli.code, 0) << ran_cli.err;
  std::ifstream md(out / "report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("fake honours; honours steps_per_contact, onset_phase"), std::string::npos);
  // The step is sent as dt too: a program that honours dt honours steps_per_contact.
  SolverConfig stepped;
  stepped.steps_per_contact = 20;
  EXPECT_TRUE(settings_not_honoured(stepped, {"dt"}).empty());
  EXPECT_EQ(settings_not_honoured(stepped, {}), std::vector<std::string>{"steps_per_contact"});
}

// Changes the working directory for a scope.
class InFolder {
public:
  explicit InFolder(const fs::path& folder) : previous_(fs::current_path()) {
    fs::current_path(folder);
  }
  InFolder(const InFolder&) = delete;
  InFolder& operator=(const InFolder&) = delete;
  ~InFolder() { fs::current_path(previous_); }

private:
  fs::path previous_;
};

TEST(ExternalChecks, AProgramBesideTheSceneStartsAsTyped) {
  const fs::path folder = scratch() / "beside";
  fs::create_directories(folder);
  const fs::path program = folder / "adapter";
  std::ofstream(program) << "#!/bin/sh\nexec python3 " PLDAMP_TEST_ADAPTERS
                            "/fake_adapter.py good\n";
  ::chmod(program.c_str(), 0755);
  const auto scene = [](const std::string& command) {
    return "name = \"beside\"\nwant = [\"e\"]\n[grid]\np = [1]\ne = [0.5]\nv0 = [1]\n"
           "[[solver]]\ncommand = [\"" +
           command + "\"]\nlabel = \"beside\"\n";
  };
  const auto judged = [](const Scene& s) {
    RunTotals totals;
    const std::vector<Record> records = run_plan(make_plan(s), 1, totals);
    return records.size() == 1 && !records[0].failed() && records[0].rel_error[0].has_value();
  };
  // A bare name beside the scene is that file, wherever pldamp runs.
  const Scene bare = parse_scene(scene("adapter"), (folder / "s.toml").string());
  EXPECT_EQ(bare.configs[0].command[0], program.string());
  EXPECT_EQ(bare.configs[0].program, "adapter");
  EXPECT_TRUE(judged(bare));
  {
    // "./adapter" and "adapter" with the scene in the working directory (no folder in its path).
    const InFolder in(folder);
    for (const std::string typed : {"./adapter", "adapter"}) {
      const Scene here = parse_scene(scene(typed), "s.toml");
      EXPECT_EQ(here.configs[0].command[0], "./adapter");
      EXPECT_TRUE(judged(here)) << typed;
    }
    std::ofstream("s.toml") << scene("./adapter");
    const auto cli = run({"run", "s.toml", "--out", "report"});
    EXPECT_EQ(cli.code, 0) << cli.err;
    try {
      judged(parse_scene(scene("./missing"), "s.toml"));
      ADD_FAILURE() << "a missing program was started";
    } catch (const ProtocolError& e) {
      EXPECT_NE(std::string(e.what()).find(
                    "[[solver]] beside: cannot start ./missing (not found or not executable)"),
                std::string::npos)
          << e.what();
    }
  }
  // A bare name with no such file beside the scene is looked up on PATH.
  EXPECT_EQ(parse_scene(scene("python3"), (folder / "s.toml").string()).configs[0].command[0],
            "python3");
  try {
    judged(parse_scene(scene("no-such-program-anywhere"), (folder / "s.toml").string()));
    ADD_FAILURE() << "a missing program was started";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot start no-such-program-anywhere (not beside the "
                                         "scene nor on PATH, or not executable)"),
              std::string::npos)
        << e.what();
  }
}

// `pldamp calibrate --json` α, parsed.
double calibrated(const std::string& p, const std::string& e, const std::string& end) {
  const auto r = run({"calibrate", "--p", p, "--e", e, "--end", end, "--json"});
  EXPECT_EQ(r.code, 0) << r.err;
  return nlohmann::json::parse(r.out).at("alpha").get<double>();
}

// `pldamp calibrate --precision PRECISION` α, its digits as printed.
std::string calibrated_digits(const std::string& p, const std::string& e, const std::string& end,
                              const std::string& precision) {
  const auto r = run({"calibrate", "--p", p, "--e", e, "--end", end, "--precision", precision});
  std::istringstream lines(r.out);
  for (std::string key, value; lines >> key >> value;) {
    if (key == "alpha") {
      return value;
    }
  }
  ADD_FAILURE() << r.out << r.err;
  return "";
}

std::string hex(double x) {
  std::ostringstream out;
  out << std::hexfloat << x;
  return out.str();
}

// The α of a (p, e) is the same double in `calibrate`, in a double solver's record, in the problem
// line an external program reads and in the record of that program (1 or 2 ulp apart before: the
// plan calibrated in float128, `calibrate` in the precision asked).
TEST(ExternalChecks, CalibrateAndRunSendTheSameAlphaToTheLastBit) {
  for (const std::string end : {"overlap", "force"}) {
    const std::string log = (scratch() / ("alpha-" + end + ".jsonl")).string();
    fs::remove(log);
    const std::string text =
        "name = \"alpha\"\nend = \"" + end +
        "\"\nwant = [\"e\"]\n[grid]\np = [1, 1.5, 2.5]\n"
        "e = [0.3, 0.9, 0.1, 0.7]\nv0 = [1, 3]\n" +
        fake_solver("record", log) +
        "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-6\n"
        "[[solver]]\nname = \"taylor\"\nprecision = \"long\"\nrtol = 1e-10\n" +
        (PLDAMP_WITH_QUAD ? "[[solver]]\nname = \"taylor\"\nprecision = \"quad\"\nrtol = 1e-12\n"
                          : "");
    const fs::path out = scratch() / ("alpha-" + end);
    const auto r = run({"run", write_file("alpha.toml", text), "--out", out.string()});
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream file(out / "report.json");
    const nlohmann::json report = nlohmann::json::parse(file);
    std::map<std::pair<double, double>, double> expected;
    long checked = 0;
    for (const nlohmann::json& record : report["records"]) {
      const double p = record["p"];
      const std::string label = record["damping"];
      const std::string e = label.substr(2); // "e=0.3"
      const std::string ptext = to_string_full(p);
      const std::string precision = record["precision"];
      if (precision == "double") {
        const double alpha = calibrated(ptext, e, end);
        EXPECT_EQ(hex(record["alpha"].get<double>()), hex(alpha)) << record["key"];
        expected[{p, std::stod(e)}] = alpha;
      } else {
        // A scene's numbers are doubles: the same inputs, typed for a wider precision, are their
        // exact decimals (0.3 is 0.2999999999999999888977697537484345957636833190917969).
        const std::string exact_e = fmt::format("{:.70g}", std::stod(e));
        EXPECT_EQ(record["alpha_digits"], calibrated_digits(ptext, exact_e, end, precision))
            << record["key"];
      }
      ++checked;
    }
    EXPECT_EQ(checked, 3 * 4 * 2 * (PLDAMP_WITH_QUAD ? 4 : 3));
    // The problem lines the program read: the same doubles, at every v0.
    std::ifstream problems(log);
    long sent = 0;
    for (std::string line; std::getline(problems, line); ++sent) {
      const nlohmann::json problem = nlohmann::json::parse(line);
      // The fake answers p = 1 only, but every p is sent (its handshake declares none).
      bool found = false;
      for (const auto& [key, alpha] : expected) {
        if (key.first == problem["p"].get<double>() &&
            hex(alpha) == hex(problem["alpha"].get<double>())) {
          found = true;
        }
      }
      EXPECT_TRUE(found) << line;
    }
    EXPECT_EQ(sent, 3 * 4 * 2);
  }
}

} // namespace
} // namespace pldamp::harness
