"""ndlfd: learning robot paths from demonstrations with n-D key points and HMMs.

Demonstrations are reduced to key points by an n-dimensional Douglas–Peucker
algorithm over group-normalized channels, encoded as codebook states, learned by
a supervised discrete hidden Markov model, and decoded for a new timing by
Viterbi. The public names live in small private modules and are re-exported
here; the submodules ``hmm``, ``synth``, ``datasets``, ``io``, ``limits``,
``metrics``, ``plot``, ``baselines`` and ``evaluation`` are public too.
"""

from . import (
    baselines,
    datasets,
    hmm,
    io,
    limits,
    metrics,
    orientation,
    plot,
    synth,
)
from ._errors import (
    DataFileError,
    DecodeError,
    ExtrapolationWarning,
    MissingExtraError,
    ModelFormatError,
    NdlfdError,
    NdlfdWarning,
    NotFittedError,
    OptionError,
    ParallelError,
    ResourceLimitError,
    ValidationError,
)
from ._parallel import keep_workers, shutdown
from .codebook import Codebook, TimeBins
from .datasets import load_lasa
from .demonstration import Demonstration, with_velocity
from .dp import simplify, simplify_many
from .hmm import DiscreteHMM
from .jobs import evaluate, evaluation
from .learner import KeypointHMM
from .normalize import GroupScaler

__version__ = "0.1.0"

__all__ = [
    "Codebook",
    "DataFileError",
    "DecodeError",
    "Demonstration",
    "DiscreteHMM",
    "ExtrapolationWarning",
    "GroupScaler",
    "KeypointHMM",
    "MissingExtraError",
    "ModelFormatError",
    "NdlfdError",
    "NdlfdWarning",
    "NotFittedError",
    "OptionError",
    "ParallelError",
    "ResourceLimitError",
    "TimeBins",
    "ValidationError",
    "__version__",
    "baselines",
    "datasets",
    "evaluate",
    "evaluation",
    "hmm",
    "io",
    "keep_workers",
    "limits",
    "load_lasa",
    "metrics",
    "orientation",
    "plot",
    "shutdown",
    "simplify",
    "simplify_many",
    "synth",
    "with_velocity",
]
