// `pldamp timestep`'s question answered: the loosest Δt at which a DEM scheme keeps every asked
// observable within a relative tolerance of the closed form, wherever in a step the contact
// begins, and the largest stable Δt. The question is written as the scene a user would write,
// read by the scene reader, and answered by the [[search]] engine's GroupTrials (judge/search.hpp;
// docs/design.md §2: one path to an answer), so `timestep` and a [[search]] over the range it
// reports agree exactly.
#pragma once

#include "judge/search.hpp"
#include "judge/solve.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

// The question `timestep` asks, as numbers: its [[search]] scene (timestep_scene_text).
struct TimestepQuestion {
  std::string scheme;
  double tolerance = 0;
  std::vector<std::string> observables; // the first is the search's observable, then the rest
  double p = 1, damping = 0, v0 = 1, m = 1, k = 1;
  std::string damping_key = "alpha";
  std::string end = "overlap";
  std::string tau_as = "first-step-out";
  std::array<double, 2> range{}; // Δt: tightest, loosest (advise_timestep sets it)
};

// The scene whose [[search]] asks the question (for its first observable; advise_timestep adds
// the rest as Search::more_observables).
std::string timestep_scene_text(const TimestepQuestion& question);

struct TimestepAdvice {
  std::array<double, 2> range{}; // Δt searched: tightest, loosest
  SearchGroup group;             // the search's answer, its worst phase and the first failure
  // normal_force_max judged: the largest force the scheme evaluates at a step, at the answer and
  // its worst onset phase (what a code reports as its peak force).
  std::optional<double> normal_force_max_at_worst_phase;
  StableStep stable; // the largest stable Δt, as the stability claim measures it
};

// The question's answer for a contact lasting `contact_time` (τ, or t_cut at the force end); the
// question's range is set here from it and the tolerance.
TimestepAdvice advise_timestep(TimestepQuestion question, double contact_time);

} // namespace pldamp::harness
