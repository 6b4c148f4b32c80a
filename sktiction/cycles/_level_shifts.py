"""Level shifts (operator moves, load changes, setpoint steps) that hide a cycle.

A step of size S in a record of n samples puts about (S n / (2 pi k))**2 of power
into bin k of the periodogram, against (A n / 2)**2 for a cycle of amplitude A
there, and into the band around the cycle that its ACF is read from: a
production-rate change 10-50 times a cycle's amplitude hides most cycles that the eye
sees at once (``benchmarks/bench_oscillation.py --level-steps``). Where a record that
shows no oscillation holds such shifts, it is read again without them; where it holds
none but has an excursion (a trip, a bump, a step at the record's very end), again
without that (bridged by a line, or clipped where it recurs as a cycle's pulses do).
"""

from __future__ import annotations

import numpy as np

from ._signal import (
    fast_median,
    fast_percentile,
    sorted_median,
    sorted_percentile,
    true_runs,
    unit_scaled,
)

#: A shift must exceed this many interquartile ranges of the windows either side of it.
SHIFT_RATIO = 3.0
#: Most shifts taken out of one record.
MAX_SHIFTS = 6
#: Multiples of the windows and gap tried in turn: a transition lagged by a slow
#: response or a filter needs a wider gap.
SCALES = (1, 2, 4)
#: A shift found only by searching either side of a stretch's best split must be this many
#: times as clear: that search tests more points, so chance passes more often.
HALF_RATIO = 2.0
#: Share of a record beyond Tukey's far-out fences above which an excursion is taken out for
#: a second reading (see without_excursions): any, since a trip of a few samples hides a
#: cycle too and the second reading is kept only if it oscillates.
EXCURSION_SHARE = 0.0
#: Runs beyond the far-out fences from which they are read as the cycle's own and clipped,
#: not bridged: a cycle's pulses recur once a cycle, more often than the 1-3 of trips.
EXCURSION_RUNS = 4


