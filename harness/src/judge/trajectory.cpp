// One contact measured from its sampled time series (judge/trajectory.hpp; MATH.md §10): where it
// starts and ends, its peaks, e, and what the file says of its parameters. The interpolation of a
// sampled curve is judge/sampled_curve.hpp's; reading the file is trajectory_csv.cpp's, judging
// what is measured trajectory_judge.cpp's.
#include "judge/trajectory.hpp"

#include "common/input.hpp"
#include "judge/sampled_curve.hpp"
#include "judge/trajectory_peak.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <tuple>

namespace pldamp::harness {
namespace {

using sampled::at_resolving_stride;
using sampled::Curve;
using sampled::floored;
using sampled::Interpolant;
using sampled::Reading;
using sampled::Resolution;

Extracted missing(std::string why) {
  return {std::nullopt, 0, std::move(why)};
}

void require_series(const TrajectoryColumns& c) {
  const std::size_t n = c.t.size();
  if (c.delta.size() != n || (c.v && c.v->size() != n) || (c.force && c.force->size() != n)) {
    throw InputError("trajectory columns differ in length (got t with " + std::to_string(n) +
                     " rows)");
  }
  if (n < 3) {
    throw InputError("a trajectory needs at least 3 rows (got " + std::to_string(n) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const bool finite = std::isfinite(c.t[i]) && std::isfinite(c.delta[i]) &&
                        (!c.v || std::isfinite((*c.v)[i])) &&
                        (!c.force || std::isfinite((*c.force)[i]));
    if (!finite) {
      throw InputError("trajectory values must be finite (got row " + std::to_string(i) + ")");
    }
    if (i > 0 && !(c.t[i] > c.t[i - 1])) {
      throw InputError("t must increase from row to row (got row " + std::to_string(i) + ")");
    }
  }
}

// A crossing of 0 between rows a and a + 1 moves by the times' rounding and by the values' over
// the slope between them (MATH.md §10.2); its estimate becomes a Reading's error().
void add_crossing_rounding(Extracted& crossing, const Curve& curve, std::size_t a,
                           const Resolution& r) {
  if (!crossing.value) {
    return;
  }
  const double u_t = r.t * std::max(std::abs(curve.t[a]), std::abs(curve.t[a + 1]));
  const double u_y = r.y * std::max(std::abs(curve.y[a]), std::abs(curve.y[a + 1]));
  const double slope = std::abs(curve.y[a + 1] - curve.y[a]) / (curve.t[a + 1] - curve.t[a]);
  crossing.sampling = Reading{*crossing.value, crossing.sampling, u_t + u_y / slope}.error();
}

// The speed at x, where the contact ends (x_sampling its estimate), off the rows about the
// interval [end_at, end_at + 1] holding it: by the interpolant across it and by the contact
// side's (`before_end`), each with its lower-order partner (MATH.md §10.1). At the force cut,
// inside the contact, the one across it. At the overlap end the contact side's where the force
// jumps there, else the one across it (with v), or the secant across it (without: the parabola
// would bend through the kink). Its estimate, not its rounding.
Reading end_speed_of(const Curve& overlap, std::size_t end_at,
                     const std::optional<Interpolant>& before_end, double x, double x_sampling,
                     bool overlap_end, bool one_sided) {
  const auto [across_value, across_lower] = overlap.slopes(x, overlap.across(end_at, -1));
  std::vector<double> candidates{across_value, across_lower};
  double value = across_value;
  if (overlap.slope == nullptr) { // and the parabola on the interval's other side
    candidates.push_back(overlap.slopes(x, overlap.across(end_at, +1)).first);
    value = (candidates[0] + candidates[2]) / 2; // centred: the four samples' cubic, nearly
  }
  if (overlap_end) {
    value = overlap.slope != nullptr ? across_value : across_lower;
    if (before_end) {
      const auto [local_value, local_lower] = overlap.slopes(x, *before_end);
      if (one_sided) { // those across the jump are first order: no yardstick
        candidates.clear();
        value = local_value;
      }
      candidates.insert(candidates.end(), {local_value, local_lower});
    }
  }
  double spread = 0;
  for (const double candidate : candidates) {
    spread = std::max(spread, std::abs(value - candidate));
  }
  // And the end time's own estimate, carried through the speed's change over it.
  const Interpolant on_time = overlap.across(end_at, -1);
  for (const double sign : {-1.0, 1.0}) {
    const double moved = x + sign * x_sampling;
    spread = std::max(
        spread, std::abs(overlap.slopes(moved, on_time).first - overlap.slopes(x, on_time).first));
  }
  return {value, spread, 0};
}

// The speed where the contact ends, read over the stride that resolves it (MATH.md §10.2): the
// interval holding the end widened to s rows — at the overlap end from s rows before the row
// after the contact (or the file's last row), into the contact; at the force cut about the
// cut's interval — and the rows s apart about it. Its rounding: each cell it reads moved by its
// half unit (sampled::moved_by_rounding; the reading may extrapolate, p = 1, from the contact's
// side up to a row past it).
Reading end_speed(const Curve& overlap, std::size_t end_at, std::size_t first, std::size_t last,
                  double x, double x_sampling, bool overlap_end, bool one_sided,
                  const Resolution& r) {
  const std::size_t n = overlap.size();
  const std::size_t points = overlap.slope != nullptr ? 2 : 3; // the rows an interpolant needs
  const auto read = [&](std::size_t s) -> std::optional<Reading> {
    const std::size_t a = overlap_end ? std::min(last + s, n - 1) - s : end_at - (s - 1) / 2;
    // Wider than one row, the rows below the interval (and at the cut, above it) are contact's.
    if (s > 1 && (a < first + 2 * s || (!overlap_end && a + 2 * s > last))) {
      return std::nullopt;
    }
    const auto speed_off = [&](const sampled::Strided& rows) {
      const Curve curve = rows.curve();
      std::optional<Interpolant> before_end;
      if (overlap_end && a >= first + (points - 1) * s) {
        before_end = curve.interpolant(rows.at - 1, rows.at + 1 - points);
      }
      return end_speed_of(curve, rows.at, before_end, x, x_sampling, overlap_end, one_sided);
    };
    const sampled::Strided rows = sampled::strided(overlap, a, s, 2, 2, 0, n - 1);
    Reading speed = speed_off(rows);
    speed.rounding = sampled::moved_by_rounding<1>(rows, r, [&](const sampled::Strided& moved) {
      return std::array{speed_off(moved).value};
    })[0];
    speed.stride = s;
    return speed;
  };
  const std::size_t widest = std::min(std::max<std::size_t>(1, (last - first) / 2),
                                      sampled::widest_keeping_40_rows(last - first + 1));
  return *at_resolving_stride(read, widest);
}

// ---- What the file says of its parameters (MATH.md §10.2) -------------------------------------

// The approach speed: v on the last row before contact; else δ's slope over the two rows before
// contact (free flight); else δ's slope where it crosses 0 (one row before contact). Its estimate:
// the speed's change over the spacing before (an approach that is not free: gravity) or, at the
// crossing, over the crossing's interval, and the cells' rounding.
std::pair<Extracted, std::string> approach_of(const TrajectoryColumns& c, const Curve& overlap,
                                              std::size_t first, const Extracted& start) {
  const std::vector<double>& t = c.t;
  const std::vector<double>& delta = c.delta;
  if (first == 0) {
    return {missing("the series starts in contact"), ""};
  }
  const std::size_t a = first - 1;
  if (c.v) {
    const std::vector<double>& v = *c.v;
    const double change = a >= 1 ? std::abs(v[a] - v[a - 1]) : 0;
    const double rounding = resolution_of(c.digits.v) * std::abs(v[a]);
    return {Extracted{v[a], floored(change + rounding, v[a]), {}},
            "v on the last row before contact"};
  }
  // The secant over [i, i + 1] and its rounding (of δ's cells and of h).
  const auto secant = [&](std::size_t i) {
    const double h = t[i + 1] - t[i];
    const double slope = (delta[i + 1] - delta[i]) / h;
    const double rounding = 2 * resolution_of(c.digits.delta) *
                                std::max(std::abs(delta[i]), std::abs(delta[i + 1])) / h +
                            2 * resolution_of(c.digits.t) *
                                std::max(std::abs(t[i]), std::abs(t[i + 1])) / h * std::abs(slope);
    return std::pair{slope, rounding};
  };
  if (a >= 1 && delta[a] < 0 && delta[a - 1] < 0) {
    const auto [slope, rounding] = secant(a - 1);
    const double change = a >= 2 && delta[a - 2] < 0 ? std::abs(slope - secant(a - 2).first) : 0;
    return {Extracted{slope, floored(change + rounding, slope), {}},
            "delta's slope on the two rows before contact"};
  }
  if (delta[a] < 0 && start.value) {
    const Interpolant across = overlap.across(a, +1);
    const auto [value, lower] = overlap.slopes(*start.value, across);
    const double change =
        std::abs(overlap.slopes(t[first], across).first - overlap.slopes(t[a], across).first);
    const double estimate = std::max(std::abs(value - lower), change) + secant(a).second;
    return {Extracted{value, floored(estimate, value), {}}, "delta's slope where it crosses 0"};
  }
  return {missing("the overlap is 0 on the row before contact (clamped?) and there is no v column"),
          ""};
}

} // namespace

double ForceLaw::operator()(double delta, double v) const {
  if (delta <= 0) {
    return 0;
  }
  return k * std::pow(delta, p) + alpha * std::sqrt(m * k) * std::pow(delta, (p - 1) / 2) * v;
}

TrajectoryObservables extract_observables(const TrajectoryColumns& columns,
                                          const ExtractOptions& options) {
  require_series(columns);
  const std::size_t n = columns.t.size();
  const std::vector<double>& t = columns.t;
  const std::vector<double>& delta = columns.delta;
  const Curve overlap{t, delta, columns.v ? &*columns.v : nullptr};
  const Resolution rounding{resolution_of(columns.digits.t), resolution_of(columns.digits.delta),
                            resolution_of(columns.digits.v)};
  TrajectoryObservables out;

  // The first contact: the first run of rows with δ > 0.
  const auto first = static_cast<std::size_t>(
      std::find_if(delta.begin(), delta.end(), [](double d) { return d > 0; }) - delta.begin());
  if (first == n) {
    throw InputError("no contact in the series: delta is never > 0 (got " + std::to_string(n) +
                     " rows)");
  }
  std::size_t last = first;
  while (last + 1 < n && delta[last + 1] > 0) {
    ++last;
  }
  out.contact_samples = last - first + 1;
  if (last + 1 < n) {
    const auto again = std::find_if(delta.begin() + static_cast<std::ptrdiff_t>(last + 1),
                                    delta.end(), [](double d) { return d > 0; });
    if (again != delta.end()) {
      out.notes.push_back("a later contact, from t = " +
                          to_string_full(t[static_cast<std::size_t>(again - delta.begin())]) +
                          ", is ignored");
    }
  }

  // Where the force jumps at the contact's start and end, the interpolants there are those of the
  // contact's side (MATH.md §10): one across the jump mixes two curves, first order in v.
  const std::size_t points = overlap.slope != nullptr ? 2 : 3; // the samples an interpolant needs
  std::optional<Interpolant> after_start, before_end;
  const bool one_sided = options.force_jumps_at_contact;
  if (first + points - 1 <= last) {
    after_start = overlap.interpolant(first, first);
  }
  if (last + 1 >= first + points) {
    before_end = overlap.interpolant(last - 1, last + 1 - points);
  }

  // Start: δ crosses 0 upward between rows first − 1 and first.
  if (first == 0) {
    out.start = missing("the series starts in contact: its start is not in it");
  } else {
    const bool clamped = delta[first - 1] == 0 && first >= 2 && delta[first - 2] == 0;
    out.start = overlap.crossing(first - 1, after_start, one_sided, +1, clamped);
    add_crossing_rounding(out.start, overlap, first - 1, rounding);
    if (clamped) {
      out.notes.push_back("overlap 0 on the rows before contact (clamped?): the start is placed "
                          "within a whole sample spacing");
    }
  }

  // Peak.
  const auto peak = static_cast<std::size_t>(
      std::max_element(delta.begin() + static_cast<std::ptrdiff_t>(first),
                       delta.begin() + static_cast<std::ptrdiff_t>(last + 1)) -
      delta.begin());
  Extracted t_peak_absolute;
  std::tie(out.delta_max, t_peak_absolute) = peak::overlap_peak(columns, peak, first, last);
  if (t_peak_absolute.value) {
    peak::peak_law(columns, peak, first, last, t_peak_absolute, out);
  } else {
    out.peak_acceleration = missing(t_peak_absolute.missing);
    out.peak_force = missing(t_peak_absolute.missing);
  }

  // The total normal force: the F column, else the model's law on δ and v.
  std::vector<double> computed;
  if (!columns.force && columns.v && options.force_law) {
    computed.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      computed[i] = (*options.force_law)(delta[i], (*columns.v)[i]);
    }
  }
  const std::vector<double>* force = columns.force      ? &*columns.force
                                     : computed.empty() ? nullptr
                                                        : &computed;
  // The force's cells: the column's digits; computed, the relative rounding of k δ^p and of the
  // damping force, p ρ_δ and ρ_δ (p − 1)/2 + ρ_v, at most.
  const Resolution force_rounding{
      rounding.t,
      columns.force ? resolution_of(columns.digits.force)
                    : std::max(1.0, options.force_law ? options.force_law->p : 1.0) * rounding.y +
                          rounding.slope,
      0};
  Extracted t_force_absolute;
  if (force != nullptr) {
    std::tie(out.normal_force_max, t_force_absolute) =
        peak::force_peak(t, *force, force_rounding, first, last);
  } else {
    out.normal_force_max = t_force_absolute =
        missing("no F column, and no v column to compute F from");
  }

