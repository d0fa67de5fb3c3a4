"""The three front ends are one library (issue 43 points 5 to 7): an export,
the status and a comparison asked through the command line, `napkin serve` and
this module give the same bytes, fields and numbers, and the same mistake the
same sentence, which names the option as each front end spells it
("--units", "parameter 'units'", "argument 'units'")."""

import io
import json
import pathlib
import re
import subprocess
import time
import urllib.error
import urllib.parse
import urllib.request
import zipfile

import pytest

import napkin
from conftest import NAPKIN_BIN, cli_error, run_napkin


class Service:
    """`napkin --db DB serve` on a free loopback port, stopped (SIGTERM, by its process) at the end."""

    def __init__(self, db, folder):
        self.log = folder / "serve.err"
        with open(self.log, "w") as log:
            self.process = subprocess.Popen([NAPKIN_BIN, "--db", str(db), "serve", "--listen", "127.0.0.1:0"],
                                            stdout=subprocess.DEVNULL, stderr=log, cwd=folder)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            found = re.search(r"listening on http://127\.0\.0\.1:([0-9]+) ", self.log.read_text())
            if found:
                self.base = "http://127.0.0.1:" + found.group(1)
                return
            if self.process.poll() is not None:
                break
            time.sleep(0.05)
        self.stop()
        pytest.fail("napkin serve did not start: " + self.log.read_text())

    def get(self, target):
        """(status, content type, body bytes) of GET target."""
        try:
            with urllib.request.urlopen(self.base + target, timeout=60) as answer:
                return answer.status, answer.headers["Content-Type"], answer.read()
        except urllib.error.HTTPError as error:
            return error.code, error.headers["Content-Type"], error.read()

    def json(self, target):
        status, _, body = self.get(target)
        return status, json.loads(body)

    def stop(self):
        if self.process.poll() is None:
            self.process.terminate()
            self.process.wait(timeout=30)


@pytest.fixture(scope="module")
def catalogue(tmp_path_factory):
    """The demo's catalogue (its padding series, run) with an acceleration-only test added."""
    folder = tmp_path_factory.mktemp("front-ends")
    run_napkin("demo", "--out", folder / "demo")
    db = folder / "demo" / "napkin.db"
    run_napkin("synth", "--db", db, "--scenario", "random", "--array", "3a-cg", "--seed", "5", "--test-id", "accel")
    run_napkin("run", "--db", db)
    return db


@pytest.fixture(scope="module")
def service(catalogue):
    started = Service(catalogue, catalogue.parent)
    yield started
    started.stop()


def query(**parameters):
    """A query string of (name, value or list of values)."""
    pairs = []
    for name, value in parameters.items():
        for item in value if isinstance(value, list) else [value]:
            pairs.append((name, str(item)))
    return urllib.parse.urlencode(pairs)


def folder_files(folder):
    """{relative path: bytes} of every file under `folder`."""
    return {path.relative_to(folder).as_posix(): path.read_bytes()
            for path in sorted(pathlib.Path(folder).rglob("*")) if path.is_file()}


TEST = "padding-series-foam-a-02"

# Each format with the options that change its bytes (lsdyna's units and part, uds' number form,
# isomme's codes); csv and the raw channels with a stored config named.
EXPORT_OPTIONS = {
    "csv": {"config": "default"},
    "json": {},
    "lsdyna": {"units": "english", "part": 4},
    "lcfile": {},
    "isomme": {"position": "13", "dummy_type": "H3"},
    "uds": {"numform": "sun"},
    "channels": {"config": "default"},
    "recorded": {},
}


def test_the_table_is_the_commands_formats():
    assert list(napkin.EXPORT_FORMATS) == list(EXPORT_OPTIONS)
    assert [name for name, row in napkin.EXPORT_FORMATS.items() if row.folder] == ["isomme", "uds"]
    assert [name for name, row in napkin.EXPORT_FORMATS.items() if not row.needs_result] == ["recorded"]
    assert [name for name, row in napkin.EXPORT_FORMATS.items() if row.needs_rotation] == ["lsdyna", "lcfile", "uds"]


@pytest.mark.parametrize("format", list(EXPORT_OPTIONS))
def test_every_export_format_is_the_same_bytes_through_every_front_end(catalogue, service, tmp_path, format):
    options = EXPORT_OPTIONS[format]
    cli_options = [item for name, value in options.items() for item in ("--" + name.replace("_", "-"), value)]
    run_napkin("--db", catalogue, "export", "--test", TEST, "--format", format, "--out", tmp_path / "cli",
               *cli_options)
    with napkin.Catalogue(catalogue) as opened:
        opened.export(TEST, format, tmp_path / "python", **options)
    status, content_type, body = service.get(
        "/api/v1/tests/{}/channels?{}".format(TEST, query(format=format, **options)))
    assert status == 200, body[:300]
    if not napkin.EXPORT_FORMATS[format].folder:
        cli = (tmp_path / "cli").read_bytes()
        assert len(cli) > 1000
        assert (tmp_path / "python").read_bytes() == cli
        assert body == cli
        return
    assert content_type == "application/zip"
    cli = folder_files(tmp_path / "cli")
    assert len(cli) > 2
    assert folder_files(tmp_path / "python") == cli
    with zipfile.ZipFile(io.BytesIO(body)) as archive:
        assert {name: archive.read(name) for name in archive.namelist()} == cli


