"""napkin.Catalogue on the demo catalogue equals the CLI: query and compare
rows equal `--format json`, channels() equals `export --format csv`."""

import json

import numpy as np
import pytest

import napkin
from conftest import cells_of, cli_error, read_csv_cells, run_napkin

# napkin's one table of query kinds (db/query_kinds.h), as the module has it.
KINDS = list(napkin.QUERY_KINDS)
LIMITS_PRESET = "fmvss208"  # for the kinds that take limits


def cli_json(*args):
    return json.loads(run_napkin(*args, "--format", "json").stdout)


def limits_args(kind):
    """The command line's limits of `kind`: those of LIMITS_PRESET for a kind that takes them."""
    return ["--limits", LIMITS_PRESET] if napkin.QUERY_KINDS[kind].takes_limits else []


def test_query_kinds_are_the_command_lines():
    """QUERY_KINDS is the command's list, in its order: that of the sentence refusing another kind."""
    assert KINDS[:3] == ["tests", "hic", "rotation"] and "correlation" in KINDS and "limits" in KINDS
    sentence = cli_error("query", "no-such-kind")
    assert sentence == "the query kind must be {} or {}; it is 'no-such-kind'.".format(", ".join(KINDS[:-1]),
                                                                                       KINDS[-1])
    help_text = run_napkin("query", "--help").stdout
    for kind in napkin.QUERY_KINDS.values():
        assert isinstance(kind.description, str) and kind.description, kind
        assert "  {}  ".format(kind.name.ljust(max(map(len, KINDS)))) + kind.description in help_text, kind
    assert [kind.name for kind in napkin.QUERY_KINDS.values() if kind.takes_limits] == ["limits"]


@pytest.mark.parametrize("kind", KINDS)
def test_query_equals_cli_json(demo_catalogue, kind):
    catalogue = napkin.Catalogue(demo_catalogue)
    expected = cli_json("--db", demo_catalogue, "query", kind, *limits_args(kind))
    # The demo's tests have no screening findings and no stored ratings.
    assert expected or kind in ("quality", "correlation"), kind
    limits = LIMITS_PRESET if napkin.QUERY_KINDS[kind].takes_limits else None
    assert catalogue.query(kind, limits=limits) == expected


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


@pytest.mark.parametrize("kind", KINDS)
def test_query_frame_numbers_are_float64_and_missing_values_nan(demo_catalogue, kind):
    pytest.importorskip("pandas", reason="python3-pandas is not installed")
    expected = cli_json("--db", demo_catalogue, "query", kind, *limits_args(kind))
    limits = LIMITS_PRESET if napkin.QUERY_KINDS[kind].takes_limits else None
    frame = napkin.Catalogue(demo_catalogue).query_frame(kind, limits=limits)
    numeric = {name for name, field in napkin.SUMMARY_FIELDS.items()} | {
        # query limits (docs/formats.md "Limits")
        "value", "limit", "margin_pct", "higher_limit", "points", "max_points",
        "filter_cfc", "prefiltered_cfc", "bias_removed", "bias_t1_s", "bias_t2_s", "time_shift_s",
        # query correlation (docs/formats.md "Correlation ratings")
        "start_s", "end_s", "corridor", "phase", "magnitude", "slope", "overall", "shift_s",
        # query tests and criteria: 1 for a salvaged result (docs/formats.md "Salvage record")
        "salvaged"}
    for column in frame.columns:
        if column in numeric:
            assert frame[column].dtype == np.float64, (kind, column)
        else:
            assert frame[column].dtype == object, (kind, column)
        # Missing is NaN, never None, where the JSON has null.
        assert not any(cell is None for cell in frame[column]), (kind, column)
        nulls = [row[column] is None for row in expected]
        assert frame[column].isna().tolist() == nulls, (kind, column)
        assert all(isinstance(cell, float) and np.isnan(cell)
                   for cell, null in zip(frame[column], nulls) if null), (kind, column)


