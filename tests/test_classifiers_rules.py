"""The rule classifiers' shared base and the area-ratio rule on loops whose answer is known.

Fast unit tests (signals built here, no simulation): the rule ``R > 1 + d`` of Singhal and
Salsbury on control errors of known area ratio, the verdict and reason of loops without a
usable R, and what :class:`LoopClassifierMixin` promises every subclass (labels, input
checks, bad loops forced to 0 with their status).
"""

import warnings

import numpy as np
import pandas as pd
import pytest
from sklearn.base import BaseEstimator, ClassifierMixin, clone
from sklearn.exceptions import DataConversionWarning
from sklearn.utils import get_tags

from sktiction import AreaRatio, AreaRatioClassifier
from sktiction.classifiers._base import LoopClassifierMixin


def asymmetric_loop(peak_at, period=200, n_cycles=12):
    """Control error of triangular half-cycles peaking at ``peak_at`` of each half: the
    area before each peak over the area after it is ``R = peak_at / (1 - peak_at)``."""
    h = period // 2
    half = np.interp(np.arange(h), [0, peak_at * h, h], [0, 1, 0])
    e = np.tile(np.concatenate([half, -half]), n_cycles)
    op = 50 + 0.05 * np.cumsum(e)  # integral action
    return np.stack([10 - e, op, np.full(e.size, 10.0)], axis=-1)


def quiet_loop(n=2400, seed=0):
    """A loop at rest: measurement noise only, no oscillation."""
    rng = np.random.default_rng(seed)
    return np.stack(
        [10 + 0.01 * rng.normal(size=n), 50 + 0.01 * rng.normal(size=n), np.full(n, 10.0)], -1
    )


# peak position -> R = p / (1 - p): 3, 1, 1.70, 1/3
PEAKS = [0.75, 0.5, 0.63, 0.25]


@pytest.fixture(scope="module")
def known():
    X = np.stack([asymmetric_loop(p) for p in PEAKS] + [quiet_loop()])
    r = np.array([p / (1 - p) for p in PEAKS] + [np.nan])
    return X, r


def test_area_ratio_rule_on_known_ratios(known):
    X, r = known
    report = AreaRatioClassifier().fit(X).diagnose(X)
    assert list(report.columns[:5]) == [
        "prediction", "score", "reason", "area_ratio", "n_half_cycles"
    ]  # fmt: skip
    np.testing.assert_allclose(report["area_ratio"][:4], r[:4], rtol=0.02)
    # the paper's default margin d = 0.5: R = 3 and R = 1.7 are sticky, 1 and 1/3 are not
    assert report["prediction"].tolist() == [1, 0, 1, 0, 0]
    assert report["prediction"].dtype.kind == "i"  # labels, as predict gives them
    np.testing.assert_allclose(report["score"][:4], report["area_ratio"][:4] - 1.5)
    assert report["reason"].tolist() == ["ok"] * 4 + ["not_oscillating"]
    assert report["n_half_cycles"][:4].tolist() == [24.0] * 4  # 12 cycles, both halves
    # no R: scored as if R were 0, with no ratio and no half-cycles to show
    assert report.loc[4, "score"] == -1.5
    assert np.isnan(report.loc[4, "area_ratio"]) and np.isnan(report.loc[4, "n_half_cycles"])
    assert AreaRatioClassifier().fit(X).predict(X).dtype.kind == "i"


def test_margin_moves_the_verdict_and_the_rule_is_strict(known):
    X, _ = known
    strict = AreaRatioClassifier(threshold=1.0).fit(X)
    assert strict.predict(X).tolist() == [1, 0, 0, 0, 0]  # R = 1.7 < 1 + 1
    np.testing.assert_array_equal(strict.decision_function(X)[4], -2.0)
    # d exactly R - 1 puts R on the boundary: R > 1 + d is false there
    r = AreaRatioClassifier().fit(X).diagnose(X)["area_ratio"].to_numpy()
    edge = AreaRatioClassifier(threshold=r[2] - 1.0).fit(X)
    assert edge.decision_function(X[2:3])[0] == 0.0
    assert edge.predict(X[2:3])[0] == 0
    # d = 0 is allowed (R > 1): R = 1/3 stays below, R = 1.7 above
    assert AreaRatioClassifier(threshold=0).fit(X).predict(X[[3, 2]]).tolist() == [0, 1]