def test_the_options_change_the_bytes(catalogue, tmp_path):
    """The options reach the writer in every front end (the test above would pass if all were ignored)."""
    with napkin.Catalogue(catalogue) as opened:
        opened.export(TEST, "lsdyna", tmp_path / "si.k")
        opened.export(TEST, "lsdyna", tmp_path / "english.k", units="english")
    assert (tmp_path / "si.k").read_bytes() != (tmp_path / "english.k").read_bytes()


def error_of(service, target):
    status, answer = service.json(target)
    assert 400 <= status < 500, answer
    return answer["error"]


def python_error(function, *args, **kwargs):
    with pytest.raises(napkin.Error) as raised:
        function(*args, **kwargs)
    return str(raised.value)


def test_export_errors_are_one_sentence_in_every_front_end(catalogue, service, tmp_path):
    opened = napkin.Catalogue(catalogue)
    db = str(catalogue)
    # Naming the test, the format or the file: the same sentence everywhere.
    for test_id, format in (("no-such-test", "csv"), ("accel-0001", "lsdyna"), ("accel-0001", "uds")):
        cli = cli_error("--db", db, "export", "--test", test_id, "--format", format, "--out", tmp_path / "x")
        assert python_error(opened.export, test_id, format, tmp_path / "x") == cli
        assert error_of(service, "/api/v1/tests/{}/channels?format={}".format(test_id, format)) == cli
    assert "has no rotation" in cli and "format uds needs" in cli and "csv, json or isomme" in cli
    assert not (tmp_path / "x").exists()
    # Naming an option: as each front end spells it.
    for options, cli_options, sentence in (
            ({"units": "mm"}, ["--units", "mm"], "{} must be si or english; it is 'mm'."),
            ({"part": 0}, ["--part", "0"], "{} must be at least 1; it is 0."),
            ({"numform": "ibm"}, ["--numform", "ibm"], "{} must be ieee, vax or sun; it is 'ibm'.")):
        name = next(iter(options))
        cli = cli_error("--db", db, "export", "--test", TEST, "--format", "lsdyna", "--out", tmp_path / "x",
                        *cli_options)
        assert cli == sentence.format("--" + name)
        assert python_error(opened.export, TEST, "lsdyna", tmp_path / "x", **options) == sentence.format(
            "argument '{}'".format(name))
        assert error_of(service, "/api/v1/tests/{}/channels?format=lsdyna&{}".format(TEST, query(**options))) == \
            sentence.format("parameter '{}'".format(name))
    assert python_error(opened.export, TEST, "xlsx", tmp_path / "x") == (
        "argument 'format' must be csv, json, lsdyna, lcfile, isomme, uds, channels or recorded; it is 'xlsx'.")
    # The catalogue is never an output, by any front end.
    before = catalogue.read_bytes()
    assert "napkin never writes output over it" in python_error(opened.export, TEST, "csv", catalogue)
    assert catalogue.read_bytes() == before


def test_status_is_one_reading_in_the_command_and_the_service(catalogue, service):
    for config in (None, "salvage"):
        cli = json.loads(run_napkin("--db", catalogue, "status", "--format", "json",
                                    *(["--config", config] if config else [])).stdout)
        status, answer = service.json("/api/v1/status" + ("?config=" + config if config else ""))
        assert status == 200
        assert answer["catalogue"] == cli
        assert list(answer["catalogue"]) == list(cli)
        assert cli["path"] == str(catalogue)
        assert cli["config"]["name"] == (config or "default")
    assert cli["pending"] == cli["tests"] > 0  # salvage was never run here


# Combinations of compare's options, as (name, value) pairs: the command's options, the service's
# parameters and Python's arguments.
COMPARISONS = [
    [],
    [("baseline", "foam-b"), ("metrics", "hic15,bric"), ("metrics", "a3ms_g")],
    [("scale", "linear"), ("equivalence", "5")],
    [("scale", "log"), ("equivalence", "2.5"), ("limits", "fmvss208")],
    [("limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m"), ("config", "default"), ("scale", "linear")],
    [("limits", "iihs-small-overlap-head"), ("limits", "fmvss201u"), ("equivalence", "20")],
]


