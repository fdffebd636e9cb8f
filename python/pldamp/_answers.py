"""The answers of pldamp's functions: a dict of the command's JSON answer, with its keys also as
attributes and a repr one key per line (docs/python.md "Answers")."""

from __future__ import annotations

from typing import Any

import numpy as np


def _shown(value: Any) -> str:
    """A value on one line: an array of cells by numpy's summary (a few items, its shape)."""
    if isinstance(value, np.ndarray):
        text = np.array2string(value, threshold=8, edgeitems=2, separator=", ",
                               max_line_width=10**6).replace("\n", "")
        return "%s%s %s" % (value.dtype, value.shape, " ".join(text.split()))
    return repr(value)


class Answer(dict):
    """A command's answer: ``answer.delta_max`` is ``answer["delta_max"]``; ``to_dict()`` is the
    plain dict the command's JSON gives, key for key."""

    __slots__ = ()

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError("%s has no %r (it has %s)" % (type(self).__name__, name,
                                                               ", ".join(self))) from None

    def __dir__(self) -> list:
        return sorted(set(super().__dir__()) | set(self))

    def to_dict(self) -> dict:
        """The answer as a plain dict."""
        return dict(self)

    def __repr__(self) -> str:
        width = max((len(key) for key in self), default=0)
        lines = ["    %-*s = %s," % (width, key, _shown(value)) for key, value in self.items()]
        return "%s(\n%s\n)" % (type(self).__name__, "\n".join(lines)) if lines else \
            "%s()" % type(self).__name__

    def _repr_pretty_(self, printer: Any, cycle: bool) -> None:  # IPython and Jupyter
        printer.text(repr(self) if not cycle else "%s(...)" % type(self).__name__)


class Calibration(Answer):
    """The answer of calibrate(): alpha and alpha_eff for a target e (and a code's entry)."""

    __slots__ = ()


class Observables(Answer):
    """The answer of observables(): the contact and every observable of it."""

    __slots__ = ()


class Solution(Answer):
    """The answer of solve(): one collision as a solver integrated it, and the work it took."""

    __slots__ = ()


class TimestepAdvice(Answer):
    """The answer of timestep(): the largest step keeping the observables within a tolerance."""

    __slots__ = ()


class TrajectoryCheck(Answer):
    """The answer of check(): a dumped trajectory's observables against the closed forms."""

    __slots__ = ()
