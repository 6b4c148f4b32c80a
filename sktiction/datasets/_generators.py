"""Generate labelled sets of simulated oscillating control loops."""

from __future__ import annotations

import functools
import numbers

import numpy as np
import pandas as pd
from numba import njit

from .._validation import CHANNELS, check_positive, check_random_state_seed
from ..simulation import (
    FOPTD,
    SOPTD,
    ARNoise,
    BandLimitedNoise,
    CascadeSetpoint,
    ColouredLoad,
    Drift,
    HeValve,
    IntegratingPlant,
    LinearValve,
    LoadStep,
    NarrowbandDisturbance,
    NthOrderLag,
    PIController,
    RandomWalkLoad,
    RelayValve,
    SetpointSteps,
    SinusoidalDisturbance,
    SquareDisturbance,
    WhiteNoise,
    foptd_approximation,
    make_valve,
)
from ..simulation._threads import single_blas_thread
from ..simulation.disturbances import PVVariation
from ..simulation.historian import (
    DeadbandCompression,
    HoldLastValue,
    IntervalAveraging,
    SpanQuantization,
    SwingingDoorCompression,
)
from ..simulation.loop import _loop_arrays, _record, _simulate

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


@functools.cache
def _frequency_grid(n_grid):
    grid = np.geomspace(1e-3, 1e3, n_grid)
    grid.flags.writeable = False
    return grid