def python_arguments(options):
    arguments = {}
    for name, value in options:
        if name in ("metrics", "limits", "config"):
            arguments.setdefault(name, []).append(value)
        elif name == "equivalence":
            arguments[name] = float(value)
        else:
            arguments[name] = value
    return arguments


def same_numbers(rows, frame):
    """compare's rows (None for null) against compare_frame's (NaN)."""
    assert list(frame.columns) == list(rows[0])
    for i, row in enumerate(rows):
        for column, value in row.items():
            cell = frame[column].iloc[i]
            if value is None:
                assert cell != cell, (i, column)
            else:
                assert cell == value, (i, column, cell, value)


@pytest.mark.parametrize("options", COMPARISONS, ids=lambda options: "&".join(n + "=" + v for n, v in options) or "defaults")
def test_compare_gives_the_same_numbers_through_every_front_end(catalogue, service, options):
    cli_options = [item for name, value in options for item in ("--" + name, value)]
    cli = json.loads(run_napkin("--db", catalogue, "compare", "--series", "padding-series", "--format", "json",
                                *cli_options).stdout)
    assert cli
    status, answer = service.json("/api/v1/compare?series=padding-series&" + urllib.parse.urlencode(options))
    assert status == 200, answer
    assert answer == cli
    with napkin.Catalogue(catalogue) as opened:
        assert opened.compare("padding-series", **python_arguments(options)) == cli
        pandas = pytest.importorskip("pandas", reason="python3-pandas is not installed")
        frame = opened.compare_frame("padding-series", **python_arguments(options))
    assert isinstance(frame, pandas.DataFrame)
    same_numbers(cli, frame)
    for name in ("mean", "p_value", "tost_p_value", "n"):
        assert frame[name].dtype == "float64", name
    assert frame["metric"].dtype == object


def test_compare_errors_are_one_sentence_spelled_by_each_front_end(catalogue, service):
    opened = napkin.Catalogue(catalogue)
    for option, value, sentence in (
            ("by", "colour", "{} must be variant or config; it is 'colour'."),
            ("scale", "cubic", "{} must be log or linear; it is 'cubic'."),
            ("equivalence", "100", "{} must be a margin in percent between 0 and 100 (exclusive), e.g. 10 for "
                                   "±10 %; it is '100'.")):
        assert cli_error("--db", catalogue, "compare", "--series", "padding-series", "--" + option, value) == \
            sentence.format("--" + option)
        assert error_of(service, "/api/v1/compare?series=padding-series&{}={}".format(option, value)) == \
            sentence.format("parameter '{}'".format(option))
        if option != "equivalence":  # Python's is a number (100.0 is '100.0')
            assert python_error(opened.compare, "padding-series", **{option: value}) == \
                sentence.format("argument '{}'".format(option))
    assert python_error(opened.compare, "padding-series", equivalence=100) == (
        "argument 'equivalence' must be a margin in percent between 0 and 100 (exclusive), e.g. 10 for ±10 %; "
        "it is '100.0'.")
    two = ("limits", "fmvss208"), ("limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m")
    cli = cli_error("--db", catalogue, "compare", "--series", "padding-series", *[i for o in two for i in ("--" + o[0], o[1])])
    assert cli.startswith("--limits: FMVSS 208 and Euro NCAP")
    assert error_of(service, "/api/v1/compare?series=padding-series&" + urllib.parse.urlencode(two)) == \
        cli.replace("--limits", "parameter 'limits'", 1)
    assert python_error(opened.compare, "padding-series", limits=[value for _, value in two]) == \
        cli.replace("--limits", "argument 'limits'", 1)
    # A sentence without an option is the same everywhere.
    cli = cli_error("--db", catalogue, "compare", "--series", "no-such-series")
    assert error_of(service, "/api/v1/compare?series=no-such-series") == cli
    assert python_error(opened.compare, "no-such-series") == cli


def test_query_errors_are_one_sentence_spelled_by_each_front_end(catalogue, service):
    """A bad where, sort or limit: the command line's sentence, naming the option as each front end
    spells it ("--sort", "parameter 'sort'", "argument 'sort'")."""
    opened = napkin.Catalogue(catalogue)
    for option, value in (("where", "hic15>>3"), ("where", "nosuchfield=1"), ("sort", "hic16"),
                          ("sort", "hic15:up"), ("limit", "-1")):
        cli = cli_error("--db", catalogue, "query", "hic", "--" + option, value)
        assert cli.startswith("--{} ".format(option)), cli
        assert error_of(service, "/api/v1/query/hic?" + urllib.parse.urlencode({option: value})) == \
            cli.replace("--" + option, "parameter '{}'".format(option), 1)
        if option != "limit":  # Python's is an int, refused by its type
            assert python_error(opened.query, "hic", **{option: value}) == \
                cli.replace("--" + option, "argument '{}'".format(option), 1)
