"""The built-in jobs: ndlfd demo (reproduce and evaluate: their own tests)."""

from cli_helpers import (
    run,
)


def test_demo_quick(tmp_path):
    r = run("demo", "--quick", "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert "square" in r.stdout and "DTW to the held-out test" in r.stdout
    names = {p.name for p in (tmp_path / "out").iterdir()}
    assert {
        "square_generated_keypoints.csv",
        "square_generated_dense.csv",
        "square.png",
    } <= names
