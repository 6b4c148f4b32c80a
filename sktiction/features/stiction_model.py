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

FEATURES = (
    "stiction_fit_gain",
    "stiction_fit_band",
    "stiction_fit_band_share",
    "multiscale_fit_gain",
    "multiscale_fit_band_share",
)
#: Block lengths (rows averaged) of the multi-scale fit, and the fewest blocks a fit reads.
SCALES = (1, 2, 4, 8, 16)
MIN_BLOCKS = 150
#: Candidate bands as fractions of OP's peak-to-peak (made once: ``np.geomspace``
#: costs as much as a small fit).
_DEFAULT_GRID = np.geomspace(0.002, 0.6, 24)
_DEFAULT_GRID.flags.writeable = False
#: A linear fit's residual below this share of PV's sum of squares is exact to rounding.
_EXACT_FIT = 1e-20


@njit(cache=True, nogil=True)
def _play(u, d):
    """Valve position behind a dead band d: it moves only when u pushes it by > d / 2."""
    h = 0.5 * d
    x = np.empty_like(u)
    x[0] = u[0]
    for t in range(1, u.size):
        x[t] = min(max(x[t - 1], u[t] - h), u[t] + h)
    return x


@njit(cache=True, nogil=True)
def _window_sum(x, y, lag, k, n_lags, core):
    """``sum over t in [n_lags, n) of x[t - k] * y[t - k + lag]``, given ``core``, the sum
    over s in [n_lags, n - n_lags) of ``x[s] * y[s + lag]`` that every window contains."""
    n = x.size
    acc = core
    for s in range(n_lags - k, n_lags):
        acc += x[s] * y[s + lag]
    for s in range(n - n_lags, n - k):
        acc += x[s] * y[s + lag]
    return acc


@njit(cache=True, nogil=True)
def _grid_normal_equations(pv, op, bands, n_lags):
    """Normal equations ``G = A'A``, ``h = A'b`` of the ARX design whose rows t >= n_lags
    are ``[pv[t-1], pv[t-2], x[t-1..t-n_lags], 1]``
    for the valve position ``_play(op, d)`` of every band d.

    Every cross-product is a sum over a window that slides with the lag: one dot
    product per lag difference over the part all windows share, plus at most
    ``n_lags`` terms at each end, so each band costs O(n * n_lags) without ever
    building the design matrix.
    """
    n = pv.size
    m = n_lags + 3
    lo, hi = n_lags, n - n_lags
    Gs = np.empty((bands.size, m, m))
    hs = np.empty((bands.size, m))
    b = pv[n_lags:]
    p1, p2 = pv[n_lags - 1 : n - 1], pv[n_lags - 2 : n - 2]
    ones = np.ones(n)
    core_x = np.empty(n_lags)
    core_xp = np.empty(n_lags + 3)
    # the PV and intercept entries are the same for every band: computed once
    g00, g01, g11 = np.dot(p1, p1), np.dot(p1, p2), np.dot(p2, p2)
    h0, h1 = np.dot(p1, b), np.dot(p2, b)
    s1, s2, sb = p1.sum(), p2.sum(), b.sum()
    for g in range(bands.size):
        x = _play(op, bands[g])
        G, h = Gs[g], hs[g]
        G[0, 0], G[0, 1], G[1, 1] = g00, g01, g11
        G[1, 0] = G[0, 1]
        h[0], h[1] = h0, h1
        G[0, m - 1] = G[m - 1, 0] = s1
        G[1, m - 1] = G[m - 1, 1] = s2
        G[m - 1, m - 1] = n - n_lags
        h[m - 1] = sb
        xc = x[lo:hi]
        for lag in range(n_lags):  # x with x, lag difference 0..n_lags-1
            core_x[lag] = np.dot(xc, x[lo + lag : hi + lag])
        for j in range(n_lags + 3):  # x with pv, lags -2..n_lags
            core_xp[j] = np.dot(xc, pv[lo + j - 2 : hi + j - 2])
        core_1 = xc.sum()
        for a in range(n_lags):
            ka = a + 1
            for c in range(a, n_lags):
                kc = c + 1
                v = _window_sum(x, x, c - a, kc, n_lags, core_x[c - a])
                G[2 + a, 2 + c] = v
                G[2 + c, 2 + a] = v
            for q in range(2):  # pv lags 1 and 2
                lag = ka - (q + 1)
                v = _window_sum(x, pv, lag, ka, n_lags, core_xp[lag + 2])
                G[2 + a, q] = v
                G[q, 2 + a] = v
            h[2 + a] = _window_sum(x, pv, ka, ka, n_lags, core_xp[ka + 2])
            v = _window_sum(x, ones, 0, ka, n_lags, core_1)
            G[2 + a, m - 1] = v
            G[m - 1, 2 + a] = v
    return Gs, hs, np.dot(b, b)