def _phase_crossovers(plants, kc, ti, ts, n_grid):
    """Phase-crossover frequency ``w180`` of each sampled PI loop and its gain margin there
    (the hold adds ``ts / 2`` of delay; the controller sign makes the DC loop gain
    positive), frequency responses computed in batches of plants with the same number of
    states (each loop's numbers as if computed alone).

    The loops cross -180 degrees at 50-75 % of the grid, so the first three quarters are
    searched first and the rest only for loops not found there: the unwrapped phase over
    a part of the grid is that part of the phase over the whole grid.
    """
    w180, margin = np.full(len(plants), np.nan), np.full(len(plants), np.inf)
    models = [p.state_space() for p in plants]
    n_states = np.array([A.shape[0] for A, _, _ in models])
    kc, ti = np.asarray(kc, dtype=float), np.asarray(ti, dtype=float)
    delay = np.array([p.delay for p in plants])

    def search(idx, n_points):
        """Crossings of loops ``idx`` over the grid's first ``n_points``; the loops left."""
        n = n_states[idx[0]]
        A = np.stack([models[i][0] for i in idx])
        B = np.stack([models[i][1] for i in idx])
        lag = np.array([max(plants[i].time_constant, 1e-3) for i in idx])
        scale = delay[idx] + lag + ts[idx]
        w = _frequency_grid(n_grid)[None, :n_points] / scale[:, None]
        rhs = np.broadcast_to(B[:, None, :, None], (len(idx), n_points, n, 1))
        x = np.linalg.solve(_jw_minus(w, A), rhs)
        G = np.stack([
            (x[k, :, :, 0] @ models[i][2]) * np.sign(plants[i].gain) for k, i in enumerate(idx)
        ])  # fmt: skip
        t = ti[idx, None]
        loop = (
            kc[idx, None]
            * (1 + 1 / (1j * w * t))
            * G
            * np.exp(-1j * w * (delay[idx] + ts[idx] / 2)[:, None])
        )
        phase = np.unwrap(np.angle(loop), axis=-1)
        above = phase > -np.pi
        cross = above[:, :-1] & ~above[:, 1:]
        left = []
        for k, i in enumerate(idx):
            hits = np.nonzero(cross[k])[0]
            if len(hits) == 0:
                left.append(i)
                continue
            j = hits[0]
            p, wk, lk = phase[k], w[k], loop[k]
            f = (-np.pi - p[j]) / (p[j + 1] - p[j])
            w180[i] = wk[j] * (wk[j + 1] / wk[j]) ** f
            mag = np.exp(np.log(abs(lk[j])) * (1 - f) + np.log(abs(lk[j + 1])) * f)
            margin[i] = 1.0 / mag
        return np.array(left, dtype=int)

    first = max(2, (3 * n_grid) // 4)
    for n in np.unique(n_states):
        group = np.flatnonzero(n_states == n)
        # the solve holds (loops, grid, n, n) complex numbers: about 16 MB a batch at most
        step = int(np.clip(2**20 // (n_grid * n * n), 1, 128))
        for lo in range(0, len(group), step):
            left = search(group[lo : lo + step], first)
            if len(left) and first < n_grid:
                search(left, n_grid)
    return w180, margin


def _jw_minus(w, A):
    """``1j * w[:, :, None, None] * np.eye(n) - A[:, None]`` written in one pass.

    Every product there is exact (by 0 or 1), so its real part is ``0.0 - A`` (+0.0, never
    -0.0, where ``A`` is zero) and its imaginary part ``w`` on the diagonal, +0.0 elsewhere.
    """
    n = A.shape[-1]
    M = np.zeros((*w.shape, n, n), dtype=complex)
    M.real[...] = np.subtract(0.0, A)[:, None]
    diag = np.arange(n)
    M.imag[:, :, diag, diag] = w[:, :, None]
    return M


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
    # the delay-free plant's apparent delay and time constant (``NthOrderLag.foptd``)
    h, tau = foptd_approximation(int(order), float(T), 0.0)
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


def _draw_classic(
    labels, n_samples, ts, orders, lam_lo, lam_hi, p_lo, p_hi, s_lo, s_hi, snr_lo, snr_hi,
    slip_fraction, stiction_models, rng,
):  # fmt: skip
    """Loops of the classic world (sktiction 0.1): the draws of ``world="classic"``.

    Every loop's random draws first, in the order they have always been made (none
    depends on the loop's dynamics), then the phase crossovers of all loops together,
    then the objects.
    """
    draws = []
    for cause in labels:
        d = {"cause": cause, "order": orders[rng.integers(len(orders))]}
        d["lam_target"] = rng.uniform(lam_lo, lam_hi)
        d["sign"] = -1.0 if rng.random() < 0.25 else 1.0
        d["k_mag"] = float(np.exp(rng.uniform(np.log(0.5), np.log(2.0))))
        integrating = d["order"] == "integrating"
        good_rules = ("amigo", "simc") if integrating else ("amigo", "chr")
        d["rule"] = good_rules[rng.integers(2)] if cause != "aggressive_tuning" else "amigo"
        d["samples_per_cycle"] = float(np.exp(rng.uniform(np.log(p_lo), np.log(p_hi))))
        # the disturbance sets the period; place it loosely relative to the plant
        d["period_factor"] = (
            rng.uniform(1.0, 4.0) if cause in ("external_disturbance", "none") else None
        )
        d["margin_factor"] = rng.uniform(1.05, 1.3) if cause == "aggressive_tuning" else None
        _classic_effect_draws(d, n_samples, ts, s_lo, s_hi, snr_lo, snr_hi, slip_fraction,
                              stiction_models, rng)  # fmt: skip
        draws.append(d)

    # dimensionless plants (T = 1) first; Kc is invariant when time is rescaled, and the
    # PI phase does not depend on Kc, so w180 holds for any gain factor
    for d in draws:
        d["plant0"], _ = _plant_for(d["order"], d["lam_target"], 1.0, d["sign"] * d["k_mag"])
    settings0 = [_settings(d["plant0"], d["rule"], 0.0) for d in draws]
    w180, _ = _phase_crossovers(
        [d["plant0"] for d in draws], [s[0] for s in settings0], [s[1] for s in settings0],
        np.zeros(len(draws)), 600,
    )  # fmt: skip
    for d, w in zip(draws, w180, strict=True):
        period = 2 * np.pi / w
        if d["cause"] == "stiction":
            period *= _STICTION_PERIOD_FACTOR.get(d["order"], _STICTION_PERIOD_FACTOR_DEFAULT)
        elif d["period_factor"] is not None:
            period *= d["period_factor"]
        d["ts_d"] = period / d["samples_per_cycle"]  # sample time in units of T
        d["kc"], d["ti"] = _settings(d["plant0"], d["rule"], d["ts_d"])
        d["gain_factor"] = 1.0
    aggressive = [d for d in draws if d["cause"] == "aggressive_tuning"]
    if aggressive:
        _, margin = _phase_crossovers(
            [d["plant0"] for d in aggressive], [d["kc"] for d in aggressive],
            [d["ti"] for d in aggressive], np.array([d["ts_d"] for d in aggressive]), 600,
        )  # fmt: skip
        for d, m in zip(aggressive, margin, strict=True):
            d["gain_factor"] = m / d["margin_factor"]

    plants, controllers, valves, effects, rows = [], [], [], [], []
    for d in draws:
        plant, ctrl, valve, eff, row = _classic_loop(d, ts)
        plants.append(plant)
        controllers.append(ctrl)
        valves.append(valve)
        effects.append(eff)
        rows.append(row)
    return plants, controllers, valves, effects, rows


def _classic_effect_draws(
    d, n_samples, ts, s_lo, s_hi, snr_lo, snr_hi, slip_fraction, stiction_models, rng
):
    """A classic-world loop's draws for its valve and effects (in place into ``d``)."""
    cause = d["cause"]
    d["walk"] = rng.uniform(0.001, 0.004)
    d["S"] = d["J"] = np.nan
    d["valve"] = LinearValve()
    d["scenario"] = "limit_cycle" if cause == "stiction" else ""
    d["ti_slip"] = None
    if cause == "stiction" and rng.random() < slip_fraction:
        d["scenario"] = "slips"
        d["ti_slip"] = rng.uniform(5.0, 20.0)
    if cause == "stiction":
        model = stiction_models[rng.integers(len(stiction_models))]
        S = d["S"] = float(rng.uniform(s_lo, s_hi))
        if model == "relay":
            d["valve"], d["J"] = make_valve("relay", d=S), S
        else:
            d["J"] = float(S * rng.uniform(0.2, 1.0))
            d["valve"] = make_valve(model, S=S, J=d["J"])
        if d["scenario"] == "slips":
            n_steps = int(rng.integers(1, 5))
            d["sp_times"] = np.sort(rng.uniform(0.05, 0.8, n_steps) * n_samples * ts).round(6)
            d["sp_draws"] = (rng.uniform(0.5, 2.0, n_steps), _signs(rng, n_steps))
        else:
            d["sp_draws"] = (rng.uniform(0.3, 1.0), _signs(rng))
            d["sp_times"] = [ts * rng.integers(5, 20)]
    elif cause == "aggressive_tuning":
        d["sp_draws"] = (rng.uniform(0.5, 2.0), _signs(rng))
        d["sp_times"] = [ts * rng.integers(5, 20)]
    elif cause == "external_disturbance":
        d["sine"] = (rng.uniform(0.5, 2.0), float(rng.uniform(0, 2 * np.pi)))
    elif rng.random() < 0.5:
        n_steps = int(rng.integers(1, 4))
        d["sp_times"] = np.sort(rng.uniform(0, n_samples * ts, n_steps)).round(6)
        d["sp_draws"] = (rng.uniform(0.5, 2.0, n_steps), _signs(rng, n_steps))
    d["snr"] = snr = float(rng.uniform(snr_lo, snr_hi))
    # Choudhury's model re-sticks at every OP reversal, so noise inside the loop
    # would freeze it (Kano et al. 2004): its loops get noise on the record only
    where = "record" if getattr(d["valve"], "name", "") == "choudhury" else "loop"
    if rng.random() < 0.5:
        d["noise"] = WhiteNoise(snr_db=snr, where=where)
    else:
        d["noise"] = ARNoise(float(rng.uniform(0.3, 0.9)), snr_db=snr, where=where)


def _classic_loop(d, ts):
    """One classic-world loop from its draws and its tuning: simulator objects, meta row."""
    cause, rule, gain_factor = d["cause"], d["rule"], d["gain_factor"]
    scale = ts / d["ts_d"]
    plant, lam = _plant_for(d["order"], d["lam_target"], scale, d["sign"] * d["k_mag"])
    integrating = plant.integrating
    ctrl = PIController(d["kc"] * gain_factor, d["ti"] * scale, rule=rule)
    K, tau, Lapp = plant.foptd()
    g = abs(K) if not integrating else abs(K) * (plant.delay + plant.time_constant)
    nominal = 2.0 * g  # PV change of a 2 % valve move

    eff = [RandomWalkLoad(float(nominal * d["walk"]))]
    if d["ti_slip"] is not None:
        ctrl = PIController(ctrl.kc, ctrl.ti * d["ti_slip"], rule=rule)
    if "sp_times" in d:
        size, sign = d["sp_draws"]
        if cause == "stiction" and d["scenario"] == "slips":
            sizes = d["S"] * g * size * sign
            eff.append(SetpointSteps(d["sp_times"].tolist(), sizes.tolist()))
        elif cause == "stiction":
            eff.append(SetpointSteps(d["sp_times"], [float(size * d["S"] * g * sign)]))
        elif cause == "aggressive_tuning":
            eff.append(SetpointSteps(d["sp_times"], [float(nominal * size * sign)]))
        else:
            sizes = nominal * size * sign
            eff.append(SetpointSteps(d["sp_times"].tolist(), sizes.tolist()))
    if "sine" in d:
        size, phase = d["sine"]
        eff.append(
            SinusoidalDisturbance(float(nominal * size), ts * d["samples_per_cycle"], phase=phase)
        )
    eff.append(d["noise"])
    valve = d["valve"]
    row = {
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
        "S": d["S"],
        "J": d["J"],
        "rule": rule,
        "gain_factor": gain_factor,
        "Kc": ctrl.kc,
        "Ti": ctrl.ti,
        "ts": ts,
        "samples_per_cycle": d["samples_per_cycle"],
        "snr_db": d["snr"],
        "scenario": d["scenario"],
        "effects": tuple(eff),  # described by make_loops if meta is asked for
    }
    return plant, ctrl, valve, eff, row


WORLDS = ("default", "classic")
RULES = ("amigo", "chr", "zn", "cc", "simc")
_RULES_SELF = ("amigo", "chr", "zn", "cc")
_RULES_INT = ("amigo", "simc")
NOISE_COLOURS = ("white", "ar1", "bandlimited")
SETPOINT_REGIMES = ("constant", "steps", "step", "cascade")
_REGIME_WEIGHTS = {"constant": 0.35, "steps": 0.3, "step": 0.1, "cascade": 0.25}
# loop type of a simulated loop by plant order, and the orders a measured loop type allows
_LOOP_TYPES = {"integrating": "level", 1: "flow", 2: "pressure"}
_TYPE_ORDERS = {"level": ("integrating",), "flow": (1, 2), "pressure": (1, 2)}
# PV's own variation stays below this frequency (cycles per sample), so that the noise, not
# it, rules PV's second differences (noise_colour)
_OWN_MAX_CUTOFF = 0.05
RECORDING_EFFECTS = ("quantisation", "hold", "compression", "averaging")
# recording effects make_loops can draw when asked: the default ones and an interpolated export
_RECORDING_NAMES = RECORDING_EFFECTS + ("swinging_door",)

_SHARED_DEFAULTS = {
    "stiction_fraction": 0.5,
    "causes": ("aggressive_tuning", "external_disturbance", "none"),
    "ts": 1.0,
    "orders": (1, 2, 3, 4, "integrating"),
}
_CLASSIC_DEFAULTS = {
    **_SHARED_DEFAULTS,
    "lambda_range": (0.1, 1.0),
    "stiction_models": STICTION_MODELS,
    "S_range": (0.5, 10.0),
    "snr_db_range": (10.0, 40.0),
    "period_range": (20.0, 200.0),
    "slip_fraction": 0.0,
}
_DEFAULT_DEFAULTS = {
    **_SHARED_DEFAULTS,
    "lambda_range": (0.05, 1.5),
    "stiction_models": STICTION_MODELS + ("he",),
    "S_range": (0.3, 8.0),
    "snr_db_range": (0.0, 40.0),
    "period_range": (8.0, 300.0),
    "slip_fraction": 0.3,
    "rules": RULES,
    "gain_margin_range": (1.1, 2.5),
    "noise_colours": NOISE_COLOURS,
    "setpoint_regimes": SETPOINT_REGIMES,
    "recording": RECORDING_EFFECTS,
    "recording_fraction": 0.5,
    "pv_own_share": (0.0, 0.0),
    "oscillating_fraction": 1.0,
    "setpoint_weights": _REGIME_WEIGHTS,
    "short_fraction": 0.25,
    "load_step_fraction": 0.0,
    "min_length": 200,
    "warmup": None,  # max(300, n_samples // 5)
}


# frequency grid of the default world's phase-crossover search (interpolated between points)
_GRID = 240


def _loguniform(rng, lo, hi):
    return float(np.exp(rng.uniform(_log(lo), _log(hi))))


@functools.lru_cache(maxsize=1024)
def _log(x):
    return np.log(x)


_SIGNS = np.array([-1.0, 1.0])


def _signs(rng, size=None):
    """``rng.choice([-1.0, 1.0], size)``: the same draws and values, without its overhead."""
    return _SIGNS[rng.integers(0, 2, size=size)]


def _family(order):
    if order == "integrating":
        return "integrating"
    return {1: "first_order", 2: "second_order"}.get(order, "higher_order")


def _pick(rng, options, p=None):
    """One of ``options``; ``p`` are weights (renormalised)."""
    if p is None:
        return options[rng.integers(len(options))]
    return options[int(np.searchsorted(_cumulative(tuple(p)), rng.random(), side="right"))]


@functools.lru_cache(maxsize=256)
def _cumulative(p):
    """Cumulative renormalised weights ``p`` (a tuple: loops share a few weightings)."""
    p = np.asarray(p, dtype=float)
    c = np.cumsum(p / p.sum())
    c.flags.writeable = False
    return c


def _recording_effect(name, rng):
    """One historian recording effect by name, sizes relative to each tag's span."""
    if name == "quantisation":
        return [
            SpanQuantization(_loguniform(rng, 0.005, 0.1), channels=("pv",)),
            SpanQuantization(_loguniform(rng, 0.005, 0.1), channels=("op",)),
        ]
    if name == "hold":
        return [HoldLastValue(rng.uniform(0.1, 0.55), mean_run=_loguniform(rng, 1.5, 20.0))]
    if name == "compression":
        return [DeadbandCompression(_loguniform(rng, 0.01, 0.15))]
    if name == "swinging_door":
        return [SwingingDoorCompression(_loguniform(rng, 0.005, 0.05))]
    return [IntervalAveraging(int(rng.integers(2, 11)))]


def _loop_type(order):
    return _LOOP_TYPES.get(order, "temperature")


def _takes_loop_type(method):
    """Whether a realism's ``recording_effects`` takes the keyword ``loop_type``."""
    import inspect

    params = inspect.signature(method).parameters.values()
    return any(p.name == "loop_type" or p.kind == p.VAR_KEYWORD for p in params)


def _draw_default(labels, n_samples, n_warm, ts, opt, rng):
    """Loops of the default world; returns simulator inputs and per-loop post-processing.

    Two passes: every loop's random draws first, loop by loop (none depends on the loop's
    dynamics, so they come in the same order as when each loop was finished before the
    next one was drawn), then the dynamics, with the phase crossovers of all loops
    computed together, and the objects built from the draws.
    """
    realism = opt["realism"]
    profiles = callable(getattr(realism, "loop_profile", None))
    typed = realism is not None and _takes_loop_type(realism.recording_effects)
    draws = [_default_draws(cause, n_samples, n_warm, ts, opt, rng, profiles, typed)
             for cause in labels]  # fmt: skip

    # tuning on the dimensionless plant (T = 1) first; Kc is invariant when time is rescaled
    for d in draws:
        d["plant0"], _ = _plant_for(d["order"], d["lam_target"], 1.0, d["sign"] * d["k_mag"])
        d["kc0"], d["ti0"] = _settings(d["plant0"], d["rule"], 0.0)
    w180, _ = _phase_crossovers(
        [d["plant0"] for d in draws], [d["kc0"] for d in draws],
        [d["ti0"] * d["ti_factor"] for d in draws], np.zeros(len(draws)), _GRID,
    )  # fmt: skip
    for d, w in zip(draws, w180, strict=True):
        pu = 2 * np.pi / w  # ultimate period in units of T
        period = pu if d["period_factor"] is None else pu * d["period_factor"]
        # at least 4 samples per ultimate period: a loop sampled slower is not controlled
        d["ts_d"] = min(period / d["samples_per_cycle"], pu / 4.0)
        d["samples_per_cycle"] = period / d["ts_d"]
        d["pu_samples"] = pu / d["ts_d"]
        kc, ti = _settings(d["plant0"], d["rule"], d["ts_d"])
        d["kc"], d["ti"] = kc * d["kc_factor"], ti * d["ti_factor"]
        d["gain_factor"] = 1.0
    aggressive = [d for d in draws if d["cause"] == "aggressive_tuning"]
    if aggressive:
        _, base_margin = _phase_crossovers(
            [d["plant0"] for d in aggressive], [d["kc"] for d in aggressive],
            [d["ti"] for d in aggressive], np.array([d["ts_d"] for d in aggressive]), _GRID,
        )  # fmt: skip
        for d, m in zip(aggressive, base_margin, strict=True):
            d["gain_factor"] = m / d["margin"]

    plants, controllers, valves, effects, records, rows = [], [], [], [], [], []
    for d in draws:
        plant, ctrl, valve, eff, rec, row = _default_loop(d, n_samples, n_warm, ts)
        plants.append(plant)
        controllers.append(ctrl)
        valves.append(valve)
        effects.append(eff)
        records.append(rec)
        rows.append(row)
    return plants, controllers, valves, effects, records, rows


def _default_draws(cause, n_samples, n_warm, ts, opt, rng, profiles, typed):
    """One loop's random draws of the default world, in the order they have always been made.

    Objects that need none of the loop's dynamics are built here; the draws that scale
    with it are kept for :func:`_default_loop`.
    """
    lam_lo, lam_hi = opt["lambda_range"]
    p_lo, p_hi = opt["period_range"]
    s_lo, s_hi = opt["S_range"]
    realism = opt["realism"]
    # a calibrated world copies one measured loop's profile: its loop type sets the plant
    # type, its settings (noise, PV's own variation, oscillating or quiet, setpoint
    # regime) and recording are this loop's, drawn alike for every cause
    profile = realism.loop_profile(rng) if profiles else {}
    settings = profile.get("settings", {})
    lopt = {**opt, **{k: v for k, v in settings.items() if k not in opt["explicit"]}}
    allowed = opt["orders"]
    if profile.get("loop_type") in _TYPE_ORDERS:
        allowed = [o for o in opt["orders"] if o in _TYPE_ORDERS[profile["loop_type"]]]
        allowed = allowed or opt["orders"]
    d = {"cause": cause, "order": _pick(rng, allowed)}
    order = d["order"]
    d["loop_type"] = profile.get("loop_type") or _loop_type(order)
    snr_lo, snr_hi = lopt["snr_db_range"]
    integrating = d["integrating"] = order == "integrating"
    d["lam_target"] = rng.uniform(lam_lo, lam_hi)
    # direct and reverse acting loops alike
    d["sign"] = -1.0 if rng.random() < 0.5 else 1.0
    d["k_mag"] = _loguniform(rng, 0.5, 2.0)
    rules = [r for r in opt["rules"] if r in (_RULES_INT if integrating else _RULES_SELF)]
    d["rule"] = _pick(rng, rules)
    # how the loop is run, drawn alike for every cause
    kc_factor = ti_factor = 1.0
    loop_kind = "standard"
    # quiet loops of every cause: sluggish integral action and slow process variation
    # swamp the cycle's drive (an external oscillation is weak, a sticky valve sticks
    # for long stretches and jerks along a wandering OP)
    oscillating = True
    if lopt["oscillating_fraction"] < 1.0:
        oscillating = bool(rng.random() < lopt["oscillating_fraction"])
    if integrating and rng.random() < 0.5:
        # averaging level control: loose P-dominant tuning, OP follows PV in phase
        loop_kind = "averaging"
        kc_factor, ti_factor = _loguniform(rng, 0.1, 0.5), _loguniform(rng, 2.0, 10.0)
    elif not oscillating or rng.random() < opt["slip_fraction"]:
        loop_kind = "sluggish"
        kc_factor, ti_factor = rng.uniform(0.4, 1.0), _loguniform(rng, 3.0, 20.0)
    d.update(oscillating=oscillating, loop_kind=loop_kind, kc_factor=kc_factor,
             ti_factor=ti_factor)  # fmt: skip
    # the period in ultimate periods (the aggressively tuned loop's is the ultimate one)
    d["period_factor"] = {
        "stiction": (1.5, 6.0), "external_disturbance": (0.7, 20.0), "none": (1.0, 4.0),
    }.get(cause)  # fmt: skip
    if d["period_factor"] is not None:
        d["period_factor"] = _loguniform(rng, *d["period_factor"])
    d["samples_per_cycle"] = _loguniform(rng, p_lo, p_hi)
    d["margin"] = np.nan
    if cause == "aggressive_tuning":
        d["margin"] = _loguniform(rng, *opt["gain_margin_range"])

    # a feed change at the start of the warm-up moves every loop off its initial
    # rest, so a sticky valve is cycling or slipping by the time the record starts
    d["load_step"] = LoadStep(_loguniform(rng, 0.5, 5.0) * _signs(rng))
    # process noise near the loop's bandwidth and a slow random walk, every loop
    d["load_where"] = "input" if rng.random() < 0.5 else "output"
    d["load_cutoff"] = _loguniform(rng, 0.3, 3.0)  # times the ultimate frequency
    d["load_size"] = _loguniform(rng, 0.005, 0.5)
    if not oscillating:
        d["load_cutoff"] = _loguniform(rng, 0.05, 0.5)
        d["load_size"] = _loguniform(rng, 0.5, 3.0)
    d["load_order"] = int(rng.integers(1, 3))
    d["walk"] = rng.uniform(0.001, 0.004) if rng.random() < 0.5 else None
    d["drift"] = rng.random() < 0.3
    if d["drift"]:
        d["drift_where"] = "input" if rng.random() < 0.5 else "output"
        d["drift_size"] = _loguniform(rng, 0.3, 2.0)
        d["drift_segments"] = int(rng.integers(1, 4))

    S = J = np.nan
    valve = LinearValve()
    model = "linear"
    if cause == "stiction":
        model = _pick(rng, opt["stiction_models"])
        S = _loguniform(rng, s_lo, s_hi)
        J = S if model == "relay" else float(S * rng.uniform(0.1, 1.0))
        if model == "relay":
            valve = RelayValve(S)
        elif model == "he":
            valve = HeValve.from_sj(S, J)
        else:
            valve = make_valve(model, S=S, J=J)
    d.update(S=S, J=J, valve=valve)
    d["disturbance"] = ""
    if cause == "external_disturbance":
        kind = d["disturbance"] = _pick(rng, ("sine", "narrowband", "square"))
        d["dist_where"] = "input" if rng.random() < 0.4 else "output"
        d["dist_size"] = [_loguniform(rng, 0.5, 3.0)]
        if not oscillating:
            d["dist_size"].append(_loguniform(rng, 0.05, 0.3))
        if kind == "sine":
            d["dist_args"] = {"phase": rng.uniform(0, 2 * np.pi)}
        elif kind == "narrowband":
            d["dist_args"] = {"damping": _loguniform(rng, 0.01, 0.2)}
        else:
            d["dist_args"] = {"lag": rng.uniform(0.0, 0.15), "phase": rng.uniform(0, 2 * np.pi),
                              "jitter": rng.uniform(0.0, 0.2)}  # fmt: skip

    regime = lopt.get("setpoint_regime")
    if regime not in opt["setpoint_regimes"]:
        weights = [lopt["setpoint_weights"].get(r, 0.0) for r in opt["setpoint_regimes"]]
        regime = _pick(rng, opt["setpoint_regimes"], weights)
    d["regime"] = regime
    if regime in ("steps", "step"):
        n_steps = int(rng.integers(1, 7)) if regime == "steps" else 1
        lo_size, hi_size = (0.2, 2.0) if regime == "steps" else (1.0, 4.0)
        d["sp_times"] = n_warm + np.sort(rng.uniform(0.05, 0.9, n_steps)) * n_samples
        d["sp_sizes"] = np.exp(rng.uniform(np.log(lo_size), np.log(hi_size), n_steps))
        d["sp_signs"] = _signs(rng, n_steps)
    elif regime == "cascade":
        d["cascade"] = (_loguniform(rng, 0.5, 5.0), _loguniform(rng, 0.1, 1.0),
                        rng.uniform(0.0, 0.5))  # fmt: skip

    # PV's own variation, which OP does not explain, slower than the loop's bandwidth: at
    # the sensor, so the controller does not act on it (seen by the controller, it is
    # rejected and moves OP: PV and OP stay as tightly linked as without it)
    own_lo, own_hi = lopt["pv_own_share"]
    d["own"], d["own_cutoff"] = 0.0, None
    if own_hi > 0:
        d["own"] = float(rng.uniform(own_lo, own_hi))
        d["own_cutoff"] = _loguniform(rng, 0.1, 1.0)  # times the ultimate frequency

    colour = d["colour"] = _pick(rng, lopt["noise_colours"])
    snr = d["snr"] = float(rng.uniform(snr_lo, snr_hi))
    # the SNR is relative to PV with its own variation, the noise's reference without it
    snr_noise = snr + 10.0 * np.log10(1.0 - d["own"])
    # Choudhury's model re-sticks at every OP reversal, so noise inside the loop would
    # freeze it (Kano et al. 2004); some controllers filter PV and give a smooth OP too
    path = d["path"] = "record" if model == "choudhury" or rng.random() < 0.35 else "loop"
    if colour == "white":
        d["noise"] = WhiteNoise(snr_db=snr_noise, where=path)
    elif colour == "ar1":
        d["noise"] = ARNoise(float(rng.uniform(0.5, 0.95)), snr_db=snr_noise, where=path)
    else:
        d["noise"] = BandLimitedNoise(_loguniform(rng, 0.03, 0.25), snr_db=snr_noise,
                                      where=path)  # fmt: skip

    # historian recording, applied after the warm-up is cut and PV units are set
    d["pv_scale"] = _loguniform(rng, 0.05, 20.0)
    d["pv_center"] = rng.uniform(20.0, 80.0)
    extra, rec_names = [], []
    if profile:
        extra = list(profile.get("recording", []))
        rec_names = [type(e).__name__ for e in extra]
    elif realism is not None:
        extra = list(
            realism.recording_effects(rng, loop_type=d["loop_type"])
            if typed
            else realism.recording_effects(rng)
        )
        rec_names = [type(e).__name__ for e in extra]
    elif opt["recording"] and rng.random() < opt["recording_fraction"]:
        n_rec = 1 if rng.random() < 0.7 or len(opt["recording"]) == 1 else 2
        picks = rng.choice(len(opt["recording"]), n_rec, replace=False)
        for i in sorted(picks):
            name = opt["recording"][i]
            extra += _recording_effect(name, rng)
            rec_names.append(name)
    d["recording"], d["rec_names"] = extra, rec_names
    d["length"] = n_samples
    if rng.random() < opt["short_fraction"]:
        d["length"] = int(_loguniform(rng, min(opt["min_length"], n_samples), n_samples))
    d["initial_op"] = rng.uniform(15.0, 85.0)
    # unannounced load steps in the record (feed or supply changes), every cause alike;
    # drawn last and only when asked for, so that the older worlds keep their draws
    d["load_steps"] = None
    if opt["load_step_fraction"] > 0 and rng.random() < opt["load_step_fraction"]:
        n_steps = int(rng.integers(1, 5))
        d["load_steps"] = (
            np.sort(rng.uniform(0.05, 0.95, n_steps)),
            np.exp(rng.uniform(np.log(0.5), np.log(4.0), n_steps)) * _signs(rng, n_steps),
            "input" if rng.random() < 0.5 else "output",
        )
    return d


def _default_loop(d, n_samples, n_warm, ts):
    """One default-world loop from its draws and its tuning: the simulator's objects, its
    recording and its meta row."""
    order, integrating, oscillating = d["order"], d["integrating"], d["oscillating"]
    pu_samples, samples_per_cycle = d["pu_samples"], d["samples_per_cycle"]
    cause, rule, gain_factor = d["cause"], d["rule"], d["gain_factor"]
    scale = ts / d["ts_d"]
    plant, lam = _plant_for(order, d["lam_target"], scale, d["sign"] * d["k_mag"])
    ctrl = PIController(d["kc"] * gain_factor, d["ti"] * scale, rule=rule)
    K, tau, Lapp = plant.foptd()
    g = abs(K) if not integrating else abs(K) * (plant.delay + plant.time_constant)
    nominal = 2.0 * g  # PV change of a 2 % valve move

    eff = [d["load_step"]]
    unit = 2.0 if d["load_where"] == "input" else nominal
    cutoff = min(d["load_cutoff"] / pu_samples, 0.45)
    eff.append(ColouredLoad(unit * d["load_size"], cutoff, d["load_order"], d["load_where"]))
    if d["walk"] is not None:
        eff.append(RandomWalkLoad(float(nominal * d["walk"])))
    if d["drift"]:
        unit = 2.0 if d["drift_where"] == "input" else nominal
        eff.append(Drift(unit * d["drift_size"], d["drift_segments"], d["drift_where"]))
    if d["load_steps"] is not None:
        times, sizes, where = d["load_steps"]
        unit = 2.0 if where == "input" else nominal
        for t_frac, size in zip(times, sizes):
            t_step = ts * round(n_warm + t_frac * d["length"])
            eff.append(LoadStep(float(unit * size), t_step, where))
    if cause == "external_disturbance":
        where = d["dist_where"]
        amp = (2.0 if where == "input" else nominal) * d["dist_size"][0]
        for factor in d["dist_size"][1:]:
            amp *= factor
        dist_period = ts * samples_per_cycle
        args = d["dist_args"]
        if d["disturbance"] == "sine":
            eff.append(SinusoidalDisturbance(amp, dist_period, args["phase"], where))
        elif d["disturbance"] == "narrowband":
            eff.append(NarrowbandDisturbance(amp, dist_period, args["damping"], where))
        else:
            eff.append(SquareDisturbance(
                amp, dist_period, lag=dist_period * args["lag"], phase=args["phase"],
                jitter=args["jitter"], where=where,
            ))  # fmt: skip
    if "sp_times" in d:
        sizes = nominal * d["sp_sizes"]
        sizes *= d["sp_signs"]
        eff.append(SetpointSteps((ts * np.round(d["sp_times"])).tolist(), sizes.tolist()))
    elif "cascade" in d:
        tau_factor, size, jitter = d["cascade"]
        phi = float(np.exp(-1.0 / (pu_samples * tau_factor)))
        eff.append(CascadeSetpoint(nominal * size, phi, jitter))
    eff.append(d["noise"])
    own = d["own"]
    if own > 0:
        own_cutoff = min(d["own_cutoff"] / pu_samples, _OWN_MAX_CUTOFF)
        eff.append(PVVariation(own, own_cutoff, "record", order=2))

    sensor = [e for e in eff if e.kind == "recording"]
    rec = sensor + d["recording"]
    valve = d["valve"]
    record = (rec, d["pv_scale"], d["pv_center"], d["length"], d["initial_op"])
    row = {
        "cause": cause,
        "y": int(cause == "stiction"),
        "plant": "integrating" if integrating else type(plant).__name__.lower(),
        "plant_family": _family(order),
        "loop_type": d["loop_type"],
        "order": plant.order,
        "gain": plant.gain,
        "action": "reverse" if plant.gain > 0 else "direct",
        "time_constant": plant.time_constant,
        "delay": plant.delay,
        "apparent_time_constant": tau,
        "apparent_delay": Lapp,
        "lambda": lam,
        "pv_per_valve": g,
        "valve": getattr(valve, "name", "linear"),
        "S": d["S"],
        "J": d["J"],
        "rule": rule,
        "loop_kind": d["loop_kind"],
        "kc_factor": d["kc_factor"],
        "ti_factor": d["ti_factor"],
        "gain_factor": gain_factor,
        "gain_margin": d["margin"],
        "Kc": ctrl.kc,
        "Ti": ctrl.ti,
        "ts": ts,
        "samples_per_cycle": samples_per_cycle,
        "samples_per_ultimate_period": pu_samples,
        "snr_db": d["snr"],
        "noise_colour": d["colour"],
        "noise_path": d["path"],
        "drift": d["drift"],
        "load_steps": 0 if d["load_steps"] is None else len(d["load_steps"][0]),
        "disturbance": d["disturbance"],
        "setpoint_regime": d["regime"],
        "pv_own_share": own,
        "oscillating": oscillating,
        "recording": "+".join(d["rec_names"]) if d["rec_names"] else "none",
        "record_length": d["length"],
        "initial_op": d["initial_op"],
        "pv_scale": d["pv_scale"],
        "pv_center": d["pv_center"],
        "warmup": n_warm,
        "scenario": ("slips" if d["loop_kind"] != "standard" else "limit_cycle")
        if cause == "stiction"
        else "",
        "effects": tuple(eff + d["recording"]),  # described by make_loops if meta is asked for
    }
    return plant, ctrl, valve, [e for e in eff if e.kind == "exogenous"], record, row


# a sticky valve must slip this often in the record, or the record holds no evidence of it
_MIN_SLIPS = 3
_MAX_REDRAWS = 6


def _slip_starts(valve, length):
    """Valve moves over a record and the first sample of each run of movement (the slips:
    ``starts.sum()`` is how many times the valve starts to move within the record)."""
    step = np.abs(np.diff(valve[:length]))
    moving = step > 1e-9
    starts = moving.copy()
    starts[1:] &= ~moving[:-1]
    return step, starts


# a slip whose PV effect is below one noise standard deviation cannot be seen in the record
_VISIBLE_SLIP_SNR = 1.0


def _slip_snr(pv, step, starts, length, pv_per_valve, snr_db):
    """Median PV change of a valve slip over the PV noise's standard deviation.

    A slip is the first sample of each run of valve movement (``step`` and ``starts`` from
    :func:`_slip_starts`); its PV change is taken as the plant's gain (for an integrating
    plant, the PV change while the delay and time constant pass) times the jump. The
    noise's standard deviation follows from the SNR, which is relative to the noise-free
    PV's spread: ``sd(PV) / sqrt(1 + 10^(snr/10))``.
    """
    if not starts.any():
        return 0.0
    jump = float(np.median(step[starts]))
    pv = pv[:length]
    # np.std is np.nanstd's value without NaN, at a fraction of its cost
    sd = np.std(pv) if np.isfinite(pv).all() else np.nanstd(pv)
    noise_sd = float(sd) / np.sqrt(1.0 + 10.0 ** (snr_db / 10.0))
    return jump * pv_per_valve / noise_sd if noise_sd > 0 else np.inf


def _simulate_default(labels, n_samples, n_warm, ts, opt, rng):
    """Draw and simulate the default world; sticky loops whose valve never slips in the
    record (a band wider than anything OP does there) are drawn again.

    The records are written straight into the output (the warm-up is simulated, not
    stored); each chunk's valve positions are looked at and its PV put in its units
    while the chunk is fresh, so the valve positions are never kept whole.
    """
    X = np.empty((len(labels), n_samples, 3))
    todo = np.arange(len(labels))
    records, rows = [None] * len(labels), [None] * len(labels)
    for _ in range(_MAX_REDRAWS):
        plants, controllers, valves, effects, rec, row = _draw_default(
            [labels[i] for i in todo], n_samples, n_warm, ts, opt, rng
        )
        for k, i in enumerate(todo):
            records[i], rows[i] = rec[k], row[k]
        sticky = np.array([labels[i] == "stiction" for i in todo])
        slips = np.zeros(len(todo), dtype=int)
        out = X if len(todo) == len(labels) else np.empty((len(todo), n_samples, 3))

        def look(lo, hi, valve, out=out, rec=rec, row=row, sticky=sticky, slips=slips):
            for k in np.flatnonzero(sticky[lo:hi]) + lo:
                step, starts = _slip_starts(valve[k - lo], rec[k][3])
                slips[k] = starts.sum()
                row[k]["slip_snr"] = _slip_snr(
                    out[k, :, 0], step, starts, rec[k][3], row[k]["pv_per_valve"],
                    row[k]["snr_db"],
                )  # fmt: skip
            for k in range(lo, hi):
                row[k].setdefault("slip_snr", np.nan)
                row[k]["stiction_visible"] = bool(row[k]["slip_snr"] >= _VISIBLE_SLIP_SNR)
            # a linear plant's PV can be relabelled exactly: other units, other level
            scale = np.array([r[1] for r in rec[lo:hi]])
            center = np.array([r[2] for r in rec[lo:hi]])
            _relabel(out[lo:hi], 50.0 - center, scale)

        loops = _loop_arrays(
            plants, controllers, valves, np.full(len(todo), float(ts)),
            np.array([r[4] for r in rec]),
        )  # fmt: skip
        _simulate(
            loops, np.full((len(todo), 1), 50.0), effects, n_samples + n_warm, rng, out,
            start=n_warm, on_chunk=look,
        )  # fmt: skip
        if out is not X:
            X[todo] = out
        todo = todo[sticky & (slips < _MIN_SLIPS)]
        if len(todo) == 0:
            break
    return _finish_default(X, records, ts, rng), records, rows


@njit(cache=True)
def _relabel(X, offset, scale):
    """PV and SP of loop ``j`` to ``(x - offset[j]) * scale[j]``, in place, in one pass."""
    for j in range(X.shape[0]):
        for k in range(X.shape[1]):
            X[j, k, 0] = (X[j, k, 0] - offset[j]) * scale[j]
            X[j, k, 2] = (X[j, k, 2] - offset[j]) * scale[j]


def _finish_default(X, records, ts, rng):
    """Apply recording effects and record lengths, in place."""
    for j, (rec, _, _, length, _) in enumerate(records):
        if rec:
            sig = {"pv": X[j, :, 0].copy(), "op": X[j, :, 1].copy(), "sp": X[j, :, 2].copy()}
            for eff in rec:
                sig = eff.record(sig, ts, rng)
            for c, key in enumerate(CHANNELS):
                X[j, :, c] = sig[key]
        X[j, length:, :] = np.nan
    return X


def _check_weights(weights, regimes):
    """Setpoint regime weights: a mapping regime -> weight >= 0, positive over ``regimes``."""
    try:
        weights = {str(k): float(v) for k, v in dict(weights).items()}
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"setpoint_weights must map regimes to weights; got {weights!r}."
        ) from exc
    bad = [k for k in weights if k not in SETPOINT_REGIMES]
    if bad or any(not np.isfinite(v) or v < 0 for v in weights.values()):
        raise ValueError(
            f"setpoint_weights must map regimes of {SETPOINT_REGIMES} to finite weights >= 0; "
            f"got {weights!r}."
        )
    if sum(weights.get(r, 0.0) for r in regimes) <= 0:
        raise ValueError(
            f"setpoint_weights must give a positive weight to one of {regimes}; got {weights!r}."
        )
    return weights


def _check_subset(values, allowed, name):
    values = tuple(values)
    bad = [v for v in values if v not in allowed]
    if bad or not values:
        raise ValueError(f"{name} must be a non-empty subset of {allowed}; got {values!r}.")
    return values


@single_blas_thread
def make_loops(
    n_loops=100,
    n_samples=2000,
    *,
    world="default",
    stiction_fraction=None,
    causes=None,
    ts=None,
    lambda_range=None,
    orders=None,
    stiction_models=None,
    S_range=None,
    snr_db_range=None,
    period_range=None,
    slip_fraction=None,
    rules=None,
    gain_margin_range=None,
    noise_colours=None,
    setpoint_regimes=None,
    recording=None,
    recording_fraction=None,
    pv_own_share=None,
    oscillating_fraction=None,
    setpoint_weights=None,
    short_fraction=None,
    load_step_fraction=None,
    min_length=None,
    warmup=None,
    realism=None,
    random_state=None,
    return_meta=False,
):
    """Generate simulated control loops, oscillating because of stiction or not.

    Each loop is a closed loop (plant, PI controller, valve) simulated with
    :func:`sktiction.simulation.simulate_loops`. Two worlds:

    * ``world="default"``: loops as plant historians record them, every nuisance
      drawn alike for sticky and healthy loops so that no cause can be read from
      it (see *Default world* below).
    * ``world="classic"``: the clean world of sktiction 0.1 (see *Classic world*);
      for the same seed and arguments it reproduces that version's loops exactly.

    Arguments left at ``None`` take the world's default (listed with each
    parameter), then any value from ``realism.overrides``.

    **Causes** (both worlds): ``"stiction"`` (``y = 1``), ``"aggressive_tuning"``,
    ``"external_disturbance"`` and ``"none"`` (``y = 0``).

    **Default world.** Every loop runs 50 % direct, 50 % reverse acting
    (plant gain sign), from an OP of 15-85 %, with PV in its own units (scale
    0.05-20, level 20-80 scaled) and is recorded after a warm-up of ``warmup``
    samples, which begins with a feed change (a load step of 0.5-5 % at the
    plant input), so that no loop is recorded at rest and a sticky valve is
    already cycling or slipping (the start-up is the same for all causes).
    Drawn alike for every cause:

    - tuning rule (AMIGO, CHR, Ziegler-Nichols, Cohen-Coon; AMIGO or SIMC for
      integrating plants), and how the loop is run: averaging level control for
      half of the integrating plants (``Kc`` x 0.1-0.5, ``Ti`` x 2-10: OP follows
      PV in phase), sluggish integral action for a share ``slip_fraction`` of the
      others (``Ti`` x 3-20), standard otherwise;
    - process noise near the loop's bandwidth (band-limited at the plant input
      or output: with a lightly damped loop this gives irregular,
      amplitude-modulated cycles), a random-walk load in half, a slow
      piecewise-linear drift in 30 % (the loop rejects it, OP ramps);
    - setpoint regime (weights ``setpoint_weights``): constant (35 %), 1-6
      operator steps (30 %), one large step (10 %), cascade setpoint moving on
      every sample (25 %);
    - quiet loops in a share ``1 - oscillating_fraction`` (none by default) and PV's
      own variation, a share of the PV variance in ``pv_own_share`` (none by
      default);
    - measurement noise: white, AR(1) or band-limited, SNR uniform in
      ``snr_db_range`` dB, seen by the controller or (35 %, and always with
      Choudhury's valve, which noise in the loop would freeze) on the record
      only, as behind a PV filter;
    - historian recording in a share ``recording_fraction``: one or two of
      ``recording`` (quantisation, hold-last-value, compression, interval
      averaging);
    - record length: a share ``short_fraction`` of the loops is cut to a
      log-uniform length between ``min_length`` and ``n_samples`` (NaN-padded).

    Per cause: stiction with a relay, Choudhury, Kano or He et al. (2007)
    valve, ``S`` log-uniform in ``S_range`` (small bands included), ``J / S``
    0.1-1; limit cycles, slips at setpoint moves, intermittent stick-slip in
    noise and long stuck stretches while OP ramps all arise from the draws
    above. Aggressive tuning: ``Kc`` set so that the gain margin is log-uniform
    in ``gain_margin_range`` (noise-driven, lightly damped). External
    disturbance: sine, narrow-band (wandering amplitude and phase) or filtered
    square wave at the plant input or output, with a period of 0.7-20 times
    the loop's ultimate period (slow ones are rejected: OP carries the cycle).

    **Classic world.** Starts at steady state with PV = SP = 50 and OP = 50 %.
    Stiction: relay, Choudhury or Kano valve, ``S`` uniform in ``S_range``,
    ``J / S`` uniform in 0.2-1, good tuning (AMIGO or CHR; AMIGO or SIMC for
    integrating plants), started by a setpoint step of 0.3-1 times ``S``; a
    share ``slip_fraction`` has sluggish integral action (``Ti`` 5-20 times the
    rule's) and 1-4 setpoint moves instead (scenario ``"slips"``). Aggressive
    tuning: AMIGO ``Kc`` raised so the gain margin is 1.05-1.3, started by a
    setpoint step. External disturbance: sinusoidal load at the plant output.
    None: noise, random-walk load and, for half of them, setpoint steps. White
    or AR(1) noise with SNR in ``snr_db_range`` (Choudhury loops on the record
    only), a quarter direct acting.

    Both worlds: plants are n-th order lags ``K e^{-Ls} / (T s + 1)^n`` or
    integrating plants ``K e^{-Ls} / (s (T s + 1))``, ``|K|`` log-uniform in
    0.5-2; the delay ``L`` makes the apparent ``lambda = (h + L) / tau``
    (Singhal & Salsbury 2005, Eq. 6) uniform in ``lambda_range`` (higher
    orders whose own lambda exceeds it get ``L = 0.02 T``; meta records the
    actual value; NaN for integrating plants, where ``L = lambda T``). The
    plant time constant is scaled so that the expected oscillation period
    spans a number of samples drawn log-uniformly from ``period_range``. SNR is
    relative to the PV of a noise-free pilot run
    (:mod:`sktiction.simulation.effects`).

    Parameters
    ----------
    n_loops : int, default=100
        Number of loops (>= 1).
    n_samples : int, default=2000
        Samples per loop (>= 2).
    world : {"default", "classic"}, default="default"
        Which simulated world (above).
    stiction_fraction : float, default 0.5
        Share of stiction loops (0-1), rounded to a whole number of loops; the
        rest is split evenly over ``causes``.
    causes : tuple of str, default ("aggressive_tuning", "external_disturbance", "none")
        Non-stiction causes to draw from.
    ts : float, default 1.0
        Sample time (> 0), also the time unit of the meta data.
    lambda_range : tuple of float, default (0.05, 1.5); classic (0.1, 1.0)
        Range of ``lambda`` (0 < low <= high).
    orders : tuple, default (1, 2, 3, 4, "integrating")
        Plant orders (integers 1-10) and/or ``"integrating"``, drawn uniformly.
    stiction_models : tuple of str, default ("relay", "choudhury", "kano", "he")
        Stiction valve models drawn uniformly for stiction loops (classic: no "he").
    S_range : tuple of float, default (0.3, 8.0); classic (0.5, 10.0)
        Stiction band ``S`` (relay ``d``) in % of span (0 < low <= high <= 50).
    snr_db_range : tuple of float, default (0.0, 30.0); classic (10.0, 40.0)
        Signal-to-noise ratio of the measurement noise in dB.
    period_range : tuple of float, default (8.0, 300.0); classic (20.0, 200.0)
        Target oscillation period in samples (2 < low <= high).
    slip_fraction : float, default 0.3; classic 0.0
        Default world: share (0-1) of loops of every cause with sluggish integral
        action (sticky ones among them slip and stay stuck while OP ramps).
        Classic world: share of stiction loops in scenario ``"slips"``.
    rules : tuple of str, default ("amigo", "chr", "zn", "cc", "simc")
        Default world only: tuning rules to draw from (``"simc"`` is for
        integrating plants only, ``"chr"``, ``"zn"``, ``"cc"`` for self-regulating
        ones; each plant type needs one).
    gain_margin_range : tuple of float, default (1.1, 2.5)
        Default world only: gain margin of aggressively tuned loops (> 1).
    noise_colours : tuple of str, default ("white", "ar1", "bandlimited")
        Default world only: measurement noise colours to draw from.
    setpoint_regimes : tuple of str, default ("constant", "steps", "step", "cascade")
        Default world only: setpoint regimes to draw from (weights above).
    recording : tuple of str, default ("quantisation", "hold", "compression", "averaging")
        Default world only: historian effects to draw from (may be empty), sizes
        relative to each tag's span (:mod:`sktiction.simulation.historian`):
        PV and OP on a grid of 0.5-10 %, rows frozen together on 10-55 % of the
        samples, per-tag exception compression with a band of 1-15 %, 2-10
        sample interval averages; ``"swinging_door"`` (not drawn by default) exports
        PV and OP interpolated from a swinging door of 0.5-5 %.
    recording_fraction : float, default 0.5
        Default world only: share of loops with historian recording effects.
    pv_own_share : tuple of float, default (0.0, 0.0)
        Default world only: range (0-0.95) of the share of the recorded PV variance
        that PV's own variation carries, drawn uniformly per loop: a slow low-pass
        component (second order, corner at 0.1-1 times the loop's ultimate frequency,
        at most 0.05 cycles per sample) added at the sensor, which the controller does
        not act on and OP does not explain
        (:class:`~sktiction.simulation.disturbances.PVVariation`). It scales the PV-OP
        correlation by about ``sqrt(1 - share)``; the measurement noise's SNR stays
        relative to PV with this component. Detected by ``pv_op_corr``.
    oscillating_fraction : float, default 1.0
        Default world only: share (0-1) of loops whose cycle has its drive on; the
        others, of every cause alike, are quiet: sluggish integral action (``Ti`` x
        3-20), large slow process variation (load 0.5-3 times the nominal, corner
        at 0.05-0.5 times the ultimate frequency) and, for external disturbances, an
        oscillation 0.05-0.3 times as large. Detected by ``acf_peak``.
    setpoint_weights : mapping, default see above
        Default world only: weight of each setpoint regime of ``setpoint_regimes``
        (regimes left out weigh 0; default ``{"constant": 0.35, "steps": 0.3,
        "step": 0.1, "cascade": 0.25}``). Detected by ``sp_steps`` and
        ``sp_change_fraction``.
    short_fraction : float, default 0.25
        Default world only: share of loops with a shortened record.
    load_step_fraction : float, default 0.0
        Default world only: share (0-1) of loops, of every cause alike, whose record
        holds 1-4 unannounced load steps (feed or supply changes, 1-8 % of valve travel
        at the plant input or as large a PV change at its output, at uniform times in the
        record): PV leaves its setpoint first, then OP moves to a new level and PV
        returns. ``meta["load_steps"]`` counts them. Drawn after every other draw and
        only when the share is above 0, so 0 leaves the world as it was.
    min_length : int, default 200
        Default world only: shortest record (>= 20).
    warmup : int or None, default None
        Default world only: samples simulated and dropped before the record;
        ``None`` means ``max(300, n_samples // 5)``.
    realism : object or None, default=None
        Default world only: a calibrated world from
        :func:`sktiction.realism.calibrate`: a mapping ``realism.overrides`` of
        keyword arguments of this function (explicit arguments win) and a method
        ``realism.recording_effects(rng, loop_type=None)`` returning the recording
        effects of one loop of that type (replacing the draw from ``recording``;
        ``loop_type`` is passed when the method takes it). With a method
        ``realism.loop_profile(rng)`` each loop instead copies one measured loop's
        profile: its loop type sets the plant type (``"level"``: integrating;
        ``"flow"``, ``"pressure"``: first or second order; others: any), its
        settings (``snr_db_range``, ``noise_colours``, ``pv_own_share``,
        ``oscillating_fraction``, ``setpoint_regime``, unless given explicitly) and
        its recording effects are the loop's.
    random_state : None, int or numpy.random.Generator, default=None
        Seed for reproducible output.
    return_meta : bool, default=False
        Also return a DataFrame describing each loop.

    Returns
    -------
    X : ndarray of shape (n_loops, n_samples, 3)
        Channels PV, OP (%), SP; shortened records NaN-padded at the end.
    y : ndarray of shape (n_loops,), dtype int
        1 when stiction causes the oscillation, else 0.
    meta : pandas.DataFrame, only if ``return_meta``
        One row per loop: ``cause``, ``y``, ``plant``, ``order``, ``gain``,
        ``time_constant``, ``delay``, ``apparent_time_constant``,
        ``apparent_delay``, ``lambda``, ``valve``, ``S``, ``J``, ``rule``,
        ``gain_factor``, ``Kc``, ``Ti``, ``ts``, ``samples_per_cycle``,
        ``snr_db``, ``scenario``, ``effects``; the default world adds
        ``plant_family``, ``action``, ``loop_kind``, ``kc_factor``, ``ti_factor``,
        ``gain_margin``, ``samples_per_ultimate_period``, ``noise_colour``,
        ``loop_type`` (``"level"`` for integrating plants, ``"flow"`` first order,
        ``"pressure"`` second order, ``"temperature"`` higher; a calibrated world's
        profile type when it has one), ``pv_own_share``, ``oscillating``,
        ``noise_path``, ``drift``, ``disturbance``, ``setpoint_regime``,
        ``recording``, ``record_length``, ``initial_op``, ``pv_scale``,
        ``pv_center``, ``warmup``, ``pv_per_valve`` (PV change of a unit valve move:
        the plant's gain, for an integrating plant over its delay and time constant),
        ``slip_snr`` (sticky loops: median PV change of a valve slip over the PV
        noise's standard deviation; NaN otherwise) and ``stiction_visible`` (True when
        ``slip_snr >= 1``: the slips can be seen above the noise).

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> X, y, meta = make_loops(8, 300, random_state=0, return_meta=True)
    >>> X.shape, int(y.sum())
    ((8, 300, 3), 4)
    >>> sorted(meta["cause"].unique())[:2]
    ['aggressive_tuning', 'external_disturbance']
    >>> Xc, yc = make_loops(8, 300, world="classic", random_state=0)
    >>> float(Xc[0, 0, 2])  # the classic world starts at SP = 50
    50.0
    """
    if world not in WORLDS:
        raise ValueError(f"world must be one of {WORLDS}; got {world!r}.")
    if not isinstance(n_loops, numbers.Integral) or n_loops < 1:
        raise ValueError(f"n_loops must be an integer >= 1; got {n_loops!r}.")
    if not isinstance(n_samples, numbers.Integral) or n_samples < 2:
        raise ValueError(f"n_samples must be an integer >= 2; got {n_samples!r}.")
    given = {
        "stiction_fraction": stiction_fraction, "causes": causes, "ts": ts,
        "lambda_range": lambda_range, "orders": orders, "stiction_models": stiction_models,
        "S_range": S_range, "snr_db_range": snr_db_range, "period_range": period_range,
        "slip_fraction": slip_fraction, "rules": rules, "gain_margin_range": gain_margin_range,
        "noise_colours": noise_colours, "setpoint_regimes": setpoint_regimes,
        "recording": recording, "recording_fraction": recording_fraction,
        "pv_own_share": pv_own_share, "oscillating_fraction": oscillating_fraction,
        "setpoint_weights": setpoint_weights, "short_fraction": short_fraction,
        "load_step_fraction": load_step_fraction, "min_length": min_length, "warmup": warmup,
    }  # fmt: skip
    defaults = _DEFAULT_DEFAULTS if world == "default" else _CLASSIC_DEFAULTS
    if world == "classic":
        extra = [k for k, v in given.items() if v is not None and k not in defaults]
        if realism is not None:
            extra.append("realism")
        if extra:
            raise ValueError(f"{', '.join(extra)} only apply to world='default'.")
    overrides = {}
    if realism is not None:
        overrides = dict(getattr(realism, "overrides", {}) or {})
        unknown = sorted(set(overrides) - set(defaults))
        if unknown:
            raise ValueError(
                f"realism.overrides has keys make_loops does not take: {unknown}; "
                f"allowed: {sorted(defaults)}."
            )
        if not callable(getattr(realism, "recording_effects", None)):
            raise ValueError("realism must have a method recording_effects(rng, loop_type=None).")
    opt = {
        k: (given[k] if given[k] is not None else overrides.get(k, defaults[k])) for k in defaults
    }

    stiction_fraction = check_positive(
        opt["stiction_fraction"], "stiction_fraction", strict=False, upper=1.0
    )
    causes = tuple(opt["causes"])
    bad = [c for c in causes if c not in CAUSES[1:]]
    if bad or not causes:
        raise ValueError(f"causes must be a non-empty subset of {CAUSES[1:]}; got {causes!r}.")
    ts = check_positive(opt["ts"], "ts")
    lam_lo, lam_hi = _check_range(opt["lambda_range"], "lambda_range", lo=0.0, strict_lo=True)
    orders = tuple(opt["orders"])
    for o in orders:
        if o != "integrating" and not (isinstance(o, numbers.Integral) and 1 <= o <= 10):
            raise ValueError(f"orders must hold integers 1-10 or 'integrating'; got {o!r}.")
    if not orders:
        raise ValueError("orders must not be empty (integers 1-10 or 'integrating').")
    models = STICTION_MODELS + ("he",) if world == "default" else STICTION_MODELS
    stiction_models = tuple(opt["stiction_models"])
    for m in stiction_models:
        if m not in models:
            raise ValueError(f"stiction_models must be among {models}; got {m!r}.")
    if not stiction_models:
        raise ValueError(f"stiction_models must be a non-empty subset of {models}.")
    slip_fraction = check_positive(opt["slip_fraction"], "slip_fraction", strict=False, upper=1.0)
    s_lo, s_hi = _check_range(opt["S_range"], "S_range", lo=0.0, hi=50.0, strict_lo=True)
    snr_lo, snr_hi = _check_range(opt["snr_db_range"], "snr_db_range")
    p_lo, p_hi = _check_range(opt["period_range"], "period_range", lo=2.0, strict_lo=True)
    rng = check_random_state_seed(random_state)

    n_stiction = int(round(stiction_fraction * n_loops))
    rest = n_loops - n_stiction
    labels = ["stiction"] * n_stiction + [causes[i % len(causes)] for i in range(rest)]
    labels = list(rng.permutation(np.array(labels, dtype=object)))

    if world == "classic":
        plants, controllers, valves, effects, rows = _draw_classic(
            labels, n_samples, ts, orders, lam_lo, lam_hi, p_lo, p_hi, s_lo, s_hi,
            snr_lo, snr_hi, slip_fraction, stiction_models, rng,
        )  # fmt: skip
        # simulate_loops' work without the valve positions nobody reads
        n = len(labels)
        loops = _loop_arrays(plants, controllers, valves, np.full(n, ts), np.full(n, 50.0))
        X = np.empty((n, int(n_samples), 3))
        _simulate(loops, np.full((n, 1), 50.0), effects, int(n_samples), rng, X)
        _record(X, effects, np.full(n, ts), rng)
    else:
        opt = _check_default_options(opt, orders, n_samples, realism)
        # arguments the caller gave win over a calibrated world's per-loop settings too
        opt["explicit"] = frozenset(k for k, v in given.items() if v is not None)
        opt.update(
            lambda_range=(lam_lo, lam_hi), period_range=(p_lo, p_hi), S_range=(s_lo, s_hi),
            snr_db_range=(snr_lo, snr_hi), slip_fraction=slip_fraction, orders=orders,
            stiction_models=stiction_models,
        )  # fmt: skip
        n_warm = opt["warmup"]
        X, records, rows = _simulate_default(labels, int(n_samples), n_warm, ts, opt, rng)
    y = np.array([r["y"] for r in rows], dtype=int)
    if return_meta:
        for r in rows:
            r["effects"] = ", ".join(repr(e) for e in r["effects"])
        return X, y, pd.DataFrame(rows)
    return X, y


def _check_default_options(opt, orders, n_samples, realism):
    opt = dict(opt)
    opt["rules"] = _check_subset(opt["rules"], RULES, "rules")
    for integrating, own in ((False, _RULES_SELF), (True, _RULES_INT)):
        has_type = any((o == "integrating") == integrating for o in orders)
        if has_type and not set(opt["rules"]) & set(own):
            kind = "integrating" if integrating else "self-regulating"
            raise ValueError(
                f"rules must include one of {own} for {kind} plants; got {opt['rules']!r}."
            )
    lo, hi = _check_range(opt["gain_margin_range"], "gain_margin_range", lo=1.0, strict_lo=True)
    opt["gain_margin_range"] = (lo, hi)
    opt["noise_colours"] = _check_subset(opt["noise_colours"], NOISE_COLOURS, "noise_colours")
    opt["setpoint_regimes"] = _check_subset(
        opt["setpoint_regimes"], SETPOINT_REGIMES, "setpoint_regimes"
    )
    rec = tuple(opt["recording"])
    bad = [r for r in rec if r not in _RECORDING_NAMES]
    if bad:
        raise ValueError(f"recording must be a subset of {_RECORDING_NAMES}; got {rec!r}.")
    opt["recording"] = rec
    for name in ("recording_fraction", "short_fraction", "oscillating_fraction",
                 "load_step_fraction"):
        opt[name] = check_positive(opt[name], name, strict=False, upper=1.0)
    opt["pv_own_share"] = _check_range(opt["pv_own_share"], "pv_own_share", lo=0.0, hi=0.95)
    opt["setpoint_weights"] = _check_weights(opt["setpoint_weights"], opt["setpoint_regimes"])
    if not isinstance(opt["min_length"], numbers.Integral) or opt["min_length"] < 20:
        raise ValueError(f"min_length must be an integer >= 20; got {opt['min_length']!r}.")
    if opt["warmup"] is None:
        opt["warmup"] = max(300, n_samples // 5)
    if not isinstance(opt["warmup"], numbers.Integral) or opt["warmup"] < 0:
        raise ValueError(f"warmup must be an integer >= 0; got {opt['warmup']!r}.")
    opt["warmup"] = int(opt["warmup"])
    opt["realism"] = realism
    return opt
