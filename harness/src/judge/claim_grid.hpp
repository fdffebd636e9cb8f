// The cells a claim is judged over (scene.hpp ClaimGrid), and how verdicts write them.
#pragma once

#include "scene/scene.hpp"

#include <string>
#include <vector>

namespace pldamp::harness {

// A damping as a claim's cells name it: "e = 0.5", "alpha_eff = 1.5".
std::string damping_text(const Damping& d);

// The grid text of a verdict: "p in {1, 1.5, 2} x e in [0.1, 0.99] (10 values): 30 cells".
std::string grid_text(const ClaimGrid& grid);

// The grid with each list of more than one value refined (log-spaced where it spans more than a
// decade of positive values) so that every square of the grid holds at least ten cells: with d
// varied lists, ⌈10^(1/d)⌉ − 1 values between each pair of neighbours.
ClaimGrid denser_grid(const ClaimGrid& grid);

// One cell of a claim's grid.
struct ClaimCell {
  double p;
  Damping damping;
  double v0, m, k;
};

// The grid's cells: p, then damping, v0, m, k, the last varying fastest.
std::vector<ClaimCell> cells_of(const ClaimGrid& grid);

// "p = 1.5, e = 0.5", with v0, m and k where the grid varies them.
std::string cell_text(const ClaimGrid& grid, const ClaimCell& cell);

// A list for the grid text: "{1, 1.5, 2}", or "[0.1, 0.99] (10 values)".
std::string list_text(const std::vector<double>& values);

// A number in a verdict's texts: six significant digits.
std::string verdict_number(double x);

} // namespace pldamp::harness
