"""Task success in the simulator: ``ndlfd evaluate --tasks`` (issue 40).

For each task (Transfer Cube, Insertion; :mod:`ndlfd.sim`) the scripted
expert (:func:`~ndlfd.sim.record_expert`) records demonstrations on object
poses drawn from one seed stream (failed recordings are not kept, as a person
would not keep them); held-out object poses come from another. For each
number of demonstrations N every method is fitted on the first N and asked
for one path per held-out pose, which runs open loop in the joint-position
scene; success is the task's own reward at its maximum (4) at any step.

The methods, all given the same inputs (the start and the objects' positions,
as each can take them):

==================  ==========================================================
``ndlfd-ee``        :class:`~ndlfd.KeypointHMM` on the hands' poses: both
                    hands as pose groups (``left_position``,
                    ``left_orientation``, ``right_position``,
                    ``right_orientation``) and the grippers, the objects'
                    positions as task frames (each hand follows the frame its
                    demonstrations agree in); generated from the start with
                    the new frames, run through inverse kinematics
                    (:func:`~ndlfd.sim.run_hands`)
``ndlfd-joint``     :class:`~ndlfd.KeypointHMM` on the 12 joints and the two
                    grippers, from the start, the objects' positions as task
                    frames (the path moves along a regression on them)
``object-mean``     the demonstrations' mean (normalized time), each hand's
                    positions shifted by its object's move (the right hand by
                    the first object, the left by the second; eased in over
                    the first :data:`EASE_IN` of the motion, so the path
                    starts at the start)
``promp``           ProMP (:class:`~ndlfd.baselines.ProMPBaseline`) on each
                    hand with an object, on its positions, conditioned on the
                    start and a via point at its grasp (the object's new
                    position plus the demonstrations' mean grasp offset, at
                    their mean grasp time); every other column the
                    demonstrations' mean
``nearest``         the demonstration whose objects were nearest, replayed,
                    each hand shifted by its object's move (eased in as
                    ``object-mean``'s)
``promp-joint``     contextual ProMP (Paraschos et al. 2013;
                    ``ContextualProMP`` in :mod:`ndlfd.jobs._task_peers`) on
                    the 12 joints and the two grippers (normalized time, 25
                    basis functions each): the weights' mean conditioned on
                    the objects' positions (those that vary across the
                    demonstrations); the start is in every demonstration
``nearest-joint``   the demonstration whose objects were nearest, its joint
                    commands replayed (no shift is possible in joint space)
==================  ==========================================================

Reported per task, method and N: success rate, the joint commands' peak
velocity and acceleration (finite differences at 50 Hz, arm joints only)
against the ViperX's velocity limit (:data:`~ndlfd.sim.VIPERX_LIMITS`), the
fit's seconds and the generation's seconds per episode. The expert itself is
run on the same held-out poses (``expert``: closed loop, it looks at the
objects), the ceiling.
"""

from __future__ import annotations

import csv
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .._errors import ValidationError

__all__ = ["EASE_IN", "TASK_METHODS", "TaskResult", "TaskRow", "evaluate_tasks"]

#: The methods compared, in the report's order.
TASK_METHODS = (
    "ndlfd-ee",
    "ndlfd-joint",
    "object-mean",
    "promp",
    "nearest",
    "promp-joint",
    "nearest-joint",
)
#: Each hand's position columns in the end-effector rows and the object it
#: takes (Transfer Cube: the right hand the cube; Insertion: the right hand
#: the peg, the left the socket).
_HANDS = (([8, 9, 10], 0), ([0, 1, 2], 1))
#: The fraction of the motion over which object-mean and nearest ease their
#: shift in (the expert's grasp begins after about a third).
EASE_IN = 0.25


@dataclass
class TaskRow:
    """One held-out episode of one method.

    Attributes
    ----------
    task, method : str
    n_demos : int
        Demonstrations fitted on (0 for the expert).
    episode : int
    objects : list of float
        The objects' positions, flattened (x, y, z per object).
    success : bool
    max_reward : int
    peak_velocity, peak_acceleration : float
        The arm joints' commands' largest |velocity| (rad/s) and
        |acceleration| (rad/s^2).
    generate_seconds, fit_seconds : float
    error : str
        Empty unless the method raised (the episode counts as failed).
    """

    task: str
    method: str
    n_demos: int
    episode: int
    objects: list
    success: bool
    max_reward: int
    peak_velocity: float
    peak_acceleration: float
    generate_seconds: float
    fit_seconds: float
    error: str = ""
    hands: np.ndarray | None = field(default=None, repr=False)


