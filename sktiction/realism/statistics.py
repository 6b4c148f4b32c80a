"""Per-loop statistics of recording artefacts, noise, setpoint regime and PV-OP relation.

One set of statistics, computed once per loop, read by :func:`compare` (which effect of the
simulated world differs from measured loops). The applicability check (is a loop fit for a
verdict) reads two of them, the repeat shares, computed alone by the same code
(:func:`_repeat_fractions`). Each statistic is made *specific*: it answers to one effect and
stays put under the others (see the notes of each column in :func:`loop_statistics`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd
from scipy.fft import irfft, next_fast_len, rfft

from .._validation import OP, PV, SP, check_loops
from ..cycles._level_shifts import level_shifts
from ..cycles._signal import (
    _stored_noise,
    drawn_lines,
    fast_median,
    fast_percentile,
    true_runs,
)

__all__ = ["loop_statistics", "STATISTIC_COLUMNS"]

# Robust noise sd from second differences: white noise of sd s gives var(d2) = 6 s**2.
_MAD_TO_SD = 1.4826 / np.sqrt(6.0)
# Lags of the difference ACF searched for the dip that interval averaging leaves.
_AVERAGING_LAGS = (2, 12)
# Below this many lags an ACF is cheaper as dot products than through the FFT.
_DIRECT_LAGS = 40
# Fewest pairs of fresh differences for an ACF value (its sd is about 1 / sqrt(pairs)).
_MIN_PAIRS = 30
# A spike departs from its 3-point median by more than this many noise sd ...
_SPIKE_NOISE_SD = 8.0
# ... and by more than this share of the channel's 5-95 % range.
_SPIKE_SPAN = 0.2
# The scatter of a swinging door's stored points about their neighbours' line, in
# deviations: about 2 where noise sets the points (a deviation of 1.5 noise sd), about 5
# where a smooth cycle's curvature does (classic-world loops at 0.5-10 % of their span,
# 10-90 % 2-10); between the two, so a fitted deviation is within a factor of 2.5.
_SCATTER_PER_DEVIATION = 4.0
# SP changes on more than this share of samples: a remote (cascade) setpoint, not steps.
_CASCADE_SHARE = 0.2

STATISTIC_COLUMNS = (
    "n_samples",
    "ts",
    "has_op",
    "has_sp",
    "nan_fraction",
    "pv_span",
    "op_span",
    "error_span",
    "pv_noise",
    "op_noise",
    "noise_level",
    "op_noise_level",
    "noise_colour",
    "diff_acf_min",
    "averaging_lag",
    "averaging_contrast",
    "pv_averaging_contrast",
    "pv_repeat_fraction",
    "op_repeat_fraction",
    "row_repeat_fraction",
    "joint_repeat_excess",
    "hold_fraction",
    "hold_run_length",
    "independent_freeze",
    "line_share",
    "line_deviation",
    "pv_level_reuse",
    "op_level_reuse",
    "pv_step",
    "pv_band",
    "op_band",
    "spike_rate",
    "spike_size",
    "pv_drift",
    "op_drift",
    "op_load_shifts",
    "sp_change_fraction",
    "sp_steps",
    "sp_step_size",
    "sp_offset",
    "acf_peak",
    "period",
    "regularity",
    "decorrelation_lag",
    "pv_op_corr",
    "pv_op_max_corr",
    "pv_op_lag",
    "op_saturation",
)


def _span(x):
    """5-95 % range (robust to spikes and a few wild samples)."""
    lo, hi = fast_percentile(x, [5, 95])
    if hi - lo == 0:
        # fast_percentile gives np.percentile's numbers but a zero may carry the other sign,
        # which only a zero span shows: numpy's own then
        lo, hi = np.percentile(x, [5, 95])
    return float(hi - lo)


def _valid_differences(same):
    """First differences that join two fresh samples.

    ``same[k]`` says sample ``k + 1`` repeats sample ``k``. The difference ``x[k+1] - x[k]``
    is left out when ``x[k+1]`` is a repeat, and when ``x[k]`` is a stale repeat (the jump
    that ends a frozen run carries the change of the whole run).
    """
    stale_start = np.concatenate([[False], same[:-1]])
    return ~same & ~stale_start


def _noise_sd(x, same):
    """Robust noise sd from second differences of fresh samples (frozen runs left out)."""
    ok1 = _valid_differences(same)
    d2 = np.diff(x, 2)[ok1[1:] & ok1[:-1]]
    if len(d2) < 5:
        return 0.0
    # fast_median: np.median to the bit here (a zero's sign cannot reach the |deviations|)
    return float(_MAD_TO_SD * fast_median(np.abs(d2 - fast_median(d2))))


def _acf(x, max_lag, demean=True):
    """Autocorrelation at lags 0..max_lag (biased estimate), mean removed unless told.

    A few lags are direct dot products; many go through the FFT.
    """
    n = len(x)
    if demean:
        x = x - x.mean()
    if max_lag < _DIRECT_LAGS:
        r = np.array([x[: n - k] @ x[k:] for k in range(min(max_lag, n - 1) + 1)])
        r = np.concatenate([r, np.zeros(max_lag + 1 - len(r))])
        return r / r[0] if r[0] > 0 else np.full(max_lag + 1, np.nan)
    nfft = next_fast_len(2 * n, real=True)
    f = rfft(x, nfft)
    r = irfft(f * np.conj(f), nfft)[: max_lag + 1]
    return r / r[0] if r[0] > 0 else np.full(max_lag + 1, np.nan)


def _xcorr(a, b, max_lag):
    """Correlation of ``a[k]`` with ``b[k - lag]`` for lags -max_lag..max_lag."""
    n = len(a)
    a = a - a.mean()
    b = b - b.mean()
    den = np.sqrt((a @ a) * (b @ b))
    if den == 0:
        return np.full(2 * max_lag + 1, np.nan)
    nfft = next_fast_len(2 * n, real=True)
    r = irfft(rfft(a, nfft) * np.conj(rfft(b, nfft)), nfft)
    return np.concatenate([r[nfft - max_lag :], r[: max_lag + 1]]) / den


def _detrend(x):
    t = np.arange(len(x), dtype=float)
    t -= t.mean()
    slope = (t @ (x - x.mean())) / (t @ t) if len(x) > 1 else 0.0
    return x - x.mean() - slope * t, slope


def _fill(x):
    """Replace NaN inside a record by linear interpolation (statistics need no gaps)."""
    bad = np.isnan(x)
    if not bad.any():
        return x
    if bad.all():
        return x
    idx = np.arange(len(x))
    out = x.copy()
    out[bad] = np.interp(idx[bad], idx[~bad], x[~bad])
    return out


def _repeats(x):
    """Which samples equal the one before, and their share (NaN without a difference)."""
    same = np.diff(x) == 0
    return same, float(same.mean()) if len(same) else np.nan


def _level_reuse(x, same):
    """``1 - distinct values / (changes + 1)``; NaN without a change."""
    n_changes = int((~same).sum())
    distinct = len(np.unique(x))
    # Quantised signals revisit the same levels: distinct values fall far below the changes.
    reuse = 1.0 - distinct / (n_changes + 1.0) if n_changes > 0 else np.nan
    return max(reuse, 0.0)


def _band(x, same, span):
    """Smallest jump that ends a frozen run, as a share of the range (compression band)."""
    if span <= 0:
        return np.nan
    d = np.abs(np.diff(x))
    ends = np.flatnonzero(same[:-1] & ~same[1:]) + 1
    if len(ends) < 3:
        return 0.0
    return float(np.percentile(d[ends], 10) / span)


def _median3(a, b, c):
    """Element-wise median of three arrays (without sorting)."""
    return np.maximum(np.minimum(a, b), np.minimum(np.maximum(a, b), c))


def _despike(x, span):
    """Replace spikes by their 3-point median.

    Returns the clean signal, the spike sizes (share of the span) and the noise sd when no
    spike was found (None otherwise: the clean signal's noise must be measured again).

    A spike departs from its 3-point median by more than 8 noise sd and 20 % of the span.
    Steps (holds, setpoint moves, slips) survive a 3-point median, so they do not count.
    """
    if len(x) < 3 or span <= 0:
        return x, np.empty(0), None
    med = _median3(x[:-2], x[1:-1], x[2:])
    dev = np.abs(x[1:-1] - med)
    noise = _noise_sd(x, np.diff(x) == 0)
    hit = dev > max(_SPIKE_NOISE_SD * noise, _SPIKE_SPAN * span)
    if not hit.any():
        return x, np.empty(0), noise
    clean = x.copy()
    clean[1:-1][hit] = med[hit]
    return clean, dev[hit] / span, None


class _Channel(NamedTuple):
    """One channel after :func:`_clean_channel`; ``noise`` is None when spikes were
    replaced (see :func:`_despike`)."""

    span: float
    clean: np.ndarray
    spike_sizes: np.ndarray
    noise: float | None
    same: np.ndarray
    repeat_fraction: float


def _clean_channel(x):
    """Span, spikes replaced, then repeats, of one channel without NaN (a :class:`_Channel`)."""
    span = _span(x)
    clean, spikes, noise = _despike(x, span)
    same, rep = _repeats(clean)
    return _Channel(span, clean, spikes, noise, same, rep)


def _recorded_rows(x):
    """``x`` cut to the rows from the first to the last one where PV, and OP when it holds
    numbers, are both recorded.

    Missing rows at a record's edges have one neighbour only: bridged like an inner gap,
    they would be extended flat and read as a tag frozen there (a historian hold). They are
    left out instead, as the padding is; ``nan_fraction`` still counts them.
    """
    ok = np.isfinite(x[:, PV])
    op_ok = np.isfinite(x[:, OP])
    if op_ok.any():
        ok &= op_ok
    rows = np.flatnonzero(ok)
    if len(rows) == 0:
        return x
    return x[rows[0] : rows[-1] + 1]


def _first_steps(x):
    """The steps every statistic of one loop starts from (``x``: n_samples x 3, padding cut).

    NaN gaps in PV and OP are bridged linearly; then PV, and OP when it holds numbers, get
    their spikes replaced first (so that one glitch does not break a frozen run or pass for
    a grid level) and their repeats found, by :func:`_clean_channel`.

    Returns
    -------
    has_op : bool
        OP holds numbers.
    pv, op : _Channel or None
        :func:`_clean_channel` of each; PV None for a loop of fewer than 8 samples or a PV
        without numbers (no statistic then), OP None also without OP.
    """
    has_op = bool(np.isfinite(x[:, OP]).any())
    pv = _fill(x[:, PV])
    if len(x) < 8 or np.isnan(pv).any():
        return has_op, None, None
    pv = _clean_channel(pv)
    op = _fill(x[:, OP]) if has_op else x[:, OP]
    if not has_op or np.isnan(op).any():
        return has_op, pv, None
    return has_op, pv, _clean_channel(op)


def _repeat_fractions(x):
    """``pv_repeat_fraction`` and ``op_repeat_fraction`` of :func:`loop_statistics`, alone.

    For the applicability check, which reads only these two: the same steps (gaps bridged,
    spikes replaced, then repeats counted), without the other statistics.

    Parameters
    ----------
    x : ndarray of shape (n_samples, 3)
        One loop (PV, OP, SP), NaN padding cut.

    Returns
    -------
    pv_rep, op_rep : float
        Share of samples equal to the one before, NaN where :func:`loop_statistics` gives
        NaN (fewer than 8 samples, PV or OP without numbers).
    """
    _, pv, op = _first_steps(_recorded_rows(x))
    return tuple(np.nan if c is None else c.repeat_fraction for c in (pv, op))


def _freezes(x, same, other_runs, step):
    """Hold and independent-freeze shares of one channel.

    A run of repeats that starts and stops on the same samples as a run of the other channel
    (2 samples or more) is a held row; the others are frozen on their own, and count as
    compression when the jump that ends them is off the grid of the smallest change (a
    quantised tag jumps by whole steps).
    """
    n = max(len(same), 1)
    start, stop = true_runs(same)
    if other_runs is not None:
        both = set(zip(*other_runs, strict=True))
        coincident = np.array(
            [(a, b) in both for a, b in zip(start, stop, strict=True)], dtype=bool
        )
    else:
        coincident = np.zeros(len(start), dtype=bool)
    lengths = stop - start
    # single repeats coincide by chance when both tags are compressed; rows held longer do not
    held = float(lengths[coincident & (lengths >= 2)].sum() / n)
    held_len = float(lengths[coincident].mean()) if coincident.any() else np.nan
    alone = ~coincident & (stop < len(same))
    if not alone.any() or not np.isfinite(step) or step <= 0:
        return held, held_len, 0.0
    d = np.diff(x)
    jumps = np.abs(d[stop[alone]])
    ratio = jumps / step
    off_grid = np.abs(ratio - np.round(ratio)) > 1e-3 * np.maximum(ratio, 1.0)
    return held, held_len, float(lengths[alone][off_grid].sum() / n)


def _min_change(x):
    """Smallest non-zero change (the grid step of quantised values); NaN if none."""
    d = np.abs(np.diff(x))
    d = d[d > 1e-12 * max(float(np.ptp(x)), 1e-300)]
    return float(d.min()) if len(d) else np.nan


def _masked_acf(d, ok, max_lag):
    """ACF of ``d`` over the pairs of entries where ``ok`` holds at both ends.

    Each lag is normalised by its own number of valid pairs, so that frozen stretches left
    out do not shrink the ACF towards 0; lags with fewer than ``_MIN_PAIRS`` pairs are NaN.
    """
    z = np.where(ok, d - np.median(d[ok]), 0.0)
    r = _acf(z, max_lag, demean=False)
    pairs = _acf(ok.astype(float), max_lag, demean=False)
    n_pairs = pairs * ok.sum()
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(n_pairs >= _MIN_PAIRS, r / pairs, np.nan)


def _noise_shape(x, same):
    """Noise colour and the averaging dip, from high differences where the noise rules.

    Differencing removes the loop's slow signal (a sine of P samples per cycle shrinks by
    ``2 pi / P`` per difference) and keeps the noise. The lag-1 ACF of the second difference
    is -2/3 for white noise and rises towards -1/2 as AR(1) noise gets coloured (-0.56 for
    phi = 0.5, -0.51 for phi = 0.9). The ACF of the third difference is near 0 beyond lag 3
    for white and AR(1) noise, and dips to -0.5 at lag ``m`` after a trailing mean of ``m``
    samples (interval averaging). Differences touching a frozen sample are left out.
    """
    lo, hi = _AVERAGING_LAGS
    d2 = np.diff(x, 2)
    d3 = np.diff(d2)
    ok1 = _valid_differences(same)
    ok2 = ok1[1:] & ok1[:-1]
    ok3 = ok2[1:] & ok2[:-1]
    if ok3.sum() < 4 * hi:
        return np.nan, np.nan, np.nan, np.nan
    r2 = _masked_acf(d2, ok2, 1)
    colour = float(np.clip((r2[1] + 2.0 / 3.0) * 6.0, -1.0, 1.0)) if np.isfinite(r2[0]) else np.nan
    r3 = _masked_acf(d3, ok3, hi + 1)
    if not np.isfinite(r3[0]):
        return colour, np.nan, np.nan, np.nan
    if not np.isfinite(r3[lo : hi + 1]).any():
        return colour, np.nan, np.nan, np.nan
    k = lo + int(np.nanargmin(r3[lo : hi + 1]))
    # a trailing mean's dip stands between two positive lobes (+0.3 to +0.4) at k - 1 and
    # k + 1 (for k = 2 the lag-1 value belongs to the differencing, only k + 1 counts);
    # chance minima of a noisy ACF have no such lobes
    side = [r3[k + 1]] if k == lo else [r3[k - 1], r3[k + 1]]
    contrast = float(r3[k] - np.mean(side)) if np.isfinite(side).all() else np.nan
    return colour, float(r3[k]), float(k), contrast


def _oscillation(err):
    """ACF peak, period and Thornhill regularity of the detrended control error."""
    n = len(err)
    r = _acf(err, n // 2)
    peak = period = decor = np.nan
    if np.isfinite(r[0]):
        below = np.flatnonzero(r < 0.5)
        decor = float(below[0]) if len(below) else float(n // 2)
        neg = np.flatnonzero(r < 0)
        if len(neg):
            pos = neg[0] + np.flatnonzero(r[neg[0] :] > 0)
            if len(pos):
                after = pos[0] + np.flatnonzero(r[pos[0] :] < 0)
                end = after[0] if len(after) else len(r)
                lag = pos[0] + int(np.argmax(r[pos[0] : end]))
                period, peak = float(lag), float(r[lag])
            else:
                peak = 0.0
        else:
            peak = 0.0
    zc = np.flatnonzero(np.diff(np.signbit(err)))
    reg = np.nan
    if len(zc) >= 5:
        full = zc[2:] - zc[:-2]
        sd = full.std()
        reg = float(full.mean() / (3 * sd)) if sd > 0 else 10.0
    return peak, period, reg, decor


def _drawn(x, span):
    """Share of the rows of ``x`` that lie on lines drawn between stored points (0 when
    it is no interpolated export, :func:`~sktiction.cycles._signal.drawn_lines`) and the
    swinging door's deviation as a share of ``span`` (NaN when no export)."""
    rows = drawn_lines(x)
    if rows is None or not span > 0:
        return 0.0, np.nan
    deviation = _stored_noise(x, rows) / _SCATTER_PER_DEVIATION / span
    return 1.0 - rows.size / x.size, deviation


