"""Applicability before diagnosis: can this loop be diagnosed at all?

A verdict on valve stiction reads the relation between controller output (OP) and
process variable (PV) over enough samples of a closed loop. A record of white noise, two
unrelated signals, a 50-sample snippet, a historian export where most rows are repeats or a
signal that moves on three levels holds no such relation, and any classifier asked about it
answers anyway. :func:`assess_applicability` says, per loop, whether a verdict makes sense
and, if not, why, in words a person can act on.

Every threshold is a chance level or a physical bound, none is fitted to measured loops:

- ``too_short``: fewer than :data:`MIN_SAMPLES` samples, the shortest record on which the
  coherence below has 7 half-overlapping segments of 32 samples (the 32 points a cycle is
  averaged into for template matching).
- ``pv_op_unrelated``: in a closed loop the controller makes OP a linear filter of the
  control error, so PV (or SP - PV) and OP are coherent at the frequencies where the loop
  moves. The largest magnitude-squared coherence (Welch, Hann windows, half overlap,
  linear detrend per segment; segments of 1/12 and 1/4 of the record, for fast dynamics
  and slow cycles) must exceed its chance level: for independent signals and ``K``
  independent segments ``P(C > c) = (1 - c) ** (K - 1)`` (Carter 1987); ``K`` is the
  equivalent count of the overlapping, detrended segments (``K / 1.2``, checked by a Monte
  Carlo of independent noise), and the level is Bonferroni-corrected over the frequencies,
  the signals and the two resolutions, at :data:`ALPHA`. Rows where neither PV nor OP
  moved (historian holds) are left out first: unrelated signals held together would share
  their step times.
- ``quantised``: the values sit on a grid of step ``q`` (sample-to-sample changes are whole
  multiples of it) and the quantisation noise ``q**2 / 12`` is within 10 dB of the signal
  (signal-to-quantisation-noise ratio ``12 sd**2 / q**2`` below
  :data:`MIN_QUANTISATION_SNR_DB` = 10 dB, i.e. fewer than about one grid step per standard
  deviation): the record shows the grid as much as the loop.
- ``too_compressed``: fewer than :data:`MIN_SAMPLES` rows in which PV or OP moved (the
  rest are holds: the informative record is shorter than the shortest one analysed), or PV
  or OP changes on fewer than :data:`MIN_CHANGES` samples (fewer than the 32 points one
  cycle is averaged into for template matching); and, in place of ``pv_op_unrelated``, a
  loop whose PV or OP is drawn as straight lines through fewer than :data:`MIN_CHANGES`
  points that bend on their way, not only where they turn back (an interpolated export
  compressed with a deviation about as large as the channel's movement: 32 and 26 of the
  62 and 63 loops the coherence refused among the third simulator's 400 interpolated
  exports of ``benchmarks/third_world.py``, draws 0 and 1, whose sampled copies it refused
  2 and 3 times; a clean triangle or a ramp is no export). Such a loop is refused only when the
  coherence refuses it: a few-point square wave of a sticky valve is evidence (refusing
  every loop drawn through fewer points lost 0.03 of balanced accuracy on the default
  world's exports). Repeat shares are those of
  :func:`sktiction.realism.loop_statistics` (same definition, one implementation: NaN gaps
  bridged and spikes replaced before repeats are counted), computed without its other
  statistics.
- ``constant_pv``, ``constant_op``, ``no_op``, ``nan_gap``, ``empty``, ``not_finite``:
  what they say (``not_finite``: an infinite value, or values so large that their spread
  overflows).

Each loop is normalised by its own median and robust spread before anything is measured,
so scale and offset never change the outcome.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from numpy.lib.stride_tricks import sliding_window_view

from .._validation import OP, PV, SP, STATUS_EMPTY, STATUS_NAN_GAP, STATUS_OK, STATUS_TOO_SHORT
from ..cycles._signal import fast_percentile, on_grid_share, robust_spread, stored_points
from ..realism.statistics import _repeat_fractions

__all__ = [
    "ALPHA",
    "APPLICABILITY_COLUMNS",
    "MIN_CHANGES",
    "MIN_QUANTISATION_SNR_DB",
    "MIN_SAMPLES",
    "assess_applicability",
]

MIN_SAMPLES = 128
# False-alarm rate of the coherence test for one loop whose PV and OP are unrelated.
ALPHA = 1e-3
MIN_QUANTISATION_SNR_DB = 10.0
MIN_CHANGES = 32
# Equivalent number of independent segments: K / 1.2. Welch's K / (1 + 2 rho**2) = K / 1.056
# for Hann windows overlapping by half (rho = 0.167) is not conservative once each segment's
# straight line is removed; a Monte Carlo of independent white noise (300-3,000 samples,
# see tests/test_applicability.py) gives at most the nominal false-alarm rate with K / 1.2.
_SEGMENT_DIVISOR = 1.2
# Welch segments as a share of the record: 1/12 for fast dynamics, 1/4 for slow cycles.
_SEGMENT_FRACTIONS = (12, 4)
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
    "coherence_ratio",
    "pv_repeat_fraction",
    "op_repeat_fraction",
    "n_informative_rows",
    "n_changes",
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


def _normalise(x, spread):
    with np.errstate(over="ignore", invalid="ignore"):
        return (x - np.median(x)) / spread


def _quantisation_snr_db(x):
    """Signal to quantisation noise ratio in dB, or inf when the values sit on no grid.

    ``x`` is normalised (robust spread 1, or sd 1 when most samples share a value).
    """
    step = np.abs(np.diff(x))
    step = step[step > 0]
    if len(step) < 2:
        return -np.inf
    q = step.min()
    if on_grid_share(step, q, _GRID_TOLERANCE) < _GRID_SHARE:
        return np.inf
    q1, q3 = fast_percentile(x, [25, 75])
    sd = (q3 - q1) / 1.349
    if sd <= 0:
        return -np.inf
    return float(10.0 * np.log10(12.0 * sd**2 / q**2))


def _segments(x, nperseg):
    """Half-overlapping segments of ``x``, each with its own straight line removed."""
    seg = sliding_window_view(x, nperseg)[:: nperseg // 2]
    t = np.arange(nperseg) - (nperseg - 1) / 2.0
    seg = seg - seg.mean(axis=1, keepdims=True)
    return seg - np.outer(seg @ t / (t @ t), t)


def _chance_level(n_tests, n_segments, alpha=ALPHA):
    """Coherence that unrelated signals exceed in any of ``n_tests`` frequencies with
    probability ``alpha``: ``P(C > c) = (1 - c) ** (K - 1)`` per frequency for ``K``
    independent segments (Carter 1987), Bonferroni over the frequencies."""
    k_eff = n_segments / _SEGMENT_DIVISOR
    if n_tests == 0 or k_eff <= 1:
        return 1.0
    return float(1.0 - (alpha / n_tests) ** (1.0 / (k_eff - 1.0)))


def _coherence(pairs, n):
    """Largest coherence over frequencies, signal pairs and two resolutions, as a share of
    its chance level (unrelated signals exceed 1 with probability :data:`ALPHA`).

    Welch's estimate with periodic Hann windows, half overlap and a linear detrend
    per segment (the same numbers as ``scipy.signal.coherence(..., detrend="linear")``
    for an even ``nperseg``, without its per-segment least squares). Segments of a
    twelfth of the record resolve fast dynamics with many segments; segments of a quarter
    keep slow cycles that a short segment's detrend would remove. Each resolution is
    tested at ``ALPHA / 2``.

    Returns
    -------
    best : float
        Largest coherence found (at the resolution where it stands highest above chance).
    ratio : float
        ``best`` divided by its chance level.
    """
    best_ratio, best_value = 0.0, 0.0
    for fraction in _SEGMENT_FRACTIONS:
        nperseg = int(np.clip(n // fraction, 32, 512))
        nperseg -= nperseg % 2
        window = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(nperseg) / nperseg)
        best, n_tests, n_segments = 0.0, 0, 0
        for a, b in pairs:
            fa = np.fft.rfft(_segments(a, nperseg) * window, axis=1)[:, 1:]
            fb = np.fft.rfft(_segments(b, nperseg) * window, axis=1)[:, 1:]
            n_segments = len(fa)
            cross = np.abs((np.conj(fa) * fb).mean(axis=0)) ** 2
            power = (np.abs(fa) ** 2).mean(axis=0) * (np.abs(fb) ** 2).mean(axis=0)
            ok = power > 0  # frequency 0 is left out: the mean is removed per segment
            n_tests += int(ok.sum())
            if ok.any():
                best = max(best, float((cross[ok] / power[ok]).max()))
        chance = _chance_level(n_tests, n_segments, ALPHA / len(_SEGMENT_FRACTIONS))
        if best / chance > best_ratio:
            best_ratio, best_value = best / chance, best
    return best_value, best_ratio


def _prepare(x):
    """Checks that need no statistics, and the loop normalised for the others.

    Returns ``(reason, normalised)``: a reason when the loop fails a check (and
    ``None``), else ``None`` and the loop (n_samples, 3) with PV and SP centred on
    PV's median and divided by PV's robust spread, OP by its own.
    """
    n = len(x)
    pv, op, sp = x[:, PV], x[:, OP], x[:, SP]
    if n == 0:
        return STATUS_EMPTY, None
    if np.isinf(x).any():
        return REASON_NOT_FINITE, None
    if n < MIN_SAMPLES:
        return STATUS_TOO_SHORT, None
    if np.isnan(op).all():
        return REASON_NO_OP, None
    if np.isnan(pv).any() or np.isnan(op).any():
        return STATUS_NAN_GAP, None
    # exact comparisons: the sd of a constant is not always exactly 0 in floating point
    if (pv == pv[0]).all():
        return REASON_CONSTANT_PV, None
    if (op == op[0]).all():
        return REASON_CONSTANT_OP, None
    with np.errstate(over="ignore", invalid="ignore"):
        pv_spread, op_spread = robust_spread(pv), robust_spread(op)
        if not (np.isfinite(pv_spread) and np.isfinite(op_spread)):
            return REASON_NOT_FINITE, None
        centre = np.median(pv)
        out = np.stack(
            [(pv - centre) / pv_spread, _normalise(op, op_spread), (sp - centre) / pv_spread],
            axis=1,
        )
    if not np.isfinite(out[:, :2]).all() or np.isinf(out[:, 2]).any():
        return REASON_NOT_FINITE, None
    return None, out


def drawn_through_few(pv, op):
    """Whether PV or OP is drawn as straight lines through fewer than :data:`MIN_CHANGES`
    points that bend on their way, not only where they turn back
    (:func:`~sktiction.cycles._signal.stored_points`): an export so compressed that
    PV and OP may not look related even where the loop relates them."""
    counts = (stored_points(pv), stored_points(op))
    return any(c is not None and c < MIN_CHANGES for c in counts)


def _decide(x):
    """Statistics and reason of one normalised loop."""
    n = len(x)
    pv, op, sp = x[:, PV], x[:, OP], x[:, SP]
    pv_rep, op_rep = _repeat_fractions(x)
    row = {
        "pv_repeat_fraction": float(pv_rep),
        "op_repeat_fraction": float(op_rep),
        "pv_quantisation_snr_db": _quantisation_snr_db(pv),
        "op_quantisation_snr_db": _quantisation_snr_db(op),
    }
    # Rows where neither PV nor OP moved are historian holds, not samples: under them
    # two unrelated signals would share their step times and look related.
    moved = np.concatenate([[True], (np.diff(pv) != 0) | (np.diff(op) != 0)])
    n_rows = int(moved.sum())
    row["n_informative_rows"] = n_rows
    pairs = [(pv[moved], op[moved])]
    if not np.isnan(sp).any() and np.ptp(sp) > 0:
        pairs.append(((sp - pv)[moved], op[moved]))  # the controller's own input
    if n_rows >= MIN_SAMPLES:
        row["pv_op_coherence"], row["coherence_ratio"] = _coherence(pairs, n_rows)
    changes = (n - 1) * (1.0 - max(row["pv_repeat_fraction"], row["op_repeat_fraction"]))
    row["n_changes"] = int(round(changes))
    if min(row["pv_quantisation_snr_db"], row["op_quantisation_snr_db"]) < (
        MIN_QUANTISATION_SNR_DB
    ):
        row["reason"] = REASON_QUANTISED
    elif n_rows < MIN_SAMPLES or changes < MIN_CHANGES:
        row["reason"] = REASON_TOO_COMPRESSED
    elif not row["coherence_ratio"] > 1.0:
        row["reason"] = REASON_TOO_COMPRESSED if drawn_through_few(pv, op) else REASON_UNRELATED
    else:
        row["reason"] = STATUS_OK
    row["applicable"] = row["reason"] == STATUS_OK
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
          (and with SP - PV when SP moves); ``coherence_ratio``: the largest
          coherence over its chance level (unrelated signals exceed 1 with
          probability :data:`ALPHA`).
        - ``pv_repeat_fraction``, ``op_repeat_fraction``: share of samples equal
          to the one before, spikes replaced first (as in
          :func:`sktiction.realism.loop_statistics`).
        - ``n_changes``: samples on which the less lively of PV and OP changes.
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
    n_loops, n_samples = loops.shape[:2]
    if ts is None and hasattr(X, "meta") and "ts" in getattr(X, "meta", {}):
        ts = X.meta["ts"].to_numpy(dtype=float)
    ts = np.broadcast_to(np.asarray(np.nan if ts is None else ts, dtype=float), (n_loops,))
    present = ~np.isnan(loops[:, :, PV])
    lengths = np.where(present.any(axis=1), n_samples - np.argmax(present[:, ::-1], axis=1), 0)
    rows = [dict.fromkeys(APPLICABILITY_COLUMNS, np.nan) for _ in range(n_loops)]
    for i, n in enumerate(lengths):
        rows[i]["n_samples"] = int(n)
        reason, x = _prepare(loops[i, :n])
        if reason is None:
            rows[i].update(_decide(x))
        else:
            rows[i].update(applicable=False, reason=reason)
    out = pd.DataFrame(rows, columns=list(APPLICABILITY_COLUMNS))
    out["applicable"] = out["applicable"].astype(bool)
    out["n_samples"] = out["n_samples"].astype(int)
    out["ts"] = ts
    return out
