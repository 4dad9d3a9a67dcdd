"""ndlfd: learning robot paths from demonstrations with n-D key points and HMMs.

The public names live in private modules and are re-exported here.
"""

from ._errors import (
    DataFileError,
    DecodeError,
    MissingExtraError,
    ModelFormatError,
    NdlfdError,
    NotFittedError,
    OptionError,
    ValidationError,
)

__version__ = "0.1.0"

__all__ = [
    "DataFileError",
    "DecodeError",
    "MissingExtraError",
    "ModelFormatError",
    "NdlfdError",
    "NotFittedError",
    "OptionError",
    "ValidationError",
    "__version__",
]
