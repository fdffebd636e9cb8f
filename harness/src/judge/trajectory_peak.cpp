// The readings of a contact about its peaks (judge/trajectory_peak.hpp; MATH.md §10.1, §10.2).
//
// Each is a sampled::Reading: the value, the §10.1 estimate (its comparison with the other
// reasonable readings of the same rows) and a bound on what the cells' rounding does to it, a
// cell y of a column written with d digits being known to u = ρ |y|, ρ = resolution_of(d)
// (§10.2). The bounds for a peak's value and time are with_rounding's; δ'' at the peak: a
// second difference of values known to u is known to 4 u/(h₁h₂), a secant of slopes to
// 2 u_v (1/h₁ + 1/h₂), and a time known to u_t = ρ_t |t| moves a difference quotient by
// |its value| · 2 u_t/h on each of its divisions.
#include "judge/trajectory_peak.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace pldamp::harness::peak {
namespace {

using sampled::at_resolving_stride;
using sampled::cubic_peak;
using sampled::Curve;
using sampled::floored;
using sampled::hermite_peak;
using sampled::Quadratic;
using sampled::Reading;
using sampled::Resolution;
using sampled::strided;
using sampled::vertex_of;

Extracted missing(std::string why) {
  return {std::nullopt, 0, std::move(why)};
}

Extracted extracted(const Reading& r) {
  return {r.value, floored(r.error(), r.value), {}};
}

double largest_of(const std::vector<double>& y, std::size_t from, std::size_t to) {
  double largest = 0;
  for (std::size_t j = from; j <= to; ++j) {
    largest = std::max(largest, std::abs(y[j]));
  }
  return largest;
}

// A peak's time no stride resolves is somewhere in the contact, rows first … last.
Reading within_contact(Reading time, double contact) {
  time.rounding = std::min(time.rounding, contact);
  return time;
}

// The largest stride whose rows i ± 2s, the comparisons one stride over, lie in first … last.
std::size_t widest_about(std::size_t i, std::size_t first, std::size_t last) {
  return std::max<std::size_t>(1, std::min(i - first, last - i) / 2);
}

// The curvature a peak's time is pinned by, and its rounding: with slopes, their centred secant
// over i − 1 … i + 1 (slopes near a peak are near 0 and so written finely); else δ's second
// difference.
std::pair<double, double> peak_curvature(const Curve& y, std::size_t i, const Resolution& r) {
  const double h1 = y.t[i] - y.t[i - 1], h2 = y.t[i + 1] - y.t[i];
  const double u_t = r.t * std::max(std::abs(y.t[i - 1]), std::abs(y.t[i + 1]));
  if (y.slope != nullptr) {
    const std::vector<double>& v = *y.slope;
    const double a = (v[i + 1] - v[i - 1]) / (h1 + h2);
    return {a, 2 * r.slope * largest_of(v, i - 1, i + 1) / (h1 + h2) +
                   4 * u_t / (h1 + h2) * std::abs(a)};
  }
  const double a = 2 * y.quadratic(i - 1).d012;
  return {a, 4 * r.y * largest_of(y.y, i - 1, i + 1) / (h1 * h2) +
                 4 * u_t / std::min(h1, h2) * std::abs(a)};
}

struct PeakReadings {
  Reading value, time;
};

// The largest value of a curve and its time about its largest sample i (1 ≤ i < size − 1). With
// slopes: the largest value of the cubic Hermite pieces on both sides of it, against the parabola
// through the three samples; without: that parabola's vertex, against the largest sample and
// against the vertex of the parabola one sample over, toward the vertex (MATH.md §10.1). Among
// every s-th row (s > 1: `sample_is_a_reading` false) the largest sample is where rounding put
// it — that is why the stride grew — and is no reading of the peak to compare with.
PeakReadings peak_of(const Curve& y, std::size_t i, bool sample_is_a_reading) {
  assert(i >= 1 && i + 1 < y.size());
  const std::pair<double, double> sample{y.t[i], y.y[i]};
  const std::pair<double, double> vertex = vertex_of(y, i - 1).value_or(sample);
  std::pair<double, double> best = vertex;
  std::vector<std::pair<double, double>> others;
  if (y.slope != nullptr) {
    best = hermite_peak(y, i);
    others.push_back(vertex);
  } else {
    if (sample_is_a_reading) {
      others.push_back(sample);
    }
    const bool later = vertex.first > y.t[i];
    if (later ? i + 2 < y.size() : i >= 2) {
      if (const auto shifted = vertex_of(y, later ? i : i - 2)) {
        others.push_back(*shifted);
      }
    }
  }
  double t_spread = 0;
  double y_spread = 0;
  for (const auto& [t, value] : others) {
    t_spread = std::max(t_spread, std::abs(best.first - t));
    y_spread = std::max(y_spread, std::abs(best.second - value));
  }
  return {{best.second, y_spread}, {best.first, t_spread}};
}

// The largest total normal force and its time about the largest sample i among rows first …
// last of `force`: the vertex of the parabola through it and its neighbours, against the peaks
// of the cubics through four samples about it (one order higher: its sampling estimate; the
// sample itself where there are not four).
PeakReadings force_peak_of(const Curve& force, std::size_t i, std::size_t first, std::size_t last) {
  assert(first < i && i < last);
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
  return {{vertex.second, y_spread}, {vertex.first, t_spread}};
}

// A peak read by `read_peak` off `rows` (its anchor i the largest sample), with the rounding of
// its value — 1.25 u (a parabola's value within its rows' span, the Lebesgue constant of three
// equispaced nodes; a cubic Hermite piece's, u + h u_v/3, its slope weights peaking at 4/27) —
// and of its time: where the slope vanishes, the slope's rounding (a parabola's anywhere in its
// span 4 u/h, a Hermite piece's 3 u/h + u_v) over the curvature, and the times' own. That bounds
// how far the peak of the true curve may be from the one read, not only how far the reading moves
// with its cells: with rows finer than their digits the largest sample may lie a hundred rows
// from the peak, and a noise-made extremum of the Hermite there moved little with its cells yet
// stood 55 times its moves from the peak (6 digits, 10^5 rows, with v). Infinite where the rows
// do not hold the peak: their curvature not negative beyond its rounding, the vertex clamped to
// their span, or (with v) no change of v's sign over them.
template <class ReadPeak>
PeakReadings with_rounding(const sampled::Strided& rows, const Resolution& r,
                           const ReadPeak& read_peak) {
  PeakReadings peak = read_peak(rows);
  const Curve y = rows.curve();
  const std::size_t i = rows.at;
  const double h_min = std::min(y.t[i] - y.t[i - 1], y.t[i + 1] - y.t[i]);
  const double h_max = std::max(y.t[i] - y.t[i - 1], y.t[i + 1] - y.t[i]);
  const double u_y = r.y * largest_of(y.y, i - 1, i + 1);
  const double u_slope = y.slope != nullptr ? r.slope * largest_of(*y.slope, i - 1, i + 1) : 0;
  const double u_t = r.t * std::max(std::abs(y.t[i - 1]), std::abs(y.t[i + 1]));
  peak.value.rounding = 1.25 * u_y + h_max * u_slope / 3;
  const auto [curvature, curvature_rounding] = peak_curvature(y, i, r);
  const double t = peak.time.value;
  const bool holds_the_peak = -curvature > 2 * curvature_rounding &&
                              (y.slope != nullptr ? (*y.slope)[i - 1] >= 0 && (*y.slope)[i + 1] <= 0
                                                  : t != y.t[i - 1] && t != y.t[i + 1]);
  peak.time.rounding = holds_the_peak
                           ? u_t + (4 * u_y / h_min + u_slope) / (-curvature - curvature_rounding)
                           : std::numeric_limits<double>::infinity();
  return peak;
}

// δ'' at t_star off rows i − s, i, i + s (all in contact): the curvature of δ's parabola,
// compared with the parabolas one stride over; or, with v, the slope of v's parabola at t_star,
// compared with v's secants on either side of i and v's parabolas one stride over.
Reading acceleration_at(const TrajectoryColumns& c, std::size_t i, std::size_t first,
                        std::size_t last, double t_star, std::size_t s) {
  assert(i >= first + s && i + s <= last);
  const std::vector<double>& t = c.t;
  const double h1 = t[i] - t[i - s], h2 = t[i + s] - t[i];
  const auto parabola = [&](const std::vector<double>& y, std::size_t from) {
    return Quadratic(t[from], y[from], t[from + s], y[from + s], t[from + 2 * s], y[from + 2 * s]);
  };
  // The first rows of the parabolas one stride over, i − 2s … i and i … i + 2s, where in contact.
  std::vector<std::size_t> one_stride_over;
  if (i >= first + 2 * s) {
    one_stride_over.push_back(i - 2 * s);
  }
  if (i + 2 * s <= last) {
    one_stride_over.push_back(i);
  }
  Reading a{.stride = s};
  if (c.v) {
    const std::vector<double>& v = *c.v;
    a.value = parabola(v, i - s).slope(t_star);
    const double before = (v[i] - v[i - s]) / h1;
    const double after = (v[i + s] - v[i]) / h2;
    a.estimate =
        std::max(std::abs(a.value - (t_star < t[i] ? before : after)), std::abs(after - before));
    for (const std::size_t from : one_stride_over) {
      a.estimate = std::max(a.estimate, std::abs(a.value - parabola(v, from).slope(t_star)));
    }
    a.rounding = 2 * resolution_of(c.digits.v) * largest_of(v, i - s, i + s) * (1 / h1 + 1 / h2);
  } else {
    a.value = 2 * parabola(c.delta, i - s).d012;
    for (const std::size_t from : one_stride_over) {
      a.estimate = std::max(a.estimate, std::abs(a.value - 2 * parabola(c.delta, from).d012));
    }
    if (one_stride_over.empty()) { // three rows of contact: nothing to compare with
      a.estimate = std::abs(a.value);
    }
    a.rounding = 4 * resolution_of(c.digits.delta) * largest_of(c.delta, i - s, i + s) / (h1 * h2);
  }
  const double u_t = resolution_of(c.digits.t) * std::max(std::abs(t[i - s]), std::abs(t[i + s]));
  a.rounding += 4 * u_t / std::min(h1, h2) * std::abs(a.value);
  return a;
}

// How far δ'' strays from `acceleration` over the readings at the same stride s centred within
// two and a half rows of i (a staggered loop's force belongs to a state up to two steps away):
// δ's second differences over j − s, j, j + s, or v's secants over [j, j + s].
double acceleration_spread(const TrajectoryColumns& c, std::size_t i, std::size_t first,
                           std::size_t last, std::size_t s, double acceleration) {
  const std::vector<double>& t = c.t;
  double spread = 0;
  // Centres in half rows: 2j + s for v's secant over [j, j + s], 2j for δ's parabola about j.
  const std::size_t offset = c.v ? s : 0;
  for (std::size_t j = std::max(first, i - std::min(i, 3 + s)); j <= std::min(last, i + 3); ++j) {
    const std::size_t twice_centre = 2 * j + offset;
    if (twice_centre + 5 < 2 * i || twice_centre > 2 * i + 5) {
      continue;
    }
    double nearby = 0;
    if (c.v) {
      if (j + s > last) {
        continue;
      }
      nearby = ((*c.v)[j + s] - (*c.v)[j]) / (t[j + s] - t[j]);
    } else {
      if (j < first + s || j + s > last) {
        continue;
      }
      nearby =
          2 * Quadratic(t[j - s], c.delta[j - s], t[j], c.delta[j], t[j + s], c.delta[j + s]).d012;
    }
    spread = std::max(spread, std::abs(nearby - acceleration));
  }
  return spread;
}

} // namespace

