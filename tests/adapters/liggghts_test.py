#!/usr/bin/env python3
"""Acceptance test of adapters/liggghts (issue 17, item 3, the LIGGGHTS half).

    python3 tests/adapters/liggghts_test.py PLDAMP_BINARY [unittest options]

Exit 0: passed; 77: `liggghts` is not installed (skipped); anything else: failed, with the
unittest report saying what. It runs the real LIGGGHTS through the adapter and compares with
`PLDAMP_BINARY solve --solver dem-verlet` (pldamp's replica of the same loop: to rounding) and
with `PLDAMP_BINARY observables` (the closed forms: first order in the step).
"""

import sys

sys.dont_write_bytecode = True  # nothing written into the tree

import itertools  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import select  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402
import unittest  # noqa: E402

ADAPTER = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                        "adapters", "liggghts"))
PLDAMP = None  # set from the command line
HELLO = {"protocol": "pldamp-solver", "version": 1}
MODELS = {"hertz": 1.5, "hooke": 1}
OBSERVABLES = ("e", "delta_max", "t_peak", "tau")

# Measured on Debian 12's liggghts 3.8.0 (the test prints what it measures): over the agreement
# grid below the largest relative difference from dem-verlet is 7.9e-15 in e, 1.3e-15 in δ_max,
# 0 in t_peak and τ (the same step), 2.1e-15 of ½mv0² in the energies. The bound is 2.5 times that.
AGREEMENT = 2e-14
REPLY_SECONDS = 120


