#!/usr/bin/python3
"""`pldamp timestep`'s answers checked outside pldamp's solver code (issue 47).

Each fixed-step scheme is written here again, as the DEM codes step a head-on contact
(docs/MATH.md §5), in numpy, over random onset phases at once: the contact begins at t = 0, the
first step position in contact is at t = φ Δt. For every case (scheme, p, e, tolerance, --tau-as)
the answer Δt must keep e, δ_max and τ (counted as --tau-as says) within the tolerance of the
closed forms (`pldamp observables`) at every phase tried (random ones, 0 and the largest double
below 1), and 1.25 Δt must break it at some phase. Where 1.25 Δt holds at every phase tried (the
error need not grow with Δt: τ counted as steps in contact is a sawtooth in τ/Δt), the answer's
tightness is checked at the first failing Δt it reports (≤ 1.02 Δt), at the phase it names and at
the random ones, in this script's own loop.

    python3 scripts/timestep_check.py build/harness/pldamp            # the CI subset
    python3 scripts/timestep_check.py build/harness/pldamp --all      # the whole table
    python3 scripts/timestep_check.py PLDAMP --phases 10000 --seed 1

Prints one line per case and exits 1 if any answer fails its check (or is not tight).
"""
import argparse
import json
import subprocess
import sys
import time

import numpy as np

SCHEMES = ["dem-verlet", "dem-symplectic-euler", "dem-leapfrog", "verlet-predicted"]
TAU_AS = ["first-step-out", "steps-in-contact", "crossing"]


