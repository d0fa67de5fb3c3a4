"""napkin from Python: head kinematics and injury criteria of crash-test dummies.

A thin layer over the compiled module ``napkin._napkin``, built from the same
libraries as the ``napkin`` command, so a result here is the command's result
(docs/python.md):

- ``transform(channels, time_s=..., dt_s=..., array=..., ...)`` -- one test's
  raw signals (numpy arrays) to a ``TransformResult``: its summary (the
  ``summary.json`` of ``napkin transform``) and derived channels;
  ``transform_file(path, array=None, ...)`` -- the same of one test file in
  any input format ``napkin import`` reads (DTS SLICEWare CSV, ISO-MME, ...);
- ``hic(resultant_g, dt_s)`` -- HIC and its window, a named tuple ``HIC(hic,
  t1_s, t2_s)``; ``cfc(x, dt_s)`` -- the SAE J211 / ISO 6487 filter;
  ``bric(omega_body_radps)`` -- BrIC;
- the injury-risk curves ``hic15_p_ais3``, ``hic36_p_ais4``, ``bric_p_ais3``,
  ``bric_p_ais4``, element-wise on numbers or numpy arrays; ``RISK_CURVES``
  -- their names;
- ``SUMMARY_FIELDS`` -- a dict name -> ``SummaryField``: each summary field's
  label, unit and meaning (and a risk's curve), as the report and the verdict
  label them;
- ``iso18571(reference, candidate, dt_s, ...)`` -- the ISO/TS 18571 rating of
  a model's (or another test's) curve against a test's, an ``ISO18571Rating``;
- ``Catalogue(path)`` -- a catalogue read-only, a context manager
  (``with napkin.Catalogue(path) as c:``): ``tests()``, ``query()``,
  ``query_frame()``, ``limits_frame()``, ``channels()``, ``export()``,
  ``test_inputs()``, ``compare()``, ``compare_frame()``, ``close()``;
- ``EXPORT_FORMATS`` -- the output formats of ``Catalogue.export`` and
  ``napkin export``, a dict name -> ``ExportFormat`` (what it writes, whether
  it needs a result, the rotation, a folder);
- ``presets(kind)`` -- the preset names of a kind ("array", "processing",
  "limits", "channel-map"), as the command lists them;
- ``LIMITS`` -- the limit presets (config/limits: regulations, Euro NCAP's
  sliding scales, IIHS's bands), a dict preset -> ``LimitPreset`` with its
  source; ``exceed_probability(values, limit)`` -- the chance a further test
  exceeds a limit, as ``compare --limits`` gives it;
- ``QUERY_KINDS`` -- the kinds ``query()`` takes, a dict name -> ``QueryKind``
  (its description and whether it takes ``limits=``), napkin's one table of them;
- ``tune_memory()`` -- raises glibc malloc's thresholds for the process, as
  ``napkin run`` does (never called implicitly).

Numbers: keywords name their unit (``dt_s``, ``orientation_rad``,
``initial_velocity_mps``, ...). Arrays are float64; a missing
value is NaN in arrays and in ``query_frame``'s columns (float64 also when all
missing), None only in the dicts that mirror the command's JSON (``summary``,
``query``).

Errors (docs/python.md "Errors"): every error napkin raises is a
``napkin.Error`` with the sentence the command prints --

- ``InputError`` (also a ValueError): bad input the caller can correct;
- ``ScreeningFailure`` (an InputError): a test that fails screening, its
  ``.findings`` a list of ``Finding(check, channel, severity, detail)``;
- ``CatalogueError`` (also a RuntimeError): a busy, damaged or closed
  catalogue; ``NotFoundError`` (a CatalogueError and an InputError): a
  catalogue file or a test that is not there;
- ``InternalError`` (also a RuntimeError): a bug in napkin.

An argument of the wrong type raises TypeError naming it. Ctrl-C stops a
transform within a fraction of a second (KeyboardInterrupt), and one that
cannot fit in memory is refused up front (MemoryError).

Typing: the package ships type stubs and its PEP 561 marker (py.typed), so
mypy and IDEs check code that uses it.
"""

