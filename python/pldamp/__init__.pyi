# Type stubs of the module pldamp (docs/python.md).
from decimal import Decimal
from os import PathLike
from typing import Any, Iterable, Literal, Optional, Union

import numpy as np
import numpy.typing as npt

Number = Union[float, int, str, Decimal]
ArrayLike = Union[Number, npt.ArrayLike]

ARRAY_OBSERVABLES: tuple[str, ...]

class Answer(dict[str, Any]):
    """A command's answer: a dict of its JSON answer whose keys are also attributes."""
    def __getattr__(self, name: str) -> Any: ...
    def to_dict(self) -> dict[str, Any]: ...

class Calibration(Answer):
    alpha: Any
    alpha_eff: Any

class Observables(Answer):
    e: Any
    delta_max: Any
    t_peak: Any
    tau: Any

class Solution(Answer):
    outcome: Any
    e: Any
    steps: Any
    rhs_evals: Any
    wall_seconds: Any

class TimestepAdvice(Answer):
    dt: Any
    tau_over_dt: Any
    worst_error: Any

class TrajectoryCheck(Answer): ...

class Report(Answer):
    def table(self) -> np.ndarray: ...
    def dataframe(self) -> Any: ...  # pandas.DataFrame

def cli(*args: str, progress: bool = ...) -> tuple[int, str, str]: ...
def calibrate(p: Optional[ArrayLike] = ..., e: Optional[ArrayLike] = ...,
              jobs: Optional[int] = ..., **options: Any) -> Calibration: ...
def observables(p: Optional[ArrayLike] = ..., e: Optional[ArrayLike] = ...,
                alpha: Optional[ArrayLike] = ..., alpha_eff: Optional[ArrayLike] = ...,
                v0: Optional[ArrayLike] = ..., m: Optional[ArrayLike] = ...,
                k: Optional[ArrayLike] = ..., end: Optional[str] = ...,
                precision: Optional[str] = ..., want: Optional[Iterable[str]] = ...,
                **options: Any) -> Observables: ...
def solve(solver: str, jobs: Optional[int] = ..., **options: Any) -> Solution: ...
def timestep(scheme: str, jobs: Optional[int] = ..., **options: Any) -> TimestepAdvice: ...
# delta(t), v(t) at any times, with the free flight before the contact and after its end: at tau
# from delta = 0 at -e v0 (end="overlap"), at t_cut from delta(t_cut) at -e_cap v0 (end="force",
# where e= is e_cap).
def trajectory(t: npt.ArrayLike, p: Optional[Number] = ..., e: Optional[Number] = ...,
               alpha: Optional[Number] = ..., alpha_eff: Optional[Number] = ...,
               v0: Number = ..., m: Number = ..., k: Number = ...,
               end: Literal["overlap", "force"] = ...) -> tuple[np.ndarray, np.ndarray]: ...
def check(t: npt.ArrayLike, delta: npt.ArrayLike, v: Optional[npt.ArrayLike] = ...,
          F: Optional[npt.ArrayLike] = ..., **options: Any) -> TrajectoryCheck: ...
def run(scene: Union[str, PathLike[str]], out: Optional[Union[str, PathLike[str]]] = ...,
        strict: bool = ..., progress: bool = ..., **options: Any) -> Report: ...
