"""ndlfd fit / generate / sample --task-frame: frames from columns, new poses."""

import numpy as np
import pytest
from cli_helpers import build_parser_help, cli, fit_model

from ndlfd import synth
from ndlfd.io import read_csv, write_table

OBJECT = ["obj_x", "obj_y", "obj_z", "obj_qw", "obj_qx", "obj_qy", "obj_qz"]
PLACE = ["place_x", "place_y", "place_z"]
FRAME_FLAGS = (
    "--task-frame",
    "object=" + ",".join(OBJECT),
    "--task-frame",
    "place=" + ",".join(PLACE),
)
T = np.linspace(0.0, 6.0, 60)
NEW_OBJECT = [0.45, 0.05, 0.02, 0.0, 1.0, 0.0, 0.0]
NEW_PLACE = [0.35, 0.3, 0.02]


def values(path, like):
    """The path written to CSV ``path``, its columns in the order of ``like``'s."""
    got = read_csv(path)
    assert sorted(got.columns) == sorted(like.columns)
    return got.X[:, [got.columns.index(c) for c in like.columns]]


def write_pick_place(folder, n_demos=6):
    """``synth.pick_place`` as CSV files, each frame in constant columns."""
    folder.mkdir(parents=True, exist_ok=True)
    demos, frames = synth.pick_place(n_demos, n_samples=100)
    for i, (d, f) in enumerate(zip(demos, frames, strict=True)):
        n = d.n_samples
        data = np.column_stack(
            [d.t, d.X, np.tile(f["object"], (n, 1)), np.tile(f["place"][:3], (n, 1))]
        )
        header = ["t", "x", "y", "z", "qw", "qx", "qy", "qz", "gripper"]
        write_table(folder / f"d{i}.csv", header + OBJECT + PLACE, data)
    return folder, frames


@pytest.fixture(scope="module")
def framed(tmp_path_factory):
    """A model fitted with both frames from the files, and the true frames."""
    root = tmp_path_factory.mktemp("frames")
    folder, frames = write_pick_place(root / "demos")
    model = fit_model(folder, root / "m.ndlfd", *FRAME_FLAGS)
    return root, root / "m.ndlfd", model, frames


def test_fit_takes_frames_from_constant_columns(capsys, tmp_path, framed):
    root, _, model, frames = framed
    assert list(model.task_frames_) == ["object", "place"]
    np.testing.assert_allclose(
        model.task_frames_["object"], [f["object"] for f in frames], atol=1e-12
    )
    np.testing.assert_array_equal(
        model.task_frames_["place"], [f["place"][:3] for f in frames]
    )
    # the frame columns are not learned as data, and not written back
    assert not any(c.startswith(("obj_", "place_")) for c in model.columns_)
    assert model.groups_ == ("position", "velocity", "orientation", "gripper")
    assert model.input_mapping_ is not None
    assert "obj_x" not in model.input_mapping_.order
    rc, err = cli(
        capsys, "fit", root / "demos", "-o", tmp_path / "m.ndlfd", *FRAME_FLAGS
    )
    assert rc == 0, err
    assert "task frame object=" + ",".join(OBJECT) in err[0], err
    assert "task frame place=" + ",".join(PLACE) in err[0], err
    line = next(e for e in err if e.startswith("task frames"))
    places = np.array([f["place"][:3] for f in frames])
    apart = max(np.linalg.norm(a - b) for a in places for b in places)
    assert (
        "object (7 values" in line
        and f"place (3 values; moved over {apart:.3g})" in line
    )
    assert "--task-frame place=X,Y,Z" in line
    assert not any(e.startswith("not learned") for e in err), err


def test_generate_with_task_frames_is_the_library_path(capsys, tmp_path, framed):
    _, path, model, _ = framed
    frames = {"object": NEW_OBJECT, "place": NEW_PLACE}
    flags = [
        "--task-frame",
        "object=" + ",".join(map(str, NEW_OBJECT)),
        "--task-frame",
        "place=" + ",".join(map(str, NEW_PLACE)),
    ]
    rc, err = cli(
        capsys,
        "generate",
        path,
        "--duration",
        "6",
        "--samples",
        "60",
        "--dense",
        *flags,
        "-o",
        tmp_path / "g.csv",
    )
    assert rc == 0, err
    expected = model.generate(T, dense=True, frames=frames)
    got = values(tmp_path / "g.csv", expected)
    np.testing.assert_allclose(got, expected.X, rtol=5e-10, atol=1e-12)
    plain = model.generate(T, dense=True)
    assert np.abs(plain.X - expected.X).max() > 1e-3  # the frames moved it
    # one frame alone
    rc, err = cli(
        capsys,
        "generate",
        path,
        "--duration",
        "6",
        "--samples",
        "60",
        "--dense",
        *flags[2:],
        "-o",
        tmp_path / "p.csv",
    )
    assert rc == 0, err
    expected = model.generate(T, dense=True, frames={"place": NEW_PLACE})
    np.testing.assert_allclose(
        values(tmp_path / "p.csv", expected), expected.X, rtol=5e-10, atol=1e-12
    )


