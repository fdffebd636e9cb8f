// The readings of a sampled contact about its peaks (MATH.md §10.1, §10.2): the largest overlap
// and its time, the largest total normal force and its time, and δ'' and F where v = 0, each with
// its sampling estimate and the rounding of the digits its cells were written with. Derivatives
// are read over every s-th row where adjacent rows are closer than their digits resolve
// (sampled::at_resolving_stride). extract_observables (trajectory.cpp) is their one caller.
#pragma once

#include "judge/sampled_curve.hpp"
#include "judge/trajectory.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace pldamp::harness::peak {

// The largest overlap and its time (absolute) about the contact's largest sample i (rows first
// … last): the value off rows i − 1 … i + 1, the time over the stride that resolves it.
std::pair<Extracted, Extracted> overlap_peak(const TrajectoryColumns& c, std::size_t i,
                                             std::size_t first, std::size_t last);

// The largest total normal force `force` (a column, or computed by the model's law; its cells
// known to `resolution` of themselves) and its time (absolute) over the contact's rows.
std::pair<Extracted, Extracted> force_peak(const std::vector<double>& t,
                                           const std::vector<double>& force,
                                           const sampled::Resolution& resolution, std::size_t first,
                                           std::size_t last);

// δ'' and, with an F column, F at the peak time t_star (its estimate carried into F's), read
// about the row nearest it (the largest overlap `largest` must have a row of contact on either
// side); and how far δ, δ'' and F stray from their peak values over the rows about it (MATH.md
// §10.2). Into out.peak_acceleration, peak_force and the spreads.
void peak_law(const TrajectoryColumns& c, std::size_t largest, std::size_t first, std::size_t last,
              const Extracted& t_star, TrajectoryObservables& out);

} // namespace pldamp::harness::peak
