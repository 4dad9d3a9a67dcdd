"""docs/two_arms.md runs as written: its doctests and its shell examples.

The shell examples run on the lab CSV files of test_cli_frame_hands (the
handover whose right hand is known to close on the cube's grasp point), and
the summary lines the page quotes must be what the fit printed.
"""

import doctest
import re
import shlex
from pathlib import Path

import numpy as np
from cli_helpers import run
from test_cli_frame_hands import GRASP, HANDOVER, write_two_arms

from ndlfd.io import read_csv

PAGE = Path(__file__).resolve().parents[2] / "docs" / "two_arms.md"
COMMAND = re.compile(r"^\$ (ndlfd .+)$", re.M)


def _text():
    return PAGE.read_text(encoding="utf-8")


def test_the_pages_doctests_run():
    text = _text()
    test = doctest.DocTestParser().get_doctest(text, {}, PAGE.name, str(PAGE), 0)
    assert len(test.examples) > 20
    runner = doctest.DocTestRunner(
        optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    )
    report = []
    result = runner.run(test, out=report.append)
    assert result.failed == 0, "".join(report)


def test_every_python_block_is_a_doctest():
    # a block that is not a doctest would be shown and never run
    blocks = re.findall(r"^```python\n(.*?)^```", _text(), re.M | re.S)
    assert blocks and all(b.lstrip().startswith(">>>") for b in blocks)


def test_the_shell_examples_run_and_say_what_the_page_quotes(tmp_path):
    text = _text()
    examples = [shlex.split(c) for c in COMMAND.findall(text)]
    assert [e[1] for e in examples] == ["fit", "generate"]
    _, cubes = write_two_arms(tmp_path / "episodes")
    fit = run(*examples[0][1:], cwd=tmp_path)
    assert fit.returncode == 0, fit.stderr
    said = fit.stderr.splitlines()
    quoted = re.search(r"The fit's summary.*?```text\n(.*?)```", text, re.S)
    lines = [q for q in quoted.group(1).splitlines() if q != "..."]
    assert len(lines) == 2
    for line in lines:
        assert line in said, (line, said)
    # the header the page shows is the files' (its middle elided)
    header = (tmp_path / "episodes" / "episode_00.csv").read_text().split("\n")[0]
    shown = re.search(r"```text\n(t,left_x.*)\n```", text).group(1)
    head, tail = shown.split(",...,")
    assert header.startswith(head) and header.endswith(tail)
    gen = run(*examples[1][1:], cwd=tmp_path)
    assert gen.returncode == 0, gen.stderr
    path = read_csv(tmp_path / "path.csv")
    cube = np.array([float(v) for v in examples[1][-3].split("=")[1].split(",")])
    assert np.min(np.linalg.norm(cubes - cube, axis=1)) > 0.005  # a new cube
    right = path.X[:, [path.columns.index(f"right_{c}") for c in "xyz"]]
    grip = path.X[:, path.columns.index("right_gripper")]
    closes = right[np.argmax(grip < 0.5)]
    assert np.linalg.norm(closes - (cube + GRASP)) < 0.001
    assert np.linalg.norm(right[-1] - HANDOVER) < 0.003
