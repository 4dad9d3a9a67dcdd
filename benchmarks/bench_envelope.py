"""Do conditioned paths stay within the demonstrations' motion envelope?

For each set, 1,000 random conditions (a third each: a start, a goal, a via
point at a random time between 10 % and 90 % of the motion), each within 3
times the demonstrations' spread there (starts: around the mean start, by the
starts' standard deviation per column; goals likewise; via points: around
the mean of one route's demonstrations at that phase, by their standard
deviation, so a via point is never between two routes); and as many observed
prefixes as each of those (``prefix_draw`` of
tests/learner/test_learner_envelope.py: a demonstration run up to 15 % late
or early, as far off, cut between 10 % and 90 %; counted from its last
observed sample on, ``envelope_ratios(..., since=)``). Each path is
generated on 1,000 samples over the demonstrations' median duration and its
largest speed and acceleration are divided by the demonstrations' envelope
at that phase (:func:`ndlfd.metrics.phase_envelope`: the 95th percentile of
their per-phase maxima over 50 bins, widened by one bin). ProMP
(movement_primitives, via ``ndlfd.baselines``) conditioned on the same
points, in the same run, on the position sets (it has no joint groups); its
goal is a via point at the last time stamp.

Prints, per set and kind, the median, 99th percentile and largest ratio.

Run: ``.venv/bin/python benchmarks/bench_envelope.py [--draws 1000]``
(about a minute).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from ndlfd import Demonstration, KeypointHMM, synth
from ndlfd.baselines import make_baseline
from ndlfd.datasets import load_lasa
from ndlfd.metrics import envelope_ratios, phase_envelope

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "learner"))

KINDS = ("start", "goal", "via", "prefix")


def prefix_draw(*args):
    """The test's draw of a prefix (``tests/learner/test_learner_envelope.py``)."""
    from test_learner_envelope import prefix_draw as draw

    return draw(*args)


def so101_resting():
    """SO-101-like episodes in degrees, at rest before and after (the test's)."""
    from test_learner_replan import _resting

    demos, model = _resting()
    return demos, model, "joints"


def _phase_values(demos, group, phase):
    return np.array(
        [
            [np.interp(phase, (d.t - d.t[0]) / d.duration, c) for c in d.get(group).T]
            for d in demos
        ]
    )


def draw_conditions(demos, group, routes, n, rng):
    """``n`` conditions per kind, within 3 spreads (see the module text)."""
    starts = np.array([d.get(group)[0] for d in demos])
    goals = np.array([d.get(group)[-1] for d in demos])
    span = np.ptp(np.vstack([d.get(group) for d in demos]), axis=0)
    out = []
    for kind in KINDS:
        for _ in range(n):
            u = rng.uniform(-1.0, 1.0, span.size)
            if kind == "prefix":
                cut = rng.uniform(0.1, 0.9)
                draw = prefix_draw(demos, group, routes, cut, span, u, rng)
                out.append((kind, cut, draw))
                continue
            if kind == "via":
                phase = rng.uniform(0.1, 0.9)
                r = rng.choice(np.unique(routes))
                on = [d for d, k in zip(demos, routes, strict=True) if k == r]
                vals = _phase_values(on, group, phase)
            else:
                phase, vals = (0.0, starts) if kind == "start" else (1.0, goals)
            spread = vals.std(axis=0) + 1e-3 * span
            out.append((kind, phase, vals.mean(axis=0) + 3.0 * spread * u))
    return out


def ndlfd_path(model, t, group, kind, phase, point):
    if kind == "prefix":
        return model.generate(t, dense=True, observed=point(t))
    if kind == "via":
        k = round(phase * (t.size - 1))
        return model.generate(t, dense=True, via=[(t[k], {group: point})])
    return model.generate(t, dense=True, **{kind: {group: point}})


def promp_path(promp, t, kind, phase, point):
    if kind == "prefix":
        P = promp.generate(t, observed=point(t).get("position"))
    elif kind == "start":
        P = promp.generate(t, start=point)
    else:
        k = t.size - 1 if kind == "goal" else round(phase * (t.size - 1))
        P = promp.generate(t, via=[(t[k], point)])
    return Demonstration.from_arrays(t, position=P)


def run(name, demos, model, group, draws, peer, rng):
    env = phase_envelope(demos, group)
    t = np.linspace(0.0, float(np.median([d.duration for d in demos])), 1000)
    conds = draw_conditions(demos, group, model.routes_, draws // 3, rng)
    promp = make_baseline("promp").fit(demos) if peer else None
    rows = {}
    base = envelope_ratios(model.generate(t, dense=True), env, group)
    for kind, phase, point in conds:
        # a prefix's continuation: from its last observed sample on
        since = round(phase * (t.size - 1)) if kind == "prefix" else 0
        path = ndlfd_path(model, t, group, kind, phase, point)
        r = envelope_ratios(path, env, group, since=since)
        rows.setdefault((kind, "ndlfd"), []).append(r)
        if promp is not None:
            p = promp_path(promp, t, kind, phase, point)
            r = envelope_ratios(p, env, since=since)
            rows.setdefault((kind, "promp"), []).append(r)
    print(f"\n{name} ({len(demos)} demonstrations, {group}); unconditioned ndlfd:"
          f" speed {base[0]:.2f}, acceleration {base[1]:.2f}")  # fmt: skip
    print("| kind | generator | speed: median | p99 | max | acceleration: median"
          " | p99 | max |")  # fmt: skip
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for (kind, gen), r in rows.items():
        r = np.array(r)
        stats = (np.median, lambda x: np.quantile(x, 0.99), np.max)
        cells = [f"{f(r[:, j]):.2f}" for j in (0, 1) for f in stats]
        print(f"| {kind} | {gen} | " + " | ".join(cells) + " |")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=1000)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    t0 = time.perf_counter()
    for shape in ("Angle", "Sshape", "Worm", "BendedLine"):
        demos = load_lasa(shape)
        run(f"LASA {shape}", demos, KeypointHMM().fit(demos), "position",
            args.draws, True, rng)  # fmt: skip
    demos = synth.obstacle(7, 5)
    run("synth.obstacle (two routes)", demos, KeypointHMM().fit(demos), "position",
        args.draws, True, rng)  # fmt: skip
    demos, model, group = so101_resting()
    run("SO-101-like, at rest before and after (degrees)", demos, model, group,
        args.draws, False, rng)  # fmt: skip
    print(f"\n{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
