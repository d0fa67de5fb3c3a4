"""napkin.Catalogue on the demo catalogue equals the CLI: query and compare
rows equal `--format json`, channels() equals `export --format csv`."""

import json

import numpy as np
import pytest

import napkin
from conftest import cells_of, cli_error, read_csv_cells, run_napkin

KINDS = ["tests", "hic", "rotation", "criteria", "risk", "quality", "conditioning", "correlation"]


def cli_json(*args):
    return json.loads(run_napkin(*args, "--format", "json").stdout)


@pytest.mark.parametrize("kind", KINDS)
def test_query_equals_cli_json(demo_catalogue, kind):
    catalogue = napkin.Catalogue(demo_catalogue)
    expected = cli_json("--db", demo_catalogue, "query", kind)
    # The demo's tests have no screening findings and no stored ratings.
    assert expected or kind in ("quality", "correlation"), kind
    assert catalogue.query(kind) == expected


def test_query_filters_equal_cli_json(demo_catalogue):
    catalogue = napkin.Catalogue(demo_catalogue)
    expected = cli_json("--db", demo_catalogue, "query", "hic", "--where", "hic15>300", "--where",
                        "variant!=foam-a", "--sort", "hic15:desc", "--limit", "4", "--series", "padding-series")
    assert len(expected) == 4
    rows = catalogue.query("hic", where=["hic15>300", "variant!=foam-a"], sort="hic15:desc", limit=4,
                           series="padding-series")
    assert rows == expected
    assert catalogue.tests() == [row["test_id"] for row in cli_json("--db", demo_catalogue, "query", "tests")]


def test_query_frame_equals_cli_json(demo_catalogue):
    pandas = pytest.importorskip("pandas", reason="python3-pandas is not installed")
    expected = cli_json("--db", demo_catalogue, "query", "criteria")
    frame = napkin.Catalogue(demo_catalogue).query_frame("criteria")
    assert list(frame.columns) == list(expected[0])
    assert len(frame) == len(expected)
    for i, row in enumerate(expected):
        for column, value in row.items():
            cell = frame[column].iloc[i]
            if value is None:
                assert pandas.isna(cell), (i, column)
            else:
                assert cell == value, (i, column)
    # An empty result keeps the query's columns (those of the same query with rows).
    hic_columns = list(cli_json("--db", demo_catalogue, "query", "hic")[0])
    empty = napkin.Catalogue(demo_catalogue).query_frame("hic", where="hic15>1e9")
    assert len(empty) == 0 and list(empty.columns) == hic_columns


def test_query_frame_without_pandas_names_the_package(demo_catalogue, monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` raises ImportError
    with pytest.raises(ImportError, match="python3-pandas"):
        napkin.Catalogue(demo_catalogue).query_frame("hic")


@pytest.mark.parametrize("by,baseline", [("variant", "production"), ("variant", None)])
def test_compare_equals_cli_json(demo_catalogue, by, baseline):
    args = ["--db", demo_catalogue, "compare", "--series", "padding-series", "--by", by]
    if baseline:
        args += ["--baseline", baseline]
    expected = cli_json(*args)
    assert expected
    assert napkin.Catalogue(demo_catalogue).compare("padding-series", by=by, baseline=baseline) == expected
    metrics = cli_json(*args, "--metrics", "hic15,bric")
    assert napkin.Catalogue(demo_catalogue).compare("padding-series", by=by, baseline=baseline,
                                                    metrics=["hic15", "bric"]) == metrics


def test_channels_equal_export_csv(demo_catalogue, tmp_path):
    catalogue = napkin.Catalogue(demo_catalogue)
    test_id = catalogue.tests()[0]
    run_napkin("--db", demo_catalogue, "export", "--test", test_id, "--format", "csv", "--out", tmp_path / "e.csv")
    cells = read_csv_cells(tmp_path / "e.csv")
    channels = catalogue.channels(test_id)
    assert sorted(channels) == sorted(name for name, column in cells.items() if any(column))
    for name, values in channels.items():
        assert cells_of(values) == cells[name], name
    raw = catalogue.channels(test_id, derived=False)
    inputs = catalogue.test_inputs(test_id)
    assert list(raw) == ["time_s", *inputs["channels"]]
    np.testing.assert_array_equal(raw["time_s"], inputs["time_s"])


def test_catalogue_errors_are_the_cli_sentences(demo_catalogue, tmp_path):
    catalogue = napkin.Catalogue(demo_catalogue)
    with pytest.raises(ValueError) as error:
        catalogue.query("hic", where="hic15>>3")
    assert str(error.value) == cli_error("--db", demo_catalogue, "query", "hic", "--where", "hic15>>3")
    with pytest.raises(ValueError) as error:
        catalogue.query("hic", sort="nonsense")
    assert str(error.value) == cli_error("--db", demo_catalogue, "query", "hic", "--sort", "nonsense")
    with pytest.raises(ValueError) as error:
        catalogue.channels("no-such-test")
    assert str(error.value) == cli_error("--db", demo_catalogue, "export", "--test", "no-such-test",
                                         "--format", "csv", "--out", tmp_path / "x.csv")
    with pytest.raises(ValueError) as error:
        catalogue.compare("padding-series", baseline="no-such-variant")
    assert str(error.value) == cli_error("--db", demo_catalogue, "compare", "--series", "padding-series",
                                         "--baseline", "no-such-variant")
    with pytest.raises(ValueError, match="unknown query kind"):
        catalogue.query("hics")
    with pytest.raises(ValueError, match="does not exist"):
        napkin.Catalogue(tmp_path / "missing.db")
    assert not (tmp_path / "missing.db").exists()  # read-only: nothing created
