"""`napkin compare --format json` against independent implementations
(issue 30): scipy.stats for Welch's and the paired t on the logs and on the
values, statsmodels for the equivalence tests (ttost_ind, ttost_paired) and
the smallest detectable difference (TTestIndPower, TTestPower), to 1e-9.

The series is the demo's padding series (`napkin synth --scenario padding-series`) (three variants of five tests, by
variant) and the same tests run under a second processing config (by config,
paired). The per-test values come from `napkin query ... --format json`.
scipy and statsmodels are Debian's python3-scipy and python3-statsmodels
(`make deps`): without them this test fails, it does not skip."""

import json
import math
import os
import shutil

try:
    import numpy as np
    from scipy import stats
    from statsmodels.stats.power import TTestIndPower, TTestPower
    from statsmodels.stats.weightstats import CompareMeans, DescrStatsW, ttost_ind, ttost_paired
except ImportError as error:  # pragma: no cover - the failure is the point
    raise RuntimeError("test_compare_statistics needs Debian's python3-scipy and python3-statsmodels "
                       "(make deps installs them): " + str(error)) from error

import pytest

from conftest import run_napkin

TOLERANCE = 1e-9
MARGIN = 0.10  # the default --equivalence 10
RATIO_METRICS = {"hic15", "hic36", "hic", "hic_d", "bric", "damage", "peak_acc_g", "a3ms_g", "peak_omega_x_radps",
                 "peak_omega_y_radps", "peak_omega_z_radps", "peak_omega_radps", "peak_alpha_radps2"}
# Every default metric of compare, and two linear ones.
METRICS = ["hic15", "hic36", "hic_d", "peak_acc_g", "a3ms_g", "peak_omega_radps", "peak_alpha_radps2", "bric",
           "damage", "max_rotation_deg", "hic15_p_ais3", "bric_p_ais3", "bric_p_ais4"]

worst = {}  # the largest difference seen per quantity, printed at the end


def close(actual, expected, what):
    """actual (from napkin's JSON) equals expected to 1e-9, relative above 1."""
    assert actual is not None, what + " is null"
    difference = abs(actual - expected) / max(1.0, abs(expected))
    worst[what.split(" ")[-1]] = max(worst.get(what.split(" ")[-1], 0.0), difference)
    assert difference <= TOLERANCE, "{}: napkin {!r}, reference {!r}".format(what, actual, expected)


def compare_json(db, *args):
    return json.loads(run_napkin("--db", db, "compare", "--series", "padding-series", "--metrics",
                                 ",".join(METRICS), "--format", "json", *args).stdout)


def values_by(db, key, *args):
    """{group: {test_id: {field: value}}} of query criteria and risk."""
    rows = {}
    for kind in ("criteria", "risk"):
        for row in json.loads(run_napkin("--db", db, "query", kind, "--series", "padding-series", "--format", "json",
                                         *args).stdout):
            rows.setdefault(row[key] if key else None, {}).setdefault(row["test_id"], {}).update(row)
    return rows


def t_quantile_975(df):
    """t_{0.975, df} from scipy's beta quantile (Boost's inverse incomplete beta): P(|T| > q) = 0.05
    where df / (df + q^2) is the 0.05 quantile of Beta(df/2, 1/2). scipy 1.10's t.ppf (Cephes) is off by
    up to 2e-9 for fractional df (checked against mpmath), more than the tolerance of this test."""
    x = stats.beta.ppf(0.05, df / 2, 0.5)
    return math.sqrt(df * (1 - x) / x)


