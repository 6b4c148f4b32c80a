"""Singhal and Salsbury's decision rule on the area ratio: stiction when R > 1 + d."""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, ClassifierMixin, clone

from ..features import AreaRatio
from ..features._loops import analyse_loops
from ._base import INPUT_PROBLEMS, REASON_NOT_OSCILLATING, LoopClassifierMixin, said_unjudged


class AreaRatioClassifier(LoopClassifierMixin, ClassifierMixin, BaseEstimator):
    """Stiction when the mean area ratio of the control error exceeds ``1 + threshold``.

    Singhal and Salsbury (2005, section 6) compare R = A1/A2, the areas of the
    control error before and after each peak, with 1: a sticking valve gives a
    rectangular-pulse plant input and R > 1, aggressive tuning a sinusoid and
    R close to 1. They recommend the margin ``d`` (here ``threshold``) between 0.5
    and 1. The rule assumes a self-regulating plant, an OP that does not cycle
    between its limits and no external periodic disturbance; integrating (level)
    loops give R close to 1 even when the valve sticks.

    A loop that does not oscillate, or cannot be analysed (NaN gaps, constant,
    too short), gets prediction 0 and its reason in :meth:`diagnose`: the rule
    has no evidence either way there, and says so rather than guessing.

    Parameters
    ----------
    threshold : float, default=0.5
        The margin ``d`` of the rule ``R > 1 + d``.
    area_ratio : AreaRatio or None, default=None
        The transformer that measures R; ``None`` uses ``AreaRatio()``. Its
        parameters can be grid-searched as ``area_ratio__<name>``.

    Attributes
    ----------
    classes_ : ndarray of shape (2,)
        ``[0, 1]``.
    area_ratio_ : AreaRatio
        The fitted transformer.

    See Also
    --------
    sktiction.AreaRatio : the feature this rule thresholds.
    ShapeLibraryClassifier : the shape-based rule of Srinivasan et al. (2005).

    References
    ----------
    A. Singhal, T. I. Salsbury, "A simple method for detecting valve stiction in
    oscillating control loops", J. Process Control 15 (2005) 371-382.

    Examples
    --------
    >>> from sktiction import AreaRatioClassifier
    >>> from sktiction.datasets import make_loops
    >>> X, y = make_loops(6, n_samples=1500, random_state=0)
    >>> clf = AreaRatioClassifier(threshold=0.5).fit(X, y)
    >>> clf.predict(X).shape
    (6,)
    """

    def __init__(self, threshold=0.5, area_ratio=None):
        self.threshold = threshold
        self.area_ratio = area_ratio

    def _fit_loops(self, loops, y):
        if not np.isfinite(self.threshold) or self.threshold < 0:
            raise ValueError(f"threshold must be a finite number >= 0; got {self.threshold!r}.")
        self.area_ratio_ = clone(self.area_ratio if self.area_ratio is not None else AreaRatio())
        self.area_ratio_.fit(loops)

    def _score_loops(self, loops, analyses=None, status=None):
        if analyses is None:
            analyses = analyse_loops(loops)
        feats = pd.DataFrame(
            self.area_ratio_.transform_analysed(loops, analyses, status),
            columns=self.area_ratio_.get_feature_names_out(),
        )
        r = feats["area_ratio"].to_numpy(dtype=float)
        oscillating = np.nan_to_num(feats["oscillating"].to_numpy(dtype=float)) > 0
        has_r = oscillating & np.isfinite(r)
        score = np.where(has_r, r - 1.0 - self.threshold, -1.0 - self.threshold)
        return pd.DataFrame(
            {
                "prediction": (score > 0).astype(int),
                "score": score,
                "reason": np.where(has_r, "ok", REASON_NOT_OSCILLATING),
                "area_ratio": r,
                "n_half_cycles": feats["n_half_cycles"].to_numpy(),
            }
        )

    def decision_function(self, X):
        """``R - 1 - threshold``; loops without a usable R score as if R were 0.

        Loops with an input problem (see :meth:`diagnose`) score so too, with a warning
        that counts them, as :meth:`predict` says ``0`` for them: ``predict(X)`` is
        always ``decision_function(X) > 0``.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        scores : ndarray of shape (n_loops,)
            Positive means stiction.
        """
        report = said_unjudged(self.diagnose(X), f"they score {-1.0 - self.threshold:g}",
                               problems=INPUT_PROBLEMS)  # fmt: skip
        return report["score"].to_numpy(dtype=float)
