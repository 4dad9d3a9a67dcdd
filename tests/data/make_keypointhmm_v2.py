"""Write tests/data/keypointhmm_v2.ndlfd, the committed KeypointHMM format-v2 fixture.

Format 2 (every training demonstration's normalized values stored whole) was
written by ndlfd up to commit bbb93c1; the fixture was made with that code:

    git archive bbb93c1 src/ndlfd | tar -x -C /tmp/v2
    PYTHONPATH=/tmp/v2/src .venv/bin/python tests/data/make_keypointhmm_v2.py

Today's code writes format 4, so this script cannot re-create the file; it is
kept to show what the file holds. The file also records what the model
generated on the grid below (blended generation, unconditioned and from a
start), so tests/learner/test_learner_persist.py notices a change of loading or
generation. When generation changes on purpose, those two CSV files are
recorded again from the committed model file with today's code:

    .venv/bin/python tests/data/make_keypointhmm_v2.py --record

(last: issue 27, the blend's time warps smoothed, ``WARP_SMOOTH``, and a
start's offset faded by the path's progress; the positions moved by at most
0.11 on a range of 11).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

FIXTURE = Path(__file__).with_name("keypointhmm_v2.ndlfd")
EXPECTED = Path(__file__).with_name("keypointhmm_v2_generated.csv")
EXPECTED_START = Path(__file__).with_name("keypointhmm_v2_generated_start.csv")
PARAMS = dict(
    groups=("position", "velocity"),
    levels={"position": 12, "velocity": 6},
    epsilon=0.1,
    n_time_bins=10,
)
GRID = np.linspace(0.0, 5.0, 26)
START = {"position": [0.2, -0.1]}


def build(**overrides):
    """Fit the fixture model (``overrides``: parameters that came later)."""
    from ndlfd import KeypointHMM, synth

    train, _ = synth.make_dataset("square", n_demos=6, random_state=11)
    return KeypointHMM(**PARAMS, **overrides).fit(train)


def main() -> None:
    """Write the model file and what it generates on GRID."""
    from ndlfd.io import write_csv

    model = build()
    model.save(FIXTURE)
    write_csv(model.generate(GRID, dense=True), EXPECTED)
    write_csv(model.generate(GRID, dense=True, start=START), EXPECTED_START)
    print(f"wrote {FIXTURE}, {EXPECTED} and {EXPECTED_START}")


def record() -> None:
    """Write what the committed model file generates today on GRID."""
    from ndlfd import KeypointHMM
    from ndlfd.io import write_csv

    model = KeypointHMM.load(FIXTURE)
    write_csv(model.generate(GRID, dense=True), EXPECTED)
    write_csv(model.generate(GRID, dense=True, start=START), EXPECTED_START)
    print(f"wrote {EXPECTED} and {EXPECTED_START} from {FIXTURE}")


if __name__ == "__main__":
    import sys

    record() if sys.argv[1:] == ["--record"] else main()
