"""The default model on loops from a second simulator written apart from ``make_loops``.

The learned classifier is trained on ``make_loops``; judging it only on ``make_loops``
measures how well it learned that simulator. This script builds loops with code that
shares nothing with :mod:`sktiction.simulation` (no import from it) and differs from it
where a simulator can differ:

- **valve**: a physical force-balance valve (Karnopp friction: static friction ``Fs``,
  Coulomb ``Fc < Fs``, viscous damping, actuator spring, valve mass), integrated at
  20 sub-steps per second, instead of the data-driven relay/Choudhury/Kano/He models
  of ``make_loops``; its dead band is about ``2 Fs`` and its slip jump at most
  ``2 (Fs - Fc)`` (about 1.0-1.2 times ``Fs - Fc`` at damping ratios 0.5-1) in % of span
  (actuator force per % set to 1); a healthy valve is a first-order actuator lag of 1-3 s.
  Every valve with friction is labelled sticky, also the few that slip fewer than three
  times in the record kept;
- **plant**: first order, second order or integrating, with dead time, integrated by
  Euler sub-steps; a constant load moves every loop off its starting point (so that a
  sticky valve has somewhere to go) and an AR(1) load is the process noise;
- **controller**: a velocity-form PI at 1 s on a measurement filtered over up to half the
  dead time, tuned by the lambda rule, or aggressively to a gain margin of 1.2-2.0
  (noise-driven, lightly damped healthy loops), the margin read from the frequency
  response of the loop computed here, filter and actuator included;
- **healthy causes**: noise-driven aggressive loops, an external sinusoid rejected by a
  lambda-tuned loop, a lambda-tuned loop with a random-walk load;
- **recording**: every loop sampled at 1, 2 or 5 s; PV and OP of some loops on a grid of
  0.1-0.5 PV noise standard deviations, of others stored with a dead-band compression
  (a value kept until it moves by more than 0.3 noise standard deviations).

Printed: balanced accuracy of the default model (``pretrained_classifier()``), the area-
ratio rule and the shape library; recall per plant and per band size, specificity per
healthy cause; the default model's stiction verdicts among loops that cycle and loops that
do not, here and on 600 held-out loops of its own world; "no verdict" counts as "no
stiction". Nothing here is tuned to the
default model: the draws were fixed before the model was run on them.

With ``--pid``, only this: the same draws with derivative action added to each controller
(``td_ratio`` 0.1 and 0.25 of the integral time, on the filtered measurement, filtered at a
tenth of itself; nothing retuned), judged by the default model, and the share of sticky
loops whose PV cycles.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/independent_world.py [n_loops] [n_seconds]
[--pid]``
"""

from __future__ import annotations

import sys
import time

import numpy as np
import pandas as pd
from numba import njit
from sklearn.metrics import balanced_accuracy_score

SUB = 20  # valve and plant sub-steps per second
DT = 1.0 / SUB
PLANTS = ("first_order", "second_order", "integrating")
HEALTHY = ("noise_driven", "external_sine", "random_walk_load")


