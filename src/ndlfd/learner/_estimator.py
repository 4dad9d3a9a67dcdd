"""KeypointHMM: the whole method as one scikit-learn style estimator.

It composes the stages, each in its own module of :mod:`ndlfd.learner`::

    demos → _passes (GroupScaler → simplify → Codebook + TimeBins) → FitStats
          → _segments (hmm.estimate) → model
    new timing → _generation (decode, align, blend, condition) → path

and holds the parameters, the learned attributes and the entry points.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from .._errors import NotFittedError, ValidationError
from .._parallel import keep_workers
from ._blend import MATCH_WINDOW
from ._conditioning import check_condition
from ._generation import GENERATIONS, decode_key_points, observations
from ._params import ParamsMixin, check_params
from ._passes import collect_statistics, scan_ranges
from ._persist import load_model, model_file_errors, save_model
from ._segments import learned_from_stats
from ._spec import DemoSpec
from ._stats import FitStats

__all__ = ["KeypointHMM"]


class KeypointHMM(ParamsMixin):
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
        :mod:`ndlfd.learner._blend`); it follows the demonstrations' shape, can be
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
        :mod:`ndlfd.learner._blend`). Between 0 and 0.5. Models saved before it
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
        :class:`~ndlfd.learner.FitStats`); the attributes above are views of
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

    def _check_fitted(self) -> None:
        if not hasattr(self, "model_"):
            raise NotFittedError(
                "this KeypointHMM is not fitted yet; call fit(demos) first"
            )

    # --------------------------------------------------------------------- fit
    def fit(
        self, demos, y=None, *, client=None, progress=None, after_scan=None
    ) -> KeypointHMM:
        """Learn the key points, codebook states and HMM from demonstrations.

        The fit is a map over the demonstrations and an exact reduce, in two
        passes (see :mod:`ndlfd.learner._stats`): their per-column ranges (the
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
        after_scan : callable, optional
            ``after_scan(ranges) -> dict or None``, called between the two
            passes with what the first found (a
            :class:`~ndlfd.learner.RangeStats`: per-column ranges, the number
            of demonstrations, the fewest and most samples, how files were
            read). A dict it returns is set as parameters before the second
            pass, which may change only those the first does not use
            (``n_time_bins``, ``epsilon``, ``n_points``); the command line's
            ``ndlfd fit`` reports the column mappings and bounds the time bins
            this way.

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
        check_params(self.get_params())
        if self.weights is not None and not isinstance(self.weights, Mapping):
            raise ValidationError(
                f"weights must be a mapping of group to weight; got {self.weights!r}"
            )
        with keep_workers():  # one pool for both passes, ended after them
            scanned = scan_ranges(
                self.get_params(), demos, client=client, progress=progress
            )
            changes = after_scan(scanned.ranges) if after_scan is not None else None
            if changes:
                self.set_params(**changes)
                check_params(self.get_params())
            spec, stats = collect_statistics(self.get_params(), scanned)
        self._set_fitted(spec, stats)
        return self

    def _set_fitted(self, spec: DemoSpec, stats: FitStats | None) -> None:
        """The learned attributes: the groups, the stages and the statistics."""
        self.columns_, self.column_groups_ = spec.columns, spec.col_groups
        self.groups_ = spec.groups
        self.scaler_, self.codebook_ = spec.scaler, spec.codebook
        self.time_bins_ = spec.time_bins
        self._widths = {}  # conditioning kernel widths, computed when first asked
        if stats is not None:
            vars(self).update(
                learned_from_stats(
                    stats,
                    self.codebook_.n_states,
                    self.n_time_bins,
                    pseudo_transition=self.pseudo_transition,
                    pseudo_emission=self.pseudo_emission,
                )
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
        return observations(self, times_or_demo)

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
        return decode_key_points(self, times_or_demo, self._widths)

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
        start = check_condition(start, "start", self.column_groups_, self.groups_)
        goal = check_condition(goal, "goal", self.column_groups_, self.groups_)
        how = GENERATIONS.get(self.generation)
        return how(self, times_or_demo, dense=dense, start=start, goal=goal,
                   return_std=return_std, cache=self._widths)  # fmt: skip

    # --------------------------------------------------------------- save/load
    def save(self, path: str | os.PathLike) -> None:
        """Save the fitted learner (``.npz`` + JSON metadata, never pickle).

        Format version 4 (:mod:`ndlfd.learner._persist`): the scaler's
        ranges, the codebook levels and the fit statistics
        (:meth:`FitStats.to_arrays`, keys ``stats_*``); loading rebuilds the
        HMMs and centroids from them exactly. A model loaded from a version-1
        file is written as version 1.

        Parameters
        ----------
        path : str or path-like
            Destination (conventionally ``*.ndlfd``).
        """
        self._check_fitted()
        save_model(self, path)

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

        def make(params):
            est = cls(**params)
            check_params(est.get_params())
            return est

        with model_file_errors(path):
            file = load_model(path, make)
            self = file.estimator
            spec = DemoSpec(
                groups=tuple(self.groups),
                columns=file.columns,
                col_groups=file.column_groups,
                scaler=file.scaler,
                codebook=file.codebook,
                time_bins=file.time_bins,
            )
            self._set_fitted(spec, file.stats)
            vars(self).update(file.v1)  # a version-1 file: key points and HMM
            self.n_states_used_ = file.n_states_used
            self.n_clipped_ = file.n_clipped
        return self
