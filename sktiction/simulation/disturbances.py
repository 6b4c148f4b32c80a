"""Exogenous effects of plant operation: coloured noise, process noise, drifts, setpoints.

These are the disturbances measured loops carry and clean simulations lack
(Thornhill & Horch 2007 list them among the causes of plant-wide oscillations;
Jelali & Huang 2010, ch. 2, among the confounders of stiction detection):

* :class:`BandLimitedNoise`: low-pass measurement noise (sensor and transmitter
  filtering), by standard deviation or SNR like
  :class:`~sktiction.simulation.WhiteNoise`.
* :class:`PVVariation`: PV's own variation, which OP does not explain: a slow
  low-pass component that makes up a given share of the PV variance, at the
  sensor (the controller never acts on it) or seen by the controller.
* :class:`ColouredLoad`: process noise, white noise through a low-pass filter,
  added at the plant output or input. Through a lightly damped loop it gives
  the irregular, amplitude-modulated oscillations of noise-driven loops.
* :class:`NarrowbandDisturbance`: a lightly damped resonator driven by white
  noise; an upstream oscillation whose amplitude and phase wander.
* :class:`SquareDisturbance`: a filtered square wave (an upstream on-off or
  limit-cycling unit): non-sinusoidal, but not caused by this valve.
* :class:`Drift`: slow piecewise-linear trend (feed changes, fouling); the
  loop rejects it and its OP ramps.
* :class:`CascadeSetpoint`: the setpoint of a cascade secondary loop, which
  the primary controller moves on nearly every sample.
* :class:`LoadStep`: a step in the load (a feed change), e.g. to move a loop
  off its initial rest before the recorded window starts.

All of them are exogenous effects (:class:`~sktiction.simulation.Effect`):
their arrays are drawn before the compiled loop runs.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_positive
from .effects import Effect, WhiteNoise, _lfilter, _padded

__all__ = [
    "BandLimitedNoise",
    "PVVariation",
    "ColouredLoad",
    "NarrowbandDisturbance",
    "SquareDisturbance",
    "Drift",
    "CascadeSetpoint",
    "LoadStep",
]


def _check_where(where):
    if where not in ("output", "input"):
        raise ValueError(f"where must be 'output' or 'input'; got {where!r}.")
    return where


def _lowpass_unit(n_samples, cutoff, order, rng):
    """Unit-variance low-pass noise: white noise through ``order`` equal first-order lags.

    Each lag has its corner frequency at about ``cutoff`` cycles per sample (< 0.5). A burn-in of
    a few time constants is drawn and dropped so that the first sample is stationary.
    """
    a = np.exp(-2.0 * np.pi * cutoff)
    b, den = _padded([(1.0 - a) ** order], _lag_power(a, order))
    burn = int(min(5.0 * order / (1.0 - a), 20_000))
    e = rng.standard_normal(n_samples + burn)
    out = _lfilter(b, den, e, np.zeros(order))[burn:]
    # stationary variance: sum of the squared impulse response
    h = _lfilter(b, den, _impulse(burn + 65), np.zeros(order))
    out /= np.sqrt(np.sum(h * h))
    return out


def _impulse(n):
    x = np.zeros(n)
    x[0] = 1.0
    return x


def _lag_power(a, order):
    """Coefficients of ``(1 - a z^-1)^order``, as ``np.poly(np.full(order, a))`` gives them.

    Each step multiplies by ``(1 - a z^-1)``: every coefficient is a sum of at most two
    products, so the order of the sums cannot change the result.
    """
    den = [1.0]
    for _ in range(order):
        den = [c - a * p for c, p in zip([*den, 0.0], [0.0, *den], strict=True)]
    return np.array(den)


class BandLimitedNoise(WhiteNoise):
    """Measurement noise through a low-pass filter (``order`` equal first-order lags).

    Parameters
    ----------
    cutoff : float
        Cut-off frequency in cycles per sample, ``0 < cutoff < 0.5``.
    std, snr_db, where
        As in :class:`~sktiction.simulation.WhiteNoise` (of the filtered noise).
    order : int, default=2
        Filter order (1-4).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import BandLimitedNoise
    >>> noise = BandLimitedNoise(0.05, std=1.0).signals(20000, 1.0, np.random.default_rng(0))
    >>> bool(0.9 < noise["noise"].std() < 1.1)
    True
    """

    def __init__(self, cutoff, std=None, snr_db=None, where="loop", order=2):
        if not (isinstance(cutoff, (int, float)) and 0 < cutoff < 0.5):
            raise ValueError(f"cutoff must be a number with 0 < cutoff < 0.5; got {cutoff!r}.")
        if order not in (1, 2, 3, 4):
            raise ValueError(f"order must be 1, 2, 3 or 4; got {order!r}.")
        self.cutoff = float(cutoff)
        self.order = int(order)
        super().__init__(std=std, snr_db=snr_db, where=where)

    def _unit(self, n_samples, rng):
        return _lowpass_unit(n_samples, self.cutoff, self.order, rng)


class PVVariation(BandLimitedNoise):
    """PV's own variation: a low-pass component carrying a share of the PV variance.

    Measured PV carries variation that OP does not explain: coloured sensor noise,
    disturbances entering at the sensor or after the valve, process variation the
    controller does not act on. This adds such a component of unit-variance shape
    (``order`` equal first-order lags at ``cutoff``) scaled so that it makes up
    ``share`` of the variance of PV plus component: its standard deviation is
    ``sqrt(share / (1 - share))`` times the reference PV's (the recorded PV's over its
    second half at the sensor, ``where="record"``; the noise-free pilot run's when the
    controller sees it, ``where="loop"``). It is :class:`BandLimitedNoise` with
    ``snr_db = 10 log10((1 - share) / share)``. It lowers the PV-OP correlation
    (``pv_op_corr`` of :func:`sktiction.realism.loop_statistics`) towards
    ``sqrt(1 - share)`` of its value without it.

    Parameters
    ----------
    share : float
        Share of the PV variance, ``0 < share < 1``.
    cutoff : float
        Cut-off frequency in cycles per sample, ``0 < cutoff < 0.5``.
    where : {"record", "loop"}, default="record"
        ``"record"``: at the sensor, the controller never sees it (a recording effect);
        ``"loop"``: in the measurement the controller acts on (an exogenous effect).
    order : int, default=1
        Filter order (1-4).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import PVVariation
    >>> pv = np.sin(np.arange(4000) / 20)
    >>> rec = PVVariation(0.5, 0.01).record({"pv": pv}, 1.0, np.random.default_rng(0))
    >>> u = rec["pv"] - pv
    >>> bool(0.35 < u.var() / (u.var() + pv[2000:].var()) < 0.65)
    True
    """

    def __init__(self, share, cutoff, where="record", order=1):
        if not (isinstance(share, (int, float)) and 0 < share < 1):
            raise ValueError(f"share must be a number with 0 < share < 1; got {share!r}.")
        self.share = float(share)
        super().__init__(
            cutoff, snr_db=10.0 * np.log10((1.0 - self.share) / self.share), where=where,
            order=order,
        )  # fmt: skip

    def _params(self):
        return {"share": self.share, "cutoff": self.cutoff, "where": self.where,
                "order": self.order}  # fmt: skip


class ColouredLoad(Effect):
    """Process noise: white noise through a low-pass filter, at the plant output or input.

    Parameters
    ----------
    std : float
        Standard deviation of the load (> 0): PV units at the output, % of span
        at the input.
    cutoff : float
        Cut-off frequency in cycles per sample, ``0 < cutoff < 0.5``.
    order : int, default=1
        Filter order (1-4).
    where : {"output", "input"}, default="output"

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import ColouredLoad
    >>> load = ColouredLoad(2.0, 0.01).signals(50000, 1.0, np.random.default_rng(0))
    >>> bool(1.7 < load["output_load"].std() < 2.3)
    True
    """

    def __init__(self, std, cutoff, order=1, where="output"):
        self.std = check_positive(std, "std")
        if not (isinstance(cutoff, (int, float)) and 0 < cutoff < 0.5):
            raise ValueError(f"cutoff must be a number with 0 < cutoff < 0.5; got {cutoff!r}.")
        if order not in (1, 2, 3, 4):
            raise ValueError(f"order must be 1, 2, 3 or 4; got {order!r}.")
        self.cutoff = float(cutoff)
        self.order = int(order)
        self.where = _check_where(where)

    def signals(self, n_samples, ts, rng):
        unit = _lowpass_unit(n_samples, self.cutoff, self.order, rng)
        unit *= self.std  # in place: a fresh array
        return {f"{self.where}_load": unit}


class NarrowbandDisturbance(Effect):
    """An oscillation of wandering amplitude and phase: a resonator driven by white noise.

    The second-order resonator ``1 / (s^2 + 2 zeta w s + w^2)``, discretised by
    its poles ``exp(s ts)``, has a spectral peak at ``period`` whose width is set
    by ``damping``; 0.01 is almost a sine, 0.3 a broad band.

    Parameters
    ----------
    amplitude : float
        Standard deviation times sqrt(2) (the amplitude of a sine of the same
        power), > 0; PV units at the output, % of span at the input.
    period : float
        Period of the peak, in the time unit of ``ts`` (> 2 ts).
    damping : float, default=0.05
        Damping ratio ``zeta``, ``0 < zeta < 1``.
    where : {"output", "input"}, default="output"

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import NarrowbandDisturbance
    >>> d = NarrowbandDisturbance(1.0, 50.0).signals(50000, 1.0, np.random.default_rng(0))
    >>> bool(0.6 < d["output_load"].std() < 0.85)
    True
    """

    def __init__(self, amplitude, period, damping=0.05, where="output"):
        self.amplitude = check_positive(amplitude, "amplitude")
        self.period = check_positive(period, "period")
        if not (isinstance(damping, (int, float)) and 0 < damping < 1):
            raise ValueError(f"damping must be a number with 0 < damping < 1; got {damping!r}.")
        self.damping = float(damping)
        self.where = _check_where(where)

    def signals(self, n_samples, ts, rng):
        if self.period <= 2 * ts:
            raise ValueError(f"period must exceed 2 ts = {2 * ts}; got {self.period!r}.")
        w = 2 * np.pi / self.period * ts  # rad per sample
        r = np.exp(-self.damping * w)
        a = [1.0, -2.0 * r * np.cos(w * np.sqrt(1 - self.damping**2)), r * r]
        burn = int(min(6.0 / (self.damping * w), 50_000))
        e = rng.standard_normal(n_samples + burn)
        b, a = _padded([1.0], a)
        out = _lfilter(b, a, e, np.zeros(2))[burn:]
        h = _lfilter(b, a, _impulse(burn + 257), np.zeros(2))
        out *= self.amplitude / np.sqrt(2.0 * np.sum(h * h))
        return {f"{self.where}_load": out}


class SquareDisturbance(Effect):
    """A square wave through a first-order lag: an upstream unit switching or limit-cycling.

    Parameters
    ----------
    amplitude : float
        Half the peak-to-peak of the square wave (> 0).
    period : float
        Period (> 0), in the time unit of ``ts``.
    lag : float, default=0.0
        Time constant of the first-order lag (>= 0), in the time unit of ``ts``.
    phase : float, default=0.0
        Phase in radians.
    jitter : float, default=0.0
        Relative standard deviation of each half-period's length (0-0.5), so
        that the switching is not perfectly regular.
    where : {"output", "input"}, default="output"

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import SquareDisturbance
    >>> SquareDisturbance(1.0, 4.0).signals(6, 1.0, np.random.default_rng(0))["output_load"]
    array([ 1.,  1., -1., -1.,  1.,  1.])
    """

    def __init__(self, amplitude, period, lag=0.0, phase=0.0, jitter=0.0, where="output"):
        self.amplitude = check_positive(amplitude, "amplitude")
        self.period = check_positive(period, "period")
        self.lag = check_positive(lag, "lag", strict=False)
        self.phase = float(phase)
        self.jitter = check_positive(jitter, "jitter", strict=False, upper=0.5)
        self.where = _check_where(where)

    def signals(self, n_samples, ts, rng):
        half = 0.5 * self.period / ts  # samples per half period
        n_half = int(1.5 * n_samples / half) + 10
        lengths = np.full(n_half, half)
        if self.jitter > 0:
            lengths = lengths * np.clip(1 + self.jitter * rng.standard_normal(n_half), 0.2, None)
        start = -(self.phase % (2 * np.pi)) / np.pi * half
        edges = start + np.concatenate([[0.0], np.cumsum(lengths)])
        idx = np.searchsorted(edges, np.arange(n_samples), side="right") - 1
        wave = self.amplitude * np.where(idx % 2 == 0, 1.0, -1.0)
        if self.lag > 0:
            a = np.exp(-ts / self.lag)
            wave = _lfilter(*_padded([1 - a], [1.0, -a]), wave, np.array([a * wave[0]]))
        return {f"{self.where}_load": wave}


class Drift(Effect):
    """Slow piecewise-linear drift through random knots, starting at 0.

    Parameters
    ----------
    amplitude : float
        Standard deviation of the change from one knot to the next (> 0).
    n_segments : int, default=2
        Number of linear segments over the record (>= 1), knots evenly spaced.
    where : {"output", "input"}, default="output"

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import Drift
    >>> d = Drift(1.0, n_segments=1).signals(5, 1.0, np.random.default_rng(0))["output_load"]
    >>> bool(np.allclose(np.diff(d, 2), 0)), float(d[0])
    (True, 0.0)
    """

    def __init__(self, amplitude, n_segments=2, where="output"):
        self.amplitude = check_positive(amplitude, "amplitude")
        if not (isinstance(n_segments, (int, np.integer)) and n_segments >= 1):
            raise ValueError(f"n_segments must be an integer >= 1; got {n_segments!r}.")
        self.n_segments = int(n_segments)
        self.where = _check_where(where)

    def signals(self, n_samples, ts, rng):
        knots = np.concatenate([[0.0], np.cumsum(rng.standard_normal(self.n_segments))])
        x = np.linspace(0, self.n_segments, n_samples)
        return {f"{self.where}_load": self.amplitude * np.interp(x, np.arange(len(knots)), knots)}


class CascadeSetpoint(Effect):
    """Setpoint of a cascade secondary loop: moves on nearly every sample.

    The primary controller's output is modelled as a low-pass random process
    (AR(1) with coefficient ``phi``, the primary loop's slow variation) plus a
    white part (the primary's own measurement noise through its gain).

    Parameters
    ----------
    std : float
        Standard deviation of the slow part (> 0), PV units.
    phi : float, default=0.98
        AR coefficient of the slow part, ``0 <= phi < 1``.
    jitter : float, default=0.2
        Standard deviation of the white part relative to ``std`` (>= 0).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import CascadeSetpoint
    >>> sp = CascadeSetpoint(1.0).signals(1000, 1.0, np.random.default_rng(0))["setpoint"]
    >>> bool(np.mean(np.diff(sp) != 0) > 0.99)
    True
    """

    def __init__(self, std, phi=0.98, jitter=0.2):
        self.std = check_positive(std, "std")
        if not (isinstance(phi, (int, float)) and 0 <= phi < 1):
            raise ValueError(f"phi must be a number with 0 <= phi < 1; got {phi!r}.")
        self.phi = float(phi)
        self.jitter = check_positive(jitter, "jitter", strict=False)

    def signals(self, n_samples, ts, rng):
        e = rng.standard_normal(n_samples)
        e *= np.sqrt(1 - self.phi**2)
        zi = np.array([self.phi * rng.standard_normal()])
        slow = _lfilter(*_padded([1.0], [1.0, -self.phi]), e, zi)
        # std * (slow + jitter * white), in place (fresh arrays)
        sp = rng.standard_normal(n_samples)
        sp *= self.jitter
        sp += slow
        sp *= self.std
        # the loop starts at rest on its setpoint: shift so that sp[0] = 0
        sp -= sp[0]
        return {"setpoint": sp}


class LoadStep(Effect):
    """A load step of ``size`` from time ``time`` on.

    Parameters
    ----------
    size : float
        Step size (PV units at the output, % of span at the input).
    time : float, default=0.0
        Time of the step (>= 0), in the time unit of ``ts``; the first sample stays
        at rest, so a step at 0 acts from the second sample on.
    where : {"output", "input"}, default="input"

    Examples
    --------
    >>> from sktiction.simulation import LoadStep
    >>> LoadStep(2.0).signals(4, 1.0, None)["input_load"].tolist()
    [0.0, 2.0, 2.0, 2.0]
    """

    def __init__(self, size, time=0.0, where="input"):
        self.size = float(size)
        if not np.isfinite(self.size):
            raise ValueError(f"size must be a finite number; got {size!r}.")
        self.time = check_positive(time, "time", strict=False)
        self.where = _check_where(where)

    def signals(self, n_samples, ts, rng):
        k0 = max(1, int(np.ceil(self.time / ts - 1e-9)))
        load = np.zeros(n_samples)
        load[k0:] = self.size
        return {f"{self.where}_load": load}
