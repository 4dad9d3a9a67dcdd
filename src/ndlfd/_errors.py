"""The one small error hierarchy of ndlfd.

Every error that ndlfd raises on purpose subclasses :class:`NdlfdError`, which
itself subclasses :class:`ValueError`, so ``except ValueError`` keeps working for
callers that do not know ndlfd.
"""

__all__ = [
    "DataFileError",
    "DecodeError",
    "ExtrapolationWarning",
    "MissingExtraError",
    "ModelFormatError",
    "NdlfdError",
    "NdlfdWarning",
    "NotFittedError",
    "OptionError",
    "ParallelError",
    "ResourceLimitError",
    "ValidationError",
]


class NdlfdError(ValueError):
    """Base class of every error raised by ndlfd on purpose."""


class ValidationError(NdlfdError):
    """An argument has the wrong shape, dtype, range or value."""


class ResourceLimitError(ValidationError):
    """An input is larger than a documented bound (see ``docs/robustness.md``).

    Raised before anything of the refused size is allocated; the message states
    the bound and the value got.
    """


class OptionError(NdlfdError):
    """An option name is not one of the valid choices (listed in the message)."""


class NotFittedError(NdlfdError, AttributeError):
    """An estimator was used before ``fit``."""


class DecodeError(NdlfdError):
    """A sequence of symbols cannot be decoded by a model."""


class DataFileError(NdlfdError):
    """A data file (CSV, NPZ) cannot be read; the message names file and row."""


class ModelFormatError(NdlfdError):
    """A model file is foreign, truncated, tampered with or of another version."""


class MissingExtraError(NdlfdError, ImportError):
    """An optional dependency is missing; the message says how to install it."""


class ParallelError(NdlfdError, RuntimeError):
    """A worker process died before it returned its result (killed, out of memory)."""


class NdlfdWarning(UserWarning):
    """Data that ndlfd accepted after a repair the user should know about.

    For example quaternions logged with a few decimals (renormalized) or time
    stamps with large jitter (velocity derived over a time window).
    """


class ExtrapolationWarning(NdlfdWarning):
    """A request far outside what the demonstrations show, accepted as given.

    For example a start or goal many times the demonstrations' spread away
    from every demonstration's start or goal
    (:func:`ndlfd.learner._conditioning.warn_far_condition`): the path is
    made, but it extrapolates.
    """
