"""DTW distances of each OP and PV cycle to its four shape templates (seed 001)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.utils.validation import check_is_fitted

from .._validation import check_loops, loop_status
from ._loops import LoopAnalysis, LoopTransformer, analyse_loops
from .area_ratio import loop_half_cycles
from .templates import SHAPES, match_cycles, range_extrema

SIGNALS = ("op", "pv")
BACKENDS = ("numba", "tslearn")


def _feature_names(signals):
    names = [f"{s}_dist_{shape}" for s in signals for shape in SHAPES]
    names += [f"{s}_share_{shape}" for s in signals for shape in SHAPES]
    return (*names, "n_cycles", "period", "oscillating")


def _nearest_cycles(reference, analysis):
    """For each reference cycle (start, mid, end), the analysis' full cycle nearest in time.

    PV lags OP by the loop's phase, so PV's own crossings bound its cycles; each OP
    cycle is paired with the PV cycle whose centre is closest. Without PV cycles the
    reference bounds are used as they are.
    """
    c = analysis.crossings
    if c.size < 3:
        return reference
    starts = np.flatnonzero(analysis.signs[:-2] == analysis.signs[0])
    if starts.size == 0:
        return reference
    own = np.column_stack([c[starts], c[starts + 1], c[starts + 2]])
    centres = own[:, [0, 2]].mean(axis=1)  # increasing, as the crossings are
    wanted = reference[:, [0, 2]].mean(axis=1)
    # nearest centre by bisection (linear in the cycles); a tie goes to the earlier one
    right = np.clip(np.searchsorted(centres, wanted), 1, max(centres.size - 1, 1))
    left = right - 1
    if centres.size == 1:
        return own[np.zeros(len(reference), dtype=int)]
    pick = np.where(
        np.abs(centres[left] - wanted) <= np.abs(centres[right] - wanted), left, right
    )
    return own[pick]


class TemplateDistances(LoopTransformer):
    """Shape of each OP and PV cycle, by DTW to templates generated per cycle.

    Cycles are located on OP (seed 001, steps 4-5) or on PV when ``signals`` has
    no OP; each OP cycle is paired with the PV cycle nearest in time. For every
    cycle four templates are generated (rectangular, triangular, sinusoidal,
    trapezoidal) with each half's duration and area matched to the data
    (section 4.2.1); cycle and templates are averaged into ``n_points`` bins and
    scaled by the cycle's RMS, and their DTW distances computed.

    Columns, per signal ``s`` in ``signals``: ``s_dist_<shape>`` (mean distance
    over the cycles), ``s_share_<shape>`` (share of cycles whose best match is that
    shape); then ``n_cycles``, ``period`` (median, samples) and ``oscillating``.
    A loop that does not oscillate or cannot be analysed gets NaN and
    ``oscillating = 0``. :meth:`cycle_table` gives the per-cycle detail.

    Parameters
    ----------
    n_points : int, default=32
        Bins per cycle.
    sakoe_chiba_radius : int or None, default=2
        DTW band in bins; ``None`` for unconstrained DTW as in seed 001.
    signals : tuple of {"op", "pv"}, default=("op", "pv")
        Signals whose cycles are matched. With ``"op"``, X must carry OP.
    dtw_backend : {"numba", "tslearn"}, default="numba"
        DTW implementation: the package's batched kernel or tslearn's ``dtw``
        (identical distances, much slower).
    min_cycles : int, default=3
        Consecutive regular cycles that make an oscillating stretch.

    Attributes
    ----------
    n_channels_in_ : int
        Channels of the input seen in ``fit``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction import TemplateDistances
    >>> t = np.arange(1500)
    >>> op = 50 + 5 * np.abs((t % 100) / 50 - 1)          # triangular OP
    >>> pv = 50 + np.sign(np.sin(2 * np.pi * (t + 25) / 100))  # square PV
    >>> X = np.stack([pv, op], axis=1)[None]
    >>> td = TemplateDistances().set_output(transform="pandas").fit(X)
    >>> out = td.transform(X)
    >>> float(out["op_share_triangular"][0]), float(out["pv_share_rectangular"][0])
    (1.0, 1.0)
    """

    def __init__(
        self,
        n_points=32,
        sakoe_chiba_radius=2,
        signals=SIGNALS,
        dtw_backend="numba",
        min_cycles=3,
    ):
        self.n_points = n_points
        self.sakoe_chiba_radius = sakoe_chiba_radius
        self.signals = signals
        self.dtw_backend = dtw_backend
        self.min_cycles = min_cycles

    @property
    def feature_names(self):
        return _feature_names(tuple(self.signals))

    @property
    def _needs_op(self):
        return "op" in tuple(self.signals)

    def _validate_params(self):
        signals = tuple(self.signals)
        if not signals or any(s not in SIGNALS for s in signals) or len(set(signals)) < len(
            signals
        ):
            raise ValueError(f"signals must be a non-empty subset of {SIGNALS}; got {signals!r}.")
        if int(self.n_points) != self.n_points or self.n_points < 8:
            raise ValueError(f"n_points must be an integer >= 8; got {self.n_points!r}.")
        r = self.sakoe_chiba_radius
        if r is not None and (int(r) != r or r < 0):
            raise ValueError(f"sakoe_chiba_radius must be None or an integer >= 0; got {r!r}.")
        if self.dtw_backend not in BACKENDS:
            raise ValueError(f"dtw_backend must be one of {BACKENDS}; got {self.dtw_backend!r}.")
        if int(self.min_cycles) != self.min_cycles or self.min_cycles < 1:
            raise ValueError(f"min_cycles must be an integer >= 1; got {self.min_cycles!r}.")

    def _cycles(self, loops, i, n):
        """Per-signal (analysis, bounds, distances) of one loop; None if it does not oscillate."""
        return self._cycles_analysed(LoopAnalysis(loops, i, n))

    def _cycles_analysed(self, loop):
        """:meth:`_cycles` from the loop's shared analysis, computed once per loop."""
        signals = tuple(self.signals)
        radius = self.sakoe_chiba_radius
        key = ("templates", signals, int(self.n_points), None if radius is None else int(radius),
               self.dtw_backend, int(self.min_cycles))
        return loop.memo(key, lambda: self._match(loop, signals))

    def _match(self, loop, signals):
        lead = "op" if "op" in signals else "pv"
        analyses = {s: loop.cycles(s, self.min_cycles) for s in signals}
        ref = analyses[lead]
        if not ref.oscillating or len(ref.cycles) == 0:
            return None
        bounds = {lead: ref.crossings[ref.cycles]}
        for s in signals:
            if s != lead:
                bounds[s] = _nearest_cycles(bounds[lead], analyses[s])
        out = {}
        for s in signals:
            d = match_cycles(
                analyses[s].centred,
                bounds[s],
                n_points=int(self.n_points),
                sakoe_chiba_radius=self.sakoe_chiba_radius,
                backend=self.dtw_backend,
            )
            out[s] = (analyses[s], bounds[s], d)
        return out

    def _transform_analysis(self, loop):
        found = self._cycles_analysed(loop)
        row = np.full(len(self.feature_names), np.nan)
        if found is None:
            row[-1] = 0.0
            return row
        k = len(SHAPES)
        for j, s in enumerate(self.signals):
            _, bounds, d = found[s]
            row[j * k : (j + 1) * k] = d.mean(axis=0)
            best = d.argmin(axis=1)
            share = np.bincount(best, minlength=k) / len(best)
            off = len(self.signals) * k
            row[off + j * k : off + (j + 1) * k] = share
        lead_bounds = found["op" if "op" in self.signals else "pv"][1]
        row[-3] = len(lead_bounds)
        row[-2] = float(np.median(lead_bounds[:, 2] - lead_bounds[:, 0]))
        row[-1] = 1.0
        return row

    def cycle_table(self, X):
        """One row per analysed cycle, for reports and for people who want to look.

        Parameters
        ----------
        X : array-like of shape (n_loops, n_samples, n_channels)
            Loops, channels PV, OP, SP.

        Returns
        -------
        table : pandas.DataFrame
            Columns ``loop, cycle, start, end, period, amplitude_pos,
            amplitude_neg`` (of the signal the cycles are located on),
            ``area_ratio`` (mean R of the control error's half-cycles inside the
            cycle), ``<s>_shape``, ``<s>_peak_to_peak`` and ``<s>_dist_<shape>``
            for each signal. Loops without analysed cycles have no rows.
        """
        check_is_fitted(self, "n_channels_in_")
        loops = check_loops(X)
        self._check_channels(loops)
        return self.cycle_table_analysed(loops, analyse_loops(loops))

    def cycle_table_analysed(self, loops, analyses, status=None):
        """:meth:`cycle_table` of checked loops whose analyses may already be done.

        Parameters
        ----------
        loops : ndarray of shape (n_loops, n_samples, 3)
            Checked loops.
        analyses : list of LoopAnalysis
            One per loop, shared with other users (see :meth:`transform_analysed`).
        status : ndarray of str or None, default=None
            :func:`~sktiction._validation.loop_status` with ``require_op`` as this
            transformer needs, if already known.

        Returns
        -------
        table : pandas.DataFrame
            As :meth:`cycle_table`.
        """
        if status is None:
            status = loop_status(loops, require_op=self._needs_op)
        lead = "op" if "op" in self.signals else "pv"
        parts = []
        for i, loop in enumerate(analyses):
            found = None if status[i] != "ok" else self._cycles_analysed(loop)
            if found is not None:
                parts.append(self._loop_cycle_table(i, loop, found, lead))
        if not parts:
            return pd.DataFrame()
        return pd.concat(parts, ignore_index=True)

    def _loop_cycle_table(self, position, loop, found, lead):
        """The cycle-table columns of one loop, one array per column; ``loop`` column:
        the loop's ``position`` in the analyses given (a scan passes a subset of a chunk's
        analyses, whose ``loop.i`` count in the whole chunk)."""
        ana, bounds, _ = found[lead]
        a, b = bounds[:, 0], bounds[:, 2]
        n_cyc = len(bounds)
        err, ratios, halves = loop_half_cycles(loop, None, self.min_cycles)
        # mean finite R of the error's half-cycles whose middle lies in [a, b): the
        # middles increase, so each cycle's halves are one run found by bisection
        mids = (err.crossings[halves] + err.crossings[halves + 1]) / 2 if halves.size else []
        mids = np.asarray(mids, dtype=float)
        finite = np.isfinite(ratios)
        csum = np.concatenate([[0.0], np.cumsum(np.where(finite, ratios, 0.0))])
        ccount = np.concatenate([[0], np.cumsum(finite)])
        lo, hi = np.searchsorted(mids, a, "left"), np.searchsorted(mids, b, "left")
        count = ccount[hi] - ccount[lo]
        with np.errstate(invalid="ignore", divide="ignore"):
            area = np.where(count > 0, (csum[hi] - csum[lo]) / count, np.nan)
        first = np.floor(a).astype(np.int64)
        top, bottom = range_extrema(ana.centred, first, np.ceil(b).astype(np.int64) + 1)
        cols = {
            "loop": np.full(n_cyc, position),
            "cycle": np.arange(n_cyc),
            "start": a,
            "end": b,
            "period": b - a,
            "amplitude_pos": top,
            "amplitude_neg": -bottom,
            "area_ratio": area,
        }
        for s in self.signals:
            sana, sb, d = found[s]
            hi_s, lo_s = range_extrema(
                sana.centred,
                np.floor(sb[:, 0]).astype(np.int64),
                np.ceil(sb[:, 2]).astype(np.int64) + 1,
            )
            cols[f"{s}_shape"] = np.asarray(SHAPES, dtype=object)[np.argmin(d, axis=1)]
            cols[f"{s}_peak_to_peak"] = hi_s - lo_s
            cols.update({f"{s}_dist_{sh}": d[:, q] for q, sh in enumerate(SHAPES)})
        return pd.DataFrame(cols)


def cycle_table(X, **params):
    """Per-cycle table of loops ``X``: ``TemplateDistances(**params).cycle_table(X)``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction import cycle_table
    >>> t = np.arange(1000)
    >>> op = np.abs((t % 100) / 50 - 1)
    >>> pv = np.sign(np.sin(2 * np.pi * (t + 25) / 100))
    >>> cycle_table(np.stack([pv, op], axis=1)[None])["op_shape"].iloc[0]
    'triangular'
    """
    return TemplateDistances(**params).fit(X).cycle_table(X)
