// The analytic layer's templates, instantiated once per precision of core's list.
//
// The closed forms are header templates, so every translation unit that evaluates them in four
// precisions instantiated and optimised them again: in the harness that was half the compile time
// of its heaviest units (commands_analytic.cpp: 22 s, 11 s with the declarations below). A target
// linking pldamp::analytic_instances compiles with PLDAMP_ANALYTIC_EXTERN and sees these as
// explicit instantiation declarations; analytic/src/instances.cpp defines them. A consumer of the
// header-only pldamp::analytic needs neither.
#pragma once

#include "pldamp/analytic/contact.hpp"
#include "pldamp/analytic/conventions.hpp"
#include "pldamp/analytic/observables.hpp"
#include "pldamp/analytic/quadrature.hpp"
#include "pldamp/analytic/seed.hpp"
#include "pldamp/analytic/special.hpp"
#include "pldamp/analytic/time.hpp"
#include "pldamp/analytic/trajectory.hpp"
#include "pldamp/analytic/trajectory_ends.hpp"

// The instantiations of one precision, each preceded by `prefix` (extern, or nothing).
#define PLDAMP_ANALYTIC_INSTANCES(prefix, Real)                                                    \
  prefix template class Contact<Real>;                                                             \
  prefix template class ScaledTime<Real>;                                                          \
  prefix template class Trajectory<Real>;                                                          \
  prefix template class OnsetSeries<Real>;                                                         \
  prefix template class SlowDecay<Real>;                                                           \
  prefix template Damping<Real> damping_from_log_e(const Real&);                                   \
  prefix template Damping<Real> damping_from_e(const Real&);                                       \
  prefix template Damping<Real> damping_from_one_minus_e(const Real&);                             \
  prefix template Damping<Real> damping_from_alpha_eff(const Real&);                               \
  prefix template Damping<Real> damping_from_e_cap(const Real&);                                   \
  prefix template Real log_restitution(const Damping<Real>&);                                      \
  prefix template Real restitution(const Damping<Real>&);                                          \
  prefix template Real peak_exponent(const Damping<Real>&);                                        \
  prefix template Real peak_phase(const Damping<Real>&);                                           \
  prefix template Real capped_restitution(const Damping<Real>&);                                   \
  prefix template NormalForcePeak<Real> normal_force_peak(const Damping<Real>&, const Real&,       \
                                                          const Real&);                            \
  prefix template Real restitution(const Contact<Real>&);                                          \
  prefix template Real log_delta_max(const Contact<Real>&);                                        \
  prefix template Real delta_max(const Contact<Real>&);                                            \
  prefix template Real spring_force_max(const Contact<Real>&);                                     \
  prefix template Real normal_force_max(const Contact<Real>&);                                     \
  prefix template Real t_normal_force_max(const Contact<Real>&);                                   \
  prefix template Real log_time_scale(const Contact<Real>&);                                       \
  prefix template Real t_peak(const Contact<Real>&);                                               \
  prefix template Real energy_load(const Contact<Real>&);                                          \
  prefix template Real energy_unload(const Contact<Real>&);                                        \
  prefix template Real log_undamped_duration(const Contact<Real>&);                                \
  prefix template Real undamped_duration(const Contact<Real>&);                                    \
  prefix template Real contact_duration(const Contact<Real>&);                                     \
  prefix template Real duration_ratio(const Contact<Real>&);                                       \
  prefix template Real duration_ratio_slope(const Real&);                                          \
  prefix template Real duration_ratio_curvature(const Real&);                                      \
  prefix template Real capped_restitution(const Contact<Real>&);                                   \
  prefix template Real cut_time(const Contact<Real>&);                                             \
  prefix template Real dt_crit_seed(const Contact<Real>&);                                         \
  prefix template Real dt_crit_tangent(const Contact<Real>&);                                      \
  prefix template Observables<Real> observables(const Contact<Real>&, unsigned);                   \
  prefix template Real tsuji_polynomial(const Real&);                                              \
  prefix template Real alpha_set(const Convention&, const Real&, const Real&);                     \
  prefix template Real e_given(const Real&, const Real&, bool);                                    \
  prefix template std::optional<Real> e_to_enter(const Convention&, const Real&, const Real&,      \
                                                 bool);                                            \
  prefix template Real log_duration_ratio(const Damping<Real>&, const Real&, const Real&);         \
  prefix template Real log_undamped_scaled_duration(const Real&);                                  \
  prefix template Real log_scaled_duration(const Damping<Real>&, const Real&);                     \
  prefix template Real log_abs_gamma_ratio(const Real&, const Real&);                              \
  prefix template Real log_gamma(const Real&);                                                     \
  prefix template Real log_abs_gamma(const Real&, const Real&);                                    \
  prefix template const JacobiRule<Real>& jacobi_rule(const Real&, int);                           \
  prefix template Real seed::evaluate(seed::Formula, const Contact<Real>&);                        \
  prefix template Real seed::alpha_of_e(const Real&, const Real&);

#if defined(PLDAMP_ANALYTIC_EXTERN) && PLDAMP_ANALYTIC_EXTERN
namespace pldamp::analytic {
#define PLDAMP_ANALYTIC_DECLARE(Real, name) PLDAMP_ANALYTIC_INSTANCES(extern, Real)
PLDAMP_FOR_EACH_PRECISION(PLDAMP_ANALYTIC_DECLARE)
#undef PLDAMP_ANALYTIC_DECLARE
} // namespace pldamp::analytic
#endif
