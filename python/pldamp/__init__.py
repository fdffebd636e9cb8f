"""pldamp from Python: the power-law damped contact oscillator

    m δ'' + α √(m k) δ^((p−1)/2) δ' + k δ^p = 0,

the normal contact of discrete-element (DEM) simulations, in closed form and integrated.

Every function mirrors a command of the `pldamp` command line (docs/cli.md) and
takes its flags as keyword arguments, named as the flags with `_` for `-`: ``alpha_eff=0.2`` is
``--alpha-eff 0.2``. calibrate, observables, solve and timestep ask the library the command asks,
in-process and without its text; check and run run the command itself. Either way the answer is
the command's JSON answer, as a dict whose keys are also attributes (pldamp.Answer), and its
values, precisions and refusals are the command line's, word for word:

    >>> import pldamp
    >>> pldamp.observables(p=1.5, e=0.5, v0=1.0).delta_max
    0.8609907729949561

Numbers go in as the command line reads them: a float by its shortest round-trip digits (the very
double), an int, a str or a decimal.Decimal as written (``e="0.3"`` is 0.3 in the precision asked,
not the double nearest 0.3). Answers in ``precision="double"`` are floats; in ``"long"``, ``"quad"``
and ``"50"`` every number is a decimal.Decimal with all the digits the command printed, never a
rounded float.

``observables`` with an array for any of p, e, alpha, alpha_eff, v0, m, k (numpy broadcasting)
evaluates the closed forms element-wise in C++ in double, the GIL released, and returns arrays.

Bad input raises ValueError with the command line's one line; a claim or tolerance that fails
(exit 1) is an answer, not an exception, except ``run(..., strict=True)``, which raises
RuntimeError. docs/python.md is the guide.
"""

from __future__ import annotations

import contextlib
import decimal
import difflib
import json
import math
import numbers
import os
import re
import tempfile
from typing import Any, Iterable, Optional

try:
    import numpy as np
except ImportError as missing:  # a Python other than the one the module was built for
    import sys as _sys

    raise ImportError(
        "pldamp needs numpy, which this Python (%s) does not have: run the Python the build "
        "found (Debian's /usr/bin/python3, with python3-numpy), or install numpy into this one"
        % _sys.executable
    ) from missing

from . import _pldamp
from ._answers import (Answer, Calibration, Observables, Solution, TimestepAdvice,
                       TrajectoryCheck)
from ._report import Report

__all__ = ["calibrate", "observables", "solve", "timestep", "trajectory", "check", "run", "cli",
           "Answer", "Calibration", "Observables", "Solution", "TimestepAdvice",
           "TrajectoryCheck", "Report"]

# The observables a vectorised `observables` computes by default, in this order.
ARRAY_OBSERVABLES = ("e", "delta_max", "t_peak", "tau", "tau0", "energy_load", "energy_unload",
                     "spring_force_max", "normal_force_max", "t_normal_force_max", "dt_crit",
                     "dt_tangent", "e_cap", "t_cut")


def _no_nul(name: str, text: str) -> str:
    """`text` as an argument: a NUL would end it where C reads it (p='1.5\\x00garbage' was 1.5),
    and a lone surrogate has no UTF-8 (pybind11 raised four lines of TypeError)."""
    if "\x00" in text:
        raise ValueError("%s holds a NUL character (got %r)" % (name, text))
    if text.isascii():
        return text
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError("%s is not text UTF-8 can hold (got %r)" % (name, text)) from None
    return text


def _float_text(value: float, exact: bool) -> str:
    """A float as the command reads it: its shortest round-trip digits in double (the same
    double), every digit of its binary value in a wider precision (where "0.3" would be the
    float128 nearest 0.3, not the double the caller gave)."""
    if not exact or not math.isfinite(value):
        return repr(value)
    return str(decimal.Decimal(value))  # exact: a double is a finite binary fraction


