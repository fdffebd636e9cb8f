"""The part of adapters/yade that runs inside YADE (`yade -n -j1 -x adapters/yade_session.py LAW`).

adapters/yade starts this once per run (YADE's start-up costs about 3 s) with YADE's own output
on standard error and pldamp's protocol on the file descriptor PLDAMP_PROTOCOL_FD; every problem
is then one YADE scene (O.reset()). See adapters/yade for the models and the mapping.
"""

import io
import math
import os
import sys

sys.dont_write_bytecode = True
# YADE runs this through execfile: __file__ is YADE's own; adapters/yade names the folder
sys.path.insert(0, os.environ["PLDAMP_ADAPTERS"])
import pldamp_protocol  # noqa: E402

from yade import O  # noqa: E402  (YADE's own modules, only inside YADE)
import yade  # noqa: E402

HORIZON_UNITS = 1000.0  # pldamp's default horizon, in delta_u/v0 (solvers: Collision::horizon)
MAX_STEPS = 1000000     # pldamp's default --max-steps
POISSON = 0.25          # Hertz-Mindlin: any nu; 1 - nu^2 = 0.9375 is exact in binary

# p, damping exponent, the YADE classes, the entry's name
LAWS = {
    "viscel": dict(p=1.0, beta=0.0, label="ViscElPhys (Law2_ScGeom_ViscElPhys_Basic)",
                   entry="en of ViscElMat (with tc)"),
    "hertz-mindlin": dict(p=1.5, beta=0.25, label="MindlinPhys (Law2_ScGeom_MindlinPhys_Mindlin)",
                          entry="en of Ip2_FrictMat_FrictMat_MindlinPhys"),
}
WANTED = {"e": ["e"], "delta_max": ["delta_max"], "t_peak": ["t_peak"], "tau": ["tau"],
          "energy_load": ["energy_load"], "energy_unload": ["energy_unload"],
          "energy": ["energy_load", "energy_unload"]}


class Unsupported(Exception):
    """A problem this law cannot run; becomes outcome `unsupported` with the message."""


def _number(table, key):
    value = table.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise Unsupported("%s must be a number (got %r)" % (key, value))
    value = float(value)
    if not math.isfinite(value):
        raise Unsupported("%s must be finite (got %r)" % (key, value))
    return value


def checked(problem, law):
    facts = LAWS[law]
    p = _number(problem, "p")
    if p != facts["p"]:
        raise Unsupported("YADE %s runs p = %g only (got p = %r)" % (law, facts["p"], p))
    asked = problem.get("damping_exponent", "seed")
    beta = (p - 1) / 2 if asked == "seed" else asked
    if isinstance(beta, bool) or not isinstance(beta, (int, float)) or \
            abs(float(beta) - facts["beta"]) > 1e-12:
        raise Unsupported("YADE %s has damping exponent %g (got %r)" % (law, facts["beta"], asked))
    if problem.get("end", "force") != "force":
        raise Unsupported("YADE's %s clips the total normal force at 0: end must be force (got %r)"
                          % (law, problem.get("end")))
    if "dt" not in problem:
        raise Unsupported("YADE steps with a fixed time step: the problem needs dt "
                          "(steps_per_contact), not rtol")
    values = {key: _number(problem, key) for key in ("m", "k", "v0", "alpha", "dt")}
    for key in ("m", "k", "v0", "dt"):
        if not values[key] > 0:
            raise Unsupported("%s must be > 0 (got %r)" % (key, values[key]))
    if not values["alpha"] >= 0:
        raise Unsupported("alpha must be >= 0 (got %r)" % values["alpha"])
    phase = _number(problem, "onset_phase") if "onset_phase" in problem else 0.0
    if not 0 <= phase < 1:
        raise Unsupported("onset_phase must be in [0, 1) (got %r)" % phase)
    options = problem.get("options") or {}
    if not isinstance(options, dict):
        raise Unsupported("options must be a table (got %r)" % (options,))
    unknown = sorted(set(options) - {"entry"})
    if unknown:
        raise Unsupported("the YADE adapter takes one option, entry (got %s)" % ", ".join(unknown))
    if "entry" in options:
        entry = _number(options, "entry")
        if not 0 < entry <= 1:
            raise Unsupported("entry is %s, in (0, 1] (got %r)" % (facts["entry"], entry))
    else:
        entry = None
    values.update(p=p, onset_phase=phase, en=entry)
    return values