def test_sample_with_task_frames_is_the_library_draw(capsys, tmp_path, framed):
    _, path, model, _ = framed
    rc, err = cli(
        capsys,
        "sample",
        path,
        "--duration",
        "6",
        "--samples",
        "60",
        "-n",
        "2",
        "--random-state",
        "3",
        "--task-frame",
        "place=" + ",".join(map(str, NEW_PLACE)),
        "-o",
        tmp_path / "s",
    )
    assert rc == 0, err
    expected = model.sample(T, 2, random_state=3, frames={"place": NEW_PLACE})
    files = sorted((tmp_path / "s").glob("sample_*.csv"))
    assert len(files) == 2
    for f, e in zip(files, expected, strict=True):
        np.testing.assert_allclose(values(f, e), e.X, rtol=5e-10, atol=1e-12)


@pytest.mark.parametrize(
    ("flag", "message"),
    [
        ("object", "--task-frame must look like NAME=X,Y,Z[,QW,QX,QY,QZ]"),
        ("object=", "--task-frame must look like NAME=X,Y,Z[,QW,QX,QY,QZ]"),
        (
            "object=a,b,c",
            "--task-frame object must be comma-separated numbers; got 'a,b,c'",
        ),
        ("9x=1,2,3", "--task-frame NAME must be a name of letters"),
        ("place=1,nan,3", "--task-frame place must be finite numbers"),
        (
            "cup=1,2,3",
            "--task-frame names frame 'cup', which the model did not"
            " learn; it learned object, place",
        ),
        (
            "object=0.4,0,0.02",
            "--task-frame object must give 7 values (x, y, z,"
            " then a unit quaternion qw, qx, qy, qz)",
        ),
        ("place=1,2,3,4", "--task-frame place must give 3 values (a position)"),
        ("object=0.4,0,0.02,2,0,0,0", "--task-frame object: the quaternion"),
    ],
)
@pytest.mark.parametrize("command", ["generate", "sample"])
def test_bad_task_frames_are_one_line(capsys, tmp_path, framed, command, flag, message):
    _, path, _, _ = framed
    rc, err = cli(
        capsys,
        command,
        path,
        "--duration",
        "6",
        "--task-frame",
        flag,
        "-o",
        tmp_path / "out.csv",
    )
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(f"ndlfd {command}: error: {message}"), err


def test_a_frame_given_twice(capsys, tmp_path, framed):
    _, path, _, _ = framed
    rc, err = cli(
        capsys,
        "generate",
        path,
        "--duration",
        "6",
        "--task-frame",
        "place=1,2,3",
        "--task-frame",
        "place=1,2,4",
        "-o",
        tmp_path / "out.csv",
    )
    assert rc == 2 and len(err) == 1, err
    assert "--task-frame gives place twice ('place=1,2,4')" in err[0]


def test_models_without_frames_or_blend_refuse_them(capsys, tmp_path, framed):
    root = framed[0]
    drop = ",".join(OBJECT + PLACE)
    plain = fit_model(root / "demos", tmp_path / "plain.ndlfd", "--drop", drop)
    assert plain.task_frames_ == {}
    rc, err = cli(
        capsys,
        "generate",
        tmp_path / "plain.ndlfd",
        "--duration",
        "6",
        "--task-frame",
        "place=1,2,3",
        "-o",
        tmp_path / "out.csv",
    )
    assert rc == 2 and len(err) == 1, err
    assert "this model learned none (fit it with --task-frame" in err[0]
    fit_model(
        root / "demos", tmp_path / "paper.ndlfd", "--generation", "paper", *FRAME_FLAGS
    )
    rc, err = cli(
        capsys,
        "generate",
        tmp_path / "paper.ndlfd",
        "--duration",
        "6",
        "--task-frame",
        "place=1,2,3",
        "-o",
        tmp_path / "out.csv",
    )
    assert rc == 2 and len(err) == 1, err
    assert "--task-frame needs a model fitted with --generation blend" in err[0]


