"""Parquet output in LeRobot's episode layout (``ndlfd.io._parquet``), read back."""

import json
import shutil
import sys

import numpy as np
import pytest

pytest.importorskip("pyarrow")

import pyarrow as pa
import pyarrow.parquet as pq

from lerobot_writer import SO101_STATE, write_lerobot, write_so101
from ndlfd import DataFileError, KeypointHMM, MissingExtraError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.io import read_demos, read_lerobot, read_parquet, write_parquet
from ndlfd.io._lerobot import lerobot_episodes, read_episode_mapped
from ndlfd.io._mapping import LIBRARY_HINTS, MAPPING_DEFAULTS


def _episode(root, e=0, feature="observation.state"):
    (item,) = lerobot_episodes(root, feature, episodes=[e])
    return read_episode_mapped(item, LIBRARY_HINTS, **MAPPING_DEFAULTS)[0]


def _as_dataset(parquet, root, feature, names):
    """A LeRobot v3.0 dataset of one episode: ``parquet`` as its data file."""
    info = {
        "codebase_version": "v3.0",
        "features": {
            feature: {"dtype": "float32", "shape": [len(names)], "names": names}
        },
        "data_path": "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet",
        "total_episodes": 1,
        "fps": 30,
    }
    (root / "meta" / "episodes" / "chunk-000").mkdir(parents=True)
    (root / "meta" / "info.json").write_text(json.dumps(info))
    episodes = {"episode_index": [0], "data/chunk_index": [0], "data/file_index": [0]}
    pq.write_table(
        pa.table(episodes), root / "meta/episodes/chunk-000/file-000.parquet"
    )
    (root / "data" / "chunk-000").mkdir(parents=True)
    shutil.copy(parquet, root / "data/chunk-000/file-000.parquet")
    return root


@pytest.mark.parametrize("feature", ["observation.state", "action"])
def test_a_generated_path_is_written_as_a_lerobot_episode(tmp_path, feature):
    root, _ = write_so101(tmp_path / "so101", n_demos=4)
    like, m = _episode(root, 3, feature)
    model = KeypointHMM().fit(read_lerobot(root, feature=feature)[:3])
    path = model.generate(like, dense=True)  # gripper first, then the joints
    out = write_parquet(path, tmp_path / "out.parquet", mapping=m)
    table = pq.read_table(out)
    # LeRobot's layout: the bookkeeping columns and the feature as float32 lists
    assert table.schema.names == [
        "timestamp", "frame_index", "episode_index", "index", "task_index", feature
    ]  # fmt: skip
    assert table.schema.field("timestamp").type == pa.float32()
    for c in ("frame_index", "episode_index", "index", "task_index"):
        assert table.schema.field(c).type == pa.int64()
    assert table.schema.field(feature).type == pa.list_(pa.float32(), 6)
    n = path.n_samples
    np.testing.assert_array_equal(table.column("frame_index").to_numpy(), np.arange(n))
    np.testing.assert_array_equal(table.column("episode_index").to_numpy(), 0)
    values = np.array(table.column(feature).to_pylist())
    # the dataset's order: five joints, then the gripper
    want = np.column_stack([path.get("joints"), path.get("gripper")])
    np.testing.assert_array_equal(values, want.astype(np.float32))
    np.testing.assert_array_equal(
        table.column("timestamp").to_numpy(), like.t.astype(np.float32)
    )
    # read back: the same names and groups as the dataset's
    back = read_parquet(out)
    assert back.columns == like.columns and back.groups == like.groups
    # and as the data file of a LeRobot dataset, with the names of info.json
    ds = _as_dataset(out, tmp_path / "ds", feature, SO101_STATE)
    (again,) = read_lerobot(ds, feature=feature)
    assert again == back
    np.testing.assert_array_equal(again.X[:, :5], want[:, :5].astype(np.float32))


def test_euler_angles_and_a_derived_velocity_keep_their_names(tmp_path):
    names = ["x", "y", "z", "roll", "pitch", "yaw", "gripper"]
    rng = np.random.default_rng(1)
    eps = []
    for n in (40, 44, 48):
        s = np.linspace(0, 1, n)
        state = (
            np.column_stack([s, s**2, 0.1 * s, 0.3 * s, -0.2 * s, 0.5 - s, (s > 0.5)])
            + np.r_[rng.normal(0, 0.002, (n, 6)).T, np.zeros((1, n))].T
        )
        eps.append({"observation.state": state})
    root = write_lerobot(tmp_path / "ds", eps, {"observation.state": names})
    like, m = _episode(root, 2)
    model = KeypointHMM().fit(read_lerobot(root))
    path = model.generate(like, dense=True)
    assert "velocity" in path.group_names
    out = write_parquet(path, tmp_path / "p.parquet", mapping=m)
    meta = json.loads(pq.read_schema(out).metadata[b"ndlfd"])
    got = meta["features"]["observation.state"]["names"]
    assert got == [*names, "vx", "vy", "vz"]  # the input's, then the derived
    back = read_parquet(out)
    np.testing.assert_allclose(
        back.get("orientation"), path.get("orientation"), atol=1e-6
    )  # float32 angles
    np.testing.assert_array_equal(
        back.get("velocity"), path.get("velocity").astype(np.float32)
    )


def test_fit_reads_parquet_files(tmp_path):
    t = np.linspace(0.0, 2.0, 30)
    files = []
    for i in range(3):
        d = Demonstration.from_arrays(t, joints=np.column_stack([t * i, -t]))
        files.append(write_parquet(d, tmp_path / f"d{i}.parquet", feature="action"))
    demos = read_demos(files)
    assert [d.columns for d in demos] == [("joints0", "joints1")] * 3
    np.testing.assert_array_equal(demos[2].X[:, 0], (2 * t).astype(np.float32))


def test_time_stamps_float32_cannot_keep_apart_are_an_error(tmp_path):
    t = np.array([0.0, 1000.0, 1000.00001, 1001.0])
    d = Demonstration.from_arrays(t, joints=np.zeros((4, 2)))
    with pytest.raises(ValidationError, match=r"samples 1 and 2.*expected stamps"):
        write_parquet(d, tmp_path / "p.parquet")
    with pytest.raises(ValidationError, match="feature must name a feature"):
        write_parquet(d, tmp_path / "q.parquet", feature="timestamp")


def test_files_without_names(tmp_path):
    n = 5
    flat = pa.array(np.arange(2 * n, dtype=np.float32))
    cols = {
        "timestamp": pa.array(np.arange(n, dtype=np.float32) / 10),
        "observation.state": pa.FixedSizeListArray.from_arrays(flat, 2),
    }
    pq.write_table(pa.table(cols), tmp_path / "one.parquet")
    d = read_parquet(tmp_path / "one.parquet", groups={"position": ["state_0"]},
                     drop=["state_1"])  # fmt: skip
    np.testing.assert_array_equal(d.X[:, 0], np.arange(0, 2 * n, 2))
    cols["action"] = cols["observation.state"]
    pq.write_table(pa.table(cols), tmp_path / "two.parquet")
    with pytest.raises(DataFileError, match=r"expected one list column .* got 2"):
        read_parquet(tmp_path / "two.parquet")


def test_without_pyarrow_the_error_says_how_to_install_it(tmp_path, monkeypatch):
    d = Demonstration.from_arrays([0.0, 1.0], joints=[[0.0], [1.0]])
    for name in ("pyarrow", "pyarrow.parquet"):
        monkeypatch.setitem(sys.modules, name, None)
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[lerobot\]"'):
        write_parquet(d, tmp_path / "p.parquet")