std::pair<Extracted, Extracted> overlap_peak(const TrajectoryColumns& c, std::size_t i,
                                             std::size_t first, std::size_t last) {
  const Curve delta{c.t, c.delta, c.v ? &*c.v : nullptr};
  if (i == 0 || i + 1 >= delta.size()) {
    const char* why = i == 0 ? "the largest overlap is the first row: the peak is not in the series"
                             : "the largest overlap is the last row: the peak is not in the series";
    return {missing(why), missing(why)};
  }
  const Resolution r{resolution_of(c.digits.t), resolution_of(c.digits.delta),
                     resolution_of(c.digits.v)};
  // The value off adjacent rows: a peak's value is not a difference, wider rows would only add
  // truncation. Its time is where the slope vanishes: read over the stride that resolves it.
  const auto peak_at = [&](std::size_t s) {
    return with_rounding(
        strided(delta, i, s, 2, 2, 0, delta.size() - 1), r,
        [&](const sampled::Strided& rows) { return peak_of(rows.curve(), rows.at, s == 1); });
  };
  const Reading value = peak_at(1).value;
  const auto time_at = [&](std::size_t s) {
    Reading time = peak_at(s).time;
    time.stride = s;
    return std::optional<Reading>(time);
  };
  const std::size_t widest =
      std::min(widest_about(i, first, last), sampled::widest_keeping_40_rows(last - first + 1));
  const Reading time =
      within_contact(*at_resolving_stride(time_at, widest), c.t[last] - c.t[first]);
  return {extracted(value), extracted(time)};
}

