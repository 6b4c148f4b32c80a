"""Compare simulated and measured loops effect by effect, and as a whole (domain AUC)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.stats import mannwhitneyu
from threadpoolctl import threadpool_limits

from .._validation import check_random_state_seed
from ._catalog import EFFECTS
from .statistics import STATISTIC_COLUMNS, loop_statistics

__all__ = ["compare", "domain_gap", "as_statistics"]

# Largest difference in the share of loops missing a statistic for it to enter the domain AUC.
_MISSING_GAP = 0.1


def as_statistics(loops):
    """Per-loop statistics from loops, a ``read_loops`` Bunch, or statistics already computed.

    Parameters
    ----------
    loops : array-like (n_loops, n_samples, n_channels), Bunch or pandas.DataFrame
        A DataFrame holding the columns of :func:`loop_statistics` is returned as is.

    Returns
    -------
    stats : pandas.DataFrame

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.realism import as_statistics
    >>> stats = as_statistics(np.random.default_rng(0).normal(size=(2, 50, 3)))
    >>> as_statistics(stats) is stats
    True
    """
    if isinstance(loops, pd.DataFrame) and set(STATISTIC_COLUMNS) <= set(loops.columns):
        return loops
    return loop_statistics(loops)


def _holm(p):
    """Holm's step-down adjustment of p-values (family-wise error rate)."""
    p = np.asarray(p, dtype=float)
    out = np.full_like(p, np.nan)
    ok = np.isfinite(p)
    m = int(ok.sum())
    if m == 0:
        return out
    idx = np.flatnonzero(ok)[np.argsort(p[ok])]
    adj = np.maximum.accumulate((m - np.arange(m)) * p[idx])
    out[idx] = np.minimum(adj, 1.0)
    return out


def _iqr(x):
    q1, q3 = np.percentile(x, [25, 75])
    return q3 - q1


def _one(sim, meas):
    """Median of each side, Cliff's delta (measured vs simulated), p-value, robust shift."""
    sim = sim[np.isfinite(sim)]
    meas = meas[np.isfinite(meas)]
    if len(sim) < 2 or len(meas) < 2:
        med_s = float(np.median(sim)) if len(sim) else np.nan
        med_m = float(np.median(meas)) if len(meas) else np.nan
        return med_s, med_m, np.nan, np.nan, np.nan
    med_s, med_m = float(np.median(sim)), float(np.median(meas))
    if np.all(sim == sim[0]) and np.all(meas == sim[0]):
        return med_s, med_m, 0.0, 1.0, 0.0
    res = mannwhitneyu(meas, sim, alternative="two-sided", method="asymptotic")
    delta = 2.0 * res.statistic / (len(sim) * len(meas)) - 1.0
    scale = 0.5 * (_iqr(sim) + _iqr(meas))
    scale = max(scale, 1e-9 * max(abs(med_s), abs(med_m)), 1e-300)
    return med_s, med_m, float(delta), float(res.pvalue), abs(med_m - med_s) / scale


