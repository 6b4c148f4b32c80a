"""The classic world of ``make_loops`` (sktiction 0.1): regular limit cycles, sinusoidal
disturbances, every aggressive loop started by a setpoint step.
"""

from __future__ import annotations

import numpy as np

from ..simulation import (
    ARNoise,
    LinearValve,
    PIController,
    RandomWalkLoad,
    SetpointSteps,
    SinusoidalDisturbance,
    WhiteNoise,
    make_valve,
)
from ._draws import _signs
from ._tuning import _phase_crossovers, _plant_for, _settings

# Stiction limit-cycle period over the phase-crossover period 2 pi / w180, median
# measured on generated loops (good tuning, relay/Kano valves, lambda 0.1-1).
_STICTION_PERIOD_FACTOR = {1: 6.0, "integrating": 6.0}
_STICTION_PERIOD_FACTOR_DEFAULT = 4.0


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
