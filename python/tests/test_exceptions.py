"""napkin's exceptions (docs/python.md "Errors"): one base class, napkin.Error;
bad input an InputError (a ValueError, as before); a test that fails screening
a ScreeningFailure carrying what screening found, the findings `napkin run`
records for the same test; catalogue problems a CatalogueError (a
RuntimeError, as before); a missing catalogue or test a NotFoundError (both a
CatalogueError and, as before, a ValueError); wrong types TypeError."""

import pathlib

import numpy as np
import pytest

import napkin
from conftest import cli_error, run_napkin, write_signals_csv

SLOTS = ["cg_x", "cg_y", "cg_z"]


def failing_channels():
    """A 3a-cg test with a 5000 g sample: beyond the 2,000 g plausibility limit."""
    channels = {slot: np.full(400, 1.0) for slot in SLOTS}
    channels["cg_x"][100] = 5000.0
    return channels


def test_the_classes_and_their_bases():
    assert issubclass(napkin.InputError, napkin.Error) and issubclass(napkin.InputError, ValueError)
    assert issubclass(napkin.ScreeningFailure, napkin.InputError)
    assert issubclass(napkin.CatalogueError, napkin.Error) and issubclass(napkin.CatalogueError, RuntimeError)
    assert not issubclass(napkin.CatalogueError, ValueError)
    assert issubclass(napkin.NotFoundError, napkin.CatalogueError)
    assert issubclass(napkin.NotFoundError, napkin.InputError)
    assert issubclass(napkin.InternalError, napkin.Error) and issubclass(napkin.InternalError, RuntimeError)
    assert not issubclass(napkin.InputError, RuntimeError)
    for cls in (napkin.Error, napkin.InputError, napkin.ScreeningFailure, napkin.CatalogueError,
                napkin.NotFoundError, napkin.InternalError):
        assert cls.__module__ == "napkin" and cls.__doc__, cls


def test_bad_input_is_an_input_error():
    with pytest.raises(napkin.InputError, match='no channel for slot "cg_y"'):
        napkin.transform({"cg_x": np.ones(10), "cg_z": np.ones(10)}, dt_s=1e-4, array="3a-cg")
    with pytest.raises(napkin.InputError, match="is neither a file nor a preset"):
        napkin.transform(failing_channels(), dt_s=1e-4, array="no-such-array")
    with pytest.raises(napkin.InputError, match='variant "x" is neither'):
        napkin.cfc(np.ones(100), 1e-4, variant="x")


def test_a_failing_test_raises_screening_failure_with_the_findings_run_records(tmp_path):
    channels = failing_channels()
    with pytest.raises(napkin.ScreeningFailure) as raised:
        napkin.transform(channels, dt_s=1e-4, array="3a-cg", test_id="bad")
    error = raised.value
    assert isinstance(error, ValueError)  # code that caught ValueError before still does
    findings = error.findings
    assert findings and all(isinstance(finding, napkin.Finding) for finding in findings)
    failing = [finding for finding in findings if finding.severity == "error"]
    # The sentence is the first error finding's, after the test id.
    assert str(error) == "bad: " + failing[0].detail
    assert failing[0] == napkin.Finding(
        "implausible", "cg_x", "error",
        "channel cg_x reads 5000 g at sample 100 (t = 0.01 s), beyond the plausibility limit of 2000 g: a "
        "corrupt sample or a wrong unit; correct the data (or raise plausibility limits in the processing "
        "config).")

    # `napkin run` records the same findings for the same test (query quality).
    write_signals_csv(tmp_path / "bad.csv", np.arange(400) * 1e-4, channels)
    db = tmp_path / "lab.db"
    run_napkin("init", "--db", db)
    run_napkin("import", "--db", db, "--array", "3a-cg", "--test-id", "bad", tmp_path / "bad.csv")
    assert run_napkin("run", "--db", db, check=False).returncode != 0  # the test fails
    recorded = napkin.Catalogue(db).query("quality")
    assert recorded
    as_tuples = sorted((row["check"], row["channel"], row["severity"], row["detail"]) for row in recorded)
    assert sorted(tuple(finding) for finding in findings) == as_tuples


def test_a_passing_test_raises_nothing_and_its_findings_are_in_the_summary():
    channels = {slot: np.full(400, 1.0) for slot in SLOTS}
    quality = napkin.transform(channels, dt_s=1e-4, array="3a-cg").summary["quality"]
    assert {finding["severity"] for finding in quality} <= {"info", "warning"}
    assert all(set(finding) == set(napkin.Finding._fields) for finding in quality)


def test_catalogue_errors(demo_catalogue, tmp_path):
    # A catalogue that is not there, a test it does not hold: NotFoundError, and ValueError as before.
    with pytest.raises(napkin.NotFoundError, match="does not exist") as raised:
        napkin.Catalogue(tmp_path / "missing.db")
    assert isinstance(raised.value, napkin.CatalogueError) and isinstance(raised.value, ValueError)
    catalogue = napkin.Catalogue(demo_catalogue)
    for call in (lambda: catalogue.test_inputs("no-such-test"), lambda: catalogue.channels("no-such-test")):
        with pytest.raises(napkin.NotFoundError) as raised:
            call()
        assert str(raised.value) == "test 'no-such-test' is not in catalogue '{}'.".format(demo_catalogue)
    # A file that is not a catalogue, a damaged one: CatalogueError (a RuntimeError), the CLI's sentence.
    damaged = tmp_path / "damaged.db"
    damaged.write_bytes(b"this is not an SQLite database, " * 200)
    with pytest.raises(napkin.CatalogueError) as raised:
        napkin.Catalogue(damaged)
    assert isinstance(raised.value, RuntimeError) and not isinstance(raised.value, ValueError)
    assert str(raised.value) == cli_error("--db", damaged, "query", "hic")
    malformed = tmp_path / "malformed.db"
    content = bytearray(pathlib.Path(demo_catalogue).read_bytes())
    page_size = int.from_bytes(content[16:18], "big")
    for page in range(2, len(content) // page_size):  # every page but the schema's: its tables' b-trees
        content[page * page_size:page * page_size + 8] = b"\xff" * 8
    malformed.write_bytes(bytes(content))
    with pytest.raises(napkin.CatalogueError) as raised:
        napkin.Catalogue(malformed).query("hic")
    assert "is damaged" in str(raised.value)
    assert str(raised.value) == cli_error("--db", malformed, "query", "hic")


def test_wrong_types_are_type_errors(demo_catalogue):
    catalogue = napkin.Catalogue(demo_catalogue)
    with pytest.raises(TypeError, match=r"napkin.Catalogue.query: limit is '4' \(a str\)"):
        catalogue.query("hic", limit="4")
    with pytest.raises(TypeError, match="napkin.Catalogue.query: kind is 3"):
        catalogue.query(3)
    with pytest.raises(TypeError, match="napkin.transform: dt_s"):
        napkin.transform(failing_channels(), dt_s="1e-4", array="3a-cg")
