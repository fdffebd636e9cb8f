#include "judge/search.hpp"

#include "judge/budget.hpp"
#include "judge/claims.hpp"
#include "run/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pldamp::harness {
namespace {

// The parameter at a trial value, in the configuration.
void set_parameter(SolverConfig& config, SearchParameter parameter, double value) {
  switch (parameter) {
  case SearchParameter::rtol:
    config.rtol = value;
    break;
  case SearchParameter::steps_per_contact:
    config.steps_per_contact = static_cast<int>(value);
    break;
  case SearchParameter::dt:
    config.dt = value;
    break;
  }
}

// The group scenes of a search: its grid split by p, damping, both, or not at all.
std::vector<std::pair<std::string, Scene>> groups_of(const Scene& scene, const Search& search) {
  Scene base = scene;
  base.p = search.grid.p;
  base.damping = search.grid.damping;
  base.v0 = search.grid.v0;
  base.m = search.grid.m;
  base.k = search.grid.k;
  base.claims.clear();
  base.searches.clear();
  base.figures.clear();
  base.repeats = 1;
  base.configs = {search.config};
  std::vector<std::pair<std::string, Scene>> groups;
  const bool by_p = search.group_by == SearchGroups::p || search.group_by == SearchGroups::point;
  const bool by_damping =
      search.group_by == SearchGroups::damping || search.group_by == SearchGroups::point;
  const std::vector<double> ps = by_p ? base.p : std::vector<double>{0};
  const std::vector<Damping> dampings = by_damping ? base.damping : std::vector<Damping>{{}};
  for (const double p : ps) {
    for (const Damping& damping : dampings) {
      Scene group = base;
      std::string name;
      if (by_p) {
        group.p = {p};
        name = fmt::format("p = {:g}", p);
      }
      if (by_damping) {
        group.damping = {damping};
        name += (name.empty() ? "" : ", ") + damping_text(damping);
      }
      groups.emplace_back(name.empty() ? "all cells" : name, group);
    }
  }
  return groups;
}

struct Trial {
  bool holds = false;
  std::optional<double> measured;
  std::string worst, failure;
};

Trial try_value(Plan& plan, const Search& search, double value, int jobs, long& runs) {
  set_parameter(plan.configs.front(), search.parameter, value);
  RunTotals totals;
  const std::vector<Record> records = run_plan(plan, jobs, totals);
  runs += totals.solver_runs;
  const auto observable = static_cast<std::size_t>(
      std::find_if(plan.observables.begin(), plan.observables.end(),
                   [&](const Observable* o) { return o->key == search.observable; }) -
      plan.observables.begin());
  Trial trial;
  std::vector<double> errors;
  std::vector<std::string> where;
  for (const Record& record : records) {
    if (record.failed()) {
      trial.failure =
          fmt::format("{} at {}", record.outcome_name(), cell_text(plan, plan.cells[record.cell]));
      return trial;
    }
    const std::optional<double>& error =
        (search.relative ? record.rel_error : record.abs_error)[observable];
    if (error) {
      errors.push_back(*error);
      where.push_back(cell_text(plan, plan.cells[record.cell]));
    }
  }
  if (errors.empty()) {
    trial.failure = "no cell gave " + search.observable;
    return trial;
  }
  const std::size_t at = nearest_rank(errors, search.quantile);
  trial.measured = errors[at];
  trial.worst = where[at];
  trial.holds = errors[at] <= search.bound;
  return trial;
}

// Whether two trial values are close enough to stop: neighbours for an integer parameter, within
// 12 % of each other otherwise.
bool resolved(SearchParameter parameter, double a, double b) {
  if (parameter == SearchParameter::steps_per_contact) {
    return std::abs(a - b) <= 1;
  }
  return std::abs(std::log(a / b)) <= std::log(1.12);
}

// The geometric mean, an integer for steps per contact.
double middle(SearchParameter parameter, double a, double b) {
  const double mean = std::sqrt(a * b);
  return parameter == SearchParameter::steps_per_contact ? std::round(mean) : mean;
}

SearchGroup search_group(const std::string& name, const Scene& scene, const Search& search,
                         int jobs) {
  SearchGroup group;
  group.group = name;
  Plan plan = make_plan(scene);
  auto attempt = [&](double value) {
    ++group.trials;
    return try_value(plan, search, value, jobs, group.solver_runs);
  };
  const double tightest = search.range[0], loosest = search.range[1];
  Trial tight = attempt(tightest);
  if (!tight.holds) {
    group.failing = tightest;
    group.measured = tight.measured;
    group.worst = tight.worst;
    group.note = tight.failure.empty()
                     ? "the bound fails even at the tightest value of the range"
                     : "a record fails at the tightest value of the range: " + tight.failure;
    return group;
  }
  Trial loose = attempt(loosest);
  if (loose.holds) {
    group.loosest = loosest;
    group.measured = loose.measured;
    group.worst = loose.worst;
    group.note = "the bound holds over the whole range";
    return group;
  }
  double held = tightest, broke = loosest;
  Trial best = tight;
  while (!resolved(search.parameter, held, broke)) {
    const double mid = middle(search.parameter, held, broke);
    if (mid == held || mid == broke) {
      break;
    }
    Trial trial = attempt(mid);
    if (trial.holds) {
      held = mid;
      best = trial;
    } else {
      broke = mid;
    }
  }
  group.loosest = held;
  group.failing = broke;
  group.measured = best.measured;
  group.worst = best.worst;
  // The bisection assumed the error grows as the parameter loosens. Checked at the powers of ten
  // strictly between the tightest value and the answer (an adaptive solver's error is not
  // monotone in its tolerance): one that breaks the bound is said.
  const double decade_from = std::log10(std::min(tightest, held));
  const double decade_to = std::log10(std::max(tightest, held));
  for (double decade = std::floor(decade_from) + 1; decade < decade_to; ++decade) {
    const double value = std::pow(10.0, decade);
    if (!resolved(search.parameter, value, tightest) && !resolved(search.parameter, value, held) &&
        !attempt(value).holds) {
      group.note = fmt::format("not monotone: the bound also breaks at {:g}, tighter than the "
                               "answer",
                               value);
      break;
    }
  }
  return group;
}

} // namespace