@pytest.mark.parametrize("threshold", [-0.1, np.nan, np.inf])
def test_margin_must_be_finite_and_not_negative(known, threshold):
    X, _ = known
    with pytest.raises(ValueError, match="threshold must be a finite number >= 0"):
        AreaRatioClassifier(threshold=threshold).fit(X)


def test_the_given_area_ratio_transformer_is_used(known):
    X, _ = known
    # 12 cycles are too few for a transformer that asks for 20: nothing oscillates
    own = AreaRatio(min_cycles=20)
    clf = AreaRatioClassifier(area_ratio=own).fit(X)
    assert clf.get_params()["area_ratio"] is own
    assert clf.area_ratio_ is not own and clf.area_ratio_.get_params() == own.get_params()
    assert clf.diagnose(X)["reason"].eq("not_oscillating").all()
    assert clone(clf).get_params()["area_ratio__min_cycles"] == 20


def test_bad_loops_get_their_status_and_no_ratio(known):
    X, _ = known
    bad = X[:3].copy()
    bad[0, 500:540] = np.nan  # a gap in a sticky loop (R = 3): bridged, as a scan does
    bad[1, :, 0] = 4.0  # constant PV
    bad[2, 15:] = np.nan  # too short
    report = AreaRatioClassifier().fit(X).diagnose(bad)
    assert report["reason"].tolist() == ["ok", "constant", "too_short"]
    assert report["prediction"].tolist() == [1, 0, 0]
    assert report.loc[0, "area_ratio"] == pytest.approx(3.0, rel=0.1)
    assert report.loc[1:, "area_ratio"].isna().all() and report.loc[1:, "score"].eq(-1.5).all()


# ---- what the base class promises every subclass ----------------------------------------


class AlwaysSticky(LoopClassifierMixin, ClassifierMixin, BaseEstimator):
    """A rule that calls every loop sticky (as floats): the base class must still
    give bad loops 0 and their status, and integer labels."""

    _require_op = True

    def _score_loops(self, loops, analyses=None, status=None):
        n = len(loops)
        return pd.DataFrame({"prediction": np.ones(n), "score": np.ones(n), "reason": ["ok"] * n})


def test_bad_loops_are_zero_whatever_the_subclass_says(known):
    X, _ = known
    bad = X[:4].copy()
    bad[1, :, 1] = np.nan  # no OP, which this rule requires
    bad[2, 15:] = np.nan  # too short
    clf = AlwaysSticky().fit(X)
    report = clf.diagnose(bad)
    assert report["prediction"].tolist() == [1, 0, 0, 1]
    assert report["reason"].tolist() == ["ok", "missing_op", "too_short", "ok"]
    with pytest.warns(UserWarning, match=r"missing_op: 1, too_short: 1\); predict gives"):
        pred = clf.predict(bad)
    assert pred.dtype.kind == "i" and pred.tolist() == [1, 0, 0, 1]


def test_fit_checks_labels_and_records_the_input(known):
    X, _ = known
    y = np.array([1, 0, 1, 0, 0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        AreaRatioClassifier().fit(X, y)
    with pytest.warns(DataConversionWarning):
        AreaRatioClassifier().fit(X, y.reshape(-1, 1))
    with pytest.raises(ValueError, match="Unknown label type"):
        AreaRatioClassifier().fit(X, np.linspace(0, 1, 5))
    clf = AreaRatioClassifier().fit(X[:, :, :2])
    assert clf.n_channels_in_ == 2 and list(clf.classes_) == [0, 1]
    assert not hasattr(clf, "n_features_in_")  # 3-D loops may have any length
    assert AreaRatioClassifier().fit(X).n_channels_in_ == 3


def test_two_dimensional_input_is_pv_records_of_a_fixed_length(known):
    X, _ = known
    pv = X[:, :, 0]
    clf = AreaRatioClassifier().fit(pv)
    assert clf.n_channels_in_ == 1 and clf.n_features_in_ == pv.shape[1]
    # SP is constant in these loops: PV alone gives the same verdicts as the whole loop
    assert clf.predict(pv).tolist() == [1, 0, 1, 0, 0]
    with pytest.raises(ValueError, match="features"):
        clf.predict(pv[:, :-10])
    # a refit on another length resets what was recorded
    assert AreaRatioClassifier().fit(pv[:, :-10]).n_features_in_ == pv.shape[1] - 10


def test_tags_say_loops_may_be_padded_and_labels_are_optional():
    tags = get_tags(AreaRatioClassifier())
    assert tags.input_tags.allow_nan is True
    assert tags.input_tags.three_d_array is True
    assert tags.target_tags.required is False
