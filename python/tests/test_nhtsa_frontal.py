"""HIC15 and HIC36 with their windows on three real NHTSA frontal crash tests
equal NHTSA's own programs (the reference table of the recordings' README),
through napkin.transform (acceleration-only array 3a-cg, default config) and
napkin.hic on the conditioned resultant."""

import numpy as np
import pytest

import napkin

# test: (HIC15, t1, t2 in ms), (HIC36, t1, t2 in ms) -- NHTSA-Tools.
REFERENCE = {
    "corolla": ((205.727, 74.7, 89.7), (345.510, 67.6, 103.6)),
    "crv": ((177.693, 74.5, 89.5), (330.697, 58.7, 94.7)),
    "f150": ((189.339, 73.1, 88.1), (317.976, 65.3, 101.3)),
}


def load(path):
    """A recording as published: time_s, ax_g, ay_g, az_g."""
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return data[:, 0], {"cg_x": data[:, 1], "cg_y": data[:, 2], "cg_z": data[:, 3]}


@pytest.mark.parametrize("test", sorted(REFERENCE))
def test_hic_and_windows_equal_nhtsa(nhtsa_dir, test):
    time_s, channels = load(nhtsa_dir / (test + ".csv"))
    result = napkin.transform(channels, time_s=time_s, array="3a-cg", test_id=test)
    summary = result.summary
    for field, (value, t1_ms, t2_ms) in zip(("hic15", "hic36"), REFERENCE[test]):
        # The table gives HIC to 3 decimals and the window to 0.1 ms (one sample).
        assert summary[field] == pytest.approx(value, abs=5e-4), field
        assert summary[field + "_t1_s"] * 1e3 == pytest.approx(t1_ms, abs=1e-6), field
        assert summary[field + "_t2_s"] * 1e3 == pytest.approx(t2_ms, abs=1e-6), field

    # napkin.hic on the conditioned resultant finds the same windows.
    acc = np.column_stack([result.channels["acc_body_" + axis + "_g"] for axis in "xyz"])
    resultant = np.sqrt(np.sum(acc * acc, axis=1))
    dt = (time_s[-1] - time_s[0]) / (len(time_s) - 1)
    for field, window_s in (("hic15", 0.015), ("hic36", 0.036)):
        hic, t1, t2 = napkin.hic(resultant, dt, max_window_s=window_s, t0_s=result.channels["time_s"][0])
        assert hic == pytest.approx(summary[field], rel=1e-9), field  # resultant recomputed here
        assert (t1, t2) == pytest.approx((summary[field + "_t1_s"], summary[field + "_t2_s"]), abs=1e-12), field
    # The risk of the summary is the curve's at its HIC15.
    assert summary["hic15_p_ais3"] == pytest.approx(napkin.hic15_p_ais3(summary["hic15"]), rel=1e-15)
