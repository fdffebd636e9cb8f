#!/usr/bin/python3
"""diff and diff --exact of a report against itself hold a record or two of each at a time, not
the reports: their peak memory does not grow with the report (docs/scaling.md, "Diff at size").

Two maps of bench/map_scene.py, of 2*10^4 and 2*10^5 solver runs (8 000 and 80 000 records; 7 and
70 MB of report.json), each diffed with itself. The larger map's peak may exceed the smaller's by
at most 8 MB; before diff was streamed, it exceeded it by 132 MB (diff: every record's facts) and
23 MB (diff --exact: every record's key); now by 3 and 2 MB.

    tests/harness/diff_memory_test.py PLDAMP SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile

GROWTH_ALLOWED_KB = 8 * 1024


def peak_kb(command):
    """Runs `command`; its exit code and its peak resident memory in KB (wait4's ru_maxrss)."""
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode not in (0, 1):
        sys.exit(f"{' '.join(command)} exited {child.returncode}: {child.stderr.read().decode()}")
    return usage.ru_maxrss


def main():
    pldamp, source = sys.argv[1], sys.argv[2]
    failures = []
    with tempfile.TemporaryDirectory(prefix="pldamp-diff-memory-") as scratch:
        peaks = {}
        for runs in ("2e4", "2e5"):
            scene = os.path.join(scratch, f"map{runs}.toml")
            with open(scene, "w") as out:
                subprocess.run([sys.executable, os.path.join(source, "bench", "map_scene.py"), runs],
                               stdout=out, check=True)
            folder = os.path.join(scratch, runs)
            ran = subprocess.run([pldamp, "run", scene, "--out", folder], capture_output=True,
                                 text=True)
            if ran.returncode != 0:
                sys.exit(f"pldamp run {scene} exited {ran.returncode}: {ran.stderr}")
            report = os.path.join(folder, "report.json")
            for mode in ("diff", "diff --exact"):
                command = [pldamp, *mode.split(), report, report]
                peaks[(mode, runs)] = peak_kb(command)
        for mode in ("diff", "diff --exact"):
            small, large = peaks[(mode, "2e4")], peaks[(mode, "2e5")]
            print(f"{mode}: {small} KB at 2e4 runs, {large} KB at 2e5 runs")
            if large - small > GROWTH_ALLOWED_KB:
                failures.append(f"{mode} grew by {large - small} KB from 2e4 to 2e5 runs "
                                f"(at most {GROWTH_ALLOWED_KB} KB)")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
