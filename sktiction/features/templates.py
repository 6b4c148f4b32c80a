"""Per-cycle reference templates (seed 001, section 4.2.1) and matching them by DTW."""

from __future__ import annotations

import numpy as np
from numba import njit

from .._validation import check_random_state_seed
from .dtw import paired_dtw, tslearn_paired_dtw

SHAPES = ("rectangular", "triangular", "sinusoidal", "trapezoidal")
#: Trapezoid ramps take this share of each half at either end.
TRAPEZOID_RAMP = 0.2
# mean of each unit half-shape over its half, to match areas
_SHAPE_MEAN = np.array([1.0, 0.5, 2.0 / np.pi, 1.0 - TRAPEZOID_RAMP])


def unit_half(shape, tau):
    """One half-cycle of a unit-height shape at positions ``tau`` in [0, 1]."""
    tau = np.asarray(tau, dtype=float)
    if shape == "rectangular":
        return np.ones_like(tau)
    if shape == "triangular":
        return 1.0 - np.abs(2.0 * tau - 1.0)
    if shape == "sinusoidal":
        return np.sin(np.pi * tau)
    if shape == "trapezoidal":
        return np.minimum(1.0, np.minimum(tau, 1.0 - tau) / TRAPEZOID_RAMP)
    raise ValueError(f"shape must be one of {SHAPES}; got {shape!r}.")


def cycle_templates(split, mean_first, mean_second, n_points):
    """The four templates of full cycles, on ``n_points`` bins each.

    Each half keeps the data's duration (the first half ends at fraction ``split``
    of the cycle) and its area: the template half is scaled so its mean equals the
    data half's mean (``mean_first``, ``mean_second``, signed). Matching areas
    rather than peaks keeps a single noisy sample from setting the template height.
    Arguments may be arrays, one value per cycle.

    Returns
    -------
    templates : ndarray of shape (4, n_points), or (n_cycles, 4, n_points)
        Shapes in the order of :data:`SHAPES`.
    """
    split, m1, m2 = (np.asarray(v, dtype=float)[..., None] for v in (split, mean_first,
                                                                      mean_second))
    t = (np.arange(n_points) + 0.5) / n_points  # bin centres
    first = t < split
    tau = np.where(first, t / np.maximum(split, 1e-12), (t - split) / np.maximum(1 - split, 1e-12))
    scale = np.where(first, m1, m2)
    return np.stack([unit_half(s, tau) * scale / m for s, m in zip(SHAPES, _SHAPE_MEAN)], axis=-2)


def resample(x, start, end, n_points, cumulative=None):
    """Mean of ``x`` over each of ``n_points`` equal bins from ``start`` to ``end``.

    Averaging over bins (not sampling points) lowers the noise by the square root
    of the samples per bin, which keeps DTW from warping noise into a better match.
    ``start`` and ``end`` may be arrays (one row of bins per cycle); ``cumulative``
    may pass ``concatenate([[0], cumsum(x)])`` precomputed.
    """
    c = np.concatenate([[0.0], np.cumsum(x)]) if cumulative is None else cumulative
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    frac = np.linspace(0.0, 1.0, n_points + 1)
    edges = start[..., None] + (end - start)[..., None] * frac
    # integral of the piecewise-constant signal (sample i covers [i - 0.5, i + 0.5))
    integral = np.interp(edges + 0.5, np.arange(c.size), c)
    return np.diff(integral, axis=-1) / np.diff(edges, axis=-1)


@njit(cache=True, nogil=True)
def _range_extrema(x, starts, stops):
    top = np.empty(starts.size)
    bottom = np.empty(starts.size)
    for k in range(starts.size):
        lo, hi = max(starts[k], 0), min(stops[k], x.size)
        t, b = -np.inf, np.inf
        for i in range(lo, hi):
            if x[i] > t:
                t = x[i]
            if x[i] < b:
                b = x[i]
        top[k], bottom[k] = t, b
    return top, bottom


def range_extrema(x, starts, stops):
    """Largest and smallest value of ``x[starts[k]:stops[k]]`` for every k.

    One compiled pass over the ranges (cycles of a loop barely overlap, so this is
    linear in the record length); an empty range gives ``-inf, inf``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.features.templates import range_extrema
    >>> top, bottom = range_extrema(np.array([0.0, 3, -1, 2]), np.array([0, 2]),
    ...                             np.array([2, 9]))
    >>> top.tolist(), bottom.tolist()
    ([3.0, 2.0], [0.0, -1.0])
    """
    return _range_extrema(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(starts, dtype=np.int64),
        np.ascontiguousarray(stops, dtype=np.int64),
    )


