// The batch path of verlet-predicted (verlet.cpp): N contacts stepped together in structure-of-
// arrays lanes, each lane bit for bit the scalar solver's Result (docs/performance.md, "Batch
// mode"; tests/solvers/batch_test.cpp). The kick, drift and force of a step are loops over the
// lanes; |δ|^β is evaluated once per lane-step (LanePower) and serves both the force and the
// dashpot power of the dissipated work at the new position, which verlet.cpp evaluates twice
// with the same arguments. Events (the peak, the exit) and the budget are per lane, as in
// verlet.cpp and in its order.
#include "batch_lanes.hpp"
#include "collision.hpp"
#include "hermite.hpp"
#include "methods.hpp"
#include "step_timing.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

namespace pldamp::solvers::detail {
namespace {

class VerletBatch {
public:
  VerletBatch(std::span<const Problem<double>> problems, std::span<const Options<double>> options,
              std::span<const std::size_t> lanes)
      : n_(lanes.size()), power_(ContactOde<double>(problems[lanes[0]]).damping_exponent()) {
    const ContactOde<double> first(problems[lanes[0]]);
    p_ = first.p();
    seed_ = first.damping_exponent() == (p_ - 1) / 2; // as ContactOde decides it
    for (std::vector<double>* array : arrays()) {
      array->assign(n_, 0.0);
    }
    lane_.assign(n_, Lane{});
    slot_lane_.resize(n_);
    collisions_.reserve(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      const Problem<double>& problem = problems[lanes[i]];
      const Options<double> stepped = with_fixed_step(problem, options[lanes[i]]);
      collisions_.push_back(std::make_unique<Collision>(problem, stepped));
      Collision& collision = *collisions_.back();
      const ContactOde<double>& ode = collision.ode();
      Lane& lane = lane_[i];
      slot_lane_[i] = i;
      lane.capped = stepped.end == End::force;
      lane.want_force = (stepped.want & want_normal_force) != 0;
      lane.with_work = collision.with_work();
      lane.horizon = collision.horizon();
      lane.max_steps = stepped.max_steps;
      dt_[i] = *stepped.fixed_step;
      m_[i] = ode.m();
      k_[i] = ode.k();
      c_[i] = ode.damping_coefficient();
      phase_[i] = stepped.onset_phase;
      // verlet.cpp: the first step position, φ of a step after the moment of contact.
      t_[i] = stepped.onset_phase * dt_[i];
      State y = collision.initial_state();
      y[0] = t_[i] * y[1];
      a_[i] = collision.rhs(y)[1];
      d_[i] = y[0];
      v_[i] = y[1];
      w_[i] = y[2];
      offer_force(i, t_[i]);
      if (y[0] > 0) {
        lane.timing.acted(t_[i], y[0], -ode.m() * a_[i]);
      }
      power_at_[i] =
          lane.with_work ? ode.damping_coefficient() * ode.dashpot_factor(y[0]) * y[1] * y[1] : 0.0;
    }
  }

  std::vector<Result<double>> run() {
    std::vector<Result<double>> results(n_);
    while (active_ > 0) {
      // The running lanes have all made steps_ steps; their budgets are looked at before steps
      // 0, 256, 512, ... (step), with the batch's time shared among them first.
      if (steps_ % 256 == 0) {
        clock_.share(collisions_, active_);
      }
      const std::size_t completed = step(results);
      ++steps_;
      if (completed > 0) {
        compact_lanes(active_, arrays(), lane_, collisions_, slot_lane_);
      }
    }
    return results;
  }

private:
  struct Lane {
    bool done = false, capped = false, want_force = false, with_work = false;
    bool peak_found = false;
    double horizon = 0;
    LaneCounts counts;
    StepTiming timing;
    long max_steps = 0;
  };

  // verlet.cpp's offer_force: −m a at the step position, while the force's peak is pending.
  void offer_force(std::size_t i, double t) {
    Lane& lane = lane_[i];
    if (lane.want_force && !lane.peak_found) {
      lane.counts.offer(t, -m_[i] * a_[i]);
    }
  }

  void finish(std::size_t i, Outcome outcome, Result<double>& result) {
    Lane& lane = lane_[i];
    result = lane.counts.finish(*collisions_[i], outcome);
    lane.timing.fill(result);
    lane.done = true;
    dt_[i] = 0; // the lane stands still from here on (masked)
    a_[i] = 0;
  }

  std::array<std::vector<double>*, 18> arrays() {
    return {&t_, &d_,     &v_,     &w_,     &a_,     &power_at_, &dt_,     &m_,           &k_,
            &c_, &phase_, &d_old_, &v_old_, &w_old_, &t_old_,    &v_half_, &v_predicted_, &da_};
  }

