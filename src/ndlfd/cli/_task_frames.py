"""``ndlfd fit --task-frame NAME=COL,...``: columns that are a demonstration's frame.

A task frame is a pose constant over a demonstration (where the object or the
place was; :class:`~ndlfd.Demonstration`'s ``frames``). Training files may
record it as columns whose value is the same on every row: ``--task-frame
object=ox,oy,oz,oqw,oqx,oqy,oqz`` makes those columns the demonstration's
frame ``object`` (position, then optionally a unit quaternion w,x,y,z), and
they are not learned as data.

The columns are read with the file, by the same column mapping as the others
(names in any case, ``--bad-rows``, ``--rate``): each frame is a group of its
own under a hidden name (:data:`FRAME_GROUP` and the frame's name), taken out
of the demonstration afterwards (:func:`read_framed`). The files of a fit are
read on the workers: :class:`FramedDemoFiles` gives them
:class:`FramedDemoFile` items that read so. Every error names the file and
``--task-frame``.

A ROS 2 bag or a LeRobot episode names its frames by where they are recorded
instead of by columns: ``--task-frame object=/object_pose`` (a topic) or
``object=tf:object_frame`` (a tf frame) of a bag, ``object=observation.
object_pose`` (a feature) of a dataset; their readers take them as ``frames``
(:func:`~ndlfd.io.read_bag`, :func:`~ndlfd.io.read_lerobot`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from functools import partial
from pathlib import Path

import numpy as np

from .._errors import DataFileError, ValidationError
from .._pose_groups import pose_dims
from .._poses import check_frames, pose_size_ok
from ..io import (
    CLI_HINTS,
    ColumnMapping,
    DemoFile,
    DemoFiles,
    read_file,
    read_or_skip,
)
from ..io._bag import BAG_SUFFIXES, is_bag_folder
from ..io._files import RateMapping
from ..io._lerobot import LeRobotEpisode
from ._conditions import flag_named, parse_named
from ._options import split_names

__all__ = [
    "FRAME_GROUP",
    "FramedDemoFile",
    "FramedDemoFiles",
    "FramedMapping",
    "parse_frame_columns",
    "read_framed",
    "read_framed_or_skip",
]

#: The prefix of the hidden group a frame's columns are read into.
FRAME_GROUP = "_task-frame_"

#: How much a frame column may vary over a file, relative to its largest
#: magnitude (at least 1): the rounding of a value written as text.
CONSTANT_TOLERANCE = 1e-9

_EXAMPLE = "NAME=COLUMN,COLUMN,... (e.g. object=obj_x,obj_y,obj_z)"


def parse_frame_columns(texts: list[str] | None) -> dict | None:
    """Repeated ``--task-frame`` flags of ``ndlfd fit`` as ``{name: columns}``.

    Examples
    --------
    >>> parse_frame_columns(["object=ox,oy,oz", "place=px,py,pz"])
    {'object': ['ox', 'oy', 'oz'], 'place': ['px', 'py', 'pz']}
    """
    if not texts:
        return None
    return parse_named(texts, "--task-frame", _EXAMPLE, split_names)


def _framed_text(text: str, frames) -> str:
    return "; ".join(
        [text, *(f"task frame {n}={','.join(cols)}" for n, cols in frames)]
    )


@dataclass(frozen=True)
class FramedMapping(ColumnMapping):
    """A :class:`~ndlfd.io.ColumnMapping` that also names the frames' columns.

    Attributes
    ----------
    frames : tuple of (str, tuple of str)
        Each task frame with the file's names of its columns.

    Examples
    --------
    >>> m = FramedMapping("a.csv", "t", (("position", ("x", "y")),),
    ...                   frames=(("object", ("ox", "oy")),))
    >>> str(m)
    'time=t; position=x,y; task frame object=ox,oy'
    """

    frames: tuple = ()

    def __str__(self) -> str:
        return _framed_text(super().__str__(), self.frames)


@dataclass(frozen=True)
class _FramedRateMapping(RateMapping):
    """A :class:`FramedMapping` of a file read at a fixed rate (``--rate``)."""

    frames: tuple = ()

    def __str__(self) -> str:
        return _framed_text(super().__str__(), self.frames)


def _hidden(name: str) -> str:
    return FRAME_GROUP + name


def _renamed(exc: Exception, frames: dict) -> Exception:
    """The reader's error with the hidden groups named as the flag names them."""
    text = str(exc).replace(f"{CLI_HINTS['groups']} maps", "the flags map")
    for name in frames:
        text = text.replace(
            f"{CLI_HINTS['groups']} {_hidden(name)}", f"--task-frame {name}"
        )
        text = text.replace(f"'{_hidden(name)}'", f"--task-frame {name}")
    return type(exc)(text)


