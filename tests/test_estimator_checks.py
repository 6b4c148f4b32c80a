"""Package-specific estimator checks, fed with the loops the estimators are for.

scikit-learn's generic checks (``test_common.py``) feed 2-D random data, on which
most of these estimators can only refuse or return NaN. Here every transformer, both
rule classifiers and the learned classifier get 3-D loops from ``make_loops`` (as
imbalanced-learn feeds its samplers its own data) and must keep the promises a user
relies on: shapes and feature names, pandas output, clone and parameters, the same
answer twice, an untouched input, loops of unequal length padded with NaN, and a
per-loop verdict that does not depend on the other loops of the batch.
"""

import inspect
import pickle

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone, is_classifier

import sktiction.features as features
from sktiction import (
    AreaRatio,
    AreaRatioClassifier,
    LoopDescriptors,
    ShapeLibraryClassifier,
    StictionModelFit,
    TemplateDistances,
    make_learned_classifier,
)
from sktiction.datasets import make_loops

# the clean world of sktiction 0.1, which these checks were written for
CLASSIC = {"world": "classic"}

# one table of what is checked, as imbalanced-learn's instance generator
TRANSFORMERS = [
    AreaRatio(),
    TemplateDistances(),
    TemplateDistances(signals=("pv",)),
    LoopDescriptors(),
    StictionModelFit(),
    # transformers other helpers add are checked as soon as they are exported
    *[getattr(features, name)() for name in ("PVOPHysteresis", "OscillationFeatures")
      if hasattr(features, name)],
]  # fmt: skip
NEEDS_OP = (TemplateDistances, StictionModelFit)  # refuse or give NaN without OP
RULES = [AreaRatioClassifier(), ShapeLibraryClassifier()]


def _learned():
    return make_learned_classifier(random_state=0, max_iter=30)


def _id(est):
    return repr(est).replace("\n", "").replace(" ", "")


@pytest.fixture(scope="module")
def loops():
    X, y = make_loops(10, 1200, random_state=0, **CLASSIC)
    return X, y


@pytest.fixture(scope="module")
def learned():
    X, y = make_loops(40, 1000, random_state=1, **CLASSIC)
    return _learned().fit(X, y)


def _padded(X, k, n):
    """X with loop ``k`` cut to ``n`` samples and NaN-padded back to full length."""
    Xp = X.copy()
    Xp[k, n:] = np.nan
    return Xp


def _scores(clf, X):
    """Prediction and score (stiction probability where there is one) per loop."""
    report = clf.diagnose(X)
    score = clf.predict_proba(X)[:, 1] if hasattr(clf, "predict_proba") else report["score"]
    return np.column_stack([report["prediction"].to_numpy(dtype=float), score])


