#include "run/record_check.hpp"

#include "common/observables.hpp"
#include "run/answers.hpp"

#include "pldamp/solvers/contact_ode.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace pldamp::harness {
namespace {

using RecordValues = std::vector<std::optional<double>>;

// Whether a and b agree to `ulps` units in the last place of the larger magnitude (exactly when
// either is 0 or infinite).
bool agree_to_ulps(double a, double b, double ulps) {
  if (std::isinf(a) || std::isinf(b) || a == 0 || b == 0) {
    return a == b;
  }
  return std::abs(a - b) <=
         ulps * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b));
}

// Why observable `o`'s numbers cannot be its run's; empty when they can.
std::string impossible_numbers(const Plan& plan, const Record& r, std::size_t o,
                               const std::optional<Exact>& truth, bool external, double allowance,
                               double energy_scale) {
  const std::string_view key = plan.observables[o]->key;
  const std::optional<double>&value = r.value[o], &reference = r.reference[o], &error = r.error[o],
        &abs_error = r.abs_error[o], &rel_error = r.rel_error[o];
  const bool duration = key == "tau"; // the one that may be infinite (a contact that never ends)
  for (const auto& [name, number] : {std::pair{"value", &value},
                                     {"reference", &reference},
                                     {"error", &error},
                                     {"abs_error", &abs_error},
                                     {"rel_error", &rel_error},
                                     {"spread", &r.spread[o]}}) {
    if (*number && std::isnan(**number)) {
      return fmt::format("{}'s {} is NaN", key, name);
    }
    if (*number && std::isinf(**number) && !duration) {
      return fmt::format("{}'s {} is {}", key, name, to_string_full(**number));
    }
  }
  if (r.spread[o] && *r.spread[o] < 0) {
    return fmt::format("{}'s spread {} is negative", key, to_string_full(*r.spread[o]));
  }
  if (value) {
    // The ranges the run held the record's solver to: an external program's answers as
    // impossible_answer holds them; pldamp's own solvers as BasicCollision::violated_invariant
    // does, which bounds e alone (a coarse fixed step's dashpot work can come out negative).
    const bool energy = key == "energy_load" || key == "energy_unload";
    if (energy ? external && *value < -allowance * energy_scale : *value < 0) {
      return fmt::format("{} = {} is impossible (energy gained, or a negative size)", key,
                         to_string_full(*value));
    }
    if (key == "e" && *value > 1 + allowance) {
      return fmt::format("e = {} gains energy (allowed up to 1 + {:.3g})", to_string_full(*value),
                         allowance);
    }
  }
  // The truth: the plan's to the bit, where the plan is the record's truth (not a code's own β).
  if (r.note.empty() && reference &&
      (!truth || !(static_cast<double>(*truth) == *reference ||
                   (std::isnan(static_cast<double>(*truth)) && std::isnan(*reference))))) {
    return fmt::format("{}'s reference {} is not the plan's ({})", key, to_string_full(*reference),
                       truth ? to_string_full(static_cast<double>(*truth)) : std::string("none"));
  }
  if (!error) {
    if (abs_error || rel_error) {
      return fmt::format("{} has an error's size but no error", key);
    }
    return {};
  }
  if (!value || !reference || !abs_error || !rel_error) {
    return fmt::format("{} has an error without its value, reference and sizes", key);
  }
  // The error as run.cpp's compare made it: value − reference in Exact, rounded once (the value
  // kept is rounded to double: a wider solver's differs from it by half an ulp of the value).
  double expected = 0;
  if (std::isinf(*value) || std::isinf(*reference)) {
    expected = *value == *reference  ? 0.0
               : *value > *reference ? std::numeric_limits<double>::infinity()
                                     : -std::numeric_limits<double>::infinity();
  } else {
    expected =
        static_cast<double>(Exact(*value) - (truth && r.note.empty() ? *truth : Exact(*reference)));
  }
  const double slack = std::abs(*error) + std::abs(*value);
  if (!(std::isinf(expected)
            ? *error == expected
            : std::abs(*error - expected) <= 4 * std::numeric_limits<double>::epsilon() * slack)) {
    return fmt::format("{}'s error {} is not its value {} minus its reference {}", key,
                       to_string_full(*error), to_string_full(*value), to_string_full(*reference));
  }
  if (*abs_error != std::abs(*error)) {
    return fmt::format("{}'s abs_error {} is not |error| = {}", key, to_string_full(*abs_error),
                       to_string_full(std::abs(*error)));
  }
  // Relative to the reference, or the absolute error (a reference 0, or e of a late return).
  const double relative =
      *reference == 0 || std::isinf(*reference) ? *abs_error : *abs_error / std::abs(*reference);
  if (!agree_to_ulps(*rel_error, relative, 4) && *rel_error != *abs_error) {
    return fmt::format("{}'s rel_error {} is not |error| / |reference| = {}", key,
                       to_string_full(*rel_error), to_string_full(relative));
  }
  return {};
}

} // namespace

