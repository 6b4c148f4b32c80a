"""Whole-loop descriptors that need no cycles: OP-PV correlation shape and stick-slip jumps.

They complement the cycle features for windows that do not oscillate: a sticky valve
in a flow loop may show up only as a few slips (PV jumps while OP ramps) during a
setpoint move, and such a window has no cycles to match.
"""

from __future__ import annotations

import numpy as np

from .._validation import OP, PV
from ._loops import LoopTransformer

FEATURES = (
    "ccf_zero_lag",
    "ccf_peak_lag",
    "pv_jump_share",
    "op_jump_share",
    "pv_op_jump_ratio",
    "op_saturated_share",
)


def _jump_share(x, top=0.02):
    """Share of the total absolute increments carried by the largest ``top`` fraction.

    A ramp spreads its travel evenly (share close to ``top``); a signal that moves in
    a few slips concentrates it (share close to 1).
    """
    dx = np.abs(np.diff(x))
    total = dx.sum()
    if total == 0:
        return np.nan
    k = max(1, int(np.ceil(top * dx.size)))
    return float(np.partition(dx, dx.size - k)[-k:].sum() / total)


def _saturated_share(op, tol=1e-3):
    """Share of samples with OP pinned at its own minimum or maximum.

    Measured from OP's own range, not 0/100 %, so the units of OP do not matter: a
    saturated controller output sits on one value for long runs, while a moving one
    touches its extremes once.
    """
    lo, hi = op.min(), op.max()
    band = tol * (hi - lo)
    at_edge = (op <= lo + band) | (op >= hi - band)
    return float(at_edge.mean()) if at_edge.mean() > 0.01 else 0.0


def _ccf_features(pv, op, max_lag):
    """Horch's cross-correlation test, reduced to two numbers.

    Returns the normalised CCF at lag 0 relative to its largest magnitude within
    ``max_lag`` (near 0 for the odd CCF of a sticking valve in a self-regulating loop,
    near +-1 for the even CCF of tuning or disturbance problems), and the lag of
    that largest magnitude as a fraction of ``max_lag``.
    """
    pv = pv - pv.mean()
    op = op - op.mean()
    denom = np.sqrt(np.dot(pv, pv) * np.dot(op, op))
    if denom == 0:
        return np.nan, np.nan
    n = pv.size
    lags = np.arange(-max_lag, max_lag + 1)
    ccf = (
        np.array(
            [np.dot(op[max(0, -k) : n - max(0, k)], pv[max(0, k) : n - max(0, -k)]) for k in lags]
        )
        / denom
    )
    peak = int(np.argmax(np.abs(ccf)))
    return float(ccf[max_lag] / abs(ccf[peak])), float(lags[peak] / max_lag)


class LoopDescriptors(LoopTransformer):
    """Cycle-free descriptors of each loop: CCF shape, stick-slip jumps, saturation.

    Columns:

    - ``ccf_zero_lag``, ``ccf_peak_lag``: Horch's (1999) OP-PV cross-correlation
      test, as the CCF at lag 0 over its largest magnitude and where that lies.
    - ``pv_jump_share``, ``op_jump_share``: share of total travel carried by the
      largest 2 % of sample-to-sample moves; ``pv_op_jump_ratio`` their ratio
      (large when PV slips while OP ramps, the mark of stick-slip).
    - ``op_saturated_share``: share of samples with OP pinned at its own minimum
      or maximum (0 up to 1 %, so a single touch does not count).

    Every column is unchanged when PV and OP are scaled or shifted. The kurtosis
    of PV increments minus OP increments was dropped: in simulated training sets it
    read the OP kick of a setpoint step (a nuisance), not the valve.

    Loops that cannot be analysed (see :func:`~sktiction._validation.loop_status`)
    get NaN; OP-based columns are NaN without OP.

    Parameters
    ----------
    max_lag : int, default=100
        Largest CCF lag in samples (capped at a quarter of the loop length).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.features import LoopDescriptors
    >>> t = np.arange(600)
    >>> op = 50 + 5 * np.abs((t % 100) / 50 - 1)         # triangular OP
    >>> pv = 50 + 3 * np.sign(np.sin(2 * np.pi * t / 100))  # square PV
    >>> X = np.stack([pv, op], axis=1)[None]
    >>> d = LoopDescriptors().fit(X).transform(X)
    >>> bool(d[0, 4] > 5)  # PV carries its travel in jumps, OP does not
    True
    """

    feature_names = FEATURES

    def __init__(self, max_lag=100):
        self.max_lag = max_lag

    def _validate_params(self):
        if int(self.max_lag) != self.max_lag or self.max_lag < 1:
            raise ValueError(f"max_lag must be an integer >= 1; got {self.max_lag!r}.")

    def _transform_loop(self, loops, i, n):
        row = np.full(len(FEATURES), np.nan)
        pv = loops[i, :n, PV]
        row[2] = _jump_share(pv)
        op = loops[i, :n, OP]
        if np.isnan(op).any() or np.ptp(op) == 0:
            return row
        row[:2] = _ccf_features(pv, op, max(1, min(int(self.max_lag), n // 4)))
        row[3] = _jump_share(op)
        row[4] = row[2] / row[3] if row[3] > 0 else np.nan
        row[5] = _saturated_share(op)
        return row
