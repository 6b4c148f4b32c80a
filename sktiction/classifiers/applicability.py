"""Applicability before diagnosis: can this loop be diagnosed at all?

A verdict on valve stiction reads the relation between controller output (OP) and
process variable (PV) over enough samples of a closed loop. A record of white noise, two
unrelated signals, a 50-sample snippet, a historian export where most rows are repeats or a
signal that moves on three levels holds no such relation, and any classifier asked about it
answers anyway. :func:`assess_applicability` says, per loop, whether a verdict makes sense
and, if not, why, in words a person can act on.

Every threshold is a chance level or a physical bound, none is fitted to measured loops:

- ``too_short``: fewer than :data:`MIN_SAMPLES` samples, the shortest record on which the
  coherence below has 7 half-overlapping segments of 32 samples (the 32 bins a cycle is
  averaged into for template matching).
- ``pv_op_unrelated``: in a closed loop the controller makes OP a linear filter of the
  control error, so PV (or SP - PV) and OP are coherent at the frequencies where the loop
  moves. The largest magnitude-squared coherence (Welch, Hann windows, half overlap,
  linear detrend per segment) must exceed its chance level: for independent signals and
  ``K`` independent segments ``P(C > c) = (1 - c) ** (K - 1)``; ``K`` is corrected for the
  overlap (Welch's equivalent count, ``K / 1.056`` for Hann at 50 %) and the level is
  Bonferroni-corrected over the frequencies and signals tested, at :data:`ALPHA`.
- ``quantised``: the values sit on a grid of step ``q`` (sample-to-sample changes are whole
  multiples of it) and the quantisation noise ``q**2 / 12`` is louder than the noisiest loops
  the classifiers are trained on: signal-to-quantisation-noise ratio below
  :data:`MIN_QUANTISATION_SNR_DB` (the low end of ``make_loops``' noise range).
- ``too_compressed``: more than half of the samples of PV or OP repeat the one before:
  recording artefacts (hold-last-value, compression) then dominate the record.
- ``constant_pv``, ``constant_op``, ``no_op``, ``nan_gap``, ``empty``, ``not_finite``:
  what they say (``not_finite``: an infinite value, or values so large that their spread
  overflows).

Each loop is normalised by its own median and robust spread before anything is measured,
so scale and offset never change the outcome.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import signal

from .._validation import OP, PV, SP, STATUS_EMPTY, STATUS_NAN_GAP, STATUS_OK, STATUS_TOO_SHORT

__all__ = [
    "ALPHA",
    "APPLICABILITY_COLUMNS",
    "MIN_QUANTISATION_SNR_DB",
    "MIN_SAMPLES",
    "assess_applicability",
]

MIN_SAMPLES = 128
# False-alarm rate of the coherence test for one loop whose PV and OP are unrelated.
ALPHA = 1e-3
MIN_QUANTISATION_SNR_DB = 10.0
# Share of repeated samples above which recording artefacts dominate a channel.
MAX_REPEAT_FRACTION = 0.5
# Welch's equivalent number of independent segments: K / (1 + 2 rho**2), rho = 0.167 for Hann
# windows overlapping by half (Welch 1967; Percival & Walden 1993, Table 292).
_HANN_HALF_OVERLAP = 1.0 + 2.0 * 0.167**2
# A change this many grid steps off a whole multiple is off the grid.
_GRID_TOLERANCE = 0.05
# Share of changes on the grid for a signal to count as sitting on one.
_GRID_SHARE = 0.9

REASON_NOT_FINITE = "not_finite"
REASON_NO_OP = "no_op"
REASON_CONSTANT_PV = "constant_pv"
REASON_CONSTANT_OP = "constant_op"
REASON_QUANTISED = "quantised"
REASON_TOO_COMPRESSED = "too_compressed"
REASON_UNRELATED = "pv_op_unrelated"

APPLICABILITY_COLUMNS = (
    "applicable",
    "reason",
    "n_samples",
    "pv_op_coherence",
    "coherence_chance_level",
    "pv_repeat_fraction",
    "op_repeat_fraction",
    "pv_quantisation_snr_db",
    "op_quantisation_snr_db",
)


def _as_loops(X):
    """Loops ``(n_loops, n_samples, 3)`` as float, keeping infinities (they are a reason)."""
    if hasattr(X, "X") and hasattr(X, "meta"):
        X = X.X
    arr = np.asarray(X)
    if np.iscomplexobj(arr):
        raise ValueError("Complex data not supported: X holds complex values.")
    try:
        arr = np.array(arr, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"X must hold numbers; got dtype {arr.dtype}.") from exc
    if arr.ndim == 2:
        arr = arr[:, :, None]
    if arr.ndim != 3:
        raise ValueError(
            f"X must be 3-D (n_loops, n_samples, n_channels) or 2-D (PV only); got {arr.ndim}-D."
        )
    n_loops, n_samples, n_channels = arr.shape
    if n_loops == 0 or n_samples == 0:
        raise ValueError(f"X is empty: shape {arr.shape}.")
    if n_channels == 0 or n_channels > 3:
        raise ValueError(
            f"X must have 1 to 3 channels (PV, OP, SP in that order); got {n_channels}."
        )
    if n_channels < 3:
        pad = np.full((n_loops, n_samples, 3 - n_channels), np.nan)
        arr = np.concatenate([arr, pad], axis=2)
    return arr


def _robust_spread(x):
    """Interquartile range as a standard deviation; the sd when most samples share a value."""
    q1, q3 = np.percentile(x, [25, 75])
    spread = (q3 - q1) / 1.349
    if not spread > 0:
        spread = np.std(x)
    return float(spread)


def _normalise(x, spread):
    with np.errstate(over="ignore", invalid="ignore"):
        return (x - np.median(x)) / spread


def _repeat_fraction(x):
    return float(np.mean(np.diff(x) == 0)) if len(x) > 1 else 0.0


def _quantisation_snr_db(x):
    """Signal to quantisation noise ratio in dB, or inf when the values sit on no grid.

    ``x`` is normalised (robust spread 1, or sd 1 when most samples share a value).
    """
    step = np.abs(np.diff(x))
    step = step[step > 0]
    if len(step) < 2:
        return -np.inf
    q = step.min()
    ratio = step / q
    on_grid = np.mean(np.abs(ratio - np.round(ratio)) < _GRID_TOLERANCE)
    if on_grid < _GRID_SHARE:
        return np.inf
    q1, q3 = np.percentile(x, [25, 75])
    sd = (q3 - q1) / 1.349
    if sd <= 0:
        return -np.inf
    return float(10.0 * np.log10(12.0 * sd**2 / q**2))


def _coherence(pairs, n):
    """Largest coherence over frequencies and signal pairs, and its chance level."""
    nperseg = int(np.clip(n // 8, 32, 256))
    noverlap = nperseg // 2
    n_segments = (n - noverlap) // (nperseg - noverlap)
    k_eff = n_segments / _HANN_HALF_OVERLAP
    best = 0.0
    n_tests = 0
    for a, b in pairs:
        _, c = signal.coherence(
            a, b, nperseg=nperseg, noverlap=noverlap, detrend="linear"
        )
        c = c[1:]  # the mean is removed per segment: no information at frequency 0
        c = c[np.isfinite(c)]
        n_tests += len(c)
        if len(c):
            best = max(best, float(c.max()))
    if n_tests == 0 or k_eff <= 1:
        return best, 1.0
    chance = 1.0 - (ALPHA / n_tests) ** (1.0 / (k_eff - 1.0))
    return best, float(chance)


def _assess_one(x):
    """One loop ``x`` (n_samples, 3) with the end padding cut: a row of the result."""
    row = dict.fromkeys(APPLICABILITY_COLUMNS, np.nan)
    row["applicable"] = False
    n = len(x)
    row["n_samples"] = n
    pv, op, sp = x[:, PV], x[:, OP], x[:, SP]
    has_op = bool(np.isfinite(op).any())
    has_sp = bool(np.isfinite(sp).any()) and not np.isnan(sp).any()
    if n == 0:
        row["reason"] = STATUS_EMPTY
        return row
    if np.isinf(x).any():
        row["reason"] = REASON_NOT_FINITE
        return row
    if n < MIN_SAMPLES:
        row["reason"] = STATUS_TOO_SHORT
        return row
    if not has_op:
        row["reason"] = REASON_NO_OP
        return row
    if np.isnan(pv).any() or np.isnan(op).any():
        row["reason"] = STATUS_NAN_GAP
        return row
    with np.errstate(over="ignore", invalid="ignore"):
        pv_spread, op_spread = _robust_spread(pv), _robust_spread(op)
    if not (np.isfinite(pv_spread) and np.isfinite(op_spread)):
        row["reason"] = REASON_NOT_FINITE
        return row
    if pv_spread == 0:
        row["reason"] = REASON_CONSTANT_PV
        return row
    if op_spread == 0:
        row["reason"] = REASON_CONSTANT_OP
        return row
    pvn = _normalise(pv, pv_spread)
    opn = _normalise(op, op_spread)
    # the control error in PV units: SP shares PV's offset and scale
    errn = _normalise(sp - pv, pv_spread) if has_sp else None
    if not (np.isfinite(pvn).all() and np.isfinite(opn).all()) or (
        errn is not None and not np.isfinite(errn).all()
    ):
        row["reason"] = REASON_NOT_FINITE
        return row
    row["pv_repeat_fraction"] = _repeat_fraction(pvn)
    row["op_repeat_fraction"] = _repeat_fraction(opn)
    row["pv_quantisation_snr_db"] = _quantisation_snr_db(pvn)
    row["op_quantisation_snr_db"] = _quantisation_snr_db(opn)
    pairs = [(pvn, opn)]
    if errn is not None and np.ptp(sp) > 0:
        pairs.append((errn, opn))
    coh, chance = _coherence(pairs, n)
    row["pv_op_coherence"], row["coherence_chance_level"] = coh, chance
    if min(row["pv_quantisation_snr_db"], row["op_quantisation_snr_db"]) < (
        MIN_QUANTISATION_SNR_DB
    ):
        row["reason"] = REASON_QUANTISED
    elif max(row["pv_repeat_fraction"], row["op_repeat_fraction"]) > MAX_REPEAT_FRACTION:
        row["reason"] = REASON_TOO_COMPRESSED
    elif not coh > chance:
        row["reason"] = REASON_UNRELATED
    else:
        row["reason"] = STATUS_OK
        row["applicable"] = True
    return row


def assess_applicability(X, ts=None):
    """Say for each loop whether it can be diagnosed at all, and if not, why.

    Run before any verdict: a loop that is not applicable gets ``verdict =
    "no_verdict"`` with the reason given here. See the module notes for how each
    reason is decided; every threshold is a chance level or a physical bound. Each
    loop is normalised by its own median and robust spread first, so scale and
    offset never change the outcome.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels) or sklearn.utils.Bunch
        Loops with channels PV, OP, SP, NaN-padded at the end (2-D input is PV
        only; a ``read_loops`` Bunch is read from its ``X``). Infinite values are
        allowed: they make that loop ``not_finite``.
    ts : float, array-like of shape (n_loops,) or None, default=None
        Sample time of each loop; statistics are in samples, so it is only
        reported (column ``ts``).

    Returns
    -------
    applicability : pandas.DataFrame of shape (n_loops, n_columns)
        One row per loop:

        - ``applicable`` (bool) and ``reason``: ``"ok"``, or the first that
          applies of ``empty``, ``not_finite``, ``too_short``, ``no_op``,
          ``nan_gap``, ``constant_pv``, ``constant_op``, ``quantised``,
          ``too_compressed``, ``pv_op_unrelated``.
        - ``n_samples``: record length before the NaN padding.
        - ``pv_op_coherence``: largest magnitude-squared coherence of OP with PV
          (and with SP - PV when SP moves); ``coherence_chance_level``: the level
          unrelated signals exceed with probability :data:`ALPHA`.
        - ``pv_repeat_fraction``, ``op_repeat_fraction``: share of samples equal
          to the one before.
        - ``pv_quantisation_snr_db``, ``op_quantisation_snr_db``: signal to
          quantisation noise ratio (``inf`` when the values sit on no grid).
        - ``ts``.

        Statistics a loop did not reach (it failed an earlier check) are NaN.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.classifiers.applicability import assess_applicability
    >>> X, _ = make_loops(2, n_samples=1000, random_state=0)
    >>> rng = np.random.default_rng(0)
    >>> noise = rng.standard_normal((1, 1000, 3))     # PV, OP, SP: unrelated noise
    >>> snippet = np.full((1, 1000, 3), np.nan)
    >>> snippet[:, :50] = X[:1, :50]                  # 50 samples, NaN-padded
    >>> assess_applicability(np.concatenate([X, noise, snippet]))["reason"].tolist()
    ['ok', 'ok', 'pv_op_unrelated', 'too_short']
    >>> assess_applicability(1e12 * X + 7)["applicable"].tolist()
    [True, True]
    """
    loops = _as_loops(X)
    n_loops = loops.shape[0]
    if ts is None and hasattr(X, "meta") and "ts" in getattr(X, "meta", {}):
        ts = X.meta["ts"].to_numpy(dtype=float)
    ts = np.broadcast_to(
        np.asarray(np.nan if ts is None else ts, dtype=float), (n_loops,)
    )
    present = ~np.isnan(loops[:, :, PV])
    rows = []
    for i in range(n_loops):
        idx = np.flatnonzero(present[i])
        n = idx[-1] + 1 if len(idx) else 0
        rows.append(_assess_one(loops[i, :n]))
    out = pd.DataFrame(rows, columns=list(APPLICABILITY_COLUMNS))
    out["applicable"] = out["applicable"].astype(bool)
    out["n_samples"] = out["n_samples"].astype(int)
    out["ts"] = ts
    return out
