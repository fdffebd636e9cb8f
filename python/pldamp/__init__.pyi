# Type stubs of the module pldamp (docs/python.md).
from decimal import Decimal
from os import PathLike
from typing import Any, Iterable, Literal, Optional, Union

import numpy as np
import numpy.typing as npt

Number = Union[float, int, str, Decimal]
ArrayLike = Union[Number, npt.ArrayLike]

ARRAY_OBSERVABLES: tuple[str, ...]

def cli(*args: str) -> tuple[int, str, str]: ...
def calibrate(p: Optional[Number] = ..., e: Optional[Number] = ..., **options: Any) -> dict[str, Any]: ...
def observables(p: Optional[ArrayLike] = ..., e: Optional[ArrayLike] = ...,
                alpha: Optional[ArrayLike] = ..., alpha_eff: Optional[ArrayLike] = ...,
                v0: Optional[ArrayLike] = ..., m: Optional[ArrayLike] = ...,
                k: Optional[ArrayLike] = ..., end: Optional[str] = ...,
                precision: Optional[str] = ..., want: Optional[Iterable[str]] = ...,
                **options: Any) -> dict[str, Any]: ...
def solve(solver: str, **options: Any) -> dict[str, Any]: ...
def timestep(scheme: str, **options: Any) -> dict[str, Any]: ...
# delta(t), v(t) at any times, with the free flight before the contact and after its end: at tau
# from delta = 0 at -e v0 (end="overlap"), at t_cut from delta(t_cut) at -e_cap v0 (end="force",
# where e= is e_cap).
def trajectory(t: npt.ArrayLike, p: Optional[Number] = ..., e: Optional[Number] = ...,
               alpha: Optional[Number] = ..., alpha_eff: Optional[Number] = ...,
               v0: Number = ..., m: Number = ..., k: Number = ...,
               end: Literal["overlap", "force"] = ...) -> tuple[np.ndarray, np.ndarray]: ...
def check(t: npt.ArrayLike, delta: npt.ArrayLike, v: Optional[npt.ArrayLike] = ...,
          F: Optional[npt.ArrayLike] = ..., **options: Any) -> dict[str, Any]: ...
def run(scene: Union[str, PathLike[str]], out: Optional[Union[str, PathLike[str]]] = ...,
        strict: bool = ..., **options: Any) -> dict[str, Any]: ...
