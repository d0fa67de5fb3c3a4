"""Python's contract is the command's (issue 43, point 12; docs/python.md):
transform needs the array as ``napkin transform`` needs --array, config
takes a dict as array does, the keywords of the unreleased 0.1.0 are gone,
and the presets and the sentence for an unknown one come from the library
(formats/presets.h), the same for every kind."""

import json
import pathlib
import re

import numpy as np
import pytest

import napkin
from conftest import run_napkin

SLOTS = ["cg_x", "cg_y", "cg_z"]
KIND_FOLDERS = {"array": "arrays", "processing": "processing", "limits": "limits", "channel-map": "channel-maps"}


def channels(n=200):
    return {slot: np.full(n, 1.0) for slot in SLOTS}


def test_transform_needs_the_array():
    with pytest.raises(TypeError, match="missing 1 required keyword-only argument: 'array'"):
        napkin.transform(channels(), dt_s=1e-4)
    # The options are keywords, as the command's are named: a fourth positional argument is refused.
    with pytest.raises(TypeError, match="positional argument"):
        napkin.transform(channels(), None, 1e-4, "3a-cg")


def test_transform_file_still_takes_the_array_from_the_channel_codes():
    assert napkin.transform_file.__defaults__[0] is None  # array=None: docs/python.md "transform_file"


def test_config_takes_a_dict_as_the_file_holds_it():
    config_path = pathlib.Path(napkin._config_dir()) / "processing" / "default.json"
    as_dict = json.loads(config_path.read_text())
    by_name = napkin.transform(channels(), dt_s=1e-4, array="3a-cg", config="default")
    by_dict = napkin.transform(channels(), dt_s=1e-4, array="3a-cg", config=as_dict)
    by_path = napkin.transform(channels(), dt_s=1e-4, array="3a-cg", config=str(config_path))
    assert by_dict.summary == by_name.summary == by_path.summary
    # A dict that is no config says so in the file reader's words, naming where it came from.
    with pytest.raises(napkin.InputError, match="the processing config given to napkin.transform"):
        napkin.transform(channels(), dt_s=1e-4, array="3a-cg", config=dict(as_dict, unknown_key=1))


def test_the_renamed_keywords_of_0_1_0_are_gone():
    for call in (lambda: napkin.transform(channels(), dt=1e-4, array="3a-cg"),
                 lambda: napkin.hic(np.ones(100), dt=1e-4),
                 lambda: napkin.cfc(np.ones(100), dt=1e-4)):
        with pytest.raises(TypeError, match="unexpected keyword argument 'dt'"):
            call()
    with pytest.raises(TypeError, match="missing 1 required positional argument: 'dt_s'"):
        napkin.hic(np.ones(100))
    assert not hasattr(napkin, "_with_old_keywords") and not hasattr(napkin, "_RENAMED")


def test_presets_are_the_files_of_their_folder():
    config = pathlib.Path(napkin._config_dir())
    for kind, folder in KIND_FOLDERS.items():
        files = sorted(path.stem for path in (config / folder).glob("*.json"))
        assert napkin.presets(kind) == files, kind
        assert files, kind
    assert napkin.presets("limits") == list(napkin.LIMITS)
    with pytest.raises(napkin.InputError, match='preset kind "arrays" is not one of array, processing, limits, '
                                                'channel-map.'):
        napkin.presets("arrays")


def unknown_sentence(call):
    with pytest.raises(napkin.InputError) as error:
        call()
    return str(error.value)


def test_an_unknown_preset_is_one_sentence_for_every_kind(tmp_path, demo_catalogue):
    config = pathlib.Path(napkin._config_dir())
    csv = tmp_path / "t.csv"
    csv.write_text("time_s,cg_x,cg_y,cg_z\n" + "".join("{},1,1,1\n".format(k * 1e-4) for k in range(200)))
    said = {
        "array": unknown_sentence(lambda: napkin.transform(channels(), dt_s=1e-4, array="nope")),
        "processing": unknown_sentence(lambda: napkin.transform(channels(), dt_s=1e-4, array="3a-cg",
                                                                config="nope")),
        "channel-map": unknown_sentence(lambda: napkin.transform_file(csv, array="3a-cg", channel_map="nope")),
        "limits": unknown_sentence(lambda: napkin.Catalogue(demo_catalogue).query("limits", limits="nope")),
    }
    for kind, sentence in said.items():
        expected = '"nope" is neither a file nor a preset in {} (presets: {}).'.format(
            config / KIND_FOLDERS[kind], ", ".join(napkin.presets(kind)))
        assert sentence == expected, kind
    # The command says the same and exits 2 (a usage error) for each kind.
    commands = {
        "array": ["transform", csv, "--array", "nope", "--out", tmp_path / "o.csv"],
        "processing": ["transform", csv, "--array", "3a-cg", "--config", "nope", "--out", tmp_path / "o.csv"],
        "channel-map": ["transform", csv, "--array", "3a-cg", "--channel-map", "nope", "--out", tmp_path / "o.csv"],
        "limits": ["--db", demo_catalogue, "query", "limits", "--limits", "nope"],
    }
    for kind, args in commands.items():
        result = run_napkin(*args, check=False)
        assert result.returncode == 2, (kind, result.stderr)
        assert result.stderr == "napkin: " + said[kind] + "\n", kind
    assert not (tmp_path / "o.csv").exists()
    assert re.fullmatch(r'"nope" is neither a file nor a preset in .+ \(presets: .+\)\.', said["array"])
