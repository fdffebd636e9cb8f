#!/usr/bin/env python3
"""The external-solver protocol end to end against the real codes: data/scenes/dem-codes-smoke.toml.

    python3 tests/adapters/dem_codes_smoke_test.py PLDAMP_BINARY

Runs the scene with --strict (its claims must hold) and reads report.json: no record failed, the
codes agree with pldamp's replica of their loop (dem-verlet) to rounding, a record is skipped only
for a p its model does not have, and a dashpot that is not the seed's is judged against the reference solve of its own exponent.
Exit 77 (skipped) when a code answers `unavailable` (not installed).
"""

import os
import sys

from adapter_process import run_scene_strictly

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "data", "scenes", "dem-codes-smoke.toml")
ROUNDING = 1e-12  # measured: 1.2e-14 (docs/external.md "LAMMPS adapter")


def main():
    pldamp = sys.argv[1]
    problems, records, _ = run_scene_strictly(pldamp, SCENE, timeout=300)
    compared = 0
    for record in records:
        where = record["key"]
        if record["failed"]:
            problems.append("%s failed: %s" % (where, record.get("failure")))
        if "skipped" in record:
            if not record["skipped"].startswith("it runs p = "):
                problems.append("%s skipped: %s" % (where, record["skipped"]))
            continue
        for key, difference in record.get("replica_difference", {}).items():
            compared += 1
            if difference is None or difference > ROUNDING:
                problems.append("%s: %s differs from dem-verlet by %s" % (where, key, difference))
        if "gran/hertz/history" in where:
            # Its dashpot is delta^(1/2) delta': judged against the reference solve of that exponent.
            if not record.get("note", "").startswith("truth by reference solve"):
                problems.append("%s: no note that its truth is a reference solve" % where)
            e = record["value"]["e"]
            if e is None or not 0 < e < 1:
                problems.append("%s: e = %s" % (where, e))
            error = record.get("rel_error", {}).get("e")
            if error is None or not error < 0.05:
                problems.append("%s: e is %s off the reference solve" % (where, error))
    if compared < 8 * 4:  # 4 seed configurations × 2 steps × 4 observables at their p
        problems.append("only %d replica comparisons" % compared)
    for problem in problems:
        print(problem)
    print("%d records, %d replica comparisons, %d problems" % (len(records), compared, len(problems)))
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
