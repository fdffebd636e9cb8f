// The interpolation of a sampled curve (judge/sampled_curve.hpp).
#include "judge/sampled_curve.hpp"

namespace pldamp::harness::sampled {
namespace {

// Where `inside` (f > 0) changes on [lo, hi], the two ends being on different sides: the first
// change of 64 even subintervals, then bisection to adjacent doubles.
template <class F>
double boundary(const F& f, double lo, double hi) {
  const bool inside_at_lo = f(lo) > 0;
  double a = lo;
  double b = hi;
  for (int i = 1; i <= 64; ++i) {
    const double s = i == 64 ? hi : lo + (hi - lo) * i / 64;
    if ((f(s) > 0) != inside_at_lo) {
      b = s;
      break;
    }
    a = s;
  }
  for (int i = 0; i < 200; ++i) {
    const double mid = a + (b - a) / 2;
    if (mid <= a || mid >= b) {
      break;
    }
    ((f(mid) > 0) == inside_at_lo ? a : b) = mid;
  }
  return (f(a) == 0) ? a : (f(b) == 0 ? b : a + (b - a) / 2);
}

} // namespace

Extracted Curve::crossing(std::size_t a, const std::optional<Interpolant>& local, bool one_sided,
                          int inside_side, bool clamped) const {
  const std::size_t b = a + 1;
  const double h = t[b] - t[a];
  const auto line = [&](double x) { return y[a] + (y[b] - y[a]) * ((x - t[a]) / h); };
  std::vector<double> others{boundary(line, t[a], t[b])};
  double value = boundary(across(a, inside_side), t[a], t[b]);
  if (local && ((*local)(t[a]) > 0) != ((*local)(t[b]) > 0)) {
    const double on_local = boundary(*local, t[a], t[b]);
    others.push_back(one_sided ? value : on_local);
    if (one_sided) {
      value = on_local;
      clamped = false;
    }
  }
  double sampling = 0;
  for (const double other : others) {
    sampling = std::max(sampling, std::abs(value - other));
  }
  if (clamped) {
    sampling = std::max(sampling, h);
  }
  return {value, floored(sampling, std::max(std::abs(t[a]), std::abs(t[b]))), {}};
}

std::pair<double, double> Curve::slopes(double x, const Interpolant& by) const {
  const std::size_t a = by.near;
  const std::size_t b = a + 1;
  const double h = t[b] - t[a];
  if (by.cubic) {
    return {by.cubic->slope(x), (*slope)[a] + ((*slope)[b] - (*slope)[a]) * ((x - t[a]) / h)};
  }
  return {by.parabola->slope(x), (y[b] - y[a]) / h};
}

Strided strided(const Curve& curve, std::size_t anchor, std::size_t stride, std::size_t before,
                std::size_t after, std::size_t lo, std::size_t hi) {
  assert(stride >= 1 && lo <= anchor && anchor <= hi && hi < curve.size());
  Strided rows;
  const std::size_t down = std::min(before, (anchor - lo) / stride);
  const std::size_t up = std::min(after, (hi - anchor) / stride);
  for (std::size_t j = anchor - down * stride; j <= anchor + up * stride; j += stride) {
    rows.t.push_back(curve.t[j]);
    rows.y.push_back(curve.y[j]);
    if (curve.slope != nullptr) {
      rows.slope.push_back((*curve.slope)[j]);
    }
  }
  rows.at = down;
  return rows;
}

std::optional<std::pair<double, double>> vertex_of(const Curve& curve, std::size_t first) {
  const Quadratic parabola = curve.quadratic(first);
  if (!(parabola.d012 < 0)) {
    return std::nullopt;
  }
  const double t = std::clamp(parabola.vertex(), curve.t[first], curve.t[first + 2]);
  return std::pair{t, parabola(t)};
}

std::pair<double, double> hermite_peak(const Curve& curve, std::size_t i) {
  assert(i >= 1 && i + 1 < curve.size()); // peak_of's: a largest sample inside the series
  double t_best = curve.t[i];
  double y_best = curve.y[i];
  for (const std::size_t a : {i - 1, i}) {
    const Hermite piece = curve.hermite(a);
    // Roots of the derivative c1 + 2 c2 s + 3 c3 s² in (0, 1).
    const double qa = 3 * piece.c[3], qb = 2 * piece.c[2], qc = piece.c[1];
    std::vector<double> roots;
    if (qa == 0) {
      if (qb != 0) {
        roots.push_back(-qc / qb);
      }
    } else if (const double disc = qb * qb - 4 * qa * qc; disc >= 0) {
      const double q = -(qb + std::copysign(std::sqrt(disc), qb)) / 2;
      roots.push_back(q / qa);
      if (q != 0) {
        roots.push_back(qc / q);
      }
    }
    for (const double s : roots) {
      if (s > 0 && s < 1 && piece.at_s(s) > y_best) {
        y_best = piece.at_s(s);
        t_best = piece.ta + s * piece.h;
      }
    }
  }
  return {t_best, y_best};
}

std::pair<double, double> cubic_peak(const Curve& curve, std::size_t from) {
  assert(from + 3 < curve.size());
  const double* x = &curve.t[from];
  const double* y = &curve.y[from];
  // Newton's divided differences.
  const double d01 = (y[1] - y[0]) / (x[1] - x[0]), d12 = (y[2] - y[1]) / (x[2] - x[1]),
               d23 = (y[3] - y[2]) / (x[3] - x[2]);
  const double d012 = (d12 - d01) / (x[2] - x[0]), d123 = (d23 - d12) / (x[3] - x[1]);
  const double d0123 = (d123 - d012) / (x[3] - x[0]);
  auto at = [&](double t) {
    return y[0] + (t - x[0]) * (d01 + (t - x[1]) * (d012 + (t - x[2]) * d0123));
  };
  // Where its slope vanishes, from s = t − x₁: a s² + b s + c with a0 = x₀ − x₁, a2 = x₂ − x₁.
  // Solved, not searched: a search comparing the cubic's values places a flat peak only to
  // √(2ε y/|y''|) (1e−8 in time on a contact of unit scale), coarser than the sampling's error
  // once there are some ten thousand rows.
  const double a0 = x[0] - x[1], a2 = x[2] - x[1];
  const double a = 3 * d0123, b = 2 * d012 - 2 * d0123 * (a0 + a2),
               c = d01 - d012 * a0 + d0123 * a0 * a2;
  std::vector<double> roots;
  if (a == 0) {
    if (b != 0) {
      roots.push_back(-c / b);
    }
  } else if (const double disc = b * b - 4 * a * c; disc >= 0) {
    const double q = -(b + std::copysign(std::sqrt(disc), b)) / 2;
    roots.push_back(q / a);
    if (q != 0) {
      roots.push_back(c / q);
    }
  }
  for (const double s : roots) { // a cubic has one maximum at most
    const double t = x[1] + s;
    if (2 * a * s + b < 0 && t > x[0] && t < x[3]) {
      return {t, at(t)};
    }
  }
  std::size_t largest = 0; // none inside: the largest sample
  for (std::size_t j = 1; j < 4; ++j) {
    largest = y[j] > y[largest] ? j : largest;
  }
  return {x[largest], y[largest]};
}

} // namespace pldamp::harness::sampled
