#include "common/record_consistency.hpp"

#include "common/input.hpp"
#include "common/observables.hpp"

#include "pldamp/solvers/problem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace pldamp::harness {
namespace {

constexpr double epsilon = std::numeric_limits<double>::epsilon();
constexpr double infinity = std::numeric_limits<double>::infinity();

// The most a double rounded once from a wider number is off by: half an ulp, at most ½ ε |x|, and
// below the normal range half the least subnormal (taken whole: half of it is no double).
double rounding_of(double x) {
  return 0.5 * epsilon * std::abs(x) + std::numeric_limits<double>::denorm_min();
}

// τ, the one observable that may be infinite: a contact that never ends, which a solver's no_exit
// leaves unresolved (common/observables.hpp).
bool may_be_infinite(const Observable* observable) {
  return observable != nullptr && observable->late_return == LateReturn::unresolved;
}

// Whether a record's numbers may be those of a no_exit phase (run/run.cpp, measure: a late return
// compared absolutely, or not at all): its outcome is no_exit, or its worst phase's may be.
bool maybe_no_exit(const RecordRun& run) {
  return run.outcome == solvers::outcome_name(solvers::Outcome::no_exit) || run.several_phases;
}

} // namespace

std::string inconsistent_numbers(const ObservedNumbers& n, const RecordRun& run) {
  const Observable* observable = find_observable(n.key);
  const auto key = [&] { return one_line(n.key, 100); };
  for (const auto& [name, number] : {std::pair{"value", &n.value},
                                     {"reference", &n.reference},
                                     {"error", &n.error},
                                     {"rel_error", &n.rel_error},
                                     {"spread", &n.spread}}) {
    if (*number && std::isnan(**number)) {
      return fmt::format("{}'s {} is NaN", key(), name);
    }
    if (*number && std::isinf(**number) && !may_be_infinite(observable)) {
      return fmt::format("{}'s {} is {}", key(), name, to_string_full(**number));
    }
  }
  if (n.spread && *n.spread < 0) {
    return fmt::format("{}'s spread {} is negative", key(), to_string_full(*n.spread));
  }
  if (n.replica_difference &&
      !(std::isfinite(*n.replica_difference) && *n.replica_difference >= 0)) {
    return fmt::format("{}'s difference from its replica is {}", key(),
                       to_string_full(*n.replica_difference));
  }
  // Sizes and times are not negative. An energy is work done, which a coarse fixed step can make
  // negative (run/record_check.cpp bounds an external program's); an observable this build does
  // not know has no sign known.
  const bool signed_value = observable == nullptr || observable->dimension == Dimension::energy;
  if (n.value && !signed_value && *n.value < 0) {
    return fmt::format("{} = {} is impossible (a negative size or time)", key(),
                       to_string_full(*n.value));
  }
  const std::optional<double>&value = n.value, &reference = n.reference, &error = n.error,
        &rel_error = n.rel_error;
  if (!error) {
    if (rel_error) {
      return fmt::format("{} has a rel_error {} but no error", key(), to_string_full(*rel_error));
    }
    // A value and a reference are compared, but for τ on a late return (LateReturn::unresolved).
    if (value && reference && !(may_be_infinite(observable) && maybe_no_exit(run))) {
      return fmt::format("{} has a value {} and a reference {} but no error", key(),
                         to_string_full(*value), to_string_full(*reference));
    }
    return {};
  }
  if (!value || !reference || !rel_error) {
    return fmt::format("{} has an error {} without its value, reference and rel_error", key(),
                       to_string_full(*error));
  }
  // The error as run.cpp's compare makes it: of infinities, 0 between equal ones and else the
  // infinity of the difference's sign; of numbers, value − reference computed in Exact from the
  // solver's value and the truth, and rounded once, as the value and the reference are. So the
  // error lies within the three roundings of value − reference; twice them leaves room for this
  // check's own rounding of the difference.
  const bool agrees =
      std::isinf(*value) || std::isinf(*reference)
          ? *error == (*value == *reference  ? 0.0
                       : *value > *reference ? infinity
                                             : -infinity)
          : std::abs(*error - (*value - *reference)) <=
                2 * (rounding_of(*value) + rounding_of(*reference) + rounding_of(*error));
  if (!agrees) {
    return fmt::format("{}'s error {} is not its value {} minus its reference {}", key(),
                       to_string_full(*error), to_string_full(*value), to_string_full(*reference));
  }
  // The relative error: |error| of an infinite error or reference (τ), and of a reference 0 (e of
  // a contact that never returns) or e compared absolutely on a late return
  // (LateReturn::absolute); otherwise |error| / |truth| in Exact, rounded once.
  const double size = std::abs(*error);
  const bool absolute =
      *reference == 0 || (observable != nullptr &&
                          observable->late_return == LateReturn::absolute && maybe_no_exit(run));
  if (std::isinf(*error) || std::isinf(*reference) || (absolute && *rel_error == size)) {
    if (*rel_error == size) {
      return {};
    }
  } else {
    // The error and the truth each within twice the rounding of what the record holds of them
    // (twice: for this check's own arithmetic), so |error| / |truth| between the quotients of
    // those bounds, widened by twice the rounding of the relative error itself. A reference 0 is
    // a truth 0 (relative error |error|, above) or one below the least subnormal: no bound above.
    const double error_room = 2 * rounding_of(*error), reference_room = 2 * rounding_of(*reference);
    const double least = std::max(0.0, size - error_room) / (std::abs(*reference) + reference_room);
    const double most = std::abs(*reference) > reference_room
                            ? (size + error_room) / (std::abs(*reference) - reference_room)
                            : infinity;
    if (*rel_error >= least - 2 * rounding_of(least) &&
        *rel_error <= most + 2 * rounding_of(most)) {
      return {};
    }
  }
  return fmt::format("{}'s rel_error {} is not |error| / |reference| = {}", key(),
                     to_string_full(*rel_error),
                     to_string_full(*reference == 0 ? size : size / std::abs(*reference)));
}