@njit(cache=True, nogil=True)
def _cholesky_solve(Gs, hs, min_pivot):
    """Each band's coefficients by Cholesky on the unit-diagonal scaled normal equations,
    and whether every pivot reached ``min_pivot`` (else the band is left to the
    eigen-decomposition of :func:`_solve_normal`)."""
    n_g, m = hs.shape
    coefs = np.zeros((n_g, m))
    ok = np.ones(n_g, dtype=np.bool_)
    L = np.empty((m, m))
    d = np.empty(m)
    y = np.empty(m)
    for g in range(n_g):
        for i in range(m):
            d[i] = np.sqrt(Gs[g, i, i]) if Gs[g, i, i] > 0 else 1.0
        for j in range(m):
            s = Gs[g, j, j] / (d[j] * d[j])
            for k in range(j):
                s -= L[j, k] * L[j, k]
            if not s >= min_pivot:  # also NaN
                ok[g] = False
                break
            L[j, j] = np.sqrt(s)
            for i in range(j + 1, m):
                s = Gs[g, i, j] / (d[i] * d[j])
                for k in range(j):
                    s -= L[i, k] * L[j, k]
                L[i, j] = s / L[j, j]
        if not ok[g]:
            continue
        for i in range(m):  # L y = h / d
            s = hs[g, i] / d[i]
            for k in range(i):
                s -= L[i, k] * y[k]
            y[i] = s / L[i, i]
        for i in range(m - 1, -1, -1):  # L' z = y
            s = y[i]
            for k in range(i + 1, m):
                s -= L[k, i] * coefs[g, k]
            coefs[g, i] = s / L[i, i]
        for i in range(m):
            coefs[g, i] /= d[i]
    return coefs, ok


def _solve_normal(Gs, hs):
    """Least-squares coefficients from a stack of normal equations.

    Columns are scaled to a unit diagonal. Where the scaled Gram matrix is well
    conditioned (every Cholesky pivot at least 1e-6: its smallest eigenvalue is then far
    above the 1e-15 cut below) Cholesky solves it; otherwise it is inverted on its
    well-determined eigen-directions (a pseudo-inverse), so a valve position that barely
    moves (collinear columns) still gets the least-squares fit (least norm in the scaled
    columns). Cholesky's loops cost a tenth of a batched ``eigh`` on these 11 x 11 systems.
    """
    coefs, ok = _cholesky_solve(Gs, hs, 1e-6)
    if ok.all():
        return coefs
    bad = ~ok
    G, h = Gs[bad], hs[bad]
    d = np.sqrt(np.einsum("gii->gi", G))
    d[d == 0] = 1.0
    w, V = np.linalg.eigh(G / (d[:, :, None] * d[:, None, :]))
    keep = w > 1e-15 * w[:, -1:]
    proj = np.einsum("gij,gi->gj", V, h / d)
    proj = np.where(keep, proj / np.where(keep, w, 1.0), 0.0)
    coefs[bad] = np.einsum("gij,gj->gi", V, proj) / d
    return coefs


@njit(cache=True, nogil=True)
def _residual_sse(pv, x, n_lags, coef):
    """``|b - A coef|^2`` on the ARX design, row by row without building
    it: exact for the coefficients given, and off the least squares only to second order
    in their error."""
    m = n_lags + 3
    acc = 0.0
    for t in range(n_lags, pv.size):
        pred = coef[0] * pv[t - 1] + coef[1] * pv[t - 2]
        for k in range(1, n_lags + 1):
            pred += coef[1 + k] * x[t - k]
        r = pv[t] - (pred + coef[m - 1])
        acc += r * r
    return acc


