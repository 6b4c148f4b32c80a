"""Singhal and Salsbury's area ratio R = A1 / A2 of each half-cycle of the control error."""

from __future__ import annotations

import numpy as np

from ..cycles import horch_filter
from ..cycles._analysis import _analyze_cycles
from ._loops import LoopTransformer

FILTERS = (None, "horch")


def _integrals(cumulative, a, b):
    """Integrals from ``a`` to ``b`` (arrays of fractional indices) of the piecewise-linear
    signal whose trapezoidal cumulative integral is ``cumulative``: one interpolation
    for all half-cycles, O(n + h log n) instead of O(n) per half-cycle."""
    idx = np.arange(cumulative.size)
    ends = np.interp(np.concatenate([a, b]), idx, cumulative)
    return ends[a.size :] - ends[: a.size]


def half_cycle_ratios(analysis, signal=None):
    """R = A1 / A2 for each half-cycle of the oscillating stretches.

    A1 is the area from the half-cycle's opening zero crossing to its peak, A2
    from the peak to its closing crossing (seed 000, Fig. 1). Areas are exact
    integrals of the linearly interpolated signal between fractional crossing
    positions; the peak is taken on the analysis' smoothed signal so a noise spike
    cannot move it.

    Parameters
    ----------
    analysis : CycleAnalysis
        From :func:`~sktiction.cycles.analyze_cycles`.
    signal : ndarray or None, default=None
        Signal to integrate (e.g. Horch-filtered); ``analysis.centred`` by default.

    Returns
    -------
    ratios : ndarray
        One R per half-cycle (two per full cycle), in time order.
    halves : ndarray of int
        Index of each half-cycle (crossing number it starts at).
    """
    x = analysis.centred if signal is None else signal
    c = analysis.crossings
    halves = np.unique(np.concatenate([analysis.cycles[:, 0], analysis.cycles[:, 1]]))
    if halves.size == 0:
        return np.empty(0), halves
    # trapezoidal cumulative integral, one value per sample
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (x[1:] + x[:-1]))])
    a, b = c[halves], c[halves + 1]
    s, p = analysis.signs[halves], analysis.peaks[halves].astype(float)
    areas = _integrals(cumulative, np.concatenate([a, p]), np.concatenate([p, b]))
    a1, a2 = s * areas[: halves.size], s * areas[halves.size :]
    ok = (a2 > 0) & (a1 >= 0)
    ratios = np.full(halves.size, np.nan)
    ratios[ok] = a1[ok] / a2[ok]
    return ratios, halves


def _ratios(analysis, filter):
    signal = None
    if filter == "horch" and np.isfinite(analysis.period):
        signal = horch_filter(analysis.centred, analysis.period)
    return half_cycle_ratios(analysis, signal)


def loop_half_cycles(loop, filter=None, min_cycles=3):
    """Control-error analysis and per-half-cycle R of one loop, computed once per loop.

    Parameters
    ----------
    loop : LoopAnalysis
        The loop's shared analysis (:class:`~sktiction.features._loops.LoopAnalysis`).
    filter : {None, "horch"}, default=None
        As in :class:`AreaRatio`.
    min_cycles : int, default=3
        As in :class:`AreaRatio`.

    Returns
    -------
    analysis : CycleAnalysis
    ratios : ndarray
    halves : ndarray of int
        As :func:`half_cycle_ratios`.
    """
    analysis = loop.cycles("error", min_cycles)
    ratios, halves = loop.memo(
        ("half_cycle_ratios", filter, int(min_cycles)), lambda: _ratios(analysis, filter)
    )
    return analysis, ratios, halves


class AreaRatio(LoopTransformer):
    """Area ratio of the control error, per loop (Singhal and Salsbury, 2005).

    For each half-cycle of the control error (SP - PV; PV about its adaptive mean
    when there is no setpoint) in the stretches that oscillate, R = A1 / A2 is the
    ratio of the areas before and after its peak. A sticking valve feeds the plant a
    rectangular pulse train, so the error rises quickly and decays slowly: R > 1;
    aggressive tuning gives a sinusoid and R close to 1 (seed 000, section 2).

    Columns: ``area_ratio`` (mean R over the half-cycles), ``area_ratio_median``,
    ``n_half_cycles``, ``oscillating`` (1 when the error oscillates, see
    :func:`~sktiction.cycles.analyze_cycles`). A loop that does not oscillate
    or cannot be analysed (NaN gaps, constant, too short) gets NaN and
    ``oscillating = 0``.

    Parameters
    ----------
    filter : {None, "horch"}, default=None
        ``"horch"`` low-pass filters the error at three times its oscillation
        frequency before the areas are taken (seed 000, Eq. 23), run forwards and
        backwards so that peaks keep their place.
    min_cycles : int, default=3
        Consecutive regular cycles that make an oscillating stretch.

    Attributes
    ----------
    n_channels_in_ : int
        Channels of the input seen in ``fit``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction import AreaRatio
    >>> t = np.arange(2000.0)
    >>> square = np.sign(np.sin(2 * np.pi * t / 200))
    >>> pv = np.convolve(square, np.exp(-np.arange(300) / 20) / 20)[:2000]  # 1st order
    >>> X = np.stack([pv, np.full(2000, np.nan), np.zeros(2000)], axis=1)[None]
    >>> r = AreaRatio().fit_transform(X)[0, 0]
    >>> bool(r > 2)
    True
    """

    feature_names = ("area_ratio", "area_ratio_median", "n_half_cycles", "oscillating")

    def __init__(self, filter=None, min_cycles=3):
        self.filter = filter
        self.min_cycles = min_cycles

    def _validate_params(self):
        if self.filter not in FILTERS:
            raise ValueError(f"filter must be one of {FILTERS}; got {self.filter!r}.")
        if int(self.min_cycles) != self.min_cycles or self.min_cycles < 1:
            raise ValueError(f"min_cycles must be an integer >= 1; got {self.min_cycles!r}.")

    def half_cycles(self, error):
        """Analysis and per-half-cycle R of one control-error signal."""
        analysis = _analyze_cycles(error, min_cycles=int(self.min_cycles))
        return (analysis, *_ratios(analysis, self.filter))

    def _transform_analysis(self, loop):
        analysis, ratios, _ = loop_half_cycles(loop, self.filter, self.min_cycles)
        ratios = ratios[np.isfinite(ratios)]
        if not analysis.oscillating or ratios.size == 0:
            return [np.nan, np.nan, np.nan, 0.0]
        return [ratios.mean(), np.median(ratios), ratios.size, 1.0]
