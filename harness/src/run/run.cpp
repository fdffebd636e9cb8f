#include "run/run.hpp"

#include "run/record_store.hpp"
#include "run/record_values.hpp"

#include "common/parallel.hpp"
#include "common/record_consistency.hpp"
#include "run/external.hpp"
#include "run/phase_supremum.hpp"
#include "run/shard.hpp"
#include "truth/reference_solve.hpp"

#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <tuple>

#include <time.h>

namespace pldamp::harness {
namespace {

// This thread's CPU time in seconds: what a solve costs, whatever else the machine runs (wall
// time also counts the time other processes held the core; docs/ci.md, "Thresholds").
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// The registered solver of a configuration, or its external program (which runs in double).
template <SupportedReal Real>
solvers::Result<Real> solve_with(const SolverConfig& config, ExternalSolver* external,
                                 const solvers::Problem<Real>& problem,
                                 const solvers::Options<Real>& options) {
  if constexpr (std::is_same_v<Real, double>) {
    if (external != nullptr) {
      return external->solve(config, problem, options);
    }
  }
  return solvers::solve(config.name, problem, options);
}

// An external solver's values against pldamp's replica of its scheme on the same problem, into
// record.replica_difference (the largest over the phases).
template <SupportedReal Real>
void compare_with_replica(const Plan& plan, const SolverConfig& config,
                          const solvers::Problem<Real>& problem,
                          const solvers::Options<Real>& options,
                          const solvers::Result<Real>& result, Record& record) {
  using std::abs;
  using std::isfinite;
  const solvers::Result<Real> replica = solvers::solve(config.replica, problem, options);
  record.replica_difference.resize(plan.observables.size());
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    const std::optional<Real> value = plan.observables[o]->measured(result);
    const std::optional<Real> expected = plan.observables[o]->measured(replica);
    if (value && expected && isfinite(*value) && isfinite(*expected)) {
      const Real difference = abs(*value - *expected) / (*expected == 0 ? 1 : abs(*expected));
      std::optional<double>& largest = record.replica_difference[o];
      largest = std::max(largest.value_or(0.0), static_cast<double>(difference));
    }
  }
}

// Every onset phase k/n, one solve at a time (repeats for the timing only, and only for runs
// shorter than repeat_below: they remove the noise of a short run, a timer tick or a preemption,
// which a long one averages itself; the nightly's overdamped solves, 80 % of its CPU time, are
// timed once). `options` is the record's own, its onset_phase set here phase by phase: not copied,
// which also spares GCC 12 at -O3 a false "may be used uninitialized" on the copy of a disengaged
// std::optional<float128> (GCC bug 80635; it showed in the unity build).
template <SupportedReal Real>
std::vector<PhaseRun<Real>>
run_phases(const Plan& plan, const SolverConfig& config, ExternalSolver* external,
           const solvers::Problem<Real>& problem, solvers::Options<Real>& options, Record& record) {
  std::vector<PhaseRun<Real>> runs;
  for (int phase = 0; phase < config.onset_phases; ++phase) {
    options.onset_phase = Real(phase) / Real(config.onset_phases);
    PhaseRun<Real> run;
    run.phase = double(phase) / double(config.onset_phases);
    double cpu_start = thread_cpu_seconds();
    ++record.runs; // counted if it throws too
    count_solver_runs(1);
    run.result = solve_with(config, external, problem, options);
    run.cpu.add(thread_cpu_seconds() - cpu_start);
    if (!config.replica.empty()) {
      compare_with_replica(plan, config, problem, options, run.result, record);
    }
    time_contact_as(run.result, config.tau_as);
    run.wall.add(run.result.wall_seconds);
    for (int repeat = 1; repeat < (external != nullptr ? 1 : plan.scene.repeats) &&
                         run.cpu.fastest < plan.scene.repeat_below;
         ++repeat) {
      cpu_start = thread_cpu_seconds();
      count_solver_runs(1);
      run.wall.add(solvers::solve(config.name, problem, options).wall_seconds);
      run.cpu.add(thread_cpu_seconds() - cpu_start);
      ++record.runs;
    }
    runs.push_back(std::move(run));
  }
  return runs;
}

// What a record is solved with: its problem, its options and its truth, built in place (the truth
// holds references; and copying an Options<float128> is what trips GCC bug 80635, run_phases).
// Named so that no other unit of a unity build has the name.
template <SupportedReal Real>
struct RecordSetup {
  solvers::Problem<Real> problem;
  solvers::Options<Real> options;
  RecordTruth truth;

