#include "judge/step_study.hpp"

#include "common/parallel.hpp"
#include "judge/search.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace pldamp::harness {
namespace {

std::optional<std::size_t> index_of(const Plan& plan, std::string_view key) {
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    if (plan.observables[o]->key == key) {
      return o;
    }
  }
  return std::nullopt;
}

// The sweeps: fixed-step configurations with a steps-per-contact value, grouped by line, coarse
// to fine; only groups of two or more.
std::vector<StepSweep> sweeps_of(const std::vector<SolverConfig>& configs) {
  std::map<std::string, std::vector<std::size_t>> groups;
  std::vector<std::string> order;
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const SolverConfig& config = configs[c];
    if (!config.steps_per_contact || !config.fixed_step()) {
      continue;
    }
    if (groups.find(config.line()) == groups.end()) {
      order.push_back(config.line());
    }
    groups[config.line()].push_back(c);
  }
  std::vector<StepSweep> sweeps;
  for (const std::string& line : order) {
    std::vector<std::size_t> members = groups[line];
    if (members.size() < 2) {
      continue;
    }
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
      return *configs[a].steps_per_contact < *configs[b].steps_per_contact;
    });
    StepSweep sweep;
    sweep.line = line;
    sweep.configs = members;
    sweeps.push_back(sweep);
  }
  return sweeps;
}

bool compares_e_and_tau(const Scene& scene) {
  const std::vector<const Observable*> wanted = observables_of(scene.want);
  auto has = [&](std::string_view key) {
    return std::any_of(wanted.begin(), wanted.end(),
                       [&](const Observable* observable) { return observable->key == key; });
  };
  return has("e") && has("tau");
}

// The search that answers "how many steps per contact keep e within `target`" for a sweep at one
// (p, damping) point, over the sweep's range (judge/search.hpp).
Search study_search(const Scene& scene, const std::vector<SolverConfig>& configs,
                    const StepSweep& sweep, double p, const Damping& damping) {
  SolverConfig config = configs[sweep.configs.front()];
  config.steps_per_contact.reset();
  const int phases = Search{}.onset_phases; // sampled, then every phase sought
  Search search{
      .name = sweep.line,
      .where = {},
      .quote = {},
      .config = config,
      .parameter = SearchParameter::steps_per_contact,
      .range = {double(*configs[sweep.configs.back()].steps_per_contact),
                double(*configs[sweep.configs.front()].steps_per_contact)},
      .observable = "e",
      .bound = step_targets.front(),
      .relative = true,
      .group_by = SearchGroups::point,
      // One cell: at a given steps per contact and onset phase, e is the same at
      // every v0, m, k (MATH.md §7: the step is a fraction of the natural time).
      .grid = ClaimGrid{{p}, {scene.v0.front()}, {scene.m.front()}, {scene.k.front()}, {damping}},
      .onset_phases = phases};
  return search;
}

// An external program's answer, off its sweep: the coarsest sweep value from which every finer
// one held (the error at each point is the worst over the cells of its p and damping).
StepsNeeded needed_from_sweep(const std::vector<std::pair<double, double>>& by_steps,
                              double target) {
  StepsNeeded needed;
  needed.from_sweep = true;
  for (std::size_t k = by_steps.size(); k-- > 0;) { // fine to coarse
    if (!(by_steps[k].second <= target)) {
      break;
    }
    needed.steps = by_steps[k].first;
    needed.within_sweep = k > 0;
  }
  return needed;
}

