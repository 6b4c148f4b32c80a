"""Composable effects around the compiled loop.

Two kinds, so that new effects never touch the core loop:

* **exogenous** effects return arrays the loop consumes, computed before it
  runs: :meth:`Effect.signals` gives a dict with any of the keys
  ``"setpoint"`` (added to the base setpoint), ``"output_load"`` (added to the
  plant output), ``"input_load"`` (added to the valve position at the plant
  input), ``"noise"`` (measurement noise, absolute units) and
  ``"noise_relative"`` (measurement noise in units of the reference PV
  standard deviation, see below). Contributions of several effects add up.
* **recording** effects transform the recorded ``pv``, ``op``, ``sp`` arrays
  after the loop: :meth:`Effect.record` (historian quantisation, compression).

Noise given by a signal-to-noise ratio needs the power of the signal. The
reference is the standard deviation of the measured PV over the second half of
a noise-free *pilot run* of the same loop (same loads, setpoint and valve);
the simulator runs it only when a relative noise is requested, so it costs one
extra noise-free simulation. ``SNR_dB = 20 log10(std(pv_pilot) / std(noise))``.
If the pilot PV does not move, a reference of 1 PV unit is used.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .._validation import CHANNELS, check_positive

__all__ = [
    "Effect",
    "WhiteNoise",
    "ARNoise",
    "RandomWalkLoad",
    "SetpointSteps",
    "SinusoidalDisturbance",
    "Quantization",
    "EXOGENOUS_KEYS",
]

EXOGENOUS_KEYS = ("setpoint", "output_load", "input_load", "noise", "noise_relative")


@njit(cache=True)
def _lfilter(b, a, x, z):
    """``scipy.signal.lfilter(b, a, x, zi=z)[0]`` to the last bit, without scipy's per-call
    overhead and with the state of first and second order filters in registers (scipy
    keeps it in memory, which doubles the time of each sample's chain of operations).

    ``b`` and ``a`` have equal length >= 2 and ``a[0] == 1`` (scipy's division by it changes
    nothing); ``z`` is consumed. Every sample takes scipy's operations in scipy's order,
    zero coefficients included, and numba fuses no multiply-add without ``fastmath``.
    """
    if len(a) == 2:
        return _lfilter1(b[0], b[1], a[1], x, z[0])
    if len(a) == 3:
        return _lfilter2(b[0], b[1], b[2], a[1], a[2], x, z[0], z[1])
    y = np.empty_like(x)
    m = len(a) - 1
    for k in range(len(x)):
        xk = x[k]
        y[k] = yk = z[0] + b[0] * xk
        for i in range(m - 1):
            z[i] = z[i + 1] + xk * b[i + 1] - yk * a[i + 1]
        z[m - 1] = xk * b[m] - yk * a[m]
    return y


@njit(cache=True)
def _lfilter1(b0, b1, a1, x, z0):
    y = np.empty_like(x)
    for k in range(len(x)):
        xk = x[k]
        y[k] = yk = z0 + b0 * xk
        z0 = xk * b1 - yk * a1
    return y


@njit(cache=True)
def _lfilter2(b0, b1, b2, a1, a2, x, z0, z1):
    y = np.empty_like(x)
    for k in range(len(x)):
        xk = x[k]
        y[k] = yk = z0 + b0 * xk
        z0 = z1 + xk * b1 - yk * a1
        z1 = xk * b2 - yk * a2
    return y


def _padded(num, den):
    """``num`` zero-padded to the length of ``den``, as scipy pads it (``den[0] == 1``)."""
    b = np.zeros(len(den))
    b[: len(num)] = num
    return b, np.asarray(den, dtype=float)


class Effect:
    """Base class. Subclasses set ``kind`` and implement one of the two hooks."""

    kind = "exogenous"

    def signals(self, n_samples, ts, rng):
        """Arrays of length ``n_samples`` keyed by :data:`EXOGENOUS_KEYS`."""
        return {}

    def record(self, signals, ts, rng):
        """Return transformed copies of the recorded ``{"pv", "op", "sp"}`` arrays."""
        return signals

    def _params(self):
        return dict(vars(self))

    def __repr__(self):
        params = ", ".join(f"{k}={v!r}" for k, v in self._params().items())
        return f"{type(self).__name__}({params})"


def _noise_scale(std, snr_db):
    if (std is None) == (snr_db is None):
        raise ValueError("give exactly one of std (> 0) or snr_db (finite, in dB).")
    if std is not None:
        return check_positive(std, "std"), False
    if not np.isfinite(snr_db):
        raise ValueError(f"snr_db must be a finite number of dB; got {snr_db!r}.")
    return 10.0 ** (-float(snr_db) / 20.0), True


class WhiteNoise(Effect):
    """Gaussian white measurement noise, by standard deviation or by SNR.

    Parameters
    ----------
    std : float or None
        Noise standard deviation in PV units.
    snr_db : float or None
        Signal-to-noise ratio in dB relative to the pilot-run PV (module docstring).
    where : {"loop", "record"}, default="loop"
        ``"loop"``: measurement noise the controller sees (exogenous effect).
        ``"record"``: added to the recorded PV only (recording effect; with
        ``snr_db`` relative to the recorded PV's standard deviation over the
        second half). Use it with valve models that a noisy OP would freeze,
        such as :class:`~sktiction.simulation.ChoudhuryValve`.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import WhiteNoise
    >>> WhiteNoise(snr_db=20)
    WhiteNoise(std=None, snr_db=20, where='loop')
    >>> sig = WhiteNoise(std=0.5).signals(4, 1.0, np.random.default_rng(0))
    >>> sorted(sig), sig["noise"].shape
    (['noise'], (4,))
    """

    def __init__(self, std=None, snr_db=None, where="loop"):
        _noise_scale(std, snr_db)
        self.std = std
        self.snr_db = snr_db
        if where not in ("loop", "record"):
            raise ValueError(f"where must be 'loop' or 'record'; got {where!r}.")
        self.where = where

    @property
    def kind(self):
        return "exogenous" if self.where == "loop" else "recording"

    def _unit(self, n_samples, rng):
        return rng.standard_normal(n_samples)

    def signals(self, n_samples, ts, rng):
        scale, relative = _noise_scale(self.std, self.snr_db)
        key = "noise_relative" if relative else "noise"
        return {key: scale * self._unit(n_samples, rng)}

    def record(self, signals, ts, rng):
        scale, relative = _noise_scale(self.std, self.snr_db)
        pv = np.asarray(signals["pv"])
        if relative:
            ref = pv[len(pv) // 2 :].std()
            scale *= ref if ref > 1e-12 else 1.0
        out = dict(signals)
        out["pv"] = pv + scale * self._unit(len(pv), rng)
        return out


class ARNoise(WhiteNoise):
    """Coloured AR(1) measurement noise ``n[k] = phi n[k-1] + e[k]``, unit-variance shape.

    Parameters
    ----------
    phi : float
        AR coefficient, ``0 <= phi < 1``.
    std, snr_db : float or None
        As in :class:`WhiteNoise` (of the stationary AR process).

    Examples
    --------
    >>> from sktiction.simulation import ARNoise
    >>> ARNoise(0.9, snr_db=30)
    ARNoise(phi=0.9, std=None, snr_db=30, where='loop')
    """

    def __init__(self, phi, std=None, snr_db=None, where="loop"):
        if not (isinstance(phi, (int, float)) and 0 <= phi < 1):
            raise ValueError(f"phi must be a number with 0 <= phi < 1; got {phi!r}.")
        self.phi = float(phi)
        super().__init__(std=std, snr_db=snr_db, where=where)

    def _unit(self, n_samples, rng):
        e = rng.standard_normal(n_samples) * np.sqrt(1 - self.phi**2)
        # stationary start: the first sample already has unit variance
        zi = np.array([self.phi * rng.standard_normal()])
        return _lfilter(*_padded([1.0], [1.0, -self.phi]), e, zi)


class RandomWalkLoad(Effect):
    """Slow load disturbance: a random walk with increments ``N(0, std^2)`` per sample.

    Parameters
    ----------
    std : float
        Increment standard deviation per sample (PV units at the output, %
        of span at the input).
    where : {"output", "input"}, default="output"
        Added to the plant output or to the plant input.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import RandomWalkLoad
    >>> load = RandomWalkLoad(0.01).signals(3, 1.0, np.random.default_rng(0))["output_load"]
    >>> load.shape, float(load[0])
    ((3,), 0.0)
    """

    def __init__(self, std, where="output"):
        self.std = check_positive(std, "std")
        if where not in ("output", "input"):
            raise ValueError(f"where must be 'output' or 'input'; got {where!r}.")
        self.where = where

    def signals(self, n_samples, ts, rng):
        walk = np.empty(n_samples)  # written in place: the arrays are long, the calls many
        walk[0] = 0.0
        np.cumsum(rng.standard_normal(n_samples - 1), out=walk[1:])
        walk *= self.std
        return {f"{self.where}_load": walk}


class SetpointSteps(Effect):
    """Setpoint steps: ``sizes[i]`` added from time ``times[i]`` on (cumulative).

    Parameters
    ----------
    times : sequence of float
        Step times, in the time unit of ``ts`` (t = 0 at the first sample).
    sizes : sequence of float
        Step sizes in PV units, same length as ``times``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import SetpointSteps
    >>> SetpointSteps([2.0], [5.0]).signals(4, 1.0, None)["setpoint"].tolist()
    [0.0, 0.0, 5.0, 5.0]
    """

    def __init__(self, times, sizes):
        times = [float(t) for t in np.atleast_1d(times)]
        sizes = [float(s) for s in np.atleast_1d(sizes)]
        if len(times) != len(sizes):
            raise ValueError(
                f"times and sizes must have the same length; got {len(times)} and {len(sizes)}."
            )
        if any(t < 0 or not np.isfinite(t) for t in times):
            raise ValueError(f"times must be finite and >= 0; got {times!r}.")
        self.times = tuple(times)
        self.sizes = tuple(sizes)

    def signals(self, n_samples, ts, rng):
        t = np.arange(n_samples) * ts
        sp = np.zeros(n_samples)
        for t0, size in zip(self.times, self.sizes, strict=True):
            if ts > 0:  # t increases: the samples from t0 on are a tail, cheaper than a mask
                sp[np.searchsorted(t, t0 - 1e-9 * ts) :] += size
            else:
                sp[t >= t0 - 1e-9 * ts] += size
        return {"setpoint": sp}


class SinusoidalDisturbance(Effect):
    """External periodic load ``amplitude sin(2 pi t / period + phase)``.

    Parameters
    ----------
    amplitude : float
        Amplitude (> 0), PV units at the output, % of span at the input.
    period : float
        Period (> 0), in the time unit of ``ts``.
    phase : float, default=0.0
        Phase in radians.
    where : {"output", "input"}, default="output"

    Examples
    --------
    >>> from sktiction.simulation import SinusoidalDisturbance
    >>> SinusoidalDisturbance(1.0, 4.0).signals(3, 1.0, None)["output_load"].round(6).tolist()
    [0.0, 1.0, 0.0]
    """

    def __init__(self, amplitude, period, phase=0.0, where="output"):
        self.amplitude = check_positive(amplitude, "amplitude")
        self.period = check_positive(period, "period")
        self.phase = float(phase)
        if where not in ("output", "input"):
            raise ValueError(f"where must be 'output' or 'input'; got {where!r}.")
        self.where = where

    def signals(self, n_samples, ts, rng):
        t = np.arange(n_samples) * ts
        wave = self.amplitude * np.sin(2 * np.pi * t / self.period + self.phase)
        return {f"{self.where}_load": wave}


class Quantization(Effect):
    """Recording effect: round recorded channels to multiples of ``step``.

    Parameters
    ----------
    step : float
        Quantisation step (> 0).
    channels : tuple of str, default=("pv",)
        Any of ``"pv"``, ``"op"``, ``"sp"``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import Quantization
    >>> out = Quantization(0.5).record({"pv": np.array([1.2, 1.3])}, 1.0, None)
    >>> out["pv"].tolist()
    [1.0, 1.5]
    """

    kind = "recording"

    def __init__(self, step, channels=("pv",)):
        self.step = check_positive(step, "step")
        channels = tuple(channels)
        bad = [c for c in channels if c not in CHANNELS]
        if bad:
            raise ValueError(f"channels must be among ('pv', 'op', 'sp'); got {bad!r}.")
        self.channels = channels

    def record(self, signals, ts, rng):
        out = dict(signals)
        for c in self.channels:
            out[c] = np.round(np.asarray(signals[c]) / self.step) * self.step
        return out
