// solve_batch (registry.hpp; dem_batch.cpp): every lane's Result bit for bit the scalar solver's
// for the same problem, over cells that end every way a contact can end, lanes of one batch
// ending at different steps.
#include "every_solver.hpp"

#include "pldamp/solvers/contact_ode.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

namespace pldamp::solvers::testing {
namespace {

// Every solver with a batch path: the DEM schemes and verlet-predicted.
const std::vector<std::string> batched_schemes{"dem-verlet", "dem-symplectic-euler", "dem-leapfrog",
                                               "verlet-predicted"};

// The bits of a value (NaN and −0 told apart from anything else), or a marker for none.
std::string bits(const std::optional<double>& x) {
  return x ? std::to_string(std::bit_cast<std::uint64_t>(*x)) : "none";
}

// Every field but wall_seconds, bit for bit; the first difference, or empty.
std::string difference(const Result<double>& batch, const Result<double>& scalar) {
  auto field = [](const char* name, const std::optional<double>& a,
                  const std::optional<double>& b) -> std::string {
    return bits(a) == bits(b) ? std::string()
                              : std::string(name) + " " + to_string_full(a.value_or(-1)) + " vs " +
                                    to_string_full(b.value_or(-1));
  };
  if (batch.outcome != scalar.outcome) {
    return "outcome " + std::string(outcome_name(batch.outcome)) + " vs " +
           std::string(outcome_name(scalar.outcome));
  }
  for (const std::string& d :
       {field("e", batch.e, scalar.e), field("delta_max", batch.delta_max, scalar.delta_max),
        field("t_peak", batch.t_peak, scalar.t_peak), field("tau", batch.tau, scalar.tau),
        field("energy_load", batch.energy_load, scalar.energy_load),
        field("energy_unload", batch.energy_unload, scalar.energy_unload),
        field("normal_force_max", batch.normal_force_max, scalar.normal_force_max),
        field("t_normal_force_max", batch.t_normal_force_max, scalar.t_normal_force_max),
        field("fixed_step", batch.fixed_step, scalar.fixed_step),
        field("horizon", batch.horizon, scalar.horizon),
        field("tau_crossing", batch.tau_crossing, scalar.tau_crossing)}) {
    if (!d.empty()) {
      return d;
    }
  }
  if (batch.invariant != scalar.invariant) {
    return "invariant '" + batch.invariant + "' vs '" + scalar.invariant + "'";
  }
  if (batch.steps_in_contact != scalar.steps_in_contact) {
    return "steps_in_contact " + std::to_string(batch.steps_in_contact.value_or(-1)) + " vs " +
           std::to_string(scalar.steps_in_contact.value_or(-1));
  }
  if (batch.steps != scalar.steps || batch.rhs_evals != scalar.rhs_evals ||
      batch.jacobian_evals != scalar.jacobian_evals) {
    return "steps " + std::to_string(batch.steps) + " vs " + std::to_string(scalar.steps) +
           ", rhs " + std::to_string(batch.rhs_evals) + " vs " + std::to_string(scalar.rhs_evals);
  }
  if (batch.events.size() != scalar.events.size() ||
      batch.samples.size() != scalar.samples.size()) {
    return "events or samples";
  }
  for (std::size_t i = 0; i < batch.events.size(); ++i) {
    if (batch.events[i].kind != scalar.events[i].kind ||
        bits(batch.events[i].t) != bits(scalar.events[i].t)) {
      return "event " + std::to_string(i);
    }
  }
  for (std::size_t i = 0; i < batch.samples.size(); ++i) {
    const Sample<double>& a = batch.samples[i];
    const Sample<double>& b = scalar.samples[i];
    if (bits(a.t) != bits(b.t) || bits(a.delta) != bits(b.delta) || bits(a.v) != bits(b.v)) {
      return "sample " + std::to_string(i);
    }
  }
  return {};
}

struct Lanes {
  std::vector<Problem<double>> problems;
  std::vector<Options<double>> options;
  std::vector<std::string> names;
  void add(const Problem<double>& problem, const Options<double>& o, const std::string& name) {
    problems.push_back(problem);
    options.push_back(o);
    names.push_back(name);
  }
};

// Runs the lanes as one batch and each alone; returns the outcomes seen.
std::vector<Outcome> expect_bit_identical(const std::string& scheme, const Lanes& lanes) {
  const std::vector<Result<double>> batch = solve_batch(scheme, lanes.problems, lanes.options);
  EXPECT_EQ(batch.size(), lanes.problems.size());
  std::vector<Outcome> outcomes;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const Result<double> scalar = solve(scheme, lanes.problems[i], lanes.options[i]);
    EXPECT_EQ(difference(batch[i], scalar), "")
        << scheme << " lane " << i << ": " << lanes.names[i];
    EXPECT_GE(batch[i].wall_seconds, 0);
    outcomes.push_back(scalar.outcome);
  }
  return outcomes;
}

// One batch per (scheme, p, β): the onset phases k/8 of several cells (e, v0, m, k, steps, end,
// observables) of that p, so that lanes end at different steps and in different ways.
TEST(Batch, EveryLaneIsTheScalarSolveBitForBit) {
  struct Exponents {
    double p;
    std::optional<double> beta;
  };
  const std::vector<Exponents> exponents{{1.0, {}}, {1.5, {}},  {2.0, {}},  {3.0, {}},
                                         {2.5, {}}, {1.5, 0.5}, {1.0, 0.5}, {2.0, 0.0}};
  std::vector<Outcome> seen;
  std::size_t lanes_run = 0;
  for (const std::string& scheme : batched_schemes) {
    for (const Exponents& x : exponents) {
      Lanes lanes;
      for (const double e : {0.95, 0.5, 0.05}) {
        for (const End end : {End::overlap, End::force}) {
          for (const unsigned want : {unsigned(want_all), unsigned(want_delta_max | want_t_peak),
                                      unsigned(want_e | want_tau)}) {
            for (int phase = 0; phase < 8; ++phase) {
              const int steps = 10 + 17 * phase; // lanes ending at different steps
              const auto c = Contact<double>::from_e(x.p, e, 1.0 + 0.25 * phase);
              Problem<double> q = problem_of(c);
              q.m = 1 +
                    0.37 * (phase % 3); // not powers of 2: a product in another order rounds apart
              q.k = 1.7 / (1 + phase % 2);
              q.damping_exponent = x.beta;
              Options<double> o;
              o.end = end;
              o.want = want;
              o.steps_per_contact = steps;
              o.onset_phase = phase / 8.0;
              lanes.add(q, o,
                        "p=" + std::to_string(x.p) + " e=" + std::to_string(e) +
                            " steps=" + std::to_string(steps) + " phase=" + std::to_string(phase));
            }
          }
        }
      }
      // A lane cut by its step limit, one stepped far beyond stability, an overdamped one (no
      // exit by the horizon), a critical-ish one with a short horizon.
      const auto c = Contact<double>::from_e(x.p, 0.5, 1.0);
      Options<double> o;
      o.max_steps = 7;
      lanes.add(problem_of(c), o, "step limit");
      o = {};
      o.fixed_step = 40 * ContactOde<double>(problem_of(c)).time_scale();
      o.onset_phase = 0.3;
      lanes.add(problem_of(c), o, "dt beyond stability");
      o = {};
      o.steps_per_contact = 3;
      lanes.add(problem_of(c), o, "three steps per contact");
      Problem<double> over = problem_of(c);
      over.alpha *= 40;
      o = {};
      o.horizon = 30 * ContactOde<double>(over).time_scale();
      lanes.add(over, o, "overdamped");
      Problem<double> settling = problem_of(c);
      settling.alpha *= 6; // α_eff ≈ 1.3 at p = 1: overdamped, and stable at 50 steps per contact
      o = {};
      o.onset_phase = 0.6;
      lanes.add(settling, o, "overdamped, default horizon (verlet-predicted: settled at p = 1)");
      for (Problem<double>& q : lanes.problems) {
        q.damping_exponent = x.beta;
      }
      const std::vector<Outcome> outcomes = expect_bit_identical(scheme, lanes);
      seen.insert(seen.end(), outcomes.begin(), outcomes.end());
      lanes_run += outcomes.size();
    }
  }
  // The cells above end every way a fixed step can end (a test that saw only exits would not
  // show the masking of lanes that stop early).
  for (const Outcome outcome :
       {Outcome::exited, Outcome::peak, Outcome::no_exit, Outcome::step_limit, Outcome::unstable}) {
    EXPECT_NE(std::find(seen.begin(), seen.end(), outcome), seen.end())
        << "no lane ended " << outcome_name(outcome);
  }
  EXPECT_EQ(lanes_run, batched_schemes.size() * exponents.size() * (3 * 2 * 3 * 8 + 5));
}

TEST(Batch, LanesOfOtherExponentsOrWithSamplesAreSolvedAlone) {
  // Mixed p, a lane with sample times: each still its scalar solve.
  Lanes lanes;
  for (const double p : {1.5, 2.0, 1.5, 3.0}) {
    Options<double> o;
    o.onset_phase = 0.25;
    lanes.add(problem_of(Contact<double>::from_e(p, 0.4, 1.0)), o, "p=" + std::to_string(p));
  }
  Options<double> sampled;
  sampled.sample_times = {0.1, 0.5, 1.0};
  lanes.add(problem_of(Contact<double>::from_e(1.5, 0.4, 1.0)), sampled, "samples");
  for (const std::string& scheme : batched_schemes) {
    expect_bit_identical(scheme, lanes);
  }
  const std::vector<Result<double>> with_samples =
      solve_batch("dem-verlet", lanes.problems, lanes.options);
  EXPECT_EQ(with_samples.back().samples.size(), 3u);
}

TEST(Batch, OtherSolversAreSolvedOneByOne) {
  EXPECT_TRUE(solver_named("dem-leapfrog").batched);
  EXPECT_TRUE(solver_named("verlet-predicted").batched);
  EXPECT_FALSE(solver_named("cvode-bdf").batched);
  Lanes lanes;
  for (const double e : {0.9, 0.5, 0.1}) {
    lanes.add(problem_of(Contact<double>::from_e(2.0, e, 1.0)), {}, "e=" + std::to_string(e));
  }
  expect_bit_identical("cvode-bdf", lanes);
}

TEST(Batch, RefusesWhatSolveRefuses) {
  const Problem<double> q = problem_of(Contact<double>::from_e(1.5, 0.5, 1.0));
  Options<double> bad;
  bad.onset_phase = 1.5;
  const std::vector<Problem<double>> problems{q, q};
  EXPECT_THROW(solve_batch("dem-verlet", problems, std::vector<Options<double>>{{}, bad}),
               std::invalid_argument);
  EXPECT_THROW(solve_batch("dem-verlet", problems, std::vector<Options<double>>{{}}),
               std::invalid_argument);
  EXPECT_THROW(solve_batch("no-such-solver", problems, std::vector<Options<double>>{{}, {}}),
               std::invalid_argument);
}

} // namespace
} // namespace pldamp::solvers::testing
