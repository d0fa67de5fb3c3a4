"""docs/python.md "Catalogue": ``napkin.transform(**catalogue.test_inputs(t),
config=...)`` computes what ``napkin run`` stored under that config, bit for
bit: every summary field, and the derived channels where the config stores
them as float64 (the default's float32 storage keeps 7 significant digits)."""

import json
import math
import os
import pathlib

import numpy as np

import napkin
from conftest import run_napkin


def float64_config(tmp_path):
    """The default preset storing its derived channels as float64."""
    folder = pathlib.Path(os.environ.get("NAPKIN_CONFIG_DIR") or napkin._config_dir())
    config = json.loads((folder / "processing" / "default.json").read_text())
    config["name"] = "float64"
    config["storage"]["derived_channels"] = "float64"
    path = tmp_path / "float64.json"
    path.write_text(json.dumps(config))
    return path


def same_number(computed, stored):
    """A summary value against its stored one: NULL in the catalogue is NaN."""
    if stored is None:
        return computed is None or (isinstance(computed, float) and math.isnan(computed))
    return computed == stored


def test_transform_of_the_test_inputs_is_the_stored_result(tmp_path):
    config = float64_config(tmp_path)
    db = tmp_path / "lab.db"
    run_napkin("init", "--db", db)
    run_napkin("synth", "--db", db, "--scenario", "seed-fixed-axis")
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", "denton-3222", "--count", "2",
               "--seed", "3", "--test-id", "denton")
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", "3a-cg", "--seed", "5", "--test-id",
               "accel")
    run_napkin("run", "--db", db, "--config", config)

    catalogue = napkin.Catalogue(db)
    rows = {}
    for kind in ("criteria", "risk"):
        for row in catalogue.query(kind, config="float64"):
            rows.setdefault(row["test_id"], {}).update(row)
    fields = [name for name, field in napkin.SUMMARY_FIELDS.items() if field.group != "quality"]
    assert len(catalogue.tests()) == 4
    for test_id in catalogue.tests():
        result = napkin.transform(**catalogue.test_inputs(test_id), config=config)
        for name in fields:
            assert same_number(result.summary[name], rows[test_id][name]), (test_id, name)
        stored = catalogue.channels(test_id, config="float64")
        assert sorted(result.channels) == sorted(stored), test_id
        for name, values in stored.items():
            assert values.dtype == np.float64
            assert np.array_equal(result.channels[name], values, equal_nan=True), (test_id, name)
            # Bit for bit: the same doubles, not merely equal ones (-0.0 is not 0.0 here).
            assert result.channels[name].tobytes() == values.tobytes(), (test_id, name)