@njit(cache=True)
def _run(
    n_sec,
    warm,
    plant,
    K,
    tau,
    tau2,
    delay,
    kc,
    ti,
    sticky,
    fs,
    fc,
    wn,
    zeta,
    act_tau,
    noise_sd,
    load_sd,
    load_phi,
    load0,
    sine_amp,
    sine_period,
    walk_sd,
    sp_step,
    tf,
    td,
    shocks,
):
    """One closed loop; returns PV (measured), OP and SP per second. ``shocks``: standard
    normal draws (n_sec + warm, 3) for the load, the walk and the measurement noise.
    ``td``: derivative time (s) acting on the filtered measurement, itself filtered at
    ``td / 10`` (0: a PI controller)."""
    pv_out, op_out, sp_out = np.empty(n_sec), np.empty(n_sec), np.empty(n_sec)
    n_all = n_sec + warm  # the first ``warm`` seconds settle the loop and are not kept
    nd = max(1, int(round(delay * SUB)))
    buf = np.zeros(nd)  # valve position delayed by the dead time
    head = 0
    x = v = 0.0  # valve position and velocity
    stuck = True
    y1 = y2 = 0.0  # plant states
    load = walk = 0.0
    u = 0.0
    e_prev = 0.0
    pv_f = pv_f_prev = 0.0  # the controller's filtered measurement (tf s; 0: none)
    d = d_prev = 0.0  # the derivative term
    m = 1.0 / (wn * wn)  # mass for natural frequency wn with a unit spring
    fv = 2.0 * zeta * np.sqrt(m)
    for t in range(n_all):
        sp = sp_step if t >= warm + n_sec // 2 and sp_step != 0.0 else 0.0
        for _ in range(SUB):
            if sticky:
                f = u - x  # actuator spring force, 1 per % of span
                if stuck:
                    if abs(f) > fs:
                        stuck = False
                        v = 0.0
                if not stuck:
                    s = np.sign(v) if v != 0.0 else np.sign(f)
                    a = (f - fc * s - fv * v) / m
                    v_new = v + a * DT
                    if v != 0.0 and np.sign(v_new) != np.sign(v) and abs(f) <= fs:
                        stuck = True
                        v = 0.0
                    else:
                        v = v_new
                        x += v * DT
            else:
                x += (u - x) * DT / act_tau
            delayed = buf[head]
            buf[head] = x
            head = (head + 1) % nd
            if plant == 0:
                y1 += (K * delayed - y1) * DT / tau
                y = y1
            elif plant == 1:
                y1 += (K * delayed - y1) * DT / tau
                y2 += (y1 - y2) * DT / tau2
                y = y2
            else:
                y1 += K * delayed * DT / tau  # deviation from the balanced opening
                y = y1
        load = load_phi * load + load_sd * shocks[t, 0]
        walk += walk_sd * shocks[t, 1]
        dist = load0 + load + walk + sine_amp * np.sin(2 * np.pi * t / sine_period)
        pv = y + dist + noise_sd * shocks[t, 2]
        pv_f = pv if tf < 1.0 else pv_f + (pv - pv_f) / tf
        e = sp - pv_f
        if td > 0.0:  # backward Euler of -td s / (1 + td s / 10) on the measurement
            d = (td / 10.0 * d_prev - td * (pv_f - pv_f_prev)) / (td / 10.0 + 1.0)
        u += kc * (e - e_prev + e / ti + d - d_prev)  # velocity-form PI(D), 1 s sample
        u = min(max(u, -200.0), 200.0)
        e_prev, d_prev, pv_f_prev = e, d, pv_f
        if t >= warm:
            pv_out[t - warm], op_out[t - warm], sp_out[t - warm] = pv, u, sp
    return pv_out, op_out, sp_out


def _gain_margin(plant, K, tau, tau2, delay, act_tau, kc, ti, tf):
    """Gain margin of the linear loop (PI at 1 s taken as continuous plus half a sample,
    measurement filter of ``tf`` s when ``tf >= 1``, as in :func:`_run`)."""
    w = np.geomspace(1e-4, 10, 20000)
    s = 1j * w
    g = K / (tau * s + 1) if plant == 0 else K / ((tau * s + 1) * (tau2 * s + 1))
    if plant == 2:
        g = K / (tau * s)
    loop = kc * (1 + 1 / (ti * s)) * g * np.exp(-s * (delay + 0.5)) / (act_tau * s + 1)
    if tf >= 1.0:
        loop = loop / (tf * s + 1)
    phase = np.unwrap(np.angle(loop))
    i = np.flatnonzero((phase[:-1] > -np.pi) & (phase[1:] <= -np.pi))
    return 1.0 / abs(loop[i[0]]) if len(i) else np.inf


def _record(x, ts, quant, band):
    """Historian: one value per ``ts`` seconds, optional grid and dead-band compression."""
    x = x[::ts].copy()
    if quant:
        x = np.round(x / quant) * quant
    if band:
        kept = x[0]
        for i in range(1, len(x)):
            if abs(x[i] - kept) > band:
                kept = x[i]
            x[i] = kept
    return x


