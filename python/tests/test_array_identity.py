"""The stored geometry is the test's geometry (issue 29 point 6):
``transform(**catalogue.test_inputs(t))`` recomputes what ``napkin run``
stored with the array the test was imported with, also when that is an
edited copy of a preset under the preset's name, or an array no preset
names."""

import json
import os
import pathlib

import napkin
from conftest import run_napkin, write_signals_csv


def preset_json(name):
    folder = pathlib.Path(os.environ.get("NAPKIN_CONFIG_DIR") or napkin._config_dir())
    return json.loads((folder / "arrays" / (name + ".json")).read_text())


def recorded_csv(tmp_path, name, array_path, seed):
    """A random-motion test that `napkin synth` records with the array of
    `array_path`, exported as a signals CSV (raw channels, exact)."""
    db = tmp_path / (name + "-synth.db")
    run_napkin("init", "--db", db)
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", array_path, "--seed", seed)
    catalogue = napkin.Catalogue(db)
    inputs = catalogue.test_inputs(catalogue.tests()[0])
    path = tmp_path / (name + ".csv")
    write_signals_csv(path, inputs["time_s"], inputs["channels"])
    return path


def test_recomputation_uses_the_stored_array(tmp_path):
    edited = preset_json("denton-3222")  # its name kept, the y arm 0.4 in longer
    for sensor in edited["sensors"]:
        if sensor["slot"] in ("yarm_z", "yarm_x"):
            sensor["position"][1] += 0.4
    edited_path = tmp_path / "my-denton.json"
    edited_path.write_text(json.dumps(edited))
    rig = dict(preset_json("denton-3222"), name="rig-no-preset")
    rig_path = tmp_path / "rig.json"
    rig_path.write_text(json.dumps(rig))

    db = tmp_path / "lab.db"
    run_napkin("init", "--db", db)
    run_napkin("import", "--db", db, "--array", "denton-3222", "--test-id", "t-preset",
               recorded_csv(tmp_path, "preset", "denton-3222", 5))
    run_napkin("import", "--db", db, "--array", edited_path, "--test-id", "t-edited",
               recorded_csv(tmp_path, "edited", edited_path, 6))
    run_napkin("import", "--db", db, "--array", rig_path, "--test-id", "t-rig",
               recorded_csv(tmp_path, "rig", rig_path, 7))
    run_napkin("run", "--db", db)

    catalogue = napkin.Catalogue(db)
    stored = {row["test_id"]: row["hic15"] for row in catalogue.query("hic")}
    for test_id in ("t-preset", "t-edited", "t-rig"):
        inputs = catalogue.test_inputs(test_id)
        assert napkin.transform(**inputs).summary["hic15"] == stored[test_id], test_id
    arrays = {row["test_id"]: row["array"] for row in catalogue.query("tests")}
    assert arrays["t-preset"] == "denton-3222"
    assert arrays["t-edited"].startswith("denton-3222@") and len(arrays["t-edited"]) == len("denton-3222@") + 12
    assert arrays["t-rig"] == "rig-no-preset"
    # The stored definition is the edited one (in metres), not the preset's.
    inputs = catalogue.test_inputs("t-edited")
    assert isinstance(inputs["array"], dict)
    yarm_z = next(s for s in inputs["array"]["sensors"] if s["slot"] == "yarm_z")
    assert abs(yarm_z["position"][1] - 2.3 * 0.0254) < 1e-15
    # The preset of that name would compute something else.
    by_name = napkin.transform(**dict(inputs, array="denton-3222"))
    assert by_name.summary["hic15"] != stored["t-edited"]
