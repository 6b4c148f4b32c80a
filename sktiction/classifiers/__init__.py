"""Decisions: the shape library, the area-ratio rule and a learned classifier."""

from .._lazy import attach

__getattr__, __dir__, __all__ = attach(
    __name__,
    {
        ".applicability": ["assess_applicability"],
        ".area_ratio": ["AreaRatioClassifier"],
        "._coupling": ["domain_statistics", "pv_op_coupling"],
        ".learned": [
            "LearnedStictionClassifier",
            "make_learned_classifier",
            "make_loop_features",
        ],
        "._pretrained": ["pretrained_classifier"],
        ".shape_library": ["SHAPE_LIBRARY", "ShapeLibraryClassifier"],
    },
)
