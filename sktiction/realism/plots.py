"""Figure of the largest differences between simulated and measured loops."""

from __future__ import annotations

import numpy as np

from .compare import as_statistics

__all__ = ["plot_compare"]


def plot_compare(table, simulated, measured, *, n_effects=6, fig=None):
    """Draw the distributions of the ``n_effects`` most evident effects' statistics.

    One panel per effect (the first rows of ``table``): the statistic's empirical
    distribution on simulated and on measured loops (cumulative, so that point masses such as
    "no repeats at all" stay visible), titled with the effect, Cliff's delta and the
    Holm-adjusted p-value.

    Parameters
    ----------
    table : pandas.DataFrame
        Output of :func:`sktiction.realism.compare`.
    simulated, measured : array-like, Bunch or DataFrame
        The loops compared (or their :func:`~sktiction.realism.loop_statistics`).
    n_effects : int, default=6
        Panels to draw.
    fig : matplotlib Figure or None, default=None
        Figure to draw into (a new one when None).

    Returns
    -------
    fig : matplotlib Figure

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.realism import compare, plot_compare
    >>> sim, _ = make_loops(10, 300, world="classic", random_state=0)
    >>> meas, _ = make_loops(10, 300, world="classic", random_state=1)
    >>> fig = plot_compare(compare(sim, meas, domain=False), sim, meas, n_effects=2)
    >>> len(fig.axes)
    2
    """
    import matplotlib.pyplot as plt

    if not (isinstance(n_effects, (int, np.integer)) and n_effects >= 1):
        raise ValueError(f"n_effects must be an integer >= 1; got {n_effects!r}.")
    s_stats, m_stats = as_statistics(simulated), as_statistics(measured)
    rows = table.head(n_effects)
    ncols = min(3, len(rows))
    nrows = int(np.ceil(len(rows) / ncols))
    if fig is None:
        fig = plt.figure(figsize=(4.2 * ncols, 3.2 * nrows))
    axes = fig.subplots(nrows, ncols, squeeze=False).ravel()
    for ax, (_, row) in zip(axes, rows.iterrows()):
        for stats, label, colour in ((s_stats, "simulated", "C0"), (m_stats, "measured", "C3")):
            v = np.sort(stats[row["statistic"]].to_numpy(dtype=float))
            v = v[np.isfinite(v)]
            if len(v):
                ax.step(v, np.arange(1, len(v) + 1) / len(v), where="post", color=colour,
                        label=f"{label} (n={len(v)})")  # fmt: skip
        mark = "*" if row["significant"] else ""
        ax.set_title(
            f"{row['effect']}{mark}\ndelta={row['effect_size']:+.2f}, p={row['p_value']:.2g}",
            fontsize=9,
        )
        ax.set_xlabel(row["statistic"], fontsize=8)
        ax.set_ylabel("share of loops <= x", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7, loc="lower right")
    for ax in axes[len(rows) :]:
        ax.set_visible(False)
    auc = table.attrs.get("domain_auc", np.nan)
    if np.isfinite(auc):
        fig.suptitle(f"domain AUC (simulated vs measured) = {auc:.2f}", fontsize=10)
    fig.tight_layout()
    return fig
