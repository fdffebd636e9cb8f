"""What the adapter tests share: an adapter run as pldamp runs it, and pldamp's own answers.

An adapter is a process spoken to one JSON line at a time each way (docs/external.md "The protocol,
version 1"); `pldamp(...)` runs the CLI with --json for the value an adapter is compared with.
"""

import json
import os
import re
import subprocess
import sys
import tempfile


class AdapterProcess:
    """The adapter `command` (an argument vector) as pldamp runs it, after its handshake."""

    def __init__(self, command, handshake):
        self.stderr = tempfile.TemporaryFile()
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=self.stderr, text=True)
        self.hello = self.exchange(handshake) if handshake is not None else None
        self.next_id = 0

    def exchange(self, obj):
        self.process.stdin.write(json.dumps(obj) + "\n")
        self.process.stdin.flush()
        line = self.process.stdout.readline()
        if not line:
            raise AssertionError("the adapter closed its output; its stderr ends: "
                                 + self.error_tail())
        return json.loads(line)

    def solve(self, problem):
        problem = dict(problem, id=self.next_id)
        self.next_id += 1
        reply = self.exchange(problem)
        if reply.get("id") != problem["id"]:
            raise AssertionError("reply for id %r to problem %d" % (reply.get("id"), problem["id"]))
        return reply

    def error_tail(self):
        self.stderr.seek(0)
        return self.stderr.read().decode(errors="replace").strip()[-2000:]

    def kill(self):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()

    def close(self):
        """Closes standard input as pldamp does; returns the exit status."""
        self.process.stdin.close()
        status = self.process.wait(timeout=60)
        self.process.stdout.close()
        self.stderr.close()
        return status


def run_pldamp(binary, *arguments):
    """`binary ARGUMENTS --json`, its answer parsed; a refusal fails the test with its line."""
    run = subprocess.run([binary] + [str(a) for a in arguments] + ["--json"],
                         capture_output=True, text=True, check=False)
    if run.returncode != 0:
        raise AssertionError("pldamp %s: %s" % (" ".join(map(str, arguments)), run.stderr))
    return json.loads(run.stdout)


def run_scene_strictly(binary, scene, timeout):
    """`binary run SCENE --strict` into a scratch folder: (its exit problems, report.json's records,
    the report). Exits 77 (skipped) when a code answers `unavailable` (not installed), and fails
    when no report was written. The report must diff cleanly against itself: `pldamp diff` holds
    every record to itself (an external program's records too)."""
    with tempfile.TemporaryDirectory() as out:
        run = subprocess.run([binary, "run", scene, "--strict", "--out", out, "--jobs", "2"],
                             capture_output=True, text=True, timeout=timeout, check=False)
        report_path = os.path.join(out, "report.json")
        if not os.path.exists(report_path):
            sys.exit("no report (exit %d): %s" % (run.returncode, run.stderr.strip()))
        with open(report_path, encoding="utf-8") as f:
            report = json.load(f)
        diff = subprocess.run([binary, "diff", report_path, report_path], capture_output=True,
                              text=True, timeout=timeout, check=False)
    records = report["records"]
    unavailable = [r for r in records if r.get("skipped", "").startswith("unavailable")]
    if unavailable:
        print("skipped: " + unavailable[0]["skipped"])
        sys.exit(77)
    problems = []
    if run.returncode != 0:
        problems.append("exit %d: %s" % (run.returncode, run.stderr.strip()))
    if diff.returncode != 0 or diff.stdout != "0 regressions, 0 changes\n":
        problems.append("diff against itself, exit %d: %s%s" % (diff.returncode, diff.stdout,
                                                               diff.stderr.strip()))
    problems += plan_bound_problems(run.stdout)
    return problems, records, report


def plan_bound_problems(out):
    """The plan line's count of solver runs (the first line) bounds what the run made: the
    summary's grid runs, or with the judging's solves "N in all" (tests/harness/end_to_end_test.cpp
    holds the other shipped scenes to it)."""
    lines = out.splitlines()
    planned = re.search(r"(\d+) solver runs", lines[0] if lines else "")
    made = None
    for line in lines[1:]:
        every = re.search(r"more solves for the claims.*, (\d+) in all", line)
        grid = re.search(r"(\d+) solver runs, \d+ rhs evaluations", line)
        if every:
            made = int(every.group(1))
        elif grid and made is None:
            made = int(grid.group(1))
    if not planned or made is None:
        return ["no plan line or summary to compare: %s" % out[:300]]
    if int(planned.group(1)) < made:
        return ["the plan counted %s solver runs, the run made %d" % (planned.group(1), made)]
    return []
