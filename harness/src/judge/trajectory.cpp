// One contact measured from its sampled time series (judge/trajectory.hpp; MATH.md §10): where it
// starts and ends, its peaks, e, and what the file says of its parameters. The interpolation of a
// sampled curve is judge/sampled_curve.hpp's; reading the file is trajectory_csv.cpp's, judging
// what is measured trajectory_judge.cpp's.
#include "judge/trajectory.hpp"

#include "common/input.hpp"
#include "judge/sampled_curve.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <tuple>

namespace pldamp::harness {
namespace {

using sampled::cubic_peak;
using sampled::Curve;
using sampled::floored;
using sampled::hermite_peak;
using sampled::Interpolant;
using sampled::vertex_of;

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

// The largest total normal force and its time (absolute) over the contact's rows first .. last:
// the vertex of the parabola through the largest sample and its neighbours, against the peaks of
// the cubics through four samples about it (one order higher: its sampling estimate; the sample
// itself where there are not four). Largest at the first row (p = 1 and α_eff ≥ ½: the dashpot's
// jump at the onset, MATH.md §3): that row, which a sampling one row finer could raise by the
// change to the next.
std::pair<Extracted, Extracted> force_peak_of(const Curve& force, std::size_t first,
                                              std::size_t last) {
  assert(first <= last && last < force.size()); // the contact's rows
  const auto i = static_cast<std::size_t>(
      std::max_element(force.y.begin() + static_cast<std::ptrdiff_t>(first),
                       force.y.begin() + static_cast<std::ptrdiff_t>(last + 1)) -
      force.y.begin());
  if (i == first || i == last) {
    const std::size_t next = i == first ? std::min(i + 1, last) : i - 1;
    return {Extracted{force.y[i], std::abs(force.y[i] - force.y[next]), {}},
            Extracted{force.t[i], std::abs(force.t[i] - force.t[next]), {}}};
  }
  const std::pair<double, double> sample{force.t[i], force.y[i]};
  const std::pair<double, double> vertex = vertex_of(force, i - 1).value_or(sample);
  // The cubics through four samples about the peak, the fourth before and after: the larger
  // disagreement (one alone can agree with the parabola by accident: 36-fold too small at p = 3).
  double t_spread = 0, y_spread = 0;
  bool compared = false;
  for (const std::size_t before : {1, 2}) { // samples before i among the four
    if (i >= first + before && i - before + 3 <= last) {
      const std::pair<double, double> cubic = cubic_peak(force, i - before);
      t_spread = std::max(t_spread, std::abs(vertex.first - cubic.first));
      y_spread = std::max(y_spread, std::abs(vertex.second - cubic.second));
      compared = true;
    }
  }
  if (!compared) {
    t_spread = std::abs(vertex.first - sample.first);
    y_spread = std::abs(vertex.second - sample.second);
  }
  return {Extracted{vertex.second, floored(y_spread, vertex.second), {}},
          Extracted{vertex.first, floored(t_spread, vertex.first), {}}};
}

// The largest overlap and its time (absolute), about the largest sample i. With v: the largest
// value of the cubic Hermite pieces on both sides of it, against the parabola through the three
// samples; without: that parabola's vertex, against the largest sample and against the vertex
// of the parabola one sample over, toward the vertex.
std::pair<Extracted, Extracted> peak_of(const Curve& delta, std::size_t i) {
  if (i == 0 || i + 1 >= delta.size()) {
    const char* why = i == 0 ? "the largest overlap is the first row: the peak is not in the series"
                             : "the largest overlap is the last row: the peak is not in the series";
    return {missing(why), missing(why)};
  }
  const std::pair<double, double> sample{delta.t[i], delta.y[i]};
  const std::pair<double, double> vertex = vertex_of(delta, i - 1).value_or(sample);
  std::pair<double, double> best = vertex;
  std::vector<std::pair<double, double>> others;
  if (delta.slope != nullptr) {
    best = hermite_peak(delta, i);
    others.push_back(vertex);
  } else {
    others.push_back(sample);
    const bool later = vertex.first > delta.t[i];
    if (later ? i + 2 < delta.size() : i >= 2) {
      if (const auto shifted = vertex_of(delta, later ? i : i - 2)) {
        others.push_back(*shifted);
      }
    }
  }
  double t_spread = 0;
  double y_spread = 0;
  for (const auto& [t, y] : others) {
    t_spread = std::max(t_spread, std::abs(best.first - t));
    y_spread = std::max(y_spread, std::abs(best.second - y));
  }
  return {Extracted{best.second, floored(y_spread, best.second), {}},
          Extracted{best.first, floored(t_spread, best.first), {}}};
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

// δ'' and, with an F column, F at the peak time t_star, from the rows i − 1 … i + 1 about the
// largest overlap: δ'' the curvature of δ's parabola, compared with the parabolas one row over,
// or the slope of v's parabola, compared with v's secants on either side of i and v's parabolas
// one row over; F on its parabola, compared with the straight line. The cells' rounding is
// added: 4 ε/(h₁h₂) on a second difference of values known to ε. And how far δ, δ'' (v's secants
// or δ's second differences) and F stray from their peak values over the rows within three
// spacings of row i: a force evaluated up to two steps away from the state dumped with it (a
// staggered DEM loop's) lies within that of the peak's (MATH.md §10.2).
void peak_law_of(const TrajectoryColumns& c, std::size_t i, std::size_t first, std::size_t last,
                 double t_star, TrajectoryObservables& out) {
  if (i < first + 1 || i + 1 > last) {
    const std::string why = "fewer than three rows of contact about the peak";
    out.peak_acceleration = missing(why);
    out.peak_force = missing(why);
    return;
  }
  const std::vector<double>& t = c.t;
  const double h1 = t[i] - t[i - 1];
  const double h2 = t[i + 1] - t[i];
  const std::size_t k = t_star < t[i] ? i - 1 : i; // the interval holding t_star
  const std::size_t lo = std::max(first, i - std::min(i, std::size_t(3)));
  const std::size_t hi = std::min(last, i + 3);
  const double t_rounding = resolution_of(c.digits.t) *
                            std::max(std::abs(t[i - 1]), std::abs(t[i + 1])) /
                            std::min(h1, h2); // relative, on a difference quotient
  const auto largest = [&](const std::vector<double>& y) {
    return std::max({std::abs(y[i - 1]), std::abs(y[i]), std::abs(y[i + 1])});
  };
  // The first rows of the parabolas one row over, i − 2 … i and i … i + 2, where in contact.
  std::vector<std::size_t> one_row_over;
  if (i >= first + 2) {
    one_row_over.push_back(i - 2);
  }
  if (i + 2 <= last) {
    one_row_over.push_back(i);
  }
  double acceleration = 0;
  double estimate = 0;
  std::vector<double> nearby; // δ'' over the rows about the peak
  if (c.v) {
    const Curve speed{t, *c.v, nullptr};
    acceleration = speed.quadratic(i - 1).slope(t_star);
    const double before = speed.slopes(t_star, speed.across(i - 1, +1)).second;
    const double after = speed.slopes(t_star, speed.across(i, +1)).second;
    estimate =
        std::max({std::abs(acceleration - (k < i ? before : after)), std::abs(after - before)});
    for (const std::size_t shifted : one_row_over) { // v's parabolas one row over
      estimate =
          std::max(estimate, std::abs(acceleration - speed.quadratic(shifted).slope(t_star)));
    }
    estimate += 2 * resolution_of(c.digits.v) * largest(*c.v) * (1 / h1 + 1 / h2);
    for (std::size_t j = lo; j < hi; ++j) {
      nearby.push_back(((*c.v)[j + 1] - (*c.v)[j]) / (t[j + 1] - t[j]));
    }
  } else {
    const Curve overlap{t, c.delta, nullptr};
    acceleration = 2 * overlap.quadratic(i - 1).d012;
    bool compared = false;
    for (const std::size_t shifted : one_row_over) {
      estimate = std::max(estimate, std::abs(acceleration - 2 * overlap.quadratic(shifted).d012));
      compared = true;
    }
    if (!compared) { // three rows of contact: nothing to compare with
      estimate = std::abs(acceleration);
    }
    estimate += 4 * resolution_of(c.digits.delta) * largest(c.delta) / (h1 * h2);
    for (std::size_t j = lo; j + 2 <= hi; ++j) {
      nearby.push_back(2 * overlap.quadratic(j).d012);
    }
  }
  estimate += 4 * t_rounding * std::abs(acceleration);
  out.peak_acceleration = {acceleration, floored(estimate, acceleration), {}};
  for (const double a : nearby) {
    out.peak_acceleration_spread =
        std::max(out.peak_acceleration_spread, std::abs(a - acceleration));
  }
  for (std::size_t j = lo; j <= hi; ++j) {
    out.peak_overlap_spread = std::max(out.peak_overlap_spread, *out.delta_max.value - c.delta[j]);
  }
  if (!c.force) {
    out.peak_force = missing("no F column");
    return;
  }
  const std::vector<double>& force = *c.force;
  const Curve total{t, force, nullptr};
  const double value = total.quadratic(i - 1)(t_star);
  const double line = force[k] + (force[k + 1] - force[k]) * ((t_star - t[k]) / (t[k + 1] - t[k]));
  out.peak_force = {
      value,
      floored(std::abs(value - line) + resolution_of(c.digits.force) * largest(force), value),
      {}};
  for (std::size_t j = lo; j <= hi; ++j) {
    out.peak_force_spread = std::max(out.peak_force_spread, std::abs(force[j] - value));
  }
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
  std::tie(out.delta_max, t_peak_absolute) = peak_of(overlap, peak);
  if (t_peak_absolute.value) {
    peak_law_of(columns, peak, first, last, *t_peak_absolute.value, out);
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
  Extracted t_force_absolute;
  if (force != nullptr) {
    std::tie(out.normal_force_max, t_force_absolute) =
        force_peak_of(Curve{t, *force, nullptr}, first, last);
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
      if (clamped) {
        out.notes.push_back("F 0 on the rows after the cut (clamped): the cut is placed within a "
                            "whole sample spacing");
      }
    }
  }

  // e from the velocity at the end.
  if (end_at) {
    // The slopes at the end by the interpolant across it and by the contact side's, each with its
    // lower-order partner. At the force cut, inside the contact, the one across it. At the
    // overlap end the contact side's where the force jumps there, else the one across it (with
    // v), or the secant across it (without: the parabola would bend through the kink).
    const double x = *out.end.value;
    const auto [across_value, across_lower] = overlap.slopes(x, overlap.across(*end_at, -1));
    std::vector<double> candidates{across_value, across_lower};
    double value = across_value;
    if (overlap.slope == nullptr) { // and the parabola on the interval's other side
      candidates.push_back(overlap.slopes(x, overlap.across(*end_at, +1)).first);
      value = (candidates[0] + candidates[2]) / 2; // centred: the four samples' cubic, nearly
    }
    if (options.end == solvers::End::overlap) {
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
    const Interpolant on_time = overlap.across(*end_at, -1);
    for (const double sign : {-1.0, 1.0}) {
      const double moved = x + sign * out.end.sampling;
      spread = std::max(spread, std::abs(overlap.slopes(moved, on_time).first -
                                         overlap.slopes(x, on_time).first));
    }
    const Extracted speed{value, floored(spread, value), {}};
    out.e = {std::abs(*speed.value) / options.v0, 0, {}};
    out.e.sampling = floored(speed.sampling / options.v0, *out.e.value);
    if (*speed.value > 0) {
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
