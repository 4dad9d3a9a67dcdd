"""ndlfd fit --frame-hands: which hands a task frame may move (issue 43).

Two arms written as a lab writes them (``left_x``, ..., ``left_qw``, ...,
``left_gripper``, then the same for ``right_``) with the object's position in
constant columns (``cube_x``, ``cube_y``, ``cube_z``). The task is built so
the answer is known: the right hand comes down onto the cube, holds a fixed
grasp point in the cube's frame, then carries it to a handover point fixed in
the world; the left hand's whole motion is in the world (it waits, then comes
to the handover point). So for a new cube the generated right hand must pass
through the new cube's grasp point, and a cube that may move only the right
hand leaves the left hand's path as it was, wherever the cube is.
"""

import numpy as np
import pytest
from cli_helpers import cli, fit_model

from ndlfd.io import read_csv, write_table

HOME_R = np.array([0.30, 0.50, 0.30])
HOME_L = np.array([-0.30, 0.50, 0.30])
HANDOVER = np.array([0.0, 0.50, 0.25])
GRASP = np.array([0.0, 0.0, 0.03])  # the grasp point in the cube's frame
HAND = ["x", "y", "z", "qw", "qx", "qy", "qz", "gripper"]
HEADER = (
    ["t"]
    + [f"left_{c}" for c in HAND]
    + [f"right_{c}" for c in HAND]
    + ["cube_x", "cube_y", "cube_z"]
)
FIT = ("--task-frame", "cube=cube_x,cube_y,cube_z", "--frame-hands", "cube=right")
#: New cube positions inside the demonstrated ones (x 0-0.16, y 0.42-0.58).
NEW_CUBES = ([0.05, 0.45, 0.02], [0.13, 0.56, 0.02])


def _ease(s):
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10 - 15 * s + 6 * s**2)


def _pieces(tau, knots, points):
    """Minimum-jerk pieces through ``points`` at normalized times ``knots``."""
    out = np.empty((tau.size, 3))
    for a in range(len(knots) - 1):
        m = (tau >= knots[a]) & (tau <= knots[a + 1])
        s = _ease((tau[m] - knots[a]) / (knots[a + 1] - knots[a]))[:, None]
        out[m] = points[a] + s * (points[a + 1] - points[a])
    return out


def _yaw(angle):
    """Unit quaternions w, x, y, z of turns about z by ``angle`` (n,)."""
    z = np.zeros_like(angle)
    return np.column_stack([np.cos(angle / 2), z, z, np.sin(angle / 2)])


def write_two_arms(folder, n_demos=12, seed=0, n=150):
    """The handover task as lab CSV files; each file's cube position."""
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    cubes = []
    for i in range(n_demos):
        cube = np.array([rng.uniform(0.0, 0.16), rng.uniform(0.42, 0.58), 0.02])
        grasp = cube + GRASP
        t = np.linspace(0.0, 5.0, n)
        tau = t / t[-1]
        j = rng.uniform(-0.03, 0.03, 3)
        knots = np.array([0.0, 0.30 + j[0], 0.45 + j[1], 0.75 + j[2], 1.0])
        right = _pieces(tau, knots, np.array([HOME_R, grasp, grasp, HANDOVER,
                                              HANDOVER]))  # fmt: skip
        # come down onto the cube from above: the approach's end lifted
        lift = np.interp(tau, [0.0, 0.6 * knots[1], knots[1]], [0.0, 0.04, 0.0])
        right[:, 2] += lift
        wait = HANDOVER - [0.06, 0.0, 0.0]  # beside the handover point
        left = _pieces(
            tau,
            np.array([0.0, 0.55, 0.80 + j[2], 1.0]),
            np.array([HOME_L, HOME_L, wait, wait]),
        )
        right += rng.normal(0.0, 2e-4, right.shape)
        left += rng.normal(0.0, 2e-4, left.shape)
        r_grip = np.where((tau > knots[1] + 0.03) & (tau < 0.92), 0.0, 1.0)
        l_grip = np.where(tau > 0.85, 0.0, 1.0)
        data = np.column_stack(
            [
                t,
                left,
                _yaw(0.3 * _ease((tau - 0.5) / 0.3)),
                l_grip,
                right,
                _yaw(np.pi - 0.4 * _ease(tau / 0.3)),
                r_grip,
                np.tile(cube, (n, 1)),
            ]
        )
        write_table(folder / f"episode_{i:02d}.csv", HEADER, data)
        cubes.append(cube)
    return folder, np.array(cubes)


@pytest.fixture(scope="module")
def two_arms(tmp_path_factory):
    """Demonstration files, a model fitted on them with --frame-hands, the cubes."""
    root = tmp_path_factory.mktemp("two_arms")
    folder, cubes = write_two_arms(root / "demos")
    model = fit_model(folder, root / "m.ndlfd", *FIT)
    return root, folder, root / "m.ndlfd", model, cubes


def _generate(capsys, model_path, cube, out):
    rc, err = cli(
        capsys,
        "generate",
        model_path,
        "--duration",
        "5",
        "--samples",
        "150",
        "--dense",
        "--task-frame",
        "cube=" + ",".join(map(str, cube)),
        "-o",
        out,
    )
    assert rc == 0, err
    return read_csv(out)


