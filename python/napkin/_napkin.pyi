# Type stubs of napkin's compiled module (python/py_*.cpp). The public API is
# the package's (napkin/__init__.pyi); these are the functions it wraps.
from typing import Any, NamedTuple, Sequence, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

class Error(Exception): ...
class InputError(Error, ValueError): ...

class ScreeningFailure(InputError):
    findings: list[Finding]

class CatalogueError(Error, RuntimeError): ...
class NotFoundError(CatalogueError, InputError): ...
class InternalError(Error, RuntimeError): ...

class Finding(NamedTuple):
    check: str
    channel: str | None
    severity: str
    detail: str

_HIC15_WINDOW_S: float
_CFC1000: float

def transform(
    channels: Any,
    time_s: Any,
    dt_s: Any,
    array: Any,
    config: Any,
    orientation_rad: Any,
    initial_velocity_mps: Any,
    initial_omega_body_radps: Any,
    solver: Any,
    test_id: Any,
    config_dir: str,
) -> tuple[str, dict[str, NDArray[np.float64]]]: ...
def transform_file(
    path: Any,
    array: Any,
    channel_map: Any,
    position: Any,
    columns: Any,
    config: Any,
    orientation_rad: Any,
    initial_velocity_mps: Any,
    solver: Any,
    config_dir: str,
) -> tuple[str, dict[str, NDArray[np.float64]], list[str]]: ...
def _transform_bytes(
    array: str, samples: int, dt_s: float, config: str = ..., config_dir: str = ...
) -> int: ...
def hic(
    resultant_g: ArrayLike, dt_s: float, max_window_s: float | None = ..., from_time_zero: bool = ..., t0_s: float = ...
) -> tuple[float, float, float]: ...
def cfc(x: ArrayLike, dt_s: float, cfc: float = ..., variant: str = ...) -> NDArray[np.float64]: ...
def bric(omega_body_radps: ArrayLike, critical_radps: Sequence[float] | NDArray[Any] | None = ...) -> float: ...
def _iso18571(
    reference: ArrayLike,
    candidate: ArrayLike,
    dt_s: float,
    start_s: float | None = ...,
    end_s: float | None = ...,
    edition: str = ...,
) -> tuple[float, float, float, float, float, str, float]: ...
@overload
def hic15_p_ais3(hic15: float) -> float: ...
@overload
def hic15_p_ais3(hic15: NDArray[Any] | Sequence[float]) -> NDArray[np.float64]: ...
@overload
def hic36_p_ais4(hic36: float) -> float: ...
@overload
def hic36_p_ais4(hic36: NDArray[Any] | Sequence[float]) -> NDArray[np.float64]: ...
@overload
def bric_p_ais3(bric: float) -> float: ...
@overload
def bric_p_ais3(bric: NDArray[Any] | Sequence[float]) -> NDArray[np.float64]: ...
@overload
def bric_p_ais4(bric: float) -> float: ...
@overload
def bric_p_ais4(bric: NDArray[Any] | Sequence[float]) -> NDArray[np.float64]: ...
def _summary_fields() -> list[tuple[str, str, str, str, str, str | None, int | None, str | None]]: ...
def _limit_presets() -> list[tuple[str, str, str, str, str, str, str, str, str]]: ...
def exceed_probability(values: ArrayLike, limit: float) -> float: ...
def tune_memory() -> bool: ...

class Catalogue:
    def __init__(self, path: str) -> None: ...
    @property
    def path(self) -> str: ...
    @property
    def closed(self) -> bool: ...
    def close(self) -> None: ...
    def query(
        self,
        kind: str,
        where: list[str] | None,
        sort: list[str] | None,
        limit: str | None,
        config: str | None,
        series: list[str] | None,
        variant: list[str] | None,
        limits: str | None = ...,
    ) -> tuple[list[str], list[NDArray[np.float64] | list[Any]]]: ...
    def compare_json(
        self,
        series: str,
        by: str,
        baseline: str | None,
        metrics: list[str] | None,
        config: list[str] | None,
        limits: list[str] | None = ...,
    ) -> str: ...
    def channels(self, test_id: str, derived: bool, config: str | None) -> dict[str, NDArray[np.float64]]: ...
    def test_inputs(self, test_id: str) -> dict[str, Any]: ...
