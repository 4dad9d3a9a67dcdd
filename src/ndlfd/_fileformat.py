"""The one file format of ndlfd: ``.npz`` arrays plus JSON metadata, never pickle.

A file written by :func:`save_npz` is a plain numpy ``.npz`` archive. Besides the
caller's arrays it holds one entry, ``__ndlfd__``, a 0-d unicode string with JSON
metadata: ``{"format": "ndlfd", "kind": KIND, "version": N, ...}``. Loading uses
``allow_pickle=False`` so nothing in the file can run code; any file that is not
such an archive of the expected kind and version is refused with
:class:`~ndlfd.ModelFormatError`. Writes go to a temporary file in the same folder
and are renamed into place, so a crash never leaves a half-written file.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import zipfile
from collections.abc import Iterator, Mapping
from pathlib import Path

import numpy as np

from ._errors import ModelFormatError

__all__ = ["atomic_path", "load_npz", "save_npz"]

_META_KEY = "__ndlfd__"
META_KEY = _META_KEY  # public: io tells an ndlfd archive from a plain one


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = "") -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it into place on success.

    Parameters
    ----------
    path : str or path-like
        The final destination.
    suffix : str, default=""
        Suffix of the temporary file (some writers, such as matplotlib, choose the
        format from it).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_path(d / "a.txt") as tmp:
    ...     _ = tmp.write_text("hello")
    >>> (d / "a.txt").read_text()
    'hello'
    """
    final = Path(path)
    final.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{final.name}.", suffix=suffix + ".tmp", dir=final.parent
    )
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        # mkstemp makes the file private (0600); give it the mode a plain open()
        # would have: the existing file's, or 0666 less the umask
        try:
            mode = final.stat().st_mode & 0o7777
        except FileNotFoundError:
            mode = 0o666 & ~_umask()
        os.chmod(tmp_path, mode)
        os.replace(tmp_path, final)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def save_npz(
    path: str | os.PathLike,
    arrays: Mapping[str, np.ndarray],
    *,
    kind: str,
    version: int,
    metadata: Mapping | None = None,
    compress: bool = True,
) -> Path:
    """Write ``arrays`` and JSON ``metadata`` atomically to an ``.npz`` file.

    Parameters
    ----------
    path : str or path-like
        Destination (written as given; no suffix is added).
    arrays : mapping of str to ndarray
        Numeric arrays (object arrays are refused).
    kind : str
        What the file holds, checked on load (for example ``"DiscreteHMM"``).
    version : int
        The format version of ``kind``, checked on load.
    metadata : mapping, optional
        JSON-serialisable values stored beside the arrays.
    compress : bool, default=True
        Deflate the arrays (``np.savez_compressed``); ``False`` stores them as
        they are (``np.savez``), larger but about twice as fast to read.

    Returns
    -------
    path : Path
    """
    meta = {"format": "ndlfd", "kind": kind, "version": int(version)}
    meta.update(metadata or {})
    payload = {}
    for key, value in arrays.items():
        a = np.asarray(value)
        if a.dtype == object:
            raise TypeError(f"array {key!r} has dtype object, which is not saved")
        payload[key] = a
    payload[_META_KEY] = np.array(json.dumps(meta, sort_keys=True))
    final = Path(path)
    with atomic_path(final) as tmp, open(tmp, "wb") as fh:
        (np.savez_compressed if compress else np.savez)(fh, **payload)
    return final


def _noun(kind: str) -> str:
    return "demonstration" if kind == "Demonstration" else "model"


def _describe_file(p: Path) -> str:
    """What a file that is not an ``.npz`` archive looks like, from its bytes."""
    try:
        with open(p, "rb") as fh:
            head = fh.read(512)
    except OSError as exc:
        return f"a file that cannot be read ({exc.strerror})"
    if not head:
        return "an empty file"
    if head.startswith(b"\x93NUMPY"):
        return "a plain .npy array"
    if head.startswith(b"\x89HDF\r\n\x1a\n"):
        return "an HDF5 file"
    if head[:1] == b"\x80" and head[1:2] in (b"\x02", b"\x03", b"\x04", b"\x05"):
        return "a Python pickle, which ndlfd never loads (it could run code)"
    if b"\x00" not in head:
        try:
            text = head.decode("utf-8")
        except UnicodeDecodeError as exc:
            text = (
                head[: exc.start].decode("utf-8") if exc.start > len(head) - 4 else None
            )
        if text is not None:
            body = text.lstrip("\ufeff \t\r\n")
            if body[:1] in ("{", "["):
                return "a JSON text file"
            first = body.splitlines()[0] if body else ""
            return f"a text file starting {first[:40]!r} (a CSV file?)"
    return "a binary file of an unknown kind"


