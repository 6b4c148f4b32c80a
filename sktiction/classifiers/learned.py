"""A classifier learned on simulated loops, that says when a loop is outside what it learned.

:class:`LearnedStictionClassifier` chains four steps, each there for a reason found
when the first learned model met data it had not seen:

1. **Per-loop normalisation** (:func:`normalise_loops`): PV and SP are centred on PV's
   median and divided by PV's robust spread, OP by its own. Units, offsets and the
   size of the numbers cannot enter a feature, so a verdict never changes when a loop
   is scaled (even by 1e12) or shifted. Before it, a start-up transient at the
   record's start is dropped and an OP recorded a row out of step with PV is moved
   back in line (:func:`~sktiction._cleaning.in_step`).
2. **Features whose meaning carries over** from simulation to plants: area ratios,
   template distances, the fitted valve model and the PV-OP hysteresis
   (:class:`~sktiction.features.PVOPHysteresis`, at the period and at OP's own time
   scale, so loops without cycles have evidence too). Counts that grow with the
   record length are replaced by shares (a classifier must not read record length).
3. **An explicit domain check** fitted on the training features: hard rules (enough
   samples, PV and OP related as in a closed loop, not mostly frozen rows) and per-
   feature ranges of the training loops with a margin. Outside them the model gives no
   probability (NaN), predicts the negative class and says why. One range is a matter of
   recording, not of the loop: cycles slower in samples than any the model learned (a
   finer sampling) are read in block means that bring them into range. A record much
   longer than the training loops is also read in windows of about their length, and
   its probability is the mean of the whole record's and the windows' (``long_record``).
4. **Calibrated probabilities** from two models that fail differently, averaged:
   gradient-boosted trees and a logistic regression, each inside
   :class:`~sklearn.calibration.CalibratedClassifierCV`, so that ``p = 0.8`` means
   about 8 sticky loops in 10 among simulated loops like the training ones
   (``benchmarks/simulated_accuracy.py`` prints the reliability table and Brier score).

:func:`~sktiction.pretrained_classifier` (:mod:`sktiction.classifiers._pretrained`)
trains the default model once and keeps it in a user cache
(:mod:`sktiction.classifiers._persistence`: why joblib, how a stale or corrupt entry is
found and rebuilt); the domain rules' statistics are :mod:`sktiction.classifiers._coupling`'s.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np
import pandas as pd
from joblib import Parallel, delayed
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.calibration import CalibratedClassifierCV
from sklearn.ensemble import HistGradientBoostingClassifier, VotingClassifier
from sklearn.impute import SimpleImputer
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import FeatureUnion, make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.validation import check_is_fitted, column_or_1d
from threadpoolctl import threadpool_limits

from .._cleaning import as_judged, put_record
from .._validation import (
    OP,
    PV,
    SP,
    STATUS_OK,
    loop_lengths,
    loop_status,
    validate_loops,
)
from ._base import said_unjudged
from ._coupling import _MIN_WHITE, _WEAK_COUPLING, DOMAIN_STATISTICS, domain_statistics
from .applicability import drawn_through_few

#: Reasons :meth:`LearnedStictionClassifier.diagnose` gives for no verdict, besides the
#: :func:`~sktiction._validation.loop_status` codes and ``out_of_domain:<feature>``.
REASON_TOO_SHORT = "too_short"
REASON_UNRELATED = "pv_op_unrelated"
REASON_COMPRESSED = "too_compressed"
OUT_OF_DOMAIN = "out_of_domain"

# _ONE_THREAD: the booster's OpenMP threads spin against each other when other
# processes keep the cores busy: a 3 s fit took 37 s on a loaded 2-core machine. One
# thread costs little at this size; parallelism comes from the feature chunks instead.

# Feature columns that count things and so grow with the record length: replaced
# by the share of the record that oscillates.
_LENGTH_COUNTS = ("area__n_half_cycles", "templates__n_cycles")
# The one feature column in OP units (all others are ratios within a signal): what
# diagnose_analysed rescales when it reads features from loops that are not normalised.
_OP_UNIT_FEATURES = ("valve_model__stiction_fit_band",)
# A loop whose cycles are slower, in samples, than any the model learned (a finer recording
# is not another loop) is read in block means that bring its period to the training
# periods' upper quartile, keeping at least _MIN_COARSE_ROWS rows (and min_samples). The
# second simulator's records interpolated ten times finer had fallen from 0.807 to 0.710
# (14 % of them beyond the period range); read coarser, 0.800. Loops within the range are
# never touched (benchmarks/sampling_rate.py).
_PERIOD, _OSCILLATING = "templates__period", "templates__oscillating"
_MIN_COARSE_ROWS = 600


def make_loop_features(n_jobs=None):
    """The learned model's per-loop features side by side: area ratios, template
    distances, the fitted valve model and the PV-OP hysteresis.

    :class:`~sktiction.features.LoopDescriptors` is left out on evidence: its jump
    shares read a historian's hold-then-jump as much as a valve's slip. In a
    development ablation (trained on 1,500 default-world loops, tested on 400 held-out
    loops of each world) leaving it out changed balanced accuracy by +0.002 on the
    default world and -0.005 on the classic world, and raised it on the measured
    windows grouped by tag; adding the slow hysteresis and valve-fit columns of
    :class:`~sktiction.features.PVOPHysteresis` raised it from 0.68 to 0.73 (default)
    and from 0.83 to 0.91 (classic).

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
    # imported here: loading a fitted model in a new process needs no feature code
    # (nor numba, which it compiles with)
    from ..features import AreaRatio, PVOPHysteresis, StictionModelFit, TemplateDistances

    return FeatureUnion(
        [
            ("area", AreaRatio()),
            ("templates", TemplateDistances()),
            ("valve_model", StictionModelFit()),
            ("hysteresis", PVOPHysteresis()),
        ],
        n_jobs=n_jobs,
    )


