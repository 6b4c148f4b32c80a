"""Sim-to-real: measure what the simulated world gets wrong on measured loops.

:func:`loop_statistics` gives one row of statistics per loop (noise, recording artefacts,
setpoint regime, PV-OP relation); the other tools of this package read them.
"""

from .statistics import STATISTIC_COLUMNS, loop_statistics

__all__ = ["loop_statistics", "STATISTIC_COLUMNS"]
