// The physical equation of MATH.md §1 as a first-order system, for every solver in solvers/:
//
//     δ' = v,   v' = −(c |δ|^β v + k sgn(δ) |δ|^p) / m,   W' = c |δ|^β v²
//
// with c = α √(m k), β the damping exponent (the seed's a = (p − 1)/2 unless the problem states
// one, MATH.md §12) and W the work done by the dashpot (the dissipated energy, integrated so that
// energy splits are measured rather than assumed).
//
// Extension to δ < 0. An integrator steps across the exit before it finds it, so the right-hand
// side must exist there. |δ|^a in the dashpot and sgn(δ)|δ|^p in the spring make the extension
// analytic for p = 1 (the linear oscillator) and p = 5 (δ⁵ and δ² are polynomials), so error
// control is not fooled there by a kink the model does not have; for other p the power law is not
// analytic at δ = 0 anyway. Events are located on the contact side.
//
// Natural scales (from the undamped energy balance k δ_u^(p+1)/(p+1) = m v0²/2 only; no solution
// of the damped equation is used): δ_u, v0, KE0 = m v0²/2 and time δ_u/v0. They set the default
// absolute tolerances (Collision::absolute_tolerances), the default horizon and verlet's step.
#pragma once

#include "pldamp/solvers/problem.hpp"

#include <array>
#include <cmath>

namespace pldamp::solvers {

template <SupportedReal Real>
class ContactOde {
public:
  explicit ContactOde(const Problem<Real>& problem)
      : ContactOde(problem.p, problem.m, problem.k, problem.v0,
                   problem.alpha * sqrt_of(problem.m * problem.k), problem.beta()) {
    problem.validate();
  }

  // m δ'' + c δ^β δ' + k δ^p = 0 from its coefficients, v0 = 1, nothing validated: for evaluating
  // its functions on the state of an equation already scaled (the taylor solver's contact series,
  // whose scaled equation is this one with m = 1, k = κ, c = γ: two_power_series.hpp).
  static ContactOde from_coefficients(const Real& p, const Real& m, const Real& k, const Real& c,
                                      const Real& beta) {
    return ContactOde(p, m, k, Real(1), c, beta);
  }

  Real p() const { return p_; }
  Real m() const { return m_; }
  Real k() const { return k_; }
  Real v0() const { return v0_; }
  Real damping_coefficient() const { return c_; }

  Real delta_scale() const { return delta_scale_; }
  Real time_scale() const { return delta_scale_ / v0_; }
  Real energy_scale() const { return m_ * v0_ * v0_ / 2; }

  Real damping_exponent() const { return a_; }

  // |δ|^β, the dashpot's overlap factor; 1 for β = 0 (0^0 = 1 is the linear dashpot).
  Real dashpot_factor(const Real& delta) const {
    using std::abs;
    using std::pow;
    return pow(abs(delta), a_);
  }
  // sgn(δ)|δ|^p from |δ|^β: one power less for the seed's β = (p − 1)/2, where 2β + 1 = p.
  Real spring_factor(const Real& delta, const Real& d_a) const {
    using std::abs;
    using std::pow;
    if (seed_) {
      return d_a * d_a * delta;
    }
    const Real magnitude = pow(abs(delta), p_);
    return delta < 0 ? -magnitude : magnitude;
  }

  // (δ', v', W') at (δ, v); `with_work` false leaves W' = 0 (W is then not wanted).
  std::array<Real, 3> rhs(const Real& delta, const Real& v, bool with_work) const {
    const Real d_a = dashpot_factor(delta);
    const Real spring = k_ * spring_factor(delta, d_a); // k sgn(δ)|δ|^p
    const Real dashpot = c_ * d_a;
    return {v, -(dashpot * v + spring) / m_, with_work ? dashpot * v * v : Real(0)};
  }

  // With F = k δ^p + c δ^β v the total normal force (positive = repulsive),
  // F / δ^β = k sgn(δ)|δ|^(p−β) + c v: the sign of the force for δ > 0 without the factor
  // δ^β that vanishes at contact. It is c v0 > 0 at t = 0 (0 if α = 0), so the force-cut event
  // never fires at the start, and at δ = 0 it equals c v < 0 while unloading (β < p), so the cut
  // is never later than the overlap exit.
  Real force_sign(const Real& delta, const Real& v) const {
    using std::abs;
    using std::pow;
    if (seed_) {
      return k_ * dashpot_factor(delta) * delta + c_ * v;
    }
    const Real magnitude = pow(abs(delta), p_ - a_);
    return k_ * (delta < 0 ? -magnitude : magnitude) + c_ * v;
  }

