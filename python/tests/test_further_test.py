"""The chance that a further test exceeds a limit, and its expected points on
a sliding scale (issue 44; docs/algorithms.md "A further test"), against an
independent implementation: scipy's Student's t (`stats.t.sf`, `stats.t.pdf`)
and its adaptive quadrature (`integrate.quad`), to 1e-10, on values generated
here and on the demo's padding series as `napkin compare --limits` gives them.
Also the limit presets as Python lists them (napkin.LIMITS) and
Catalogue.limits_frame against `napkin query limits`. scipy is Debian's
python3-scipy (`make deps`): without it this test fails, it does not skip."""

import json
import math

try:
    import numpy as np
    from scipy import integrate, stats
except ImportError as error:  # pragma: no cover - the failure is the point
    raise RuntimeError("test_further_test needs Debian's python3-scipy (make deps installs it): " +
                       str(error)) from error

import pytest

import napkin
from conftest import run_napkin

TOLERANCE = 1e-10
EURO_NCAP = "euro-ncap-aop-v9.3-frontal-head-hiii50m"


def reference_exceed(values, limit):
    """1 - T_{n-1}((ln L - m) / (s sqrt(1 + 1/n))) with scipy's t upper tail."""
    logs = np.log(np.asarray(values, dtype=float))
    n = len(logs)
    m, s = float(np.mean(logs)), float(np.std(logs, ddof=1))
    return float(stats.t.sf((math.log(limit) - m) / (s * math.sqrt(1 + 1 / n)), n - 1))


def reference_points(values, higher, lower, points):
    """The expected points of a further test on a sliding scale, by scipy's quad over the t density."""
    logs = np.log(np.asarray(values, dtype=float))
    n = len(logs)
    m, scale = float(np.mean(logs)), float(np.std(logs, ddof=1)) * math.sqrt(1 + 1 / n)
    t_full, t_zero = (math.log(higher) - m) / scale, (math.log(lower) - m) / scale
    between, _ = integrate.quad(
        lambda u: (lower - math.exp(m + scale * u)) / (lower - higher) * stats.t.pdf(u, n - 1), t_full, t_zero,
        epsabs=1e-14, epsrel=1e-13, limit=200)
    return points * (float(stats.t.cdf(t_full, n - 1)) + between)


def relative(actual, expected):
    return abs(actual - expected) / max(abs(expected), 1e-300)


def test_exceed_probability_is_scipys_t_on_generated_values():
    generator = np.random.default_rng(44)
    checked, worst = 0, 0.0
    for n in (3, 4, 5, 8, 20, 60):
        for sigma in (0.02, 0.15, 0.6):
            values = np.exp(generator.normal(math.log(600.0), sigma, n))
            logs = np.log(values)
            scale = np.std(logs, ddof=1) * math.sqrt(1 + 1 / n)
            # Limits from far below to far above the tests: P from near 1 to about 1e-9.
            for z in (-6.0, -2.0, -0.5, 0.0, 0.7, 2.5, 6.0, 15.0):
                limit = float(math.exp(np.mean(logs) + z * scale))
                actual = napkin.exceed_probability(values, limit)
                expected = reference_exceed(values, limit)
                worst = max(worst, relative(actual, expected))
                assert relative(actual, expected) <= TOLERANCE, (n, sigma, z, actual, expected)
                checked += 1
    assert checked == 6 * 3 * 8
    print("exceed_probability vs scipy: {} values, largest relative difference {:.2e}".format(checked, worst))


def test_no_estimate_from_too_few_tests_or_no_spread():
    assert math.isnan(napkin.exceed_probability([600.0, 650.0], 700.0))
    assert math.isnan(napkin.exceed_probability([600.0, 600.0, 600.0], 700.0))
    assert math.isnan(napkin.exceed_probability([600.0, 0.0, 650.0], 700.0))
    with pytest.raises(ValueError, match="limit must be a positive number"):
        napkin.exceed_probability([600.0, 610.0, 650.0], 0.0)
    with pytest.raises(TypeError, match="values"):
        napkin.exceed_probability("600", 700.0)


@pytest.fixture(scope="module")
def padding(demo_catalogue):
    """compare --limits fmvss201u --limits EURO_NCAP's rows, and each variant's values by metric."""
    rows = json.loads(run_napkin("--db", demo_catalogue, "compare", "--series", "padding-series", "--metrics",
                                 "hic15,hic_d,a3ms_g", "--limits", "fmvss201u", "--limits", EURO_NCAP, "--format",
                                 "json").stdout)
    criteria = json.loads(run_napkin("--db", demo_catalogue, "query", "criteria", "--series", "padding-series",
                                     "--format", "json").stdout)
    values = {}
    for row in criteria:
        for metric in ("hic15", "hic_d", "a3ms_g"):
            values.setdefault((metric, row["variant"]), []).append(row[metric])
    return rows, values