def _same(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and np.allclose(a, b, rtol=1e-9, atol=1e-12, equal_nan=True)


@pytest.mark.parametrize("est", TRANSFORMERS, ids=_id)
def test_transformer_on_loops(est, loops):
    X, y = loops
    X0 = X.copy()
    est = clone(est)
    assert est.fit(X, y) is est
    Z = est.transform(X)
    names = est.get_feature_names_out()
    assert Z.shape == (len(X), len(names)) and Z.dtype.kind == "f"
    assert len(set(names)) == len(names) and all(isinstance(n, str) for n in names)
    assert np.array_equal(X, X0), "the input was modified"
    # the loops oscillate (half are sticky): most features exist for most loops
    assert np.isfinite(Z).mean() > 0.5
    assert _same(clone(est).fit_transform(X), Z), "two fits give different features"

    frame = clone(est).set_output(transform="pandas").fit_transform(X)
    assert isinstance(frame, pd.DataFrame) and list(frame.columns) == list(names)
    assert _same(frame.to_numpy(), Z)

    # features of a loop do not depend on the other loops of the batch
    idx = [7, 2, 5]
    assert _same(clone(est).fit_transform(X[idx]), Z[idx])
    # a loop NaN-padded at the end reads as the shorter loop
    Zp = clone(est).fit_transform(_padded(X, 3, 800))
    assert _same(Zp[3], clone(est).fit_transform(X[3:4, :800])[0])
    assert _same(np.delete(Zp, 3, axis=0), np.delete(Z, 3, axis=0))
    # pickled and restored, it gives the same features
    assert _same(pickle.loads(pickle.dumps(est)).transform(X), Z)


@pytest.mark.parametrize("est", [*TRANSFORMERS, *RULES, _learned()], ids=_id)
def test_clone_and_params_round_trip(est):
    params = est.get_params(deep=False)
    twin = clone(est)
    assert repr(twin) == repr(est)
    assert twin.set_params(**params) is twin and repr(twin) == repr(est)
    assert sorted(params) == sorted(inspect.signature(type(est)).parameters)
    # __init__ only stores: no fitted attribute before fit
    assert not [a for a in vars(twin) if a.endswith("_") and not a.startswith("_")]


@pytest.mark.parametrize("est", TRANSFORMERS, ids=_id)
def test_bad_loops_give_a_row_and_leave_the_others_alone(est, loops):
    X, _ = loops
    bad = X[:4].copy()
    bad[0, 300:340] = np.nan  # gap inside the record
    bad[1, :, 0] = 50.0  # constant PV
    bad[2, 10:] = np.nan  # too short
    Xb = np.concatenate([bad[:3], X[3:6]])
    fitted = clone(est).fit(Xb)
    Z = fitted.transform(Xb)
    assert Z.shape[0] == 6
    assert _same(Z[3:], clone(est).fit_transform(X[3:6]))
    names = list(fitted.get_feature_names_out())
    if "oscillating" in names:
        assert (Z[:3, names.index("oscillating")] == 0).all()


@pytest.mark.parametrize("est", [t for t in TRANSFORMERS if isinstance(t, NEEDS_OP)
                                 and "op" in getattr(t, "signals", ("op",))], ids=_id)  # fmt: skip
def test_transformers_that_read_op_say_nothing_on_a_constant_op(est, loops):
    X, _ = loops
    Xc = X.copy()
    Xc[:, :, 1] = 37.0
    fitted = clone(est).fit(Xc)
    Z = fitted.transform(Xc)
    names = list(fitted.get_feature_names_out())
    cols = [i for i, n in enumerate(names) if n != "oscillating"]
    assert np.isnan(Z[:, cols]).all()


@pytest.mark.parametrize("clf", [*RULES, "learned"], ids=_id)
def test_classifier_on_loops(clf, loops, learned):
    X, y = loops
    X0 = X.copy()
    clf = learned if clf == "learned" else clone(clf).fit(X, y)
    assert is_classifier(clf) and list(clf.classes_) == [0, 1]
    pred = clf.predict(X)
    assert pred.shape == (len(X),) and set(np.unique(pred)) <= {0, 1}
    assert np.array_equal(X, X0), "the input was modified"
    report = clf.diagnose(X)
    assert len(report) == len(X) and "reason" in report
    assert np.array_equal(report["prediction"].to_numpy(dtype=int), pred)
    if hasattr(clf, "predict_proba"):
        proba = clf.predict_proba(X)
        assert proba.shape == (len(X), 2)
        ok = np.isfinite(proba).all(axis=1)  # the learned model may abstain with NaN
        assert ok.mean() >= 0.5 and np.allclose(proba[ok].sum(axis=1), 1.0)
        # a loop predicted sticky has more stiction probability than one predicted not
        if pred.any() and (pred[ok] == 0).any():
            assert proba[pred == 1, 1].min() >= proba[ok & (pred == 0), 1].max()

    # per loop: the other loops of the batch and NaN padding change nothing
    def out(Z):
        return _scores(clf, Z)

    idx = [7, 2, 5]
    assert _same(out(X[idx]), out(X)[idx])
    Xp = _padded(X, 4, 900)
    assert _same(out(Xp)[4], out(X[4:5, :900])[0])
    assert _same(_scores(pickle.loads(pickle.dumps(clf)), X), out(X))


def test_learned_classifier_is_reproducible(learned, loops):
    X, y = make_loops(40, 1000, random_state=1, **CLASSIC)
    again = _learned().fit(X, y)
    Xt, _ = loops
    assert _same(_scores(again, Xt), _scores(learned, Xt))


@pytest.mark.parametrize("clf", [ShapeLibraryClassifier(), "learned"], ids=_id)
def test_a_constant_op_gives_no_verdict(clf, loops, learned):
    """Both need OP: a stuck OP record (constant) cannot say anything about the valve."""
    X, _ = loops
    Xc = X.copy()
    Xc[2, :, 1] = 42.0
    Xc[5, :, 1] = 0.0
    clf = learned if clf == "learned" else clone(clf).fit(X)
    report = clf.diagnose(Xc)
    assert (report.loc[[2, 5], "prediction"] == 0).all()
    assert report.loc[[2, 5], "reason"].str.contains("constant").all(), report["reason"]
    others = [0, 1, 3, 4, 6, 7, 8, 9]
    assert _same(_scores(clf, Xc)[others], _scores(clf, X)[others])
