"""What the transformers share: one analysis per loop, and their output plumbing.

Every feature of a loop starts from the same few things: its signals and their cycle
analyses. :class:`LoopAnalysis` computes each of them on first use and keeps it, so a
scan that feeds the area-ratio rule, the shape library and the learned model analyses
each signal once, as :func:`scipy.signal.peak_widths` accepts the ``prominence_data``
that :func:`scipy.signal.peak_prominences` already computed.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from .._validation import OP, PV, SP, loop_lengths, loop_status, validate_loops
from ..cycles import dominant_period
from ..cycles._analysis import _analyze_cycles

_CHANNEL = {"pv": PV, "op": OP}


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


class LoopAnalysis:
    """One loop's signals and cycle analyses, each computed on first use and kept.

    Transformers and classifiers ask it for what they need; whatever another one
    already asked for is not computed again, so the features of one loop agree
    with each other (the shape library's cycles are the template features' cycles).

    Parameters
    ----------
    loops : ndarray of shape (n_loops, n_samples, 3)
        Checked loops (:func:`~sktiction._validation.check_loops`).
    i : int
        Loop index.
    n : int
        Its length before the NaN padding.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.features._loops import LoopAnalysis
    >>> t = np.arange(1000.0)
    >>> pv = np.sign(np.sin(2 * np.pi * t / 100))
    >>> a = LoopAnalysis(np.stack([pv, pv, 0 * pv], axis=1)[None], 0, 1000)
    >>> a.cycles("error") is a.cycles("error")  # analysed once
    True
    """

    __slots__ = ("loops", "i", "n", "_memo")

    def __init__(self, loops, i, n):
        self.loops = loops
        self.i = int(i)
        self.n = int(n)
        self._memo = {}

    def memo(self, key, compute):
        """``compute()`` the first time ``key`` is asked for; the kept value after."""
        try:
            return self._memo[key]
        except KeyError:
            value = self._memo[key] = compute()
            return value

    def signal(self, name):
        """``"pv"``, ``"op"`` or ``"error"`` (see :func:`control_error`), without padding."""
        if name == "error":
            return self.memo("error", lambda: control_error(self.loops, self.i, self.n))
        return self.loops[self.i, : self.n, _CHANNEL[name]]

    def dominant_period(self, name):
        """:func:`~sktiction.cycles.dominant_period` of signal ``name`` (the cycle
        analysis of a record with historian repeats and the PV-OP features both read it)."""
        return self.memo(("dominant_period", name), lambda: dominant_period(self.signal(name)))

    def cycles(self, name, min_cycles=3):
        """:func:`~sktiction.cycles.analyze_cycles` of signal ``name``."""
        return self.memo(
            ("cycles", name, int(min_cycles)),
            lambda: _analyze_cycles(
                self.signal(name),
                min_cycles=int(min_cycles),
                dominant=lambda: self.dominant_period(name),
            ),
        )


def analyse_loops(loops):
    """One :class:`LoopAnalysis` per loop of checked ``loops``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._validation import check_loops
    >>> from sktiction.features._loops import analyse_loops
    >>> [a.n for a in analyse_loops(check_loops(np.ones((2, 30))))]
    [30, 30]
    """
    return [LoopAnalysis(loops, i, n) for i, n in enumerate(loop_lengths(loops))]


class LoopTransformer(TransformerMixin, BaseEstimator):
    """Base of the per-loop transformers: stateless ``fit``, NaN rows for bad loops.

    Subclasses define ``feature_names`` (a tuple; an ``oscillating`` column is 0
    for loops that cannot be analysed), ``_needs_op`` and either
    ``_transform_analysis(analysis)`` (from the shared :class:`LoopAnalysis`) or
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
        return self.transform_analysed(loops, analyse_loops(loops))

    def transform_analysed(self, loops, analyses, status=None):
        """:meth:`transform` of checked loops whose analyses may already be done.

        Parameters
        ----------
        loops : ndarray of shape (n_loops, n_samples, 3)
            Checked loops (:func:`~sktiction._validation.check_loops`).
        analyses : list of LoopAnalysis
            One per loop (:func:`analyse_loops`), shared with other users.
        status : ndarray of str or None, default=None
            :func:`~sktiction._validation.loop_status` with this transformer's
            ``require_op``, if already known.

        Returns
        -------
        features : ndarray of shape (n_loops, n_features)
        """
        out = np.full((len(loops), len(self.feature_names)), np.nan)
        if "oscillating" in self.feature_names:
            out[:, self.feature_names.index("oscillating")] = 0.0
        if status is None:
            status = loop_status(loops, require_op=self._needs_op)
        for i, analysis in enumerate(analyses):
            if status[i] == "ok":
                out[i] = self._transform_analysis(analysis)
        return out

    def _transform_analysis(self, analysis):
        """One row from the loop's shared analysis; by default from the raw loop."""
        return self._transform_loop(analysis.loops, analysis.i, analysis.n)

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

