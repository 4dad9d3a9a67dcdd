"""The evaluation's protocols, metrics and folds (used by :mod:`ndlfd.jobs.evaluation`).

A *protocol* says what a generator is given besides the training
demonstrations, taken from the held-out demonstration, and which of its samples
are scored:

================  ==========================================================
``"time"``        its time stamps only
``"time+start"``  also its start position (a robot knows where it is)
``"via"``         protocol *V*: also its start and its position at its middle
                  sample, a via point (``via=[(t[n // 2], p[n // 2])]``)
``"prefix"``      protocol *P*: its first :data:`PREFIX_FRACTION` of samples
                  observed (``observed=p[:n_observed]``, as a robot replanning
                  during an execution); only the remaining samples are scored
``"task"``        its start, its position at the grasp (the object's, at
                  :data:`~ndlfd.synth.PICK_PLACE_GRASP` of its samples) and
                  its goal, the last two as via points
                  (``via=[(t[g], p[g]), (t[-1], p[-1])]``): a pick-and-place
                  whose object and place moved
``"frames"``      as ``"task"``, and the held-out demonstration's task frames
                  (the object's and the place's poses): a generator that
                  takes frames (ndlfd) is given the start and the frames
                  only, no time; the others the start and the via points
================  ==========================================================

Besides LASA's shapes, :data:`TASK_SHAPES` are pick-and-place sets
(:func:`ndlfd.synth.pick_place`, 12 demonstrations: the object and the place
moved by up to 0.1 m, and in ``"PickPlaceTurned"`` turned by up to 60
degrees), the group ``"task"``.

:func:`run_fold` fits every generator on all demonstrations of a shape but
one and scores each protocol's path (:func:`score`).
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._errors import ValidationError
from .._registry import Registry
from ..datasets import load_lasa
from ..demonstration import Demonstration, unit_time
from ..metrics import (
    discrete_frechet,
    dtw_distance,
    endpoint_error,
    path_length_ratio,
    time_aligned_rmse,
    turning_ratio,
)
from ..synth import PICK_PLACE_GRASP, pick_place

__all__ = [
    "METRICS",
    "PREFIX_FRACTION",
    "PROTOCOLS",
    "ROW_KEYS",
    "SAMPLES",
    "TASK_PROTOCOLS",
    "TASK_SHAPES",
    "Protocol",
    "load_shape",
    "message",
    "run_fold",
    "score",
    "shape_group",
    "shape_range",
]

#: Share of the held-out samples observed in the ``"prefix"`` protocol.
PREFIX_FRACTION = 0.3
#: Paths drawn from the reference generator (when it samples) for the figures.
SAMPLES = 20

#: Recorded metrics, with the labels used in tables.
METRICS = {
    "dtw": "DTW/range",
    "on_route": "on-route/range",
    "frechet": "Fréchet/range",
    "rmse": "RMSE/range",
    "endpoint": "endpoint/range",
    "path_length_ratio": "length ratio",
    "turning_ratio": "turning ratio",
    "via_error": "via error/range",
    "prefix_jump": "prefix jump/range",
    "seconds": "seconds",
}

ROW_KEYS = (
    "shape",
    "group",
    "fold",
    "protocol",
    "generator",
    "ok",
    "error",
    "range",
    *METRICS,
)


@dataclass(frozen=True)
class Protocol:
    """What a generator is given, from the held-out demonstration.

    Attributes
    ----------
    conditions : callable
        ``conditions(test) -> (kwargs, first)``: the keyword arguments of
        ``generate`` besides the time stamps (``start``, ``via``,
        ``observed``) and the first scored sample.
    metrics : tuple of str
        The metrics only this protocol records (NaN elsewhere).
    """

    conditions: Callable[[Demonstration], tuple[dict, int]]
    metrics: tuple[str, ...] = ()


def _time(test):
    return {}, 0


def _start(test):
    return {"start": test.get("position")[0]}, 0


def _via(test):
    P, k = test.get("position"), test.n_samples // 2
    return {"start": P[0], "via": [(float(test.t[k]), P[k])]}, 0


def _task(test):
    P, n = test.get("position"), test.n_samples
    g = round(PICK_PLACE_GRASP * (n - 1))
    return {"start": P[0], "via": [(float(test.t[g]), P[g]),
                                   (float(test.t[-1]), P[-1])]}, 0  # fmt: skip


def _frames(test):
    kw, first = _task(test)
    return {**kw, "frames": dict(test.frames)}, first


def _prefix(test):
    n = min(test.n_samples - 1, math.ceil(PREFIX_FRACTION * test.n_samples))
    return {"observed": test.get("position")[:n]}, n


#: The evaluation protocols.
PROTOCOLS: Registry[Protocol] = Registry("protocol")
PROTOCOLS.add("time", Protocol(_time))
PROTOCOLS.add("time+start", Protocol(_start))
PROTOCOLS.add("via", Protocol(_via, ("via_error",)))
PROTOCOLS.add("prefix", Protocol(_prefix, ("prefix_jump",)))
PROTOCOLS.add("task", Protocol(_task, ("via_error",)))
PROTOCOLS.add("frames", Protocol(_frames, ("via_error",)))
#: The protocols that need a pick-and-place set (task frames, a grasp).
TASK_PROTOCOLS = ("task", "frames")

#: The pick-and-place sets besides LASA's shapes: name -> largest turn (deg).
TASK_SHAPES = {"PickPlace": 0.0, "PickPlaceTurned": 60.0}


def load_shape(name: str) -> list[Demonstration]:
    """The demonstrations of a LASA shape or of a :data:`TASK_SHAPES` set.

    Examples
    --------
    >>> len(load_shape("PickPlace")), load_shape("PickPlace")[0].group_names
    (12, ('position', 'orientation', 'gripper'))
    """
    if name in TASK_SHAPES:
        return pick_place(12, yaw=math.radians(TASK_SHAPES[name]), random_state=0)[0]
    return load_lasa(name)


def shape_group(name: str) -> str:
    """The group a shape's results are pooled in.

    ``"multi"`` for the 4 ``Multi_Models_*`` shapes, ``"task"`` for the
    :data:`TASK_SHAPES`, ``"single"`` otherwise.

    Examples
    --------
    >>> [shape_group(s) for s in ("Multi_Models_2", "GShape", "PickPlace")]
    ['multi', 'single', 'task']
    """
    if name in TASK_SHAPES:
        return "task"
    return "multi" if name.startswith("Multi_Models") else "single"


def shape_range(demos) -> float:
    """The diagonal of the bounding box of the demonstrations' positions."""
    P = np.concatenate([d.get("position") for d in demos])
    return float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))


