"""A classifier learned on simulated loops from all the package's features."""

from __future__ import annotations

import copy
import functools

from sklearn.ensemble import HistGradientBoostingClassifier
from sklearn.pipeline import FeatureUnion, Pipeline

from ..features import AreaRatio, LoopDescriptors, StictionModelFit, TemplateDistances


def make_loop_features(n_jobs=None):
    """All per-loop features side by side: area ratios, template distances, descriptors
    and the fitted valve model.

    Parameters
    ----------
    n_jobs : int or None, default=None
        Passed to :class:`~sklearn.pipeline.FeatureUnion`.

    Returns
    -------
    features : sklearn.pipeline.FeatureUnion
        Transformer from loops ``(n_loops, n_samples, 3)`` to a feature matrix with
        NaN where a feature does not exist (no oscillation, no OP).

    Examples
    --------
    >>> from sktiction.classifiers import make_loop_features
    >>> from sktiction.datasets import make_loops
    >>> X, _ = make_loops(3, n_samples=1000, random_state=0)
    >>> make_loop_features().fit_transform(X).shape[0]
    3
    """
    return FeatureUnion(
        [
            ("area", AreaRatio()),
            ("templates", TemplateDistances()),
            ("descriptors", LoopDescriptors()),
            ("valve_model", StictionModelFit()),
        ],
        n_jobs=n_jobs,
    )


def make_learned_classifier(random_state=None, **model_params):
    """An untrained pipeline: loop features, then gradient-boosted trees.

    Gradient boosting (:class:`~sklearn.ensemble.HistGradientBoostingClassifier`)
    fits here because the features are few, on different scales, and missing where
    a loop does not oscillate: the trees learn from the training loops which way a
    missing value points instead of assuming that no oscillation means no stiction.

    Recipe::

        X, y = make_loops(3000, slip_fraction=0.25, random_state=0)
        clf = make_learned_classifier(random_state=0).fit(X, y)

    Parameters
    ----------
    random_state : int, Generator or None, default=None
        Seed of the booster.
    **model_params
        Overrides for :class:`~sklearn.ensemble.HistGradientBoostingClassifier`.

    Returns
    -------
    pipeline : sklearn.pipeline.Pipeline
        Steps ``features`` and ``model``.

    Examples
    --------
    >>> from sktiction.classifiers import make_learned_classifier
    >>> make_learned_classifier(random_state=0).steps[-1][0]
    'model'
    """
    params = {"max_iter": 300, "learning_rate": 0.08, "l2_regularization": 1.0}
    params.update(model_params)
    model = HistGradientBoostingClassifier(random_state=random_state, **params)
    return Pipeline([("features", make_loop_features()), ("model", model)])


@functools.lru_cache(maxsize=4)
def _train(random_state, n_loops, n_samples):
    from ..datasets import make_loops

    # a quarter of the sticky loops only slip during setpoint moves, so the model does
    # not learn that a window without a cycle is a healthy valve
    X, y = make_loops(
        n_loops, n_samples=n_samples, slip_fraction=0.25, random_state=random_state
    )
    return make_learned_classifier(random_state=random_state).fit(X, y)


def pretrained_classifier(random_state=0, *, n_loops=1500, n_samples=2000):
    """A learned classifier trained on the spot on simulated loops.

    Trains :func:`make_learned_classifier` on
    ``make_loops(n_loops, n_samples, slip_fraction=0.25)`` (a quarter of the sticky
    loops show only slips during setpoint moves, no cycle; well under a minute with
    the defaults); the result is cached per argument set
    within the process, and a copy is returned so callers may change it.

    Parameters
    ----------
    random_state : int, default=0
        Seed of both the simulated loops and the booster.
    n_loops : int, default=1500
        Number of simulated training loops.
    n_samples : int, default=2000
        Samples per simulated loop.

    Returns
    -------
    classifier : sklearn.pipeline.Pipeline
        Fitted; ``predict``, ``predict_proba`` on loops ``(n_loops, n_samples, 3)``.

    Examples
    --------
    >>> from sktiction import pretrained_classifier
    >>> clf = pretrained_classifier(n_loops=60, n_samples=1000)
    >>> clf.classes_.tolist()
    [0, 1]
    """
    return copy.deepcopy(_train(random_state, int(n_loops), int(n_samples)))
