# The compiled module behind `ihbm` (private: use `ihbm.Model`).
from typing import Any, Callable, Dict, List, Optional, Tuple, final

import numpy.typing as npt

__all__ = ["NativeModel", "builtin_names", "IhbmError", "DEFAULT_HARMONICS"]

DEFAULT_HARMONICS: int

class IhbmError(ValueError): ...

_Progress = Optional[Callable[[int, float], object]]
_Pairs = List[Tuple[str, float]]
_SweepOut = Tuple[str, Dict[str, npt.NDArray[Any]], Optional[BaseException]]

def builtin_names() -> List[str]: ...

@final
class NativeModel:
    def __new__(cls, text: str, origin: str) -> "NativeModel": ...
    @staticmethod
    def builtin(name: str) -> "NativeModel": ...
    @staticmethod
    def file(path: str) -> "NativeModel": ...
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
    def params(self) -> List[Tuple[str, float, str]]: ...
    def solve(
        self,
        omega: float,
        harmonics: int,
        set: _Pairs,
        aft_samples: Optional[int] = None,
        sensitivity: List[str] = ...,
    ) -> str: ...
    def sweep(
        self,
        omega_from: float,
        omega_to: float,
        harmonics: int,
        set: _Pairs,
        settings: str,
        progress: _Progress = None,
        aft_samples: Optional[int] = None,
    ) -> _SweepOut: ...
    def sweep_param(
        self,
        param: str,
        value_from: float,
        value_to: float,
        omega: float,
        harmonics: int,
        set: _Pairs,
        settings: str,
        progress: _Progress = None,
        aft_samples: Optional[int] = None,
    ) -> _SweepOut: ...
    def simulate(
        self,
        omega: float,
        set: _Pairs,
        periods: Optional[int] = None,
        dt: Optional[float] = None,
        scheme: Optional[str] = None,
    ) -> str: ...
    def backbone(
        self,
        to: float,
        mode: int,
        harmonics: int,
        set: _Pairs,
        output: Optional[str] = None,
        progress: _Progress = None,
        aft_samples: Optional[int] = None,
    ) -> Tuple[str, Optional[BaseException]]: ...
    def folds(
        self,
        param: str,
        value_from: float,
        value_to: float,
        omega_from: float,
        omega_to: float,
        harmonics: int,
        set: _Pairs,
        settings: str,
        boundary: Optional[str] = None,
        progress: _Progress = None,
    ) -> Tuple[str, Optional[BaseException]]: ...
    def cycle(self, omega: float, harmonics: int, set: _Pairs) -> str: ...
    def cycles(
        self,
        param: str,
        value_from: float,
        value_to: float,
        omega: float,
        harmonics: int,
        set: _Pairs,
        progress: _Progress = None,
    ) -> Tuple[str, Optional[BaseException]]: ...
