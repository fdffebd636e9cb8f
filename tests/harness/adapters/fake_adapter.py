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
no_outcome   answers without an outcome
wrong_version  its handshake says version 2
no_handshake   exits before its handshake
crash        writes to stderr and exits with status 3 on its first problem
crash_once   crashes on its first problem of all (STATE_FILE remembers), then behaves as good
hang         never answers its first problem
hang_once    never answers its first problem of all (STATE_FILE remembers), then behaves as good
partial      writes half a line and exits
record       appends every problem line to STATE_FILE, then answers as good
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
    return {"outcome": "exited", "e": e, "delta_max": delta_max, "t_peak": t_peak, "tau": tau,
            "steps": 1, "wall_seconds": 1e-6}


def first_time(state):
    """True the first time any instance asks (the state file is created then)."""
    try:
        os.close(os.open(state, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        return True
    except FileExistsError:
        return False


def main():
    mode = sys.argv[1]
    state = sys.argv[2] if len(sys.argv) > 2 else None
    hello = json.loads(sys.stdin.readline())
    assert hello == {"protocol": "pldamp-solver", "version": 1}, hello
    if mode == "no_handshake":
        sys.exit(0)
    handshake = {"protocol": "pldamp-solver", "version": 2 if mode == "wrong_version" else 1,
                 "solver": "fake " + mode}
    if mode == "beta":
        handshake["damping_exponent"] = 0.5
    if mode == "unavailable":
        handshake["unavailable"] = "fakecode not found on PATH"
    print(json.dumps(handshake), flush=True)
    for line in sys.stdin:
        problem = json.loads(line)
        reply = {"id": problem["id"]}
        if mode == "record":
            with open(state, "a", encoding="utf-8") as log:
                log.write(line)
        if mode == "crash" or (mode == "crash_once" and first_time(state)):
            sys.stderr.write("fake: boom\n")
            sys.exit(3)
        if mode == "hang" or (mode == "hang_once" and first_time(state)):
            time.sleep(3600)
        if mode == "partial":
            sys.stdout.write('{"id": %d, "outc' % problem["id"])
            sys.stdout.flush()
            sys.exit(0)
        if mode == "bad_json":
            print("e = 0.5", flush=True)
            continue
        if mode == "unsupported" or problem["p"] != 1:
            reply.update(outcome="unsupported", reason="p = 1 only")
        elif mode == "error":
            reply.update(outcome="error", reason="fakecode: lost atoms")
        elif mode == "wrong_id":
            reply.update(closed_forms(problem), id=problem["id"] + 7)
        elif mode == "negative":
            reply.update(closed_forms(problem), e=-0.5)
        elif mode == "no_outcome":
            reply.update(closed_forms(problem))
            del reply["outcome"]
        else:
            reply.update(closed_forms(problem))
        print(json.dumps(reply), flush=True)


if __name__ == "__main__":
    main()