def _fitted_loop_features():
    """:func:`make_loop_features`, fitted. Its transformers learn nothing from data, but
    fitting checks the channels: a neutral loop with all three, not a chunk's first loop,
    which may lack OP and would fail the whole chunk instead of getting its own reason."""
    return make_loop_features().fit(np.zeros((1, 30, 3)))


def _raw_rows(loops, analyses, status):
    """Loop features and domain statistics of checked loops from their analyses.

    Each transformer reads the shared analyses, so a loop is analysed once, and a loop
    without OP gets NaN from the transformers that need it (its reason comes from
    ``status``) instead of failing the batch as ``transform`` would.
    """
    union = _fitted_loop_features()
    with threadpool_limits(limits=1):  # tiny least-squares fits: see _ONE_THREAD
        parts = [
            est.transform_analysed(loops, analyses, status if est._needs_op else None)
            for _, est in union.transformer_list
        ]
        parts.append(domain_statistics(loops, status))
    return np.hstack(parts)


def _raw_names():
    return list(_fitted_loop_features().get_feature_names_out()) + list(DOMAIN_STATISTICS)


def _robust_spread(x):
    """Interquartile range per row, falling back to the standard deviation, then 1."""
    q1, q3 = np.nanpercentile(x, [25, 75], axis=1)
    spread = q3 - q1
    sd = np.nanstd(x, axis=1)
    spread = np.where(spread > 1e-9 * sd, spread, sd)
    return np.where(spread > 0, spread, 1.0)