def load_npz(
    path: str | os.PathLike, *, kind: str, version: int | tuple[int, ...]
) -> tuple[dict[str, np.ndarray], dict]:
    """Read a file written by :func:`save_npz`, refusing anything else.

    Nothing is ever unpickled: a file that is not such an archive (a CSV, JSON
    or pickle file, a plain ``.npz`` archive, another kind or version) is
    refused with a one-line :class:`~ndlfd.ModelFormatError` that says what the
    file is instead.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    kind : str
        The expected kind.
    version : int or tuple of int
        The format version(s) this code reads (``metadata["version"]`` tells
        which one a file has).

    Returns
    -------
    arrays : dict of str to ndarray
    metadata : dict
    """
    p = Path(path)
    wrong = _not_a(p, kind)
    if p.is_dir():
        raise ModelFormatError(f"{p}: is a folder; expected an ndlfd {kind} file")
    arrays = read_archive(p, ModelFormatError, f"{wrong} (.npz archive)")
    return parse_metadata(arrays, p, kind=kind, version=version)


def _not_a(p: Path, kind: str) -> str:
    """The head of the error for a file that is not an ndlfd ``kind`` file."""
    return f"{p}: not an ndlfd {_noun(kind)} file: expected an ndlfd {kind} file"


def read_archive(p: Path, error: type[Exception], expected: str) -> dict:
    """Every array of the ``.npz`` archive ``p``, never unpickling anything.

    ``error`` is raised (with ``expected`` saying what the file should have
    been) for a missing file or one that is not a readable archive.
    """
    if not p.is_file():
        raise error(f"{p}: no such file")
    with open(p, "rb") as fh:
        magic = fh.read(4)
    if magic not in (b"PK\x03\x04", b"PK\x05\x06"):
        raise error(f"{expected}; got {_describe_file(p)}, not readable as one")
    try:
        with open(p, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        reason = f"{type(exc).__name__}: {exc}"
        if "pickle" in str(exc).lower():
            reason = "it holds pickled Python objects, which ndlfd never loads"
        raise error(f"{expected}; the file is not readable as one ({reason})") from None


def parse_metadata(
    arrays: dict, p: Path, *, kind: str, version: int | tuple[int, ...]
) -> tuple[dict[str, np.ndarray], dict]:
    """Split the ndlfd metadata off ``arrays`` (read from ``p``) and check it."""
    wrong = _not_a(p, kind)
    arrays = dict(arrays)
    raw = arrays.pop(_META_KEY, None)
    if raw is None or raw.shape != () or raw.dtype.kind != "U":
        raise ModelFormatError(
            f"{wrong}; got an .npz archive without ndlfd metadata (a foreign file)"
        )
    try:
        meta = json.loads(str(raw))
    except json.JSONDecodeError as exc:
        raise ModelFormatError(f"{p}: the metadata is not valid JSON ({exc})") from None
    if not isinstance(meta, dict) or meta.get("format") != "ndlfd":
        raise ModelFormatError(f"{p}: expected ndlfd metadata; got {meta!r:.200}")
    if meta.get("kind") != kind:
        raise ModelFormatError(f"{wrong}; got a {meta.get('kind')!r} file")
    accepted = (version,) if isinstance(version, int) else tuple(version)
    if meta.get("version") not in accepted:
        wanted = " or ".join(str(v) for v in accepted)
        raise ModelFormatError(
            f"{p}: expected {kind} format version {wanted}; got version"
            f" {meta.get('version')!r} (written by another ndlfd release)"
        )
    return arrays, meta