def fit_stiction_band(pv, op, *, n_lags=8, grid=None):
    """Best dead band d of the valve model and how much of PV it explains.

    Parameters
    ----------
    pv, op : ndarray of shape (n_samples,)
        Process variable and controller output of one loop, without NaN.
    n_lags : int, default=8
        Valve-position lags of the ARX model (covers the dead time in samples);
        at least 2, as the model's two PV lags need.
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
    if int(n_lags) != n_lags or n_lags < 2:
        raise ValueError(f"n_lags must be an integer >= 2; got {n_lags!r}.")
    curve = band_curve(pv, op, n_lags=n_lags, grid=grid)
    if curve is None:
        return np.nan, np.nan
    pv, op, n_lags, bands, coefs, sses = curve
    best = 1 + int(np.argmin(sses[1:]))
    # the two residuals that are reported, recomputed on the design itself
    base = _residual_sse(pv, op, n_lags, coefs[0])
    # PV that its own two lags predict exactly (a noise-free sine or ramp) leaves both
    # residuals at rounding level, whose ratio means nothing: no room for a band
    if base <= _EXACT_FIT * float(pv[n_lags:] @ pv[n_lags:]):
        return 0.0, 0.0
    sse_best = _residual_sse(pv, _play(op, bands[best]), n_lags, coefs[best])
    if sse_best >= base:
        return 0.0, 0.0
    return 1.0 - sse_best / base, float(bands[best])


def block_means(x, k):
    """Means of consecutive blocks of ``k`` samples (a last, shorter block is dropped)."""
    m = x.size // k
    return x[: m * k].reshape(m, k).mean(axis=1)


def _chance_gain(m):
    """The gain a dead band reaches by chance on ``m`` fitted rows: the smallest that lowers
    the Bayesian information criterion of the fit by its one extra parameter,
    ``m ln(SSE_linear / SSE_band) > ln m``."""
    return 1.0 - m ** (-1.0 / m)


def fit_stiction_band_multiscale(pv, op, *, n_lags=8, scales=SCALES, min_blocks=MIN_BLOCKS,
                                 first=None):
    """:func:`fit_stiction_band` on block means of 1, 2, 4, 8 and 16 samples: the valve
    fit at the loop's own time scale.

    One step ahead, PV moves little: in a loop sampled finely next to its dynamics (a
    delay beyond the model's lags, a time constant of tens of samples) the valve's part
    of that step is small next to the noise, and no band helps the fit. On block means the
    same loop's dead band shows. Each scale's gain is counted beyond what a band gains by
    chance on that many rows (:func:`_chance_gain`, larger on fewer blocks), and the scale
    with the most is kept. Univariate AUC of the gain, sticky against healthy (one scale /
    the best of these scales): default world 0.67 / 0.77, second simulator 0.67 / 0.93,
    third 0.52 / 0.58, measured windows 0.53 / 0.80.

    Parameters
    ----------
    pv, op : ndarray of shape (n_samples,)
        Process variable and controller output of one loop, without NaN.
    n_lags : int, default=8
        As :func:`fit_stiction_band`, at every scale.
    scales : tuple of int, default=(1, 2, 4, 8, 16)
        Block lengths tried, shortest first.
    min_blocks : int, default=150
        Fewest block means a scale must give to be tried.
    first : tuple (gain, band) or None, default=None
        The fit at block length 1 when the caller has it already.

    Returns
    -------
    gain : float
        The best scale's :func:`fit_stiction_band` gain beyond chance, at least 0 (NaN
        when no scale can be fitted).
    band_share : float
        Its band over the peak-to-peak of OP's block means (0 when no scale's band
        gains more than chance).
    scale : int
        Its block length (0 when no scale gains more than chance or none can be fitted).

    Examples
    --------
    A delay of 20 samples, beyond the eight lags of a one-step fit, hides the band at
    the record's own sampling and not on block means:

    >>> import numpy as np
    >>> from scipy.signal import lfilter
    >>> from sktiction.features.stiction_model import (
    ...     _play, fit_stiction_band, fit_stiction_band_multiscale)
    >>> rng = np.random.default_rng(0)
    >>> op = 50 + np.cumsum(rng.normal(0, 0.3, 4000))
    >>> valve = _play(op, 4.0)  # a dead band of 4 % in OP's units
    >>> lagged = lfilter([0.05], [1, -0.95], valve - valve[0])  # time constant 20
    >>> pv = np.r_[np.zeros(20), lagged[:-20]] + rng.normal(0, 0.2, 4000)
    >>> bool(fit_stiction_band(pv, op)[0] < 0.05)
    True
    >>> gain, share, scale = fit_stiction_band_multiscale(pv, op)
    >>> bool(gain > 0.3), scale > 1, bool(share > 0.02)
    (True, True, True)
    """
    best, fitted = (0.0, 0.0, 0), False
    for k in scales:
        m = pv.size // k
        if m < min_blocks:
            break
        opk = op if k == 1 else block_means(op, k)
        if k == 1 and first is not None:
            gain, band = first
        else:
            gain, band = fit_stiction_band(pv if k == 1 else block_means(pv, k), opk,
                                           n_lags=n_lags)  # fmt: skip
        if not np.isfinite(gain):
            continue
        fitted = True
        excess = gain - _chance_gain(m)
        if excess > best[0]:
            best = (excess, band / np.ptp(opk), k)
    return best if fitted else (np.nan, np.nan, 0)


def band_curve(pv, op, *, n_lags=8, grid=None):
    """The fit of every band of the grid, from its normal equations (O(n) per band, no
    design matrix), or ``None`` when there is nothing to fit.

    Returns ``(pv, op, n_lags, bands, coefs, sses)``: the centred signals, the lags
    used, the bands in OP units (band 0 first: the linear model on OP itself, as the
    play operator with d = 0 is u), each band's ARX coefficients and residual sum of
    squares. :func:`fit_stiction_band` picks the best; a fit over several block phases
    (:func:`~sktiction.features.hysteresis.valve_fit`) averages the curves first.
    """
    pv = np.ascontiguousarray(pv, dtype=float)
    op = np.ascontiguousarray(op, dtype=float)
    n_lags = int(min(n_lags, max(2, pv.size // 20)))
    if pv.size < 4 * (n_lags + 3):
        return None
    span = float(np.ptp(op))
    if span == 0 or np.ptp(pv) == 0:
        return None
    fracs = _DEFAULT_GRID if grid is None else np.asarray(grid, dtype=float)
    # shifting PV and OP changes no residual (the model has an intercept and the play
    # operator commutes with a shift); centred, the normal equations lose no precision
    pv = pv - pv.mean()
    op = op - op.mean()
    bands = np.concatenate([[0.0], fracs * span])
    Gs, hs, bb = _grid_normal_equations(pv, op, bands, n_lags)
    coefs = _solve_normal(Gs, hs)
    sses = bb - np.einsum("gi,gi->g", coefs, hs)
    return pv, op, n_lags, bands, coefs, sses


class StictionModelFit(LoopTransformer):
    """Evidence of stiction from fitting a valve model, with or without oscillation.

    For each loop, searches the dead band d of a valve model (the play operator)
    that best explains PV from OP through a linear ARX model, and reports how much
    of the linear model's residual it removes. A healthy valve
    gives a gain near 0; a sticky one a clear gain and d near its band, also when
    the window holds only a few slips during setpoint moves.

    Columns: ``stiction_fit_gain`` (share of residual removed, 0-1),
    ``stiction_fit_band`` (best d in OP units), ``stiction_fit_band_share`` (d over
    OP's peak-to-peak), and the same fit at the loop's own time scale
    (:func:`fit_stiction_band_multiscale`: the best of the fits on block means of 1-16
    samples), ``multiscale_fit_gain`` and ``multiscale_fit_band_share``. Loops without
    OP or that cannot be analysed get NaN.

    Parameters
    ----------
    n_lags : int, default=8
        Valve-position lags of the ARX model, in samples (at least 2).

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.features import StictionModelFit
    >>> X, _ = make_loops(2, n_samples=1500, random_state=0)
    >>> StictionModelFit().fit_transform(X).shape
    (2, 5)
    """

    feature_names = FEATURES
    _needs_op = True

    def __init__(self, n_lags=8):
        self.n_lags = n_lags

    def _validate_params(self):
        # the ARX design always has two PV lags, so its rows start at t = max(n_lags, 2)
        if int(self.n_lags) != self.n_lags or self.n_lags < 2:
            raise ValueError(f"n_lags must be an integer >= 2; got {self.n_lags!r}.")

    def _transform_loop(self, loops, i, n):
        pv, op = loops[i, :n, PV], loops[i, :n, OP]
        gain, band = fit_stiction_band(pv, op, n_lags=self.n_lags)
        coarse, share, _ = fit_stiction_band_multiscale(pv, op, n_lags=self.n_lags,
                                                        first=(gain, band))  # fmt: skip
        return [gain, band, band / np.ptp(op) if np.isfinite(band) else np.nan, coarse, share]
