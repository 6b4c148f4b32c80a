"""Features of each loop, as scikit-learn transformers: area ratios, template distances,
cycle-free descriptors and a fitted valve model."""

from .._lazy import attach

__getattr__, __dir__, __all__ = attach(
    __name__,
    {
        ".area_ratio": ["AreaRatio"],
        ".descriptors": ["LoopDescriptors"],
        ".dtw": ["paired_dtw"],
        ".hysteresis": ["PVOPHysteresis"],
        ".oscillation": ["OscillationFeatures"],
        ".stiction_model": ["StictionModelFit"],
        ".template_distances": ["TemplateDistances", "cycle_table"],
    },
)
