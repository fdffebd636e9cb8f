// One contact's time series, as a DEM code that cannot be driven dumps it, read and measured:
// the contact start and end, e, δ_max, t_peak and τ interpolated between the samples, each with
// an estimate of how much of its error the sampling alone can explain, and judged against the
// closed forms (`pldamp check`; docs/MATH.md §10 "Measuring a sampled trajectory").
//
// The extraction is a pure function of the columns, so a scene can run it on many files.
#pragma once

#include "truth/plan.hpp"

#include "pldamp/solvers/problem.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// The columns of a trajectory file: t and delta (the overlap, > 0 in contact) always; v (dδ/dt,
// > 0 while loading) and F (the total normal force, > 0 repulsive) when the file has them.
struct TrajectoryColumns {
  std::vector<double> t, delta;
  std::optional<std::vector<double>> v, force;
  // The most significant digits a cell of each column has: the precision it was written with
  // (17, a double's round trip, for columns built in code). Each cell is known to half a unit in
  // that digit: resolution_of().
  struct Digits {
    int t = 17, delta = 17, v = 17, force = 17;
  } digits;
};

// The significant digits of a number as written ("0.0480886": 6, "1.50": 3, "7e9": 1); 0 for
// text that is not one.
int significant_digits(std::string_view number);

// The relative rounding of a number written with `digits` significant digits: half a unit in the
// last, and at least a double's epsilon.
double resolution_of(int digits);

// A larger file is refused before it is read whole (64 MiB: some two million rows of four
// columns, far more than one contact needs).
inline constexpr std::size_t max_trajectory_bytes = std::size_t(64) << 20;

// "t|delta|v|F (or time, overlap, velocity, force)": the column names, for messages and --help.
std::string trajectory_column_names();

// Parses CSV text: blank lines and lines starting with '#' skipped, then a header naming the
// columns (case-insensitive; t, delta, v, F or their aliases; no other), then rows of finite
// numbers separated by commas (blanks around a cell allowed), t strictly increasing, at least 3
// rows. `name` heads every error: InputError "NAME:LINE: <what> (got <value>)".
TrajectoryColumns parse_trajectory_csv(std::string_view text, const std::string& name);

// Reads and parses the file at `path` (InputError when it cannot be read, or is larger than
// max_trajectory_bytes).
TrajectoryColumns load_trajectory(const std::string& path);

// The model's total normal force k δ^p + α√(mk) δ^((p−1)/2) v (0 without overlap): the force end
// of a file without an F column, from its v column.
struct ForceLaw {
  double p, m, k, alpha;
  double operator()(double delta, double v) const;
};

struct ExtractOptions {
  double v0 = 1;                            // e = |v at the end| / v0
  solvers::End end = solvers::End::overlap; // the contact ends where δ, or F, returns to 0
  std::optional<ForceLaw> force_law = {};   // End::force without an F column (needs v)
  // The force jumps where the contact starts and ends (p = 1 with damping: α√(mk) v at δ = 0⁺,
  // 0 outside): δ and v are then interpolated there from the contact's side alone.
  bool force_jumps_at_contact = false;
};

// One extracted observable: its value, or why it is missing; and the sampling estimate, the
// difference between the interpolation used and one of an order lower (MATH.md §10), ≥ 0.
struct Extracted {
  std::optional<double> value;
  double sampling = 0;
  std::string missing; // when there is no value: why
};

// What a series gives. Under End::force, e and tau are the capped restitution and the cut time.
// Times are absolute (the file's clock) for start and end, relative to the start for t_peak, tau.
struct TrajectoryObservables {
  Extracted e, delta_max, t_peak, tau;
  // The peak of the total normal force (from an F column, else the model's law on δ and v) and
  // its time from the start: the parabola through the largest sample and its neighbours.
  Extracted normal_force_max, t_normal_force_max;
  Extracted start, end;            // the contact's start and end on the file's clock
  std::size_t contact_samples = 0; // rows with δ > 0 in the (first) contact
  std::vector<std::string> notes;  // what a reader should know: an ignored second contact, ...
  // What the file says of the contact's parameters (MATH.md §10.2), each estimate including the
  // cells' rounding: the approach speed (`incoming_from` says read from what); δ'' at the peak,
  // where v = 0 and so m δ'' = −k δ^p; F there (an F column only). And how far δ, δ'' and F
  // stray from their peak values over the rows within three spacings of the peak: a force
  // evaluated up to two steps away from the state dumped with it (a staggered DEM loop's) lies
  // within that.
  Extracted incoming_speed, peak_acceleration, peak_force;
  std::string incoming_from;
  double peak_overlap_spread = 0, peak_acceleration_spread = 0, peak_force_spread = 0;
};

// Throws InputError when the series has no contact (δ never > 0), or asks the force end with
// neither an F column nor a v column and a force law.
TrajectoryObservables extract_observables(const TrajectoryColumns& columns,
                                          const ExtractOptions& options);

// An extracted observable against its truth.
struct SampledJudgement {
  std::optional<double> error;             // value − truth (absolute)
  std::optional<double> relative_error;    // error / |truth|; the absolute error for a truth of 0
  std::optional<double> relative_sampling; // the sampling estimate on the same scale
  std::optional<bool> explained;           // |error| ≤ the sampling estimate
  std::string why_not;                     // no verdict: why
};

SampledJudgement judge_extracted(const Extracted& measured, const std::optional<Exact>& truth);

// The parameters a trajectory is checked under, as given (`pldamp check`, a scene's
// [[trajectory]]).
struct StatedContact {
  double p, m, k, v0;
};

// The first way the file contradicts the stated parameters beyond what its sampling and digits
// allow (MATH.md §10.2): its approach speed against v0, its force at the peak against k δ^p, its
// force against m δ'' there (or, without F, δ'' against (k/m) δ^p); one line ending in "(got
// <the options>)" that says by how much and what to give. None: no contradiction found.
std::optional<std::string> contradiction(const TrajectoryObservables& x, const StatedContact& c);

// "explained by sampling", "beyond sampling", or "-" without a verdict.
std::string verdict_name(const SampledJudgement& judgement);

// One observable of a checked trajectory, as the reports show it.
struct TrajectoryRow {
  std::string key; // e, delta_max, t_peak, tau (e_cap, t_cut at the force end)
  std::optional<double> value, sampling, truth;
  SampledJudgement judgement;
};

// A scene's [[trajectory]] checked (`pldamp run`): its rows, or why the file could not be.
struct TrajectoryCheck {
  std::string label, file;
  std::string inputs;  // "p = 1.5, e = 0.5, v0 = 1, m = 1, k = 1, end overlap"
  std::string failure; // not empty: the file could not be read or measured
  std::vector<TrajectoryRow> rows;
  std::vector<std::string> notes;
};

} // namespace pldamp::harness