def _peaks(joints: np.ndarray, dt: float) -> tuple[float, float]:
    arm = joints[:, [0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]]
    v = np.diff(arm, axis=0) / dt
    a = np.diff(arm, n=2, axis=0) / dt**2
    return float(np.abs(v).max()), float(np.abs(a).max())


def _ee_demo(rec, spec):
    from ..demonstration import Demonstration

    ee = rec.ee_action
    frames = {o: rec.objects[j] for j, o in enumerate(spec.objects)}
    return Demonstration.from_arrays(
        rec.t,
        left_position=ee[:, 0:3],
        left_orientation=ee[:, 3:7],
        right_position=ee[:, 8:11],
        right_orientation=ee[:, 11:15],
        gripper=ee[:, [7, 15]],
        frames=frames,
    )


def _joint_demo(rec, spec):
    from ..demonstration import Demonstration

    j = rec.joint_action
    return Demonstration.from_arrays(
        rec.t,
        joints=j[:, [0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]],
        gripper=j[:, [6, 13]],
        frames={o: rec.objects[k] for k, o in enumerate(spec.objects)},
    )


def _ee_rows(path) -> np.ndarray:
    """A generated end-effector Demonstration as run_hands' rows (n, 16)."""
    g = path.get
    grip = g("gripper")
    return np.column_stack(
        [
            g("left_position"),
            g("left_orientation"),
            grip[:, 0],
            g("right_position"),
            g("right_orientation"),
            grip[:, 1],
        ]
    )


def _unit_resample(a: np.ndarray, n: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, len(a))
    u = np.linspace(0.0, 1.0, n)
    return np.column_stack([np.interp(u, s, a[:, k]) for k in range(a.shape[1])])


def _fit(method: str, recs: Sequence, spec, times: np.ndarray) -> Callable:
    """Fit one method; the generator it returns maps objects to (space, rows)."""
    n = len(times)
    if method == "ndlfd-ee":
        from ..learner import KeypointHMM

        model = KeypointHMM().fit([_ee_demo(r, spec) for r in recs])
        start = recs[0].ee_action[0]

        def gen(objects):
            frames = {o: objects[j] for j, o in enumerate(spec.objects)}
            at = {"left_position": start[0:3], "right_position": start[8:11]}
            path = model.generate(times, dense=True, start=at, frames=frames)
            return "ee", _ee_rows(path)

        return gen
    if method == "ndlfd-joint":
        from ..learner import KeypointHMM

        model = KeypointHMM().fit([_joint_demo(r, spec) for r in recs])
        q0 = recs[0].joint_action[0]

        def gen(objects):
            path = model.generate(
                times,
                dense=True,
                start={"joints": q0[[0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]]},
                frames={o: objects[k] for k, o in enumerate(spec.objects)},
            )
            j, grip = path.get("joints"), path.get("gripper")
            return "joint", np.column_stack(
                [j[:, :6], grip[:, 0], j[:, 6:], grip[:, 1]]
            )

        return gen
    placed = np.array([np.ravel(r.objects) for r in recs])
    if method == "promp-joint":
        from ._task_peers import ContextualProMP

        joints = [_unit_resample(r.joint_action, n) for r in recs]
        cpromp = ContextualProMP().fit(joints, placed)
        return lambda objects: ("joint", cpromp.generate(objects, n))
    if method == "nearest-joint":

        def gen(objects):
            k = int(np.argmin(np.linalg.norm(placed - np.ravel(objects), axis=1)))
            return "joint", _unit_resample(recs[k].joint_action, n)

        return gen
    mean = np.mean([_unit_resample(r.ee_action, n) for r in recs], axis=0)
    hands = _HANDS[: len(spec.objects)]  # (columns of the hand, its object)
    # the shift eased in (minimum jerk) over the first EASE_IN of the motion:
    # shifted from its first sample the path would jump away from the start
    s = np.clip(np.linspace(0.0, 1.0, n) / EASE_IN, 0.0, 1.0)
    ease = s**3 * (10 - 15 * s + 6 * s**2)
    if method == "object-mean":
        shift0 = placed.mean(axis=0)

        def gen(objects):
            rows = mean.copy()
            moved = np.ravel(objects) - shift0
            for cols, k in hands:
                rows[:, cols] += ease[:, None] * moved[3 * k : 3 * k + 3]
            return "ee", rows

        return gen
    if method == "nearest":

        def gen(objects):
            k = int(np.argmin(np.linalg.norm(placed - np.ravel(objects), axis=1)))
            rows = _unit_resample(recs[k].ee_action, n)
            moved = np.ravel(objects) - placed[k]
            for cols, o in hands:
                rows[:, cols] += ease[:, None] * moved[3 * o : 3 * o + 3]
            return "ee", rows

        return gen
    if method == "promp":
        from ..baselines import ProMPBaseline
        from ..demonstration import Demonstration

        # one ProMP per hand with an object, on its positions, given the start
        # and a via point at its grasp (where its gripper has closed: the
        # object's new position plus the mean grasp offset, at the mean time)
        each = []
        for cols, o in hands:
            demos = [Demonstration.from_arrays(r.t, position=r.ee_action[:, cols])
                     for r in recs]  # fmt: skip
            grip = cols[-1] + 4 + 1  # the gripper column after the quaternion
            grasp = []
            for r in recs:
                k = int(np.argmax(r.ee_action[:, grip] < 0.5))
                grasp.append((k / (len(r.t) - 1), r.ee_action[k, cols] - r.objects[o]))
            at = float(np.mean([g[0] for g in grasp]))
            offset = np.mean([g[1] for g in grasp], axis=0)
            each.append((cols, o, ProMPBaseline().fit(demos), at, offset))
        start = recs[0].ee_action[0]

        def gen(objects):
            rows = mean.copy()
            for cols, o, promp, at, offset in each:
                tg = float(times[round(at * (len(times) - 1))])  # one of times
                via = [(tg, objects[o] + offset)]
                rows[:, cols] = promp.generate(times, start=start[cols], via=via)
            return "ee", rows

        return gen
    raise ValidationError(
        f"method must be one of {', '.join(TASK_METHODS)}; got {method!r}"
    )


