"""KeypointHMM: the whole method as one scikit-learn style estimator.

It composes the stages and holds no algorithm of its own::

    demos → GroupScaler → simplify (key points) → Codebook + TimeBins → hmm.estimate
    new timing → TimeBins → hmm.viterbi → Codebook.decode → inverse_transform
"""

from __future__ import annotations

import itertools
import numbers
import os
from collections.abc import Mapping, Sequence

import numpy as np

from . import _fitmap, hmm
from ._blend import (
    MATCH_WINDOW,
    align_many,
    blend,
    condition_bandwidth,
    condition_log_weights,
    minimum_jerk,
    pin_offset,
    segment_states,
    skeleton_times,
)
from ._errors import (
    DecodeError,
    NotFittedError,
    ValidationError,
)
from ._fileformat import load_npz, save_npz
from ._fitstats import FitStats, RangeStats, scale_exponents, seed_word
from ._parallel import keep_workers
from ._registry import Registry
from ._simplify import DISTANCES, simplify
from ._validation import (
    check_nonnegative_scalar,
    check_positive_int,
    check_times,
)
from .codebook import Codebook, TimeBins
from .demonstration import Demonstration, unit_time, with_velocity
from .normalize import SCALING_MODES, GroupScaler, _group_ranges
from .orientation import normalize_quaternions

__all__ = ["AUTO_GROUPS", "DEFAULT_LEVELS", "FitStats", "KeypointHMM"]

#: The groups ``groups="auto"`` learns when a demonstration has them, in this
#: order (velocity also when it can be derived from position).
AUTO_GROUPS = ("position", "velocity", "orientation", "force")

#: Codebook levels per physical group when ``levels`` does not name the group
#: (the paper's 20 for position and 10 for velocity).
DEFAULT_LEVELS = {"position": 20, "velocity": 10, "orientation": 10, "force": 10}

_FORMAT_KIND = "KeypointHMM"
#: Version 2 added the normalized training values the blended generation needs
#: (version-1 files still load and generate with ``generation="paper"``).
#: Version 3 stores the fit statistics (:class:`~ndlfd._fitstats.FitStats`):
#: every demonstration's key points, states, bins and first/last samples, the
#: exact centroid sums, and the full values of the blend templates only.
#: Version 4 adds the parameter ``match_window``; older files load with 0
#: (raw matching). Versions 1 to 3 still load and generate as before.
_FORMAT_VERSION = 4

#: The scaler's range modes under the learner's parameter name (the errors
#: then say "normalization").
NORMALIZATIONS = Registry("normalization")
for _name in SCALING_MODES:
    NORMALIZATIONS.add(_name, SCALING_MODES.get(_name))
#: Start modes of the decoders: the HMM's own registry.
STARTS = hmm.STARTS


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