import collections as _collections
import math as _math
import numbers as _numbers
import os as _os
import warnings as _warnings

from . import _napkin
from ._napkin import bric, tune_memory  # noqa: F401  (the public API)
from ._napkin import (  # noqa: F401  (the public API: napkin's exceptions, python/py_errors.cpp)
    CatalogueError, Error, Finding, InputError, InternalError, NotFoundError, ScreeningFailure)

__version__ = _napkin.__version__

_AT_REST = (0.0, 0.0, 0.0)  # the initial state's default, compared by identity


SummaryField = _collections.namedtuple(
    "SummaryField", ["name", "group", "label", "unit", "meaning", "criterion", "ais", "source"])
SummaryField.__doc__ = """A per-test summary field (docs/formats.md "Per-test summary fields").

name     -- its key in a summary and its column in queries, e.g. "hic15"
group    -- the query that shows it: "hic", "rotation", "risk" or "quality"
label    -- short, for text and plots, e.g. "HIC15", "P(AIS 3+ | HIC15)"
unit     -- e.g. "g", "rad/s"; "" for a number without unit
meaning  -- one line, with the unit
criterion, ais, source -- for an injury risk: the field it is read from, the AIS
                          level of P(AIS >= ais) and its curve's source; else None"""

# The summary fields in the order of the results table, by name: napkin's own table
# (engine/summary_fields.h), so labels and units are those of the report and the verdict.
SUMMARY_FIELDS = {field[0]: SummaryField(*field) for field in _napkin._summary_fields()}

# The injury-risk curves, one function per risk field (hic15_p_ais3, ...).
RISK_CURVES = tuple(name for name, field in SUMMARY_FIELDS.items() if field.criterion is not None)
for _name in RISK_CURVES:
    globals()[_name] = getattr(_napkin, _name)

LimitPreset = _collections.namedtuple(
    "LimitPreset", ["preset", "name", "title", "applies_to", "source", "url", "version", "note", "path"])
LimitPreset.__doc__ = """A limit set of config/limits (docs/formats.md "Limits"), as ``--limits PRESET`` reads it.

preset     -- what ``--limits`` and ``limits=`` take, e.g. "euro-ncap-aop-v9.3-frontal-head-hiii50m"
name       -- short, as the verdict names it, e.g. "FMVSS 208"
title, applies_to -- what the limits are and the test and dummy they are for
source, url -- the public document each number is cited from
version    -- the protocol's version and date ("" where the file gives none)
note       -- what the file leaves out and why ("" where it says nothing)
path       -- the file"""

# The limit presets by name, read with the same function as `--limits` (app/limits.h).
LIMITS = {row[0]: LimitPreset(*row) for row in _napkin._limit_presets()}

exceed_probability = _napkin.exceed_probability

QueryKind = _collections.namedtuple("QueryKind", ["name", "description", "takes_limits"])
QueryKind.__doc__ = """A kind of ``Catalogue.query`` (``napkin query KIND``, docs/formats.md "Query filters").

name         -- what ``kind=`` takes, e.g. "hic"
description  -- what its rows are, as ``napkin query --help`` says
takes_limits -- whether it needs ``limits=`` (a preset of ``LIMITS`` or a limits JSON file)"""

# The query kinds by name, in the command line's order: napkin's one table of them (db/query_kinds.h).
QUERY_KINDS = {row[0]: QueryKind(*row) for row in _napkin._query_kinds()}

ExportFormat = _collections.namedtuple("ExportFormat", ["name", "description", "needs_result", "needs_rotation",
                                                        "folder"])
