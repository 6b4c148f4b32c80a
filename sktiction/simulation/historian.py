"""Recording effects of plant historians and sensors, applied to the recorded signals.

Each is a *recording* :class:`~sktiction.simulation.Effect`: it transforms the recorded
``pv``, ``op``, ``sp`` arrays after the loop ran, so the controller never sees it. Sizes are
given as a share of each channel's 5-95 % range in the record (its *span*), so one setting
means the same on loops of any scale. Each effect has a statistic of
:func:`sktiction.realism.loop_statistics` that detects it (see :data:`sktiction.realism.EFFECTS`):

=======================  ===================================  ======================
effect                   what the historian or sensor does    statistic
=======================  ===================================  ======================
HoldLastValue            whole rows frozen, then all jump     ``hold_fraction``
DeadbandCompression      each tag stored when it moved more   ``independent_freeze``
                         than a band (exception deviation)
SwingingDoorCompression  lines drawn between the points a     ``line_share``
                         swinging door stored (interpolated)
IntervalAveraging        trailing mean over an interval       ``diff_acf_min``
SpanQuantization         values on a grid                     ``pv_level_reuse``
Spikes                   isolated wild samples                ``spike_rate``
SensorDrift              slow ramp added to the measurement   ``pv_drift``
ShortRecord              record cut short (NaN padding)       ``n_samples``
=======================  ===================================  ======================
"""

from __future__ import annotations

import functools
import numbers

import numpy as np
from numba import njit

from .._validation import CHANNELS, check_positive
from .effects import Effect

__all__ = [
    "HoldLastValue",
    "DeadbandCompression",
    "SwingingDoorCompression",
    "IntervalAveraging",
    "SpanQuantization",
    "Spikes",
    "SensorDrift",
    "ShortRecord",
]


def _check_channels(channels):
    channels = tuple(channels)
    bad = [c for c in channels if c not in CHANNELS]
    if bad or not channels:
        raise ValueError(f"channels must be a non-empty subset of {CHANNELS}; got {channels!r}.")
    return channels


def _check_share(value, name, upper=1.0):
    return check_positive(value, name, upper=upper)


def _span(x):
    """5-95 % range over the finite samples (0 when there are none).

    ``np.percentile(x, [5, 95])`` (linear method) computed the way numpy does, in one
    partition and without its per-call overhead: the same value to the last bit.
    """
    x = x[np.isfinite(x)]
    n = len(x)
    if n < 2:
        return 0.0
    i, kth, t = _span_positions(n)
    x.partition(kth)  # x is a copy already
    a, b = x[i], x[i + 1]
    d = b - a
    lo, hi = np.where(t < 0.5, a + d * t, b - d * (1 - t))  # numpy's lerp
    return float(hi - lo)


_SPAN_Q = np.array([5.0, 95.0]) / 100


@functools.lru_cache(maxsize=64)
def _span_positions(n):
    """Where :func:`_span` reads a sorted record of ``n`` samples: the lower indices, the
    indices to partition at and the interpolation weights (records share a few lengths)."""
    v = (n - 1) * _SPAN_Q
    i = np.floor(v)
    t = v - i
    i = i.astype(np.intp)
    kth = np.unique(np.concatenate([i, i + 1]))
    for a in (i, kth, t):
        a.flags.writeable = False
    return i, kth, t


def _noise_sd(x):
    """Robust noise sd from second differences (white noise: var(d2) = 6 sd**2)."""
    d2 = np.diff(x[np.isfinite(x)], 2)
    d2 = d2[d2 != 0]  # frozen samples are not noise
    if len(d2) < 5:
        return 0.0
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6.0))


def _unit(x, unit):
    """Scale of a channel: its 5-95 % range, or its noise sd."""
    return _span(x) if unit == "span" else _noise_sd(x)


def _check_unit(unit):
    if unit not in ("span", "noise"):
        raise ValueError(f"unit must be 'span' or 'noise'; got {unit!r}.")
    return unit


def _finite_length(sig):
    """Samples before the NaN padding (from PV)."""
    idx = np.flatnonzero(np.isfinite(np.asarray(sig["pv"], dtype=float)))
    return idx[-1] + 1 if len(idx) else 0


class _Recording(Effect):
    kind = "recording"

    def _present(self, signals):
        return [c for c in self.channels if c in signals]