  // The total normal force F = k δ^p + c δ^β v (δ > 0; positive = repulsive).
  Real total_force(const Real& delta, const Real& v) const {
    const Real d_a = dashpot_factor(delta);
    return k_ * spring_factor(delta, d_a) + c_ * d_a * v;
  }

  // The sign of dF/dt = k p δ^(p−1) v + c β δ^(β−1) v² + c δ^β a (a = −F/m), positive while the
  // normal force grows: the event function of its peak. For β > 0 the rate is multiplied by
  // δ^(1−β) > 0,
  //     k p δ^(p−β) v + c β v² + c δ a,
  // finite at δ = 0 for every β ≤ p (β < 1 has an infinite rate there; β > 1 a rate that
  // underflows to 0 over a whole stretch at large p, which root finders take for a root), and
  // c β v0² > 0 at the onset: the force grows from 0. For β = 0 the dashpot's c v0 acts at once,
  // and the rate at the onset, (k v0 if p = 1) − c² v0/m, may already be < 0: the peak is then at
  // the onset (BasicCollision::offer_onset_force). Undamped, F = k δ^p peaks with δ: the sign of v.
  Real force_rate_sign(const Real& delta, const Real& v) const {
    using std::abs;
    using std::pow;
    if (c_ == 0) {
      return v;
    }
    const Real d = abs(delta);
    const Real d_a = dashpot_factor(d);
    if (a_ > 0) {
      // Fewer powers (the event is evaluated a dozen times a collision by the taylor solver's
      // root finder): δ^(p−β) is δ^β δ for the seed's β and δ itself for p − β = 1 (Hertz's
      // spring with the viscoelastic dashpot), and δ^p = δ^(p−β) δ^β: one power where there
      // were two (the seed's β) or three.
      const Real d_spring = seed_ ? d_a * d : (p_ - a_ == 1 ? d : pow(d, p_ - a_));
      const Real spring = seed_ ? spring_factor(d, d_a) : d_spring * d_a;
      const Real acceleration = -(k_ * spring + c_ * d_a * v) / m_;
      return k_ * p_ * d_spring * v + c_ * a_ * v * v + c_ * d * acceleration;
    }
    const Real acceleration = -(k_ * spring_factor(d, d_a) + c_ * d_a * v) / m_;
    const Real spring_rate = p_ == 1 ? k_ * v : k_ * p_ * pow(d, p_ - 1) * v;
    return spring_rate + c_ * acceleration;
  }

  // Dissipated-work-free mechanical energy ½ m v² + k |δ|^(p+1)/(p+1).
  Real mechanical_energy(const Real& delta, const Real& v) const {
    using std::abs;
    return m_ * v * v / 2 +
           k_ * spring_factor(abs(delta), dashpot_factor(delta)) * abs(delta) / (p_ + 1);
  }

  // ∂(δ', v', W')/∂(δ, v, W), row-major. For 0 < β < 1, ∂|δ|^β/∂δ = β|δ|^(β−1) is infinite at
  // δ = 0, where every contact starts and ends. Implicit methods use this matrix only inside a
  // (modified) Newton iteration, which converges with any matrix close enough to the true one at
  // the iterates; the singular factor is therefore evaluated at max(|δ|, delta_floor), finite
  // everywhere and exact above the floor. Below it the error h·|∂f/∂δ − J| ≤ h c a δ^(a−1)|v|/m
  // stays small because the steps that start there are short (h ~ δ/v0, so h δ^(a−1) ~ δ^a/v0).
  std::array<std::array<Real, 3>, 3> jacobian(const Real& delta, const Real& v, bool with_work,
                                              const Real& delta_floor) const {
    using std::abs;
    using std::max;
    using std::pow;
    const Real d_a = dashpot_factor(delta);
    const Real floored = max(abs(delta), delta_floor);
    const Real sign = delta < 0 ? Real(-1) : Real(1);
    const Real d_da = a_ == 0 ? Real(0) : sign * a_ * pow(floored, a_ - 1); // ∂|δ|^a/∂δ
    // ∂(k sgn δ|δ|^p)/∂δ = k p |δ|^(p−1), from |δ|^p / |δ| away from 0 (p = 1: k).
    const Real spring_slope = seed_ ? k_ * p_ * d_a * d_a : k_ * p_ * pow(abs(delta), p_ - 1);
    const Real w = with_work ? Real(1) : Real(0);
    return {{{Real(0), Real(1), Real(0)},
             {-(c_ * v * d_da + spring_slope) / m_, -c_ * d_a / m_, Real(0)},
             {w * c_ * v * v * d_da, w * 2 * c_ * d_a * v, Real(0)}}};
  }

