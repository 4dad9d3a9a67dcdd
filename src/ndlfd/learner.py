"""KeypointHMM: the whole method as one scikit-learn style estimator.

It composes the stages and holds no algorithm of its own::

    demos → GroupScaler → simplify (key points) → Codebook + TimeBins → hmm.estimate
    new timing → TimeBins → hmm.viterbi → Codebook.decode → inverse_transform
"""

from __future__ import annotations

import numbers
import os
from collections.abc import Mapping, Sequence

import numpy as np

from . import hmm
from ._blend import (
    align_many,
    blend,
    condition_weights,
    fade_ramp,
    segment_states,
    skeleton_times,
)
from ._errors import DecodeError, NotFittedError, ValidationError
from ._fileformat import load_npz, save_npz
from ._registry import Registry
from ._simplify import DISTANCES, simplify, simplify_many
from ._validation import (
    check_nonnegative_scalar,
    check_positive_int,
    check_times,
)
from .codebook import Codebook, TimeBins
from .demo import Demonstration, with_velocity
from .normalize import GroupScaler
from .orientation import normalize_quaternions

__all__ = ["AUTO_GROUPS", "DEFAULT_LEVELS", "KeypointHMM"]

#: The groups ``groups="auto"`` learns when a demonstration has them, in this
#: order (velocity also when it can be derived from position).
AUTO_GROUPS = ("position", "velocity", "orientation", "force")

#: Codebook levels per physical group when ``levels`` does not name the group
#: (the paper's 20 for position and 10 for velocity).
DEFAULT_LEVELS = {"position": 20, "velocity": 10, "orientation": 10, "force": 10}

_FORMAT_KIND = "KeypointHMM"
#: Version 2 adds the normalized training values the blended generation needs;
#: version-1 files still load and generate with ``generation="paper"``.
_FORMAT_VERSION = 2

NORMALIZATIONS = Registry("normalization")
for _name in ("group", "per-dimension", "none"):
    NORMALIZATIONS.add(_name, _name)
STARTS = Registry("start")
for _name in ("learned", "state1"):
    STARTS.add(_name, _name)


def _decode_viterbi(model, symbols, start):
    return hmm.viterbi(model, symbols, start=start)


def _decode_map(model, symbols, start):
    post = hmm.posterior(model, symbols, start=start)
    best = np.argmax(post.probabilities, axis=1)  # ties: the lowest state
    logp = float(np.sum(np.log(post.probabilities[np.arange(best.size), best])))
    return post.states[best], logp


#: Decoders: a function ``(model, symbols, start) -> (states, log_probability)``.
#: ``"viterbi"`` is the most likely state sequence; ``"map"`` the most likely
#: state at each step on its own (posterior argmax; the log-probability is the
#: sum of the chosen states' log posteriors).
DECODERS = Registry("decoder")
DECODERS.add("viterbi", _decode_viterbi)
DECODERS.add("map", _decode_map)


def _as_demo_list(demos) -> list[Demonstration]:
    if isinstance(demos, Demonstration):
        return [demos]
    if isinstance(demos, (str, bytes, os.PathLike)) or not isinstance(demos, Sequence):
        raise ValidationError(
            "demos must be a Demonstration or a list of them; got"
            f" {type(demos).__name__}. Load files with ndlfd.io.read_demos."
        )
    out = list(demos)
    if not out:
        raise ValidationError("demos must hold at least one demonstration; got none")
    for i, d in enumerate(out):
        if not isinstance(d, Demonstration):
            raise ValidationError(
                f"demos[{i}] must be a Demonstration; got {type(d).__name__}"
            )
    return out