def test_a_frame_column_that_varies_names_file_column_and_range(capsys, tmp_path):
    folder, frames = write_pick_place(tmp_path / "demos", n_demos=2)
    text = (folder / "d1.csv").read_text().splitlines()
    j = text[0].split(",").index("obj_y")
    row = text[5].split(",")
    row[j] = "0.75"
    text[5] = ",".join(row)
    (folder / "d1.csv").write_text("\n".join(text) + "\n")
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", *FRAME_FLAGS)
    assert rc == 2, err
    low = min(frames[1]["object"][1], 0.75)
    assert err[-1] == (
        f"ndlfd fit: error: {folder / 'd1.csv'}: --task-frame object: column"
        " 'obj_y' must be constant over the demonstration (a task frame is one"
        f" pose per demonstration); got values from {low:.10g} to 0.75"
    )


@pytest.mark.parametrize(
    ("flags", "drop", "message"),
    [
        (["object"], OBJECT, "--task-frame must look like NAME=COLUMN,COLUMN,..."),
        (
            ["place=place_x,,place_z"],
            OBJECT,
            "--task-frame place must be a comma-separated list of names without"
            " empty entries",
        ),
        (
            ["place=place_x,place_y,place_z", "place=obj_x,obj_y,obj_z"],
            OBJECT,
            "--task-frame gives place twice",
        ),
        (
            ["place=place_x,place_y,nope"],
            OBJECT,
            "d0.csv: --task-frame place names 'nope', but there is no such column",
        ),
        (
            ["place=place_x,place_y"],
            [*OBJECT, "place_z"],
            "--task-frame place names 2 column(s); expected 3 (a position, as the"
            " position group of",
        ),
        (
            ["object=place_x,place_y,place_z", "place=place_x,place_y,place_z"],
            OBJECT,
            "d0.csv: the flags map column 'place_x' to both --task-frame"
            " object and --task-frame place",
        ),
        (
            ["place=place_x,place_y,place_z"],
            [*OBJECT, "place_z"],
            "d0.csv: --task-frame place names column 'place_z', which is the time"
            " column or dropped",
        ),
    ],
)
def test_bad_frame_columns_are_one_line(capsys, tmp_path, framed, flags, drop, message):
    root = framed[0]
    args = [a for f in flags for a in ("--task-frame", f)]
    rc, err = cli(
        capsys,
        "fit",
        root / "demos",
        "-o",
        tmp_path / "m.ndlfd",
        "--drop",
        ",".join(drop),
        *args,
    )
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith("ndlfd fit: error: "), err
    assert message in err[0], err


def test_two_dimensional_frames(capsys, tmp_path):
    """A 2-D position: a frame is x,y (where each square ended)."""
    demos, _ = synth.make_dataset("square", n_demos=6, random_state=0)
    for i, d in enumerate(demos):
        end = np.tile(d.get("position")[-1], (d.n_samples, 1))
        write_table(
            tmp_path / "demos" / f"s{i}.csv",
            ["t", *d.columns, "end_x", "end_y"],
            np.column_stack([d.t, d.X, end]),
        )
    model = fit_model(
        tmp_path / "demos", tmp_path / "sq.ndlfd", "--task-frame", "end=end_x,end_y"
    )
    np.testing.assert_array_equal(
        model.task_frames_["end"], [d.get("position")[-1] for d in demos]
    )
    t = np.linspace(0.0, float(demos[0].t[-1]), 50)
    rc, err = cli(
        capsys,
        "generate",
        tmp_path / "sq.ndlfd",
        "--duration",
        repr(float(t[-1])),
        "--samples",
        "50",
        "--dense",
        "--task-frame=end=0.2,-0.1",
        "-o",
        tmp_path / "g.csv",
    )
    assert rc == 0, err
    expected = model.generate(t, dense=True, frames={"end": [0.2, -0.1]})
    np.testing.assert_allclose(
        values(tmp_path / "g.csv", expected), expected.X, rtol=5e-10, atol=1e-12
    )
    rc, err = cli(
        capsys,
        "generate",
        tmp_path / "sq.ndlfd",
        "--duration",
        "1",
        "--task-frame",
        "end=0.2,-0.1,0",
        "-o",
        tmp_path / "g.csv",
    )
    assert rc == 2 and "--task-frame end must give 2 values (a position)" in err[0]


def test_every_command_of_a_path_lists_task_frame():
    for command in ("fit", "generate", "sample"):
        assert "--task-frame" in build_parser_help(command)