std::string inconsistent_with_outcome(const RecordRun& run,
                                      std::span<const ObservedNumbers> observed) {
  const std::string_view outcome = run.outcome;
  using solvers::Outcome;
  using solvers::outcome_name;
  const auto value_of = [&](std::string_view key) -> std::optional<double> {
    const auto at = std::find_if(observed.begin(), observed.end(),
                                 [&](const ObservedNumbers& o) { return o.key == key; });
    return at != observed.end() ? at->value : std::nullopt;
  };
  // Nothing measured when the solver threw, was skipped or gave an impossible answer; at the peak,
  // nothing after it; no return, no e but 0.
  const bool any = std::any_of(observed.begin(), observed.end(),
                               [](const ObservedNumbers& o) { return o.value.has_value(); });
  if (any && (outcome == threw_outcome || outcome == skipped_outcome ||
              outcome == outcome_name(Outcome::unstable))) {
    return fmt::format("values beside outcome {}", outcome);
  }
  if (outcome == outcome_name(Outcome::peak) &&
      (value_of("e") || value_of("tau") || value_of("energy_unload"))) {
    return "e, tau or energy_unload beside outcome peak";
  }
  if (const std::optional<double> e = value_of("e");
      !run.several_phases && outcome == outcome_name(Outcome::no_exit) && e && *e != 0) {
    return fmt::format("e = {} beside outcome no_exit", to_string_full(*e));
  }
  return {};
}

std::string inconsistent_reported(const ReportedRecord& record) {
  const std::string_view outcome = record.run.outcome;
  const std::optional<solvers::Outcome> solver_outcome = solvers::outcome_named(outcome);
  const bool skipped = outcome == skipped_outcome;
  if (!solver_outcome && outcome != threw_outcome && !skipped) {
    return fmt::format("unknown outcome \"{}\"", one_line(outcome, 100));
  }
  // Failed when its solver threw, its outcome fails or it has a failure (a no_exit before the
  // truth's return); a skipped record never (Record::failed, which the report's "failed" is).
  const bool fails = !solver_outcome || solvers::failing(*solver_outcome) || record.has_failure;
  if (skipped ? record.failed || record.has_failure : fails && !record.failed) {
    return fmt::format("failed is {} beside outcome {}{}", record.failed, outcome,
                       record.has_failure ? " and a failure" : "");
  }
  if (std::string why = inconsistent_with_outcome(record.run, record.observed); !why.empty()) {
    return why;
  }
  for (ObservedNumbers numbers : record.observed) {
    // JSON has no infinity: τ of a contact that never ends is null, its reference too where the
    // truth never returns, and their error (0) and relative error (0) are numbers.
    if (numbers.error && !numbers.value && !numbers.reference &&
        may_be_infinite(find_observable(numbers.key))) {
      numbers.value = numbers.reference = infinity;
    }
    if (std::string why = inconsistent_numbers(numbers, record.run); !why.empty()) {
      return why;
    }
  }
  return {};
}

} // namespace pldamp::harness
