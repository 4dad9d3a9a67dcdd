"""ALOHA / ACT episode files (``episode_<i>.hdf5``) read as two arms.

The files are written as the ACT repository's ``record_sim_episodes.py`` and
ALOHA's ``aloha_scripts/record_episodes.py`` write them (the same calls: a
group ``observations`` with ``images``, one image dataset per camera chunked a
frame a chunk, ``qpos``/``qvel``/``action`` created without a dtype, then
every array assigned with ``root[name][...] = array``); the real robot's
compressed images as mobile ALOHA's script writes them. The groups each
episode must read into are worked out by hand from its 14 columns (per arm,
left then right, 6 joints and the gripper).
"""

import tracemalloc
import warnings

import numpy as np
import pytest

from ndlfd import DataFileError, KeypointHMM, NdlfdWarning
from ndlfd.cli import main
from ndlfd.io import DemoFiles, read_demos, read_hdf5

h5py = pytest.importorskip("h5py")
#: h5py 3.16 warns of a dataset created without a dtype (float32 by default),
#: as the recording scripts create qpos, qvel and action.
NO_DTYPE = getattr(h5py, "h5py_warnings", None)
NO_DTYPE = getattr(NO_DTYPE, "H5pyDeprecationWarning", DeprecationWarning)

NAMES = (
    "left_waist,left_shoulder,left_elbow,left_forearm_roll,left_wrist_angle,"
    "left_wrist_rotate"
)
MAPPING = (
    f"left_joints={NAMES}; gripper=left_gripper,right_gripper;"
    f" right_joints={NAMES.replace('left', 'right')}"
)
SIM_CAMERAS = ("top",)
REAL_CAMERAS = ("cam_high", "cam_low", "cam_left_wrist", "cam_right_wrist")


def write_episode(path, data, cameras=SIM_CAMERAS, *, sim=True, images=None,
                  compress=None, shapes=None):  # fmt: skip
    """An episode file as ACT's and ALOHA's recording scripts write it.

    ``data`` maps ``/observations/qpos``, ``/observations/qvel``, ``/action``
    (and on the real robot ``/observations/effort``) to their arrays;
    ``images`` the frames of each camera (none: the datasets are created and
    left unwritten, which is the same layout without 0.9 MB a frame on disk);
    ``compress`` the padded size of the real robot's JPEG bytes (mobile
    ALOHA's ``COMPRESS``); ``shapes`` overrides a dataset's shape.
    """
    shapes = shapes or {}
    n = len(data["/action"])
    with h5py.File(path, "w", rdcc_nbytes=1024**2 * 2) as root:
        root.attrs["sim"] = sim
        if compress is not None:
            root.attrs["compress"] = True
        obs = root.create_group("observations")
        image = obs.create_group("images")
        for cam_name in cameras:
            if compress is not None:
                image.create_dataset(cam_name, (n, compress), dtype="uint8",
                                     chunks=(1, compress))  # fmt: skip
            else:
                image.create_dataset(cam_name, (n, 480, 640, 3), dtype="uint8",
                                     chunks=(1, 480, 640, 3))  # fmt: skip
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NO_DTYPE)
            for name in data:
                group, key = name.rsplit("/", 1)
                where = root[group] if group else root
                where.create_dataset(key, shapes.get(name, (n, 14)))
            if compress is not None:
                root.create_dataset("compress_len", (len(cameras), n))
        for name, array in data.items():
            root[name][...] = array
        for cam_name, frames in (images or {}).items():
            root[f"/observations/images/{cam_name}"][...] = frames
    return path


def episode_data(n=40, seed=0, effort=False):
    """qpos, qvel, action of ``n`` steps: 12 joints, grippers in [0, 1]."""
    rng = np.random.default_rng(seed)
    qpos = np.cumsum(rng.normal(0, 0.01, (n, 14)), axis=0)
    qpos[:, [6, 13]] = rng.uniform(0, 1, (n, 2))
    action = qpos + rng.normal(0, 0.005, (n, 14))
    data = {
        "/observations/qpos": qpos,
        "/observations/qvel": np.gradient(qpos, 0.02, axis=0),
        "/action": action,
    }
    if effort:
        data["/observations/effort"] = rng.normal(size=(n, 14))
    return data


