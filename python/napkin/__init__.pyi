# Type stubs of napkin's Python API (docs/python.md; PEP 561: napkin/py.typed
# marks the package as typed). python/tests/test_typing.py holds them to
# `mypy --strict` on an example that uses every public name.
import os
from typing import Any, Mapping, NamedTuple, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._napkin import CatalogueError as CatalogueError
from ._napkin import Error as Error
from ._napkin import Finding as Finding
from ._napkin import InputError as InputError
from ._napkin import InternalError as InternalError
from ._napkin import NotFoundError as NotFoundError
from ._napkin import ScreeningFailure as ScreeningFailure
from ._napkin import bric as bric
from ._napkin import bric_p_ais3 as bric_p_ais3
from ._napkin import bric_p_ais4 as bric_p_ais4
from ._napkin import hic15_p_ais3 as hic15_p_ais3
from ._napkin import hic36_p_ais4 as hic36_p_ais4
from ._napkin import tune_memory as tune_memory

__version__: str
__all__ = [
    "transform",
    "transform_file",
    "TransformResult",
    "Catalogue",
    "hic",
    "HIC",
    "cfc",
    "bric",
    "iso18571",
    "ISO18571Rating",
    "SummaryField",
    "SUMMARY_FIELDS",
    "RISK_CURVES",
    "LimitPreset",
    "LIMITS",
    "QueryKind",
    "QUERY_KINDS",
    "ExportFormat",
    "EXPORT_FORMATS",
    "presets",
    "exceed_probability",
    "tune_memory",
    "Error",
    "InputError",
    "ScreeningFailure",
    "Finding",
    "CatalogueError",
    "NotFoundError",
    "InternalError",
    "hic15_p_ais3",
    "hic36_p_ais4",
    "bric_p_ais3",
    "bric_p_ais4",
]

# A 3-vector: phi, theta, psi (rad) or a velocity's components.
_Triple = Sequence[float] | NDArray[Any]
# A str or a pathlib.Path.
_Path = str | os.PathLike[str]
# One name, or a list (tuple, ...) of them.
_Names = str | Sequence[str]

class SummaryField(NamedTuple):
    name: str
    group: str
    label: str
    unit: str
    meaning: str
    criterion: str | None
    ais: int | None
    source: str | None

SUMMARY_FIELDS: dict[str, SummaryField]
RISK_CURVES: tuple[str, ...]

class LimitPreset(NamedTuple):
    preset: str
    name: str
    title: str
    applies_to: str
    source: str
    url: str
    version: str
    note: str
    path: str

LIMITS: dict[str, LimitPreset]

class QueryKind(NamedTuple):
    name: str
    description: str
    takes_limits: bool

QUERY_KINDS: dict[str, QueryKind]

class ExportFormat(NamedTuple):
    name: str
    description: str
    needs_result: bool
    needs_rotation: bool
    folder: bool

EXPORT_FORMATS: dict[str, ExportFormat]

def presets(kind: str) -> list[str]: ...

def exceed_probability(values: ArrayLike, limit: float) -> float: ...

class HIC(NamedTuple):
    hic: float
    t1_s: float
    t2_s: float

def hic(
    resultant_g: ArrayLike,
    dt_s: float,
    max_window_s: float | None = ...,
    from_time_zero: bool = ...,
    t0_s: float = ...,
) -> HIC: ...
def cfc(x: ArrayLike, dt_s: float, cfc: float = ..., variant: str = ...) -> NDArray[np.float64]: ...

class ISO18571Rating(NamedTuple):
    corridor: float
    phase: float
    magnitude: float
    slope: float
    overall: float
    grade: str
    shift_s: float

def iso18571(
    reference: ArrayLike,
    candidate: ArrayLike,
    dt_s: float,
    start_s: float | None = ...,
    end_s: float | None = ...,
    edition: str = ...,
) -> ISO18571Rating: ...

class TransformResult:
    summary: dict[str, Any]
    channels: dict[str, NDArray[np.float64]]
    conditioning: list[dict[str, Any]]
    salvage: dict[str, Any] | None
    def __init__(self, summary: dict[str, Any], channels: dict[str, NDArray[np.float64]]) -> None: ...

def transform(
    channels: Mapping[str, ArrayLike] | ArrayLike,
    time_s: ArrayLike | None = ...,
    dt_s: float | None = ...,
    *,
    array: _Path | Mapping[str, Any],
    config: _Path | Mapping[str, Any] = ...,
    orientation_rad: _Triple = ...,
    initial_velocity_mps: _Triple = ...,
    initial_omega_body_radps: _Triple = ...,
    solver: str | None = ...,
    test_id: str = ...,
) -> TransformResult: ...

def transform_file(
    path: _Path,
    array: _Path | None = ...,
    channel_map: _Path | None = ...,
    position: str | None = ...,
    columns: Mapping[str, str] | None = ...,
    config: _Path | Mapping[str, Any] = ...,
    orientation_rad: _Triple = ...,
    initial_velocity_mps: _Triple = ...,
    solver: str | None = ...,
) -> TransformResult: ...

class Catalogue:
    def __init__(self, path: _Path) -> None: ...
    @property
    def path(self) -> str: ...
    @property
    def closed(self) -> bool: ...
    def close(self) -> None: ...
    def __enter__(self) -> Catalogue: ...
    def __exit__(self, *exception: object) -> None: ...
    def tests(self) -> list[str]: ...
    def query(
        self,
        kind: str,
        where: _Names | None = ...,
        sort: _Names | None = ...,
        limit: int | None = ...,
        config: str | None = ...,
        series: _Names | None = ...,
        variant: _Names | None = ...,
        limits: _Path | None = ...,
    ) -> list[dict[str, Any]]: ...
    # A pandas.DataFrame (Any: Debian's pandas carries no type information).
    def query_frame(
        self,
        kind: str,
        where: _Names | None = ...,
        sort: _Names | None = ...,
        limit: int | None = ...,
        config: str | None = ...,
        series: _Names | None = ...,
        variant: _Names | None = ...,
        limits: _Path | None = ...,
    ) -> Any: ...
    def limits_frame(
        self,
        limits: _Path,
        where: _Names | None = ...,
        sort: _Names | None = ...,
        limit: int | None = ...,
        config: str | None = ...,
        series: _Names | None = ...,
        variant: _Names | None = ...,
    ) -> Any: ...
    def channels(
        self, test_id: str, derived: bool = ..., config: str | None = ...
    ) -> dict[str, NDArray[np.float64]]: ...
    def test_inputs(self, test_id: str) -> dict[str, Any]: ...
    def export(
        self,
        test_id: str,
        format: str,
        path: _Path,
        config: str | None = ...,
        units: str | None = ...,
        part: int | None = ...,
        numform: str | None = ...,
        position: str | None = ...,
        dummy_type: str | None = ...,
        force: bool = ...,
    ) -> None: ...
    def compare(
        self,
        series: str,
        by: str = ...,
        baseline: str | None = ...,
        metrics: _Names | None = ...,
        config: _Names | None = ...,
        limits: _Path | Sequence[_Path] | None = ...,
        scale: str | None = ...,
        equivalence: float | None = ...,
    ) -> list[dict[str, Any]]: ...
    # A pandas.DataFrame (Any: Debian's pandas carries no type information).
    def compare_frame(
        self,
        series: str,
        by: str = ...,
        baseline: str | None = ...,
        metrics: _Names | None = ...,
        config: _Names | None = ...,
        limits: _Path | Sequence[_Path] | None = ...,
        scale: str | None = ...,
        equivalence: float | None = ...,
    ) -> Any: ...