def test_the_lab_names_are_two_hands_and_the_cube_a_frame(capsys, tmp_path, two_arms):
    _, folder, _, model, cubes = two_arms
    assert model.groups_ == (
        "left_position",
        "right_position",
        "left_velocity",
        "right_velocity",
        "left_orientation",
        "right_orientation",
        "gripper",
    )
    assert model.frame_hands == {"cube": ["right"]}  # saved with the model
    np.testing.assert_array_equal(model.task_frames_["cube"], cubes)
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", *FIT)
    assert rc == 0, err
    line = next(e for e in err if e.startswith("task frames"))
    assert "cube (3 values; moved over" in line and "; moves right only)" in line
    # the peaks of each hand's positions, none of a quaternion or of the
    # velocities derived from the positions
    peaks = next(e for e in err if e.startswith("demonstrations' peaks"))
    said = [part.split(" velocity ")[0] for part in peaks.split(": ", 1)[1].split("; ")]
    assert said == ["left_position", "right_position"], peaks


@pytest.mark.parametrize("cube", NEW_CUBES)
def test_the_right_hand_reaches_a_new_cube(capsys, tmp_path, two_arms, cube):
    _, _, path, _, cubes = two_arms
    far = np.min(np.linalg.norm(cubes - cube, axis=1))
    assert far > 0.005  # not one of the demonstrations' cubes
    got = _generate(capsys, path, cube, tmp_path / "g.csv")
    right = got.X[:, [got.columns.index(f"right_{c}") for c in "xyz"]]
    grip = got.X[:, got.columns.index("right_gripper")]
    target = np.asarray(cube) + GRASP
    held = right[grip < 0.5]  # while the right gripper is closed
    assert held.size
    # the grasp: where the gripper closes, the hand on the new cube's grasp point
    miss = np.linalg.norm(held[0] - target)
    assert miss < 0.001, miss  # the noise is 0.2 mm
    # and it carries the cube to the handover point, fixed in the world
    assert np.linalg.norm(right[-1] - HANDOVER) < 0.003
    # the frame moved the hand: without it the grasp is elsewhere
    plain = _generate(capsys, path, cubes.mean(axis=0), tmp_path / "p.csv")
    pr = plain.X[:, [plain.columns.index(f"right_{c}") for c in "xyz"]]
    assert np.abs(pr - right).max() > 0.02


def test_a_cube_for_the_right_hand_leaves_the_left_one(capsys, tmp_path, two_arms):
    _, _, path, _, _ = two_arms
    a, b = (_generate(capsys, path, c, tmp_path / f"{k}.csv")
            for k, c in enumerate(NEW_CUBES))  # fmt: skip
    cols = [
        a.columns.index(f"left_{c}") for c in ("x", "y", "z", "qw", "qx", "qy", "qz")
    ]
    assert a.columns == b.columns
    np.testing.assert_allclose(a.X[:, cols], b.X[:, cols], atol=1e-9)
    # while the right hand went to each cube
    r = [a.columns.index(f"right_{c}") for c in "xyz"]
    assert np.abs(a.X[:, r] - b.X[:, r]).max() > 0.05


@pytest.mark.parametrize(
    ("flag", "message"),
    [
        (
            "cup=right",
            "--frame-hands names the frame 'cup', which the demonstrations do not"
            " carry; their task frames: cube",
        ),
        (
            "cube=middle",
            "--frame-hands cube names the hand 'middle'; the learned hands are"
            " 'left', 'right'",
        ),
        ("cube", "--frame-hands must look like FRAME=HAND[,HAND...]"),
        ("cube=", "--frame-hands must look like FRAME=HAND[,HAND...]"),
        ("cube=left,left", "--frame-hands cube names 'left' twice"),
        ("cube=right,", "--frame-hands cube must be a comma-separated list of names"),
        ("9cube=right", "--frame-hands NAME must be a name of letters"),
    ],
)
def test_bad_frame_hands_are_one_line(capsys, tmp_path, two_arms, flag, message):
    _, folder, _, _, _ = two_arms
    out = tmp_path / "m.ndlfd"
    rc, err = cli(
        capsys,
        "fit",
        folder,
        "-o",
        out,
        "--task-frame",
        "cube=cube_x,cube_y,cube_z",
        "--frame-hands",
        flag,
    )
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(f"ndlfd fit: error: {message}"), err
    assert not out.exists()  # nothing fitted


def test_frame_hands_without_task_frames_says_where_frames_come_from(
    capsys, tmp_path, two_arms
):
    _, folder, _, _, _ = two_arms
    rc, err = cli(
        capsys,
        "fit",
        folder,
        "-o",
        tmp_path / "m.ndlfd",
        "--drop",
        "cube_x,cube_y,cube_z",
        "--frame-hands",
        "cube=right",
    )
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(
        "ndlfd fit: error: --frame-hands names the frame 'cube', which the"
        " demonstrations do not carry; their task frames: none (give them with"
        " --task-frame)"
    ), err
