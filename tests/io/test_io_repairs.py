"""Repairs of recorded data: one summary warning per kind and fit, naming files.

Files with quaternions logged to 4 decimals and jittery time stamps, fitted
serially and on two worker processes: each kind of repair gives exactly one
warning (not one per pass, not one per worker), naming every file and its
count, however the fit runs; ``ndlfd fit -q`` silences them.
"""

import re
import warnings

import numpy as np
import pytest

from ndlfd import KeypointHMM, NdlfdWarning
from ndlfd._repairs import (
    SHOWN_FILES,
    collecting_repairs,
    repaired,
    summary_warnings,
)
from ndlfd.cli import main
from ndlfd.io import DemoFiles, write_table

HEADER = ["t", "x", "y", "qw", "qx", "qy", "qz"]


def _write(path, *, jitter: bool, rounded: bool, n=200):
    """A smooth reach; stamps off by +-2 ms in turn, quaternions to 4 decimals."""
    nominal = np.arange(n) * 0.02
    t = nominal + (0.002 * (-1.0) ** np.arange(n) if jitter else 0.0)
    s = nominal / nominal[-1]
    half = 0.4 * s + 0.1
    q = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
    if rounded:
        q = q.round(4)
    data = np.column_stack([t, s, np.sin(np.pi * s), q])
    write_table(path, HEADER, data)
    # how many rows 4 decimals put off by more than 1e-6 (hand count)
    return int(np.sum(np.abs(np.linalg.norm(q, axis=1) - 1) > 1e-6))


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """Four files: a.csv jittery + rounded, b.csv rounded, c.csv jittery, d clean."""
    root = tmp_path_factory.mktemp("repairs")
    kinds = {
        "a": (True, True),
        "b": (False, True),
        "c": (True, False),
        "d": (False, False),
    }
    counts = {}
    for name, (jitter, rounded) in kinds.items():
        counts[name] = _write(root / f"{name}.csv", jitter=jitter, rounded=rounded)
    return root, counts


def _fit_warnings(folder, **params):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        KeypointHMM(epsilon=0.1, n_time_bins=20, **params).fit(DemoFiles(folder))
    return [str(w.message) for w in caught if issubclass(w.category, NdlfdWarning)]


@pytest.mark.parametrize("n_jobs", [1, 2])
def test_one_warning_per_kind_naming_the_files(folder, n_jobs):
    root, counts = folder
    assert counts["a"] > 0 and counts["b"] > 0 and counts["c"] == counts["d"] == 0
    texts = _fit_warnings(root, n_jobs=n_jobs)
    assert len(texts) == 2, texts
    quats = [m for m in texts if "quaternion" in m]
    jitter = [m for m in texts if "jittery" in m]
    assert len(quats) == len(jitter) == 1
    total = counts["a"] + counts["b"]
    assert quats[0].startswith(f"renormalized {total} quaternion(s)")
    assert quats[0].endswith(
        f"in 2 files: {root / 'a.csv'} ({counts['a']}), {root / 'b.csv'}"
        f" ({counts['b']})"
    )
    assert jitter[0].endswith(f"in 2 files: {root / 'a.csv'}, {root / 'c.csv'}")


def test_serial_and_processes_same_model(folder):
    root, _ = folder
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NdlfdWarning)
        a = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(DemoFiles(root))
        b = KeypointHMM(epsilon=0.1, n_time_bins=20, n_jobs=2).fit(DemoFiles(root))
    assert [k.tolist() for k in a.keypoints_] == [k.tolist() for k in b.keypoints_]


def test_cli_fit_one_line_per_kind_and_quiet(folder, tmp_path, capsys):
    root, _ = folder
    capsys.readouterr()
    assert main(["fit", str(root), "-o", str(tmp_path / "m.ndlfd")]) == 0
    err = capsys.readouterr().err.splitlines()
    warned = [line for line in err if ": warning: " in line]
    assert len(warned) == 2, err
    assert sum("quaternion" in line for line in warned) == 1
    assert sum("jittery" in line for line in warned) == 1
    assert main(["fit", str(root), "-o", str(tmp_path / "q.ndlfd"), "-q"]) == 0
    assert capsys.readouterr().err == ""


