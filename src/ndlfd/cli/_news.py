"""News while reading: one warning line per kind, silenced by ``-q``.

Re-exported by :mod:`ndlfd.cli._options`.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import re
import warnings

from .._errors import NdlfdWarning

__all__ = ["noting", "quiet_news", "tell"]


def quiet_news(command):
    """``command(args)`` with its :class:`~ndlfd.NdlfdWarning` lines silenced by ``-q``.

    The repairs of the data (dropped rows, skipped files) are news for the
    user, one line per kind; ``-q`` asks for none.
    """

    @functools.wraps(command)
    def run(args: argparse.Namespace):
        with warnings.catch_warnings():
            if getattr(args, "quiet", False):
                warnings.simplefilter("ignore", NdlfdWarning)
            return command(args)

    return run


@contextlib.contextmanager
def noting(source, news: list):
    """Collect the NdlfdWarnings raised while ``source`` is handled."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", NdlfdWarning)
        yield
    for w in caught:
        if issubclass(w.category, NdlfdWarning):
            news.append((str(source), " ".join(str(w.message).split())))
        else:  # pragma: no cover - not ndlfd's news: as it came
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def tell(news: list) -> None:
    """One warning line per kind of news, naming the first file and the count."""
    kinds: dict[str, list] = {}
    for source, text in news:
        kinds.setdefault(re.sub(r"[\d.]+", "#", text), []).append((source, text))
    for items in kinds.values():
        source, text = items[0]
        more = ""
        if len(items) > 1:
            others = [s for s, _ in items[1:]]
            shown = ", ".join(others[:3]) + (", ..." if len(others) > 3 else "")
            more = f" (likewise in {len(others)} more: {shown})"
        warnings.warn(f"{source}: {text}{more}", NdlfdWarning, stacklevel=2)
