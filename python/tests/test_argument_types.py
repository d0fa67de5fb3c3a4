"""An argument of the wrong type raises TypeError with a sentence naming the
argument (never pybind11's "Unable to cast" or its list of overloads);
complex samples are refused, not silently cut to their real part; compare's
metrics take a list or the command's comma-separated spelling."""

import json
import warnings

import numpy as np
import pytest

import napkin
from conftest import run_napkin

SLOTS = ["cg_x", "cg_y", "cg_z"]


def good_channels(n=200):
    return {slot: np.full(n, 1.0) for slot in SLOTS}


def transform(channels=None, **options):
    options.setdefault("dt_s", 1e-4)
    options.setdefault("array", "3a-cg")
    return napkin.transform(good_channels() if channels is None else channels, **options)


def type_error(call):
    """The TypeError sentence of `call` (a TypeError, and one sentence)."""
    with pytest.raises(TypeError) as error:
        call()
    text = str(error.value)
    assert "pybind11" not in text and "incompatible function arguments" not in text, text
    assert "Unable to cast" not in text and text.endswith("."), text
    return text


@pytest.mark.parametrize("name,value", [
    ("dt_s", "0.0001"), ("dt_s", [1e-4]), ("dt_s", True), ("dt_s", 1e-4 + 0j),
    ("array", 5), ("config", 3.0), ("solver", 1), ("test_id", 7),
    ("orientation_rad", "abc"), ("orientation_rad", 0.1), ("orientation_rad", (0, "a", 0)),
    ("initial_velocity_mps", (0, 0, None)), ("initial_omega_body_radps", {"x": 1}),
])
def test_transform_names_the_argument_of_the_wrong_type(name, value):
    text = type_error(lambda: transform(**{name: value}))
    assert text.startswith("napkin.transform: {} ".format(name)), text


def test_transform_dt_as_text_says_what_it_got():
    assert type_error(lambda: transform(dt_s="0.0001")) == \
        "napkin.transform: dt_s is '0.0001' (a str), not a number (the sampling interval in s)."


def test_numpy_numbers_are_numbers():
    expected = transform(dt_s=1e-4).summary
    assert transform(dt_s=np.float64(1e-4)).summary == expected
    assert transform(dt_s=np.float32(1e-4)).summary["peak_acc_g"] == pytest.approx(expected["peak_acc_g"])
    assert transform(orientation_rad=np.zeros(3)).summary == expected


@pytest.mark.parametrize("where", ["dict", "matrix", "time_s"])
def test_complex_samples_are_refused(where):
    channels, options = good_channels(), {}
    if where == "dict":
        channels["cg_y"] = channels["cg_y"] + 1e-3j
        name = 'channel "cg_y"'
    elif where == "matrix":
        channels = np.column_stack([channels[s] for s in SLOTS]).astype(complex)
        name = "channels"
    else:
        options = {"dt_s": None, "time_s": np.arange(200) * 1e-4 + 0j}
        name = "time_s"
    # Refused with the TypeError alone: no numpy ComplexWarning from a cast tried first.
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        text = type_error(lambda: transform(channels, **options))
    assert name in text and "complex" in text, text
    assert [str(w.message) for w in said] == []


def test_text_samples_are_refused():
    # numpy would parse "1.0" into a number: a channel of text is a mistake, not a recording.
    text = type_error(lambda: transform(dict(good_channels(), cg_x=["1.0"] * 200)))
    assert 'channel "cg_x"' in text and "not an array of numbers" in text, text


@pytest.mark.parametrize("call,name", [
    (lambda: napkin.hic(np.ones(100), "1e-4"), "dt_s"),
    (lambda: napkin.hic(np.ones(100), 1e-4, max_window_s="0.015"), "max_window_s"),
    (lambda: napkin.hic(np.ones(100) + 1j, 1e-4), "resultant_g"),
    (lambda: napkin.cfc(np.ones(100), 1e-4, cfc="1000"), "cfc"),
    (lambda: napkin.cfc(np.ones(100), 1e-4, variant=1), "variant"),
    (lambda: napkin.cfc(np.ones(100) * 1j, 1e-4), "x"),
    (lambda: napkin.bric(np.ones((10, 3)), critical_radps="66"), "critical_radps"),
    (lambda: napkin.bric(np.ones((10, 3)) + 0j), "omega_body_radps"),
    (lambda: napkin.hic15_p_ais3("700"), "hic15"),
    (lambda: napkin.bric_p_ais3(np.array([0.5 + 0.1j])), "bric"),
])
def test_criteria_name_the_argument_of_the_wrong_type(call, name):
    text = type_error(call)
    assert name in text, text


def test_risk_curves_still_take_numbers_and_arrays():
    assert isinstance(napkin.hic15_p_ais3(700), float)
    assert napkin.hic15_p_ais3(np.float32(700.0)) == pytest.approx(napkin.hic15_p_ais3(700.0), rel=1e-6)
    values = napkin.hic15_p_ais3(np.array([[100.0, 700.0], [1000.0, 2000.0]]))
    assert values.shape == (2, 2) and values[0, 1] == napkin.hic15_p_ais3(700.0)
    assert napkin.hic15_p_ais3([100, 700]).tolist() == [napkin.hic15_p_ais3(100.0), napkin.hic15_p_ais3(700.0)]


def cli_json(*args):
    return json.loads(run_napkin(*args, "--format", "json").stdout)


def test_compare_metrics_take_the_commands_comma_spelling(demo_catalogue):
    catalogue = napkin.Catalogue(demo_catalogue)
    expected = cli_json("--db", demo_catalogue, "compare", "--series", "padding-series", "--metrics", "hic15,bric")
    assert expected
    assert catalogue.compare("padding-series", metrics="hic15,bric") == expected
    assert catalogue.compare("padding-series", metrics=["hic15", "bric"]) == expected
    assert catalogue.compare("padding-series", metrics=["hic15,bric"]) == expected
    assert catalogue.compare("padding-series", metrics=("hic15", "bric")) == expected
    text = type_error(lambda: catalogue.compare("padding-series", metrics=5))
    assert "metrics" in text, text
    text = type_error(lambda: catalogue.compare("padding-series", metrics=["hic15", 5]))
    assert "metrics" in text, text