def _text(name: str, value: Any, exact: bool = False) -> str:
    """A value as the command line reads it (`exact`: for a precision wider than double)."""
    kind = type(value)  # the common cases first, by exact type: a call costs a few µs in all
    if kind is float:
        return _float_text(value, exact)
    if kind is int:
        return str(value)
    if kind is str:
        return _no_nul(name, value)
    if isinstance(value, bool):
        raise TypeError("%s takes a number or text, not a bool" % name)
    if isinstance(value, (float, np.floating)):
        return _float_text(float(value), exact)
    if isinstance(value, (numbers.Integral, decimal.Decimal, str)):
        return _no_nul(name, str(value))
    if isinstance(value, (list, tuple)) or (isinstance(value, np.ndarray) and value.ndim == 1):
        return ",".join(_text(name, item, exact) for item in value)
    raise TypeError("%s takes a number, text or a list of them (got %s)" % (name,
                                                                           type(value).__name__))


# The commands' flags that take no value: True sets them, False leaves them out. Any other
# keyword given a bool is refused (e=True once became a bare "--e", and m=False dropped m).
SWITCHES = {"limit_damping", "strict", "verbose", "allow_scene_change"}
_SWITCH_SET = frozenset(SWITCHES)


# Words a newcomer reaches for, and the keyword that means it.
_MEANT = {"mass": "m", "stiffness": "k", "velocity": "v0", "speed": "v0", "restitution": "e",
          "exponent": "p", "damping": "alpha"}
_KEYWORDS: dict = {}


def _keywords(command: str) -> dict:
    """The keywords `command` takes, as Python spells them, each with its flag: its --help's
    options, read once."""
    if command not in _KEYWORDS:
        _, out, _ = _pldamp.cli([command, "--help"])
        names = re.findall(r"^\s+(?:-\w,)?--([a-z0-9-]+)", out, flags=re.MULTILINE)
        _KEYWORDS[command] = {n.replace("-", "_"): "--" + n for n in names
                              if n not in ("help", "json")}
    return _KEYWORDS[command]


def _refuse_unknown(command: str, name: str) -> None:
    """An unknown keyword is Python's TypeError, naming it and the nearest one taken (the command
    line's 'unknown argument (got --mass 5.0)' named neither)."""
    known = _keywords(command)
    if name in known:
        return
    meant = [_MEANT[word] for word in difflib.get_close_matches(name, list(_MEANT), n=1,
                                                                cutoff=0.75)]
    near = [word for word in meant if word in known] or \
        difflib.get_close_matches(name, list(known), n=1, cutoff=0.5)
    raise TypeError("%s() got an unexpected keyword argument %r%s" % (
        command, name, "; did you mean %r?" % near[0] if near else
        " (it takes %s)" % ", ".join(known)))


def _arguments(command: str, positional: Iterable[str], options: dict) -> list:
    args = [command, *(_no_nul(command, str(item)) for item in positional)]
    for name, value in options.items():
        _refuse_unknown(command, name)
        flag = "--" + name.replace("_", "-")
        if name in SWITCHES:
            if not isinstance(value, bool) and value is not None:
                raise TypeError("%s is a switch: True or False (got %r)" % (name, value))
            if value:
                args.append(flag)
            continue
        if value is None:
            continue
        args += [flag, _text(name, value)]
    return args


def cli(*args: str, progress: bool = False) -> tuple:
    """`pldamp ARGS...` in-process: (exit code, standard output, standard error).

    progress=True shows a run's progress on sys.stderr as it goes (none by default)."""
    if not isinstance(progress, bool):
        raise TypeError("progress is a switch: True or False (got %r)" % (progress,))
    return _pldamp.cli([_no_nul("an argument", str(a)) for a in args], progress)


def _answer(command: str, positional: Iterable[str] = (), json_flag: bool = True,
            progress: bool = False, **options) -> tuple:
    args = _arguments(command, positional, options)
    if json_flag:
        args.append("--json")
    code, out, err = _pldamp.cli(args, progress)
    if code == 130:  # SIGINT (Ctrl-C) stopped the run, as the command exits 128 + 2
        raise KeyboardInterrupt(err.strip().removeprefix("error: "))
    if code == 2:
        raise ValueError(err.strip().removeprefix("error: "))
    if code not in (0, 1):
        raise RuntimeError(err.strip().removeprefix("error: "))
    return code, out, err