def _record(task: str, scene, n: int, seed: int, *, keep_failed: bool):
    """Expert recordings on poses from one seed stream (failures skipped)."""
    from ..sim import expert_episode, record_expert, sample_objects

    recs, tried = [], 0
    while len(recs) < n:
        rng = np.random.default_rng([seed, tried])
        tried += 1
        objects = sample_objects(task, rng)
        scene.reset(objects)
        rec = record_expert(
            scene, expert_episode(task, objects, rng, start=scene.hands()), objects
        )
        if rec.success or keep_failed:
            recs.append(rec)
        if tried > 3 * n + 10:
            raise ValidationError(
                f"the {task} expert succeeded on {len(recs)} of {tried} poses;"
                f" {n} demonstrations were asked for"
            )
    return recs, tried


@dataclass
class TaskResult:
    """The rows of a task evaluation and what produced them.

    Attributes
    ----------
    rows : list of TaskRow
    demos : dict of str to tuple of (int, int)
        Per task, (successful recordings kept, poses tried) for the
        demonstrations.
    seconds : float
    """

    rows: list
    demos: dict
    seconds: float = 0.0

    @classmethod
    def read_csv(cls, path) -> TaskResult:
        """The rows of a written ``results.csv`` (without the hands' paths)."""
        rows = []
        with open(path, newline="") as fh:
            for d in csv.DictReader(fh):
                rows.append(
                    TaskRow(
                        d["task"],
                        d["method"],
                        int(d["n_demos"]),
                        int(d["episode"]),
                        [float(v) for v in d["objects"].split()],
                        d["success"] == "True",
                        int(d["max_reward"]),
                        float(d["peak_velocity"]),
                        float(d["peak_acceleration"]),
                        float(d["generate_seconds"]),
                        float(d["fit_seconds"]),
                        d["error"],
                    )
                )
        return cls(rows, {})

    def summary(self) -> list[dict]:
        """Per task, method and N: success rate, peaks and times."""
        out = {}
        for r in self.rows:
            out.setdefault((r.task, r.method, r.n_demos), []).append(r)
        table = []
        for (task, method, n), rows in out.items():
            ok = [r.success for r in rows]
            table.append(
                {
                    "task": task,
                    "method": method,
                    "n_demos": n,
                    "episodes": len(rows),
                    "success": float(np.mean(ok)),
                    "peak_velocity_p95": float(
                        np.percentile([r.peak_velocity for r in rows], 95)
                    ),
                    "over_velocity": int(
                        sum(r.peak_velocity > _VMAX * (1 + 1e-9) for r in rows)
                    ),
                    "peak_acceleration_p95": float(
                        np.percentile([r.peak_acceleration for r in rows], 95)
                    ),
                    "fit_seconds": float(rows[0].fit_seconds),
                    "generate_ms": 1000
                    * float(np.median([r.generate_seconds for r in rows])),
                    "errors": int(sum(bool(r.error) for r in rows)),
                }
            )
        return table

    def to_markdown(self) -> str:
        """The summary as a Markdown table."""
        head = (
            "| task | method | N | episodes | success | peak joint velocity p95 (rad/s)"
            " | episodes over pi rad/s | peak joint acceleration p95 (rad/s^2)"
            " | fit (s) | generate (ms, median) |\n"
            "|---|---|---|---|---|---|---|---|---|---|\n"
        )
        lines = [
            f"| {s['task']} | {s['method']} | {s['n_demos'] or '-'} | {s['episodes']}"
            f" | {s['success']:.2f} | {s['peak_velocity_p95']:.2f}"
            f" | {s['over_velocity']} | {s['peak_acceleration_p95']:.1f}"
            f" | {s['fit_seconds']:.2f} | {s['generate_ms']:.0f} |"
            for s in self.summary()
        ]
        return head + "\n".join(lines) + "\n"

    def write_report(self, out, *, plots: bool = True) -> Path:
        """results.csv, summary.md and (with matplotlib) the figures in ``out``."""
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        names = [f for f in TaskRow.__dataclass_fields__ if f != "hands"]
        with open(out / "results.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=names)
            w.writeheader()
            for r in self.rows:
                d = asdict(r)
                d.pop("hands")
                d["objects"] = " ".join(f"{v:.4f}" for v in d["objects"])
                w.writerow(d)
        demos = "; ".join(
            f"{t}: {k} demonstrations kept of {n} expert recordings"
            for t, (k, n) in self.demos.items()
        )
        (out / "summary.md").write_text(self.to_markdown() + "\n" + demos + "\n")
        if plots:
            from ._tasks_figures import failures_top_view, success_curve

            success_curve(self, out / "tasks_success.png")
            for task in dict.fromkeys(r.task for r in self.rows):
                failures_top_view(self, task, out / f"tasks_failures_{task}.png")
        return out


_VMAX = np.pi  # ndlfd.sim.VIPERX_LIMITS["velocity"] (without importing sim)


def evaluate_tasks(
    tasks: Sequence[str],
    *,
    demos: Sequence[int] = (5, 10, 20, 50),
    episodes: int = 200,
    methods: Sequence[str] | None = None,
    seed: int = 0,
    echo: Callable | None = None,
) -> TaskResult:
    """Fit each method on N expert demonstrations, run it on held-out poses.

    Parameters
    ----------
    tasks : sequence of str
        Names from :data:`ndlfd.sim.TASKS`.
    demos : sequence of int, default=(5, 10, 20, 50)
        The numbers of demonstrations N (the first N of one recording).
    episodes : int, default=200
        Held-out object poses per task (each method and N runs on all).
    methods : sequence of str, optional
        From :data:`TASK_METHODS` (default: all).
    seed : int, default=0
        Demonstrations come from seed stream ``(seed, 1, task)``, held-out
        poses from ``(seed, 2, task)``: deterministic, and a task's own
        (its place in :data:`ndlfd.sim.TASKS`) whichever tasks run beside it.
    echo : callable, optional
        Progress lines (e.g. ``print``).

    Returns
    -------
    result : TaskResult

    Raises
    ------
    MissingExtraError
        The extra ``sim`` is missing.
    ValidationError
        An unknown task or method, or N or episodes below 1.
    """
    from ..sim import (
        TASKS,
        Scene,
        expert_episode,
        record_expert,
        run_hands,
        sample_objects,
    )

    say = echo or (lambda *_: None)
    methods = list(TASK_METHODS if methods is None else methods)
    for m in methods:
        if m not in TASK_METHODS:
            raise ValidationError(
                f"method must be one of {', '.join(TASK_METHODS)}; got {m!r}"
            )
    demos = sorted({int(n) for n in demos})
    if not demos or demos[0] < 1 or episodes < 1:
        raise ValidationError(
            "demos and episodes must be at least 1; got"
            f" demos={demos}, episodes={episodes}"
        )
    t0 = time.perf_counter()
    rows, kept = [], {}
    for task in tasks:
        spec = TASKS.get(task)
        # the task's own seed streams, whichever tasks run beside it
        ti = list(TASKS).index(task)
        scene = Scene(task, "joint")
        say(f"{task}: recording {demos[-1]} expert demonstrations")
        recs, tried = _record(
            task, scene, demos[-1], seed * 1000 + 10 * ti + 1, keep_failed=False
        )
        kept[task] = (len(recs), tried)
        held = [
            sample_objects(task, np.random.default_rng([seed * 1000 + 10 * ti + 2, e]))
            for e in range(episodes)
        ]
        say(f"{task}: the expert on {episodes} held-out poses")
        for e, objects in enumerate(held):
            rng = np.random.default_rng([seed * 1000 + 10 * ti + 3, e])
            scene.reset(objects)
            t1 = time.perf_counter()
            rec = record_expert(
                scene, expert_episode(task, objects, rng, start=scene.hands()), objects
            )
            v, a = _peaks(rec.joint_action, rec.t[1] - rec.t[0])
            rows.append(
                TaskRow(
                    task,
                    "expert",
                    0,
                    e,
                    objects.ravel().tolist(),
                    rec.success,
                    int(rec.reward.max()),
                    v,
                    a,
                    time.perf_counter() - t1,
                    0.0,
                    hands=rec.hands[:, :, :3],
                )
            )
        for n in demos:
            train = recs[:n]
            times = (
                np.arange(round(np.mean([r.t[-1] for r in train]) / 0.02) + 1) * 0.02
            )
            for method in methods:
                t1 = time.perf_counter()
                try:
                    gen = _fit(method, train, spec, times)
                    fit_s, err = time.perf_counter() - t1, ""
                except Exception as exc:  # a method that fails is reported
                    gen, fit_s, err = (
                        None,
                        time.perf_counter() - t1,
                        f"{type(exc).__name__}: {exc}",
                    )
                ok = 0
                for e, objects in enumerate(held):
                    row = _episode(scene, run_hands, gen, objects, err)
                    where = objects.ravel().tolist()
                    rows.append(TaskRow(task, method, n, e, where, *row[:5], fit_s,
                                        row[5], hands=row[6]))  # fmt: skip
                    ok += row[0]
                say(
                    f"{task}: {method:<12} N={n:<3} success {ok}/{episodes}"
                    f" (fit {fit_s:.1f} s)"
                )
    return TaskResult(rows, kept, time.perf_counter() - t0)


def _episode(scene, run_hands, gen, objects, err):
    """(success, max reward, peak v, peak a, generate s, error, tool points)."""
    if gen is None:
        return False, 0, np.nan, np.nan, np.nan, err, None
    t1 = time.perf_counter()
    try:
        space, rows = gen(objects)
    except Exception as exc:  # reported per episode, never dropped
        msg = f"{type(exc).__name__}: {exc}"
        return False, 0, np.nan, np.nan, time.perf_counter() - t1, msg, None
    gen_s = time.perf_counter() - t1
    if space == "ee":
        joints, reward = run_hands(scene, rows, objects)
    else:
        scene.reset(objects)
        joints = np.asarray(rows, dtype=float)
        reward = np.array([scene.step(q) for q in joints])
    hands = None
    if reward.max() < 4:  # where the hands went, for the failures' picture
        hands = _tool_points(scene, joints)
    v, a = _peaks(joints, 0.02)
    return bool(reward.max() >= 4), int(reward.max()), v, a, gen_s, "", hands


def _tool_points(scene, joints: np.ndarray) -> np.ndarray:
    """The tool points (n, 2, 3) the joint commands put the hands at."""
    from ..sim import ArmIK

    ik = ArmIK(scene.physics)
    sides = ("left", "right")
    return np.array(
        [[ik.pose(side, q[7 * h : 7 * h + 6])[0] for h, side in enumerate(sides)]
         for q in joints]
    )  # fmt: skip
