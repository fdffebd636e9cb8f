// What the batch paths (dem_batch.cpp, verlet_batch.cpp) share: |δ|^β over the lanes as
// ContactOde::dashpot_factor evaluates it, bit for bit (docs/performance.md, "Batch mode"), a
// lane's counts, and the split of a batch into the lanes stepped together and the rest.
#pragma once

#include "collision.hpp"

#include <boost/math/constants/constants.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace pldamp::solvers::detail {

// std::pow(|δ|, β) is exact for β = 0 (1) and β = 1 (|δ|), so any exact evaluation equals it and
// vectorizes; otherwise only std::pow itself rounds as the scalar path does (glibc's pow is not
// correctly rounded: pow(x, 0.5) and sqrt(x) differ in about 1 in 1100 arguments).
class LanePower {
public:
  explicit LanePower(double beta) : beta_(beta) {}

  void operator()(std::span<const double> delta, std::span<double> out) const {
    const std::size_t n = delta.size();
    if (beta_ == 0) {
      for (std::size_t i = 0; i < n; ++i) {
        out[i] = 1;
      }
    } else if (beta_ == 1) {
      for (std::size_t i = 0; i < n; ++i) {
        out[i] = std::abs(delta[i]);
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        out[i] = std::pow(std::abs(delta[i]), beta_);
      }
    }
  }

private:
  double beta_;
};

// The lanes a batch steps together: those that share the first one's p and damping exponent
// (one power for all) and record no samples; the others are left to the scalar solver.
template <class Problems, class OptionsList>
std::vector<std::size_t> lanes_together(const Problems& problems, const OptionsList& options) {
  std::vector<std::size_t> lanes;
  for (std::size_t i = 0; i < problems.size(); ++i) {
    const bool shares =
        lanes.empty() || (problems[i].p == problems[lanes[0]].p &&
                          problems[i].damping_exponent == problems[lanes[0]].damping_exponent);
    if (options[i].sample_times.empty() && shares) {
      lanes.push_back(i);
    }
  }
  return lanes;
}

// Moves the lanes that are done (lanes[i].done) out of the slots [0, active) that a step's loops
// run over: the last running lane takes a finished one's slot, its entries in every array, in
// `lanes` and in each of `others` moving with it. Without it a batch of contacts of different
// lengths (the cells of a configuration, an overdamped one among them) costs its longest lane's
// steps in every lane. A lane's arithmetic is elementwise, so its slot does not change what it
// computes.
template <std::size_t N, class Lanes, class... Others>
void compact_lanes(std::size_t& active, const std::array<std::vector<double>*, N>& arrays,
                   Lanes& lanes, Others&... others) {
  for (std::size_t i = 0; i < active;) {
    if (!lanes[i].done) {
      ++i;
      continue;
    }
    const std::size_t last = --active;
    for (std::vector<double>* array : arrays) {
      std::swap((*array)[i], (*array)[last]);
    }
    std::swap(lanes[i], lanes[last]);
    (std::swap(others[i], others[last]), ...);
  }
}

// A batch's time shared among its running lanes: each lane's solve is charged its share, the
// batch's time over the lanes running (what max_seconds limits, Collision::discount_time), so that
// a lane batched with 15 others neither stops at a 16th of its allowance nor, once they have
// finished, runs on with 16 times it. share() is called every 256 steps, before the lanes'
// budgets are looked at, with the running lanes in the first `active` slots.
class SharedClock {
public:
  template <class Collisions>
  void share(Collisions& collisions, std::size_t active) {
    const auto now = std::chrono::steady_clock::now();
    const auto interval = now - last_;
    last_ = now;
    if (active > 1) {
      const auto others = interval * static_cast<long>(active - 1) / static_cast<long>(active);
      for (std::size_t i = 0; i < active; ++i) {
        collisions[i]->discount_time(others);
      }
    }
  }

private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// The options a fixed-step solver runs with: Δt from steps_per_contact unless given (it is
// reported in the result), as dem.cpp and verlet.cpp set it.
inline Options<double> with_fixed_step(const Problem<double>& problem,
                                       const Options<double>& options) {
  Options<double> stepped = options;
  stepped.fixed_step = options.fixed_step.value_or(boost::math::constants::pi<double>() *
                                                   ContactOde<double>(problem).time_scale() /
                                                   options.steps_per_contact);
  return stepped;
}

// A lane's steps, its right-hand sides and the largest normal force offered (what the scalar
// solvers hand to their Collision as they go, handed over when the lane finishes).
struct LaneCounts {
  long steps = 0, rhs_evals = 0;
  bool has_force = false;
  double force_max = 0, t_force_max = 0;

  // BasicCollision::offer_normal_force: the first, then only a larger one.
  void offer(double t, double force) {
    if (!has_force || force > force_max) {
      has_force = true;
      force_max = force;
      t_force_max = t;
    }
  }
  Result<double> finish(Collision& collision, Outcome outcome) const {
    if (has_force) {
      collision.offer_normal_force(t_force_max, force_max);
    }
    collision.count_rhs_evals(rhs_evals);
    return collision.finish(outcome, steps);
  }
};

// Every problems[i] with options[i]: the lanes that can be stepped together by `batch` (a
// callable taking their indices and returning their Results), the others by `scalar`. Each
// batched Result's wall_seconds is the batch's time, its lanes' set-up included, over its lanes.
template <class Scalar, class Batch>
std::vector<Result<double>> solve_in_lanes(std::span<const Problem<double>> problems,
                                           std::span<const Options<double>> options,
                                           Scalar&& scalar, Batch&& batch) {
  std::vector<Result<double>> results(problems.size());
  const std::vector<std::size_t> lanes = lanes_together(problems, options);
  for (std::size_t i = 0, j = 0; i < problems.size(); ++i) {
    if (j < lanes.size() && lanes[j] == i) {
      ++j;
    } else {
      results[i] = scalar(problems[i], options[i]);
    }
  }
  if (lanes.empty()) {
    return results;
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<Result<double>> batched = batch(std::span<const std::size_t>(lanes));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (std::size_t j = 0; j < lanes.size(); ++j) {
    results[lanes[j]] = std::move(batched[j]);
    results[lanes[j]].wall_seconds = seconds / double(lanes.size());
  }
  return results;
}

} // namespace pldamp::solvers::detail
