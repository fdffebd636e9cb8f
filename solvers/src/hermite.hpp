// verlet-predicted's trajectory between two step positions (verlet.cpp), shared with its batch
// path (verlet_batch.cpp), which must interpolate bit for bit as it does.
#pragma once

#include "collision.hpp"

namespace pldamp::solvers::detail {

// Cubic Hermite interpolation of δ on [t0, t0 + h] from δ and v = δ' at both ends, at fraction θ.
inline double hermite(double theta, double h, const State& y0, const State& y1) {
  const double t2 = theta * theta, t3 = t2 * theta;
  return (2 * t3 - 3 * t2 + 1) * y0[0] + (t3 - 2 * t2 + theta) * h * y0[1] +
         (-2 * t3 + 3 * t2) * y1[0] + (t3 - t2) * h * y1[1];
}

// δ by hermite, v and W linearly.
inline State interpolate(double theta, double h, const State& y0, const State& y1) {
  return {hermite(theta, h, y0, y1), y0[1] + theta * (y1[1] - y0[1]),
          y0[2] + theta * (y1[2] - y0[2])};
}

} // namespace pldamp::solvers::detail
