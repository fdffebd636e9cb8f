#!/usr/bin/env python3
"""A test double for pldamp's external-solver protocol: well behaved, or misbehaving on purpose.

    fake_adapter.py MODE [STATE_FILE]

good         answers every problem with the linear oscillator's closed forms (p = 1 only; other p
             unsupported), an independent truth for the harness's p = 1 cells
unsupported  says so for every problem
unavailable  says so in its handshake
error        answers every problem with outcome "error"
bad_json     answers a line that is not JSON
wrong_id     answers for another problem
negative     answers e = -0.5
above_one    answers e = 1.3 (energy gained), the rest as good
negative_delta  answers delta_max = -0.1, the rest as good
peak         answers outcome peak (delta_max and t_peak only), whatever is wanted
gained       answers energy_load = -0.2 m v0^2/2 (energy gained), the rest as good
imbalance    answers the energies 0.1 m v0^2/2 more than the balance with e allows
dmax_huge    answers delta_max = 1e308 (far above the undamped peak), the rest as good
tpeak_zero   answers t_peak = 0, the rest as good
tpeak_after_tau  answers t_peak = 2 tau, the rest as good
tau_tiny     answers tau = 5e-324, the rest as good
fast_compression  answers t_peak = delta_max / (2 v0) (compressed at twice v0), the rest as good
fast_return  answers without t_peak and with tau = 1.5 delta_max / v0, the rest as good
gaps         its handshake runs p = 1 and 2 only; at p = 2 it answers exited without any value
honours      its handshake honours steps_per_contact and onset_phase only; answers as good
no_outcome   answers without an outcome
wrong_version  its handshake says version 2
no_handshake   exits before its handshake
crash        writes to stderr and exits with status 3 on its first problem
crash_once   crashes on its first problem of all (STATE_FILE remembers), then behaves as good
hang         never answers its first problem
hang_once    never answers its first problem of all (STATE_FILE remembers), then behaves as good
partial      writes half a line and exits
record       appends every problem line to STATE_FILE, then answers as good
fork_stay    forks a child that sleeps (holding the pipes), appends its pid and the program's to
             STATE_FILE, then answers as good
fork_exit    on its first problem forks such a child, appends the pids, and exits (status 0)
             without answering
fork_handshake  forks such a child, appends the pids, and exits before its handshake
deaf         never reads a problem (a problem line longer than a pipe's buffer then cannot be
             written)
slow_clock   answers as good, with wall_seconds 1e300 (longer than any round trip)
deep         answers e nested in 100 000 arrays (and a reason of 10^5 characters)
beta         says its dashpot goes as delta^0.5 delta' (not the seed's), then answers as good
"""

import json
import math
import os
import sys
import time


def closed_forms(problem):
    """The underdamped linear oscillator m x'' + c x' + k x = 0, x(0) = 0, x'(0) = v0."""
    m, k, v0, alpha = (problem[key] for key in ("m", "k", "v0", "alpha"))
    zeta = alpha / 2  # c = alpha sqrt(mk) = 2 zeta sqrt(mk)
    omega0 = math.sqrt(k / m)
    root = math.sqrt(1 - zeta * zeta)
    omega = omega0 * root
    tau = math.pi / omega
    t_peak = math.atan2(root, zeta) / omega
    delta_max = v0 / omega * math.exp(-zeta * omega0 * t_peak) * math.sin(omega * t_peak)
    e = math.exp(-zeta * omega0 * tau)
    # Dissipated: to the peak (at rest, the spring holding k delta_max^2/2), then to the exit.
    kinetic0, spring = 0.5 * m * v0 * v0, 0.5 * k * delta_max * delta_max
    return {"outcome": "exited", "e": e, "delta_max": delta_max, "t_peak": t_peak, "tau": tau,
            "energy_load": kinetic0 - spring, "energy_unload": spring - kinetic0 * e * e,
            "steps": 1, "wall_seconds": 1e-6}


