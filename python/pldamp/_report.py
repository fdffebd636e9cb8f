"""A run's report (report.json) in Python, and its records as a table: one row per cell and
configuration, the columns of report.csv (docs/run.md), as a numpy structured array or a pandas
DataFrame."""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from ._answers import Answer

# The record's own columns, in report.csv's order; then each observable's five.
_RECORD_COLUMNS = ("p", "damping", "alpha_eff", "alpha", "v0", "m", "k", "contact", "onset_phase",
                   "outcome", "failed", "steps", "rhs_evals", "wall_seconds",
                   "wall_seconds_slowest", "cpu_seconds", "cpu_seconds_slowest", "dt")
_PER_OBSERVABLE = (("", "value"), ("_reference", "reference"), ("_error", "error"),
                   ("_abs_error", None), ("_rel_error", "rel_error"))


def _column(values: list) -> np.ndarray:
    """One column as the narrowest array that holds it: bool, int64, float64 (NaN where a record
    has no value: τ of a contact that never returns, an error without a truth) or text."""
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present) and len(present) == len(values):
        return np.array(values, dtype=bool)
    if present and all(isinstance(v, numbers.Integral) and not isinstance(v, bool)
                       for v in present) and len(present) == len(values):
        return np.array(values, dtype=np.int64)
    if all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in present):
        return np.array([np.nan if v is None else float(v) for v in values], dtype=np.float64)
    return np.array(["" if v is None else str(v) for v in values], dtype=str)


class Report(Answer):
    """What run() returns: report.json as a dict (its keys also attributes), and its records as a
    table: table() a numpy structured array, dataframe() a pandas DataFrame."""

    __slots__ = ()

    def _columns(self) -> dict:
        configs = {c["label"]: c for c in self.get("scene", {}).get("configs", [])}
        records = self.get("records", [])
        config_keys = [key for c in configs.values() for key in c if key != "label"]
        config_keys = list(dict.fromkeys(config_keys))  # in order, once
        columns: dict = {}
        for key in config_keys:
            columns[key] = [configs.get(r["config"], {}).get(key) for r in records]
        columns["config"] = [r.get("config") for r in records]  # the label: its one name
        for key in _RECORD_COLUMNS:
            if any(key in r for r in records):
                columns[key] = [r.get(key) for r in records]
        observables = list(dict.fromkeys(o for r in records for o in r.get("value", {})))
        for observable in observables:
            for suffix, part in _PER_OBSERVABLE:
                if part is None:  # |error|, as report.csv gives it
                    columns[observable + suffix] = [
                        None if r.get("error", {}).get(observable) is None
                        else abs(r["error"][observable]) for r in records]
                else:
                    columns[observable + suffix] = [r.get(part, {}).get(observable)
                                                    for r in records]
        return columns

    def table(self) -> np.ndarray:
        """The records as a numpy structured array: one row per cell and configuration, the
        columns of report.csv (solver, precision, rtol, atol, steps_per_contact, config (the
        label: "cvode-bdf rtol=1e-10 end=force"), p, damping, ..., e, e_reference, e_error,
        e_abs_error, e_rel_error, ...): report.json's values, NaN where it has null (a value
        absent, or infinite: report.csv writes τ of a contact that never returns inf)."""
        columns = {name: _column(values) for name, values in self._columns().items()}
        rows = len(self.get("records", []))
        table = np.empty(rows, dtype=[(name, array.dtype) for name, array in columns.items()])
        for name, array in columns.items():
            table[name] = array
        return table

    def dataframe(self) -> Any:
        """The records as a pandas DataFrame (pandas is optional: python3-pandas in Debian)."""
        try:
            import pandas
        except ImportError:
            raise ImportError("dataframe() needs pandas, which this Python does not have "
                              "(Debian: apt install python3-pandas); table() gives the same "
                              "records as a numpy structured array") from None
        return pandas.DataFrame({name: _column(values)
                                 for name, values in self._columns().items()})

    def __repr__(self) -> str:
        run = self.get("run", {})
        return "Report(%r: %d records, %s claims%s)" % (
            self.get("scene", {}).get("name", "?"), len(self.get("records", [])),
            len(self.get("claims", [])),
            ", build %s" % run["build"] if isinstance(run, dict) and "build" in run else "")
