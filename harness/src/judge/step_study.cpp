#include "judge/step_study.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <algorithm>
#include <cmath>
#include <map>

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
std::vector<StepSweep> sweeps_of(const Plan& plan) {
  std::map<std::string, std::vector<std::size_t>> groups;
  std::vector<std::string> order;
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const SolverConfig& config = plan.configs[c];
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
    std::vector<std::size_t> configs = groups[line];
    if (configs.size() < 2) {
      continue;
    }
    std::sort(configs.begin(), configs.end(), [&](std::size_t a, std::size_t b) {
      return *plan.configs[a].steps_per_contact < *plan.configs[b].steps_per_contact;
    });
    sweeps.push_back({line, configs, {}, {}, {}});
  }
  return sweeps;
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

// The steps per contact where a cell's error falls to `target` for good, interpolated in log-log
// between the last sweep point above it and the next; `points` are (τ/Δt, error), coarse to fine.
StepsNeeded steps_for(const std::vector<std::pair<double, double>>& points, double target) {
  std::size_t first_good = points.size();
  for (std::size_t k = points.size(); k-- > 0;) {
    if (!(points[k].second <= target)) {
      break;
    }
    first_good = k;
  }
  if (first_good == points.size()) {
    return {std::nullopt, true};
  }
  if (first_good == 0) {
    return {points[0].first, false};
  }
  const auto [n_a, e_a] = points[first_good - 1];
  const auto [n_b, e_b] = points[first_good];
  if (!(e_b > 0) || !(e_a > e_b) || !std::isfinite(e_a)) {
    return {n_b, true};
  }
  const double fraction = (std::log(target) - std::log(e_a)) / (std::log(e_b) - std::log(e_a));
  return {std::exp(std::log(n_a) + fraction * (std::log(n_b) - std::log(n_a))), true};
}

} // namespace

StepStudy make_step_study(const Plan& plan, const std::vector<Record>& records) {
  StepStudy study;
  const std::optional<std::size_t> tau = index_of(plan, "tau"), e = index_of(plan, "e");
  if (!tau || !e) {
    return study;
  }
  study.sweeps = sweeps_of(plan);
  if (study.sweeps.empty()) {
    return study;
  }
  study.e = *e;
  const std::size_t observables = plan.observables.size(), ps = plan.scene.p.size(),
                    dampings = plan.scene.damping.size();
  for (const double p : plan.scene.p) {
    const auto undamped = analytic::Contact<double>::from_alpha(p, 0.0, 1.0);
    const double tau0 = analytic::undamped_duration(undamped);
    study.dt_crit_over_tau0.push_back(analytic::dt_crit_seed(undamped) / tau0);
    study.dt_tangent_over_tau0.push_back(analytic::dt_crit_tangent(undamped) / tau0);
  }
  // Records by (configuration, cell).
  std::map<std::pair<std::size_t, std::size_t>, const Record*> by_config_cell;
  for (const Record& record : records) {
    by_config_cell[{record.config, record.cell}] = &record;
  }
  for (StepSweep& sweep : study.sweeps) {
    const std::size_t configs = sweep.configs.size();
    sweep.points.assign(observables,
                        std::vector<std::vector<StepPoint>>(ps, std::vector<StepPoint>(configs)));
    sweep.order.assign(ps, std::nullopt);
    sweep.needed.assign(ps, {});
    std::vector<std::vector<long>> counts(ps, std::vector<long>(configs, 0));
    // Per p and target: the worst steps needed over the cells.
    std::vector<std::array<StepsNeeded, 3>> worst(ps);
    std::vector<std::array<bool, 3>> seen(ps, {false, false, false});
    for (std::size_t cell_index = 0; cell_index < plan.cells.size(); ++cell_index) {
      const Cell& cell = plan.cells[cell_index];
      const std::size_t p_index = cell.point / dampings;
      std::vector<std::pair<double, double>> e_by_steps; // (τ/Δt, error in e), coarse to fine
      for (std::size_t k = 0; k < configs; ++k) {
        const auto found = by_config_cell.find({sweep.configs[k], cell_index});
        const std::optional<Exact> truth =
            reference_at(plan, cell, *tau, plan.configs[sweep.configs[k]]);
        if (found == by_config_cell.end() || !found->second->dt || !truth || !isfinite(*truth)) {
          continue; // no return (overdamped): no contact duration to divide by
        }
        const Record& record = *found->second;
        if (record.skipped() || !record.note.empty()) {
          continue; // not run, or no truth to measure its error against
        }
        const double dt_over_tau = *record.dt / static_cast<double>(*truth);
        for (std::size_t o = 0; o < observables; ++o) {
          StepPoint& point = sweep.points[o][p_index][k];
          const std::optional<double>& error = record.rel_error[o];
          if (error && (!point.error || !(*error <= *point.error))) {
            point.error = std::isnan(*error) ? INFINITY : *error;
          }
          const std::optional<double>& spread = record.spread[o];
          if (spread && (!point.spread || *spread > *point.spread)) {
            point.spread = spread;
          }
        }
        sweep.points[*e][p_index][k].dt_over_tau += dt_over_tau; // a sum, then a mean
        ++counts[p_index][k];
        const std::optional<double>& e_error = record.rel_error[*e];
        e_by_steps.emplace_back(1 / dt_over_tau,
                                e_error ? *e_error : std::numeric_limits<double>::infinity());
      }
      if (e_by_steps.size() < 2) {
        continue;
      }
      for (std::size_t t = 0; t < step_targets.size(); ++t) {
        const StepsNeeded needed = steps_for(e_by_steps, step_targets[t]);
        StepsNeeded& w = worst[p_index][t];
        if (!seen[p_index][t]) {
          w = needed;
          seen[p_index][t] = true;
        } else if (!w.steps || !needed.steps) {
          w = {std::nullopt, true};
        } else if (*needed.steps > *w.steps || (needed.within_sweep && !w.within_sweep)) {
          w = {std::max(*needed.steps, *w.steps), needed.within_sweep || w.within_sweep};
        }
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
      sweep.needed[i] = worst[i];
    }
  }
  return study;
}

} // namespace pldamp::harness
