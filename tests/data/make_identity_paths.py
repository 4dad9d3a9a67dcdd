"""Write tests/data/identity_paths.npz, the paths test_learner_identity.py expects.

Each case of the test is fitted on the stored inputs (identity_inputs.npz) and
its path generated; the script checks each path's digest against the known
digest of commit 8de859a before writing. It was run with OpenBLAS's Haswell
kernel, the one those digests were made with:

    OPENBLAS_CORETYPE=Haswell .venv/bin/python tests/data/make_identity_paths.py

With another kernel the last bits differ (the test allows for that) and the
check below refuses to write.
"""

from __future__ import annotations

import hashlib
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

#: Digests of the paths at commit 8de859a (when they were in the test's KNOWN).
DIGESTS = {
    "arm": "3de3b0ad70460fee",
    "arm-segment-weights": "2282804d341580b0",
    "loops-none": "68155d117e76eefc",
    "loops-paper": "ae4f6fbf59ffcc42",
    "loops-sed-budget": "8ada2ea9d196370b",
}


def _digest(a) -> str:
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"{a.dtype.str}{a.shape}".encode())
    h.update(a.tobytes())
    return h.hexdigest()[:16]


def main() -> None:
    sys.path.insert(0, str(HERE.parent / "learner"))
    import test_learner_identity as cases

    paths = {}
    warnings.simplefilter("ignore")  # the test itself checks the warnings
    for name in sorted(cases.CASES):
        with tempfile.TemporaryDirectory() as tmp:
            _, X = cases.fit_digests(name, Path(tmp))
        if _digest(X) != DIGESTS[name]:
            raise SystemExit(f"{name}: the path is not the one of 8de859a; not written")
        paths[name] = X
    np.savez_compressed(cases.PATHS, **paths)
    print(f"wrote {cases.PATHS}")


if __name__ == "__main__":
    main()
