"""Two historian artefacts a scan undoes before it analyses a loop.

- **Spikes**: one to three samples far from both neighbours, which agree with each other
  (a "Bad" value written as 0 or -9999, a transmitter glitch). A single one wrecks every
  least-squares statistic of the loop (the PV-OP coupling test read one zero in 751 rows
  as "PV and OP unrelated"). A valve's slip is a step, not a spike: after it the signal
  stays where it went, so it is never taken for one.
- **Regular holds**: every value written k times because the export grid is k times finer
  than the historian's storage interval. The record then looks like a valve that sticks
  for k - 1 samples out of k; read every k-th row, it is the loop as stored.
"""

from __future__ import annotations

import numpy as np

from .cycles._signal import fast_percentile

#: Widest spike removed, in samples.
MAX_SPIKE_WIDTH = 3
#: Fewest value changes from which a hold grid is believed (a chance alignment of 20
#: changes on one phase of 2 has probability 2e-6).
MIN_HOLD_CHANGES = 20


def _spike_limit(x, d):
    """How far a spike must stand out (``d`` = ``diff(x)``): six robust sds of the steps,
    and 0.6 of the 5-95 % spread, so neither noise nor a cycle's own peaks (a cycle of 4
    samples at most) count. ``inf`` when no step is that large (most records: the spread,
    which needs a partition, is then not computed)."""
    # scales from about 2,000 evenly spread samples: as robust, and cheap on long records
    every = max(1, d.size // 2000)
    d = np.abs(d[np.isfinite(d)])
    if d.size < 8:
        return np.inf
    limit = 6.0 * 1.4826 * np.median(d[::every])  # steps are centred: |d|'s median is their MAD
    if not (d > limit).any():
        return np.inf
    finite = x[np.isfinite(x)][::every]
    lo, hi = fast_percentile(finite, [5, 95])
    return max(limit, 0.6 * (hi - lo))


def spike_mask(x):
    """Samples of ``x`` (1-D) that are spikes: runs of one to :data:`MAX_SPIKE_WIDTH`
    samples that jump away by more than the limit and straight back to within half of it.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._cleaning import spike_mask
    >>> x = np.sin(np.arange(200) / 10.0)
    >>> x[50] = -9999.0                                  # a "Bad" value
    >>> step = np.r_[np.zeros(100), np.ones(100)]        # a slip stays where it went
    >>> np.flatnonzero(spike_mask(x)).tolist(), int(spike_mask(step).sum())
    ([50], 0)
    """
    x = np.asarray(x, dtype=float)
    mask = np.zeros(x.size, dtype=bool)
    d = np.diff(x)
    limit = _spike_limit(x, d)
    if not np.isfinite(limit):
        return mask
    with np.errstate(invalid="ignore"):
        start = np.flatnonzero(np.abs(d) > limit)  # jumps away (or back): a few at most
    for w in range(1, MAX_SPIKE_WIDTH + 1):
        i = start[start + w + 1 < x.size]
        before, after = x[i], x[i + w + 1]
        with np.errstate(invalid="ignore"):
            hit = (np.abs(d[i + w]) > limit) & (np.sign(d[i]) == -np.sign(d[i + w]))
            hit &= np.abs(after - before) <= limit / 2
            base = (before + after) / 2
            for j in range(1, w + 1):
                hit &= (x[i + j] - base) * np.sign(d[i]) > limit
        for j in range(1, w + 1):
            mask[i[hit] + j] = True
    return mask


def remove_spikes(loop, n):
    """Replace the spikes of each channel of one loop (first ``n`` samples) by a straight
    line between their neighbours, in place; returns how many samples were replaced."""
    count = 0
    t = np.arange(n)
    for c in range(loop.shape[1]):
        x = loop[:n, c]
        mask = spike_mask(x)
        if mask.any():
            keep = ~mask & np.isfinite(x)
            x[mask] = np.interp(t[mask], t[keep], x[keep])
            count += int(mask.sum())
    return count


def hold_step(loop, n):
    """``(k, phase)`` when every channel of one loop changes value only on rows
    ``phase + j * k`` (k >= 2; at least 98 % of :data:`MIN_HOLD_CHANGES` or more changes),
    else ``(1, 0)``: the largest such k."""
    x = loop[:n]
    if _changes(x[:400]) > 0.51 * min(n, 400):  # most records change on most rows
        return 1, 0
    with np.errstate(invalid="ignore"):
        changed = (np.diff(x, axis=0) != 0) & np.isfinite(x[1:]) & np.isfinite(x[:-1])
    rows = np.flatnonzero(changed.any(axis=1)) + 1
    if rows.size < MIN_HOLD_CHANGES or rows.size > 0.51 * n:  # a hold of 2 changes <= n / 2
        return 1, 0
    for k in range(10, 1, -1):
        counts = np.bincount(rows % k, minlength=k)
        if counts.max() >= 0.98 * rows.size:
            return k, int(np.argmax(counts))
    return 1, 0


def _changes(x):
    """Rows of ``x`` (samples, channels) where some channel takes a new value."""
    d = np.diff(x, axis=0)
    return int(((d != 0) & ~np.isnan(d)).any(axis=1).sum())  # NaN: no value, no change