def _parse(out: str, precision: Optional[str]) -> dict:
    exact = precision not in (None, "double")
    return json.loads(out, parse_float=decimal.Decimal if exact else float)


def _call(command: str, positional: Iterable[str] = (), **options) -> dict:
    _, out, _ = _answer(command, positional, **options)
    return _parse(out, options.get("precision"))


# What is taken element-wise, as cells.
_ARRAYS = (np.ndarray, list, tuple)

# The options a question takes as arrays of cells (a list for one of these is cells, as numpy
# broadcasts them; materials' lists stay one value per body).
_CELL_OPTIONS = {
    "calibrate": ("p", "e"),
    "solve": ("p", "e", "alpha", "alpha_eff", "v0", "m", "k", "rtol", "atol", "dt",
              "steps_per_contact", "onset_phase"),
    "timestep": ("p", "e", "alpha", "alpha_eff", "v0", "m", "k", "tolerance"),
}
_CELL_SETS = {command: frozenset(names) for command, names in _CELL_OPTIONS.items()}
_NO_CELLS: frozenset = frozenset()


def _ask(kind: type, command: str, options: dict) -> Answer:
    """`pldamp COMMAND --json` asked of the library directly (ask/ask.hpp): the options (a dict
    the caller made for this call: `jobs` is taken out of it) by their flags, the answer as the
    command's JSON reads in Python (precision other than double: every float a decimal.Decimal).
    An array for an option of _CELL_OPTIONS asks at every cell."""
    jobs = options.pop("jobs", None)
    exact = options.get("precision") not in (None, "double")
    takes_cells = _CELL_SETS.get(command, _NO_CELLS)
    if jobs is None:  # the keywords read in C++ (questions.cpp ask_keywords), _typed_one's rules
        answer = _pldamp.ask_keywords(command, options, _KEYWORDS.get(command) or
                                      _keywords(command), _SWITCH_SET, takes_cells, _typed_one,
                                      _refuse_unknown, exact)
        if answer is not None:
            return kind(answer)
    cells = [name for name, value in options.items()
             if isinstance(value, _ARRAYS) and name in takes_cells]
    if cells:
        return _ask_cells(kind, command, cells, jobs, exact, options)
    raise ValueError("jobs goes with arrays of cells (got jobs=%r)" % (jobs,))


@contextlib.contextmanager
def _cells_named_in(shape: tuple):
    """A refusal "... at element 7" names the cell by its index in the arrays' shape: (1, 3)."""
    try:
        yield
    except ValueError as error:
        found = re.fullmatch(r"(.*) at element (\d+)", str(error), re.S)
        if found is None or len(shape) < 2:
            raise
        index = tuple(int(i) for i in np.unravel_index(int(found.group(2)), shape))
        raise ValueError("%s at element %s" % (found.group(1), index)) from None


def _jobs(jobs: Any) -> int:
    """The threads of an array call: 1 to 1024, as run's --jobs; 0 for every core (None)."""
    if jobs is None:
        return 0
    if isinstance(jobs, bool) or not isinstance(jobs, numbers.Integral) or not 1 <= jobs <= 1024:
        raise ValueError("jobs is a count of threads in [1, 1024], as run's --jobs (got %r)"
                         % (jobs,))
    return int(jobs)


