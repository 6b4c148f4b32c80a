"""The valve-model fit: the normal-equation grid search gives the least-squares answer."""

import numpy as np

from sktiction._validation import loop_lengths
from sktiction.datasets import make_loops
from sktiction.features.stiction_model import (
    _design,
    _grid_normal_equations,
    _play,
    _sse,
    fit_stiction_band,
)


def lstsq_grid(pv, op, n_lags=8):
    """The fit as it was: one least-squares fit of the design per band (reference)."""
    n_lags = int(min(n_lags, max(2, pv.size // 20)))
    span = float(np.ptp(op))
    fracs = np.geomspace(0.002, 0.6, 24)
    base = _sse(pv, op, n_lags)
    sses = np.array([_sse(pv, _play(op, f * span), n_lags) for f in fracs])
    best = int(np.argmin(sses))
    if sses[best] >= base:
        return 0.0, 0.0
    return 1.0 - sses[best] / base, fracs[best] * span


def test_normal_equations_equal_the_design_products():
    rng = np.random.default_rng(0)
    pv, op = rng.normal(size=80), np.cumsum(rng.normal(size=80))
    bands = np.array([0.0, 0.7, 3.0])
    Gs, hs, bb = _grid_normal_equations(pv, op, bands, 5)
    for G, h, d in zip(Gs, hs, bands):
        A, b = _design(pv, _play(op, d), 5), pv[5:]
        np.testing.assert_allclose(G, A.T @ A, rtol=1e-12, atol=1e-10)
        np.testing.assert_allclose(h, A.T @ b, rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(bb, pv[5:] @ pv[5:])


def test_grid_search_gives_the_least_squares_gain_and_band():
    X, _ = make_loops(30, n_samples=4000, slip_fraction=0.25, random_state=3)
    n = loop_lengths(X)
    pairs = [(X[i, : n[i], 0], X[i, : n[i], 1]) for i in range(len(X))]
    rng = np.random.default_rng(1)
    for band in (0.5, 2.0, 5.0):  # PV driven through a known dead band
        op = 50 + np.cumsum(rng.normal(0, 0.3, 3000))
        pv = np.convolve(_play(op, band), [0.0, 0.0, 0.5, 0.3, 0.2])[:3000]
        pairs.append((pv + rng.normal(0, 0.05, 3000), op))
    gains = []
    for pv, op in pairs:
        gain, band = fit_stiction_band(pv, op)
        ref_gain, ref_band = lstsq_grid(pv, op)
        np.testing.assert_allclose([gain, band], [ref_gain, ref_band], rtol=1e-8, atol=1e-10)
        gains.append(gain)
    assert max(gains) > 0.5 and min(gains) < 0.01  # clear and absent valve models