def test_compare_gives_scipys_chance_and_expected_points_for_each_variant(padding, demo_catalogue):
    rows, values = padding
    scales = {"hic15": (500.0, 700.0), "a3ms_g": (72.0, 80.0)}
    seen = set()
    for row in rows:
        what = "{}/{}".format(row["metric"], row["group"])
        if row["limit"] is None:  # peak_acc_g, the hard-contact rule's: compared, not limited
            assert row["metric"] == "peak_acc_g" and row["exceed_probability"] is None, what
            continue
        group_values = values[(row["metric"], row["group"])]
        assert row["limits"] == ("FMVSS 201U" if row["metric"] == "hic_d" else "Euro NCAP v9.3 frontal head (HIII 50M)")
        expected = reference_exceed(group_values, row["limit"])
        assert relative(row["exceed_probability"], expected) <= TOLERANCE, (what, row["exceed_probability"], expected)
        if row["metric"] in scales:
            higher, lower = scales[row["metric"]]
            assert row["limit"] == lower, what
            points = reference_points(group_values, higher, lower, 4.0)
            assert abs(row["expected_points"] - points) <= 1e-9, (what, row["expected_points"], points)
            # The 80 % interval: the points of the 90 % and 10 % predictive quantiles.
            logs = np.log(group_values)
            n = len(logs)
            scale = np.std(logs, ddof=1) * math.sqrt(1 + 1 / n)
            for key, p in (("points_low", 0.9), ("points_high", 0.1)):
                x = math.exp(np.mean(logs) + scale * stats.t.ppf(p, n - 1))
                reference = 4.0 * min(1.0, max(0.0, (lower - x) / (lower - higher)))
                assert abs(row[key] - reference) <= 1e-7, (what, key, row[key], reference)
            # (The expected points may lie outside the 80 % interval: the 10 % of tests beyond it count too.)
            assert 0.0 <= row["points_low"] <= row["points_high"] <= 4.0, what
        else:
            assert row["expected_points"] is None and row["points_low"] is None, what
        seen.add(row["metric"])
    assert seen == {"hic15", "hic_d", "a3ms_g"}
    # Python's compare gives the command's rows.
    with napkin.Catalogue(demo_catalogue) as catalogue:
        assert catalogue.compare("padding-series", metrics="hic15,hic_d,a3ms_g",
                                 limits=["fmvss201u", EURO_NCAP]) == rows
        with pytest.raises(napkin.InputError, match="both limit hic15"):
            catalogue.compare("padding-series", limits=["fmvss208", EURO_NCAP])


def test_limits_lists_every_preset_with_its_source():
    presets = run_napkin("query", "limits", check=False)  # the usage error lists the presets
    listed = presets.stderr.split("presets: ")[1].rstrip(").\n").split(", ")
    assert sorted(napkin.LIMITS) == sorted(listed)
    assert EURO_NCAP in napkin.LIMITS and "iihs-small-overlap-head" in napkin.LIMITS
    for preset, limits in napkin.LIMITS.items():
        assert limits.preset == preset
        assert limits.source and limits.url and limits.name, preset
    assert "version 9.3 (December 2023)" in napkin.LIMITS[EURO_NCAP].source
    assert napkin.LIMITS[EURO_NCAP].version == "9.3 (December 2023)"
    assert "DAMAGE" in napkin.LIMITS["euro-ncap-aop-v9.3-mpdb-head-thor50m"].note


def test_limits_frame_is_the_commands_query_limits(demo_catalogue):
    command = json.loads(run_napkin("--db", demo_catalogue, "query", "limits", "--limits", EURO_NCAP, "--series",
                                    "padding-series", "--format", "json").stdout)
    with napkin.Catalogue(demo_catalogue) as catalogue:
        frame = catalogue.limits_frame(EURO_NCAP, series="padding-series")
        rows = catalogue.query("limits", series="padding-series", limits=EURO_NCAP)
    assert rows == command
    assert list(frame.columns) == list(command[0])
    for column in ("value", "limit", "margin_pct", "higher_limit", "points", "max_points"):
        assert frame[column].dtype == np.float64, column
    heads = frame[frame["kind"] == "combined"]
    assert len(heads) == 15 and set(heads["metric"]) == {"head"}
    # The head's points: the lower of HIC15's and a3ms's, a hard contact assumed (every peak above 80 g).
    for test_id, head in heads.set_index("test_id")["points"].items():
        criteria = frame[(frame["test_id"] == test_id) & (frame["kind"] == "scale")]
        assert head == criteria["points"].min(), test_id
    assert all(text.startswith("assumed (peak_acc_g ") for text in heads["hard_contact"])
