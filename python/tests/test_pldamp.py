"""The Python module `pldamp` (docs/python.md) against the reference tables the C++ tests use and
against the command line it mirrors.

    PYTHONPATH=build/python PLDAMP_DATA_DIR=data python3 -m pytest python/tests
"""

import csv
import decimal
import math
import os
import re

import numpy as np
import pytest

import pldamp

DATA = os.environ.get("PLDAMP_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "data"))


def table(name):
    with open(os.path.join(DATA, "reference", name), encoding="utf-8") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def relative(got, want):
    return abs(float(got) / float(want) - 1)


# The underdamped rows of analytic.csv (cpp_bin_float_50, 40 digits), away from critical damping
# where double's own condition number, not the code, sets the error (docs/MATH.md §8).
REFERENCE = [row for row in table("analytic.csv")
             if row["tau"] not in ("inf", "") and
             (row["input"] == "e" or float(row["value"]) <= 0.9)]


def test_double_agrees_with_the_reference_table():
    assert len(REFERENCE) > 100
    for row in REFERENCE:
        answer = pldamp.observables(p=row["p"], **{row["input"]: row["value"]}, v0=row["v0"],
                                    m=row["m"], k=row["k"])
        for key in ("e", "delta_max", "t_peak", "tau", "normal_force_max"):
            if float(row[key]) != 0:
                assert relative(answer[key], row[key]) < 2e-13, (row["p"], row["value"], key)


def test_quad_answers_every_digit_as_a_decimal():
    row = next(r for r in REFERENCE if r["p"] == "1.5" and r["input"] == "e" and
               r["value"] == "0.5")
    answer = pldamp.observables(p="1.5", e="0.5", v0=1, precision="quad")
    assert isinstance(answer["tau"], decimal.Decimal)
    assert len(answer["tau"].as_tuple().digits) >= 33
    with decimal.localcontext() as context:
        context.prec = 50
        for key in ("delta_max", "t_peak", "tau"):
            assert abs(answer[key] / decimal.Decimal(row[key]) - 1) < decimal.Decimal("1e-30"), key


def test_the_peak_normal_force_against_mpmath():
    for row in table("normal_force_peak.csv"):
        answer = pldamp.observables(p=row["p"], alpha_eff=row["alpha_eff"], v0=1)
        assert relative(answer["normal_force_max"], row["normal_force_max"]) < 1e-13
        if float(row["t_normal_force_max"]) == 0:  # the peak at the onset: exactly 0
            assert answer["t_normal_force_max"] == 0
        else:
            assert relative(answer["t_normal_force_max"], row["t_normal_force_max"]) < 1e-13


def test_arrays_are_the_scalars_element_for_element():
    alpha = np.array([0.0, 0.1, 0.6, 1.3, 5.0])
    v0 = np.array([[0.5], [2.0]])
    arrays = pldamp.observables(p=1.5, alpha=alpha, v0=v0, k=3.0)
    assert arrays["e"].shape == (2, 5)
    for i in range(2):
        for j in range(5):
            one = pldamp.observables(p=1.5, alpha=float(alpha[j]), v0=float(v0[i, 0]), k=3.0)
            for key in ("e", "delta_max", "t_peak", "tau", "energy_load"):
                if one.get(key) is None:  # τ of a contact that never returns
                    assert math.isnan(arrays[key][i, j]) or math.isinf(arrays[key][i, j])
                else:
                    assert arrays[key][i, j] == one[key], (key, i, j)
            # The command line prints α_eff formed in float128 and rounded once; the array path
            # gives the double contact's: one rounding apart at most.
            assert abs(arrays["alpha_eff"][i, j] - one["alpha_eff"]) <= 2.3e-16 * one["alpha_eff"]


def test_arrays_from_e_calibrate_as_the_command_line_does():
    # Both calibrate in float128 and round once (Contact::from_e): α and α_eff bit for bit, at
    # both contact ends.
    e = np.array([0.05, 0.3, 0.61, 0.9, 0.999])
    for end in ("overlap", "force"):
        for p in (1.0, 1.5, 2.5):
            arrays = pldamp.observables(p=p, e=e, v0=1.0, end=end, want="e")
            for j in range(len(e)):
                one = pldamp.calibrate(p=p, e=float(e[j]), end=end)
                assert arrays["alpha"][j] == one["alpha"], (end, p, e[j])
                assert arrays["alpha_eff"][j] == one["alpha_eff"], (end, p, e[j])


def test_arrays_keep_the_force_peak_and_the_loading_loss_as_damping_vanishes():
    # α_eff whose square underflows double (docs/MATH.md §3, "Vanishing damping"): the arrays run
    # the same closed forms, which gave normal_force_max 0 at t 0 and energy_load 0 there.
    alpha_eff = np.array([0.0, 1e-200, 1e-160, 5e-324])
    arrays = pldamp.observables(p=1.5, alpha_eff=alpha_eff, v0=1.0)
    for key in ("normal_force_max", "t_normal_force_max", "delta_max", "t_peak", "tau"):
        np.testing.assert_allclose(arrays[key], arrays[key][0], rtol=4.5e-16, atol=0, err_msg=key)
    loss = math.pi / 2 * alpha_eff  # KE0 π α_eff, a subnormal at 5e-324
    for key in ("energy_load", "energy_unload"):
        np.testing.assert_allclose(arrays[key], loss, rtol=4.5e-16, atol=5e-324, err_msg=key)


def test_arrays_by_target_e_at_the_force_end():
    e = np.linspace(0.1, 1.0, 7)
    arrays = pldamp.observables(p=[1.0, 1.5, 2.0], e=e[:, None], v0=1.0, end="force",
                                want=["e_cap", "tau"])
    assert set(arrays) == {"alpha", "alpha_eff", "e_cap", "tau"}
    np.testing.assert_allclose(arrays["e_cap"], np.broadcast_to(e[:, None], (7, 3)), rtol=1e-12)


def test_bad_input_raises_the_command_lines_line():
    _, _, err = pldamp.cli("observables", "--p", "1.5", "--e", "2", "--v0", "1")
    with pytest.raises(ValueError) as caught:
        pldamp.observables(p=1.5, e=2, v0=1)
    assert str(caught.value) == err.strip().removeprefix("error: ")
    with pytest.raises(ValueError, match=r"e must be in \(0, 1\] \(got 2\) at element 1"):
        pldamp.observables(p=1.5, e=[0.5, 2.0], v0=1)
    with pytest.raises(ValueError, match="runs in double"):
        pldamp.observables(p=1.5, e=[0.5], v0=1, precision="quad")
    with pytest.raises(ValueError, match="unknown observable in want"):
        pldamp.observables(p=1.5, e=[0.5], v0=1, want=["colour"])
    with pytest.raises(ValueError, match="unknown --code"):
        pldamp.timestep("dem-verlet", p=1.5, e=0.5, code="nosuchcode")


def test_materials_as_the_command_line_derives_them():
    row = table("hertz.csv")[0]  # two equal aluminium spheres
    answer = pldamp.observables(geometry="sphere-sphere", radius=0.01, young=7e10, poisson=0.3,
                                density=2700, e=0.5, v0=1.0)
    assert relative(answer["m"], row["m"]) < 4e-16
    assert relative(answer["k"], row["k"]) < 8e-16
    assert answer["units"]["delta_max"] == "m"


def test_the_trajectory_peaks_at_delta_max_and_leaves_at_minus_e_v0():
    closed = pldamp.observables(p=1.5, e=0.5, v0=2.0, m=3.0)
    t = np.array([-1.0, closed["t_peak"], closed["tau"] + 1.0])
    delta, v = pldamp.trajectory(t, p=1.5, e=0.5, v0=2.0, m=3.0)
    assert delta[0] == -2.0 and v[0] == 2.0
    assert relative(delta[1], closed["delta_max"]) < 1e-14
    assert abs(v[1]) < 1e-12
    assert relative(v[2], -0.5 * 2.0) < 1e-14
    assert relative(delta[2], -1.0) < 1e-14
    with pytest.raises(ValueError, match="unknown contact end"):  # once taken as the overlap end
        pldamp.trajectory(t, p=1.5, e=0.5, end="sideways")


def test_the_trajectory_at_extreme_times_against_mpmath():
    # data/reference/trajectory_ends.csv (mpmath at 80 digits, independent of the C++ code): every
    # row whose t = 2^n a double holds, 2^-1074 to 2^1023, within 16 eps times the problem's own
    # condition number |d ln y/d ln t| where that exceeds 1; values below double's normal range
    # within a few subnormal steps (0 where they underflow).
    eps, tiny, subnormal = np.finfo(float).eps, np.finfo(float).tiny, math.ldexp(1.0, -1074)
    contacts = {}
    for row in table("trajectory_ends.csv"):
        if -1074 <= int(row["log2_t"]) <= 1023:
            key = tuple(float(row[name]) for name in ("p", "alpha_eff", "v0", "m", "k"))
            contacts.setdefault(key, []).append(row)
    checked = 0
    for (p, alpha_eff, v0, m, k), rows in contacts.items():
        t = np.array([math.ldexp(1.0, int(row["log2_t"])) for row in rows])
        delta, v = pldamp.trajectory(t, p=p, alpha_eff=alpha_eff, v0=v0, m=m, k=k)
        for i, row in enumerate(rows):
            # After tau the table has the exit state; pldamp.trajectory flies on from delta = 0.
            returned = float(row["cond_v"]) == 0 and float(row["delta"]) == 0
            for got, name in ((delta[i], "delta"), (v[i], "v")):
                if returned and name == "delta":
                    assert got < 0
                    continue
                want, condition = float(row[name]), abs(float(row["cond_" + name]))
                where = (p, alpha_eff, v0, m, k, row["log2_t"], name, got, want)
                assert math.isfinite(got), where
                if abs(want) < tiny:
                    assert abs(got - want) <= 4 * subnormal + 16 * eps * abs(want), where
                else:
                    assert abs(got / want - 1) <= 16 * eps * max(1.0, condition), where
                checked += 1
    assert checked > 700


def test_the_times_of_issue_46_are_finite_and_right():
    # v was NaN at t = 1e100 and 1e300 (p = 1.5, alpha_eff = 2), where delta ~ (kappa t/T)^-4 is
    # below 1e-395: it underflows, v with it. delta/(v0 t) was 2.5e41 at t = 1e-300 (p = 1.5),
    # 3.3e84 (p = 2), 2.6e138 (p = 3), and 2.6e38 at t = 1e-200 (p = 3); it is 1 to the last bit.
    delta, v = pldamp.trajectory([1e100, 1e300], p=1.5, alpha_eff=2)
    assert np.all(np.isfinite(v)) and np.all(np.abs(v) <= np.finfo(float).tiny)
    assert np.all(delta == 0)
    t = np.array([1e-300, 1e-200, 1e-100])
    for p in (1.5, 2, 3):
        delta, v = pldamp.trajectory(t, p=p, alpha_eff=2)
        assert np.all(np.abs(delta / t - 1) <= np.finfo(float).eps), p
        assert np.all(v == 1.0), p


def test_the_force_end_parts_at_e_cap_from_delta_at_t_cut():
    # end="force" (docs/MATH.md §4): the contact ends at t_cut, where the total force reaches 0
    # with delta > 0, and the bodies fly apart at -e_cap v0 from delta(t_cut). alpha and
    # alpha_eff are the damping as given; overdamped contacts end so too.
    for damping in ({"alpha": 0.5}, {"alpha_eff": 2.0}):
        closed = pldamp.observables(p=1.5, v0=2.0, m=3.0, end="force", **damping)
        t_cut, e_cap = closed["t_cut"], closed["e_cap"]
        t = np.array([t_cut * (1 - 1e-9), t_cut, t_cut * 1.5, t_cut * 4])
        delta, v = pldamp.trajectory(t, p=1.5, v0=2.0, m=3.0, end="force", **damping)
        assert np.all(v[1:] == -e_cap * 2.0), damping
        # v is continuous at the cut (the force is 0 there), delta too, and it flies on.
        assert abs(v[0] / (-e_cap * 2.0) - 1) < 1e-12, damping
        assert 0 < delta[1] and abs(delta[0] - delta[1]) <= 2.0 * t_cut * 1e-9, damping
        for i in (2, 3):
            flown = delta[1] - e_cap * 2.0 * (t[i] - t_cut)
            assert abs(delta[i] - flown) <= 4e-16 * (abs(delta[1]) + 2.0 * t[i]), (damping, i)
    # The overlap end of the same contact parts later, at tau, from delta = 0 and at -e v0.
    closed = pldamp.observables(p=1.5, alpha=0.5, v0=2.0, m=3.0)
    delta, v = pldamp.trajectory([2 * closed["tau"]], p=1.5, alpha=0.5, v0=2.0, m=3.0)
    assert relative(v[0], -closed["e"] * 2.0) < 1e-15
    assert relative(delta[0], -closed["e"] * 2.0 * closed["tau"]) < 1e-14


def test_the_force_end_takes_e_as_e_cap():
    # With e= the damping is calibrated at the end asked for: at the force end e is e_cap, the
    # speed the bodies part at (the overlap end's e of that damping would be 0.436).
    closed = pldamp.observables(p=1.5, e=0.5, v0=2.0, end="force")
    assert relative(closed["e_cap"], 0.5) < 1e-15
    t = np.array([closed["t_cut"] * 1.01, closed["tau"] * 2])
    delta, v = pldamp.trajectory(t, p=1.5, e=0.5, v0=2.0, end="force")
    assert np.all(v == -closed["e_cap"] * 2.0)
    assert relative(v[0], -0.5 * 2.0) < 1e-15
    assert delta[0] > 0 > delta[1]


def test_the_trajectory_refuses_what_is_not_a_number():
    # t=[True, False] once ran as t = 1 and 0, p="1.5" as 1.5 and p=True as p = 1.
    with pytest.raises(TypeError, match="t takes numbers, not bools"):
        pldamp.trajectory([True, False], p=1.5, e=0.5)
    with pytest.raises(TypeError, match="p takes numbers, not bools"):
        pldamp.trajectory([0.1], p=True, e=0.5)
    with pytest.raises(ValueError, match="p holds '1.5' at index 0: not a number"):
        pldamp.trajectory([0.1], p="1.5", e=0.5)
    with pytest.raises(ValueError, match="t holds '0.1' at index 0: not a number"):
        pldamp.trajectory(["0.1"], p=1.5, e=0.5)
    with pytest.raises(TypeError, match="v0 takes real numbers, not complex ones"):
        pldamp.trajectory([0.1], p=1.5, e=0.5, v0=1 + 0j)
    with pytest.raises(TypeError, match=r"p takes one number \(got an array of shape \(2,\)\)"):
        pldamp.trajectory([0.1], p=[1.5, 2], e=0.5)
    with pytest.raises(ValueError, match="t must be finite"):
        pldamp.trajectory([float("nan")], p=1.5, e=0.5)
    # A Decimal and numpy scalars are numbers.
    delta, v = pldamp.trajectory(0.1, p=decimal.Decimal("1.5"), e=np.float32(0.5))
    want_delta, want_v = pldamp.trajectory([0.1], p=1.5, e=float(np.float32(0.5)))
    assert delta.shape == () and delta == want_delta[0] and v == want_v[0]


def test_check_judges_closed_form_samples_as_the_command_does():
    closed = pldamp.observables(p=1.5, e=0.5, v0=1.0)
    t = np.linspace(-0.1, closed["tau"] + 0.2, 2000)
    delta, v = pldamp.trajectory(t, p=1.5, e=0.5)
    answer = pldamp.check(t, delta, v, p=1.5, e=0.5, v0=1.0, tolerance=1e-4)
    assert answer["passed"] is True
    assert abs(answer["e"]["rel_error"]) < 1e-4


def test_solve_calibrate_and_timestep_answer_as_the_command_line():
    solved = pldamp.solve("cvode-bdf", p=1.5, e=0.5, v0=1.0, rtol=1e-10)
    assert solved["outcome"] == "exited" and relative(solved["e"], 0.5) < 1e-7
    assert pldamp.calibrate(p=1.5, e=0.5)["alpha"] == pldamp.observables(p=1.5, e=0.5,
                                                                         v0=1)["alpha"]
    quad = pldamp.calibrate(p="1.5", e="0.5", precision="50")
    assert isinstance(quad["alpha"], decimal.Decimal)
    step = pldamp.timestep("dem-verlet", p=1.5, e=0.5)
    assert step["tau_over_dt"] > 50


def test_tau_as_the_code_counts_it():
    # The answer names how tau is counted, and holds at the phase it names as worst: `solve` there
    # gives its error again, counted the same way.
    step = pldamp.timestep("dem-verlet", p=1.5, e=0.5, v0=1.0, observables="tau",
                           tau_as="crossing")
    assert step["tau_as"] == "crossing" and step["worst_error"] <= 0.01
    at = pldamp.solve("dem-verlet", p=1.5, e=0.5, v0=1.0, dt=step["dt"],
                      onset_phase=step["worst_onset_phase"], tau_as="crossing")
    assert at["tau"] == at["tau_crossing"]
    assert abs(relative(at["tau"], step["tau"]) - step["worst_error"]) < 1e-12
    counted = pldamp.solve("dem-verlet", p=1.5, e=0.5, v0=1.0, dt=0.05, onset_phase=0.3,
                           tau_as="steps-in-contact")
    assert counted["tau"] == counted["steps_in_contact"] * 0.05
    with pytest.raises(ValueError, match="--tau-as must be"):
        pldamp.timestep("dem-verlet", p=1.5, e=0.5, tau_as="rounded")


def test_run_returns_the_report(tmp_path):
    scene = os.path.join(DATA, "scenes", "quick.toml")
    report = pldamp.run(scene, out=tmp_path)
    assert report["totals"]["failed_records"] == 0
    assert len(report["records"]) > 100
    assert (tmp_path / "report.html").exists()
    with pytest.raises(ValueError, match="cannot read the scene"):
        pldamp.run(tmp_path / "missing.toml")


def test_a_run_shows_its_progress_on_sys_stderr_only_when_asked(tmp_path, capfd):
    # A run of about 2.5 s on one thread (7 200 solves at rtol 1e-10): its progress went to the
    # process's stderr (file descriptor 2) unasked, which a notebook does not show; now none
    # unless progress=True, and then on sys.stderr, a line at a time.
    e = ", ".join("%.4f" % (0.05 + 0.9 * i / 39) for i in range(40))
    v0 = ", ".join("%.6g" % (10 ** (-2 + 4 * i / 59)) for i in range(60))
    scene = tmp_path / "long.toml"
    scene.write_text('want = ["e"]\n[grid]\np = [1.0, 1.5, 2.0]\ne = [%s]\nv0 = [%s]\n'
                     '[[solver]]\nname = "cvode-bdf"\nrtol = 1e-10\n'
                     '[report]\nformats = ["json"]\n' % (e, v0))
    capfd.readouterr()
    pldamp.run(scene, out=tmp_path / "quiet", jobs=1)
    assert capfd.readouterr().err == ""
    pldamp.run(scene, out=tmp_path / "shown", jobs=1, progress=True)
    shown = capfd.readouterr().err
    assert re.search(r"^\d+ s: \d+/7200 records, ", shown, re.M), shown
    with pytest.raises(TypeError, match="progress is a switch"):
        pldamp.run(scene, progress="yes")


def test_ctrl_c_during_a_run_is_a_keyboard_interrupt(tmp_path):
    # The run stops at SIGINT and exits 130, as the command does; Python sees the Ctrl-C it was
    # (a RuntimeError before), and the report folder keeps no half-written file.
    import signal
    import threading
    import time
    scene = os.path.join(DATA, "scenes", "nightly.toml")  # about 25 s: stopped long before
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            pldamp.run(scene, out=tmp_path)
    finally:
        timer.cancel()
    assert time.monotonic() - started < 15
    assert not (tmp_path / "report.json").exists()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_bool_is_refused_where_a_number_is_meant_and_check_names_array_indices():
    with pytest.raises(TypeError, match="not a bool"):
        pldamp.observables(p=1.5, e=True, v0=1)
    with pytest.raises(TypeError, match="not a bool"):
        pldamp.observables(p=1.5, e=0.5, v0=1, m=False)
    with pytest.raises(TypeError, match="is a switch"):
        pldamp.calibrate(p=1.5, e=0.5, code="lammps-tsuji", limit_damping="yes")
    with_cap = pldamp.calibrate(p=1.5, e=0.5, code="lammps-tsuji", limit_damping=True)
    assert with_cap != pldamp.calibrate(p=1.5, e=0.5, code="lammps-tsuji", limit_damping=False)
    t = np.linspace(0.0, 1.0, 5)
    with pytest.raises(ValueError, match="1-D arrays of one length"):
        pldamp.check(t, t[:4], p=1.5, e=0.5, v0=1.0)
    with pytest.raises(ValueError, match=r"^at index 2 of the arrays: "):
        pldamp.check(np.array([0.0, 0.1, 0.1, 0.3]), np.array([0.0, 0.1, 0.2, 0.3]), p=1.5,
                     e=0.5, v0=1.0)


def test_what_python_hands_over_is_checked_not_cut_or_converted(tmp_path):
    # want: a name, or names each once, of ARRAY_OBSERVABLES ("tau" was read as t, a, u; "taux"
    # dropped everything), the same on the scalar and the array path.
    assert "tau" in pldamp.observables(p=1.5, e=0.5, v0=1.0, want="tau")
    assert set(pldamp.observables(p=[1.5], e=0.5, v0=1.0, want="tau")) == {"alpha", "alpha_eff",
                                                                           "tau"}
    for want in (["taux"], "taux", ["e", "e"], []):
        for p in (1.5, [1.5]):
            with pytest.raises(ValueError, match="want"):
                pldamp.observables(p=p, e=0.5, v0=1.0, want=want)
    # A NUL would cut the text where C reads it: p='1.5\x00garbage' was 1.5, and
    # run('tiny.toml\x00.bak') ran tiny.toml.
    with pytest.raises(ValueError, match="holds a NUL character"):
        pldamp.observables(p="1.5\x00garbage", e=0.5, v0=1.0)
    scene = tmp_path / "tiny.toml"
    scene.write_text('name = "tiny"\nwant = ["e"]\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [1.0]\n'
                     '[[solver]]\nname = "cvode-bdf"\nrtol = 1e-6\n[report]\nformats = ["csv"]\n')
    with pytest.raises(ValueError, match="holds a NUL character"):
        pldamp.run(str(scene) + "\x00.bak")
    with pytest.raises(ValueError, match="holds a NUL character"):
        pldamp.cli("observables", "--p", "1.5\x00", "--e", "0.5", "--v0", "1")
    # A scene without report.json, and a shard, write no report for run() to return: said so,
    # not a FileNotFoundError naming a deleted temporary.
    with pytest.raises(ValueError, match="writes no report.json"):
        pldamp.run(scene)
    with pytest.raises(ValueError, match="a shard writes none"):
        pldamp.run(scene, shard="1/2")
    # check of too few samples speaks of the arrays, not of index -1.
    with pytest.raises(ValueError) as refused:
        pldamp.check([], [], p=1.5, e=0.5, v0=1.0)
    assert "index -1" not in str(refused.value) and "trajectory.csv" not in str(refused.value)
    assert str(refused.value).startswith("the arrays: ")
    # Arrays of numbers only: a bool was 1.0, a complex number lost its imaginary part.
    with pytest.raises(TypeError, match="not bools"):
        pldamp.observables(p=[1.5], e=True, v0=1.0)
    with pytest.raises(TypeError, match="not bools"):
        pldamp.observables(p=[1.5], e=np.array([True]), v0=1.0)
    with pytest.raises(TypeError, match="complex"):
        pldamp.observables(p=[1.5], e=[0.5 + 1j], v0=1.0)
    with pytest.raises(ValueError, match=r"e holds '0.5x' at index 1: not a number"):
        pldamp.observables(p=[1.5, 1.5], e=[0.5, "0.5x"], v0=1.0)
    # A contact that never returns: tau is inf on the array path, null (None) on the scalar one.
    arrays = pldamp.observables(p=[1.5], alpha_eff=[1.5], v0=1.0, want=["tau", "e"])
    assert np.isinf(arrays["tau"][0]) and arrays["e"][0] == 0
    assert pldamp.observables(p=1.5, alpha_eff=1.5, v0=1.0)["tau"] is None


def test_arrays_take_plain_real_numbers_only_and_text_must_be_utf8():
    # Found by the second hostile pass: check() and the arrays took complex values (their
    # imaginary part dropped), bools, timedeltas and masked arrays (the mask ignored).
    t = np.linspace(0.0, 1.0, 5)
    with pytest.raises(TypeError, match="complex"):
        pldamp.check(t, t + 1j, p=1.5, e=0.5, v0=1.0)
    with pytest.raises(TypeError, match="bool"):
        pldamp.check(t, t > 0.5, p=1.5, e=0.5, v0=1.0)
    with pytest.raises(TypeError, match="timedelta64"):
        pldamp.observables(p=[1.5], e=np.array([1], dtype="timedelta64[s]"), v0=1.0)
    with pytest.raises(TypeError, match="masked"):
        pldamp.observables(p=np.ma.masked_array([1.5, 2.0], mask=[False, True]), e=0.5, v0=1.0)
    with pytest.raises(ValueError, match="UTF-8"):
        pldamp.cli("observables", "--p", "\udcff")
    with pytest.raises(ValueError, match="give it alone"):
        pldamp.solve("taylor", p=1.5, e=0.5, v0=1.0, want="all,e")


def test_an_unknown_keyword_is_a_type_error_naming_the_nearest():
    # The command line said "unknown argument (got --mass 5.0)" and, for vo=1, "--v0 is required".
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'mass'; did you mean 'm'\?"):
        pldamp.observables(p=1.5, e=0.5, v0=1.0, mass=5.0)
    with pytest.raises(TypeError, match=r"'vo'; did you mean 'v0'\?"):
        pldamp.observables(p=1.5, e=0.5, vo=1.0)
    with pytest.raises(TypeError, match=r"'rtl'; did you mean 'rtol'\?"):
        pldamp.solve("cvode-bdf", p=1.5, e=0.5, v0=1.0, rtl=1e-8)
    with pytest.raises(TypeError, match=r"'colour' \(it takes p, e, end"):
        pldamp.observables(p=1.5, e=0.5, v0=1.0, colour="red")
