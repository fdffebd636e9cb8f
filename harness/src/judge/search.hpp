// [[search]]: per group of cells, the loosest value of a configuration's sweep parameter (the
// largest rtol or Δt, the fewest steps per contact) that keeps a bound on an observable's error,
// over the group's cells (their worst, or a quantile).
//
// The error is not monotone in the parameter (an adaptive solver's in its tolerance; a fixed
// step's in Δt, as the exit falls at another place within a step), so the range is first scanned
// from its tightest end towards its loosest at 8 values a decade (integers for steps per contact),
// and only the interval between the last value that held and the first that failed is bisected,
// down to neighbouring integers (steps per contact), 2 % (Δt) or 12 % (rtol). Values tighter than
// the answer all held; nothing looser than the first failure is trusted.
//
// A fixed step's error depends on where in a step the contact begins (the onset phase, which a
// simulation does not control): every trial of a steps_per_contact or dt search takes each cell's
// worst over every onset phase (SolverConfig::every_phase, run/phase_supremum.hpp), sought from
// `onset_phases` sampled phases k/n (default 8). Last, the values between the answer and twice as
// tight are checked (every step count there when there are at most 16, or 8 log-spaced), and the
// answer sought again tighter than any that fails.
//
// Each trial solves every cell of the group once, through a plan of its own (truth/plan.hpp: the
// same references and errors as the run's records); the solver runs are counted. A record that
// failed, or a cell without a value of the observable, fails the trial with the reason.
#pragma once

#include "run/workers.hpp"
#include "scene/scene.hpp"
#include "truth/plan.hpp"

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pldamp::harness {

struct SearchGroup {
  std::string group;              // "p = 1.5", "e = 0.5", "all cells"
  std::optional<double> loosest;  // the loosest value that kept the bound (none: not even the
                                  // tightest)
  std::optional<double> failing;  // the tightest value seen to break it (none: none did)
  std::optional<double> measured; // the error (or its quantile) at `loosest`
  std::string worst;              // the cell it comes from
  std::optional<double> worst_onset_phase; // a fixed step: the onset phase k/n it comes from
  int trials = 0;                          // values solved (each over the group's cells and phases)
  int scanned = 0;                         // of them, the scan's
  int onset_phases = 1;     // the phases each fixed-step trial sampled before seeking every phase
  bool every_phase = false; // a fixed step: each trial's worst is over every onset phase
  int band_refinements = 0; // times a value between the answer and the scan failed, and moved it
  // The error at `failing` (a relative bound: the first found beyond it, where the seeking stops)
  // and the onset phase it comes from.
  std::optional<double> failing_measured, failing_onset_phase;
  long solver_runs = 0;
  std::string note; // a failed record, the bound held over the whole range, ...
};

struct SearchResult {
  std::string name, where, quote, line, parameter, observable, measure;
  double bound = 0;
  std::vector<SearchGroup> groups;
  long solver_runs = 0;
};

// The trials of one group of cells, kept per (value, phases), so that several bounds on one
// observable (the time-step study's 1 %, 0.1 %, 0.01 %) share their solves.
class GroupTrials {
public:
  GroupTrials(std::string name, const Scene& group_scene, const Search& search,
              const Workers& workers);

  // The loosest value keeping `bound` (the search's own when none is given).
  SearchGroup answer(std::optional<double> bound = std::nullopt);

private:
  struct Trial {
    std::optional<double> measured;
    std::string worst, failure;
    std::optional<double> worst_phase;
    double enough = 0; // its worst was sought until an error passed this (the bound then asked)
  };
  // At one value, judged against `bound`: a trial kept from another bound serves when its worst is
  // complete (at most the bound it was sought under) or already beyond `bound`.
  const Trial& trial(double value, int phases, double bound);
  const Trial* kept(double value, int phases, double bound) const;
  // The trials of `values` not kept yet, side by side on the workers' threads.
  void prefetch(const std::vector<double>& values, int phases, double bound);
  Trial compute(Plan& plan, const Workers& workers, double value, int phases, double bound,
                long& runs) const;
  bool holds(const Trial& trial, double bound) const;
  std::vector<double> scan_values() const;

  std::string name_;
  Plan plan_; // the group's cells and the search's configuration, its references computed once
  const Search& search_;
  unsigned judged_want_; // the observables judged (solvers::Want bits)
  Workers workers_;      // each trial's cells: threads, and ranks when shared
  std::map<std::pair<double, int>, Trial> trials_;
  long solver_runs_ = 0;
};

// The observables a search judges: its own, then any more (`pldamp timestep`); as solvers::Want
// bits.
std::vector<std::string> search_observable_keys(const Search& search);
unsigned judged_want(const Search& search);

// The groups of cells a search answers for, each as a scene of its own: its grid split by p,
// damping, both, or not at all, with the search's configuration alone.
std::vector<std::pair<std::string, Scene>> search_groups_of(const Scene& scene,
                                                            const Search& search);

// Runs a search: its groups on the workers' threads, shared among their ranks (run/workers.hpp),
// the answers in the groups' order whatever their number (common/parallel.hpp).
SearchResult run_search(const Scene& scene, const Search& search, const Workers& workers);

// What a search's measured value is: "the largest relative error of e over the group's cells".
std::string search_measure(const Search& search);

// The solver runs a search costs at most: its cells times the phases times the values a scan
// and a bisection of its range can take (and the checks at twice the phases and at a prime).
double search_runs_estimate(const Search& search);

// The solves a record's worst over every onset phase takes beyond its sampled phases, as plans
// count them (run/phase_supremum.hpp: about two jumps bisected to 2^-52 and a Brent search per
// score and maximum; its budget, 4000, is a safety net no shipped scene comes near).
inline constexpr double phase_refinement_runs = 150;

// The values a search's scan tries, tightest first.
std::vector<double> search_scan(const Search& search);

} // namespace pldamp::harness
