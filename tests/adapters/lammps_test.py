#!/usr/bin/env python3
"""adapters/lammps against pldamp: python3 tests/adapters/lammps_test.py PLDAMP_BINARY

Exit 0 when every test passes, 77 when LAMMPS is not installed (the adapter answers the handshake
`unavailable`), 1 with the failures named otherwise. Plain unittest; the adapter is driven through
the protocol itself (a subprocess, one JSON line each way).

  1. Seed-exponent models (beta = (p-1)/2) agree with `pldamp solve --solver dem-verlet` (the same
     p, alpha, v0, m, k, time step, onset phase, contact end) to round-off in e, delta_max, t_peak,
     tau, the energies and the step count.
  2. At 2000 steps per contact they approach the closed forms (`pldamp observables`) at first
     order: the worst error over 8 onset phases is about 10x smaller than at 200.
  3. Non-seed models declare their beta, run, and give sane values; they also agree to round-off
     with a transcription of dem-verlet's loop (solvers/src/dem.cpp) for a general beta, which
     pldamp's own solvers do not run.
  4. The protocol: handshake, a wrong version, problems the model cannot run, no library.
  5. The time per problem at 20 and 2000 steps per contact (printed, loosely bounded).
  6. The code's own entry end to end: the cor `pldamp calibrate --code lammps-tsuji` says to enter
     for e = 0.5, run by LAMMPS through the adapter's `entry` option, gives e = 0.5 within the
     scheme's step error; entering 0.5 gives the e_given calibrate predicts.
"""

import json
import math
import os
import subprocess
import sys
import tempfile
import time
import unittest

from adapter_process import AdapterProcess, run_pldamp

HERE = os.path.dirname(os.path.abspath(__file__))
ADAPTER = os.path.join(HERE, "..", "..", "adapters", "lammps")
PLDAMP = None  # set from the command line
HANDSHAKE = {"protocol": "pldamp-solver", "version": 1}

# Measured (Debian 12, LAMMPS 29 Sep 2021): relative differences up to 1.2e-14 (the energies
# relative to the impact energy); the bound is a little above.
ROUND_OFF = 5e-14

SEED_MODELS = [  # (arguments, p)
    (["--normal", "hooke", "--damping", "velocity"], 1.0),
    (["--normal", "hooke", "--damping", "mass_velocity"], 1.0),
    (["--normal", "hooke", "--damping", "tsuji"], 1.0),
    (["--normal", "hertz", "--damping", "tsuji"], 1.5),
    (["--normal", "hertz/material", "--damping", "tsuji"], 1.5),
    (["--pair", "gran/hooke"], 1.0),
    (["--pair", "gran/hooke/history"], 1.0),
]
NON_SEED_MODELS = [  # (arguments, p, beta read from the source)
    (["--normal", "hooke", "--damping", "viscoelastic"], 1.0, 0.5),
    (["--normal", "hertz", "--damping", "velocity"], 1.5, 0.0),
    (["--normal", "hertz", "--damping", "mass_velocity"], 1.5, 0.0),
    (["--normal", "hertz", "--damping", "viscoelastic"], 1.5, 0.5),
    (["--normal", "hertz/material", "--damping", "viscoelastic"], 1.5, 0.5),
    (["--normal", "hertz/material", "--damping", "velocity"], 1.5, 0.0),
    (["--pair", "gran/hertz/history"], 1.5, 0.5),
]
UNITS = [(1.0, 1.0, 1.0), (2.5e-3, 3.0e7, 0.7)]  # (m, k, v0): unit scales, and a bead-like contact
PHASES = [0.1, 0.5, 0.85]
OBSERVABLES = ["e", "delta_max", "t_peak", "tau", "energy_load", "energy_unload"]


class Adapter(AdapterProcess):
    def __init__(self, arguments, handshake=HANDSHAKE):
        super().__init__([ADAPTER] + arguments, handshake)


def pldamp(*arguments):
    return run_pldamp(PLDAMP, *arguments)


