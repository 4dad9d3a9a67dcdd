"""Write tests/data/keypointhmm_v1.ndlfd, the committed KeypointHMM format-v1 fixture.

Run from the repository root:  .venv/bin/python tests/data/make_keypointhmm_v1.py

The model is fitted on a small seeded synthetic set; the file also records what
it generated on the grid below when it was written (format version 1), so a
change of the format or of generation is noticed by
tests/learner/test_learner_estimator.py.
Re-run only on a deliberate change, together with a new version number.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

FIXTURE = Path(__file__).with_name("keypointhmm_v1.ndlfd")
EXPECTED = Path(__file__).with_name("keypointhmm_v1_generated.csv")
PARAMS = dict(
    groups=("position", "velocity"),
    levels={"position": 12, "velocity": 6},
    epsilon=0.1,
    n_time_bins=10,
)
GRID = np.linspace(0.0, 5.0, 26)


def build():
    """Fit the fixture model."""
    from ndlfd import KeypointHMM, synth

    train, _ = synth.make_dataset("square", n_demos=6, random_state=11)
    return KeypointHMM(**PARAMS, generation="paper").fit(train)


def main() -> None:
    """Write the model file and what it generates on GRID."""
    from ndlfd.io import write_csv

    model = build()
    model.save(FIXTURE)
    write_csv(model.generate(GRID, dense=True), EXPECTED)
    print(f"wrote {FIXTURE} and {EXPECTED}")


if __name__ == "__main__":
    main()
