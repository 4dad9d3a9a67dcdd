"""The examples of the README and the user guides, found and run as written.

A shell example is a ``$ ndlfd ...`` line of a ``console`` block; it runs as a
command of this source tree. A Python example is a ``python`` block: in the
guides a doctest (``>>>``), in the README's quickstart a script.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GUIDES = ROOT / "docs" / "guides"
BIN = Path(sys.executable).parent / "ndlfd"

HEADING = re.compile(r"^(#+) .*$", re.M)
COMMAND = re.compile(r"^\$ (ndlfd .+)$", re.M)
PYTHON = re.compile(r"^```python\n(.*?)^```", re.M | re.S)


def section(text: str, heading: str) -> str:
    """The text under the line ``heading`` (``"## Title"``) to the next heading."""
    lines = text.splitlines(keepends=True)
    starts = [i for i, line in enumerate(lines) if line.rstrip("\n") == heading]
    assert len(starts) == 1, f"{heading!r} is {len(starts)} times a heading"
    rest = "".join(lines[starts[0] + 1 :])
    stop = HEADING.search(rest)
    return rest[: stop.start()] if stop else rest


def commands(text: str) -> list[list[str]]:
    """The ``$ ndlfd`` lines of ``text``, split as a shell splits them."""
    return [shlex.split(m, comments=True) for m in COMMAND.findall(text)]


def sections_with_commands(text: str) -> dict[str, list[list[str]]]:
    """Each heading under which ``$ ndlfd`` lines stand, with those lines."""
    found = {}
    bounds = [*HEADING.finditer(text)]
    for i, head in enumerate(bounds):
        end = bounds[i + 1].start() if i + 1 < len(bounds) else len(text)
        here = commands(text[head.end() : end])
        if here:
            found[head.group(0)] = here
    return found


def python_blocks(text: str) -> list[str]:
    """The contents of the ``python`` blocks of ``text``."""
    return PYTHON.findall(text)


def run(args: list[str], cwd: Path) -> None:
    """Run one ``ndlfd ...`` example in ``cwd``; it must succeed, warning-free."""
    env = dict(os.environ, PYTHONWARNINGS="error")
    # this source tree, also from the examples' folder (PYTHONPATH=src)
    paths = env.get("PYTHONPATH", "").split(os.pathsep)
    env["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in paths if p)
    r = subprocess.run(
        [str(BIN), *args[1:]],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert r.returncode == 0, f"{shlex.join(args)} failed: {r.stderr}"


def write_recordings(folder: Path) -> Path:
    """Six noisy squares as a lab writes them: ``time;pos_x;pos_y`` files.

    The recordings of the README's quickstart and its picture
    (docs/images/plot-own-data.png).
    """
    from ndlfd import synth

    own, _ = synth.make_dataset("square", n_demos=6, noise=0.02, random_state=2)
    folder.mkdir()
    for i, d in enumerate(own):
        rows = np.column_stack([d.t, d.get("position")]).tolist()
        text = ["time;pos_x;pos_y"] + [";".join(f"{v:.6g}" for v in r) for r in rows]
        (folder / f"reach{i}.csv").write_text("\n".join(text) + "\n")
    return folder
