#!/usr/bin/env python3
"""Taylor (double) against the fastest other adaptive configuration that reaches err <= 1e-12, per
case, from one run of taylor_bench (issue 31's goal: >= 100x at every case). Standard library only.

    python3 bench/taylor_speedup.py build/bench/taylor_bench [extra taylor_bench flags]
"""
import json
import subprocess
import sys

bench = sys.argv[1] if len(sys.argv) > 1 else "build/bench/taylor_bench"
extra = sys.argv[2:] or ["--benchmark_min_time=0.2"]
out = subprocess.run(
    [bench, "--benchmark_filter=^(adaptive/|taylor(_cold)?/double/)", "--benchmark_format=json", *extra],
    check=True, capture_output=True, text=True).stdout
runs = json.loads(out)["benchmarks"]
to_us = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}


def cpu_us(run):
    return run["cpu_time"] * to_us[run["time_unit"]]


taylor, cold, others = {}, {}, {}
for run in runs:
    parts = run["name"].split("/")
    if parts[0] == "taylor":
        taylor[parts[2]] = run
    elif parts[0] == "taylor_cold":
        cold[parts[2]] = run
    elif parts[1] != "taylor" and run.get("err", 1.0) <= 1e-12:
        case = parts[2]
        if case not in others or cpu_us(run) < cpu_us(others[case]):
            others[case] = run

print(f"{'case':<14}{'taylor us':>10}{'cold us':>9}{'err':>10}  {'fastest other at err<=1e-12':<34}"
      f"{'us':>9}{'err':>10}{'ratio':>8}{'cold ratio':>11}")
worst = float("inf")
for case, run in taylor.items():
    other = others.get(case)
    if other is None:
        print(f"{case:<14}{cpu_us(run):>10.2f}  no other configuration reached 1e-12")
        worst = 0
        continue
    ratio = cpu_us(other) / cpu_us(run)
    cold_ratio = cpu_us(other) / cpu_us(cold[case])
    worst = min(worst, cold_ratio)
    name = "/".join(other["name"].split("/")[1:4:2])
    print(f"{case:<14}{cpu_us(run):>10.2f}{cpu_us(cold[case]):>9.2f}{run['err']:>10.1e}  {name:<34}"
          f"{cpu_us(other):>9.1f}{other['err']:>10.1e}{ratio:>8.0f}{cold_ratio:>11.0f}")
print(f"smallest ratio (cold taylor): {worst:.0f}x")
