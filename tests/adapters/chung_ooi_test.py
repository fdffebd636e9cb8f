#!/usr/bin/env python3
"""The Chung & Ooi (2011) normal-impact benchmarks, tests 1-3, end to end: data/scenes/chung-ooi.toml.

    python3 tests/adapters/chung_ooi_test.py PLDAMP_BINARY

Runs the scene with --strict (its claims must hold: each DEM code's tau within 1e-3 at 1000 steps
per contact) and reads report.json: no record failed; a record is skipped only where LAMMPS's
tsuji damping cannot be zero (e = 1); every code agrees with pldamp's replica of its loop to
rounding; and the truth of each elastic contact is Hertz's, written out here from the materials
without pldamp: m* = m1 m2/(m1 + m2), 1/R* = 1/R1 + 1/R2, 1/E* = sum (1 - nu^2)/E, k = 4/3 E* sqrt(R*),
delta_max = (5 m* v0^2/(4 k))^(2/5), F_max = k delta_max^(3/2), tau = 2 (delta_max/v0) (2/5) B(2/5, 1/2).
Exit 77 (skipped) when a code answers `unavailable` (not installed).
"""

import math
import os
import sys

from adapter_process import run_scene_strictly

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "data", "scenes", "chung-ooi.toml")
ROUNDING = 1e-12  # a code against its replica (measured: 3e-14)
BETA = 3.6790939804058  # B(2/5, 1/2) (mpmath)

# name: (geometry, R, E, nu, rho, v0), the scene's contacts as Chung & Ooi give them.
CONTACTS = {
    "test 1 glass": ("sphere-sphere", 0.010, 4.8e10, 0.20, 2800, 20.0),
    "test 1 limestone": ("sphere-sphere", 0.010, 2.0e10, 0.25, 2500, 20.0),
    "test 2 aluminium alloy": ("sphere-wall", 0.10, 7.0e10, 0.30, 2699, 0.2),
    "test 2 magnesium alloy": ("sphere-wall", 0.10, 4.0e10, 0.35, 1800, 0.2),
    "test 3 aluminium oxide": ("sphere-wall", 0.0025, 3.8e11, 0.23, 4000, 3.9),
    "test 3 cast iron": ("sphere-wall", 0.0025, 1.0e11, 0.25, 7000, 3.9),
}


def hertz(geometry, radius, young, poisson, density, v0):
    mass = 4 / 3 * math.pi * radius ** 3 * density
    if geometry == "sphere-sphere":
        m, r, e = mass / 2, radius / 2, young / (2 * (1 - poisson ** 2))
    else:
        m, r, e = mass, radius, young / (1 - poisson ** 2)
    k = 4 / 3 * e * math.sqrt(r)
    delta_max = (5 * m * v0 ** 2 / (4 * k)) ** 0.4
    return {"m": m, "k": k, "delta_max": delta_max, "normal_force_max": k * delta_max ** 1.5,
            "tau": 2 * 0.4 * BETA * delta_max / v0}


def main():
    pldamp = sys.argv[1]
    problems, records, report = run_scene_strictly(pldamp, SCENE, timeout=600)
    truths = 0
    for record in records:
        where = record["key"]
        if record["failed"]:
            problems.append("%s failed: %s" % (where, record.get("failure")))
        if "skipped" in record:
            if not (record["config"].startswith("lammps") and record["damping"] == "e=1"):
                problems.append("%s skipped: %s" % (where, record["skipped"]))
            continue
        for key, difference in record.get("replica_difference", {}).items():
            if record["value"].get(key) is None:
                continue  # not measured by the code (the adapters do not report the force)
            if difference is None or difference > ROUNDING:
                problems.append("%s: %s differs from its replica by %s" % (where, key, difference))
        if record["config"].startswith("cvode") and record["damping"] == "e=1":
            want = hertz(*CONTACTS[record["contact"]])
            for key in ("m", "k"):
                if abs(record[key] / want[key] - 1) > 1e-15:
                    problems.append("%s: %s %r, Hertz %r" % (where, key, record[key], want[key]))
            for key in ("delta_max", "normal_force_max", "tau"):
                truth = record["reference"][key]
                if abs(truth / want[key] - 1) > 1e-13:
                    problems.append("%s: the truth's %s %r, Hertz %r" % (where, key, truth,
                                                                         want[key]))
                truths += 1
    if truths != 3 * len(CONTACTS):
        problems.append("checked %d truths, expected %d" % (truths, 3 * len(CONTACTS)))
    verdicts = [claim["verdict"] for claim in report["claims"]]
    if verdicts != ["holds"] * 3:
        problems.append("claims: %s" % verdicts)
    for problem in problems:
        print(problem)
    print("%d records, %d truths checked against Hertz, %d problems" % (len(records), truths,
                                                                        len(problems)))
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
