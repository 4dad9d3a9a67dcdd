"""Re-run analogues of the paper's experiments (``ndlfd reproduce``).

:func:`reproduce` regenerates the paper's Fig. 2, 3, 5 and 6 on ndlfd's synthetic
data (:mod:`ndlfd.synth`), writes one PNG per figure and ``report.md``: our
numbers beside the paper's (SPEC §2), the exact definitions behind them and, per
figure, a sentence chosen *by the measured numbers* saying whether the paper's
qualitative result holds. Every experiment runs twice, with the exact
perpendicular distance (``distance="line"``) and with the paper's determinant
formula (``distance="paper"``, exact only in 2-D).

Everything is deterministic (fixed seeds). The experiment functions
(:func:`fig2_normalization`, :func:`fig3_channels`, :func:`fig5_learning`,
:func:`fig6_levels`) return plain dictionaries so tests can check the
qualitative results directly, at reduced sizes where that is cheaper.

The job is three private modules: the runs and settings
(``_reproduction_runs``), the figures (``_reproduction_figures``) and the
report text (``_reproduction_report``); this module runs them in order.
"""

from __future__ import annotations

import inspect
import os
import time
from collections.abc import Callable

from .. import synth
from ._report import Report
from ._reproduction_figures import draw_fig2, draw_fig3, draw_fig5, draw_fig6
from ._reproduction_report import noise_model_text, report_blocks, sentences
from ._reproduction_runs import (
    CHANNELS,
    DISTANCES,
    NORMALIZATION_MODES,
    PAPER,
    ReproductionSettings,
    fig2_normalization,
    fig3_channels,
    fig5_learning,
    fig5_spread_sweep,
    fig6_levels,
    fig6_noise_sweep,
)

__all__ = [
    "PAPER",
    "ReproductionSettings",
    "fig2_normalization",
    "fig3_channels",
    "fig5_learning",
    "fig5_spread_sweep",
    "fig6_levels",
    "fig6_noise_sweep",
    "reproduce",
]

Echo = Callable[[str], None]


# ------------------------------------------------------------------ main
def _default_speed(generator) -> str:
    return str(inspect.signature(generator).parameters["speed"].default)


def reproduce(
    out: str | os.PathLike = "reproduction",
    *,
    quick: bool = False,
    echo: Echo | None = print,
    settings: ReproductionSettings | None = None,
) -> dict:
    """Re-run the paper's experiments; write figures and ``report.md``.

    Parameters
    ----------
    out : str or path-like, default="reproduction"
        Output folder (created): ``fig2.png``, ``fig3.png``,
        ``fig5_square.png``, ``fig5_square_spiral.png``, ``fig6.png`` and
        ``report.md``.
    quick : bool, default=False
        Reduced sizes (20 training demonstrations, 2 seeds per sweep level)
        for tests.
    echo : callable or None, default=print
        Where progress lines go (``None`` for silence).
    settings : ReproductionSettings, optional
        Override the documented parameters.

    Returns
    -------
    results : dict
        ``"fig2"``, ``"fig3"``, ``"fig5"``, ``"fig6"`` (each keyed by
        distance, Fig. 5 first by shape), the sweeps ``"fig3_sweep"``,
        ``"fig5_sweep"``, ``"fig6_sweep"``, ``"sentences"``, ``"files"`` and
        ``"seconds"`` (the run time: printed through ``echo``, never written
        into ``report.md``, so a rerun leaves the report byte for byte the
        same).

    Examples
    --------
    >>> ReproductionSettings().quick().n_demos  # what --quick changes
    20
    >>> import tempfile
    >>> from pathlib import Path
    >>> with tempfile.TemporaryDirectory() as tmp:  # doctest: +SKIP
    ...     res = reproduce(tmp, quick=True, echo=None)
    ...     sorted(p.name for p in Path(tmp).iterdir())
    ['fig2.png', 'fig3.png', 'fig5_square.png', 'fig5_square_spiral.png',
     'fig6.png', 'report.md']
    """
    say = echo if echo is not None else (lambda _: None)
    settings = settings or ReproductionSettings()
    if quick:
        settings = settings.quick()
    report = Report(out, dpi=settings.dpi)
    t0 = time.perf_counter()
    spiral, curve = synth.spiral(), synth.curve()
    res = _reduction_runs(spiral, curve, settings, say)
    data = {
        shape: synth.make_dataset(
            shape,
            n_demos=settings.n_demos,
            noise=settings.noise,
            test_noise=settings.test_noise,
            random_state=settings.seed + k,
        )
        for k, shape in enumerate(settings.shapes)
    }
    res["samples"] = _samples(spiral, curve, data)
    res.update(_learning_runs(data, settings, say))
    res.update(_level_runs(*data[settings.shapes[0]], settings, say))
    _draw_figures(report, res, curve, data, settings.fig3_epsilon)
    res["seconds"] = time.perf_counter() - t0
    res["noise_model"] = noise_model_text()
    res["sentences"] = sentences(res, settings)
    report.write("report.md", report_blocks(res, settings, quick))
    res["files"] = report.files
    say(
        f"wrote {', '.join(f.name for f in report.files)} to {report.folder}/ in"
        f" {res['seconds']:.1f} s; see report.md"
    )
    return res


