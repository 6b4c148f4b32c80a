"""PI(D) controller settings and tuning rules from FOPTD models.

Rules for a self-regulating FOPTD model ``K e^{-Ls} / (tau s + 1)`` (PI forms as
listed by Astrom & Hagglund, *Advanced PID Control*, 2006, and used by Singhal &
Salsbury 2005, section 4.1):

========  =====================================================  ===========================
rule      ``K Kc``                                                ``Ti``
========  =====================================================  ===========================
amigo     ``0.15 + (0.35 - L tau / (L + tau)^2) tau / L``          ``0.35 L + 13 L tau^2 /
                                                                  (tau^2 + 12 L tau + 7 L^2)``
chr       ``0.35 tau / L`` (setpoint response, 0 % overshoot)     ``1.2 tau``
zn        ``0.9 tau / L`` (Ziegler-Nichols step response)         ``3 L``
cc        ``tau / L (0.9 + L / (12 tau))`` (Cohen-Coon)           ``L (30 + 3 r) / (9 + 20 r)``,
                                                                  ``r = L / tau``
========  =====================================================  ===========================

Integrating plants ``Kv e^{-Ls} / s`` (:func:`tune_pi_integrating`): AMIGO
``Kc = 0.35 / (Kv L)``, ``Ti = 13.4 L``; SIMC with ``tau_c = L``:
``Kc = 0.5 / (Kv L)``, ``Ti = 8 L`` (Skogestad 2003).
"""

from __future__ import annotations

import functools
import math
import numbers

from .._validation import check_positive

__all__ = [
    "PIController",
    "tune_pi",
    "tune_pi_integrating",
    "foptd_approximation",
    "TUNING_RULES",
]

TUNING_RULES = ("amigo", "chr", "zn", "cc")
INTEGRATING_RULES = ("amigo", "simc")


def foptd_approximation(order, time_constant=1.0, delay=0.0):
    """Apparent delay and time constant of ``e^{-Ls} / (T s + 1)^n``.

    Astrom & Hagglund's method as used by Singhal & Salsbury (2005, Eqs. 4-6):
    the average residence time is ``T_ar = n T``; the apparent delay ``h`` is
    where the tangent through the inflection point ``t = (n - 1) T`` of the unit
    step response crosses the time axis; the apparent time constant is
    ``T_ar - h``. The pure delay ``L`` is added to the apparent delay only.

    Parameters
    ----------
    order : int
        Number of equal lags ``n >= 1``.
    time_constant : float, default=1.0
        ``T > 0``.
    delay : float, default=0.0
        Pure delay ``L >= 0``.

    Returns
    -------
    apparent_delay : float
        ``h + L``.
    apparent_time_constant : float
        ``n T - h``.

    Examples
    --------
    >>> from sktiction.simulation import foptd_approximation
    >>> h, tau = foptd_approximation(3)
    >>> round(h / tau, 2)  # Singhal & Salsbury (2005), Table 1
    0.37
    """
    if not isinstance(order, int) or isinstance(order, bool) or order < 1:
        raise ValueError(f"order must be an integer >= 1; got {order!r}.")
    T = check_positive(time_constant, "time_constant")
    L = check_positive(delay, "delay", strict=False)
    if order == 1:
        return L, T
    h = _apparent_delay(order) * T
    return h + L, order * T - h


@functools.lru_cache(maxsize=64)
def _apparent_delay(order):
    """Apparent delay of ``n >= 2`` equal unit lags (``foptd_approximation`` over ``T``)."""
    k = order - 1
    # Step response of n equal lags is the Erlang CDF; work in log space so large n is safe.
    log_pdf = k * math.log(k) - k - math.lgamma(k + 1)
    slope = math.exp(log_pdf)  # dy/d(t/T) at the inflection point t = k T
    y = 1.0 - sum(math.exp(i * math.log(k) - k - math.lgamma(i + 1)) for i in range(order))
    return k - y / slope


def _check_gain(gain):
    """A plant gain as a float: any real number but bool (numpy's too), finite, nonzero."""
    if not (isinstance(gain, numbers.Real) and not isinstance(gain, bool)
            and math.isfinite(gain)) or gain == 0:  # fmt: skip
        raise ValueError(f"gain must be a finite nonzero number; got {gain!r}.")
    return float(gain)


def tune_pi(gain, time_constant, delay, rule="amigo"):
    """PI settings from a FOPTD model ``K e^{-Ls} / (tau s + 1)``.

    Parameters
    ----------
    gain : float
        Process gain ``K`` (nonzero); its sign does not matter, ``Kc`` is
        returned positive and the action is set by :class:`PIController`.
    time_constant : float
        ``tau > 0``.
    delay : float
        ``L > 0`` (all four rules divide by it).
    rule : {"amigo", "chr", "zn", "cc"}, default="amigo"
        AMIGO, Chien-Hrones-Reswick (setpoint, 0 % overshoot), Ziegler-Nichols
        step response, Cohen-Coon. See the module docstring for formulas.

    Returns
    -------
    kc : float
        Proportional gain (> 0).
    ti : float
        Integral time.

    Examples
    --------
    >>> from sktiction.simulation import tune_pi
    >>> kc, ti = tune_pi(1.0, 1.0, 0.5, rule="zn")
    >>> round(kc, 3), round(ti, 3)
    (1.8, 1.5)
    """
    gain = _check_gain(gain)
    tau = check_positive(time_constant, "time_constant")
    L = check_positive(delay, "delay")
    K = abs(gain)
    if rule == "amigo":
        kc = (0.15 + (0.35 - L * tau / (L + tau) ** 2) * tau / L) / K
        ti = 0.35 * L + 13 * L * tau**2 / (tau**2 + 12 * L * tau + 7 * L**2)
    elif rule == "chr":
        kc, ti = 0.35 * tau / (K * L), 1.2 * tau
    elif rule == "zn":
        kc, ti = 0.9 * tau / (K * L), 3.0 * L
    elif rule == "cc":
        r = L / tau
        kc = tau / (K * L) * (0.9 + r / 12)
        ti = L * (30 + 3 * r) / (9 + 20 * r)
    else:
        raise ValueError(f"rule must be one of {TUNING_RULES}; got {rule!r}.")
    return kc, ti


