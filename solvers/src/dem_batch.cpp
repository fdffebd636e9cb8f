// The batch path of dem-verlet, dem-symplectic-euler and dem-leapfrog: N contacts of one scheme
// stepped together, one lane each, the state held as structure of arrays so that the arithmetic
// of a step is one loop over the lanes the compiler vectorizes (docs/performance.md, "Batch
// mode"). Each lane computes what dem.cpp computes for its problem, bit for bit: the same
// operations in the same order on the same values (tests/solvers/batch_test.cpp), so a lane's
// Result is the scalar solver's.
//
// What differs is where the work goes:
// - |δ|^β, the one power of a step, is std::pow per lane as in ContactOde::dashpot_factor, except
//   where std::pow is exact and so any exact evaluation equals it: β = 0 (1) and β = 1 (|δ|), the
//   seed's p = 1 and p = 3. sqrt for β = 1/2 would not do: glibc's pow(x, 0.5) differs from the
//   correctly rounded sqrt(x) in the last bit for about 1 in 1100 arguments (measured, glibc
//   2.36), and a lane must round as the scalar path does.
// - The dissipated work W = ½mv0² − ½mv² − kδ^(p+1)/(p+1), which dem.cpp evaluates after every
//   step, is a function of (δ, v) alone and is read only where an event is recorded or a state is
//   tested for being finite: the lanes evaluate it there, with the same expression. A state whose
//   W might overflow (v or δ beyond the lane's bound below) has it evaluated at every step, so
//   that a diverging lane is found at the same step.
// - The bookkeeping (the events, the budget) is inline per lane instead of calls per step.
// Lanes must share p and β (one power per batch) and have no sample times; solve_dem_batch
// hands any other lane to the scalar solver.
#include "batch_lanes.hpp"
#include "collision.hpp"
#include "methods.hpp"
#include "step_timing.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace pldamp::solvers::detail {
namespace {

class DemBatch {
public:
  DemBatch(DemScheme scheme, std::span<const Problem<double>> problems,
           std::span<const Options<double>> options, std::span<const std::size_t> lanes)
      : scheme_(scheme), n_(lanes.size()),
        power_(ContactOde<double>(problems[lanes[0]]).damping_exponent()) {
    const ContactOde<double> first(problems[lanes[0]]);
    p_ = first.p();
    seed_ = first.damping_exponent() == (p_ - 1) / 2; // as ContactOde decides it
    resize();
    collisions_.reserve(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      const Problem<double>& problem = problems[lanes[i]];
      const Options<double> stepped = with_fixed_step(problem, options[lanes[i]]);
      collisions_.push_back(std::make_unique<Collision>(problem, stepped));
      const Collision& collision = *collisions_.back();
      const ContactOde<double>& ode = collision.ode();
      slot_lane_[i] = i;
      dt_[i] = *stepped.fixed_step;
      m_[i] = ode.m();
      k_[i] = ode.k();
      c_[i] = ode.damping_coefficient();
      // DemContact: t = (φ − 1)Δt, δ = v0 t, v = v0.
      t_[i] = (stepped.onset_phase - 1) * dt_[i];
      d_[i] = ode.v0() * t_[i];
      v_[i] = ode.v0();
      f_[i] = 0;
      lane_[i].capped = stepped.end == End::force;
      lane_[i].want_force = (stepped.want & want_normal_force) != 0;
      lane_[i].horizon = collision.horizon();
      lane_[i].max_steps = stepped.max_steps;
      lane_[i].t_last = t_[i];
      lane_[i].last_d = d_[i];
      lane_[i].last_v = v_[i];
      // Beyond these W = E0 − ½mv² − k|δ|^(p+1)/(p+1) may overflow (1e299 with a margin for the
      // rounding of the power): W is then evaluated at each step, as dem.cpp does.
      lane_[i].v_bound = std::sqrt(1e299 / ode.m());
      lane_[i].d_bound = std::exp((std::log(1e299) - std::log(ode.k())) / (ode.p() + 1)) / 2;
    }
  }

  std::vector<Result<double>> run() {
    std::vector<Result<double>> results(n_);
    std::size_t completed = 0;
    for (std::size_t i = 0; i < n_; ++i) {
      if (const auto spent = collisions_[i]->out_of_budget(0)) { // dem.cpp looks before a step
        finish(i, *spent, results[i]);
        ++completed;
      }
    }
    while (active_ > 0) {
      if (completed > 0) {
        compact_lanes(active_, arrays(), lane_, collisions_, slot_lane_);
      }
      if (active_ > 0) {
        // The running lanes have all made steps_ steps; their budgets are looked at after steps
        // 256, 512, ... (after_step_in_full), with the batch's time shared among them first.
        if ((steps_ + 1) % 256 == 0) {
          clock_.share(collisions_, active_);
        }
        ++steps_;
        completed = scheme_ == DemScheme::verlet ? verlet_step(results) : force_first_step(results);
      }
    }
    return results;
  }

private:
  struct Lane {
    bool done = false, capped = false, want_force = false;
    bool touched = false, ended = false, peak_found = false;
    double t_last = 0, last_d = 0, last_v = 0; // the last step position and the code's state
    bool last_initial = true;                  // last_ is the start: W = 0 there (dem.cpp)
    LaneCounts counts;
    StepTiming timing;
    long max_steps = 0;
    double v_bound = 0, d_bound = 0, horizon = 0;
  };

