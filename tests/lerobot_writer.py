"""Write LeRobot datasets with pyarrow, as LeRobot lays them out (tests only).

Layouts as in huggingface/lerobot (``datasets/utils.py``,
``scripts/convert_dataset_v21_to_v30.py``): ``meta/info.json`` with
``codebase_version``, ``features`` (dtype, shape, names), ``data_path``,
``total_episodes``, ``chunks_size``, ``fps``; data files with ``timestamp``
(float32), ``frame_index``, ``episode_index``, ``index``, ``task_index``
(int64) and one fixed-size list column per feature (``datasets.Sequence`` of a
given length). v2.1: one file per episode and ``meta/episodes.jsonl``; v3.0:
several episodes per file, one row group per episode, and
``meta/episodes/chunk-000/file-000.parquet``.
"""

import json
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

#: The SO-100/101 arm's motor names as LeRobot records them (``so101_follower``:
#: degrees for the five joints, 0-100 for the gripper).
SO101_MOTORS = (
    "shoulder_pan",
    "shoulder_lift",
    "elbow_flex",
    "wrist_flex",
    "wrist_roll",
    "gripper",
)
SO101_STATE = [f"{m}.pos" for m in SO101_MOTORS]
#: The same motors as older (v2.x) SO-100 datasets name them.
SO100_STATE = [f"main_{m}" for m in SO101_MOTORS]

V2_PATH = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"
V3_PATH = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"


def _features(names: dict, names_as) -> dict:
    stored = {list: lambda n: n, dict: lambda n: {"motors": n}, None: lambda n: None}
    features = {
        key: {"dtype": "float32", "shape": [len(n)], "names": stored[names_as](n)}
        for key, n in names.items()
    }
    features["observation.images.top"] = {
        "dtype": "video",
        "shape": [480, 640, 3],
        "names": ["height", "width", "channels"],
    }
    for key, dtype in (
        ("timestamp", "float32"),
        ("frame_index", "int64"),
        ("episode_index", "int64"),
        ("index", "int64"),
        ("task_index", "int64"),
    ):
        features[key] = {"dtype": dtype, "shape": [1], "names": None}
    return features


def _episode_table(values: dict, episode: int, start: int, fps: float, variable):
    n = len(next(iter(values.values())))
    cols = {
        "timestamp": pa.array((np.arange(n) / fps).astype(np.float32)),
        "frame_index": pa.array(np.arange(n, dtype=np.int64)),
        "episode_index": pa.array(np.full(n, episode, dtype=np.int64)),
        "index": pa.array(np.arange(start, start + n, dtype=np.int64)),
        "task_index": pa.array(np.zeros(n, dtype=np.int64)),
    }
    for key, a in values.items():
        a = np.asarray(a, dtype=np.float32).reshape(n, -1)
        flat = pa.array(a.ravel())
        if variable:
            offsets = pa.array(np.arange(n + 1, dtype=np.int32) * a.shape[1])
            cols[key] = pa.ListArray.from_arrays(offsets, flat)
        else:
            cols[key] = pa.FixedSizeListArray.from_arrays(flat, a.shape[1])
    return pa.table(cols)


