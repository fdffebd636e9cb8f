"""calibrate, observables, solve and timestep ask the library directly (ask/ask.hpp); the command
line asks it through its text. Both doors must give one answer, bit for bit and type for type, and
one refusal, word for word (issue 51).

    PYTHONPATH=build/python PLDAMP_DATA_DIR=data python3 -m pytest python/tests
"""

import decimal
import itertools
import json

import numpy as np
import pytest

import pldamp

MATERIALS = dict(geometry="sphere-sphere", radius="0.01", young="7e10", poisson="0.3",
                 density="2700")


def by_command_line(command, positional=(), **options):
    """The command's --json answer read as the module reads it: floats as float in double,
    decimal.Decimal in every wider precision."""
    args = [command, *positional]
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if value is True:
            args.append(flag)
        elif value is not None:
            args += [flag, value if isinstance(value, str) else repr(value)]
    code, out, err = pldamp.cli(*args, "--json")
    if code != 0:
        raise ValueError(err.strip().removeprefix("error: "))
    exact = options.get("precision") not in (None, "double")
    return json.loads(out, parse_float=decimal.Decimal if exact else float)


def identical(a, b):
    """Equal in value and in type, all the way down (1 and 1.0 differ; so do 0.0 and -0.0)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return list(a) == list(b) and all(identical(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(identical(x, y) for x, y in zip(a, b))
    if isinstance(a, float):
        return a.hex() == b.hex()
    if isinstance(a, decimal.Decimal):
        return str(a) == str(b)
    return a == b


def same_both_ways(command, positional, function, **options):
    direct = function(*positional, **options)
    assert isinstance(direct, pldamp.Answer)
    wanted = by_command_line(command, () if command != "solve" and command != "timestep" else (),
                             **({"solver": positional[0]} if command == "solve" else
                                {"scheme": positional[0]} if command == "timestep" else {}),
                             **options)
    assert identical(direct.to_dict(), wanted), (command, options)
    return direct


PRECISIONS = ["double", "long", "quad", "50"]


@pytest.mark.parametrize("precision", PRECISIONS)
def test_observables_and_calibrate_over_a_grid(precision):
    for p, damping, end in itertools.product(["1", "1.5", "2.5"],
                                             [("e", "0.5"), ("e", "1"), ("alpha", "0.3"),
                                              ("alpha_eff", "1.5"), ("alpha_eff", "0")],
                                             ["overlap", "force"]):
        options = {damping[0]: damping[1], "p": p, "end": end, "precision": precision}
        same_both_ways("observables", (), pldamp.observables, v0="0.42", m="3", k="2e3",
                       **options)
        if damping[0] == "e":
            same_both_ways("calibrate", (), pldamp.calibrate, p=p, e=damping[1], end=end,
                           precision=precision)


def test_floats_go_in_as_the_same_double_both_ways():
    for e in [0.1, 0.5, 1 / 3, 0.999999999999]:
        same_both_ways("observables", (), pldamp.observables, p=1.5, e=e, v0=0.42)


def test_a_float_keyword_goes_in_as_python_writes_it():
    # The keywords' floats are written in C++ (questions.cpp python_repr), as repr writes them:
    # an integer option's refusal quotes the text it read. Random bit patterns, and the edges of
    # the fixed notation (exponents -5 to -4, 15 to 16), signs, subnormals, whole numbers.
    random = np.random.default_rng(20261129)
    bits = random.integers(0, 2**63 - 1, size=4000, dtype=np.int64)
    values = [float(x) for x in bits.view(np.float64) if np.isfinite(x)]
    values += [-value for value in values[:1000]]
    values += [1e-5, 1.5e-5, 9.99e-5, 1e-4, 0.00012345, 1e15 + 0.5, 999999999999999.9, 1e16,
               1.5e16, 123456.789, -0.0025, 5e-324, 2.2250738585072014e-308, 0.1, 0.3, 2.5,
               -7.75e-7, 1.7976931348623157e308]
    for value in values:
        if value == int(value) and abs(value) < 2**63:
            continue  # a whole number is an integer option's value, not a refusal
        with pytest.raises(ValueError) as refused:
            pldamp.solve("dem-verlet", p=1.5, e=0.5, v0=1, steps_per_contact=value)
        assert str(refused.value) == "--steps-per-contact is not an integer (got %r)" % value


def test_whole_numbers_are_int_or_float_as_the_json_writes_them():
    # "99999" is an int, "1e+05" a float: the answer's m and k either side of where the shortest
    # digits turn to an exponent, and a whole number past 2^53.
    for m, k in [("99999", "1e5"), ("1e6", "12345678"), ("123456", "2e16")]:
        same_both_ways("observables", (), pldamp.observables, p=1.5, e=0.5, v0=1, m=m, k=k)
    assert type(pldamp.observables(p=1.5, e=0.5, v0=1, m="99999").m) is int
    assert type(pldamp.observables(p=1.5, e=0.5, v0=1, m="1e5").m) is float


def test_codes_materials_and_other_damping_exponents():
    same_both_ways("calibrate", (), pldamp.calibrate, p="1.5", e="0.5", code="lammps-tsuji",
                   limit_damping=True)
    same_both_ways("calibrate", (), pldamp.calibrate, p="1.5", e="0.7", code="yade-hertz-mindlin",
                   precision="quad")
    same_both_ways("calibrate", (), pldamp.calibrate, e="0.5", code="lammps-viscoelastic",
                   v0="1", speeds="0.5,2", **MATERIALS)
    # LAMMPS divides its entry by sqrt(Reff): reff changes the entry, and only the entry.
    small = same_both_ways("calibrate", (), pldamp.calibrate, p="1.5", e="0.5",
                           code="lammps-viscoelastic", v0="2", reff="0.25")
    large = same_both_ways("calibrate", (), pldamp.calibrate, p="1.5", e="0.5",
                           code="lammps-viscoelastic", v0="2", reff="1")
    assert small.entry == 2 * large.entry and small.alpha == large.alpha
    same_both_ways("observables", (), pldamp.observables, e="0.5", v0="1", end="force",
                   **MATERIALS)
    same_both_ways("observables", (), pldamp.observables, p="1.5", e="0.5", v0="1",
                   damping_exponent="0.5")


@pytest.mark.parametrize("solver", ["taylor", "cvode-bdf", "dem-verlet", "odeint-rkf78"])
def test_solve_both_ways(solver):
    options = dict(p="1.5", e="0.61", v0="0.42", repeats="1")
    if solver == "dem-verlet":
        options.update(dt="0.01", onset_phase="0.25", sample_times="0.5,1", tau_as="crossing")
    direct = pldamp.solve(solver, **options)
    cli = by_command_line("solve", solver=solver, **options)
    # wall_seconds is the one value a second solve does not repeat.
    assert identical({k: v for k, v in direct.items() if k != "wall_seconds"},
                     {k: v for k, v in cli.items() if k != "wall_seconds"})
    assert isinstance(direct.wall_seconds, float) and direct.wall_seconds > 0


def test_timestep_both_ways():
    same_both_ways("timestep", ("dem-verlet",), pldamp.timestep, p="1.5", e="0.5",
                   code="lammps-tsuji")
    same_both_ways("timestep", ("dem-verlet",), pldamp.timestep, e="0.5", v0="1",
                   observables="e,normal_force_max", **MATERIALS)


REFUSED = [
    ("observables", dict(p="1.5", e="0.5")),                      # --v0 is required
    ("observables", dict(p="1.5", e="0.5", alpha="1", v0="1")),   # two dampings
    ("observables", dict(p="0.5", e="0.5", v0="1")),
    ("observables", dict(p="1.5", e="2", v0="1")),
    ("observables", dict(p="1.5", e="x", v0="1")),
    ("observables", dict(e="0.5", v0="1", m="2", **MATERIALS)),
    ("observables", dict(e="0.5", v0="1", radius="0.01")),
    ("observables", dict(p="1.5", e="0.5", v0="1", precision="octuple")),
    ("observables", dict(p="1.5", e="0.5", v0="1", damping_exponent="0.5", precision="50")),
    ("calibrate", dict(p="1.5")),
    ("calibrate", dict(p="1.5", e="0.5", v0="2")),
    ("calibrate", dict(p="1.5", e="0.5", limit_damping=True)),
    ("calibrate", dict(p="1.5", e="0.5", code="nobody")),
    ("calibrate", dict(p="1.5", e="0.5", code="lammps-viscoelastic", precision="quad")),
    ("solve", dict(p="1.5", e="0.5")),                            # --v0, then --solver
    ("solve", dict(p="1.5", e="0.5", v0="1")),
    ("solve", dict(solver="taylor", p="1.5", e="0.5", v0="1", dt="0.1")),
    ("solve", dict(solver="dem-verlet", p="1.5", e="0.5", v0="1", rtol="1e-3")),
    ("solve", dict(solver="taylor", p="1.5", e="0.5", v0="1", sample_times="1,1")),
    ("solve", dict(solver="taylor", p="1.5", e="0.5", v0="1", repeats="0")),
    ("timestep", dict(p="1.5", e="0.5")),                         # --scheme is required
    ("timestep", dict(scheme="taylor", p="1.5", e="0.5")),
    ("timestep", dict(scheme="dem-verlet", p="1.5", e="0.5", code="lammps-tsuji", end="force")),
    ("timestep", dict(scheme="dem-verlet", e="0.5", **MATERIALS)),
    ("timestep", dict(scheme="dem-verlet", p="1.5", alpha_eff="1", tolerance="2")),
]


@pytest.mark.parametrize("command,options", REFUSED)
def test_refusals_word_for_word(command, options):
    with pytest.raises(ValueError) as cli:
        by_command_line(command, **options)
    function = getattr(pldamp, command)
    with pytest.raises(ValueError) as direct:
        if command in ("solve", "timestep"):
            first = "solver" if command == "solve" else "scheme"
            function(options.pop(first, None), **options)
        else:
            function(**options)
    assert str(direct.value) == str(cli.value)


def test_answers_read_as_attributes_and_print_one_key_a_line():
    answer = pldamp.observables(p=1.5, e=0.5, v0=1.0)
    assert isinstance(answer, pldamp.Observables) and answer.delta_max == answer["delta_max"]
    assert type(answer.to_dict()) is dict and answer.to_dict() == answer
    shown = repr(answer)
    assert shown.startswith("Observables(\n") and "    delta_max " in shown
    assert shown.count("\n") == len(answer) + 1
    with pytest.raises(AttributeError, match="has no 'delta_min'"):
        answer.delta_min  # noqa: B018
    assert isinstance(pldamp.calibrate(p=1.5, e=0.5), pldamp.Calibration)
    cells = repr(pldamp.calibrate(p=1.5, e=[[0.5, 0.6]]))
    assert "    alpha     = float64(1, 2) [[0.48176926, 0.35887336]]," in cells and "precision = 'double'" in cells
    assert isinstance(pldamp.solve("taylor", p=1.5, e=0.5, v0=1), pldamp.Solution)
