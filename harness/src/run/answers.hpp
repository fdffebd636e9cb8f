// What an external program's answers and handshake are held to (docs/external.md "The protocol,
// version 1"): the invariants pldamp's own solvers are held to (solvers/src/collision.cpp,
// BasicCollision::violated_invariant), and the settings of a configuration it says it honours.
#pragma once

#include "scene/scene.hpp"

#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// The fixed step of a configuration swept by steps per contact or dt (MATH.md §5: Δt = π δ_u/v0
// over the steps, as pldamp's own fixed-step schemes take it), none for an error-controlled one.
std::optional<double> step_of(const SolverConfig& config, const solvers::Problem<double>& problem);

// How far an answer's e may exceed 1, and its energy balance miss, relative to ½ m v0², as
// pldamp's own solvers are allowed: with a fixed step min((ωΔt)²/8, 1/4), ω² = k p δ_u^(p−1)/m
// at the undamped peak δ_u (the stiffest the contact gets); under error control
// min(1e4 tol, √tol) + 1000 ε, tol the rtol (or atol over the problem's scales, where larger),
// and for a program given neither, its own default taken as rtol = 1e-6.
double answer_allowance(const SolverConfig& config, const solvers::Problem<double>& problem);

// Why `value`, an answer's `key` (e, delta_max, t_peak, tau, energy_load or energy_unload), can
// be no answer to `problem` from a program run as `config`, whatever the answer's other values;
// empty when it can be one. Impossible: not finite (τ may be infinite); negative, or for an
// energy dissipated below −allowance · ½ m v0² (energy gained); e above 1 beyond the allowance;
// δ_max, t_peak or τ not positive; δ_max above the undamped peak δ_u beyond the allowance (and,
// at a fixed step Δt, the v0 Δt a step may overshoot by: (1 + allowance)(δ_u + v0 Δt)).
std::string impossible_value(std::string_view key, double value, const SolverConfig& config,
                             const solvers::Problem<double>& problem);

// Why an answer (the program's outcome and values for `problem`, asked with `options`) is
// impossible; empty when it is not. Impossible: a value impossible_value refuses; `exited` with τ
// infinite; `peak` where e, τ or the energies were wanted; `no_exit` with e ≠ 0; δ_max above
// v0 t_peak (1 + allowance) (compressed faster than v0); τ not after t_peak; at the overlap end
// τ below 2 δ_max/v0 (1 − allowance) (in and out faster than v0); under error control the energy
// balance ½ m v0² = ½ m (e v0)² + W off by more than the allowance (at the force end:
// W + ½ m (e v0)² above it, the spring keeping the rest). answers.cpp derives the bounds on δ_max,
// t_peak and τ: every damping ≥ 0 keeps them.
std::string impossible_answer(const solvers::Result<double>& answer, const SolverConfig& config,
                              const solvers::Problem<double>& problem,
                              const solvers::Options<double>& options);

// The settings a configuration sends (steps_per_contact, dt, onset_phase when it runs more than
// one phase, rtol, atol, and options.KEY for each key of its options) that are not among those a
// program declared in its handshake's `honours`. steps_per_contact is honoured by a program
// that honours dt (it is sent with its dt).
std::vector<std::string> settings_not_honoured(const SolverConfig& config,
                                               const std::vector<std::string>& honours);

} // namespace pldamp::harness
