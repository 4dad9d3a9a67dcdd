import json
import zipfile

import numpy as np
import pytest

from ndlfd import ModelFormatError
from ndlfd._fileformat import atomic_path, load_npz, save_npz


def test_round_trip(tmp_path):
    arrays = {"a": np.arange(5), "b": np.linspace(0, 1, 7).reshape(7, 1)}
    p = save_npz(tmp_path / "m.npz", arrays, kind="Thing", version=2, metadata={"x": 1})
    out, meta = load_npz(p, kind="Thing", version=2)
    assert set(out) == {"a", "b"}
    for k in arrays:
        np.testing.assert_array_equal(out[k], arrays[k])
        assert out[k].dtype == arrays[k].dtype
    assert meta["x"] == 1 and meta["kind"] == "Thing" and meta["version"] == 2
    # no temporary files left behind
    assert [f.name for f in tmp_path.iterdir()] == ["m.npz"]


def test_object_arrays_refused(tmp_path):
    with pytest.raises(TypeError, match="object"):
        save_npz(
            tmp_path / "m.npz",
            {"a": np.array([1, "x"], dtype=object)},
            kind="T",
            version=1,
        )
    assert not list(tmp_path.iterdir())


def test_wrong_kind_and_version(tmp_path):
    p = save_npz(tmp_path / "m.npz", {"a": np.zeros(2)}, kind="A", version=1)
    with pytest.raises(ModelFormatError, match="expected an ndlfd B file; got a 'A'"):
        load_npz(p, kind="B", version=1)
    with pytest.raises(ModelFormatError, match="expected A format version 3"):
        load_npz(p, kind="A", version=3)


def test_foreign_truncated_and_garbage_files(tmp_path):
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, a=np.zeros(3))
    with pytest.raises(ModelFormatError, match="foreign"):
        load_npz(foreign, kind="A", version=1)

    good = save_npz(tmp_path / "good.npz", {"a": np.zeros(100)}, kind="A", version=1)
    data = good.read_bytes()
    truncated = tmp_path / "trunc.npz"
    truncated.write_bytes(data[: len(data) // 2])
    with pytest.raises(ModelFormatError, match="not readable"):
        load_npz(truncated, kind="A", version=1)

    garbage = tmp_path / "garbage.npz"
    garbage.write_bytes(b"\x00\x01 not a zip at all")
    with pytest.raises(ModelFormatError, match="not readable"):
        load_npz(garbage, kind="A", version=1)

    with pytest.raises(ModelFormatError, match="no such file"):
        load_npz(tmp_path / "missing.npz", kind="A", version=1)

    npy = tmp_path / "plain.npy"
    np.save(npy, np.zeros(3))
    with pytest.raises(ModelFormatError, match=r"plain \.npy"):
        load_npz(npy, kind="A", version=1)


def test_pickled_object_array_is_refused(tmp_path):
    p = tmp_path / "evil.npz"
    meta = json.dumps({"format": "ndlfd", "kind": "A", "version": 1})
    np.savez(p, a=np.array([{"x": 1}], dtype=object), __ndlfd__=np.array(meta))
    with pytest.raises(ModelFormatError, match="not readable"):
        load_npz(p, kind="A", version=1)


def test_bad_metadata(tmp_path):
    p = tmp_path / "badmeta.npz"
    np.savez(p, a=np.zeros(1), __ndlfd__=np.array("{not json"))
    with pytest.raises(ModelFormatError, match="not valid JSON"):
        load_npz(p, kind="A", version=1)
    q = tmp_path / "otherformat.npz"
    np.savez(q, __ndlfd__=np.array(json.dumps({"format": "other"})))
    with pytest.raises(ModelFormatError, match="expected ndlfd metadata"):
        load_npz(q, kind="A", version=1)
    assert zipfile.is_zipfile(q)


def test_atomic_path_leaves_nothing_on_error(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [f.name for f in tmp_path.iterdir()] == ["out.txt"]


def test_atomic_path_gives_normal_file_permissions(tmp_path):
    import os
    import stat

    old = os.umask(0o022)
    try:
        with atomic_path(tmp_path / "new.txt") as tmp:
            tmp.write_text("x")
        assert stat.S_IMODE((tmp_path / "new.txt").stat().st_mode) == 0o644
        os.chmod(tmp_path / "new.txt", 0o600)
        with atomic_path(tmp_path / "new.txt") as tmp:
            tmp.write_text("y")
        assert stat.S_IMODE((tmp_path / "new.txt").stat().st_mode) == 0o600
    finally:
        os.umask(old)