class HoldLastValue(_Recording):
    """Historian hold-last-value: whole rows frozen in runs, then all tags jump together.

    A stale historian (or a collection gap filled with the last value) repeats the previous
    row: PV, OP and SP freeze on the same samples, unlike per-tag compression.

    Parameters
    ----------
    fraction : float
        Sets the share of rows frozen, in (0, 1]. Each run follows an unheld row, so the
        expected share is ``mean_run / (mean_run / fraction + 1)``, a little below
        ``fraction`` (0.28 for 0.3 at runs of 5, 0.40 for 0.5 at runs of 2) and at most
        ``mean_run / (mean_run + 1)``; kept as it is so that worlds made before are made
        again to the bit.
    mean_run : float, default=5.0
        Mean length of a frozen run in samples (>= 1); run lengths are geometric.
    channels : tuple of str, default=("pv", "op", "sp")
        Channels frozen together.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import HoldLastValue
    >>> sig = {"pv": np.arange(2000.0), "op": np.arange(2000.0), "sp": np.zeros(2000)}
    >>> out = HoldLastValue(0.3).record(sig, 1.0, np.random.default_rng(0))
    >>> frozen = np.diff(out["pv"]) == 0
    >>> bool(0.2 < frozen.mean() < 0.4), bool(np.all(frozen == (np.diff(out["op"]) == 0)))
    (True, True)
    """

    def __init__(self, fraction, mean_run=5.0, channels=CHANNELS):
        self.fraction = _check_share(fraction, "fraction")
        if not (isinstance(mean_run, numbers.Real) and mean_run >= 1):
            raise ValueError(f"mean_run must be a number >= 1; got {mean_run!r}.")
        self.mean_run = float(mean_run)
        self.channels = _check_channels(channels)

    def mask(self, n_samples, rng):
        """Boolean array, True on rows that repeat the row before."""
        f = min(self.fraction, 0.99)
        mean_gap = self.mean_run * (1.0 - f) / f
        p_gap, p_run = 1.0 / (1.0 + mean_gap), 1.0 / self.mean_run
        # gap, run, gap, run, ... until a gap ends past the record: draw a batch that
        # surely covers the record, then rewind and draw exactly the ones used, so the
        # generator ends where drawing them one at a time would leave it
        state = rng.bit_generator.state
        size = 2 * int(n_samples / (self.mean_run + mean_gap)) + 21
        while True:
            p = np.where(np.arange(size) % 2 == 0, p_gap, p_run)
            steps = rng.geometric(p)
            ends = np.cumsum(steps)
            past = np.flatnonzero((ends >= n_samples) & (np.arange(size) % 2 == 0))
            if len(past):
                break
            rng.bit_generator.state = state
            size *= 2
        used = past[0] + 1
        rng.bit_generator.state = state
        ends = np.cumsum(rng.geometric(p[:used]))
        # runs start where a gap ends (even entries) and stop where they end (odd ones)
        starts, stops = ends[:-1:2], np.minimum(ends[1::2], n_samples)
        delta = np.zeros(n_samples + 1, dtype=np.int64)
        delta[starts] += 1  # starts and stops are each strictly increasing
        delta[stops] -= 1
        return np.cumsum(delta[:-1]) > 0

    def record(self, signals, ts, rng):
        n = len(signals["pv"])
        held = self.mask(n, rng)
        held[_finite_length(signals) :] = False  # the NaN padding stays padding
        # index of the last row that was stored, for every row
        idx = np.where(held, 0, np.arange(n))
        np.maximum.accumulate(idx, out=idx)
        out = dict(signals)
        for c in self._present(signals):
            out[c] = np.asarray(signals[c], dtype=float)[idx]
        return out


@njit(cache=True)
def _deadband(x, band):
    out = np.empty_like(x)
    last = x[0]
    for k in range(len(x)):
        v = x[k]
        if not np.isfinite(v):
            out[k] = v
            continue
        if not np.isfinite(last) or abs(v - last) > band:
            last = v
        out[k] = last
    return out


class DeadbandCompression(_Recording):
    """Per-tag exception-deviation compression: a value is stored when it moved more than a band.

    Each tag keeps its last stored value until the signal departs from it by more than
    ``band`` times the tag's span; tags freeze independently (unlike :class:`HoldLastValue`),
    and the stored values stay off any grid (unlike quantisation). Retrieval repeats the last
    stored value (step interpolation), as trend displays of compressed tags do.

    Parameters
    ----------
    band : float
        Deadband as a share of each channel's 5-95 % range, in (0, 1]; with
        ``unit="noise"``, in units of the channel's noise sd (> 0, at most 100).
    channels : tuple of str, default=("pv", "op")
    unit : {"span", "noise"}, default="span"
        What ``band`` is measured in. Noise units reproduce how often a tag freezes on
        loops whose noise differs from the ones the band was measured on.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import DeadbandCompression
    >>> x = np.sin(np.arange(500) / 20)
    >>> out = DeadbandCompression(0.1, channels=("pv",)).record({"pv": x}, 1.0, None)
    >>> bool(np.mean(np.diff(out["pv"]) == 0) > 0.5), bool(np.max(np.abs(out["pv"] - x)) <= 0.2)
    (True, True)
    """

    def __init__(self, band, channels=("pv", "op"), unit="span"):
        self.unit = _check_unit(unit)
        self.band = _check_share(band, "band", upper=1.0 if unit == "span" else 100.0)
        self.channels = _check_channels(channels)

    def record(self, signals, ts, rng):
        out = dict(signals)
        for c in self._present(signals):
            x = np.asarray(signals[c], dtype=float)
            out[c] = _deadband(x, self.band * _unit(x, self.unit))
        return out