def check_row(row, scale, a, b, paired):
    """One non-baseline row against scipy and statsmodels; a, b: the values (paired: aligned)."""
    what = "{}/{}".format(row["metric"], row["group"])
    assert row["scale"] == scale, what
    log = scale == "log"
    x, y = (np.log(a), np.log(b)) if log else (np.asarray(a), np.asarray(b))
    if paired:
        result = stats.ttest_rel(x, y)
        described = DescrStatsW(x - y)
        q = t_quantile_975(described.nobs - 1)
        low, high = described.mean - q * described.std_mean, described.mean + q * described.std_mean
        tost_p = ttost_paired(np.asarray(a), np.asarray(b), 1 - MARGIN, 1 + MARGIN, transform=np.log)[0] if log else \
            ttost_paired(np.asarray(a), np.asarray(b), -MARGIN * abs(np.mean(b)), MARGIN * abs(np.mean(b)))[0]
        sd = np.std(x - y, ddof=1)
    else:
        result = stats.ttest_ind(x, y, equal_var=False)
        # statsmodels' Welch standard error and Welch–Satterthwaite df, the quantile as above.
        means = CompareMeans(DescrStatsW(x), DescrStatsW(y))
        q = t_quantile_975(means.dof_satt())
        se = means.std_meandiff_separatevar
        low, high = np.mean(x) - np.mean(y) - q * se, np.mean(x) - np.mean(y) + q * se
        tost_p = ttost_ind(np.asarray(a), np.asarray(b), 1 - MARGIN, 1 + MARGIN, usevar="unequal",
                           transform=np.log)[0] if log else \
            ttost_ind(np.asarray(a), np.asarray(b), -MARGIN * abs(np.mean(b)), MARGIN * abs(np.mean(b)),
                      usevar="unequal")[0]
        sd = math.sqrt(((len(x) - 1) * np.var(x, ddof=1) + (len(y) - 1) * np.var(y, ddof=1)) / (len(x) + len(y) - 2))
    close(row["p_value"], result.pvalue, what + " p_value")
    close(row["tost_p_value"], tost_p, what + " tost_p_value")
    diff = np.mean(x - y) if paired else np.mean(x) - np.mean(y)
    if log:
        close(row["ratio"], math.exp(diff), what + " ratio")
        close(row["ratio_ci_low"], math.exp(low), what + " ratio_ci_low")
        close(row["ratio_ci_high"], math.exp(high), what + " ratio_ci_high")
        close(row["diff_pct"], 100 * math.expm1(diff), what + " diff_pct")
        assert row["ci_low"] is None and row["ci_high"] is None, what
    else:
        close(row["diff"], diff, what + " diff")
        close(row["ci_low"], low, what + " ci_low")
        close(row["ci_high"], high, what + " ci_high")
        assert row["ratio"] is None, what

    # The smallest detectable difference: statsmodels' effect size at power 0.8 ...
    n_a, n_b = len(a), len(b)
    if paired:
        effect = TTestPower().solve_power(effect_size=None, nobs=n_a, alpha=0.05, power=0.8)
    else:
        effect = TTestIndPower().solve_power(effect_size=None, nobs1=n_a, ratio=n_b / n_a, alpha=0.05, power=0.8)
    delta = effect * sd
    base = abs(np.mean(b))
    expected_high = 100 * math.expm1(delta) if log else 100 * delta / base
    # ... solve_power stops at its own tolerance, so napkin's root is checked where statsmodels is exact:
    # its power at napkin's effect size is 0.8 to 1e-9.
    napkin_delta = math.log1p(row["mdd_high_pct"] / 100) if log else row["mdd_high_pct"] / 100 * base
    napkin_effect = napkin_delta / sd
    if paired:
        power = TTestPower().power(effect_size=napkin_effect, nobs=n_a, alpha=0.05)
    else:
        power = TTestIndPower().power(effect_size=napkin_effect, nobs1=n_a, ratio=n_b / n_a, alpha=0.05)
    close(power, 0.8, what + " mdd_power")
    assert abs(row["mdd_high_pct"] - expected_high) <= 1e-6 * max(1, abs(expected_high)), \
        "{} mdd_high_pct: napkin {}, statsmodels solve_power {}".format(what, row["mdd_high_pct"], expected_high)
    expected_low = 100 * math.expm1(-napkin_delta) if log else -row["mdd_high_pct"]
    close(row["mdd_low_pct"], expected_low, what + " mdd_low_pct")


@pytest.fixture(scope="module")
def padding_catalogue(tmp_path_factory):
    """The padding series of `napkin demo` (synth --scenario padding-series), run with the default config."""
    db = tmp_path_factory.mktemp("padding") / "napkin.db"
    run_napkin("--db", db, "synth", "--scenario", "padding-series")
    run_napkin("--db", db, "run")
    return db


def test_by_variant_matches_scipy_and_statsmodels(padding_catalogue):
    demo_catalogue = padding_catalogue
    rows = compare_json(demo_catalogue, "--baseline", "production")
    values = values_by(demo_catalogue, "variant")
    checked = 0
    for row in rows:
        if row["group"] == "production":
            assert row["p_value"] is None and row["tost_p_value"] is None
            continue
        metric = row["metric"]
        a = [test[metric] for _, test in sorted(values[row["group"]].items())]
        b = [test[metric] for _, test in sorted(values["production"].items())]
        scale = "log" if metric in RATIO_METRICS and min(a + b) > 0 else "linear"
        check_row(row, scale, a, b, paired=False)
        checked += 1
    assert checked == 2 * len(METRICS)
    linear = compare_json(demo_catalogue, "--baseline", "production", "--scale", "linear")
    for row in linear:
        if row["group"] == "production":
            continue
        metric = row["metric"]
        a = [test[metric] for _, test in sorted(values[row["group"]].items())]
        b = [test[metric] for _, test in sorted(values["production"].items())]
        check_row(row, "linear", a, b, paired=False)
    print("largest relative differences, by variant:", worst)


def test_by_config_matches_the_paired_tests(padding_catalogue, tmp_path):
    demo_catalogue = padding_catalogue
    db = tmp_path / "paired.db"
    shutil.copy(demo_catalogue, db)
    # The default processing config with another CFC for the linear channels: the same tests, other values.
    # The presets napkin reads (NAPKIN_CONFIG_DIR in CTest); against the installed package, the
    # checkout's, which the package installs.
    presets = os.environ.get("NAPKIN_CONFIG_DIR") or os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                                  os.pardir, os.pardir, "config")
    with open(os.path.join(presets, "processing", "default.json")) as source:
        config = json.load(source)
    config["name"] = "cfc600"
    config["filter"]["linear_cfc"] = 600.0
    with open(tmp_path / "cfc600.json", "w") as out:
        json.dump(config, out)
    run_napkin("--db", db, "run", "--config", tmp_path / "cfc600.json")
    rows = compare_json(db, "--by", "config", "--baseline", "default")
    default = values_by(db, None, "--config", "default")[None]
    other = values_by(db, None, "--config", "cfc600")[None]
    ids = sorted(set(default) & set(other))
    assert len(ids) == 15
    checked = 0
    for row in rows:
        if row["group"] == "default":
            continue
        metric = row["metric"]
        a = [other[i][metric] for i in ids]
        b = [default[i][metric] for i in ids]
        scale = "log" if metric in RATIO_METRICS and min(a + b) > 0 else "linear"
        check_row(row, scale, a, b, paired=True)
        checked += 1
    assert checked == len(METRICS)
    print("largest relative differences, with by config:", worst)
