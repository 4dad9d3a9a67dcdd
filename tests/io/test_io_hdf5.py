import pytest
from io_samples import reach

from ndlfd._errors import DataFileError, MissingExtraError
from ndlfd.demonstration import Demonstration
from ndlfd.io import (
    read_demos,
    read_hdf5,
)

h5py = pytest.importorskip("h5py")


def test_hdf5_one_group_per_episode(tmp_path):
    p = tmp_path / "reach.h5"
    demos = []
    with h5py.File(p, "w") as f:
        for i in (2, 10, 1):  # natural order: ep1, ep2, ep10
            t, pos, quat = reach(seed=i)
            g = f.create_group(f"ep{i}")
            g["time"], g["obs/eef"], g["quat"] = t, pos, quat
            g["label"] = "reach"
            demos.append((i, Demonstration.from_arrays(t, position=pos,
                                                       orientation=quat)))  # fmt: skip
    want = [d for _, d in sorted(demos, key=lambda x: x[0])]
    got, maps = read_demos(p, groups={"position": "obs/eef"}, return_mappings=True)
    assert got == want
    assert [m.source for m in maps] == [f"{p}:/ep{i}" for i in (1, 2, 10)]
    assert (
        str(maps[0]) == "time=time; position=obs/eef; orientation=quat; ignored label"
    )
    assert read_hdf5(p, groups={"position": "OBS/EEF"}) == want
    with pytest.raises(DataFileError, match=r"reach\.h5:/ep1: cannot tell the group"):
        read_hdf5(p)
    # datasets at the root: one episode
    q = tmp_path / "one.hdf5"
    t, pos, _ = reach()
    with h5py.File(q, "w") as f:
        f["t"], f["pos"] = t, pos
    assert read_hdf5(q) == [Demonstration.from_arrays(t, position=pos)]


def test_hdf5_errors_and_missing_extra(tmp_path, monkeypatch):
    empty = tmp_path / "empty.h5"
    with h5py.File(empty, "w"):
        pass
    with pytest.raises(DataFileError, match="expected one HDF5 group per episode"):
        read_hdf5(empty)
    bad = tmp_path / "bad.h5"
    bad.write_text("t,x\n0,1\n")
    with pytest.raises(DataFileError, match=r"bad\.h5: expected an HDF5 file"):
        read_hdf5(bad)
    with pytest.raises(DataFileError, match=r"none\.h5: no such file"):
        read_hdf5(tmp_path / "none.h5")
    import sys

    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now fails
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[hdf5\]"'):
        read_hdf5(empty)
