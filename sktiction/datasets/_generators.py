"""Generate labelled sets of simulated oscillating control loops."""

from __future__ import annotations

import numbers

import numpy as np
import pandas as pd

from .._validation import check_positive, check_random_state_seed
from ..simulation import (
    FOPTD,
    SOPTD,
    ARNoise,
    IntegratingPlant,
    LinearValve,
    NthOrderLag,
    PIController,
    RandomWalkLoad,
    SetpointSteps,
    SinusoidalDisturbance,
    WhiteNoise,
    make_valve,
    simulate_loops,
)
from ..simulation._threads import single_blas_thread

__all__ = ["make_loops"]

CAUSES = ("stiction", "aggressive_tuning", "external_disturbance", "none")
STICTION_MODELS = ("relay", "choudhury", "kano")
# Stiction limit-cycle period over the phase-crossover period 2 pi / w180, median
# measured on generated loops (good tuning, relay/Kano valves, lambda 0.1-1).
_STICTION_PERIOD_FACTOR = {1: 6.0, "integrating": 6.0}
_STICTION_PERIOD_FACTOR_DEFAULT = 4.0


def _check_range(value, name, lo=None, hi=None, strict_lo=False):
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a pair (low, high); got {value!r}.") from exc
    ok = np.isfinite(a) and np.isfinite(b) and a <= b
    if lo is not None:
        ok = ok and (a > lo if strict_lo else a >= lo)
    if hi is not None:
        ok = ok and b <= hi
    if not ok:
        low = "" if lo is None else f"{lo} {'<' if strict_lo else '<='} "
        high = "" if hi is None else f" <= {hi}"
        raise ValueError(f"{name} must be (low, high) with {low}low <= high{high}; got {value!r}.")
    return a, b


def _phase_crossover(plant, kc, ti, ts):
    """Phase-crossover frequency ``w180`` of the sampled PI loop and the gain margin there.

    The hold adds ``ts / 2`` of delay; the controller sign makes the DC loop gain positive.
    """
    A, B, C = plant.state_space()
    scale = plant.delay + max(plant.time_constant, 1e-3) + ts
    w = np.geomspace(1e-3, 1e3, 600) / scale
    eye = np.eye(A.shape[0])
    rhs = np.broadcast_to(B[:, None], (len(w), len(B), 1))
    G = (np.linalg.solve(1j * w[:, None, None] * eye - A, rhs)[:, :, 0] @ C) * np.sign(plant.gain)
    loop = kc * (1 + 1 / (1j * w * ti)) * G * np.exp(-1j * w * (plant.delay + ts / 2))
    phase = np.unwrap(np.angle(loop))
    above = phase > -np.pi
    idx = np.nonzero(above[:-1] & ~above[1:])[0]
    if len(idx) == 0:
        return np.nan, np.inf
    i = idx[0]
    f = (-np.pi - phase[i]) / (phase[i + 1] - phase[i])
    w180 = w[i] * (w[i + 1] / w[i]) ** f
    mag = np.exp(np.log(abs(loop[i])) * (1 - f) + np.log(abs(loop[i + 1])) * f)
    return w180, 1.0 / mag


def _settings(plant, rule, ts):
    c = PIController.from_plant(plant, rule, ts=ts if ts > 0 else None)
    return c.kc, c.ti


def _plant_for(order, lam_target, time_constant, gain):
    """Plant of the given order with apparent lambda as close to ``lam_target`` as possible."""
    T = time_constant
    if order == "integrating":
        lag = T
        delay = lam_target * T
        return IntegratingPlant(gain / T, delay=delay, time_constant=lag), np.nan
    probe = NthOrderLag(1.0, T, 0.0, order=order)
    _, tau, h = probe.foptd()
    # a little pure delay always, so the loop has a phase crossover
    delay = max(lam_target * tau - h, 0.02 * T)
    if order == 1:
        plant = FOPTD(gain, T, delay)
    elif order == 2:
        plant = SOPTD(gain, T, delay)
    else:
        plant = NthOrderLag(gain, T, delay, order=order)
    _, tau, L = plant.foptd()
    return plant, L / tau