def as_stored(a):
    """What the file holds: h5py's default dtype is float32."""
    return np.asarray(a, dtype=np.float32).astype(np.float64)


def expect_arms(d, values):
    """The groups of an ALOHA episode, worked by hand from its 14 columns."""
    v = as_stored(values)
    assert d.group_names == ("left_joints", "gripper", "right_joints")
    np.testing.assert_array_equal(d.get("left_joints"), v[:, 0:6])
    np.testing.assert_array_equal(d.get("gripper"), v[:, [6, 13]])
    np.testing.assert_array_equal(d.get("right_joints"), v[:, 7:13])


def test_sim_episode_reads_the_action_into_two_arms(tmp_path):
    data = episode_data(n=8)
    rng = np.random.default_rng(1)
    frames = rng.integers(0, 256, (8, 480, 640, 3), dtype=np.uint8)
    p = write_episode(tmp_path / "episode_0.hdf5", data, images={"top": frames})
    with h5py.File(p) as f:  # the layout the scripts give
        assert f["action"].dtype == np.float32 and f.attrs["sim"]
        assert f["observations/images/top"].chunks == (1, 480, 640, 3)
    (d,) = read_hdf5(p)
    expect_arms(d, data["/action"])
    np.testing.assert_array_equal(d.t, np.arange(8) * 0.02)
    demos, maps = read_demos(p, return_mappings=True)
    assert demos == [d]
    assert str(maps[0]) == (
        f"time=(row number) / 50 Hz; {MAPPING} (ALOHA HDF5, action)"
    )
    assert maps[0].source == str(p) and maps[0].rate == 50.0


@pytest.mark.parametrize("feature", ["observations/qpos", "qpos", "observation.state"])
def test_the_measured_qpos_on_request(tmp_path, feature):
    data = episode_data()
    p = write_episode(tmp_path / "episode_0.hdf5", data)
    (d,) = read_hdf5(p, feature=feature)
    expect_arms(d, data["/observations/qpos"])
    _, maps = read_demos(tmp_path, feature=feature, return_mappings=True)
    assert str(maps[0]).endswith(" (ALOHA HDF5, observations/qpos)")
    (item,) = DemoFiles(tmp_path, feature=feature)
    expect_arms(item.read()[0], data["/observations/qpos"])
    with pytest.raises(DataFileError, match=r"feature 'qvel' names neither"):
        read_hdf5(p, feature="qvel")


def test_real_robot_episode_with_effort_and_compressed_images(tmp_path):
    data = episode_data(n=30, effort=True)
    p = write_episode(tmp_path / "episode_3.hdf5", data, REAL_CAMERAS,
                      sim=False, compress=20_000)  # fmt: skip
    (d,) = read_hdf5(p)
    expect_arms(d, data["/action"])
    # uncompressed, four cameras: the same
    q = write_episode(tmp_path / "episode_4.hdf5", data, REAL_CAMERAS, sim=False)
    assert read_hdf5(q) == [d]


class _Reads:
    """Every h5py dataset read, by name (slicing, np.asarray, read_direct)."""

    def __init__(self, monkeypatch):
        self.names = []
        for method in ("__getitem__", "__array__", "read_direct"):
            original = getattr(h5py.Dataset, method)

            def spy(ds, *args, _original=original, **kwargs):
                self.names.append(ds.name)
                return _original(ds, *args, **kwargs)

            monkeypatch.setattr(h5py.Dataset, method, spy)


def test_images_are_never_read(tmp_path, monkeypatch):
    data = episode_data(n=400)  # an episode's length in ACT's tasks
    p = write_episode(tmp_path / "episode_0.hdf5", data, REAL_CAMERAS)
    reads = _Reads(monkeypatch)
    with h5py.File(p) as f:  # the spy sees a read
        f["observations/images/cam_low"][0]
    assert reads.names == ["/observations/images/cam_low"]
    reads.names.clear()
    read_demos(tmp_path)
    assert reads.names == ["/action"]
    reads.names.clear()
    read_hdf5(p, feature="qpos")
    assert reads.names == ["/observations/qpos"]
    # four cameras of 400 frames are 1.47 GB read; the reading allocates ~0
    tracemalloc.start()
    try:
        with h5py.File(p) as f:  # tracemalloc sees what h5py reads
            f["observations/images/cam_high"][0]
            one_frame = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        read_hdf5(p)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert one_frame >= 480 * 640 * 3
    assert peak < 2_000_000, peak


