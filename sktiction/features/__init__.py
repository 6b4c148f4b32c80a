"""Features of each loop, as scikit-learn transformers: area ratios, template distances,
cycle-free descriptors and a fitted valve model."""

from .area_ratio import AreaRatio
from .descriptors import LoopDescriptors
from .dtw import paired_dtw
from .hysteresis import PVOPHysteresis
from .oscillation import OscillationFeatures
from .stiction_model import StictionModelFit
from .template_distances import TemplateDistances, cycle_table

__all__ = [
    "AreaRatio",
    "LoopDescriptors",
    "StictionModelFit",
    "TemplateDistances",
    "cycle_table",
    "paired_dtw",
    "PVOPHysteresis",
    "OscillationFeatures",
]