def first_time(state):
    """True the first time any instance asks (the state file is created then)."""
    try:
        os.close(os.open(state, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        return True
    except FileExistsError:
        return False


def fork_sleeper(state):
    """Forks a child that sleeps an hour on the program's pipes; appends both pids to `state`."""
    child = os.fork()
    if child == 0:
        time.sleep(3600)
        os._exit(0)
    with open(state, "a", encoding="utf-8") as log:
        log.write("%d %d\n" % (os.getpid(), child))


def main():
    mode = sys.argv[1]
    state = sys.argv[2] if len(sys.argv) > 2 else None
    hello = json.loads(sys.stdin.readline())
    assert hello == {"protocol": "pldamp-solver", "version": 1}, hello
    if mode == "no_handshake":
        sys.exit(0)
    if mode == "fork_handshake":
        fork_sleeper(state)
        sys.exit(0)
    if mode == "fork_stay":
        fork_sleeper(state)
    handshake = {"protocol": "pldamp-solver", "version": 2 if mode == "wrong_version" else 1,
                 "solver": "fake " + mode}
    if mode == "beta":
        handshake["damping_exponent"] = 0.5
    if mode == "unavailable":
        handshake["unavailable"] = "fakecode not found on PATH"
    if mode == "unavailable_silently":
        handshake["unavailable"] = ""
    if mode == "gaps":
        handshake["p"] = [1, 2]
    if mode == "honours":
        handshake["honours"] = ["steps_per_contact", "onset_phase"]
    print(json.dumps(handshake), flush=True)
    if mode == "deaf":
        time.sleep(3600)
    for line in sys.stdin:
        problem = json.loads(line)
        reply = {"id": problem["id"]}
        if mode == "record":
            with open(state, "a", encoding="utf-8") as log:
                log.write(line)
        if mode == "fork_exit":
            fork_sleeper(state)
            sys.exit(0)
        if mode == "crash" or (mode == "crash_once" and first_time(state)):
            sys.stderr.write("fake: boom\n")
            sys.exit(3)
        if mode == "hang" or (mode == "hang_once" and first_time(state)):
            time.sleep(3600)
        if mode == "partial":
            sys.stdout.write('{"id": %d, "outc' % problem["id"])
            sys.stdout.flush()
            sys.exit(0)
        if mode == "deep":
            sys.stdout.write('{"id": %d, "outcome": "error", "reason": "%s", "e": %s%s}\n' %
                             (problem["id"], "\\u00e9\\n" * 50000, "[" * 100000, "]" * 100000))
            sys.stdout.flush()
            continue
        if mode == "bad_json":
            print("e = 0.5", flush=True)
            continue
        if mode == "gaps" and problem["p"] == 2:
            reply.update(outcome="exited", steps=1)
        elif mode == "unsupported" or problem["p"] != 1:
            reply.update(outcome="unsupported", reason="p = 1 only")
        elif mode == "error":
            reply.update(outcome="error", reason="fakecode: lost atoms")
        elif mode == "wrong_id":
            reply.update(closed_forms(problem), id=problem["id"] + 7)
        elif mode == "negative":
            reply.update(closed_forms(problem), e=-0.5)
        elif mode == "above_one":
            reply.update(closed_forms(problem), e=1.3)
        elif mode == "negative_delta":
            reply.update(closed_forms(problem), delta_max=-0.1)
        elif mode == "peak":
            forms = closed_forms(problem)
            reply.update(outcome="peak", delta_max=forms["delta_max"], t_peak=forms["t_peak"],
                         steps=1)
        elif mode == "gained":
            reply.update(closed_forms(problem))
            reply["energy_load"] = -0.2 * 0.5 * problem["m"] * problem["v0"] ** 2
        elif mode == "imbalance":
            reply.update(closed_forms(problem))
            reply["energy_unload"] += 0.1 * 0.5 * problem["m"] * problem["v0"] ** 2
        elif mode == "dmax_huge":
            reply.update(closed_forms(problem), delta_max=1e308)
        elif mode == "tpeak_zero":
            reply.update(closed_forms(problem), t_peak=0.0)
        elif mode == "tpeak_after_tau":
            forms = closed_forms(problem)
            reply.update(forms, t_peak=2 * forms["tau"])
        elif mode == "tau_tiny":
            reply.update(closed_forms(problem), tau=5e-324)
        elif mode == "fast_compression":
            forms = closed_forms(problem)
            reply.update(forms, t_peak=forms["delta_max"] / (2 * problem["v0"]))
        elif mode == "fast_return":
            reply.update(closed_forms(problem))
            del reply["t_peak"]
            reply["tau"] = 1.5 * reply["delta_max"] / problem["v0"]
        elif mode == "slow_clock":
            reply.update(closed_forms(problem), wall_seconds=1e300)
        elif mode == "no_outcome":
            reply.update(closed_forms(problem))
            del reply["outcome"]
        else:
            reply.update(closed_forms(problem))
        print(json.dumps(reply), flush=True)


if __name__ == "__main__":
    main()
