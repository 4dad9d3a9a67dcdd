"""Fuzz every CLI command in-process: bad files, bad options, a failing write.

Each run ends with exit 0 and a correct output, or exit 2 and ONE line on stderr.
"""

from pathlib import Path

import numpy as np
import pytest

from ndlfd import KeypointHMM, synth
from ndlfd import _fileformat as fileformat
from ndlfd.cli import main

DATA = Path(__file__).parent.parent / "data"
BAD = DATA / "bad"
MODEL = DATA / "keypointhmm_v2.ndlfd"
BAD_CSV = sorted(BAD.glob("*.csv"))
BAD_MODELS = sorted(BAD.glob("*.ndlfd"))


def _run(capsys, *argv):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse: usage errors
        code = exc.code
    out = capsys.readouterr()
    _run.err = out.err
    if code != 0:
        assert code == 2, (argv, code, out.err)
        lines = [ln for ln in out.err.splitlines() if ln.strip()]
        assert lines, argv
        # argparse prints its usage above the one error line
        assert sum(": error:" in ln for ln in lines) == 1, out.err
    return code


def _finite_csv(path):
    data = np.genfromtxt(path, delimiter=",", skip_header=1, ndmin=2)
    assert np.isfinite(data).all(), path


@pytest.mark.parametrize("path", BAD_CSV, ids=lambda p: p.name)
def test_fuzz_cli_simplify_and_fit_bad_csv(path, tmp_path, capsys):
    out = tmp_path / "out.csv"
    if _run(capsys, "simplify", path, "--epsilon", "0.1", "-o", out) == 0:
        _finite_csv(out)
    model = tmp_path / "m.ndlfd"
    if _run(capsys, "fit", path, "-o", model, "-q") == 0:
        assert _run(capsys, "generate", model, "--samples", 20, "-o", out) in (0, 2)


@pytest.mark.parametrize("path", BAD_MODELS, ids=lambda p: p.name)
@pytest.mark.parametrize("command", ["generate", "sample"])
def test_fuzz_cli_bad_model_files(path, command, tmp_path, capsys):
    out = tmp_path / "out"
    assert _run(capsys, command, path, "--samples", 20, "-o", out) == 2


@pytest.mark.parametrize(
    "argv",
    [
        ["simplify", "--bogus"],
        ["fit", "--levels", "banana"],
        ["fit", "--time-bins", "-3"],
        ["fit", "--levels", "4294967296,4294967296"],
        ["generate", "MODEL", "--samples", "0"],
        ["generate", "MODEL", "--duration", "nan"],
        ["generate", "MODEL", "--duration", "inf"],
        ["generate", "MODEL", "--start", "nan,0"],
        ["generate", "MODEL", "--start", "1e300,1e300"],
        ["generate", "MODEL", "--goal", "0"],
        ["sample", "MODEL", "-n", "-1"],
        ["sample", "MODEL", "--random-state", "x"],
        ["plot", "--nothing"],
        ["reproduce", "--bogus"],
        ["evaluate", "--bogus"],
        ["nonexistent-command"],
    ],
    ids=" ".join,
)
def test_fuzz_cli_bad_options(argv, tmp_path, capsys):
    argv = [str(MODEL) if a == "MODEL" else a for a in argv]
    out = tmp_path / "out.csv"
    extra = ["-o", out] if argv[0] in ("generate", "sample") else []
    if argv[0] == "fit":
        extra = [BAD / "constant.csv", "-o", tmp_path / "m.ndlfd"]
    code = _run(capsys, *argv, *extra)
    assert code == 2 or (code == 0 and argv[0] == "generate")
    if code == 0:
        _finite_csv(out)


def test_fuzz_cli_failing_write_keeps_the_old_model(tmp_path, monkeypatch, capsys):
    train, _ = synth.make_dataset("square", n_demos=4, random_state=0)
    folder = tmp_path / "demos"
    folder.mkdir()
    for i, d in enumerate(train):
        np.savetxt(folder / f"d{i}.csv", np.column_stack([d.t, d.get("position")]),
                   delimiter=",", header="t,x,y", comments="")  # fmt: skip
    target = tmp_path / "out" / "m.ndlfd"
    target.parent.mkdir()
    assert _run(capsys, "fit", folder, "-o", target, "-q") == 0
    before = target.read_bytes()
    real_open = open

    def failing(p, m="r"):
        fh = real_open(p, m)
        fh.write = lambda data: (_ for _ in ()).throw(OSError(28, "No space left"))
        return fh

    monkeypatch.setattr(fileformat, "open", failing, raising=False)
    assert _run(capsys, "fit", folder, "-o", target, "-q") == 2
    assert "No space left" in _run.err
    assert target.read_bytes() == before
    assert [p.name for p in target.parent.iterdir()] == ["m.ndlfd"]
    assert isinstance(KeypointHMM.load(target), KeypointHMM)
