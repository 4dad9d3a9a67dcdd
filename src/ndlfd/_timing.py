"""How regular time stamps and the speed they imply are (velocity's smoothing).

:func:`timing_jitter` and :func:`speed_roughness` decide, in
:func:`ndlfd.demonstration.with_velocity`, whether logged time stamps are
jittery enough to differentiate over a window instead of sample to sample.
"""

from __future__ import annotations

import numpy as np

from ._validation import check_times

__all__ = ["speed_roughness", "timing_jitter"]


def speed_roughness(P: np.ndarray, t: np.ndarray) -> float:
    """Median step-to-step change of the speed over the median speed."""
    speed = np.linalg.norm(np.diff(P, axis=0), axis=1) / np.diff(t)
    typical = float(np.median(speed))
    if not typical > 0:
        return 0.0
    return float(np.median(np.abs(np.diff(speed)))) / typical


def timing_jitter(t) -> float:
    """How jittery time stamps are, as a fraction of the median step.

    The 90th percentile of ``|dt[i+1] - dt[i]|`` over the median step: 0 for a
    uniform grid and small for a sampling rate that changes smoothly; logging
    jitter of ±30 % of the step gives about 0.4. Fewer than 10 samples
    give 0 (too few steps to tell).

    Parameters
    ----------
    t : array-like of shape (n_samples,)
        Strictly increasing time stamps.

    Returns
    -------
    jitter : float

    Examples
    --------
    >>> timing_jitter(np.arange(20.0))
    0.0
    >>> steps = np.tile([1.0, 1.5], 10)  # alternating: every change is 0.5
    >>> round(timing_jitter(np.concatenate([[0.0], np.cumsum(steps)])), 6)
    0.4
    """
    tt = check_times(t, name="t")
    if tt.size < 10:
        return 0.0
    dt = np.diff(tt)
    return float(np.percentile(np.abs(np.diff(dt)), 90) / np.median(dt))