ExportFormat.__doc__ = """An output format of ``napkin export`` and ``Catalogue.export`` (app/export.h).

name           -- what ``format=`` and ``--format`` take, e.g. "csv", "lsdyna"
description    -- what it writes
needs_result   -- whether the test must have a result (False: its channels as recorded)
needs_rotation -- whether an acceleration-only test (no rotation) is refused
folder         -- whether it is a folder of files (``path`` names a folder)"""

# The formats in the command's order, read from the library's one table of them.
EXPORT_FORMATS = {row[0]: ExportFormat(*row) for row in _napkin._export_formats()}

__all__ = ["transform", "transform_file", "TransformResult", "Catalogue", "hic", "HIC", "cfc", "bric", "iso18571", "ISO18571Rating",
           "SummaryField", "SUMMARY_FIELDS", "RISK_CURVES", "LimitPreset", "LIMITS", "QueryKind", "QUERY_KINDS",
           "ExportFormat", "EXPORT_FORMATS", "presets", "exceed_probability",
           "tune_memory", "Error", "InputError",
           "ScreeningFailure", "Finding", "CatalogueError", "NotFoundError", "InternalError", *RISK_CURVES]


HIC = _collections.namedtuple("HIC", ["hic", "t1_s", "t2_s"])
HIC.__doc__ = """What ``hic`` finds (docs/algorithms.md "Injury criteria"); unpacks as
``value, t1_s, t2_s = napkin.hic(...)``.

hic        -- the largest HIC over the windows searched
t1_s, t2_s -- its window (s, from the first sample plus t0_s)"""


def hic(resultant_g, dt_s, max_window_s=_napkin._HIC15_WINDOW_S, from_time_zero=False, t0_s=0.0):
    """HIC of a resultant acceleration ``resultant_g`` (g, a 1-D array) sampled
    every ``dt_s`` seconds: a ``HIC(hic, t1_s, t2_s)``, the exact maximum over
    windows up to ``max_window_s`` (0.015, HIC15; None: no limit), times in s
    from the first sample plus ``t0_s``. ``from_time_zero`` (NHTSA's program)
    integrates |a| and ignores samples before t = 0. Without a window of
    positive integral the value is 0 and t1_s = t2_s = the first sample used.
    Bad input (a non-positive dt_s or window, a non-finite sample) raises
    InputError."""
    return HIC(*_napkin.hic(resultant_g, dt_s, max_window_s, from_time_zero, t0_s))


def cfc(x, dt_s, cfc=_napkin._CFC1000, variant="sae"):
    """``x`` (a 1-D array sampled every ``dt_s`` seconds, any unit) filtered by
    the two-pass channel frequency class filter of SAE J211 (``variant``
    "sae") or ISO 6487 ("iso") of class ``cfc`` (1000, 600, 180, 60: the class
    number, in Hz as the standards write it); a new array. Bad input raises
    InputError."""
    return _napkin.cfc(x, dt_s, cfc, variant)


ISO18571Rating = _collections.namedtuple(
    "ISO18571Rating", ["corridor", "phase", "magnitude", "slope", "overall", "grade", "shift_s"])
ISO18571Rating.__doc__ = """An ISO/TS 18571 rating (docs/algorithms.md "Test against model: ISO/TS 18571").

corridor, phase, magnitude, slope -- the four scores in [0, 1]
overall -- 0.4 corridor + 0.2 (phase + magnitude + slope)
grade   -- "excellent" (overall > 0.94), "good" (> 0.80), "fair" (> 0.58) or "poor"
shift_s -- the shift of the candidate that correlates best with the reference
           (s; positive when the candidate lags)"""


