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


@pytest.fixture
def dask_client():
    """A client of a one-worker in-process dask cluster (dashboards on free ports: 8787 may
    be taken by another cluster); skips without ``distributed``."""
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0",
        worker_dashboard_address=None,
    )  # fmt: skip
    with cluster, distributed.Client(cluster) as client:
        yield client
