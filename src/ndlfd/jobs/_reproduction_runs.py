"""The experiments of ``ndlfd reproduce``: settings, paper numbers and runs.

One function per figure of the paper (:func:`fig2_normalization`,
:func:`fig3_channels`, :func:`fig5_learning` with :func:`fig5_spread_sweep`,
:func:`fig6_levels` with :func:`fig6_noise_sweep`). Each returns a plain
dictionary; :mod:`ndlfd.jobs.reproduction` runs them, draws them
(:mod:`ndlfd.jobs._reproduction_figures`) and writes the report
(:mod:`ndlfd.jobs._reproduction_report`).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from .. import synth
from .._errors import DecodeError
from ..demonstration import Demonstration
from ..dp import simplify
from ..learner import KeypointHMM
from ..metrics import mean_demo_baseline, path_difference, path_errors
from ..normalize import GroupScaler

__all__ = [
    "CHANNELS",
    "DISTANCES",
    "NORMALIZATION_MODES",
    "PAPER",
    "ReproductionSettings",
    "fig2_normalization",
    "fig3_channels",
    "fig3_order_holds",
    "fig5_learning",
    "fig5_spread_sweep",
    "fig6_levels",
    "fig6_noise_sweep",
    "first_split",
]

#: The numbers the paper reports (SPEC §2).
PAPER = {
    "fig3": {"position": 17, "velocity": 26, "both": 30},
    "fig5_square": {"position": (45, 60), "position+velocity": (39, 46)},
    "fig5_spiral": {"position": (48, 57), "position+velocity": (49, 51)},
    "fig6": {"10-20": 25.76, "20-30": 11.89},
}

#: The two distances every experiment is run with.
DISTANCES = ("line", "paper")

NORMALIZATION_MODES = ("none", "per-dimension", "group")
CHANNELS = {
    "position": ("position",),
    "velocity": ("velocity",),
    "both": ("position", "velocity"),
}


@dataclass(frozen=True)
class ReproductionSettings:
    """Parameters of the reproduction (all tolerances in normalized units).

    Parameters
    ----------
    seed : int, default=2025
        Seed of every random draw (training sets, test demonstrations, noise).
    n_demos : int, default=100
        Training demonstrations per dataset (the paper's 100).
    noise : float, default=0.10
        Training noise level (:func:`ndlfd.synth.make_dataset`).
    test_noise : float, default=0.05
        Noise level of the test ("ideal") demonstration.
    reduction_noise : float, default=0.05
        Position noise of the noisy variant of the Fig. 3 curve (the paper's
        5 % for its reduction examples; velocity gets 0.6 × that, its 3 %).
    fig2_epsilon : float, default=0.05
        Douglas–Peucker tolerance of Fig. 2.
    fig3_epsilon : float, default=0.05
        The one tolerance of Fig. 3 (the library's default, as for Fig. 2, 5
        and 6; not tuned to the paper's counts).
    fig3_sweep : tuple of float
        Tolerances at which the Fig. 3 order is checked and reported.
    fig5_epsilon : float, default=0.05
        Tolerance of Fig. 5 and Fig. 6 (the same for low and high dimension;
        the library's default).
    fig5_sweep : tuple of float
        Tolerances at which the Fig. 5 spread of key-point counts is reported.
    n_time_bins : int, default=50
        Time symbols of the HMM.
    levels : dict
        Codebook levels per group (the paper's 20 for position, 10 for velocity).
    fig6_levels : tuple of int, default=(10, 20, 30)
        Position levels compared in Fig. 6.
    fig6_noise_sweep : tuple of float
        Training noise levels at which Fig. 6 is repeated (test noise is half).
    n_sweep_seeds : int, default=5
        Data sets (seeds ``seed + 100, seed + 101, ...``) per noise level of
        that sweep.
    n_sweep_demos : int, default=100
        Training demonstrations per data set of that sweep (kept at 100 in
        quick mode: with few, nearly noise-free demonstrations some test time
        bins are never emitted in training).
    shapes : tuple of str
        The datasets of Fig. 5: the 2-D square and the 3-D square spiral.
    dpi : int, default=100
        Resolution of the figures.
    """

    seed: int = 2025
    n_demos: int = 100
    noise: float = 0.10
    test_noise: float = 0.05
    reduction_noise: float = 0.05
    fig2_epsilon: float = 0.05
    fig3_epsilon: float = 0.05
    fig3_sweep: tuple[float, ...] = tuple(round(0.01 * k, 2) for k in range(1, 13))
    fig5_epsilon: float = 0.05
    fig5_sweep: tuple[float, ...] = (0.05, 0.1, 0.15, 0.2)
    n_time_bins: int = 50
    levels: dict = field(default_factory=lambda: {"position": 20, "velocity": 10})
    fig6_levels: tuple[int, ...] = (10, 20, 30)
    fig6_noise_sweep: tuple[float, ...] = (0.01, 0.02, 0.05, 0.10)
    n_sweep_seeds: int = 5
    n_sweep_demos: int = 100
    shapes: tuple[str, ...] = ("square", "square_spiral")
    dpi: int = 100

    def quick(self) -> ReproductionSettings:
        """The same settings at reduced sizes (20 demos, 2 sweep seeds, 40 dpi)."""
        return replace(self, n_demos=20, n_sweep_seeds=2, dpi=40)


# ----------------------------------------------------------------- Fig. 2
def fig2_normalization(
    demo: Demonstration | None = None,
    *,
    epsilon: float = 0.05,
    distance: str = "line",
) -> dict:
    """Key points of the 6-D spiral under the three normalization modes (Fig. 2).

    Parameters
    ----------
    demo : Demonstration, optional
        A demonstration with position and velocity groups; the paper's spiral
        (:func:`ndlfd.synth.spiral`) by default.
    epsilon : float, default=0.05
        Douglas–Peucker tolerance, the same for every mode. In mode ``"none"``
        it applies to raw physical units.
    distance : {"line", "paper"}, default="line"
        Distance of the reduction.

    Returns
    -------
    result : dict
        One entry per mode (``"none"``, ``"per-dimension"``, ``"group"``) with
        ``keypoints`` (indices), ``n_keypoints``, ``values`` (the transformed
        position columns, shape ``(n_samples, 3)``), ``ranges`` (the range of
        each transformed position column), ``proportions`` (``ranges``
        divided by the first one: X:Y:Z), ``chord`` (``U[-1] - U[0]``, the
        first chord Douglas–Peucker splits) and ``first_split`` (the largest
        distance of an interior point to that chord: ``{"line": ...,
        "paper": ...}``, the paper's value from eq. 5–6 with ``numpy.linalg.det``,
        independently of the compiled kernel).

    Examples
    --------
    >>> r = fig2_normalization()
    >>> [round(float(p), 2) for p in r["group"]["proportions"]]
    [1.0, 0.5, 0.5]
    """
    if demo is None:
        demo = synth.spiral()
    demo = demo.select("position", "velocity")
    n_pos = demo.get("position").shape[1]
    out = {}
    for mode in NORMALIZATION_MODES:
        U = GroupScaler(mode=mode).fit([demo]).transform(demo)
        idx = simplify(U, epsilon, distance=distance)
        P = U[:, :n_pos]
        ranges = P.max(axis=0) - P.min(axis=0)
        out[mode] = {
            "keypoints": idx,
            "n_keypoints": int(idx.size),
            "values": P,
            "ranges": ranges,
            "proportions": ranges / ranges[0],
            "chord": U[-1] - U[0],
            "first_split": first_split(U),
        }
    return out


def first_split(U: np.ndarray) -> dict:
    """Largest line and determinant distance to the chord ``U[0]``–``U[-1]``."""
    n, d = U.shape
    if n < 3:
        return {"line": 0.0, "paper": 0.0}
    u = U[-1] - U[0]
    norm = float(np.linalg.norm(u))
    v = U[1:-1] - U[0]
    if norm == 0.0:
        dist = np.linalg.norm(v, axis=1)
        return {"line": float(dist.max()), "paper": float(dist.max())}
    line = np.linalg.norm(v - np.outer(v @ u / (u @ u), u), axis=1)
    A = np.zeros((n - 2, d + 1, d + 1))
    A[:, 0] = np.r_[1.0, U[0]]
    A[:, 1, 0] = 1.0
    A[:, 1, 1:] = U[1:-1]
    A[:, 2] = np.r_[1.0, U[-1]]
    for k in range(1, d - 1):  # eq. 5 completion: zeros in 0..k-1, ones in k..d
        A[:, 2 + k, k:] = 1.0
    paper = np.abs(np.linalg.det(A)) / norm
    return {"line": float(line.max()), "paper": float(paper.max())}


# ----------------------------------------------------------------- Fig. 3
def fig3_channels(
    demo: Demonstration | None = None,
    *,
    epsilon: float = 0.05,
    distance: str = "line",
) -> dict:
    """Key points of one curve from position, velocity, or both (Fig. 3).

    Each channel set is normalized by group (fitted on this demonstration) and
    reduced with the same ``epsilon``.

    Parameters
    ----------
    demo : Demonstration, optional
        A demonstration with position and velocity; the paper's 2-D curve with
        variable velocity (:func:`ndlfd.synth.curve`) by default.
    epsilon : float, default=0.05
        The one tolerance used for all three channel sets.
    distance : {"line", "paper"}, default="line"
        Distance of the reduction.

    Returns
    -------
    result : dict
        ``"position"``, ``"velocity"``, ``"both"`` → ``{"keypoints": indices,
        "n_keypoints": int, "chord": ..., "first_split": ...}`` (the last two
        as in :func:`fig2_normalization`).

    Examples
    --------
    >>> r = fig3_channels()
    >>> sorted(r)
    ['both', 'position', 'velocity']
    """
    if demo is None:
        demo = synth.curve()
    out = {}
    for name, groups in CHANNELS.items():
        d = demo.select(*groups)
        U = GroupScaler(mode="group").fit([d]).transform(d)
        idx = simplify(U, epsilon, distance=distance)
        out[name] = {
            "keypoints": idx,
            "n_keypoints": int(idx.size),
            "chord": U[-1] - U[0],
            "first_split": first_split(U),
        }
    return out


def fig3_order_holds(counts: dict) -> bool:
    return counts["position"] < counts["velocity"] < counts["both"]


# ----------------------------------------------------------------- Fig. 5
def _model(groups, levels, settings: ReproductionSettings, distance: str):
    return KeypointHMM(
        groups=groups,
        levels={g: levels[g] for g in groups},
        epsilon=settings.fig5_epsilon,
        n_time_bins=settings.n_time_bins,
        distance=distance,
        normalization="group",
        generation="paper",  # the paper's procedure, as reproduced
    )


def _position_demo(like: Demonstration, t, values) -> Demonstration:
    pos = like.select("position")
    return Demonstration(t, values, pos.columns, pos.groups)


def fig5_learning(
    train: Sequence[Demonstration],
    test: Demonstration,
    *,
    settings: ReproductionSettings | None = None,
    distance: str = "line",
) -> dict:
    """Learn from position only and from position + velocity, generate (Fig. 5).

    Parameters
    ----------
    train : sequence of Demonstration
        Noisy training demonstrations with position and velocity.
    test : Demonstration
        The test ("ideal") demonstration whose timing is decoded.
    settings : ReproductionSettings, optional
        Tolerance, time bins and codebook levels.
    distance : {"line", "paper"}, default="line"
        Distance of the reduction.

    Returns
    -------
    result : dict
        ``"position"`` and ``"position+velocity"`` → dict with ``counts`` (key
        points per training demonstration), ``min``, ``max``, ``iqr``, ``std``,
        ``states_used``, ``n_states``, ``model``, ``generated`` (key points),
        ``dense`` (generated path on the test's time stamps) and ``errors``
        (:func:`ndlfd.metrics.path_errors` of the dense path to the test);
        ``"baseline"`` → the errors of the mean-demonstration baseline;
        ``"demos_median"`` → the median over training demonstrations of their
        own difference % to the test (how far a typical demonstration is).
    """
    settings = settings or ReproductionSettings()
    out = {}
    for name, groups in (
        ("position", ("position",)),
        ("position+velocity", ("position", "velocity")),
    ):
        model = _model(groups, settings.levels, settings, distance).fit(train)
        counts = np.asarray(model.n_keypoints_)
        keys = model.generate(test)
        dense = model.generate(test, dense=True)
        out[name] = {
            "counts": counts,
            **_spread(counts),
            "states_used": int(model.n_states_used_),
            "n_states": int(model.codebook_.n_states),
            "model": model,
            "generated": keys,
            "dense": dense,
            "errors": path_errors(test, dense),
        }
    base = mean_demo_baseline(train, test.t)
    out["baseline"] = {"errors": path_errors(test, _position_demo(test, test.t, base))}
    out["n_samples"] = int(train[0].n_samples)
    P = test.get("position")
    out["demos_median"] = float(
        np.median([path_difference(test.t, P, d.t, d.get("position")) for d in train])
    )
    return out


def _spread(counts: np.ndarray) -> dict:
    q75, q25 = np.percentile(counts, [75, 25])
    return {
        "min": int(counts.min()),
        "max": int(counts.max()),
        "iqr": float(q75 - q25),
        "std": float(counts.std()),
    }


def fig5_spread_sweep(
    train: Sequence[Demonstration],
    epsilons: Sequence[float],
    *,
    settings: ReproductionSettings | None = None,
    distance: str = "line",
) -> dict:
    """Spread of key-point counts, position vs position + velocity, over tolerances.

    Parameters
    ----------
    train : sequence of Demonstration
        Noisy training demonstrations with position and velocity.
    epsilons : sequence of float
        Tolerances to try.
    settings : ReproductionSettings, optional
        Time bins and codebook levels.
    distance : {"line", "paper"}, default="line"
        Distance of the reduction.

    Returns
    -------
    result : dict
        ``epsilon`` → ``{"position": spread, "position+velocity": spread}`` with
        ``spread`` holding ``min``, ``max``, ``iqr`` and ``std`` of the counts.
    """
    settings = settings or ReproductionSettings()
    out = {}
    for eps in epsilons:
        s = replace(settings, fig5_epsilon=float(eps))
        out[eps] = {
            name: _spread(
                np.asarray(
                    _model(groups, s.levels, s, distance).fit(train).n_keypoints_
                )
            )
            for name, groups in (
                ("position", ("position",)),
                ("position+velocity", ("position", "velocity")),
            )
        }
    return out


# ----------------------------------------------------------------- Fig. 6
def fig6_levels(
    train: Sequence[Demonstration],
    test: Demonstration,
    *,
    levels: Sequence[int] = (10, 20, 30),
    settings: ReproductionSettings | None = None,
    distance: str = "line",
) -> dict:
    """Generated 2-D paths at several codebook resolutions and their differences.

    The difference between two generated paths is
    :func:`ndlfd.metrics.path_difference` between the two dense generated
    paths (both sampled at the test demonstration's time stamps), with the
    test demonstration's position bounding-box diagonal as 100 %.

    Parameters
    ----------
    train : sequence of Demonstration
        Training demonstrations (their position group is learned).
    test : Demonstration
        The test demonstration whose timing is decoded by every model.
    levels : sequence of int, default=(10, 20, 30)
        Position codebook levels to compare (in this order).
    settings : ReproductionSettings, optional
        Tolerance and time bins.
    distance : {"line", "paper"}, default="line"
        Distance of the reduction.

    Returns
    -------
    result : dict
        ``"paths"`` → {levels: dense generated Demonstration}, ``"keys"`` →
        {levels: generated key points}, ``"differences"`` → {"10-20": %, ...}
        between consecutive levels, ``"errors"`` → {levels: errors to test},
        ``"scale"`` → the diagonal used as 100 %, ``"ranges"`` → {levels:
        (min, max) of the position group fitted by the scaler}.
    """
    settings = settings or ReproductionSettings()
    pos = test.get("position")
    scale = float(np.linalg.norm(pos.max(axis=0) - pos.min(axis=0)))
    paths, keys, errors, ranges = {}, {}, {}, {}
    for lv in levels:
        model = _model(("position",), {"position": lv}, settings, distance).fit(train)
        ranges[lv] = (
            float(model.scaler_.data_min_.min()),
            float(model.scaler_.data_max_.max()),
        )
        keys[lv] = model.generate(test)
        paths[lv] = model.generate(test, dense=True)
        errors[lv] = path_errors(test, paths[lv])
    diffs = {}
    for a, b in itertools.pairwise(levels):
        pa, pb = paths[a], paths[b]
        diffs[f"{a}-{b}"] = path_difference(
            pa.t, pa.get("position"), pb.t, pb.get("position"), scale=scale
        )
    return {
        "paths": paths,
        "keys": keys,
        "differences": diffs,
        "errors": errors,
        "scale": scale,
        "ranges": ranges,
    }


def fig6_noise_sweep(
    noises: Sequence[float],
    *,
    settings: ReproductionSettings | None = None,
    distance: str = "line",
) -> dict:
    """Fig. 6 repeated at several training noise levels and seeds.

    For each noise level, ``settings.n_sweep_seeds`` square data sets of
    ``settings.n_sweep_demos`` demonstrations are drawn (seeds
    ``settings.seed + 100 + k``; test noise is half the training noise) and
    :func:`fig6_levels` is run on each. A data set whose test timing cannot be
    decoded by one of the models (a time bin never emitted in training) is
    recorded as ``None``.

    Parameters
    ----------
    noises : sequence of float
        Training noise levels (fractions of the path's range).
    settings : ReproductionSettings, optional
        Sizes, tolerance, time bins, levels and seeds.
    distance : {"line", "paper"}, default="line"
        Distance of the reduction.

    Returns
    -------
    result : dict
        ``noise`` → list (one per seed) of ``{"differences": ..., "errors":
        {levels: difference % to the test}}`` or ``None``.
    """
    settings = settings or ReproductionSettings()
    out = {}
    for noise in noises:
        rows = []
        for k in range(settings.n_sweep_seeds):
            train, test = synth.make_dataset(
                settings.shapes[0],
                n_demos=settings.n_sweep_demos,
                noise=noise,
                test_noise=noise / 2,
                random_state=settings.seed + 100 + k,
            )
            try:
                r = fig6_levels(
                    train,
                    test,
                    levels=settings.fig6_levels,
                    settings=settings,
                    distance=distance,
                )
            except DecodeError:
                rows.append(None)
                continue
            rows.append(
                {
                    "differences": r["differences"],
                    "errors": {
                        lv: e["difference_pct"] for lv, e in r["errors"].items()
                    },
                }
            )
        out[noise] = rows
    return out
