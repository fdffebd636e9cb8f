#!/usr/bin/env python3
"""Two figures from the Python module (docs/python.md): e against α for p = 1, 1.5 and 2 (the
closed forms over an array, in C++), and the work-precision diagram of three solvers on the Hertz
contact with e = 0.5 (each solve's error in e against its right-hand-side evaluations).

    PYTHONPATH=build/python python3 examples/python/restitution_and_work.py [OUT.png]
"""

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pldamp  # noqa: E402


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "restitution_and_work.png"
    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))

    # e depends on α_eff = α/√(2(p+1)) alone (docs/MATH.md §2): against the equation's α the
    # three exponents part; the markers, e at α_eff = 0.5 of each, all sit at one e.
    alpha = np.linspace(0.0, 2.6, 400)  # critical damping at α = √(2(p+1)): 2, 2.24, 2.45
    for p in (1.0, 1.5, 2.0):
        curve = pldamp.observables(p=p, alpha=alpha, v0=1.0, want=["e"])
        line, = left.plot(alpha, curve["e"], label="p = %g" % p)
        half = pldamp.observables(p=p, alpha_eff=[0.5], v0=1.0, want=["e"])
        left.plot(half["alpha"], half["e"], "o", color=line.get_color())
    left.set_xlabel("α (the equation's damping coefficient)")
    left.set_ylabel("coefficient of restitution e")
    left.set_title("e(α) for p = 1, 1.5, 2 (closed form); ● α_eff = 0.5")
    left.legend()
    left.grid(alpha=0.3)

    truth = pldamp.observables(p=1.5, e=0.5, v0=1.0)["e"]
    for solver in ("cvode-bdf", "arkode-dp5", "odeint-rkf78"):
        work, error = [], []
        for rtol in np.logspace(-3, -11, 9):
            solved = pldamp.solve(solver, p=1.5, e=0.5, v0=1.0, rtol=float(rtol))
            work.append(solved["rhs_evals"])
            error.append(max(abs(solved["e"] / truth - 1), 1e-17))
        right.loglog(work, error, "o-", label=solver)
    right.set_xlabel("right-hand-side evaluations per collision")
    right.set_ylabel("relative error in e")
    right.set_title("Hertz, e = 0.5: work against precision")
    right.legend()
    right.grid(alpha=0.3, which="both")

    figure.tight_layout()
    temporary = out + ".tmp.png"
    figure.savefig(temporary, dpi=100)
    os.replace(temporary, out)
    print(out)


if __name__ == "__main__":
    main()