std::string impossible_record(const Plan& plan, const Record& r) {
  if (r.cell >= plan.cells.size() || r.config >= plan.configs.size()) {
    return fmt::format("cell {} or configuration {} is not in the plan", r.cell, r.config);
  }
  const std::size_t n = plan.observables.size();
  for (const RecordValues* values : {&r.value, &r.reference, &r.error, &r.abs_error, &r.rel_error,
                                     &r.spread, &r.worst_phase, &r.replica_difference}) {
    if (!values->empty() && values->size() != n) {
      return fmt::format("it holds {} values of an observable, the plan has {} observables",
                         values->size(), n);
    }
  }
  for (const RecordValues* values :
       {&r.reference, &r.error, &r.abs_error, &r.rel_error, &r.spread}) {
    if (values->size() != r.value.size()) {
      return "its values, references and errors are not one per observable";
    }
  }
  const SolverConfig& config = plan.configs[r.config];
  const Cell& cell = plan.cells[r.cell];
  const double counts[] = {double(r.steps), double(r.rhs_evals), double(r.runs)};
  const double times[] = {r.wall_seconds, r.wall_seconds_slowest, r.cpu_seconds.value_or(0),
                          r.cpu_seconds_slowest.value_or(0)};
  for (const double x : counts) {
    if (x < 0) {
      return fmt::format("a negative count of work ({})", to_string_full(x));
    }
  }
  for (const double x : times) {
    if (!(std::isfinite(x) && x >= 0)) {
      return fmt::format("a time that is not a finite number >= 0 ({})", to_string_full(x));
    }
  }
  if (!r.skipped() && r.phases != config.onset_phases) {
    return fmt::format("{} onset phases, its configuration runs {}", r.phases, config.onset_phases);
  }
  if (r.dt && !(std::isfinite(*r.dt) && *r.dt > 0)) {
    return fmt::format("a step dt = {}", to_string_full(*r.dt));
  }
  if (!(std::isfinite(r.alpha) && r.alpha >= 0)) {
    return fmt::format("alpha = {}", to_string_full(r.alpha));
  }
  for (std::size_t o = 0; o < r.worst_phase.size(); ++o) {
    if (r.worst_phase[o] && !(*r.worst_phase[o] >= 0 && *r.worst_phase[o] < 1)) {
      return fmt::format("{}'s worst onset phase {} is not in [0, 1)", plan.observables[o]->key,
                         to_string_full(*r.worst_phase[o]));
    }
  }
  for (std::size_t o = 0; o < r.replica_difference.size(); ++o) {
    if (r.replica_difference[o] &&
        !(std::isfinite(*r.replica_difference[o]) && *r.replica_difference[o] >= 0)) {
      return fmt::format("{}'s difference from its replica is {}", plan.observables[o]->key,
                         to_string_full(*r.replica_difference[o]));
    }
  }
  const Point& point = plan.points[cell.point];
  solvers::Problem<double> problem{point.p, cell.m, cell.k, cell.v0, r.alpha};
  problem.damping_exponent = point.beta;
  const double allowance = answer_allowance(config, problem);
  const double energy_scale = solvers::ContactOde<double>(problem).energy_scale();
  for (std::size_t o = 0; o < r.value.size(); ++o) {
    const std::optional<Exact> truth = reference_at(plan, cell, o, config);
    if (std::string why =
            impossible_numbers(plan, r, o, truth, config.external(), allowance, energy_scale);
        !why.empty()) {
      return why;
    }
  }
  return {};
}

} // namespace pldamp::harness
