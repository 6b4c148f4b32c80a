"""Linear plants with pure delay, discretised exactly with a zero-order hold.

Every plant is a continuous state-space model ``dx/dt = A x + B u(t - L)``,
``y = C x`` (deviation variables: zero input gives zero output). With the
input held constant over each sample (ZOH) and the delay split as
``L = m * ts + theta`` (``m`` integer, ``0 <= theta < ts``) the exact discrete
model is (Astrom & Wittenmark, *Computer-Controlled Systems*, section 2.3)::

    x[k+1] = Ad x[k] + B0 u[k-m] + B1 u[k-m-1],   y[k] = C x[k]

with ``B0 = int_0^{ts-theta} e^{A s} ds B`` and
``B1 = e^{A (ts-theta)} int_0^{theta} e^{A s} ds B``, so fractional delays are
handled exactly, not rounded.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

from .._validation import check_positive

__all__ = ["FOPTD", "SOPTD", "NthOrderLag", "IntegratingPlant"]


def _check_gain(gain):
    if not (isinstance(gain, (int, float, np.floating, np.integer)) and np.isfinite(gain)):
        raise ValueError(f"gain must be a finite nonzero number; got {gain!r}.")
    if gain == 0:
        raise ValueError("gain must be nonzero (any sign, != 0); got 0.")
    return float(gain)


def _phi_gamma(A, B, t):
    """Return ``e^{A t}`` and ``int_0^t e^{A s} ds B`` from one matrix exponential."""
    n = A.shape[0]
    M = np.zeros((n + 1, n + 1))
    M[:n, :n] = A * t
    M[:n, n] = B * t
    E = expm(M)
    return E[:n, :n], E[:n, n]


def _lag_chain(time_constants):
    """State space of ``prod 1 / (T_i s + 1)`` as a chain of first-order lags."""
    n = len(time_constants)
    A = np.zeros((n, n))
    B = np.zeros(n)
    for i, T in enumerate(time_constants):
        A[i, i] = -1.0 / T
        if i == 0:
            B[0] = 1.0 / T
        else:
            A[i, i - 1] = 1.0 / T
    C = np.zeros(n)
    C[-1] = 1.0
    return A, B, C


class _Plant:
    """Common machinery: exact ZOH discretisation with a fractional delay."""

    integrating = False

    def state_space(self):
        """Continuous model ``(A, B, C)`` of the delay-free part (gain included)."""
        raise NotImplementedError

    def discretize(self, ts):
        """Exact ZOH discretisation at sample time ``ts``.

        Returns
        -------
        A : ndarray of shape (n, n)
        B0, B1 : ndarray of shape (n,)
            Input vectors for ``u[k-m]`` and ``u[k-m-1]``.
        C : ndarray of shape (n,)
        m : int
            Whole-sample part of the delay.
        """
        ts = check_positive(ts, "ts")
        A, B, C = self.state_space()
        m = int(math.floor(self.delay / ts + 1e-12))
        theta = max(self.delay - m * ts, 0.0)
        Phi0, B0 = _phi_gamma(A, B, ts - theta)
        if theta > 0:
            Phi1, g1 = _phi_gamma(A, B, theta)
            Ad = Phi0 @ Phi1  # e^{A ts} = e^{A (ts - theta)} e^{A theta}
            B1 = Phi0 @ g1
        else:
            Ad = Phi0
            B1 = np.zeros_like(B0)
        return Ad, B0, B1, C, m

    def foptd(self):
        """First-order-plus-dead-time approximation used for tuning.

        Returns
        -------
        gain, time_constant, delay : float
            For integrating plants ``time_constant`` is ``inf``, ``gain`` the
            velocity gain and ``delay`` the delay plus the lag time constant.
        """
        raise NotImplementedError

    def __repr__(self):
        params = ", ".join(f"{k}={v!r}" for k, v in self._params().items())
        return f"{type(self).__name__}({params})"


class NthOrderLag(_Plant):
    """n-th order lag ``K e^{-Ls} / (T s + 1)^n`` (Singhal & Salsbury 2005, Eq. 3).

    Parameters
    ----------
    gain : float
        Static gain ``K`` (nonzero; its sign sets the controller action).
    time_constant : float
        Time constant ``T > 0`` of each of the ``n`` equal lags.
    delay : float, default=0.0
        Pure delay ``L >= 0``.
    order : int, default=1
        Number of lags ``n >= 1``.

    Examples
    --------
    >>> from sktiction.simulation import NthOrderLag
    >>> plant = NthOrderLag(1.0, 1.0, order=2)
    >>> [round(v, 3) for v in plant.foptd()]
    [1.0, 1.718, 0.282]
    """

    def __init__(self, gain=1.0, time_constant=1.0, delay=0.0, order=1):
        self.gain = _check_gain(gain)
        self.time_constant = check_positive(time_constant, "time_constant")
        self.delay = check_positive(delay, "delay", strict=False)
        if not isinstance(order, (int, np.integer)) or order < 1:
            raise ValueError(f"order must be an integer >= 1; got {order!r}.")
        self.order = int(order)

    def _params(self):
        return {
            "gain": self.gain,
            "time_constant": self.time_constant,
            "delay": self.delay,
            "order": self.order,
        }

    def state_space(self):
        A, B, C = _lag_chain([self.time_constant] * self.order)
        return A, B * self.gain, C

    def foptd(self):
        from .controllers import foptd_approximation

        h, tau = foptd_approximation(self.order, self.time_constant, self.delay)
        return self.gain, tau, h


class FOPTD(NthOrderLag):
    """First order plus time delay ``K e^{-Ls} / (T s + 1)`` (Singhal & Salsbury 2005).

    Parameters
    ----------
    gain : float
        Static gain ``K`` (nonzero).
    time_constant : float
        ``T > 0``.
    delay : float, default=0.0
        ``L >= 0``.

    Examples
    --------
    >>> from sktiction.simulation import FOPTD
    >>> FOPTD(2.0, 10.0, 3.0).foptd()
    (2.0, 10.0, 3.0)
    """

    def __init__(self, gain=1.0, time_constant=1.0, delay=0.0):
        super().__init__(gain, time_constant, delay, order=1)

    def _params(self):
        return {"gain": self.gain, "time_constant": self.time_constant, "delay": self.delay}


class SOPTD(_Plant):
    """Second order plus time delay ``K e^{-Ls} / ((T1 s + 1)(T2 s + 1))``.

    Parameters
    ----------
    gain : float
        Static gain ``K`` (nonzero).
    time_constant : float
        ``T1 > 0``.
    delay : float, default=0.0
        ``L >= 0``.
    time_constant2 : float or None, default=None
        ``T2 > 0``; ``None`` means ``T2 = T1`` (Singhal & Salsbury's SOPTD).

    Examples
    --------
    >>> from sktiction.simulation import SOPTD
    >>> round(SOPTD(1.0, 1.0).foptd()[2], 4)  # apparent delay (3 - e) T
    0.2817
    """

    def __init__(self, gain=1.0, time_constant=1.0, delay=0.0, time_constant2=None):
        self.gain = _check_gain(gain)
        self.time_constant = check_positive(time_constant, "time_constant")
        self.delay = check_positive(delay, "delay", strict=False)
        if time_constant2 is not None:
            time_constant2 = check_positive(time_constant2, "time_constant2")
        self.time_constant2 = time_constant2

    def _params(self):
        return {
            "gain": self.gain,
            "time_constant": self.time_constant,
            "delay": self.delay,
            "time_constant2": self.time_constant2,
        }

    @property
    def order(self):
        return 2

    def state_space(self):
        T2 = self.time_constant if self.time_constant2 is None else self.time_constant2
        A, B, C = _lag_chain([self.time_constant, T2])
        return A, B * self.gain, C

    def foptd(self):
        from .controllers import foptd_approximation

        T1 = self.time_constant
        T2 = T1 if self.time_constant2 is None else self.time_constant2
        if math.isclose(T1, T2, rel_tol=1e-9):
            h, tau = foptd_approximation(2, T1, self.delay)
            return self.gain, tau, h
        # Distinct lags: inflection of the step response at
        # t_i = T1 T2 ln(T1/T2) / (T1 - T2); tangent there gives the apparent delay.
        ti = T1 * T2 * math.log(T1 / T2) / (T1 - T2)
        y = 1 - (T1 * math.exp(-ti / T1) - T2 * math.exp(-ti / T2)) / (T1 - T2)
        slope = (math.exp(-ti / T1) - math.exp(-ti / T2)) / (T1 - T2)
        h = ti - y / slope
        return self.gain, T1 + T2 - h, h + self.delay


class IntegratingPlant(_Plant):
    """Integrating plant ``K e^{-Ls} / (s (T s + 1))`` (``T = 0``: pure integrator).

    Parameters
    ----------
    gain : float
        Velocity gain ``K`` (nonzero), output units per second per input unit.
    delay : float, default=0.0
        ``L >= 0``.
    time_constant : float, default=0.0
        Optional lag ``T >= 0``.

    Examples
    --------
    >>> from sktiction.simulation import IntegratingPlant
    >>> IntegratingPlant(0.1, delay=2.0, time_constant=1.0).foptd()
    (0.1, inf, 3.0)
    """

    integrating = True

    def __init__(self, gain=1.0, delay=0.0, time_constant=0.0):
        self.gain = _check_gain(gain)
        self.delay = check_positive(delay, "delay", strict=False)
        self.time_constant = check_positive(time_constant, "time_constant", strict=False)

    def _params(self):
        return {"gain": self.gain, "delay": self.delay, "time_constant": self.time_constant}

    @property
    def order(self):
        return 1 if self.time_constant == 0 else 2

    def state_space(self):
        if self.time_constant == 0:
            return np.zeros((1, 1)), np.array([self.gain]), np.array([1.0])
        T = self.time_constant
        A = np.array([[-1.0 / T, 0.0], [1.0, 0.0]])
        return A, np.array([self.gain / T, 0.0]), np.array([0.0, 1.0])

    def foptd(self):
        # A lag in series with an integrator acts like extra delay (Astrom & Hagglund).
        return self.gain, math.inf, self.delay + self.time_constant
