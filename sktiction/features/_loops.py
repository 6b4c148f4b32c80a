"""What the transformers share: the per-loop signals they analyse and their output plumbing."""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from .._validation import OP, PV, SP, loop_lengths, loop_status, validate_loops


def control_error(loops, i, n):
    """SP - PV of loop ``i`` (first ``n`` samples); -PV when there is no setpoint.

    Without SP the PV is used about its adaptive mean (the analysis removes it).
    """
    pv = loops[i, :n, PV]
    sp = loops[i, :n, SP]
    return sp - pv if not np.isnan(sp).any() else -pv


def has_channel(loops, c):
    """Whether any loop carries channel ``c`` at all."""
    return bool((~np.isnan(loops[:, :, c])).any())


class LoopTransformer(TransformerMixin, BaseEstimator):
    """Base of the per-loop transformers: stateless ``fit``, NaN rows for bad loops.

    Subclasses define ``feature_names`` (a tuple; an ``oscillating`` column is 0
    for loops that cannot be analysed), ``_needs_op`` and
    ``_transform_loop(loops, i, n)`` returning one row.
    """

    feature_names = ()
    _needs_op = False

    def _validate_params(self):
        return None

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True  # NaN pads loops of unequal length
        tags.input_tags.three_d_array = True
        return tags

    def fit(self, X, y=None):
        """Check parameters and input; nothing is learned from the data.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP, NaN-padded at the end.
        y : ignored
            Present for pipeline compatibility.

        Returns
        -------
        self : object
            The fitted transformer.
        """
        self._validate_params()
        loops = validate_loops(self, X, reset=True)
        self._check_channels(loops)
        self.n_channels_in_ = int(np.shape(X)[2]) if np.ndim(X) == 3 else 1
        return self

    def _check_channels(self, loops):
        if self._needs_op and not has_channel(loops, OP):
            raise ValueError(
                f"{type(self).__name__} needs the OP channel (X[:, :, 1]), but X has no OP "
                "values. Pass loops with channels PV, OP, SP, or use signals=('pv',)."
            )

    def transform(self, X):
        """Compute the features of each loop.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP, NaN-padded at the end.

        Returns
        -------
        features : ndarray of shape (n_loops, n_features)
            NaN (and ``oscillating = 0``) for loops that cannot be analysed.
        """
        check_is_fitted(self, "n_channels_in_")
        loops = validate_loops(self, X, reset=False)
        self._check_channels(loops)
        out = np.full((len(loops), len(self.feature_names)), np.nan)
        if "oscillating" in self.feature_names:
            out[:, self.feature_names.index("oscillating")] = 0.0
        status = loop_status(loops, require_op=self._needs_op)
        for i, n in enumerate(loop_lengths(loops)):
            if status[i] == "ok":
                out[i] = self._transform_loop(loops, i, int(n))
        return out

    def get_feature_names_out(self, input_features=None):
        """Names of the output columns.

        Parameters
        ----------
        input_features : ignored
            Present for API compatibility.

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self, "n_channels_in_")
        return np.asarray(self.feature_names, dtype=object)

