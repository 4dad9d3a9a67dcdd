"""LeRobot datasets: reading one episode of a 10,000-episode v3.0 dataset.

A synthetic LeRobot v3.0 dataset (written as LeRobot lays it out, with
``tests/lerobot_writer.py``: 10,000 episodes of 100 frames, a 7-component
``observation.state`` ``x, y, z, roll, pitch, yaw, gripper``, 1,000 episodes
per data file, one row group per episode). Measured:

1. listing the episodes (``DemoFiles(root)``: ``meta/info.json`` and
   ``meta/episodes``, no data);
2. reading one episode (``DemoFiles(root)[i].read()``: the row groups that
   hold the episode, by their ``episode_index`` statistics, then a filter):
   every episode in order (as a fit's worker reads them: the file's footer
   parsed once), and 200 episodes drawn at random (the footer parsed almost
   every time), against reading the episode's whole 1,000-episode file and
   filtering in memory;
3. a whole fit of the 10,000 episodes streamed through the fit's two passes
   (each episode read once per pass, on the workers), in a fresh process,
   with that process's peak RSS.

Run: ``.venv/bin/python benchmarks/bench_lerobot.py`` (a few minutes). Writes
its section of benchmarks/RESULTS.md.
"""

from __future__ import annotations

import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench_hmm import _status_mib, write_section

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

START, END = "<!-- lerobot:start -->", "<!-- lerobot:end -->"
N_EPISODES = 10_000
N_FRAMES = 100
PER_FILE = 1_000
STATE = ["x", "y", "z", "roll", "pitch", "yaw", "gripper"]


def episodes(n_episodes=N_EPISODES, n_frames=N_FRAMES, seed=0):
    rng = np.random.default_rng(seed)
    s = np.linspace(0, 1, n_frames)
    base = np.column_stack(
        [s, 0.3 * np.sin(np.pi * s), 0.2 * s**2, 0.1 * s, -0.2 * s, 0.8 * s - 0.4]
    )
    for _ in range(n_episodes):
        state = base + rng.normal(0, 0.003, base.shape)
        grip = (s > 0.5 + rng.uniform(-0.05, 0.05)).astype(float)
        yield {"observation.state": np.column_stack([state, grip])}


def main() -> None:
    import pyarrow
    import pyarrow.parquet as pq

    from lerobot_writer import write_lerobot
    from ndlfd.io import DemoFiles

    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp) / "ds"
        t0 = time.perf_counter()
        write_lerobot(root, list(episodes()), {"observation.state": STATE},
                      per_file=PER_FILE)  # fmt: skip
        t_write = time.perf_counter() - t0
        size = sum(f.stat().st_size for f in (root / "data").rglob("*.parquet"))

        t0 = time.perf_counter()
        files = DemoFiles(root)
        t_list = time.perf_counter() - t0
        assert len(files) == N_EPISODES

        rng = np.random.default_rng(1)
        picks = rng.choice(N_EPISODES, 200, replace=False)
        files[0].read()  # imports
        t0 = time.perf_counter()
        for item in files:
            item.read()
        in_order = (time.perf_counter() - t0) / len(files)
        one = []
        for i in picks:
            t0 = time.perf_counter()
            (d,) = files[int(i)].read()
            one.append(time.perf_counter() - t0)
            assert d.n_samples == N_FRAMES
        whole = []
        for i in picks[:20]:
            item = files[int(i)].path
            t0 = time.perf_counter()
            table = pq.read_table(item.path, columns=["timestamp", item.feature,
                                                       "episode_index"])  # fmt: skip
            mask = np.asarray(table.column("episode_index")) == item.episode
            table.filter(mask)
            whole.append(time.perf_counter() - t0)

        fit = subprocess.run(
            [sys.executable, __file__, "--fit", str(root)],
            capture_output=True,
            text=True,
            check=True,
        )
        t_fit, rss, groups = fit.stdout.split(maxsplit=2)

    lines = [
        "## LeRobot datasets: one episode of a 10,000-episode v3.0 dataset",
        "",
        "Command: `.venv/bin/python benchmarks/bench_lerobot.py` (a few minutes).",
        f"Machine: {platform.machine()}, Python {platform.python_version()},"
        f" pyarrow {pyarrow.__version__}.",
        "",
        f"Dataset: {N_EPISODES:,} episodes of {N_FRAMES} frames, observation.state"
        f" = {', '.join(STATE)}; {PER_FILE:,} episodes per data file, one row group"
        f" per episode (as LeRobot writes them); {size / 2**20:.1f} MiB of data"
        f" files, written in {t_write:.1f} s.",
        "",
        "| step | time |",
        "|---|---|",
        f"| list the episodes (`DemoFiles(root)`: info.json, meta/episodes) |"
        f" {t_list * 1e3:.0f} ms |",
        f"| read one episode (its row group), all {N_EPISODES:,} in order, mean |"
        f" {in_order * 1e3:.1f} ms |",
        f"| read one episode, 200 drawn at random (footer parsed each time),"
        f" median | {np.median(one) * 1e3:.1f} ms (max {np.max(one) * 1e3:.1f}) |",
        f"| read its whole file and filter in memory, median of 20 |"
        f" {np.median(whole) * 1e3:.1f} ms |",
        f"| fit all {N_EPISODES:,} episodes streamed (two passes, groups"
        f" {groups.strip()}; default workers) | {float(t_fit):.1f} s, peak RSS"
        f" {float(rss):.0f} MiB |",
    ]
    text = "\n".join(lines)
    print(text)
    write_section(text, START, END)


def fit(root: str) -> None:
    """The fit alone, in this process: time, peak RSS (MiB) and groups."""
    from ndlfd import KeypointHMM
    from ndlfd.io import DemoFiles

    t0 = time.perf_counter()
    model = KeypointHMM(n_time_bins=50).fit(DemoFiles(root))
    elapsed = time.perf_counter() - t0
    print(f"{elapsed:.2f} {_status_mib('VmHWM'):.0f} {', '.join(model.groups_)}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--fit"]:
        fit(sys.argv[2])
    else:
        main()
