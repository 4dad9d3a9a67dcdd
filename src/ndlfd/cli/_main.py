"""The ``ndlfd`` parser with every command, and :func:`main`."""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Sequence

from .. import __version__
from .._errors import NdlfdError, NdlfdWarning
from ._firstrun import first_run_notice, mark_run
from ._fit import add_fit
from ._generate import add_generate
from ._jobs import add_evaluate, add_jobs
from ._options import EXIT_USAGE, Parser
from ._plot import add_plot
from ._sample import add_sample
from ._simplify import add_simplify

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """Build the ``ndlfd`` argument parser with all sub-commands."""
    parser = Parser(
        prog="ndlfd",
        description=(
            "Learn robot paths from demonstrations: n-dimensional Douglas-Peucker"
            " key points, a codebook of discrete states and a supervised discrete"
            " HMM. A path for a new timing blends the demonstrations aligned to"
            " the key points decoded for it (the default; 'ndlfd fit --generation"
            " paper' gives the paper's procedure: Viterbi over the time bins, cell"
            " centres, straight lines)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"ndlfd {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    add_simplify(sub)
    add_fit(sub)
    add_generate(sub)
    add_sample(sub)
    add_plot(sub)
    add_jobs(sub)
    add_evaluate(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``ndlfd`` command line; return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return EXIT_USAGE
    command = args.command

    def one_line(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        print(f"ndlfd {command}: warning: {text}", file=sys.stderr)

    first = first_run_notice(args)
    try:
        with warnings.catch_warnings():
            # repairs of the data are news for the user, one line each
            warnings.simplefilter("always", NdlfdWarning)
            warnings.showwarning = one_line
            status = int(args.func(args) or 0)
        if first and status == 0:
            mark_run(args)
        return status
    except NdlfdError as exc:
        print(f"ndlfd {command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        print(f"ndlfd {command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"ndlfd {command}: interrupted", file=sys.stderr)
        return 130
