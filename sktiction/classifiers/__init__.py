"""Decisions: the shape library, the area-ratio rule and a learned classifier."""

from .applicability import assess_applicability
from .area_ratio import AreaRatioClassifier
from .learned import (
    LearnedStictionClassifier,
    make_learned_classifier,
    make_loop_features,
    pretrained_classifier,
)
from .shape_library import SHAPE_LIBRARY, ShapeLibraryClassifier

__all__ = [
    "SHAPE_LIBRARY",
    "AreaRatioClassifier",
    "ShapeLibraryClassifier",
    "LearnedStictionClassifier",
    "assess_applicability",
    "make_learned_classifier",
    "make_loop_features",
    "pretrained_classifier",
]
