"""Dynamic time warping over a batch of equal-length pairs: a numba kernel behind a checked API.

tslearn's public ``dtw`` spends about a millisecond per call in Python; a loop has
hundreds of (cycle, template) pairs, so the pairs are batched into one compiled call.
The result equals ``tslearn.metrics.dtw`` (tests check it to 1e-9).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _dtw_pair(a, b, radius):
    """DTW distance of two 1-D series: sqrt of the least accumulated squared difference."""
    n, m = a.size, b.size
    inf = np.inf
    prev = np.full(m + 1, inf)
    cur = np.full(m + 1, inf)
    prev[0] = 0.0
    for i in range(1, n + 1):
        cur[:] = inf
        lo, hi = 1, m
        if radius >= 0:  # Sakoe-Chiba band |i - j| <= radius (series of equal length)
            lo = max(1, i - radius)
            hi = min(m, i + radius)
        for j in range(lo, hi + 1):
            d = a[i - 1] - b[j - 1]
            best = prev[j - 1]
            if prev[j] < best:
                best = prev[j]
            if cur[j - 1] < best:
                best = cur[j - 1]
            cur[j] = d * d + best
        prev, cur = cur, prev
    return np.sqrt(prev[m])


@njit(cache=True, nogil=True)
def _paired_dtw(A, B, radius):
    out = np.empty(A.shape[0])
    for k in range(A.shape[0]):
        out[k] = _dtw_pair(A[k], B[k], radius)
    return out


def paired_dtw(A, B, *, sakoe_chiba_radius=None):
    """DTW distance between ``A[k]`` and ``B[k]`` for every k.

    Parameters
    ----------
    A, B : array-like of shape (n_pairs, n_points)
        Univariate series, one pair per row, all of one length.
    sakoe_chiba_radius : int or None, default=None
        Width of the Sakoe-Chiba band in samples; ``None`` for no constraint.

    Returns
    -------
    distances : ndarray of shape (n_pairs,)
        ``sqrt(min over warping paths of the summed squared differences)``, the
        definition of :func:`tslearn.metrics.dtw`.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.features import paired_dtw
    >>> a = np.array([[0.0, 1.0, 2.0, 1.0]])
    >>> b = np.array([[0.0, 0.0, 1.0, 2.0]])
    >>> paired_dtw(a, b).round(6).tolist()
    [1.0]
    """
    A = np.ascontiguousarray(A, dtype=float)
    B = np.ascontiguousarray(B, dtype=float)
    if A.ndim != 2 or A.shape != B.shape:
        raise ValueError(
            f"A and B must be 2-D arrays of one shape (n_pairs, n_points); got {A.shape} "
            f"and {B.shape}."
        )
    if not (np.isfinite(A).all() and np.isfinite(B).all()):
        raise ValueError("A and B must not contain NaN or infinite values.")
    if sakoe_chiba_radius is None:
        radius = -1
    elif int(sakoe_chiba_radius) != sakoe_chiba_radius or sakoe_chiba_radius < 0:
        raise ValueError(
            f"sakoe_chiba_radius must be None or an integer >= 0; got {sakoe_chiba_radius!r}."
        )
    else:
        radius = int(sakoe_chiba_radius)
    if A.shape[0] == 0:
        return np.empty(0)
    return _paired_dtw(A, B, radius)


def tslearn_paired_dtw(A, B, *, sakoe_chiba_radius=None):
    """The same distances computed by tslearn, pair by pair (slow; for checks)."""
    from tslearn.metrics import dtw

    kw = {}
    if sakoe_chiba_radius is not None:
        kw = {"global_constraint": "sakoe_chiba", "sakoe_chiba_radius": int(sakoe_chiba_radius)}
    return np.array([dtw(a, b, **kw) for a, b in zip(np.asarray(A), np.asarray(B))])