def _ask_cells(kind: type, command: str, cells: list, jobs: Optional[int], exact: bool,
               options: dict) -> Answer:
    """The question at every cell of the arrays (broadcast as numpy does), on the library's
    threads with the GIL released: each cell's answer is the scalar call's, and each key an array
    of the cells' shape (a text every cell shares: one str)."""
    threads = _jobs(jobs)
    arrays = np.broadcast_arrays(*[_numbers(name, options[name]) for name in cells])
    shape = arrays[0].shape
    known = _keywords(command)
    varying = [(known[name], np.ascontiguousarray(array, dtype=np.float64).ravel())
               for name, array in zip(cells, arrays)]
    fixed = _typed(command, {name: value for name, value in options.items()
                             if name not in cells}, exact)
    with _cells_named_in(shape):
        answer = _pldamp.ask_many(command, fixed, varying, exact, threads)
    return kind((key, value.reshape(shape + value.shape[1:]) if isinstance(value, np.ndarray)
                 else value) for key, value in answer.items())


def _typed_one(name: str, value: Any, exact: bool = False) -> Optional[str]:
    """A keyword's value as the command reads it: a switch's "" (None when False), or _text."""
    if name in SWITCHES:
        if not isinstance(value, bool):
            raise TypeError("%s is a switch: True or False (got %r)" % (name, value))
        return "" if value else None
    return _text(name, value, exact)


def _typed(command: str, options: dict, exact: bool = False) -> list:
    """The options as (flag, text) pairs; an unknown keyword refused by name."""
    known = _keywords(command)
    typed = []
    for name, value in options.items():
        flag = known.get(name)
        if flag is None:
            _refuse_unknown(command, name)
        if value is not None:
            text = _typed_one(name, value, exact)
            if text is not None:
                typed.append((flag, text))
    return typed


def calibrate(p: Any = None, e: Any = None, **options) -> Calibration:
    """α for a target restitution e, as `pldamp calibrate`.

    calibrate(p=1.5, e=0.5) gives α and α_eff at the overlap end; end="force" for a code that
    caps the force; code="lammps-tsuji" (and the other codes of `calibrate --help`) for what a DEM
    code sets and really gives; a velocity-dependent code takes v0, m, k, speeds, reff or a
    contact from materials (geometry, radius, young, poisson, density). precision="quad" answers
    in decimal.Decimal.

    With an array for p or e (broadcast as numpy does), every cell is calibrated as the scalar
    call calibrates it, on `jobs` threads (default: every core), and each number of the answer is
    an array of the cells' shape.
    """
    return _ask(Calibration, "calibrate", {"p": p, "e": e, **options})


def observables(p: Any = None, e: Any = None, alpha: Any = None, alpha_eff: Any = None,
                v0: Any = None, m: Any = None, k: Any = None, end: Optional[str] = None,
                precision: Optional[str] = None, want: Optional[Iterable[str]] = None,
                **options) -> Observables:
    """Every closed-form observable of a contact, as `pldamp observables`.

    Give p, one of e, alpha and alpha_eff, and v0 (m and k default to 1), or a contact from
    materials: geometry="sphere-sphere" or "sphere-wall", radius, young, poisson, density (a
    number, or a list of one per body), p then being 3/2. damping_exponent=β answers from the
    float128 reference solve. The dict is the command's JSON answer (units with materials).

    With an array for any of p, e, alpha, alpha_eff, v0, m, k (broadcast as numpy does), the
    closed forms are evaluated element-wise in C++ in double with the GIL released, on `jobs`
    threads (default: every core), and the dict
    holds arrays of that shape: alpha, alpha_eff and each observable of `want` (default all of
    ARRAY_OBSERVABLES; inf for τ of a contact that never returns, NaN where an observable does
    not exist).
    """
    for value in (p, e, alpha, alpha_eff, v0, m, k):
        if isinstance(value, _ARRAYS):
            scalars = dict(p=p, e=e, alpha=alpha, alpha_eff=alpha_eff, v0=v0, m=m, k=k)
            return _observables_arrays(scalars, end or "overlap", precision, _wanted(want),
                                       options)
    wanted = _wanted(want) if want is not None else None
    answer = _ask(Observables, "observables", {"p": p, "e": e, "alpha": alpha,
                                               "alpha_eff": alpha_eff, "v0": v0, "m": m, "k": k,
                                               "end": end, "precision": precision, **options})
    if wanted is not None:
        answer = Observables((key, value) for key, value in answer.items()
                             if key in wanted or key not in ARRAY_OBSERVABLES)
    return answer


