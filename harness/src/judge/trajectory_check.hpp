// A contact's time series judged against the closed forms in Exact (MATH.md §10 "Measuring a
// sampled trajectory"): a file dumped by a code that cannot be driven (`pldamp check`), or a
// scene's [[trajectory]] (`pldamp run`).
#pragma once

#include "judge/trajectory.hpp"
#include "scene/scene.hpp"
#include "truth/plan.hpp"

#include "pldamp/analytic.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct Observable;

// The observables a file is judged on, in the table's order (overlap-end keys).
inline constexpr std::array<const char*, 6> checked_keys{
    "e", "delta_max", "t_peak", "tau", "normal_force_max", "t_normal_force_max"};

struct CheckedRow {
  const Observable* observable;
  Extracted measured;
  std::optional<Exact> truth;
  SampledJudgement judgement;
  std::optional<double> tolerance; // `pldamp check --tolerance`: judged against it
  std::string failure;             // judged and failed: why
};

struct CheckedTrajectory {
  analytic::Contact<Exact> contact;
  solvers::End end;
  TrajectoryColumns columns;
  TrajectoryObservables x;
  std::vector<CheckedRow> rows;
};

// The file at `path` read, measured and judged against the closed forms of `contact`; an
// InputError when it cannot be read or measured, or contradicts the contact (contradiction()).
CheckedTrajectory check_trajectory_file(const analytic::Contact<Exact>& contact, solvers::End end,
                                        const std::string& path);

// A scene's [[trajectory]] checked as `pldamp check` checks its file (under the scene's end
// unless it names one), each number the decimal the scene gave, read in Exact; a file that
// cannot be read or measured is a failed entry, not an error.
TrajectoryCheck check_trajectory(const TrajectorySpec& spec, solvers::End scene_end);

} // namespace pldamp::harness
