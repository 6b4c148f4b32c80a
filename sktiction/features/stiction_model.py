"""Fit a valve dead-band model between OP and PV: evidence that needs no cycles.

A sticky valve does not move when the controller output u reverses until u has
travelled its dead band + stick band d. If PV is explained better by a linear ARX
model driven by such a valve position x than by u itself, the loop carries the
signature of a sticking valve, whether it oscillates or shows only a few slips during
setpoint moves. This is the Hammerstein-model idea of Srinivasan et al.'s companion
paper, reduced to a grid search over d with a linear least-squares fit per point.

The valve model is the play (backlash) operator, not the relay of seed 001 Eq. 2: the
relay's slip times depend on d through the whole past, so its fit error jumps about
as d changes and a grid misses the optimum, while the play operator's output changes
smoothly with d (and it re-synchronises with u after each reversal, so noise on OP
does not compound). The slip jump itself is left to the cycle features.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .._validation import OP, PV
from ._loops import LoopTransformer

FEATURES = ("stiction_fit_gain", "stiction_fit_band", "stiction_fit_band_share")


@njit(cache=True, nogil=True)
def _play(u, d):
    """Valve position behind a dead band d: it moves only when u pushes it by > d / 2."""
    h = 0.5 * d
    x = np.empty_like(u)
    x[0] = u[0]
    for t in range(1, u.size):
        x[t] = min(max(x[t - 1], u[t] - h), u[t] + h)
    return x


def _design(pv, x, n_lags):
    """Rows t >= n_lags of [pv[t-1], pv[t-2], x[t-1..t-n_lags], 1] for ARX."""
    n = pv.size
    cols = [pv[n_lags - 1 : n - 1], pv[n_lags - 2 : n - 2]]
    cols += [x[n_lags - k : n - k] for k in range(1, n_lags + 1)]
    cols.append(np.ones(n - n_lags))
    return np.column_stack(cols)


def _sse(pv, x, n_lags):
    A = _design(pv, x, n_lags)
    b = pv[n_lags:]
    coef, *_ = np.linalg.lstsq(A, b, rcond=None)
    r = b - A @ coef
    return float(r @ r)


def fit_stiction_band(pv, op, *, n_lags=8, grid=None):
    """Best dead band d of the valve model and how much of PV it explains.

    Parameters
    ----------
    pv, op : ndarray of shape (n_samples,)
        Process variable and controller output of one loop, without NaN.
    n_lags : int, default=8
        Valve-position lags of the ARX model (covers the dead time in samples).
    grid : array-like or None, default=None
        Candidate bands as fractions of OP's peak-to-peak; ``None`` uses 24 values
        spaced geometrically from 0.2 % to 60 %.

    Returns
    -------
    gain : float
        ``1 - SSE(best d) / SSE(d = 0)``: the share of the linear model's residual
        that the stiction model removes (0 when no band helps).
    band : float
        Best d in OP units (0 when no band helps).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.features.stiction_model import _play, fit_stiction_band
    >>> rng = np.random.default_rng(0)
    >>> op = 50 + np.cumsum(rng.normal(0, 0.3, 3000))
    >>> x = _play(op, 2.0)
    >>> pv = np.convolve(x, [0.0, 0.0, 0.5, 0.3, 0.2])[:3000] + rng.normal(0, 0.05, 3000)
    >>> gain, band = fit_stiction_band(pv, op)
    >>> bool(gain > 0.5), bool(1.6 < band < 2.4)
    (True, True)
    """
    pv = np.ascontiguousarray(pv, dtype=float)
    op = np.ascontiguousarray(op, dtype=float)
    n_lags = int(min(n_lags, max(2, pv.size // 20)))
    if pv.size < 4 * (n_lags + 3):
        return np.nan, np.nan
    span = float(np.ptp(op))
    if span == 0 or np.ptp(pv) == 0:
        return np.nan, np.nan
    fracs = np.geomspace(0.002, 0.6, 24) if grid is None else np.asarray(grid, dtype=float)
    base = _sse(pv, op, n_lags)
    if base == 0:
        return 0.0, 0.0
    sses = np.array([_sse(pv, _play(op, f * span), n_lags) for f in fracs])
    best = int(np.argmin(sses))
    if sses[best] >= base:
        return 0.0, 0.0
    return 1.0 - sses[best] / base, float(fracs[best] * span)


class StictionModelFit(LoopTransformer):
    """Evidence of stiction from fitting a valve model, with or without oscillation.

    For each loop, searches the dead band d of a valve model (the play operator)
    that best explains PV from OP through a linear ARX model, and reports how much
    of the linear model's residual it removes. A healthy valve
    gives a gain near 0; a sticky one a clear gain and d near its band, also when
    the window holds only a few slips during setpoint moves.

    Columns: ``stiction_fit_gain`` (share of residual removed, 0-1),
    ``stiction_fit_band`` (best d in OP units), ``stiction_fit_band_share`` (d over
    OP's peak-to-peak). Loops without OP or that cannot be analysed get NaN.

    Parameters
    ----------
    n_lags : int, default=8
        Valve-position lags of the ARX model, in samples.

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.features import StictionModelFit
    >>> X, _ = make_loops(2, n_samples=1500, random_state=0)
    >>> StictionModelFit().fit_transform(X).shape
    (2, 3)
    """

    feature_names = FEATURES
    _needs_op = True

    def __init__(self, n_lags=8):
        self.n_lags = n_lags

    def _validate_params(self):
        if int(self.n_lags) != self.n_lags or self.n_lags < 1:
            raise ValueError(f"n_lags must be an integer >= 1; got {self.n_lags!r}.")

    def _transform_loop(self, loops, i, n):
        pv, op = loops[i, :n, PV], loops[i, :n, OP]
        gain, band = fit_stiction_band(pv, op, n_lags=self.n_lags)
        return [gain, band, band / np.ptp(op) if np.isfinite(band) else np.nan]