def dem_verlet(p, alpha, m, k, v0, spc, phase, end):
    return pldamp("solve", "--solver", "dem-verlet", "--p", p, "--alpha", repr(alpha),
                  "--m", repr(m), "--k", repr(k), "--v0", repr(v0), "--steps-per-contact", spc,
                  "--onset-phase", repr(phase), "--end", end)


def pldamp_value(answer, key, end):
    """pldamp's value of an observable of the protocol (e, tau are e_cap, t_cut when capped)."""
    if end == "force":
        key = {"e": "e_cap", "tau": "t_cut"}.get(key, key)
    return answer[key]


def problem_for(p, alpha, m, k, v0, spc, dt, phase, end, beta="seed"):
    return {"p": p, "m": m, "k": k, "v0": v0, "alpha": alpha, "damping_exponent": beta,
            "end": end, "want": OBSERVABLES, "steps_per_contact": spc, "dt": dt,
            "onset_phase": phase, "options": {}}


def relative(a, b, scale=None):
    return abs(a - b) / (scale if scale is not None else max(abs(b), 1e-300))


def dem_verlet_loop(p, beta, alpha, m, k, v0, dt, phase, end):
    """solvers/src/dem.cpp's velocity-Verlet loop and measurements for a dashpot with any beta
    (pldamp's solvers take beta = (p-1)/2 only): half kick, drift, force from the new overlap and
    the half-step velocity, half kick; the contact ends at the first force evaluation with no
    overlap or, capped, with a total force <= 0."""
    c = alpha * math.sqrt(m * k)
    t = (phase - 1) * dt
    delta, v, f = v0 * t, v0, 0.0
    touched = ended = False
    last = None
    out = {}
    kinetic0 = 0.5 * m * v0 * v0

    def dissipated(d, u):
        return kinetic0 - 0.5 * m * u * u - k * max(d, 0.0) ** (p + 1) / (p + 1)

    for steps in range(1, 10 ** 6):
        v += dt / 2 * f / m
        delta += dt * v
        if delta <= 0:
            ended, f = touched, 0.0
        else:
            touched = True
            force = k * delta ** p + c * delta ** beta * v
            if end == "force" and force <= 0:
                ended, f = True, 0.0
            else:
                f = -force
        v += dt / 2 * f / m
        t += dt
        if touched and "delta_max" not in out and last and delta < last[1]:
            out.update(delta_max=last[1], t_peak=last[0],
                       energy_load=dissipated(last[1], last[2]))
        if ended:
            out.update(e=abs(v) / v0, tau=t, steps=steps,
                       energy_unload=dissipated(delta, v) - out["energy_load"])
            return out
        last = (t, delta, v)
    raise AssertionError("no exit")