  // End: δ crosses 0 downward after the contact's last row, or F crosses 0 after the peak.
  std::optional<std::size_t> end_at; // the interval [end_at, end_at + 1] holding the end
  if (options.end == solvers::End::overlap) {
    if (last + 1 == n) {
      out.end = missing("the contact does not end within the series");
    } else {
      end_at = last;
      const bool clamped = delta[last + 1] == 0 && last + 2 < n && delta[last + 2] == 0;
      out.end = overlap.crossing(last, before_end, one_sided, -1, clamped);
      add_crossing_rounding(out.end, overlap, last, rounding);
      if (clamped) {
        out.notes.push_back("overlap 0 on the rows after contact (clamped?): the end is placed "
                            "within a whole sample spacing");
      }
    }
  } else {
    if (force == nullptr) {
      throw InputError("the force end needs an F column, or a v column to compute F from (got "
                       "the columns t, delta)");
    }
    if (!columns.force) {
      out.notes.push_back("F computed from delta and v by the model's force law");
    }
    const Curve total{t, *force, nullptr};
    for (std::size_t b = peak + 1; b < n; ++b) {
      if ((*force)[b] <= 0 && (*force)[b - 1] > 0) {
        end_at = b - 1;
        break;
      }
    }
    if (!end_at) {
      out.end = missing("the force does not return to 0 after the peak within the series");
    } else {
      const std::size_t b = *end_at + 1;
      const bool clamped = (*force)[b] == 0 && b + 1 < n && (*force)[b + 1] == 0;
      out.end = total.crossing(*end_at, std::nullopt, false, -1, clamped);
      add_crossing_rounding(out.end, total, *end_at, force_rounding);
      if (clamped) {
        out.notes.push_back("F 0 on the rows after the cut (clamped): the cut is placed within a "
                            "whole sample spacing");
      }
    }
  }

  // e from the velocity at the end.
  if (end_at) {
    const Reading speed = end_speed(overlap, *end_at, first, last, *out.end.value, out.end.sampling,
                                    options.end == solvers::End::overlap, one_sided, rounding);
    out.e = {std::abs(speed.value) / options.v0, 0, {}};
    out.e.sampling = floored(floored(speed.error(), speed.value) / options.v0, *out.e.value);
    if (speed.value > 0) {
      out.notes.push_back("the overlap still grows where the contact ends (v > 0 there)");
    }
  } else {
    out.e = missing(out.end.missing);
  }

  std::tie(out.incoming_speed, out.incoming_from) = approach_of(columns, overlap, first, out.start);

  // Times from the start.
  auto since_start = [&](const Extracted& at) {
    if (!at.value) {
      return missing(at.missing);
    }
    if (!out.start.value) {
      return missing(out.start.missing);
    }
    return Extracted{*at.value - *out.start.value, at.sampling + out.start.sampling, {}};
  };
  out.t_peak = since_start(t_peak_absolute);
  out.t_normal_force_max = since_start(t_force_absolute);
  out.tau = since_start(out.end);
  return out;
}

} // namespace pldamp::harness