std::string search_measure(const Search& search) {
  return fmt::format("the {} {} error of {} over the group's cells",
                     search.quantile == 1 ? std::string("largest")
                                          : fmt::format("{:g} quantile of the", search.quantile),
                     search.relative ? "relative" : "absolute", search.observable);
}

double search_runs_estimate(const Search& search) {
  const double cells = double(search.grid.p.size()) * double(search.grid.damping.size()) *
                       double(search.grid.v0.size()) * double(search.grid.m.size()) *
                       double(search.grid.k.size());
  // Two ends, halvings of the log-range down to 12 % (or to neighbouring integers), then the
  // powers of ten between.
  const double span = std::abs(std::log(search.range[1] / search.range[0]));
  return cells * (2 + std::ceil(std::log2(std::max(1.0, span / std::log(1.12)))) +
                  std::ceil(span / std::log(10.0)));
}

SearchResult run_search(const Scene& scene, const Search& search, int jobs) {
  SearchResult result;
  result.name = search.name;
  result.where = search.where;
  result.quote = search.quote;
  result.line = search.config.line();
  result.parameter = std::string(name_of(search_parameters, search.parameter));
  result.observable = search.observable;
  result.measure = search_measure(search);
  result.bound = search.bound;
  for (const auto& [name, group_scene] : groups_of(scene, search)) {
    if (stop_requested()) {
      break;
    }
    result.groups.push_back(search_group(name, group_scene, search, jobs));
    result.solver_runs += result.groups.back().solver_runs;
  }
  return result;
}

} // namespace pldamp::harness
