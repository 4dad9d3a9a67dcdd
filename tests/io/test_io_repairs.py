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
    assert outer == [("rows", 1), ("quaternions", 5)]
    assert inner == [("jitter", 1)]


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
