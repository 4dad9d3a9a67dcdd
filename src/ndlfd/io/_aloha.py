"""ALOHA / ACT episodes: one HDF5 file per episode, read as two arms.

The layout, as the ACT repository's ``record_sim_episodes.py`` and ALOHA's
``aloha_scripts/record_episodes.py`` write it (``episode_<i>.hdf5``):

* root attribute ``sim`` (bool); the real robot's later scripts add
  ``compress`` (images stored as padded JPEG bytes, ``(T, padded_size)``
  uint8, with a ``compress_len`` dataset);
* ``/observations/qpos`` and ``/observations/qvel``, ``(T, 14)`` (h5py's
  default float32), ``/observations/effort`` on the real robot;
* ``/observations/images/<camera>``, ``(T, 480, 640, 3)`` uint8, chunked
  one frame a chunk;
* ``/action``, ``(T, 14)``: the commanded joints;
* no time stamps: the control rate is 50 Hz (``DT = 0.02`` in their
  ``constants.py``).

The 14 values are, per arm (left, then right), the ViperX's 6 joints and the
gripper, in the order LeRobot names them (:data:`~ndlfd.io._names.ALOHA_NAMES`:
``left_waist`` ... ``left_gripper``, ``right_waist`` ...). One file is one
demonstration, read as LeRobot's ALOHA datasets are: the groups
``left_joints``, ``gripper`` (both grippers) and ``right_joints``.

* **Which values**: ``/action`` (what the policy learns to command, as ACT
  trains on) unless ``feature`` names the measured ``qpos``
  (``"observations/qpos"``, ``"qpos"``, or LeRobot's name for it,
  ``"observation.state"``).
* **Time**: row ``k`` at ``k * DT`` with ``DT = 0.02`` s, unless the file
  says otherwise in a root attribute ``dt`` (seconds) or ``fps`` (Hz);
  ``time_column=None`` gives the row number (``rate=`` then gives the rate,
  as for any file without time stamps).
* **Images are never read**: only the shapes of ``qpos`` and ``action`` and
  the one dataset learned are touched.
* **Checked**: ``qpos`` and ``action`` of 14 columns, of one length, with at
  least one row; rows with NaN or inf as everywhere else (``bad_rows``).
"""

from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np

from .._errors import DataFileError
from ..demonstration import Demonstration
from ._mapping import TIME_NAMES, ColumnMapping, RateMapping, map_arrays
from ._names import ALOHA_NAMES

__all__ = [
    "ALOHA_DT",
    "ALOHA_FEATURES",
    "is_aloha_episode",
    "read_aloha_episode",
]

#: ALOHA's and ACT's control period in seconds (``constants.DT``).
ALOHA_DT = 0.02
#: The datasets an ALOHA episode's values are read from, by the names
#: ``feature`` takes (``None``: the action).
ALOHA_FEATURES = {
    None: "action",
    "action": "action",
    "/action": "action",
    "qpos": "observations/qpos",
    "observations/qpos": "observations/qpos",
    "/observations/qpos": "observations/qpos",
    "observation.state": "observations/qpos",
}
_WIDTH = len(ALOHA_NAMES)
_CLOCK = "(row number) * dt"  # the time key handed to map_arrays, never reported


def is_aloha_episode(fh) -> bool:
    """Whether the open HDF5 file ``fh`` is laid out as an ALOHA episode.

    A dataset ``/action`` beside a group ``/observations`` holding a
    dataset ``qpos`` (whatever their shapes: those are checked on reading).
    """
    import h5py

    obs = fh.get("observations")
    return (
        isinstance(fh.get("action"), h5py.Dataset)
        and isinstance(obs, h5py.Group)
        and isinstance(obs.get("qpos"), h5py.Dataset)
    )


def _feature(p, feature) -> str:
    key = feature.strip() if isinstance(feature, str) else feature
    if key not in ALOHA_FEATURES:
        raise DataFileError(
            f"{p}: an ALOHA episode holds /action (the default) and"
            f" /observations/qpos; feature {feature!r} names neither (pass"
            " 'action' or 'observations/qpos')"
        )
    return ALOHA_FEATURES[key]


def _checked_shapes(p, fh) -> int:
    """The episode's number of time steps, its qpos and action checked."""
    shapes = {k: fh[k].shape for k in ("observations/qpos", "action")}
    for k, shape in shapes.items():
        if len(shape) != 2 or shape[1] != _WIDTH:
            raise DataFileError(
                f"{p}: an ALOHA episode's /{k} must be of shape (T, {_WIDTH}) (per"
                " arm, left then right, 6 joints and the gripper); got shape"
                f" {shape}"
            )
    n_qpos, n_action = shapes["observations/qpos"][0], shapes["action"][0]
    if n_qpos != n_action:
        raise DataFileError(
            f"{p}: /observations/qpos has {n_qpos} rows and /action {n_action};"
            " expected one row of each per time step (an ALOHA episode)"
        )
    if n_action == 0:
        raise DataFileError(
            f"{p}: the ALOHA episode holds no time step (/action has shape"
            f" {shapes['action']})"
        )
    return n_action


def _period(p, fh) -> float:
    """The control period: the root's ``dt`` or ``fps``, else ALOHA's 0.02 s."""
    for key, to_dt in (("dt", lambda v: v), ("fps", lambda v: 1.0 / v)):
        if key in fh.attrs:
            value = fh.attrs[key]
            try:
                dt = to_dt(float(value))
            except (TypeError, ValueError, ZeroDivisionError):
                dt = math.nan
            if not (math.isfinite(dt) and dt > 0):
                raise DataFileError(
                    f"{p}: the root attribute {key!r} must be a positive number"
                    f" ({'seconds' if key == 'dt' else 'Hz'}); got {value!r}"
                )
            return dt
    return ALOHA_DT


def read_aloha_episode(
    p, fh, how, feature=None, **mapping
) -> list[tuple[Demonstration, ColumnMapping]]:
    """The demonstration of the ALOHA episode file ``fh`` with the mapping used.

    ``mapping`` are the column mapping options, applied to the 14 columns
    named :data:`~ndlfd.io._names.ALOHA_NAMES` (``time_column`` at its
    default is ALOHA's clock; a name is an error: the file has no time
    dataset).
    """
    key = _feature(p, feature)
    n = _checked_shapes(p, fh)
    values = np.asarray(fh[key][()], dtype=np.float64)
    arrays = {name: values[:, j] for j, name in enumerate(ALOHA_NAMES)}
    tc = mapping.pop("time_column", TIME_NAMES)
    layout = f"ALOHA HDF5, {key}"
    if tc is None:
        demo, m = map_arrays(
            p, arrays, time_column=None, how=how, layout=layout, **mapping
        )
        return [(demo, m)]
    if isinstance(tc, str) or tuple(tc) != TIME_NAMES:
        raise DataFileError(
            f"{p}: an ALOHA episode has no time dataset ({how['time']} names"
            f" {tc!r}); its rows are {ALOHA_DT:g} s apart (a root attribute dt or"
            " fps says otherwise); leave the time column at its default, or pass"
            " None for the row number"
        )
    dt = _period(p, fh)
    clock = {_CLOCK: np.arange(n) * dt, **arrays}
    demo, m = map_arrays(
        p, clock, time_column=_CLOCK, how=how, layout=layout, **mapping
    )
    return [(demo, RateMapping(**{**asdict(m), "time": None}, rate=1.0 / dt))]