  // One step of every running lane (slots [0, active_)); returns the lanes completed.
  std::size_t step(std::vector<Result<double>>& results) {
    const std::size_t n = active_;
    std::size_t completed = 0;
    for (std::size_t i = 0; i < n; ++i) { // the budget, before each step
      Lane& lane = lane_[i];
      if (!lane.done && (lane.counts.steps >= lane.max_steps || lane.counts.steps % 256 == 0)) {
        if (const auto spent = collisions_[i]->out_of_budget(lane.counts.steps)) {
          finish(i, *spent, results[slot_lane_[i]]);
          ++completed;
        }
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      d_old_[i] = d_[i];
      v_old_[i] = v_[i];
      w_old_[i] = w_[i];
      t_old_[i] = t_[i];
      v_half_[i] = v_[i] + a_[i] * dt_[i] / 2;
      d_[i] = d_[i] + v_half_[i] * dt_[i];
      v_predicted_[i] = v_[i] + a_[i] * dt_[i];
    }
    power_({d_.data(), n}, {da_.data(), n});
    // ContactOde::rhs at (δ, v + a Δt): v' = −(c |δ|^β v + k sgn(δ)|δ|^p)/m.
    if (seed_) {
      for (std::size_t i = 0; i < n; ++i) {
        const double spring = k_[i] * (da_[i] * da_[i] * d_[i]);
        const double dashpot = c_[i] * da_[i];
        a_[i] = -(dashpot * v_predicted_[i] + spring) / m_[i];
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        const double magnitude = std::pow(std::abs(d_[i]), p_);
        const double spring = k_[i] * (d_[i] < 0 ? -magnitude : magnitude);
        const double dashpot = c_[i] * da_[i];
        a_[i] = -(dashpot * v_predicted_[i] + spring) / m_[i];
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      v_[i] = v_half_[i] + a_[i] * dt_[i] / 2;
    }
    for (std::size_t i = 0; i < n; ++i) {
      Lane& lane = lane_[i];
      if (lane.done) {
        continue;
      }
      ++lane.counts.rhs_evals;
      t_[i] = (double(++lane.counts.steps) + phase_[i]) * dt_[i];
      offer_force(i, t_[i]);
      const double power_new =
          lane.with_work ? c_[i] * da_[i] * v_[i] * v_[i] : 0.0; // ContactOde::dashpot_factor
      w_[i] = w_old_[i] + dt_[i] / 2 * (power_at_[i] + power_new);
      power_at_[i] = power_new;
      const bool routine = std::isfinite(d_[i]) && std::isfinite(v_[i]) && std::isfinite(w_[i]) &&
                           !(!lane.peak_found && v_old_[i] > 0 && v_[i] <= 0) &&
                           !(lane.peak_found && (lane.capped || d_[i] <= 0)) &&
                           t_[i] < lane.horizon &&
                           !(lane.peak_found && lane.counts.steps % 64 == 0); // settled?
      if (routine) {
        lane.timing.acted(t_[i], d_[i], -m_[i] * a_[i]);
      } else if (after_step(i, results[slot_lane_[i]])) {
        ++completed;
      }
    }
    return completed;
  }

  // verlet.cpp after a step: divergence, the peak, the exit, the horizon or a settled contact;
  // true when complete.
  [[gnu::noinline]] bool after_step(std::size_t i, Result<double>& result) {
    Lane& lane = lane_[i];
    Collision& collision = *collisions_[i];
    const double dt = dt_[i], t = t_[i], t_old = t_old_[i], delta = d_[i], v_half = v_half_[i];
    State y{delta, v_[i], w_[i]};
    const State y_old{d_old_[i], v_old_[i], w_old_[i]};
    if (Collision::diverged(y)) {
      finish(i, Outcome::unstable, result);
      return true;
    }
    auto between = [&](double s) { return interpolate((s - t_old) / dt, dt, y_old, y); };
    if (!lane.peak_found && y_old[1] > 0 && y[1] <= 0) {
      const double t_peak = t_old + dt * y_old[1] / (y_old[1] - y[1]);
      lane.peak_found = true;
      if (collision.record(EventKind::peak, t_peak, between(t_peak))) {
        finish(i, Outcome::peak, result);
        return true;
      }
    }
    const bool contact_lost =
        collision.pending(EventKind::exit) &&
        (lane.capped ? collision.ode().force_sign(delta, v_half) <= 0 : delta <= 0);
    if (contact_lost) {
      y[1] = v_half; // no contact force, hence no dashpot work, on the step that loses it
      y[2] = y_old[2];
      lane.timing.ended(t, delta, delta > 0 ? collision.ode().total_force(delta, v_half) : 0.0);
      const bool exited = collision.record(EventKind::exit, t, y); // not if tolerance noise
      finish(i, exited ? Outcome::exited : Outcome::no_exit, result);
      return true;
    }
    lane.timing.acted(t, delta, -m_[i] * a_[i]);
    // Settled (Collision::settled), looked at every 64 steps as verlet.cpp does.
    if (t >= lane.horizon || (lane.counts.steps % 64 == 0 && collision.settled(y))) {
      finish(i, Outcome::no_exit, result);
      return true;
    }
    return false;
  }

  std::size_t n_, active_ = n_; // lanes, and lanes still running (the first slots)
  long steps_ = 0;              // the steps every running lane has made
  SharedClock clock_;
  LanePower power_;
  double p_ = 1;
  bool seed_ = true;
  std::vector<std::size_t> slot_lane_; // the lane (its index among the results) in each slot
  // The lanes' state, the previous step position, the step's intermediates and the constants.
  std::vector<double> t_, d_, v_, w_, a_, power_at_, dt_, m_, k_, c_, phase_;
  std::vector<double> d_old_, v_old_, w_old_, t_old_, v_half_, v_predicted_, da_;
  std::vector<Lane> lane_;
  std::vector<std::unique_ptr<Collision>> collisions_;
};

} // namespace

std::vector<Result<double>> solve_verlet_batch(std::span<const Problem<double>> problems,
                                               std::span<const Options<double>> options) {
  return solve_in_lanes(problems, options, solve_verlet, [&](std::span<const std::size_t> lanes) {
    return VerletBatch(problems, options, lanes).run();
  });
}

} // namespace pldamp::solvers::detail
