"""Signal helpers for cycle analysis: noise level, dominant period, mean removal, filters."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numba import njit

#: Magnitudes within 2**±200 (about 1e±60) are read in their own units.
_UNIT_RANGE = 200


def unit_scaled(x):
    """``x`` and 1, or, when its largest magnitude lies beyond 2**±200, ``x`` divided by
    the power of two nearest above it (2**1023 for the largest doubles, whose next power
    overflows), and that power: values near 1e300 are read
    without overflow in a spectrum's squares and values near 1e-300 without underflow
    (a power of two scales exactly; records within the range are read as given, to the
    bit)."""
    top = np.max(np.abs(x)) if x.size else 0.0
    if not np.isfinite(top) or top == 0 or abs(np.frexp(top)[1]) <= _UNIT_RANGE:
        return x, 1.0
    # above 2**1023 the power nearest above is 2**1024, an overflow: use 2**1023 there
    unit = 2.0 ** min(int(np.frexp(top)[1]), 1023)
    return x / unit, unit


def fast_median(x):
    """``np.median`` of a 1-D float array, to the bit, by sorting.

    numpy selects the middle by partitioning, which is slow on the long runs of equal
    values of held or quantised records (second differences that are mostly zero);
    a full sort (vectorised) is 3x faster there. The middle, or the mean of the two
    middles as numpy forms it, is then the same number (a zero may carry the other
    sign: which of -0.0 and 0.0, equal to any comparison, lands in the middle depends
    on the order the selection leaves them in, in numpy too).
    """
    return sorted_median(np.sort(np.asarray(x)))


def sorted_median(s):
    """:func:`fast_median` of an array already sorted (one sort serves several statistics)."""
    if s.size == 0 or s.dtype != np.float64 or np.isnan(s[-1]):
        return np.median(s)  # NaN sorts last: numpy's answer (and warnings) for these
    h = s.size // 2  # numpy's mean of the middle one or two: a sum from 0.0, then divided
    return 0.0 + s[h] if s.size % 2 else (0.0 + s[h - 1] + s[h]) / 2


def fast_percentile(x, q):
    """``np.percentile(x, q)`` (linear method) of a 1-D float array, to the bit, by sorting.

    ``q`` is a sequence of percentiles strictly between 0 and 100; the virtual index,
    its neighbours and numpy's two-sided linear interpolation are formed as numpy
    forms them (see :func:`fast_median` for why sorting).
    """
    return sorted_percentile(np.sort(np.asarray(x)), q)


def sorted_percentile(s, q):
    """:func:`fast_percentile` of an array already sorted."""
    n = s.size
    if n < 2 or s.dtype != np.float64 or np.isnan(s[-1]):
        return np.percentile(s, q)
    v = (n - 1) * np.true_divide(q, 100)
    i = np.floor(v)
    t = v - i
    i = i.astype(np.intp)
    a, b = s[i], s[i + 1]
    d = b - a
    return np.where(t >= 0.5, b - d * (1 - t), a + d * t)


def robust_spread(x):
    """Interquartile range of a 1-D float array as a standard deviation (IQR / 1.349);
    the standard deviation when most samples share a value."""
    q1, q3 = fast_percentile(x, [25, 75])  # np.percentile's numbers, a zero's sign aside
    spread = (q3 - q1) / 1.349
    if not spread > 0:
        spread = np.std(x)
    return float(spread)


def noise_std(x):
    """Robust noise standard deviation from second differences.

    White noise of variance s**2 gives second differences of variance 6 s**2; the
    median absolute deviation ignores the few large differences of jumps and steps,
    and a smooth oscillation of P samples per cycle is scaled by (2 pi / P)**2 there.

    An interpolated historian export (:func:`drawn_lines`) holds no noise between the
    points the historian stored, and read from its rows the level was about 0: every
    line drawn between two stored points then counted as a move, and healthy loops read
    as "OP moves while PV stays". Its level is read from the stored points instead, as
    their scatter about the line through their neighbours. That is not the noise, which
    the export no longer holds, but what a move must pass in it: about twice the
    compression's deviation where noise set the points, more where a cycle's curvature
    did. On the same loops sampled and exported (``benchmarks/interpolated_exports.py``)
    the learned model's specificity on the exports rose from 0.73-0.77 to 0.79-0.87.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles import noise_std
    >>> from sktiction.cycles._signal import drawn_lines
    >>> rng = np.random.default_rng(0)
    >>> round(noise_std(np.sin(np.arange(4000) / 50) + rng.normal(0, 0.1, 4000)), 2)
    0.1

    An interpolated export of points stored with white noise reads as that noise:

    >>> stored = np.arange(0, 4000, 10)  # rows of the stored points
    >>> points = np.sin(stored / 50) + rng.normal(0, 0.1, stored.size)
    >>> export = np.interp(np.arange(3991), stored, points)
    >>> drawn_lines(export).size, round(noise_std(export), 2)
    (400, 0.1)
    """
    x = np.asarray(x, dtype=float)
    d2 = np.diff(x, 2)
    if d2.size == 0:
        return 0.0
    rows = drawn_lines(x, d2)
    if rows is not None:
        noise = _stored_noise(x, rows)
        lo, hi = fast_percentile(x, [5, 95])
        if noise > _CLEAN * (hi - lo):  # else the points lie on their lines: a clean signal
            return noise
    return float(1.4826 * fast_median(np.abs(d2 - fast_median(d2))) / np.sqrt(6.0))


#: Share of second differences that vanish (to rounding) in an interpolated export.
LINE_SHARE = 0.5
#: Fewest stored points an export is read from.
_MIN_STORED = 16
#: Least share of stored points at which the drawn line bends on its way up or down
#: (noise or a compressed curve); a clean triangle bends only at its corners.
_MIN_ON_THE_WAY = 0.05
#: Noise of the stored points, as a share of the 5-95 % range, below which they lie on
#: their lines: a clean signal, whose lines are bent by rounding only.
_CLEAN = 1e-3


def _stored_rows(x, d2):
    """Rows where the lines of ``x`` bend, and both ends, when at least
    :data:`LINE_SHARE` of its second differences ``d2`` vanish, ``x`` is not mostly held
    and its lines bend on their way up or down, not only where they turn back (a clean
    triangle, a noise-free simulation); else ``None``."""
    span = float(np.ptp(x)) if x.size else 0.0
    if d2.size == 0 or not span > 0 or np.mean(np.diff(x) == 0) >= LINE_SHARE:
        return None
    bent = np.abs(d2) > 1e-9 * span
    if np.mean(bent) > 1.0 - LINE_SHARE:
        return None
    rows = np.concatenate([[0], np.flatnonzero(bent) + 1, [x.size - 1]])
    if rows.size < 3:
        return None
    slope = np.diff(x[rows]) / np.diff(rows)
    turns = np.sign(slope[1:]) * np.sign(slope[:-1]) < 0
    return rows if np.mean(~turns) >= _MIN_ON_THE_WAY else None


def stored_points(x):
    """How many points ``x`` (1-D, finite) is drawn through when it reads as straight
    lines (the test of :func:`drawn_lines` without its least count of points), both ends
    included; ``None`` for any other record, a single straight line included.

    A channel drawn through a handful of points holds too little to read a loop from:
    an export compressed with a deviation as large as the channel's own movement.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._signal import stored_points
    >>> stored_points(np.interp(np.arange(1000), [0, 300, 700, 999], [0.0, 2.0, 3.0, 1.0]))
    4
    >>> t = np.arange(1000)  # a clean triangle turns at every point: no export
    >>> stored_points(np.abs((t % 200) - 100.0)) is None
    True
    >>> stored_points(np.random.default_rng(0).normal(size=1000)) is None
    True
    """
    x = np.asarray(x, dtype=float)
    rows = _stored_rows(x, np.diff(x, 2))
    return None if rows is None else int(rows.size)


def drawn_lines(x, d2=None):
    """Rows of the points a compressing historian stored when ``x`` (1-D, finite) is an
    interpolated export of them (straight lines drawn between them), else ``None``.

    A swinging-door historian stores a point only when the signal leaves a band around
    the line since the last one, and an interpolated export (PI's) draws straight lines
    between the stored points: at least :data:`LINE_SHARE` of the second differences
    vanish (within 1e-9 of the range, so a shifted or scaled copy reads alike), which a
    sampled noisy record never gives. Not an export: a record mostly held (a stepped
    export or a quantised signal: its repeats are not lines), one of fewer than
    :data:`_MIN_STORED` points, and one whose pieces only turn back at their corners (a
    clean triangle, a noise-free simulation). The stored points are the rows where the
    line bends, and both ends. Averaging a held or quantised signal over intervals also
    draws lines (ramps between its levels); their bends are then read the same way.

    An export written with few decimals is not read so: rounding bends its lines by a
    step or two, and allowing for that read 125 of the default world's 3,000 quantised
    channels, sampled, as exports.
    """
    x = np.asarray(x, dtype=float)
    if d2 is None:
        d2 = np.diff(x, 2)
    rows = None if d2.size < _MIN_STORED else _stored_rows(x, d2)
    return rows if rows is not None and rows.size >= _MIN_STORED else None


def true_runs(same):
    """Start and stop (exclusive) of the runs of True in a boolean array.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._signal import true_runs
    >>> [r.tolist() for r in true_runs(np.array([True, True, False, True]))]
    [[0, 3], [2, 4]]
    """
    edges = np.diff(np.concatenate([[0], same.astype(np.int8), [0]]))
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def on_grid_share(values, step, tolerance=0.05):
    """Share of ``values`` (at least one) that are whole multiples of ``step``, within
    ``tolerance`` of it: the changes or the levels of a quantised tag all are; a
    compressed tag's, which land wherever the signal was when it passed its band, are
    not.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._signal import on_grid_share
    >>> on_grid_share(np.array([0.5, 1.0, 1.5, -0.5]), 0.5)
    1.0
    >>> on_grid_share(np.array([1.0, 1.3, 1.7, 2.45]), 1.0)
    0.25
    """
    ratio = values / step
    return float(np.mean(np.abs(ratio - np.round(ratio)) < tolerance))


def lines_through_changes(x, hold_extremes=False, min_runs=1):
    """``x`` (1-D, finite) drawn as straight lines through the samples where it takes a
    new value; ``x`` itself when no sample repeats its predecessor. With
    ``hold_extremes``, a run at ``x``'s lowest or highest value stays flat (a saturated
    OP, a clipped PV, a cycle's held top) and the line leaves it at its last row; only
    at an extreme held in at least ``min_runs`` runs of two or more samples.

    A compressing historian exported stepped (each stored value held until the next)
    moves a tag only at the points it stored, at times of its own for each tag, so the
    sample-to-sample changes of PV and OP hardly ever coincide even where the loop
    relates them. The lines are what an interpolated export of the same points shows.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._signal import lines_through_changes
    >>> lines_through_changes(np.array([0.0, 0.0, 0.0, 3.0, 3.0, 1.0])).tolist()
    [0.0, 1.0, 2.0, 3.0, 2.0, 1.0]
    >>> lines_through_changes(np.array([0.0, 0.0, 0.0, 3.0, 3.0, 1.0]), True).tolist()
    [0.0, 0.0, 0.0, 3.0, 3.0, 1.0]
    >>> lines_through_changes(np.array([0.0, 2.0, 2.0, 3.0, 3.0, 1.0]), True).tolist()
    [0.0, 2.0, 2.5, 3.0, 3.0, 1.0]
    """
    x = np.asarray(x, dtype=float)
    moved = np.flatnonzero(np.diff(x) != 0) + 1
    if moved.size == x.size - 1:
        return x
    rows = [[0], moved, [x.size - 1]]
    if hold_extremes:  # the last row of each run at the lowest or highest value, too
        after = moved[moved >= 2]  # a change at row 1 ends a one-sample run
        for extreme in (x.min(), x.max()):
            ends = after[(x[after - 1] == extreme) & (x[after - 2] == extreme)] - 1
            if ends.size + (x[-1] == x[-2] == extreme) >= min_runs:
                rows.append(ends)
    rows = np.unique(np.concatenate(rows))
    return np.interp(np.arange(x.size), rows, x[rows])


def _stored_noise(x, rows):
    """Noise level of an interpolated export from its stored points ``rows``: each point's
    distance from the line through its two neighbours, read from the lower quartile so
    that the corners of slips and steps, a minority, do not enter, and scaled so that
    white noise on evenly spaced points (distances of variance ``1.5 sd**2``, lower
    quartile at 0.3186 of their sd) reads as its sd."""
    t, v = rows.astype(float), x[rows]
    a, b, c = t[:-2], t[1:-1], t[2:]
    r = v[1:-1] - (v[:-2] + (v[2:] - v[:-2]) * (b - a) / (c - a))
    return float(fast_percentile(np.abs(r), [25])[0] / 0.3186 / np.sqrt(1.5))


def autocorrelation(x, max_lag):
    """Normalised autocorrelation function of a mean-removed signal, lags 0..max_lag."""
    x = np.asarray(x, dtype=float)
    x = x - x.mean()
    n = x.size
    f = np.fft.rfft(x, 2 * n)
    r = np.fft.irfft(f * np.conj(f))[: max_lag + 1]
    return r / r[0] if r[0] > 0 else np.zeros(max_lag + 1)


def dominant_period(x):
    """Period (samples) and strength of the dominant oscillation, from the ACF.

    The signal is first detrended linearly; the period is the lag of the highest
    ACF value in its first positive lobe after the first zero crossing (later lobes
    hold multiples of the period); the strength is that ACF value (0-1). Returns
    ``(nan, 0.0)`` when the ACF never comes back above zero.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles import dominant_period
    >>> period, strength = dominant_period(np.sin(2 * np.pi * np.arange(2000) / 80))
    >>> round(period), strength > 0.9
    (80, True)
    """
    x = np.asarray(x, dtype=float)
    return first_lobe(autocorrelation(detrend_line(x), x.size // 2))


@lru_cache(maxsize=32)
def _line_design(n):
    """``np.polyfit``'s scaled design matrix and column scales for a line through
    ``t = 0..n-1``: they depend on ``n`` alone, and computing them took three quarters
    of a fit."""
    lhs = np.vander(np.arange(n) + 0.0, 2)
    scale = np.sqrt((lhs * lhs).sum(axis=0))
    lhs /= scale
    lhs.flags.writeable = False
    scale.flags.writeable = False
    return lhs, scale


def detrend_line(x):
    """``x - np.polyval(np.polyfit(t, x, 1), t)`` with ``t = 0..n-1``, to the bit.

    The same operations as numpy's (a least-squares solve of the scaled design matrix,
    then Horner's rule), with the design matrix kept per length.
    """
    n = x.size
    lhs, scale = _line_design(n)
    c = np.linalg.lstsq(lhs, x + 0.0, n * np.finfo(float).eps)[0] / scale
    return x - ((0.0 + c[0]) * np.arange(n) + c[1])


def first_lobe(r):
    """Lag and height of the highest ACF value in the first positive lobe after the
    first zero crossing of the ACF ``r`` (``(nan, 0.0)`` when there is none)."""
    neg = np.flatnonzero(r < 0)
    if neg.size == 0:
        return np.nan, 0.0
    pos = neg[0] + np.flatnonzero(r[neg[0] :] > 0)
    if pos.size == 0:
        return np.nan, 0.0
    after = pos[0] + np.flatnonzero(r[pos[0] :] < 0)
    end = after[0] if after.size else r.size
    lag = pos[0] + int(np.argmax(r[pos[0] : end]))
    return float(lag), float(r[lag])


def moving_average(x, window):
    """Centred moving average with edge values repeated (same length as ``x``)."""
    w = int(max(1, round(window)))
    if w == 1:
        return np.asarray(x, dtype=float).copy()
    left, right = w // 2, w - 1 - w // 2
    padded = np.concatenate([np.full(left, x[0]), x, np.full(right, x[-1])])
    c = np.concatenate([[0.0], np.cumsum(padded)])
    return (c[w:] - c[:-w]) / w


def remove_mean(x, period):
    """Subtract a moving mean over one oscillation period.

    A moving average over exactly one period has zeros at the oscillation frequency
    and all its harmonics, so it removes the cycle whatever its shape while keeping
    slower drift and setpoint moves; the envelope mean of seed 001 (spline through
    maxima and minima) needs clean extrema, which noise and flat tops destroy.
    Without a period a straight line is removed.
    """
    x = np.asarray(x, dtype=float)
    if not np.isfinite(period) or period < 2 or period > x.size / 2:
        # least-squares line in closed form (np.polyfit's SVD costs 10x more)
        t = np.arange(x.size) - 0.5 * (x.size - 1)
        tt = t @ t
        slope = (t @ x) / tt if tt > 0 else 0.0
        return x - x.mean() - slope * t
    return x - moving_average(x, period)


def horch_filter(x, period):
    """Horch's first-order low-pass filter, cut-off at three times the oscillation frequency.

    Seed 000 Eq. 23: ``H(q^-1) = (1 - c) / (1 - c q^-1)`` with
    ``c = exp(-3 w_osc Ts)``, ``w_osc = 2 pi / (period Ts)``: the sample time cancels,
    so only the ``period`` in samples is needed. It is run forwards and backwards so the
    filtered signal is not delayed (peaks keep their place).
    """
    x = np.asarray(x, dtype=float)
    if not np.isfinite(period) or period <= 0:
        return x.copy()
    c = np.exp(-3.0 * 2.0 * np.pi / period)
    y = _first_order(x, c)
    return _first_order(y[::-1], c)[::-1]


@njit(cache=True, nogil=True)
def _first_order(x, c):
    y = np.empty_like(x)
    y[0] = x[0]
    for k in range(1, x.size):
        y[k] = c * y[k - 1] + (1.0 - c) * x[k]
    return y


@njit(cache=True, nogil=True)
def schmitt_crossings(x, h):
    """Zero crossings confirmed by a swing beyond +-h (a Schmitt trigger).

    A crossing counts only once the signal, after crossing zero, reaches the other
    threshold before coming back: noise around zero cannot multiply crossings. The
    crossing is placed at the last sign change before the threshold was reached,
    as a fractional index found by linear interpolation.

    Returns an array of fractional indices and an array of the signs entered
    (+1: the signal went positive).
    """
    n = x.size
    out = np.empty(n)
    signs = np.empty(n, dtype=np.int64)
    k = 0
    state = 0
    last = -1.0
    for i in range(1, n):
        if (x[i - 1] <= 0.0 < x[i]) or (x[i - 1] >= 0.0 > x[i]):
            last = i - 1 + x[i - 1] / (x[i - 1] - x[i])
        if x[i] > h and state != 1:
            if state == -1 and last >= 0:
                out[k] = last
                signs[k] = 1
                k += 1
            state = 1
        elif x[i] < -h and state != -1:
            if state == 1 and last >= 0:
                out[k] = last
                signs[k] = -1
                k += 1
            state = -1
    return out[:k], signs[:k]
