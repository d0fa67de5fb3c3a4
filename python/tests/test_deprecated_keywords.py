"""Keywords name their unit (docs/python.md "Names and units"): dt_s,
orientation_rad, initial_velocity_mps, initial_omega_body_radps. The old
names (dt, orientation, initial_velocity, initial_omega_body) still work for
one release: a DeprecationWarning naming the new keyword, and the same
result, bit for bit."""

import warnings

import numpy as np
import pytest

import napkin
from conftest import run_napkin


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """A synthetic denton-3222 test with an initial orientation and velocity."""
    db = tmp_path_factory.mktemp("deprecated") / "synth.db"
    run_napkin("init", "--db", db)
    run_napkin("synth", "--db", db, "--scenario", "seed-fixed-axis")
    catalogue = napkin.Catalogue(db)
    return catalogue.test_inputs(catalogue.tests()[0])


def no_warning(call):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning fails the call
        return call()


def deprecated(call, old, new):
    """call()'s result; it warns once, a DeprecationWarning naming both keywords."""
    with pytest.warns(DeprecationWarning) as caught:
        result = call()
    messages = [str(warning.message) for warning in caught if warning.category is DeprecationWarning]
    assert len(messages) == 1, messages
    assert "keyword {} is deprecated".format(old) in messages[0] and "use {} ".format(new) in messages[0], messages
    assert caught[0].filename == __file__  # it points at the caller's line
    return result


def same_transform(a, b):
    assert a.summary == b.summary
    assert sorted(a.channels) == sorted(b.channels)
    for name in a.channels:
        assert a.channels[name].tobytes() == b.channels[name].tobytes(), name


def test_test_inputs_use_the_new_keywords(inputs):
    assert {"orientation_rad", "initial_velocity_mps", "initial_omega_body_radps"} <= set(inputs)
    assert not {"orientation", "initial_velocity", "initial_omega_body", "dt"} & set(inputs)
    assert inputs["orientation_rad"] == (0.5, 0.5, 0.5)  # report section 4.5.1
    no_warning(lambda: napkin.transform(**inputs))


@pytest.mark.parametrize("old,new", [("orientation", "orientation_rad"),
                                     ("initial_velocity", "initial_velocity_mps"),
                                     ("initial_omega_body", "initial_omega_body_radps")])
def test_transform_initial_state_keywords(inputs, old, new):
    value = (0.01, -0.02, 0.03) if old == "initial_omega_body" else inputs[new]
    current = no_warning(lambda: napkin.transform(**dict(inputs, **{new: value})))
    renamed = dict(inputs)
    del renamed[new]
    renamed[old] = value
    same_transform(deprecated(lambda: napkin.transform(**renamed), old, new), current)


def test_transform_dt(inputs):
    time_s = inputs["time_s"]
    dt_s = (time_s[-1] - time_s[0]) / (len(time_s) - 1)
    current = no_warning(lambda: napkin.transform(**dict(inputs, time_s=None, dt_s=dt_s)))
    old = deprecated(lambda: napkin.transform(**dict(inputs, time_s=None, dt=dt_s)), "dt", "dt_s")
    same_transform(old, current)


def test_hic_and_cfc_dt():
    rng = np.random.default_rng(3)
    acc = np.abs(rng.normal(0.0, 30.0, 500))
    assert deprecated(lambda: napkin.hic(acc, dt=1e-4), "dt", "dt_s") == no_warning(
        lambda: napkin.hic(acc, dt_s=1e-4)) == napkin.hic(acc, 1e-4)
    filtered = no_warning(lambda: napkin.cfc(acc, dt_s=1e-4, cfc=600))
    old = deprecated(lambda: napkin.cfc(acc, dt=1e-4, cfc=600), "dt", "dt_s")
    assert old.tobytes() == filtered.tobytes() == napkin.cfc(acc, 1e-4, 600).tobytes()


def test_both_names_or_an_unknown_keyword_is_a_type_error(inputs):
    acc = np.ones(100)
    with pytest.warns(DeprecationWarning), pytest.raises(TypeError, match="give dt_s or its deprecated name dt"):
        napkin.hic(acc, 1e-4, dt=1e-4)
    with pytest.warns(DeprecationWarning), pytest.raises(TypeError, match="give orientation_rad or its deprecated"):
        napkin.transform(**dict(inputs, orientation=(0.0, 0.0, 0.0)))
    with pytest.raises(TypeError, match="unexpected keyword argument 'window'"):
        napkin.hic(acc, 1e-4, window=0.015)
    with pytest.raises(TypeError, match="unexpected keyword argument 'dtt'"):
        napkin.transform(**dict(inputs, dtt=1e-4))
    with pytest.raises(TypeError, match="missing required argument: 'dt_s'"):
        napkin.hic(acc)
