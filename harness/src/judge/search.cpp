#include "judge/search.hpp"

#include "common/observables.hpp"
#include "common/parallel.hpp"
#include "judge/budget.hpp"
#include "judge/claims.hpp"
#include "run/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pldamp::harness {
namespace {

// The scan's density: values a decade apart by 10^(1/8) = 1.33.
constexpr double scan_per_decade = 8;

bool fixed_step(const Search& search) {
  return search.parameter != SearchParameter::rtol;
}

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

// The values a search checks beyond its answer, up to `edge` (twice as tight): every step count
// after the answer, or band_values of them log-spaced.
constexpr int band_values = 16;
std::vector<double> band_between(SearchParameter parameter, double answer, double edge) {
  std::vector<double> values;
  if (parameter == SearchParameter::steps_per_contact) {
    const double low = std::min(answer, edge), high = std::max(answer, edge);
    if (high - low <= 2 * band_values) {
      for (double n = low + 1; n <= high; ++n) {
        values.push_back(n);
      }
      return values;
    }
  }
  for (int i = 1; i <= band_values; ++i) {
    double value = answer * std::pow(edge / answer, double(i) / band_values);
    if (parameter == SearchParameter::steps_per_contact) {
      value = std::round(value);
    }
    if (value != answer && (values.empty() || value != values.back())) {
      values.push_back(value);
    }
  }
  return values;
}

} // namespace

std::vector<std::string> search_observable_keys(const Search& search) {
  std::vector<std::string> keys{search.observable};
  keys.insert(keys.end(), search.more_observables.begin(), search.more_observables.end());
  return keys;
}

unsigned judged_want(const Search& search) {
  unsigned want = 0;
  for (const std::string& key : search_observable_keys(search)) {
    want |= find_observable(key)->solver_want;
  }
  return want;
}