// The least-squares slope of log y against log x.
std::optional<double> log_slope(const std::vector<std::pair<double, double>>& xy) {
  if (xy.size() < 2) {
    return std::nullopt;
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& [x, y] : xy) {
    const double lx = std::log(x), ly = std::log(y);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double n = double(xy.size()), denominator = n * sxx - sx * sx;
  if (denominator == 0) {
    return std::nullopt;
  }
  return (n * sxy - sx * sy) / denominator;
}

// The steps needed at one point of a sweep, for each of step_targets: the searches' answers (an
// external program's off its sweep, `by_steps` its worst error per configuration), with the
// phases they took and their solves.
struct PointSteps {
  std::array<StepsNeeded, 3> needed;
  int onset_phases = 0;
  long solver_runs = 0;
};

// A point's answer as a piece of a map shared among MPI ranks (run/workers.hpp), every field.
static_assert(sizeof(StepsNeeded) == 48, "a new StepsNeeded field: write and read it below");
void put_piece(ByteWriter& out, const PointSteps& point) {
  for (const StepsNeeded& each : point.needed) {
    out.put(each.steps);
    out.put(each.tau_over_dt);
    for (const bool flag : {each.within_sweep, each.from_sweep, each.returns}) {
      Encoding<bool>::put(out, flag);
    }
  }
  out.put<std::int32_t>(point.onset_phases);
  out.put<std::int64_t>(point.solver_runs);
}
void get_piece(ByteReader& in, PointSteps& point) {
  for (StepsNeeded& each : point.needed) {
    each.steps = in.optional();
    each.tau_over_dt = in.optional();
    for (bool* flag : {&each.within_sweep, &each.from_sweep, &each.returns}) {
      *flag = Encoding<bool>::get(in);
    }
  }
  point.onset_phases = in.get<std::int32_t>();
  point.solver_runs = in.get<std::int64_t>();
}

PointSteps steps_needed(const Plan& plan, const StepSweep& sweep,
                        const std::vector<double>& by_steps, std::size_t tau, const Point& point) {
  PointSteps out;
  std::array<StepsNeeded, 3>& needed = out.needed;
  const SolverConfig& first = plan.configs[sweep.configs.front()];
  // Overdamped, a contact still returns under the force cap (e_cap > 0, MATH.md §4).
  const bool returns = !point.overdamped || end_of(plan.scene, first) == solvers::End::force;
  if (!returns || !point.no_truth.empty()) {
    for (StepsNeeded& each : needed) {
      each.returns = false; // no return, so no restitution to keep within a bound
    }
    return out;
  }
  if (first.external()) {
    std::vector<std::pair<double, double>> errors;
    for (std::size_t k = 0; k < sweep.configs.size(); ++k) {
      errors.emplace_back(*plan.configs[sweep.configs[k]].steps_per_contact, by_steps[k]);
    }
    for (std::size_t t = 0; t < step_targets.size(); ++t) {
      needed[t] = needed_from_sweep(errors, step_targets[t]);
    }
  } else {
    const Search search = study_search(plan.scene, plan.configs, sweep, point.p, point.damping);
    const auto groups = search_groups_of(plan.scene, search);
    // One cell: its trials gain nothing from threads (the points are on them instead).
    GroupTrials trials(groups.front().first, groups.front().second, search, 1);
    for (std::size_t t = 0; t < step_targets.size(); ++t) {
      const SearchGroup answer = trials.answer(step_targets[t]);
      needed[t].steps = answer.loosest;
      needed[t].within_sweep = answer.failing.has_value();
      out.onset_phases = std::max(out.onset_phases, answer.onset_phases);
      out.solver_runs = answer.solver_runs; // the trials' solves so far: the bounds share them
    }
  }
  // τ/Δt at the answer: steps per contact × τ / (π δ_u/v0), at unit scale.
  const std::optional<Exact>& unit_tau =
      point.reference.at({alpha_precision(first), end_of(plan.scene, first)})[tau];
  for (StepsNeeded& each : needed) {
    if (each.steps && unit_tau && isfinite(*unit_tau)) {
      const double delta_u = std::pow((point.p + 1) / 2, 1 / (point.p + 1));
      each.tau_over_dt =
          *each.steps * static_cast<double>(*unit_tau) / (std::numbers::pi * delta_u);
    }
  }
  return out;
}

} // namespace

