// The harness's own cost per cell, solver time excluded (issue 5), on data/scenes/quick.toml
// (45 cells × 13 configurations):
// - plan: reading the scene and the float128 references (once per (p, damping), scaled to cells)
// - run_overhead: run_plan's time beyond the solvers' own wall time, per record (threads off)
// - budgets_and_reports: budgets, report.json, .csv and .md from the records, per record
// - external_protocol: a record through the external-solver protocol (run/external.hpp) with an
//   adapter that answers at once (answering_adapter.cpp): the protocol's own cost per record,
//   the pipe round trip and both sides' JSON included (target: <= 50 µs)
// - paper_claims/JOBS: data/scenes/paper.toml's 14 claims judged on their grids (solves
//   included) on JOBS threads; 3.6 s on one thread at issue 31, target <= 1.5 s on all cores
//
// - records_as_bytes: a run's records to the bytes a shard file or an MPI message carries
//   (run/shard.hpp) and back: bytes and time per record, what a rank's results cost to send
//   (docs/scaling.md)
//
// - report_objects/N: schema::read_report of a report whose text outside the records holds an
//   array of N empty objects: linear in N (nlohmann's callback parser was quadratic: 300 000 took
//   20 s, 800 000 over a minute), per object
//
// - timestep/TOLERANCE: `pldamp timestep --scheme dem-verlet --p 1.5 --e 0.5 --tolerance 10^-T`
//   (T = 2, 3), the worst over every onset phase at each value it tries (run/phase_supremum.hpp)
//   and the stability search's likewise; target <= 1 s (issue 47)
//
//   build/bench/harness_bench
#include "ask/ask.hpp"
#include "common/parallel.hpp"
#include "common/report_schema.hpp"
#include "judge/budget.hpp"
#include "judge/claims.hpp"
#include "report/report.hpp"
#include "run/run.hpp"
#include "run/shard.hpp"
#include "scene/scene.hpp"
#include "truth/plan.hpp"

#include "pldamp/harness/cli.hpp"
#include "pldamp/solvers/registry.hpp"

#include <benchmark/benchmark.h>

#include <fmt/format.h>

#include <chrono>
#include <sstream>
#include <string>

namespace {

using namespace pldamp::harness;

const std::string scene_path = std::string(PLDAMP_DATA_DIR) + "/scenes/quick.toml";

// The questions' C++ work as the Python module asks it (ask/ask.hpp): options read, settled,
// answered into the answer tree, no text. bench/python_overhead.py sets a Python call beside it.
void answer_observables(benchmark::State& state) {
  const pldamp::harness::TypedOptions options{{"--p", "1.5"}, {"--e", "0.5"}, {"--v0", "1.0"}};
  for (auto _ : state) {
    benchmark::DoNotOptimize(pldamp::harness::ask(pldamp::harness::Question::observables, options));
  }
}
BENCHMARK(answer_observables)->Unit(benchmark::kMicrosecond);

void answer_calibrate(benchmark::State& state) {
  const pldamp::harness::TypedOptions options{{"--p", "1.5"}, {"--e", "0.5"}};
  for (auto _ : state) {
    benchmark::DoNotOptimize(pldamp::harness::ask(pldamp::harness::Question::calibrate, options));
  }
}
BENCHMARK(answer_calibrate)->Unit(benchmark::kMicrosecond);

void answer_solve(benchmark::State& state) {
  const pldamp::harness::TypedOptions options{{"--solver", "taylor"},
                                              {"--p", "1.5"},
                                              {"--e", "0.61"},
                                              {"--v0", "0.42"},
                                              {"--repeats", "1"}};
  for (auto _ : state) {
    benchmark::DoNotOptimize(pldamp::harness::ask(pldamp::harness::Question::solve, options));
  }
}
BENCHMARK(answer_solve)->Unit(benchmark::kMicrosecond);

// The solve of answer_solve alone: what the answer adds is the difference.
void answer_solve_alone(benchmark::State& state) {
  const double p = 1.5, e = 0.61;
  const double alpha = pldamp::analytic::Contact<double>::from_e(p, e, 1.0).alpha();
  const pldamp::solvers::Problem<double> problem{p, 1.0, 1.0, 0.42, alpha};
  pldamp::solvers::Options<double> options;
  options.rtol = std::numeric_limits<double>::epsilon();
  options.want = pldamp::solvers::want_all;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pldamp::solvers::solve("taylor", problem, options));
  }
}
BENCHMARK(answer_solve_alone)->Unit(benchmark::kMicrosecond);

