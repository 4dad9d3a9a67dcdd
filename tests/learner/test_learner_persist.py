"""Saving and loading: a loaded model is the fitted one, scaler included."""

import io
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner_helpers import (
    assert_same_model,
    fixture_module,
    waves,
)
from ndlfd import (
    KeypointHMM,
    ModelFormatError,
    ValidationError,
    synth,
)
from ndlfd._fileformat import load_npz, save_npz
from ndlfd.demonstration import Demonstration
from ndlfd.io import ColumnMapping
from ndlfd.learner._persist import FORMAT_VERSION, input_from_json, input_to_json

DATA = Path(__file__).parents[1] / "data"


def _same_scaler(a, b):
    got, want = vars(a), vars(b)
    assert got.keys() == want.keys()
    for k, v in want.items():
        g = got[k]
        assert np.array_equal(g, v) if isinstance(v, np.ndarray) else g == v, k


@pytest.mark.parametrize("mode", ["group", "per-dimension", "none"])
def test_a_loaded_models_scaler_is_the_fitted_one(mode, tmp_path):
    train, _ = synth.make_dataset("square", n_demos=5, random_state=0)
    m = KeypointHMM(epsilon=0.1, n_time_bins=20, normalization=mode,
                    weights={"velocity": 0.5}).fit(train)  # fmt: skip
    m.save(tmp_path / "m.ndlfd")
    again = KeypointHMM.load(tmp_path / "m.ndlfd")
    _same_scaler(again.scaler_, m.scaler_)
    assert again.scaler_.n_samples_seen_ == sum(d.n_samples for d in train)


def _rewrite_meta(src, dst, edit):
    """The model file ``src`` with its metadata changed by ``edit(meta)``."""
    with zipfile.ZipFile(src) as z:
        members = {n: z.read(n) for n in z.namelist()}
    key = next(n for n in members if n.startswith("__ndlfd__"))
    arr = np.lib.format.read_array(io.BytesIO(members[key]))
    meta = json.loads(str(arr))
    edit(meta)
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.array(json.dumps(meta, sort_keys=True)))
    members[key] = buf.getvalue()
    with zipfile.ZipFile(dst, "w") as z:
        for n, b in members.items():
            z.writestr(n, b)


def _strip_scaler_seen(src, dst):
    """A version-4 file as written before it carried the scaler's extremes."""

    def edit(meta):
        assert meta["version"] == FORMAT_VERSION
        del meta["scaler_seen"]

    _rewrite_meta(src, dst, edit)


def test_a_version_4_file_without_the_scaler_extremes_still_loads(tmp_path):
    train, test = synth.make_dataset("square", n_demos=5, random_state=0)
    m = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
    m.save(tmp_path / "m.ndlfd")
    _strip_scaler_seen(tmp_path / "m.ndlfd", tmp_path / "old.ndlfd")
    old = KeypointHMM.load(tmp_path / "old.ndlfd")
    np.testing.assert_array_equal(old.generate(test.t).X, m.generate(test.t).X)
    assert old.scaler_.n_samples_seen_ == 0  # not recorded then
    np.testing.assert_array_equal(old.scaler_.data_min_, m.scaler_.data_min_)


def test_deterministic_and_save_load_round_trip(square, tmp_path):
    # with at most max_templates demonstrations nothing is random: two fits on
    # threads agree bit for bit
    train, test = square
    a = KeypointHMM(epsilon=0.05, n_time_bins=40, n_jobs=2).fit(train)
    b = KeypointHMM(epsilon=0.05, n_time_bins=40, n_jobs=1).fit(train)
    ga, gb = a.generate(test), b.generate(test)
    np.testing.assert_array_equal(ga.X, gb.X)
    a.save(tmp_path / "m.ndlfd")
    c = KeypointHMM.load(tmp_path / "m.ndlfd")
    gc = c.generate(test)
    np.testing.assert_array_equal(gc.X, ga.X)
    np.testing.assert_array_equal(gc.t, ga.t)
    assert c.get_params() == a.get_params() | {"groups": ("position", "velocity")}
    np.testing.assert_array_equal(c.n_keypoints_, a.n_keypoints_)
    grid = np.linspace(0, 3, 200)
    np.testing.assert_array_equal(
        c.generate(grid, dense=True).X, a.generate(grid, dense=True).X
    )


def test_load_refuses_foreign_and_tampered_files(square, tmp_path):
    train, _ = square
    m = KeypointHMM(epsilon=0.05, n_time_bins=40).fit(train)
    m.save(tmp_path / "m.ndlfd")
    m.model_.save(tmp_path / "hmm.npz")
    with pytest.raises(ModelFormatError, match="KeypointHMM"):
        KeypointHMM.load(tmp_path / "hmm.npz")
    z = dict(np.load(tmp_path / "m.ndlfd", allow_pickle=False))
    z["levels"] = z["levels"][:-1]
    with open(tmp_path / "bad.ndlfd", "wb") as fh:
        np.savez(fh, **z)
    with pytest.raises(ModelFormatError, match=r"tampered|inconsistent"):
        KeypointHMM.load(tmp_path / "bad.ndlfd")