  // The last stretch of a contact from a small overlap δ1 > 0 moving out (v1 < 0) to δ = 0, by a
  // local series of the physical equation with δ as the independent variable (MATH.md §9). With
  // u = −v > 0:
  //     du/dδ = (c/m) δ^β − (k/m) δ^p / u,   dt/dδ = −1/u,   dW/dδ = −c δ^β u.
  // Integrating from 0, with b1 = β + 1, b2 = p + 1 and u_e the exit speed,
  //     u(s) = u_e + (c/m) s^b1/b1 − (k/m) s^b2/(b2 u_e) + ...
  // and one Picard iteration around u1 = u(δ1) gives
  //     u_e = u1 − (c/m) δ1^b1/b1 + (k/m)[δ1^b2/(b2 u1) + (c/m) δ1^(b1+b2)/(b2 (b1+b2) u1²)]
  //     Δt  = (δ1/u_e)[1 − (c/m) δ1^b1/(b1(b1+1) u_e) + (c/m)² δ1^(2b1)/(b1²(2b1+1) u_e²)
  //                      + (k/m) δ1^b2/(b2(b2+1) u_e²)]
  //     ΔW  = c[u_e δ1^b1/b1 + (c/m) δ1^(2b1)/(2b1²) − (k/m) δ1^(b1+b2)/(b2(b1+b2) u_e)]
  // (1/u and s^β u expanded in powers of s^b1 and s^b2, integrated term by term; for the seed's
  // β, 2b1 = b2). The expansion parameters are ε_c = (c/m) δ1^b1 / u1 and ε_k = (k/m) δ1^b2 / u1²
  // (exit_series_parameter); the first neglected terms are O(ε³) relative. For p = 1 without a
  // spring, Δt is the series of ln(1 + cδ1/(m u_e)). The series needs no step across the branch
  // point at δ = 0.
  Real exit_series_parameter(const Real& delta1, const Real& v1) const {
    using std::max;
    using std::pow;
    return max(c_ * pow(delta1, a_ + 1) / (m_ * -v1), k_ * pow(delta1, p_ + 1) / (m_ * v1 * v1));
  }

  struct ExitStretch {
    Real duration, exit_velocity, work;
  };
  ExitStretch exit_stretch(const Real& delta1, const Real& v1) const {
    using std::pow;
    const Real b1 = a_ + 1, b2 = p_ + 1;
    const Real u1 = -v1;
    const Real cm = c_ / m_, km = k_ / m_;
    const Real d_b1 = pow(delta1, b1);
    const Real d_b2 = seed_ ? d_b1 * d_b1 : pow(delta1, b2);
    const Real ue = u1 - cm * d_b1 / b1 +
                    km * (d_b2 / (b2 * u1) + cm * d_b2 * d_b1 / (b2 * (b1 + b2) * u1 * u1));
    const Real duration =
        delta1 / ue *
        (1 - cm * d_b1 / (b1 * (b1 + 1) * ue) +
         (cm * cm * d_b1 * d_b1 / (b1 * b1 * (2 * b1 + 1)) + km * d_b2 / (b2 * (b2 + 1))) /
             (ue * ue));
    const Real work = c_ * (ue * d_b1 / b1 + cm * d_b1 * d_b1 / (2 * b1 * b1) -
                            km * d_b2 * d_b1 / (b2 * (b1 + b2) * ue));
    return {duration, -ue, work};
  }

private:
  ContactOde(const Real& p, const Real& m, const Real& k, const Real& v0, const Real& c,
             const Real& beta)
      : p_(p), m_(m), k_(k), v0_(v0), c_(c), a_(beta), seed_(a_ == (p - 1) / 2) {
    using std::exp;
    using std::log;
    // δ_u = ((p+1) m v0² / (2k))^(1/(p+1)) through logs: m, k, v0 may be 1e-9 ... 1e12.
    delta_scale_ = exp((log((p_ + 1) / 2) + log(m_) - log(k_) + 2 * log(v0_)) / (p_ + 1));
  }

  static Real sqrt_of(const Real& x) {
    using std::sqrt;
    return sqrt(x);
  }

  Real p_, m_, k_, v0_, c_, a_; // a_ is β
  bool seed_;                   // β = (p − 1)/2: δ^p = (δ^β)² δ
  Real delta_scale_;
};

} // namespace pldamp::solvers
