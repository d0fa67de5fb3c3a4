"""napkin.transform equals `napkin transform` on the same input, bit for bit:
the summary JSON as parsed, every derived-channel CSV cell."""

import json
import os

import numpy as np
import pytest

import napkin
from conftest import cells_of, read_csv_cells, run_napkin, write_signals_csv


def synthetic_inputs(tmp_path, *synth_args):
    """The raw inputs of a synthetic test `napkin synth` stores."""
    db = tmp_path / "synth.db"
    run_napkin("init", "--db", db)
    run_napkin("synth", "--db", db, *synth_args)
    catalogue = napkin.Catalogue(db)
    (test_id,) = catalogue.tests()[:1]
    return db, catalogue.test_inputs(test_id)


def cli_transform(tmp_path, inputs, *extra):
    """`napkin transform` of `inputs` written as CSV: (summary dict, CSV cells)."""
    signals = tmp_path / "input.csv"
    write_signals_csv(signals, inputs["time_s"], inputs["channels"])
    out, summary = tmp_path / "out.csv", tmp_path / "summary.json"
    array = tmp_path / "array.json"  # test_inputs gives the stored definition
    array.write_text(json.dumps(inputs["array"]))
    triple = lambda values: ",".join(repr(float(v)) for v in values)  # noqa: E731
    run_napkin("transform", "--array", array, "--orientation=" + triple(inputs["orientation_rad"]),
               "--initial-velocity=" + triple(inputs["initial_velocity_mps"]), *extra, signals, "--out", out,
               "--summary", summary)
    return json.loads(summary.read_text()), read_csv_cells(out)


def assert_same_as_cli(result, summary, cells):
    assert result.summary == summary
    assert result.conditioning == summary["conditioning"]
    present = [name for name, column in cells.items() if any(column)]
    assert sorted(result.channels) == sorted(present)
    for name, values in result.channels.items():
        assert isinstance(values, np.ndarray) and values.dtype == np.float64
        assert cells_of(values) == cells[name], name


def test_report_4_5_scenario_equals_cli(tmp_path):
    _, inputs = synthetic_inputs(tmp_path, "--scenario", "seed-fixed-axis")
    assert inputs["orientation_rad"] == (0.5, 0.5, 0.5)  # report section 4.5.1
    result = napkin.transform(inputs["channels"], time_s=inputs["time_s"], array=inputs["array"],
                              orientation_rad=inputs["orientation_rad"],
                              initial_velocity_mps=inputs["initial_velocity_mps"], test_id="input")
    summary, cells = cli_transform(tmp_path, inputs)
    assert_same_as_cli(result, summary, cells)
    # Report section 4.5.2: 85.94 degrees about the fixed lateral axis, peak fixed omega_Y 50 rad/s.
    assert abs(summary["max_rotation_deg"] - 85.94) < 0.01
    assert abs(np.max(np.abs(result.channels["omega_fixed_y_radps"])) - 50.0) < 1e-6


def test_synthetic_denton_test_equals_cli_and_run(tmp_path):
    db, inputs = synthetic_inputs(tmp_path, "--scenario", "random", "--array", "denton-3222", "--seed", "7")
    result = napkin.transform(**inputs)
    summary, cells = cli_transform(tmp_path, inputs)
    summary["test_id"] = inputs["test_id"]  # the CLI names the test after its file
    assert_same_as_cli(result, summary, cells)
    # ... and `napkin run` stores the same result: its derived channels bit for
    # bit under a config that stores them as float64 (the default keeps float32).
    config_path = tmp_path / "exact64.json"  # the default config but for the storage
    config_path.write_text(json.dumps({"name": "exact64", "storage": {"derived_channels": "float64"}}))
    run_napkin("run", "--db", db, "--config", config_path)
    result = napkin.transform(**inputs, config=config_path)
    stored = napkin.Catalogue(db).channels(inputs["test_id"], config="exact64")
    assert sorted(stored) == sorted(result.channels)
    for name, values in stored.items():
        np.testing.assert_array_equal(values, result.channels[name], err_msg=name)


def test_array_forms_and_time_bases_agree(tmp_path):
    _, inputs = synthetic_inputs(tmp_path, "--scenario", "random", "--array", "denton-3222", "--seed", "3")
    by_dict = napkin.transform(**inputs)
    slots = list(inputs["channels"])  # the array's slot order
    matrix = np.column_stack([inputs["channels"][slot] for slot in slots])
    as_matrix = dict(inputs, channels=matrix)
    by_matrix = napkin.transform(**as_matrix)
    assert by_matrix.summary == by_dict.summary
    for name in by_dict.channels:
        np.testing.assert_array_equal(by_matrix.channels[name], by_dict.channels[name])
    # dt instead of time_s: the first sample at 0 and the mean step of time_s.
    time_s = inputs["time_s"]
    dt = (time_s[-1] - time_s[0]) / (len(time_s) - 1)
    by_dt = napkin.transform(**dict(inputs, time_s=None, dt_s=dt))
    assert by_dt.summary["hic15"] == by_dict.summary["hic15"]
    np.testing.assert_allclose(by_dt.channels["time_s"], by_dict.channels["time_s"] - time_s[0], atol=1e-12)


