// [[search]]: per group of cells, the loosest value of a configuration's sweep parameter (the
// largest rtol or Δt, the fewest steps per contact) that keeps a bound on an observable's error,
// over the group's cells (their worst, or a quantile).
//
// By bisection on the logarithm of the parameter between the range's two ends, assuming the
// error grows as the parameter loosens: first the tightest end (if it fails, nothing in the range
// keeps the bound), then the loosest (if it holds, the whole range does), then halving the
// interval between the loosest value that held and the tightest that failed until they are
// within 12 % of each other (rtol, Δt) or neighbours (steps per contact); then the powers of ten
// between the tightest value and the answer are tried too, and one that breaks the bound is said
// (the error of an adaptive solver is not monotone in its tolerance). Each trial solves every
// cell of the group once, through a plan of its own (truth/plan.hpp: the same references and
// errors as the run's records); the solver runs are counted.
#pragma once

#include "scene/scene.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct SearchGroup {
  std::string group;              // "p = 1.5", "e = 0.5", "all cells"
  std::optional<double> loosest;  // the loosest value that kept the bound (none: not even the
                                  // tightest)
  std::optional<double> failing;  // the tightest value seen to break it (none: none did)
  std::optional<double> measured; // the error (or its quantile) at `loosest`
  std::string worst;              // the cell it comes from
  int trials = 0;
  long solver_runs = 0;
  std::string note; // a failed record, the bound held over the whole range, ...
};

struct SearchResult {
  std::string name, where, quote, line, parameter, observable, measure;
  double bound = 0;
  std::vector<SearchGroup> groups;
  long solver_runs = 0;
};

// Runs a search (on `jobs` threads per trial).
SearchResult run_search(const Scene& scene, const Search& search, int jobs);

// What a search's measured value is: "the largest relative error of e over the group's cells".
std::string search_measure(const Search& search);

// The solver runs a search costs at most: its cells times the trials a bisection of its range
// can take.
double search_runs_estimate(const Search& search);

} // namespace pldamp::harness
