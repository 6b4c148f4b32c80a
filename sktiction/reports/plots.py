"""Plots for people who would rather look than read: one loop, its cycles and shapes."""

from __future__ import annotations

import numpy as np

from .._validation import OP, PV, SP, check_loops, loop_lengths


def plot_loop(X, *, loop=0, ts=1.0, templates=None, ax=None, title=None, cycles=None):
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
    cycles : pandas.DataFrame or None, default=None
        This loop's rows of :meth:`~sktiction.TemplateDistances.cycle_table`, if
        already computed; ``None`` computes them.

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
    table = cycles
    if table is None and not np.isnan(one[0, :n, OP]).all():
        table = matcher.fit(one).cycle_table(one)
    if table is not None and len(table):
        _shade_cycles(ax, table, ts, n)
    ax[0].set_ylabel("PV, SP")
    ax[1].set_ylabel("OP")
    ax[1].set_xlabel("time")
    for a in ax:
        a.legend(loc="upper right", fontsize=8)
    if title:
        ax[0].set_title(title)
    return ax


def _shade_cycles(ax, table, ts, n, min_width=1 / 60):
    """Shade the cycles alternately, as one collection per shade and axis (an artist per
    cycle made a day's figure slow to draw), and label those wide enough to read."""
    start, end = table["start"].to_numpy(float) * ts, table["end"].to_numpy(float) * ts
    for k, alpha in ((0, 0.16), (1, 0.08)):
        spans = list(zip(start[k::2], (end - start)[k::2]))
        for a in ax:
            a.broken_barh(spans, (0, 1), transform=a.get_xaxis_transform(), alpha=alpha,
                          color="C1", lw=0)
    # a label needs about a sixtieth of the axis; narrower cycles would print over each other
    wide = (end - start) >= min_width * max(n - 1, 1) * ts
    for row in table[wide].itertuples():
        ax[1].annotate(f"{str(row.op_shape)[:4]}/{str(row.pv_shape)[:4]}",
                       ((row.start + row.end) / 2 * ts, 1.0), xycoords=("data", "axes fraction"),
                       ha="center", va="bottom", fontsize=7)


def loop_cycles(X, *, loop=0, templates=None):
    """The cycle table of one loop (empty when it has no analysed cycle or no OP).

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP.
    loop : int, default=0
        Which loop.
    templates : TemplateDistances or None, default=None
        Matcher; ``None`` uses the default one.

    Returns
    -------
    table : pandas.DataFrame
        Rows of :meth:`~sktiction.TemplateDistances.cycle_table` for that loop.
    """
    import pandas as pd

    from ..features import TemplateDistances

    one = check_loops(X)[loop : loop + 1]
    if np.isnan(one[0, :, OP]).all() or np.isnan(one[0, :, PV]).all():
        return pd.DataFrame()
    matcher = templates if templates is not None else TemplateDistances()
    return matcher.fit(one).cycle_table(one)


def plot_pv_op(X, *, loop=0, ax=None, cycles=None):
    """Plot PV against OP: a sticky valve draws parallelograms, a healthy loop ellipses.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP.
    loop : int, default=0
        Which loop.
    ax : matplotlib Axes or None, default=None
        Where to draw; ``None`` makes a new figure.
    cycles : pandas.DataFrame or None, default=None
        The loop's cycle table; the analysed cycles are drawn darker.

    Returns
    -------
    ax : matplotlib Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.reports.plots import plot_pv_op
    >>> X, _ = make_loops(1, n_samples=600, random_state=0)
    >>> plot_pv_op(X).get_xlabel()
    'OP'
    """
    import matplotlib.pyplot as plt

    one = check_loops(X)[loop]
    n = int(loop_lengths(one[None])[0])
    if ax is None:
        _, ax = plt.subplots(figsize=(4, 4))
    op, pv = one[:n, OP], one[:n, PV]
    ax.plot(op, pv, lw=0.5, color="0.6")
    if cycles is not None and len(cycles):
        a, b = int(cycles["start"].min()), int(cycles["end"].max())
        ax.plot(op[a:b], pv[a:b], lw=0.8, color="C0", label="analysed cycles")
        ax.legend(loc="upper right", fontsize=7)
    ax.set_xlabel("OP")
    ax.set_ylabel("PV")
    ax.set_title("PV against OP", fontsize=9)
    return ax


def plot_area_ratios(cycles, *, ax=None, margin=0.5):
    """Bar chart of the area ratio R of each cycle (Singhal & Salsbury 2005).

    Parameters
    ----------
    cycles : pandas.DataFrame
        A cycle table with column ``area_ratio``.
    ax : matplotlib Axes or None, default=None
        Where to draw; ``None`` makes a new figure.
    margin : float, default=0.5
        Stiction when R > 1 + margin: the line drawn.

    Returns
    -------
    ax : matplotlib Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(4, 3))
    if cycles is not None and len(cycles) and "area_ratio" in cycles:
        r = cycles["area_ratio"].to_numpy(dtype=float)
        ax.bar(np.arange(1, len(r) + 1), r, color=np.where(r > 1 + margin, "C3", "C0"))
        ax.axhline(1.0 + margin, color="C3", lw=0.8, ls="--", label=f"R = {1 + margin:g}")
        ax.axhline(1.0, color="0.5", lw=0.6)
        ax.legend(loc="upper right", fontsize=7)
    else:
        ax.text(0.5, 0.5, "no analysed cycle", ha="center", va="center",
                transform=ax.transAxes, fontsize=9, color="0.4")
    ax.set_xlabel("cycle")
    ax.set_ylabel("R")
    ax.set_title("area ratio R per cycle", fontsize=9)
    return ax


def plot_loop_summary(X, *, loop=0, ts=1.0, title=None, cycles=None):
    """One figure per loop: trend with cycles and shapes, PV against OP, R per cycle.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP.
    loop : int, default=0
        Which loop.
    ts : float, default=1.0
        Sampling time, for the time axis.
    title : str or None, default=None
        Figure title.
    cycles : pandas.DataFrame or None, default=None
        The loop's cycle table; ``None`` computes it (:func:`loop_cycles`).

    Returns
    -------
    fig : matplotlib Figure

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.reports.plots import plot_loop_summary
    >>> X, _ = make_loops(1, n_samples=800, random_state=0)
    >>> len(plot_loop_summary(X).axes)
    4
    """
    import matplotlib.pyplot as plt

    if cycles is None:
        cycles = loop_cycles(X, loop=loop)
    # fixed margins: a constrained layout took half of a report's time per figure
    fig = plt.figure(figsize=(12, 4.2))
    grid = fig.add_gridspec(2, 3, width_ratios=[3.2, 1.2, 1.2], left=0.065, right=0.99,
                            bottom=0.12, top=0.87, wspace=0.25, hspace=0.2)
    trend = fig.add_subplot(grid[0, 0])
    op_ax = fig.add_subplot(grid[1, 0], sharex=trend)
    plot_loop(X, loop=loop, ts=ts, ax=[trend, op_ax], cycles=cycles)
    trend.tick_params(labelbottom=False)  # the OP axes below carry the time axis
    plot_pv_op(X, loop=loop, ax=fig.add_subplot(grid[:, 1]), cycles=cycles)
    plot_area_ratios(cycles, ax=fig.add_subplot(grid[:, 2]))
    if title:
        fig.suptitle(title, fontsize=10)
    return fig
