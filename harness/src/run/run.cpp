#include "run/run.hpp"

#include "pldamp/solvers/registry.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

namespace pldamp::harness {
namespace {

// |value − reference| and its relative size (see Record).
std::pair<double, double> errors(const Exact& value, const Exact& reference) {
  if (isinf(reference) || isinf(value)) {
    const double e = value == reference ? 0.0 : std::numeric_limits<double>::infinity();
    return {e, e};
  }
  const Exact absolute = abs(value - reference);
  const Exact relative = reference == 0 ? absolute : absolute / abs(reference);
  return {static_cast<double>(absolute), static_cast<double>(relative)};
}

template <SupportedReal Real>
void solve_record(const Plan& plan, Record& record) {
  const Cell& cell = plan.cells[record.cell];
  const Point& point = plan.points[cell.point];
  const SolverConfig& config = plan.configs[record.config];
  const solvers::Problem<Real> problem{Real(point.p), Real(cell.m), Real(cell.k), Real(cell.v0),
                                       static_cast<Real>(point.alpha)};
  solvers::Options<Real> options;
  options.rtol = config.rtol ? Real(*config.rtol)
                             : solvers::solver_named(config.name).template default_rtol<Real>();
  if (config.atol) {
    options.atol = Real(*config.atol);
  }
  options.want = plan.scene.want;
  options.end = plan.scene.end;
  if (config.steps_per_contact) {
    options.steps_per_contact = *config.steps_per_contact;
  }
  const solvers::Result<Real> result = solvers::solve(config.name, problem, options);
  double fastest = result.wall_seconds;
  for (int repeat = 1; repeat < plan.scene.repeats; ++repeat) {
    fastest = std::min(fastest, solvers::solve(config.name, problem, options).wall_seconds);
  }
  record.outcome = result.outcome;
  record.steps = result.steps;
  record.rhs_evals = result.rhs_evals + result.jacobian_evals;
  record.wall_seconds = fastest;
  const std::string precision = alpha_precision(config);
  for (std::size_t i = 0; i < plan.observables.size(); ++i) {
    const Observable& observable = *plan.observables[i];
    const std::optional<Real> value = observable.measured(result);
    std::optional<Exact> reference = reference_at(plan, cell, i, precision);
    record.value.push_back(value ? std::optional<double>(static_cast<double>(*value))
                                 : std::nullopt);
    if (result.outcome == solvers::Outcome::no_exit && reference && !point.overdamped) {
      // The contact returns, but too late or too slowly for the solver to tell: no_exit is its
      // documented answer (common/observables.hpp, LateReturn).
      if (observable.late_return == LateReturn::unresolved) {
        reference.reset();
      } else if (observable.late_return == LateReturn::absolute && value) {
        const Exact absolute = abs(static_cast<Exact>(*value) - *reference);
        record.abs_error.push_back(static_cast<double>(absolute));
        record.rel_error.push_back(static_cast<double>(absolute));
        continue;
      }
    }
    if (value && reference) {
      const auto [absolute, relative] = errors(static_cast<Exact>(*value), *reference);
      record.abs_error.push_back(absolute);
      record.rel_error.push_back(relative);
    } else {
      record.abs_error.push_back(std::nullopt);
      record.rel_error.push_back(std::nullopt);
    }
  }
}

} // namespace

bool Record::failed() const {
  if (!outcome || *outcome == solvers::Outcome::step_limit) {
    return true;
  }
  return std::any_of(rel_error.begin(), rel_error.end(),
                     [](const std::optional<double>& e) { return e && !std::isfinite(*e); });
}

std::string_view Record::outcome_name() const {
  return outcome ? solvers::outcome_name(*outcome) : "error";
}

std::vector<Record> run_plan(const Plan& plan, int jobs, RunTotals& totals,
                             const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Record> records;
  for (std::size_t cell = 0; cell < plan.cells.size(); ++cell) {
    for (std::size_t config = 0; config < plan.configs.size(); ++config) {
      Record record;
      record.cell = cell;
      record.config = config;
      records.push_back(record);
    }
  }
  std::atomic<std::size_t> next{0};
  std::mutex report;
  std::size_t done = 0;
  auto work = [&] {
    for (std::size_t i = next++; i < records.size(); i = next++) {
      Record& record = records[i];
      try {
        with_precision(plan.configs[record.config].precision,
                       [&]<SupportedReal Real>() { solve_record<Real>(plan, record); });
      } catch (const std::exception& e) {
        record.outcome.reset();
        record.failure = e.what();
        record.value.assign(plan.observables.size(), std::nullopt);
        record.abs_error.assign(plan.observables.size(), std::nullopt);
        record.rel_error.assign(plan.observables.size(), std::nullopt);
      }
      if (progress) {
        const std::lock_guard lock(report);
        progress(++done, records.size());
      }
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < std::max(jobs, 1); ++j) {
    workers.emplace_back(work);
  }
  work();
  for (std::thread& worker : workers) {
    worker.join();
  }
  totals = {};
  for (const Record& record : records) {
    totals.rhs_evals += record.rhs_evals;
    totals.solver_runs += record.outcome ? plan.scene.repeats : 1;
  }
  totals.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return records;
}

} // namespace pldamp::harness
