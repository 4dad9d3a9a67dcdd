"""The built-in job behind ``ndlfd demo``, and helpers shared with ``reproduce``.

:func:`run_demo` learns from built-in data and writes generated paths, a figure
and a summary. It is deterministic (fixed seeds).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path
from typing import TextIO

from numba.core import event

from .. import plot as _plot
from .. import synth
from .._errors import MissingExtraError
from ..datasets import load_lasa
from ..demonstration import Demonstration
from ..io import write_csv
from ..learner import KeypointHMM
from ..metrics import mean_demo_baseline, path_errors

__all__ = ["run_demo"]

#: Settings of the built-in jobs, per dataset (epsilon in normalized units).
#: The square's 10 % training noise needs a coarser tolerance than LASA's smooth
#: handwriting; 20 time bins keep every bin populated by training key points.
#: LASA uses 50 position levels: a finer codebook is cheap and shows its gain.
DEMO_SETTINGS = {
    "square": {
        "epsilon": 0.1,
        "n_time_bins": 20,
        "levels": {"position": 20, "velocity": 10},
    },
    "lasa": {
        "epsilon": 0.005,
        "n_time_bins": 20,
        "levels": {"position": 50, "velocity": 10},
    },
}

Echo = Callable[[str], None]


def _silent(_: str) -> None:
    pass


def _try_plot():
    """The plot module when matplotlib is installed, else None."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return None
    return _plot


#: Demonstrations of the warm-up run (see :func:`_warm_up`).
WARM_UP_DEMOS = 3


class _CompileReport(event.Listener):
    """Counts numba's compilations of kernels called from Python.

    A kernel's first call compiles it and the kernels it calls (nested
    compilations, not counted apart); with ``announce`` the first one writes
    it, so the line shows while numba works.
    """

    def __init__(self, announce: Callable[[], None]):
        self.announce = announce
        self.depth = 0
        self.kernels = 0

    def on_start(self, ev) -> None:
        if self.depth == 0:
            if self.kernels == 0:
                self.announce()
            self.kernels += 1
        self.depth += 1

    def on_end(self, ev) -> None:
        self.depth -= 1


@contextmanager
def _compiling(stage: str, what: str, progress: TextIO | None):
    """Say on ``progress``, once numba starts compiling, what it compiles.

    ``compiling the <stage> kernels (<what>; first run only, cached after)
    ...`` is written when the first kernel of the block starts compiling,
    and ended with the block's seconds and the number of kernels; a block
    whose kernels all come from numba's cache writes nothing. Yields the report, whose
    ``kernels`` counts the kernels compiled.
    """

    def announce() -> None:
        if progress is not None:
            progress.write(
                f"compiling the {stage} kernels ({what}; first run only, cached"
                " after) ..."
            )
            progress.flush()

    report = _CompileReport(announce)
    t0 = time.perf_counter()
    with event.install_listener("numba:compile", report):
        yield report
    if progress is not None and report.kernels:
        s = "" if report.kernels == 1 else "s"
        progress.write(
            f" {time.perf_counter() - t0:.1f} s, {report.kernels} kernel{s}\n"
        )
        progress.flush()


def _terminal() -> TextIO | None:
    """Standard error on a terminal, else None (like a progress bar)."""
    return sys.stderr if sys.stderr.isatty() else None


