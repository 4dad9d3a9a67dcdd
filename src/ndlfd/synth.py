"""Synthetic demonstrations reproducing the paper's data sets (SPEC §2).

:func:`obstacle` (not the paper's) makes demonstrations that take two routes
around an obstacle, the case ndlfd's routes are for; everything below is
about the paper's generators.

Every generator samples a clean analytic path at a constant rate (``t_k = k·dt``,
``k = 0..n_points-1``, default ``dt = 0.1`` s) and returns a
:class:`~ndlfd.demonstration.Demonstration` with a ``position`` and a ``velocity``
group.
The velocity is the analytic time derivative of the clean path at the sample
times; noise is added afterwards, independently to both groups.

**Speed.** A path is written as ``P(s)`` with a path parameter ``s`` in [0, 1].
With ``speed="constant"`` the parameter advances uniformly, ``s = τ`` with
``τ = t / t[-1]``. With ``speed="variable"`` the time is warped,
``s(τ) = τ + a·sin(2πkτ) / (2πk)`` with ``a = 0.5`` and ``k = 2``: the parameter
speed ``ds/dτ = 1 + a·cos(2πkτ)`` swings between 0.5 and 1.5 times its mean twice
over the path, the number of samples and the end points stay the same, and the
samples bunch up where the motion is slow.

**Noise model.** Noise is i.i.d. Gaussian, per sample and column, with standard
deviation ``noise × range`` where ``range`` is the *group's* range in the clean
path (one global max minus min over all the group's columns, the range group
normalization uses). ``noise_model="uniform"`` draws from
``U(-noise·range, +noise·range)`` instead. The velocity group gets
``velocity_noise`` (default ``0.6 × noise``, the paper's 5 % / 3 % ratio) of the
clean velocity's range. The paper does not state its noise model; this one is
ndlfd's explicit choice.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable

import numpy as np

from ._errors import ValidationError
from ._registry import Registry
from ._validation import (
    check_nonnegative_scalar,
    check_positive_int,
    check_random_state,
)
from .demonstration import Demonstration

__all__ = [
    "CURVE_SPEED_VARIATION",
    "NOISE_MODELS",
    "SHAPES",
    "SPEEDS",
    "VARIABLE_SPEED_AMPLITUDE",
    "VARIABLE_SPEED_CYCLES",
    "VELOCITY_NOISE_RATIO",
    "curve",
    "make_dataset",
    "obstacle",
    "pick_place",
    "spiral",
    "square",
    "square_spiral",
    "task_board",
]

#: ``a`` of the variable-speed warp ``s(τ) = τ + a·sin(2πkτ)/(2πk)``.
VARIABLE_SPEED_AMPLITUDE = 0.5
#: ``k`` of the variable-speed warp (number of slow/fast cycles over the path).
VARIABLE_SPEED_CYCLES = 2
#: ``(a, k)`` of :func:`curve`'s variable speed: a livelier speed profile (the
#: Fig. 3 curve is about variable velocity), so that at one tolerance velocity
#: alone gives more key points than position alone.
CURVE_SPEED_VARIATION = (0.7, 3)
#: Default ratio of velocity noise to position noise (paper: 3 % / 5 %).
VELOCITY_NOISE_RATIO = 0.6


def _constant(tau):
    return tau, np.ones_like(tau)


def _variable(tau, a=VARIABLE_SPEED_AMPLITUDE, k=VARIABLE_SPEED_CYCLES):
    w = 2 * np.pi * k
    return tau + a * np.sin(w * tau) / w, 1 + a * np.cos(w * tau)


#: ``speed`` → warp ``τ ↦ (s, ds/dτ)``.
SPEEDS: Registry[Callable] = Registry("speed")
SPEEDS.add("constant", _constant)
SPEEDS.add("variable", _variable)


def _gaussian(rng, size, scale):
    return rng.normal(scale=scale, size=size)


def _uniform(rng, size, scale):
    return rng.uniform(-scale, scale, size=size)


#: ``noise_model`` → sampler ``(rng, size, scale) -> noise``; ``scale`` is the
#: standard deviation (Gaussian) or the half-width (uniform).
NOISE_MODELS: Registry[Callable] = Registry("noise_model")
NOISE_MODELS.add("gaussian", _gaussian)
NOISE_MODELS.add("uniform", _uniform)


def _group_range(A: np.ndarray) -> float:
    return float(A.max() - A.min())


def _sample(
    path: Callable,
    n_points: int,
    *,
    speed: str,
    noise,
    velocity_noise,
    noise_model: str,
    dt,
    random_state,
    minimum: int = 2,
    variation: tuple[float, int] | None = None,
) -> Demonstration:
    warp = SPEEDS.get(speed)
    if variation is not None and speed == "variable":
        a, k = variation
        warp = functools.partial(_variable, a=a, k=k)
    draw = NOISE_MODELS.get(noise_model)
    n = check_positive_int(n_points, "n_points", minimum=minimum)
    noise = check_nonnegative_scalar(noise, "noise")
    vnoise = (
        VELOCITY_NOISE_RATIO * noise
        if velocity_noise is None
        else check_nonnegative_scalar(velocity_noise, "velocity_noise")
    )
    dt = check_nonnegative_scalar(dt, "dt")
    if dt <= 0:
        raise ValidationError(f"dt must be > 0; got {dt!r}")
    rng = check_random_state(random_state)
    t = np.arange(n, dtype=np.float64) * dt
    T = t[-1]
    tau = t / T
    s, ds_dtau = warp(tau)
    P, dP_ds = path(s)
    V = dP_ds * (ds_dtau / T)[:, None]
    P = P + draw(rng, P.shape, noise * _group_range(P))
    V = V + draw(rng, V.shape, vnoise * _group_range(V))
    return Demonstration.from_arrays(t, position=P, velocity=V)


def _square_loop(u: np.ndarray, side: float, loops: int):
    """Square (0,0)→(L,0)→(L,L)→(0,L)→(0,0) at loop parameter u in [0, loops]."""
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]])
    k = np.minimum(np.floor(4 * u).astype(np.int64), 4 * loops - 1)  # left-sided end
    local = 4 * u - k
    side_idx = k % 4
    start, step = corners[side_idx], corners[side_idx + 1] - corners[side_idx]
    return side * (start + local[:, None] * step), side * 4 * step  # P, dP/du


_SIGNATURE_DOC = """
    speed : {{"constant", "variable"}}, default="{speed}"
        Uniform path parameter, or the time warp described in the module docs.
    noise : float, default=0.0
        Position noise as a fraction of the clean position group's range.
    velocity_noise : float, optional
        Velocity noise as a fraction of the clean velocity group's range;
        ``0.6 × noise`` by default.
    noise_model : {{"gaussian", "uniform"}}, default="gaussian"
        Gaussian with that standard deviation, or uniform with that half-width.
    dt : float, default=0.1
        Sampling period (constant rate ``1 / dt``).
    random_state : None, int or numpy.random.Generator, optional
        Seed of the noise.

    Returns
    -------
    demo : Demonstration
        ``t`` of shape (n_points,), groups ``position`` and ``velocity``."""

#: The sampling keywords every shape takes after its own parameters: name,
#: default and annotation (``speed`` comes first, with each shape's default).
_SAMPLING = (
    ("noise", 0.0, "float"),
    ("velocity_noise", None, "float | None"),
    ("noise_model", "gaussian", "str"),
    ("dt", 0.1, "float"),
    ("random_state", None, inspect.Parameter.empty),
)


def _shape(n_points: int, speed: str, variation: tuple[float, int] | None = None):
    """Make a shape generator from the function that builds its path.

    The decorated function takes the shape's own keyword-only parameters
    (``side``, ``turns``, ...), checks them and returns ``path(s) -> (P,
    dP/ds)``. The generator it becomes takes ``n_points`` (default
    ``n_points``), those parameters, ``speed`` (default ``speed``) and the
    keywords of ``_SAMPLING``, written here once instead of in every shape;
    it samples the path with :func:`_sample`. Its docstring's ``{sig}`` line
    becomes the shared documentation of those keywords.
    """
    kw_only = inspect.Parameter.KEYWORD_ONLY

    def decorate(build: Callable) -> Callable[..., Demonstration]:
        own = list(inspect.signature(build).parameters.values())
        signature = inspect.Signature(
            [
                inspect.Parameter(
                    "n_points",
                    inspect.Parameter.POSITIONAL_OR_KEYWORD,
                    default=n_points,
                    annotation="int",
                ),
                *own,
                inspect.Parameter("speed", kw_only, default=speed, annotation="str"),
                *(
                    inspect.Parameter(name, kw_only, default=default, annotation=note)
                    for name, default, note in _SAMPLING
                ),
            ],
            return_annotation="Demonstration",
        )

        def generator(*args, **kwargs) -> Demonstration:
            try:
                bound = signature.bind(*args, **kwargs)
            except TypeError as exc:  # as a plain function would say it
                raise TypeError(f"{build.__name__}() {exc}") from None
            bound.apply_defaults()
            options = dict(bound.arguments)
            path = build(**{p.name: options.pop(p.name) for p in own})
            return _sample(path, variation=variation, **options)

        generator.__name__ = generator.__qualname__ = build.__name__
        generator.__module__ = build.__module__
        generator.__signature__ = signature  # type: ignore[attr-defined]
        if build.__doc__:  # None under python -OO
            generator.__doc__ = build.__doc__.replace(
                "    {sig}", _SIGNATURE_DOC.format(speed=speed).strip("\n")
            )
        return generator

    return decorate


@_shape(n_points=80, speed="constant")
def square(*, side: float = 10.0):
    """Closed 2-D square (paper Fig. 5a–f): 80 points by default.

    Counter-clockwise from the origin: ``(0, 0) → (side, 0) → (side, side) →
    (0, side) → (0, 0)``; the four sides take equal path parameter. At a corner
    the velocity is the one of the side that starts there (the last sample uses
    the last side).

    Parameters
    ----------
    n_points : int, default=80
        Number of samples (>= 2).
    side : float, default=10.0
        Side length.
    {sig}

    Examples
    --------
    >>> d = square()
    >>> d.n_samples, d.columns
    (80, ('x', 'y', 'vx', 'vy'))
    >>> d.get("position")[[0, -1]]
    array([[0., 0.],
           [0., 0.]])
    """
    side = _check_size(side, "side")

    def path(s):
        return _square_loop(s, side, 1)

    return path


@_shape(n_points=71, speed="variable")
def square_spiral(*, side: float = 10.0, height: float = 10.0, turns: int = 2):
    """3-D square spiral along Z (paper Fig. 5g–l): 71 points, variable speed.

    The square of :func:`square` is traced ``turns`` times in X–Y while Z rises
    linearly from 0 to ``height``.

    Parameters
    ----------
    n_points : int, default=71
        Number of samples (>= 2).
    side : float, default=10.0
        Side of the square.
    height : float, default=10.0
        Total rise along Z.
    turns : int, default=2
        Number of loops around the square.
    {sig}

    Examples
    --------
    >>> d = square_spiral()
    >>> d.n_samples, d.columns[:3]
    (71, ('x', 'y', 'z'))
    """
    side = _check_size(side, "side")
    height = _check_size(height, "height")
    turns = check_positive_int(turns, "turns")

    def path(s):
        P2, dP2 = _square_loop(turns * s, side, turns)
        z = height * s
        P = np.column_stack([P2, z])
        dP = np.column_stack([turns * dP2, np.full_like(z, height)])
        return P, dP

    return path


@_shape(n_points=150, speed="variable")
def spiral(*, turns: float = 3.0):
    """The Fig. 2 spiral: X from -10 to 10, Y in 0..10, Z in -5..5 (6-D with velocity).

    ``P(s) = (-10 + 20 s, 5 + 5 cos(2π·turns·s), 5 sin(2π·turns·s))``: it moves
    20 units along X but only 10 along Y and Z, which is what group
    normalization must preserve and per-dimension normalization destroys.

    Parameters
    ----------
    n_points : int, default=150
        Number of samples (>= 2).
    turns : float, default=3.0
        Number of revolutions around the X axis.
    {sig}

    Examples
    --------
    >>> P = spiral().get("position")
    >>> P.min(axis=0).round(2), P.max(axis=0).round(2)
    (array([-10.,   0.,  -5.]), array([10., 10.,  5.]))
    """
    turns = _check_size(turns, "turns")

    def path(s):
        w = 2 * np.pi * turns
        P = np.column_stack([-10 + 20 * s, 5 + 5 * np.cos(w * s), 5 * np.sin(w * s)])
        dP = np.column_stack(
            [np.full_like(s, 20.0), -5 * w * np.sin(w * s), 5 * w * np.cos(w * s)]
        )
        return P, dP

    return path


@_shape(n_points=100, speed="variable", variation=CURVE_SPEED_VARIATION)
def curve():
    """A simple 2-D curve with variable velocity (paper Fig. 3).

    One S-shaped wave, ``P(s) = (10 s, 4 sin(2π s))``. Its variable speed uses
    the warp of the module docs with ``a = 0.7`` and ``k = 3``
    (:data:`CURVE_SPEED_VARIATION`): the speed swings between 0.3 and 1.7
    times its mean three times over the path.

    Parameters
    ----------
    n_points : int, default=100
        Number of samples (>= 2).
    {sig}

    Examples
    --------
    >>> d = curve(noise=0.05, random_state=0)
    >>> d.n_samples, d.group_names
    (100, ('position', 'velocity'))
    """

    def path(s):
        w = 2 * np.pi
        P = np.column_stack([10 * s, 4 * np.sin(w * s)])
        dP = np.column_stack([np.full_like(s, 10.0), 4 * w * np.cos(w * s)])
        return P, dP

    return path


def _check_size(value, name):
    v = check_nonnegative_scalar(value, name)
    if v <= 0:
        raise ValidationError(f"{name} must be > 0; got {value!r}")
    return v


#: Shape name → generator.
SHAPES: Registry[Callable[..., Demonstration]] = Registry("shape")
SHAPES.add("square", square)
SHAPES.add("square_spiral", square_spiral)
SHAPES.add("spiral", spiral)
SHAPES.add("curve", curve)


def make_dataset(
    shape: str = "square",
    n_demos: int = 100,
    *,
    noise: float = 0.10,
    test_noise: float = 0.05,
    velocity_noise: float | None = None,
    test_velocity_noise: float | None = None,
    speed: str | None = None,
    n_points: int | None = None,
    noise_model: str = "gaussian",
    random_state=None,
    **shape_kwargs,
) -> tuple[list[Demonstration], Demonstration]:
    """The paper's training set and its "ideal" test demonstration.

    ``n_demos`` noisy copies of one clean path (10 % noise by default) and one
    test copy with less noise (5 %), all with the same timing. The demos are
    drawn first, in order, then the test demo, from one random generator.

    Parameters
    ----------
    shape : {"square", "square_spiral", "spiral", "curve"}, default="square"
        The generator (see :data:`SHAPES`).
    n_demos : int, default=100
        Number of training demonstrations.
    noise, test_noise : float, default=0.10, 0.05
        Position noise of the training and test demonstrations.
    velocity_noise, test_velocity_noise : float, optional
        Velocity noise; ``0.6 ×`` the position noise by default.
    speed : {"constant", "variable"}, optional
        The shape's default when ``None``.
    n_points : int, optional
        The shape's default when ``None``.
    noise_model : {"gaussian", "uniform"}, default="gaussian"
        See the module docs.
    random_state : None, int or numpy.random.Generator, optional
        Seed.
    **shape_kwargs
        Passed to the generator (for example ``side=`` or ``turns=``).

    Returns
    -------
    train : list of Demonstration
    test : Demonstration

    Examples
    --------
    >>> train, test = make_dataset("square", n_demos=5, random_state=0)
    >>> len(train), train[0].n_samples, test.n_samples
    (5, 80, 80)
    """
    generator = SHAPES.get(shape)
    n_demos = check_positive_int(n_demos, "n_demos")
    rng = check_random_state(random_state)
    kw = dict(shape_kwargs)
    kw["noise_model"] = noise_model
    if speed is not None:
        kw["speed"] = speed
    if n_points is not None:
        kw["n_points"] = n_points
    try:
        train = [
            generator(
                noise=noise, velocity_noise=velocity_noise, random_state=rng, **kw
            )
            for _ in range(n_demos)
        ]
    except TypeError as exc:  # an unknown keyword for this shape
        raise ValidationError(f"make_dataset({shape!r}): {exc}") from None
    test = generator(
        noise=test_noise, velocity_noise=test_velocity_noise, random_state=rng, **kw
    )
    return train, test


def obstacle(
    n_up: int = 7,
    n_down: int = 5,
    *,
    n_samples: int = 200,
    lift: float = 0.0,
    random_state=0,
) -> list[Demonstration]:
    """Demonstrations that take two routes around an obstacle.

    From ``(-10, ±lift)`` to the origin in about 5 s, ``n_up`` of them over a
    bump above (``y ≈ +5.5`` mid-course) and then ``n_down`` below
    (``y ≈ -5.5``): ``y = ±(5.5 sin(πs) + lift (1 - s))`` for ``s`` in
    [0, 1], plus a slow drift (a random walk of step ``0.0005``) and noise of
    standard deviation 0.05 on both coordinates; each demonstration's
    duration is drawn in [4.5, 5.5] s. A mean of both routes runs through the
    obstacle that every demonstration avoids: the test set of ndlfd's routes
    (:mod:`ndlfd.learner._routes`).

    Parameters
    ----------
    n_up, n_down : int, default=7, 5
        Demonstrations over the top and underneath (the first ``n_up`` are
        the upper ones).
    n_samples : int, default=200
        Samples per demonstration.
    lift : float, default=0.0
        The routes start at ``y = ±lift`` (and all end at 0).
    random_state : None, int or numpy.random.Generator, default=0
        The noise and durations.

    Returns
    -------
    demos : list of Demonstration
        Each with a ``position`` group ``(x, y)``.

    Examples
    --------
    >>> demos = obstacle(2, 1, n_samples=51)
    >>> [bool(d.X[25, 1] > 5) for d in demos], bool(demos[2].X[25, 1] < -5)
    ([True, True, False], True)
    """
    n_up = check_positive_int(n_up, "n_up", minimum=0)
    n_down = check_positive_int(n_down, "n_down", minimum=0)
    if n_up + n_down < 1:
        raise ValidationError("obstacle needs at least one demonstration; got 0")
    n_samples = check_positive_int(n_samples, "n_samples", minimum=2)
    rng = check_random_state(random_state)
    s = np.linspace(0.0, 1.0, n_samples)
    demos = []
    for k in range(n_up + n_down):
        sign = 1.0 if k < n_up else -1.0
        y = sign * (5.5 * np.sin(np.pi * s) + lift * (1.0 - s))
        y = y + 0.01 * rng.normal(0, 0.05, n_samples).cumsum()
        P = np.column_stack([-10.0 + 10.0 * s, y]) + rng.normal(0, 0.05, (n_samples, 2))
        t = 5.0 * s * rng.uniform(0.9, 1.1)
        demos.append(Demonstration(t, P, ["x", "y"], ["position"] * 2))
    return demos


def _yaw_down(yaw) -> np.ndarray:
    """Unit quaternions (w, x, y, z) of a hand pointing down, turned by ``yaw``."""
    from scipy.spatial.transform import Rotation

    yaw = np.atleast_1d(np.asarray(yaw, dtype=np.float64))
    r = Rotation.from_euler("z", yaw[:, None]) * Rotation.from_euler("x", np.pi)
    q = r.as_quat()  # x, y, z, w
    return np.column_stack([q[:, 3], q[:, :3]])


#: Waypoints of :func:`pick_place` on its normalized time: (time, where), where
#: is "home", "above object", "object", "above place", "place" or "retreat".
PICK_PLACE_PLAN = (
    (0.0, "home"),
    (0.3, "above object"),
    (0.4, "object"),
    (0.45, "object"),
    (0.55, "above object"),
    (0.8, "above place"),
    (0.9, "place"),
    (0.95, "place"),
    (1.0, "retreat"),
)

#: When :func:`pick_place`'s gripper closes and opens (normalized time).
PICK_PLACE_GRASP, PICK_PLACE_RELEASE = 0.42, 0.92

#: Where :func:`pick_place`'s hand comes down from and goes up to, from the
#: object (and the place), turned with its yaw (m): 0.1 above and 0.05 back
#: along the frame's x axis, so the approach turns with the object.
PICK_PLACE_APPROACH = (-0.05, 0.0, 0.1)


def _approach(yaw: float) -> np.ndarray:
    """:data:`PICK_PLACE_APPROACH` turned by ``yaw`` about z."""
    c, s = np.cos(yaw), np.sin(yaw)
    x, y, z = PICK_PLACE_APPROACH
    return np.array([c * x - s * y, s * x + c * y, z])


def pick_place(
    n_demos: int = 12,
    *,
    n_samples: int = 300,
    shift: float = 0.1,
    yaw: float = 0.0,
    noise: float = 5e-4,
    random_state=0,
) -> tuple[list[Demonstration], list[dict]]:
    """Pick-and-place demonstrations whose object and place move (task frames).

    Each demonstration starts near ``(0.3, 0, 0.3)`` m pointing down, moves
    above and behind an object (:data:`PICK_PLACE_APPROACH` in the object's
    frame), down to it (the hand's pose is the object's: position and yaw),
    closes the gripper (at :data:`PICK_PLACE_GRASP` of the motion), lifts
    back, carries it above and behind the place, puts it down with the
    place's yaw, opens (:data:`PICK_PLACE_RELEASE`) and retreats; minimum-jerk
    pieces between the waypoints of :data:`PICK_PLACE_PLAN`, the orientation
    slerped. The object lies at ``(0.5, 0, 0.02)`` and the place at ``(0.3,
    0.3, 0.02)``, each moved by up to ``shift`` in x and y and turned by up to
    ``yaw`` radians about z (uniformly), so the motion near each is rigid in
    its frame: the set the task-frame protocol of ``ndlfd evaluate`` holds
    out one demonstration of at a time.

    Parameters
    ----------
    n_demos : int, default=12
    n_samples : int, default=300
    shift : float, default=0.1
        Largest move of the object and the place in x and y (m).
    yaw : float, default=0.0
        Largest turn of the object and the place about z (radians).
    noise : float, default=5e-4
        Standard deviation of the position noise (m).
    random_state : None, int or numpy.random.Generator, default=0

    Returns
    -------
    demos : list of Demonstration
        Groups ``position`` (x, y, z), ``orientation`` (unit quaternions) and
        ``gripper`` (1 open, 0 closed); about 6 s each; each carries its
        task frames (``frames``, as returned beside).
    frames : list of dict of str to ndarray of shape (7,)
        Each demonstration's ``"object"`` and ``"place"`` poses: position,
        then unit quaternion (w, x, y, z) of the grasp there.

    Examples
    --------
    At the grasp, the hand is at the object:

    >>> demos, frames = pick_place(3, n_samples=101)
    >>> hand = demos[0].get("position")[int(PICK_PLACE_GRASP * 100)]
    >>> bool(np.allclose(hand, frames[0]["object"][:3], atol=3e-3))
    True
    """
    from scipy.spatial.transform import Rotation, Slerp

    from .learner import minimum_jerk

    n_demos = check_positive_int(n_demos, "n_demos", minimum=1)
    n_samples = check_positive_int(n_samples, "n_samples", minimum=len(PICK_PLACE_PLAN))
    rng = check_random_state(random_state)
    s = np.linspace(0.0, 1.0, n_samples)
    knots = np.array([k for k, _ in PICK_PLACE_PLAN])
    i = np.clip(np.searchsorted(knots, s, side="right") - 1, 0, knots.size - 2)
    u = minimum_jerk((s - knots[i]) / (knots[i + 1] - knots[i]))
    demos, frames = [], []
    for _ in range(n_demos):
        home = np.array([0.3, 0.0, 0.3]) + rng.normal(0.0, 0.01, 3)
        obj = np.array([0.5, 0.0, 0.02])
        obj[:2] += rng.uniform(-shift, shift, 2)
        place = np.array([0.3, 0.3, 0.02])
        place[:2] += rng.uniform(-shift, shift, 2)
        yaw_o, yaw_p = rng.uniform(-yaw, yaw, 2) if yaw > 0 else (0.0, 0.0)
        where = {
            "home": (home, 0.0),
            "above object": (obj + _approach(yaw_o), yaw_o),
            "object": (obj, yaw_o),
            "above place": (place + _approach(yaw_p), yaw_p),
            "place": (place, yaw_p),
            "retreat": (place + _approach(yaw_p), yaw_p),
        }
        P = np.array([where[w][0] for _, w in PICK_PLACE_PLAN])
        yaws = np.array([where[w][1] for _, w in PICK_PLACE_PLAN])
        pos = P[i] + (P[i + 1] - P[i]) * u[:, None]
        pos += rng.normal(0.0, noise, pos.shape)
        R = Rotation.from_quat(np.roll(_yaw_down(yaws), -1, axis=1))
        q = np.empty((n_samples, 4))
        for k in range(knots.size - 1):
            rows = i == k
            pair = Slerp([0.0, 1.0], R[[k, k + 1]])(u[rows]).as_quat()
            q[rows] = np.roll(pair, 1, axis=1)
        grip = np.where((s >= PICK_PLACE_GRASP) & (s < PICK_PLACE_RELEASE), 0.0, 1.0)
        t = 6.0 * s * rng.uniform(0.9, 1.1)
        frames.append({
            "object": np.concatenate([obj, _yaw_down(yaw_o)[0]]),
            "place": np.concatenate([place, _yaw_down(yaw_p)[0]]),
        })  # fmt: skip
        demos.append(Demonstration.from_arrays(
            t, position=pos, orientation=q, gripper=grip, frames=frames[-1]
        ))  # fmt: skip
    return demos, frames


#: :func:`task_board`'s waypoints in the board's frame (m): above the first
#: contact, the first contact (a press), back up, down at the start of a
#: slide, the slide's end, the goal (a plug, 2 cm above the board).
TASK_BOARD_POINTS = (
    (-0.08, -0.05, 0.06),
    (-0.08, -0.05, 0.0),
    (-0.08, -0.05, 0.03),
    (0.0, 0.02, 0.0),
    (0.06, 0.05, 0.0),
    (0.08, 0.06, 0.02),
)

#: Where :func:`task_board`'s board lies when not moved (x, y, z in m).
TASK_BOARD_ORIGIN = (0.55, 0.0, 0.05)

#: Nominal durations (s) of :func:`task_board`'s pieces: home to above the
#: first contact, then between the board's waypoints; with a rest at the
#: press (index 1 of the waypoints) of :data:`TASK_BOARD_PRESS` s.
TASK_BOARD_TIMES = (1.6, 0.5, 0.4, 0.8, 0.9, 0.5)
TASK_BOARD_PRESS = 0.4


def task_board(
    n_demos: int = 7,
    *,
    rate: float = 50.0,
    shift: float = 0.06,
    yaw: float = np.radians(18.0),
    noise: float = 5e-4,
    random_state=0,
) -> tuple[list[Demonstration], list[dict]]:
    """A task on a board that moves: everything after home is rigid in the board.

    Each demonstration starts at a home pose (``(0.3, 0, 0.45)`` m, a few mm
    apart), moves above a first contact point on the board, presses it (and
    rests there :data:`TASK_BOARD_PRESS` s), lifts, slides along the board and
    ends at a goal on it (:data:`TASK_BOARD_POINTS`, in the board's frame).
    The board lies at :data:`TASK_BOARD_ORIGIN` moved by up to ``shift`` in x
    and y and turned by up to ``yaw`` about z; each piece takes its nominal
    time (:data:`TASK_BOARD_TIMES`) times 0.85 to 1.15, minimum-jerk. So the
    whole motion but the home co-varies with the goal (the board's pose), as
    on a real task board whose place changes between executions: what the
    start-and-goal conditioning of ``ndlfd`` and ProMP is measured on.

    Parameters
    ----------
    n_demos : int, default=7
    rate : float, default=50.0
        Samples per second.
    shift : float, default=0.06
        Largest move of the board in x and y (m).
    yaw : float, default=radians(18)
        Largest turn of the board about z (radians).
    noise : float, default=5e-4
        Standard deviation of the position noise (m).
    random_state : None, int or numpy.random.Generator, default=0

    Returns
    -------
    demos : list of Demonstration
        Group ``position`` (x, y, z).
    info : list of dict
        Each demonstration's ``"board"`` (x, y, z, yaw) and ``"contact"`` and
        ``"press_end"``, the sample indices where the press begins and ends.

    Examples
    --------
    The path ends at the goal on its board:

    >>> demos, info = task_board(2)
    >>> x, y, z, a = info[0]["board"]
    >>> gx, gy, gz = TASK_BOARD_POINTS[-1]
    >>> c, s = np.cos(a), np.sin(a)
    >>> goal = [x + c * gx - s * gy, y + s * gx + c * gy, z + gz]
    >>> bool(np.allclose(demos[0].get("position")[-1], goal, atol=3e-3))
    True
    """
    from .learner import minimum_jerk

    n_demos = check_positive_int(n_demos, "n_demos", minimum=1)
    rng = check_random_state(random_state)
    local = np.array(TASK_BOARD_POINTS)
    demos, info = [], []
    for _ in range(n_demos):
        x, y = np.array(TASK_BOARD_ORIGIN[:2]) + rng.uniform(-shift, shift, 2)
        a = float(rng.uniform(-yaw, yaw)) if yaw > 0 else 0.0
        z = TASK_BOARD_ORIGIN[2]
        c, s = np.cos(a), np.sin(a)
        world = np.column_stack([x + c * local[:, 0] - s * local[:, 1],
                                 y + s * local[:, 0] + c * local[:, 1],
                                 z + local[:, 2]])  # fmt: skip
        home = np.array([0.3, 0.0, 0.45]) + rng.normal(0.0, 0.003, 3)
        points = [home, *world]
        pieces, contact, press_end = [points[0][None]], 0, 0
        for k, dur in enumerate(TASK_BOARD_TIMES):
            n = max(2, round(dur * rng.uniform(0.85, 1.15) * rate))
            u = minimum_jerk(np.linspace(0.0, 1.0, n + 1)[1:])
            pieces.append(points[k] + (points[k + 1] - points[k]) * u[:, None])
            if k == 1:  # at the press: rest there
                contact = sum(p.shape[0] for p in pieces) - 1
                rest = max(1, round(TASK_BOARD_PRESS * rng.uniform(0.85, 1.15) * rate))
                pieces.append(np.repeat(points[2][None], rest, axis=0))
                press_end = contact + rest
        P = np.concatenate(pieces)
        P = P + rng.normal(0.0, noise, P.shape)
        t = np.arange(P.shape[0]) / rate
        demos.append(Demonstration.from_arrays(t, position=P))
        info.append({"board": np.array([x, y, z, a]), "contact": contact,
                     "press_end": press_end})  # fmt: skip
    return demos, info