void plan(benchmark::State& state) {
  std::size_t cells = 0;
  for (auto _ : state) {
    const Plan p = make_plan(load_scene(scene_path));
    cells = p.cells.size();
    benchmark::DoNotOptimize(p);
  }
  state.counters["cells"] = double(cells);
  state.counters["per_cell"] =
      benchmark::Counter(double(state.iterations()) * double(cells),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(plan)->Unit(benchmark::kMillisecond);

void run_overhead(benchmark::State& state) {
  Plan p = make_plan(load_scene(scene_path));
  p.scene.repeats = 1; // each solver runs once: its wall_seconds is all its time
  double overhead = 0;
  std::size_t records = 0;
  for (auto _ : state) {
    RunTotals totals;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<Record> r = run_plan(p, 1, totals);
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    double solver_seconds = 0;
    for (const Record& record : r) {
      solver_seconds += record.wall_seconds;
    }
    overhead += took.count() - solver_seconds;
    records += r.size();
  }
  state.counters["overhead_us_per_record"] = 1e6 * overhead / double(records);
}
BENCHMARK(run_overhead)->Unit(benchmark::kMillisecond)->Iterations(3);

void budgets_and_reports(benchmark::State& state) {
  const Plan p = make_plan(load_scene(scene_path));
  RunTotals totals;
  const std::vector<Record> records = run_plan(p, 2, totals);
  const std::vector<Figure> figures;
  for (auto _ : state) {
    const Budgets b = make_budgets(p, records);
    const RunReport report{p, records, b, totals, figures};
    benchmark::DoNotOptimize(report_json(report).dump());
    benchmark::DoNotOptimize(report_csv(report));
    benchmark::DoNotOptimize(report_markdown(report));
  }
  state.counters["per_record"] =
      benchmark::Counter(double(state.iterations()) * double(records.size()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(budgets_and_reports)->Unit(benchmark::kMillisecond);

void records_as_bytes(benchmark::State& state) {
  const Plan p = make_plan(load_scene(scene_path));
  RunTotals totals;
  const std::vector<Record> records = run_plan(p, 2, totals);
  std::size_t bytes = 0;
  for (auto _ : state) {
    std::string message;
    append_records(message, records);
    bytes = message.size();
    benchmark::DoNotOptimize(read_records(message, "bench"));
  }
  state.counters["bytes_per_record"] = double(bytes) / double(records.size());
  state.counters["per_record"] =
      benchmark::Counter(double(state.iterations()) * double(records.size()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(records_as_bytes)->Unit(benchmark::kMillisecond);

void report_objects(benchmark::State& state) {
  std::string text = R"({"schema": )" + std::to_string(schema::version) +
                     R"(, "claims": [], "records": [], "x": [{})";
  for (long i = 1; i < state.range(0); ++i) {
    text += ",{}";
  }
  text += "]}";
  for (auto _ : state) {
    benchmark::DoNotOptimize(schema::read_report(text, "bench.json"));
  }
  state.counters["per_object"] =
      benchmark::Counter(double(state.iterations()) * double(state.range(0)),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(report_objects)->Arg(100000)->Arg(300000)->Unit(benchmark::kMillisecond);

void external_protocol(benchmark::State& state) {
  std::string v0s;
  for (int i = 1; i <= 5000; ++i) {
    v0s += (v0s.empty() ? "" : ", ") + std::to_string(i);
  }
  const Plan p = make_plan(parse_scene("want = [\"e\", \"delta_max\", \"t_peak\", \"tau\"]\n"
                                       "[grid]\np = [1]\ne = [0.5]\nv0 = [" +
                                           v0s +
                                           "]\n[[solver]]\ncommand = [\"" PLDAMP_ANSWERING_ADAPTER
                                           "\"]\nlabel = \"answers at once\"\n",
                                       "protocol.toml"));
  std::size_t records = 0;
  for (auto _ : state) {
    RunTotals totals;
    const std::vector<Record> r = run_plan(p, 1, totals);
    records += r.size();
    if (r.front().failed()) {
      state.SkipWithError(r.front().failure.c_str());
    }
  }
  state.counters["per_record"] = benchmark::Counter(
      double(records), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(external_protocol)->Unit(benchmark::kMillisecond)->UseRealTime();

void paper_claims(benchmark::State& state) {
  const Scene scene = load_scene(std::string(PLDAMP_DATA_DIR) + "/scenes/paper.toml");
  const int jobs = static_cast<int>(state.range(0));
  for (auto _ : state) {
    for (const Claim& claim : scene.claims) {
      if (claim.claim_kind() != ClaimKind::bound) { // the paper states none
        benchmark::DoNotOptimize(judge_on_grid(scene, claim, jobs));
      }
    }
  }
  state.counters["jobs"] = jobs;
}
BENCHMARK(paper_claims)
    ->Arg(1)
    ->Arg(all_cores())
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

void timestep(benchmark::State& state) {
  const std::string tolerance = fmt::format("1e-{}", state.range(0));
  const std::vector<const char*> argv{
      "pldamp", "timestep", "--scheme",    "dem-verlet",      "--p",   "1.5", "--e", "0.5",
      "--v0",   "1",        "--tolerance", tolerance.c_str(), "--json"};
  for (auto _ : state) {
    std::ostringstream out, err;
    if (run_cli(static_cast<int>(argv.size()), argv.data(), out, err) != 0) {
      state.SkipWithError(err.str().c_str());
      break;
    }
    benchmark::DoNotOptimize(out.str());
  }
}
BENCHMARK(timestep)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->Iterations(3);

} // namespace
