"""Fuzz models and files: damaged model files, readers, a write failing midway."""

import json
import pickle
import shutil
from pathlib import Path

import numpy as np
import pytest
from fuzz_helpers import check_outcome

import ndlfd
from ndlfd import KeypointHMM, ModelFormatError, hmm, synth
from ndlfd import _fileformat as fileformat
from ndlfd.io import read_csv, read_demos, read_npz

DATA = Path(__file__).parent.parent / "data"
GOOD = DATA / "keypointhmm_v2.ndlfd"
BAD = DATA / "bad"


def _arrays(path):
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def _save(path, arrays):
    with open(path, "wb") as fh:
        np.savez(fh, **arrays)
    return path


def _damaged(tmp_path):
    """(name, path) of model files damaged in every way the brief lists."""
    raw = GOOD.read_bytes()
    out = []
    for frac in (0.0, 0.1, 0.5, 0.99):
        p = tmp_path / f"truncated_{frac}.ndlfd"
        p.write_bytes(raw[: int(len(raw) * frac)])
        out.append((p.name, p))
    arrays = _arrays(GOOD)
    meta = json.loads(str(arrays["__ndlfd__"]))
    future = dict(arrays, __ndlfd__=np.array(json.dumps(dict(meta, version=99))))
    out.append(("future", _save(tmp_path / "future.ndlfd", future)))
    for key in arrays:
        if key == "__ndlfd__" or arrays[key].size < 2:
            continue
        shorter = dict(arrays)
        shorter[key] = arrays[key][:-1]
        out.append((f"short_{key}", _save(tmp_path / f"short_{key}.ndlfd", shorter)))
    pick = tmp_path / "pickled.ndlfd"
    pick.write_bytes(pickle.dumps({"a": 1}))
    out.append(("pickle", pick))
    objs = dict(arrays)
    with open(tmp_path / "object.ndlfd", "wb") as fh:
        np.savez(fh, **{k: v for k, v in objs.items() if k != "levels"},
                 levels=np.array([{"a": 1}], dtype=object))  # fmt: skip
    out.append(("object", tmp_path / "object.ndlfd"))
    for p in sorted(BAD.glob("*.ndlfd")):
        out.append((p.name, p))
    return out


def test_fuzz_damaged_model_files(tmp_path):
    """Each damaged file is refused with ModelFormatError, or loads and works."""
    t = np.linspace(0.0, 1.0, 40)
    for name, path in _damaged(tmp_path):
        try:
            model = KeypointHMM.load(path)
        except ModelFormatError as exc:
            assert str(exc), name
            continue
        # a loaded file must still give a finite path or one error of ours
        check_outcome(model.generate, t, dense=True)


def test_fuzz_hmm_load_of_bad_files(tmp_path):
    for _, path in _damaged(tmp_path):
        assert check_outcome(hmm.DiscreteHMM.load, path) is None


@pytest.mark.parametrize("path", sorted(BAD.glob("*.csv")), ids=lambda p: p.name)
def test_fuzz_bad_csv_files(path):
    """The bad corpus: each file is read correctly or refused with one error."""
    demo = check_outcome(read_csv, path)
    if demo is not None:
        assert (np.diff(demo.t) > 0).all()
    check_outcome(read_demos, [path])


def test_fuzz_read_npz_bad_files(tmp_path):
    for name, path in _damaged(tmp_path):
        npz = tmp_path / f"{name}.npz"
        shutil.copy(path, npz)
        check_outcome(read_npz, npz)
    for arrays in (
        {"t": np.array([0.0, 1.0, 1.0]), "pos": np.zeros((3, 2))},
        {"t": np.array([0.0, np.nan]), "pos": np.zeros((2, 2))},
        {"t": np.array([0.0, 1.0]), "pos": np.zeros((3, 2))},
        {"t": np.array([0.0, 1.0]), "pos": np.array([[1 + 1j], [2]])},
        {"t": np.array(["a", "b"]), "pos": np.zeros((2, 1))},
        {"t": np.zeros(0), "pos": np.zeros((0, 2))},
    ):
        p = _save(tmp_path / "plain.npz", arrays)
        assert check_outcome(read_npz, p) is None


def test_fuzz_demonstrations_of_very_different_lengths():
    """A 3-sample demonstration beside 3,000-sample ones fits and generates."""
    train, _ = synth.make_dataset("square", n_demos=4, random_state=0)
    d = train[0]
    short = d.take([0, 40, d.n_samples - 1])
    t = np.linspace(d.t[0], d.t[-1], 3000)
    X = np.column_stack([np.interp(t, d.t, d.X[:, j]) for j in range(d.n_dims)])
    long_ = ndlfd.Demonstration(t, X, d.columns, d.groups)
    model = KeypointHMM(epsilon=0.05, n_time_bins=20).fit([*train, short, long_])
    path = model.generate(np.linspace(0, 1, 50), dense=True)
    assert np.isfinite(path.X).all()
    samples = model.sample(np.linspace(0, 1, 50), 3, random_state=0)
    assert all(np.isfinite(s.X).all() for s in samples)


class _FailingFile:
    """A file object that writes half of what it is given, then runs out of disk."""

    def __init__(self, fh):
        self._fh = fh
        self.written = 0

    def write(self, data):
        if self.written > 100:
            raise OSError(28, "No space left on device")
        self.written += len(data)
        return self._fh.write(bytes(data)[: max(1, len(data) // 2)])

    def __getattr__(self, name):
        return getattr(self._fh, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._fh.close()


def test_fuzz_write_failing_midway_keeps_the_old_file(tmp_path, monkeypatch):
    train, _ = synth.make_dataset("square", n_demos=4, random_state=0)
    model = KeypointHMM(epsilon=0.1, n_time_bins=10).fit(train)
    target = tmp_path / "model.ndlfd"
    model.save(target)
    before = target.read_bytes()
    real_open = open
    monkeypatch.setattr(
        fileformat,
        "open",
        lambda p, m="r": _FailingFile(real_open(p, m)),
        raising=False,
    )
    with pytest.raises(OSError, match="No space left"):
        model.save(target)
    assert target.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.ndlfd"]
