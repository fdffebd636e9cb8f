#!/usr/bin/env python3
"""What a call from Python costs over the same work in C++ (issue 51's table): the scalar
functions per call, best of 5 loops, and the vectorised ones per element. The C++ side of each row
is harness_bench's answer benchmark (the command's work: options read, the contact calibrated,
the answer built, no text); for solve, the solve alone too: `pldamp solve --json` wall_seconds,
the fastest of 21 solves. A benchmark, not a
test: run it on a quiet machine.

    PYTHONPATH=build/python python3 bench/python_overhead.py build
"""

import json
import os
import subprocess
import sys
import time

import numpy as np

import pldamp


def per_call(call, loops):
    """The fastest of 5 loops of `loops` calls, per call, in seconds."""
    best = float("inf")
    for _ in range(5):
        started = time.perf_counter()
        for _ in range(loops):
            call()
        best = min(best, (time.perf_counter() - started) / loops)
    return best


def cpp_answers(build):
    """harness_bench's answer benchmarks: name -> seconds per answer (fastest repetition)."""
    bench = os.path.join(build, "bench", "harness_bench")
    if not os.path.exists(bench):
        return {}
    measured = subprocess.run([bench, "--benchmark_filter=answer_", "--benchmark_format=json",
                               "--benchmark_repetitions=3"], capture_output=True, text=True,
                              check=True)
    times = {}
    if not measured.stdout.strip():  # a harness_bench built before the answer benchmarks
        return times
    for b in json.loads(measured.stdout)["benchmarks"]:
        if b.get("run_type") == "iteration":
            scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3}[b["time_unit"]]
            name = b["run_name"]
            times[name] = min(times.get(name, float("inf")), b["real_time"] * scale)
    return times


def cpp_solve(build):
    """`pldamp solve taylor` wall_seconds, the fastest of 21 solves."""
    measured = subprocess.run([os.path.join(build, "harness", "pldamp"), "solve", "--solver",
                               "taylor", "--p", "1.5", "--e", "0.61", "--v0", "0.42", "--repeats",
                               "21", "--json"], capture_output=True, text=True, check=True)
    return json.loads(measured.stdout)["wall_seconds"]


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    cpp = cpp_answers(build)
    rows = [
        ("pldamp.observables(p=1.5, e=0.5, v0=1.0)",
         per_call(lambda: pldamp.observables(p=1.5, e=0.5, v0=1.0), 2000),
         cpp.get("answer_observables")),
        ("pldamp.calibrate(p=1.5, e=0.5)",
         per_call(lambda: pldamp.calibrate(p=1.5, e=0.5), 2000), cpp.get("answer_calibrate")),
        ('pldamp.solve("taylor", p=1.5, e=0.61, v0=0.42)',
         per_call(lambda: pldamp.solve("taylor", p=1.5, e=0.61, v0=0.42, repeats=1), 500),
         cpp.get("answer_solve")),
    ]
    alpha = 2.0 * np.arange(100000) / 100000
    rows.append(("pldamp.observables over an array, per element (all observables)",
                 per_call(lambda: pldamp.observables(p=1.5, alpha=alpha, v0=1.0), 3) / alpha.size,
                 None))
    print("| call | per call | the same in C++ | overhead |")
    print("|---|---|---|---|")
    for name, python, native in rows:
        shown = "%.2f µs" % (native * 1e6) if native else ""
        over = "%.2f µs" % ((python - native) * 1e6) if native else ""
        print("| `%s` | %.2f µs | %s | %s |" % (name, python * 1e6, shown, over))
    alone = cpp_solve(build)
    print("\nthe taylor solve alone (`pldamp solve --repeats 21` wall_seconds): %.2f µs; "
          "pldamp.solve takes %.2fx that (issue 51's goal: at most 2x)"
          % (alone * 1e6, rows[2][1] / alone))


if __name__ == "__main__":
    main()
