// The code under test: a DEM contact loop as DEM codes run it (velocity Verlet, the force from the
// half-step velocity), a sphere meeting a wall at v0 under Hertz's k δ^(3/2) and Tsuji's dashpot
// α √(m k) δ^(1/4) δ'. What it measures is what its users read off: e = |v_out|/v0, the largest
// overlap, and the contact time (the exit interpolated within its step).
#pragma once

#include <cmath>

struct Measured {
  double e = 0, delta_max = 0, tau = 0;
};

inline Measured dem_impact(double m, double k, double alpha, double v0, double dt) {
  const double c = alpha * std::sqrt(m * k);
  auto acceleration = [&](double delta, double v) {
    return delta > 0 ? -(k * std::pow(delta, 1.5) + c * std::pow(delta, 0.25) * v) / m : 0.0;
  };
  double t = 0, delta = 0, v = v0, a = acceleration(delta, v);
  Measured out;
  for (long step = 0; step < 100000000; ++step) {
    const double v_half = v + 0.5 * dt * a;
    const double before = delta;
    delta += dt * v_half;
    a = acceleration(delta, v_half);
    v = v_half + 0.5 * dt * a;
    t += dt;
    out.delta_max = std::max(out.delta_max, delta);
    if (delta <= 0 && step > 0) {
      out.tau = t - dt * delta / (delta - before); // where the overlap crossed 0 in the step
      out.e = -v / v0;
      return out;
    }
  }
  return out;
}
