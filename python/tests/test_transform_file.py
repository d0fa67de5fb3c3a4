"""napkin.transform_file reads a test file as `napkin transform` does, in any
input format `napkin import` reads (docs/python.md "transform_file"): a DTS
SLICEWare CSV export (issue 46) and napkin's own CSV give the command's
summary and derived-channel cells bit for bit, and a bad export raises the
command's sentence."""

import json
import math

import pytest

import napkin
from conftest import cli_error, read_csv_cells, run_napkin, write_signals_csv
from test_transform import assert_same_as_cli

RATE_HZ = 20000.0
SAMPLES = 400
# The 6DX headform's channels in its order: angular rates (deg/sec) then accelerations (g).
SIX_DX = [("D0HEADCG0000AVZC", "deg/sec ", "6DX0855-AV3"), ("D0HEADCG0000AVYC", "deg/sec ", "6DX0855-AV2"),
          ("D0HEADCG0000AVXC", "deg/sec ", "6DX0855-AV1"), ("D0HEADCG0000ACZA", "g ", "6DX0855-AC3"),
          ("D0HEADCG0000ACYA", "g ", "6DX0855-AC2"), ("D0HEADCG0000ACXA", "g ", "6DX0855-AC1")]


def pulse(k, height, width):
    """A haversine pulse of `height` over the first `width` samples."""
    return height * (1 - math.cos(2 * math.pi * k / width)) / 2 if k < width else 0.0


def write_6dx_export(path, units=None):
    """A SLICEWare CSV export of a 6DX headform (CRLF, a value per channel and a trailing comma a row)."""
    units = units or [unit for _, unit, _ in SIX_DX]
    values = [[pulse(k, (c + 1) * 40.0, 300 - 20 * c) for k in range(SAMPLES)] for c in range(len(SIX_DX))]
    rows = []

    def row(name, cells):
        rows.append(name + "," + "".join(str(cell) + "," for cell in cells))

    row("Headers", [""] * 6)
    row("Test ID", ["PY-6DX"] * 6)
    row("Sample Rate (Hz)", ["20000"] * 6)
    row("Hardware AA Filter (-3dB)", ["4300"] * 6)
    row("ISO Channel Code", [code for code, _, _ in SIX_DX])
    row("Sensor S/N", [serial for _, _, serial in SIX_DX])
    row("Software Filter (SAE Class)", ["None"] * 6)
    row("Engineering Unit", units)
    row("Data Starts Here", [""] * 6)
    row("Time", ["Chan {}:{}".format(c, serial) for c, (_, _, serial) in enumerate(SIX_DX)])
    for k in range(SAMPLES):
        row(repr((k - 40) / RATE_HZ), [repr(values[c][k]) for c in range(6)])
    path.write_bytes(("\r\n".join(rows) + "\r\n").encode())


def cli_transform_file(tmp_path, path, *extra):
    out, summary = tmp_path / "out.csv", tmp_path / "summary.json"
    run_napkin("transform", path, *extra, "--out", out, "--summary", summary)
    return json.loads(summary.read_text()), read_csv_cells(out)


def test_dts_slice_export_equals_the_command(tmp_path):
    export = tmp_path / "fh1_UNFILTERED.csv"
    write_6dx_export(export)
    result = napkin.transform_file(export)  # the array from the codes: 6aw-cg
    summary, cells = cli_transform_file(tmp_path, export)
    assert_same_as_cli(result, summary, cells)
    assert result.summary["test_id"] == "PY-6DX"  # the export's Test ID
    assert napkin.transform_file(export, array="6aw-cg").summary == summary


def test_napkins_csv_equals_the_command(tmp_path):
    signals = tmp_path / "t1.csv"
    time_s = [k / 10000.0 for k in range(300)]
    write_signals_csv(signals, time_s, {"cg_x": [pulse(k, 50.0, 200) for k in range(300)],
                                        "cg_y": [0.0] * 300, "cg_z": [pulse(k, -20.0, 150) for k in range(300)]})
    result = napkin.transform_file(signals, array="3a-cg")
    summary, cells = cli_transform_file(tmp_path, signals, "--array", "3a-cg")
    assert_same_as_cli(result, summary, cells)
    with pytest.raises(napkin.InputError, match=r"names slots, not sensors, so its array must be given \(array=\)"):
        napkin.transform_file(signals)


def test_a_bad_export_raises_the_commands_sentence(tmp_path):
    export = tmp_path / "bad.csv"
    write_6dx_export(export, units=["deg/sec "] * 3 + ["g ", "gee ", "g "])
    sentence = cli_error("transform", export, "--out", tmp_path / "out.csv")
    assert 'row 8 ("Engineering Unit"), channel "Chan 4:6DX0855-AC2" (D0HEADCG0000ACYA)' in sentence
    with pytest.raises(napkin.InputError) as raised:
        napkin.transform_file(export)
    assert str(raised.value) == sentence
    with pytest.raises(TypeError, match="columns"):
        napkin.transform_file(export, columns=["cg_x=a"])
