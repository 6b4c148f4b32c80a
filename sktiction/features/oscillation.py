"""How each signal of a loop oscillates: index, periods and regularity of its components."""

from __future__ import annotations

import numpy as np

from ._loops import LoopTransformer

SIGNALS = ("pv", "op")
PER_SIGNAL = (
    "osc_index",
    "oscillating",
    "n_components",
    "period",
    "regularity",
    "coherence",
    "prominence",
    "period_2",
)


def _feature_names(signals):
    return tuple(f"{s}_{name}" for s in signals for name in PER_SIGNAL)


def oscillation_row(analysis):
    """The :data:`PER_SIGNAL` values of one :class:`~sktiction.cycles.CycleAnalysis`."""
    found = [c for c in analysis.components if c.index > 0.5]
    row = np.full(len(PER_SIGNAL), np.nan)
    row[0] = analysis.oscillation_index
    row[1] = float(analysis.oscillating)
    row[2] = len(found)
    if found:
        main = found[0]
        row[3:7] = main.period, main.regularity, main.coherence, np.log10(main.prominence)
        if len(found) > 1:
            row[7] = found[1].period
    return row


class OscillationFeatures(LoopTransformer):
    """Oscillation components of each loop's PV and OP (Thornhill et al., 2003).

    Each signal is split into components around its spectral peaks, and each
    component is scored from its band-limited autocorrelation
    (:func:`~sktiction.cycles.detect_oscillations`, read from the loop's shared
    :func:`~sktiction.cycles.analyze_cycles`, so a pipeline with the cycle
    features analyses each signal once).

    Columns, per signal ``s`` in ``signals``:

    - ``s_osc_index``: largest oscillation index of the components (0-1; 0.5 is
      the decision threshold);
    - ``s_oscillating``: 1 when a component oscillates (the decision every
      classifier uses), else 0;
    - ``s_n_components``: number of oscillating components (at most 3);
    - ``s_period``, ``s_regularity``, ``s_coherence``, ``s_prominence``: period
      (samples), Thornhill's regularity r, ACF coherence (0-1) and log10 spectral
      prominence of the strongest oscillating component (NaN when none);
    - ``s_period_2``: period of the second oscillating component (NaN when none).

    Loops that cannot be analysed get NaN; so does a signal the loop does not carry
    (NaN or constant OP).

    Parameters
    ----------
    signals : tuple of {"pv", "op"}, default=("pv", "op")
        Signals to describe.

    Attributes
    ----------
    n_channels_in_ : int
        Channels of the input seen in ``fit``.

    References
    ----------
    Thornhill, N. F., Huang, B., Zhang, H. (2003). Detection of multiple oscillations
    in control loops. J. Process Control 13, 91-100.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.features import OscillationFeatures
    >>> t = np.arange(2000)
    >>> op = 50 + 5 * np.sin(2 * np.pi * t / 80) + 2 * np.sin(2 * np.pi * t / 300)
    >>> pv = 50 + np.random.default_rng(0).normal(size=t.size)
    >>> X = np.stack([pv, op], axis=1)[None]
    >>> f = OscillationFeatures().set_output(transform="pandas").fit(X).transform(X)
    >>> f[["pv_oscillating", "op_oscillating", "op_n_components"]].iloc[0].tolist()
    [0.0, 1.0, 2.0]
    >>> round(f["op_period"].iloc[0]), round(f["op_period_2"].iloc[0] / 10) * 10
    (80, 300)
    """

    def __init__(self, signals=SIGNALS):
        self.signals = signals

    @property
    def feature_names(self):
        return _feature_names(tuple(self.signals))

    def _validate_params(self):
        signals = tuple(self.signals)
        if (
            not signals
            or any(s not in SIGNALS for s in signals)
            or len(set(signals)) < len(signals)
        ):
            raise ValueError(f"signals must be a non-empty subset of {SIGNALS}; got {signals!r}.")

    def _transform_analysis(self, loop):
        rows = []
        for s in self.signals:
            x = loop.signal(s)
            if np.isnan(x).any() or np.ptp(x) == 0:
                rows.append(np.full(len(PER_SIGNAL), np.nan))
            else:
                rows.append(oscillation_row(loop.cycles(s)))
        return np.concatenate(rows)