@njit(cache=True)
def _swinging_door(x, dev):
    """``x`` (finite) as an interpolated export of the points a swinging door of deviation
    ``dev`` stores: each stored point ends the last line from the point before that kept
    every sample within ``dev``; straight lines are drawn between them."""
    n = len(x)
    out = x.copy()
    if n < 3:
        return out
    keep = np.zeros(n, dtype=np.bool_)
    keep[0] = keep[n - 1] = True
    a, up, lo = 0, -np.inf, np.inf
    for i in range(1, n):
        up = max(up, (x[i] - x[a] - dev) / (i - a))
        lo = min(lo, (x[i] - x[a] + dev) / (i - a))
        if up > lo:  # no line from the stored point keeps sample i within the door
            a = i - 1
            keep[a] = True
            up, lo = x[i] - x[a] - dev, x[i] - x[a] + dev
    prev = 0
    for i in range(1, n):
        if keep[i]:
            for k in range(prev + 1, i):
                out[k] = x[prev] + (x[i] - x[prev]) * (k - prev) / (i - prev)
            prev = i
    return out


class SwingingDoorCompression(_Recording):
    """A swinging-door historian exported interpolated: straight lines between stored points.

    The historian stores a point only when no line from the last stored point keeps the
    samples since within ``deviation`` of it; an interpolated export (PI's) draws straight
    lines between the stored points. Unlike :class:`DeadbandCompression` (values held,
    stepped export) nothing repeats: the rows between stored points lie on lines, and
    the noise on them is gone (``noise_std`` reads the level from the stored points).

    Parameters
    ----------
    deviation : float
        Compression deviation as a share of each channel's 5-95 % range, in (0, 1].
    channels : tuple of str, default=("pv", "op")

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import SwingingDoorCompression
    >>> rng = np.random.default_rng(0)
    >>> x = np.sin(np.arange(2000) / 50) + rng.normal(0, 0.02, 2000)
    >>> out = SwingingDoorCompression(0.03, channels=("pv",)).record({"pv": x}, 1.0, None)
    >>> bent = np.abs(np.diff(out["pv"], 2)) > 1e-9  # rows where a stored point bends it
    >>> int(bent.sum()), bool(np.max(np.abs(out["pv"] - x)) < 0.1)
    (53, True)
    """

    def __init__(self, deviation, channels=("pv", "op")):
        self.deviation = _check_share(deviation, "deviation")
        self.channels = _check_channels(channels)

    def record(self, signals, ts, rng):
        out = dict(signals)
        for c in self._present(signals):
            x = np.array(signals[c], dtype=float)
            ok = np.isfinite(x)
            if ok.sum() >= 3:
                x[ok] = _swinging_door(x[ok], self.deviation * _span(x))
            out[c] = x
        return out


class IntervalAveraging(_Recording):
    """Historian interval averages: each stored sample is the mean of the last ``window`` ones.

    Parameters
    ----------
    window : int
        Averaging interval in samples (>= 2).
    channels : tuple of str, default=("pv", "op")

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import IntervalAveraging
    >>> out = IntervalAveraging(2, channels=("pv",)).record({"pv": np.array([0., 2, 4])}, 1., None)
    >>> out["pv"].tolist()
    [0.0, 1.0, 3.0]
    """

    def __init__(self, window, channels=("pv", "op")):
        if not (isinstance(window, numbers.Integral) and window >= 2):
            raise ValueError(f"window must be an integer >= 2; got {window!r}.")
        self.window = int(window)
        self.channels = _check_channels(channels)

    def record(self, signals, ts, rng):
        out = dict(signals)
        m = self.window
        for c in self._present(signals):
            # the first samples average what exists so far (no start-up artefact)
            out[c] = _trailing_mean(np.asarray(signals[c], dtype=float), m)
        return out


@njit(cache=True)
def _trailing_mean(x, m):
    """Mean of the last ``m`` samples (fewer at the start), from running sums as
    ``np.cumsum`` makes them, so the result is the same to the last bit."""
    n = len(x)
    c0 = np.zeros(n + 1)
    if n:
        c0[1] = x[0]
    for k in range(1, n):
        c0[k + 1] = c0[k] + x[k]
    out = np.empty(n)
    for k in range(1, n + 1):
        lo = max(k - m, 0)
        out[k - 1] = (c0[k] - c0[lo]) / (k - lo)
    return out