std::pair<Extracted, Extracted> force_peak(const std::vector<double>& t,
                                           const std::vector<double>& force,
                                           const Resolution& resolution, std::size_t first,
                                           std::size_t last) {
  assert(first <= last && last < force.size()); // the contact's rows
  const Curve curve{t, force, nullptr};
  const auto i = static_cast<std::size_t>(
      std::max_element(force.begin() + static_cast<std::ptrdiff_t>(first),
                       force.begin() + static_cast<std::ptrdiff_t>(last + 1)) -
      force.begin());
  if (i == first || i == last) {
    // Largest at the first row (p = 1 and α_eff ≥ ½: the dashpot's jump at the onset, MATH.md
    // §3): that row, which a sampling one row finer could raise by the change to the next.
    const std::size_t next = i == first ? std::min(i + 1, last) : i - 1;
    const Reading value{force[i], std::abs(force[i] - force[next]), resolution.y * force[i]};
    const Reading time{t[i], std::abs(t[i] - t[next]), resolution.t * std::abs(t[i])};
    return {extracted(value), extracted(time)};
  }
  const auto peak_at = [&](std::size_t s) {
    return with_rounding(strided(curve, i, s, 2, 2, first, last), resolution,
                         [](const sampled::Strided& rows) {
                           return force_peak_of(rows.curve(), rows.at, 0, rows.t.size() - 1);
                         });
  };
  const Reading value = peak_at(1).value;
  const auto time_at = [&](std::size_t s) {
    Reading time = peak_at(s).time;
    time.stride = s;
    return std::optional<Reading>(time);
  };
  const std::size_t widest =
      std::min(widest_about(i, first, last), sampled::widest_keeping_40_rows(last - first + 1));
  const Reading time = within_contact(*at_resolving_stride(time_at, widest), t[last] - t[first]);
  return {extracted(value), extracted(time)};
}

