"""calibrate, solve and timestep over arrays of cells, and a run's records as a table (issue 51):
every cell is the scalar call's answer, bit for bit, and the table is report.csv's.

    PYTHONPATH=build/python PLDAMP_DATA_DIR=data python3 -m pytest python/tests
"""

import csv
import decimal
import math
import os

import numpy as np
import pytest

import pldamp

DATA = os.environ.get("PLDAMP_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "data"))


def same_number(array_value, scalar_value):
    """A cell of an array against the scalar answer: NaN where the scalar has none (JSON's null
    for an infinity), else the very double."""
    if scalar_value is None:
        return math.isnan(array_value) or math.isinf(array_value)
    return float(array_value).hex() == float(scalar_value).hex()


def cells_are_the_scalar_calls(function, first, arrays, **fixed):
    shape = np.broadcast_shapes(*[np.shape(a) for a in arrays.values()])
    answer = function(first, **arrays, **fixed) if first else function(**arrays, **fixed)
    broadcast = {name: np.broadcast_to(a, shape) for name, a in arrays.items()}
    for index in np.ndindex(*shape):
        # An integral option (steps_per_contact) as an int: the command line reads "20.0" as no
        # integer, and a float64 cell goes in as its shortest digits, "20".
        cell = {name: int(a[index]) if name == "steps_per_contact" else float(a[index])
                for name, a in broadcast.items()}
        scalar = function(first, **cell, **fixed) if first else function(**cell, **fixed)
        for key, value in scalar.items():
            if key in ("wall_seconds", "samples", "observables", "range"):
                continue
            got = answer[key]
            if isinstance(got, np.ndarray):
                assert got.shape == shape, key
                if got.dtype.kind in "fi":
                    assert same_number(got[index], value), (key, index, got[index], value)
                else:
                    assert got[index] == value, (key, index)
            else:  # a text every cell shares
                assert got == value, key
    return answer


def test_calibrate_over_arrays_is_the_scalar_calibration_per_cell():
    answer = cells_are_the_scalar_calls(pldamp.calibrate, None,
                                        {"p": [[1.0], [1.5], [2.5]], "e": [0.05, 0.5, 0.999]},
                                        end="force")
    assert answer.alpha.shape == (3, 3) and answer.precision == "double"


def test_solve_over_arrays_on_threads_is_the_scalar_solve_per_cell():
    answer = cells_are_the_scalar_calls(
        pldamp.solve, "taylor", {"e": np.linspace(0.1, 1.0, 7), "v0": [[0.1], [10.0]]},
        p=1.5, repeats=1)
    assert answer.outcome == "exited" and answer.steps.dtype == np.int64
    # A fixed-step scheme over its onset phases and steps: the worst over phases by numpy.
    phases = np.linspace(0, 1, 16, endpoint=False)
    solved = cells_are_the_scalar_calls(pldamp.solve, "dem-verlet",
                                        {"onset_phase": phases, "steps_per_contact": [[20], [80]]},
                                        p=1.5, e=0.5, v0=1.0, repeats=1)
    worst = np.max(np.abs(solved.e / 0.5 - 1), axis=1)
    assert worst[1] < worst[0] < 0.2


def test_batched_schemes_step_their_cells_in_lanes_and_answer_as_the_scalar_call():
    # 600 cells, three chunks of lanes: each cell is the scalar solve's answer, bit for bit; a
    # refused cell among them is named by its index.
    cells_are_the_scalar_calls(pldamp.solve, "dem-leapfrog",
                               {"onset_phase": np.linspace(0, 1, 300, endpoint=False),
                                "steps_per_contact": [[30], [500]]},
                               p=2.0, e=0.3, v0=2.0, repeats=1)
    dt = np.full(600, 0.01)
    dt[417] = -1.0
    with pytest.raises(ValueError, match=r" at element 417$"):
        pldamp.solve("verlet-predicted", p=1.5, e=0.5, v0=1.0, dt=dt, repeats=1)


def test_solve_over_arrays_keeps_what_a_cell_has_not():
    # α_eff 2 never returns: its τ is inf (JSON's null), its outcome no_exit beside exited; a
    # sample time outside the first contact is refused there, and a key only some cells have is
    # NaN in the others.
    answer = pldamp.solve("cvode-bdf", p=1.5, alpha_eff=[0.2, 2.0], v0=1.0, repeats=1)
    assert list(answer.outcome) == ["exited", "no_exit"]
    assert math.isfinite(answer.tau[0]) and math.isinf(answer.tau[1])
    stepped = pldamp.solve("dem-verlet", p=1.5, e=0.5, v0=1.0, dt=[0.01, 0.02], repeats=1)
    assert stepped.tau_as == "first-step-out" and stepped.steps_in_contact.dtype == np.int64


def test_timestep_over_arrays_is_one_table():
    cells_are_the_scalar_calls(pldamp.timestep, "dem-verlet",
                               {"e": [0.3, 0.9], "tolerance": [[0.01], [0.05]]}, p=1.5)


def test_a_refused_cell_names_its_index_and_jobs_is_checked():
    with pytest.raises(ValueError, match=r"^e must be in \(0, 1\] \(got 2\) at element 2$"):
        pldamp.solve("taylor", p=1.5, e=[0.5, 0.6, 2.0], v0=1.0)
    with pytest.raises(ValueError, match="jobs goes with arrays"):
        pldamp.solve("taylor", p=1.5, e=0.5, v0=1.0, jobs=2)
    with pytest.raises(ValueError, match="jobs is a count"):
        pldamp.solve("taylor", p=1.5, e=[0.5], v0=1.0, jobs=0)
    with pytest.raises(ValueError, match="hold no cell"):
        pldamp.calibrate(p=1.5, e=[])
    with pytest.raises(ValueError, match="not a number"):
        pldamp.calibrate(p=1.5, e=[0.5, "x"])


def test_the_records_table_is_report_csv(tmp_path):
    report = pldamp.run(os.path.join(DATA, "scenes", "quick.toml"), out=tmp_path)
    assert isinstance(report, pldamp.Report) and repr(report).startswith("Report('quick': 810")
    table = report.table()
    with open(tmp_path / "report.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(table) == len(rows) == len(report["records"])
    for name in rows[0]:
        if name not in table.dtype.names:
            assert all(row[name] == "" for row in rows), name  # contact: none without materials
            continue
        column = table[name]
        for value, row in zip(column, rows):
            text = row[name]
            if column.dtype.kind == "f":
                # report.json rounds a time to 4 digits, report.csv to 6; every other number is
                # written in full in both.
                close = 1e-3 if name.endswith("seconds") or name.endswith("seconds_slowest") \
                    else 0
                assert (math.isnan(value) and text in ("", "nan", "inf")) or \
                    abs(value - float(text)) <= close * abs(value), (name, value, text)
            elif column.dtype.kind == "i":
                assert value == int(text), name
            else:
                assert str(value) == text, name
    # config tells apart what solver, rtol and the rest do not (the force end's cvode-bdf 1e-10).
    assert len(set(table["config"])) == len(report["scene"]["configs"])
    assert sum(row["config"].endswith("end=force") for row in rows) == 45


def test_the_records_as_a_dataframe(tmp_path):
    pandas = pytest.importorskip("pandas")
    report = pldamp.run(os.path.join(DATA, "scenes", "quick.toml"), out=tmp_path)
    frame = report.dataframe()
    assert isinstance(frame, pandas.DataFrame) and len(frame) == len(report["records"])
    worst = frame.groupby("solver")["e_rel_error"].max()
    assert worst["taylor"] < 1e-12 < worst["verlet-predicted"]


def test_what_a_new_user_found_in_arrays():
    # A whole number of steps goes in as an integer (1e+05 was refused).
    assert pldamp.solve("dem-verlet", p=1.5, e=0.5, v0=1, steps_per_contact=[100000],
                        repeats=1).steps[0] == \
        pldamp.solve("dem-verlet", p=1.5, e=0.5, v0=1, steps_per_contact=100000, repeats=1).steps
    # A JSON null that is no infinity (no entry reaches e) is NaN in a float array, every cell's too.
    reach = pldamp.calibrate(p=1.5, e=[0.05, 0.5], code="lammps-tsuji").e_to_enter
    assert reach.dtype == np.float64 and math.isnan(reach[0]) and reach[1] > 0
    assert math.isnan(pldamp.calibrate(p=1.5, e=[0.05], code="lammps-tsuji").e_to_enter[0])
    # Wider precisions: Decimals in an object array, never collapsed, infinity as Infinity.
    quad = pldamp.calibrate(p=1.5, e=[0.5, 0.5], precision="quad").alpha
    assert quad.shape == (2,) and quad[0] == quad[1] == pldamp.calibrate(
        p=1.5, e=0.5, precision="quad").alpha
    never = pldamp.solve("taylor", p=1.5, alpha_eff=[0.5, 2.0], v0=1, precision="quad",
                         horizon=50, repeats=1).tau
    assert never[1] == decimal.Decimal("Infinity") and never[0].is_finite()
    # Pairs (timestep's range) are a float array of the cells' shape and 2; a refused cell of a
    # 2-D grid is named by its index there.
    assert pldamp.timestep("dem-verlet", p=1.5, e=[[0.3], [0.5]]).range.shape == (2, 1, 2)
    with pytest.raises(ValueError, match=r"at element \(1, 0\)$"):
        pldamp.calibrate(p=[[1.5], [0.5]], e=[0.3, 0.5])
    with pytest.raises(ValueError, match=r"jobs is a count of threads in \[1, 1024\]"):
        pldamp.calibrate(p=1.5, e=[0.3, 0.5], jobs=2**31)


def test_a_python_float_is_the_very_double_in_every_precision():
    # In quad a float goes in as every digit of its binary value: 1 - 2^-50 was rounded to
    # 16 digits on the way and gave an alpha 1.3 % off.
    x = 1 - 2**-50
    quad = pldamp.calibrate(p=1, e=x, precision="quad").alpha
    assert quad == pldamp.calibrate(p=1, e=decimal.Decimal(x), precision="quad").alpha
    assert pldamp.calibrate(p=1, e=[x], precision="quad").alpha[0] == quad
    for precision in ("long", "quad", "50"):  # a cell goes in as the scalar float does
        cells = pldamp.calibrate(p=1.5, e=[0.5, 0.3, x], precision=precision).alpha
        assert list(cells) == [pldamp.calibrate(p=1.5, e=e, precision=precision).alpha
                               for e in (0.5, 0.3, x)]
    e = pldamp.calibrate(p=1.5, e=0.3, precision="quad").e  # the double 0.29999999999999998889...
    assert abs(e - decimal.Decimal(0.3)) < decimal.Decimal("1e-35") < abs(e - decimal.Decimal("0.3"))


def test_more_threads_than_the_system_gives_are_fewer_threads_not_an_abort(tmp_path):
    # Under a 3 GB address-space limit 400 threads' stacks do not fit: the process aborted.
    import subprocess
    import sys
    program = ("import pldamp, numpy as np; "
               "print(pldamp.calibrate(p=1.5, e=np.linspace(.01, 1, 8192), jobs=400).alpha[-1])")
    done = subprocess.run(["bash", "-c", 'ulimit -v 3000000; exec "$0" -c "$1"', sys.executable,
                           program], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) == pldamp.calibrate(p=1.5, e=1.0).alpha


def test_the_closed_forms_over_arrays_on_threads_are_the_one_thread_loop():
    alpha = np.linspace(0, 2, 20001).reshape(3, 6667)
    one = pldamp.observables(p=1.5, alpha=alpha, v0=1.0, jobs=1)
    every = pldamp.observables(p=1.5, alpha=alpha, v0=1.0)
    assert all(np.array_equal(one[key], every[key], equal_nan=True) for key in one)
    e = np.full((2, 6000), 0.5)
    e[1, 4321] = 2.0  # beyond the first chunk of 4096, on another thread: named where it is
    with pytest.raises(ValueError, match=r"got 2\) at element \(1, 4321\)$"):
        pldamp.observables(p=1.5, e=e, v0=1.0)