def match_cycles(x, bounds, *, n_points=32, sakoe_chiba_radius=2, backend="numba"):
    """DTW distance of each cycle of ``x`` to its four templates.

    Parameters
    ----------
    x : ndarray of shape (n_samples,)
        Mean-removed signal.
    bounds : ndarray of shape (n_cycles, 3)
        Fractional sample positions (start, middle, end) of each full cycle; the
        middle is the zero crossing between its two halves.
    n_points : int, default=32
        Bins each cycle is averaged into, so cycles of any period compare alike.
    sakoe_chiba_radius : int or None, default=2
        DTW band in bins (``None``: unconstrained, as in seed 001).
    backend : {"numba", "tslearn"}, default="numba"
        DTW implementation (identical results; tslearn is much slower).

    Returns
    -------
    distances : ndarray of shape (n_cycles, 4)
        Columns in the order of :data:`SHAPES`; each cycle and its templates are
        divided by the cycle's RMS first, so distances do not depend on amplitude.
    """
    bounds = np.asarray(bounds, dtype=float).reshape(-1, 3)
    n = len(bounds)
    if n == 0:
        return np.empty((0, len(SHAPES)))
    a, m, b = bounds.T
    data = resample(x, a, b, n_points)
    split = (m - a) / (b - a)
    first = (np.arange(n_points) + 0.5) / n_points < split[:, None]
    n1 = np.maximum(first.sum(axis=1), 1)
    n2 = np.maximum((~first).sum(axis=1), 1)
    mean1 = np.where(first, data, 0.0).sum(axis=1) / n1
    mean2 = np.where(first, 0.0, data).sum(axis=1) / n2
    rms = np.sqrt(np.mean(data**2, axis=1))
    rms[rms == 0] = 1.0
    data /= rms[:, None]
    temps = cycle_templates(split, mean1 / rms, mean2 / rms, n_points)
    A = np.repeat(data, len(SHAPES), axis=0)
    B = temps.reshape(-1, n_points)
    fn = paired_dtw if backend == "numba" else tslearn_paired_dtw
    return fn(A, B, sakoe_chiba_radius=sakoe_chiba_radius).reshape(n, len(SHAPES))


def make_shape_cycles(
    shape,
    n_cycles=20,
    *,
    period=100,
    period_jitter=0.3,
    half_ratio=2.0,
    amplitude_ratio=1.5,
    snr_db=20.0,
    random_state=None,
):
    """A signal made of full cycles of one template shape, with known cycle bounds.

    Each cycle's period varies by up to ``period_jitter`` around ``period``; its
    halves' durations differ by a factor up to ``half_ratio`` and their heights by
    up to ``amplitude_ratio``; white noise is added at ``snr_db`` relative to the
    clean signal's power.

    Returns
    -------
    x : ndarray
        The signal.
    bounds : ndarray of shape (n_cycles, 3)
        Start, middle and end of each cycle.

    Examples
    --------
    >>> from sktiction.features.templates import make_shape_cycles
    >>> x, bounds = make_shape_cycles("triangular", 5, random_state=0)
    >>> bounds.shape
    (5, 3)
    """
    rng = check_random_state_seed(random_state)
    parts, bounds, pos = [], [], 0
    for _ in range(n_cycles):
        p = period * rng.uniform(1 - period_jitter, 1 + period_jitter)
        r = rng.uniform(1.0, half_ratio) ** rng.choice([-1, 1])
        n1 = max(3, int(round(p * r / (1 + r))))
        n2 = max(3, int(round(p - n1)))
        h = rng.uniform(1.0, amplitude_ratio) ** rng.choice([-1, 1])
        t1 = (np.arange(n1) + 0.5) / n1
        t2 = (np.arange(n2) + 0.5) / n2
        parts += [unit_half(shape, t1) * h, -unit_half(shape, t2) / h]
        bounds.append((pos, pos + n1, pos + n1 + n2))
        pos += n1 + n2
    x = np.concatenate(parts)
    noise_sd = np.sqrt(np.mean(x**2) / 10 ** (snr_db / 10))
    return x + rng.normal(0.0, noise_sd, x.size), np.array(bounds, dtype=float)