def _wanted(want: Any) -> list:
    """The observables `want` names, checked: a name or a list of names of ARRAY_OBSERVABLES, each
    once (want="tau" was read as the letters t, a, u, and want=["taux"] dropped every one)."""
    if want is None:
        return list(ARRAY_OBSERVABLES)
    names = [want] if isinstance(want, str) else list(want)
    for name in names:
        if not isinstance(name, str) or name not in ARRAY_OBSERVABLES:
            raise ValueError("unknown observable in want, expected a list of %s (got %s)"
                             % (",".join(ARRAY_OBSERVABLES), name))
        if names.count(name) > 1:
            raise ValueError("want names %s twice" % name)
    if not names:
        raise ValueError("want names no observable (got an empty list)")
    return names


def _numbers(name: str, value: Any) -> np.ndarray:
    """An array of numbers as float64: a bool (e=True was 1.0), a complex number (its imaginary
    part was dropped with a warning) or an element that is not a number is refused by name."""
    if isinstance(value, np.ma.MaskedArray):
        raise TypeError("%s takes a plain array, not a masked one: fill or drop its masked "
                        "elements first" % name)
    array = value if isinstance(value, np.ndarray) else np.asarray(value, dtype=object)
    if array.dtype.kind == "b":
        raise TypeError("%s takes numbers, not bools (got an array of bool)" % name)
    if array.dtype.kind == "c":
        raise TypeError("%s takes real numbers, not complex ones (got an array of complex)"
                        % name)
    if array.dtype.kind not in "iufO":  # times, dates, text, bytes, records
        raise TypeError("%s takes numbers (got an array of %s)" % (name, array.dtype))
    if array.dtype.kind == "O":  # element by element, as the caller wrote them
        for index, item in enumerate(array.ravel()):
            if isinstance(item, (bool, np.bool_)):
                raise TypeError("%s takes numbers, not bools (got %r at index %d)"
                                % (name, item, index))
            if isinstance(item, (complex, np.complexfloating)):
                raise TypeError("%s takes real numbers, not complex ones (got %r at index %d)"
                                % (name, item, index))
            if not isinstance(item, numbers.Real) or isinstance(item, np.timedelta64):
                raise ValueError("%s holds %r at index %d: not a number" % (name, item, index))
    try:
        return np.asarray(array, dtype=np.float64)
    except OverflowError:  # an int beyond a double's range (10**400)
        raise ValueError("%s holds a number beyond what a double holds" % name) from None


def _scalar(name: str, value: Any) -> float:
    """One real number as a float, refused as _numbers refuses an element (a Decimal is taken)."""
    if isinstance(value, decimal.Decimal):
        return float(value)
    array = _numbers(name, value)
    if array.ndim != 0:
        raise TypeError("%s takes one number (got an array of shape %s)" % (name, array.shape))
    return float(array)


def _observables_arrays(scalars: dict, end: str, precision: Optional[str],
                        want: list, options: dict) -> Observables:
    if precision not in (None, "double"):
        raise ValueError("observables over arrays runs in double; call it per element for "
                         "precision %s (got precision %s)" % (precision, precision))
    jobs = _jobs(options.pop("jobs", None))
    for name in options:  # a keyword observables does not take at all: as the scalar call says
        _refuse_unknown("observables", name)
    if options:
        raise ValueError("observables over arrays takes p, e|alpha|alpha_eff, v0, m, k, end and "
                         "want (got %s)" % ", ".join(sorted(options)))
    end = _text("end", end)  # a str, as the command line reads it (end=5 is "5")
    given = [name for name in ("e", "alpha", "alpha_eff") if scalars[name] is not None]
    if len(given) != 1:
        raise ValueError("give exactly one of e, alpha, alpha_eff (got %d)" % len(given))
    for name in ("p", "v0"):
        if scalars[name] is None:
            raise ValueError("%s is required (got nothing)" % name)
    kind = given[0]
    values = [scalars["p"], scalars[kind], scalars["v0"],
              1.0 if scalars["m"] is None else scalars["m"],
              1.0 if scalars["k"] is None else scalars["k"]]
    names = ["p", kind, "v0", "m", "k"]
    arrays = np.broadcast_arrays(*[_numbers(n, v) for n, v in zip(names, values)])
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(a).ravel() for a in arrays]
    with _cells_named_in(shape):
        result = _pldamp.observables_double(flat[0], kind, flat[1], flat[2], flat[3], flat[4],
                                            end, want, jobs)
    return Observables((key, value.reshape(shape)) for key, value in result.items())