  RecordSetup(const Plan& plan, Record& record, ExternalSolver* external)
      : problem(problem_of(plan, record)), truth{plan, plan.cells[record.cell],
                                                 plan.configs[record.config]} {
    const Cell& cell = plan.cells[record.cell];
    const Point& point = plan.points[cell.point];
    const SolverConfig& config = plan.configs[record.config];
    record.alpha = static_cast<double>(problem.alpha);
    if constexpr (!std::is_same_v<Real, double>) {
      record.alpha_digits = to_string_full(problem.alpha);
    }
    if (config.rtol) {
      options.rtol = Real(*config.rtol);
    } else if (external == nullptr) {
      options.rtol = solvers::solver_named(config.name).template default_rtol<Real>();
    }
    if (config.atol) {
      options.atol = Real(*config.atol);
    }
    options.want = plan.scene.want;
    options.end = end_of(plan.scene, config);
    options.max_steps = plan.scene.limits.max_steps;
    options.max_seconds = plan.scene.limits.max_seconds;
    options.stop = &stop_requested();
    if (config.steps_per_contact) {
      options.steps_per_contact = *config.steps_per_contact;
    }
    if (config.dt) {
      options.fixed_step = Real(*config.dt);
    }
    if (external != nullptr) {
      // A code whose dashpot is not the point's: the truth of its own β at α as it receives it.
      const double code_beta = external->facts().beta(point.p);
      if (code_beta != point.beta.value_or((point.p - 1) / 2)) {
        const Exact delta_u = unit_overlap(point.p) * cell.scale(Dimension::length);
        const Exact group = group_of(point.p, code_beta, Exact(problem.alpha), delta_u);
        truth.own = &reference_solve(point.p, code_beta, group, options.end);
        const solvers::Result<Exact>& overlap =
            reference_solve(point.p, code_beta, group, solvers::End::overlap);
        truth.returns = overlap.outcome != solvers::Outcome::no_exit;
        truth.log_duration = overlap.tau && isfinite(*overlap.tau)
                                 ? log(*overlap.tau)
                                 : std::numeric_limits<Exact>::infinity();
        record.note =
            fmt::format("truth by reference solve: it damps as delta^{:g} delta'", code_beta);
        if (solvers::failing(truth.own->outcome)) {
          record.note = fmt::format("no truth: the reference solve for delta^{:g} delta' ended {}",
                                    code_beta, solvers::outcome_name(truth.own->outcome));
        }
      }
    }
  }

private:
  static solvers::Problem<Real> problem_of(const Plan& plan, const Record& record) {
    const Cell& cell = plan.cells[record.cell];
    const Point& point = plan.points[cell.point];
    solvers::Problem<Real> problem{Real(point.p), Real(cell.m), Real(cell.k), Real(cell.v0),
                                   alpha_as_received<Real>(cell.alpha)};
    if (point.beta) {
      problem.damping_exponent = Real(*point.beta);
    }
    return problem;
  }
};

// Whether a configuration's records (in double) are solved in batches (solvers::solve_batch):
// pldamp's own fixed-step scheme with a batch path.
bool batched(const SolverConfig& config, const ExternalSolver* external) {
  return external == nullptr && config.precision == precision_name<double>() &&
         solvers::solver_named(config.name).batched;
}

// The onset phases k/n of G records of one configuration, p and β (the cells of a group, or a
// record alone) as one solve_batch, lane g·n + k each; every lane's result is bit for bit its own
// solve (solvers::solve_batch), so each record is the one solved alone. Time is attributed per lane
// as the batch's in proportion to the lane's steps (+1: a lane that ends before a step still
// costs its set-up): each repeat's CPU time and its wall time, so a record's cpu_seconds stays
// the CPU time of its contacts and a configuration's sum the CPU time its batches took
// (docs/ci.md). For one record, whose phases' shares sum to the batch, that is the batch's time
// over n. Repeats are made while the records' mean share is below repeat_below, as for a record
// alone (a batch's records are expected to take about the same steps: group_records).
std::vector<std::vector<PhaseRun<double>>> run_cells_batched(const SolverConfig& config,
                                                             std::span<RecordSetup<double>> setups,
                                                             const Scene& scene,
                                                             std::span<Record* const> records) {
  const auto n = static_cast<std::size_t>(config.onset_phases);
  const std::size_t group = setups.size();
  std::vector<solvers::Problem<double>> problems;
  std::vector<solvers::Options<double>> lanes;
  problems.reserve(group * n);
  lanes.reserve(group * n);
  for (const RecordSetup<double>& setup : setups) {
    for (std::size_t phase = 0; phase < n; ++phase) {
      problems.push_back(setup.problem);
      lanes.push_back(setup.options);
      lanes.back().onset_phase = double(phase) / double(n);
    }
  }
  std::vector<std::vector<PhaseRun<double>>> runs(group, std::vector<PhaseRun<double>>(n));
  std::vector<double> weight; // per lane: its steps + 1, from the first repeat
  double weights = 0;
  double batch_cpu = 0; // the last batch's CPU time: repeated while a record's share is short
  for (int repeat = 0; repeat < std::max(scene.repeats, 1) &&
                       (repeat == 0 || batch_cpu / double(group) < scene.repeat_below);
       ++repeat) {
    const double cpu_start = thread_cpu_seconds();
    for (Record* record : records) {
      record->runs += static_cast<long>(n);
    }
    count_solver_runs(static_cast<long>(group * n));
    std::vector<solvers::Result<double>> results =
        solvers::solve_batch(config.name, problems, lanes);
    batch_cpu = thread_cpu_seconds() - cpu_start;
    double batch_wall = 0;
    for (const solvers::Result<double>& result : results) {
      batch_wall += result.wall_seconds;
    }
    if (repeat == 0) { // the weights: the steps, which every repeat makes alike
      for (const solvers::Result<double>& result : results) {
        weight.push_back(double(result.steps) + 1);
        weights += weight.back();
      }
    }
    for (std::size_t lane = 0; lane < results.size(); ++lane) {
      PhaseRun<double>& run = runs[lane / n][lane % n];
      run.cpu.add(batch_cpu * weight[lane] / weights);
      run.wall.add(batch_wall * weight[lane] / weights);
      if (repeat == 0) {
        run.phase = lanes[lane].onset_phase;
        run.result = std::move(results[lane]);
        time_contact_as(run.result, config.tau_as);
      }
    }
  }
  return runs;
}

// SolverConfig::every_phase: the sampled phases refined to the worst over every onset phase of the
// relative error of each observable it names (run/phase_supremum.hpp), the runs it takes appended.
// A supremum not resolved within the refinement's budget fails the record: its worst would only be
// a lower bound.
template <SupportedReal Real>
void seek_every_phase(const SolverConfig& config, ExternalSolver* external,
                      RecordSetup<Real>& setup, Record& record,
                      std::vector<PhaseRun<Real>>& phase_runs) {
  if (config.every_phase == 0) {
    return;
  }
  const std::vector<const Observable*>& observables = setup.truth.plan.observables;
  constexpr double inf = std::numeric_limits<double>::infinity();
  auto point_of = [&](const PhaseRun<Real>& run) {
    PhasePoint point{.phase = run.phase, .piece = piece_of(run.result, run.phase), .scores = {}};
    const bool failed = solvers::failing(run.result.outcome);
    const std::vector<Measured> measured = measure(setup.truth, run.result);
    for (std::size_t o = 0; o < measured.size(); ++o) {
      const bool sought = (observables[o]->solver_want & config.every_phase) != 0;
      point.scores.push_back(failed ? inf : sought ? measured[o].rel_error.value_or(-inf) : -inf);
    }
    return point;
  };
  std::vector<PhasePoint> points;
  for (const PhaseRun<Real>& run : phase_runs) {
    points.push_back(point_of(run));
  }
  auto evaluate = [&](double phase) {
    setup.options.onset_phase = Real(phase);
    PhaseRun<Real> run;
    run.phase = phase;
    const double cpu_start = thread_cpu_seconds();
    ++record.runs;
    count_solver_runs(1);
    run.result = solve_with(config, external, setup.problem, setup.options);
    run.cpu.add(thread_cpu_seconds() - cpu_start);
    run.wall.add(run.result.wall_seconds);
    time_contact_as(run.result, config.tau_as);
    phase_runs.push_back(std::move(run));
    return point_of(phase_runs.back());
  };
  const double last = std::nextafter(1.0, 0.0); // the largest phase, the far side of the onset
  if (std::none_of(points.begin(), points.end(),
                   [&](const PhasePoint& p) { return p.phase == last; })) {
    points.push_back(evaluate(last));
  }
  if (!refine_to_supremum(points, evaluate, 4000, config.every_phase_enough) &&
      record.failure.empty()) {
    record.failure = "the worst onset phase is not resolved within the refinement's budget: its "
                     "error would be a lower bound";
  }
}

// One record alone: its setup, its phases (one batch where its configuration has one and more than
// one phase, one solve at a time otherwise), its values.
template <SupportedReal Real>
void solve_record(const Plan& plan, Record& record, ExternalSolver* external) {
  RecordSetup<Real> setup(plan, record, external);
  const SolverConfig& config = plan.configs[record.config];
  std::vector<PhaseRun<Real>> phase_runs;
  if constexpr (std::is_same_v<Real, double>) {
    if (batched(config, external) && config.onset_phases > 1) {
      Record* const one = &record;
      phase_runs = std::move(run_cells_batched(config, {&setup, 1}, plan.scene, {&one, 1}).front());
    }
  }
  if (phase_runs.empty()) {
    phase_runs = run_phases(plan, config, external, setup.problem, setup.options, record);
  }
  seek_every_phase(config, external, setup, record, phase_runs);
  judge_record(plan, record, setup.truth, phase_runs, external != nullptr);
}

// The work of a run in pieces, each a list of record indices: the records of a batched
// configuration (batched()) in groups of up to batch_lanes lanes (G = batch_lanes / phases records)
// of one configuration, p and β, which solve_batch steps together; any other record alone. A
// lane that ends leaves its batch (compact_lanes), and the batch is cheapest per lane while its
// lanes run together, so a configuration's records are ordered by the steps they are expected to
// take: returning contacts by ln τ (over Δt when the step is fixed, rather than a fraction of the
// contact), then the overdamped ones, which run to the settled test or the horizon. G shrinks
// where there would be fewer than four groups a thread. Which records share a group changes only
// times, never values (run_cells_batched).
std::vector<std::vector<std::size_t>> group_records(const Plan& plan,
                                                    const std::vector<Record>& records,
                                                    const std::vector<ExternalSolver*>& externals,
                                                    std::size_t batch_lanes, int jobs) {
  struct Lane {
    std::size_t record;
    double p;
    std::optional<double> beta;
    double expected; // ln of the steps expected, up to a constant per configuration
  };
  std::vector<std::vector<Lane>> by_config(plan.configs.size());
  std::vector<std::vector<std::size_t>> items;
  std::size_t batched_records = 0;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const SolverConfig& config = plan.configs[records[i].config];
    const auto phases = static_cast<std::size_t>(config.onset_phases);
    if (!batched(config, externals[records[i].config]) || 2 * phases > batch_lanes) {
      items.push_back({i});
      continue;
    }
    const Cell& cell = plan.cells[records[i].cell];
    const Point& point = plan.points[cell.point];
    double expected = point.overdamped ? std::numeric_limits<double>::infinity()
                                       : static_cast<double>(point.log_duration);
    if (config.dt) {
      expected += std::log(static_cast<double>(cell.scale(Dimension::time)) / *config.dt);
    }
    if (std::isnan(expected)) { // no truth: last, with the contacts that may never return
      expected = std::numeric_limits<double>::infinity();
    }
    by_config[records[i].config].push_back({i, point.p, point.beta, expected});
    ++batched_records;
  }
  const std::size_t threads = static_cast<std::size_t>(std::max(jobs, 1));
  for (std::vector<Lane>& lanes : by_config) {
    if (lanes.empty()) {
      continue;
    }
    std::stable_sort(lanes.begin(), lanes.end(), [](const Lane& a, const Lane& b) {
      return std::tie(a.p, a.beta, a.expected) < std::tie(b.p, b.beta, b.expected);
    });
    const std::size_t phases =
        static_cast<std::size_t>(plan.configs[records[lanes[0].record].config].onset_phases);
    const std::size_t group = std::clamp<std::size_t>(
        (batched_records + 4 * threads - 1) / (4 * threads), 1, batch_lanes / phases);
    // Each run of one p and β in ceil(size / group) batches of sizes differing by one at most:
    // none left alone by the remainder (alone, a record would take the scalar path).
    for (std::size_t first = 0; first < lanes.size();) {
      std::size_t end = first + 1;
      while (end < lanes.size() && lanes[end].p == lanes[first].p &&
             lanes[end].beta == lanes[first].beta) {
        ++end;
      }
      const std::size_t size = end - first, batches = (size + group - 1) / group;
      for (std::size_t b = 0, at = first; b < batches; ++b) {
        const std::size_t take = size / batches + (b < size % batches ? 1 : 0);
        std::vector<std::size_t> item;
        for (std::size_t k = 0; k < take; ++k) {
          item.push_back(lanes[at++].record);
        }
        items.push_back(std::move(item));
      }
      first = end;
    }
  }
  // Roughly in plan order: by each item's first record.
  std::sort(items.begin(), items.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return items;
}

} // namespace

