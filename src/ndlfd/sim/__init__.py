"""Task success in a simulator: the ALOHA scenes of gym-aloha (extra ``sim``).

Issue 40's harness, built in slices:

* :mod:`~ndlfd.sim._scene`: a task's model (:class:`Scene`, joint or
  end-effector control), stepped at 50 Hz without rendering, with gym-aloha's
  own actions and reward (success: :data:`MAX_REWARD`); object poses over
  gym-aloha's ranges (:func:`sample_objects`).
* :mod:`~ndlfd.sim._experts`: scripted experts written from the tasks'
  geometry, varied as people vary (:func:`expert_episode`), run and recorded
  in joint and end-effector space (:func:`record_expert`).
* :mod:`~ndlfd.sim._dataset`: the recordings as a LeRobot dataset
  (:func:`write_task_dataset`), read back by :func:`ndlfd.io.read_lerobot`.

The evaluation over held-out object poses (``ndlfd evaluate --tasks``) is not
built yet (see docs/tasks.md).
"""

from ._dataset import EE_NAMES, write_task_dataset
from ._experts import (
    START_HANDS,
    ExpertPlan,
    Recording,
    expert_episode,
    record_expert,
    render_plan,
)
from ._scene import (
    CONTROL_DT,
    HAND_COLUMNS,
    JOINT_NAMES,
    MAX_REWARD,
    TASKS,
    TOOL_DEPTH,
    VIPERX_LIMITS,
    Scene,
    mocap_action,
    require_sim,
    sample_objects,
)

__all__ = [
    "CONTROL_DT",
    "EE_NAMES",
    "HAND_COLUMNS",
    "JOINT_NAMES",
    "MAX_REWARD",
    "START_HANDS",
    "TASKS",
    "TOOL_DEPTH",
    "VIPERX_LIMITS",
    "ExpertPlan",
    "Recording",
    "Scene",
    "expert_episode",
    "mocap_action",
    "record_expert",
    "render_plan",
    "require_sim",
    "sample_objects",
    "write_task_dataset",
]
