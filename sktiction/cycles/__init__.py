"""Cycle analysis: oscillation detection, mean removal, zero crossings, cycles, localisation."""

from ._analysis import REGULARITY_THRESHOLD, CycleAnalysis, analyze_cycles
from ._oscillation import OscillationComponent, detect_oscillations
from ._signal import (
    autocorrelation,
    dominant_period,
    horch_filter,
    moving_average,
    noise_std,
    remove_mean,
    schmitt_crossings,
)

__all__ = [
    "REGULARITY_THRESHOLD",
    "CycleAnalysis",
    "OscillationComponent",
    "analyze_cycles",
    "autocorrelation",
    "detect_oscillations",
    "dominant_period",
    "horch_filter",
    "moving_average",
    "noise_std",
    "remove_mean",
    "schmitt_crossings",
]