def make_independent_loops(n_loops, n_sec, random_state=0, warmup=1500, td_ratio=0.0):
    """Loops (n_loops, n_samples, 3), labels and a table of what each loop is. The first
    ``warmup`` seconds settle each loop and are not kept (0: recorded from rest, with the
    start-up transient; another value than 1500 also draws other loops). ``td_ratio``:
    a derivative time of that many integral times on the same draws (0: PI, as tuned)."""
    rng = np.random.default_rng(random_state)
    rows, series = [], []
    for k in range(n_loops):
        sticky = k % 2 == 0
        plant = int(rng.integers(3))
        tau = float(np.exp(rng.uniform(np.log(5), np.log(60))))
        tau2 = tau * rng.uniform(0.2, 1.0)
        delay = float(tau * rng.uniform(0.1, 1.0)) if plant != 2 else rng.uniform(2, 15)
        K = float(np.exp(rng.uniform(np.log(0.5), np.log(3)))) * (1 if rng.random() < 0.7 else -1)
        if plant == 2:
            K = float(np.sign(K) * np.exp(rng.uniform(np.log(0.5), np.log(2))))
            tau = float(np.exp(rng.uniform(np.log(20), np.log(200))))  # integration time
        act_tau = rng.uniform(1, 3)
        lam = (tau if plant != 2 else 3 * delay) * rng.uniform(0.5, 2.0)
        if plant == 2:
            kc = (2 * lam + delay) * tau / (abs(K) * (lam + delay) ** 2)
            ti = 2 * lam + delay
        else:
            kc = (tau + tau2 * (plant == 1)) / (abs(K) * (lam + delay))
            ti = tau + tau2 * (plant == 1)
        kc *= np.sign(K)
        cause = "stiction" if sticky else HEALTHY[int(rng.integers(3))]
        tf = rng.uniform(0, 0.5) * delay  # the controller's measurement filter
        if cause == "noise_driven":
            target = rng.uniform(1.2, 2.0)
            gm = _gain_margin(plant, K, tau, tau2, delay, act_tau, kc, ti, tf)
            if np.isfinite(gm):
                kc *= gm / target
        S = float(np.exp(rng.uniform(np.log(0.5), np.log(5)))) if sticky else 0.0
        fs = S / 2
        fc = fs * rng.uniform(0.3, 0.9)
        # sizes in PV units of 1 % of valve travel (|K|): the same for both classes
        unit = abs(K) if plant != 2 else abs(K) * (lam + delay) / tau
        noise_sd = unit * np.exp(rng.uniform(np.log(0.02), np.log(0.2)))
        load_sd = unit * np.exp(rng.uniform(np.log(0.01), np.log(0.1)))
        sine_amp = unit * rng.uniform(0.5, 3.0) if cause == "external_sine" else 0.0
        period = (tau + delay) * np.exp(rng.uniform(np.log(2), np.log(10)))
        walk_sd = unit * 0.02 if cause == "random_walk_load" else 0.0
        sp_step = unit * rng.uniform(-3, 3) if rng.random() < 0.3 else 0.0
        pv, op, sp = _run(
            n_sec, warmup, plant, K, tau, tau2, delay, kc, ti, sticky, fs, fc, rng.uniform(2, 8),
            rng.uniform(0.5, 1.0), act_tau, noise_sd, load_sd, rng.uniform(0.5, 0.95),
            unit * rng.uniform(1, 5) * rng.choice([-1, 1]),
            sine_amp, period, walk_sd, sp_step, tf, td_ratio * ti,
            rng.standard_normal((n_sec + warmup, 3)),
        )  # fmt: skip
        ts = int(rng.choice([1, 2, 5]))
        quant = 0.1 * noise_sd * rng.uniform(1, 5) if rng.random() < 0.3 else 0.0
        band = 0.3 * noise_sd if rng.random() < 0.2 else 0.0
        pv0 = 100 * rng.uniform(0.2, 0.8)
        loop = np.stack([
            _record(pv + pv0, ts, quant, band),
            _record(op + 50.0, ts, quant, band),
            _record(sp + pv0, ts, 0.0, 0.0),
        ], axis=-1)  # fmt: skip
        series.append(loop)
        rows.append({"y": int(sticky), "cause": cause, "plant": PLANTS[plant], "S": S,
                     "ts": ts, "quantised": bool(quant), "compressed": bool(band)})  # fmt: skip
    n = max(len(s) for s in series)
    X = np.full((n_loops, n, 3), np.nan)
    for i, s in enumerate(series):
        X[i, : len(s)] = s
    meta = pd.DataFrame(rows)
    return X, meta["y"].to_numpy(), meta


