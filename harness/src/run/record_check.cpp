#include "run/record_check.hpp"

#include "common/observables.hpp"
#include "common/record_consistency.hpp"
#include "run/answers.hpp"
#include "run/external.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>
#include <vector>

namespace pldamp::harness {
namespace {

using RecordValues = std::vector<std::optional<double>>;

// Observable `o`'s numbers in `r`.
ObservedNumbers numbers_of(const Plan& plan, const Record& r, std::size_t o) {
  return {.key = plan.observables[o]->key,
          .value = r.value[o],
          .reference = r.reference[o],
          .error = r.error[o],
          .rel_error = r.rel_error[o],
          .spread = r.spread[o],
          .replica_difference =
              r.replica_difference.empty() ? std::nullopt : r.replica_difference[o]};
}

// Why observable `o`'s numbers (`numbers`) cannot be its run's; empty when they can: as any
// record's (common/record_consistency.hpp), and beside that what the plan tells of them.
std::string impossible_numbers(const Record& r, std::size_t o, const ObservedNumbers& numbers,
                               const std::optional<Exact>& truth, bool external, double allowance) {
  const std::string_view key = numbers.key;
  const std::optional<double>&value = numbers.value, &reference = numbers.reference,
        &error = numbers.error, &abs_error = r.abs_error[o];
  // The truth: the plan's to the bit, where the plan is the record's truth (not a code's own β).
  if (r.note.empty() && reference &&
      (!truth || !(static_cast<double>(*truth) == *reference ||
                   (std::isnan(static_cast<double>(*truth)) && std::isnan(*reference))))) {
    return fmt::format("{}'s reference {} is not the plan's ({})", key, to_string_full(*reference),
                       truth ? to_string_full(static_cast<double>(*truth)) : std::string("none"));
  }
  if (std::string why = inconsistent_numbers(
          numbers, {.outcome = r.outcome_name(), .several_phases = r.phases > 1});
      !why.empty()) {
    return why;
  }
  // The ranges the run held pldamp's own solvers to beyond a size's sign, as
  // BasicCollision::violated_invariant does, which bounds e alone (a coarse fixed step's dashpot
  // work can come out negative). An external program's values are held as its answers were, by
  // impossible_external_values.
  if (value && !external && key == "e" && *value > 1 + allowance) {
    return fmt::format("e = {} gains energy (allowed up to 1 + {:.3g})", to_string_full(*value),
                       allowance);
  }
  // |error|, which only a record in memory holds (report.json writes none).
  if (abs_error.has_value() != error.has_value() || (abs_error && *abs_error != std::abs(*error))) {
    return fmt::format("{}'s abs_error {} is not |error| = {}", key,
                       abs_error ? to_string_full(*abs_error) : std::string("none"),
                       error ? to_string_full(std::abs(*error)) : std::string("none"));
  }
  return {};
}

// The observables an external program answers, as the fields of its answer.
constexpr std::pair<std::string_view, std::optional<double> solvers::Result<double>::*>
    answer_fields[] = {{"e", &solvers::Result<double>::e},
                       {"delta_max", &solvers::Result<double>::delta_max},
                       {"t_peak", &solvers::Result<double>::t_peak},
                       {"tau", &solvers::Result<double>::tau},
                       {"energy_load", &solvers::Result<double>::energy_load},
                       {"energy_unload", &solvers::Result<double>::energy_unload},
                       {"t_normal_force_max", &solvers::Result<double>::t_normal_force_max}};

// Why an external program's record holds values its run would have refused (impossible_answer
// made such an answer unstable, nothing kept); empty when it holds none. With one onset phase the
// values are one answer's and held together; with more, each observable's is its worst phase's
// (run.cpp, judge_record), so each is held alone.
std::string impossible_external_values(const Plan& plan, const Record& r,
                                       const solvers::Problem<double>& problem) {
  const SolverConfig& config = plan.configs[r.config];
  if (!r.outcome) {
    return {}; // nothing measured (impossible_run holds it to that)
  }
  solvers::Result<double> answer;
  answer.outcome = *r.outcome;
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    for (const auto& [key, field] : answer_fields) {
      if (plan.observables[o]->key == key && r.value[o]) {
        if (r.phases > 1) {
          if (std::string why = impossible_value(key, *r.value[o], config, problem); !why.empty()) {
            return why;
          }
        }
        answer.*field = r.value[o];
      }
    }
  }
  if (r.phases > 1) {
    return {};
  }
  solvers::Options<double> options;
  options.want = plan.scene.want;
  options.end = end_of(plan.scene, config);
  return impossible_answer(answer, config, problem, options);
}

// Why what a record says of its run (work, times, α, step, skip and note) cannot be a run's of
// this plan; empty when it can.
std::string impossible_run(const Plan& plan, const Record& r) {
  const SolverConfig& config = plan.configs[r.config];
  const Cell& cell = plan.cells[r.cell];
  const Limits& limits = plan.scene.limits;
  // Work within the run's limits. pldamp's solvers: steps per solve at most max_steps (a mean over
  // phases), right-hand sides at most a thousand a step (INT64_MAX wrapped the report's total),
  // times within max_seconds a solve (twice, and a second, for the clock's grain). An external
  // program: the counts it may report (at most 1e12, external.cpp), its time within its reply's
  // limit.
  const bool external = config.external();
  const double most_steps = external ? max_reply_count : double(limits.max_steps);
  const double most_rhs = external ? max_reply_count : 1000 * double(limits.max_steps);
  const double most_seconds = external ? limits.max_seconds + 1 : 2 * limits.max_seconds + 1;
  if (r.steps < 0 || double(r.steps) > most_steps || r.rhs_evals < 0 ||
      double(r.rhs_evals) > most_rhs || r.runs < 0) {
    return fmt::format("work out of its run's limits (steps {}, rhs_evals {}, runs {})", r.steps,
                       r.rhs_evals, r.runs);
  }
  for (const double x : {r.wall_seconds, r.wall_seconds_slowest, r.cpu_seconds.value_or(0),
                         r.cpu_seconds_slowest.value_or(0)}) {
    if (!(x >= 0 && x <= most_seconds)) {
      return fmt::format("a time of {} s, not in [0, {}] (max_seconds {})", to_string_full(x),
                         most_seconds, limits.max_seconds);
    }
  }
  if (external && (r.cpu_seconds || r.cpu_seconds_slowest)) {
    return "a CPU time on an external program's record (its work is done in its own process)";
  }
  // A skip and a note come from external programs only (their handshakes and β).
  if (!external && (r.skipped() || !r.note.empty())) {
    return "a skip or a note on a configuration of pldamp's own solver";
  }
  if (r.skipped()) {
    return {};
  }
  if (r.phases != config.onset_phases) {
    return fmt::format("{} onset phases, its configuration runs {}", r.phases, config.onset_phases);
  }
  // α as the configuration receives it (truth/plan.hpp, alpha_as_received), to the bit.
  if (!(r.alpha == alpha_as_received<double>(cell.alpha))) {
    return fmt::format("alpha = {}, its cell's is {}", to_string_full(r.alpha),
                       to_string_full(alpha_as_received<double>(cell.alpha)));
  }
  // A step where the configuration runs one and the solver ran, none where it does not.
  const bool fixed = config.steps_per_contact.has_value() || config.dt.has_value();
  if ((r.dt && !fixed) || (r.dt && !(std::isfinite(*r.dt) && *r.dt > 0))) {
    return fmt::format("a step dt = {} for a configuration {}",
                       r.dt ? to_string_full(*r.dt) : std::string("none"),
                       fixed ? "of a fixed step" : "without one");
  }
  return {};
}

} // namespace