def _cores() -> int:
    """The CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class _SecondProcess:
    """The generation's kernels compiled in a second process meanwhile.

    ``python -m ndlfd.learner._warm`` (:func:`~ndlfd.learner._warm.compile_generation`)
    compiles the decoder's and the blend's kernels into numba's on-disk
    cache while this process compiles the fit's, each on its own core; the
    generation here then loads them. It imports this very ``ndlfd`` (its
    folder first on ``PYTHONPATH``) with the same environment, so the same
    cache. Where it cannot start or fails, this process compiles them
    itself, as it would without it; and on one core it is not started (it
    would only add its own start-up, about 1 s of CPU).
    """

    def __init__(self):
        self.proc = None
        self.t0 = time.perf_counter()
        if _cores() < 2:
            return
        package = Path(__file__).resolve().parents[2]  # the folder holding ndlfd
        path = os.pathsep.join(
            filter(None, [str(package), os.environ.get("PYTHONPATH")])
        )
        try:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "ndlfd.learner._warm"],
                env={**os.environ, "PYTHONPATH": path},
                stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                text=True,
            )
        except OSError:  # no second process: compiled here when needed
            pass

    def running(self) -> bool:
        return self.proc is not None and self.proc.poll() is None

    def close(self) -> None:
        """Stop it if it was not joined (its kernels then go uncounted)."""
        if self.proc is not None:
            self.proc.kill()
            self.proc.communicate()
            self.proc = None

    def join(self, progress: TextIO | None = None, timeout: float = 300.0) -> int:
        """Wait for it; how many kernels it compiled (0 if it failed).

        Still compiling, it says so on ``progress`` while it waits. Joined
        already, it returns 0 (its kernels are counted once).
        """
        if self.proc is None:  # joined already (or never started)
            return 0
        waiting = progress is not None and self.running()
        if waiting:
            progress.write(
                "compiling the generation kernels (decoder, blend) in a second"
                " process ..."
            )
            progress.flush()
        kernels, seconds = 0, time.perf_counter() - self.t0
        try:
            out, _ = self.proc.communicate(timeout=timeout)
            said = json.loads(out.strip().splitlines()[-1])
            kernels, seconds = int(said["kernels"]), float(said["seconds"])
        except (subprocess.TimeoutExpired, ValueError, IndexError, KeyError):
            self.proc.kill()
            self.proc.communicate()
        self.proc = None
        if progress is not None and (waiting or kernels):
            s = "" if kernels == 1 else "s"
            head = "" if waiting else (
                "compiled the generation kernels (decoder, blend) in a second"
                " process meanwhile:"
            )  # fmt: skip
            progress.write(f"{head} {seconds:.1f} s, {kernels} kernel{s}\n")
            progress.flush()
        return kernels


def _warm_up(
    train,
    test,
    settings: dict,
    progress: TextIO | None = None,
    second: _SecondProcess | None = None,
):
    """Compile the kernels the timed run needs; ``(seconds, kernels compiled)``.

    numba compiles a kernel on its first call (or loads it from its on-disk
    cache on later runs), and compiles per argument type, not size. One fit
    and generation on the first few demonstrations, with the same settings,
    therefore takes that one-time cost out of the timed run that follows.
    What is compiled is said on ``progress`` while it is (see
    :func:`_compiling`). With ``second`` (:class:`_SecondProcess`) compiling
    the generation's kernels meanwhile, the generation waits for it when the
    fit had to compile (a first run), and loads them from the cache.
    """
    t0 = time.perf_counter()
    with _compiling("fitting", "reduction, codebook, statistics", progress) as fit:
        model = KeypointHMM(**settings).fit(train[:WARM_UP_DEMOS])
    helped = 0
    if second is not None and (fit.kernels or not second.running()):
        helped = second.join(progress)
    with _compiling("generation", "decoder, blend", progress) as gen:
        model.generate(test.t)
        model.generate(test.t, dense=True, return_std=True)
    return time.perf_counter() - t0, fit.kernels + helped + gen.kernels


def _learn_and_generate(train, test, settings: dict):
    t0 = time.perf_counter()
    model = KeypointHMM(**settings).fit(train)
    t_fit = time.perf_counter() - t0
    t0 = time.perf_counter()
    keys = model.generate(test.t)
    dense, std = model.generate(test.t, dense=True, return_std=True)
    t_gen = time.perf_counter() - t0
    return model, keys, dense, std, t_fit, t_gen


def run_demo(
    out: str | os.PathLike = "demo-output",
    *,
    quick: bool = False,
    plot: bool = True,
    echo: Echo = _silent,
    progress: TextIO | str | None = "terminal",
) -> dict:
    """Learn from built-in data, generate, write files and a figure, summarize.

    Parameters
    ----------
    out : str or path-like, default="demo-output"
        Output folder (created).
    quick : bool, default=False
        Use 20 training demonstrations instead of 100.
    plot : bool, default=True
        Write figures (needs the ``plot`` extra; skipped with a note without it).
    echo : callable, optional
        Where summary lines go (``print`` on the command line).
    progress : text stream, None or "terminal", default="terminal"
        Where the warm-up says which kernels numba is compiling, while it
        does (``compiling the fitting kernels (...; first run only, cached
        after) ... 4.1 s, 10 kernels``): a stream, nothing with None, and
        standard error when it is a terminal with ``"terminal"``. The
        generation's kernels compile meanwhile in a second process (``python
        -m ndlfd.learner._warm``, on the other core), which the warm-up waits
        for on a first run and says so.

    Returns
    -------
    summary : dict
        One entry per dataset with key-point counts, states used, timings and
        errors to the test demonstration. The timings ``fit_s`` and
        ``generate_s`` follow a warm-up run (``warm_up_s``: the same fit and
        generation on the first 3 demonstrations), so they hold no kernel
        compilation; the warm-up holds it, and is printed apart.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # the generation's kernels on the other core, from now: the data and
    # matplotlib load meanwhile too
    second = _SecondProcess()
    try:
        plotting = _try_plot() if plot else None
        if plot and plotting is None:
            echo('(no figures: install matplotlib with pip install "ndlfd[plot]")')
        jobs = []
        n_demos = 20 if quick else 100
        train, test = synth.make_dataset("square", n_demos=n_demos, random_state=0)
        jobs.append(("square", train, test, DEMO_SETTINGS["square"]))
        try:
            lasa = load_lasa("Angle")
            jobs.append(("lasa-Angle", lasa[:-1], lasa[-1], DEMO_SETTINGS["lasa"]))
        except MissingExtraError:
            echo('(LASA skipped: install it with pip install "ndlfd[lasa]")')
        if progress == "terminal":
            progress = _terminal()
        warm = {
            name: _warm_up(tr, te, settings, progress, second)
            for name, tr, te, settings in jobs
        }
        compiled = sum(kernels for _, kernels in warm.values()) + second.join()
    finally:
        second.close()  # stopped if an error came before it was joined
    warm_up = {name: seconds for name, (seconds, _) in warm.items()}
    how = (
        f"{compiled} compiled this time, cached for the next runs"
        if compiled
        else "all loaded from numba's disk cache this time"
    )
    echo(
        f"warm-up {sum(warm_up.values()):.1f} s: one-time start-up (compiling the"
        f" kernels, {how}), not in the fit and generate times below"
    )
    summary = {}
    for name, tr, te, settings in jobs:
        model, keys, dense, std, t_fit, t_gen = _learn_and_generate(tr, te, settings)
        base = mean_demo_baseline(tr, te.t)
        base_demo = Demonstration(
            te.t, base, te.select("position").columns, ("position",) * base.shape[1]
        )
        row = {
            "n_demos": len(tr),
            "keypoints_min": int(model.n_keypoints_.min()),
            "keypoints_max": int(model.n_keypoints_.max()),
            "states_used": model.n_states_used_,
            "n_states": model.codebook_.n_states,
            "warm_up_s": warm_up[name],
            "fit_s": t_fit,
            "generate_s": t_gen,
            "generated_keypoints": keys.n_samples,
            **path_errors(te, dense),
            "baseline_difference_pct": path_errors(te, base_demo)["difference_pct"],
            "baseline_dtw_mean": path_errors(te, base_demo)["dtw_mean"],
        }
        summary[name] = row
        write_csv(keys, out / f"{name}_generated_keypoints.csv")
        write_csv(dense, out / f"{name}_generated_dense.csv")
        if plotting is not None:
            fig, (ax,) = plotting.new_figure(1)
            plotting.plot_band(
                ax,
                dense.get("position"),
                std[:, list(model.column_groups_).index("position") :][:, :2],
                k=1.0,
                label="band (1 sd)",
            )
            plotting.plot_demos(
                tr,
                keypoints=model.keypoints_,
                generated=dense,
                test=te,
                ax=ax,
                max_demos=15,
                title=f"{name}: {len(tr)} demonstrations, generated path (red)",
            )
            plotting.save_figure(fig, out / f"{name}.png")
        echo(
            f"{name:>12}: {len(tr)} demos, key points {row['keypoints_min']}-"
            f"{row['keypoints_max']}, {row['states_used']} codebook cells visited"
            f" (of {row['n_states']:,}), fit {t_fit * 1e3:.0f} ms, generate"
            f" {t_gen * 1e3:.1f} ms,"
            f" DTW to the held-out test {row['dtw_mean']:.4g}"
            f" (mean of the demonstrations {row['baseline_dtw_mean']:.4g}),"
            f" difference {row['difference_pct']:.2f} %"
            f" (mean {row['baseline_difference_pct']:.2f} %)"
        )
    echo(f"wrote generated paths{' and figures' if plotting else ''} to {out}/")
    return summary