  std::array<std::vector<double>*, 10> arrays() {
    return {&t_, &d_, &v_, &f_, &dt_, &m_, &k_, &c_, &da_, &force_};
  }

  void resize() {
    for (std::vector<double>* array : arrays()) {
      array->assign(n_, 0.0);
    }
    lane_.assign(n_, Lane{});
    slot_lane_.resize(n_);
  }

  // m · v' of ContactOde::rhs at (δ, v) for every running lane (meaningful where δ > 0): the
  // contact force on the overlap coordinate, DemContact::force before its cases.
  void contact_forces() {
    power_({d_.data(), active_}, {da_.data(), active_});
    if (seed_) {
      for (std::size_t i = 0; i < active_; ++i) {
        const double spring = k_[i] * (da_[i] * da_[i] * d_[i]);
        const double dashpot = c_[i] * da_[i];
        force_[i] = m_[i] * (-(dashpot * v_[i] + spring) / m_[i]);
      }
      return;
    }
    for (std::size_t i = 0; i < active_; ++i) {
      const double magnitude = std::pow(std::abs(d_[i]), p_);
      const double spring = k_[i] * (d_[i] < 0 ? -magnitude : magnitude);
      const double dashpot = c_[i] * da_[i];
      force_[i] = m_[i] * (-(dashpot * v_[i] + spring) / m_[i]);
    }
  }

  // DemContact::force for lane i at time t from the computed force_[i].
  double contact_force(std::size_t i, double t) {
    Lane& lane = lane_[i];
    if (d_[i] <= 0) {
      lane.ended = lane.touched;
      if (lane.ended) {
        lane.timing.ended(t, d_[i], 0);
      }
      return 0;
    }
    lane.touched = true;
    ++lane.counts.rhs_evals;
    const double force = force_[i];
    if (lane.want_force && !lane.peak_found) {
      lane.counts.offer(t, -force);
    }
    if (lane.capped && force >= 0) {
      lane.ended = true;
      lane.timing.ended(t, d_[i], -force);
      return 0;
    }
    lane.timing.acted(t, d_[i], -force);
    return force;
  }

  double dissipated(std::size_t i, double delta, double v) const {
    const ContactOde<double>& ode = collisions_[i]->ode();
    return ode.energy_scale() - ode.mechanical_energy(std::max(delta, 0.0), v);
  }

  // DemContact::after_step for lane i at its current (t, δ, v); true when the lane is complete.
  // Most steps record nothing and stay within every bound: they only move the last position on.
  [[gnu::always_inline]] bool after_step(std::size_t i, Result<double>& result) {
    Lane& lane = lane_[i];
    const double t = t_[i], delta = d_[i], v = v_[i];
    const bool routine = !(lane.touched && !lane.peak_found && delta < lane.last_d) &&
                         !lane.ended && std::abs(v) <= lane.v_bound &&
                         std::abs(delta) <= lane.d_bound && t < lane.horizon &&
                         lane.counts.steps < lane.max_steps && lane.counts.steps % 256 != 0;
    if (routine) {
      lane.t_last = t;
      lane.last_d = delta;
      lane.last_v = v;
      lane.last_initial = false;
      return false;
    }
    return after_step_in_full(i, result);
  }

  [[gnu::noinline]] bool after_step_in_full(std::size_t i, Result<double>& result) {
    Lane& lane = lane_[i];
    Collision& collision = *collisions_[i];
    const double t = t_[i], delta = d_[i], v = v_[i];
    if (lane.touched && !lane.peak_found && delta < lane.last_d) {
      lane.peak_found = true;
      const State last{lane.last_d, lane.last_v,
                       collision.with_work() && !lane.last_initial
                           ? dissipated(i, lane.last_d, lane.last_v)
                           : 0.0};
      if (collision.record(EventKind::peak, lane.t_last, last)) {
        finish(i, Outcome::peak, result);
        return true;
      }
    }
    lane.t_last = t;
    lane.last_d = delta;
    lane.last_v = v;
    lane.last_initial = false;
    const bool unbounded = !(std::abs(v) <= lane.v_bound && std::abs(delta) <= lane.d_bound);
    if ((lane.ended && lane.peak_found && collision.pending(EventKind::exit)) || unbounded) {
      const State y{delta, v, collision.with_work() ? dissipated(i, delta, v) : 0.0};
      if (lane.ended && lane.peak_found && collision.pending(EventKind::exit)) {
        const bool exited = collision.record(EventKind::exit, t, y);
        finish(i, exited ? Outcome::exited : Outcome::no_exit, result);
        return true;
      }
      if (t >= collision.horizon()) {
        finish(i, Outcome::no_exit, result);
        return true;
      }
      if (Collision::diverged(y)) {
        finish(i, Outcome::unstable, result);
        return true;
      }
    } else if (t >= collision.horizon()) {
      finish(i, Outcome::no_exit, result);
      return true;
    }
    // Within the bounds W is finite: the state is finite iff δ and v are (already tested above
    // when out of them).
    if (lane.counts.steps >= collision.options().max_steps || lane.counts.steps % 256 == 0) {
      if (const auto spent = collision.out_of_budget(lane.counts.steps)) {
        finish(i, *spent, result);
        return true;
      }
    }
    return false;
  }

