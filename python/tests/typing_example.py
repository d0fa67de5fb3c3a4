"""A script that uses napkin's public API as a typed program would, for
test_typing.py: `mypy --strict` must accept it with napkin's stubs, and it
runs. Usage: typing_example.py CATALOGUE (a catalogue `napkin demo` wrote)."""

import sys
import tempfile
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

import napkin


def half_sine(peak_g: float, duration_s: float, dt_s: float, n: int) -> NDArray[np.float64]:
    time_s = np.arange(n) * dt_s
    pulse: NDArray[np.float64] = peak_g * np.sin(np.pi * np.clip(time_s / duration_s, 0.0, 1.0))
    return pulse


def main(catalogue_path: str) -> None:
    dt_s = 1e-4
    pulse = half_sine(80.0, 0.02, dt_s, 1000)
    channels = {"cg_x": -pulse, "cg_y": 0.1 * pulse, "cg_z": np.zeros_like(pulse)}
    result: napkin.TransformResult = napkin.transform(channels, dt_s=dt_s, array="3a-cg", test_id="typed")
    hic15: float = result.summary["hic15"]
    acc_x: NDArray[np.float64] = result.channels["acc_body_x_g"]

    window: napkin.HIC = napkin.hic(np.abs(acc_x), dt_s)
    start_s: float = window.t1_s
    value, t1_s, t2_s = window
    filtered: NDArray[np.float64] = napkin.cfc(pulse, dt_s, cfc=600)
    bric: float = napkin.bric(np.zeros((100, 3)))
    risk: float = napkin.hic15_p_ais3(700.0)
    risks: NDArray[np.float64] = napkin.bric_p_ais3(np.array([0.5, 1.0]))
    rating: napkin.ISO18571Rating = napkin.iso18571(pulse, filtered, dt_s)
    grade: str = rating.grade
    field: napkin.SummaryField = napkin.SUMMARY_FIELDS["peak_acc_g"]
    unit: str = field.unit
    curves: tuple[str, ...] = napkin.RISK_CURVES
    tune: Callable[[], bool] = napkin.tune_memory  # not called: it changes this process's malloc
    version: str = napkin.__version__
    preset: napkin.LimitPreset = napkin.LIMITS["fmvss208"]
    source: str = preset.source
    chance: float = napkin.exceed_probability([600.0, 650.0, 700.0], 700.0)

    with napkin.Catalogue(catalogue_path) as catalogue:
        tests: list[str] = catalogue.tests()
        rows: list[dict[str, Any]] = catalogue.query("hic", where="hic15>0", sort=["hic15:desc"], limit=3)
        frame = catalogue.query_frame("hic")
        inputs = catalogue.test_inputs(tests[0])
        again = napkin.transform(**inputs)
        derived: dict[str, NDArray[np.float64]] = catalogue.channels(tests[0], derived=True)
        comparison = catalogue.compare("padding-series", metrics=["hic15", "bric"], limits=["fmvss208"])
        compared = catalogue.compare_frame("padding-series", scale="linear", equivalence=5.0)
        output_format: napkin.ExportFormat = napkin.EXPORT_FORMATS["lsdyna"]
        with tempfile.TemporaryDirectory() as folder:
            catalogue.export(tests[0], output_format.name, folder + "/curves.k", units="english", part=2)
        limited = catalogue.limits_frame("euro-ncap-aop-v9.3-frontal-head-hiii50m", series="padding-series")
    closed: bool = catalogue.closed

    failing = dict(channels)
    failing["cg_x"] = np.where(np.arange(1000) == 100, 5000.0, 1.0)
    try:
        napkin.transform(failing, dt_s=dt_s, array="3a-cg")
    except napkin.ScreeningFailure as failure:
        findings: list[napkin.Finding] = failure.findings
        errors = [finding.detail for finding in findings if finding.severity == "error"]
        assert errors
    except napkin.InputError:
        raise
    try:
        napkin.Catalogue(catalogue_path + ".missing")
    except napkin.NotFoundError as missing:
        problem: napkin.CatalogueError = missing
    except (napkin.CatalogueError, napkin.InternalError, napkin.Error):
        raise

    print(hic15, start_s, value, t1_s, t2_s, bric, risk, risks.shape, grade, unit, curves, tune, version,
          len(rows), len(frame), again.summary["test_id"], len(derived), len(comparison), closed, problem, source,
          chance, len(limited), len(compared))


if __name__ == "__main__":
    main(sys.argv[1])
