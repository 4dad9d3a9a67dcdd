"""Task success in the simulator (issue 40): ``ndlfd evaluate --tasks``, timed.

Runs :func:`ndlfd.jobs._tasks.evaluate_tasks` on Transfer Cube and
Insertion (the ALOHA scenes of gym-aloha, extra ``sim``; ProMP needs the
extra ``eval``) and writes the report (``results.csv``, ``summary.md``, the
success curve and the top views of failed episodes) to ``--out``, printing
the summary table. The same as::

    ndlfd evaluate --tasks transfer-cube,insertion --demos 5,10,20,50 --episodes 200

Run: ``.venv/bin/python benchmarks/bench_tasks.py [--episodes N] [--demos
5,10,20,50] [--out DIR]`` (200 held-out poses per cell: about an hour per
task on one core; ``--episodes 20`` about five minutes).
"""

from __future__ import annotations

import argparse
import sys

from ndlfd.jobs._tasks import evaluate_tasks


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tasks", default="transfer-cube,insertion")
    p.add_argument("--demos", default="5,10,20,50")
    p.add_argument("--episodes", type=int, default=200)
    p.add_argument("--out", default="tasks-evaluation")
    args = p.parse_args(argv)
    result = evaluate_tasks(
        args.tasks.split(","),
        demos=[int(n) for n in args.demos.split(",")],
        episodes=args.episodes,
        echo=lambda line: print(line, file=sys.stderr),
    )
    result.write_report(args.out)
    print(result.to_markdown())
    print(f"{len(result.rows)} episodes in {result.seconds:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