def message(exc: BaseException) -> str:
    """An exception's type and message on one line."""
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def score(test, times, path, scale: float, train, kw: dict, first: int = 0) -> dict:
    """The metrics of a generated path against the held-out demonstration.

    Parameters
    ----------
    test : Demonstration
        The held-out demonstration.
    times : ndarray of shape (n_samples,)
        The time stamps generated at (the held-out ones).
    path : array-like of shape (n_samples, n_dims)
        The generated positions.
    scale : float
        The shape's range; distances are divided by it.
    train : list of Demonstration
        The training demonstrations (for the on-route distance).
    kw : dict
        The protocol's conditions (:class:`Protocol`).
    first : int, default=0
        The first scored sample: the distances and ratios compare
        ``path[first:]`` with the held-out ``[first:]``, and the on-route
        distance uses the training demonstrations from the same normalized
        time on.

    Returns
    -------
    metrics : dict
        Every key of :data:`METRICS` but ``seconds``; ``via_error`` (the
        largest distance at a via point's time to it) and ``prefix_jump`` (the
        distance from the last observed sample to the first generated one) are
        NaN without via points or a prefix.

    Raises
    ------
    ValidationError
        ``path`` does not have one position per time stamp.
    """
    A = test.get("position")
    B = np.asarray(path, dtype=float)
    if B.shape != A.shape:
        raise ValidationError(
            f"the generator returned an array of shape {B.shape}; expected"
            f" {A.shape} (one position per time stamp)"
        )
    tau = unit_time(times)[first]
    out = {
        "dtw": dtw_distance(A[first:], B[first:], normalize=True) / scale,
        # on a route someone showed: the nearest training demonstration
        "on_route": min(
            dtw_distance(
                d.get("position")[unit_time(d.t) >= tau], B[first:], normalize=True
            )
            for d in train
        )
        / scale,
        "frechet": discrete_frechet(A[first:], B[first:]) / scale,
        "rmse": time_aligned_rmse(test.t[first:], A[first:], times[first:], B[first:])
        / scale,
        "endpoint": endpoint_error(A[first:], B[first:]) / scale,
        "path_length_ratio": path_length_ratio(A[first:], B[first:]),
        "turning_ratio": turning_ratio(A[first:], B[first:]),
        "via_error": math.nan,
        "prefix_jump": math.nan,
    }
    if kw.get("via"):
        gaps = [np.linalg.norm(B[np.searchsorted(times, v)] - p) for v, p in kw["via"]]
        out["via_error"] = float(max(gaps)) / scale
    if kw.get("observed") is not None:
        last = np.asarray(kw["observed"], dtype=float)[-1]
        out["prefix_jump"] = float(np.linalg.norm(B[first] - last)) / scale
    return out


