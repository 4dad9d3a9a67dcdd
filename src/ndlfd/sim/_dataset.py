"""Expert recordings written as a LeRobot dataset (layout 3.0).

The layout is LeRobot's own (``lerobot/datasets/utils.py``; the reader is
:mod:`ndlfd.io._lerobot`): ``meta/info.json`` (``codebase_version``
``"v3.0"``, ``fps`` 50, ``features`` with dtype, shape and component names),
one data file ``data/chunk-000/file-000.parquet`` with one row group per
episode (columns ``timestamp``, ``frame_index``, ``episode_index``, ``index``,
``task_index`` and one fixed-size float32 list per feature) and
``meta/episodes/chunk-000/file-000.parquet`` listing where each episode is.
The features:

==========================  ===========================================
``observation.state``       the 14 joints read (ALOHA's layout: per arm
                            6 joints and the gripper, 0 closed to 1 open)
``action``                  the 14 joint positions commanded (inverse
                            kinematics) with the gripper commands
``action.ee``               the hands' poses asked for: per hand the tool
                            point, the gripper link's orientation (x, y, z,
                            qw, qx, qy, qz) and the gripper
``observation.<object>``    each object's position where it was placed,
                            the same on every row (a task frame:
                            ``read_lerobot(..., frames={"cube":
                            "observation.cube"})``)
==========================  ===========================================
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .._errors import MissingExtraError, ValidationError
from ._scene import CONTROL_DT, HAND_COLUMNS, JOINT_NAMES, TASKS

__all__ = ["EE_NAMES", "write_task_dataset"]

#: The end-effector feature's component names, left hand then right.
EE_NAMES = tuple(f"{side}_{c}" for side in ("left", "right") for c in HAND_COLUMNS)
_DATA = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"


def write_task_dataset(
    recordings: Sequence, root: str | os.PathLike, task: str
) -> Path:
    """Write expert recordings as one LeRobot dataset folder.

    Parameters
    ----------
    recordings : sequence of Recording
        From :func:`~ndlfd.sim._experts.record_expert`, one episode each.
    root : str or path-like
        The dataset folder (created; must not hold a dataset already).
    task : str
        The task's name (:data:`~ndlfd.sim._scene.TASKS`), its objects'
        features are named after it.

    Returns
    -------
    root : Path

    Raises
    ------
    ValidationError
        No recordings, or ``root`` already holds ``meta/info.json``.
    MissingExtraError
        pyarrow is missing (extra ``lerobot``).
    """
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise MissingExtraError(
            'writing a LeRobot dataset needs pyarrow: pip install "ndlfd[lerobot]"'
        ) from None
    spec = TASKS.get(task)
    if not recordings:
        raise ValidationError("recordings must hold at least one episode; got none")
    root = Path(root)
    if (root / "meta" / "info.json").exists():
        raise ValidationError(f"{root} already holds a LeRobot dataset")
    names = {
        "observation.state": list(JOINT_NAMES),
        "action": list(JOINT_NAMES),
        "action.ee": list(EE_NAMES),
        **{f"observation.{o}": ["x", "y", "z"] for o in spec.objects},
    }
    features = {
        k: {"dtype": "float32", "shape": [len(v)], "names": v} for k, v in names.items()
    }
    for key, dtype in (
        ("timestamp", "float32"),
        ("frame_index", "int64"),
        ("episode_index", "int64"),
        ("index", "int64"),
        ("task_index", "int64"),
    ):
        features[key] = {"dtype": dtype, "shape": [1], "names": None}
    path = root / _DATA.format(chunk_index=0, file_index=0)
    path.parent.mkdir(parents=True, exist_ok=True)
    start, meta, writer = 0, [], None
    for e, rec in enumerate(recordings):
        n = len(rec.t)
        values = {
            "observation.state": rec.state,
            "action": rec.joint_action,
            "action.ee": rec.ee_action,
            **{
                f"observation.{o}": np.repeat(rec.objects[j][None], n, axis=0)
                for j, o in enumerate(spec.objects)
            },
        }
        cols = {
            "timestamp": pa.array((np.arange(n) * CONTROL_DT).astype(np.float32)),
            "frame_index": pa.array(np.arange(n, dtype=np.int64)),
            "episode_index": pa.array(np.full(n, e, dtype=np.int64)),
            "index": pa.array(np.arange(start, start + n, dtype=np.int64)),
            "task_index": pa.array(np.zeros(n, dtype=np.int64)),
        }
        for key, a in values.items():
            a = np.asarray(a, dtype=np.float32).reshape(n, -1)
            cols[key] = pa.FixedSizeListArray.from_arrays(
                pa.array(a.ravel()), a.shape[1]
            )
        table = pa.table(cols)
        if writer is None:
            writer = pq.ParquetWriter(path, table.schema)
        writer.write_table(table)  # one row group per episode, as LeRobot
        meta.append(
            {
                "episode_index": e,
                "data/chunk_index": 0,
                "data/file_index": 0,
                "dataset_from_index": start,
                "dataset_to_index": start + n,
                "length": n,
                "tasks": [spec.name],
            }
        )
        start += n
    writer.close()
    episodes = root / "meta" / "episodes" / "chunk-000" / "file-000.parquet"
    episodes.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(pa.Table.from_pylist(meta), episodes)
    pq.write_table(
        pa.table({"task_index": [0], "task": [spec.name]}),
        root / "meta" / "tasks.parquet",
    )
    info = {
        "codebase_version": "v3.0",
        "robot_type": "aloha",
        "total_episodes": len(recordings),
        "total_frames": start,
        "total_tasks": 1,
        "chunks_size": 1000,
        "fps": round(1 / CONTROL_DT),
        "splits": {"train": f"0:{len(recordings)}"},
        "data_path": _DATA,
        "video_path": None,
        "features": features,
    }
    (root / "meta" / "info.json").write_text(json.dumps(info, indent=4))
    return root
