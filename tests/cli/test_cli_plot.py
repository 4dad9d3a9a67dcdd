"""ndlfd plot."""

import numpy as np
import pytest
from cli_helpers import (
    cli,
    keep_figures,
    square_demos,
    write_obstacle,
    write_reach,
)

from ndlfd.cli import main
from ndlfd.io import read_csv, read_table, write_table
from ndlfd.learner import KeypointHMM


def test_plot_draws_demos_keypoints_path_and_band(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")

    figures = keep_figures(monkeypatch)
    folder = square_demos(tmp_path / "demos", n_demos=4)
    model, gen, std = tmp_path / "m.ndlfd", tmp_path / "g.csv", tmp_path / "s.csv"
    assert main(["fit", str(folder), "-o", str(model), "-q"]) == 0
    assert main(["generate", str(model), "--duration", "2", "--samples", "60",
                 "--dense", "--std", str(std), "-o", str(gen), "-q"]) == 0  # fmt: skip
    rc, err = cli(capsys, "plot", folder, "--path", gen, "--std", std,
                  "--title", "square", "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fitted = KeypointHMM.load(model)
    counts = [len(k) for k in fitted.keypoints_]
    assert err[-1] == (
        f"drew 4 demonstration(s) in 2-D (position) with their key points"
        f" ({min(counts)}-{max(counts)} at --epsilon 0.05), the generated path and"
        f" its ±1 sd band -> {tmp_path / 'p.png'}"
    )
    (ax,) = figures[-1].axes
    assert ax.get_title() == "square" and ax.name != "3d"
    # per demonstration: line, key points (those fit finds), start, goal
    demos = [read_csv(p) for p in sorted(folder.glob("*.csv"))]
    for i, (d, k) in enumerate(zip(demos, fitted.keypoints_, strict=True)):
        np.testing.assert_array_equal(ax.lines[4 * i].get_xydata(), d.get("position"))
        np.testing.assert_array_equal(
            ax.lines[4 * i + 1].get_xydata(), d.get("position")[k]
        )
    path = read_csv(gen).get("position")
    generated = [ln for ln in ax.lines if ln.get_label() == "generated"]
    np.testing.assert_array_equal(generated[0].get_xydata(), path)
    (band,) = ax.patches
    assert band.get_label() == "generated ±1 sd"
    s = read_table(std)[1][:, 1:3]
    assert band.get_path().contains_point(path[30] + 0.9 * s[30] * [1, 0])
    # 3-D positions: 3-D axes, no band; --n-points sets the key points
    folder3 = write_reach(tmp_path / "reach")
    rc, err = cli(capsys, "plot", folder3, "--n-points", "6", "-o", tmp_path / "r.svg")
    assert rc == 0, err
    assert figures[-1].axes[0].name == "3d"
    assert err[-1].startswith("drew 3 demonstration(s) in 3-D (position) with their"
                              " key points (6-6 at --n-points 6), 8 orientation"
                              " triads on ")  # fmt: skip
    assert (tmp_path / "r.svg").read_text().lstrip().startswith("<?xml")
    for args, message in [
        (["--std", std], "--std draws the band of --path FILE.csv; pass --path"),
        (["-o", tmp_path / "p.xyz"], f"-o {tmp_path / 'p.xyz'}: expected a figure"
         " file ending in"),
        (["--path", gen, "--std", folder / "demo00.csv"], "--std"),
    ]:  # fmt: skip
        out = [] if "-o" in args else ["-o", tmp_path / "q.png"]
        rc, err = cli(capsys, "plot", folder, "-q", *args, *out)
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(f"ndlfd plot: error: {message}")


def test_plot_uses_the_groups_of_fit_by_default(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    from cli_helpers import fit_model

    # 3-D reaches with orientation: fit learns position, velocity, orientation
    folder = write_reach(tmp_path / "d")
    model = fit_model(folder, tmp_path / "m.ndlfd")
    assert model.groups_ == ("position", "velocity", "orientation")
    counts = [len(k) for k in model.keypoints_]
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png")
    assert rc == 0, err
    assert f"key points ({min(counts)}-{max(counts)} at --epsilon 0.05)" in err[-1]
    # --groups still chooses (fewer groups: other key points)
    rc, err = cli(capsys, "plot", folder, "--groups", "position", "-o",
                  tmp_path / "q.png")  # fmt: skip
    assert rc == 0, err
    only = fit_model(folder, tmp_path / "p.ndlfd", "--groups", "position")
    k = [len(x) for x in only.keypoints_]
    assert f"key points ({min(k)}-{max(k)} at --epsilon 0.05)" in err[-1]


def test_plot_bad_rows_and_files(tmp_path, capsys, monkeypatch):
    """--bad-rows drop / --bad-files skip draw what fit would learn from."""
    pytest.importorskip("matplotlib")
    figures = keep_figures(monkeypatch)
    folder = square_demos(tmp_path / "demos", n_demos=3)
    good = [read_csv(p) for p in sorted(folder.glob("*.csv"))]
    second = sorted(folder.glob("*.csv"))[1]
    lines = second.read_text().splitlines()
    cells = lines[6].split(",")  # sample 5 (after the header)
    cells[1] = "nan"
    lines[6] = ",".join(cells)
    second.write_text("\n".join(lines) + "\n")
    (folder / "zz_header_only.csv").write_text("t,x,y\n")
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png")
    assert rc == 2 and len(err) == 1 and "expected a finite number" in err[0]
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png",
                  "--bad-rows", "drop", "--bad-files", "skip")  # fmt: skip
    assert rc == 0, err
    warned = [line for line in err if ": warning: " in line]
    assert len(warned) == 2, err
    assert any("dropped 1 of" in w for w in warned)
    assert any("skipped" in w and "zz_header_only.csv" in w for w in warned)
    assert err[-1].startswith("drew 3 demonstration(s) in 2-D (position)")
    (ax,) = figures[-1].axes
    keep = np.ones(good[1].n_samples, bool)
    keep[5] = False
    for i, want in enumerate([good[0].X, good[1].X[keep], good[2].X]):
        np.testing.assert_array_equal(ax.lines[4 * i].get_xydata(), want[:, :2])
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png", "-q",
                  "--bad-rows", "drop", "--bad-files", "skip")  # fmt: skip
    assert rc == 0 and err == []


def test_plot_draws_a_folder_of_samples_as_thin_lines(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    from ndlfd.plot import GEN_COLOR

    figures = keep_figures(monkeypatch)
    folder = square_demos(tmp_path / "demos", n_demos=4)
    model = tmp_path / "m.ndlfd"
    assert main(["fit", str(folder), "-o", str(model), "-q"]) == 0
    samples = tmp_path / "samples"
    assert main(["sample", str(model), "-n", "5", "--duration", "2", "--samples",
                 "50", "--random-state", "1", "-o", str(samples)]) == 0  # fmt: skip
    rc, err = cli(capsys, "plot", folder, "--samples", samples, "-o",
                  tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    assert err[-1].endswith(f", 5 sample(s) -> {tmp_path / 'p.png'}")
    (ax,) = figures[-1].axes
    thin = [ln for ln in ax.lines if ln.get_color() == GEN_COLOR
            and ln.get_linewidth() < 1]  # fmt: skip
    files = sorted(samples.glob("*.csv"))
    assert len(thin) == len(files) == 5
    for line, f in zip(thin, files, strict=True):
        np.testing.assert_array_equal(line.get_xydata(), read_csv(f).get("position"))
    assert "samples" in [t.get_text() for t in ax.get_legend().get_texts()]
    for args, message in [
        ([tmp_path / "nowhere"], "expected the folder 'ndlfd sample -o' writes"),
        ([tmp_path], "the folder holds no .csv file"),
    ]:
        rc, err = cli(capsys, "plot", folder, "--samples", *args, "-o",
                      tmp_path / "q.png")  # fmt: skip
        assert rc == 2 and len(err) == 1 and message in err[0], err


def test_plot_draws_orientation_triads_along_a_3d_path(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    from ndlfd.plot import TRIAD_COLORS, triad_indices

    figures = keep_figures(monkeypatch)
    folder = write_reach(tmp_path / "reach")  # 3-D with orientation
    model = tmp_path / "m.ndlfd"
    assert main(["fit", str(folder), "-o", str(model), "-q"]) == 0
    gen = tmp_path / "g.csv"
    assert main(["generate", str(model), "--duration", "1", "--samples", "80",
                 "--dense", "-o", str(gen), "-q"]) == 0  # fmt: skip
    rc, err = cli(capsys, "plot", folder, "--path", gen, "--triads", "5",
                  "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    assert err[-1].endswith(
        f"the generated path, 5 orientation triads on the generated path ->"
        f" {tmp_path / 'p.png'}"
    )
    (ax,) = figures[-1].axes
    path = read_csv(gen)
    idx = triad_indices(path.get("position"), 5)
    axes = [ln for ln in ax.lines if ln.get_color() in TRIAD_COLORS and
            np.isnan(ln.get_data_3d()[0]).any()]  # fmt: skip
    assert len(axes) == 3
    base = np.column_stack(axes[0].get_data_3d()).reshape(-1, 3, 3)[:, 0]
    np.testing.assert_array_equal(base, path.get("position")[idx])
    # without --path: on the first demonstration; --triads 0: none; 2-D: none
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "q.png")
    assert rc == 0 and "8 orientation triads on " in err[-1], err
    assert str(sorted(folder.glob("*.csv"))[0]) in err[-1]
    rc, err = cli(capsys, "plot", folder, "--triads", "0", "-o", tmp_path / "q.png")
    assert rc == 0 and "triads" not in err[-1], err
    rc, err = cli(capsys, "plot", folder, "--triads", "-1", "-o", tmp_path / "q.png")
    assert rc == 2 and "--triads" in err[0], err


def test_plot_colours_the_demonstrations_by_route(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    from ndlfd import plot

    folder = write_obstacle(tmp_path / "d", 4, 2)
    seen = {}

    def spy(*args, routes=None, **kw):
        seen["routes"] = routes
        return real(*args, routes=routes, **kw)

    real = plot.plot_demos
    monkeypatch.setattr(plot, "plot_demos", spy)
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png")
    assert rc == 0, err
    assert "coloured by route (2 routes: 4, 2 demonstrations)" in err[-1]
    np.testing.assert_array_equal(seen["routes"], [0, 0, 0, 0, 1, 1])
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png", "--routes", "1")
    assert rc == 0 and "coloured by route" not in err[-1]
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png", "--routes", "7")
    assert rc == 2
    assert "n_routes=7 is more than the 6 demonstrations" in err[-1]


def test_plot_joint_data_draws_each_channel_over_time(tmp_path, capsys, monkeypatch):
    # before: three joints in a 3-D projection, no time axis
    pytest.importorskip("matplotlib")
    pytest.importorskip("pyarrow")
    from lerobot_writer import SO101_MOTORS, write_so101
    from ndlfd.io import read_lerobot

    figures = keep_figures(monkeypatch)
    root, _ = write_so101(tmp_path / "so101", n_demos=4)
    model, gen, std = tmp_path / "m.ndlfd", tmp_path / "g.csv", tmp_path / "s.csv"
    assert main(["fit", str(root), "-o", str(model), "-q"]) == 0
    assert main(["generate", str(model), "--like", str(root), "--episodes", "1",
                 "--dense", "--std", str(std), "-o", str(gen), "-q"]) == 0  # fmt: skip
    rc, err = cli(capsys, "plot", root, "--path", gen, "--std", std,
                  "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    fitted = KeypointHMM.load(model)
    counts = [len(k) for k in fitted.keypoints_]
    assert err[-1] == (
        "drew 4 demonstration(s) over time, one axis per channel (6: joints,"
        f" gripper), with their key points ({min(counts)}-{max(counts)} at"
        " --epsilon 0.05), the generated path and its ±1 sd band ->"
        f" {tmp_path / 'p.png'}"
    )
    axes = figures[-1].axes
    # the dataset's channels in its order, each over the time axis
    assert [ax.get_ylabel() for ax in axes] == list(SO101_MOTORS)
    assert all(ax.name != "3d" and ax.get_aspect() == "auto" for ax in axes)
    demos = read_lerobot(root)
    path = read_csv(gen)
    s = read_table(std)[1]
    banded = 0
    for j, ax in enumerate(axes):
        for i, d in enumerate(demos):  # line, key points (those fit finds)
            np.testing.assert_array_equal(
                ax.lines[2 * i].get_xydata(), np.c_[d.t, d.X[:, j]]
            )
            k = fitted.keypoints_[i]
            np.testing.assert_array_equal(
                ax.lines[2 * i + 1].get_xydata(), np.c_[d.t[k], d.X[k, j]]
            )
        np.testing.assert_array_equal(
            ax.lines[-1].get_xydata(), np.c_[path.t, path.X[:, j]]
        )
        band = ax.collections[0].get_paths()[0]
        m = 20
        if s[m, 1 + j] > 0:  # (the gripper's sd is 0 where it is open)
            banded += 1
            y, w = path.X[m, j], s[m, 1 + j]
            assert band.contains_point((path.t[m], y + 0.9 * w))
            assert not band.contains_point((path.t[m], y + 1.1 * w))
    assert banded >= 5
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_a_position_of_one_column_over_time(tmp_path, capsys, monkeypatch):
    # before: drawn over time at equal aspect, a sliver when x spans little
    pytest.importorskip("matplotlib")

    figures = keep_figures(monkeypatch)
    folder = tmp_path / "d"
    folder.mkdir()
    t = np.linspace(0.0, 30.0, 60)
    for k in range(3):
        x = 0.01 * np.sin(t / 5 + 0.1 * k)  # 30 s against 2 cm
        rows = np.column_stack([t, x, t > 15])
        write_table(folder / f"d{k}.csv", ["t", "x", "gripper"], rows)
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png")
    assert rc == 0, err
    assert (
        "over time, one axis per channel (3: position, gripper, velocity)" in (err[-1])
    )
    axes = figures[-1].axes
    assert [ax.get_ylabel() for ax in axes] == ["x", "gripper", "vx"]
    assert all(ax.get_aspect() == "auto" for ax in axes)
    d0 = read_csv(folder / "d0.csv")
    np.testing.assert_array_equal(
        axes[0].lines[0].get_xydata(), np.c_[d0.t, d0.X[:, 0]]
    )


def test_plot_position_with_joints_draws_the_joints_over_time_beside(
    tmp_path, capsys, monkeypatch
):
    # before: only the position was drawn; the joints and gripper not at all
    pytest.importorskip("matplotlib")

    figures = keep_figures(monkeypatch)
    folder = tmp_path / "d"
    folder.mkdir()
    header = ["t", "x", "y", "z", "shoulder_pan.pos", "elbow_flex.pos", "gripper"]
    rng = np.random.default_rng(0)
    tables = []
    for i in range(4):
        n = 80 + 5 * i
        s = np.linspace(0, 1, n)
        rows = np.column_stack([
            3 * s, s + rng.normal(0, 0.003, n), 0.3 * np.sin(np.pi * s), 0.2 * s**2,
            40 * np.sin(np.pi * s) + i, -60 + 50 * s,
            np.where((s > 0.4) & (s < 0.8), 5.0, 40.0),
        ])  # fmt: skip
        write_table(folder / f"d{i}.csv", header, rows)
        tables.append(np.loadtxt(folder / f"d{i}.csv", delimiter=",", skiprows=1))
    model, gen, std = tmp_path / "m.ndlfd", tmp_path / "g.csv", tmp_path / "s.csv"
    assert main(["fit", str(folder), "-o", str(model), "-q"]) == 0
    assert main(["generate", str(model), "--duration", "3", "--samples", "60",
                 "--dense", "--std", str(std), "-o", str(gen), "-q"]) == 0  # fmt: skip
    rc, err = cli(capsys, "plot", folder, "--path", gen, "--std", std,
                  "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    fitted = KeypointHMM.load(model)
    counts = [len(k) for k in fitted.keypoints_]
    assert err[-1] == (
        "drew 4 demonstration(s) in 3-D (position) and over time (joints, gripper:"
        f" 3 channel(s)) with their key points ({min(counts)}-{max(counts)} at"
        " --epsilon 0.05), the generated path and its ±1 sd band over time (none"
        f" in 3-D) -> {tmp_path / 'p.png'}"
    )
    position, *channels = figures[-1].axes
    assert position.name == "3d"
    assert [ax.get_ylabel() for ax in channels] == [
        "shoulder_pan", "elbow_flex", "gripper"
    ]  # fmt: skip
    assert all(ax.name != "3d" for ax in channels)
    assert channels[-1].get_xlabel() == "time"
    gen_names = read_table(gen)[0]
    G, S = read_table(gen)[1], read_table(std)[1]
    for j, ax in enumerate(channels):
        col = 4 + j  # the file's column
        for i, tab in enumerate(tables):  # line, key points (those fit finds)
            np.testing.assert_array_equal(
                ax.lines[2 * i].get_xydata(), tab[:, [0, col]]
            )
            k = fitted.keypoints_[i]
            np.testing.assert_array_equal(
                ax.lines[2 * i + 1].get_xydata(), tab[k][:, [0, col]]
            )
        g = gen_names.index(header[col])
        np.testing.assert_array_equal(ax.lines[-1].get_xydata(), G[:, [0, g]])
        m = 30
        if S[m, g] > 0:
            band = ax.collections[0].get_paths()[0]
            assert band.contains_point((G[m, 0], G[m, g] + 0.9 * S[m, g]))
            assert not band.contains_point((G[m, 0], G[m, g] + 1.1 * S[m, g]))
    # without a path: the same axes, the demonstrations only
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "q.png")
    assert rc == 0 and " and over time (joints, gripper: 3 channel(s))" in err[-1]
    assert len(figures[-1].axes) == 4
