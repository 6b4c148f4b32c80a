"""sktiction: is this control loop oscillating because its valve sticks?

Signals -> cycles -> features -> decisions -> reports, in scikit-learn's idiom.
Loops are arrays ``(n_loops, n_samples, 3)`` with channels PV, OP, SP.
"""

from ._lazy import attach

__version__ = "0.1.0"

# imported on first use (see ._lazy): a new process that only loads the learned model
# does not pay for the rest of the package
__getattr__, __dir__, __all__ = attach(
    __name__,
    {
        "._cleaning": ["clean_loops"],
        ".classifiers": [
            "AreaRatioClassifier",
            "LearnedStictionClassifier",
            "ShapeLibraryClassifier",
            "make_learned_classifier",
            "pretrained_classifier",
        ],
        ".features": [
            "AreaRatio",
            "LoopDescriptors",
            "OscillationFeatures",
            "PVOPHysteresis",
            "StictionModelFit",
            "TemplateDistances",
            "cycle_table",
        ],
    },
)
