"""ndlfd plot --task-frame / --path-frame: the frames read as fit reads them, drawn."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from cli_helpers import cli, keep_figures
from test_cli_task_frames import (
    FRAME_FLAGS,
    NEW_OBJECT,
    NEW_PLACE,
    OBJECT,
    write_pick_place,
)

import ndlfd.cli
import ndlfd.plot
from ndlfd import ValidationError
from ndlfd.plot import DEMO_COLOR, ROUTE_COLORS, new_figure, plot_frames

PATH_FLAGS = [
    "--path-frame",
    "object=" + ",".join(map(str, NEW_OBJECT)),
    "--path-frame",
    "place=" + ",".join(map(str, NEW_PLACE)),
]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """``synth.pick_place`` as CSVs (frames in constant columns), fit, a path."""
    root = tmp_path_factory.mktemp("plot-frames")
    folder, frames = write_pick_place(root / "demos", n_demos=5)
    model = root / "m.ndlfd"
    new = [a.replace("--path-frame", "--task-frame") for a in PATH_FLAGS]
    assert ndlfd.cli.main(["fit", str(folder), "-o", str(model), *FRAME_FLAGS]) == 0
    args = ["generate", str(model), "--duration", "6", "--samples", "60", *new]
    assert ndlfd.cli.main([*args, "-o", str(root / "path.csv")]) == 0
    return folder, root / "path.csv", frames


@pytest.fixture
def figures(monkeypatch):
    """The figures ``ndlfd plot`` saves, kept."""
    return keep_figures(monkeypatch)


def _marks(ax, marker, color=None):
    """The positions of the markers ``marker`` (of colour ``color``) on 3-D ``ax``."""
    return np.array(
        [
            np.ravel(ln.get_data_3d())
            for ln in ax.lines
            if ln.get_marker() == marker and color in (None, ln.get_color())
        ]
    )


def _sorted(rows):
    rows = np.asarray(rows, dtype=float)
    return rows[np.lexsort(rows.T[::-1])]


def test_plot_marks_each_demonstrations_task_frames(capsys, tmp_path, fitted, figures):
    folder, path, frames = fitted
    out = tmp_path / "out.png"
    args = ["plot", folder, *FRAME_FLAGS, "--path", path, *PATH_FLAGS, "-o", out]
    rc, err = cli(capsys, *args)
    assert rc == 0, err
    assert out.read_bytes()[:8] == PNG_MAGIC
    assert "task frame object=" + ",".join(OBJECT) in err[0], err
    assert "each demonstration's task frames (object, place)" in err[-1], err
    assert "the path's (object, place)" in err[-1], err
    (ax,) = [a for a in figures[0].axes if a.name == "3d"]
    # one marker per frame name, at each demonstration's frame, in its colour
    for marker, name in (("s", "object"), ("^", "place")):
        got = _marks(ax, marker, DEMO_COLOR)
        want = [f[name][:3] for f in frames]
        np.testing.assert_allclose(_sorted(got), _sorted(want), atol=1e-9)
    np.testing.assert_allclose(_marks(ax, "s", "black"), [NEW_OBJECT[:3]])
    np.testing.assert_allclose(_marks(ax, "^", "black"), [NEW_PLACE])
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    for label in ("task frame object", "task frame place", "object of the path"):
        assert labels.count(label) == 1, labels
    # an arrow along the x axis of each pose with an orientation (the objects')
    assert len(ax.collections) == len(frames) + 1
    # the frame columns are not drawn as data: position, then the gripper
    assert [a.get_ylabel() for a in figures[0].axes if a.name != "3d"] == ["gripper"]


def test_plot_without_the_flag_cannot_tell_the_frame_columns(capsys, tmp_path, fitted):
    folder, _, _ = fitted
    rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png")
    assert rc == 2 and "cannot tell the group of column(s) ['obj_x'" in err[-1]


def test_plot_task_frame_errors_are_fits(capsys, tmp_path, fitted):
    folder, _, _ = fitted
    bad = ["--task-frame", "object=" + ",".join(OBJECT), "--task-frame"]
    for cols in ("place_x,place_y,place_w", "place_x,place_y"):
        flags = [*bad, "place=" + cols]
        rc, fit_err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", *flags)
        assert rc == 2
        rc, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png", *flags)
        assert rc == 2
        assert err[-1].replace("ndlfd plot", "ndlfd fit") == fit_err[-1], err
    _, err = cli(capsys, "plot", folder, "-o", tmp_path / "p.png", *bad, "place=w")
    assert "--task-frame place names 'w', but there is no such column" in err[-1]
    assert not (tmp_path / "p.png").exists()


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--path-frame", "object=1,2"], "--path-frame object must hold 3 values"),
        (
            ["--path-frame", "object=1,2,3,2,0,0,0"],
            "--path-frame object: the quaternion (w, x, y, z) = [2.0, 0.0, 0.0, 0.0]"
            " must have unit length",
        ),
        (["--path-frame", "object"], "--path-frame must look like NAME=X,Y,Z"),
        (
            ["--path-frame", "place=0,0,0", "--path-frame", "place=1,1,1"],
            "--path-frame gives place twice",
        ),
    ],
)
def test_path_frame_errors(capsys, tmp_path, fitted, flags, message):
    folder, path, _ = fitted
    out = tmp_path / "p.png"
    rc, err = cli(
        capsys, "plot", folder, *FRAME_FLAGS, "--path", path, *flags, "-o", out
    )
    assert rc == 2 and message in err[-1], err
    assert not out.exists()


def test_path_frame_needs_the_path(capsys, tmp_path, fitted):
    folder, _, _ = fitted
    rc, err = cli(capsys, "plot", folder, *PATH_FLAGS, "-o", tmp_path / "p.png")
    assert rc == 2 and "--path-frame marks the task frames of --path" in err[-1]


def test_plot_frames_on_2d_axes_projects_the_x_axis():
    _, (ax,) = new_figure(1)
    turned = [1.0, 2.0, 0.5, np.cos(np.pi / 8), 0.0, 0.0, np.sin(np.pi / 8)]  # 45 deg
    down = [
        3.0,
        1.0,
        0.0,
        np.sqrt(0.5),
        0.0,
        np.sqrt(0.5),
        0.0,
    ]  # x axis along z: no arrow
    frames = [{"object": turned}, {"object": down, "place": [2.0, 2.0]}]
    colors = list(ROUTE_COLORS[:2])
    plot_frames(ax, frames, colors=colors, names=["place", "object"], length=0.5)
    objects = [ln for ln in ax.lines if ln.get_marker() == "^"]
    assert [ln.get_xydata().tolist() for ln in objects] == [[[1.0, 2.0]], [[3.0, 1.0]]]
    assert [ln.get_color() for ln in objects] == colors
    assert [ln.get_label() for ln in objects] == ["task frame object", "_nolegend_"]
    (place,) = [ln for ln in ax.lines if ln.get_marker() == "s"]
    assert place.get_xydata().tolist() == [[2.0, 2.0]]
    (arrow,) = ax.collections  # at 45 degrees
    np.testing.assert_allclose(arrow.get_offsets(), [[1.0, 2.0]])
    np.testing.assert_allclose([arrow.U[0], arrow.V[0]], [0.5 * np.sqrt(0.5)] * 2)
    with pytest.raises(ValidationError, match="one colour per item"):
        plot_frames(ax, frames, colors=["red"])
    with pytest.raises(ValidationError, match="place missing"):
        plot_frames(ax, frames, names=["object"])


def test_plot_reads_the_frames_of_bags_as_fit_does(capsys, tmp_path, figures):
    pytest.importorskip("rosbags")
    from test_cli_task_frames_sources import BAG_FLAGS, write_pick_place_bags

    folder, frames = write_pick_place_bags(tmp_path / "bags", n_demos=3)
    rc, err = cli(capsys, "plot", folder, *BAG_FLAGS, "-o", tmp_path / "b.png")
    assert rc == 0, err
    assert "task frame object=/object_pose; task frame place=/place" in err[0]
    (ax,) = [a for a in figures[0].axes if a.name == "3d"]
    got = _marks(ax, "s")
    want = [f["object"][:3] for f in frames]
    np.testing.assert_allclose(_sorted(got), _sorted(want), atol=1e-9)
    # two routes here: each frame in its demonstration's colour (its key points')
    assert "coloured by route (2 routes" in err[-1], err
    colors = [ln.get_color() for ln in ax.lines if ln.get_marker() == "o"]
    for marker in ("s", "^"):
        marks = [ln for ln in ax.lines if ln.get_marker() == marker]
        assert sorted(ln.get_color() for ln in marks) == sorted(colors)
