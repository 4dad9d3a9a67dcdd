"""Write tests/data/hmm_v1.npz, the committed DiscreteHMM format-v1 fixture.

Run from the repository root:  .venv/bin/python tests/data/make_hmm_v1.py

The training data are the constants below (also imported by
tests/hmm/test_hmm_format.py, which rebuilds the model and compares it with the
loaded file). Re-run only on a deliberate format change, together with a new
version number.
"""

from __future__ import annotations

from pathlib import Path

N_STATES = 12
N_SYMBOLS = 4
PSEUDO_TRANSITION = None  # 1 / N_STATES
PSEUDO_EMISSION = 0.25
STATES = [[1, 3, 3, 7, 9], [1, 3, 7, 7, 9, 9], [2, 3, 7, 9]]
SYMBOLS = [[0, 1, 1, 2, 3], [0, 0, 1, 2, 3, 3], [0, 1, 2, 3]]
DECODE = [0, 1, 2, 2, 3]
# viterbi(model, DECODE) as written on 2026-11-23 (format version 1)
EXPECTED_PATH = [1, 3, 7, 7, 9]

FIXTURE = Path(__file__).with_name("hmm_v1.npz")


def build():
    """Estimate the fixture model from the constants above."""
    from ndlfd.hmm import estimate

    return estimate(
        STATES,
        SYMBOLS,
        N_STATES,
        N_SYMBOLS,
        pseudo_transition=PSEUDO_TRANSITION,
        pseudo_emission=PSEUDO_EMISSION,
    )


if __name__ == "__main__":
    build().save(FIXTURE)
    print(f"wrote {FIXTURE}")
