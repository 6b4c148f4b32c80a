"""Fixtures shared by test modules (with ``--import-mode=importlib`` a test module cannot
import a sibling, so shared signal makers live here)."""

import numpy as np
import pytest

from sktiction.features.stiction_model import _play


def _valve_walk(band=2.0, n=3000, seed=0):
    """PV behind a valve with dead band ``band`` and a short lag, OP a random walk, PV noisy:
    the loop of :func:`~sktiction.features.stiction_model.fit_stiction_band`'s example."""
    rng = np.random.default_rng(seed)
    op = 50 + np.cumsum(rng.normal(0, 0.3, n))
    pv = np.convolve(_play(op, band), [0.0, 0.0, 0.5, 0.3, 0.2])[:n]
    return pv + rng.normal(0, 0.05, n), op


@pytest.fixture
def valve_walk():
    """:func:`_valve_walk`: ``valve_walk(band=2.0, n=3000, seed=0) -> (pv, op)``."""
    return _valve_walk
