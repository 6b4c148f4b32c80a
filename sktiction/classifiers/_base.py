"""What the loop classifiers share: input checks, fixed labels and per-loop reasons."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.validation import check_is_fitted, column_or_1d

from .._cleaning import as_judged
from .._validation import (
    STATUS_CONSTANT,
    STATUS_EMPTY,
    STATUS_MISSING_OP,
    STATUS_NAN_GAP,
    STATUS_OK,
    STATUS_SWAPPED,
    STATUS_TOO_SHORT,
    loop_status,
    validate_loops,
)
from ..features._loops import analyse_loops

#: Why a loop got no stiction verdict; ``"ok"`` when it was analysed.
REASON_NOT_OSCILLATING = "not_oscillating"
_NO_VERDICT = "predict gives them the negative class, predict_proba NaN"
#: Reasons that are the input's fault, not a rule's answer ("not oscillating" is the
#: rules' answer "no stiction").
INPUT_PROBLEMS = (
    STATUS_EMPTY, STATUS_TOO_SHORT, STATUS_NAN_GAP, STATUS_CONSTANT, STATUS_MISSING_OP,
    STATUS_SWAPPED,
)


def said_unjudged(report, consequence=_NO_VERDICT, *, problems=None):
    """``report`` (a ``diagnose`` table, or its ``reason`` column), with a warning that
    counts the loops by reason when some were not judged: ``predict`` gives them the
    negative class, ``fit`` leaves them out, which a score or a training set would
    otherwise count or lose without a word. ``problems`` limits the warning to those
    reasons (``None``: every reason but ``ok``)."""
    reason = pd.Series(report["reason"] if isinstance(report, pd.DataFrame) else report)
    reasons = reason[reason.isin(problems) if problems else reason != STATUS_OK]
    if len(reasons):
        counts = ", ".join(f"{r}: {c}" for r, c in reasons.value_counts().items())
        warnings.warn(
            f"{len(reasons)} of {len(reason)} loops cannot be judged ({counts}); "
            f"{consequence}. diagnose(X) says why per loop.",
            UserWarning, stacklevel=3,
        )
    return report


class LoopClassifierMixin:
    """Binary stiction classifier on raw loops ``(n_loops, n_samples, 3)``.

    Labels are fixed: 0 = no stiction (or no verdict possible), 1 = stiction.
    Subclasses implement ``_fit_loops(loops, y)`` (may do nothing) and
    ``_score_loops(loops, analyses=None, status=None)`` returning a DataFrame with at
    least ``score`` (larger means more likely sticky), ``prediction`` and ``reason``;
    ``analyses`` are the loops' shared analyses (computed when ``None``) and
    ``status`` their :func:`~sktiction._validation.loop_status` when known.
    """

    _require_op = False

    def fit(self, X, y=None):
        """Check the loops and labels; rule-based subclasses learn nothing else.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP, NaN-padded at the end.
        y : array-like of shape (n_loops,), default=None
            Labels, only checked for length and type: the rules learn nothing and
            always answer 0 (no stiction) or 1 (stiction).

        Returns
        -------
        self : object
            Fitted classifier.
        """
        loops = validate_loops(self, X, reset=True)
        if y is not None:
            y = column_or_1d(y, warn=True)
            check_classification_targets(y)
            if len(y) != len(loops):
                raise ValueError(
                    f"X has {len(loops)} loops but y has {len(y)} labels; they must match."
                )
        self.classes_ = np.array([0, 1])
        self.n_channels_in_ = int(np.asarray(X).shape[2]) if np.ndim(X) == 3 else 1
        self._fit_loops(loops, y)
        return self

    def _fit_loops(self, loops, y):
        return None

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True  # NaN pads loops of unequal length
        tags.input_tags.three_d_array = True
        tags.target_tags.required = False  # the rules learn nothing from y
        return tags

    def _checked(self, X):
        """Loops as a scan reads them (as_judged): holds, spikes, placeholders and gaps
        repaired, a start-up transient dropped, OP in step with PV."""
        check_is_fitted(self, "classes_")
        return as_judged(validate_loops(self, X, reset=False))

    def diagnose(self, X):
        """Per-loop verdict with the evidence behind it.

        Each loop is read as the learned model and a file scan read it
        (:func:`~sktiction._cleaning.as_judged`): a regular hold read as stored, spikes
        replaced, placeholders read as gaps, short NaN gaps bridged and, past a long one,
        the longest stretch kept; a start-up transient at the start is dropped and an OP
        recorded a row out of step with PV is moved back in line.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        report : pandas.DataFrame
            One row per loop: ``prediction`` (0/1), ``score``, ``reason`` (``ok``, a
            :func:`~sktiction._validation.loop_status` code or ``not_oscillating``)
            and the classifier's own evidence columns.
        """
        loops = self._checked(X)
        return self.diagnose_analysed(loops, analyse_loops(loops))

    def diagnose_analysed(self, loops, analyses, status=None):
        """:meth:`diagnose` of checked loops whose analyses may already be done.

        A scan builds one :class:`~sktiction.features._loops.LoopAnalysis` per loop
        and hands it to every classifier, so each signal is analysed once.

        Parameters
        ----------
        loops : ndarray of shape (n_loops, n_samples, 3)
            Checked loops (:func:`~sktiction._validation.check_loops`).
        analyses : list of LoopAnalysis
            One per loop (:func:`~sktiction.features._loops.analyse_loops`).
        status : ndarray of str or None, default=None
            :func:`~sktiction._validation.loop_status` with this classifier's
            ``require_op`` and ``check_swap=True``, if already known.

        Returns
        -------
        report : pandas.DataFrame
            As :meth:`diagnose`.
        """
        check_is_fitted(self, "classes_")
        if status is None:
            status = loop_status(loops, require_op=self._require_op, check_swap=True)
        report = self._score_loops(loops, analyses, status)
        bad = status != "ok"
        report.loc[bad, "reason"] = status[bad]
        report.loc[bad, "prediction"] = 0
        return report

    def predict(self, X):
        """Predict 1 for stiction, 0 otherwise (including loops with no verdict).

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        y_pred : ndarray of shape (n_loops,)
            Predicted labels.
        """
        report = said_unjudged(self.diagnose(X), "predict gives them 0", problems=INPUT_PROBLEMS)
        return report["prediction"].to_numpy(dtype=int)