def episode_folder(folder, n=3):
    """``n`` episode files of 30, 31, ... rows in ``folder``, and their data."""
    folder.mkdir()
    datas = [episode_data(n=30 + i, seed=i) for i in range(n)]
    for i, data in enumerate(datas):
        write_episode(folder / f"episode_{i}.hdf5", data)
    return datas


def test_a_folder_of_episodes_reads_and_fits_through_the_command_line(tmp_path, capsys):
    folder = tmp_path / "sim_transfer_cube_scripted"
    datas = episode_folder(folder)
    demos = read_demos(folder)
    for d, data in zip(demos, datas, strict=True):
        expect_arms(d, data["/action"])
        np.testing.assert_array_equal(d.t, np.arange(len(d.t)) * 0.02)
    assert [len(d.t) for d in demos] == [30, 31, 32]
    out = tmp_path / "m.ndlfd"
    capsys.readouterr()
    assert main(["fit", str(folder), "-o", str(out)]) == 0
    said = capsys.readouterr().err.splitlines()
    assert said[0] == (
        "read 3 demonstration(s) from 3 file(s): time=(row number) / 50 Hz;"
        f" {MAPPING} (ALOHA HDF5, action)"
    )
    assert set(KeypointHMM.load(out).groups_) == {
        "left_joints",
        "gripper",
        "right_joints",
    }


def test_the_command_line_reads_the_measured_joints_on_request(tmp_path, capsys):
    folder = tmp_path / "episodes"
    episode_folder(folder)
    out = tmp_path / "m.ndlfd"
    capsys.readouterr()
    argv = ["fit", str(folder), "-o", str(out), "--feature", "observations/qpos"]
    assert main(argv) == 0
    said = capsys.readouterr().err.splitlines()
    assert said[0].endswith("(ALOHA HDF5, observations/qpos)"), said[0]
    # what a CSV source cannot take is still refused
    csv = tmp_path / "a.csv"
    csv.write_text("t,x,y\n0,0,0\n1,1,1\n2,2,0\n")
    assert main(["fit", str(csv), "-o", str(out), "--feature", "action"]) == 2
    assert "or ALOHA episode files (.hdf5)" in capsys.readouterr().err
    assert main(["fit", str(folder), "-o", str(out), "--episodes", "0:2"]) == 2
    assert "--episodes selects from a LeRobot dataset" in capsys.readouterr().err


def test_the_clock_the_file_gives_and_the_row_number(tmp_path):
    data = episode_data(n=10)
    p = write_episode(tmp_path / "episode_0.hdf5", data)
    (d,) = read_hdf5(p, time_column=None)
    np.testing.assert_array_equal(d.t, np.arange(10.0))
    (d,) = read_demos(p, rate=25)
    np.testing.assert_array_equal(d.t, np.arange(10) / 25)
    with h5py.File(p, "a") as f:
        f.attrs["fps"] = 30
    _, (m,) = read_demos(p, return_mappings=True)
    np.testing.assert_array_equal(read_hdf5(p)[0].t, np.arange(10) * (1 / 30))
    assert str(m).startswith("time=(row number) / 30 Hz;")
    with h5py.File(p, "a") as f:
        del f.attrs["fps"]
        f.attrs["dt"] = 0.1
    np.testing.assert_array_equal(read_hdf5(p)[0].t, np.arange(10) * 0.1)
    with h5py.File(p, "a") as f:
        f.attrs["dt"] = -1.0
    with pytest.raises(DataFileError, match=r"'dt' must be a positive number"):
        read_hdf5(p)
    with pytest.raises(DataFileError, match=r"has no time dataset \(time_column="):
        read_hdf5(p, time_column="time")