def test_acceleration_only_array(tmp_path):
    time_s = np.arange(0, 0.1, 1e-4)
    pulse = 80.0 * np.sin(np.pi * np.clip(time_s / 0.02, 0, 1))  # one 20 ms half sine, g
    channels = {"cg_x": -pulse, "cg_y": 0.1 * pulse, "cg_z": np.zeros_like(pulse)}
    result = napkin.transform(channels, time_s=time_s, array="3a-cg", test_id="input")
    assert sorted(result.channels) == ["acc_body_x_g", "acc_body_y_g", "acc_body_z_g", "time_s"]
    assert result.summary["bric"] is None
    write_signals_csv(tmp_path / "input.csv", time_s, channels)
    run_napkin("transform", "--array", "3a-cg", tmp_path / "input.csv", "--out", tmp_path / "out.csv",
               "--summary", tmp_path / "summary.json")
    assert result.summary == json.loads((tmp_path / "summary.json").read_text())
    cells = read_csv_cells(tmp_path / "out.csv")
    for name, values in result.channels.items():
        assert cells_of(values) == cells[name], name


def test_result_arrays_are_views_that_keep_their_buffer_alive():
    time_s = np.arange(0, 0.05, 1e-4)

    def constant(g):
        return napkin.transform({"cg_x": np.full(time_s.size, g), "cg_y": np.zeros(time_s.size),
                                 "cg_z": np.zeros(time_s.size)}, time_s=time_s, array="3a-cg")

    result = constant(10.0)
    # Views of one buffer napkin computed them in, not copies.
    assert len({id(values.base) for values in result.channels.values()}) == 1
    assert all(not values.flags.owndata for values in result.channels.values())
    acc, time = result.channels["acc_body_x_g"], result.channels["time_s"]
    del result
    constant(20.0)  # allocates and frees as much again
    # 10 g throughout, conditioned (CFC 1000 keeps a constant)
    np.testing.assert_allclose(acc, 10.0, rtol=1e-9)
    np.testing.assert_array_equal(time, time_s)


def test_threads_transform_side_by_side(tmp_path):
    # The computation runs without the GIL: tests transformed on threads equal the serial results.
    from concurrent.futures import ThreadPoolExecutor
    db = tmp_path / "threads.db"
    run_napkin("init", "--db", db)
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", "denton-3222", "--count", "4")
    catalogue = napkin.Catalogue(db)
    inputs = [catalogue.test_inputs(test_id) for test_id in catalogue.tests()]
    serial = [napkin.transform(**test).summary for test in inputs]
    with ThreadPoolExecutor(max_workers=2) as pool:
        threaded = [result.summary for result in pool.map(lambda test: napkin.transform(**test), inputs)]
    assert threaded == serial


def _pulse_on_3a_cg():
    """A 10 ms, 60 g half-sine along x on the 3a-cg array: its peak shows the filter class."""
    time_s = np.arange(0, 0.05, 1e-4)
    pulse = 60.0 * np.sin(np.pi * np.clip(time_s / 0.01, 0, 1)) ** 2
    return time_s, {"cg_x": pulse, "cg_y": np.zeros_like(pulse), "cg_z": np.zeros_like(pulse)}


def test_a_changed_config_file_is_read_again(tmp_path):
    # Presets and config files are read once per version of the file, never served stale.
    time_s, channels = _pulse_on_3a_cg()
    config = tmp_path / "filter.json"
    config.write_text(json.dumps({"name": "filter", "filter": {"linear_cfc": 1000.0}}))
    cfc1000 = napkin.transform(channels, time_s=time_s, array="3a-cg", config=config).summary["peak_acc_g"]
    config.write_text(json.dumps({"name": "filter", "filter": {"linear_cfc": 60.0}, "description": "CFC 60"}))
    cfc60 = napkin.transform(channels, time_s=time_s, array="3a-cg", config=config).summary["peak_acc_g"]
    assert cfc60 < cfc1000 - 1.0  # CFC 60 rounds the 10 ms pulse's peak off
    assert cfc1000 == napkin.transform(channels, time_s=time_s, array="3a-cg").summary["peak_acc_g"]


def test_a_config_rewritten_within_one_timestamp_tick_is_read_again(tmp_path):
    # A file rewritten in place at the same size and within the same tick of its
    # modification time (restored here with os.utime, as a fast editor or a
    # coarse filesystem clock would leave it) is its new content, not the cache's.
    time_s, channels = _pulse_on_3a_cg()
    config = tmp_path / "filter.json"
    config.write_text(json.dumps({"name": "filter", "filter": {"linear_cfc": 1000.0}}))
    before = os.stat(config)
    cfc1000 = napkin.transform(channels, time_s=time_s, array="3a-cg", config=config).summary["peak_acc_g"]
    config.write_text(json.dumps({"name": "filter", "filter": {"linear_cfc": 60.000}}).replace("60.0", "60.000"))
    os.utime(config, ns=(before.st_atime_ns, before.st_mtime_ns))
    after = os.stat(config)
    assert (after.st_size, after.st_mtime_ns) == (before.st_size, before.st_mtime_ns)
    cfc60 = napkin.transform(channels, time_s=time_s, array="3a-cg", config=config).summary["peak_acc_g"]
    assert cfc60 < cfc1000 - 1.0  # CFC 60 rounds the 10 ms pulse's peak off