def iso18571(reference, candidate, dt_s, start_s=None, end_s=None, edition="2024"):
    """ISO/TS 18571 rating of ``candidate`` against ``reference``.

    reference, candidate -- 1-D arrays sampled every ``dt_s`` seconds from t = 0
                            (e.g. a test's channel and a model's, in one unit)
    start_s, end_s       -- the evaluation interval (s; None: the arrays' common span)
    edition              -- "2024" (default, dynamic time warping within 10 % of the
                            interval) or "2014" (warping without a window)

    The curves are rated at their own sampling (the standard asks for 10 kHz:
    resample first when they are not). Returns an ``ISO18571Rating``; bad input
    (too few samples, a non-finite sample, a reference that is zero throughout,
    an interval outside the arrays) raises ValueError.
    """
    return ISO18571Rating(*_napkin._iso18571(reference, candidate, dt_s, start_s, end_s, edition))


# The configuration folder every preset is read from, as the library finds it
# (formats/presets.h: $NAPKIN_CONFIG_DIR, else the one installed beside this
# package, else the build's).
_config_dir = _napkin._config_dir


def presets(kind):
    """The names of the presets of ``kind`` -- "array", "processing", "limits"
    or "channel-map" -- in name order: what ``array=``, ``config=``,
    ``limits=`` and ``channel_map=`` take besides a JSON file (or, for array
    and config, a dict), the list the error for an unknown name gives
    (docs/formats.md "Presets"). Another kind raises InputError."""
    return _napkin._presets(kind)


class TransformResult:
    """What ``transform`` computed for one test.

    summary      -- dict equal to the ``summary.json`` of ``napkin transform``
                    (criteria, windows, risks, ``quality`` findings, ``conditioning``)
    channels     -- dict column name -> numpy array, named and scaled as the
                    derived-channel CSV (acc in g, angles in degrees, else SI);
                    an acceleration-only array gives time_s and acc_body_* only
    conditioning -- list of dicts, what conditioning did to each channel
    salvage      -- dict, the salvage record when screening.salvage excluded or
                    repaired a faulty channel (mode, channels with fault, action,
                    interval_s and samples_replaced, RMS residual before and
                    after); None for a result of the recorded channels
    """

    def __init__(self, summary, channels):
        self.summary = summary
        self.channels = channels
        self.conditioning = summary.get("conditioning", [])
        self.salvage = summary.get("salvage")

    def __repr__(self):
        return "<napkin.TransformResult hic15={} channels={}>".format(
            self.summary.get("hic15"), len(self.channels))


def transform(channels, time_s=None, dt_s=None, *, array, config="default",
              orientation_rad=_AT_REST, initial_velocity_mps=_AT_REST, initial_omega_body_radps=_AT_REST,
              solver=None, test_id=""):
    """Process one test as ``napkin transform`` does.

    channels -- dict slot name -> 1-D array of samples (in the unit the array
                gives the slot: g, rad/s), or a 2-D array (samples x slots) in
                the array's slot order
    time_s   -- the sample times (s), uniformly spaced; or give dt_s (the
                sampling interval, s) and the first sample is at t = 0
    array    -- required, as ``--array`` (napkin never guesses the array): an
                array preset name (``presets("array")``: "denton-3222",
                "3a-cg", ...), an array JSON path, or an array definition as a
                dict (the JSON file's content, e.g. the stored definition
                ``Catalogue.test_inputs`` returns)
    config   -- a processing config preset name (``presets("processing")``),
                a JSON path, or a config as a dict (the JSON file's content)
    orientation_rad          -- initial orientation phi, theta, psi (rad)
    initial_velocity_mps     -- initial CG velocity in the fixed frame (m/s)
    initial_omega_body_radps -- initial angular velocity in body axes (rad/s; usually at rest)
    solver   -- None (the config's), or a solver name as ``--solver``
    test_id  -- the summary's test_id, and the start of error sentences

    Everything after dt_s is a keyword, as the command's options are named.

    Raises InputError (a ValueError) for bad input -- a name that is neither a
    file nor a preset included, with the sentence ``napkin transform`` exits 2
    with --, ScreeningFailure (an InputError with ``.findings``) for a test
    that fails screening (the sentence ``napkin transform`` exits 1 with),
    TypeError naming an argument of the wrong type (complex samples
    included), MemoryError when the test cannot fit in the memory available
    (checked before anything is copied); the computation runs without the
    GIL, and Ctrl-C stops it (KeyboardInterrupt).
    """
    summary, derived = _napkin.transform(
        channels, time_s, dt_s, array, config, orientation_rad, initial_velocity_mps,
        initial_omega_body_radps, solver, test_id)
    return TransformResult(summary, derived)