def write_lerobot(
    root,
    episodes,
    names,
    *,
    version="v3.0",
    fps=30,
    per_file=4,
    variable=False,
    names_as=list,
    row_group_per_episode=True,
):
    """Write ``episodes`` (dicts feature -> (n, k) arrays) as a LeRobot dataset.

    ``names``: feature -> component names (``names_as=dict`` stores them as
    ``{"motors": [...]}``, as aloha datasets do). v3.0 files get one row group
    per episode (LeRobot's writer), or with ``row_group_per_episode=False``
    one for the whole file (as the v2.1 -> v3.0 conversion's
    ``DataFrame.to_parquet`` writes small files). Returns the root.
    """
    root = Path(root)
    (root / "meta").mkdir(parents=True, exist_ok=True)
    info = {
        "codebase_version": version,
        "robot_type": "so100",
        "total_episodes": len(episodes),
        "total_frames": sum(len(next(iter(e.values()))) for e in episodes),
        "total_tasks": 1,
        "chunks_size": 1000,
        "fps": fps,
        "splits": {"train": f"0:{len(episodes)}"},
        "data_path": V2_PATH if version.startswith("v2") else V3_PATH,
        "video_path": None,
        "features": _features(names, names_as),
    }
    (root / "meta" / "info.json").write_text(json.dumps(info, indent=4))
    start = 0
    meta = []
    writer = None
    file_index = -1
    pending = []
    for e, values in enumerate(episodes):
        table = _episode_table(values, e, start, fps, variable)
        n = table.num_rows
        if version.startswith("v2"):
            path = root / V2_PATH.format(episode_chunk=e // 1000, episode_index=e)
            path.parent.mkdir(parents=True, exist_ok=True)
            pq.write_table(table, path)
        else:
            if e % per_file == 0:
                if writer is not None:
                    if pending:
                        writer.write_table(pa.concat_tables(pending))
                    writer.close()
                    pending = []
                file_index += 1
                path = root / V3_PATH.format(chunk_index=0, file_index=file_index)
                path.parent.mkdir(parents=True, exist_ok=True)
                writer = pq.ParquetWriter(path, table.schema)
            if row_group_per_episode:
                writer.write_table(table)  # one row group per episode, as LeRobot
            else:
                pending.append(table)
        meta.append(
            {
                "episode_index": e,
                "data/chunk_index": 0,
                "data/file_index": max(file_index, 0),
                "dataset_from_index": start,
                "dataset_to_index": start + n,
                "length": n,
                "tasks": ["pick the cube"],
            }
        )
        start += n
    if writer is not None:
        if pending:
            writer.write_table(pa.concat_tables(pending))
        writer.close()
    if version.startswith("v2"):
        with open(root / "meta" / "episodes.jsonl", "w") as f:
            for m in meta:
                line = {"episode_index": m["episode_index"], "tasks": m["tasks"]}
                line["length"] = m["length"]
                f.write(json.dumps(line) + "\n")
    else:
        path = root / "meta" / "episodes" / "chunk-000" / "file-000.parquet"
        path.parent.mkdir(parents=True, exist_ok=True)
        pq.write_table(pa.Table.from_pylist(meta), path)
    return root


def so101_episodes(n_demos=5, seed=0, fps=30):
    """SO-101 pick episodes: joints in degrees, the gripper closing 40 -> 5 -> 40.

    Each episode's ``observation.state`` and ``action`` (the state one step
    ahead, as a leader arm leads) are ``(n, 6)`` arrays in
    :data:`SO101_STATE`'s order.
    """
    rng = np.random.default_rng(seed)
    eps = []
    for i in range(n_demos):
        n = 90 + 6 * i
        s = np.linspace(0, 1, n)
        state = np.column_stack(
            [
                40 * np.sin(np.pi * s),
                -60 + 50 * s,
                80 * s**2,
                10 * np.cos(2 * np.pi * s),
                5 * s,
                np.where((s > 0.4 + 0.01 * i) & (s < 0.8), 5.0, 40.0),
            ]
        )
        state[:, :5] += rng.normal(0, 0.3, (n, 5))
        action = np.vstack([state[1:], state[-1:]])
        eps.append({"observation.state": state, "action": action})
    return eps


def write_so101(root, n_demos=5, version="v3.0", seed=0):
    """An SO-101 dataset (:func:`so101_episodes`) as LeRobot writes it.

    Returns the root and the episodes.
    """
    eps = so101_episodes(n_demos, seed)
    names = {"observation.state": SO101_STATE, "action": SO101_STATE}
    return write_lerobot(root, eps, names, version=version), eps


def write_so100(root, n_demos=5, version="v2.1", seed=0, names_as=dict):
    """An older SO-100 dataset: :func:`so101_episodes` under ``main_`` names.

    The names stored as ``{"motors": [...]}`` (``names_as=dict``) or as a
    list. Returns the root and the episodes.
    """
    eps = so101_episodes(n_demos, seed)
    names = {"observation.state": SO100_STATE, "action": SO100_STATE}
    return write_lerobot(root, eps, names, version=version, names_as=names_as), eps
