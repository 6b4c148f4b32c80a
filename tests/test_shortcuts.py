"""Shortcut audit: in the default world the cause must not be readable from nuisance.

A classifier that sees only statistics of things that are not stiction (setpoint moves,
the start-up transient, noise level, record length, operating point) must not predict
the label: if it could, a model trained on ``make_loops`` could learn those instead of
stiction (issue 7 found a setpoint step at the start of every aggressive loop, whose OP
kick the learned model read). Statistics come from X only, never from meta.
"""

import numpy as np
import pytest
from sklearn.ensemble import HistGradientBoostingClassifier
from sklearn.model_selection import StratifiedKFold, cross_val_score
from threadpoolctl import threadpool_limits

from sktiction.datasets import make_loops

NUISANCE = (
    "sp_move_share", "sp_n_moves", "sp_largest_move", "sp_range",
    "start_error_sd_ratio", "start_error_shift", "start_op_shift", "start_op_sd_ratio",
    "pv_noise", "op_noise", "record_length", "op_level", "pv_level",
)  # fmt: skip


def _cv_balanced_accuracy(Z, y):
    clf = HistGradientBoostingClassifier(max_iter=100, learning_rate=0.1, random_state=0)
    cv = StratifiedKFold(5, shuffle=True, random_state=0)
    # one OpenMP thread: on a busy machine more threads only wait for each other
    with threadpool_limits(1):
        return cross_val_score(clf, Z, y, cv=cv, scoring="balanced_accuracy").mean()


def _robust_noise(x):
    """Noise sd from second differences (slow signal removed), robust to slips."""
    d2 = np.diff(x, 2)
    return 1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6.0)


def nuisance_statistics(X):
    """One row of nuisance statistics per loop, computed from PV, OP and SP."""
    rows = []
    for loop in X:
        n = int(np.isfinite(loop).all(axis=1).sum())
        pv, op, sp = loop[:n, 0], loop[:n, 1], loop[:n, 2]
        e = sp - pv
        pv_span = np.ptp(np.percentile(pv, [5, 95])) + 1e-12
        op_span = np.ptp(np.percentile(op, [5, 95])) + 1e-12
        dsp = np.abs(np.diff(sp))
        k = max(n // 10, 5)
        rows.append(
            [
                np.mean(dsp > 0),
                np.log1p(np.sum(dsp > 0)),
                dsp.max() / pv_span,
                np.ptp(sp) / pv_span,
                np.log((e[:k].std() + 1e-12) / (e[k:].std() + 1e-12)),
                abs(e[:k].mean() - e[k:].mean()) / (e.std() + 1e-12),
                abs(op[:k].mean() - op[k:].mean()) / op_span,
                np.log((op[:k].std() + 1e-12) / (op[k:].std() + 1e-12)),
                _robust_noise(pv) / pv_span,
                _robust_noise(op) / op_span,
                n,
                op.mean(),
                np.log10(abs(pv.mean()) + 1e-12),
            ]
        )
    return np.array(rows)


@pytest.fixture(scope="module")
def audit_data():
    X, y = make_loops(600, 800, random_state=11)
    return nuisance_statistics(X), y


def test_nuisance_does_not_predict_the_cause(audit_data):
    Z, y = audit_data
    assert Z.shape == (600, len(NUISANCE)) and np.isfinite(Z).all()
    score = _cv_balanced_accuracy(Z, y)
    assert score <= 0.60, score


def test_the_audit_catches_a_planted_shortcut(audit_data):
    # the same audit on the classic world, where a setpoint step starts every sticky and
    # every aggressive loop, must see through it: otherwise it could not fail
    X, y = make_loops(600, 800, world="classic", random_state=11)
    Z = nuisance_statistics(X)
    score = _cv_balanced_accuracy(Z, y)
    assert score > 0.70, score