std::string impossible_record(const Plan& plan, const Record& r) {
  if (r.cell >= plan.cells.size() || r.config >= plan.configs.size()) {
    return fmt::format("cell {} or configuration {} is not in the plan", r.cell, r.config);
  }
  // One value, reference, error and spread per observable, always (a run sizes them whether
  // it solved, skipped or failed; all empty crashed the merge); the worst phases and a replica's
  // differences where there are some.
  const std::size_t n = plan.observables.size();
  for (const RecordValues* values :
       {&r.value, &r.reference, &r.error, &r.abs_error, &r.rel_error, &r.spread}) {
    if (values->size() != n) {
      return fmt::format("it holds {} values of an observable, the plan has {} observables",
                         values->size(), n);
    }
  }
  for (const RecordValues* values : {&r.worst_phase, &r.replica_difference}) {
    if (!values->empty() && values->size() != n) {
      return fmt::format("it holds {} values of an observable, the plan has {} observables",
                         values->size(), n);
    }
  }
  const SolverConfig& config = plan.configs[r.config];
  const Cell& cell = plan.cells[r.cell];
  if (const std::string why = impossible_run(plan, r); !why.empty()) {
    return why;
  }
  for (std::size_t o = 0; o < r.worst_phase.size(); ++o) {
    if (r.worst_phase[o] && !(*r.worst_phase[o] >= 0 && *r.worst_phase[o] < 1)) {
      return fmt::format("{}'s worst onset phase {} is not in [0, 1)", plan.observables[o]->key,
                         to_string_full(*r.worst_phase[o]));
    }
  }
  std::vector<ObservedNumbers> observed;
  for (std::size_t o = 0; o < n; ++o) {
    observed.push_back(numbers_of(plan, r, o));
  }
  if (std::string why = inconsistent_with_outcome(
          {.outcome = r.outcome_name(), .several_phases = r.phases > 1}, observed);
      !why.empty()) {
    return why;
  }
  const Point& point = plan.points[cell.point];
  solvers::Problem<double> problem{point.p, cell.m, cell.k, cell.v0, r.alpha};
  problem.damping_exponent = point.beta;
  const double allowance = answer_allowance(config, problem);
  for (std::size_t o = 0; o < n; ++o) {
    const std::optional<Exact> truth = reference_at(plan, cell, o, config);
    if (std::string why =
            impossible_numbers(r, o, observed[o], truth, config.external(), allowance);
        !why.empty()) {
      return why;
    }
  }
  if (config.external()) {
    if (std::string why = impossible_external_values(plan, r, problem); !why.empty()) {
      return "impossible answer: " + why;
    }
  }
  return {};
}

} // namespace pldamp::harness
