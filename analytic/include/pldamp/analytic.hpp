// The analytic layer of pldamp: closed forms of MATH.md §§2–6 in any SupportedReal.
#pragma once

#include "pldamp/analytic/contact.hpp"     // Contact, Damping, calibration (§1, §3, §4)
#include "pldamp/analytic/conventions.hpp" // what DEM codes set and really give (§5)
#include "pldamp/analytic/hertz.hpp"       // m, k, p from radii, moduli and densities (§13)
#include "pldamp/analytic/instances.hpp" // instantiated once, where pldamp::analytic_instances is linked
#include "pldamp/analytic/observables.hpp" // e, δ_max, t_peak, τ, energies, e_cap, Δt (§3, §4, §6)
#include "pldamp/analytic/quadrature.hpp"      // Gauss–Jacobi rules
#include "pldamp/analytic/special.hpp"         // regime-free functions, log|Γ(x+iy)|
#include "pldamp/analytic/time.hpp"            // t(s) and the closed-form τ (§3)
#include "pldamp/analytic/trajectory.hpp"      // δ(s), v(s), t(s), δ(t), phase portrait (§3)
#include "pldamp/analytic/trajectory_ends.hpp" // its onset series and slow decay (§3)
