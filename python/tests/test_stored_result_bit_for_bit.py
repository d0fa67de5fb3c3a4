"""docs/python.md "Catalogue": ``napkin.transform(**catalogue.test_inputs(t),
config=...)`` computes what ``napkin run`` stored under that config, bit for
bit: every summary field, and the derived channels where the config stores
them as float64 (the default's float32 storage keeps 7 significant digits).
For any array: presets, an array imported from a JSON file (an edited copy
of a preset under its name), and a preset's geometry under another name --
the stored geometry travels, not the name."""

import json
import math
import os
import pathlib

import numpy as np

import napkin
from conftest import run_napkin, write_signals_csv


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


def preset_json(name):
    folder = pathlib.Path(os.environ.get("NAPKIN_CONFIG_DIR") or napkin._config_dir())
    return json.loads((folder / "arrays" / (name + ".json")).read_text())


def import_recorded(tmp_path, db, test_id, array_path, seed):
    """Imports into `db`, with the array file `array_path`, a random-motion
    test `napkin synth` recorded with that array (as a signals CSV, exact)."""
    synth_db = tmp_path / (test_id + "-synth.db")
    run_napkin("init", "--db", synth_db)
    run_napkin("synth", "--db", synth_db, "--scenario", "random", "--array", array_path, "--seed", seed)
    with napkin.Catalogue(synth_db) as synth:
        inputs = synth.test_inputs(synth.tests()[0])
    csv = tmp_path / (test_id + ".csv")
    write_signals_csv(csv, inputs["time_s"], inputs["channels"])
    run_napkin("import", "--db", db, "--array", array_path, "--test-id", test_id, csv)


def test_transform_of_the_test_inputs_is_the_stored_result(tmp_path):
    config = float64_config(tmp_path)
    db = tmp_path / "lab.db"
    run_napkin("init", "--db", db)
    run_napkin("synth", "--db", db, "--scenario", "seed-fixed-axis")
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", "denton-3222", "--count", "2",
               "--seed", "3", "--test-id", "denton")
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", "3a-cg", "--seed", "5", "--test-id",
               "accel")
    # An array imported from a JSON file: a copy of the preset with its name kept and
    # its y arm 0.37 in longer (stored as "denton-3222@<hash>").
    edited = preset_json("denton-3222")
    for sensor in edited["sensors"]:
        if sensor["slot"] in ("yarm_z", "yarm_x"):
            sensor["position"][1] += 0.37
    (tmp_path / "edited.json").write_text(json.dumps(edited))
    import_recorded(tmp_path, db, "from-file", tmp_path / "edited.json", 11)
    # A preset's geometry under a name no preset has.
    (tmp_path / "renamed.json").write_text(json.dumps(dict(preset_json("denton-3222"), name="rig-7")))
    import_recorded(tmp_path, db, "renamed", tmp_path / "renamed.json", 12)
    run_napkin("run", "--db", db, "--config", config)

    catalogue = napkin.Catalogue(db)
    arrays = {row["test_id"]: row["array"] for row in catalogue.query("tests")}
    assert arrays == {"seed-fixed-axis": "ideal-3222", "denton-0001": "denton-3222", "denton-0002": "denton-3222",
                      "accel-0001": "3a-cg", "from-file": arrays["from-file"], "renamed": "rig-7"}
    assert arrays["from-file"].startswith("denton-3222@")  # the preset's name, another geometry
    rows = {}
    for kind in ("criteria", "risk"):
        for row in catalogue.query(kind, config="float64"):
            rows.setdefault(row["test_id"], {}).update(row)
    fields = [name for name, field in napkin.SUMMARY_FIELDS.items() if field.group != "quality"]
    assert len(catalogue.tests()) == 6
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
    # The geometry travels: the preset of the file array's name computes something else.
    by_name = napkin.transform(**dict(catalogue.test_inputs("from-file"), array="denton-3222"), config=config)
    assert by_name.summary["peak_omega_radps"] != rows["from-file"]["peak_omega_radps"]