@pytest.mark.parametrize(
    ("shapes", "message"),
    [
        ({"/action": (40, 16)}, r"/action must be of shape \(T, 14\) .*got shape"
         r" \(40, 16\)"),
        ({"/observations/qpos": (40, 12)}, r"/observations/qpos must be of shape"
         r" \(T, 14\) \(per arm, left then right, 6 joints and the gripper\); got"
         r" shape \(40, 12\)"),
        ({"/action": (40,)}, r"/action must be of shape \(T, 14\).*got shape \(40,\)"),
        ({"/observations/qpos": (41, 14)}, r"/observations/qpos has 41 rows and"
         r" /action 40; expected one row of each per time step"),
    ],
)  # fmt: skip
def test_wrong_shapes_say_what_was_expected(tmp_path, shapes, message):
    data = episode_data(n=40)
    for name, shape in shapes.items():
        data[name] = np.zeros(shape)
    p = write_episode(tmp_path / "episode_0.hdf5", data, shapes=shapes)
    with pytest.raises(DataFileError, match=message):
        read_hdf5(p)
    with pytest.raises(DataFileError, match=r"episode_0\.hdf5: "):
        read_demos(tmp_path)


def test_an_empty_episode(tmp_path):
    data = {k: np.zeros((0, 14)) for k in episode_data()}
    # no cameras: h5py refuses a chunk of one frame in an empty image dataset
    p = write_episode(tmp_path / "episode_0.hdf5", data, cameras=())
    with pytest.raises(DataFileError, match=r"holds no time step \(/action has"
                       r" shape \(0, 14\)\)"):  # fmt: skip
        read_hdf5(p)


def test_nan_rows_as_everywhere(tmp_path):
    data = episode_data(n=20)
    data["/action"][[4, 9], 3] = np.nan
    data["/observations/qpos"][0, 0] = np.nan  # not read: not checked
    p = write_episode(tmp_path / "episode_0.hdf5", data)
    with pytest.raises(DataFileError, match=r"episode_0\.hdf5: .*row 4"):
        read_hdf5(p)
    with pytest.warns(NdlfdWarning, match="dropped 2 of 20 row"):
        (d,) = read_hdf5(p, bad_rows="drop")
    keep = np.setdiff1d(np.arange(20), [4, 9])
    expect_arms(d, data["/action"][keep])
    np.testing.assert_array_equal(d.t, keep * 0.02)  # the clock keeps its gaps


def test_a_model_fitted_on_aloha_episodes_generates_both_arms(tmp_path):
    """Synthetic episodes: each joint a smooth move, grippers close then open."""
    n = 100
    s = np.linspace(0, 1, n)
    u = s**3 * (10 - 15 * s + 6 * s**2)
    rng = np.random.default_rng(3)
    goals = []
    for i in range(5):
        goal = rng.uniform(-0.5, 0.5, 14)
        q = np.outer(u, goal) + rng.normal(0, 1e-3, (n, 14))
        q[:, [6, 13]] = (np.abs(s - 0.5) < 0.25)[:, None] * 1.0
        data = {"/observations/qpos": q, "/observations/qvel": 0 * q, "/action": q}
        write_episode(tmp_path / f"episode_{i}.hdf5", data)
        goals.append(goal)
    model = KeypointHMM().fit(DemoFiles(tmp_path))
    t = np.arange(60) * (2.0 / 59)
    path = model.generate(t, dense=True)
    assert set(path.group_names) == {"left_joints", "gripper", "right_joints"}
    # every joint ends within the demonstrations' goals (their spread's range)
    goals = as_stored(np.array(goals))
    end = np.concatenate([path.get("left_joints")[-1], path.get("right_joints")[-1]])
    lo, hi = goals.min(0), goals.max(0)
    cols = [*range(6), *range(7, 13)]
    assert np.all(end >= lo[cols] - 0.01) and np.all(end <= hi[cols] + 0.01)
    # the grippers keep their two values: closed in the middle, open at the ends
    g = path.get("gripper")
    assert set(np.unique(g)) <= {0.0, 1.0}
    assert g[0].tolist() == [0.0, 0.0] and g[30].tolist() == [1.0, 1.0]