def _windows(n):
    """Length of the windows compared either side of a shift (a twentieth of the
    record) and of the gap left between them for a lagged transition (half that)."""
    w = max(n // 20, 10)
    return w, max(w // 2, 1)


def _sorted_iqr(y):
    q1, q3 = sorted_percentile(y, [25, 75])
    return q3 - q1


def _best_shift(s, w, g, ratio, cusum=None):
    """Where a level shift in ``s`` most likely is (the CUSUM's extreme) and how many
    window spreads it measures, by the tests of :func:`level_shifts` with windows of
    ``w`` samples ``g`` samples off the point; ``None`` when it is not a shift.
    ``cusum``: :func:`_cusum` of ``s``, if already computed."""
    short = max(w // 4, 5)  # a window cut short by the stretch's end
    if s.size < 2 * (short + g):
        return None
    k = _best_split(s, short + g, cusum)  # left: s[:k]
    # each window sorted once for its median and quartiles; the rest only if it passes
    before, after = s[max(0, k - g - w) : k - g], s[k + g : k + g + w]
    sorted_before, sorted_after = np.sort(before), np.sort(after)
    change = sorted_median(sorted_after) - sorted_median(sorted_before)
    spread = max(_sorted_iqr(sorted_before), _sorted_iqr(sorted_after))
    if not abs(change) > ratio * spread:
        return None
    near = fast_median(s[k : k + g]) - fast_median(s[k - g : k])
    same_way = (near > 0) == (change > 0)  # signs, not a product: no underflow at 1e-200
    if not (same_way and abs(near) >= 0.5 * abs(change)):
        return None
    if max(_drift(before), _drift(after)) > 0.25 * abs(change):
        return None
    return k, abs(change) / max(spread, 1e-12 * abs(change))  # a flat step: 1e12, not inf


def _best_split(s, margin, cusum=None):
    """The extreme of the cumulative sum of ``s`` about its mean, at least ``margin``
    samples from either end: the best single split of ``s`` into two levels."""
    c = _cusum(s) if cusum is None else cusum
    return int(np.argmax(c[margin - 1 : s.size - margin])) + margin


def _cusum(s):
    """Size of the cumulative sum of ``s`` about its mean (one per stretch: each window
    scale and the stairs split read it)."""
    return np.abs(np.cumsum(s - s.mean()))


def _drift(y):
    """Change of the median from the first half of ``y`` to the second."""
    h = y.size // 2
    return abs(fast_median(y[h:]) - fast_median(y[:h]))


def level_shifts(x, *, ratio=SHIFT_RATIO, max_shifts=MAX_SHIFTS, stairs=True):
    """Sample indices where the level of a signal shifts, as an operator move or a
    load change shifts it, and a cycle would not.

    The edges of a square cycle whose half period exceeds the windows are shifts too,
    by this test: :func:`~sktiction.cycles.analyze_cycles` takes shifts out only of a
    record that shows no oscillation as it is.

    Binary segmentation: the strongest shift of any stretch (the extreme of its
    cumulative sum about its mean) is kept when

    - the median of the window after it differs from that of the window before it by
      more than ``ratio`` interquartile ranges of either window (windows of a
      twentieth of the record, shorter at the stretch's ends, half a window off the
      point): a cycle, whose windows span both its levels, is not cut;
    - half of that change happens within half a window of the point, and neither
      window's median moves by more than a quarter of it from its first half to its
      second: a ramp or a drift, which changes as much over any stretch of equal
      length, is not cut (a random walk's larger jumps can be: 15 of 60 walks of the
      oscillation benchmark have one, which is why a cut is only used for a second
      reading that must find a cycle);

    with windows and gap twice and four times as wide tried in turn (a transition
    lagged by a slow response). The stretches on either side are then searched again,
    up to ``max_shifts`` shifts. Where three or more levels climb as stairs, or two
    shifts lie close, the best single split falls on a level between them, where no
    window test passes; so a stretch in which no shift is found is split there once
    (``stairs``) and each side searched, for a shift :data:`HALF_RATIO` times as
    clear. On the oscillation benchmark (seeds 0-2, 900 records per class) the cycles
    under level steps found rose from 0.931 to 0.959, and the random walks with a
    shift from 23.4 % to 25.4 % (without the stricter ratio: 0.964 and 44.7 %).

    Parameters
    ----------
    x : array-like of shape (n_samples,)
        One finite signal.
    ratio : float, default=3.0
        Size a shift must exceed, in interquartile ranges of the windows beside it.
    max_shifts : int, default=6
        Most shifts returned.
    stairs : bool, default=True
        Search either side of a stretch's best split once when no shift is found
        there (see above); ``False``: binary segmentation alone.

    Returns
    -------
    shifts : ndarray of int
        Sorted indices: the new level starts at each.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles._level_shifts import level_shifts
    >>> t = np.arange(2000)
    >>> x = np.sin(2 * np.pi * t / 80) + 20.0 * (t >= 1200) - 15.0 * (t >= 1500)
    >>> level_shifts(x).tolist()
    [1200, 1500]
    >>> level_shifts(np.sin(2 * np.pi * t / 80) + 0.01 * t).tolist()  # a ramp is no shift
    []
    """
    x, _ = unit_scaled(np.asarray(x, dtype=float))  # cumulative sums near 1e307
    w, g = _windows(x.size)
    margin = max(w // 4, 5) + g  # the shortest stretch searched is twice this
    found, stretches, done, halves = [], [(0, x.size)], set(), set()
    while len(found) < max_shifts:
        best = None
        for a, b in list(stretches):
            if (a, b) in done:
                continue
            need = ratio * (HALF_RATIO if (a, b) in halves else 1.0)
            cusum = _cusum(x[a:b])
            for scale in SCALES:  # wider windows and gaps pass lagged transitions
                shift = _best_shift(x[a:b], scale * w, scale * g, need, cusum)
                if shift is not None:
                    break
            if shift is not None:
                if best is None or shift[1] > best[1]:
                    best = (a + shift[0], shift[1], (a, b))
                continue
            done.add((a, b))
            if stairs and (a, b) not in halves and b - a >= 4 * margin:
                k = a + _best_split(x[a:b], margin, cusum)  # searched either side, not a shift
                stretches.remove((a, b))
                stretches += [(a, k), (k, b)]
                halves.update(stretches[-2:])
        if best is None:
            if all(st in done for st in stretches):
                break
            continue
        t, _, (a, b) = best
        stretches.remove((a, b))
        stretches += [(a, t), (t, b)]
        found.append(t)
    return np.array(sorted(found), dtype=int)


def without_level_shifts(x):
    """``x`` without its level shifts, and where they were.

    Each stretch between :func:`level_shifts` is brought to a median of zero; within
    the widest gap of a shift (a tenth of the record either side), values are
    clipped to the 1-99 % range of the rest, so a lagged transition leaves no spike.

    Returns
    -------
    y : ndarray of shape (n_samples,)
        ``x`` itself when it has no shift.
    shifts : ndarray of int
        Sorted indices of the shifts.
    """
    x = np.asarray(x, dtype=float)
    shifts = level_shifts(x)
    if shifts.size == 0:
        return x, shifts
    edges = np.concatenate([[0], shifts, [x.size]])
    out = x.copy()
    for a, b in zip(edges[:-1], edges[1:]):
        out[a:b] -= fast_median(x[a:b])
    gap = SCALES[-1] * _windows(x.size)[1]
    near = np.zeros(x.size, dtype=bool)
    for t in shifts:
        near[max(0, t - gap) : t + gap] = True
    rest = out[~near] if np.count_nonzero(~near) >= 10 else out  # gaps cover a short record
    lo, hi = fast_percentile(rest, [1, 99])
    out[near] = np.clip(out[near], lo, hi)
    return out, shifts


def read_without_shifts(x, read, oscillates):
    """``read(x)``, or, when that reading does not oscillate and ``x`` holds level
    shifts, ``read`` of ``x`` without them if that one oscillates (without shifts but with
    excursions, of ``x`` without them: :func:`without_excursions`): the second reading
    of :func:`~sktiction.cycles.analyze_cycles` and
    :func:`~sktiction.cycles.detect_oscillations`.

    Returns
    -------
    reading : object
        What ``read`` returned for the reading kept.
    shifts : ndarray of int
        The shifts taken out (empty when the record was read as it is).
    """
    first = read(x)
    if oscillates(first) or not np.isfinite(x).all():  # a gap inside a loop: NaN features
        return first, np.empty(0, dtype=int)
    flat, shifts = without_level_shifts(x)
    if not shifts.size:
        flat = without_excursions(x)
    if flat is not None:
        second = read(flat)
        if oscillates(second):
            return second, shifts
    return first, np.empty(0, dtype=int)


def without_excursions(x):
    """``x`` without its excursions when more than :data:`EXCURSION_SHARE` of it lies
    beyond Tukey's far-out fences (3 interquartile ranges beyond the quartiles), else
    None. Excursions beyond them in fewer than :data:`EXCURSION_RUNS` runs are bridged
    by straight lines between the samples within the inner fences (1.5 ranges), as a
    gap is; more (a pulse train's pulses, when its low level holds both quartiles) are
    the cycle's, and are clipped to the inner fences.

    An excursion that is no level shift hides a cycle as a shift does: an operator's bump
    (two opposite steps closer than the shift windows), a step within the outer 3.75 % of
    the record, where no shift is searched, a trip of a few samples (OP to 0 and back:
    two trips of six samples each in 3,000 hid a cycle ten times smaller in every one of
    20 records while 0.5 % of the record was asked for). Clipped to the fence, a trip
    still stands 2.8 amplitudes of a sine below its median; bridged, it is gone. A cycle
    lies within the inner fences, and Gaussian noise passes the far-out fences on two
    samples in a million, so only excursions are taken out.
    """
    q1, q3 = fast_percentile(x, [25, 75])
    spread = q3 - q1
    if not spread > 0:  # half the record on one value: no scale to call anything far
        return None
    far = (x < q1 - 3.0 * spread) | (x > q3 + 3.0 * spread)
    if not np.count_nonzero(far) > EXCURSION_SHARE * x.size:
        return None
    if true_runs(far)[0].size >= EXCURSION_RUNS:
        return np.clip(x, q1 - 1.5 * spread, q3 + 1.5 * spread)
    inside = np.flatnonzero((x >= q1 - 1.5 * spread) & (x <= q3 + 1.5 * spread))
    return np.interp(np.arange(x.size), inside, x[inside])