def transform_file(path, array=None, channel_map=None, position=None, columns=None, config="default",
                   orientation_rad=_AT_REST, initial_velocity_mps=_AT_REST, solver=None):
    """Process one test file as ``napkin transform PATH`` does, in any input
    format ``napkin import`` reads (napkin's CSV, DTS SLICEWare CSV, an ISO-MME
    test folder or .mme file, UDS-1992 files, a zip archive; docs/formats.md).

    path        -- the test file or folder (one test)
    array       -- array preset name or JSON path; None: the one the channels'
                   ISO/TS 13499 codes define (head CG accelerometers and
                   angular-rate sensors: 6aw-cg; accelerometers alone: 3a-cg)
    channel_map -- channel map preset or JSON path (None: "default")
    position    -- the dummy head to take, of a test that records several
    columns     -- dict slot -> CSV column name (``--column SLOT=NAME``)
    config, orientation_rad, initial_velocity_mps, solver -- as ``transform``
                  (config a preset name, a JSON path or a dict)

    Returns a TransformResult equal to the command's summary.json and derived
    channels; the reader's warnings (ignored columns, cropped spans) are
    issued as UserWarning. Raises InputError (one sentence naming the file,
    row and channel) for a file napkin does not read, ScreeningFailure for a
    test that fails screening.
    """
    summary, derived, warnings = _napkin.transform_file(
        path, array, channel_map, position, columns, config, orientation_rad, initial_velocity_mps,
        solver)
    for warning in warnings:
        _warnings.warn(warning, stacklevel=2)
    return TransformResult(summary, derived)


_NAN = float("nan")


def _json_cells(column):
    """A typed query column as the values of ``--format json``'s rows: a
    float64 array's NaN (and any non-finite number, which JSON cannot hold)
    as None."""
    if isinstance(column, list):
        return [None if isinstance(value, float) and not _math.isfinite(value) else value for value in column]
    return [value if _math.isfinite(value) else None for value in column.tolist()]


def _described(value):
    text = repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    kind = type(value).__name__
    return "{} ({} {})".format(text, "an" if kind[:1].lower() in "aeiou" else "a", kind)


def _names(value, what, meaning):
    """None, or a list of str from a str or a list (tuple, ...) of them; any
    other type raises TypeError naming `what`."""
    if value is None:
        return None
    if isinstance(value, str):
        return [value]
    if isinstance(value, (list, tuple)):
        for item in value:
            if not isinstance(item, str):
                raise TypeError("{} holds {}, which is not {} (a str).".format(what, _described(item), meaning))
        return list(value)
    raise TypeError("{} is {}, not {} (a str) or a list of them.".format(what, _described(value), meaning))


def _path(value, what):
    if isinstance(value, str):
        return value
    if hasattr(value, "__fspath__"):
        path = _os.fsdecode(value)
        if isinstance(path, str):
            return path
    raise TypeError("{} is {}, not a file path (a str or a pathlib.Path).".format(what, _described(value)))


def _pandas(method):
    try:
        import pandas
    except ImportError as error:
        raise ImportError("napkin.Catalogue.{} needs pandas: install it with "
                          "`sudo apt install python3-pandas` (or pip install pandas).".format(method)) from error
    return pandas