class Adapter:
    """The adapter as pldamp runs it: a subprocess spoken to one JSON line at a time."""

    def __init__(self, *args):
        env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
        self.proc = subprocess.Popen([ADAPTER, *args], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
        self.pending = b""

    def send(self, obj):
        self.proc.stdin.write((json.dumps(obj) + "\n").encode())
        self.proc.stdin.flush()

    def line(self):
        """One line of the adapter's standard output, or None at its end."""
        deadline = time.monotonic() + REPLY_SECONDS
        fd = self.proc.stdout.fileno()
        while b"\n" not in self.pending:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([fd], [], [], left)[0]:
                self.proc.kill()
                raise AssertionError("no reply from the adapter within %d s" % REPLY_SECONDS)
            chunk = os.read(fd, 65536)
            if not chunk:
                return None
            self.pending += chunk
        line, self.pending = self.pending.split(b"\n", 1)
        return line.decode()

    def handshake(self):
        self.send(HELLO)
        return json.loads(self.line())

    def ask(self, problem):
        self.send(problem)
        reply = self.line()
        if reply is None:
            raise AssertionError("the adapter ended: " + self.stderr_tail())
        return json.loads(reply)

    def stderr_tail(self):
        return self.proc.stderr.read().decode(errors="replace").strip()[-500:]

    def close(self):
        """Closes standard input as pldamp does; returns the exit code."""
        self.proc.stdin.close()
        rest = self.proc.stdout.read()
        self.proc.stderr.read()
        code = self.proc.wait(timeout=60)
        self.proc.stdout.close()
        self.proc.stderr.close()
        if rest.strip():
            raise AssertionError("output after the last problem: %r" % rest[:200])
        return code

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        for stream in (self.proc.stdin, self.proc.stdout, self.proc.stderr):
            if not stream.closed:
                stream.close()


def pldamp(*args):
    done = subprocess.run([PLDAMP, *args, "--json"], capture_output=True, text=True, timeout=60)
    if done.returncode != 0:
        raise AssertionError("%s %s: exit %d: %s" % (PLDAMP, " ".join(args), done.returncode,
                                                    done.stderr.strip()))
    return json.loads(done.stdout)


def numbers(**values):
    """Command-line options: numbers(onset_phase=0.5) is ["--onset-phase", "0.5"]."""
    return [arg for key, value in values.items()
            for arg in ("--" + key.replace("_", "-"), repr(value))]


def problem(i, p, m, k, v0, alpha, end, spc, dt, phase, want=OBSERVABLES):
    return {"id": i, "p": p, "m": m, "k": k, "v0": v0, "alpha": alpha,
            "damping_exponent": (p - 1) / 2, "end": end, "want": list(want),
            "steps_per_contact": spc, "dt": dt, "onset_phase": phase, "options": {}}


def pldamp_keys(end):
    """dem-verlet's and the closed forms' keys for the adapter's e, delta_max, t_peak, tau."""
    capped = end == "force"
    return {"e": "e_cap" if capped else "e", "delta_max": "delta_max", "t_peak": "t_peak",
            "tau": "t_cut" if capped else "tau"}


class ProtocolTest(unittest.TestCase):
    def test_handshake(self):
        for model, p in MODELS.items():
            with self.subTest(model=model), Adapter("--model", model) as adapter:
                hello = adapter.handshake()
                self.assertEqual(hello["protocol"], "pldamp-solver")
                self.assertEqual(hello["version"], 1)
                self.assertIn("LIGGGHTS", hello["solver"])
                self.assertIn("model " + model, hello["solver"])
                self.assertEqual(hello["p"], [p])
                self.assertEqual(hello["ends"], ["overlap", "force"])
                self.assertEqual(hello["damping_exponent"], "seed")
                self.assertEqual(hello["honours"], ["steps_per_contact", "dt", "onset_phase"])
                self.assertNotIn("unavailable", hello)
                self.assertEqual(adapter.close(), 0)

    def test_wrong_protocol_or_version_exits_non_zero(self):
        for hello in ({"protocol": "pldamp-solver", "version": 2},
                      {"protocol": "other", "version": 1}, "not json"):
            with self.subTest(hello=hello), Adapter("--model", "hertz") as adapter:
                adapter.proc.stdin.write(((hello if isinstance(hello, str) else json.dumps(hello))
                                          + "\n").encode())
                adapter.proc.stdin.flush()
                self.assertIsNone(adapter.line(), "no handshake reply to a wrong handshake")
                self.assertNotEqual(adapter.proc.wait(timeout=60), 0)
                self.assertIn("adapter:", adapter.stderr_tail())

    def unsupported(self, model, changes, words):
        with Adapter("--model", model) as adapter:
            adapter.handshake()
            base = problem(7, MODELS[model], 1, 1, 1, 0.4, "overlap", 20, math.pi / 20, 0.5)
            reply = adapter.ask(dict(base, **changes))
            self.assertEqual(reply["id"], 7)
            self.assertEqual(reply["outcome"], "unsupported", reply)
            for word in words:
                self.assertIn(word, reply["reason"])
            # the adapter goes on with the next problem
            self.assertEqual(adapter.ask(dict(base, id=8))["outcome"], "exited")
            self.assertEqual(adapter.close(), 0)

    def test_unsupported_p(self):
        self.unsupported("hertz", {"p": 2, "damping_exponent": 0.5}, ["p = 1.5", "not 2"])
        self.unsupported("hooke", {"p": 1.5, "damping_exponent": 0.25}, ["p = 1", "not 1.5"])

    def test_unsupported_damping_exponent(self):
        self.unsupported("hertz", {"damping_exponent": 0}, ["delta^0.25"])

    def test_unsupported_damping_beyond_liggghts_restitution_range(self):
        # hertz α = 1.6 needs coefficientRestitution 0.044, below LIGGGHTS's 0.05
        self.unsupported("hertz", {"alpha": 1.6}, ["0.05 < coefficientRestitution"])
        self.unsupported("hooke", {"alpha": 2.5}, ["no coefficientRestitution"])

    def test_broken_problem_is_an_error_record(self):
        with Adapter("--model", "hooke") as adapter:
            adapter.handshake()
            reply = adapter.ask({"id": 3, "p": 1, "end": "overlap"})
            self.assertEqual((reply["id"], reply["outcome"]), (3, "error"))
            self.assertIn("reason", reply)
            self.assertEqual(adapter.close(), 0)

    def test_unavailable_without_liggghts(self):
        for program, words in (("/nonexistent/liggghts", "not found"), ("false", "does not start")):
            with self.subTest(program=program), \
                    Adapter("--model", "hertz", "--liggghts", program) as adapter:
                hello = adapter.handshake()
                self.assertIn(words, hello["unavailable"])
                ask = problem(0, 1.5, 1, 1, 1, 0.4, "overlap", 20, math.pi / 20, 0.5)
                reply = adapter.ask(ask)
                self.assertEqual(reply["outcome"], "unsupported")
                self.assertEqual(adapter.close(), 0)


class AgreementTest(unittest.TestCase):
    """LIGGGHTS and dem-verlet: the same loop, so the same numbers to rounding."""

    CONTACTS = [  # m, k, v0, alpha: unit scales, and a 1 cm glass-like bead in SI units
        (1.0, 1.0, 1.0, 0.4),
        (0.01, 7e9, 2.0, 1.0),
    ]
    PHASES = (0.0, 0.3, 0.7)

    def test_matches_dem_verlet_to_rounding(self):
        worst = {}
        for model, p in MODELS.items():
            with Adapter("--model", model) as adapter:
                adapter.handshake()
                ends = ("overlap", "force")
                grid = itertools.product(self.CONTACTS, ends, (20, 200), self.PHASES)
                for i, (contact, end, spc, phase) in enumerate(grid):
                    with self.subTest(model=model, contact=contact, end=end, spc=spc, phase=phase):
                        self.compare(adapter, i, p, contact, end, spc, phase, worst)
                self.assertEqual(adapter.close(), 0)
        print("\n  LIGGGHTS vs dem-verlet, largest relative difference: "
              + ", ".join("%s %.1e" % item for item in worst.items()), file=sys.stderr)

    def compare(self, adapter, i, p, contact, end, spc, phase, worst):
        m, k, v0, alpha = contact
        ref = pldamp("solve", "--solver", "dem-verlet", "--end", end,
                     "--steps-per-contact", str(spc),
                     *numbers(p=p, m=m, k=k, v0=v0, alpha=alpha, onset_phase=phase))
        want = OBSERVABLES + ("energy_load", "energy_unload")
        got = adapter.ask(problem(i, p, m, k, v0, alpha, end, spc, ref["dt"], phase, want))
        self.assertEqual(got["outcome"], "exited", got)
        self.assertEqual(ref["outcome"], "exited", ref)
        scale = 0.5 * m * v0 * v0  # the energies' (they vanish at e = 1)
        pairs = list(pldamp_keys(end).items()) + [("energy_load",) * 2, ("energy_unload",) * 2]
        for key, ref_key in pairs:
            size = scale if key.startswith("energy") else abs(ref[ref_key])
            diff = abs(got[key] - ref[ref_key]) / size
            worst[key] = max(worst.get(key, 0.0), diff)
            self.assertLessEqual(diff, AGREEMENT, (key, got[key], ref[ref_key]))


class ConvergenceTest(unittest.TestCase):
    """At 200 and 2000 steps per contact LIGGGHTS approaches the closed forms at first order:
    the worst error over onset phases falls ~10-fold (measured 7.6 to 15) and is ~1/N (measured
    N·error ≤ 1.9 at 2000)."""

    PHASES = (0.0, 0.25, 0.5, 0.75)

    def test_first_order_to_the_closed_forms(self):
        for model, p in MODELS.items():
            with Adapter("--model", model) as adapter:
                adapter.handshake()
                for alpha, end in itertools.product((0.2, 0.7), ("overlap", "force")):
                    truth = pldamp("observables", "--end", end, *numbers(p=p, alpha=alpha, v0=1.0))
                    coarse = self.worst_errors(adapter, p, alpha, end, 200, truth)
                    fine = self.worst_errors(adapter, p, alpha, end, 2000, truth)
                    for key in OBSERVABLES:
                        with self.subTest(model=model, alpha=alpha, end=end, observable=key):
                            self.assertGreater(fine[key], 0.0)
                            self.assertLessEqual(fine[key] * 2000, 3.0, (coarse[key], fine[key]))
                            self.assertTrue(5.0 <= coarse[key] / fine[key] <= 20.0,
                                            "error 200 -> 2000 steps: %.3g -> %.3g, not first order"
                                            % (coarse[key], fine[key]))
                self.assertEqual(adapter.close(), 0)

    def worst_errors(self, adapter, p, alpha, end, spc, truth):
        """The largest relative error of each observable over the onset phases."""
        worst = dict.fromkeys(OBSERVABLES, 0.0)
        for phase in self.PHASES:
            got = adapter.ask(problem(0, p, 1, 1, 1, alpha, end, spc, math.pi / spc, phase))
            self.assertEqual(got["outcome"], "exited", got)
            for key, ref_key in pldamp_keys(end).items():
                worst[key] = max(worst[key], abs(got[key] - truth[ref_key]) / truth[ref_key])
        return worst


def main():
    global PLDAMP
    if len(sys.argv) < 2 or sys.argv[1].startswith("-"):
        sys.exit("usage: %s PLDAMP_BINARY [unittest options]" % sys.argv[0])
    PLDAMP = os.path.abspath(sys.argv.pop(1))
    if not os.access(PLDAMP, os.X_OK):
        sys.exit("not an executable: " + PLDAMP)
    if shutil.which("liggghts") is None:
        print("liggghts is not installed: skipped", file=sys.stderr)
        sys.exit(77)
    unittest.main()


if __name__ == "__main__":
    main()