@contextlib.contextmanager
def _single_threaded_blas():
    """Limit BLAS to one thread while the baselines run, when threadpoolctl is here.

    ProMP's and GMR's matrices are small (a few hundred rows): BLAS threads
    only contend with each other and with parallel folds (ten times slower
    measured on LASA).
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - depends on the environment
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def run_fold(
    shape: str,
    fold: int,
    protocols: tuple[str, ...],
    factories: dict[str, Callable],
    keep_paths: bool,
) -> tuple[list[dict], dict | None]:
    """Fit every generator on all demos of ``shape`` but ``fold``; score each protocol.

    Returns
    -------
    rows : list of dict
        One per generator and protocol, keys :data:`ROW_KEYS`.
    example : dict or None
        With ``keep_paths``: the fold, the paths and standard deviations by
        ``(protocol, generator)``, the conditions by protocol, and
        :data:`SAMPLES` paths drawn from the first generator that samples.
    """
    with _single_threaded_blas():
        return _run_fold(shape, fold, protocols, factories, keep_paths)


def _given(gen, kw: dict) -> dict:
    """A protocol's conditions for one generator: frames only if it takes them."""
    if "frames" not in kw:
        return kw
    if getattr(gen, "takes_frames", False):
        return {k: v for k, v in kw.items() if k != "via"}
    return {k: v for k, v in kw.items() if k != "frames"}


def _run_fold(shape, fold, protocols, factories, keep_paths):
    demos = load_shape(shape)
    test = demos[fold]
    train = [d for i, d in enumerate(demos) if i != fold]
    scale = shape_range(demos)
    times = test.t
    conditions = {p: PROTOCOLS.get(p).conditions(test) for p in protocols}
    base = {"shape": shape, "group": shape_group(shape), "fold": fold}
    rows = []
    example = None
    if keep_paths:
        example = {"fold": fold, "paths": {}, "stds": {}, "samples": []}
        example["conditions"] = {p: kw for p, (kw, _) in conditions.items()}
    for name, factory in factories.items():
        t0 = time.perf_counter()
        try:
            gen = factory()
            gen.fit(train)
            fit_error = None
        except Exception as exc:
            fit_error = message(exc)
        fit_seconds = time.perf_counter() - t0
        for protocol in protocols:
            kw, first = conditions[protocol]
            row = dict.fromkeys(ROW_KEYS, math.nan)
            row.update(base, protocol=protocol, generator=name, range=scale)
            row.update(ok=False, error=fit_error or "")
            if fit_error is None:
                t0 = time.perf_counter()
                try:
                    path = gen.generate(times, **_given(gen, kw))
                    seconds = fit_seconds + time.perf_counter() - t0
                    row.update(score(test, times, path, scale, train, kw, first))
                    row.update(ok=True, seconds=seconds)
                except Exception as exc:
                    row["error"] = message(exc)
            rows.append(row)
            if example is not None and row["ok"]:
                example["paths"][protocol, name] = np.asarray(path, dtype=float)
                std = _std(gen, times, kw, path)
                if std is not None:
                    example["stds"][protocol, name] = std
        if example is not None and fit_error is None and not example["samples"]:
            example["samples"] = _samples(gen, times)
    return rows, example


def _std(gen, times, kw, path) -> np.ndarray | None:
    """The generator's standard deviation when it offers one (else None)."""
    if not getattr(gen, "has_std", False):
        return None
    try:
        _, std = gen.generate(times, **kw, return_std=True)
    except Exception:
        return None
    std = np.asarray(std, dtype=float)
    ok = std.shape == np.shape(path) and np.isfinite(std).all()
    return std if ok else None


def _samples(gen, times) -> list:
    """:data:`SAMPLES` paths drawn from the generator when it samples (else [])."""
    if not callable(getattr(gen, "sample", None)):
        return []
    try:
        draws = gen.sample(times, SAMPLES, random_state=0)
        return [np.asarray(p, dtype=float) for p in draws]
    except Exception:
        return []
