"""LeRobot datasets written with pyarrow (both layouts), read back through ndlfd."""

import pickle

import numpy as np
import pytest

pytest.importorskip("pyarrow")

from lerobot_writer import write_lerobot
from ndlfd import DataFileError, KeypointHMM, ValidationError
from ndlfd.io import DemoFiles, read_demos, read_lerobot
from ndlfd.io._lerobot import lerobot_episodes, parse_episodes
from ndlfd.orientation import euler_to_quaternions

STATE = ["x", "y", "z", "roll", "pitch", "yaw", "gripper"]
LAYOUTS = ["v2.1", "v3.0"]


def _episodes(lengths, seed=0):
    rng = np.random.default_rng(seed)
    out = []
    for n in lengths:
        s = np.linspace(0, 1, n)
        state = np.column_stack(
            [s, s**2, 0.1 * s, 0.3 * s, -0.2 * s, 0.5 - s, (s > 0.5).astype(float)]
        ) + rng.normal(0, 0.01, (n, 7))
        out.append({"observation.state": state, "action": rng.normal(size=(n, 2))})
    return out


def _names(action=("vx", "vy")):
    return {"observation.state": STATE, "action": list(action)}


@pytest.mark.parametrize("version", LAYOUTS)
@pytest.mark.parametrize("variable", [False, True])
def test_episodes_read_back_as_written(tmp_path, version, variable):
    eps = _episodes([5, 8, 3, 6, 7], seed=1)
    root = write_lerobot(
        tmp_path / "ds", eps, _names(), version=version, per_file=2, variable=variable
    )
    demos = read_lerobot(root)
    assert len(demos) == len(eps)
    for d, e in zip(demos, eps, strict=True):
        written = e["observation.state"].astype(np.float32).astype(np.float64)
        n = len(written)
        t = (np.arange(n) / 30).astype(np.float32).astype(np.float64)
        np.testing.assert_array_equal(d.t, t)
        np.testing.assert_array_equal(d.get("position"), written[:, :3])
        np.testing.assert_array_equal(d.get("gripper")[:, 0], written[:, 6])
        Q = euler_to_quaternions(written[:, 3:6], "xyz")
        np.testing.assert_allclose(d.get("orientation"), Q, atol=1e-12)
        assert d.columns == ("x", "y", "z", "qw", "qx", "qy", "qz", "gripper")


@pytest.mark.parametrize("version", LAYOUTS)
def test_another_feature_and_names_as_a_dict(tmp_path, version):
    eps = _episodes([4, 6])
    root = write_lerobot(tmp_path, eps, _names(), version=version, names_as=dict)
    demos = read_lerobot(root, feature="action")
    for d, e in zip(demos, eps, strict=True):
        np.testing.assert_array_equal(
            d.get("velocity"), e["action"].astype(np.float32).astype(np.float64)
        )


def test_components_without_names_are_numbered(tmp_path):
    root = write_lerobot(tmp_path, _episodes([4]), _names(), names_as=None)
    with pytest.raises(DataFileError, match=r"cannot tell the group.*'action_0'"):
        read_lerobot(root, feature="action")
    (d,) = read_lerobot(root, feature="action", groups={"joints": ["action_0"]},
                        drop=["action_1"])  # fmt: skip
    assert d.columns == ("action_0",)


@pytest.mark.parametrize("version", LAYOUTS)
def test_episode_selection(tmp_path, version):
    eps = _episodes([4, 5, 6, 7, 8, 9])
    root = write_lerobot(tmp_path, eps, _names(), version=version, per_file=4)
    lengths = [d.n_samples for d in read_lerobot(root, episodes="1:5:2")]
    assert lengths == [5, 7]
    assert [d.n_samples for d in read_lerobot(root, episodes="5,0")] == [9, 4]
    assert [d.n_samples for d in read_lerobot(root, episodes=3)] == [7]
    assert [d.n_samples for d in read_lerobot(root, episodes=slice(-2, None))] == [
        8,
        9,
    ]
    with pytest.raises(
        DataFileError, match=r"has no episode 6; its 6 episodes are 0-5"
    ):
        read_lerobot(root, episodes=[6])
    with pytest.raises(DataFileError, match=r"the episodes 7: select none of its 6"):
        read_lerobot(root, episodes="7:")
    with pytest.raises(ValidationError, match=r"episodes must look like 0:40.*'a:b'"):
        read_lerobot(root, episodes="a:b")


def test_parse_episodes_known_answers():
    eps = list(range(10))
    assert parse_episodes(None, eps, "d") == eps
    assert parse_episodes("::3", eps, "d") == [0, 3, 6, 9]
    assert parse_episodes(" 2 ", eps, "d") == [2]
    with pytest.raises(ValidationError, match="episodes must be None, an episode"):
        parse_episodes(1.5, eps, "d")
    assert parse_episodes(iter([4, 1]), eps, "d") == [4, 1]
    with pytest.raises(
        ValidationError, match=r"names episode 3 twice; got \[3, 1, 3\]"
    ):
        parse_episodes("3,1,3", eps, "d")