struct PlanRunner::Programs {
  std::vector<std::unique_ptr<ExternalSolver>> owned;
  std::vector<ExternalSolver*> of_config; // per configuration: its program, or none
};

PlanRunner::PlanRunner(const Plan& plan, int jobs, std::size_t batch_lanes)
    : plan_(plan), jobs_(jobs), batch_lanes_(batch_lanes), programs_(std::make_unique<Programs>()) {
  // Every external program started and its handshake read before any record: one that cannot be
  // started or speaks another protocol stops the run here.
  // The configurations of one [[solver]] entry (one command and options: a sweep) share one
  // program, so that a code's start-up (a second for LAMMPS) is paid once per entry.
  std::vector<ExternalSolver*>& externals = programs_->of_config;
  externals.assign(plan.configs.size(), nullptr);
  external_.assign(plan.configs.size(), "");
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const SolverConfig& config = plan.configs[c];
    if (!config.external()) {
      continue;
    }
    for (std::size_t earlier = 0; earlier < c && externals[c] == nullptr; ++earlier) {
      const SolverConfig& other = plan.configs[earlier];
      if (externals[earlier] != nullptr && other.command == config.command &&
          other.options == config.options) {
        externals[c] = externals[earlier];
      }
    }
    if (externals[c] == nullptr) {
      programs_->owned.push_back(std::make_unique<ExternalSolver>(
          config, plan.scene.limits.max_seconds, &stop_requested()));
      externals[c] = programs_->owned.back().get();
    }
    externals[c]->facts().require_honoured(config);
    external_[c] = externals[c]->facts().describe();
  }
}

