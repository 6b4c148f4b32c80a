"""Plots for people who would rather look than read: one loop, its cycles and shapes."""

from __future__ import annotations

import numpy as np

from .._validation import OP, PV, SP, check_loops, loop_lengths


def plot_loop(X, *, loop=0, ts=1.0, templates=None, ax=None, title=None):
    """Plot PV, SP and OP of one loop with each analysed cycle and its best shapes.

    Cycles found by :class:`~sktiction.TemplateDistances` are shaded, alternately,
    and labelled with the best-matching OP/PV templates (``tri/rect`` means OP
    triangular, PV rectangular).

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP.
    loop : int, default=0
        Which loop to plot.
    ts : float, default=1.0
        Sampling time, for the time axis.
    templates : TemplateDistances or None, default=None
        Matcher used for the cycles; ``None`` uses the default one.
    ax : pair of matplotlib Axes or None, default=None
        Axes for PV/SP and for OP; ``None`` makes a new figure.
    title : str or None, default=None
        Figure title.

    Returns
    -------
    axes : ndarray of matplotlib Axes
        The PV/SP axes and the OP axes.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.reports import plot_loop
    >>> X, _ = make_loops(1, n_samples=1500, stiction_fraction=1.0, random_state=0)
    >>> axes = plot_loop(X)
    >>> len(axes)
    2
    """
    import matplotlib.pyplot as plt

    from ..features import TemplateDistances

    loops = check_loops(X)
    one = loops[loop : loop + 1]
    n = int(loop_lengths(one)[0])
    t = np.arange(n) * ts
    if ax is None:
        _, ax = plt.subplots(2, 1, sharex=True, figsize=(10, 5))
    ax = np.asarray(ax)
    ax[0].plot(t, one[0, :n, PV], lw=0.9, label="PV")
    if not np.isnan(one[0, :n, SP]).all():
        ax[0].plot(t, one[0, :n, SP], lw=0.9, ls="--", label="SP")
    ax[1].plot(t, one[0, :n, OP], lw=0.9, color="C2", label="OP")
    matcher = templates if templates is not None else TemplateDistances()
    if not np.isnan(one[0, :n, OP]).all():
        table = matcher.fit(one).cycle_table(one)
        for k, row in enumerate(table.itertuples()):
            for a in ax:
                a.axvspan(row.start * ts, row.end * ts, alpha=0.08 if k % 2 else 0.16, color="C1")
            label = f"{str(row.op_shape)[:4]}/{str(row.pv_shape)[:4]}"
            ax[1].annotate(label, ((row.start + row.end) / 2 * ts, 1.0),
                           xycoords=("data", "axes fraction"), ha="center", va="bottom",
                           fontsize=7)
    ax[0].set_ylabel("PV, SP")
    ax[1].set_ylabel("OP")
    ax[1].set_xlabel("time")
    for a in ax:
        a.legend(loc="upper right", fontsize=8)
    if title:
        ax[0].set_title(title)
    return ax
