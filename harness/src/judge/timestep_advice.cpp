#include "judge/timestep_advice.hpp"

#include "common/observables.hpp"
#include "common/parallel.hpp"
#include "truth/plan.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace pldamp::harness {
namespace {

// The Δt range searched, in contact times τ: from τ/(30/tolerance), at most τ/1e5 (a step limit
// of 1e6 leaves room), to τ/2 (two steps a contact, beyond every scheme's accuracy). The schemes
// are first order: their answers lie between 0.7 and 8 steps per contact over the tolerance (the
// table of docs/timestep.md), so the scan begins nearly four times tighter than any answer, and
// each of its values costs a search over every onset phase of contacts 30/tolerance steps long.
constexpr double tightest_steps_per_contact = 1e5;
constexpr double steps_per_contact_per_tolerance = 30;
constexpr double loosest_steps_per_contact = 2;
// The onset phases each trial samples before its worst over every phase is sought from them
// (run/phase_supremum.hpp): more samples find the smooth maxima's neighbourhoods with fewer Brent
// steps, fewer cost less per trial.
constexpr int onset_phases = 16;

std::string word_of(const std::string& key) {
  for (const Observable& o : observable_table()) {
    if (o.key == key) {
      return std::string(o.want_word);
    }
  }
  return key;
}

} // namespace

std::string timestep_scene_text(const TimestepQuestion& q) {
  std::string want;
  for (const std::string& key : q.observables) {
    want += fmt::format("{}\"{}\"", want.empty() ? "" : ", ", word_of(key));
  }
  // The scene's end as well as the search's: a target e is calibrated under the scene's end, so
  // without it a force-end question searched the contact of the overlap end's α (e = 0.1 at p = 1:
  // α_eff 0.59 searched, 1.24 asked; the answer failed by 2.4 % at its own worst phase).
  return fmt::format(R"(name = "timestep"
end = "{}"
want = [{}]
[grid]
p = [{:.17g}]
{} = [{:.17g}]
v0 = [{:.17g}]
m = [{:.17g}]
k = [{:.17g}]
[[search]]
name = "timestep"
solver = "{}"
parameter = "dt"
range = [{:.17g}, {:.17g}]
observable = "{}"
bound_rel = {:.17g}
end = "{}"
onset_phases = {}
tau_as = "{}"
)",
                     q.end, want, q.p, q.damping_key, q.damping, q.v0, q.m, q.k, q.scheme,
                     q.range[0], q.range[1], q.observables.front(), q.tolerance, q.end,
                     onset_phases, q.tau_as);
}

TimestepAdvice advise_timestep(TimestepQuestion q, double contact_time) {
  TimestepAdvice advice;
  q.range = {contact_time / std::min(tightest_steps_per_contact,
                                     steps_per_contact_per_tolerance / q.tolerance),
             contact_time / loosest_steps_per_contact};
  advice.range = q.range;
  Scene scene = parse_scene(timestep_scene_text(q), "timestep");
  Search& search = scene.searches.front();
  search.more_observables.assign(q.observables.begin() + 1, q.observables.end());
  // One cell: the trials themselves side by side on the cores (the scan's next values, the band).
  GroupTrials trials("timestep", search_groups_of(scene, search).front().second, search,
                     all_cores());
  advice.group = trials.answer();
  const SearchGroup& group = advice.group;
  // The largest stable Δt measured as the stability claim measures it (judge/solve.hpp: e <= 1
  // at the return from every onset phase).
  SolverConfig config = search.config;
  const double alpha_sent =
      q.damping_key == "alpha"
          ? q.damping
          : seed_alpha(
                q.p, q.damping_key == "e" ? Damping::Kind::e : Damping::Kind::alpha_eff, q.damping,
                q.end == "force" ? analytic::ContactEnd::force : analytic::ContactEnd::overlap);
  const Inputs inputs{.p = q.p, .alpha = alpha_sent, .v0 = q.v0, .m = q.m, .k = q.k};
  if (std::find(q.observables.begin(), q.observables.end(), "normal_force_max") !=
          q.observables.end() &&
      group.loosest && group.worst_onset_phase) {
    const solvers::Result<double> at_worst =
        solve_unchecked(config, inputs, solvers::want_normal_force, scene.limits, {},
                        *group.loosest, *group.worst_onset_phase);
    advice.normal_force_max_at_worst_phase = at_worst.normal_force_max;
  }
  advice.stable = largest_stable_dt(config, inputs, scene.limits, contact_time);
  return advice;
}

} // namespace pldamp::harness