class LammpsAdapterTest(unittest.TestCase):

    def adapter(self, arguments, handshake=HANDSHAKE):
        """An adapter that is stopped when the test ends, passed or failed."""
        adapter = Adapter(arguments, handshake)
        self.addCleanup(adapter.kill)
        return adapter

    def agree(self, got, reference, end, label, observables=OBSERVABLES):
        """Round-off agreement of the adapter's answer with a dem-verlet answer; returns the worst."""
        self.assertEqual(got.get("outcome"), "exited", "%s: %r" % (label, got))
        self.assertEqual(got["steps"], reference["steps"], label)
        worst = 0.0
        energy = 0.5 * reference["m"] * reference["v0"] ** 2 if "m" in reference else None
        for key in observables:
            mine = got[key]
            theirs = pldamp_value(reference, key, end)
            scale = energy if key.startswith("energy") and energy else None
            error = relative(mine, theirs, scale)
            worst = max(worst, error)
            self.assertLess(error, ROUND_OFF, "%s %s: adapter %.17g, dem-verlet %.17g"
                            % (label, key, mine, theirs))
        return worst

    def test_1_seed_models_agree_with_dem_verlet_to_round_off(self):
        worst = 0.0
        for arguments, p in SEED_MODELS:
            alpha = 0.6 if p == 1 else 0.5
            adapter = self.adapter(arguments)
            self.assertEqual(adapter.hello["damping_exponent"], "seed", arguments)
            for m, k, v0 in UNITS:
                for spc in (20, 200):
                    for phase in PHASES:
                        for end in ("overlap", "force"):
                            ref = dem_verlet(p, alpha, m, k, v0, spc, phase, end)
                            got = adapter.solve(problem_for(p, alpha, m, k, v0, spc, ref["dt"],
                                                            phase, end))
                            label = "%s m=%g k=%g v0=%g spc=%d phase=%g end=%s" % (
                                " ".join(arguments), m, k, v0, spc, phase, end)
                            worst = max(worst, self.agree(got, ref, end, label))
            self.assertEqual(adapter.close(), 0)
        print("\n  seed models vs dem-verlet: worst relative difference %.2g" % worst,
              file=sys.stderr)

    def test_2_first_order_approach_to_the_closed_forms(self):
        # The error of one run depends on where the step grid falls at the entry and the exit, so
        # each error is the worst over 8 onset phases, as in data/scenes/dem.toml's step study.
        phases = [i / 8 for i in range(8)]
        keys = ["e", "delta_max", "t_peak", "tau"]
        for arguments, p in SEED_MODELS:
            alpha = 0.6 if p == 1 else 0.5
            adapter = self.adapter(arguments)
            for end in ("overlap", "force"):
                truth = pldamp("observables", "--p", p, "--alpha", alpha, "--v0", 1, "--end", end)
                worst = {}
                for spc in (200, 2000):
                    dt = dem_verlet(p, alpha, 1.0, 1.0, 1.0, spc, 0.0, end)["dt"]
                    for phase in phases:
                        got = adapter.solve(problem_for(p, alpha, 1.0, 1.0, 1.0, spc, dt, phase,
                                                        end))
                        for key in keys:
                            error = relative(got[key], pldamp_value(truth, key, end))
                            worst[spc, key] = max(worst.get((spc, key), 0.0), error)
                for key in keys:
                    ratio = worst[200, key] / worst[2000, key]
                    message = ("%s end=%s %s: worst error %.3g at 200 steps per contact, %.3g at "
                               "2000 (ratio %.3g; first order: ~10)"
                               % (" ".join(arguments), end, key, worst[200, key],
                                  worst[2000, key], ratio))
                    self.assertLess(worst[2000, key], 2e-3, message)
                    if key == "e" and end == "overlap":
                        # e at the overlap end also carries where the last step falls before the
                        # exit: at p = 1 the worst at 200 is a phase whose exit lands badly
                        # (measured ratio 72; 12 at p = 3/2): at least first order
                        self.assertGreater(ratio, 6, message)
                    else:
                        self.assertTrue(6 < ratio < 16, message)
            self.assertEqual(adapter.close(), 0)

    def test_3_non_seed_models_declare_beta_and_agree_with_the_loop(self):
        worst = 0.0
        for arguments, p, beta in NON_SEED_MODELS:
            adapter = self.adapter(arguments)
            self.assertEqual(adapter.hello["damping_exponent"], beta, arguments)
            self.assertEqual(adapter.hello["p"], [p], arguments)
            alpha = 0.5
            for end in ("overlap", "force"):
                for spc, phase in ((20, 0.3), (200, 0.7)):
                    delta_u = ((p + 1) / 2) ** (1 / (p + 1))
                    dt = math.pi * delta_u / spc
                    got = adapter.solve(problem_for(p, alpha, 1.0, 1.0, 1.0, spc, dt, phase, end,
                                                    beta))
                    label = "%s end=%s spc=%d" % (" ".join(arguments), end, spc)
                    self.assertEqual(got["outcome"], "exited", label)
                    self.assertTrue(0 < got["e"] < 1 and got["delta_max"] > 0
                                    and 0 < got["t_peak"] < got["tau"], "%s: %r" % (label, got))
                    loop = dem_verlet_loop(p, beta, alpha, 1.0, 1.0, 1.0, dt, phase, end)
                    loop.update(m=1.0, v0=1.0)
                    worst = max(worst, self.agree(got, loop, "overlap", label))
            self.assertEqual(adapter.close(), 0)
        print("\n  non-seed models vs the loop: worst relative difference %.2g" % worst,
              file=sys.stderr)

    def test_4_protocol(self):
        adapter = self.adapter(["--normal", "hertz", "--damping", "tsuji"])
        hello = adapter.hello
        self.assertEqual((hello["protocol"], hello["version"]), ("pldamp-solver", 1))
        self.assertIn("LAMMPS", hello["solver"])
        self.assertIn("tsuji", hello["solver"])
        self.assertEqual(hello["p"], [1.5])
        self.assertEqual(sorted(hello["ends"]), ["force", "overlap"])
        self.assertEqual(hello["honours"],
                         ["steps_per_contact", "dt", "onset_phase", "options.entry"])
        self.assertNotIn("unavailable", hello)
        base = problem_for(1.5, 0.5, 1.0, 1.0, 1.0, 50, 0.07, 0.5, "overlap")
        cases = [
            (dict(base, p=1.0), "p = 1.5 only"),
            (dict(base, damping_exponent=0.5), "damping exponent"),
            (dict(base, alpha=2.0), "tsuji"),  # above T(0) = 1.2728: no cor in [0, 1]
            ({k: v for k, v in base.items() if k not in ("dt", "steps_per_contact")}, "dt"),
            (dict(base, end="sideways"), "end"),
        ]
        for problem, words in cases:
            reply = adapter.solve(problem)
            self.assertEqual(reply["outcome"], "unsupported", reply)
            self.assertIn(words, reply["reason"])
        self.assertEqual(adapter.solve(base)["outcome"], "exited")  # still serving
        self.assertEqual(adapter.close(), 0)

        missing = self.adapter(["--normal", "hooke", "--damping", "tsuji", "--library",
                                "/nonexistent/liblammps.so.0"])
        self.assertIn("not loadable", missing.hello["unavailable"])
        self.assertEqual((missing.hello["p"], missing.hello["damping_exponent"]), ([1.0], "seed"))
        self.assertEqual(missing.close(), 0)

        wrong = self.adapter(["--pair", "gran/hertz/history"], handshake=None)
        wrong.process.stdin.write(json.dumps({"protocol": "pldamp-solver", "version": 2}) + "\n")
        wrong.process.stdin.flush()
        self.assertEqual(wrong.process.stdout.readline(), "")  # no answer
        self.assertNotEqual(wrong.close(), 0)

    def test_5_time_per_problem(self):
        """Reported, not judged: the wall time per problem at 20 and 2000 steps per contact."""
        adapter = self.adapter(["--normal", "hertz", "--damping", "tsuji"])
        for spc in (20, 2000):
            ref = dem_verlet(1.5, 0.5, 1.0, 1.0, 1.0, spc, 0.5, "overlap")
            problem = problem_for(1.5, 0.5, 1.0, 1.0, 1.0, spc, ref["dt"], 0.5, "overlap")
            adapter.solve(problem)  # warm
            started = time.perf_counter()
            replies = [adapter.solve(problem) for _ in range(10)]
            round_trip = (time.perf_counter() - started) / 10
            print("\n  %4d steps per contact: %.1f ms per problem (round trip), %.1f ms in the "
                  "adapter" % (spc, 1e3 * round_trip,
                               1e3 * sum(r["wall_seconds"] for r in replies) / 10),
                  file=sys.stderr)
            self.assertLess(round_trip, 1.0)
        self.assertEqual(adapter.close(), 0)

    def test_6_the_codes_own_entry_gives_what_calibrate_says(self):
        """"Enter 0.36665, get 0.5", through the real code: the entry of LAMMPS's tsuji damping
        (its cor) that pldamp calibrate prints, passed as the adapter's `entry` option, against
        the target at 200 and 2000 steps per contact (worst of three onset phases): the error
        falls at first order toward it, and every run agrees with dem-verlet at the alpha
        LAMMPS sets for that cor (T(cor) in double) to round-off."""
        code = pldamp("calibrate", "--code", "lammps-tsuji", "--p", 1.5, "--e", 0.5)
        seed = pldamp("calibrate", "--p", 1.5, "--e", 0.5)
        cases = [  # (entry, the alpha LAMMPS sets for it, the e it gives)
            (code["e_to_enter"], seed["alpha"], 0.5),
            (0.5, code["alpha"], code["e_given"]),
        ]
        self.assertGreater(abs(code["e_given"] - 0.5), 0.1)  # the two cases are far apart
        adapter = self.adapter(["--normal", "hertz", "--damping", "tsuji"])
        for entry, alpha, target in cases:
            worst = {}
            for spc in (200, 2000):
                for phase in (0.1, 0.5, 0.85):
                    ref = dem_verlet(1.5, alpha, 1.0, 1.0, 1.0, spc, phase, "overlap")
                    # the problem's own alpha is another: the entry alone decides what runs
                    problem = problem_for(1.5, 1.0, 1.0, 1.0, 1.0, spc, ref["dt"], phase,
                                          "overlap")
                    problem["options"] = {"entry": entry}
                    got = adapter.solve(problem)
                    label = "entry %r spc %d phase %g" % (entry, spc, phase)
                    self.agree(got, ref, "overlap", label, ["e", "delta_max", "tau"])
                    worst[spc] = max(worst.get(spc, 0.0), abs(got["e"] - target))
            message = ("entry %r: |e - %.6g| at most %.3g at 200 steps per contact, %.3g at 2000"
                       % (entry, target, worst[200], worst[2000]))
            print("\n  " + message, file=sys.stderr)
            self.assertLess(worst[2000], 2e-3, message)
            self.assertGreater(worst[200] / worst[2000], 6, message)  # first order: ~10
        # Through a scene (pldamp run, 2000 steps per contact): the truth is e = 0.5, the record's
        # value what LAMMPS gives for the entry; an option the handshake does not honour is
        # refused before any work.
        with tempfile.TemporaryDirectory() as folder:
            def scene(options):
                path = os.path.join(folder, "entry.toml")
                with open(path, "w", encoding="utf-8") as out:
                    out.write('want = ["e"]\n[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n[[solver]]\n'
                              'command = [%s, "--normal", "hertz", "--damping", "tsuji"]\n'
                              'label = "lammps hertz tsuji, entered"\n'
                              'steps_per_contact = 2000\noptions = %s\n'
                              '[report]\nformats = ["json"]\n'
                              % (json.dumps(os.path.abspath(ADAPTER)), options))
                return subprocess.run([PLDAMP, "run", path, "--out", folder], capture_output=True,
                                      text=True, check=False)
            for entry, _, target in cases:
                run = scene("{ entry = %r }" % entry)
                self.assertEqual(run.returncode, 0, run.stderr)
                with open(os.path.join(folder, "report.json"), encoding="utf-8") as report:
                    (record,) = json.load(report)["records"]
                self.assertEqual(record["reference"]["e"], 0.5)
                self.assertLess(abs(record["value"]["e"] - target), 2e-3, record)
            refused = scene("{ entry = 0.5, newton_off = true }")
            self.assertEqual(refused.returncode, 2)
            self.assertIn("newton_off", refused.stderr)
        # an entry LAMMPS would refuse, and an option the adapter does not take
        base = problem_for(1.5, 0.5, 1.0, 1.0, 1.0, 50, 0.07, 0.5, "overlap")
        for options, words in (({"entry": 1.5}, "cor, in [0, 1]"), ({"entry": "x"}, "number"),
                               ({"entry": 0.5, "newton_off": True}, "one option, entry")):
            reply = adapter.solve(dict(base, options=options))
            self.assertEqual(reply["outcome"], "unsupported", reply)
            self.assertIn(words, reply["reason"])
        self.assertEqual(adapter.close(), 0)


def main():
    global PLDAMP
    if len(sys.argv) != 2:
        sys.exit("usage: python3 tests/adapters/lammps_test.py PLDAMP_BINARY")
    PLDAMP = os.path.abspath(sys.argv[1])
    probe = Adapter(["--normal", "hooke", "--damping", "velocity"])
    probe.close()
    if "unavailable" in probe.hello:
        print("skipped: " + probe.hello["unavailable"], file=sys.stderr)
        return 77
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(LammpsAdapterTest)
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    return 0 if result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