def tune_pi_integrating(gain, delay, rule="amigo"):
    """PI settings for an integrating plant ``Kv e^{-Ls} / s``.

    Parameters
    ----------
    gain : float
        Velocity gain ``Kv`` (nonzero).
    delay : float
        ``L > 0`` (add any lag time constant to it).
    rule : {"amigo", "simc"}, default="amigo"
        AMIGO for integrating processes (``Kc = 0.35/(Kv L)``, ``Ti = 13.4 L``)
        or SIMC with ``tau_c = L`` (``Kc = 0.5/(Kv L)``, ``Ti = 8 L``).

    Returns
    -------
    kc, ti : float

    Examples
    --------
    >>> from sktiction.simulation import tune_pi_integrating
    >>> tune_pi_integrating(0.5, 2.0, rule="simc")
    (0.5, 16.0)
    """
    gain = _check_gain(gain)
    L = check_positive(delay, "delay")
    Kv = abs(gain)
    if rule == "amigo":
        return 0.35 / (Kv * L), 13.4 * L
    if rule == "simc":
        return 0.5 / (Kv * L), 8.0 * L
    raise ValueError(f"rule must be one of {INTEGRATING_RULES}; got {rule!r}.")


class PIController:
    """Discrete PI(D) controller in velocity form with OP limits.

    ``du[k] = s Kc ((e[k] - e[k-1]) + ts / Ti e[k] - Td / ts (pv[k] - 2 pv[k-1] + pv[k-2]))``,
    ``op[k] = clip(op[k-1] + du[k], lo, hi)``: the velocity form needs no
    separate anti-windup, clipping the output stops integration at a limit.
    The derivative acts on the measurement (no setpoint kick).

    Parameters
    ----------
    kc : float
        Proportional gain magnitude (> 0).
    ti : float
        Integral time (> 0), same unit as ``ts``.
    td : float, default=0.0
        Derivative time (>= 0).
    action : {"auto", "reverse", "direct"}, default="auto"
        ``"reverse"``: OP rises when PV is below SP (``s = +1``, positive plant
        gain); ``"direct"``: the opposite; ``"auto"``: from the sign of the
        plant gain.
    op_limits : tuple of float, default=(0.0, 100.0)
        OP range in % of span.
    rule : str or None, default=None
        Name of the tuning rule, kept for records.

    Examples
    --------
    >>> from sktiction.simulation import FOPTD, PIController
    >>> ctrl = PIController.from_plant(FOPTD(1.0, 1.0, 0.5), rule="chr")
    >>> round(ctrl.kc, 3), round(ctrl.ti, 3)
    (0.7, 1.2)
    """

    def __init__(self, kc, ti, td=0.0, *, action="auto", op_limits=(0.0, 100.0), rule=None):
        self.kc = check_positive(kc, "kc")
        self.ti = check_positive(ti, "ti")
        self.td = check_positive(td, "td", strict=False)
        if action not in ("auto", "reverse", "direct"):
            raise ValueError(f"action must be 'auto', 'reverse' or 'direct'; got {action!r}.")
        self.action = action
        lo, hi = (float(v) for v in op_limits)
        if not lo < hi:
            raise ValueError(f"op_limits must be (low, high) with low < high; got {op_limits!r}.")
        self.op_limits = (lo, hi)
        self.rule = rule

    @classmethod
    def from_plant(cls, plant, rule="amigo", *, gain_factor=1.0, ts=None, **kwargs):
        """Tune from ``plant.foptd()`` with a named rule.

        Parameters
        ----------
        plant : plant object
            Anything with ``foptd()`` and ``integrating``.
        rule : str, default="amigo"
            See :func:`tune_pi` and :func:`tune_pi_integrating`.
        gain_factor : float, default=1.0
            Multiplies ``Kc``; values of 2-5 give an aggressive, oscillatory loop.
        ts : float or None, default=None
            If given, ``ts / 2`` is added to the apparent delay (the usual
            allowance for sampling and hold).
        **kwargs
            Passed to the constructor.
        """
        gain_factor = check_positive(gain_factor, "gain_factor")
        K, tau, L = plant.foptd()
        if ts is not None:
            L = L + check_positive(ts, "ts") / 2
        if plant.integrating:
            kc, ti = tune_pi_integrating(K, L, rule)
        else:
            kc, ti = tune_pi(K, tau, L, rule)
        return cls(kc * gain_factor, ti, rule=rule, **kwargs)

    def sign(self, plant_gain):
        """Controller sign ``s`` applied to ``Kc`` for a plant of this gain."""
        if self.action == "reverse":
            return 1.0
        if self.action == "direct":
            return -1.0
        return 1.0 if plant_gain > 0 else -1.0

    def __repr__(self):
        return (
            f"PIController(kc={self.kc!r}, ti={self.ti!r}, td={self.td!r}, "
            f"action={self.action!r}, op_limits={self.op_limits!r}, rule={self.rule!r})"
        )
