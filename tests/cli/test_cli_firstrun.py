"""The first run of a command says that it compiles kernels, once, on a terminal."""

import io

from cli_helpers import square_demos

from ndlfd.cli import _firstrun, main


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_the_first_fit_says_it_compiles_then_never_again(tmp_path, monkeypatch):
    markers = tmp_path / "cache"
    monkeypatch.setattr(_firstrun, "_marker", lambda c: markers / f"{c}.ran")
    demos = square_demos(tmp_path / "demos")
    said = []
    for _ in range(2):
        err = _Terminal()
        monkeypatch.setattr("sys.stderr", err)
        assert main(["fit", str(demos), "-o", str(tmp_path / "m.ndlfd")]) == 0
        said.append(
            [line for line in err.getvalue().splitlines() if "first run" in line]
        )
    assert said[0] == [
        "ndlfd fit: first run of this install: compiling its kernels once"
        " (cached for the next runs)"
    ]
    assert said[1] == []
    assert (markers / "fit.ran").exists()


def test_nothing_is_said_off_a_terminal_or_after_a_failure(tmp_path, monkeypatch):
    markers = tmp_path / "cache"
    monkeypatch.setattr(_firstrun, "_marker", lambda c: markers / f"{c}.ran")
    err = io.StringIO()  # a pipe, a file, a test's capture
    monkeypatch.setattr("sys.stderr", err)
    assert (
        main(["fit", str(square_demos(tmp_path / "d")), "-o", str(tmp_path / "m")]) == 0
    )
    assert "first run" not in err.getvalue()
    term = _Terminal()
    monkeypatch.setattr("sys.stderr", term)
    assert main(["fit", str(tmp_path / "missing"), "-o", str(tmp_path / "m")]) == 2
    assert "first run" in term.getvalue()
    assert not (markers / "fit.ran").exists()  # said again next time