def _frame(pandas, columns, values):
    """Typed columns (a float64 array, or a list with None for NULL) as a
    DataFrame: the arrays as they are, the lists of dtype object with NaN for
    None."""
    import numpy
    data = {}
    for name, column in zip(columns, values):
        if not isinstance(column, numpy.ndarray):
            column = numpy.array([_NAN if cell is None else cell for cell in column], dtype=object)
        data[name] = column
    return pandas.DataFrame(data, columns=columns)


def _compare_options(series, by, baseline, metrics, config, limits, scale, equivalence):
    """compare's arguments as the (name, value) pairs of the command's options,
    for the library's one parser (app::ParseCompareRequest); None is an
    option not given."""
    what = "napkin.Catalogue.compare: "
    if baseline is not None and not isinstance(baseline, str):
        raise TypeError("{}baseline is {}, not a group name (a str).".format(what, _described(baseline)))
    if scale is not None and not isinstance(scale, str):
        raise TypeError("{}scale is {}, not a scale name (a str: \"log\" or \"linear\").".format(
            what, _described(scale)))
    if equivalence is not None and (isinstance(equivalence, bool) or not isinstance(equivalence, _numbers.Real)):
        raise TypeError("{}equivalence is {}, not a margin in percent (a number).".format(
            what, _described(equivalence)))
    if limits is not None and hasattr(limits, "__fspath__"):
        limits = _path(limits, what + "limits")
    if isinstance(limits, (list, tuple)):
        limits = [_path(item, what + "limits") if hasattr(item, "__fspath__") else item for item in limits]
    options = [("series", str(series))]
    if by is not None:
        options.append(("by", str(by)))
    if baseline is not None:
        options.append(("baseline", baseline))
    for name, values in (("metrics", _names(metrics, what + "metrics", "a summary field")),
                         ("config", _names(config, what + "config", "a stored config's name or hash prefix")),
                         ("limits", _names(limits, what + "limits", "a limits preset or file"))):
        options.extend((name, value) for value in values or [])
    if scale is not None:
        options.append(("scale", scale))
    if equivalence is not None:
        # repr: the shortest text that reads back as the same double.
        options.append(("equivalence", repr(float(equivalence))))
    return options


