"""Closed-loop simulator: plants, PI(D) tuning, valves (healthy and sticky), effects."""

from .controllers import (
    TUNING_RULES,
    PIController,
    foptd_approximation,
    tune_pi,
    tune_pi_integrating,
)
from .effects import (
    ARNoise,
    Effect,
    Quantization,
    RandomWalkLoad,
    SetpointSteps,
    SinusoidalDisturbance,
    WhiteNoise,
)
from .historian import (
    DeadbandCompression,
    HoldLastValue,
    IntervalAveraging,
    SensorDrift,
    ShortRecord,
    SpanQuantization,
    Spikes,
    SwingingDoorCompression,
)
from .loop import simulate_loop, simulate_loops
from .plants import FOPTD, SOPTD, IntegratingPlant, NthOrderLag
from .valves import (
    VALVE_MODELS,
    ChoudhuryValve,
    DeadbandValve,
    KanoValve,
    LinearValve,
    RelayValve,
    make_valve,
)

__all__ = [
    "FOPTD",
    "SOPTD",
    "NthOrderLag",
    "IntegratingPlant",
    "PIController",
    "tune_pi",
    "tune_pi_integrating",
    "foptd_approximation",
    "TUNING_RULES",
    "LinearValve",
    "RelayValve",
    "ChoudhuryValve",
    "KanoValve",
    "DeadbandValve",
    "make_valve",
    "VALVE_MODELS",
    "Effect",
    "WhiteNoise",
    "ARNoise",
    "RandomWalkLoad",
    "SetpointSteps",
    "SinusoidalDisturbance",
    "Quantization",
    "simulate_loop",
    "simulate_loops",
    "HoldLastValue",
    "DeadbandCompression",
    "SwingingDoorCompression",
    "IntervalAveraging",
    "SpanQuantization",
    "Spikes",
    "SensorDrift",
    "ShortRecord",
]

from .disturbances import (  # noqa: E402
    BandLimitedNoise,
    CascadeSetpoint,
    ColouredLoad,
    Drift,
    LoadStep,
    NarrowbandDisturbance,
    PVVariation,
    SquareDisturbance,
)
from .valves import HeValve  # noqa: E402

__all__ += [
    "HeValve",
    "BandLimitedNoise",
    "ColouredLoad",
    "NarrowbandDisturbance",
    "SquareDisturbance",
    "Drift",
    "CascadeSetpoint",
    "LoadStep",
    "PVVariation",
]