def _load_shifts(op, sp):
    """OP level shifts (:func:`~sktiction.cycles._level_shifts.level_shifts`) farther than
    two of their windows from every SP shift: loads the loop rejected, not setpoint moves."""
    shifts = level_shifts(op)
    if not len(shifts):
        return 0.0
    sp_moves = sp is not None and np.isfinite(sp).all() and np.ptp(sp) > 0
    sp_shifts = level_shifts(sp) if sp_moves else np.array([], dtype=int)
    reach = 2 * max(len(op) // 20, 10)
    return float(sum(bool(np.all(np.abs(sp_shifts - k) > reach)) for k in shifts))


def _one_loop(x, ts):
    """Statistics of one loop ``x`` (n_samples, 3) with the padding already cut."""
    row = dict.fromkeys(STATISTIC_COLUMNS, np.nan)
    n = x.shape[0]
    if n == 0:
        row.update(n_samples=0, ts=ts, has_op=False, has_sp=False)
        return row
    has_op = bool(np.isfinite(x[:, OP]).any())
    has_sp = bool(np.isfinite(x[:, SP]).any())
    row.update(n_samples=n, ts=ts, has_op=has_op, has_sp=has_sp)
    chans = x[:, PV] if not has_op else np.concatenate([x[:, PV], x[:, OP]])
    row["nan_fraction"] = float(np.isnan(chans).mean())
    x = _recorded_rows(x)
    n, sp = len(x), x[:, SP]
    has_sp = bool(np.isfinite(sp).any())  # within the recorded rows (the row says: at all)
    _, pv_first, op_first = _first_steps(x)
    if pv_first is None:
        return row
    sp = _fill(sp) if has_sp else sp
    pv_span, pv, pv_noise = pv_first.span, pv_first.clean, pv_first.noise
    same_pv, pv_rep = pv_first.same, pv_first.repeat_fraction
    pv_reuse = _level_reuse(pv, same_pv)
    spikes = [pv_first.spike_sizes]
    err = pv - sp if has_sp else pv
    err_span = _span(err)
    if pv_noise is None:
        pv_noise = _noise_sd(pv, same_pv)
    lines = [_drawn(pv, pv_span)]
    if lines[0][0] > 0:  # an interpolated export holds no noise between stored points
        pv_noise = np.nan
    row.update(pv_span=pv_span, error_span=err_span, pv_noise=pv_noise)
    row["noise_level"] = pv_noise / err_span if err_span > 0 else np.nan

    colour, dip, lag, contrast = _noise_shape(pv, same_pv)
    row.update(noise_colour=colour, diff_acf_min=dip, averaging_lag=lag)
    row["averaging_contrast"] = row["pv_averaging_contrast"] = contrast
    row.update(pv_repeat_fraction=pv_rep, pv_level_reuse=pv_reuse)
    row["pv_band"] = _band(pv, same_pv, pv_span)
    pv_q = _min_change(pv)
    row["pv_step"] = pv_q / pv_span if pv_span > 0 else np.nan
    det, slope = _detrend(err)
    det_span = _span(det)
    row["pv_drift"] = abs(slope) * n / det_span if det_span > 0 else np.nan

    peak, period, reg, decor = _oscillation(det)
    row.update(acf_peak=peak, period=period, regularity=reg, decorrelation_lag=decor)

    if op_first is not None:
        op_span, op, op_noise = op_first.span, op_first.clean, op_first.noise
        same_op, op_rep = op_first.same, op_first.repeat_fraction
        op_reuse = _level_reuse(op, same_op)
        spikes.append(op_first.spike_sizes)
        if op_noise is None:
            op_noise = _noise_sd(op, same_op)
        lines.append(_drawn(op, op_span))
        if lines[-1][0] > 0:
            op_noise = np.nan
        row.update(op_span=op_span, op_noise=op_noise, op_repeat_fraction=op_rep)
        row["op_level_reuse"] = op_reuse
        row["op_noise_level"] = op_noise / op_span if op_span > 0 else np.nan
        row["op_band"] = _band(op, same_op, op_span)
        # a historian averages every tag over the same interval: OP must dip at the same lag
        _, _, op_lag, op_contrast = _noise_shape(op, same_op)
        if op_lag == row["averaging_lag"]:
            row["averaging_contrast"] = max(row["averaging_contrast"], op_contrast)
        else:
            row["averaging_contrast"] = 0.0
        both = float((same_pv & same_op).mean())
        row["row_repeat_fraction"] = both
        hold, hold_len, pv_alone = _freezes(pv, same_pv, true_runs(same_op), pv_q)
        _, _, op_alone = _freezes(op, same_op, true_runs(same_pv), _min_change(op))
        row.update(hold_fraction=hold, hold_run_length=hold_len)
        row["independent_freeze"] = 0.5 * (pv_alone + op_alone)
        # Historian holds freeze whole rows: joint repeats beyond what independent
        # per-tag freezes (compression, quantisation) would give by chance.
        row["joint_repeat_excess"] = both - pv_rep * op_rep
        op_det, op_slope = _detrend(op)
        op_det_span = _span(op_det)
        row["op_drift"] = abs(op_slope) * n / op_det_span if op_det_span > 0 else np.nan
        row["op_load_shifts"] = _load_shifts(op, sp if has_sp else None)
        max_lag = int(min(n // 4, 3 * period if np.isfinite(period) else n // 4))
        max_lag = max(max_lag, 1)
        xc = _xcorr(det, op_det, max_lag)
        if np.isfinite(xc).all():
            row["pv_op_corr"] = float(abs(xc[max_lag]))
            k = int(np.argmax(np.abs(xc)))
            row["pv_op_max_corr"] = float(abs(xc[k]))
            row["pv_op_lag"] = float(k - max_lag)
        in_pct = op.min() >= -1 and op.max() <= 101 and op.mean() > 2
        row["op_saturation"] = float(np.mean((op <= 0.5) | (op >= 99.5))) if in_pct else np.nan
    shares, deviations = np.array(lines).T
    row["line_share"] = float(shares.mean())
    if np.isfinite(deviations).any():
        row["line_deviation"] = float(np.nanmedian(deviations))
    spikes = np.concatenate(spikes)
    row["spike_rate"] = len(spikes) / n
    row["spike_size"] = float(np.median(spikes)) if len(spikes) else np.nan

    if has_sp and not np.isnan(sp).any():
        dsp = np.abs(np.diff(sp))
        moved = dsp > 1e-9 * max(1.0, float(np.abs(sp).max()))
        share = float(moved.mean())
        row["sp_change_fraction"] = share
        row["sp_steps"] = float(moved.sum()) if share <= _CASCADE_SHARE else np.nan
        row["sp_step_size"] = (
            float(np.median(dsp[moved]) / pv_span) if moved.any() and pv_span > 0 else 0.0
        )
        row["sp_offset"] = float(np.median(pv - sp) / pv_span) if pv_span > 0 else np.nan
    return row


def loop_statistics(X, ts=None):
    """Per-loop statistics of noise, recording artefacts, setpoint regime and PV-OP relation.

    One row per loop, read by :func:`sktiction.realism.compare`; the applicability check
    computes its two repeat shares by the same steps. Each column is made specific to one effect of
    :data:`sktiction.realism.EFFECTS` (notes below say what else could move it).

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels) or sklearn.utils.Bunch
        Loops with channels PV, OP, SP, NaN-padded at the end (a ``read_loops`` Bunch is read
        from its ``X``, and its ``meta.ts`` gives ``ts`` when ``ts`` is None). NaN gaps inside
        a record are bridged linearly and counted in ``nan_fraction``.
    ts : float, array-like of shape (n_loops,) or None, default=None
        Sample time of each loop (only reported, in column ``ts``; statistics are in samples).

    Returns
    -------
    stats : pandas.DataFrame of shape (n_loops, len(STATISTIC_COLUMNS))
        Columns (stable names; spans are 5-95 % ranges; "error" is PV - SP, or PV without SP):

        - ``n_samples``: samples before the NaN padding (record length); ``ts``;
          ``has_op``, ``has_sp``: the channel holds numbers; ``nan_fraction``: NaN share of PV
          and OP inside the record.
        - ``pv_span``, ``op_span``, ``error_span``; ``pv_noise``, ``op_noise``: robust noise
          sd from second differences, frozen samples left out.
        - ``noise_level``: ``pv_noise / error_span``; ``op_noise_level``: ``op_noise / op_span``.
        - ``noise_colour``: ``6 (r1 + 2/3)`` with ``r1`` the lag-1 autocorrelation of the PV
          second difference: 0 for white noise, 0.6 for AR(1) noise with phi = 0.5, towards 1
          for strongly coloured noise (clipped to -1..1). Interval averaging also moves it.
        - ``diff_acf_min``, ``averaging_lag``: lowest autocorrelation of the PV third
          difference at lags 2-12 and its lag. A trailing mean of ``m`` samples leaves a dip of
          about -0.5 at lag ``m``; white and AR(1) noise stay above -0.1 (interval averaging).
          ``averaging_contrast``: the dip minus the mean ACF at the lags either side (about
          -0.8 for a trailing mean, whose dip sits between two positive lobes; near 0 to -0.25
          for a chance minimum); with OP, the weaker of PV's and OP's, and 0 unless both dip
          at the same lag (a historian averages every tag over the same interval).
          ``pv_averaging_contrast``: PV's alone (a PV filter or PV-only averaging).
        - ``pv_repeat_fraction``, ``op_repeat_fraction``: share of samples equal to the one
          before; ``row_repeat_fraction``: PV and OP both repeated.
        - ``hold_fraction``: share of samples in runs of repeats (2 samples or more) that
          start and stop on the same samples in PV and OP: whole rows held (hold-last-value).
          Per-tag compression freezes tags on their own, so its runs rarely coincide;
          ``hold_run_length``: mean length of those coincident runs.
        - ``joint_repeat_excess``: ``row_repeat_fraction - pv_repeat * op_repeat``, joint
          freezing beyond chance (a cruder hold indicator; compression of tags that move
          together also raises it).
        - ``independent_freeze``: mean over PV and OP of the share of samples in runs of
          repeats not matched by the other tag and ended by a jump off the grid of the
          tag's smallest change: tags frozen on their own at values off any grid (deadband
          or swinging-door compression); zero for held rows and for quantised values.
        - ``line_share``: mean over PV and OP of the share of rows on straight lines drawn
          between stored points (an interpolated export of a swinging-door historian,
          :func:`~sktiction.cycles._signal.drawn_lines`: at least half the second
          differences vanish; 0 otherwise, held or quantised values included).
          ``line_deviation``: the door's deviation read from the stored points' scatter,
          share of the span (NaN without such an export). A channel so exported has no
          noise left to read: its ``pv_noise`` or ``op_noise`` (and ``noise_level``) is NaN.
        - ``pv_level_reuse``, ``op_level_reuse``: ``1 - distinct values / (changes + 1)``;
          quantised signals revisit their levels (near 1), continuous ones do not (0).
        - ``pv_step``: smallest non-zero PV change, share of the span (the grid step when
          ``pv_level_reuse`` is high).
        - ``pv_band``, ``op_band``: 10th percentile of the jumps that end frozen runs, share of
          the span (the compression band; 0 with fewer than 3 runs).
        - ``spike_rate``: samples of PV or OP departing from their 3-point median by more than
          8 noise sd and 20 % of the span, per sample. Steps (holds, setpoint moves) do not count.
          Spikes are replaced by that median before every other statistic is computed.
          ``spike_size``: their median departure, share of the span.
        - ``pv_drift``: linear trend of the error over the record, in units of the detrended
          error's span; ``op_drift``: the same for OP (loads the loop rejects).
        - ``op_load_shifts``: number of OP level shifts (a window's median moving by more
          than three interquartile ranges, at most 6) farther than two windows (a tenth of
          the record) from every SP shift: steps in a load the loop rejected. A cycle's own
          swing does not count, nor a setpoint move, nor a ramp; a square OP cycle slower
          than a tenth of the record would.
        - ``sp_change_fraction``: share of samples whose SP changed (cascade setpoints: most);
          ``sp_steps``: number of SP changes when they are at most 20 % of samples (NaN
          otherwise); ``sp_step_size``: median SP change, share of PV span; ``sp_offset``:
          median PV - SP, share of PV span.
        - ``acf_peak``, ``period``: height and lag of the ACF maximum in the first positive lobe
          after the first zero crossing of the detrended error (0 if none: no oscillation);
          ``regularity``: Thornhill's r, mean / (3 sd) of intervals between alternate zero
          crossings; ``decorrelation_lag``: first lag with ACF < 0.5 (samples: sampling
          against the loop's dynamics).
        - ``pv_op_corr``: absolute correlation of detrended error and OP at lag 0 (PV follows
          OP in phase: near 1); ``pv_op_max_corr``, ``pv_op_lag``: the largest absolute
          correlation within three periods and its lag (PV after OP: positive).
        - ``op_saturation``: share of OP at 0-0.5 % or 99.5-100 % (NaN unless OP is in %).

        Columns that need an absent channel are NaN; a loop of fewer than 8 samples or an
        all-NaN PV has only its length and flags.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.realism import loop_statistics
    >>> rng = np.random.default_rng(0)
    >>> pv = np.sin(np.arange(600) / 10) + 0.05 * rng.standard_normal(600)
    >>> X = np.stack([pv, 50 + 5 * pv, np.zeros(600)], axis=-1)[None]
    >>> stats = loop_statistics(X)
    >>> int(stats.loc[0, "n_samples"]), round(float(stats.loc[0, "period"]))
    (600, 63)
    >>> held = X.copy()
    >>> held[0, 100:300] = held[0, 100]   # whole rows frozen
    >>> s = loop_statistics(held)
    >>> bool(s.loc[0, "joint_repeat_excess"] > 0.2), float(s.loc[0, "independent_freeze"])
    (True, 0.0)
    """
    meta_ts = None
    if hasattr(X, "X") and hasattr(X, "meta"):
        meta_ts = X.meta["ts"].to_numpy(dtype=float) if "ts" in X.meta else None
        X = X.X
    loops = check_loops(X)
    n_loops = loops.shape[0]
    if ts is None:
        ts = meta_ts if meta_ts is not None else np.full(n_loops, np.nan)
    ts = np.broadcast_to(np.asarray(ts, dtype=float), (n_loops,))
    finite = np.isfinite(loops[:, :, PV])
    rows = []
    for i in range(n_loops):
        idx = np.flatnonzero(finite[i])
        n = idx[-1] + 1 if len(idx) else 0
        rows.append(_one_loop(loops[i, :n], float(ts[i])))
    out = pd.DataFrame(rows, columns=list(STATISTIC_COLUMNS))
    out["has_op"] = out["has_op"].astype(bool)
    out["has_sp"] = out["has_sp"].astype(bool)
    return out