@single_blas_thread
def make_loops(
    n_loops=100,
    n_samples=2000,
    *,
    stiction_fraction=0.5,
    causes=("aggressive_tuning", "external_disturbance", "none"),
    ts=1.0,
    lambda_range=(0.1, 1.0),
    orders=(1, 2, 3, 4, "integrating"),
    stiction_models=STICTION_MODELS,
    S_range=(0.5, 10.0),
    snr_db_range=(10.0, 40.0),
    period_range=(20.0, 200.0),
    slip_fraction=0.0,
    random_state=None,
    return_meta=False,
):
    """Generate simulated control loops, oscillating because of stiction or not.

    Each loop is a closed loop (plant, PI controller, valve) simulated with
    :func:`sktiction.simulation.simulate_loops`, starting at steady state with
    PV = SP = 50 and OP = 50 %. Causes:

    * ``"stiction"`` (``y = 1``): sticky valve (relay, Choudhury or Kano model,
      ``S`` uniform in ``S_range`` % of span, ``J / S`` uniform in 0.2-1),
      good tuning (AMIGO or CHR; AMIGO or SIMC for integrating plants),
      started by a setpoint step of 0.3-1 times ``S`` (in PV units). A share
      ``slip_fraction`` of them has sluggish integral action (``Ti`` 5-20 times
      the rule's) and 1-4 setpoint moves instead: their stick-slip cycle is longer
      than the record, which shows only a few slips, as sticky valves often do in
      plant data (scenario ``"slips"``; the others are ``"limit_cycle"``).
    * ``"aggressive_tuning"``: healthy valve, AMIGO ``Kc`` raised by a gain
      factor so that the gain margin is 1.05-1.3 (sustained or slowly decaying
      oscillation), kept alive by the noise and loads.
    * ``"external_disturbance"``: healthy valve, good tuning, sinusoidal load at
      the plant output (amplitude 0.5-2 times the PV change of a 2 % valve move).
    * ``"none"``: healthy valve, good tuning, only noise, random-walk load and,
      for half of them, setpoint steps.

    Every loop gets measurement noise (white or AR(1), SNR uniform in
    ``snr_db_range`` relative to the noise-free PV, see
    :mod:`sktiction.simulation.effects`) and a small random-walk output load.
    Choudhury's model re-sticks at every reversal of its input, so a noisy OP
    freezes it (the weakness Kano et al. 2004 addressed); loops with that model
    get their noise added to the recorded PV only (their OP is smoother).

    Plants are n-th order lags ``K e^{-Ls} / (T s + 1)^n`` or integrating
    plants ``K e^{-Ls} / (s (T s + 1))``, ``|K|`` log-uniform in 0.5-2 with a
    random sign (a quarter direct acting). The delay ``L`` is chosen so the
    apparent ``lambda = (h + L) / tau`` (Singhal & Salsbury 2005, Eq. 6) is
    uniform in ``lambda_range``; higher orders whose own lambda exceeds the
    target get ``L = 0.02 T`` (the meta records the actual value). For integrating
    plants ``L = lambda T`` and the meta ``lambda`` is NaN.

    All loops share the sample time ``ts``; the plant time constant is scaled
    so that the expected oscillation period spans a number of samples drawn
    log-uniformly from ``period_range`` (exact for external disturbances,
    estimated from the phase-crossover frequency otherwise).

    Parameters
    ----------
    n_loops : int, default=100
        Number of loops (>= 1).
    n_samples : int, default=2000
        Samples per loop (>= 2).
    stiction_fraction : float, default=0.5
        Share of stiction loops (0-1), rounded to a whole number of loops; the
        rest is split evenly over ``causes``.
    causes : tuple of str, default=("aggressive_tuning", "external_disturbance", "none")
        Non-stiction causes to draw from.
    ts : float, default=1.0
        Sample time (> 0), also the time unit of the meta data.
    lambda_range : tuple of float, default=(0.1, 1.0)
        Range of ``lambda`` (0 < low <= high).
    orders : tuple, default=(1, 2, 3, 4, "integrating")
        Plant orders (integers 1-10) and/or ``"integrating"``, drawn uniformly.
    stiction_models : tuple of str, default=("relay", "choudhury", "kano")
        Stiction valve models drawn uniformly for stiction loops.
    S_range : tuple of float, default=(0.5, 10.0)
        Stiction band ``S`` (relay ``d``) in % of span (0 < low <= high <= 50).
    snr_db_range : tuple of float, default=(10.0, 40.0)
        Signal-to-noise ratio of the measurement noise in dB.
    period_range : tuple of float, default=(20.0, 200.0)
        Target oscillation period in samples (2 < low <= high).
    slip_fraction : float, default=0.0
        Share (0-1) of stiction loops that show slips during setpoint moves
        rather than a sustained limit cycle. The seeds' methods need a cycle, so
        the default leaves these out; training sets for plant data want them.
    random_state : None, int or numpy.random.Generator, default=None
        Seed for reproducible output.
    return_meta : bool, default=False
        Also return a DataFrame describing each loop.

    Returns
    -------
    X : ndarray of shape (n_loops, n_samples, 3)
        Channels PV, OP (%), SP.
    y : ndarray of shape (n_loops,), dtype int
        1 when stiction causes the oscillation, else 0.
    meta : pandas.DataFrame, only if ``return_meta``
        One row per loop: ``cause``, ``y``, ``plant``, ``order``, ``gain``,
        ``time_constant``, ``delay``, ``apparent_time_constant``,
        ``apparent_delay``, ``lambda``, ``valve``, ``S``, ``J``, ``rule``,
        ``gain_factor``, ``Kc``, ``Ti``, ``ts``, ``samples_per_cycle``,
        ``snr_db``, ``scenario``, ``effects``.

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> X, y, meta = make_loops(8, 300, random_state=0, return_meta=True)
    >>> X.shape, int(y.sum())
    ((8, 300, 3), 4)
    >>> sorted(meta["cause"].unique())[:2]
    ['aggressive_tuning', 'external_disturbance']
    """
    if not isinstance(n_loops, numbers.Integral) or n_loops < 1:
        raise ValueError(f"n_loops must be an integer >= 1; got {n_loops!r}.")
    if not isinstance(n_samples, numbers.Integral) or n_samples < 2:
        raise ValueError(f"n_samples must be an integer >= 2; got {n_samples!r}.")
    stiction_fraction = check_positive(
        stiction_fraction, "stiction_fraction", strict=False, upper=1.0
    )
    causes = tuple(causes)
    bad = [c for c in causes if c not in CAUSES[1:]]
    if bad or not causes:
        raise ValueError(f"causes must be a non-empty subset of {CAUSES[1:]}; got {causes!r}.")
    ts = check_positive(ts, "ts")
    lam_lo, lam_hi = _check_range(lambda_range, "lambda_range", lo=0.0, strict_lo=True)
    orders = tuple(orders)
    for o in orders:
        if o != "integrating" and not (isinstance(o, numbers.Integral) and 1 <= o <= 10):
            raise ValueError(f"orders must hold integers 1-10 or 'integrating'; got {o!r}.")
    if not orders:
        raise ValueError("orders must not be empty (integers 1-10 or 'integrating').")
    stiction_models = tuple(stiction_models)
    for m in stiction_models:
        if m not in STICTION_MODELS:
            raise ValueError(f"stiction_models must be among {STICTION_MODELS}; got {m!r}.")
    if not stiction_models:
        raise ValueError(f"stiction_models must be a non-empty subset of {STICTION_MODELS}.")
    slip_fraction = check_positive(slip_fraction, "slip_fraction", strict=False, upper=1.0)
    s_lo, s_hi = _check_range(S_range, "S_range", lo=0.0, hi=50.0, strict_lo=True)
    snr_lo, snr_hi = _check_range(snr_db_range, "snr_db_range")
    p_lo, p_hi = _check_range(period_range, "period_range", lo=2.0, strict_lo=True)
    rng = check_random_state_seed(random_state)

    n_stiction = int(round(stiction_fraction * n_loops))
    rest = n_loops - n_stiction
    labels = ["stiction"] * n_stiction + [causes[i % len(causes)] for i in range(rest)]
    labels = list(rng.permutation(np.array(labels, dtype=object)))

    plants, controllers, valves, effects, rows = [], [], [], [], []
    for cause in labels:
        order = orders[rng.integers(len(orders))]
        lam_target = rng.uniform(lam_lo, lam_hi)
        sign = -1.0 if rng.random() < 0.25 else 1.0
        k_mag = float(np.exp(rng.uniform(np.log(0.5), np.log(2.0))))
        # dimensionless plant (T = 1) first; Kc is invariant when time is rescaled
        plant0, _ = _plant_for(order, lam_target, 1.0, sign * k_mag)
        integrating = plant0.integrating
        good_rules = ("amigo", "simc") if integrating else ("amigo", "chr")
        rule = good_rules[rng.integers(2)] if cause != "aggressive_tuning" else "amigo"
        # the PI phase does not depend on Kc, so w180 holds for any gain factor
        w180, _ = _phase_crossover(plant0, *_settings(plant0, rule, 0.0), 0.0)
        samples_per_cycle = float(np.exp(rng.uniform(np.log(p_lo), np.log(p_hi))))
        period = 2 * np.pi / w180
        if cause == "stiction":
            period *= _STICTION_PERIOD_FACTOR.get(order, _STICTION_PERIOD_FACTOR_DEFAULT)
        elif cause in ("external_disturbance", "none"):
            # the disturbance sets the period; place it loosely relative to the plant
            period *= rng.uniform(1.0, 4.0)
        ts_d = period / samples_per_cycle  # sample time in units of T
        kc, ti = _settings(plant0, rule, ts_d)
        gain_factor = 1.0
        if cause == "aggressive_tuning":
            _, margin = _phase_crossover(plant0, kc, ti, ts_d)
            gain_factor = margin / rng.uniform(1.05, 1.3)
        scale = ts / ts_d
        plant, lam = _plant_for(order, lam_target, scale, sign * k_mag)
        ctrl = PIController(kc * gain_factor, ti * scale, rule=rule)
        K, tau, Lapp = plant.foptd()
        g = abs(K) if not integrating else abs(K) * (plant.delay + plant.time_constant)
        nominal = 2.0 * g  # PV change of a 2 % valve move

        eff = [RandomWalkLoad(float(nominal * rng.uniform(0.001, 0.004)))]
        S = J = np.nan
        valve = LinearValve()
        scenario = "limit_cycle" if cause == "stiction" else ""
        if cause == "stiction" and rng.random() < slip_fraction:
            scenario = "slips"
            ctrl = PIController(ctrl.kc, ctrl.ti * rng.uniform(5.0, 20.0), rule=rule)
        if cause == "stiction":
            model = stiction_models[rng.integers(len(stiction_models))]
            S = float(rng.uniform(s_lo, s_hi))
            if model == "relay":
                valve, J = make_valve("relay", d=S), S
            else:
                J = float(S * rng.uniform(0.2, 1.0))
                valve = make_valve(model, S=S, J=J)
            if scenario == "slips":
                n_steps = int(rng.integers(1, 5))
                times = np.sort(rng.uniform(0.05, 0.8, n_steps) * n_samples * ts).round(6)
                sizes = S * g * rng.uniform(0.5, 2.0, n_steps) * rng.choice([-1.0, 1.0], n_steps)
                eff.append(SetpointSteps(times.tolist(), sizes.tolist()))
            else:
                step = float(rng.uniform(0.3, 1.0) * S * g * rng.choice([-1.0, 1.0]))
                eff.append(SetpointSteps([ts * rng.integers(5, 20)], [step]))
        elif cause == "aggressive_tuning":
            step = float(nominal * rng.uniform(0.5, 2.0) * rng.choice([-1.0, 1.0]))
            eff.append(SetpointSteps([ts * rng.integers(5, 20)], [step]))
        elif cause == "external_disturbance":
            eff.append(
                SinusoidalDisturbance(
                    float(nominal * rng.uniform(0.5, 2.0)),
                    ts * samples_per_cycle,
                    phase=float(rng.uniform(0, 2 * np.pi)),
                )
            )
        elif rng.random() < 0.5:
            n_steps = int(rng.integers(1, 4))
            times = np.sort(rng.uniform(0, n_samples * ts, n_steps)).round(6)
            sizes = nominal * rng.uniform(0.5, 2.0, n_steps) * rng.choice([-1.0, 1.0], n_steps)
            eff.append(SetpointSteps(times.tolist(), sizes.tolist()))
        snr = float(rng.uniform(snr_lo, snr_hi))
        # Choudhury's model re-sticks at every OP reversal, so noise inside the loop
        # would freeze it (Kano et al. 2004): its loops get noise on the record only
        where = "record" if getattr(valve, "name", "") == "choudhury" else "loop"
        if rng.random() < 0.5:
            eff.append(WhiteNoise(snr_db=snr, where=where))
        else:
            eff.append(ARNoise(float(rng.uniform(0.3, 0.9)), snr_db=snr, where=where))

        plants.append(plant)
        controllers.append(ctrl)
        valves.append(valve)
        effects.append(eff)
        rows.append(
            {
                "cause": cause,
                "y": int(cause == "stiction"),
                "plant": "integrating" if integrating else type(plant).__name__.lower(),
                "order": plant.order,
                "gain": plant.gain,
                "time_constant": plant.time_constant,
                "delay": plant.delay,
                "apparent_time_constant": tau,
                "apparent_delay": Lapp,
                "lambda": lam,
                "valve": getattr(valve, "name", "linear"),
                "S": S,
                "J": J,
                "rule": rule,
                "gain_factor": gain_factor,
                "Kc": ctrl.kc,
                "Ti": ctrl.ti,
                "ts": ts,
                "samples_per_cycle": samples_per_cycle,
                "snr_db": snr,
                "scenario": scenario,
                "effects": ", ".join(repr(e) for e in eff),
            }
        )

    res = simulate_loops(
        plants, controllers, valves, int(n_samples), ts, effects=effects, random_state=rng
    )
    X = res.X
    y = np.array([r["y"] for r in rows], dtype=int)
    if return_meta:
        return X, y, pd.DataFrame(rows)
    return X, y
