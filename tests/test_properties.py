"""Invariants a user relies on, as property-based tests (hypothesis).

A verdict must not change with the units of a loop (scale and offset of PV and SP
together, of OP on its own), with the order of the loops in a batch, with NaN padding
at the end, or with the batch (chunk, subset, number of workers) a loop is scanned in.
Examples are few and loops short so the file stays fast; the draws are derandomised so
a failure is reproducible.
"""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sktiction import AreaRatioClassifier, ShapeLibraryClassifier, pretrained_classifier
from sktiction.datasets import make_loops
from sktiction.reports import scan_loops

N_LOOPS, N_SAMPLES = 6, 1000
FEW = settings(
    max_examples=8,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
RULES = {"area_ratio": AreaRatioClassifier, "shape_library": ShapeLibraryClassifier}
SCAN_VERDICTS = ["status", "verdict", "area_ratio_stiction", "shape_stiction", "reason"]


@pytest.fixture(scope="module")
def loops():
    X, y = make_loops(N_LOOPS, N_SAMPLES, random_state=11, world="classic")
    return X


@pytest.fixture(scope="module")
def learned():
    # the small model test_reports.py uses: built once, then read from the user cache
    return pretrained_classifier(n_loops=80, n_samples=1000)


def _verdicts(name, X):
    report = RULES[name]().fit(X).diagnose(X)
    return report["prediction"].to_numpy(), report["score"].to_numpy(dtype=float)


def _scan(X, learned, **kwargs):
    return scan_loops(X, classifier=learned, **kwargs)


def _assert_same_scan(a, b):
    pd.testing.assert_frame_equal(
        a[SCAN_VERDICTS].reset_index(drop=True), b[SCAN_VERDICTS].reset_index(drop=True)
    )
    assert np.allclose(a["stiction_probability"], b["stiction_probability"], rtol=1e-6,
                       atol=1e-9, equal_nan=True)  # fmt: skip


def _rescale(X, pv_scale, pv_offset, op_scale, op_offset):
    Z = X.copy()
    Z[:, :, [0, 2]] = pv_scale * Z[:, :, [0, 2]] + pv_offset  # PV and SP share units
    Z[:, :, 1] = op_scale * Z[:, :, 1] + op_offset
    return Z


scales = st.floats(1e-3, 1e3).filter(lambda s: abs(np.log10(s)) > 0.05)
offsets = st.floats(-1e4, 1e4)


@pytest.mark.parametrize("name", RULES)
@FEW
@given(pv_scale=scales, pv_offset=offsets, op_scale=scales, op_offset=offsets)
def test_rule_verdicts_do_not_depend_on_units(loops, name, pv_scale, pv_offset, op_scale,
                                              op_offset):  # fmt: skip
    pred, score = _verdicts(name, loops)
    pred2, score2 = _verdicts(name, _rescale(loops, pv_scale, pv_offset, op_scale, op_offset))
    assert np.array_equal(pred, pred2)
    assert np.allclose(score, score2, rtol=1e-6, atol=1e-9, equal_nan=True)


@pytest.mark.parametrize("name", RULES)
@FEW
@given(order=st.permutations(range(N_LOOPS)), pad=st.integers(1, 400))
def test_rule_verdicts_do_not_depend_on_order_or_padding(loops, name, order, pad):
    pred, score = _verdicts(name, loops)
    order = np.array(order)
    pred2, score2 = _verdicts(name, loops[order])
    assert np.array_equal(pred2, pred[order]) and np.allclose(score2, score[order], equal_nan=True)
    padded = np.concatenate([loops, np.full((N_LOOPS, pad, 3), np.nan)], axis=1)
    pred3, score3 = _verdicts(name, padded)
    assert np.array_equal(pred3, pred) and np.allclose(score3, score, equal_nan=True)


@settings(FEW, max_examples=3)
@given(pv_scale=scales, pv_offset=offsets, op_scale=scales, op_offset=offsets)
def test_scan_verdicts_do_not_depend_on_units(loops, learned, pv_scale, pv_offset, op_scale,
                                              op_offset):  # fmt: skip
    base = _scan(loops, learned)
    _assert_same_scan(base, _scan(_rescale(loops, pv_scale, pv_offset, op_scale, op_offset),
                                  learned))  # fmt: skip


@settings(FEW, max_examples=3)
@given(order=st.permutations(range(N_LOOPS)), chunk=st.integers(1, N_LOOPS),
       pad=st.integers(1, 300))  # fmt: skip
def test_scan_does_not_depend_on_order_chunks_or_padding(loops, learned, order, chunk, pad):
    base = _scan(loops, learned)
    order = np.array(order)
    _assert_same_scan(_scan(loops[order], learned, chunk_size=chunk), base.iloc[order])
    padded = np.concatenate([loops, np.full((N_LOOPS, pad, 3), np.nan)], axis=1)
    _assert_same_scan(_scan(padded, learned, chunk_size=chunk), base)
    # a subset scanned alone gets the verdicts it gets in the whole batch
    sub = np.sort(order[:3])
    _assert_same_scan(_scan(loops[sub], learned), base.iloc[sub])


def test_scan_with_two_workers_equals_one(loops, learned):
    one = _scan(loops, learned, chunk_size=2, n_jobs=1)
    two = _scan(loops, learned, chunk_size=2, n_jobs=2)
    _assert_same_scan(one, two)
    pd.testing.assert_frame_equal(one, two)


def test_scan_gives_no_verdict_on_a_constant_op(loops, learned):
    X = loops.copy()
    X[1, :, 1] = 55.0
    report = _scan(X, learned)
    assert report.loc[1, "verdict"] == "no_verdict"
    assert "constant" in report.loc[1, "reason"]
    others = [0, 2, 3, 4, 5]
    _assert_same_scan(report.iloc[others], _scan(loops, learned).iloc[others])
