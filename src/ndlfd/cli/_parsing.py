"""Parsing the values of flags: comma-separated names and numbers, ranges, outputs.

Re-exported by :mod:`ndlfd.cli._options`, where every command takes them.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from .._errors import ValidationError

__all__ = [
    "check_output",
    "check_range",
    "parse_floats",
    "parse_pairs",
    "split_names",
]


# ------------------------------------------------------------------ parsing
def split_names(text: str | None, flag: str) -> list[str] | None:
    """``a,b,c`` strictly: no empty entry (a trailing comma is an error)."""
    if text is None:
        return None
    names = [s.strip() for s in text.split(",")]
    if not text.strip() or any(not s for s in names):
        raise ValidationError(
            f"{flag} must be a comma-separated list of names without empty entries;"
            f" got {text!r}"
        )
    dup = next((s for s in names if names.count(s) > 1), None)
    if dup is not None:
        raise ValidationError(f"{flag} names {dup!r} twice; got {text!r}")
    return names


def parse_floats(text: str | None, flag: str) -> list[float] | None:
    if text is None:
        return None
    try:
        values = [float(s) for s in text.split(",")]
    except ValueError:
        raise ValidationError(
            f"{flag} must be comma-separated numbers; got {text!r}"
        ) from None
    if not all(math.isfinite(v) for v in values):
        raise ValidationError(f"{flag} must be finite numbers; got {text!r}")
    return values


def parse_pairs(text: str, flag: str, cast, example: str) -> dict:
    """``name=value,name=value`` strictly (no empty entry, no repeated name)."""
    out: dict = {}
    for part in text.split(","):
        part = part.strip()
        if not part:
            raise ValidationError(
                f"{flag} must look like {example}; got {text!r} (an empty entry:"
                " a trailing or doubled comma)"
            )
        if "=" not in part:
            raise ValidationError(f"{flag} must look like {example}; got {text!r}")
        key, _, value = part.partition("=")
        key, value = key.strip(), value.strip()
        if not key:
            raise ValidationError(
                f"{flag} must look like {example}; got {part!r} without a name"
            )
        if key in out:
            raise ValidationError(f"{flag} names {key!r} twice; got {text!r}")
        try:
            out[key] = cast(value)
        except ValueError:
            raise ValidationError(
                f"{flag}: {value!r} is not a valid number in {text!r}"
            ) from None
    return out


def check_range(value, flag: str, low=None, high=None) -> None:
    """One message for every bounded setting: ``FLAG must be ... ; got V``."""
    ok = value is not None and math.isfinite(value)
    if ok and low is not None:
        ok = value >= low
    if ok and high is not None:
        ok = value <= high
    if ok:
        return
    noun = "an integer" if isinstance(value, int) else "a finite number"
    if low is not None and high is not None:
        bound = f"between {low} and {high}"
    elif low is not None:
        bound = f"{noun} >= {low}"
    else:
        bound = f"{noun} <= {high}"
    raise ValidationError(f"{flag} must be {bound}; got {value}")


def check_output(path: str, flag: str = "-o") -> Path:
    """Refuse an output that is a folder or lies in a missing folder."""
    p = Path(path)
    if p.is_dir():
        raise ValidationError(
            f"{flag} {path}: is a folder; expected a file name (e.g."
            f" {p / ('out' + (p.suffix or '.csv'))})"
        )
    parent = p.parent
    if not parent.exists():
        raise ValidationError(
            f"{flag} {path}: the folder {parent} does not exist; create it first"
        )
    if not parent.is_dir():
        raise ValidationError(f"{flag} {path}: {parent} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValidationError(f"{flag} {path}: the folder {parent} is not writable")
    return p
