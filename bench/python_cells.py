#!/usr/bin/env python3
"""solve over 10^4 cells from Python against `pldamp run` on the same cells (issue 51): taylor in
double at p = 1.5, v0 = 1, e from 0.05 to 1, on every core. The run also computes each cell's
closed-form truth and writes report.csv; the Python call only solves. A benchmark, not a test.

    PYTHONPATH=build/python python3 bench/python_cells.py build/harness/pldamp
"""

import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import pldamp

CELLS = 10000


def main():
    program = sys.argv[1] if len(sys.argv) > 1 else "build/harness/pldamp"
    e = np.round(np.linspace(0.05, 1.0, CELLS), 12)
    with tempfile.TemporaryDirectory() as folder:
        scene = os.path.join(folder, "cells.toml")
        with open(scene, "w", encoding="utf-8") as out:
            out.write('name = "cells"\n[grid]\np = 1.5\nv0 = 1.0\ne = [%s]\n'
                      '[[solver]]\nname = "taylor"\n[report]\nformats = "csv"\n'
                      % ", ".join(repr(float(x)) for x in e))
        run = float("inf")
        for _ in range(3):
            started = time.perf_counter()
            subprocess.run([program, "run", scene, "--out", os.path.join(folder, "report")],
                           check=True, capture_output=True)
            run = min(run, time.perf_counter() - started)
    python = float("inf")
    for _ in range(3):
        started = time.perf_counter()
        solved = pldamp.solve("taylor", p=1.5, e=e, v0=1.0, repeats=1)
        python = min(python, time.perf_counter() - started)
    assert solved.outcome == "exited" and np.all(np.abs(solved.e / e - 1) < 1e-12)
    print("10^4 taylor cells, best of 3: pldamp run %.3f s, pldamp.solve over arrays %.3f s, "
          "ratio %.2f" % (run, python, python / run))


if __name__ == "__main__":
    main()