def _reduction_runs(spiral, curve, settings: ReproductionSettings, say: Echo):
    """Fig. 2 and 3 with both distances, and the Fig. 3 tolerance sweep."""
    noisy_curve = synth.curve(
        noise=settings.reduction_noise, random_state=settings.seed
    )
    res = {
        "fig2": {
            d: fig2_normalization(spiral, epsilon=settings.fig2_epsilon, distance=d)
            for d in DISTANCES
        },
        "fig3": {
            d: fig3_channels(curve, epsilon=settings.fig3_epsilon, distance=d)
            for d in DISTANCES
        },
        "fig3_sweep": {
            variant: {
                eps: {
                    d: {
                        c: v["n_keypoints"]
                        for c, v in fig3_channels(demo, epsilon=eps, distance=d).items()
                    }
                    for d in DISTANCES
                }
                for eps in settings.fig3_sweep
            }
            for variant, demo in (("clean", curve), ("noisy", noisy_curve))
        },
    }
    say(
        "Fig. 2: key points none/per-dimension/group = "
        + "/".join(
            str(res["fig2"]["line"][m]["n_keypoints"]) for m in NORMALIZATION_MODES
        )
    )
    say(
        f"Fig. 3 (ε={settings.fig3_epsilon:g}): position/velocity/both = "
        + "/".join(str(res["fig3"]["line"][c]["n_keypoints"]) for c in CHANNELS)
        + " (paper 17/26/30)"
    )
    return res


def _samples(spiral, curve, data: dict) -> dict:
    """Samples and speed of each shape, for the report."""
    samples = {
        "spiral (Fig. 2)": (spiral.n_samples, _default_speed(synth.spiral)),
        "curve (Fig. 3)": (curve.n_samples, _default_speed(synth.curve)),
    }
    for k, (shape, (_, test)) in enumerate(data.items()):
        samples[f"{shape} (Fig. 5{', 6' if k == 0 else ''})"] = (
            test.n_samples,
            _default_speed(synth.SHAPES.get(shape)),
        )
    return samples


def _learning_runs(data: dict, settings: ReproductionSettings, say: Echo) -> dict:
    """Fig. 5 and its tolerance sweep on every shape with both distances."""
    fig5: dict = {}
    sweep: dict = {}
    for shape, (train, test) in data.items():
        fig5[shape], sweep[shape] = {}, {}
        for d in DISTANCES:
            r = fig5_learning(train, test, settings=settings, distance=d)
            r["dims"] = test.get("position").shape[1]
            fig5[shape][d] = r
            sweep[shape][d] = fig5_spread_sweep(
                train, settings.fig5_sweep, settings=settings, distance=d
            )
        r = fig5[shape]["line"]
        say(
            f"Fig. 5 {shape}: key points {r['position']['min']}-"
            f"{r['position']['max']} vs {r['position+velocity']['min']}-"
            f"{r['position+velocity']['max']}, difference to test"
            f" {r['position']['errors']['difference_pct']:.2f} % /"
            f" {r['position+velocity']['errors']['difference_pct']:.2f} %"
            f" (baseline {r['baseline']['errors']['difference_pct']:.2f} %)"
        )
    return {"fig5": fig5, "fig5_sweep": sweep}


def _level_runs(train, test, settings: ReproductionSettings, say: Echo) -> dict:
    """Fig. 6 with both distances, and its noise sweep."""
    fig6 = {
        d: fig6_levels(
            train, test, levels=settings.fig6_levels, settings=settings, distance=d
        )
        for d in DISTANCES
    }
    sweep = fig6_noise_sweep(settings.fig6_noise_sweep, settings=settings)
    say(
        "Fig. 6: differences "
        + ", ".join(f"{k}: {v:.2f} %" for k, v in fig6["line"]["differences"].items())
        + " (paper {:.2f} %, {:.2f} %)".format(*PAPER["fig6"].values())
    )
    return {"fig6": fig6, "fig6_sweep": sweep}


def _draw_figures(report: Report, res: dict, curve, data: dict, eps: float) -> None:
    """Draw the line-distance runs; save one PNG per figure into the report."""
    report.figure(draw_fig2(res["fig2"]["line"]), "fig2.png")
    report.figure(draw_fig3(curve, res["fig3"]["line"], eps), "fig3.png")
    for shape, (train, test) in data.items():
        r = res["fig5"][shape]
        fig = draw_fig5(shape, train, test, r["line"], r["paper"])
        report.figure(fig, f"fig5_{shape}.png")
    _, test = next(iter(data.values()))
    report.figure(draw_fig6(test, res["fig6"]["line"]), "fig6.png")