class SpanQuantization(_Recording):
    """Values rounded to a grid whose step is a share of each channel's span.

    Like :class:`~sktiction.simulation.Quantization`, with a step relative to the record
    (coarse A/D converters, integer percent, few stored digits).

    Parameters
    ----------
    step : float
        Grid step as a share of the channel's 5-95 % range, in (0, 1]; with
        ``unit="noise"``, in units of the channel's noise sd (> 0, at most 100).
    channels : tuple of str, default=("pv",)
    unit : {"span", "noise"}, default="span"
        What ``step`` is measured in (noise units reproduce how often values revisit a
        level on loops whose noise differs).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import SpanQuantization
    >>> x = np.linspace(0, 1, 101)
    >>> out = SpanQuantization(0.1).record({"pv": x}, 1.0, None)
    >>> len(np.unique(out["pv"]))
    12
    """

    def __init__(self, step, channels=("pv",), unit="span"):
        self.unit = _check_unit(unit)
        self.step = _check_share(step, "step", upper=1.0 if unit == "span" else 100.0)
        self.channels = _check_channels(channels)

    def record(self, signals, ts, rng):
        out = dict(signals)
        for c in self._present(signals):
            x = np.asarray(signals[c], dtype=float)
            q = self.step * _unit(x, self.unit)
            out[c] = np.round(x / q) * q if q > 0 else x
        return out


class Spikes(_Recording):
    """Isolated wild samples (transmitter glitches, communication errors).

    Parameters
    ----------
    rate : float
        Expected spikes per sample, in (0, 0.5).
    amplitude : float, default=1.0
        Spike size as a multiple of the channel's span (> 0); each spike is drawn uniformly
        in 0.5-1.5 times it, with a random sign.
    channels : tuple of str, default=("pv",)

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import Spikes
    >>> x = np.sin(np.arange(1000) / 20)
    >>> out = Spikes(0.01).record({"pv": x}, 1.0, np.random.default_rng(0))
    >>> int(np.sum(out["pv"] != x)) > 0
    True
    """

    def __init__(self, rate, amplitude=1.0, channels=("pv",)):
        self.rate = _check_share(rate, "rate", upper=0.5)
        self.amplitude = check_positive(amplitude, "amplitude")
        self.channels = _check_channels(channels)

    def record(self, signals, ts, rng):
        out = dict(signals)
        n = _finite_length(signals)
        for c in self._present(signals):
            x = np.asarray(signals[c], dtype=float).copy()
            hit = np.flatnonzero(rng.random(n) < self.rate)
            size = self.amplitude * _span(x[:n]) * rng.uniform(0.5, 1.5, len(hit))
            x[hit] += size * rng.choice([-1.0, 1.0], len(hit))
            out[c] = x
        return out


class SensorDrift(_Recording):
    """A slow linear drift added to the recorded measurement (a drifting transmitter).

    Parameters
    ----------
    size : float
        Total drift over the record as a multiple of the channel's span (> 0), random sign.
    channels : tuple of str, default=("pv",)

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import SensorDrift
    >>> x = np.sin(np.arange(1000) / 20)
    >>> out = SensorDrift(1.0).record({"pv": x}, 1.0, np.random.default_rng(0))
    >>> round(float(abs(out["pv"][-1] - x[-1])), 1)
    2.0
    """

    def __init__(self, size, channels=("pv",)):
        self.size = check_positive(size, "size")
        self.channels = _check_channels(channels)

    def record(self, signals, ts, rng):
        out = dict(signals)
        n = _finite_length(signals)
        ramp = np.zeros(len(signals["pv"]))
        ramp[:n] = np.linspace(0.0, 1.0, n) if n > 1 else 0.0
        sign = rng.choice([-1.0, 1.0])
        for c in self._present(signals):
            x = np.asarray(signals[c], dtype=float)
            out[c] = x + sign * self.size * _span(x[:n]) * ramp
        return out


class ShortRecord(_Recording):
    """Keep only the first ``n_samples`` samples; the rest becomes NaN padding.

    Parameters
    ----------
    n_samples : int
        Samples kept (>= 2).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import ShortRecord
    >>> ShortRecord(2).record({"pv": np.ones(4)}, 1.0, None)["pv"].tolist()
    [1.0, 1.0, nan, nan]
    """

    def __init__(self, n_samples):
        if not (isinstance(n_samples, numbers.Integral) and n_samples >= 2):
            raise ValueError(f"n_samples must be an integer >= 2; got {n_samples!r}.")
        self.n_samples = int(n_samples)

    def record(self, signals, ts, rng):
        out = dict(signals)
        for c, x in signals.items():
            x = np.asarray(x, dtype=float).copy()
            x[self.n_samples :] = np.nan
            out[c] = x
        return out
