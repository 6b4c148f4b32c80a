"""Whether PV and OP are related as a closed loop's are: the domain rules' per-loop statistics.

A learned verdict is only given where the loop is what the model learned: PV and OP of one
closed loop, not mostly frozen rows. :func:`pv_op_coupling` tests how clearly OP follows the
control error as a controller's output does; :func:`domain_statistics` gives it (plain and
prewhitened) and the share of frozen rows for every loop, the columns that
:class:`~sktiction.classifiers.LearnedStictionClassifier` checks but never learns from.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from .._validation import OP, PV, SP, STATUS_OK, loop_lengths, loop_status
from ..cycles._signal import lines_through_changes

# Statistics checked by the domain rules but not given to the model.
DOMAIN_STATISTICS = ("pv_op_coupling", "pv_op_coupling_white", "frozen_share")
# A coupling z below _WEAK_COUPLING must also hold after prewhitening (z >= _MIN_WHITE):
# measured on 400 default-world loops against OP and PV of two different loops, this
# lets 0.2 % of such pairs through instead of 2.2 %, for 1 % more simulated loops
# without a verdict.
_WEAK_COUPLING, _MIN_WHITE = 10.0, 3.0
_HELD_APART = 0.1  # see domain_statistics
_PREWHITEN_ORDER = 8


def _ar_filter(x, coef):
    """Residual of ``x`` after the AR prediction with coefficients ``coef`` (lags 1..p)."""
    p = coef.size
    out = x[p:].copy()
    for k in range(p):
        out -= coef[k] * x[p - 1 - k : x.size - 1 - k]
    return out


def pv_op_coupling(pv, op, sp=None, *, prewhiten=0):
    """How clearly OP follows the control error as a controller's output does, as a z-score.

    Any PI(D) controller moves its output by ``dOP[t] = Kc de[t] + Kc Ts / Ti e[t]``
    (plus filter and derivative terms), with ``e = SP - PV``. The increments of OP are
    regressed on the error and its increment at lags 0 and 1, and the regression's
    F-test is turned into a one-sided normal z-score (capped near 37). Conditional on
    the error, unrelated OP increments make the F-test exact, so unrelated signals
    (white noise, independent random walks, repeated values) give z of about 0 and
    rarely above 3; a closed loop gives a large z whether it oscillates or not, a
    noise-free limit cycle included.

    Parameters
    ----------
    pv, op : ndarray of shape (n_samples,)
        One loop, without NaN.
    sp : ndarray or None, default=None
        Setpoint; ``None`` or any NaN uses ``-PV`` about its mean as the error.
    prewhiten : int, default=0
        Order of an AR filter fitted to OP's increments and applied to both sides
        first (Box and Jenkins' prewhitening). Smooth, autocorrelated OP increments
        make the plain F-test too generous: OP and PV of two different loops, each
        oscillating, can reach z of 5-10 without it.

    Returns
    -------
    z : float
        NaN when OP never moves or the record is shorter than 10 samples.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.classifiers import pv_op_coupling
    >>> rng = np.random.default_rng(0)
    >>> a, b = rng.normal(size=(2, 1000)).cumsum(axis=1)
    >>> bool(pv_op_coupling(a, b) < 5), bool(pv_op_coupling(a, -2 * a + b / 10) > 20)
    (True, True)
    """
    pv = np.asarray(pv, dtype=float)
    if sp is None or np.isnan(sp).any():
        err = -(pv - pv.mean())
    else:
        err = np.asarray(sp, dtype=float) - pv
    y = np.diff(op)[1:]
    if y.size < 10 or np.ptp(y) == 0:
        return np.nan
    # de[t] = err[t] - err[t - 1]: the error at lags 0 and 1 and its increment at lag 1
    # span the increments at lags 0 and 1 too, without a redundant column that would
    # give the F-test one numerator degree of freedom too many
    de = np.diff(err)
    A = np.column_stack([de[:-1], err[2:], err[1:-1], np.ones(y.size)])
    if prewhiten:
        p = int(min(prewhiten, max(1, y.size // 20)))
        lagged = np.column_stack([y[p - 1 - k : y.size - 1 - k] for k in range(p)])
        scale = float(np.mean(lagged * lagged)) or 1.0
        # a little ridge keeps a noise-free ramp (a singular design) from blowing up
        ar = np.linalg.solve(
            lagged.T @ lagged + 1e-6 * len(lagged) * scale * np.eye(p), lagged.T @ y[p:]
        )
        y = _ar_filter(y, ar)
        A = np.column_stack([_ar_filter(a, ar) for a in A[:, :-1].T] + [np.ones(y.size)])
        if np.ptp(y) == 0:
            return np.nan
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ coef
    sst = float(np.sum((y - y.mean()) ** 2))
    k, dof = A.shape[1] - 1, y.size - A.shape[1]
    r2 = 1.0 - float(r @ r) / sst
    f = (r2 / k) / max(1.0 - r2, 1e-300) * dof
    log_p = stats.f.logsf(f, k, dof)
    return float(stats.norm.isf(np.exp(max(log_p, -700.0))))


def _share(held, where):
    return float(np.mean(held[where])) if where.any() else 0.0


def domain_statistics(loops, status=None):
    """Per-loop statistics of the domain rules: ``pv_op_coupling`` (plain and
    ``_white``: prewhitened) and ``frozen_share``.

    ``frozen_share`` is the share of sample steps in which PV and OP both stay
    exactly the same (a historian holding its last value); NaN for loops that
    :func:`~sktiction._validation.loop_status` (with ``require_op=True``; pass it as
    ``status`` when known) rejects. All three are unchanged when a channel is shifted
    or scaled. Where one channel is held on more than a tenth of the steps in which the
    other moves (an export stepped tag by tag: deadband or swinging-door compression,
    or a quantised channel; a historian holding whole rows holds both at once), each coupling
    is the larger of the record's and that of the lines through each channel's changes
    (:func:`~sktiction.cycles._signal.lines_through_changes`), these only where their
    prewhitened coupling is at least 3: the steps of one tag rarely fall on those of the
    other, which hides their relation sample by sample.

    Parameters
    ----------
    loops : ndarray of shape (n_loops, n_samples, 3)
        Checked loops (channels PV, OP, SP), NaN-padded at the end.
    status : ndarray of str or None, default=None
        Their :func:`~sktiction._validation.loop_status` with ``require_op=True``;
        ``None`` computes it.

    Returns
    -------
    statistics : ndarray of shape (n_loops, 3)
        Columns in the order of ``DOMAIN_STATISTICS``; the prewhitened coupling is
        computed only where the plain one is below 10 (NaN elsewhere).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.classifiers import domain_statistics
    >>> from sktiction.datasets import make_loops
    >>> X, _ = make_loops(2, n_samples=600, random_state=0)
    >>> X[1, :, 1] = np.random.default_rng(0).permutation(X[1, :, 1])  # OP of no loop
    >>> z = domain_statistics(X)[:, 0]
    >>> bool(z[0] > 10), bool(z[1] < 3)
    (True, True)
    """
    out = np.full((len(loops), len(DOMAIN_STATISTICS)), np.nan)
    if status is None:
        status = loop_status(loops, require_op=True)
    for i, n in enumerate(loop_lengths(loops)):
        if status[i] != STATUS_OK:
            continue
        pv, op = loops[i, :n, PV], loops[i, :n, OP]
        sp = loops[i, :n, SP]
        pv_held, op_held = np.diff(pv) == 0, np.diff(op) == 0
        out[i, 0] = pv_op_coupling(pv, op, sp)
        if out[i, 0] < _WEAK_COUPLING:  # only needed there
            out[i, 1] = pv_op_coupling(pv, op, sp, prewhiten=_PREWHITEN_ORDER)
        if max(_share(op_held, ~pv_held), _share(pv_held, ~op_held)) > _HELD_APART:
            # an export stepped tag by tag moves PV and OP at times of their own: the
            # lines through their changes relate them as the loop did. Their increments
            # are smooth, which makes the plain test generous: they count only prewhitened
            lines = lines_through_changes(pv), lines_through_changes(op)
            white = pv_op_coupling(*lines, sp, prewhiten=_PREWHITEN_ORDER)
            if white >= _MIN_WHITE:
                out[i, 0] = np.fmax(out[i, 0], pv_op_coupling(*lines, sp))
                out[i, 1] = np.fmax(out[i, 1], white) if out[i, 0] < _WEAK_COUPLING else np.nan
        out[i, 2] = np.mean(pv_held & op_held)
    return out