def read_framed(p: Path | LeRobotEpisode, how, frames: dict, **mapping) -> list:
    """:func:`~ndlfd.io.read_file` with the columns of ``frames`` as task frames.

    Parameters
    ----------
    p : Path or LeRobotEpisode
    how : dict
        ``CLI_HINTS``.
    frames : dict of str to list of str
        Each frame's columns (:func:`parse_frame_columns`).
    **mapping
        The column mapping (:func:`~ndlfd.cli._options.column_options`).

    Returns
    -------
    pairs : list of (Demonstration, FramedMapping)
        Each demonstration with its frames, without their columns.
    """
    if (
        isinstance(p, LeRobotEpisode)
        or is_bag_folder(p)
        or (p.suffix.lower() in BAG_SUFFIXES)
    ):
        return _read_recorded(p, how, frames, mapping)
    groups = dict(mapping.get("groups") or {})
    for name, cols in frames.items():
        groups[_hidden(name)] = list(cols)
    try:
        pairs = read_file(p, how, **{**mapping, "groups": groups})
    except (DataFileError, ValidationError) as exc:
        if any(_hidden(name) in str(exc) for name in frames):
            raise _renamed(exc, frames) from None
        raise
    return [_taken_out(demo, m, frames) for demo, m in pairs]


def _read_recorded(p, how, frames: dict, mapping: dict) -> list:
    """A bag's or an episode's demonstrations with the frames their reader took."""
    episode = isinstance(p, LeRobotEpisode)
    example = "observation.object_pose" if episode else "/object_pose"
    sources = {}
    for name, cols in frames.items():
        if len(cols) != 1:
            what = (
                "a feature (such as observation.object_pose)"
                if episode
                else "a topic (such as /object_pose) or a tf frame (such as"
                " tf:object_frame)"
            )
            raise ValidationError(
                f"--task-frame {name} names {len(cols)} columns"
                f" ({','.join(cols)}); {p} is a"
                f" {'LeRobot episode' if episode else 'ROS 2 bag'}, whose frame is"
                f" {what}: --task-frame {name}={example}"
            )
        sources[name] = cols[0]
    out = []
    for demo, m in read_file(p, how, **{**mapping, "frames": sources}):
        own = {f.name: getattr(m, f.name) for f in fields(m)}
        own["frames"] = tuple((n, (s,)) for n, s in sources.items())
        out.append((demo, FramedMapping(**own)))
    return out


