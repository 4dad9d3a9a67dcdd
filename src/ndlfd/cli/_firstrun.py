"""Say once, on a command's first run, that ndlfd compiles its kernels.

ndlfd's kernels are compiled by numba the first time they run and cached
beside the code (``cache=True``), so the first ``ndlfd fit`` of an install
takes seconds more than the next (measured in the README). A marker file per
command and numba version in the package's ``__pycache__`` remembers that the
command has run; where that folder cannot be written, nothing is remembered.
Said on a terminal only (like a progress bar): scripts and tests that read
the command's standard error see the same lines on every run.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numba

from .. import __version__
from ._options import say

__all__ = ["COMPILING", "first_run_notice", "mark_run"]

#: Commands that run compiled kernels.
COMPILING = ("simplify", "fit", "generate", "sample", "plot", "demo", "reproduce",
             "evaluate")  # fmt: skip


def _marker(command: str) -> Path:
    folder = Path(__file__).resolve().parents[1] / "__pycache__"
    return folder / f"ndlfd-{__version__}-numba-{numba.__version__}-{command}.ran"


def first_run_notice(args: argparse.Namespace) -> bool:
    """Say (unless ``-q``) that this first run compiles kernels; whether it is one."""
    if args.command not in COMPILING or not sys.stderr.isatty():
        return False
    marker = _marker(args.command)
    if marker.exists():
        return False
    say(args, f"ndlfd {args.command}: first run of this install: compiling its"
        " kernels once (cached for the next runs)")  # fmt: skip
    return True


def mark_run(args: argparse.Namespace) -> None:
    """Remember that the command ran (its kernels are cached now)."""
    try:
        marker = _marker(args.command)
        marker.parent.mkdir(exist_ok=True)
        marker.touch()
    except OSError:  # a read-only install: numba caches elsewhere, or not at all
        pass
