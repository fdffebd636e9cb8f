#!/usr/bin/env python3
"""Writes the example trajectories of data/scenes/trajectories.toml, as a DEM code would dump them.

    python3 data/trajectories/generate.py build/harness/pldamp

Each is one contact solved by `pldamp solve` and sampled at fixed times (t, delta, v inside the
contact), with a free-flight row at v0 before it and one at the exit speed after it: what a dump
every N steps around one collision looks like.
"""

import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def write(pldamp, name, solver_args, spacing):
    def solve(extra):
        args = [pldamp, "solve", "--p", "1.5", "--e", "0.5", "--v0", "1", "--json"] + extra
        return json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)

    tau = solve(solver_args)["tau"]
    times = [i * spacing for i in range(int(tau / spacing) + 1)]
    result = solve(solver_args + ["--sample-times", ",".join(repr(t) for t in times)])
    rows = [(-spacing / 2, -spacing / 2, 1.0)] + [tuple(s) for s in result["samples"]]
    rows.append((result["tau"] + spacing / 2, -result["e"] * spacing / 2, -result["e"]))
    with open(os.path.join(HERE, name), "w", encoding="utf-8") as out:
        out.write("# %s, p = 1.5, e = 0.5, v0 = 1 (data/trajectories/generate.py)\nt,delta,v\n"
                  % " ".join(solver_args))
        for row in rows:
            out.write(",".join("%.17g" % x for x in row) + "\n")


def main():
    pldamp = sys.argv[1]
    write(pldamp, "hertz_taylor_every_0.1.csv", ["--solver", "taylor"], 0.1)
    write(pldamp, "hertz_dem_verlet_50.csv",
          ["--solver", "dem-verlet", "--steps-per-contact", "50"], 0.0687)


if __name__ == "__main__":
    main()