def main(n_loops=400, n_sec=6000):
    from sktiction import AreaRatioClassifier, ShapeLibraryClassifier, pretrained_classifier

    t0 = time.perf_counter()
    X, y, meta = make_independent_loops(n_loops, n_sec, random_state=2026)
    per_ts = meta["ts"].value_counts().sort_index().to_dict()
    print(f"{n_loops} loops of {n_sec} s in {time.perf_counter() - t0:.1f} s ({per_ts} per ts)")
    clfs = {
        "learned (default model)": pretrained_classifier(),
        "area ratio (d=0.5)": AreaRatioClassifier().fit(X),
        "shape library": ShapeLibraryClassifier().fit(X),
    }
    rows = []
    for name, clf in clfs.items():
        pred = clf.diagnose(X)["prediction"].fillna(0).to_numpy(dtype=int)
        meta[name] = pred
        rows.append(
            {
                "classifier": name,
                "balanced_acc": balanced_accuracy_score(y, pred),
                "recall": pred[y == 1].mean(),
                "specificity": 1 - pred[y == 0].mean(),
            }
        )
    pd.set_option("display.width", 160)
    fmt = "{:.2f}".format
    print(pd.DataFrame(rows).to_string(index=False, float_format=fmt))
    name = "learned (default model)"
    sticky = meta[meta["y"] == 1]
    print("\nrecall of the default model per plant and band (% of span):")
    bands = pd.cut(sticky["S"], [0, 1, 2, 5])
    print(sticky.groupby(["plant", bands], observed=True)[name].agg(["size", "mean"])
          .unstack().to_string(float_format=fmt))  # fmt: skip
    healthy = meta[meta["y"] == 0]
    print("\nstiction verdicts of the default model among healthy loops, per cause and plant:")
    print(healthy.groupby(["cause", "plant"])[name].agg(["size", "mean"]).unstack()
          .to_string(float_format=fmt))  # fmt: skip
    print("\nstiction verdicts of the default model among loops that cycle and loops that do not")
    print("(a cycle found in OP and PV by the template features), here and in its own world:")
    from sktiction.datasets import make_loops

    model = clfs[name]
    Xd, yd = make_loops(600, n_samples=2000, random_state=12345)
    parts, feats = [], {}
    for world, A, b in (("independent", X, y), ("default (held out)", Xd, yd)):
        feats[world] = model.loop_features(A)
        cycles = feats[world]["templates__oscillating"].fillna(0).to_numpy() > 0
        part = pd.DataFrame({"world": world, "class": np.where(b == 1, "sticky", "healthy"),
                             "cycles": cycles, "stiction verdict": model.predict(A)})  # fmt: skip
        parts.append(part)
    table = pd.concat(parts).groupby(["world", "cycles", "class"])["stiction verdict"]
    print(table.agg(["size", "mean"]).unstack().to_string(float_format=fmt))
    _stuck_look(model, feats, meta, yd)
    return 0


# PVOPHysteresis at OP's own time scale: what reads "OP moves while PV stays" as stiction
_SLOW = {
    "hysteresis__stuck_share_slow": "stuck",
    "hysteresis__moving_share_slow": "OP moving",
    "hysteresis__hysteresis_fill_slow": "fill",
    "hysteresis__valve_fit_band_share": "valve band",
}


