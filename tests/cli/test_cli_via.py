"""ndlfd generate / sample --via TIME:GROUP=values (a via point, repeatable)."""

import re

import numpy as np
import pytest
from cli_helpers import cli

from ndlfd.io import read_csv
from ndlfd.learner import KeypointHMM
from ndlfd.synth import obstacle


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("via") / "m.ndlfd"
    KeypointHMM().fit(obstacle(9, 3)).save(path)
    return path


def test_generate_via_matches_the_library(capsys, tmp_path, model_file):
    rc, err = cli(capsys, "generate", model_file, "--duration", "5", "--samples",
                  "201", "--dense", "--via", "2.5:position=-5,-5.2",
                  "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 0, err
    path = read_csv(tmp_path / "p.csv")
    expected = KeypointHMM.load(model_file).generate(
        np.linspace(0.0, 5.0, 201), dense=True,
        via=[(2.5, {"position": [-5.0, -5.2]})],
    )  # fmt: skip
    np.testing.assert_allclose(path.X, expected.X, rtol=5e-10, atol=1e-9)
    np.testing.assert_allclose(path.get("position")[100], [-5.0, -5.2], atol=1e-8)


def test_sample_via_repeatable(capsys, tmp_path, model_file):
    rc, err = cli(capsys, "sample", model_file, "-n", "3", "--duration", "5",
                  "--samples", "201", "--via", "2.5:position=-5,-5.2",
                  "--via", "1.25:position=-7.5,-3.9", "--random-state", "1",
                  "-o", tmp_path / "s")  # fmt: skip
    assert rc == 0, err
    for f in sorted((tmp_path / "s").glob("sample_*.csv")):
        P = read_csv(f).get("position")
        np.testing.assert_allclose(P[100], [-5.0, -5.2], atol=1e-8)
        np.testing.assert_allclose(P[50], [-7.5, -3.9], atol=1e-8)


@pytest.mark.parametrize(
    ("via", "match"),
    [
        ("2.5position=1,2", "--via must look like TIME:GROUP=V1,V2"),
        ("2.5:position", "--via must look like"),
        ("x:position=1,2", "the time 'x' is not a number"),
        ("nan:position=1,2", "the time must be finite"),
        ("2.5:position=1,y", "must be comma-separated numbers"),
        ("9:position=1,2", "time must lie within the timing, 0 to 5; got 9"),
        ("2.5:force=1", "names group 'force', which is not learned"),
        ("2.5:position=1", "must hold 2 finite value"),
    ],
)
def test_bad_via_flags(capsys, tmp_path, model_file, via, match):
    rc, err = cli(capsys, "generate", model_file, "--duration", "5", "--via", via,
                  "-o", tmp_path / "bad.csv")  # fmt: skip
    assert rc == 2 and len(err) == 1
    assert re.search(match, err[0]), err
