"""Bad input raises ValueError with the CLI's sentence, and the interpreter
goes on: wrong shapes, NaN, an unknown slot, an unknown preset."""

import numpy as np
import pytest

import napkin
from conftest import cli_error, write_signals_csv

SLOTS = ["cg_x", "cg_y", "cg_z"]


def good_channels(n=200):
    return {slot: np.full(n, 1.0) for slot in SLOTS}


def transform(channels, **options):
    options.setdefault("dt_s", 1e-4)
    options.setdefault("array", "3a-cg")
    return napkin.transform(channels, **options)


def test_unknown_presets_raise_the_cli_sentence(tmp_path):
    write_signals_csv(tmp_path / "in.csv", np.arange(200) * 1e-4, good_channels())
    with pytest.raises(ValueError) as error:
        transform(good_channels(), array="no-such-array")
    assert str(error.value) == cli_error("transform", "--array", "no-such-array", tmp_path / "in.csv",
                                         "--out", tmp_path / "o.csv")
    with pytest.raises(ValueError) as error:
        transform(good_channels(), config="no-such-config")
    assert str(error.value) == cli_error("transform", "--array", "3a-cg", "--config", "no-such-config",
                                         tmp_path / "in.csv", "--out", tmp_path / "o.csv")


def test_a_definition_given_as_a_dict_is_read_as_its_json_file_would_be():
    """A dict is converted to JSON directly (no text passes between the module and the library):
    what a JSON file cannot hold is refused naming the argument, what it can is read by the file's
    reader with its sentences."""
    filtered = transform(good_channels(), config={"name": "cfc60", "filter": {"linear_cfc": 60.0}})
    assert filtered.summary["peak_acc_g"] == pytest.approx(np.sqrt(3.0), rel=1e-9)
    with pytest.raises(napkin.InputError, match=r"^napkin.transform: config\['filter'\]\['linear_cfc'\] holds nan"):
        transform(good_channels(), config={"name": "x", "filter": {"linear_cfc": float("nan")}})
    with pytest.raises(TypeError, match=r"config has the key 1; the keys of a definition are str"):
        transform(good_channels(), config={1: "x"})
    with pytest.raises(TypeError, match=r"config\['name'\] is .*set.*which a JSON file cannot hold"):
        transform(good_channels(), config={"name": {"x"}})
    with pytest.raises(napkin.InputError, match="the processing config given to napkin.transform"):
        transform(good_channels(), config={"name": "x", "filter": {"linear_cfc": "sixty"}})


def test_unknown_and_missing_slots():
    with pytest.raises(ValueError, match=r'slot "cg_w", which array "3a-cg" does not have \(its slots: '
                                         r'cg_x, cg_y, cg_z\)'):
        transform(dict(good_channels(), cg_w=np.zeros(200)))
    channels = good_channels()
    del channels["cg_y"]
    with pytest.raises(ValueError, match='no channel for slot "cg_y" of array "3a-cg"'):
        transform(channels)


def test_wrong_shapes():
    with pytest.raises(ValueError, match=r"channels is an array of shape \(3, 200\); .*\(3 columns: cg_x, cg_y, cg_z\)"):
        transform(np.zeros((3, 200)))
    with pytest.raises(ValueError, match=r'channel "cg_x" has 2 dimensions'):
        transform(dict(good_channels(), cg_x=np.zeros((200, 1))))
    with pytest.raises(ValueError, match=r'channel "cg_z" has 199 samples but channel "cg_x" has 200'):
        transform(dict(good_channels(), cg_z=np.zeros(199)))
    with pytest.raises(ValueError, match=r"time_s has 10 values but the channels have 200 samples"):
        transform(good_channels(), dt_s=None, time_s=np.arange(10) * 1e-4)
    with pytest.raises(TypeError, match='channel "cg_x" is not an array of numbers'):
        transform(dict(good_channels(), cg_x=["a"] * 200))
    with pytest.raises(ValueError, match="give either time_s .* or dt_s .*, not both"):
        transform(good_channels(), time_s=np.arange(200) * 1e-4)


def test_nan_and_bad_time_raise_the_cli_sentence(tmp_path):
    channels = good_channels()
    channels["cg_y"][17] = np.nan
    write_signals_csv(tmp_path / "in.csv", np.arange(200) * 1e-4, channels)
    sentence = cli_error("transform", "--array", "3a-cg", tmp_path / "in.csv", "--out", tmp_path / "o.csv")
    with pytest.raises(ValueError) as error:
        transform(channels, test_id="in")
    # The same sentence, the sample named by its index instead of its file line.
    assert str(error.value) == sentence.replace(str(tmp_path / "in.csv"), "in").replace(
        "row 19, column", "sample 17, channel")
    time_s = np.arange(200) * 1e-4
    time_s[50] = time_s[49]
    write_signals_csv(tmp_path / "in.csv", time_s, good_channels())
    sentence = cli_error("transform", "--array", "3a-cg", tmp_path / "in.csv", "--out", tmp_path / "o.csv")
    with pytest.raises(ValueError) as error:
        transform(good_channels(), dt_s=None, time_s=time_s)
    # The same sentence, the sample named by its index instead of its file line.
    assert str(error.value) == sentence.replace(str(tmp_path / "in.csv"), "napkin.transform").replace(
        "row 52", "time_s[50]").replace("previous row's", "previous sample's")


def test_a_failing_test_raises_like_transform_exits_1(tmp_path):
    # A sample beyond the plausibility limit (2,000 g) fails screening (an error finding).
    channels = good_channels(400)
    channels["cg_x"][100] = 5000.0
    write_signals_csv(tmp_path / "in.csv", np.arange(400) * 1e-4, channels)
    sentence = cli_error("transform", "--array", "3a-cg", tmp_path / "in.csv", "--out", tmp_path / "o.csv")
    with pytest.raises(ValueError) as error:
        transform(channels, test_id="in")
    # The same sentence; arrays have no file rows, so the CSV's "row 102, " is not in it.
    assert "(row 102, t = 0.01 s)" in sentence
    assert str(error.value) == sentence.replace(str(tmp_path / "in.csv"), "in").replace("row 102, ", "")


def test_the_interpreter_survives_and_computes_on():
    for bad in (np.zeros((3, 200)), {"cg_x": None}, "channels", None):
        with pytest.raises((ValueError, TypeError)):
            transform(bad)
    result = transform(good_channels())
    assert result.summary["peak_acc_g"] == pytest.approx(3 ** 0.5, rel=1e-9)