def test_cli_fit_quiet_still_prints_errors(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("t,x\n0,1\n0,2\n")
    assert main(["fit", str(bad), "-o", str(tmp_path / "m.ndlfd"), "-q"]) == 2
    err = capsys.readouterr().err
    assert re.search(r"error: .*strictly increasing", err)


def test_repaired_warns_alone_and_records_inside():
    with pytest.warns(NdlfdWarning, match="^dropped 2 rows$"):
        repaired("rows", 2, "dropped 2 rows")
    with collecting_repairs() as outer:
        repaired("rows", 1, "x")
        with collecting_repairs() as inner:
            repaired("jitter", 1, "y")
        repaired("quaternions", 5, "z")
    assert outer == [("rows", 1, None), ("quaternions", 5, None)]
    assert inner == [("jitter", 1, None)]


def test_summary_names_the_first_files_then_how_many_more():
    records = [("rows", f"f{i}.csv", i + 1) for i in range(SHOWN_FILES + 3)]
    with pytest.warns(NdlfdWarning) as caught:
        summary_warnings(records)
    assert len(caught) == 1
    shown = ", ".join(f"f{i}.csv ({i + 1})" for i in range(SHOWN_FILES))
    total = sum(range(1, SHOWN_FILES + 4))
    assert str(caught[0].message) == (
        f"dropped {total} row(s) with NaN or inf (bad_rows='drop') in"
        f" {SHOWN_FILES + 3} files: {shown} and 3 more"
    )


# ------------------------------------------------------- bad rows, bad files
GOOD = "t,x,y\n0,0,0\n1,1,0.5\n2,2,0\n3,3,0.5\n"


@pytest.fixture()
def bad_folder(tmp_path):
    """good.csv; header.csv (header only); nan.csv (one NaN); text.csv (words)."""
    (tmp_path / "a_good.csv").write_text(GOOD)
    (tmp_path / "b_header.csv").write_text("t,x,y\n")
    (tmp_path / "c_nan.csv").write_text(GOOD.replace("1,1,0.5", "1,nan,0.5"))
    (tmp_path / "d_text.csv").write_text("t,x,y\n0,a,b\n1,c,d\n")
    (tmp_path / "e_good.csv").write_text(GOOD.replace("0.5", "0.25"))
    return tmp_path


@pytest.mark.parametrize(
    ("name", "match"),
    [
        ("b_header.csv", r"b_header.csv: expected data rows .* \(header only\)"),
        ("c_nan.csv", r"c_nan.csv, line 3, column 'x': expected a finite number"),
        ("d_text.csv", r"d_text.csv, line 2, column 'x': expected a number; got 'a'"),
    ],
)
def test_bad_files_are_errors_by_default(bad_folder, name, match):
    from ndlfd import DataFileError
    from ndlfd.io import read_csv, read_demos

    with pytest.raises(DataFileError, match=match):
        read_csv(bad_folder / name)
    with pytest.raises(DataFileError, match=match):
        read_demos([bad_folder / "a_good.csv", bad_folder / name])


def test_bad_rows_drop_keeps_the_other_rows(bad_folder):
    from ndlfd.io import read_csv

    with pytest.warns(NdlfdWarning, match=r"c_nan.csv: dropped 1 of 4 row"):
        d = read_csv(bad_folder / "c_nan.csv", bad_rows="drop")
    ref = np.array([[0, 0, 0], [2, 2, 0], [3, 3, 0.5]], dtype=float)  # by hand
    assert np.array_equal(np.column_stack([d.t, d.X]), ref)
    # a file without bad rows is read the same either way, without a warning
    a = read_csv(bad_folder / "a_good.csv", bad_rows="drop")
    assert a == read_csv(bad_folder / "a_good.csv")


def test_bad_rows_drop_leaving_fewer_than_two_rows_is_a_bad_file(tmp_path):
    from ndlfd import DataFileError
    from ndlfd.io import read_csv

    p = tmp_path / "mostly_nan.csv"
    p.write_text("t,x\n0,nan\n1,2\n2,inf\n")
    with pytest.raises(
        DataFileError, match=r"at least 2 rows .* got 1 after dropping 2 of 3"
    ):
        read_csv(p, bad_rows="drop")


def test_bad_options_are_checked(bad_folder):
    from ndlfd import ValidationError
    from ndlfd.io import read_csv, read_demos

    with pytest.raises(
        ValidationError, match=r"bad_rows must be one of 'error', 'drop'; got 'keep'"
    ):
        read_csv(bad_folder / "a_good.csv", bad_rows="keep")
    with pytest.raises(
        ValidationError, match=r"bad_files must be one of 'error', 'skip'; got 'drop'"
    ):
        DemoFiles(bad_folder, bad_files="drop")
    with pytest.raises(ValidationError, match=r"bad_files must be one of"):
        read_demos(bad_folder, bad_files=None)


def test_read_demos_skip_and_drop_report_once(bad_folder):
    from ndlfd.io import read_demos

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        demos = read_demos(bad_folder, bad_rows="drop", bad_files="skip")
    assert [d.n_samples for d in demos] == [4, 3, 4]
    texts = [str(w.message) for w in caught]
    assert len(texts) == 2, texts
    rows = next(m for m in texts if m.startswith("dropped"))
    assert rows.endswith(f"in 1 file: {bad_folder / 'c_nan.csv'} (1)")
    files = next(m for m in texts if m.startswith("skipped"))
    assert files.startswith("skipped 2 file(s) that cannot be read")
    assert f"{bad_folder / 'b_header.csv'}: expected data rows" in files
    assert f"{bad_folder / 'd_text.csv'}, line 2, column 'x'" in files
    # skipping without dropping: the NaN file is skipped too, with its reason
    with pytest.warns(NdlfdWarning, match=r"skipped 3 file\(s\).*finite number"):
        assert len(read_demos(bad_folder, bad_files="skip")) == 2


@pytest.mark.parametrize("n_jobs", [1, 2])
def test_fit_skips_and_drops_with_one_summary_each(bad_folder, n_jobs):
    texts = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = KeypointHMM(epsilon=0.1, n_time_bins=3, n_jobs=n_jobs).fit(
            DemoFiles(bad_folder, bad_rows="drop", bad_files="skip")
        )
    texts = [str(w.message) for w in caught]
    assert model.n_demos_ == 3
    assert model.n_keypoints_.max() <= 4
    assert len(texts) == 2, texts
    assert sum(m.startswith("skipped 2 file(s)") for m in texts) == 1
    assert sum(m.startswith("dropped 1 row(s)") for m in texts) == 1


def test_fit_skips_a_bad_first_file(bad_folder):
    (bad_folder / "0_bad.csv").write_text("t,x,y\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = KeypointHMM(epsilon=0.1, n_time_bins=3).fit(
            DemoFiles(bad_folder, bad_rows="drop", bad_files="skip")
        )
    assert model.n_demos_ == 3
    texts = [str(w.message) for w in caught]
    assert len(texts) == 2, texts
    files = next(m for m in texts if m.startswith("skipped 3 file(s)"))
    assert f": {bad_folder / '0_bad.csv'}: expected data rows" in files


def test_fit_every_file_skipped_is_an_error(tmp_path):
    from ndlfd import DataFileError

    (tmp_path / "a.csv").write_text("t,x\n")
    (tmp_path / "b.csv").write_text("t,x\n0,z\n")
    with pytest.raises(
        DataFileError, match=r"every one of the 2 file\(s\) was skipped"
    ):
        KeypointHMM().fit(DemoFiles(tmp_path, bad_files="skip"))


def test_cli_fit_bad_rows_and_files(bad_folder, tmp_path, capsys):
    out = tmp_path / "m.ndlfd"
    assert main(["fit", str(bad_folder), "-o", str(out)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "b_header.csv: expected data rows" in err[0]
    args = ["fit", str(bad_folder), "-o", str(out), "--bad-rows", "drop"]
    assert main([*args, "--bad-files", "skip", "--time-bins", "3"]) == 0
    err = capsys.readouterr().err.splitlines()
    warned = [line for line in err if ": warning: " in line]
    assert len(warned) == 2, err
    assert any("skipped 2 file(s)" in line for line in warned)
    assert any("fitted 3 demonstration(s)" in line for line in err)
    assert main([*args, "--bad-files", "skip", "--time-bins", "3", "-q"]) == 0
    assert capsys.readouterr().err == ""


def test_one_warning_per_kind_on_threads(tmp_path):
    # demonstrations of 5,000 samples and more are mapped on threads
    n = {
        name: _write(tmp_path / f"{name}.csv", jitter=name != "b", rounded=True, n=5000)
        for name in ("a", "b", "c")
    }
    texts = _fit_warnings(tmp_path, n_jobs=2)
    assert len(texts) == 2, texts
    quats = next(m for m in texts if "quaternion" in m)
    assert quats.endswith(
        f"in 3 files: {tmp_path / 'a.csv'} ({n['a']}), {tmp_path / 'b.csv'}"
        f" ({n['b']}), {tmp_path / 'c.csv'} ({n['c']})"
    )
    jitter = next(m for m in texts if "jittery" in m)
    assert jitter.endswith(f"in 2 files: {tmp_path / 'a.csv'}, {tmp_path / 'c.csv'}")


# ------------------------------------------- bad_rows on every single-file reader
def _reach_arrays(n=12):
    """A smooth 3-D reach with orientation and a NaN in row 4 and inf in row 7."""
    t = np.arange(n) * 0.1
    s = t / t[-1]
    pos = np.column_stack([s, s**2, 0.5 * s])
    half = 0.3 * s
    quat = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
    bad = pos.copy()
    bad[4, 1] = np.nan
    bad[7, 2] = np.inf
    return t, pos, quat, bad


def _write_npz(path, t, pos, quat):
    np.savez(path, t=t, position=pos, orientation=quat)
    return path, {}


def _write_hdf5(path, t, pos, quat):
    h5py = pytest.importorskip("h5py")
    path = path.with_suffix(".h5")
    with h5py.File(path, "w") as f:
        g = f.create_group("ep0")
        g["t"], g["position"], g["orientation"] = t, pos, quat
    return path, {}


def _write_bag(path, t, pos, quat):
    pytest.importorskip("rosbags")
    from bag_samples import pose_stamped, write_bag

    ns = 1_700_000_000 * 10**9 + np.round(t * 1e9).astype(np.int64)
    msgs = [
        (int(k), pose_stamped(int(k), p, q))
        for k, p, q in zip(ns, pos, quat, strict=True)
    ]
    path = path.with_suffix(".mcap")
    return write_bag(path, {"/ee_pose": msgs}), {"topic": "/ee_pose"}


def _write_lerobot(path, t, pos, quat):
    pytest.importorskip("pyarrow")
    from lerobot_writer import write_lerobot

    state = np.column_stack([pos, quat])
    names = {"observation.state": ["x", "y", "z", "qw", "qx", "qy", "qz"]}
    root = write_lerobot(path, [{"observation.state": state}], names, fps=10)
    return root, {}


def _readers():
    from ndlfd.io import read_bag, read_hdf5, read_lerobot, read_npz

    def single(fn):
        return lambda p, **kw: [fn(p, **kw)]

    return {
        "npz": (_write_npz, single(read_npz)),
        "hdf5": (_write_hdf5, read_hdf5),
        "bag": (_write_bag, read_bag),
        "lerobot": (_write_lerobot, read_lerobot),
    }


@pytest.mark.parametrize("kind", ["npz", "hdf5", "bag", "lerobot"])
def test_bad_rows_on_every_single_file_reader(tmp_path, kind):
    """The same semantics and report as read_csv, through one implementation.

    The reference: the same file with finite values in those rows, read
    without ``bad_rows``, less those rows.
    """
    from ndlfd import DataFileError

    write, read = _readers()[kind]
    t, pos, quat, bad = _reach_arrays()
    (tmp_path / "bad").mkdir()
    (tmp_path / "ref").mkdir()
    p, opts = write(tmp_path / "bad" / "demo.npz", t, pos=bad, quat=quat)
    keep = np.ones(t.size, bool)
    keep[[4, 7]] = False
    ref_p, _ = write(tmp_path / "ref" / "demo.npz", t, pos, quat)
    with pytest.raises(DataFileError, match=r"finite|NaN|inf"):
        read(p, **opts)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = read(p, bad_rows="drop", **opts)
    texts = [str(w.message) for w in caught]
    assert len(texts) == 1, texts
    assert re.search(r"dropped 2 of 12 row\(s\) with NaN or inf", texts[0])
    assert str(p) in texts[0]
    (full,) = read(ref_p, **opts)
    assert len(got) == 1
    assert np.array_equal(got[0].t, full.t[keep])
    assert np.array_equal(got[0].X, full.X[keep])
    with pytest.raises(Exception, match=r"bad_rows must be one of 'error', 'drop'"):
        read(p, bad_rows="keep", **opts)


def test_cli_generate_like_bad_rows(tmp_path, capsys):
    """generate --like reads the time column: --bad-rows drop drops bad stamps.

    A NaN among the values does not matter (the time stamps alone are used);
    a NaN time stamp is an error, or with ``--bad-rows drop`` left out.
    """
    from ndlfd import Demonstration
    from ndlfd.io import read_csv, write_csv

    t = np.linspace(0.0, 1.0, 30)
    demos = tmp_path / "demos"
    demos.mkdir()
    for k in range(3):
        xy = np.column_stack([t, np.sin(np.pi * t) * (1 + 0.1 * k)])
        write_csv(Demonstration.from_arrays(t, position=xy), demos / f"d{k}.csv")
    model = tmp_path / "m.ndlfd"
    assert main(["fit", str(demos), "-o", str(model), "-q"]) == 0
    lines = (demos / "d0.csv").read_text().splitlines()
    value, stamp = lines[5].split(","), lines[9].split(",")
    value[1] = "nan"  # sample 4's x
    stamp[0] = "inf"  # sample 8's time
    lines[5], lines[9] = ",".join(value), ",".join(stamp)
    like = tmp_path / "like.csv"
    like.write_text("\n".join(lines) + "\n")
    out = tmp_path / "g.csv"
    args = ["generate", str(model), "--like", str(like), "--dense", "-o", str(out)]
    capsys.readouterr()
    assert main(args) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "time column 't'" in err[0], err
    assert main([*args, "--bad-rows", "drop"]) == 0
    err = capsys.readouterr().err
    assert f"--like {like}: dropped 1 of 30 row(s) with NaN or inf in the time" in err
    np.testing.assert_array_equal(read_csv(out).t, np.delete(t, 8))


def test_one_warning_per_kind_on_dask(folder, tmp_path):
    """The Dask path of the fit: the same single summaries as the serial fit.

    Four files with renormalized quaternions and jittery stamps, one with a
    NaN row (dropped) and one header-only file (skipped), fitted on a Dask
    LocalCluster (threads: the same map steps and merges as processes).
    """
    distributed = pytest.importorskip("distributed")
    root, counts = folder
    data = tmp_path / "data"
    data.mkdir()
    for p in sorted(root.glob("*.csv")):
        (data / p.name).write_text(p.read_text())
    lines = (data / "d.csv").read_text().splitlines()
    cells = lines[3].split(",")
    cells[1] = "nan"
    lines[3] = ",".join(cells)
    (data / "e.csv").write_text("\n".join(lines) + "\n")  # d with a NaN row
    (data / "f.csv").write_text(",".join(HEADER) + "\n")  # header only

    def fit(**kw):
        files = DemoFiles(data, bad_rows="drop", bad_files="skip")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(files, **kw)
        texts = [str(w.message) for w in caught if w.category is NdlfdWarning]
        return model, texts

    serial, want = fit()
    with (
        distributed.LocalCluster(
            n_workers=2, processes=False, threads_per_worker=1, dashboard_address=":0"
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        before = cluster.scheduler.transition_counter
        model, texts = fit(client=client)
        assert cluster.scheduler.transition_counter > before  # ran as Dask tasks
    assert model.fit_stats_ == serial.fit_stats_
    assert sorted(texts) == sorted(want)
    assert len(texts) == 4, texts  # one per kind: quaternions, jitter, rows, files
    by_kind = {k: [m for m in texts if k in m] for k in
               ("quaternion", "jittery", "NaN", "skipped")}  # fmt: skip
    assert all(len(v) == 1 for v in by_kind.values()), by_kind
    assert by_kind["quaternion"][0].endswith(
        f"in 2 files: {data / 'a.csv'} ({counts['a']}), {data / 'b.csv'}"
        f" ({counts['b']})"
    )
    assert by_kind["jittery"][0].endswith(
        f"in 2 files: {data / 'a.csv'}, {data / 'c.csv'}"
    )
    assert by_kind["NaN"][0] == (
        "dropped 1 row(s) with NaN or inf (bad_rows='drop') in 1 file:"
        f" {data / 'e.csv'} (1)"
    )
    assert by_kind["skipped"][0].startswith("skipped 1 file(s)")
    assert f"{data / 'f.csv'}: expected data rows" in by_kind["skipped"][0]
