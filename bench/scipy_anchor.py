#!/usr/bin/env python3
"""An outside anchor for taylor_bench (docs/performance.md): SciPy's solve_ivp on the same collision,
p = 1.5, e = 0.61, v0 = 0.42, m = k = 1, integrated to the exit (a terminal event at delta = 0),
at the tolerances where it comes near 1e-12. Errors of e and tau against pldamp's closed forms; the
time of one collision is the fastest of 20. A benchmark, not a test: run it on a quiet machine
(SciPy from Debian, python3-scipy).

    PYTHONPATH=build/python python3 bench/scipy_anchor.py
"""

import time

import numpy as np
from scipy.integrate import solve_ivp

import pldamp

P, E, V0 = 1.5, 0.61, 0.42


def main():
    exact = pldamp.observables(p=P, e=E, v0=V0)
    alpha = exact["alpha"]
    power = (P - 1) / 2

    def rhs(_t, y):
        overlap = max(y[0], 0.0)  # a step may probe just past the exit
        return [y[1], -alpha * overlap**power * y[1] - overlap**P]

    def exit_event(_t, y):
        return y[0]

    exit_event.terminal, exit_event.direction = True, -1
    print(f"{'method':<8}{'rtol':>8}{'us':>10}{'rhs':>7}{'err e':>10}{'err tau':>10}")
    for method in ("DOP853", "RK45", "Radau", "LSODA"):
        for rtol in (1e-10, 1e-12, 1e-13):
            best, solution = float("inf"), None
            for _ in range(20):
                started = time.perf_counter()
                solution = solve_ivp(rhs, (0.0, 100.0), [0.0, V0], method=method, rtol=rtol,
                                     atol=rtol * 1e-3, events=exit_event)
                best = min(best, time.perf_counter() - started)
            if not solution.t_events[0].size:
                print(f"{method:<8}{rtol:>8.0e}  no exit")
                continue
            tau = solution.t_events[0][0]
            e = -solution.y_events[0][0][1] / V0
            print(f"{method:<8}{rtol:>8.0e}{best * 1e6:>10.0f}{solution.nfev:>7}"
                  f"{abs(e - exact['e']) / exact['e']:>10.1e}"
                  f"{abs(tau - exact['tau']) / exact['tau']:>10.1e}")


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