PlanRunner::~PlanRunner() = default;

std::vector<Record> PlanRunner::run_cells(std::span<const std::size_t> cells,
                                          const Progress& progress) {
  const Plan& plan = plan_;
  const std::vector<ExternalSolver*>& externals = programs_->of_config;
  std::vector<Record> records;
  records.reserve(cells.size() * plan.configs.size());
  for (const std::size_t cell : cells) {
    for (std::size_t config = 0; config < plan.configs.size(); ++config) {
      Record record;
      record.cell = cell;
      record.config = config;
      records.push_back(record);
    }
  }
  // A record alone, or a record of a group that threw (solve_batch throws for every lane when
  // one would): its message is the one it has alone.
  const auto solve_alone = [&](Record& record) {
    try {
      with_precision(plan.configs[record.config].precision, [&]<SupportedReal Real>() {
        solve_record<Real>(plan, record, externals[record.config]);
      });
    } catch (const Skipped& e) {
      Record skipped;
      skipped.cell = record.cell;
      skipped.config = record.config;
      skipped.alpha = record.alpha;
      skipped.alpha_digits = record.alpha_digits;
      record = std::move(skipped);
      record.skip_reason = e.what();
      record.value.assign(plan.observables.size(), std::nullopt);
      record.reference = record.error = record.abs_error = record.rel_error = record.spread =
          record.value;
    } catch (const std::exception& e) {
      record.outcome.reset();
      record.failure = e.what();
      record.value.assign(plan.observables.size(), std::nullopt);
      record.reference = record.error = record.abs_error = record.rel_error = record.spread =
          record.value;
    }
  };
  const std::vector<std::vector<std::size_t>> items =
      group_records(plan, records, externals, batch_lanes_, jobs_);
  std::mutex report;
  std::size_t done = 0;
  for_each_index(items.size(), jobs_, [&](std::size_t item) {
    if (stop_requested()) {
      return; // no new record
    }
    const std::vector<std::size_t>& members = items[item];
    if (members.size() == 1) {
      solve_alone(records[members[0]]);
    } else {
      std::vector<Record*> group;
      for (const std::size_t i : members) {
        group.push_back(&records[i]);
      }
      try {
        std::vector<RecordSetup<double>> setups;
        setups.reserve(group.size());
        for (Record* record : group) {
          setups.emplace_back(plan, *record, nullptr);
        }
        const SolverConfig& config = plan.configs[group[0]->config];
        std::vector<std::vector<PhaseRun<double>>> runs =
            run_cells_batched(config, setups, plan.scene, group);
        for (std::size_t g = 0; g < group.size(); ++g) {
          seek_every_phase(config, nullptr, setups[g], *group[g], runs[g]);
          judge_record(plan, *group[g], setups[g].truth, runs[g], false);
        }
      } catch (const std::exception&) {
        for (Record* record : group) {
          Record fresh;
          fresh.cell = record->cell;
          fresh.config = record->config;
          *record = std::move(fresh);
          solve_alone(*record);
        }
      }
    }
    if (progress) {
      const std::lock_guard lock(report);
      for (std::size_t k = 0; k < members.size(); ++k) {
        progress(++done, records.size());
      }
    }
  });
  return records;
}

