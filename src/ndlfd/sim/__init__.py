"""Task success in a simulator: the ALOHA scenes of gym-aloha (extra ``sim``).

Issue 40's harness, built in slices:

* :mod:`~ndlfd.sim._scene`: a task's model (:class:`Scene`, joint or
  end-effector control), stepped at 50 Hz without rendering, with gym-aloha's
  own actions and reward (success: :data:`MAX_REWARD`); object poses over
  gym-aloha's ranges (:func:`sample_objects`).
* :mod:`~ndlfd.sim._ik`: the arms' inverse kinematics (:class:`ArmIK`,
  damped least squares on mujoco's Jacobian).
* :mod:`~ndlfd.sim._experts`: scripted experts written from the tasks'
  geometry, varied as people vary (:func:`expert_episode`), run in the
  joint-position scene through inverse kinematics and recorded in joint and
  end-effector space (:func:`record_expert`); hand poses run the same way
  (:func:`run_hands`).
* :mod:`~ndlfd.sim._dataset`: the recordings as a LeRobot dataset
  (:func:`write_task_dataset`), read back by :func:`ndlfd.io.read_lerobot`.

The evaluation over held-out object poses is ``ndlfd evaluate --tasks``
(:mod:`ndlfd.jobs._tasks`; docs/tasks.md).
"""

from ._dataset import EE_NAMES, write_task_dataset
from ._experts import (
    START_HANDS,
    ExpertPlan,
    Recording,
    expert_episode,
    record_expert,
    render_plan,
    run_hands,
)
from ._ik import ArmIK
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
    "ArmIK",
    "ExpertPlan",
    "Recording",
    "Scene",
    "expert_episode",
    "mocap_action",
    "record_expert",
    "render_plan",
    "require_sim",
    "run_hands",
    "sample_objects",
    "write_task_dataset",
]
