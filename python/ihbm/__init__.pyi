from os import PathLike
from typing import Any, Callable, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

from matplotlib.axes import Axes

from ._native import DEFAULT_HARMONICS as DEFAULT_HARMONICS
from ._native import IhbmError as IhbmError

__all__ = [
    "Model",
    "Curve",
    "IhbmError",
    "Interrupted",
    "builtin_models",
    "plot",
    "DEFAULT_HARMONICS",
]

# A result as the command line's JSON gives it.
_Result = Dict[str, Any]
# `None`: a tqdm bar where tqdm is installed; `False`: none; or called as
# `progress(points, value)` now and then while the run goes on.
_ProgressArg = Union[None, Literal[False], Callable[[int, float], object]]
_Settings = Union[float, int, bool, str]

class Interrupted(KeyboardInterrupt):
    result: _Result
    def __init__(self, result: _Result) -> None: ...

class Curve(Dict[str, Any]):
    def to_dataframe(self) -> Any: ...

def builtin_models() -> List[str]: ...
def plot(
    result: Mapping[str, Any],
    ax: Optional[Axes] = None,
    output: Optional[str] = None,
    *,
    label: Optional[str] = None,
) -> Axes: ...

class Model:
    def __init__(self, text: str, origin: str = "<text>") -> None: ...
    @classmethod
    def builtin(cls, name: str) -> "Model": ...
    @classmethod
    def file(cls, path: Union[str, PathLike[str]]) -> "Model": ...
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def dofs(self) -> List[str]: ...
    @property
    def outputs(self) -> List[str]: ...
    @property
    def equations(self) -> List[str]: ...
    @property
    def params(self) -> Dict[str, Tuple[float, str]]: ...
    def solve(
        self,
        omega: float,
        harmonics: int = ...,
        set: Optional[Mapping[str, float]] = None,
        aft_samples: Optional[int] = None,
        sensitivity: Union[str, Sequence[str], None] = None,
    ) -> _Result: ...
    def sweep(
        self,
        omega_from: float,
        omega_to: float,
        harmonics: int = ...,
        set: Optional[Mapping[str, float]] = None,
        progress: _ProgressArg = None,
        aft_samples: Optional[int] = None,
        **settings: _Settings,
    ) -> Curve: ...
    def sweep_param(
        self,
        param: str,
        value_from: float,
        value_to: float,
        omega: float,
        harmonics: int = ...,
        set: Optional[Mapping[str, float]] = None,
        progress: _ProgressArg = None,
        aft_samples: Optional[int] = None,
        **settings: _Settings,
    ) -> Curve: ...
    def simulate(
        self,
        omega: float,
        periods: Optional[int] = None,
        dt: Optional[float] = None,
        scheme: Optional[Literal["bdf2", "gl"]] = None,
        set: Optional[Mapping[str, float]] = None,
    ) -> _Result: ...
    def backbone(
        self,
        to: float,
        mode: int = 1,
        output: Optional[str] = None,
        harmonics: int = ...,
        set: Optional[Mapping[str, float]] = None,
        progress: _ProgressArg = None,
        aft_samples: Optional[int] = None,
    ) -> _Result: ...
    def folds(
        self,
        param: str,
        value_from: float,
        value_to: float,
        omega_from: float,
        omega_to: float,
        harmonics: int = ...,
        boundary: Optional[Literal["fold", "period-doubling", "torus"]] = None,
        set: Optional[Mapping[str, float]] = None,
        progress: _ProgressArg = None,
        **settings: _Settings,
    ) -> _Result: ...
    def cycle(
        self,
        omega: float,
        harmonics: int = ...,
        set: Optional[Mapping[str, float]] = None,
    ) -> _Result: ...
    def cycles(
        self,
        param: str,
        value_from: float,
        value_to: float,
        omega: float,
        harmonics: int = ...,
        set: Optional[Mapping[str, float]] = None,
        progress: _ProgressArg = None,
    ) -> _Result: ...