def compare(simulated, measured, *, alpha=0.05, domain=True, cv=5, groups=None,
            random_state=0):
    """Effects of the catalog that set simulated loops apart from measured ones, clearest first.

    For each effect of :data:`sktiction.realism.EFFECTS`, its statistic of
    :func:`loop_statistics` is compared between the two sets with a two-sided Mann-Whitney U
    test (non-parametric, robust to outliers and to the statistics' odd distributions); the
    effect size is Cliff's delta, ``P(measured > simulated) - P(measured < simulated)``
    (-1 to 1); p-values are adjusted for the number of effects by Holm's method.

    Parameters
    ----------
    simulated, measured : array-like (n_loops, n_samples, n_channels), Bunch or DataFrame
        Loops (channels PV, OP, SP, NaN-padded), ``read_loops`` Bunches, or the output of
        :func:`loop_statistics` for them.
    alpha : float, default=0.05
        Family-wise error rate for ``significant``.
    domain : bool, default=True
        Also compute :func:`domain_gap` into ``result.attrs["domain_auc"]``.
    cv : int, default=5
        Folds of the domain classifier.
    groups : array-like of shape (n_measured,) or None, default=None
        Group of each measured loop (e.g. its valve tag) for the domain classifier's folds
        (:func:`domain_gap`).
    random_state : None, int or numpy.random.Generator, default=0
        Seed of the domain classifier's folds.

    Returns
    -------
    table : pandas.DataFrame
        One row per effect, sorted by ``|effect_size|`` then by the robust shift (difference of
        medians over the mean interquartile range), columns ``effect``, ``statistic``,
        ``simulated``, ``measured`` (medians), ``effect_size`` (Cliff's delta), ``p_value``
        (Holm-adjusted), ``significant`` (``p_value < alpha``), ``shift``, ``kind``,
        ``n_simulated``, ``n_measured`` (loops with a finite statistic) and ``simulator``.
        Effects whose statistic is missing on one side (e.g. no SP) get NaN and
        ``significant = False``. ``table.attrs["domain_auc"]``: cross-validated AUC of a
        classifier telling the two sets apart from all the statistics (0.5: no gap; 1:
        every loop betrays its origin), NaN when ``domain=False``.

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.realism import apply_effects, compare
    >>> from sktiction.simulation import HoldLastValue
    >>> sim, _ = make_loops(20, 400, world="classic", random_state=0)
    >>> meas, _ = make_loops(20, 400, world="classic", random_state=1)
    >>> meas = apply_effects(meas, [HoldLastValue(0.3)], random_state=0)
    >>> table = compare(sim, meas, domain=False)
    >>> str(table.loc[0, "effect"]), bool(table.loc[0, "significant"])
    ('hold_last_value', True)
    """
    s_stats = as_statistics(simulated)
    m_stats = as_statistics(measured)
    rows = []
    for e in EFFECTS.values():
        med_s, med_m, delta, p, shift = _one(
            s_stats[e.statistic].to_numpy(dtype=float), m_stats[e.statistic].to_numpy(dtype=float)
        )
        rows.append(
            {
                "effect": e.name,
                "statistic": e.statistic,
                "simulated": med_s,
                "measured": med_m,
                "effect_size": delta,
                "p_value": p,
                "shift": shift,
                "kind": e.kind,
                "n_simulated": int(np.isfinite(s_stats[e.statistic].to_numpy(float)).sum()),
                "n_measured": int(np.isfinite(m_stats[e.statistic].to_numpy(float)).sum()),
                "simulator": e.simulator,
            }
        )
    table = pd.DataFrame(rows)
    table["p_value"] = _holm(table["p_value"].to_numpy())
    table.insert(6, "significant", (table["p_value"] < alpha).to_numpy())
    key = pd.DataFrame(
        {"d": -table["effect_size"].abs().round(6).fillna(-1), "s": -table["shift"].fillna(0)}
    )
    order = np.lexsort((key["s"].to_numpy(), key["d"].to_numpy()))
    table = table.iloc[order].reset_index(drop=True)
    table.attrs["domain_auc"] = (
        domain_gap(s_stats, m_stats, cv=cv, groups=groups, random_state=random_state)
        if domain
        else np.nan
    )
    table.attrs["alpha"] = alpha
    return table


