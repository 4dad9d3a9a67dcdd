"""Write tests/data/keypointhmm_v4.ndlfd, the committed KeypointHMM format-v4 fixture.

Format 4 numbered every state by its codebook cell in mixed radix
(``stats_centroid_states``); format 5 (issue 37) interns the visited cells.
The fixture was made with the code of commit 3b2d5ab, the last to write
format 4:

    git worktree add /tmp/v4 3b2d5ab
    PYTHONPATH=/tmp/v4/src .venv/bin/python tests/data/make_keypointhmm_v4.py

It also records what that code generated on the grid below (unconditioned,
from a start, and the paper's key points), so
tests/learner/test_learner_persist.py checks that today's code loads the file
into the same model and path. When generation changes on purpose, the CSV
files are recorded again from the committed model file with today's code:

    .venv/bin/python tests/data/make_keypointhmm_v4.py --record
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
FIXTURE = HERE / "keypointhmm_v4.ndlfd"
EXPECTED = HERE / "keypointhmm_v4_generated.csv"
EXPECTED_START = HERE / "keypointhmm_v4_generated_start.csv"
PARAMS = dict(epsilon=0.05, n_time_bins=20, random_state=4)
GRID = np.linspace(0.0, 5.0, 41)
START = {"position": [0.25, -0.1]}


def build(**overrides):
    """Fit the fixture model (``overrides``: parameters that came later)."""
    from ndlfd import KeypointHMM, synth

    train, _ = synth.make_dataset("square", n_demos=8, random_state=21)
    return KeypointHMM(**PARAMS, **overrides).fit(train)


def _write(model) -> None:
    from ndlfd.io import write_csv

    write_csv(model.generate(GRID, dense=True), EXPECTED)
    write_csv(model.generate(GRID, dense=True, start=START), EXPECTED_START)


def main() -> None:
    """Write the model file and what it generates on GRID."""
    model = build()
    model.save(FIXTURE)
    _write(model)
    print(f"wrote {FIXTURE}, {EXPECTED} and {EXPECTED_START}")


def record() -> None:
    """Write what the committed model file generates today on GRID."""
    from ndlfd import KeypointHMM

    _write(KeypointHMM.load(FIXTURE))
    print(f"wrote {EXPECTED} and {EXPECTED_START} from {FIXTURE}")


if __name__ == "__main__":
    import sys

    record() if sys.argv[1:] == ["--record"] else main()
