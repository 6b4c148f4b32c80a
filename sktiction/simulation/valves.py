"""Control valve models: healthy, deadband and four stiction models.

Each valve is a small parameter holder; the stepping itself is one compiled
function, ``_kernel._valve_update``, selected by an integer ``kind`` so that the
closed loop can run every valve type inside one numba kernel (which keeps the
state in local variables; ``_kernel.valve_step`` steps a state array). Positions
and parameters are in % of the valve span.

State vector (``STATE_SIZE`` floats):
``[y, u_prev, du_sign_prev, stuck, direction, u_stick]``.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_positive

__all__ = [
    "LinearValve",
    "RelayValve",
    "ChoudhuryValve",
    "KanoValve",
    "DeadbandValve",
    "HeValve",
    "make_valve",
    "VALVE_MODELS",
]

from ._kernel import (
    _STUCK,
    _UPREV,
    _USTICK,
    _Y,
    CHOUDHURY,
    DEADBAND,
    HE,
    KANO,
    LINEAR,
    N_PARAMS,
    RELAY,
    STATE_SIZE,
    _valve_run,
)


class _Valve:
    kind = LINEAR
    name = "linear"

    def params(self):
        """Parameter array of length ``N_PARAMS`` for the compiled kernel."""
        return np.zeros(N_PARAMS)

    def _param_dict(self):
        return {}

    def initial_state(self, position):
        """State of a valve at rest at ``position`` with no previous motion."""
        state = np.zeros(STATE_SIZE)
        state[_Y] = position
        state[_UPREV] = position
        state[_USTICK] = position
        state[_STUCK] = 1.0
        return state

    def simulate(self, u, initial_position=None):
        """Valve position for an input sequence ``u`` (open loop, valve alone).

        Parameters
        ----------
        u : array-like of shape (n_samples,)
            Valve input (controller output), % of span.
        initial_position : float or None, default=None
            Position at rest before ``u[0]``; defaults to ``u[0]``.

        Returns
        -------
        y : ndarray of shape (n_samples,)
        """
        u = np.asarray(u, dtype=float)
        y0 = u[0] if initial_position is None else float(initial_position)
        return _valve_run(self.kind, self.params(), self.initial_state(y0), u)

    def __repr__(self):
        params = ", ".join(f"{k}={v!r}" for k, v in self._param_dict().items())
        return f"{type(self).__name__}({params})"


class LinearValve(_Valve):
    """Healthy valve: the stem follows the controller output exactly.

    Examples
    --------
    >>> from sktiction.simulation import LinearValve
    >>> LinearValve().simulate([1.0, 2.0, 3.0]).tolist()
    [1.0, 2.0, 3.0]
    """


class RelayValve(_Valve):
    """One-parameter stiction model of Hagglund (2002).

    ``y[t] = y[t-1]`` if ``|u[t] - y[t-1]| <= d`` else ``u[t]``
    (Srinivasan, Rengaswamy, Narasimhan & Miller 2005, Eq. 2). In a loop it acts
    as a relay with hysteresis (Singhal & Salsbury 2005, Fig. 2).

    Parameters
    ----------
    d : float
        Stiction band ``d > 0``, % of span.

    Examples
    --------
    >>> from sktiction.simulation import RelayValve
    >>> RelayValve(1.0).simulate([0.0, 0.5, 1.0, 1.5, 1.7]).tolist()
    [0.0, 0.0, 0.0, 1.5, 1.5]
    """

    kind = RELAY
    name = "relay"

    def __init__(self, d):
        self.d = check_positive(d, "d", upper=100.0)

    def params(self):
        return np.array([self.d, 0.0])

    def _param_dict(self):
        return {"d": self.d}


def _check_sj(S, J):
    S = check_positive(S, "S", upper=100.0)
    J = check_positive(J, "J", strict=False)
    if J > S:
        raise ValueError(f"J must satisfy 0 <= J <= S (S={S!r}); got J={J!r}.")
    return S, J


class ChoudhuryValve(_Valve):
    """Two-parameter data-driven stiction model of Choudhury, Thornhill & Shah.

    Choudhury, M.A.A.S., Thornhill, N.F., Shah, S.L. (2005), Modelling valve
    stiction, *Control Engineering Practice* 13:641-658. The valve sticks
    whenever the input velocity changes sign or becomes zero, remembering the
    input ``x_ss`` at that moment. It slips when the input has moved more than
    ``S`` from ``x_ss`` against the previous motion (deadband + stickband), or
    more than ``J`` in the same direction (stickband only), and then moves to
    ``u - sign(du) (S - J) / 2``, which produces a slip jump of ``J``. While the
    input keeps its direction the valve slides with it (slope 1).

    Parameters
    ----------
    S : float
        Deadband plus stickband, ``0 < S <= 100`` % of span.
    J : float
        Slip jump, ``0 <= J <= S``. Choudhury's model also allows ``J > S``
        (overshoot); it is forbidden here to keep the parameter space to the
        cases the area-ratio papers study.

    Notes
    -----
    With ``J = S`` the sliding offset vanishes and, when each slip is followed
    by a reversal (the limit cycle of a loop with little delay), the model
    equals :class:`RelayValve` with ``d = S``. From rest with no previous
    motion the first slip needs ``S``. As published, ``x_ss`` is reset at every
    sign change of the input, even while the valve is stuck: after a reversal
    smaller than ``S`` and a move back of more than ``J``, the valve slips to
    ``u - sign(du) (S - J) / 2``, which may lie behind where it stuck, a move
    against the input. Kano et al. (2004) mended this (:class:`KanoValve`).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import ChoudhuryValve
    >>> u = np.r_[np.linspace(50, 45, 6), np.linspace(45, 52, 8)]
    >>> ChoudhuryValve(S=4.0, J=2.0).simulate(u).round(1).tolist()[-6:]
    [46.0, 46.0, 46.0, 49.0, 50.0, 51.0]
    """

    kind = CHOUDHURY
    name = "choudhury"

    def __init__(self, S, J):
        self.S, self.J = _check_sj(S, J)

    def params(self):
        return np.array([self.S, self.J])

    def _param_dict(self):
        return {"S": self.S, "J": self.J}


class KanoValve(ChoudhuryValve):
    """Stiction model of Kano, Maruta, Kugemoto & Shimizu (2004).

    Kano, M. et al. (2004), Practical model and detection algorithm for valve
    stiction, *IFAC DYCOPS*, Cambridge. Unlike Choudhury's model the stop
    position ``u_s`` is only updated when a *moving* valve stops or reverses,
    so small input wiggles while stuck do not reset the friction threshold; the
    friction direction ``d`` is that of the last motion. A stuck valve moves
    when ``-d (u - u_s) > S`` (reversal) or ``d (u - u_s) > J`` (same
    direction), to ``u - d (S - J) / 2``.

    Parameters
    ----------
    S : float
        Static friction band (deadband + stickband), ``0 < S <= 100`` %.
    J : float
        Dynamic friction band (slip jump), ``0 <= J <= S`` (Kano's overshoot
        case ``J > S`` is forbidden here).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.simulation import KanoValve
    >>> u = np.r_[np.linspace(50, 45, 6), np.linspace(45, 52, 8)]
    >>> KanoValve(S=4.0, J=2.0).simulate(u).round(1).tolist()[-6:]
    [46.0, 46.0, 46.0, 49.0, 50.0, 51.0]
    """

    kind = KANO
    name = "kano"


class DeadbandValve(_Valve):
    """Pure backlash (deadband) of total width ``deadband``.

    The stem lags the input by ``deadband / 2`` in the direction of motion and
    does not move until a reversal has taken up the whole band (Choudhury et
    al. 2005, Fig. 1 without stickband).

    Parameters
    ----------
    deadband : float
        Total width ``> 0``, % of span.

    Examples
    --------
    >>> from sktiction.simulation import DeadbandValve
    >>> DeadbandValve(2.0).simulate([50.0, 52.0, 51.5, 49.0]).tolist()
    [50.0, 51.0, 51.0, 50.0]
    """

    kind = DEADBAND
    name = "deadband"

    def __init__(self, deadband):
        self.deadband = check_positive(deadband, "deadband", upper=100.0)

    def params(self):
        return np.array([self.deadband, 0.0])

    def _param_dict(self):
        return {"deadband": self.deadband}


class HeValve(_Valve):
    """Two-layer stiction model of He, Wang, Pottmann & Qin (2007).

    He, Q.P., Wang, J., Pottmann, M., Qin, S.J. (2007), A curve fitting method for
    detecting valve stiction in oscillating control loops, *Ind. Eng. Chem. Res.*
    46:4549-4560. A residual force ``u_r = u - y`` builds up while the valve is
    stuck; when it exceeds the static friction ``fs`` the valve moves to
    ``u - sign(u_r) fd`` (dynamic friction ``fd``) and the residual drops to
    ``fd``. A valve that keeps moving slowly therefore sticks again after each
    slip (stick-slip while moving), unlike :class:`ChoudhuryValve`, which slides.
    In Choudhury's terms ``S = fs + fd`` (reversal) and ``J = fs - fd`` (slip).

    Parameters
    ----------
    fs : float
        Static friction band, ``0 < fs <= 100`` % of span.
    fd : float
        Dynamic friction band, ``0 <= fd <= fs``.

    Examples
    --------
    >>> from sktiction.simulation import HeValve
    >>> HeValve(fs=2.0, fd=0.5).simulate([50.0, 51.0, 52.5, 53.0, 50.0, 48.0]).tolist()
    [50.0, 50.0, 52.0, 52.0, 52.0, 48.5]
    """

    kind = HE
    name = "he"

    def __init__(self, fs, fd):
        self.fs = check_positive(fs, "fs", upper=100.0)
        self.fd = check_positive(fd, "fd", strict=False)
        if self.fd > self.fs:
            raise ValueError(f"fd must satisfy 0 <= fd <= fs (fs={fs!r}); got fd={fd!r}.")

    @classmethod
    def from_sj(cls, S, J):
        """The same valve from Choudhury's band ``S`` and slip jump ``J <= S``."""
        S, J = _check_sj(S, J)
        return cls(fs=0.5 * (S + J), fd=0.5 * (S - J))

    def params(self):
        return np.array([self.fs, self.fd])

    def _param_dict(self):
        return {"fs": self.fs, "fd": self.fd}


VALVE_MODELS = {
    "linear": LinearValve,
    "relay": RelayValve,
    "choudhury": ChoudhuryValve,
    "kano": KanoValve,
    "deadband": DeadbandValve,
    "he": HeValve,
}


def make_valve(model, **params):
    """Valve from its model name, e.g. ``make_valve("choudhury", S=4, J=1)``.

    Examples
    --------
    >>> from sktiction.simulation import make_valve
    >>> make_valve("relay", d=2.0)
    RelayValve(d=2.0)
    """
    if model not in VALVE_MODELS:
        raise ValueError(f"valve model must be one of {sorted(VALVE_MODELS)}; got {model!r}.")
    return VALVE_MODELS[model](**params)
