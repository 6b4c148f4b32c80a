"""Signal-level repairs: spikes and placeholders for missing data found in one record,
and :func:`one_signal`, which reads a record as a scan reads each channel of a loop.

Loop-level cleaning (``sktiction._cleaning``) builds on these; they build only on the
signal helpers (``_signal``), so data flows one way.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._validation import repair_gaps
from ._signal import fast_percentile

#: Widest spike removed, in samples.
MAX_SPIKE_WIDTH = 3
#: Samples either side of a spike that must hold no other jump as large: a spike is alone,
#: while a fast flat-topped cycle (a sticky valve's levels of 2-3 samples) jumps all the time.
_QUIET = MAX_SPIKE_WIDTH + 1
#: Largest share of a record that may be spikes (at least 3 samples): beyond it the signal
#: itself jumps (pulses, a fast cycle), and nothing is removed.
MAX_SPIKE_SHARE = 0.01
#: Beyond any process quantity in any unit: a placeholder wherever it stands.
IMPLAUSIBLE = 1e20
#: A placeholder cluster lies this many times the range of the other values away from
#: them; a real excursion passes through values in between, so it never leaves such a gap.
_PLACEHOLDER_GAP = 10.0
#: Most distinct values a placeholder cluster holds (a historian writes one or two codes).
_PLACEHOLDER_VALUES = 2
#: Largest share of a record read as placeholders: below half, so that the values left are
#: the record's majority (a transmitter out for the last hours of a day's export writes
#: -9999 on a quarter or a third of its rows, and read as data it decides the verdict).
MAX_PLACEHOLDER_SHARE = 0.45


def _spike_limit(x, d):
    """How far a spike must stand out (``x`` finite, ``d`` = ``diff(x)``): six robust sds
    of the steps (on a held or quantised record, whose typical step is 0, of its typical
    change instead), and 0.6 of the 5-95 % spread, so neither noise, a recording grid nor a
    cycle's own peaks count. ``inf`` when no step is that large (most records: the spread,
    which needs a partition, is then not computed)."""
    # scales from about 2,000 evenly spread samples: as robust, and cheap on long records
    every = max(1, d.size // 2000)
    steps = np.abs(d)
    if steps.size < 8:
        return np.inf
    scale = np.median(steps[::every])  # steps are centred: |d|'s median is their MAD
    if scale == 0:
        changes = steps[steps > 0]
        if changes.size < 3:
            return np.inf
        scale = np.median(changes)
    limit = 6.0 * 1.4826 * scale
    if not (steps > limit).any():
        return np.inf
    lo, hi = fast_percentile(x[::every], [5, 95])
    return max(limit, 0.6 * (hi - lo))


def _tail_run(y, d, big, limit):
    """Spike samples among the last :data:`MAX_SPIKE_WIDTH` of ``y``, which have one
    neighbour only: a run at the end beyond ``limit`` from the sample before it, reached by
    the only jump that large within :data:`_QUIET` samples."""
    found = np.zeros(y.size, dtype=bool)
    m = y.size
    for w in range(1, MAX_SPIKE_WIDTH + 1):
        if m < w + 2 + _QUIET:
            break
        j = m - w - 1  # the jump into the run at the end
        if big[j] and not big[j - _QUIET : j].any():
            if ((y[j + 1 :] - y[j]) * np.sign(d[j]) > limit).all():
                found[j + 1 :] = True
                break
    return found


def _end_runs(y, d, big, limit):
    """:func:`_tail_run` at both ends of ``y`` (the start read backwards). A "Bad" value in
    the last row otherwise stays and sets the record's span; what is lost instead is a
    real slip in the last rows, one to three samples of it."""
    head = _tail_run(y[::-1], -d[::-1], big[::-1], limit)[::-1]
    return _tail_run(y, d, big, limit) | head


def spike_mask(x):
    """Samples of ``x`` (1-D) that are spikes: runs of one to :data:`MAX_SPIKE_WIDTH`
    samples that jump away by more than the limit and straight back to within half of it,
    with no other jump as large within :data:`_QUIET` samples. Neighbours are read across
    NaN holes (a "Bad" value beside a hole is a spike too); none when more than
    :data:`MAX_SPIKE_SHARE` of the record would be.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._repairs import spike_mask
    >>> x = np.sin(np.arange(200) / 10.0)
    >>> x[50] = -9999.0                                  # a "Bad" value
    >>> step = np.r_[np.zeros(100), np.ones(100)]        # a slip stays where it went
    >>> np.flatnonzero(spike_mask(x)).tolist(), int(spike_mask(step).sum())
    ([50], 0)
    """
    x = np.asarray(x, dtype=float)
    mask = np.zeros(x.size, dtype=bool)
    finite = np.flatnonzero(np.isfinite(x))
    y = x[finite]
    d = np.diff(y)
    limit = _spike_limit(y, d)
    if not np.isfinite(limit):
        return mask
    big = np.abs(d) > limit
    start = np.flatnonzero(big)  # jumps away (or back): a few at most
    n_big = np.concatenate([[0], np.cumsum(big)])  # big jumps before each step
    found = np.zeros(y.size, dtype=bool)
    for w in range(1, MAX_SPIKE_WIDTH + 1):
        i = start[start + w + 1 < y.size]
        before, after = y[i], y[i + w + 1]
        hit = big[i + w] & (np.sign(d[i]) == -np.sign(d[i + w]))
        hit &= np.abs(after - before) <= limit / 2
        base = (before + after) / 2
        for j in range(1, w + 1):
            hit &= (y[i + j] - base) * np.sign(d[i]) > limit
        lo, hi = np.maximum(i - _QUIET, 0), np.minimum(i + w + 1 + _QUIET, d.size)
        hit &= (n_big[hi] - n_big[lo]) == (n_big[i + w + 1] - n_big[i])  # alone
        for j in range(1, w + 1):
            found[i[hit] + j] = True
    found |= _end_runs(y, d, big, limit)
    if found.sum() > max(3, MAX_SPIKE_SHARE * y.size):
        return mask
    mask[finite[found]] = True
    return mask


def replace_spikes(x):
    """Replace the spikes of ``x`` (1-D, in place) by a straight line between their
    neighbours; returns their mask (:func:`spike_mask`)."""
    mask = spike_mask(x)
    if mask.any():
        t = np.arange(x.size)
        keep = ~mask & np.isfinite(x)
        x[mask] = np.interp(t[mask], t[keep], x[keep])
    return mask


def placeholder_mask(x):
    """Samples of ``x`` (1-D) that hold a placeholder for missing data: beyond
    :data:`IMPLAUSIBLE`, or one or two distinct values at either end of the value range
    (or both ends) that stand apart from all the others by more than
    :data:`_PLACEHOLDER_GAP` times the others' range and their distance from zero, on at
    most :data:`MAX_PLACEHOLDER_SHARE` of the record.

    Real moves are left alone: a move to a new level passes through values in between or
    carries noise (many distinct values); a trip to 0 or a saturation at 100 % from working
    values is within ten times their distance from zero; a setpoint's few levels are too
    close to each other. Missed by design: a code within ten times a signal's own level
    (-9999 on a flow of 3,500-6,500 kg/h) and an outage of half the record or more (the
    code is then the record's majority).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._repairs import placeholder_mask
    >>> x = 50 + np.sin(np.arange(300) / 10.0)
    >>> x[100:120] = -9999.0                             # an outage written as a number
    >>> np.flatnonzero(placeholder_mask(x))[[0, -1]].tolist()
    [100, 119]
    >>> tripped = x.copy()
    >>> tripped[100:120] = 0.0                           # a trip to 0: a real move
    >>> int(placeholder_mask(tripped).sum())
    0
    """
    x = np.asarray(x, dtype=float)
    with np.errstate(invalid="ignore"):
        mask = np.abs(x) > IMPLAUSIBLE
    y = x[np.isfinite(x) & ~mask]
    if y.size < 4:
        return mask
    # Most records end here, in O(n): placeholders take at most k of the samples, so
    # the others hold the k-th smallest and k-th largest (k < n / 2): their range is at
    # least the distance between these. Their median sample is the (n - k) // 2-th to the
    # (n + k) // 2-th smallest (codes all at the top, all at the bottom), so it is at
    # least as far from zero as the nearer of those two when both have one sign (not the
    # k-th smallest: with codes on the top 40 % of the rows that is the others' 75th
    # percentile); a placeholder's gap is within the range.
    k = int(MAX_PLACEHOLDER_SHARE * y.size)
    lo_m, hi_m = (y.size - k) // 2, (y.size + k) // 2
    part = np.partition(y, [0, lo_m, k, y.size - 1 - k, hi_m, y.size - 1])
    a, b = part[k], part[y.size - 1 - k]
    c, d = part[lo_m], part[hi_m]
    level = min(abs(c), abs(d)) if c * d > 0 else 0.0
    if part[-1] - part[0] <= _PLACEHOLDER_GAP * max(b - a, level):
        return mask
    values, counts = np.unique(y, return_counts=True)
    low, high = _codes(values, counts, MAX_PLACEHOLDER_SHARE * y.size)
    if low:
        mask |= x <= values[low - 1]
    if high:
        mask |= x >= values[values.size - high]
    return mask


def _codes(values, counts, budget):
    """``(low, high)``: how many of the sorted distinct ``values`` at the bottom and at the
    top are placeholder codes (``counts`` samples each, at most ``budget`` in all), each end
    judged against the values left once both ends' codes are out."""
    n = values.size
    cum = np.concatenate([[0], np.cumsum(counts)])  # samples below each distinct value
    best = (0, 0)
    for low in range(_PLACEHOLDER_VALUES + 1):
        for high in range(_PLACEHOLDER_VALUES + 1):
            if low + high <= sum(best) or n - low - high < 3:
                continue
            if cum[low] + cum[n] - cum[n - high] > budget:
                continue
            first, last = values[low], values[n - high - 1]  # the others' range
            middle = (cum[low] + cum[n - high]) // 2  # their median sample
            level = abs(values[np.searchsorted(cum, middle, side="right") - 1])
            apart = _PLACEHOLDER_GAP * max(last - first, level)
            if (low == 0 or first - values[low - 1] > apart) and (
                high == 0 or values[n - high] - last > apart
            ):
                best = (low, high)
    return best


#: Longest gap :func:`one_signal` bridges, as a share of the record (at least one
#: sample): a few lost samples are a historian's; a longer gap ends a stretch.
MAX_BRIDGED_RUN = 0.01


def one_signal(x, name="x"):
    """``x`` as a 1-D float array, without NaN padding at either end, with spikes,
    placeholders and gaps repaired as a scan repairs them.

    A loop array pads shorter records with NaN at the end (tslearn's layout), so
    ``X[i, :, 1]`` of such an array is read as the record it holds; padding at the
    start is dropped too. The rest is repaired with the rules a scan applies to each
    channel of a loop, and a warning says what was done (sample numbers are the
    input's): spikes (one to three samples far from both neighbours,
    :func:`spike_mask`) are replaced by straight lines,
    placeholders for missing data written as numbers (-9999 for a stretch,
    :func:`placeholder_mask`) are read as missing, and a gap (or any
    value that is not finite) of at most 1 % of the record (at least one sample) is
    bridged by a straight line, while a longer one splits the record and the longest
    stretch is kept. Input that is not one signal or holds no value is an error: a gap
    must not read as "not oscillating".
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1:
        raise ValueError(f"{name} must be one signal (1-D); got shape {x.shape}.")
    lost = ~np.isfinite(x)  # as given: placeholders read as missing are not counted here
    x, notes = _artefacts_out(x, ~lost)
    finite = np.isfinite(x)
    if finite.all() and x.size:
        return _noted(x, name, notes)
    if not finite.any():
        raise ValueError(f"{name} holds no value (length {x.size}, all NaN or infinite).")
    size = x.size
    first, last = int(np.argmax(finite)), size - int(np.argmax(finite[::-1]))
    if np.isnan(x[:first]).all() and np.isnan(x[last:]).all():  # padding at either end
        if lost[:first].sum() < first or lost[last:].sum() < size - last:
            notes.append(f"read from sample {first} to {last} (placeholders at an end)")
        x, finite, lost = x[first:last], finite[first:last], lost[first:last]
    else:
        first = 0
    if finite.all():
        return _noted(x, name, notes)
    limit = max(1, int(MAX_BRIDGED_RUN * x.size))
    fixed, info = repair_gaps(np.where(finite, x, np.nan)[None, :, None], max_gap=limit)
    a, b = int(info["kept_start"].iloc[0]), int(info["kept_stop"].iloc[0])
    done = []
    if info["n_gaps_split"].iloc[0]:
        done.append("the longest stretch between gaps of more than 1 % of it kept, rows "
                    f"{first + a}-{first + b}")
    if info["n_bridged"].iloc[0]:
        done.append("short gaps bridged by straight lines")
    if lost.any():
        notes.append(f"{int(lost.sum())} NaN or infinite value(s) inside the record (first at "
                     f"sample {first + int(np.argmax(lost))} of {size}): " + "; ".join(done))
    else:
        notes.extend(done)
    return _noted(np.ascontiguousarray(fixed[0, : b - a, 0]), name, notes)


def _artefacts_out(x, finite):
    """``x`` (``finite`` where it is) with its spikes replaced by straight lines and its
    placeholders set to NaN,
    as a scan reads each channel (spikes first: a lone -9999 is a spike, not a gap), and
    what was done; ``x`` itself when it holds neither (most records). A record whose
    median magnitude exceeds 1 is read divided by a power of two near it (exact), so that
    a record near 1e300 does not overflow and a record near 1e20 is not read as codes (a
    scan's loops are in process units; a signal here may be in any)."""

    size = np.abs(x[finite])
    # the median by partition (the mean of two middles could overflow near 1e308); never
    # below 1: a record of tiny values is read in its own units, as a scan reads it
    typical = np.partition(size, size.size // 2)[size.size // 2] if size.size else 0.0
    unit = 2.0 ** min(int(np.frexp(typical)[1]), 1023) if typical > 1 else 1.0
    y, notes = x / unit, []
    spikes = replace_spikes(y)
    if spikes.any():
        notes.append(f"{int(spikes.sum())} spike sample(s) replaced by straight lines "
                     f"(first at sample {int(np.argmax(spikes))})")
    held = placeholder_mask(y) & finite  # inf is not a code: it is read as lost
    if held.any():
        y[held] = np.nan
        notes.append(f"{int(held.sum())} placeholder value(s) for missing data (such as -9999) "
                     f"read as missing (first at sample {int(np.argmax(held))})")
    return (y * unit if notes else x), notes


def _noted(x, name, notes):
    """``x``, after one warning that lists ``notes`` (what was repaired), if any."""
    if notes:
        warnings.warn(f"{name}: " + "; ".join(notes) + ".", UserWarning, stacklevel=4)
    return x