def test_committed_v1_model_file_still_loads_and_generates_the_same():
    import importlib.util
    from pathlib import Path

    from ndlfd.io import read_csv

    here = Path(__file__).parent.parent / "data"
    spec = importlib.util.spec_from_file_location(
        "make_kp", here / "make_keypointhmm_v1.py"
    )
    mk = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mk)
    model = KeypointHMM.load(mk.FIXTURE)
    expected = read_csv(mk.EXPECTED)
    got = model.generate(mk.GRID, dense=True)
    np.testing.assert_array_equal(got.t, expected.t)
    np.testing.assert_allclose(got.X, expected.X, rtol=0, atol=1e-12)
    assert got.columns == expected.columns
    # and the file holds what a fresh fit with the recorded parameters learns
    np.testing.assert_array_equal(mk.build().generate(mk.GRID, dense=True).X, got.X)


def test_a_model_loaded_from_a_v1_file_is_saved_as_v1(tmp_path):
    import json

    mk = fixture_module("make_keypointhmm_v1")
    model = KeypointHMM.load(mk.FIXTURE)
    assert not hasattr(model, "fit_stats_")  # v1 has no statistics
    model.save(tmp_path / "again.ndlfd")
    with np.load(tmp_path / "again.ndlfd", allow_pickle=False) as z:
        assert json.loads(str(z["__ndlfd__"]))["version"] == 1
        with np.load(mk.FIXTURE, allow_pickle=False) as ref:
            for k in ref.files:
                if k != "__ndlfd__":
                    np.testing.assert_array_equal(z[k], ref[k], err_msg=k)
    again = KeypointHMM.load(tmp_path / "again.ndlfd")
    np.testing.assert_array_equal(
        again.generate(mk.GRID, dense=True).X, model.generate(mk.GRID, dense=True).X
    )


def test_committed_v2_model_file_still_loads_and_generates_the_same():
    from ndlfd.io import read_csv

    mk = fixture_module("make_keypointhmm_v2")
    model = KeypointHMM.load(mk.FIXTURE)
    for expected, kw in ((mk.EXPECTED, {}), (mk.EXPECTED_START, {"start": mk.START})):
        got = model.generate(mk.GRID, dense=True, **kw)
        want = read_csv(expected)
        np.testing.assert_array_equal(got.t, want.t)
        np.testing.assert_allclose(got.X, want.X, rtol=0, atol=1e-12)
        # a fresh fit of the recorded data and parameters generates the same,
        # matching raw samples as format 2 did; today's default does not
        fresh = mk.build(match_window=0.0).generate(mk.GRID, dense=True, **kw)
        np.testing.assert_array_equal(fresh.X, got.X)
        assert not np.array_equal(mk.build().generate(mk.GRID, dense=True).X, got.X)
    # every demonstration was a template; the statistics are a fresh fit's
    assert model.max_templates is None and model.template_indices_.size == 6
    assert model.match_window == 0.0 and KeypointHMM().match_window == 0.05
    assert model.fit_stats_ == mk.build().fit_stats_


def test_committed_v4_model_file_loads_into_interned_states(tmp_path):
    # format 4 numbered states in mixed radix; today's code interns the cells
    from ndlfd.io import read_csv

    mk = fixture_module("make_keypointhmm_v4")
    model = KeypointHMM.load(mk.FIXTURE)
    with np.load(mk.FIXTURE, allow_pickle=False) as z:
        numbers = z["stats_centroid_states"]
    # the same states in the same order: each id's cell is its old number's
    np.testing.assert_array_equal(
        model.codebook_.from_levels(model.centroid_cells_), numbers
    )
    fresh = mk.build()
    assert model.fit_stats_ == fresh.fit_stats_
    for expected, kw in ((mk.EXPECTED, {}), (mk.EXPECTED_START, {"start": mk.START})):
        want = read_csv(expected)
        for m in (model, fresh):
            got = m.generate(mk.GRID, dense=True, **kw)
            np.testing.assert_array_equal(got.t, want.t)
            np.testing.assert_allclose(got.X, want.X, rtol=0, atol=1e-12)
    # saved again, it is a version-5 file of the same model
    model.save(tmp_path / "again.ndlfd")
    load_npz(tmp_path / "again.ndlfd", kind="KeypointHMM", version=5)
    assert KeypointHMM.load(tmp_path / "again.ndlfd").fit_stats_ == model.fit_stats_


def test_a_tampered_cell_table_is_a_format_error(tmp_path):
    mk = fixture_module("make_keypointhmm_v4")
    model = KeypointHMM.load(mk.FIXTURE)
    model.save(tmp_path / "m.ndlfd")
    arrays, meta = load_npz(tmp_path / "m.ndlfd", kind="KeypointHMM", version=5)
    extra = {k: v for k, v in meta.items() if k not in ("format", "kind", "version")}
    cells = arrays["stats_centroid_cells"]
    for name, bad in (
        ("repeated", np.r_[cells[:1], cells[:-1]]),
        ("out of order", cells[::-1]),
        ("past the levels", cells + 100),
        ("negative", cells - 100),
    ):
        tampered = {**arrays, "stats_centroid_cells": bad}
        save_npz(tmp_path / "bad.ndlfd", tampered, kind="KeypointHMM", version=5,
                 metadata=extra)  # fmt: skip
        with pytest.raises(ModelFormatError, match="tampered"):
            KeypointHMM.load(tmp_path / "bad.ndlfd")
        assert name  # each case a format error, never a wrong model