// A rank's records as a piece of a shared map (run/workers.hpp).
void put_piece(ByteWriter& out, const std::vector<Record>& records) {
  put_records(out, records);
}
void get_piece(ByteReader& in, std::vector<Record>& records) {
  records = get_records(in);
}

std::vector<Record> run_plan(const Plan& plan, const Workers& workers, RunTotals& totals,
                             const Progress& progress, std::size_t batch_lanes) {
  const auto start = std::chrono::steady_clock::now();
  totals = {};
  PlanRunner runner(plan, workers.jobs, batch_lanes);
  totals.external = runner.external();
  const std::size_t ranks = workers.shared() ? static_cast<std::size_t>(workers.ranks->size()) : 1;
  // One piece a rank, its cells strided as a shard's (each rank gets every p, damping and scale),
  // solved on its threads; the records then in plan order.
  std::vector<std::vector<Record>> shares =
      map_shared<std::vector<Record>>(ranks, workers, [&](std::size_t rank) {
        return runner.run_cells(shard_cells(plan.cells.size(), rank + 1, ranks), progress);
      });
  std::vector<Record> records;
  if (ranks == 1) {
    records = std::move(shares.front());
  } else {
    records.resize(plan.cells.size() * plan.configs.size());
    for (std::vector<Record>& share : shares) {
      for (Record& record : share) {
        records.at(record.cell * plan.configs.size() + record.config) = std::move(record);
      }
    }
  }
  add_to_totals(records, totals);
  totals.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return records;
}

} // namespace pldamp::harness
