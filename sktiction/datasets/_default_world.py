"""The default world of ``make_loops``: loops as plants and historians make them (noise-driven
healthy loops, rejected disturbances, operator and cascade setpoints, several valve models,
recording effects); drawn, simulated, redrawn where a sticky valve never slips, recorded.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .._validation import CHANNELS
from ..simulation import (
    ARNoise,
    BandLimitedNoise,
    CascadeSetpoint,
    ColouredLoad,
    Drift,
    HeValve,
    LinearValve,
    LoadStep,
    NarrowbandDisturbance,
    PIController,
    RandomWalkLoad,
    RelayValve,
    SetpointSteps,
    SinusoidalDisturbance,
    SquareDisturbance,
    WhiteNoise,
    make_valve,
)
from ..simulation.disturbances import PVVariation
from ..simulation.historian import (
    DeadbandCompression,
    HoldLastValue,
    IntervalAveraging,
    SpanQuantization,
    SwingingDoorCompression,
)
from ..simulation.loop import _loop_arrays, _simulate
from ._draws import _loguniform, _pick, _signs
from ._tuning import _phase_crossovers, _plant_for, _settings

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


# frequency grid of the default world's phase-crossover search (interpolated between points)
_GRID = 240


def _family(order):
    if order == "integrating":
        return "integrating"
    return {1: "first_order", 2: "second_order"}.get(order, "higher_order")


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


def _valve_evidence(pv, op, valve, length, integrating, samples_per_cycle):
    """Share of PV's variance left unexplained by OP that stays unexplained when the true
    valve position is added: near 1 when the record carries no evidence of how the valve
    moved beyond what OP says, near 0 when the valve explains what OP cannot.

    Linear fits of PV (of PV's change for an integrating plant) on both inputs at 20 lags
    or fewer, spread evenly from 1 to half a cycle (10 to 40 samples)."""
    pv, op, valve = pv[:length], op[:length], valve[:length]
    if integrating:
        pv, op, valve = np.diff(pv), op[1:], valve[1:]
    reach = int(min(40, max(10, 0.5 * samples_per_cycle)))
    lags = np.arange(1, reach + 1, -(-reach // 20))  # a step of ceil(reach / 20)
    n = pv.size - reach
    if n < 4 * reach or not np.isfinite(pv).all():
        return np.nan
    k = lags.size
    design = np.ones((n, 2 * k + 1))
    for j, lag in enumerate(lags):
        design[:, j] = op[reach - lag : pv.size - lag]
        design[:, k + j] = valve[reach - lag : pv.size - lag]
    target = pv[reach:] - pv[reach:].mean()
    # normal equations: a fraction of least squares' cost; the rounding they add is far
    # below the differences this figure reads
    gram, moment, total = design.T @ design, design.T @ target, target @ target

    def left(columns):
        coef = np.linalg.lstsq(gram[np.ix_(columns, columns)], moment[columns], rcond=1e-12)[0]
        return max(total - moment[columns] @ coef, 0.0)

    with_op = left(np.r_[0:k, 2 * k])
    return float(min(left(np.arange(2 * k + 1)) / with_op, 1.0)) if with_op > 0 else np.nan


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
                row[k]["valve_evidence"] = _valve_evidence(
                    out[k, :, 0], out[k, :, 1], valve[k - lo], rec[k][3],
                    row[k]["plant_family"] == "integrating", row[k]["samples_per_cycle"],
                )  # fmt: skip
            for k in range(lo, hi):
                row[k].setdefault("slip_snr", np.nan)
                row[k].setdefault("valve_evidence", np.nan)
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
