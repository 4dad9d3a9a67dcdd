"""Data sets that judge route discovery (``ndlfd.learner._routes``).

Every set is a :class:`RouteSet`: demonstrations of one skill, the route each
one truly takes, and where and how far apart the routes are. The data are
realistic robot recordings: minimum-jerk motions, noise of a few mm (or
1e-4 rad), durations varying 10-30 %, sample rates 30-500 Hz, seeded.

:data:`CASES` maps each set's name to a function of no argument that makes
it. The file journeys (``tf_bag``, ``pick_place_csv``) also take an optional
``folder``: where to write their files (default: a temporary folder, removed
once the demonstrations are read back).
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from ndlfd.demonstration import Demonstration
from ndlfd.learner import minimum_jerk

#: Points of the normalized-time grid the route means are compared on.
GRID = 200
#: Joint names of the 6-axis arm (joint space sets).
JOINTS = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3")
#: A user-named group has no default codebook: the joints get position's 20.
JOINT_PARAMS = {"levels": {"joints": 20}}


@dataclass(frozen=True)
class RouteSet:
    """Demonstrations of one skill and their true routes.

    Attributes
    ----------
    name : str
    demos : list of Demonstration
    labels : ndarray of int
        The true route of each demonstration, ``0..k-1``.
    columns : tuple of str
        The columns the routes differ in (``"y"``, or ``"group.column"``).
    tau_star : float
        Normalized time where the true routes' means differ most (one route:
        where the demonstrations spread most).
    route_values : ndarray of shape (n_routes, len(columns))
        Each route's mean at ``tau_star``, physical units.
    separation : float
        Smallest distance between two rows of ``route_values`` (inf for one).
    params : dict
        Extra ``KeypointHMM(**params)`` keywords.
    """

    name: str
    demos: list
    labels: np.ndarray
    columns: tuple
    tau_star: float
    route_values: np.ndarray
    separation: float
    params: dict

    @property
    def n_routes(self) -> int:
        """Number of true routes."""
        return int(np.unique(self.labels).size)


# ------------------------------------------------------------------ measures
def column_values(demo: Demonstration, columns) -> np.ndarray:
    """The ``columns`` of ``demo``, shape (n_samples, len(columns)).

    A name is a column's own name or ``group.column``.
    """
    out = []
    for name in columns:
        if name in demo.columns:
            j = demo.columns.index(name)
        else:
            group, col = name.split(".", 1)
            j = next(
                i
                for i, (c, g) in enumerate(zip(demo.columns, demo.groups, strict=True))
                if c == col and g == group
            )
        out.append(demo.X[:, j])
    return np.column_stack(out)


def normalized_time(demo: Demonstration) -> np.ndarray:
    """``(t - t0) / (t_end - t0)``."""
    return (demo.t - demo.t[0]) / (demo.t[-1] - demo.t[0])


def at_tau(demo: Demonstration, columns, tau) -> np.ndarray:
    """The ``columns`` at normalized times ``tau`` (linear interpolation)."""
    V = column_values(demo, columns)
    s = normalized_time(demo)
    return np.column_stack([np.interp(tau, s, v) for v in V.T])


def route_error(rs: RouteSet, path: Demonstration) -> float:
    """Distance of ``path`` from the nearest route at ``tau_star``, in separations.

    0 for a one-route set.
    """
    if rs.n_routes < 2:
        return 0.0
    v = at_tau(path, rs.columns, [rs.tau_star])[0]
    return float(np.linalg.norm(rs.route_values - v, axis=1).min() / rs.separation)


def route_set(name, demos, labels, columns, params=None) -> RouteSet:
    """A :class:`RouteSet` whose ``tau_star`` and route values come from ``demos``.

    Each demonstration is resampled on :data:`GRID` normalized times; the
    routes' means are compared there and ``tau_star`` is the grid point of
    the largest smallest distance between two route means. With one route,
    it is where the demonstrations' spread (RMS about their mean) is largest.
    """
    labels = np.asarray(labels, dtype=np.int64)
    columns = tuple(columns)
    grid = np.linspace(0.0, 1.0, GRID)
    R = np.stack([at_tau(d, columns, grid) for d in demos])  # (n, GRID, k)
    routes = np.unique(labels)
    means = np.stack([R[labels == r].mean(axis=0) for r in routes])
    if routes.size < 2:
        spread = np.sqrt(((R - means[0]) ** 2).sum(axis=2).mean(axis=0))
        i = int(np.argmax(spread))
        separation = np.inf
    else:
        gaps = np.stack(
            [
                np.linalg.norm(means[a] - means[b], axis=1)
                for a in range(routes.size)
                for b in range(a + 1, routes.size)
            ]
        ).min(axis=0)
        i = int(np.argmax(gaps))
        separation = float(gaps[i])
    return RouteSet(
        name=name,
        demos=list(demos),
        labels=labels,
        columns=columns,
        tau_star=float(grid[i]),
        route_values=means[:, i, :],
        separation=separation,
        params=dict(params or {}),
    )


# ------------------------------------------------------------- motion parts
def stamps(rng, duration, rate, t0=0.0, jitter=0.0):
    """Sample times at ``rate`` Hz over ``duration`` s from ``t0``.

    ``jitter``: each step's relative random deviation (uniform).
    """
    n = round(duration * rate) + 1
    steps = np.full(n - 1, 1.0 / rate)
    if jitter:
        steps *= 1.0 + rng.uniform(-jitter, jitter, n - 1)
    return t0 + np.concatenate([[0.0], np.cumsum(steps)])


def phase_warp(rng, tau, amount, n_terms=3):
    """A smooth random monotone warp of ``[0, 1]`` moving phases up to ~``amount``."""
    c = rng.normal(0.0, amount / np.sqrt(n_terms), n_terms)
    k = np.arange(1, n_terms + 1)
    c = c / max(1.0, np.abs(c * np.pi * k).sum() / 0.5)  # slope stays >= 0.5
    return tau + np.sin(np.pi * np.outer(tau, k)) @ c


def bump(u, center, half_width):
    """A smooth bump ``(1 - x^2)^3``: 1 at ``center``, 0 beyond ``half_width``."""
    x = np.clip((np.asarray(u) - center) / half_width, -1.0, 1.0)
    return (1.0 - x * x) ** 3


def waypoints(tau, knots, values):
    """Minimum-jerk pieces through ``values`` (rows) at normalized times ``knots``.

    Rest at every knot; constant before the first and after the last.
    """
    knots = np.asarray(knots, dtype=float)
    values = np.asarray(values, dtype=float)
    out = np.repeat(values[:1], tau.size, axis=0)
    for a, b, va, vb in zip(
        knots[:-1], knots[1:], values[:-1], values[1:], strict=True
    ):
        s = minimum_jerk((tau - a) / (b - a))[:, None]
        inside = tau >= a
        out[inside] = (va + s * (vb - va))[inside]
    return out


def tool_down(yaw, rng=None, wobble=0.0):
    """Quaternions (w, x, y, z) of a tool pointing down, turned by ``yaw``."""
    n = np.size(yaw)
    angles = np.column_stack([np.full(n, np.pi), np.zeros(n), yaw])
    if rng is not None and wobble:
        angles = angles + rng.normal(0.0, wobble, 3)
    return Rotation.from_euler("xyz", angles).as_quat(scalar_first=True)


def reach(rng, tau, start, goal, lateral, axis=1, *, spread=0.01, noise=0.002):
    """A minimum-jerk reach bent by ``lateral(s)`` on ``axis`` (s: path parameter).

    Start and goal are each moved by ``spread`` (sd, m) per demonstration;
    every sample gets ``noise`` (sd, m).
    """
    s = minimum_jerk(tau)
    a = np.asarray(start) + rng.normal(0.0, spread, 3)
    b = np.asarray(goal) + rng.normal(0.0, spread, 3)
    P = a + s[:, None] * (b - a)
    P[:, axis] += lateral(s)
    return P + rng.normal(0.0, noise, P.shape), s


def _fresh(folder):
    """A folder to write to, and the temporary directory to remove (or None)."""
    if folder is not None:
        Path(folder).mkdir(parents=True, exist_ok=True)
        return Path(folder), None
    tmp = tempfile.TemporaryDirectory(prefix="route_corpus_")
    return Path(tmp.name), tmp


# ------------------------------------------------------------ file journeys
def tf_bag(folder=None) -> RouteSet:
    """6 reaches recorded as ``/tf`` in ROS 2 bags, 4 left and 2 right of an obstacle.

    About 0.5 m, 3-5 s, 100-250 Hz with stamps off by up to 10 % of a step;
    the tool turns 90 degrees about z. Each ``TFMessage`` holds
    ``world -> base_link`` (fixed) and ``base_link -> tool0``; read back
    with ``read_bag(path, topic="/tf", frame="tool0")``.
    """
    from bag_samples import T, header, write_bag
    from ndlfd.io import read_bag

    def tf(ns, parent, child, p, q):
        tr = T["geometry_msgs/msg/Transform"](
            translation=T["geometry_msgs/msg/Vector3"](x=p[0], y=p[1], z=p[2]),
            rotation=T["geometry_msgs/msg/Quaternion"](w=q[0], x=q[1], y=q[2], z=q[3]),
        )
        return T["geometry_msgs/msg/TransformStamped"](
            header=header(ns, parent), child_frame_id=child, transform=tr
        )

    rng = np.random.default_rng(101)
    sides = [1, 1, -1, 1, -1, 1]
    where, tmp = _fresh(folder)
    demos = []
    try:
        for k, side in enumerate(sides):
            duration = rng.uniform(3.0, 5.0)
            t = stamps(rng, duration, (100, 125, 250)[k % 3], jitter=0.1)
            tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), 0.02)
            P, s = reach(
                rng,
                tau,
                [0.30, 0.0, 0.40],
                [0.75, 0.0, 0.20],
                lambda s, side=side: side * 0.15 * np.sin(np.pi * s) ** 2,
            )
            Q = tool_down(np.pi / 2 * s, rng, 0.01)
            ns0 = 1_700_000_000 * 10**9 + k * 600 * 10**9
            ns = (ns0 + np.round(t * 1e9)).astype(np.int64)
            msgs = []
            for n_k, p, q in zip(ns, P, Q, strict=True):
                base = tf(int(n_k), "world", "base_link", [0, 0, 0.8], [1, 0, 0, 0])
                tool = tf(int(n_k), "base_link", "tool0", p, q)
                msg = T["tf2_msgs/msg/TFMessage"](transforms=[base, tool])
                msgs.append((int(n_k) + 300_000, msg))  # received 0.3 ms later
            path = where / f"reach_{k}"
            write_bag(path, {"/tf": msgs})
            demos += read_bag(path, topic="/tf", frame="tool0")
    finally:
        if tmp is not None:
            tmp.cleanup()
    labels = [0 if s > 0 else 1 for s in sides]
    return route_set("tf_bag", demos, labels, ("y",))


def pick_place_csv(folder=None) -> RouteSet:
    """8 pick-and-place demonstrations as CSV files, 5 left and 3 right.

    Home, down to the grasp (gripper closes at ~35 %), lift, carry past an
    obstacle at y = +-0.12 m (~65 %), down to the place (opens at ~80 %),
    retreat; the tool turns 60 degrees while carrying. 2 % phase jitter,
    6.5-9 s at 30-100 Hz. Columns ``t,x,y,z,qw,qx,qy,qz,gripper``, read back
    with :func:`ndlfd.io.read_csv`.
    """
    from ndlfd.io import read_csv

    rng = np.random.default_rng(202)
    sides = [1, -1, 1, 1, -1, 1, -1, 1]
    where, tmp = _fresh(folder)
    demos = []
    try:
        for k, side in enumerate(sides):
            duration = rng.uniform(6.5, 9.0)
            t = stamps(rng, duration, (30, 50, 100, 60)[k % 4], t0=rng.uniform(0, 50))
            tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), 0.02)
            home = np.array([0.30, 0.0, 0.30]) + rng.normal(0, 0.01, 3)
            pick = np.array([0.35, -0.05, 0.03]) + rng.normal(0, 0.005, 3)
            place = np.array([0.70, 0.05, 0.04]) + rng.normal(0, 0.005, 3)
            up_pick = pick + [0.0, 0.0, 0.12]
            up_place = place + [0.0, 0.0, 0.12]
            knots = [0.0, 0.30, 0.37, 0.46, 0.80, 0.84, 1.0]
            values = [home, pick, pick, up_pick, place, place, up_place]
            P = waypoints(tau, knots, values)
            P[:, 1] += side * 0.12 * bump(tau, 0.63, 0.17)
            P += rng.normal(0.0, 0.002, P.shape)
            yaw = np.deg2rad(60) * minimum_jerk((tau - 0.46) / 0.34)
            Q = tool_down(yaw, rng, 0.01)
            grip = ((tau >= 0.35 + rng.normal(0, 0.005)) & (tau < 0.81)).astype(float)
            table = np.column_stack([t, P, Q, grip])
            path = where / f"pick_place_{k:02d}.csv"
            np.savetxt(
                path,
                table,
                fmt="%.9g",
                delimiter=",",
                header="t,x,y,z,qw,qx,qy,qz,gripper",
                comments="",
            )
            demos.append(read_csv(path))
    finally:
        if tmp is not None:
            tmp.cleanup()
    labels = [0 if s > 0 else 1 for s in sides]
    return route_set("pick_place_csv", demos, labels, ("y",))


# ------------------------------------------------------------ separated sets
def brief() -> RouteSet:
    """5 + 4 reaches that differ only in a short detour (12 % of the time).

    3-D, 0.6 m in 2-3 s at 100-200 Hz; the detour is y = +-0.08 m at
    half-time.
    """
    rng = np.random.default_rng(303)
    sides = [1, -1, 1, 1, -1, 1, -1, 1, -1]
    demos = []
    for k, side in enumerate(sides):
        t = stamps(rng, rng.uniform(2.0, 3.0), (100, 150, 200)[k % 3])
        tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), 0.01)
        P, _ = reach(rng, tau, [0.2, -0.1, 0.3], [0.8, -0.1, 0.3], lambda s: 0 * s)
        P[:, 1] += side * 0.08 * bump(tau, 0.5, 0.06)
        demos.append(Demonstration.from_arrays(t, position=P))
    return route_set("brief", demos, [0 if s > 0 else 1 for s in sides], ("y",))


def two_vs_one() -> RouteSet:
    """3 planar pushes: 2 left (y = +0.15 m mid-way), 1 right, 2.5-3.5 s."""
    rng = np.random.default_rng(404)
    sides = [1, -1, 1]
    demos = []
    for k, side in enumerate(sides):
        t = stamps(rng, rng.uniform(2.5, 3.5), (60, 100, 120)[k])
        tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), 0.02)
        P, _ = reach(
            rng,
            tau,
            [0.3, 0.0, 0.0],
            [0.8, 0.05, 0.0],
            lambda s, side=side: side * 0.15 * np.sin(np.pi * s) ** 2,
        )
        demos.append(Demonstration.from_arrays(t, position=P[:, :2]))
    return route_set("two_vs_one", demos, [0 if s > 0 else 1 for s in sides], ("y",))


def three_routes() -> RouteSet:
    """4 / 3 / 2 reaches on one side, peaking at y = 0.05, 0.15 and 0.25 m."""
    rng = np.random.default_rng(505)
    heights = [0.05, 0.15, 0.25]
    labels = [0, 1, 2, 0, 1, 0, 2, 1, 0]
    demos = []
    for k, r in enumerate(labels):
        t = stamps(rng, rng.uniform(2.5, 3.5), (50, 100, 200)[k % 3])
        tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), 0.02)
        h = heights[r] + rng.normal(0.0, 0.005)
        P, _ = reach(
            rng,
            tau,
            [0.3, 0.0, 0.25],
            [0.8, 0.0, 0.25],
            lambda s, h=h: h * np.sin(np.pi * s) ** 2,
        )
        demos.append(Demonstration.from_arrays(t, position=P))
    return route_set("three_routes", demos, labels, ("y",))


def _grasp_motion(rng, t, *, high, warp=0.02):
    """A reach over (``high``) or under a bar, closing the gripper at ~85 %.

    Position, clean velocity (of the noiseless path), orientation, gripper.
    """
    tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), warp)
    s = minimum_jerk(tau)
    a = np.array([0.25, -0.30, 0.20]) + rng.normal(0, 0.01, 3)
    b = np.array([0.65, 0.25, 0.08]) + rng.normal(0, 0.01, 3)
    clean = a + s[:, None] * (b - a)
    lift = (0.35 if high else 0.12) - (a[2] + b[2]) / 2 + rng.normal(0, 0.005)
    clean[:, 2] += lift * np.sin(np.pi * s) ** 2
    V = np.gradient(clean, t, axis=0) + rng.normal(0.0, 0.005, clean.shape)
    P = clean + rng.normal(0.0, 0.002, clean.shape)
    Q = tool_down(np.deg2rad(45) * s, rng, 0.01)
    grip = (tau >= 0.85 + rng.normal(0, 0.01)).astype(float)
    return P, V, Q, grip


def pose_gripper_velocity() -> RouteSet:
    """6 reaches over a bar (z = 0.35 m mid-way), 4 under it (z = 0.12 m).

    3-D pose, the controller's velocity (given), gripper; 2 % phase jitter,
    3 s +-20 % at 50-500 Hz.
    """
    rng = np.random.default_rng(606)
    high = [True, True, False, True, False, True, False, True, False, True]
    demos = []
    for k, h in enumerate(high):
        t = stamps(rng, 3.0 * rng.uniform(0.8, 1.2), (50, 125, 400, 100, 250)[k % 5])
        P, V, Q, grip = _grasp_motion(rng, t, high=h)
        demos.append(
            Demonstration.from_arrays(
                t,
                position=P,
                velocity=V,
                orientation=Q,
                gripper=grip,
                columns={"gripper": ["gripper"]},
            )
        )
    labels = [0 if h else 1 for h in high]
    return route_set("pose_gripper_velocity", demos, labels, ("z",))


def _arm(rng, t, pan_route=0.0, *, vary=0.03, warp=0.02):
    """A 6-joint motion (rad); ``pan_route`` bends the shoulder pan mid-way."""
    tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), warp)
    s = minimum_jerk(tau)[:, None]
    a = np.array([0.0, -1.57, 1.57, -1.57, -1.57, 0.0]) + rng.normal(0, vary, 6)
    b = np.array([0.9, -1.10, 1.20, -1.70, -1.57, 0.6]) + rng.normal(0, vary, 6)
    Q = a + s * (b - a)
    wiggle = rng.normal(0, vary, 6)  # each demonstration's own mid-course shape
    Q += wiggle * np.sin(np.pi * s) ** 2
    Q[:, 0] += pan_route * np.sin(np.pi * s[:, 0]) ** 2
    return Q + rng.normal(0.0, 1e-4, Q.shape)


def joint6() -> RouteSet:
    """9 joint-space motions: shoulder pan +-0.26 rad about its mean mid-way (6 / 3).

    UR-like arm, 2.5-3.5 s at 125-400 Hz.
    """
    rng = np.random.default_rng(707)
    sides = [1, 1, -1, 1, -1, 1, 1, -1, 1]
    demos = []
    for k, side in enumerate(sides):
        t = stamps(rng, rng.uniform(2.5, 3.5), (125, 250, 400)[k % 3])
        Q = _arm(rng, t, side * 0.26)
        demos.append(Demonstration.from_arrays(t, joints=Q, columns={"joints": JOINTS}))
    labels = [0 if s > 0 else 1 for s in sides]
    return route_set("joint6", demos, labels, ("joints.shoulder_pan",), JOINT_PARAMS)


# ------------------------------------------------------------ one-route sets
def _bumped_reaches(rng, heights, durations, rates, *, t0=None, rest=None):
    """Reaches bent to y = ``heights`` mid-way, after a ``rest``, clocks at ``t0``."""
    demos = []
    for k, h in enumerate(heights):
        rate = rates[k % len(rates)]
        t = stamps(rng, durations[k], rate)
        tau = phase_warp(rng, (t - t[0]) / (t[-1] - t[0]), 0.02)
        P, _ = reach(
            rng,
            tau,
            [0.3, 0.0, 0.25],
            [0.8, 0.0, 0.25],
            lambda s, h=h: h * np.sin(np.pi * s) ** 2,
        )
        if rest is not None:  # standing still before the motion starts
            r = stamps(rng, rest[k], rate)[:-1]
            if r.size:
                t = np.concatenate([r, r[-1] + 1.0 / rate + t])
                P = np.concatenate([P[0] + rng.normal(0.0, 0.002, (r.size, 3)), P])
        if t0 is not None:
            t = t + t0[k]
        demos.append(Demonstration.from_arrays(t, position=P))
    return demos


def amplitude_spread() -> RouteSet:
    """12 reaches, bump of 0.15 m +-25 % (uniform), 2.5-3.5 s."""
    rng = np.random.default_rng(808)
    heights = 0.15 * rng.uniform(0.75, 1.25, 12)
    demos = _bumped_reaches(rng, heights, rng.uniform(2.5, 3.5, 12), (50, 100, 200))
    return route_set("amplitude_spread", demos, np.zeros(12), ("y",))


def amplitude_gaussian() -> RouteSet:
    """15 reaches, bump of 0.15 m with a normal 15 % sd."""
    rng = np.random.default_rng(909)
    heights = 0.15 * rng.normal(1.0, 0.15, 15)
    demos = _bumped_reaches(rng, heights, rng.uniform(2.5, 3.5, 15), (50, 100, 200))
    return route_set("amplitude_gaussian", demos, np.zeros(15), ("y",))


def speeds() -> RouteSet:
    """10 reaches of one course, 3 s +-30 %."""
    rng = np.random.default_rng(1010)
    heights = 0.15 + rng.normal(0.0, 0.005, 10)
    demos = _bumped_reaches(rng, heights, 3.0 * rng.uniform(0.7, 1.3, 10), (100, 200))
    return route_set("speeds", demos, np.zeros(10), ("y",))


def time_shifts() -> RouteSet:
    """10 reaches after a rest of 0-1 s, clocks starting anywhere in 0-1000 s."""
    rng = np.random.default_rng(1111)
    heights = 0.15 + rng.normal(0.0, 0.005, 10)
    demos = _bumped_reaches(
        rng,
        heights,
        3.0 * rng.uniform(0.9, 1.1, 10),
        (100, 200),
        t0=rng.uniform(0.0, 1000.0, 10),
        rest=rng.uniform(0.0, 1.0, 10),
    )
    return route_set("time_shifts", demos, np.zeros(10), ("y",))


def jitter_3d() -> RouteSet:
    """12 pose + gripper reaches over a bar, 3 % phase jitter, 3 s +-20 %."""
    rng = np.random.default_rng(1212)
    demos = []
    for k in range(12):
        t = stamps(rng, 3.0 * rng.uniform(0.8, 1.2), (50, 100, 250)[k % 3])
        P, _, Q, grip = _grasp_motion(rng, t, high=True, warp=0.03)
        demos.append(
            Demonstration.from_arrays(
                t,
                position=P,
                orientation=Q,
                gripper=grip,
                columns={"gripper": ["gripper"]},
            )
        )
    return route_set("jitter_3d", demos, np.zeros(12), ("z",))


def joint6_one() -> RouteSet:
    """10 joint-space motions varying continuously.

    Start, goal and mid-course shape 0.04 rad (sd) per joint, the shoulder
    pan's bend uniform in +-0.12 rad.
    """
    rng = np.random.default_rng(1313)
    demos = []
    for k in range(10):
        t = stamps(rng, rng.uniform(2.5, 3.5), (125, 250, 400)[k % 3])
        Q = _arm(rng, t, rng.uniform(-0.12, 0.12), vary=0.04)
        demos.append(Demonstration.from_arrays(t, joints=Q, columns={"joints": JOINTS}))
    return route_set(
        "joint6_one", demos, np.zeros(10), ("joints.shoulder_pan",), JOINT_PARAMS
    )


#: The sets of several true routes.
SEPARATED = (
    "tf_bag",
    "pick_place_csv",
    "brief",
    "two_vs_one",
    "three_routes",
    "pose_gripper_velocity",
    "joint6",
)
#: The sets of one true route (which must not be split).
ONE_ROUTE = (
    "amplitude_spread",
    "amplitude_gaussian",
    "speeds",
    "time_shifts",
    "jitter_3d",
    "joint6_one",
)
#: Every set: name -> function making it (no argument needed).
CASES = {name: globals()[name] for name in SEPARATED + ONE_ROUTE}