def domain_gap(
    simulated, measured, *, exclude=("n_samples",), cv=5, groups=None, random_state=0
):
    """Cross-validated AUC of a classifier telling simulated from measured loops.

    One number for the whole gap: a gradient-boosted tree classifier
    (:class:`~sklearn.ensemble.HistGradientBoostingClassifier`, NaN-aware, classes weighted
    equally) learns "measured" from the catalog's statistics; its stratified ``cv``-fold
    ROC AUC is 0.5 when the simulated loops are indistinguishable from the measured ones and
    1 when every loop betrays its origin.

    Left out: the record length (``exclude``; the caller of ``make_loops`` sets it, and the
    table reports it), and any statistic missing far more often on one side (by more than 10
    percentage points of the loops, e.g. SP statistics when only one side records SP): a
    missing channel is not a realism gap the simulator could close.

    Parameters
    ----------
    simulated, measured : array-like, Bunch or DataFrame
        As in :func:`compare`.
    exclude : tuple of str, default=("n_samples",)
        Statistics not given to the classifier.
    cv : int, default=5
        Folds (reduced to the size of the smaller set when needed, at least 2).
    groups : array-like of shape (n_measured,) or None, default=None
        Group of each measured loop, e.g. its valve tag: the folds keep a group together
        (stratified group folds; each simulated loop is its own group). Windows of one valve
        are near copies; split apart, the classifier recognises a valve it has already seen
        rather than telling measured from simulated, and the AUC rises.
    random_state : None, int or numpy.random.Generator, default=0

    Returns
    -------
    auc : float
        NaN when either set has fewer than 2 loops.

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.realism import apply_effects, domain_gap
    >>> from sktiction.simulation import SpanQuantization
    >>> sim, _ = make_loops(20, 300, world="classic", random_state=0)
    >>> meas, _ = make_loops(20, 300, world="classic", random_state=1)
    >>> domain_gap(sim, apply_effects(meas, [SpanQuantization(0.05)], random_state=0)) > 0.9
    True
    """
    from sklearn.metrics import roc_auc_score
    from sklearn.model_selection import StratifiedGroupKFold, StratifiedKFold

    s_stats = as_statistics(simulated)
    m_stats = as_statistics(measured)
    if groups is not None:  # checked first: a wrong length must not hide behind a NaN
        groups = np.asarray(groups).astype(str)
        if len(groups) != len(m_stats):
            raise ValueError(
                f"groups must have one entry per measured loop ({len(m_stats)}); "
                f"got {len(groups)}."
            )
    exclude = set(exclude)
    cols = []
    for c in dict.fromkeys(e.statistic for e in EFFECTS.values()):
        missing_s = np.isnan(s_stats[c].to_numpy(dtype=float)).mean()
        missing_m = np.isnan(m_stats[c].to_numpy(dtype=float)).mean()
        if c not in exclude and abs(missing_s - missing_m) <= _MISSING_GAP:
            cols.append(c)
    if not cols:
        return np.nan
    X = np.vstack(
        [s_stats[cols].to_numpy(dtype=float), m_stats[cols].to_numpy(dtype=float)]
    )
    y = np.r_[np.zeros(len(s_stats)), np.ones(len(m_stats))]
    n_min = int(min(len(s_stats), len(m_stats)))
    if n_min < 2:
        return np.nan
    seed = int(check_random_state_seed(random_state).integers(2**31 - 1))
    split_groups = None
    if groups is None:
        folds = StratifiedKFold(n_splits=max(2, min(cv, n_min)), shuffle=True, random_state=seed)
    else:
        n_groups = len(set(groups))
        if n_groups < 2:
            raise ValueError("groups must hold at least 2 groups.")
        sim_groups = np.array([f"simulated {i}" for i in range(len(s_stats))])
        split_groups = np.r_[sim_groups, np.char.add("measured ", groups)]
        folds = StratifiedGroupKFold(
            n_splits=max(2, min(cv, n_groups)), shuffle=True, random_state=seed
        )
    scores = np.empty(len(y))
    # one thread: the sets are small, and threads fight over shared cores
    with threadpool_limits(limits=1):
        _fit_folds(X, y, folds, seed, scores, split_groups)
    return float(roc_auc_score(y, scores))


def _fit_folds(X, y, folds, seed, scores, groups=None):
    from sklearn.ensemble import HistGradientBoostingClassifier

    for train, test in folds.split(X, y, groups):
        clf = HistGradientBoostingClassifier(
            max_iter=100, learning_rate=0.1, max_leaf_nodes=8, min_samples_leaf=5,
            class_weight="balanced", random_state=seed,
        )  # fmt: skip
        clf.fit(X[train], y[train])
        scores[test] = clf.predict_proba(X[test])[:, 1]