@pytest.mark.parametrize("version", LAYOUTS)
def test_missing_feature_is_one_line_naming_the_features(tmp_path, version):
    root = write_lerobot(tmp_path, _episodes([3]), _names(), version=version)
    with pytest.raises(DataFileError) as info:
        read_lerobot(root, feature="observation.effort")
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.endswith(
        "has no feature 'observation.effort'; its features are observation.state,"
        " action, observation.images.top"
    )
    with pytest.raises(
        DataFileError, match=r"'observation.images.top' is of dtype video"
    ):
        read_lerobot(root, feature="observation.images.top")


@pytest.mark.parametrize("version", LAYOUTS)
def test_episodes_of_one_frame(tmp_path, version):
    eps = _episodes([1, 4, 1])
    root = write_lerobot(tmp_path, eps, _names(), version=version)
    demos = read_lerobot(root)
    assert [d.n_samples for d in demos] == [1, 4, 1]
    np.testing.assert_array_equal(demos[2].t, [0.0])


@pytest.mark.parametrize("version", LAYOUTS)
def test_nan_in_a_state_names_the_episode_and_row(tmp_path, version):
    eps = _episodes([4, 5])
    eps[1]["observation.state"][3, 0] = np.nan
    eps[0]["observation.state"][2, 4] = np.nan  # an Euler angle
    root = write_lerobot(tmp_path, eps, _names(), version=version)
    with pytest.raises(DataFileError, match=r"episode 0: .*finite.*row 2"):
        read_lerobot(root, episodes=[0])
    with pytest.raises(DataFileError, match=r"episode 1: .*finite.*row 3"):
        read_lerobot(root, episodes=[1])


def test_not_a_dataset_and_bad_info(tmp_path):
    with pytest.raises(DataFileError, match="not a LeRobot dataset"):
        read_lerobot(tmp_path)
    (tmp_path / "meta").mkdir()
    (tmp_path / "meta" / "info.json").write_text('{"codebase_version": "v1.6"}')
    with pytest.raises(DataFileError, match="lacks features"):
        read_lerobot(tmp_path)
    (tmp_path / "meta" / "info.json").write_text(
        '{"codebase_version": "v1.6", "features": {}}'
    )
    with pytest.raises(DataFileError, match=r"'v1\.6' is not a LeRobot layout"):
        read_lerobot(tmp_path)
    (tmp_path / "meta" / "info.json").write_text("{")
    with pytest.raises(DataFileError, match="cannot be read as JSON"):
        read_lerobot(tmp_path)


def test_a_missing_data_file_names_the_episode(tmp_path):
    root = write_lerobot(tmp_path, _episodes([3, 3]), _names(), version="v2.1")
    (root / "data" / "chunk-000" / "episode_000001.parquet").unlink()
    with pytest.raises(DataFileError, match=r"episode 1: its data file .* not exist"):
        read_lerobot(root)


@pytest.mark.parametrize("version", LAYOUTS)
def test_files_stream_episodes_lazily_and_pickle(tmp_path, version):
    eps = _episodes([6, 7, 8, 9])
    root = write_lerobot(tmp_path / "ds", eps, _names(), version=version, per_file=3)
    files = DemoFiles(root, episodes="1:")
    assert len(files) == 3
    item = pickle.loads(pickle.dumps(files[1]))
    assert str(item.path) == f"{root} episode 2"
    assert item.read() == read_lerobot(root, episodes=[2])
    # read_demos and the fit take the dataset like a folder of files
    assert read_demos(root, feature="action") == read_lerobot(root, feature="action")
    model = KeypointHMM(groups=["position", "velocity"], n_time_bins=4).fit(files)
    assert model.n_demos_ == 3


def test_a_folder_listed_with_files_and_unknown_options(tmp_path):
    root = write_lerobot(tmp_path / "ds", _episodes([3, 4]), _names())
    assert len(lerobot_episodes(root)) == 2
    with pytest.raises(ValidationError, match=r"unexpected argument\(s\) \['colour'\]"):
        DemoFiles(root, colour="red")


def test_v3_files_of_one_row_group_and_a_missing_column(tmp_path):
    eps = _episodes([4, 5, 6, 3, 2])
    root = write_lerobot(tmp_path / "a", eps, _names(), per_file=3,
                         row_group_per_episode=False)  # fmt: skip
    for e, d in enumerate(read_lerobot(root, episodes="::-1")[::-1]):
        written = eps[e]["observation.state"].astype(np.float32).astype(np.float64)
        np.testing.assert_array_equal(d.get("position"), written[:, :3])
    # info.json names a feature the data files do not hold
    info = root / "meta" / "info.json"
    text = info.read_text().replace('"action"', '"action.missing"')
    info.write_text(text)
    with pytest.raises(
        DataFileError, match=r"episode 0: .* no column 'action.missing'"
    ):
        read_lerobot(root, feature="action.missing", episodes=[0])