std::vector<std::pair<std::string, Scene>> search_groups_of(const Scene& scene,
                                                            const Search& search) {
  Scene base = with_cells(scene, search.grid);
  base.damping = search.grid.damping;
  base.claims.clear();
  base.searches.clear();
  base.figures.clear();
  base.repeats = 1;
  base.configs = {search.config};
  // Only what the search judges is solved for (and its worst sought over every onset phase), and
  // with δ_max the peak's time: where its step changes, δ_max has a kink (phase_supremum.hpp).
  base.want = judged_want(search);
  if ((base.want & solvers::want_delta_max) != 0) {
    base.want |= solvers::want_t_peak;
  }
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

namespace {

// Whether two trial values are close enough to stop: neighbours for an integer parameter, within
// 2 % for a step, 12 % for a tolerance.
bool resolved(SearchParameter parameter, double a, double b) {
  switch (parameter) {
  case SearchParameter::steps_per_contact:
    return std::abs(a - b) <= 1;
  case SearchParameter::dt:
    return std::abs(std::log(a / b)) <= std::log(1.02);
  case SearchParameter::rtol:
    break;
  }
  return std::abs(std::log(a / b)) <= std::log(1.12);
}

// The geometric mean, an integer for steps per contact.
double middle(SearchParameter parameter, double a, double b) {
  const double mean = std::sqrt(a * b);
  return parameter == SearchParameter::steps_per_contact ? std::round(mean) : mean;
}

} // namespace

std::vector<double> search_scan(const Search& search) {
  const double tightest = search.range[0], loosest = search.range[1];
  const double decades = std::abs(std::log10(loosest / tightest));
  const int intervals = std::max(1, static_cast<int>(std::ceil(decades * scan_per_decade)));
  std::vector<double> values;
  for (int i = 0; i <= intervals; ++i) {
    double value =
        i == intervals ? loosest : tightest * std::pow(loosest / tightest, double(i) / intervals);
    if (search.parameter == SearchParameter::steps_per_contact) {
      value = std::round(value);
    }
    if (values.empty() || value != values.back()) {
      values.push_back(value);
    }
  }
  return values;
}

GroupTrials::GroupTrials(std::string name, const Scene& group_scene, const Search& search,
                         const Workers& workers)
    : name_(std::move(name)), plan_(make_plan(group_scene)), search_(search),
      judged_want_(judged_want(search)), workers_(workers) {}

const GroupTrials::Trial* GroupTrials::kept(double value, int phases, double bound) const {
  const auto found = trials_.find(std::make_pair(value, phases));
  if (found == trials_.end()) {
    return nullptr;
  }
  const Trial& trial = found->second;
  const bool usable = !trial.measured || *trial.measured <= trial.enough || *trial.measured > bound;
  return usable ? &trial : nullptr;
}

const GroupTrials::Trial& GroupTrials::trial(double value, int phases, double bound) {
  if (const Trial* known = kept(value, phases, bound)) {
    return *known;
  }
  long runs = 0;
  Trial computed = compute(plan_, workers_, value, phases, bound, runs);
  solver_runs_ += runs;
  return trials_.insert_or_assign(std::make_pair(value, phases), std::move(computed)).first->second;
}

void GroupTrials::prefetch(const std::vector<double>& values, int phases, double bound) {
  std::vector<double> missing;
  for (const double value : values) {
    if (kept(value, phases, bound) == nullptr &&
        std::find(missing.begin(), missing.end(), value) == missing.end()) {
      missing.push_back(value);
    }
  }
  // Trials side by side: each on a copy of the plan, one thread each. Not with MPI ranks (their
  // trials must follow one another alike) nor an external program (one process per plan).
  if (missing.size() < 2 || workers_.jobs < 2 || workers_.shared() ||
      plan_.configs.front().external()) {
    return;
  }
  std::vector<long> runs(missing.size(), 0);
  std::vector<Trial> computed =
      map_indices<Trial>(missing.size(), workers_.jobs, [&](std::size_t i) {
        Plan copy = plan_;
        return compute(copy, Workers(1), missing[i], phases, bound, runs[i]);
      });
  for (std::size_t i = 0; i < missing.size(); ++i) {
    solver_runs_ += runs[i];
    trials_.insert_or_assign(std::make_pair(missing[i], phases), std::move(computed[i]));
  }
}

GroupTrials::Trial GroupTrials::compute(Plan& plan, const Workers& workers, double value,
                                        int phases, double bound, long& runs) const {
  SolverConfig& config = plan.configs.front();
  set_parameter(config, search_.parameter, value);
  config.onset_phases = phases;
  config.every_phase = fixed_step(search_) ? judged_want_ : 0;
  // A relative bound: the worst of a relative error is sought no further than past it (the value
  // fails whatever the worst is). The seeking maximizes relative errors, so an absolute bound
  // does not stop it.
  config.every_phase_enough = search_.relative ? bound : std::numeric_limits<double>::infinity();
  RunTotals totals;
  const std::vector<Record> records = run_plan(plan, workers, totals);
  runs = totals.solver_runs;
  // The observables judged: the search's, then any more (`pldamp timestep`); a cell's error is
  // the largest over them, and its onset phase that observable's worst.
  const std::vector<std::string> keys = search_observable_keys(search_);
  std::vector<std::size_t> columns;
  for (const std::string& wanted : keys) {
    columns.push_back(static_cast<std::size_t>(
        std::find_if(plan.observables.begin(), plan.observables.end(),
                     [&](const Observable* o) { return o->key == wanted; }) -
        plan.observables.begin()));
  }
  Trial trial;
  std::vector<double> errors;
  std::vector<std::string> where;
  std::vector<std::optional<double>> phase_of;
  for (const Record& record : records) {
    const std::string cell = cell_text(plan, plan.cells[record.cell]);
    if (record.failed()) {
      trial.failure = fmt::format("{} at {}{}", record.outcome_name(), cell,
                                  record.failure.empty() ? "" : " (" + record.failure + ")");
      break;
    }
    std::optional<double> largest, phase;
    for (std::size_t i = 0; i < columns.size() && trial.failure.empty(); ++i) {
      const std::optional<double>& error =
          (search_.relative ? record.rel_error : record.abs_error)[columns[i]];
      if (!error) { // a cell it cannot judge fails it, as a claim (claims.hpp)
        trial.failure = fmt::format("no value of {} at {}{}", keys[i], cell,
                                    record.note.empty() ? "" : " (" + record.note + ")");
      } else if (!largest || *error > *largest) {
        largest = *error;
        phase = record.worst_phase[columns[i]];
      }
    }
    if (!trial.failure.empty()) {
      break;
    }
    errors.push_back(*largest);
    where.push_back(cell);
    phase_of.push_back(phase);
  }
  if (trial.failure.empty()) {
    const std::size_t at = nearest_rank(errors, search_.quantile);
    trial.measured = errors[at];
    trial.worst = where[at];
    trial.worst_phase = phase_of[at];
  }
  trial.enough = config.every_phase_enough;
  return trial;
}

bool GroupTrials::holds(const Trial& trial, double bound) const {
  return trial.failure.empty() && trial.measured && *trial.measured <= bound;
}

SearchGroup GroupTrials::answer(std::optional<double> bound_given) {
  const double bound = bound_given.value_or(search_.bound);
  const std::vector<double> scan = search_scan(search_);
  const int phases = fixed_step(search_) ? search_.onset_phases : 1;
  SearchGroup group;
  group.group = name_;
  group.onset_phases = phases;
  group.every_phase = fixed_step(search_);
  std::vector<double> tried;
  auto attempt = [&](double value) -> const Trial& {
    if (std::find(tried.begin(), tried.end(), value) == tried.end()) {
      tried.push_back(value);
    }
    return trial(value, phases, bound);
  };
  // Bisects between a value that held and one that failed; returns the loosest that held and sets
  // group.failing.
  auto bisect = [&](double held, double broke) {
    while (!resolved(search_.parameter, held, broke)) {
      const double mid = middle(search_.parameter, held, broke);
      if (mid == held || mid == broke) {
        break;
      }
      (holds(attempt(mid), bound) ? held : broke) = mid;
    }
    group.failing = broke;
    return held;
  };
  // The loosest of the scan's values tighter than `than` that holds.
  auto tighter_held = [&](double than) -> std::optional<double> {
    for (std::size_t i = scan.size(); i-- > 0;) { // loosest first
      if ((search_.parameter == SearchParameter::steps_per_contact ? scan[i] > than
                                                                   : scan[i] < than) &&
          holds(attempt(scan[i]), bound)) {
        return scan[i];
      }
    }
    return std::nullopt;
  };
  // The scan from the tightest end to the first failure, then the bisection there.
  std::size_t first_failure = scan.size();
  const auto threads = static_cast<std::size_t>(std::max(workers_.jobs, 1));
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (i % threads == 0) { // the next values side by side (the scan stops at a failure)
      prefetch({scan.begin() + static_cast<std::ptrdiff_t>(i),
                scan.begin() + static_cast<std::ptrdiff_t>(std::min(scan.size(), i + threads))},
               phases, bound);
    }
    ++group.scanned;
    if (!holds(attempt(scan[i]), bound)) {
      first_failure = i;
      break;
    }
  }
  if (first_failure == 0) {
    const Trial& tight = trial(scan[0], phases, bound);
    group.failing = scan[0];
    group.measured = tight.measured;
    group.worst = tight.worst;
    group.note = tight.failure.empty()
                     ? "the bound fails even at the tightest value of the range"
                     : "a record fails at the tightest value of the range: " + tight.failure;
  } else if (first_failure == scan.size()) {
    group.loosest = scan.back();
    group.note =
        fmt::format("the bound holds over the whole range ({} values scanned)", scan.size());
  } else {
    group.loosest = bisect(scan[first_failure - 1], scan[first_failure]);
  }
  // The scan sees the error at 8 values a decade, and between two of them it could rise above the
  // bound and fall again (when the phases were sampled it did: a report answered 546 steps per
  // contact for e within 1e-4 where counts from 548 to 600 failed). So values up to twice as tight
  // as the answer are checked too (each step count when there are at most 16, else 8 log-spaced;
  // a first-order error is half the bound there; 16 before the worst was over every phase, 8 now
  // to keep `timestep` under a second), and where one fails the answer is sought again tighter
  // than the tightest that fails, until the band holds.
  while (fixed_step(search_) && group.loosest) {
    const bool steps = search_.parameter == SearchParameter::steps_per_contact;
    const double answer = *group.loosest;
    const double edge = steps ? std::min(2 * answer, scan.front()) // the range's tight end
                              : std::max(answer / 2, scan.front());
    std::optional<double> failed; // the tightest value of the band that fails
    const std::vector<double> band = band_between(search_.parameter, answer, edge);
    prefetch(band, phases, bound);
    for (const double value : band) {
      if (!holds(attempt(value), bound) &&
          (!failed || (steps ? value > *failed : value < *failed))) {
        failed = value;
      }
    }
    if (!failed) {
      break;
    }
    ++group.band_refinements;
    if (const std::optional<double> held = tighter_held(*failed)) {
      group.loosest = bisect(*held, *failed);
    } else {
      group.loosest.reset();
      group.failing = scan.front();
      group.note = "the bound fails even at the tightest value";
    }
  }
  if (group.loosest) {
    const Trial& best = trial(*group.loosest, phases, bound);
    group.measured = best.measured;
    group.worst = best.worst;
    group.worst_onset_phase = best.worst_phase;
  }
  if (group.failing) {
    const Trial& beyond = trial(*group.failing, phases, bound);
    group.failing_measured = beyond.measured;
    group.failing_onset_phase = beyond.worst_phase;
    if (!beyond.failure.empty() && first_failure > 0) {
      group.note += (group.note.empty() ? "" : "; ") + ("beyond it: " + beyond.failure);
    }
  }
  group.trials = static_cast<int>(tried.size());
  group.solver_runs = solver_runs_;
  return group;
}

