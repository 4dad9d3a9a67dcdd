"""The README gets out of the way (issue 41), and its quickstart really runs.

Its shell quickstart (``$ ndlfd`` lines) and its Python quickstart (a script)
run on the recordings they name, written here; its joint-trajectory commands
run in tests/cli/test_cli_bag.py. The examples that moved to the user guides
run in tests/test_guides.py.
"""

import re
import runpy

import numpy as np
import pytest

from doc_blocks import (
    README,
    ROOT,
    commands,
    python_blocks,
    run,
    section,
    write_recordings,
)
from ndlfd.io import read_csv

TEXT = README.read_text(encoding="utf-8")
#: run with a robot's bags by tests/cli/test_cli_bag.py
TRAJECTORIES = "### Joint trajectories for a ROS 2 controller"


def _quickstart() -> list[list[str]]:
    return commands(section(TEXT, "## Quickstart: your CSV files to a path and a plot"))


def test_readme_is_short():
    assert len(README.read_bytes()) <= 8192


def test_the_two_commands_are_on_the_first_screen():
    # within the first 25 lines, as the set-up commands, in a console block
    lines = TEXT.splitlines()[:25]
    for command in ("make demo", "make test"):
        assert any(ln.startswith(command + " ") for ln in lines), command
    assert "```console" in lines


def test_readme_links_lead_somewhere():
    links = re.findall(r"\]\(([^)\s]+)\)", TEXT)
    local = [link for link in links if "://" not in link]
    assert "docs/images/routes.png" in local  # the one picture
    for link in local:
        target, _, anchor = link.partition("#")
        path = ROOT / target
        assert path.exists(), link
        if anchor:  # a heading of the page, as GitHub names its anchor
            headings = re.findall(r"^#+ (.+)$", path.read_text(), re.M)
            assert anchor in {_slug(h) for h in headings}, link


def _slug(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def test_slug_of_known_headings():
    assert _slug("Pick-and-place with moved objects (protocols `task` and "
                 "`frames`, issue 29)") == (
        "pick-and-place-with-moved-objects-protocols-task-and-frames-issue-29"
    )  # fmt: skip
    assert _slug("Two commands") == "two-commands"


def test_readme_shell_quickstart_runs(tmp_path):
    pytest.importorskip("matplotlib")
    examples = _quickstart()
    assert [e[1] for e in examples] == ["fit", "generate", "plot"]
    # every README command is the quickstart's or the trajectories'
    trajectories = commands(section(TEXT, TRAJECTORIES))
    assert examples + trajectories == commands(TEXT)
    write_recordings(tmp_path / "recordings")
    for args in examples:
        run(args, tmp_path)
    # the generated path keeps the recordings' names (fit recorded them)
    assert (tmp_path / "reach.csv").read_text().startswith("time,pos_x,pos_y,")
    assert "`time,pos_x,pos_y,vx,vy`" in TEXT  # as it says
    reach = read_csv(tmp_path / "reach.csv", groups={"position": ["pos_x", "pos_y"]})
    assert reach.n_samples == 200 and reach.columns[:2] == ("pos_x", "pos_y")
    assert (tmp_path / "reach.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_readme_python_quickstart_runs(tmp_path, monkeypatch):
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    import matplotlib.pyplot as plt

    (script,) = python_blocks(TEXT)
    code = [ln for ln in script.splitlines() if ln and not ln.startswith("#")]
    assert len(code) <= 10  # a ten-line quickstart
    recordings = write_recordings(tmp_path / "recordings")
    (tmp_path / "quickstart.py").write_text(script)
    monkeypatch.chdir(tmp_path)
    try:
        runpy.run_path(str(tmp_path / "quickstart.py"), run_name="__main__")
    finally:
        plt.close("all")
    path = read_csv(tmp_path / "reach.csv", groups={"position": ["pos_x", "pos_y"]})
    assert path.columns[:2] == ("pos_x", "pos_y")
    # a path on the recordings' square: its corners within the recordings' span
    first = read_csv(recordings / "reach0.csv", time_column="time",
                     groups={"position": ["pos_x", "pos_y"]})  # fmt: skip
    assert path.n_samples == first.n_samples
    lo, hi = first.get("position").min(0), first.get("position").max(0)
    span = hi - lo
    P = path.get("position")
    assert np.all(P.min(0) > lo - 0.2 * span) and np.all(P.max(0) < hi + 0.2 * span)
    assert (tmp_path / "reach.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