def _stuck_look(model, feats, meta, yd):
    """Where the false alarms on random-walk loads come from: the slow-scale PV-OP columns
    (medians) per cause here and per class in the default world, and the share of the
    self-regulating random-walk loops called sticky once a group of columns is replaced by
    the values of a random quiet healthy loop of the default world (all columns of the
    group taken from the same loop)."""
    fmt = "{:.2f}".format
    ind, dflt = feats["independent"], feats["default (held out)"]
    cause = np.where(meta["cause"] == "random_walk_load", np.where(
        meta["plant"] == "integrating", "random_walk_load (integrating)",
        "random_walk_load (self-regulating)"), meta["cause"])  # fmt: skip
    rows = [ind[list(_SLOW)].groupby(cause).median()]
    cls = np.where(yd == 1, "default world: sticky", "default world: healthy")
    rows.append(dflt[list(_SLOW)].groupby(cls).median())
    print("\nslow-scale PV-OP columns of the learned model (medians; PVOPHysteresis):")
    print(pd.concat(rows).rename(columns=_SLOW).to_string(float_format=fmt))
    cols = list(model.feature_names_)
    walk = cause == "random_walk_load (self-regulating)"
    A = ind.loc[walk, cols].to_numpy()
    quiet = (dflt["templates__oscillating"].fillna(0).to_numpy() == 0) & (yd == 0)
    donors = dflt.loc[quiet, cols].to_numpy()
    groups = {
        "none": [],
        "area ratio": [c for c in cols if c.startswith("area__")],
        "templates": [c for c in cols if c.startswith("templates__")] + ["oscillating_share"],
        "valve model": [c for c in cols if c.startswith("valve_model__")],
        "hysteresis, fast": [f"hysteresis__{c}" for c in
                             ("stuck_share", "moving_share", "hysteresis_fill")],
        "hysteresis, slow": [f"hysteresis__{c}" for c in
                             ("stuck_share_slow", "moving_share_slow", "hysteresis_fill_slow")],
        "hysteresis, valve fit": ["hysteresis__valve_fit_gain",
                                  "hysteresis__valve_fit_band_share"],
    }  # fmt: skip
    pick = donors[np.random.default_rng(0).integers(len(donors), size=len(A))]
    out = {}
    for group, names in groups.items():
        B = A.copy()
        idx = [cols.index(c) for c in names]
        B[:, idx] = pick[:, idx]
        out[group] = float(np.mean(model.model_.predict_proba(B)[:, 1] >= 0.5))
    print(f"\n{int(walk.sum())} self-regulating random-walk loops called sticky, with one group "
          "of columns taken from quiet healthy default-world loops:")  # fmt: skip
    print(pd.Series(out, name="called sticky").to_string(float_format=fmt))


def pid(n_loops=400, n_sec=6000):
    """The default model on the same draws with PI and with PID controllers."""
    from sktiction import pretrained_classifier
    from sktiction.cycles import analyze_cycles

    model = pretrained_classifier()
    print("controller: balanced accuracy / recall / specificity of the default model; share "
          "of sticky loops whose PV cycles (analyze_cycles)")
    for ratio in (0.0, 0.1, 0.25):
        X, y, _ = make_independent_loops(n_loops, n_sec, random_state=2026, td_ratio=ratio)
        pred = model.diagnose(X)["prediction"].fillna(0).to_numpy(dtype=int)
        pv = [X[i, np.isfinite(X[i, :, 0]), 0] for i in np.flatnonzero(y == 1)]
        cycling = np.mean([analyze_cycles(x).oscillating for x in pv])
        name = "PI" if ratio == 0 else f"PID, Td = {ratio} Ti"
        print(f"{name:18s} {balanced_accuracy_score(y, pred):.3f} / {pred[y == 1].mean():.3f} / "
              f"{1 - pred[y == 0].mean():.3f}; sticky PV cycling {cycling:.2f}", flush=True)
    return 0


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:] if not a.startswith("--")]
    sys.exit(pid(*args) if "--pid" in sys.argv else main(*args))
