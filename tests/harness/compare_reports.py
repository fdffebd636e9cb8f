#!/usr/bin/env python3
"""Two report.json compared key by key but for what timing decides (times, the runs repeats
made, the timestamp) and what made them (`run`): exit 1 and the first differences when they differ.
    compare_reports.py A/report.json B/report.json"""
import json
import sys


def timing(key):
    # `run`: what made the report (date, host, command line), not what it computed.
    return "second" in key or key in ("runs", "solver_runs", "x_analytic", "generated", "run")


def differences(a, b, path, found):
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if timing(key):
                continue
            if key not in a or key not in b:
                found.append(f"{path}/{key}: in one report only")
            else:
                differences(a[key], b[key], f"{path}/{key}", found)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            found.append(f"{path}: {len(a)} items against {len(b)}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            differences(x, y, f"{path}[{i}]", found)
    elif a != b:
        found.append(f"{path}: {a!r} against {b!r}")


def main():
    with open(sys.argv[1]) as a, open(sys.argv[2]) as b:
        found = []
        differences(json.load(a), json.load(b), "", found)
    for line in found[:20]:
        print(line, file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