def solve(solver: str, **options) -> Solution:
    """Integrate one collision with a registered solver, as `pldamp solve`.

    solve("cvode-bdf", p=1.5, e=0.5, v0=1.0, rtol=1e-10) returns the outcome, the measured e,
    delta_max, t_peak, tau, energies and peak force, steps, rhs_evals and wall_seconds; every flag
    of `pldamp solve --help` is a keyword (dt, steps_per_contact, onset_phase, sample_times, ...).

    With arrays for any of p, e, alpha, alpha_eff, v0, m, k, rtol, atol, dt, steps_per_contact and
    onset_phase (broadcast as numpy does), every cell is solved as the scalar call solves it, on
    `jobs` threads (default: every core) with the GIL released, and each number of the answer is
    an array of the cells' shape (inf where the scalar answer has None, JSON's null: τ of a contact
    that did not end; NaN where a cell has no such key); the outcome is one str when every cell
    shares it, else an array of them.
    """
    return _ask(Solution, "solve", {"solver": solver, **options})


def timestep(scheme: str, **options) -> TimestepAdvice:
    """The largest Δt keeping e, δ_max and τ within a tolerance at every onset phase, as
    `pldamp timestep` (scheme "dem-verlet", ...; tolerance=0.01; tau_as="first-step-out",
    "steps-in-contact" or "crossing": τ as the user's code counts it; materials add the step as a
    fraction of the Hertz and Rayleigh times).

    With arrays for any of p, e, alpha, alpha_eff, v0, m, k and tolerance, one table in one call:
    every cell answered as the scalar call answers it, on `jobs` threads, each number an array."""
    return _ask(TimestepAdvice, "timestep", {"scheme": scheme, **options})


def trajectory(t: Any, p: Any = None, e: Any = None, alpha: Any = None, alpha_eff: Any = None,
               v0: Any = 1.0, m: Any = 1.0, k: Any = 1.0, end: str = "overlap") -> tuple:
    """δ(t) and v(t) from the closed form (docs/MATH.md §3 "Time-domain solution"), in double, at
    the times `t` (an array; any t a double holds, 5e-324 to 1.8e308, and ±inf), free flight at
    v0 before the contact (t < 0), and after it the free flight at the exit speed from where it
    ended:

    end="overlap": the contact ends at τ with δ = 0 and v = −e v0 (a contact with α_eff ≥ 1
    never ends: δ decays to 0, as t^(−2/(p−1)) for p > 1);
    end="force": it ends at t_cut, where the total force k δ^p + α√(mk) δ^((p−1)/2) δ' reaches 0
    (MATH.md §4), and δ = δ(t_cut) − e_cap v0 (t − t_cut), v = −e_cap v0 after it; `e` is then the
    e_cap the contact gives (calibrated at that end), as observables(..., end="force") has it.

    Returns two numpy arrays of t's shape."""
    given = [(name, value) for name, value in (("e", e), ("alpha", alpha),
                                                ("alpha_eff", alpha_eff)) if value is not None]
    if len(given) != 1:
        raise ValueError("give exactly one of e, alpha, alpha_eff (got %d)" % len(given))
    if p is None:
        raise ValueError("p is required (got nothing)")
    times = _numbers("t", t)
    delta, v = _pldamp.trajectory_double(_scalar("p", p), given[0][0],
                                         _scalar(given[0][0], given[0][1]), _scalar("v0", v0),
                                         _scalar("m", m), _scalar("k", k), _text("end", end),
                                         np.ascontiguousarray(times).ravel())
    return delta.reshape(times.shape), v.reshape(times.shape)


