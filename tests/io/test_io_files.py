import numpy as np
import pytest
from io_samples import reach, rich_demo

from ndlfd._errors import DataFileError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import (
    read_demos,
    write_csv,
    write_npz,
)


def test_read_demos_folder_glob_list(tmp_path):
    demos = [rich_demo(4, s) for s in range(3)]
    write_csv(demos[0], tmp_path / "b.csv")
    write_npz(demos[1], tmp_path / "a.npz")
    write_csv(demos[2], tmp_path / "c.csv")
    (tmp_path / "notes.txt").write_text("not data")
    (tmp_path / "sub").mkdir()
    got = read_demos(tmp_path)
    assert got == [demos[1], demos[0], demos[2]]
    assert read_demos(str(tmp_path / "*.csv")) == [demos[0], demos[2]]
    assert read_demos([tmp_path / "c.csv", tmp_path / "a.npz"]) == [demos[2], demos[1]]
    assert read_demos(tmp_path / "b.csv") == [demos[0]]
    r = tmp_path / "sub" / "r.csv"
    r.write_text("x\n1\n2\n")
    assert read_demos(r, time_column=None)[0].t.tolist() == [0.0, 1.0]


def test_demo_files_read_lazily_like_read_demos(tmp_path):
    import pickle

    from ndlfd import KeypointHMM
    from ndlfd.io import DemoFile, DemoFiles

    demos = [rich_demo(6, s) for s in range(3)]
    for i, d in enumerate(demos):
        write_csv(d, tmp_path / f"d{i}.csv")
    (tmp_path / "d1.csv").rename(tmp_path / "renamed.csv")  # no longer sorted last
    files = DemoFiles(tmp_path)
    assert len(files) == 3 and all(isinstance(f, DemoFile) for f in files)
    assert [f.path.name for f in files] == ["d0.csv", "d2.csv", "renamed.csv"]
    assert [x for f in files for x in f.read()] == read_demos(tmp_path)
    assert [f.path for f in files[1:]] == [f.path for f in list(files)[1:]]
    # items travel to worker processes (pickled), not their data
    f = pickle.loads(pickle.dumps(files[0]))
    assert f == files[0] and f.read() == [demos[0]]
    # the column mapping goes with every file
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "r.csv").write_text("stamp,a,b\n0,1,2\n1,3,4\n")
    mapped = DemoFiles(sub, time_column="stamp", groups={"position": ["a", "b"]})
    assert mapped[0].read() == read_demos(
        sub, time_column="stamp", groups={"position": ["a", "b"]}
    )
    with pytest.raises(ValidationError, match=r"DemoFiles got .*\['colums'\]"):
        DemoFiles(sub, colums=["a"])
    # fitting from it: the model of the demonstrations in memory
    kw = dict(epsilon=0.1, n_time_bins=5, n_jobs=1)
    a = KeypointHMM(**kw).fit(DemoFiles(tmp_path / "*.csv"))
    b = KeypointHMM(**kw).fit(read_demos(tmp_path / "*.csv"))
    assert a.fit_stats_ == b.fit_stats_


def test_read_demos_errors(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(
        DataFileError,
        match=r"empty: expected \.csv, \.tsv, \.npz, \.npy, \.h5, \.hdf5, \.mcap or"
        r" \.db3 files or ROS 2 bag folders in the folder \(any case\); found none",
    ):
        read_demos(tmp_path / "empty")
    with pytest.raises(DataFileError, match=r"\*\.csv: the pattern matched no files"):
        read_demos(str(tmp_path / "*.csv"))
    with pytest.raises(DataFileError, match=r"missing\.csv: no such file"):
        read_demos(tmp_path / "missing.csv")
    with pytest.raises(
        DataFileError, match="expected at least one file; got an empty list"
    ):
        read_demos([])
    with pytest.raises(
        ValidationError, match="paths must be str or path-like; got int"
    ):
        read_demos([1])
    with pytest.raises(ValidationError, match="source must be a file, a folder"):
        read_demos(3.5)


def test_read_demos_folder_takes_every_format_in_any_case(tmp_path):
    h5py = pytest.importorskip("h5py")
    t, pos, _ = reach()
    d = Demonstration.from_arrays(t, position=pos)
    write_csv(d, tmp_path / "a.CSV")
    np.savez(tmp_path / "b.NPZ", t=t, pos=pos)
    with h5py.File(tmp_path / "c.H5", "w") as f:
        f["e/t"], f["e/pos"] = t, pos
    (tmp_path / "d.tsv").write_text(
        "t\tx\ty\tz\n" + "\n".join("\t".join(map(repr, r)) for r in
                                   np.column_stack([t, pos]).tolist()) + "\n"
    )  # fmt: skip
    (tmp_path / "notes.txt").write_text("not data")
    demos, maps = read_demos(tmp_path, return_mappings=True)
    assert demos == [d] * 4
    assert [m.layout for m in maps] == [
        "comma-separated", "arrays", "arrays", "tab-separated"
    ]  # fmt: skip
    with pytest.raises(ValidationError, match=r"unexpected argument\(s\) \['group'\]"):
        read_demos(tmp_path, group={})
