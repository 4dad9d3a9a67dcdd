"""Template choice: which demonstrations a fit keeps whole for the blend.

The choice depends on ``random_state`` and each demonstration's index only, so
serial, threaded and Dask fits keep the same templates.
"""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError

__all__ = ["seed_word", "template_keys", "template_mask"]

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


def _splitmix64(z: np.ndarray) -> np.ndarray:
    with np.errstate(over="ignore"):
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def seed_word(random_state) -> np.uint64:
    """One 64-bit word from ``random_state`` (None, an int >= 0 or a Generator).

    An int is mixed by :class:`numpy.random.SeedSequence`; ``None`` is the
    same as 0, so a fit without a seed is deterministic; a Generator (or a
    legacy RandomState) gives one draw.

    Examples
    --------
    >>> bool(seed_word(None) == seed_word(0))
    True
    """
    if random_state is None:
        seq = np.random.SeedSequence(0)
    elif isinstance(random_state, np.random.Generator):
        seq = np.random.SeedSequence(int(random_state.integers(0, 2**63)))
    elif isinstance(random_state, np.random.RandomState):  # scikit-learn style
        seq = np.random.SeedSequence(int(random_state.randint(0, 2**31)))
    elif isinstance(random_state, (int, np.integer)) and not isinstance(
        random_state, bool
    ):
        if random_state < 0:
            raise ValidationError(f"random_state must be >= 0; got {random_state}")
        seq = np.random.SeedSequence(int(random_state))
    else:
        raise ValidationError(
            "random_state must be None, an int >= 0 or a numpy Generator; got"
            f" {random_state!r}"
        )
    return seq.generate_state(1, np.uint64)[0]


def template_keys(word, indices) -> np.ndarray:
    """Key of each demonstration index: ``splitmix64(word + (i + 1) * golden)``.

    Parameters
    ----------
    word : int
        The seed word (see :func:`seed_word`).
    indices : array-like of int
        Demonstration indices.

    Returns
    -------
    keys : ndarray, dtype uint64

    Examples
    --------
    >>> template_keys(0, [0, 1])
    array([16294208416658607535,  7960286522194355700], dtype=uint64)
    """
    i = np.asarray(indices, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = np.uint64(word) + (i + np.uint64(1)) * _GOLDEN
    return _splitmix64(z)


def template_mask(n_demos: int, max_templates: int | None, random_state) -> np.ndarray:
    """Which demonstrations are kept whole for the blended generation.

    All of them when ``n_demos <= max_templates`` (or ``max_templates`` is
    None); otherwise the ``max_templates`` whose :func:`template_keys` are the
    smallest (ties by index). The choice depends on ``random_state`` and each
    demonstration's index only, not on how the demonstrations are split.

    Parameters
    ----------
    n_demos : int
    max_templates : int or None
    random_state : None, int or Generator

    Returns
    -------
    mask : ndarray of shape (n_demos,), dtype bool

    Examples
    --------
    >>> template_mask(3, 5, None)
    array([ True,  True,  True])
    >>> int(template_mask(1000, 10, 0).sum())
    10
    """
    mask = np.ones(n_demos, dtype=bool)
    if max_templates is None or n_demos <= max_templates:
        return mask
    keys = template_keys(seed_word(random_state), np.arange(n_demos))
    order = np.lexsort((np.arange(n_demos), keys))
    mask[:] = False
    mask[order[:max_templates]] = True
    return mask
