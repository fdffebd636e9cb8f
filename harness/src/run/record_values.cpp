#include "run/record_values.hpp"

#include "common/record_consistency.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pldamp::harness {

namespace {

// value − reference, its absolute and its relative size (see Record), into `m`.
void compare(const Exact& value, const Exact& reference, Measured& m) {
  if (isinf(reference) || isinf(value)) {
    const double inf = std::numeric_limits<double>::infinity();
    m.error = value == reference ? 0.0 : value > reference ? inf : -inf;
    m.abs_error = m.rel_error = std::abs(*m.error);
    return;
  }
  const Exact signed_error = value - reference;
  const Exact relative = reference == 0 ? abs(signed_error) : abs(signed_error) / abs(reference);
  m.error = static_cast<double>(signed_error);
  m.abs_error = static_cast<double>(abs(signed_error));
  m.rel_error = static_cast<double>(relative);
}

} // namespace

bool Record::failed() const {
  if (skipped()) {
    return false;
  }
  if (!outcome || solvers::failing(*outcome) || !failure.empty()) {
    return true;
  }
  return std::any_of(rel_error.begin(), rel_error.end(),
                     [](const std::optional<double>& e) { return e && !std::isfinite(*e); });
}

std::string_view Record::outcome_name() const {
  if (skipped()) {
    return skipped_outcome;
  }
  return outcome ? solvers::outcome_name(*outcome) : threw_outcome;
}

template <SupportedReal Real>
std::vector<Measured> measure(const RecordTruth& truth, const solvers::Result<Real>& result) {
  const Plan& plan = truth.plan;
  const Point& point = plan.points[truth.cell.point];
  const bool overdamped = truth.own != nullptr ? !truth.returns : point.overdamped;
  std::vector<Measured> out;
  for (std::size_t i = 0; i < plan.observables.size(); ++i) {
    const Observable& observable = *plan.observables[i];
    const std::optional<Real> value = observable.measured(result);
    std::optional<Exact> reference = truth.at(i);
    Measured m;
    if (value) {
      m.value = static_cast<double>(*value);
    }
    if (reference) {
      m.reference = static_cast<double>(*reference);
    }
    if (result.outcome == solvers::Outcome::no_exit && reference && !overdamped) {
      // The contact returns, but too late or too slowly for the solver to tell: no_exit is its
      // documented answer (common/observables.hpp, LateReturn).
      if (observable.late_return == LateReturn::unresolved) {
        reference.reset();
      } else if (observable.late_return == LateReturn::absolute && value) {
        compare(static_cast<Exact>(*value), *reference, m);
        m.rel_error = m.abs_error;
        out.push_back(m);
        continue;
      }
    }
    if (value && reference) {
      compare(static_cast<Exact>(*value), *reference, m);
    }
    out.push_back(m);
  }
  return out;
}

template <SupportedReal Real>
void judge_record(const Plan& plan, Record& record, const RecordTruth& truth,
                  const std::vector<PhaseRun<Real>>& phase_runs, bool external) {
  const Cell& cell = plan.cells[record.cell];
  const Point& point = plan.points[cell.point];
  const SolverConfig& config = plan.configs[record.config];
  const std::size_t observables = plan.observables.size();
  record.phases = config.onset_phases;
  record.value.assign(observables, std::nullopt);
  record.reference = record.error = record.abs_error = record.rel_error = record.spread =
      record.worst_phase = record.value;
  std::vector<double> lowest(observables, std::numeric_limits<double>::infinity()),
      highest(observables, -std::numeric_limits<double>::infinity());
  double steps = 0, rhs_evals = 0, fastest_seconds = 0, slowest_seconds = 0, fastest_cpu = 0,
         slowest_cpu = 0;
  for (std::size_t phase = 0; phase < phase_runs.size(); ++phase) {
    const solvers::Result<Real>& result = phase_runs[phase].result;
    const RepeatTimes& times = phase_runs[phase].wall;
    const RepeatTimes& cpu = phase_runs[phase].cpu;
    // A failed phase fails the record; the outcome kept is the worst seen.
    if (!record.outcome || solvers::failing(result.outcome)) {
      record.outcome = result.outcome;
    }
    if (result.outcome == solvers::Outcome::unstable && record.failure.empty()) {
      record.failure = result.invariant;
    }
    if (result.outcome == solvers::Outcome::no_exit && record.failure.empty()) {
      // An honest no_exit is a return beyond the horizon (or none at all).
      const Exact log_duration = truth.own != nullptr ? truth.log_duration : point.log_duration;
      const Exact tau = exp(log_duration) * cell.scale(Dimension::time);
      if (tau < Exact(result.horizon)) {
        record.failure = fmt::format("no_exit, yet the contact returns at tau = {:.6g}, before "
                                     "the horizon {:.6g}",
                                     static_cast<double>(tau), static_cast<double>(result.horizon));
      }
    }
    if (result.fixed_step) {
      record.dt = static_cast<double>(*result.fixed_step);
    }
    steps += double(result.steps);
    rhs_evals += double(result.rhs_evals + result.jacobian_evals);
    fastest_seconds += times.fastest;
    slowest_seconds += times.slowest;
    fastest_cpu += cpu.fastest;
    slowest_cpu += cpu.slowest;
    const std::vector<Measured> measured = measure(truth, result);
    for (std::size_t o = 0; o < observables; ++o) {
      const Measured& m = measured[o];
      if (m.value) {
        lowest[o] = std::min(lowest[o], *m.value);
        highest[o] = std::max(highest[o], *m.value);
      }
      const bool worse =
          phase == 0 ||
          (m.rel_error && (!record.rel_error[o] || !(*m.rel_error <= *record.rel_error[o])));
      if (worse) {
        record.value[o] = m.value;
        record.reference[o] = m.reference;
        record.error[o] = m.error;
        record.abs_error[o] = m.abs_error;
        record.rel_error[o] = m.rel_error;
        record.worst_phase[o] = phase_runs[phase].phase;
      }
    }
  }
  const double runs = double(phase_runs.size());
  record.steps = std::lround(steps / runs);
  record.rhs_evals = std::lround(rhs_evals / runs);
  record.wall_seconds = fastest_seconds / runs;
  record.wall_seconds_slowest = slowest_seconds / runs;
  if (!external) { // an external program's work is done in its own process
    record.cpu_seconds = fastest_cpu / runs;
    record.cpu_seconds_slowest = slowest_cpu / runs;
  }
  if (config.onset_phases > 1) {
    for (std::size_t o = 0; o < observables; ++o) {
      const std::optional<Exact> reference = truth.at(o);
      if (highest[o] >= lowest[o] && reference && isfinite(*reference) && *reference != 0) {
        record.spread[o] = static_cast<double>(Exact(highest[o] - lowest[o]) / abs(*reference));
      }
    }
  }
}

#define PLDAMP_INSTANTIATE_RECORD_VALUES(T, NAME)                                                  \
  template std::vector<Measured> measure(const RecordTruth&, const solvers::Result<T>&);           \
  template void judge_record(const Plan&, Record&, const RecordTruth&,                             \
                             const std::vector<PhaseRun<T>>&, bool);
PLDAMP_FOR_EACH_PRECISION(PLDAMP_INSTANTIATE_RECORD_VALUES)
#undef PLDAMP_INSTANTIATE_RECORD_VALUES

} // namespace pldamp::harness
