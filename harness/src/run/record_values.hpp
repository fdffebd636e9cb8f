// What a record's runs are worth against its truth (run/run.cpp solves them): each run's values
// measured against the reference, and a record's values from its onset phases' runs.
#pragma once

#include "run/run.hpp"
#include "truth/plan.hpp"

#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <vector>

namespace pldamp::harness {

// One collision's value of an observable against its reference (see Record).
struct Measured {
  std::optional<double> value, reference, error, abs_error, rel_error;
};

// The truth of a record: the plan's (reference_at), or, for an external code whose dashpot is not
// the point's, the reference solve of the code's own β at this cell (MATH.md §12.2).
struct RecordTruth {
  const Plan& plan;
  const Cell& cell;
  const SolverConfig& config;
  const solvers::Result<Exact>* own = nullptr; // the code's reference solve, v0 = m = k = 1
  bool returns = true;                         // whether the contact returns (own truth)
  Exact log_duration = 0;                      // ln τ at the overlap end (own truth)

  std::optional<Exact> at(std::size_t observable) const {
    if (own == nullptr) {
      return reference_at(plan, cell, observable, config);
    }
    const std::optional<Exact> unit = plan.observables[observable]->measured(*own);
    if (!unit || solvers::failing(own->outcome)) {
      return std::nullopt;
    }
    return *unit * cell.scale(plan.observables[observable]->dimension);
  }
};

// Each observable of one run's result against the record's truth.
template <SupportedReal Real>
std::vector<Measured> measure(const RecordTruth& truth, const solvers::Result<Real>& result);

// One onset phase of a record: its result (the first run's) and the times of its repeats.
template <SupportedReal Real>
struct PhaseRun {
  double phase = 0;
  solvers::Result<Real> result;
  RepeatTimes wall, cpu;
};

// A record's values from its phases' runs: per observable the phase with the largest error, the
// spread over the phases, the worst outcome, the mean steps and times.
template <SupportedReal Real>
void judge_record(const Plan& plan, Record& record, const RecordTruth& truth,
                  const std::vector<PhaseRun<Real>>& phase_runs, bool external);

} // namespace pldamp::harness