def pldamp_json(pldamp, *args):
    out = subprocess.run([pldamp, *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def contact_forces(delta, v, p, k, c):
    """The total normal force k δ^p + c δ^β v, β = (p − 1)/2, where δ > 0 (0 elsewhere)."""
    d = np.maximum(delta, 0.0)
    return k * d**p + c * d ** ((p - 1) / 2) * v


def dem(scheme, phases, dt, p, m, k, c, v0, max_steps):
    """dem-verlet (LAMMPS), dem-symplectic-euler (Chrono), dem-leapfrog (YADE): e, δ_max, and the
    contact time three ways, per onset phase."""
    n = phases.size
    t = (phases - 1) * dt
    delta = v0 * t
    v = np.full(n, float(v0))
    f = np.zeros(n)
    touched = np.zeros(n, bool)
    done = np.zeros(n, bool)
    delta_max = np.zeros(n)
    acting = np.zeros(n, np.int64)
    t_act = np.zeros(n)
    d_act = np.zeros(n)
    e = np.full(n, np.nan)
    tau = np.full(n, np.nan)
    steps_tau = np.full(n, np.nan)
    crossing = np.full(n, np.nan)

    def evaluate(at_t, live):
        """The force at the step positions of `live`: acting, or the contact's end."""
        in_contact = live & (delta > 0)
        ended = live & ~in_contact & touched
        force = np.where(in_contact, contact_forces(delta, v, p, k, c), 0.0)
        touched[in_contact] = True
        acting[in_contact] += 1
        t_act[in_contact] = at_t[in_contact]
        d_act[in_contact] = delta[in_contact]
        np.maximum(delta_max, np.where(in_contact, delta, 0.0), out=delta_max)
        return force, ended

    def finish(ended, at_t, velocity):
        e[ended] = np.abs(velocity[ended]) / v0
        tau[ended] = at_t[ended]
        steps_tau[ended] = acting[ended] * dt
        crossing[ended] = t_act[ended] + (at_t[ended] - t_act[ended]) * (
            d_act[ended] / (d_act[ended] - delta[ended]))
        done[ended] = True

    for _ in range(max_steps):
        live = ~done
        if not live.any():
            break
        if scheme == "dem-verlet":
            v[live] += dt / 2 * f[live] / m
            delta[live] += dt * v[live]
            force, ended = evaluate(t + dt, live)
            f[live] = -force[live]
            v[live] += dt / 2 * f[live] / m
            t[live] += dt
            finish(ended, t, v)
        else:
            force, ended = evaluate(t, live)
            finish(ended, t, v)
            go = live & ~ended
            v[go] += dt * (-force[go]) / m
            delta[go] += dt * v[go]
            t[go] += dt
    return e, delta_max, {"first-step-out": tau, "steps-in-contact": steps_tau,
                          "crossing": crossing}


def verlet_predicted(phases, dt, p, m, k, c, v0, max_steps):
    """Velocity Verlet whose dashpot sees the predicted full-step velocity (verlet.cpp): δ_max
    from the cubic Hermite interpolant at the linear zero of v."""
    n = phases.size
    t = phases * dt
    delta = v0 * t
    v = np.full(n, float(v0))
    acc = -contact_forces(delta, v, p, k, c) / m
    acc[delta <= 0] = -(c * v0 if p == 1 else 0.0) / m
    done = np.zeros(n, bool)
    acting = (delta > 0).astype(np.int64)
    t_act = t.copy()
    d_act = delta.copy()
    delta_max = np.full(n, np.nan)
    e = np.full(n, np.nan)
    tau = np.full(n, np.nan)
    steps_tau = np.full(n, np.nan)
    crossing = np.full(n, np.nan)
    step = 0
    while step < max_steps and not done.all():
        step += 1
        live = ~done
        v_half = v + acc * dt / 2
        new_delta = delta + v_half * dt
        predicted = v + acc * dt
        new_acc = -np.where(new_delta > 0, contact_forces(new_delta, predicted, p, k, c), 0.0) / m
        new_v = v_half + new_acc * dt / 2
        new_t = (step + phases) * dt
        peak = live & np.isnan(delta_max) & (v > 0) & (new_v <= 0)
        theta = np.where(peak, v / np.where(peak, v - new_v, 1.0), 0.0)
        t2, t3 = theta * theta, theta**3
        hermite = ((2 * t3 - 3 * t2 + 1) * delta + (t3 - 2 * t2 + theta) * dt * v
                   + (-2 * t3 + 3 * t2) * new_delta + (t3 - t2) * dt * new_v)
        delta_max[peak] = hermite[peak]
        lost = live & ~np.isnan(delta_max) & (new_delta <= 0)
        e[lost] = np.abs(v_half[lost]) / v0
        tau[lost] = new_t[lost]
        steps_tau[lost] = acting[lost] * dt
        crossing[lost] = t_act[lost] + (new_t[lost] - t_act[lost]) * (
            d_act[lost] / (d_act[lost] - new_delta[lost]))
        stay = live & ~lost
        acting[stay] += 1
        t_act[stay] = new_t[stay]
        d_act[stay] = new_delta[stay]
        done |= lost
        delta = np.where(live, new_delta, delta)
        v = np.where(live, new_v, v)
        acc = np.where(live, new_acc, acc)
    return e, delta_max, {"first-step-out": tau, "steps-in-contact": steps_tau,
                          "crossing": crossing}


def worst_error(scheme, dt, answer, truth, tau_as, phases):
    p, m, k, v0 = answer["p"], answer["m"], answer["k"], answer["v0"]
    c = answer["alpha"] * np.sqrt(m * k)
    max_steps = int(5 * truth["tau"] / dt) + 10
    if scheme == "verlet-predicted":
        e, delta_max, taus = verlet_predicted(phases, dt, p, m, k, c, v0, max_steps)
    else:
        e, delta_max, taus = dem(scheme, phases, dt, p, m, k, c, v0, max_steps)
    errors = np.stack([np.abs(e / truth["e"] - 1), np.abs(delta_max / truth["delta_max"] - 1),
                       np.abs(taus[tau_as] / truth["tau"] - 1)])
    if np.isnan(errors).any():
        raise RuntimeError(f"{scheme} dt {dt}: a phase did not return")
    worst = errors.max(axis=0)
    i = int(worst.argmax())
    return float(worst[i]), float(phases[i])


def check(pldamp, scheme, p, e, tolerance, tau_as, phases):
    start = time.time()
    answer = pldamp_json(pldamp, "timestep", "--scheme", scheme, "--p", str(p), "--e", str(e),
                         "--tolerance", str(tolerance), "--tau-as", tau_as)
    seconds = time.time() - start
    truth = pldamp_json(pldamp, "observables", "--p", str(p), "--alpha",
                        repr(answer["alpha"]), "--v0", "1")
    dt = answer["dt"]
    at, at_phase = worst_error(scheme, dt, answer, truth, tau_as, phases)
    factor = 1.25
    beyond, beyond_phase = worst_error(scheme, factor * dt, answer, truth, tau_as, phases)
    if beyond <= tolerance:  # not monotone: the first failing Δt pldamp reports, at its phase too
        factor = answer["dt_failing"] / dt
        with_failing = np.append(phases, answer["failing_onset_phase"])
        beyond, beyond_phase = worst_error(scheme, answer["dt_failing"], answer, truth, tau_as,
                                           with_failing)
    ok = at <= tolerance and beyond > tolerance
    print(f"{'ok  ' if ok else 'FAIL'} {scheme:21} p {p:<4} e {e:<4} tol {tolerance:<6} "
          f"{tau_as:16} tau/dt {truth['tau'] / dt:9.1f}  worst {at / tolerance:.4f} tol "
          f"(phase {at_phase:.4f}; pldamp {answer['worst_error'] / tolerance:.4f} at "
          f"{answer['worst_onset_phase']:.4f})  {factor:.4g} dt: {beyond / tolerance:.3f} tol "
          f"(phase {beyond_phase:.17g})  [{seconds:.2f} s]", flush=True)
    return ok, factor != 1.25, seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("pldamp")
    parser.add_argument("--all", action="store_true", help="the whole table of issue 47")
    parser.add_argument("--phases", type=int, default=10000)
    parser.add_argument("--seed", type=int, default=47)
    args = parser.parse_args()
    phases = np.append(np.random.default_rng(args.seed).random(args.phases),
                       [0.0, np.nextafter(1.0, 0.0)])
    if args.all:
        cases = [(s, p, e, tol, a) for s in SCHEMES for p in (1, 1.5, 2) for e in (0.1, 0.5, 0.9)
                 for tol in (1e-2, 1e-3) for a in TAU_AS]
    else:  # the CI subset: every scheme and --tau-as once, at 1 %, across p and e
        cases = [("dem-verlet", 1.5, 0.5, 1e-2, "first-step-out"),
                 ("dem-verlet", 1, 0.1, 1e-2, "steps-in-contact"),
                 ("dem-symplectic-euler", 2, 0.9, 1e-2, "crossing"),
                 ("dem-leapfrog", 1, 0.5, 1e-2, "first-step-out"),
                 ("verlet-predicted", 1.5, 0.1, 1e-2, "crossing"),
                 ("verlet-predicted", 2, 0.5, 1e-2, "steps-in-contact")]
    results = [check(args.pldamp, *case, phases) for case in cases]
    failed = sum(not ok for ok, _, _ in results)
    nearer = sum(near for _, near, _ in results)
    seconds = [s for _, _, s in results]
    print(f"{len(cases) - failed} of {len(cases)} answers hold at {args.phases} random phases "
          f"(and 0, and the largest phase below 1) and break at 1.25 dt, or ({nearer} where "
          f"1.25 dt holds) at the first failing dt pldamp reports; `pldamp timestep` took "
          f"{min(seconds):.2f} to {max(seconds):.2f} s, {sum(seconds):.1f} s in all")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