  void finish(std::size_t i, Outcome outcome, Result<double>& result) {
    Lane& lane = lane_[i];
    result = lane.counts.finish(*collisions_[i], outcome);
    lane.timing.fill(result);
    lane.done = true;
    dt_[i] = 0; // the lane stands still from here on (masked)
    f_[i] = 0;
  }

  // One LAMMPS step in every running lane (dem.cpp, DemScheme::verlet); returns the lanes
  // completed.
  std::size_t verlet_step(std::vector<Result<double>>& results) {
    const std::size_t n = active_;
    for (std::size_t i = 0; i < n; ++i) {
      v_[i] += dt_[i] / 2 * f_[i] / m_[i]; // half kick
      d_[i] += dt_[i] * v_[i];             // drift
    }
    contact_forces();
    for (std::size_t i = 0; i < n; ++i) {
      if (!lane_[i].done) {
        f_[i] = contact_force(i, t_[i] + dt_[i]);
      }
    }
    for (std::size_t i = 0; i < n; ++i) {  // a finished lane: Δt = 0 and f = 0, it stands still
      v_[i] += dt_[i] / 2 * f_[i] / m_[i]; // half kick
      t_[i] += dt_[i];
    }
    std::size_t completed = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!lane_[i].done) {
        ++lane_[i].counts.steps;
        completed += after_step(i, results[slot_lane_[i]]) ? 1 : 0;
      }
    }
    return completed;
  }

  // One Chrono or YADE step in every running lane (dem.cpp: the force at the start of the step).
  std::size_t force_first_step(std::vector<Result<double>>& results) {
    const std::size_t n = active_;
    contact_forces();
    std::size_t completed = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (lane_[i].done) {
        continue;
      }
      f_[i] = contact_force(i, t_[i]);
      if (lane_[i].ended) {
        // No force from here on: the body leaves with v_n. dem.cpp leaves its loop and, with the
        // exit pending, ends the contact at the state it holds; otherwise as the loop left it.
        if (lane_[i].peak_found && collisions_[i]->pending(EventKind::exit)) {
          // Ended with the exit pending: records it, the lane is done.
          after_step(i, results[slot_lane_[i]]);
        } else { // dem.cpp's outcome is still its initial one
          finish(i, Outcome::step_limit, results[slot_lane_[i]]);
        }
        ++completed;
        continue;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      v_[i] += dt_[i] * f_[i] / m_[i];
      d_[i] += dt_[i] * v_[i];
      t_[i] += dt_[i];
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (lane_[i].done) {
        continue;
      }
      ++lane_[i].counts.steps;
      completed += after_step(i, results[slot_lane_[i]]) ? 1 : 0;
    }
    return completed;
  }

  DemScheme scheme_;
  std::size_t n_, active_ = n_; // lanes, and lanes still running (the first slots)
  long steps_ = 0;              // the steps every running lane has made
  SharedClock clock_;
  LanePower power_;
  double p_ = 1;
  bool seed_ = true;
  std::vector<std::size_t> slot_lane_; // the lane (its index among the results) in each slot
  // The lanes' state and constants, structure of arrays.
  std::vector<double> t_, d_, v_, f_, dt_, m_, k_, c_, da_, force_;
  std::vector<Lane> lane_;
  std::vector<std::unique_ptr<Collision>> collisions_;
};

} // namespace

std::vector<Result<double>> solve_dem_batch(DemScheme scheme,
                                            std::span<const Problem<double>> problems,
                                            std::span<const Options<double>> options) {
  return solve_in_lanes(
      problems, options,
      [&](const Problem<double>& problem, const Options<double>& lane) {
        return solve_dem(scheme, problem, lane);
      },
      [&](std::span<const std::size_t> lanes) {
        return DemBatch(scheme, problems, options, lanes).run();
      });
}

} // namespace pldamp::solvers::detail
