"""Route discovery on the route corpus, and how often a continuous spread splits.

Run:  .venv/bin/python benchmarks/bench_routes.py            (about a minute)
      .venv/bin/python benchmarks/bench_routes.py --draws 100 --no-write

Three tables, from this run's code:

* **the corpus** (``tests/route_corpus.py``: ROS 2 ``/tf`` bags written with
  rosbags' Writer and pick-and-place CSV files read back as a user does,
  brief detours, two against one, three routes, pose + gripper + velocity
  with phase jitter, joint space; and sets of one route with continuous
  variation): the routes found against the true ones, and the unconditioned
  path's distance at the point of largest divergence from the nearest true
  route, in route separations (0.15 or less is on a route);
* **false splits**: noiseless bumps whose heights are drawn from one uniform
  or normal distribution (one route) in ``--draws`` draws per size: the
  share split into more than one route;
* **cost**: route discovery alone (``model_routes``) on the two-route
  obstacle set with 200 templates, best of 5.

The tables go into benchmarks/RESULTS.md between ``<!-- routes:start -->``
and ``<!-- routes:end -->``.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from bench_hmm import write_section
from ndlfd import KeypointHMM, NdlfdWarning, synth
from ndlfd.learner._routes import model_routes, split_routes
from route_corpus import CASES, route_error

START, END = "<!-- routes:start -->", "<!-- routes:end -->"
COMMAND = ".venv/bin/python benchmarks/bench_routes.py"


def corpus_rows():
    rows = []
    for name, make in CASES.items():
        rs = make()
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "time stamps are jittery", NdlfdWarning)
            model = KeypointHMM(**rs.params).fit(rs.demos)
        duration = float(np.median([d.duration for d in rs.demos]))
        path = model.generate(np.linspace(0.0, duration, 300), dense=True)
        true = np.bincount(rs.labels).tolist()
        found = np.bincount(model.routes_).tolist()
        first: dict = {}
        same = [first.setdefault(x, len(first)) for x in model.routes_]
        first = {}
        want = [first.setdefault(x, len(first)) for x in rs.labels]
        err = route_error(rs, path)
        rows.append((name, len(rs.demos), true, found, same == want, err))
    return rows


def bumps(heights, n_points=32):
    tau = np.linspace(0.0, 1.0, n_points)
    bump = np.exp(-(((tau - 0.5) / 0.15) ** 2))
    return np.stack([np.column_stack([tau, h * bump]) for h in heights])


def split_rates(draws):
    out = []
    for law in ("uniform", "normal"):
        for n in (5, 8, 10, 12, 15, 20):
            bad = 0
            for seed in range(draws):
                rng = np.random.default_rng(seed)
                h = (
                    rng.uniform(-0.5, 0.5, n)
                    if law == "uniform"
                    else rng.normal(0, 0.3, n)
                )
                bad += int(split_routes(bumps(h)).max() > 0)
            out.append((law, n, bad / draws))
    return out


def cost():
    demos = synth.obstacle(150, 100, random_state=1)
    model = KeypointHMM().fit(demos)
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        model_routes(model)
        best = min(best, time.perf_counter() - t0)
    return len(model.template_indices_), best


def report(rows, rates, templates, seconds, draws):
    lines = [
        "## Routes: the corpus, false splits, cost",
        "",
        f"Command: `{COMMAND}`.",
        "",
        "| set | demos | true routes | found | same grouping | path's route error |",
        "|---|---:|---|---|:-:|---:|",
    ]
    for name, n, true, found, same, err in rows:
        lines.append(
            f"| {name} | {n} | {true} | {found} | {'yes' if same else 'NO'} |"
            f" {err:.3f} |"
        )
    lines += [
        "",
        f"False splits of one continuous spread (noiseless bumps, {draws} draws each):",
        "",
        "| heights | " + " | ".join(f"n={n}" for _, n, _ in rates[:6]) + " |",
        "|---|" + "---:|" * 6,
    ]
    for law in ("uniform", "normal"):
        cells = [f"{r:.1%}" for lw, _, r in rates if lw == law]
        lines.append(f"| {law} | " + " | ".join(cells) + " |")
    lines += [
        "",
        f"Route discovery alone on {templates} templates (obstacle, 150 + 100"
        f" demonstrations): {seconds * 1e3:.0f} ms (best of 5).",
    ]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=400)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    rows = corpus_rows()
    rates = split_rates(args.draws)
    templates, seconds = cost()
    text = report(rows, rates, templates, seconds, args.draws)
    print(text)
    if not args.no_write:
        write_section(text, START, END)


if __name__ == "__main__":
    main()