class KeypointHMM:
    """Learn a path from demonstrations and generate it for a new timing.

    Parameters
    ----------
    groups : "auto", sequence of str or None, default="auto"
        The physical groups to learn from, in this order. ``"auto"`` learns
        those of :data:`AUTO_GROUPS` (position, velocity, orientation, force)
        that the first demonstration has, velocity derived when missing, so a
        file's orientation is never dropped in silence (learning it leaves the
        position path unchanged: 16.98 mm mean error on a held-out 3-D reach
        either way). ``None`` uses every group of the first demonstration. A
        ``"velocity"`` group missing from a demonstration is derived from its
        position and time stamps when ``derive_velocity`` is true.
    levels : int or mapping of str to int, optional
        Codebook levels per group (one int for all groups). Groups not named
        fall back to :data:`DEFAULT_LEVELS` (20 for position, 10 otherwise).
    epsilon : float, default=0.05
        Douglas–Peucker tolerance on the normalized (and weighted) values.
        Ignored when ``n_points`` is given.
    n_time_bins : int, default=50
        Number of time symbols ``N_t``.
    n_points : int, optional
        Key-point budget per demonstration instead of ``epsilon``.
    distance : {"line", "segment", "sed", "paper"}, default="line"
        Distance used by the reduction (see :func:`ndlfd.simplify`).
    normalization : {"group", "per-dimension", "none"}, default="group"
        How values are normalized before reduction and encoding.
    weights : mapping of str to float, optional
        Per-group weights multiplying the normalized values during reduction
        only (the codebook always sees the unweighted values in ``[0, 1]``).
    pseudo_transition : float, optional
        Transition pseudo-count; ``None`` means ``1 / n_states``.
    pseudo_emission : float, default=0.0
        Emission pseudo-count.
    start : {"learned", "state1"}, default="learned"
        Start distribution of the decoder (``"state1"`` reproduces MATLAB
        ``hmmviterbi``).
    generation : {"blend", "paper"}, default="blend"
        How a path is generated. ``"blend"`` decodes the key points and their
        times jointly (a segment model over all time bins), aligns the training
        demonstrations to the decoded key points and blends them (see
        :mod:`ndlfd._blend`); it follows the demonstrations' shape, can be
        conditioned on a start and goal, and gives an uncertainty band.
        ``"paper"`` is the paper's procedure: one observation per time bin (or
        per key point of a test demonstration), codebook cell centres and
        straight lines between them.
    decoder : {"viterbi", "map"}, default="viterbi"
        ``"viterbi"``: the most likely state sequence; ``"map"``: the most
        likely state at each step (posterior argmax, :func:`ndlfd.hmm.posterior`).
    derive_velocity : bool, default=True
        Derive a missing velocity group from position and time.
    n_jobs : int, optional
        Threads used to reduce many demonstrations.
    random_state : None, int or Generator, default=None
        Accepted for the estimator contract; fitting and generation are fully
        deterministic, so it changes nothing today.

    Attributes
    ----------
    columns_ : tuple of str
        Names of the learned columns.
    column_groups_ : tuple of str
        Group of each learned column.
    scaler_ : GroupScaler
        The fitted normalization.
    codebook_ : Codebook
        The discrete states.
    time_bins_ : TimeBins
        The time symbols.
    model_ : ndlfd.hmm.DiscreteHMM
        The supervised discrete HMM.
    keypoints_ : list of ndarray of int
        Key-point indices of each training demonstration.
    n_keypoints_ : ndarray of shape (n_demos,)
        Number of key points per demonstration.
    n_states_used_ : int
        Number of distinct codebook states seen in training.
    n_clipped_ : int
        Values clipped by the codebook while fitting (0 unless weights or
        normalization ``"none"`` push values outside ``[0, 1]``).

    Examples
    --------
    >>> from ndlfd import synth
    >>> train, test = synth.make_dataset("square", n_demos=20, random_state=0)
    >>> model = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
    >>> path = model.generate(test)
    >>> path.groups[:2]
    ('position', 'position')
    """

    def __init__(
        self,
        groups="auto",
        levels=None,
        epsilon=0.05,
        n_time_bins=50,
        *,
        n_points=None,
        distance="line",
        normalization="group",
        weights=None,
        pseudo_transition=None,
        pseudo_emission=0.0,
        start="learned",
        generation="blend",
        decoder="viterbi",
        derive_velocity=True,
        n_jobs=None,
        random_state=None,
    ):
        self.groups = groups
        self.levels = levels
        self.epsilon = epsilon
        self.n_time_bins = n_time_bins
        self.n_points = n_points
        self.distance = distance
        self.normalization = normalization
        self.weights = weights
        self.pseudo_transition = pseudo_transition
        self.pseudo_emission = pseudo_emission
        self.start = start
        self.generation = generation
        self.decoder = decoder
        self.derive_velocity = derive_velocity
        self.n_jobs = n_jobs
        self.random_state = random_state

    # ------------------------------------------------------------------ params
    def get_params(self, deep: bool = True) -> dict:
        """Return the constructor parameters (scikit-learn convention)."""
        return {k: getattr(self, k) for k in _PARAM_NAMES}

    def set_params(self, **params) -> KeypointHMM:
        """Set constructor parameters (scikit-learn convention)."""
        for k, v in params.items():
            if k not in _PARAM_NAMES:
                raise ValidationError(
                    f"unknown parameter {k!r}; expected one of: "
                    + ", ".join(_PARAM_NAMES)
                )
            setattr(self, k, v)
        return self

    def __repr__(self) -> str:
        defaults = KeypointHMM().get_params()
        changed = {
            k: v for k, v in self.get_params().items() if not _same(v, defaults[k])
        }
        inner = ", ".join(f"{k}={v!r}" for k, v in changed.items())
        return f"KeypointHMM({inner})"

    # ----------------------------------------------------------------- helpers
    def _check_params(self) -> None:
        NORMALIZATIONS.get(self.normalization)
        STARTS.get(self.start)
        GENERATIONS.get(self.generation)
        DECODERS.get(self.decoder)
        DISTANCES.get(self.distance)
        if self.n_points is None:
            check_nonnegative_scalar(self.epsilon, "epsilon")
        else:
            check_positive_int(self.n_points, "n_points", minimum=2)
        check_positive_int(self.n_time_bins, "n_time_bins")
        if self.pseudo_transition is not None:
            check_nonnegative_scalar(self.pseudo_transition, "pseudo_transition")
        check_nonnegative_scalar(self.pseudo_emission, "pseudo_emission")

    def _wanted_groups(self, first: Demonstration) -> tuple[str, ...]:
        if self.groups is None:
            return tuple(first.group_names)
        if isinstance(self.groups, str) and self.groups == "auto":
            have = set(first.group_names)
            if self.derive_velocity and "position" in have:
                have.add("velocity")
            auto = tuple(g for g in AUTO_GROUPS if g in have)
            return auto or tuple(first.group_names)
        if isinstance(self.groups, str):
            return (self.groups,)
        groups = tuple(self.groups)
        if not groups or not all(isinstance(g, str) for g in groups):
            raise ValidationError(
                f"groups must be a non-empty sequence of group names; got {groups!r}"
            )
        if len(set(groups)) != len(groups):
            raise ValidationError(f"groups must not repeat a name; got {groups!r}")
        return groups

    def _prepare(self, demo: Demonstration, groups: Sequence[str]) -> Demonstration:
        if (
            "velocity" in groups
            and "velocity" not in demo.group_names
            and self.derive_velocity
        ):
            demo = with_velocity(demo)
        missing = [g for g in groups if g not in demo.group_names]
        if missing:
            raise ValidationError(
                f"a demonstration lacks group(s) {', '.join(missing)}; it has"
                f" {', '.join(demo.group_names)}"
            )
        return demo.select(*groups)

    def _levels_by_group(self, groups: Sequence[str]) -> dict[str, int]:
        lv = self.levels
        if lv is None:
            lv = {}
        if isinstance(lv, numbers.Integral) and not isinstance(lv, bool):
            return {g: check_positive_int(lv, "levels") for g in groups}
        if not isinstance(lv, Mapping):
            raise ValidationError(
                f"levels must be an int or a mapping of group to int; got {lv!r}"
            )
        unknown = [g for g in lv if g not in groups]
        if unknown:
            raise ValidationError(
                f"levels names group(s) {', '.join(map(repr, unknown))} that are not"
                f" learned; the learned groups are {', '.join(groups)}"
            )
        out = {}
        for g in groups:
            if g in lv:
                out[g] = check_positive_int(lv[g], f"levels[{g!r}]")
            elif g in DEFAULT_LEVELS:
                out[g] = DEFAULT_LEVELS[g]
            else:
                raise ValidationError(
                    f"no codebook levels for group {g!r}; pass levels={{{g!r}: N}}"
                )
        return out

    def _column_weights(self) -> np.ndarray | None:
        """The scaler's per-column weights for the reduction (None if all 1)."""
        w = self.scaler_.column_weights_
        return None if np.all(w == 1.0) else w

    def _check_fitted(self) -> None:
        if not hasattr(self, "model_"):
            raise NotFittedError(
                "this KeypointHMM is not fitted yet; call fit(demos) first"
            )

    def _reduce(self, U_list, t_list) -> list[np.ndarray]:
        times = t_list if self.distance == "sed" else None
        return simplify_many(
            U_list,
            None if self.n_points is not None else self.epsilon,
            distance=self.distance,
            weights=self._column_weights(),
            times=times,
            n_points=self.n_points,
            n_jobs=self.n_jobs,
        )

    # --------------------------------------------------------------------- fit
    def fit(self, demos, y=None) -> KeypointHMM:
        """Learn the key points, codebook states and HMM from demonstrations.

        Parameters
        ----------
        demos : Demonstration or sequence of Demonstration
            Training demonstrations (lengths may differ).
        y : None
            Ignored.

        Returns
        -------
        self : KeypointHMM
        """
        self._check_params()
        demo_list = _as_demo_list(demos)
        groups = self._wanted_groups(demo_list[0])
        prepared = [self._prepare(d, groups) for d in demo_list]
        columns, col_groups = prepared[0].columns, prepared[0].groups
        for i, d in enumerate(prepared[1:], start=1):
            if d.columns != columns or d.groups != col_groups:
                raise ValidationError(
                    f"all demonstrations must have the same columns; demos[0] has"
                    f" {columns} and demos[{i}] has {d.columns}"
                )
        self.columns_ = tuple(columns)
        self.column_groups_ = tuple(col_groups)
        self.groups_ = groups
        if self.weights is not None and not isinstance(self.weights, Mapping):
            raise ValidationError(
                f"weights must be a mapping of group to weight; got {self.weights!r}"
            )
        self.scaler_ = GroupScaler(mode=self.normalization, weights=self.weights)
        self.scaler_.fit(prepared)
        # the codebook and the blend see [0, 1] values; weights act in reduction
        U = [self.scaler_.transform(d, weighted=False) for d in prepared]
        self.keypoints_ = self._reduce(U, [d.t for d in prepared])
        self.codebook_ = Codebook.from_groups(
            self._levels_by_group(groups), self.column_groups_
        )
        self.time_bins_ = TimeBins(self.n_time_bins)
        states, symbols, clipped = [], [], 0
        for d, u, idx in zip(prepared, U, self.keypoints_, strict=True):
            s, c = self.codebook_.encode(u[idx], return_n_clipped=True)
            states.append(s)
            clipped += int(c)
            symbols.append(self.time_bins_.transform(d.t)[idx])
        self.model_ = hmm.estimate(
            states,
            symbols,
            self.codebook_.n_states,
            self.n_time_bins,
            pseudo_transition=self.pseudo_transition,
            pseudo_emission=self.pseudo_emission,
        )
        self.n_keypoints_ = np.array([k.size for k in self.keypoints_], np.int64)
        self.n_states_used_ = int(np.unique(np.concatenate(states)).size)
        self.n_clipped_ = clipped
        self.n_demos_ = len(prepared)
        seen = np.zeros(self.n_time_bins, dtype=bool)
        seen[np.concatenate(symbols)] = True
        self.symbols_seen_ = seen
        self._fit_segments(U, [d.t for d in prepared])
        return self

    def _fit_segments(self, U_list, t_list) -> None:
        """Statistics of the blended generation (see :mod:`ndlfd._blend`)."""
        self.train_values_ = [np.asarray(u, np.float64) for u in U_list]
        self.train_tau_ = [self.time_bins_.normalize(t) for t in t_list]
        key_states, key_bins = [], []
        for u, tau, idx in zip(U_list, self.train_tau_, self.keypoints_, strict=True):
            key_states.append(self.codebook_.encode(u[idx]))
            key_bins.append(self.time_bins_.transform(tau)[idx])
        all_states = np.concatenate(key_states)
        ids, inv = np.unique(all_states, return_inverse=True)
        values = np.concatenate(
            [u[i] for u, i in zip(U_list, self.keypoints_, strict=True)]
        )
        sums = np.zeros((ids.size, values.shape[1]))
        np.add.at(sums, inv.reshape(-1), values)
        self.centroid_states_ = ids
        self.centroids_ = sums / np.bincount(inv.reshape(-1))[:, None]
        self._key_states = key_states
        self._key_bins = key_bins
        self.segment_model_ = self._segment_model(np.arange(len(U_list)))

    def _segment_model(self, demos: np.ndarray) -> hmm.DiscreteHMM:
        nt = self.n_time_bins
        seqs = [
            segment_states(self._key_bins[j], self._key_states[j], nt) for j in demos
        ]
        return hmm.estimate(
            seqs,
            [np.arange(nt)] * len(seqs),
            self.codebook_.n_states,
            nt,
            pseudo_transition=self.pseudo_transition,
            pseudo_emission=self.pseudo_emission,
        )

    # ---------------------------------------------------------------- generate
    def timing(self, times_or_demo) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Observation times and symbols for a new execution.

        A :class:`Demonstration` is normalized and reduced like the training
        demonstrations; its key points' times are the observations (the paper's
        procedure with its "ideal" test demonstration). A plain time vector has
        no key points: it contributes one observation per time bin it touches,
        at the bin's first time stamp, keeping only bins that training key points
        fell into (unless ``pseudo_emission > 0``, where every bin can be
        emitted).

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            The new execution or its time stamps.

        Returns
        -------
        key_times : ndarray of shape (n_obs,)
            Time of each observation.
        symbols : ndarray of shape (n_obs,), dtype int64
            Time symbol of each observation.
        all_times : ndarray of shape (n_samples,)
            Every time stamp of the new execution (for dense generation).
        """
        self._check_fitted()
        if isinstance(times_or_demo, Demonstration):
            d = self._prepare(times_or_demo, self.groups_)
            if d.columns != self.columns_:
                raise ValidationError(
                    f"the demonstration's columns {d.columns} differ from the"
                    f" learned columns {self.columns_}"
                )
            u = self.scaler_.transform(d, weighted=False)
            idx = simplify(
                u,
                None if self.n_points is not None else self.epsilon,
                n_points=self.n_points,
                distance=self.distance,
                weights=self._column_weights(),
                times=d.t if self.distance == "sed" else None,
            )
            return d.t[idx], self.time_bins_.transform(d.t)[idx], d.t
        t = check_times(times_or_demo, name="times")
        sym = self.time_bins_.transform(t)
        first = np.flatnonzero(np.r_[True, sym[1:] != sym[:-1]])
        if self.pseudo_emission == 0:
            first = first[self.symbols_seen_[sym[first]]]
        if first.size == 0:
            raise DecodeError(
                "none of the time bins of this timing was seen in training; cannot"
                " generate a path"
            )
        return t[first], sym[first], t

    def decode(self, times_or_demo) -> tuple[np.ndarray, np.ndarray, float]:
        """Decoded key points of a new timing: their times and codebook states.

        With ``generation="blend"`` the key points come from decoding every time
        bin with the segment model (a key point where the decoded state
        changes); with ``"paper"`` from decoding the observations of
        :meth:`timing`.

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            See :meth:`timing`.

        Returns
        -------
        key_times : ndarray of shape (n_keys,)
        states : ndarray of shape (n_keys,), dtype int64
        log_probability : float
        """
        self._check_fitted()
        if self.generation == "paper":
            key_t, states, logp, _ = self._decode_paper(times_or_demo)
            return key_t, states, logp
        all_t = self._times_of(times_or_demo)
        plan = self._plan(all_t, None, None)
        return self._key_times(all_t, plan["key_tau"]), plan["states"], plan["logp"]

    def _run_decoder(self, model, symbols):
        try:
            return DECODERS.get(self.decoder)(model, symbols, self.start)
        except DecodeError as exc:
            raise DecodeError(
                f"cannot generate a path for this timing: {exc}. Use fewer time"
                " bins, more demonstrations, or pseudo_emission > 0."
            ) from None

    def _decode_paper(self, times_or_demo):
        key_t, symbols, all_t = self.timing(times_or_demo)
        states, logp = self._run_decoder(self.model_, symbols)
        return key_t, states, logp, all_t

    def generate(
        self,
        times_or_demo,
        *,
        dense: bool = False,
        start=None,
        goal=None,
        return_std: bool = False,
    ):
        """Generate a path for a new timing, optionally from a start to a goal.

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            The new execution's time stamps (at least two), or a demonstration
            whose time stamps are used (with ``generation="paper"`` its key
            points' times are decoded, the paper's procedure).
        dense : bool, default=False
            Return every time stamp of the new execution instead of the
            generated key points only.
        start, goal : mapping of str to array-like, optional
            Where the robot starts and must end, in physical units, e.g.
            ``{"position": [x, y]}``. The demonstrations whose start (goal) is
            near are followed (a Gaussian kernel whose width is the typical
            distance between neighbouring demonstrations' starts), and the path
            begins (ends) exactly there: the remaining offset is faded out over
            the motion by a minimum-jerk ramp. With ``generation="paper"`` only
            the offset is applied.
        return_std : bool, default=False
            Also return the per-sample standard deviation of the learned
            positions at each time: the spread of the codebook centroids under
            the posterior state probabilities of the segment model
            (:func:`ndlfd.hmm.posterior`), in physical units. Only with
            ``generation="blend"``.

        Returns
        -------
        path : Demonstration
            The generated key points at their times, or the dense path when
            ``dense=True``. A velocity group is the derivative of the generated
            positions (``numpy.gradient`` over the path's time stamps).
        std : ndarray of shape (n_samples, n_columns)
            Only with ``return_std=True``.

        Examples
        --------
        >>> from ndlfd import synth
        >>> train, test = synth.make_dataset("square", n_demos=10, random_state=0)
        >>> model = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
        >>> path = model.generate(test.t, dense=True, start={"position": [0.5, 0.0]})
        >>> path.get("position")[0]
        array([0.5, 0. ])
        >>> bool(np.all(path.t == test.t))
        True
        """
        self._check_fitted()
        start = self._condition(start, "start")
        goal = self._condition(goal, "goal")
        how = GENERATIONS.get(self.generation)
        return how(self, times_or_demo, dense, start, goal, return_std)

    def _generate_blend(self, times_or_demo, dense, start, goal, return_std):
        all_t = self._times_of(times_or_demo)
        plan = self._plan(all_t, start, goal)
        tq = self.time_bins_.normalize(all_t)
        key_tau = plan["key_tau"]
        U = blend(
            [self.train_values_[j] for j in plan["demos"]],
            [self.train_tau_[j] for j in plan["demos"]],
            plan["index"],
            plan["weights"],
            np.concatenate([tq, key_tau]),
            quat_cols=self._quat_cols(),
        )[0]
        X = self._renormalize(self.scaler_.inverse_transform(U))
        X = self._pin(X, np.concatenate([tq, key_tau]), start, goal, tq.size)
        X = self._derive_velocity(X, tq, key_tau, all_t)
        if dense:
            path = Demonstration(
                all_t, X[: tq.size], self.columns_, self.column_groups_
            )
            band_tau = tq
        else:
            key_t = self._key_times(all_t, key_tau)
            path = Demonstration(
                key_t, X[tq.size :], self.columns_, self.column_groups_
            )
            band_tau = key_tau
        if not return_std:
            return path
        return path, self._band(plan["model"], band_tau)

    def _times_of(self, times_or_demo) -> np.ndarray:
        if isinstance(times_or_demo, Demonstration):
            t = times_or_demo.t
        else:
            t = check_times(times_or_demo, name="times")
        if t.size < 2:
            raise ValidationError(
                f"a timing needs at least two time stamps; got {t.size}"
            )
        return t

    def _key_times(self, all_t, key_tau):
        t = all_t[0] + key_tau * (all_t[-1] - all_t[0])
        t[-1] = all_t[-1]  # exact, not up to the rounding of the product
        return t

    def _condition(self, values, what: str) -> dict | None:
        """Check a start/goal mapping; return it as {group: float array}."""
        if values is None:
            return None
        if not isinstance(values, Mapping) or not values:
            raise ValidationError(
                f"{what} must be a mapping of group to values, e.g."
                f" {{'position': [x, y]}}; got {values!r}"
            )
        out = {}
        for g, v in values.items():
            cols = [i for i, cg in enumerate(self.column_groups_) if cg == g]
            if not cols:
                raise ValidationError(
                    f"{what} names group {g!r}, which is not learned; the learned"
                    f" groups are {', '.join(self.groups_)}"
                )
            arr = np.asarray(v, dtype=np.float64).reshape(-1)
            if arr.size != len(cols) or not np.all(np.isfinite(arr)):
                raise ValidationError(
                    f"{what}[{g!r}] must hold {len(cols)} finite value(s); got"
                    f" {np.asarray(v).tolist()!r}"
                )
            out[g] = arr
        return out

    def _cols(self, group: str) -> list[int]:
        return [i for i, g in enumerate(self.column_groups_) if g == group]

    def _quat_cols(self):
        cols = self._cols("orientation")
        return cols if len(cols) == 4 else None

    def _weights_for(self, cond, end: int) -> np.ndarray:
        J = len(self.train_values_)
        if cond is None:
            return np.ones(J)
        cols = [c for g in cond for c in self._cols(g)]
        target = self.scaler_.transform(
            self._physical_row(cond)[None, :], weighted=False
        )[0, cols]
        pts = np.array([u[end, cols] for u in self.train_values_])
        return condition_weights(pts, target)

    def _physical_row(self, cond) -> np.ndarray:
        row = self.scaler_.data_min_.copy()
        for g, v in cond.items():
            row[self._cols(g)] = v
        return row

    def _plan(self, all_t, start, goal) -> dict:
        """Decode the skeleton and align the demonstrations to it."""
        if not hasattr(self, "train_values_"):
            raise ValidationError(
                "this model has no training values (a format-1 file); use"
                " generation='paper' or fit it again"
            )
        w = self._weights_for(start, 0) * self._weights_for(goal, -1)
        w = w / w.max()
        demos = np.flatnonzero(w >= _KEEP_WEIGHT)
        model = (
            self.segment_model_ if demos.size == w.size else self._segment_model(demos)
        )
        states, logp = self._run_decoder(model, np.arange(self.n_time_bins))
        change = np.flatnonzero(np.r_[True, states[1:] != states[:-1]])
        skel = states[change]
        if skel.size == 1:
            skel = np.repeat(skel, 2)  # a start and an end in one state
        C = self.centroids_[np.searchsorted(self.centroid_states_, skel)]
        index = align_many(
            [self.train_values_[j] for j in demos],
            C,
            self.n_jobs,
            _ALIGN_CANDIDATES,
        )
        key_tau = skeleton_times([self.train_tau_[j] for j in demos], index, w[demos])
        # every alignment pins the ends to samples at tau 0 and 1: exact ends
        key_tau[0], key_tau[-1] = 0.0, 1.0
        return {
            "states": skel,
            "logp": logp,
            "demos": demos,
            "weights": w[demos],
            "index": index,
            "key_tau": key_tau,
            "model": model,
        }

    def _derive_velocity(self, X, tq, key_tau, all_t) -> np.ndarray:
        """Velocity columns as the derivative of the generated positions.

        ``X`` holds the dense rows (at ``all_t``) followed by the key rows (at
        normalized times ``key_tau``), whose velocity is interpolated from the
        dense derivative.
        """
        pos, vel = self._cols("position"), self._cols("velocity")
        if pos and len(pos) == len(vel):
            n = all_t.size
            V = np.gradient(X[:n, pos], all_t, axis=0)
            X[:n, vel] = V
            X[n:, vel] = np.column_stack([np.interp(key_tau, tq, c) for c in V.T])
        return X

    def _band(self, model, tq) -> np.ndarray:
        """Posterior spread of the centroids at each output time."""
        post = hmm.posterior(model, np.arange(self.n_time_bins), start=self.start)
        C = self.centroids_[np.searchsorted(self.centroid_states_, post.states)]
        gamma = post.probabilities
        gamma = gamma / gamma.sum(axis=1, keepdims=True)
        sd = np.empty((gamma.shape[0], C.shape[1]))
        for b, g in enumerate(gamma):  # two passes over the states with mass
            nz = np.flatnonzero(g)
            dev = C[nz] - g[nz] @ C[nz]
            sd[b] = np.sqrt(g[nz] @ (dev * dev))
        sd *= self.scaler_._divisor()
        centres = (np.arange(self.n_time_bins) + 0.5) / self.n_time_bins
        return np.column_stack([np.interp(tq, centres, c) for c in sd.T])

    def _generate_paper(self, times_or_demo, dense, start, goal, return_std):
        if return_std:
            raise ValidationError(
                "return_std needs generation='blend'; the paper's generation has"
                " no uncertainty band"
            )
        key_t, states, _, all_t = self._decode_paper(times_or_demo)
        X = self.scaler_.inverse_transform(self.codebook_.decode(states))
        X = self._renormalize(X)
        if dense:
            X = np.column_stack(
                [np.interp(all_t, key_t, X[:, c]) for c in range(X.shape[1])]
            )
            X = self._renormalize(X)
            key_t = all_t
        if start is not None or goal is not None:
            span = all_t[-1] - all_t[0]
            tq = (key_t - all_t[0]) / span if span > 0 else np.zeros_like(key_t)
            X = self._pin(X, tq, start, goal)
        return Demonstration(key_t, X, self.columns_, self.column_groups_)

    def _pin(self, X, tq, start, goal, n_dense=None) -> np.ndarray:
        """Shift the path onto ``start`` and ``goal`` with a faded offset.

        The offsets are measured on the first and last of the first ``n_dense``
        rows (the path at normalized times 0 and 1) and applied to every row at
        its normalized time ``tq``.
        """
        if start is None and goal is None:
            return X
        n = X.shape[0] if n_dense is None else n_dense
        ramp = fade_ramp(tq)
        X = X.copy()
        for cond, fade, row in ((start, 1.0 - ramp, 0), (goal, ramp, n - 1)):
            for g, v in (cond or {}).items():
                cols = self._cols(g)
                X[:, cols] += (v - X[row, cols])[None, :] * fade[:, None]
                X[row, cols] = v  # exact, not up to the rounding of the sum
        return X

    def _renormalize(self, X: np.ndarray) -> np.ndarray:
        cols = self._quat_cols()
        if cols is None:
            return X
        X = X.copy()
        X[:, cols] = normalize_quaternions(X[:, cols], zero="identity")
        return X

    def _load_training(self, arrays, path) -> None:
        from ._errors import ModelFormatError

        counts = np.asarray(arrays["train_counts"], np.int64)
        if counts.shape != (self.n_demos_,) or np.any(counts < 1):
            raise ModelFormatError(f"{path}: train_counts do not match the key points")
        values = _split_rows(arrays, "train_values", counts, len(self.columns_), path)
        tau = _split_rows(arrays, "train_tau", counts, None, path)
        for k, n in zip(self.keypoints_, counts, strict=True):
            if k.size == 0 or k.min() < 0 or k.max() >= n:
                raise ModelFormatError(f"{path}: key points out of range")
        self._fit_segments(values, tau)  # tau is already normalized: unchanged

    # --------------------------------------------------------------- save/load
    def save(self, path: str | os.PathLike) -> None:
        """Save the fitted learner (``.npz`` + JSON metadata, never pickle).

        Parameters
        ----------
        path : str or path-like
            Destination file (conventionally ``*.ndlfd``).
        """
        self._check_fitted()
        arrays = {
            "scaler_min": self.scaler_.data_min_,
            "scaler_max": self.scaler_.data_max_,
            "levels": self.codebook_.levels,
            "keypoints": np.concatenate(self.keypoints_),
            "keypoint_counts": self.n_keypoints_,
            "symbols_seen": self.symbols_seen_,
            "train_values": np.concatenate(self.train_values_),
            "train_tau": np.concatenate(self.train_tau_),
            "train_counts": np.array([u.shape[0] for u in self.train_values_]),
        }
        arrays.update(self.model_.to_arrays(prefix="hmm_"))
        params = self.get_params()
        params["groups"] = list(self.groups_)
        meta = {
            "params": _jsonable(params),
            "columns": list(self.columns_),
            "column_groups": list(self.column_groups_),
            "n_states_used": self.n_states_used_,
            "n_clipped": self.n_clipped_,
        }
        save_npz(
            path, arrays, kind=_FORMAT_KIND, version=_FORMAT_VERSION, metadata=meta
        )

    @classmethod
    def load(cls, path: str | os.PathLike) -> KeypointHMM:
        """Load a learner written by :meth:`save`.

        Parameters
        ----------
        path : str or path-like
            The file.

        Returns
        -------
        model : KeypointHMM
        """
        from ._errors import ModelFormatError

        arrays, meta = load_npz(path, kind=_FORMAT_KIND, version=(1, _FORMAT_VERSION))
        try:
            params = dict(meta["params"])
            if meta["version"] == 1:  # written before the blended generation
                params.update(generation="paper", decoder="viterbi")
            columns = tuple(meta["columns"])
            col_groups = tuple(meta["column_groups"])
            if isinstance(params.get("groups"), list):
                params["groups"] = tuple(params["groups"])
            self = cls(**params)
            self._check_params()
            d = len(columns)
            mins = np.asarray(arrays["scaler_min"], np.float64)
            maxs = np.asarray(arrays["scaler_max"], np.float64)
            levels = np.asarray(arrays["levels"])
            counts = np.asarray(arrays["keypoint_counts"], np.int64)
            flat = np.asarray(arrays["keypoints"], np.int64)
            seen = np.asarray(arrays["symbols_seen"], bool)
            if (
                len(col_groups) != d
                or mins.shape != (d,)
                or maxs.shape != (d,)
                or levels.shape != (d,)
                or counts.sum() != flat.size
                or seen.shape != (self.n_time_bins,)
                or not (np.all(np.isfinite(mins)) and np.all(np.isfinite(maxs)))
            ):
                raise ModelFormatError(
                    f"{path}: inconsistent KeypointHMM arrays (tampered file?)"
                )
            self.columns_ = columns
            self.column_groups_ = col_groups
            self.groups_ = tuple(params["groups"])
            self.scaler_ = GroupScaler.from_ranges(
                mins,
                maxs,
                col_groups,
                columns=columns,
                mode=self.normalization,
                weights=self.weights,
            )
            self.codebook_ = Codebook([int(x) for x in levels])
            self.time_bins_ = TimeBins(self.n_time_bins)
            self.model_ = hmm.DiscreteHMM.from_arrays(arrays, prefix="hmm_")
            if (
                self.model_.n_states != self.codebook_.n_states
                or self.model_.n_symbols != self.n_time_bins
            ):
                raise ModelFormatError(
                    f"{path}: the HMM does not match the codebook (tampered file?)"
                )
            self.keypoints_ = np.split(flat, np.cumsum(counts)[:-1])
            self.n_keypoints_ = counts
            self.n_states_used_ = int(meta["n_states_used"])
            self.n_clipped_ = int(meta["n_clipped"])
            self.n_demos_ = int(counts.size)
            self.symbols_seen_ = seen
            if meta["version"] >= 2:
                self._load_training(arrays, path)
        except ModelFormatError:
            raise
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelFormatError(
                f"{path}: not a valid KeypointHMM file ({type(exc).__name__}: {exc})"
            ) from None
        return self


#: Demonstrations whose start/goal weight falls below this fraction of the
#: largest are left out of the conditioned skeleton and blend.
_KEEP_WEIGHT = 0.1

#: Generations: ``KeypointHMM`` methods ``(self, times_or_demo, dense, start,
#: goal, return_std)``.
GENERATIONS = Registry("generation")

#: Samples of a demonstration the skeleton is matched to (evenly spread, ends
#: included). On held-out LASA (1,000 samples) 128, 250, 500 and all gave the
#: same DTW medians to 0.1 %; the cost is linear in it.
_ALIGN_CANDIDATES = 256
GENERATIONS.add("blend", KeypointHMM._generate_blend)
GENERATIONS.add("paper", KeypointHMM._generate_paper)


def _split_rows(arrays, key, counts, width, path):
    from ._errors import ModelFormatError

    a = np.asarray(arrays[key], np.float64)
    shape = (int(counts.sum()),) + (() if width is None else (width,))
    if a.shape != shape or not np.all(np.isfinite(a)):
        raise ModelFormatError(
            f"{path}: {key} has shape {a.shape}, expected {shape} with finite"
            " values (tampered file?)"
        )
    return np.split(a, np.cumsum(counts)[:-1])


_PARAM_NAMES = (
    "groups",
    "levels",
    "epsilon",
    "n_time_bins",
    "n_points",
    "distance",
    "normalization",
    "weights",
    "pseudo_transition",
    "pseudo_emission",
    "start",
    "generation",
    "decoder",
    "derive_velocity",
    "n_jobs",
    "random_state",
)


def _same(a, b) -> bool:
    try:
        return bool(a == b)
    except (ValueError, TypeError):
        return a is b


def _jsonable(params: dict) -> dict:
    out = {}
    for k, v in params.items():
        if isinstance(v, np.generic):
            v = v.item()
        if isinstance(v, Mapping):
            v = {
                str(kk): (vv.item() if isinstance(vv, np.generic) else vv)
                for kk, vv in v.items()
            }
        if k == "random_state" and not (v is None or isinstance(v, int)):
            v = None  # a Generator is not stored; generation is deterministic
        out[k] = v
    return out