std::string search_measure(const Search& search) {
  return fmt::format("the {} {} error of {} over the group's cells{}",
                     search.quantile == 1 ? std::string("largest")
                                          : fmt::format("{:g} quantile of the", search.quantile),
                     search.relative ? "relative" : "absolute", search.observable,
                     fixed_step(search) ? " and every onset phase" : "");
}

double search_runs_estimate(const Search& search) {
  const double cells = double(search.grid.p.size()) * double(search.grid.damping.size()) *
                       double(grid_scales(search.grid).size());
  // The scan, a bisection of one of its intervals (to 1 %), and for a fixed step the band of 16
  // values beyond the answer, each over the sampled phases and the refinement to every phase
  // (about two jumps bisected to 2^-52 and a Brent search per observable and maximum: ~150).
  const double bisection =
      std::ceil(std::log2(std::log(std::pow(10.0, 1 / scan_per_decade)) / std::log(1.01))) + 1;
  const double values = double(search_scan(search).size()) + bisection;
  if (!fixed_step(search)) {
    return cells * values;
  }
  return cells * (search.onset_phases + phase_refinement_runs) * (values + band_values);
}

// A group's answer as a piece of a map shared among MPI ranks (run/workers.hpp), every field.
static_assert(sizeof(SearchGroup) == 224, "a new SearchGroup field: write and read it below");
void put_piece(ByteWriter& out, const std::optional<SearchGroup>& answer) {
  Encoding<bool>::put(out, answer.has_value());
  if (!answer) {
    return;
  }
  const SearchGroup& g = *answer;
  out.put(g.group);
  for (const std::optional<double>* value :
       {&g.loosest, &g.failing, &g.measured, &g.worst_onset_phase, &g.failing_measured,
        &g.failing_onset_phase}) {
    out.put(*value);
  }
  out.put(g.worst);
  for (const int count : {g.trials, g.scanned, g.onset_phases, g.band_refinements}) {
    out.put<std::int32_t>(count);
  }
  Encoding<bool>::put(out, g.every_phase);
  out.put<std::int64_t>(g.solver_runs);
  out.put(g.note);
}
void get_piece(ByteReader& in, std::optional<SearchGroup>& answer) {
  if (!Encoding<bool>::get(in)) {
    answer.reset();
    return;
  }
  SearchGroup& g = answer.emplace();
  g.group = in.string();
  for (std::optional<double>* value : {&g.loosest, &g.failing, &g.measured, &g.worst_onset_phase,
                                       &g.failing_measured, &g.failing_onset_phase}) {
    *value = in.optional();
  }
  g.worst = in.string();
  for (int* count : {&g.trials, &g.scanned, &g.onset_phases, &g.band_refinements}) {
    *count = in.get<std::int32_t>();
  }
  g.every_phase = Encoding<bool>::get(in);
  g.solver_runs = in.get<std::int64_t>();
  g.note = in.string();
}

