"""Srinivasan, Rengaswamy and Miller's shape library (seed 001, Table 1) as a classifier."""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, ClassifierMixin, clone

from .._validation import OP
from ..features import TemplateDistances
from ..features._loops import analyse_loops
from ._base import INPUT_PROBLEMS, REASON_NOT_OSCILLATING, LoopClassifierMixin, said_unjudged

#: (OP shape, PV shape) pairs that mean stiction, per loop type (seed 001 Table 1).
#: Trapezoidal PV counts for flow loops: the paper's own industrial flow loops (its
#: Table 3, loops 1, 4, 5) were matched as OP triangular, PV trapezoidal and sticky.
#: Parabolic PV (level under PI) has no template; its nearest template is sinusoidal.
SHAPE_LIBRARY = {
    "flow": {
        ("triangular", "rectangular"),
        ("triangular", "trapezoidal"),
        ("rectangular", "rectangular"),  # P-dominant control
    },
    "pressure": {("triangular", "sinusoidal"), ("triangular", "triangular")},
    "temperature": {("triangular", "sinusoidal"), ("triangular", "triangular")},
    "level": {("triangular", "triangular"), ("triangular", "sinusoidal")},
}
LOOP_TYPES = (*SHAPE_LIBRARY, "auto")

# With loop_type="auto" the process is read off the PV shape most cycles share, since the
# rows of Table 1 differ in the PV shape: square-ish PV -> fast (flow), sinusoidal -> slow
# (pressure/temperature), triangular -> integrating (level).
_PV_SHAPE_TO_LOOP = {
    "rectangular": "flow",
    "trapezoidal": "flow",
    "sinusoidal": "pressure",
    "triangular": "level",
}


def _infer_loop_type(pv_shapes):
    shapes = pd.Series(pv_shapes).dropna()
    if shapes.empty:
        return "unknown"
    return _PV_SHAPE_TO_LOOP.get(shapes.mode().iloc[0], "unknown")