def _taken_out(demo, m: ColumnMapping, frames: dict):
    """The demonstration without its frame columns, and with its frames."""
    read = dict(m.groups)
    missing = [n for n in frames if _hidden(n) not in read]
    if missing:  # a reader that does not map columns by name
        raise DataFileError(
            f"{m.source}: --task-frame {missing[0]} names columns"
            f" {','.join(frames[missing[0]])}, which were not read from it"
        )
    dims = pose_dims(demo.groups)
    poses, shown = {}, []
    for name in frames:
        g = _hidden(name)
        cols = read[g]
        if not pose_size_ok(len(cols), dims):
            seven = " or 7 (x, y, z, then a unit quaternion qw, qx, qy, qz)"
            want = (
                f"{dims} (a position, as the position group of {m.source})"
                if dims
                else f"2 or 3 (a position: {m.source} has no position group)"
            )
            raise ValidationError(
                f"--task-frame {name} names {len(cols)} column(s); expected"
                f" {want}" + (seven if dims in (3, None) else "")
            )
        block = demo.get(g)
        lo, hi = block.min(axis=0), block.max(axis=0)
        scale = np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)))
        varies = np.flatnonzero(hi - lo > CONSTANT_TOLERANCE * scale)
        if varies.size:
            j = int(varies[0])
            raise DataFileError(
                f"{m.source}: --task-frame {name}: column {cols[j]!r} must be"
                " constant over the demonstration (a task frame is one pose per"
                " demonstration);"
                f" got values from {lo[j]:.10g} to {hi[j]:.10g}"
            )
        poses[name] = block[0]
        shown.append((name, tuple(cols)))
    kept = [g for g in demo.group_names if not g.startswith(FRAME_GROUP)]
    if not kept:
        raise DataFileError(
            f"{m.source}: expected value columns besides the time column and the"
            " task frames' (--task-frame); got none"
        )
    try:
        checked = check_frames(poses, dims, what=f"{m.source}: --task-frame")
    except ValidationError as exc:
        raise DataFileError(flag_named(exc)) from None
    demo = demo.select(*kept).with_frames(checked)
    own = {f.name: getattr(m, f.name) for f in fields(m)}
    own["groups"] = tuple((g, c) for g, c in m.groups if not g.startswith(FRAME_GROUP))
    hidden = {k for g, ks in m.groups if g.startswith(FRAME_GROUP) for k in ks}
    own["order"] = tuple(k for k in m.order if k not in hidden)
    own["frames"] = tuple(shown)
    cls = _FramedRateMapping if isinstance(m, RateMapping) else FramedMapping
    return demo, cls(**own)


def read_framed_or_skip(p, how, frames: dict | None, **mapping) -> list:
    """:func:`read_framed`, or nothing for a bad file with ``--bad-files skip``.

    As :func:`~ndlfd.io.read_or_skip` (a skipped file is reported as a repair);
    without ``frames``, that function.
    """
    if not frames:
        return read_or_skip(p, how, **mapping)
    return read_or_skip(p, how, read=partial(read_framed, frames=frames), **mapping)


@dataclass(frozen=True)
class FramedDemoFile(DemoFile):
    """A :class:`~ndlfd.io.DemoFile` whose demonstrations carry task frames.

    Attributes
    ----------
    frames : tuple of (str, tuple of str)
        Each frame with its columns.
    """

    frames: tuple = field(default=())

    def read_with_mappings(self) -> list:
        """The file's demonstrations with their frames, and the mappings used."""
        frames = {name: list(cols) for name, cols in self.frames}
        return read_framed_or_skip(self.path, CLI_HINTS, frames, **self.mapping)


class FramedDemoFiles(DemoFiles):
    """The files of ``ndlfd fit --task-frame``: :class:`FramedDemoFile` items."""

    frames: tuple = ()

    @classmethod
    def for_cli(cls, paths, frames: dict | None = None, **mapping) -> DemoFiles:
        """The files ``paths``, read for the command line with ``frames``.

        Parameters
        ----------
        paths : sequence of path-like
        frames : dict of str to list of str, optional
            Each task frame's columns (:func:`parse_frame_columns`); without
            them, a plain :class:`~ndlfd.io.DemoFiles`.
        **mapping
            As for :class:`~ndlfd.io.DemoFiles`.
        """
        if not frames:
            return DemoFiles.for_cli(paths, **mapping)
        files = super().for_cli(paths, **mapping)
        files.frames = tuple((n, tuple(c)) for n, c in frames.items())
        return files

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return FramedDemoFile(
            self.paths[i], dict(self._mapping), self.hints, frames=self.frames
        )
