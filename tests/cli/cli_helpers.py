"""Helpers shared by the command-line tests: running ndlfd, sample files."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from ndlfd import synth
from ndlfd.cli import main
from ndlfd.demonstration import Demonstration
from ndlfd.io import write_csv, write_table
from ndlfd.learner import KeypointHMM

BIN = Path(sys.executable).parent / "ndlfd"


def run(*args, cwd=None):
    cmd = (
        [str(BIN), *map(str, args)]
        if BIN.exists()
        else [sys.executable, "-m", "ndlfd.cli", *map(str, args)]
    )
    env = dict(os.environ, PYTHONWARNINGS="error")
    return subprocess.run(
        cmd, capture_output=True, text=True, cwd=cwd, env=env, timeout=300
    )


def walk_csv(path, n=300, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    xy = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    data = np.column_stack([t, xy, rng.normal(size=n)])
    write_table(path, ["t", "x", "y", "extra"], data)
    return data


def square_demos(folder, n_demos=6, seed=0):
    """A folder of small demonstrations (position and velocity, 80 samples)."""
    folder.mkdir(parents=True, exist_ok=True)
    train, _ = synth.make_dataset("square", n_demos=n_demos, random_state=seed)
    for i, d in enumerate(train):
        write_csv(d, folder / f"demo{i:02d}.csv")
    return folder


def cli(capsys, *args):
    """Run ``ndlfd ARGS`` in-process: (exit status, stderr lines)."""
    capsys.readouterr()
    rc = main([str(a) for a in args])
    return rc, capsys.readouterr().err.splitlines()


def reach_demos(n_demos=3, seed=0):
    """3-D reaches with orientation at 50/100/125 Hz, irregular time stamps."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_demos):
        n = (50, 100, 125)[i % 3]
        t = np.cumsum(rng.uniform(0.97, 1.03, n)) / n
        s = np.linspace(0.0, 1.0, n)
        pos = np.column_stack([s, np.sin(np.pi * s) * 0.3, 0.2 * s**2])
        pos += rng.normal(0.0, 1e-3, pos.shape)
        half = 0.4 * s + 0.05 * i  # about z: exact unit quaternions
        q = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
        out.append((t, pos, q))
    return out


def write_reach(folder, sep=",", names=("t", "x", "y", "z", "qw", "qx", "qy", "qz"),
                 suffix=".csv", demos=None):  # fmt: skip
    folder.mkdir(parents=True, exist_ok=True)
    for i, (t, pos, q) in enumerate(demos or reach_demos()):
        rows = np.column_stack([t, pos, q]).tolist()
        text = [sep.join(names)] + [sep.join(map(repr, r)) for r in rows]
        (folder / f"reach{i}{suffix}").write_text("\n".join(text) + "\n")
    return folder


def write_obstacle(folder, n_up, n_down):
    """``synth.obstacle``'s two-route demonstrations as CSV files ``t,x,y``."""
    from ndlfd.synth import obstacle

    folder.mkdir(parents=True, exist_ok=True)
    for i, d in enumerate(obstacle(n_up, n_down)):
        rows = np.column_stack([d.t, d.X])
        np.savetxt(folder / f"o{i}.csv", rows, delimiter=",", header="t,x,y",
                   comments="")  # fmt: skip
    return folder


def fit_model(folder, out, *options):
    assert main(["fit", str(folder), "-o", str(out), "-q", *options]) == 0
    return KeypointHMM.load(out)


def fitted_arrays(model):
    """Everything fit learns (not the constructor parameters)."""
    arrays = {
        "keypoints": np.concatenate(model.keypoints_),
        "levels": np.asarray(model.codebook_.levels),
        "scaler_min": model.scaler_.data_min_,
        "scaler_max": model.scaler_.data_max_,
    }
    arrays.update(model.model_.to_arrays())
    return arrays


def assert_same_fit(a, b):
    fa, fb = fitted_arrays(a), fitted_arrays(b)
    assert fa.keys() == fb.keys()
    for k in fa:
        np.testing.assert_array_equal(fa[k], fb[k], err_msg=k)


def build_parser_help(command):
    from ndlfd.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    return sub.choices[command].format_help()


def ndlfd_demo(t, pos, q):
    return Demonstration.from_arrays(t, position=pos, orientation=q)


def own_name_demos(folder, n_demos=4, seed=0):
    """``time;pos_x;pos_y;gripper`` files: a square with the hand closing."""
    folder.mkdir(parents=True, exist_ok=True)
    demos, _ = synth.make_dataset("square", n_demos=n_demos, random_state=seed)
    for i, d in enumerate(demos):
        grip = (np.arange(d.n_samples) > d.n_samples // 2).astype(float)
        rows = np.column_stack([d.t, d.get("position"), grip]).tolist()
        text = ["time;pos_x;pos_y;gripper"]
        text += [";".join(repr(v) for v in r) for r in rows]
        (folder / f"d{i}.csv").write_text("\n".join(text) + "\n")
    return folder


def keep_figures(monkeypatch) -> list:
    """The figures ``ndlfd plot`` saves, kept for the test (matplotlib needed)."""
    import ndlfd.plot

    figures = []
    save = ndlfd.plot.save_figure

    def keep(fig, path, **kw):
        figures.append(fig)
        return save(fig, path, **kw)

    monkeypatch.setattr(ndlfd.plot, "save_figure", keep)
    return figures
