"""Sim-to-real: measure what the simulated world gets wrong on measured loops, name it, fit it.

- :func:`loop_statistics`: one row of statistics per loop (noise, recording artefacts,
  setpoint regime, PV-OP relation), read by :func:`compare`; the applicability check
  computes two of them, the repeat shares, by the same code.
- :data:`EFFECTS`: the catalog, each effect with the statistic that detects it, the simulator
  effect that produces it and how it is fitted.
- :func:`compare`: effect-by-effect table, most evident first, and the domain AUC.
- :func:`calibrate`: a :class:`Realism` for ``make_loops(..., realism=...)``;
  :func:`apply_recording` applies its recording effects to loops already simulated.
"""

from ._catalog import EFFECTS, RealismEffect, effect_names
from .calibrate import Realism, apply_effects, apply_recording, calibrate
from .compare import as_statistics, compare, domain_gap
from .plots import plot_compare
from .statistics import STATISTIC_COLUMNS, loop_statistics

__all__ = [
    "loop_statistics",
    "STATISTIC_COLUMNS",
    "EFFECTS",
    "RealismEffect",
    "effect_names",
    "compare",
    "domain_gap",
    "as_statistics",
    "calibrate",
    "Realism",
    "apply_effects",
    "apply_recording",
    "plot_compare",
]