def _centre_scale(x):
    """Median and robust spread of each row of ``x``: what :func:`normalise_loops` uses."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN channels stay NaN
        return np.nan_to_num(np.nanmedian(x, axis=1)), np.nan_to_num(_robust_spread(x), nan=1.0)


def normalise_loops(loops):
    """Centre and scale each loop: PV and SP by PV's median and IQR, OP by its own.

    PV and SP share one scale so that the control error keeps its meaning. The IQR
    ignores spikes and setpoint steps; it falls back to the standard deviation when
    the interquartile range is zero (both quartiles on one value, as in a mostly frozen
    historian record).

    Parameters
    ----------
    loops : ndarray of shape (n_loops, n_samples, 3)
        Output of :func:`~sktiction._validation.check_loops`.

    Returns
    -------
    normalised : ndarray of shape (n_loops, n_samples, 3)

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.classifiers.learned import normalise_loops
    >>> X = np.random.default_rng(0).normal(size=(2, 100, 3))
    >>> np.allclose(normalise_loops(X), normalise_loops(3e12 * X - 7e12))
    True
    """
    out = np.array(loops, dtype=float)
    pv_mid, pv_scale = _centre_scale(out[:, :, PV])
    op_mid, op_scale = _centre_scale(out[:, :, OP])
    pv_mid, pv_scale, op_mid, op_scale = (v[:, None] for v in (pv_mid, pv_scale, op_mid, op_scale))
    out[:, :, PV] = (out[:, :, PV] - pv_mid) / pv_scale
    out[:, :, SP] = (out[:, :, SP] - pv_mid) / pv_scale
    out[:, :, OP] = (out[:, :, OP] - op_mid) / op_scale
    return out


_MODELS = ("ensemble", "boosting", "logistic")


class LearnedStictionClassifier(ClassifierMixin, BaseEstimator):
    """Stiction classifier learned from loops, with a domain check and calibrated output.

    ``fit`` normalises each loop (scale and offset cannot matter), computes the
    features of :func:`make_loop_features`, fits the domain check and a calibrated
    classifier. ``diagnose`` says per loop whether the model may speak
    (``in_domain``) and why not (``reason``); outside its domain ``predict_proba``
    gives NaN and ``predict`` the negative class.

    The default model averages the calibrated probabilities of two models that fail
    differently. Gradient boosting learns from the training loops which way a
    missing feature points (no oscillation is not no stiction) and how features
    interact, which also lets it learn the simulator's quirks. A logistic
    regression on standardised features (missing ones imputed, with an indicator)
    can only weigh evidence, one monotone term per feature. Trained on the default
    world and judged on data made differently, neither wins everywhere:

    ==========================================  =========  =========  =========
    trained on 3,000 default-world loops         boosting   logistic   ensemble
    ==========================================  =========  =========  =========
    leave one family out, mean bal. accuracy        0.759      0.746      0.765
    classic world (1,000 loops), bal. accuracy      0.924      0.917      0.922
    measured windows, ROC AUC (5 subsets)       0.81-0.86  0.82-0.84  0.84-0.86
    ==========================================  =========  =========  =========

    The ensemble was chosen on the two simulated rows; the measured row (models
    trained on five 1,500-loop subsets, ``benchmarks/measured_data.py``'s windows)
    is reported, not tuned to.

    Parameters
    ----------
    model : {"ensemble", "boosting", "logistic"}, default="ensemble"
        Gradient boosting, logistic regression or the mean of both probabilities.
    max_iter, learning_rate, l2_regularization, min_samples_leaf : numbers
        Of :class:`~sklearn.ensemble.HistGradientBoostingClassifier`.
    C : float, default=1.0
        Inverse regularisation strength of the logistic regression.
    calibration : {"isotonic", "sigmoid"} or None, default="isotonic"
        Method of :class:`~sklearn.calibration.CalibratedClassifierCV` (``cv`` folds),
        applied to each model; ``None`` leaves their probabilities as they are.
    cv : int, default=3
        Folds of the calibration.
    min_samples : int, default=200
        Fewer samples give ``too_short``: too few for the dynamics of a loop.
    min_coupling : float, default=5.0
        :func:`~sktiction.classifiers.pv_op_coupling` below this gives
        ``pv_op_unrelated``: OP does not follow the control error as a controller's
        output does (unrelated signals give z below 3). Below 10 the coupling must
        also survive prewhitening (z >= 3), so that two unrelated oscillating signals
        are not taken for a loop.
        A loop so refused whose PV or OP is drawn as straight lines through fewer than
        32 points (an export compressed about as much as the channel moves) gets
        ``too_compressed`` instead: the export, not the loop, hides the relation.
    max_frozen_share : float, default=0.8
        A larger share of steps with PV and OP both frozen gives ``too_compressed``.
    domain_quantile : float, default=0.002
        Each feature's training range is taken between this quantile and its
        complement ...
    domain_margin : float, default=0.5
        ... widened by this share of its width on each side; a loop with a feature
        outside gets ``out_of_domain:<feature>``. ``None`` turns the range check off.
    window : int, default=3000
        Samples per window of a long record (see ``long_record``).
    long_record : int or None, default=10000
        A loop with more samples than this (at least twice ``window``; counted after a
        finer recording is read coarser) is read twice: whole, and in ``k = n // window``
        equal windows, each read as a record of its own. Its probability is the mean of
        the two readings, the windows' being the mean of those in domain; a record the
        hard rules refuse whole (too short, PV and OP unrelated, too compressed, a status
        code) stays refused. The default model learned records of 2,000 samples. Windows
        alone lifted long records sampled as the training loops were but dropped rare
        slips on records sampled ten times finer than their dynamics; with both
        readings the first gain +0.009 to +0.016 and the second move by -0.017 to
        +0.014, +0.002 pooled (``benchmarks/long_records.py``, ``docs/realism.md``).
        Above 10,000 so that a day at 10 s (8,640 samples) costs a scan nothing more:
        each window is analysed again. ``None`` reads every record whole. Fitting always
        reads records whole.
    random_state : int or None, default=None
        Seed of the booster. With the defaults it changes nothing: scikit-learn's
        booster draws only for early stopping (off below 10,000 loops) and for bin
        subsampling (above 200,000), and the calibration folds are not shuffled, so
        the model is a function of its training loops alone.
    n_jobs : int or None, default=None
        Processes for the features (loops are split into chunks).

    Attributes
    ----------
    classes_ : ndarray of shape (2,)
        Labels; the second is the stiction class.
    feature_names_ : ndarray of str
        Columns given to the model.
    domain_low_, domain_high_ : ndarray
        Accepted range of each feature; ``domain_nan_`` whether NaN was seen in training.
    trained_period_ : float
        Upper quartile of the training loops' OP periods (samples): a loop whose period
        lies beyond the domain is read in block means that bring it there.
    model_ : estimator
        The fitted (calibrated) classifier.

    Examples
    --------
    >>> from sktiction.classifiers import LearnedStictionClassifier
    >>> from sktiction.datasets import make_loops
    >>> X, y = make_loops(40, n_samples=1000, random_state=0)
    >>> clf = LearnedStictionClassifier(max_iter=30, random_state=0).fit(X, y)
    >>> clf.diagnose(X[:2]).columns.tolist()
    ['prediction', 'probability', 'in_domain', 'reason', 'rows_per_sample']
    """

    def __init__(
        self,
        *,
        model="ensemble",
        max_iter=300,
        learning_rate=0.08,
        l2_regularization=1.0,
        min_samples_leaf=20,
        C=1.0,
        calibration="isotonic",
        cv=3,
        min_samples=200,
        min_coupling=5.0,
        max_frozen_share=0.8,
        domain_quantile=0.002,
        domain_margin=0.5,
        window=3000,
        long_record=10000,
        random_state=None,
        n_jobs=None,
    ):
        self.model = model
        self.max_iter = max_iter
        self.learning_rate = learning_rate
        self.l2_regularization = l2_regularization
        self.min_samples_leaf = min_samples_leaf
        self.C = C
        self.calibration = calibration
        self.cv = cv
        self.min_samples = min_samples
        self.min_coupling = min_coupling
        self.max_frozen_share = max_frozen_share
        self.domain_quantile = domain_quantile
        self.domain_margin = domain_margin
        self.window = window
        self.long_record = long_record
        self.random_state = random_state
        self.n_jobs = n_jobs

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = True  # NaN pads loops of unequal length
        tags.input_tags.three_d_array = True
        return tags

    def _validate_params(self):
        if self.model not in _MODELS:
            raise ValueError(f"model must be one of {_MODELS}; got {self.model!r}.")
        if not (isinstance(self.C, numbers.Real) and self.C > 0):
            raise ValueError(f"C must be > 0; got {self.C!r}.")
        if self.calibration not in ("isotonic", "sigmoid", None):
            raise ValueError(
                f"calibration must be 'isotonic', 'sigmoid' or None; got {self.calibration!r}."
            )
        if not 0 <= self.domain_quantile < 0.5:
            raise ValueError(f"domain_quantile must be in [0, 0.5); got {self.domain_quantile!r}.")
        if self.domain_margin is not None and not self.domain_margin >= 0:
            raise ValueError(f"domain_margin must be >= 0 or None; got {self.domain_margin!r}.")
        if not 0 < self.max_frozen_share <= 1:
            raise ValueError(f"max_frozen_share must be in (0, 1]; got {self.max_frozen_share!r}.")
        if int(self.min_samples) != self.min_samples or self.min_samples < 20:
            raise ValueError(f"min_samples must be an integer >= 20; got {self.min_samples!r}.")
        self._check_windows()

    def _check_windows(self):
        """``window`` and ``long_record``, checked in ``fit`` and again before a verdict:
        they may be set on a fitted model (a window shorter than ``min_samples`` would
        never be judged)."""
        if not (isinstance(self.window, numbers.Integral) and self.window >= self.min_samples):
            raise ValueError(f"window must be an integer >= min_samples; got {self.window!r}.")
        if self.long_record is not None and not (
            isinstance(self.long_record, numbers.Integral) and self.long_record >= 2 * self.window
        ):
            raise ValueError(
                f"long_record must be None or an integer >= 2 * window; got {self.long_record!r}."
            )

    # ---- features -------------------------------------------------------------------

    def _raw_features(self, loops):
        """Feature matrix of normalised loops plus the domain statistics, in chunks."""
        from ..features._loops import analyse_loops

        def chunk(part):
            return _raw_rows(part, analyse_loops(part), loop_status(part, require_op=True))

        n_jobs = self.n_jobs if self.n_jobs is not None else 1
        size = max(1, int(np.ceil(len(loops) / max(1, 4 * abs(n_jobs)))))
        parts = [loops[s : s + size] for s in range(0, len(loops), size)]
        if n_jobs == 1 or len(parts) == 1:
            rows = [chunk(p) for p in parts]
        else:
            rows = Parallel(n_jobs=n_jobs)(delayed(chunk)(p) for p in parts)
        return pd.DataFrame(np.vstack(rows), columns=_raw_names())

    @staticmethod
    def _model_columns(raw, lengths):
        """Model inputs: raw features minus counts that grow with the record length,
        plus the share of the record that oscillates."""
        cols = [c for c in raw.columns if c not in _LENGTH_COUNTS + DOMAIN_STATISTICS]
        out = raw[cols].replace([np.inf, -np.inf], np.nan)
        with np.errstate(all="ignore"):
            share = raw["templates__n_cycles"] * raw["templates__period"] / lengths
        out["oscillating_share"] = np.clip(share, 0.0, 1.0)
        return out

    def loop_features(self, X):
        """The features the model reads and the domain statistics, one row per loop.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP, NaN-padded at the end.

        Returns
        -------
        features : pandas.DataFrame
            Model columns, then the domain statistics ``pv_op_coupling``,
            ``pv_op_coupling_white`` and ``frozen_share``.
        """
        check_is_fitted(self, "model_")
        loops = as_judged(validate_loops(self, X, reset=False))
        return self._features(normalise_loops(loops))

    def _features(self, loops):
        raw = self._raw_features(loops)
        feats = self._model_columns(raw, loop_lengths(loops))
        return pd.concat([feats, raw[list(DOMAIN_STATISTICS)]], axis=1)

    # ---- fit ------------------------------------------------------------------------

    def _make_model(self):
        def calibrated(est):
            if self.calibration is None:
                return est
            return CalibratedClassifierCV(est, method=self.calibration, cv=self.cv)

        booster = calibrated(
            HistGradientBoostingClassifier(
                max_iter=self.max_iter,
                learning_rate=self.learning_rate,
                l2_regularization=self.l2_regularization,
                min_samples_leaf=self.min_samples_leaf,
                random_state=self.random_state,
            )
        )
        logistic = calibrated(
            make_pipeline(
                SimpleImputer(strategy="median", add_indicator=True, keep_empty_features=True),
                StandardScaler(),
                LogisticRegression(C=self.C, max_iter=1000),
            )
        )
        if self.model == "boosting":
            return booster
        if self.model == "logistic":
            return logistic
        return VotingClassifier([("boosting", booster), ("logistic", logistic)], voting="soft")

    def fit(self, X, y):
        """Compute the features, fit the domain check and the calibrated model.

        NaN gaps are repaired as at prediction (bridged, or the longest stretch kept), and
        loops that cannot be judged are left out with a warning that counts them by
        reason. Holds, spikes, placeholders and OP alignment are *not* undone here, unlike
        :meth:`diagnose`: the model is trained on simulated loops read as made (the spike
        rule finds a "spike" in 7 of the default model's 1,420). To train on measured
        loops, clean them first with :func:`sktiction.clean_loops`.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP, NaN-padded at the end.
        y : array-like of shape (n_loops,)
            Two classes; the second in sorted order is stiction (e.g. 0/1).

        Returns
        -------
        self : object
            Fitted classifier.
        """
        self._validate_params()
        loops = as_judged(validate_loops(self, X, reset=True), training=True)
        y = column_or_1d(y, warn=True)
        check_classification_targets(y)
        if len(y) != len(loops):
            raise ValueError(
                f"X has {len(loops)} loops but y has {len(y)} labels; they must match."
            )
        self.classes_, y_idx = np.unique(y, return_inverse=True)
        if len(self.classes_) != 2:
            raise ValueError(f"y must hold exactly two classes; got {self.classes_.tolist()}.")
        self.n_channels_in_ = int(np.shape(X)[2]) if np.ndim(X) == 3 else 1
        feats = self._features(normalise_loops(loops))
        reasons = self._hard_reasons(loops, feats)
        usable = reasons == STATUS_OK
        if usable.sum() < 10 or len(np.unique(y_idx[usable])) < 2:
            raise ValueError(
                f"only {int(usable.sum())} of {len(loops)} training loops can be analysed "
                "(long enough, with OP, PV and OP related); need at least 10 of both classes."
            )
        said_unjudged(reasons, "fit leaves them out of training")
        model_cols = [c for c in feats.columns if c not in DOMAIN_STATISTICS]
        F = feats.loc[usable, model_cols].to_numpy()
        cycling = feats.loc[usable, _OSCILLATING].to_numpy(dtype=float) > 0
        periods = feats.loc[usable, _PERIOD].to_numpy(dtype=float)[cycling]
        periods = periods[np.isfinite(periods)]
        self.trained_period_ = float(np.percentile(periods, 75)) if periods.size else np.nan
        self.feature_names_ = np.asarray(model_cols, dtype=object)
        q = self.domain_quantile
        with np.errstate(all="ignore"):
            lo, hi = np.nanquantile(F, [q, 1 - q], axis=0)
        width = np.nan_to_num(hi - lo)
        margin = 0.0 if self.domain_margin is None else self.domain_margin
        self.domain_low_ = lo - margin * width
        self.domain_high_ = hi + margin * width
        self.domain_nan_ = np.isnan(F).any(axis=0)
        with threadpool_limits(limits=1):  # see _ONE_THREAD
            self.model_ = self._make_model().fit(F, y_idx[usable])
        return self

    # ---- verdicts -------------------------------------------------------------------

    def _hard_reasons(self, loops, feats):
        status = loop_status(loops, require_op=True, check_swap=True).astype(object)
        n = loop_lengths(loops)
        ok = status == STATUS_OK
        status[ok & (n < self.min_samples)] = REASON_TOO_SHORT
        coupling = feats["pv_op_coupling"].to_numpy()
        white = feats["pv_op_coupling_white"].to_numpy()
        weak = (coupling < _WEAK_COUPLING) & ~(white >= _MIN_WHITE)
        ok = status == STATUS_OK
        unrelated = np.flatnonzero(ok & (~(coupling >= self.min_coupling) | weak))
        status[unrelated] = REASON_UNRELATED
        for i in unrelated:  # the same refusal, named for what the record shows
            if drawn_through_few(loops[i, : n[i], PV], loops[i, : n[i], OP]):
                status[i] = REASON_COMPRESSED
        ok = status == STATUS_OK
        status[ok & (feats["frozen_share"].to_numpy() > self.max_frozen_share)] = REASON_COMPRESSED
        return status

    def _range_reasons(self, F, reasons):
        if self.domain_margin is None:
            return reasons
        with np.errstate(invalid="ignore"):
            below = (self.domain_low_ - F) / np.where(
                self.domain_high_ > self.domain_low_, self.domain_high_ - self.domain_low_, 1.0
            )
            above = (F - self.domain_high_) / np.where(
                self.domain_high_ > self.domain_low_, self.domain_high_ - self.domain_low_, 1.0
            )
        excess = np.fmax(below, above)
        excess = np.where(np.isnan(F) & ~self.domain_nan_, np.inf, excess)
        excess = np.nan_to_num(excess, nan=-np.inf)
        worst = np.argmax(excess, axis=1)
        out = reasons.copy()
        for i in np.flatnonzero((reasons == STATUS_OK) & (excess.max(axis=1) > 0)):
            out[i] = f"{OUT_OF_DOMAIN}:{self.feature_names_[worst[i]]}"
        return out

    def _coarsening(self, loops, feats):
        """Rows per block for each loop: > 1 where its period lies beyond the model's
        domain (see _MIN_COARSE_ROWS), else 1."""
        period = feats[_PERIOD].to_numpy(dtype=float)
        high = self.domain_high_[list(self.feature_names_).index(_PERIOD)]
        with np.errstate(invalid="ignore"):
            slow = (feats[_OSCILLATING].to_numpy(dtype=float) > 0) & (period > high)
            k = np.ceil(period / getattr(self, "trained_period_", np.nan))
        keep = max(_MIN_COARSE_ROWS, self.min_samples)  # never shorter than a verdict needs
        k = np.minimum(np.where(slow, k, 1), loop_lengths(loops) // keep)
        return np.maximum(np.nan_to_num(k, nan=1.0), 1).astype(int)

    def _at_trained_scale(self, loops, feats):
        """Loops and features with the loops of :meth:`_coarsening` > 1 read as block means
        of that many rows, and the rows per block of each loop."""
        k = self._coarsening(loops, feats)
        idx = np.flatnonzero(k > 1)
        if not idx.size:
            return loops, feats, k
        loops = np.array(loops, dtype=float)
        for i, n in zip(idx, loop_lengths(loops[idx])):
            m = int(n) // k[i]
            put_record(loops, i, loops[i, : m * k[i]].reshape(m, k[i], -1).mean(axis=1))
        feats = feats.copy()
        feats.iloc[idx] = self._features(normalise_loops(loops[idx])).to_numpy()
        return loops, feats, k

    def _diagnose_features(self, loops, feats):
        return self._verdicts(*self._at_trained_scale(loops, feats))

    def _verdicts(self, loops, feats, rows_per_sample):
        """The report of loops at the trained scale, from their features."""
        reasons = self._hard_reasons(loops, feats)
        F = feats[list(self.feature_names_)].to_numpy()
        reasons = self._range_reasons(F, reasons)
        in_domain = reasons == STATUS_OK
        proba = np.full(len(loops), np.nan)
        if in_domain.any():
            with threadpool_limits(limits=1):  # see _ONE_THREAD
                proba[in_domain] = self.model_.predict_proba(F[in_domain])[:, 1]
        pred_idx = (in_domain & (proba >= 0.5)).astype(int)
        return pd.DataFrame(
            {
                "prediction": self.classes_[pred_idx],
                "probability": proba,
                "in_domain": in_domain,
                "reason": reasons.astype(str),
                "rows_per_sample": rows_per_sample,
            }
        )

    def _judge(self, loops, feats):
        """The report of checked loops from their features. A loop still longer than
        ``long_record`` once read at the trained scale (a finer recording is read coarser
        first) and judged whole or outside the trained ranges only (not refused by a hard
        rule: too short, PV and OP unrelated, too compressed, a status code) is read in
        windows too (:meth:`_diagnose_windows`); its probability is the mean of the two
        readings, or the one reading in domain."""
        loops, feats, rows = self._at_trained_scale(loops, feats)
        report = self._verdicts(loops, feats, rows)
        if getattr(self, "long_record", None) is None:  # None, or a model pickled before it
            return report
        self._check_windows()
        reason = report["reason"].to_numpy(dtype=str)
        readable = (reason == STATUS_OK) | np.char.startswith(reason, OUT_OF_DOMAIN)
        long = np.flatnonzero(readable & (loop_lengths(loops) > self.long_record))
        if long.size:
            in_windows, rows_windows = self._diagnose_windows(loops[long])
            with warnings.catch_warnings():  # neither reading in domain: NaN, no verdict
                warnings.simplefilter("ignore", RuntimeWarning)
                p = np.nanmean([report["probability"].to_numpy()[long], in_windows], axis=0)
            judged = np.isfinite(p)
            at = report.columns.get_loc
            report.iloc[long, at("probability")] = p
            report.iloc[long, at("in_domain")] = judged
            report.iloc[long[judged], at("reason")] = STATUS_OK
            report.iloc[long, at("prediction")] = self.classes_[(judged & (p >= 0.5)).astype(int)]
            report.iloc[long, at("rows_per_sample")] = rows[long] * rows_windows
        return report

    def _diagnose_windows(self, loops):
        """The windows' reading of loops that :meth:`_judge` found readable (so with no
        :func:`~sktiction._validation.loop_status` code): each loop's ``k = n // window``
        equal windows, normalised, analysed and checked as records of their own; returns
        the mean probability of those in domain (NaN if none) and the most rows per
        sample."""
        from ..datasets._measured import pad_loops

        owner, pieces = [], []
        for i, n in enumerate(loop_lengths(loops)):
            k = int(n) // self.window
            size = int(n) // k
            pieces += [loops[i : i + 1, j * size : (j + 1) * size] for j in range(k)]
            owner += [i] * k
        windows = pad_loops(pieces)
        judged = self._diagnose_features(windows, self._features(normalise_loops(windows)))
        judged["owner"] = owner
        rows = judged.groupby("owner")["rows_per_sample"].max().to_numpy()
        mean = judged[judged["in_domain"]].groupby("owner")["probability"].mean()
        proba = np.full(len(loops), np.nan)
        proba[mean.index.to_numpy()] = mean.to_numpy()
        return proba, rows

    def diagnose(self, X):
        """Per loop: verdict, calibrated probability, whether the model may speak, and why.

        Each loop is read as a file scan reads it (:func:`~sktiction._cleaning.as_judged`):
        a regular hold is read as stored (a loop held k rows per value becomes k times
        shorter), spikes are replaced, placeholders read as gaps, short NaN gaps bridged
        and, past a long one, the longest stretch kept; a start-up transient at the start
        is dropped and an OP recorded a row out of step with PV is moved back in line.
        A loop then longer than ``long_record`` samples is also read in windows.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP, NaN-padded at the end.

        Returns
        -------
        report : pandas.DataFrame
            ``prediction`` (a class; the negative one without a verdict),
            ``probability`` of stiction (NaN without a verdict), ``in_domain`` (bool)
            and ``reason``: ``ok``, a :func:`~sktiction._validation.loop_status` code,
            ``too_short``, ``pv_op_unrelated``, ``too_compressed`` or
            ``out_of_domain:<feature>`` (the feature furthest outside its training range),
            and ``rows_per_sample``: 1, or the rows averaged into each sample of a loop
            whose cycles are slower, in samples, than any the model learned (a recording
            finer than the training loops' is read coarser instead of refused; for a
            loop also read in windows, the most of its readings).
        """
        check_is_fitted(self, "model_")
        loops = as_judged(validate_loops(self, X, reset=False))
        return self._judge(loops, self._features(normalise_loops(loops)))

    def diagnose_analysed(self, loops, analyses, status=None):
        """:meth:`diagnose` of checked loops from their shared, already made analyses.

        A scan analyses each loop's raw signals once for all its classifiers
        (:class:`~sktiction.features._loops.LoopAnalysis`); the features are read from
        those analyses instead of analysing the normalised loops again. Normalising
        shifts and scales each channel, and every feature is a ratio within one
        signal (areas, shares, template distances after each cycle's RMS, residual
        shares, F-tests) except the fitted band in OP units, which is divided by the
        OP scale of :func:`normalise_loops`. The features so agree with
        :meth:`diagnose`'s to rounding; a decision taken exactly on a threshold (a
        cycle period at the tolerance, a move at its limit, common on quantised
        records) can still go either way, as it can for a shifted copy of a loop. The
        windows of a record longer than ``long_record`` are not in the shared analyses:
        they are normalised and analysed here, as :meth:`diagnose` does.

        Parameters
        ----------
        loops : ndarray of shape (n_loops, n_samples, 3)
            Checked loops (:func:`~sktiction._validation.check_loops`), not normalised.
        analyses : list of LoopAnalysis
            One per loop (:func:`~sktiction.features._loops.analyse_loops`), shared
            with other users.
        status : ndarray of str or None, default=None
            :func:`~sktiction._validation.loop_status` with ``require_op=True`` (a scan
            passes it with ``check_swap=True``), if known.

        Returns
        -------
        report : pandas.DataFrame
            As :meth:`diagnose`.

        Examples
        --------
        >>> from sktiction._validation import check_loops
        >>> from sktiction.classifiers import LearnedStictionClassifier
        >>> from sktiction.datasets import make_loops
        >>> from sktiction.features._loops import analyse_loops
        >>> X, y = make_loops(40, n_samples=1000, random_state=0)
        >>> clf = LearnedStictionClassifier(max_iter=30, random_state=0).fit(X, y)
        >>> loops = check_loops(X[:3])
        >>> shared = clf.diagnose_analysed(loops, analyse_loops(loops))
        >>> bool((shared["in_domain"] == clf.diagnose(loops)["in_domain"]).all())
        True
        """
        check_is_fitted(self, "model_")
        if status is None:
            status = loop_status(loops, require_op=True)
        raw = pd.DataFrame(_raw_rows(loops, analyses, status), columns=_raw_names())
        _, op_scale = _centre_scale(loops[:, :, OP])
        for name in _OP_UNIT_FEATURES:  # in the normalised OP units the model learned
            raw[name] = raw[name] / op_scale
        feats = self._model_columns(raw, loop_lengths(loops))
        feats = pd.concat([feats, raw[list(DOMAIN_STATISTICS)]], axis=1)
        return self._judge(loops, feats)

    def predict_proba(self, X):
        """Calibrated class probabilities; NaN rows for loops outside the model's domain.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        proba : ndarray of shape (n_loops, 2)
            Columns follow ``classes_``; NaN where :meth:`diagnose` says
            ``in_domain`` is False.
        """
        p = said_unjudged(self.diagnose(X))["probability"].to_numpy()
        return np.column_stack([1.0 - p, p])

    def predict(self, X):
        """The stiction class where the calibrated probability is >= 0.5 in domain, else
        the other class (outside the domain the model gives no verdict: see
        :meth:`diagnose`).

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        y_pred : ndarray of shape (n_loops,)
        """
        return said_unjudged(self.diagnose(X))["prediction"].to_numpy()


def make_learned_classifier(random_state=None, **params):
    """An untrained :class:`LearnedStictionClassifier`.

    The default model's recipe (:func:`~sktiction.pretrained_classifier`)::

        X, y, meta = make_loops(1500, n_samples=2000, random_state=0, return_meta=True)
        keep = ((meta["y"] == 0) | meta["stiction_visible"]).to_numpy()  # slips show
        clf = make_learned_classifier(random_state=0).fit(X[keep], y[keep])

    Parameters
    ----------
    random_state : int or None, default=None
        Seed of the booster (no effect with the defaults: see
        :class:`LearnedStictionClassifier`).
    **params
        Other parameters of :class:`LearnedStictionClassifier`.

    Returns
    -------
    classifier : LearnedStictionClassifier

    Examples
    --------
    >>> from sktiction.classifiers import make_learned_classifier
    >>> make_learned_classifier(random_state=0).calibration
    'isotonic'
    """
    return LearnedStictionClassifier(random_state=random_state, **params)


__all__ = [
    "LearnedStictionClassifier",
    "make_learned_classifier",
    "make_loop_features",
    "normalise_loops",
]


def __getattr__(name):
    # names this module held before the thirty-seventh session moved them out: code that
    # imported them from here still finds them (imported on first use: _pretrained
    # imports this module)
    if name == "pretrained_classifier":
        from ._pretrained import pretrained_classifier

        return pretrained_classifier
    if name == "pv_op_coupling":
        from ._coupling import pv_op_coupling

        return pv_op_coupling
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