void peak_law(const TrajectoryColumns& c, std::size_t largest, std::size_t first, std::size_t last,
              const Extracted& t_star, TrajectoryObservables& out) {
  if (largest < first + 1 || largest + 1 > last) {
    const std::string why = "fewer than three rows of contact about the peak";
    out.peak_acceleration = missing(why);
    out.peak_force = missing(why);
    return;
  }
  const std::vector<double>& t = c.t;
  const double at = *t_star.value;
  // Read about the row nearest t_star. Where the digits resolve the rows' spacing that is the
  // largest sample (t_star lies within half a row of it); where they do not, the largest sample
  // is where rounding put it, up to √(4u/|δ''|) from the peak, and a parabola through it and
  // its neighbours, read at t_star, would be extrapolated far outside its rows.
  auto i = static_cast<std::size_t>(
      std::lower_bound(t.begin() + static_cast<std::ptrdiff_t>(first),
                       t.begin() + static_cast<std::ptrdiff_t>(last + 1), at) -
      t.begin());
  if (i > first && (i > last || at - t[i - 1] < t[i] - at)) {
    --i;
  }
  i = std::clamp(i, first + 1, last - 1);
  const auto read = [&](std::size_t s) {
    return std::optional<Reading>(acceleration_at(c, i, first, last, at, s));
  };
  const Reading acceleration = *at_resolving_stride(read, widest_about(i, first, last));
  out.peak_acceleration = extracted(acceleration);
  out.peak_acceleration_spread =
      acceleration_spread(c, i, first, last, acceleration.stride, acceleration.value);
  const std::size_t lo = std::max(first, i - std::min(i, std::size_t(3)));
  const std::size_t hi = std::min(last, i + 3);
  for (std::size_t j = lo; j <= hi; ++j) {
    out.peak_overlap_spread = std::max(out.peak_overlap_spread, *out.delta_max.value - c.delta[j]);
  }
  if (!c.force) {
    out.peak_force = missing("no F column");
    return;
  }
  // F at t_star on its parabola through i − 1 … i + 1, against the straight line over the
  // interval holding t_star; known to 1.25 u_F (the Lebesgue constant of three equispaced nodes:
  // a parabola's value within its rows' span).
  const std::vector<double>& force = *c.force;
  const std::size_t k = at < t[i] ? i - 1 : i; // the interval holding t_star
  const Quadratic parabola(t[i - 1], force[i - 1], t[i], force[i], t[i + 1], force[i + 1]);
  const double value = parabola(at);
  const double line = force[k] + (force[k + 1] - force[k]) * ((at - t[k]) / (t[k + 1] - t[k]));
  out.peak_force =
      extracted({value, std::abs(value - line),
                 1.25 * resolution_of(c.digits.force) * largest_of(force, i - 1, i + 1)});
  // How far F strays over the rows within three spacings of the peak, or within t_star's own
  // estimate where that is wider: at the true peak time the damping force vanishes, a little off
  // it not, and a peak time the digits place only to some rows reads F that far off.
  std::size_t from = lo, to = hi;
  while (from > first && t[from - 1] >= at - t_star.sampling) {
    --from;
  }
  while (to < last && t[to + 1] <= at + t_star.sampling) {
    ++to;
  }
  for (std::size_t j = from; j <= to; ++j) {
    out.peak_force_spread = std::max(out.peak_force_spread, std::abs(force[j] - value));
  }
}

} // namespace pldamp::harness::peak
