"""scikit-learn's estimator checks on every public estimator and transformer."""

from sklearn.utils.estimator_checks import parametrize_with_checks

from sktiction import (
    AreaRatio,
    AreaRatioClassifier,
    LoopDescriptors,
    ShapeLibraryClassifier,
    TemplateDistances,
)

ESTIMATORS = [
    AreaRatio(),
    TemplateDistances(),
    LoopDescriptors(),
    AreaRatioClassifier(),
    ShapeLibraryClassifier(),
]

EXPECTED_FAILED = {}


def _expected_failed_checks(estimator):
    return EXPECTED_FAILED.get(type(estimator).__name__, {})


@parametrize_with_checks(ESTIMATORS, expected_failed_checks=_expected_failed_checks)
def test_sklearn_compatible(estimator, check):
    check(estimator)
