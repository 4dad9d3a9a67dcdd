"""KeypointHMM: the whole method as one scikit-learn style estimator.

It composes the stages, each in its own module of :mod:`ndlfd.learner`::

    demos → _passes (GroupScaler → simplify → Codebook + TimeBins) → FitStats
          → _segments (hmm.estimate) → model
    new timing → _generation (decode, align, blend, condition) → path

and holds the parameters, the learned attributes and the entry points.
"""

from __future__ import annotations

import os
from functools import partial

import numpy as np

from .._parallel import keep_workers
from ..limits import limited
from ._blend import MATCH_WINDOW
from ._cache import ModelCache
from ._conditioning import check_condition
from ._frames import check_frame_hands, check_learned_frames, split_frames
from ._generation import GENERATIONS, decode_key_points, observations
from ._params import ParamsMixin, check_fitted, check_params
from ._passes import collect_statistics, scan_ranges
from ._persist import load_model, model_file_errors, save_model
from ._routes import model_routes
from ._sampling import sample_paths
from ._segments import learned_from_stats
from ._spec import DemoSpec
from ._stats import FitStats

__all__ = ["KeypointHMM"]


class KeypointHMM(ParamsMixin):
    r"""Learn a path from demonstrations and generate it for a new timing.

    Parameters
    ----------
    groups : "auto", sequence of str or None, default="auto"
        The physical groups to learn from, in this order. ``"auto"`` learns
        every group of the first demonstration, those of :data:`AUTO_GROUPS`
        (position, velocity, orientation, force, gripper) first, then the
        others (joints, ...) in its order, so none is dropped in silence;
        ``None`` every group of the first demonstration as it is. A missing
        ``"velocity"`` is derived from position when ``derive_velocity``.
    levels : int or mapping of str to int, optional
        Codebook levels per group (one int for all groups). Groups not named
        fall back to :data:`DEFAULT_LEVELS` (20 for position and joints, 2
        for a gripper, 10 for the others), any other group to
        :data:`OTHER_LEVELS` (10).
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
        ``"blend"`` aligns the demonstrations to the decoded key points and
        blends them (their shape, conditioning, a band); ``"paper"`` is the
        paper's procedure, cell centres and straight lines (both in
        :mod:`ndlfd.learner._generation`).
    decoder : {"viterbi", "map"}, default="viterbi"
        ``"viterbi"``: the most likely state sequence; ``"map"``: the most
        likely state at each step (posterior argmax, :func:`ndlfd.hmm.posterior`).
    derive_velocity : bool, default=True
        Derive a missing velocity group from position and time.
    n_jobs : int, optional
        Workers of :meth:`fit` (threads or processes, ended when it returns:
        :mod:`ndlfd.learner._passes`) and threads aligning templates in
        generation. ``None``: one per CPU. The model does not depend on it.
    max_templates : int or None, default=200
        How many demonstrations are kept whole as templates of the blend
        (``None``: all). Everything else of the model uses every
        demonstration.
    match_window : float, default=0.05
        The blend matches each decoded key point on every template's moving
        average over this fraction of its samples on each side (0: raw
        samples, which spike towards the key points on noisy data; see
        :mod:`ndlfd.learner._blend`). Between 0 and 0.5.
    n_routes : int, optional
        How many routes the demonstrations take; by default found
        (:mod:`ndlfd.learner._routes`: gaps on the route groups).
    route_groups : list of str, optional
        The groups routes are judged on; by default every hand's position,
        else every group but velocity, orientation, force and gripper.
    frame_hands : mapping of str to list of str, optional
        Which hands each task frame may move (``{"socket": ["left"]}``: a hand
        by its name, ``position`` the unnamed one); by default any, each phase
        as the demonstrations agree (:mod:`ndlfd.learner._frames`).
    random_state : None, int or Generator, default=None
        Chooses the templates when there are more than ``max_templates``
        demonstrations (:mod:`ndlfd.learner._templates`); ``None`` is seed 0.
        Nothing else of a fit is random.

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
    n_states_used_, n_demos_ : int
        Distinct codebook states seen in training; training demonstrations.
    template_indices_ : ndarray of int
        Indices of the demonstrations kept as blend templates (sorted).
    first_values_, last_values_ : ndarray of shape (n_demos, n_columns)
        Each demonstration's first and last normalized sample (conditioning).
    fit_stats_ : FitStats
        The statistics the model was built from (the attributes above view it).
    n_clipped_ : int
        Values clipped by the codebook while fitting.
    routes_ : ndarray of shape (n_demos,), dtype int64
        Each demonstration's route, numbered from 0 by first demonstration.
    task_frames_ : dict of str to ndarray of shape (n_demos, pose_size)
        Each task frame's pose in every demonstration (empty without frames).

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
        n_routes=None,
        route_groups=None,
        frame_hands=None,
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
        self.n_routes = n_routes
        self.route_groups = route_groups
        self.frame_hands = frame_hands
        self.random_state = random_state

    # --------------------------------------------------------------------- fit
    def fit(
        self, demos, y=None, *, client=None, progress=None, after_scan=None
    ) -> KeypointHMM:
        """Learn the key points, codebook states and HMM from demonstrations.

        Two passes, each a map over the demonstrations and an exact reduce:
        the model is the same bit for bit however they run
        (:mod:`ndlfd.learner._passes`).

        Parameters
        ----------
        demos : Demonstration, iterable of Demonstration, or sequence of paths
            The training demonstrations (lengths may differ): a list or a
            *re-iterable* (a generator is refused), iterated exactly twice;
            paths are read on the workers (:class:`ndlfd.io.DemoFiles`).
        y : None
            Ignored.
        client : distributed.Client or True, optional
            Run both passes as Dask tasks, merged on the workers; ``True``:
            the running default client. Needs ``pip install "ndlfd[dask]"``.
        progress : bool or None, default=None
            Progress bars of the two passes on standard error: ``True``
            always, ``False`` never, ``None`` on a terminal when a pass takes
            over a second.
        after_scan : callable, optional
            ``after_scan(ranges) -> dict or None`` between the passes, given a
            :class:`~ndlfd.learner.RangeStats`; a dict sets ``n_time_bins``,
            ``epsilon`` or ``n_points`` for the second (as ``ndlfd fit`` does).

        Returns
        -------
        self : KeypointHMM

        Raises
        ------
        ValidationError, DataFileError, MissingExtraError, ParallelError
            Bad parameters or demonstrations (or a one-shot iterator), a file
            that cannot be read, ``client`` without Dask, a dead worker.
        """
        check_params(self.get_params())
        with keep_workers():  # one pool for both passes, ended after them
            scanned = scan_ranges(
                self.get_params(), demos, client=client, progress=progress
            )
            changes = after_scan(scanned.ranges) if after_scan is not None else None
            if changes:
                self.set_params(**changes)
                check_params(self.get_params())
            spec, stats = collect_statistics(self.get_params(), scanned)
        _set_fitted(self, spec, stats)
        return self

    # ---------------------------------------------------------------- generate
    def timing(self, times_or_demo) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Observation times and symbols for a new execution.

        A :class:`Demonstration` gives its key points' times (the paper's
        procedure); a time vector one per emittable time bin it touches.

        Parameters
        ----------
        times_or_demo : Demonstration or array-like of shape (n_samples,)
            The new execution or its time stamps.

        Returns
        -------
        key_times, symbols : ndarray of shape (n_obs,)
            Time and time symbol (int64) of each observation.
        all_times : ndarray of shape (n_samples,)
            Every time stamp of the new execution (for dense generation).
        """
        check_fitted(self)
        return observations(self, times_or_demo)

    def decode(self, times_or_demo) -> tuple[np.ndarray, np.ndarray, float]:
        """Decoded key points of a new timing: their times and codebook states.

        ``"blend"`` decodes every time bin with the segment model (a key point
        where the state changes); ``"paper"`` the observations of :meth:`timing`.

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
        check_fitted(self)
        return decode_key_points(self, times_or_demo, self._cache)

    def generate(self, times_or_demo, *, dense: bool = False, start=None, goal=None,
                 return_std: bool = False, via=None, observed=None, limits=None,
                 frames=None):  # fmt: skip
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
            ``{"position": [x, y]}``: the demonstrations that start (end) near
            are followed, and the path begins (ends) exactly there
            (:mod:`ndlfd.learner._conditioning`; ``"paper"``: the offset only).
        return_std : bool, default=False
            Also return the band (blend): the weighted standard deviation of
            the templates the path blends, as aligned
            (:func:`~ndlfd.learner._blend.spread`).
        via, observed : list of (time, mapping) / Demonstration, optional
            Via points ``[(time, {group: values})]`` the path passes through;
            the samples executed so far, continued (blend: :mod:`~ndlfd.learner._via`;
            learned groups it lacks are the plan's, ``_via.complete_prefix``).
        limits : mapping, optional
            ``{group or column: {"velocity": v, "acceleration": a, "jerk": j}}``:
            the dense path slowed where it would exceed them (:mod:`ndlfd.limits`).
        frames : mapping of str to array-like, optional
            New poses of the task frames the demonstrations carried, e.g.
            ``{"object": [x, y, z, qw, qx, qy, qz]}``: each part of the motion
            follows the frame where the demonstrations agree most
            (:mod:`ndlfd.learner._frames`); no time is needed.

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
        check_fitted(self)
        start = check_condition(start, "start", self.column_groups_, self.groups_)
        goal = check_condition(goal, "goal", self.column_groups_, self.groups_)
        how = GENERATIONS.get(self.generation)
        out = how(self, times_or_demo, dense=dense, start=start, goal=goal,
                  return_std=return_std, cache=self._cache, via=via,
                  observed=observed, frames=frames)  # fmt: skip
        if limits is None:
            return out
        return limited(out, limits, dense, return_std, observed)

    def sample(self, times_or_demo, n_samples=1, *, dense=True, start=None, goal=None,
               via=None, observed=None, random_state=None, frames=None,
               limits=None) -> list:  # fmt: skip
        """Paths drawn from the model, each on one route (always blended).

        Routes in proportion to their weight, varying within a route about as
        the demonstrations do (:mod:`ndlfd.learner._sampling`).

        Parameters
        ----------
        times_or_demo, dense, start, goal, via, observed, frames, limits
            As in :meth:`generate` (``dense`` true by default; each path
            time-scaled to ``limits`` on its own).
        n_samples : int, default=1
        random_state : None, int or Generator, default=None
            The same seed and input give the same paths.

        Returns
        -------
        paths : list of Demonstration

        Examples
        --------
        >>> from ndlfd import synth
        >>> train, test = synth.make_dataset("square", n_demos=10, random_state=0)
        >>> model = KeypointHMM(epsilon=0.1, n_time_bins=20).fit(train)
        >>> paths = model.sample(test.t, 3, random_state=0)
        >>> len(paths), bool(np.all(paths[0].t == test.t))
        (3, True)
        """
        check_fitted(self)
        paths = sample_paths(self, times_or_demo, n_samples, dense=dense,
                            start=start, goal=goal, via=via, observed=observed,
                            random_state=random_state, cache=self._cache,
                            frames=frames)  # fmt: skip
        if limits is None:
            return paths
        return [limited(p, limits, dense, False, observed) for p in paths]

    # --------------------------------------------------------------- save/load
    def save(self, path: str | os.PathLike) -> None:
        """Save the fitted learner (``.npz`` + JSON metadata, never pickle).

        Format version 5, or 1 for a model loaded from a version-1 file.

        Parameters
        ----------
        path : str or path-like, conventionally ``*.ndlfd``
        """
        check_fitted(self)
        save_model(self, path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> KeypointHMM:
        """Load a learner written by :meth:`save` (format versions 1 to 5).

        Parameters
        ----------
        path : str or path-like

        Returns
        -------
        model : KeypointHMM
        """
        with model_file_errors(path):
            file = load_model(path, partial(_checked, cls))
            self = file.estimator
            _set_fitted(self, file.spec(tuple(self.groups)), file.stats)
            vars(self).update(file.v1)  # a version-1 file: key points and HMM
            self.n_states_used_ = file.n_states_used
            self.n_clipped_ = file.n_clipped
        return self


def _checked(cls, params: dict):
    """The estimator of a model file's parameters, checked."""
    check_params({**cls().get_params(), **params})
    return cls(**params)


def _set_fitted(est, spec: DemoSpec, stats: FitStats | None) -> None:
    """The learned attributes: the groups, the stages, the statistics, the routes."""
    est.columns_, est.column_groups_ = spec.columns, spec.col_groups
    est.groups_ = spec.groups
    est.scaler_, est.codebook_ = spec.scaler, spec.codebook
    est.time_bins_ = spec.time_bins
    est._cache = ModelCache()  # computed when first asked (never saved)
    if stats is not None:
        vars(est).update(
            learned_from_stats(
                stats,
                est.codebook_.n_states,
                est.n_time_bins,
                pseudo_transition=est.pseudo_transition,
                pseudo_emission=est.pseudo_emission,
            )
        )
        est.routes_ = model_routes(est, est._cache)
        est.task_frames_ = split_frames(stats.frames, spec.frames)
        check_learned_frames(est)
        check_frame_hands(est)
    else:
        est.task_frames_ = {}