def check(t: Any, delta: Any, v: Any = None, F: Any = None, **options) -> TrajectoryCheck:
    """A code's dumped trajectory against the closed forms, as `pldamp check`: t and delta (and v,
    F when the code dumps them) as arrays, the contact as keywords (p, e|alpha|alpha_eff, v0, m,
    k, or materials; end, tolerance). Returns the command's answer: each observable's value,
    truth, error and verdict, and `passed` under a tolerance."""
    columns = {"t": t, "delta": delta}
    if v is not None:
        columns["v"] = v
    if F is not None:
        columns["F"] = F
    arrays = {name: _numbers(name, c) for name, c in columns.items()}
    shapes = {name: a.shape for name, a in arrays.items()}
    if any(len(shape) != 1 for shape in shapes.values()) or len(set(shapes.values())) != 1:
        raise ValueError("t, delta, v and F are 1-D arrays of one length (got shapes %s)" %
                         ", ".join("%s %s" % item for item in shapes.items()))
    data = np.column_stack(list(arrays.values()))
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "trajectory.csv")
        np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="",
                   fmt="%.17g")
        try:
            answer = TrajectoryCheck(_call("check", [path], **options))
            answer["trajectory"] = "arrays " + ", ".join(columns)  # not the scratch file's path
            return answer
        except ValueError as error:
            # "FILE:LINE: what" names the scratch file: say the index in the arrays instead.
            # The scratch file's name means nothing to the caller: its line 1 is the header,
            # line n >= 2 the arrays' index n - 2.
            match = re.match(re.escape(path) + r"(?::(\d+))?: (.*)", str(error), re.S)
            if match is None:
                raise
            if match.group(1) is None or int(match.group(1)) < 2:
                raise ValueError("the arrays: %s" % match.group(2)) from None
            raise ValueError("at index %d of the arrays: %s" % (int(match.group(1)) - 2,
                                                                 match.group(2))) from None


def run(scene: str, out: Optional[str] = None, strict: bool = False, progress: bool = False,
        **options) -> Report:
    """Run a scene, as `pldamp run SCENE`, and return its report.json as a dict (a Report: its
    records as a table by report.table(), a numpy structured array, or report.dataframe(), a
    pandas DataFrame).

    out: the folder for the report files (report.json, .csv, .md, .html); a temporary one that is
    removed when None. strict=True raises RuntimeError when a claim's verdict is not the one
    expected. progress=True writes the run's progress to sys.stderr as it goes (a line every 5 s
    with the time left; none by default). jobs, max_steps, max_seconds, max_runs as the
    command's flags.
    """
    if not isinstance(progress, bool):
        raise TypeError("progress is a switch: True or False (got %r)" % (progress,))
    if options.get("shard") is not None:
        raise ValueError("run() returns a report and a shard writes none: run the shards with "
                         "cli('run', scene, '--shard', 'K/N', '--out', DIR) and merge their "
                         "folders with cli('merge', DIR_1, ..., '--out', OUT) (got shard=%r)"
                         % (options["shard"],))

    def run_into(folder: str) -> Report:
        code, _, err = _answer("run", [os.fspath(scene)], json_flag=False, progress=progress,
                               out=folder, strict=strict, **options)
        if code == 1:
            raise RuntimeError(err.strip())
        path = os.path.join(folder, "report.json")
        if not os.path.exists(path):
            raise ValueError("the scene writes no report.json, which run() returns: add \"json\" "
                             "to its [report] formats (got %s)" % os.fspath(scene))
        with open(path, encoding="utf-8") as report:
            return Report(json.load(report))

    if out is not None:
        return run_into(os.fspath(out))
    with tempfile.TemporaryDirectory() as folder:
        return run_into(folder)
