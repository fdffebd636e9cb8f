#!/usr/bin/env python3
"""The Python module's observables over an array against the same loop in C++ (docs/python.md):
10⁶ restitutions in double, each a contact from its α (0 to 2 at p = 1.5). Target: the module at
most twice the C++ loop (bench/analytic_bench.cpp, restitutions_over_an_array). A benchmark, not
a test: run it on a quiet machine.

    PYTHONPATH=build/python python3 bench/python_vectorised.py build/bench/analytic_bench
"""

import json
import subprocess
import sys
import time

import numpy as np

import pldamp

N = 1000000


def main():
    bench = sys.argv[1] if len(sys.argv) > 1 else "build/bench/analytic_bench"
    measured = subprocess.run([bench, "--benchmark_filter=restitutions_over_an_array",
                               "--benchmark_format=json", "--benchmark_repetitions=5"],
                              capture_output=True, text=True, check=True)
    runs = [b for b in json.loads(measured.stdout)["benchmarks"] if b.get("run_type") == "iteration"]
    cpp = min(b["real_time"] for b in runs) / 1000  # ms -> s
    alpha = 2.0 * np.arange(N) / N
    best = float("inf")
    for _ in range(5):
        started = time.perf_counter()
        pldamp.observables(p=1.5, alpha=alpha, v0=1.0, want=["e"])
        best = min(best, time.perf_counter() - started)
    print("10^6 restitutions, best of 5: C++ loop %.3f s, pldamp.observables %.3f s, ratio %.2f"
          % (cpp, best, best / cpp))


if __name__ == "__main__":
    main()