def scene(law, x, radius, gap):
    """Two spheres of mass 2m each (reduced mass m) approaching at v0 along x, YADE's engines."""
    p, m, k, v0, en = (x[key] for key in ("p", "m", "k", "v0", "en"))
    O.reset()
    alpha = x["alpha"]
    if law == "viscel" and en is None:
        # the materials' kn and cn in series (1/(1/kn1 + 1/kn2)): 2k and 2c give the pair k, c
        material = yade.wrapper.ViscElMat(kn=2 * k, cn=2 * alpha * math.sqrt(m * k), ks=0.0,
                                          cs=0.0, frictionAngle=0.0)
        ip2 = yade.wrapper.Ip2_ViscElMat_ViscElMat_ViscElPhys()
        law2 = yade.wrapper.Law2_ScGeom_ViscElPhys_Basic()
    elif law == "viscel":
        # Ip2_ViscElMat_ViscElMat_ViscElPhys with tc and en: kn = massR (pi^2 + ln^2 en)/tc^2,
        # cn = -2 massR ln(en)/tc, massR the reduced mass: kn = k is tc = sqrt(m (pi^2+ln^2 en)/k)
        log_en = math.log(en)
        tc = math.sqrt(m * (math.pi ** 2 + log_en ** 2) / k)
        material = yade.wrapper.ViscElMat(tc=tc, en=en, et=1.0, frictionAngle=0.0)
        ip2 = yade.wrapper.Ip2_ViscElMat_ViscElMat_ViscElPhys()
        law2 = yade.wrapper.Law2_ScGeom_ViscElPhys_Basic()
    else:
        # kno = 4/3 E* sqrt(R*), E* = E/(2(1-nu^2)) for equal materials, R* = R/2: kno = k
        young = k * 2 * (1 - POISSON ** 2) * 3 / (4 * math.sqrt(radius / 2))
        material = yade.wrapper.FrictMat(young=young, poisson=POISSON, frictionAngle=0.0)
        # en: YADE sets betan by Thornton et al.'s fit; alpha: betan itself, alpha/sqrt(6)
        # (cn = 2 betan sqrt(mbar kn), kn = 3/2 kno sqrt(uN): alpha = sqrt(6) betan)
        ip2 = yade.wrapper.Ip2_FrictMat_FrictMat_MindlinPhys(
            **({"en": en} if en is not None else {"betan": alpha / math.sqrt(6.0)}))
        law2 = yade.wrapper.Law2_ScGeom_MindlinPhys_Mindlin()
    O.materials.append(material)
    left = O.bodies.append(yade.utils.sphere((-gap / 2, 0, 0), radius, material=material))
    right = O.bodies.append(yade.utils.sphere((gap / 2, 0, 0), radius, material=material))
    for body, sign in ((left, 1), (right, -1)):
        O.bodies[body].state.mass = 2 * m
        O.bodies[body].state.vel = (sign * v0 / 2, 0, 0)
    O.engines = [
        yade.wrapper.ForceResetter(),
        yade.wrapper.InsertionSortCollider([yade.wrapper.Bo1_Sphere_Aabb()]),
        yade.wrapper.InteractionLoop([yade.wrapper.Ig2_Sphere_Sphere_ScGeom()], [ip2], [law2]),
        yade.wrapper.NewtonIntegrator(damping=0.0, gravity=(0, 0, 0)),
    ]
    return left, right


def collide(law, problem):
    import time
    started = time.perf_counter()
    try:
        x = checked(problem, law)
    except Unsupported as why:
        return {"outcome": "unsupported", "reason": str(why)}
    p, m, k, v0, dt, phase = (x[key] for key in ("p", "m", "k", "v0", "dt", "onset_phase"))
    delta_u = math.exp((math.log((p + 1) / 2) + math.log(m) - math.log(k) + 2 * math.log(v0))
                       / (p + 1))
    radius = 4 * delta_u
    radsum = 2 * radius
    # as dem-leapfrog: the contact begins phase*dt before the first step position in contact
    t0 = (phase - 1) * dt
    left, right = scene(law, x, radius, radsum - v0 * t0)
    O.dt = dt
    horizon = HORIZON_UNITS * delta_u / v0
    steps = min(MAX_STEPS, int(math.ceil((horizon - t0) / dt)) + 1)
    a, b = O.bodies[left].state, O.bodies[right].state
    rows, t, touched = [], t0, False
    for _ in range(steps):
        # YADE's step (Scene::moveToNextTimeStep): the force from x_n and v_{n-1/2}, then
        # NewtonIntegrator's v_{n+1/2} and x_{n+1}. A row is that evaluation: (t_n, delta_n, the
        # velocity v_{n-1/2} it sees, the force it applied), dem-leapfrog's after_step() state
        # (the position with the velocity that brought the bodies there)
        delta = radsum - (b.pos[0] - a.pos[0])
        rate = a.vel[0] - b.vel[0]
        O.step()
        force = -O.forces.f(left)[0]
        if not all(map(math.isfinite, (delta, rate, force))) or b.pos[0] <= a.pos[0]:
            return {"outcome": "unstable", "invariant": "a state no longer finite or the bodies "
                    "passed through each other", "wall_seconds": time.perf_counter() - started}
        rows.append((t, delta, rate, force))
        # contact_from_steps's end (the force end: no overlap, or the force clipped to 0); the
        # steps after it are not run, as dem-leapfrog stops there
        touched = touched or delta > 0
        if touched and len(rows) > 1 and rows[-2][1] > 0 and (delta <= 0 or force == 0):
            break
        t += dt
        if t >= horizon:
            break
    result = pldamp_protocol.contact_from_steps(rows, dict(problem, end="force"))
    if result["outcome"] == "exited":
        # the last O.step() is the evaluation that found the contact over: dem-leapfrog (and the
        # step count of the protocol) stops there, before that step's kick and drift
        result["steps"] -= 1
    if result["outcome"] == "step_limit" and rows and rows[-1][0] >= horizon:
        result.update(outcome="no_exit", e=0.0)
    want = problem.get("want")
    if want:
        keep = {key for word in want for key in WANTED.get(word, [])}
        result = {key: value for key, value in result.items()
                  if key in ("outcome", "steps") or key in keep}
    result["wall_seconds"] = time.perf_counter() - started
    return result


def main():
    law = sys.argv[-1]
    sys.stdout = io.TextIOWrapper(os.fdopen(int(os.environ["PLDAMP_PROTOCOL_FD"]), "wb"),
                                  encoding="utf-8", line_buffering=True)
    facts = LAWS[law]
    version = getattr(yade.config, "version", "?") if hasattr(yade, "config") else "?"
    pldamp_protocol.serve("YADE %s %s" % (version, facts["label"]),
                          lambda problem: collide(law, problem), p=[facts["p"]], ends=["force"],
                          damping_exponent="seed",
                          honours=pldamp_protocol.FIXED_STEP_SETTINGS + ("options.entry",))


main()