def test_all_null_and_empty_columns_keep_their_dtype(demo_catalogue):
    pytest.importorskip("pandas", reason="python3-pandas is not installed")
    catalogue = napkin.Catalogue(demo_catalogue)
    conditioning = catalogue.query_frame("conditioning")
    # The demo's channels were not prefiltered and their bias window is unset: all null.
    for column in ("prefiltered_cfc", "bias_t1_s", "bias_t2_s"):
        assert conditioning[column].isna().all() and conditioning[column].dtype == np.float64, column
    assert conditioning["prefiltered_cfc"].mean() != conditioning["prefiltered_cfc"].mean()  # NaN, no error
    empty = catalogue.query_frame("hic", where="hic15>1e9")
    assert len(empty) == 0
    assert all(empty[name].dtype == np.float64 for name in empty.columns if name in napkin.SUMMARY_FIELDS)
    assert empty["test_id"].dtype == object


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
    # The command's sentence, the option named as Python spells it (issue 43 point 8).
    assert str(error.value) == cli_error("--db", demo_catalogue, "query", "hic", "--where", "hic15>>3").replace(
        "--where", "argument 'where'", 1)
    with pytest.raises(ValueError) as error:
        catalogue.query("hic", sort="nonsense")
    assert str(error.value) == cli_error("--db", demo_catalogue, "query", "hic", "--sort", "nonsense").replace(
        "--sort", "argument 'sort'", 1)
    with pytest.raises(ValueError) as error:
        catalogue.channels("no-such-test")
    assert str(error.value) == cli_error("--db", demo_catalogue, "export", "--test", "no-such-test",
                                         "--format", "csv", "--out", tmp_path / "x.csv")
    with pytest.raises(ValueError) as error:
        catalogue.compare("padding-series", baseline="no-such-variant")
    assert str(error.value) == cli_error("--db", demo_catalogue, "compare", "--series", "padding-series",
                                         "--baseline", "no-such-variant")
    with pytest.raises(ValueError) as error:
        catalogue.query("hics")
    assert str(error.value) == cli_error("--db", demo_catalogue, "query", "hics")
    with pytest.raises(ValueError, match="does not exist"):
        napkin.Catalogue(tmp_path / "missing.db")
    assert not (tmp_path / "missing.db").exists()  # read-only: nothing created


def open_files(path):
    """How many of this process's file descriptors are open on `path`."""
    import os
    target = os.path.realpath(path)
    count = 0
    for fd in os.listdir("/proc/self/fd"):
        try:
            count += os.path.realpath(os.readlink("/proc/self/fd/" + fd)) == target
        except OSError:
            pass
    return count


def test_catalogue_is_a_context_manager(demo_catalogue, tmp_path):
    # A copy no other connection of this process has open (SQLite keeps a closed
    # connection's file open while another holds a lock on the same file).
    import shutil
    copy = tmp_path / "copy.db"
    shutil.copyfile(demo_catalogue, copy)
    with napkin.Catalogue(copy) as catalogue:
        assert isinstance(catalogue, napkin.Catalogue) and not catalogue.closed
        rows = catalogue.query("hic")
        channels = catalogue.channels(rows[0]["test_id"])
        assert open_files(copy) == 1
    assert catalogue.closed and "(closed)" in repr(catalogue)
    assert open_files(copy) == 0  # the database connection is closed
    assert rows == cli_json("--db", demo_catalogue, "query", "hic")
    assert np.isfinite(channels["time_s"]).all()  # what was read stays valid
    calls = [lambda: catalogue.tests(), lambda: catalogue.query("hic"), lambda: catalogue.query("hic", where="x>>"),
             lambda: catalogue.channels(rows[0]["test_id"]), lambda: catalogue.test_inputs(rows[0]["test_id"]),
             lambda: catalogue.compare("padding-series")]
    for call in calls:
        with pytest.raises(napkin.CatalogueError) as error:
            call()
        assert str(error.value) == ("catalogue '{}' is closed; open it again with napkin.Catalogue(path) to read "
                                    "from it.".format(copy))
    catalogue.close()  # again: nothing
    assert catalogue.path == str(copy)


def test_a_with_block_that_raises_closes_the_catalogue(demo_catalogue):
    with pytest.raises(KeyError):
        with napkin.Catalogue(demo_catalogue) as catalogue:
            raise KeyError("inside")
    assert catalogue.closed
    explicit = napkin.Catalogue(demo_catalogue)
    explicit.close()
    assert explicit.closed
    with pytest.raises(napkin.CatalogueError, match="is closed"):
        explicit.query_frame("hic")