StepStudy make_step_study(const Plan& plan, RecordRange records, const Workers& workers) {
  StepStudy study;
  const std::optional<std::size_t> tau = index_of(plan, "tau"), e = index_of(plan, "e");
  if (!tau || !e) {
    return study;
  }
  study.sweeps = sweeps_of(plan.configs);
  if (study.sweeps.empty()) {
    return study;
  }
  study.e = *e;
  const std::size_t observables = plan.observables.size(), ps = plan.scene.p.size();
  for (const double p : plan.scene.p) {
    const auto undamped = analytic::Contact<double>::from_alpha(p, 0.0, 1.0);
    const double tau0 = analytic::undamped_duration(undamped);
    study.dt_crit_over_tau0.push_back(analytic::dt_crit_seed(undamped) / tau0);
    study.dt_tangent_over_tau0.push_back(analytic::dt_crit_tangent(undamped) / tau0);
  }
  auto p_index_of = [&](double p) {
    return static_cast<std::size_t>(std::find(plan.scene.p.begin(), plan.scene.p.end(), p) -
                                    plan.scene.p.begin());
  };
  // What the sweeps read of their configurations' records, by (configuration, cell): records are
  // read one at a time (a merge's are decoded as they are read, run/record_store.hpp).
  struct SweptRecord {
    bool skipped, noted;
    std::optional<double> dt;
    std::vector<std::optional<double>> rel_error, spread;
  };
  std::set<std::size_t> swept;
  for (const StepSweep& sweep : study.sweeps) {
    swept.insert(sweep.configs.begin(), sweep.configs.end());
  }
  std::map<std::pair<std::size_t, std::size_t>, SweptRecord> by_config_cell;
  for (const Record& record : records) {
    if (swept.contains(record.config)) {
      by_config_cell[{record.config, record.cell}] = {record.skipped(), !record.note.empty(),
                                                      record.dt, record.rel_error, record.spread};
    }
  }
  // by_steps_of[sweep][point][k]: the worst error in e over the point's cells at configuration k
  // (an external program's answer is read off it).
  std::vector<std::vector<std::vector<double>>> by_steps_of;
  for (StepSweep& sweep : study.sweeps) {
    const std::size_t configs = sweep.configs.size();
    sweep.points.assign(observables,
                        std::vector<std::vector<StepPoint>>(ps, std::vector<StepPoint>(configs)));
    sweep.order.assign(ps, std::nullopt);
    std::vector<std::vector<long>> counts(ps, std::vector<long>(configs, 0));
    std::vector<std::vector<double>> by_steps(plan.points.size(), std::vector<double>(configs, 0));
    for (std::size_t cell_index = 0; cell_index < plan.cells.size(); ++cell_index) {
      const Cell& cell = plan.cells[cell_index];
      const std::size_t p_index = p_index_of(plan.points[cell.point].p);
      for (std::size_t k = 0; k < configs; ++k) {
        const auto found = by_config_cell.find({sweep.configs[k], cell_index});
        const std::optional<Exact> truth =
            reference_at(plan, cell, *tau, plan.configs[sweep.configs[k]]);
        const SweptRecord* record = found == by_config_cell.end() ? nullptr : &found->second;
        const std::optional<double> e_error =
            record && !record->skipped ? record->rel_error[*e] : std::nullopt;
        by_steps[cell.point][k] = std::max(by_steps[cell.point][k],
                                           e_error && !std::isnan(*e_error) ? *e_error : INFINITY);
        if (!record || !record->dt || !truth || !isfinite(*truth)) {
          continue; // no return (overdamped): no contact duration to divide by
        }
        if (record->skipped || record->noted) {
          continue; // not run, or no truth to measure its error against
        }
        for (std::size_t o = 0; o < observables; ++o) {
          StepPoint& point = sweep.points[o][p_index][k];
          const std::optional<double>& error = record->rel_error[o];
          if (error && (!point.error || !(*error <= *point.error))) {
            point.error = std::isnan(*error) ? INFINITY : *error;
          }
          const std::optional<double>& spread = record->spread[o];
          if (spread && (!point.spread || *spread > *point.spread)) {
            point.spread = spread;
          }
        }
        // Δt/τ, a sum, then a mean
        sweep.points[*e][p_index][k].dt_over_tau += *record->dt / static_cast<double>(*truth);
        ++counts[p_index][k];
      }
    }
    for (std::size_t i = 0; i < ps; ++i) {
      std::vector<std::pair<double, double>> fine; // (Δt/τ, error in e) over the finest half
      for (std::size_t k = 0; k < configs; ++k) {
        const long n = counts[i][k];
        const double mean = n > 0 ? sweep.points[*e][i][k].dt_over_tau / double(n) : 0;
        for (std::size_t o = 0; o < observables; ++o) {
          sweep.points[o][i][k].dt_over_tau = mean;
        }
        const StepPoint& point = sweep.points[*e][i][k];
        if (n > 0 && k >= configs / 2 && point.error && *point.error > 0 &&
            std::isfinite(*point.error)) {
          fine.emplace_back(point.dt_over_tau, *point.error);
        }
      }
      sweep.order[i] = log_slope(fine);
    }
    by_steps_of.push_back(std::move(by_steps));
  }
  // The steps needed at every point of every sweep. An external program's are read off its
  // sweep's records (no solve; under MPI, rank 0 holds the records and alone reads them). pldamp's
  // own sweeps' points are searched on the threads and the ranks, then gathered in order
  // (common/parallel.hpp, run/workers.hpp): each point's searches are independent of the others'.
  const std::size_t points = plan.points.size();
  const auto needed_at = [&](std::size_t i) -> PointSteps {
    if (stop_requested()) {
      return {};
    }
    const std::size_t s = i / points, pi = i % points;
    return steps_needed(plan, study.sweeps[s], by_steps_of[s][pi], *tau, plan.points[pi]);
  };
  std::vector<PointSteps> found(study.sweeps.size() * points);
  std::vector<std::size_t> searched;
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (plan.configs[study.sweeps[i / points].configs.front()].external()) {
      found[i] = needed_at(i);
    } else {
      searched.push_back(i);
    }
  }
  const std::vector<PointSteps> searches = map_shared<PointSteps>(
      searched.size(), workers, [&](std::size_t k) { return needed_at(searched[k]); });
  for (std::size_t k = 0; k < searched.size(); ++k) {
    found[searched[k]] = searches[k];
  }
  for (std::size_t s = 0; s < study.sweeps.size(); ++s) {
    StepSweep& sweep = study.sweeps[s];
    sweep.by_point.assign(points, {});
    for (std::size_t pi = 0; pi < points; ++pi) {
      const PointSteps& at = found[s * points + pi];
      sweep.by_point[pi] = at.needed;
      sweep.onset_phases = std::max(sweep.onset_phases, at.onset_phases);
      sweep.solver_runs += at.solver_runs;
    }
    // Per p, the worst over its points: none if one is not reached; an upper bound if any is.
    sweep.needed.assign(ps, {});
    std::vector<bool> seen(ps, false);
    for (std::array<StepsNeeded, 3>& worst : sweep.needed) {
      for (StepsNeeded& each : worst) {
        each.returns = false; // until a returning point of that p is seen
      }
    }
    for (std::size_t pi = 0; pi < plan.points.size(); ++pi) {
      const std::size_t i = p_index_of(plan.points[pi].p);
      if (!sweep.by_point[pi].front().returns) {
        continue;
      }
      for (std::size_t t = 0; t < step_targets.size(); ++t) {
        const StepsNeeded& each = sweep.by_point[pi][t];
        StepsNeeded& worst = sweep.needed[i][t];
        if (!seen[i]) {
          worst = {each.steps, each.within_sweep, each.from_sweep, std::nullopt, true};
        } else if (!worst.steps || !each.steps) {
          worst = {std::nullopt, true, worst.from_sweep || each.from_sweep, std::nullopt, true};
        } else {
          worst = {std::max(*worst.steps, *each.steps), worst.within_sweep || each.within_sweep,
                   worst.from_sweep || each.from_sweep, std::nullopt, true};
        }
      }
      seen[i] = true;
    }
  }
  return study;
}

double step_study_runs_estimate(const Scene& scene) {
  if (!compares_e_and_tau(scene)) {
    return 0;
  }
  double runs = 0;
  for (const StepSweep& sweep : sweeps_of(scene.configs)) {
    if (scene.configs[sweep.configs.front()].external()) {
      continue;
    }
    for (const double p : scene.p) {
      for (const Damping& damping : scene.damping) {
        if (damping.kind == Damping::Kind::alpha_eff && damping.value >= 1 &&
            end_of(scene, scene.configs[sweep.configs.front()]) == solvers::End::overlap) {
          continue; // overdamped: no return, no search (make_step_study)
        }
        runs += search_runs_estimate(study_search(scene, scene.configs, sweep, p, damping));
      }
    }
  }
  return runs;
}

} // namespace pldamp::harness