def test_match_window_is_checked_saved_and_zero_for_older_files(tmp_path):
    from ndlfd._fileformat import load_npz, save_npz

    demos = [Demonstration.from_arrays(t, position=P) for t, P in waves(8)]
    for bad in (-0.1, 0.6, float("nan"), "wide"):
        with pytest.raises(ValidationError, match="match_window"):
            KeypointHMM(match_window=bad).fit(demos)
    model = KeypointHMM(epsilon=0.02, n_time_bins=20, match_window=0.1).fit(demos)
    model.save(tmp_path / "m.ndlfd")
    again = KeypointHMM.load(tmp_path / "m.ndlfd")
    assert again.match_window == 0.1
    t = np.linspace(0.0, 2.0, 60)
    assert_same_model(model, again, t)
    # the same file as format 3 wrote it (no match_window): raw matching
    arrays, meta = load_npz(tmp_path / "m.ndlfd", kind="KeypointHMM", version=5)
    del meta["params"]["match_window"]
    extra = {k: v for k, v in meta.items() if k not in ("format", "kind", "version")}
    save_npz(tmp_path / "v3.ndlfd", arrays, kind="KeypointHMM", version=3,
             metadata=extra)  # fmt: skip
    old = KeypointHMM.load(tmp_path / "v3.ndlfd")
    raw = KeypointHMM(epsilon=0.02, n_time_bins=20, match_window=0.0).fit(demos)
    assert old.match_window == 0.0
    assert_same_model(old, raw, t)


_NAME = st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=8)


@settings(max_examples=50, deadline=None, derandomize=True)
@given(
    source=_NAME,
    time=st.none() | _NAME,
    groups=st.lists(st.tuples(_NAME, st.lists(_NAME, max_size=4)), max_size=4),
    dropped=st.lists(_NAME, max_size=3),
    layout=_NAME,
    euler=st.none() | st.sampled_from(["xyz", "ZYX"]),
    order=st.lists(_NAME, max_size=4),
)
def test_input_mapping_json_round_trip(
    source, time, groups, dropped, layout, euler, order
):
    m = ColumnMapping(
        source,
        time,
        tuple((g, tuple(ks)) for g, ks in groups),
        tuple(dropped),
        (),
        layout,
        euler,
        tuple(order),
    )
    text = json.dumps(input_to_json(m))  # what the model file stores
    assert input_from_json(json.loads(text), "m.ndlfd") == m
    # a model file written before the input's column order was kept
    older = {k: v for k, v in json.loads(text).items() if k != "order"}
    assert input_from_json(older, "m.ndlfd").order == ()


def test_the_input_mapping_is_saved_and_older_files_load_without_it(tmp_path):
    train, test = synth.make_dataset("square", n_demos=4, random_state=0)
    m = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
    m.save(tmp_path / "plain.ndlfd")  # fitted from Demonstrations: none recorded
    plain = KeypointHMM.load(tmp_path / "plain.ndlfd")
    assert plain.input_mapping_ is None
    _rewrite_meta(tmp_path / "plain.ndlfd", tmp_path / "copy.ndlfd",
                  lambda meta: assert_not_in("input", meta))  # fmt: skip
    mapping = ColumnMapping(
        "d0.csv",
        "time",
        (("position", ("pos_x", "pos_y")),),
        layout="semicolon-separated",
    )
    m.input_mapping_ = mapping
    m.save(tmp_path / "named.ndlfd")
    named = KeypointHMM.load(tmp_path / "named.ndlfd")
    assert named.input_mapping_ == mapping
    # the mapping is metadata only: the same model and path
    assert_same_model(named, plain, test.t)
    np.testing.assert_array_equal(named.generate(test.t).X, plain.generate(test.t).X)
    # the committed older files (versions 1 and 2) have no such key
    for name in ("keypointhmm_v1.ndlfd", "keypointhmm_v2.ndlfd"):
        assert KeypointHMM.load(DATA / name).input_mapping_ is None


def assert_not_in(key, meta):
    assert key not in meta


def test_a_malformed_input_mapping_is_a_model_format_error(tmp_path):
    train, _ = synth.make_dataset("square", n_demos=4, random_state=0)
    m = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
    m.save(tmp_path / "m.ndlfd")

    def edit(meta):
        meta["input"] = {"source": "a.csv", "time": 3, "groups": "x"}

    _rewrite_meta(tmp_path / "m.ndlfd", tmp_path / "bad.ndlfd", edit)
    with pytest.raises(ModelFormatError, match=r"bad.ndlfd: the 'input' metadata"):
        KeypointHMM.load(tmp_path / "bad.ndlfd")