class ShapeLibraryClassifier(LoopClassifierMixin, ClassifierMixin, BaseEstimator):
    """Stiction from the shapes of OP and PV cycles, by the shape library of seed 001.

    Each full cycle of OP and PV is matched by dynamic time warping to
    rectangular, triangular, sinusoidal and trapezoidal templates generated for that
    cycle (:class:`~sktiction.TemplateDistances`). A cycle is *sticky* when its
    (OP shape, PV shape) pair is in the library row of the loop type:

    ============  =====================  ================================
    loop type     OP                     PV
    ============  =====================  ================================
    flow          triangular             rectangular or trapezoidal
    flow (P-dom.) rectangular            rectangular
    pressure,     triangular             sinusoidal or triangular
    temperature
    level         triangular             triangular or sinusoidal
                                         (parabolic has no template)
    ============  =====================  ================================

    The confidence (``predict_proba[:, 1]``) is the share of sticky cycles among
    those analysed, as in the paper; the loop is called sticky when it reaches
    ``min_confidence``. The stiction size is the OP peak-to-peak over the sticky
    cycles, in OP units (% of span for OP in %), mean and max
    (:meth:`stiction_size`; the paper reports the max and recommends the mean).

    A loop that does not oscillate, has fewer than ``min_cycles`` cycles, or cannot
    be analysed gets confidence 0, prediction 0 and its reason in :meth:`diagnose`.
    The method needs OP: without it every loop gets reason ``missing_op``.

    Parameters
    ----------
    loop_type : {"auto", "flow", "pressure", "temperature", "level"}, default="auto"
        Row of the shape library. ``"auto"`` infers it per loop from the PV shape
        that most cycles share (rectangular/trapezoidal: flow; sinusoidal:
        pressure; triangular: level).
    min_confidence : float, default=0.5
        Share of sticky cycles from which a loop is called sticky.
    min_cycles : int, default=2
        Fewer analysed cycles than this give no verdict.
    templates : TemplateDistances or None, default=None
        Template matcher; ``None`` uses ``TemplateDistances()``. Its options can be
        grid-searched as ``templates__<name>``.

    Attributes
    ----------
    classes_ : ndarray of shape (2,)
        ``[0, 1]``.
    templates_ : TemplateDistances
        The fitted matcher.

    References
    ----------
    R. Srinivasan, R. Rengaswamy, R. Miller, "Control loop performance assessment.
    1. A qualitative approach for stiction diagnosis", Ind. Eng. Chem. Res. 44
    (2005) 6708-6718.

    Examples
    --------
    >>> from sktiction import ShapeLibraryClassifier
    >>> from sktiction.datasets import make_loops
    >>> X, y = make_loops(6, n_samples=1500, random_state=0)
    >>> clf = ShapeLibraryClassifier().fit(X, y)
    >>> clf.predict_proba(X).shape
    (6, 2)
    """

    _require_op = True

    def __init__(self, loop_type="auto", min_confidence=0.5, min_cycles=2, templates=None):
        self.loop_type = loop_type
        self.min_confidence = min_confidence
        self.min_cycles = min_cycles
        self.templates = templates

    def _fit_loops(self, loops, y):
        if self.loop_type not in LOOP_TYPES:
            raise ValueError(f"loop_type must be one of {LOOP_TYPES}; got {self.loop_type!r}.")
        if not 0 < self.min_confidence <= 1:
            raise ValueError(
                f"min_confidence must be in (0, 1]; got {self.min_confidence!r}."
            )
        if int(self.min_cycles) != self.min_cycles or self.min_cycles < 1:
            raise ValueError(f"min_cycles must be an integer >= 1; got {self.min_cycles!r}.")
        templates = self.templates if self.templates is not None else TemplateDistances()
        self.templates_ = clone(templates).set_params(signals=("op", "pv"))
        self.templates_._validate_params()
        self.templates_.n_channels_in_ = self.n_channels_in_  # stateless: fitted as it is

    def _sticky_cycles(self, loops, analyses=None, status=None):
        """The cycle table with ``loop_type`` and ``sticky`` per cycle."""
        if np.isnan(loops[:, :, OP]).all():  # no OP at all: every loop says missing_op
            return pd.DataFrame()
        if analyses is None:
            analyses = analyse_loops(loops)
        table = self.templates_.cycle_table_analysed(loops, analyses, status)
        if table.empty:
            return table.assign(loop_type=pd.Series(dtype=str), sticky=pd.Series(dtype=bool))
        if self.loop_type == "auto":
            inferred = table.groupby("loop")["pv_shape"].agg(_infer_loop_type)
            table["loop_type"] = table["loop"].map(inferred)
        else:
            table["loop_type"] = self.loop_type
        pairs = zip(table["loop_type"], table["op_shape"], table["pv_shape"])
        table["sticky"] = [(op, pv) in SHAPE_LIBRARY.get(lt, ()) for lt, op, pv in pairs]
        return table

    def _score_loops(self, loops, analyses=None, status=None):
        table = self._sticky_cycles(loops, analyses, status)
        n = len(loops)
        report = pd.DataFrame(
            {
                "prediction": np.zeros(n, dtype=int),
                "score": np.zeros(n),
                "reason": REASON_NOT_OSCILLATING,
                "loop_type": self.loop_type if self.loop_type != "auto" else "unknown",
                "n_cycles": np.zeros(n, dtype=int),
                "n_sticky_cycles": np.zeros(n, dtype=int),
                "stiction_size_mean": np.nan,
                "stiction_size_max": np.nan,
            }
        )
        if table.empty:
            return report
        per_loop = table.groupby("loop")
        n_cycles = per_loop.size()
        n_sticky = per_loop["sticky"].sum()
        pp = table.loc[table["sticky"]].groupby("loop")["op_peak_to_peak"]
        idx = n_cycles.index.to_numpy()
        report.loc[idx, "n_cycles"] = n_cycles.to_numpy()
        report.loc[idx, "n_sticky_cycles"] = n_sticky.to_numpy()
        report.loc[idx, "loop_type"] = per_loop["loop_type"].first().to_numpy()
        sizes = pp.agg(["mean", "max"])
        report.loc[sizes.index, ["stiction_size_mean", "stiction_size_max"]] = sizes.to_numpy()
        enough = report["n_cycles"] >= self.min_cycles
        conf = np.where(enough, report["n_sticky_cycles"] / np.maximum(report["n_cycles"], 1), 0)
        report["score"] = conf
        report["prediction"] = (conf >= self.min_confidence).astype(int)
        report.loc[enough, "reason"] = "ok"
        report.loc[(report["n_cycles"] > 0) & ~enough, "reason"] = "too_few_cycles"
        return report

    def cycle_table(self, X):
        """The per-cycle table of :meth:`TemplateDistances.cycle_table`, with verdicts.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        table : pandas.DataFrame
            One row per analysed cycle, plus ``loop_type`` (the library row used)
            and ``sticky`` (its OP/PV shapes are in that row).
        """
        return self._sticky_cycles(self._checked(X))

    def predict_proba(self, X):
        """Confidence of stiction: share of sticky cycles (seed 001).

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        proba : ndarray of shape (n_loops, 2)
            Columns: no stiction, stiction.
        """
        report = said_unjudged(
            self.diagnose(X), "predict_proba gives them 0", problems=INPUT_PROBLEMS
        )
        conf = report["score"].to_numpy(dtype=float)
        return np.column_stack([1.0 - conf, conf])

    def stiction_size(self, X):
        """OP peak-to-peak over the sticky cycles of each loop, mean and max.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        size : pandas.DataFrame
            Columns ``stiction_size_mean`` and ``stiction_size_max`` in OP units
            (% of span when OP is in %); NaN where no cycle was sticky.
        """
        return self.diagnose(X)[["stiction_size_mean", "stiction_size_max"]]