#: Sequences per ``hmm.estimate`` call when counting many demonstrations.
_ESTIMATE_BATCH = 4096


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
        Workers for the per-demonstration work of :meth:`fit` (read, prepare,
        normalize, reduce, encode, count) and threads for aligning the
        templates in generation. In fit, long demonstrations (5,000 samples or
        more on average) go to threads, as the kernels release the GIL; the
        work of shorter ones is mostly Python, so they go to worker processes
        (a persistent pool: ``fork`` on Linux before Python 3.12, ``spawn``
        otherwise, which imports the caller's main module: guard a script
        with ``if __name__ == "__main__":``). ``None``: one per CPU, except
        that fewer than 256 short demonstrations are fitted in the calling
        thread. The model does not depend on it. Ignored by :meth:`fit` with
        a Dask ``client``.
    max_templates : int or None, default=200
        How many training demonstrations are kept whole as templates of the
        blended generation (the path is their aligned, weighted average). The
        counts, centroids, conditioning weights and segment model always use
        every demonstration; only the full values, which cannot be kept for
        100,000 demonstrations, are limited. With at most ``max_templates``
        demonstrations all are templates. ``None`` keeps all.
    match_window : float, default=0.05
        The blended generation matches each decoded key point to a sample of
        every template's moving average over this fraction of its samples on
        each side (0: raw samples), so that noisy samples are not matched for
        their noise, which makes the path spike towards the key points (see
        :mod:`ndlfd._blend`). Between 0 and 0.5. Models saved before it
        existed (format 3 and older) load with 0, and generate as they did.
    random_state : None, int or Generator, default=None
        Chooses the templates when there are more than ``max_templates``
        demonstrations: those whose key ``splitmix64(s + (i + 1) *
        0x9E3779B97F4A7C15)`` (``i`` the demonstration's index, ``s`` a 64-bit
        word drawn from ``random_state`` by :class:`numpy.random.SeedSequence`)
        are among the ``max_templates`` smallest. The choice depends on the
        index only, so serial, threaded and Dask fits agree. ``None`` (like
        an int) gives the same templates every time: the word of
        ``SeedSequence(0)``, so the same demonstrations always give the same
        model and path; a Generator gives one draw. Nothing else is random.

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
    n_demos_ : int
        Number of training demonstrations.
    template_indices_ : ndarray of int
        Indices of the demonstrations kept as blend templates (sorted).
    first_values_, last_values_ : ndarray of shape (n_demos, n_columns)
        Each demonstration's first and last normalized sample (conditioning).
    fit_stats_ : FitStats
        The sufficient statistics the model was built from (see
        :class:`~ndlfd._fitstats.FitStats`); the attributes above are views of
        its arrays.
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
        max_templates=200,
        match_window=MATCH_WINDOW,
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
        self.max_templates = max_templates
        self.match_window = match_window
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
        if self.n_jobs is not None:
            check_positive_int(self.n_jobs, "n_jobs")
        if self.max_templates is not None:
            check_positive_int(self.max_templates, "max_templates")
        w = check_nonnegative_scalar(self.match_window, "match_window")
        if w > 0.5:
            raise ValidationError(
                f"match_window must be between 0 and 0.5; got {self.match_window!r}"
            )
        if not (
            self.random_state is None
            or isinstance(
                self.random_state, (np.random.Generator, np.random.RandomState)
            )
        ):
            seed_word(self.random_state)  # checks an int (cheap)

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

    def _prepare(
        self, demo: Demonstration, groups: Sequence[str], cli: bool = False
    ) -> Demonstration:
        if (
            "velocity" in groups
            and "velocity" not in demo.group_names
            and "position" in demo.group_names
            and self.derive_velocity
        ):
            demo = with_velocity(demo)
        missing = [g for g in groups if g not in demo.group_names]
        if missing:
            hint = (
                f"; map its columns with --group {missing[0]}=NAME,... or leave it"
                " out of --groups"
                if cli
                else ""
            )
            raise ValidationError(
                f"a demonstration lacks group(s) {', '.join(missing)}; it has"
                f" {', '.join(demo.group_names)}{hint}"
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

    # --------------------------------------------------------------------- fit
    def fit(self, demos, y=None, *, client=None, progress=None) -> KeypointHMM:
        """Learn the key points, codebook states and HMM from demonstrations.

        The fit is a map over the demonstrations and an exact reduce, in two
        passes (see :mod:`ndlfd._fitstats`): their per-column ranges (the
        scaler), then per demonstration its key points, codebook states, time
        bins, centroid sums and first/last samples, and its full values only
        if it is a blend template (see ``max_templates``). Only these
        statistics are kept, never all demonstrations at once (unless the
        caller's list holds them), and the model is the same bit for bit
        serially, on threads or processes (``n_jobs``) or on Dask
        (``client``).

        Parameters
        ----------
        demos : Demonstration, iterable of Demonstration, or sequence of paths
            The training demonstrations (lengths may differ): a list, or any
            *re-iterable* (an object whose ``__iter__`` starts over each
            time, e.g. one that reads files lazily), iterated exactly twice.
            File paths are read with :func:`ndlfd.io.read_demos` (a file may
            hold several demonstrations) in each pass, on the workers;
            :class:`ndlfd.io.DemoFiles` does so with a column mapping. A
            one-shot iterator such as a generator is refused: two passes are
            needed.
        y : None
            Ignored.
        client : distributed.Client or True, optional
            Run both passes as Dask tasks over chunks of the demonstrations,
            merged on the workers by a tree reduction; ``True`` uses the
            running default client. Needs ``pip install "ndlfd[dask]"``. Give
            paths for data that should be read on the workers. An error in a
            task (a bad demonstration or file) is raised here, naming it.
        progress : bool or None, default=None
            Progress bars of the two passes on standard error: ``True``
            always, ``False`` never, ``None`` on a terminal when a pass takes
            over a second.

        Returns
        -------
        self : KeypointHMM

        Raises
        ------
        ValidationError
            Bad parameters or demonstrations (the message names
            ``demos[i]``), or a one-shot iterator.
        DataFileError
            A file that cannot be read.
        MissingExtraError
            ``client`` without Dask installed.
        ParallelError
            A worker process died (killed, out of memory, or an unguarded
            script under ``spawn``).

        Examples
        --------
        A re-iterable that makes its demonstrations on demand:

        >>> from ndlfd import synth
        >>> class Lazy:
        ...     def __iter__(self):
        ...         for seed in range(12):
        ...             yield synth.make_dataset("square", n_demos=1,
        ...                                      random_state=seed)[0][0]
        >>> model = KeypointHMM(epsilon=0.1, n_time_bins=20, max_templates=5,
        ...                     random_state=0).fit(Lazy())
        >>> model.n_demos_, model.template_indices_.size
        (12, 5)
        """
        self._check_params()
        if self.weights is not None and not isinstance(self.weights, Mapping):
            raise ValidationError(
                f"weights must be a mapping of group to weight; got {self.weights!r}"
            )
        with keep_workers():  # one pool for both passes, ended after them
            spec, stats = _fitmap.count(
                self, _fitmap.scan(self, demos, client=client, progress=progress)
            )
        self._set_from_spec(spec, stats)
        return self

    def _set_from_spec(self, spec, stats: FitStats) -> None:
        """The learned attributes of a fit: its groups, stages and statistics."""
        self.columns_ = tuple(spec.columns)
        self.column_groups_ = tuple(spec.col_groups)
        self.groups_ = spec.groups
        self.scaler_ = spec.scaler
        self.codebook_ = spec.codebook
        self.time_bins_ = spec.time_bins
        self._set_from_stats(stats)

    def _scaler_from_ranges(self, ranges: RangeStats, columns, col_groups):
        """Exactly ``GroupScaler(mode, weights).fit(prepared demos)``."""
        mins, maxs = ranges.data_min, ranges.data_max
        lo, hi = NORMALIZATIONS.get(self.normalization)(mins, maxs, col_groups)
        scaler = GroupScaler.from_ranges(
            lo,
            hi,
            col_groups,
            columns=columns,
            mode=self.normalization,
            weights=self.weights,
        )
        # as fit sets them: the data's group extremes and sample count
        gmin, gmax = _group_ranges(mins, maxs, col_groups)
        names = scaler.group_names_
        scaler.group_min_ = {g: float(gmin[col_groups.index(g)]) for g in names}
        scaler.group_max_ = {g: float(gmax[col_groups.index(g)]) for g in names}
        scaler.n_samples_seen_ = ranges.n_samples
        return scaler

    def _set_from_stats(self, stats: FitStats) -> None:
        """Every learned attribute from the fit statistics (fit and load)."""
        keypoints, key_states, key_bins = stats.keypoint_lists()
        nt = self.n_time_bins
        self.model_ = self._estimate(key_states, key_bins)
        self.keypoints_ = keypoints
        self.n_keypoints_ = stats.n_keys
        self.n_states_used_ = int(self.model_.states_.size)
        self.n_clipped_ = int(stats.n_clipped)
        self.n_demos_ = stats.n_demos
        seen = np.zeros(nt, dtype=bool)
        seen[stats.key_bins] = True
        self.symbols_seen_ = seen
        # the blended generation (see ndlfd._blend)
        self._key_states = key_states
        self._key_bins = key_bins
        self.first_values_ = stats.first
        self.last_values_ = stats.last
        self.template_indices_ = stats.template_index
        self.train_values_, self.train_tau_ = stats.templates()
        self.centroid_states_, self.centroids_ = stats.centroids()
        self.segment_model_ = self._segment_model(np.arange(stats.n_demos))
        self.fit_stats_ = stats
        self._widths = {}  # conditioning kernel widths, computed when first asked

    def _segment_model(self, demos: np.ndarray) -> hmm.DiscreteHMM:
        nt = self.n_time_bins
        return self._estimate(
            (segment_states(self._key_bins[j], self._key_states[j], nt) for j in demos),
            itertools.repeat(np.arange(nt), len(demos)),
        )

    def _estimate(self, states, symbols) -> hmm.DiscreteHMM:
        """``hmm.estimate`` on batches of sequences, merged (the same counts).

        Batches keep the temporary memory of counting 100,000 demonstrations
        small; :func:`ndlfd.hmm.merge` adds the counts exactly.
        """
        states, symbols = iter(states), iter(symbols)
        models = []
        while True:
            s = list(itertools.islice(states, _ESTIMATE_BATCH))
            if not s:
                break
            models.append(
                hmm.estimate(
                    s,
                    list(itertools.islice(symbols, len(s))),
                    self.codebook_.n_states,
                    self.n_time_bins,
                    pseudo_transition=self.pseudo_transition,
                    pseudo_emission=self.pseudo_emission,
                )
            )
        return models[0] if len(models) == 1 else hmm.merge(models)

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
        at = np.concatenate([tq, key_tau])  # the dense rows, then the key rows
        U = blend(
            plan["values"],
            plan["taus"],
            plan["index"],
            plan["weights"],
            at,
            quat_cols=self._quat_cols(),
        )[0]
        X = self._renormalize(self.scaler_.inverse_transform(U))
        X = self._pin(X, at, start, goal, tq.size)
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
            cols = self._cols(g)
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

    def _log_weights_for(self, cond, end: int) -> np.ndarray:
        """Every demonstration's log weight for a start (``end=0``) or goal (-1)."""
        if cond is None:
            return np.zeros(self.n_demos_)
        cols = [c for g in cond for c in self._cols(g)]
        target = self.scaler_.transform(
            self._physical_row(cond)[None, :], weighted=False
        )[0, cols]
        pts = (self.first_values_ if end == 0 else self.last_values_)[:, cols]
        # the kernel width depends on the training points only: once per model
        key = (end, tuple(cols))
        if key not in self._widths:  # reset by every fit and load
            self._widths[key] = condition_bandwidth(pts)
        return condition_log_weights(pts, target, self._widths[key])

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
        # the skeleton: from the statistics of every demonstration that carries
        # weight; the blend: from the templates among them
        logw = self._log_weights_for(start, 0) + self._log_weights_for(goal, -1)
        # normalized in log space over each set: however far the start, the
        # nearest demonstration and the nearest template weigh 1
        w = np.exp(logw - logw.max())
        demos = np.flatnonzero(w >= _KEEP_WEIGHT)
        model = (
            self.segment_model_ if demos.size == w.size else self._segment_model(demos)
        )
        tlogw = logw[self.template_indices_]
        tw = np.exp(tlogw - tlogw.max())
        templates = np.flatnonzero(tw >= _KEEP_WEIGHT)
        states, logp = self._run_decoder(model, np.arange(self.n_time_bins))
        change = np.flatnonzero(np.r_[True, states[1:] != states[:-1]])
        skel = states[change]
        if skel.size == 1:
            skel = np.repeat(skel, 2)  # a start and an end in one state
        C = self.centroids_[np.searchsorted(self.centroid_states_, skel)]
        values = [self.train_values_[j] for j in templates]
        taus = [self.train_tau_[j] for j in templates]
        window = float(self.match_window)
        index = align_many(values, C, self.n_jobs, _ALIGN_CANDIDATES, window)
        key_tau = skeleton_times(taus, index, tw[templates])
        # every alignment pins the ends to samples at tau 0 and 1: exact ends
        key_tau[0], key_tau[-1] = 0.0, 1.0
        return {
            "states": skel,
            "logp": logp,
            "values": values,
            "taus": taus,
            "weights": tw[templates],
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
            tq = unit_time(np.r_[all_t[0], key_t, all_t[-1]])[1:-1]
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
        ramp = minimum_jerk(tq)
        X = X.copy()
        for cond, fade, row in ((start, 1.0 - ramp, 0), (goal, ramp, n - 1)):
            for g, v in (cond or {}).items():
                pin_offset(X, fade, row, v, self._cols(g))
        return X

    def _renormalize(self, X: np.ndarray) -> np.ndarray:
        cols = self._quat_cols()
        if cols is None:
            return X
        X = X.copy()
        X[:, cols] = normalize_quaternions(X[:, cols], zero="identity")
        return X

    def _stats_from_v2(self, arrays, path) -> FitStats:
        """Fit statistics of a format-2 file (every demonstration kept whole)."""
        from ._errors import ModelFormatError

        counts = np.asarray(arrays["train_counts"], np.int64)
        if counts.shape != (self.n_demos_,) or np.any(counts < 1):
            raise ModelFormatError(f"{path}: train_counts do not match the key points")
        values = _split_rows(arrays, "train_values", counts, len(self.columns_), path)
        tau = _split_rows(arrays, "train_tau", counts, None, path)
        for k, n in zip(self.keypoints_, counts, strict=True):
            if k.size == 0 or k.min() < 0 or k.max() >= n:
                raise ModelFormatError(f"{path}: key points out of range")
        exponents = scale_exponents(np.abs(np.concatenate(values)).max(axis=0))
        parts = []
        for j, (u, tq, idx) in enumerate(
            zip(values, tau, self.keypoints_, strict=True)
        ):
            states, clipped = self.codebook_.encode(u[idx], return_n_clipped=True)
            bins = self.time_bins_.transform(tq)[idx]  # tau is already normalized
            parts.append(
                FitStats.of_demo(
                    j, u, tq, idx, states, bins,
                    exponents=exponents, n_clipped=clipped, template=True,
                )
            )  # fmt: skip
        return parts[0].merge(*parts[1:])

    # --------------------------------------------------------------- save/load
    def save(self, path: str | os.PathLike) -> None:
        """Save the fitted learner (``.npz`` + JSON metadata, never pickle).

        Format version 4: the scaler's ranges, the codebook levels and the fit
        statistics (:meth:`FitStats.to_arrays`, keys ``stats_*``); loading
        rebuilds the HMMs and centroids from them exactly. A model loaded from
        a version-1 file is written as version 1.

        Parameters
        ----------
        path : str or path-like
            Destination (conventionally ``*.ndlfd``).
        """
        self._check_fitted()
        arrays = {
            "scaler_min": self.scaler_.data_min_,
            "scaler_max": self.scaler_.data_max_,
            "levels": self.codebook_.levels,
        }
        if hasattr(self, "fit_stats_"):
            version = _FORMAT_VERSION
            arrays.update(self.fit_stats_.to_arrays(prefix="stats_"))
        else:  # loaded from a version-1 file: no statistics to write
            version = 1
            arrays.update(
                keypoints=np.concatenate(self.keypoints_),
                keypoint_counts=self.n_keypoints_,
                symbols_seen=self.symbols_seen_,
            )
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
        save_npz(path, arrays, kind=_FORMAT_KIND, version=version, metadata=meta)

    @classmethod
    def load(cls, path: str | os.PathLike) -> KeypointHMM:
        """Load a learner written by :meth:`save` (format versions 1 to 4).

        Parameters
        ----------
        path : str or path-like
            The file.

        Returns
        -------
        model : KeypointHMM
        """
        from ._errors import ModelFormatError

        arrays, meta = load_npz(
            path, kind=_FORMAT_KIND, version=tuple(range(1, _FORMAT_VERSION + 1))
        )
        try:
            version = meta["version"]
            params = dict(meta["params"])
            if version == 1:  # written before the blended generation
                params.update(generation="paper", decoder="viterbi")
            if version < 3:  # every demonstration was kept whole
                params.update(max_templates=None)
            if version < 4:  # matched raw samples
                params.update(match_window=0.0)
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
            if (
                len(col_groups) != d
                or mins.shape != (d,)
                or maxs.shape != (d,)
                or levels.shape != (d,)
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
            if version >= 3:
                stats = FitStats.from_arrays(arrays, prefix="stats_")
                if stats.n_dims != d:
                    raise ModelFormatError(
                        f"{path}: the fit statistics have {stats.n_dims} columns,"
                        f" the model {d} (tampered file?)"
                    )
            else:
                self._load_v1_arrays(arrays, path)
                stats = self._stats_from_v2(arrays, path) if version == 2 else None
            if stats is not None:
                self._set_from_stats(stats)
            self.n_states_used_ = int(meta["n_states_used"])
            self.n_clipped_ = int(meta["n_clipped"])
        except ModelFormatError:
            raise
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelFormatError(
                f"{path}: not a valid KeypointHMM file ({type(exc).__name__}: {exc})"
            ) from None
        return self

    def _load_v1_arrays(self, arrays, path) -> None:
        """The key points and the HMM as format versions 1 and 2 store them."""
        from ._errors import ModelFormatError

        counts = np.asarray(arrays["keypoint_counts"], np.int64)
        flat = np.asarray(arrays["keypoints"], np.int64)
        seen = np.asarray(arrays["symbols_seen"], bool)
        if counts.sum() != flat.size or seen.shape != (self.n_time_bins,):
            raise ModelFormatError(
                f"{path}: inconsistent KeypointHMM arrays (tampered file?)"
            )
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
        self.n_demos_ = int(counts.size)
        self.symbols_seen_ = seen


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
    "max_templates",
    "match_window",
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
