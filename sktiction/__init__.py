"""sktiction: is this control loop oscillating because its valve sticks?

Signals -> cycles -> features -> decisions -> reports, in scikit-learn's idiom.
Loops are arrays ``(n_loops, n_samples, 3)`` with channels PV, OP, SP.
"""

from .classifiers import (
    AreaRatioClassifier,
    LearnedStictionClassifier,
    ShapeLibraryClassifier,
    make_learned_classifier,
    pretrained_classifier,
)
from .features import (
    AreaRatio,
    LoopDescriptors,
    OscillationFeatures,
    PVOPHysteresis,
    StictionModelFit,
    TemplateDistances,
    cycle_table,
)

__version__ = "0.1.0"

__all__ = [
    "AreaRatio",
    "AreaRatioClassifier",
    "LoopDescriptors",
    "OscillationFeatures",
    "ShapeLibraryClassifier",
    "StictionModelFit",
    "TemplateDistances",
    "cycle_table",
    "make_learned_classifier",
    "pretrained_classifier",
    "LearnedStictionClassifier",
    "PVOPHysteresis",
]
