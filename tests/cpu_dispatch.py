"""Print the numpy CPU features to disable to simulate a smaller machine.

``make test-portable`` runs the identity tests and a smoke with numpy's
dispatch limited (``NPY_DISABLE_CPU_FEATURES``) and numba at a generic CPU,
so that a machine unlike the developer's is simulated on every run (issue 25).
numpy names its dispatch targets differently across versions (``AVX512F``,
``AVX512_SKX`` ... up to 2.3; ``X86_V4``, ``AVX512_ICL`` ... from 2.4), so the
names are read from numpy itself: every dispatched feature of the level asked
for and above, whether or not this machine has it (numpy accepts disabling a
feature the machine lacks, and refuses a name it does not dispatch).

Usage: ``python tests/cpu_dispatch.py avx512`` (no AVX-512: an AVX2 machine)
or ``python tests/cpu_dispatch.py avx2`` (no AVX2, FMA or AVX-512 either).
"""

from __future__ import annotations

import sys

#: Name prefixes of numpy's dispatch targets at each level, and above it.
LEVELS = {
    "avx512": ("AVX512", "X86_V4"),
    "avx2": ("AVX512", "X86_V4", "AVX2", "FMA3", "X86_V3", "AVX_VNNI"),
}


def features(level: str) -> list[str]:
    """The dispatched numpy features at ``level`` and above."""
    try:
        prefixes = LEVELS[level]
    except KeyError:
        msg = f"level must be one of {', '.join(LEVELS)}; got {level!r}"
        raise SystemExit(msg) from None
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__ as dispatch
    except ImportError:  # numpy < 2
        from numpy.core._multiarray_umath import __cpu_dispatch__ as dispatch
    return [f for f in dispatch if f.startswith(prefixes)]


if __name__ == "__main__":
    print(" ".join(features(sys.argv[1] if len(sys.argv) > 1 else "avx512")))
