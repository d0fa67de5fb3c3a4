"""napkin.iso18571: the ISO/TS 18571 rating as a named tuple, on analytic cases,
against numpy's own corridor and slope formulas, and its refusals."""

import math

import numpy as np
import pytest

import napkin

DT = 1e-4  # 10 kHz


def pulse(n=1000, start=200, width=300, peak=50.0):
    k = np.arange(n)
    x = (k - start) / width
    return np.where((x >= 0) & (x <= 1), 0.5 * peak * (1 - np.cos(2 * np.pi * x)), 0.0)


def test_identical_curves_rate_one_and_excellent():
    t = pulse()
    for edition in ("2014", "2024"):
        r = napkin.iso18571(t, t, dt_s=DT, edition=edition)
        assert isinstance(r, napkin.ISO18571Rating)
        assert r._fields == ("corridor", "phase", "magnitude", "slope", "overall", "grade", "shift_s")
        assert (r.corridor, r.phase, r.magnitude, r.slope, r.overall) == (1.0, 1.0, 1.0, 1.0, 1.0)
        assert r.grade == "excellent" and r.shift_s == 0.0


def test_a_shift_within_the_allowed_range():
    # 50 samples later: the best shift is 5 ms, phase (0.2 N - 50) / (0.2 N) = 0.75,
    # and the shifted curves coincide (magnitude and slope 1).
    r = napkin.iso18571(pulse(), pulse(start=250), DT)
    assert r.shift_s == pytest.approx(0.005, abs=1e-15)
    assert r.phase == pytest.approx(0.75, abs=1e-15)
    assert r.magnitude == 1.0 and r.slope == 1.0


def test_corridor_and_slope_equal_numpy_formulas():
    # The corridor (inner a0 = 0.05, outer b0 = 0.5 of max |T|, exponent 2) and the
    # slope score (central differences, 9-sample centred moving average, eps_S = 2)
    # written here in numpy, for a candidate that does not shift (no phase shift).
    t = pulse()
    c = 1.15 * t + 1.0
    r = napkin.iso18571(t, c, DT)
    assert r.shift_s == 0.0
    inner, outer = 0.05 * t.max(), 0.5 * t.max()
    d = np.abs(c - t)
    z = np.where(d <= inner, 1.0, np.where(d >= outer, 0.0, ((outer - d) / (outer - inner)) ** 2))
    assert r.corridor == pytest.approx(z.mean(), abs=1e-12)

    def smoothed(y):
        g = np.gradient(y, DT)
        out = np.empty_like(g)
        for k in range(len(g)):
            h = min(4, k, len(g) - 1 - k)
            out[k] = g[k - h:k + h + 1].mean()
        return out

    e = np.abs(smoothed(c) - smoothed(t)).sum() / np.abs(smoothed(t)).sum()
    assert r.slope == pytest.approx(max(0.0, 1 - e / 2.0), abs=1e-12)
    assert r.overall == pytest.approx(0.4 * r.corridor + 0.2 * (r.phase + r.magnitude + r.slope), abs=1e-15)


def test_interval_and_grades():
    t = pulse()
    whole = napkin.iso18571(t, -t, DT)
    assert whole.magnitude == 0.0 and whole.grade == "poor"
    part = napkin.iso18571(t, t, DT, start_s=0.02, end_s=0.05)
    assert part.overall == 1.0
    assert napkin.iso18571(t, 1.3 * t, DT).grade in ("good", "fair")


def test_bad_input_is_one_sentence():
    t = pulse()
    with pytest.raises(ValueError, match=r"needs at least 9 samples in the evaluation interval, but it has 5"):
        napkin.iso18571(t[:5], t[:5], DT)
    with pytest.raises(ValueError, match=r"reaches outside napkin.iso18571: candidate"):
        napkin.iso18571(t, t[:500], DT, start_s=0.0, end_s=0.09)
    with pytest.raises(ValueError, match=r"zero throughout the evaluation interval"):
        napkin.iso18571(np.zeros(100), t[:100], DT)
    with pytest.raises(ValueError, match=r'edition "2020" is neither "2014" nor "2024"'):
        napkin.iso18571(t, t, DT, edition="2020")
    bad = t.copy()
    bad[300] = math.nan
    with pytest.raises(ValueError, match=r"non-finite sample"):
        napkin.iso18571(t, bad, DT)
    with pytest.raises(TypeError, match=r"napkin.iso18571: dt_s"):
        napkin.iso18571(t, t, "fast")
