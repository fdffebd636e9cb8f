"""The adapter's side of pldamp's external-solver protocol, version 1 (docs/external.md "Your code in the loop").

An adapter calls serve() with its handshake facts and a function that solves one problem (a dict,
as pldamp wrote it) and returns the result's keys (outcome and observables; the id is added here).
An exception becomes an `error` record with its message, so one bad problem never ends the run.

contact_from_steps() reads a head-on contact off a DEM code's state after each time step, with
the definitions of pldamp's own replicas of the codes' loops (solvers/src/dem.cpp), so that a
code and its replica can be compared to rounding:
  e        the speed the code holds when the contact has ended, over v0;
  tau      the time of the first force evaluation that finds the contact over (no overlap, or,
           under a force cap, a clipped force), from the moment of contact;
  delta_max, t_peak   the largest overlap over the step positions and its time (no interpolation);
  energy_load, energy_unload   dissipated by balance with the code's velocity, at the peak and
           from the peak to the exit.
"""

import json
import math
import sys

PROTOCOL = "pldamp-solver"
VERSION = 1
# The settings of a fixed-step code (the handshake's `honours`): the step, sent both as
# steps_per_contact and as dt, and the onset phase.
FIXED_STEP_SETTINGS = ("steps_per_contact", "dt", "onset_phase")


def _number(x):
    """A JSON number, or "inf" for an infinite one (the protocol's spelling)."""
    return "inf" if isinstance(x, float) and math.isinf(x) and x > 0 else x


def _write(obj):
    sys.stdout.write(json.dumps({k: _number(v) for k, v in obj.items()}, allow_nan=False) + "\n")
    sys.stdout.flush()


def serve(solver, run_problem, *, p=None, ends=None, damping_exponent="seed", unavailable=None,
          honours=None):
    """Answers pldamp's handshake, then every problem line until standard input closes.

    solver: the adapter's name for what it runs (shown in reports).
    p, ends, damping_exponent, unavailable, honours: the handshake's optional keys (docs/external.md);
    honours lists the settings the adapter acts on (pldamp refuses a scene that sets another).
    """
    hello = sys.stdin.readline()
    try:
        asked = json.loads(hello)
    except json.JSONDecodeError:
        sys.exit("adapter: the first line is not pldamp's handshake: " + hello[:80])
    if asked.get("protocol") != PROTOCOL or asked.get("version") != VERSION:
        sys.exit("adapter: speaks %s version %d, was asked %r" % (PROTOCOL, VERSION, asked))
    reply = {"protocol": PROTOCOL, "version": VERSION, "solver": solver,
             "damping_exponent": damping_exponent}
    if p is not None:
        reply["p"] = list(p)
    if ends is not None:
        reply["ends"] = list(ends)
    if unavailable:
        reply["unavailable"] = unavailable
    if honours is not None:
        reply["honours"] = list(honours)
    _write(reply)
    for line in sys.stdin:
        if not line.strip():
            continue
        problem = json.loads(line)
        try:
            result = dict(run_problem(problem))
        except Exception as error:  # noqa: BLE001 - any failure is that record's, with its reason
            result = {"outcome": "error", "reason": "%s: %s" % (type(error).__name__, error)}
        result["id"] = problem["id"]
        _write(result)


def contact_from_steps(rows, problem):
    """Observables of one contact from the code's state after each step.

    rows: (t, delta, v, force) after each step in time order, t from the moment of contact, delta
    the overlap, v its rate as the code holds it (positive while loading), force the total normal
    force the code applied at that step's evaluation (0 when none acted or when it was clipped).
    problem: pldamp's problem dict (p, m, k, v0, end, want).
    Returns the result's keys: outcome and what was measured.
    """
    p, m, k, v0 = (float(problem[key]) for key in ("p", "m", "k", "v0"))
    capped = problem.get("end") == "force"
    kinetic0 = 0.5 * m * v0 * v0

    def dissipated(delta, v):
        # By balance: without damping it is 0 up to rounding, which must not read as negative
        # (the protocol's numbers are >= 0).
        work = kinetic0 - 0.5 * m * v * v - k * max(delta, 0.0) ** (p + 1) / (p + 1)
        return max(work, 0.0)

    result = {"outcome": "step_limit", "steps": len(rows)}
    touched, last = False, None
    for t, delta, v, force in rows:
        ended = touched and (delta <= 0 or (capped and force == 0))
        if touched and "delta_max" not in result and (delta < last[1] or ended):
            result.update(delta_max=last[1], t_peak=last[0])
            work_peak = dissipated(last[1], last[2])
            result["energy_load"] = work_peak
        if ended:
            result.update(outcome="exited", e=abs(v) / v0, tau=t)
            result["energy_unload"] = max(dissipated(delta, v) - work_peak, 0.0)
            return result
        touched = touched or delta > 0
        last = (t, delta, v)
    return result
