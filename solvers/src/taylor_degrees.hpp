// The taylor solver's Taylor order for a tolerance, and the degrees of its two-variable contact
// series (two_power_series.hpp) that follow from it: what taylor.cpp asks for, and what
// generate_stored_tables.cpp keeps in the source for float128, so that the two cannot drift.
#pragma once

#include <algorithm>
#include <cmath>

namespace pldamp::solvers::detail {

// N = ⌈1 − ½ ln ε⌉ (Jorba & Zou; taylor.cpp): 20 in double, 40 in float128.
inline int taylor_order(double tolerance) {
  return std::max(2, static_cast<int>(std::ceil(1 - std::log(tolerance) / 2)));
}

// The two-variable entry series to N + 3, the exit's to N. The entry's values are summed once per
// (p, β, γ) (taylor.cpp keeps its end state, and its stretch ends before the normal force's peak,
// so no collision searches it): its degree costs a collision nothing, and its reach in x grows as
// ε^(1/D). The exit's is evaluated in every collision (Newton, the guard, the work), where a
// wider one cost more than the step it saved.
inline constexpr int entry_degree(int order) {
  return order + 3;
}

} // namespace pldamp::solvers::detail
