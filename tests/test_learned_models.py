"""The learned classifier's model choice: boosting, logistic regression or their mean."""

import numpy as np
import pytest

from sktiction.classifiers import LearnedStictionClassifier
from sktiction.datasets import make_loops


@pytest.fixture(scope="module")
def loops():
    X, y = make_loops(200, n_samples=1000, world="classic", random_state=3)
    return X[:150], y[:150], X[150:], y[150:]


@pytest.fixture(scope="module")
def fitted(loops):
    """Each model fitted once on the same loops, shared by the tests below."""
    X, y, _, _ = loops
    return {
        model: LearnedStictionClassifier(model=model, max_iter=40, cv=2, random_state=0).fit(X, y)
        for model in ("boosting", "logistic", "ensemble")
    }


def test_ensemble_probability_is_the_mean_of_its_two_models(loops, fitted):
    X_test = loops[2]
    ens, boost, logit = (
        fitted[m].predict_proba(X_test)[:, 1] for m in ("ensemble", "boosting", "logistic")
    )
    judged = np.isfinite(ens)
    assert judged.sum() >= 20
    np.testing.assert_allclose(ens[judged], (boost[judged] + logit[judged]) / 2, atol=1e-12)
    # the two models differ, so the mean is not either of them
    assert np.abs(boost[judged] - logit[judged]).max() > 0.05


@pytest.mark.parametrize("model", ["boosting", "logistic", "ensemble"])
def test_each_model_separates_classic_loops(loops, fitted, model):
    _, _, X_test, y_test = loops
    pred = fitted[model].predict(X_test)
    assert np.mean(pred == y_test) >= 0.8


@pytest.mark.parametrize(("params", "name"), [({"model": "forest"}, "model"), ({"C": 0}, "C")])
def test_bad_model_parameters_are_named(loops, params, name):
    X, y, _, _ = loops
    with pytest.raises(ValueError, match=f"^{name} must"):
        LearnedStictionClassifier(**params).fit(X, y)
