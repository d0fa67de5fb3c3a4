"""napkin.hic, napkin.cfc, napkin.bric and the risk curves against analytic truth."""

import math

import numpy as np
import pytest

import napkin


def test_hic_of_a_constant_pulse():
    # A constant a over the whole record: every window has mean a, so
    # HIC = a^2.5 * d is largest for the longest window allowed.
    dt, a = 1e-4, 100.0
    record = np.full(201, a)  # 20 ms
    hic, t1, t2 = napkin.hic(record, dt)  # 15 ms windows by default
    assert hic == pytest.approx(a ** 2.5 * 0.015, rel=1e-12)
    # Every 15 ms window scores a^2.5 * 15 ms up to round-off, which picks one of them.
    assert t2 - t1 == pytest.approx(0.015, abs=1e-12) and 0.0 <= t1 <= 0.005 + 1e-12
    hic, t1, t2 = napkin.hic(record, dt, max_window_s=None)
    assert hic == pytest.approx(a ** 2.5 * 0.020, rel=1e-12)
    assert (t1, t2) == pytest.approx((0.0, 0.020), abs=1e-12)


def test_hic_equals_an_exhaustive_search():
    rng = np.random.default_rng(5)
    dt = 1e-4
    acc = np.abs(rng.normal(0, 1, 400)).cumsum() % 60.0  # saw teeth, g
    integral = np.concatenate([[0.0], np.cumsum((acc[1:] + acc[:-1]) * dt / 2)])
    best = (0.0, 0.0, 0.0)
    steps = int(round(0.015 / dt))
    for i in range(len(acc)):
        for j in range(i + 1, min(len(acc), i + steps + 1)):
            d = (j - i) * dt
            value = d * ((integral[j] - integral[i]) / d) ** 2.5
            if value > best[0]:
                best = (value, i * dt, j * dt)
    hic, t1, t2 = napkin.hic(acc, dt)
    assert hic == pytest.approx(best[0], rel=1e-12)
    assert (t1, t2) == pytest.approx(best[1:], abs=1e-12)


def test_hic_is_a_named_tuple():
    dt, a = 1e-4, 100.0
    result = napkin.hic(np.full(201, a), dt, max_window_s=None, t0_s=-0.005)
    assert isinstance(result, napkin.HIC) and isinstance(result, tuple)
    assert result._fields == ("hic", "t1_s", "t2_s")
    assert result.hic == pytest.approx(a ** 2.5 * 0.020, rel=1e-12)
    assert (result.t1_s, result.t2_s) == pytest.approx((-0.005, 0.015), abs=1e-12)
    value, t1_s, t2_s = result  # unpacks as before
    assert (value, t1_s, t2_s) == (result.hic, result.t1_s, result.t2_s)
    assert napkin.hic(np.full(201, a), dt) == napkin.hic(np.full(201, a), dt, max_window_s=0.015)


def test_cfc_keeps_the_passband_and_removes_the_stopband():
    dt = 1e-5
    t = np.arange(0, 0.2, dt)
    slow = np.sin(2 * np.pi * 20 * t)
    filtered = napkin.cfc(slow + 0.5 * np.sin(2 * np.pi * 20000 * t), dt, cfc=1000)
    # SAE J211: CFC 1000 passes 20 Hz (gain 1 within 0.5 dB) and removes 20 kHz (> 40 dB down).
    assert np.max(np.abs(filtered[2000:-2000] - slow[2000:-2000])) < 0.01
    np.testing.assert_allclose(napkin.cfc(np.full(500, 3.0), 1e-4), 3.0, rtol=1e-12)


def test_bric_at_the_critical_values():
    critical = np.array([66.25, 56.45, 42.87])  # Takhounts 2013
    omega = np.outer(np.sin(np.linspace(0, np.pi, 101)), critical)  # each axis peaks at its critical value
    assert napkin.bric(omega) == pytest.approx(math.sqrt(3.0), rel=1e-12)
    assert napkin.bric(omega, critical_radps=2 * critical) == pytest.approx(math.sqrt(3.0) / 2, rel=1e-12)


def test_risk_curves():
    # NCAP HIC15 -> AIS 3+: lognormal, 50 % at exp(7.45231).
    assert napkin.hic15_p_ais3(math.exp(7.45231)) == pytest.approx(0.5, abs=1e-12)
    # Prasad-Mertz HIC36 -> AIS 4+: 1 / (1 + exp(4.9 + 200/HIC - 0.00351 HIC)).
    assert napkin.hic36_p_ais4(1000.0) == pytest.approx(1 / (1 + math.exp(4.9 + 0.2 - 3.51)), rel=1e-12)
    # Takhounts BrIC: Weibull, 1 - 1/e at the scale.
    assert napkin.bric_p_ais3(0.987) == pytest.approx(1 - math.exp(-1), rel=1e-12)
    assert napkin.bric_p_ais4(1.204) == pytest.approx(1 - math.exp(-1), rel=1e-12)
    values = napkin.bric_p_ais3(np.array([0.5, 0.987, 2.0]))
    assert values.shape == (3,) and values[1] == pytest.approx(1 - math.exp(-1))
    assert set(napkin.RISK_CURVES) == {"hic15_p_ais3", "hic36_p_ais4", "bric_p_ais3", "bric_p_ais4"}


def test_summary_fields_carry_the_labels_and_units_of_the_report():
    fields = napkin.SUMMARY_FIELDS
    assert list(fields)[:3] == ["hic15", "hic15_t1_s", "hic15_t2_s"]
    assert fields["peak_acc_g"] == napkin.SummaryField(
        "peak_acc_g", "hic", "peak acceleration", "g", "peak resultant CG acceleration, fixed frame (g)",
        None, None, None)
    assert fields["bric_p_ais3"].label == "P(AIS 3+ | BrIC)"
    assert (fields["bric_p_ais3"].criterion, fields["bric_p_ais3"].ais, fields["bric_p_ais3"].source) == \
        ("bric", 3, "Takhounts")
    assert napkin.RISK_CURVES == tuple(name for name, field in fields.items() if field.group == "risk")
    # Each risk function is its field's curve at its criterion.
    for name in napkin.RISK_CURVES:
        assert fields[fields[name].criterion].criterion is None
        assert callable(getattr(napkin, name))