SearchResult run_search(const Scene& scene, const Search& search, const Workers& workers) {
  SearchResult result;
  result.name = search.name;
  result.where = search.where;
  result.quote = search.quote;
  result.line = search.config.line();
  result.parameter = std::string(name_of(search_parameters, search.parameter));
  result.observable = search.observable;
  result.measure = search_measure(search);
  result.bound = search.bound;
  // The groups on the threads (and the ranks), each trial's cells on the threads left over
  // (common/parallel.hpp); a group not begun when a stop was asked for ends the list. With fewer
  // groups than ranks, the groups one after the other, each trial's cells shared among the ranks
  // (whose trials, the same on every rank, then follow one another alike).
  const std::vector<std::pair<std::string, Scene>> groups = search_groups_of(scene, search);
  std::vector<std::optional<SearchGroup>> answers;
  if (workers.shared() && groups.size() < static_cast<std::size_t>(workers.ranks->size())) {
    for (const auto& [name, group_scene] : groups) {
      answers.push_back(GroupTrials(name, group_scene, search, workers).answer());
    }
  } else {
    const int per_group =
        std::max(1, workers.jobs / static_cast<int>(std::max<std::size_t>(groups.size(), 1)));
    answers = map_shared<std::optional<SearchGroup>>(
        groups.size(), workers, [&](std::size_t g) -> std::optional<SearchGroup> {
          if (stop_requested()) {
            return std::nullopt;
          }
          GroupTrials trials(groups[g].first, groups[g].second, search, per_group);
          return trials.answer();
        });
  }
  for (const std::optional<SearchGroup>& answer : answers) {
    if (!answer) {
      break;
    }
    result.groups.push_back(*answer);
    result.solver_runs += answer->solver_runs;
  }
  return result;
}

} // namespace pldamp::harness