class Catalogue:
    """A napkin catalogue opened read-only (writing stays with the CLI).

    A context manager: ``with napkin.Catalogue(path) as catalogue: ...``
    closes it at the end of the block; ``close()`` does so at any time, and
    any use after that raises CatalogueError. ``query`` rows are those of
    ``napkin query --format json`` (None for null), ``query_frame`` a pandas
    DataFrame (float64 numbers, NaN for missing values).
    """

    def __init__(self, path):
        self._catalogue = None
        self._catalogue = _napkin.Catalogue(_path(path, "napkin.Catalogue: path"))

    @property
    def path(self):
        """The catalogue's file, as given."""
        return self._catalogue.path

    @property
    def closed(self):
        """Whether ``close()`` was called."""
        return self._catalogue.closed

    def close(self):
        """Closes the catalogue's database connection (a second call does
        nothing); any use after it raises CatalogueError. Arrays read from it
        stay valid."""
        self._catalogue.close()

    def __enter__(self):
        return self

    def __exit__(self, *exception):
        self.close()

    def __repr__(self):
        if self._catalogue is None:
            return "<napkin.Catalogue (not opened)>"
        return "<napkin.Catalogue {!r}{}>".format(self.path, " (closed)" if self.closed else "")

    def tests(self):
        """The test ids, in order."""
        return [row["test_id"] for row in self.query("tests")]

    def _query(self, kind, where, sort, limit, config, series, variant, limits=None):
        """(column names, one value per column: a float64 array for a numeric
        column, NaN for NULL; else a list, None for NULL)."""
        what = "napkin.Catalogue.query: "
        if not isinstance(kind, str):
            raise TypeError("{}kind is {}, not a query kind (a str).".format(what, _described(kind)))
        if limit is not None and (isinstance(limit, bool) or not isinstance(limit, _numbers.Integral)):
            raise TypeError("{}limit is {}, not a whole number of rows (an int).".format(what, _described(limit)))
        if config is not None and not isinstance(config, str):
            raise TypeError("{}config is {}, not a stored config's name or hash prefix (a str).".format(
                what, _described(config)))
        if limits is not None and not isinstance(limits, str) and not hasattr(limits, "__fspath__"):
            raise TypeError("{}limits is {}, not a limits preset or file (a str or a pathlib.Path).".format(
                what, _described(limits)))
        return self._catalogue.query(
            kind, _names(where, what + "where", "a filter expression"),
            _names(sort, what + "sort", "a sort key"), None if limit is None else str(limit), config,
            _names(series, what + "series", "a series name"), _names(variant, what + "variant", "a variant name"),
            None if limits is None else _path(limits, what + "limits"))

    def query(self, kind, where=None, sort=None, limit=None, config=None, series=None, variant=None, limits=None):
        """``napkin query KIND`` as a list of dicts, the rows of ``--format json``
        (None where the JSON has null).

        kind    -- a name of ``QUERY_KINDS``: tests, hic, rotation, criteria, risk, ... (an unknown one
                   raises ValueError with the sentence of ``napkin query``)
        where   -- an expression (or a list, all must hold), e.g. "hic15>700 and variant=foam-a"
        sort    -- "FIELD[:desc]" (or a list)
        limit   -- at most this many rows
        config  -- results of this stored config (name or hash prefix; default: each test's latest)
        series, variant -- only tests of this series / variant (or any of a list)
        limits  -- a kind that takes limits (``QUERY_KINDS[kind].takes_limits``: limits): the limit set,
                   a preset of ``LIMITS`` or a JSON file
        """
        columns, values = self._query(kind, where, sort, limit, config, series, variant, limits)
        cells = [_json_cells(column) for column in values]
        return [dict(zip(columns, row)) for row in zip(*cells)] if cells else []

    def query_frame(self, kind, where=None, sort=None, limit=None, config=None, series=None, variant=None,
                    limits=None):
        """``query`` as a pandas DataFrame, columns in the query's order: each
        numeric column float64 (also when every cell is missing), the others
        of dtype object; a missing value is NaN in either."""
        pandas = _pandas("query_frame")
        return _frame(pandas, *self._query(kind, where, sort, limit, config, series, variant, limits))

    def limits_frame(self, limits, where=None, sort=None, limit=None, config=None, series=None, variant=None):
        """``napkin query limits --limits LIMITS`` as a pandas DataFrame (``query_frame``):
        per test and criterion its value, the limit (and a scale's higher_limit),
        margin_pct, and ``meets`` (a maximum), ``points`` and ``max_points`` (a
        sliding scale) or ``band`` (bands); a set that combines its criteria
        (Euro NCAP's head) adds a row per test, metric ``head``, kind
        ``combined``, with the hard-contact rule's finding.

        limits -- a preset of ``LIMITS`` or a limits JSON file
        """
        return self.query_frame("limits", where, sort, limit, config, series, variant, limits)

    def channels(self, test_id, derived=True, config=None):
        """One test's channels as a dict name -> numpy array.

        derived=True: its result's derived channels, as ``napkin export --format
        csv`` writes them (config: the stored config's name or hash prefix;
        default: its latest result). derived=False: its raw channels (time_s and
        one per slot, in the slot's unit).
        """
        return self._catalogue.channels(str(test_id), bool(derived), config)

    def export(self, test_id, format, path, config=None, units=None, part=None, numform=None, position=None,
               dummy_type=None, force=False):
        """``napkin export --test TEST_ID --format FORMAT --out PATH``: the same
        bytes, by the command's writer (docs/formats.md; ``EXPORT_FORMATS``
        lists the formats). The arguments are the command's options, read by
        the same parser (its sentences name them "argument 'units'"):

        format     -- csv, json, lsdyna, lcfile, isomme, uds (a folder), channels or recorded
        path       -- the file to write (written atomically), or for a folder format the
                      folder whose files appear beside what it holds
        config     -- the result under this stored config (name or hash prefix; default:
                      the test's latest result), as ``channels``
        units      -- lsdyna: "si" (default) or "english"
        part       -- lsdyna: the rigid part id (an int, default 1)
        numform    -- uds: "ieee" (default), "vax" or "sun"
        position, dummy_type -- isomme: the channel codes' (default: the test's stored ones)
        force      -- a folder format: replace files of the same names in the folder

        The catalogue itself is never written (refused in a sentence naming it).
        """
        what = "napkin.Catalogue.export: "
        options = []
        for name, value in (("format", format), ("config", config), ("units", units), ("numform", numform),
                            ("position", position), ("dummy_type", dummy_type)):
            if value is None:
                continue
            if not isinstance(value, str):
                raise TypeError("{}{} is {}, not a str.".format(what, name, _described(value)))
            options.append((name, value))
        if part is not None:
            if isinstance(part, bool) or not isinstance(part, _numbers.Integral):
                raise TypeError("{}part is {}, not a part id (an int).".format(what, _described(part)))
            options.append(("part", str(int(part))))
        self._catalogue.export(str(test_id), options, _path(path, what + "path"), bool(force))

    def test_inputs(self, test_id):
        """What ``napkin run`` computes the test's result from, as ``transform``'s
        keyword arguments: test_id, array (the test's stored array definition
        as a dict, the JSON its record holds: the geometry it was imported
        with, even where its name is a preset's), time_s,
        channels (slot -> raw samples), orientation_rad, initial_velocity_mps,
        initial_omega_body_radps. ``transform(**catalogue.test_inputs(t), config=c)``
        computes what ``napkin run --config c`` stores for it, bit for bit."""
        return self._catalogue.test_inputs(str(test_id))

    def compare(self, series, by="variant", baseline=None, metrics=None, config=None, limits=None, scale=None,
                equivalence=None):
        """``napkin compare --series S --format json`` as a list of dicts, the
        command's rows (None where the JSON has null). The arguments are the
        command's options, read by the same parser (its sentences name them
        "argument 'metrics'"):

        by          -- "variant" (Welch's t) or "config" (paired t over the same tests)
        baseline    -- the group the others are compared with (default: first by name)
        metrics     -- summary fields, as a list or as ``--metrics`` spells them
                       ("hic15,bric"); default: the command's
        config      -- a stored config's name or hash prefix, or a list of them
        limits      -- limit sets (presets of ``LIMITS`` or files), one or a list:
                       each row of a limited metric gains limit, tests_within_limit,
                       worst_test, limit_margin_pct, limits, and for a further test
                       exceed_probability, expected_points, points_low, points_high
                       (None where not estimated: fewer than 3 tests, no spread)
        scale       -- "log" (default: ratio metrics as ratios of geometric means) or "linear"
        equivalence -- the equivalence margin in % (0 to 100, exclusive; default 10)
        """
        columns, values = self._catalogue.compare(
            _compare_options(series, by, baseline, metrics, config, limits, scale, equivalence), False)
        cells = [_json_cells(column) for column in values]
        return [dict(zip(columns, row)) for row in zip(*cells)] if cells else []

    def compare_frame(self, series, by="variant", baseline=None, metrics=None, config=None, limits=None,
                      scale=None, equivalence=None):
        """``compare`` as a pandas DataFrame, columns in the command's order:
        each numeric column float64 (NaN where the JSON has null), the text
        columns (metric, group, baseline, scale, worst_test, limits) of dtype
        object."""
        pandas = _pandas("compare_frame")
        return _frame(pandas, *self._catalogue.compare(
            _compare_options(series, by, baseline, metrics, config, limits, scale, equivalence), True))
