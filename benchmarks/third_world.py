"""A third, independently written closed-loop simulator to judge sktiction's learned model.

Written from the literature only (no code shared with ``sktiction.simulation`` or
``benchmarks/independent_world.py``):

* Sticky valves: He, Wang, Pottmann & Qin (2007) two-parameter model (static fs, kinetic fd;
  band S = fs + fd, slip J = fs - fd), Kano et al. (2004) model with stop detection
  (band S, slip J), and a force-balance stem (mass, spring, viscous + Stribeck friction)
  driven by a pneumatic actuator lag and an optional P or PI positioner, integrated in
  sub-steps inside each controller period.  Bands 0.3-5 % of span, slip 5-100 % of the band.
* Healthy valves: ideal (optionally a first-order actuator lag), or the force-balance stem
  with negligible friction.  Every valve, sticky or not, may have an equal-percentage
  installed characteristic (inherent rangeability R, valve share of pressure drop Phi).
* Plants: FOPTD, SOPTD, integrating with lag, inverse response (RHP zero), lead-lag; exact
  zero-order-hold discretisation at the controller period (0.2-1 s), delay rounded to it.
* Controllers: ISA PI / PID (derivative on PV with filter, or on a filtered PV), setpoint
  weighting, 0-100 % limits with clamping or back-calculation anti-windup, SIMC tuning from
  an engineer's bump test (two-point FOPTD fit of the whole path) with tau_c = 0.5-4 x delay.
  Reverse and direct acting (sign of the plant gain).
* Disturbances (drawn alike for both classes): step loads, external sinusoid, AR(1) load,
  random-walk load (entering at the plant input or at its output through a lag), operator
  setpoint changes; none at all in some loops.
* Sensor: Student-t noise, first-order sensor lag, A/D quantisation in some.
* Recording: historian at 1-10 s after a warm-up: plain sampling, or swinging-door
  compression exported either interpolated (PI-style) or stepped (last value).

``make(n_loops, random_state)`` returns ``X`` (n, n_samples, 3: PV, OP, SP, NaN-padded),
``y`` (1 = sticky valve) and ``meta`` (every drawn parameter).  ``python third_world.py``
scores sktiction's pretrained model on two seeds and prints tables per factor.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/third_world.py [--clean]`` (about 1 min).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import pandas as pd
from numba import njit
from scipy import signal

# --------------------------------------------------------------------------------------
# compiled kernels
# --------------------------------------------------------------------------------------

VALVE_IDEAL, VALVE_HE, VALVE_KANO, VALVE_FORCE = 0, 1, 2, 3
VALVE_NAMES = {
    VALVE_IDEAL: "ideal",
    VALVE_HE: "he2007",
    VALVE_KANO: "kano2004",
    VALVE_FORCE: "force_balance",
}


@njit(cache=True)
def _char(x, code, R, phi):
    """Installed flow characteristic: stem position (% travel) -> flow (% of max)."""
    if code == 0:
        return x
    xx = min(max(x, 0.0), 100.0)
    f = R ** (xx / 100.0 - 1.0)
    return 100.0 * f / math.sqrt(phi + (1.0 - phi) * f * f)


@njit(cache=True)
def _force_valve(st, u, p, count):
    """Advance the force-balance valve over one controller period with OP = u held.

    st: [x, v, P, Ip, stuck, x_at_breakaway, n_slips, sum_jump]
    p:  [Fs, Fc, vs, m, c, Kp, Ti_p, pos_code, tau_a, dt, nsub]
    Forces are in % of travel (normalised by the spring rate; the spring holds x = P).
    """
    Fs, Fc, vs, m, c = p[0], p[1], p[2], p[3], p[4]
    Kp, Tip, pos, tau_a, dt = p[5], p[6], p[7], p[8], p[9]
    nsub = int(p[10])
    ea = math.exp(-dt / tau_a)
    x, v, P, Ip, stuck = st[0], st[1], st[2], st[3], st[4]
    for _ in range(nsub):
        if pos == 0.0:
            Pc = u
        else:
            e = u - x
            Pc = u + Kp * e + Ip
            if pos == 2.0:
                Ip += dt * Kp / Tip * e
                Ip = min(max(Ip, -30.0), 30.0)
        Pc = min(max(Pc, -20.0), 120.0)
        P = Pc + (P - Pc) * ea
        F = P - x
        if stuck > 0.5:
            if abs(F) > Fs:
                s = 1.0 if F > 0 else -1.0
                v = dt / m * (F - s * Fs) / (1.0 + dt * c / m)
                stuck = 0.0
                st[5] = x
        else:
            s = 1.0 if v > 0 else -1.0
            Ff = Fc + (Fs - Fc) * math.exp(-abs(v) / vs)  # exponential Stribeck curve
            vn = (v + dt / m * (F - s * Ff)) / (1.0 + dt * c / m)
            if vn * s <= 0.0:  # velocity reverses or stops: stick (Karnopp-like)
                v = 0.0
                stuck = 1.0
                if count and abs(x - st[5]) > 1e-9:
                    st[6] += 1.0
                    st[7] += abs(x - st[5])
            else:
                v = vn
        x += dt * v
        if x < 0.0:
            x, v = 0.0, 0.0
        elif x > 100.0:
            x, v = 100.0, 0.0
    st[0], st[1], st[2], st[3], st[4] = x, v, P, Ip, stuck
    return x


@njit(cache=True)
def _simulate(
    Ad,
    Bd,
    Cd,
    nd,
    vcode,
    vp,
    fp,
    char_code,
    R,
    phi,
    ctl,
    sp,
    din,
    dout,
    noise,
    s_alpha,
    quant,
    rec_start,
    m_rec,
    n_rec,
    u0,
    y0,
    x_off,
):
    """One closed loop at the controller period; returns records at the historian period.

    ctl: [sgn, Kc, Ti, Td, N, b, mode, Tf_pv, aw, Tt, h]; mode 0 PI, 1 PID (D on PV,
    filtered), 2 PID on a first-order filtered PV; aw 0 clamping, 1 back-calculation.
    vp: [S or fs, J or fd, act_alpha]   (He: fs, fd; Kano: S, J)
    """
    n = sp.shape[0]
    nx = Ad.shape[0]
    xs = np.zeros(nx)
    xn = np.zeros(nx)
    buf = np.zeros(nd + 1)
    pv_rec = np.empty(n_rec)
    op_rec = np.empty(n_rec)
    sp_rec = np.empty(n_rec)
    x_rec = np.empty(n_rec)
    sgn, Kc, Ti, Td, N, b = ctl[0], ctl[1], ctl[2], ctl[3], ctl[4], ctl[5]
    mode, Tfpv, aw, Tt, h = ctl[6], ctl[7], ctl[8], ctl[9], ctl[10]
    Tf = Td / N if Td > 0 else 0.0
    ad = Tf / (Tf + h) if Td > 0 else 0.0
    bd = Kc * Td / (Tf + h) if Td > 0 else 0.0
    af = math.exp(-h / Tfpv) if Tfpv > 0 else 0.0
    integ = u0
    D = 0.0
    ys = y0
    yf = y0
    ycp = y0
    la = vp[2]
    # valve states
    x = u0 + x_off  # valve starts away from equilibrium (stuck there if sticky)
    ua = u0 + x_off
    uprev = u0 + x_off
    ur = 0.0  # He: residual force
    stp = 1  # Kano: stopped flag
    d = 1.0  # Kano: direction
    us = u0 + x_off  # Kano: OP at stop
    fst = np.zeros(8)
    fst[0] = u0 + x_off
    fst[2] = u0 + x_off
    fst[4] = 1.0
    stuck_prev = True
    n_slips = 0
    sum_jump = 0.0
    n_sat = 0
    q0 = _char(u0, char_code, R, phi)
    kr = 0
    for k in range(n):
        y = y0 + dout[k]
        for i in range(nx):
            y += Cd[i] * xs[i]
        ys = s_alpha * ys + (1.0 - s_alpha) * y
        ym = ys + noise[k]
        if quant > 0:
            ym = quant * math.floor(ym / quant + 0.5)
        r = sp[k]
        # --- controller (ISA form, deviation variables around y0) ---
        if mode == 2:
            yf = af * yf + (1.0 - af) * ym
            yc = yf
        else:
            yc = ym
        Pt = sgn * Kc * (b * (r - y0) - (yc - y0))
        if mode >= 1:
            D = ad * D - bd * sgn * (yc - ycp)
        ycp = yc
        v = Pt + integ + D
        u = min(max(v, 0.0), 100.0)
        e = sgn * (r - yc)
        if aw == 0:
            if not ((v > 100.0 and e > 0) or (v < 0.0 and e < 0)):
                integ += Kc * h / Ti * e
        else:
            integ += Kc * h / Ti * e + h / Tt * (u - v)
        recording = k >= rec_start
        # --- valve ---
        if vcode == 3:
            fst[6] = 0.0
            fst[7] = 0.0
            xnew = _force_valve(fst, u, fp, recording)
            if recording:
                n_slips += int(fst[6])
                sum_jump += fst[7]
        else:
            ua = la * ua + (1.0 - la) * u
            if vcode == 0:
                xnew = ua
            elif vcode == 1:  # He et al. 2007
                ur += ua - uprev
                if abs(ur) > vp[0]:
                    sg = 1.0 if ur > 0 else -1.0
                    xnew = x + ur - sg * vp[1]
                    ur = sg * vp[1]
                else:
                    xnew = x
            else:  # Kano et al. 2004
                S, J = vp[0], vp[1]
                xnew = x
                if stp == 0:
                    if d * (ua - uprev) > 0:
                        xnew = ua - d * (S - J) / 2.0
                    else:
                        stp = 1
                        us = uprev
                if stp == 1:
                    if -d * (ua - us) > S:
                        d = -d
                        stp = 0
                        xnew = ua - d * (S - J) / 2.0
                    elif d * (ua - us) > J:
                        stp = 0
                        xnew = ua - d * (S - J) / 2.0
            uprev = ua
            if vcode != 0:
                moved = xnew != x
                if recording and moved and stuck_prev:
                    n_slips += 1
                    sum_jump += abs(xnew - x)
                stuck_prev = not moved
        x = min(max(xnew, 0.0), 100.0)
        w = _char(x, char_code, R, phi) - q0 + din[k]
        # --- record (what the DCS shows at this instant) ---
        if recording and (k - rec_start) % m_rec == 0 and kr < n_rec:
            pv_rec[kr] = ym
            op_rec[kr] = u
            sp_rec[kr] = r
            x_rec[kr] = x
            if u <= 0.5 or u >= 99.5:
                n_sat += 1
            kr += 1
        # --- plant with input delay ---
        buf[k % (nd + 1)] = w
        wd = buf[(k - nd) % (nd + 1)] if k >= nd else 0.0
        for i in range(nx):
            acc = Bd[i] * wd
            for j in range(nx):
                acc += Ad[i, j] * xs[j]
            xn[i] = acc
        for i in range(nx):
            xs[i] = xn[i]
    return pv_rec, op_rec, sp_rec, x_rec, n_slips, sum_jump, n_sat


@njit(cache=True)
def _step_response(Ad, Bd, Cd, n):
    nx = Ad.shape[0]
    xs = np.zeros(nx)
    xn = np.zeros(nx)
    out = np.empty(n)
    for k in range(n):
        acc = 0.0
        for i in range(nx):
            acc += Cd[i] * xs[i]
        out[k] = acc
        for i in range(nx):
            acc = Bd[i]
            for j in range(nx):
                acc += Ad[i, j] * xs[j]
            xn[i] = acc
        for i in range(nx):
            xs[i] = xn[i]
    return out


@njit(cache=True)
def _swinging_door(t, v, dev, max_dt):
    """Indices of archived points (swinging-door compression, deviation dev)."""
    n = v.shape[0]
    keep = np.zeros(n, dtype=np.bool_)
    keep[0] = True
    a = 0
    up = -1e300
    lo = 1e300
    for i in range(1, n):
        dt = t[i] - t[a]
        su = (v[i] - (v[a] + dev)) / dt
        sl = (v[i] - (v[a] - dev)) / dt
        up2 = max(up, su)
        lo2 = min(lo, sl)
        if up2 > lo2 or dt > max_dt:
            a = i - 1
            keep[a] = True
            dt = t[i] - t[a]
            up = (v[i] - (v[a] + dev)) / dt
            lo = (v[i] - (v[a] - dev)) / dt
        else:
            up, lo = up2, lo2
    keep[n - 1] = True
    return keep


# --------------------------------------------------------------------------------------
# drawing one loop
# --------------------------------------------------------------------------------------


def _logu(rng, lo, hi):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def _inner_gain_margin(tau_a, fn, zeta):
    """Gain margin of the positioner loop: pneumatic lag times the stem's mass-spring."""
    wn = 2 * np.pi * fn
    w = np.logspace(-3, 3, 6000)
    G = 1.0 / ((1j * w * tau_a + 1) * (1 - (w / wn) ** 2 + 2j * zeta * w / wn))
    ph = np.unwrap(np.angle(G))
    i = np.nonzero(ph < -np.pi)[0]
    return float(1.0 / abs(G[i[0]])) if len(i) else 1e3


def _plant_tf(kind, K, tau1, tau2, tz):
    """Continuous transfer function (num, den) of the plant without delay."""
    if kind == "foptd":
        return [K], [tau1, 1.0]
    if kind == "soptd":
        return [K], np.polymul([tau1, 1.0], [tau2, 1.0])
    if kind == "integrating":
        return [K], np.polymul([tau1, 1.0], [1.0, 0.0])
    if kind == "inverse":
        return [-K * tz, K], np.polymul([tau1, 1.0], [tau2, 1.0])
    if kind == "leadlag":
        return [K * tz, K], np.polymul([tau1, 1.0], [tau2, 1.0])
    raise ValueError(kind)


def _bump_test(num, den, theta, lags):
    """What an engineer reads from an open-loop step: two-point FOPTD fit (Smith)."""
    for tl in lags:
        if tl > 0:
            den = np.polymul(den, [tl, 1.0])
    taus = np.abs(1.0 / np.roots(den)[np.abs(np.roots(den)) > 0]) if len(den) > 1 else [1.0]
    tmax = 12.0 * float(np.sum(taus)) + 10.0
    t = np.linspace(0.0, tmax, 4000)
    A, B, C, Dm = signal.tf2ss(num, den)
    Ad, Bd, Cd, _, _ = signal.cont2discrete((A, B, C, Dm), t[1], method="zoh")
    yresp = _step_response(Ad, Bd.ravel().copy(), Cd.ravel().copy(), len(t))
    yinf = yresp[-1]
    yn = yresp / yinf
    t28 = t[np.argmax(yn >= 0.283)]
    t63 = t[np.argmax(yn >= 0.632)]
    tau = max(1.5 * (t63 - t28), 1e-3)
    th = max(t63 - tau, 0.0) + theta
    return float(yinf), float(tau), float(th)


def draw_loop(rng, sticky):
    """Draw every parameter of one loop (dict)."""
    p = {"sticky": int(sticky)}
    # ---- plant ----
    kind = rng.choice(["foptd", "soptd", "integrating", "inverse", "leadlag"])
    p["plant"] = str(kind)
    p["tau1"] = _logu(rng, 5.0, 300.0)
    p["tau2"] = p["tau1"] * rng.uniform(0.05, 0.8) if kind != "foptd" else 0.0
    if kind == "integrating":
        p["tau1"] = _logu(rng, 5.0, 100.0)
        p["tau2"] = 0.0
    p["tz"] = 0.0
    if kind == "inverse":
        p["tz"] = p["tau1"] * rng.uniform(0.1, 0.7)
    elif kind == "leadlag":
        p["tz"] = p["tau2"] * rng.uniform(0.2, 4.0)
    p["theta"] = 0.0 if rng.random() < 0.15 else _logu(rng, 0.5, 60.0)
    if kind == "integrating":
        p["gain"] = _logu(rng, 0.002, 0.03)  # %PV per s per % flow
    else:
        p["gain"] = _logu(rng, 0.3, 3.0)
    p["gain"] *= 1.0 if rng.random() < 0.5 else -1.0
    p["action"] = "reverse" if p["gain"] > 0 else "direct"
    # ---- controller period, historian ----
    p["h"] = float(rng.choice([0.2, 0.25, 0.5, 1.0]))
    speed = p["tau1"] + p["tau2"] + p["theta"]
    allowed = [T for T in (1, 2, 3, 5, 10) if T <= max(1.0, speed / 2.0)]
    p["T_hist"] = int(rng.choice(allowed))
    p["n_samples"] = round(_logu(rng, 1000, 8000))
    p["recording"] = str(rng.choice(["sampled", "sdc_interp", "sdc_step"], p=[0.4, 0.3, 0.3]))
    # most records are pulled long enough to hold many closed-loop time scales (set after tuning)
    p["record_rule"] = "covers_loop" if rng.random() < 0.8 else "as_drawn"
    # ---- valve ----
    p["characteristic"] = "eq_pct" if rng.random() < 0.4 else "linear"
    p["R"] = rng.uniform(20.0, 50.0)
    p["phi"] = rng.uniform(0.15, 1.0)
    p["op0"] = rng.uniform(20.0, 80.0)
    p["sp0"] = rng.uniform(20.0, 80.0)
    p["act_lag"] = 0.0 if rng.random() < 0.5 else rng.uniform(0.5, 5.0)
    p["band"] = 0.0
    p["jump_frac"] = 0.0
    p["positioner"] = "none"
    for key in ("Fs", "Fc", "vs", "fn", "zeta", "Kp_pos", "Ti_pos", "tau_a"):
        p[key] = 0.0
    if sticky:
        vm = rng.choice([VALVE_HE, VALVE_KANO, VALVE_FORCE], p=[0.35, 0.3, 0.35])
    else:
        vm = VALVE_FORCE if rng.random() < 0.25 else VALVE_IDEAL
    p["valve_code"] = int(vm)
    p["valve"] = VALVE_NAMES[vm] + ("" if sticky or vm == VALVE_IDEAL else "_lowfric")
    if vm in (VALVE_HE, VALVE_KANO):
        p["band"] = _logu(rng, 0.3, 5.0)
        p["jump_frac"] = rng.uniform(0.05, 1.0)
    elif vm == VALVE_FORCE:
        p["positioner"] = str(rng.choice(["none", "P", "PI"], p=[0.4, 0.45, 0.15]))
        p["Kp_pos"] = 0.0 if p["positioner"] == "none" else _logu(rng, 1.0, 10.0)
        p["Ti_pos"] = _logu(rng, 1.0, 20.0) if p["positioner"] == "PI" else 0.0
        p["tau_a"] = rng.uniform(0.3, 3.0)
        p["act_lag"] = p["tau_a"]
        p["fn"] = rng.uniform(0.3, 1.5)  # stem natural frequency, Hz
        p["zeta"] = rng.uniform(0.2, 1.0)  # viscous damping ratio
        if p["positioner"] != "none":  # a commissioned positioner is stable:
            gm = _inner_gain_margin(
                p["tau_a"], p["fn"], p["zeta"]
            )  # gain margin >= 2.5 (P), 3 (PI)
            p["Kp_pos"] = min(p["Kp_pos"], gm / (2.5 if p["positioner"] == "P" else 3.0))
            if p["positioner"] == "PI":
                p["Ti_pos"] = max(p["Ti_pos"], 4.0 * p["tau_a"])
        fc_ratio = rng.uniform(0.3, 0.9)
        if sticky:
            target = _logu(rng, 0.3, 5.0)  # apparent band seen from OP (P positioner)
            p["Fs"] = (
                target * (1.0 + p["Kp_pos"]) / 2.0 if p["positioner"] != "PI" else target / 2.0
            )
        else:
            p["Fs"] = _logu(rng, 0.002, 0.02)
        p["Fc"] = fc_ratio * p["Fs"]
        p["vs"] = _logu(rng, 0.002, 0.1)  # Stribeck velocity, %/s
    # ---- sensor ----
    p["noise_sd"] = _logu(rng, 0.02, 1.0)  # % of span
    p["noise_df"] = _logu(rng, 2.5, 30.0)
    p["sensor_lag"] = 0.0 if rng.random() < 0.5 else _logu(rng, 0.5, 10.0)
    p["quant"] = float(
        rng.choice([0.0, 100 / 4096, 100 / 1024, 0.1, 0.25], p=[0.7, 0.1, 0.08, 0.07, 0.05])
    )
    # ---- controller ----
    p["controller"] = str(rng.choice(["PI", "PID_Dpv", "PID_filt"], p=[0.65, 0.2, 0.15]))
    p["tauc_ratio"] = _logu(rng, 0.5, 4.0)
    p["b"] = 1.0 if rng.random() < 0.5 else rng.uniform(0.3, 1.0)
    p["N"] = rng.uniform(8.0, 20.0)
    p["antiwindup"] = "clamp" if rng.random() < 0.5 else "backcalc"
    # an engineer does not leave the valve jittering from PV noise: above a tolerated OP jitter
    # the gain is cut or the PV filtered (some loops are left as tuned)
    p["op_jitter_max"] = _logu(rng, 0.2, 1.5)
    p["remedy"] = str(rng.choice(["none", "detune", "pv_filter"], p=[0.15, 0.425, 0.425]))
    # ---- disturbances (same distribution for both classes) ----
    p["d_steps"] = rng.random() < 0.35
    p["d_sine"] = rng.random() < 0.25
    p["d_ar"] = rng.random() < 0.45
    p["d_rw"] = rng.random() < 0.3
    p["d_sp"] = rng.random() < 0.35
    p["load_at"] = "input" if rng.random() < 0.6 else "output"
    p["load_tau"] = _logu(rng, 10.0, 300.0)
    p["step_size"] = _logu(rng, 0.3, 3.0)
    p["step_rate"] = _logu(rng, 1.0, 6.0)  # expected steps per record
    p["sine_amp"] = _logu(rng, 0.2, 3.0)
    p["sine_period"] = float(np.clip(speed * _logu(rng, 0.5, 20.0), 20.0, 5000.0))
    p["ar_sd"] = _logu(rng, 0.1, 2.0)
    p["ar_tau"] = _logu(rng, 5.0, 300.0)
    p["rw_total"] = _logu(rng, 0.5, 5.0)  # sd of the walk over the record, %
    p["sp_moves"] = _logu(rng, 1.0, 8.0)
    p["sp_size"] = _logu(rng, 1.0, 10.0)
    p["compdev_pv"] = _logu(rng, 0.03, 0.5)  # % of span, as set per tag
    p["compdev_op"] = _logu(rng, 0.03, 0.5)
    p["comp_max"] = rng.uniform(3600.0, 28800.0)
    return p


def _tune(p, K_loc):
    """SIMC from a bump test of valve + plant + sensor (ISA parameters)."""
    num, den = _plant_tf(p["plant"], abs(p["gain"]) * K_loc, p["tau1"], p["tau2"], p["tz"])
    lags = [p["act_lag"], p["sensor_lag"]]
    if p["plant"] == "integrating":
        Ki = abs(p["gain"]) * K_loc
        th = p["theta"] + p["tau1"] + sum(lags) + p["h"] / 2
        tauc = p["tauc_ratio"] * th
        Kc, Ti = 1.0 / (Ki * (tauc + th)), 4.0 * (tauc + th)
        tau_fit, K_fit, tau2 = np.inf, Ki, p["tau1"]
    else:
        K_fit, tau_fit, th = _bump_test(num, den, p["theta"], lags)
        th += p["h"] / 2
        tauc = p["tauc_ratio"] * max(th, 0.1 * tau_fit)
        Kc = tau_fit / (K_fit * (tauc + th))
        Ti = min(tau_fit, 4.0 * (tauc + th))
        tau2 = p["tau2"]
    Td = 0.0
    if p["controller"] != "PI":
        Td_s = min(tau2, th) if tau2 > 0 else 0.4 * th
        Td_s = min(Td_s, 0.5 * Ti)
        Kc, Ti, Td = Kc * (1 + Td_s / Ti), Ti + Td_s, Ti * Td_s / (Ti + Td_s)
    # OP jitter from PV noise: proportional part, plus the derivative's high-frequency gain N
    gain_hf = Kc * (1.0 + (p["N"] if p["controller"] == "PID_Dpv" else 0.0))
    jit = gain_hf * p["noise_sd"]
    p["pv_filter"] = Td / p["N"] * 3 if p["controller"] == "PID_filt" else 0.0
    p["op_jitter_tuned"] = jit
    p["remedy_applied"] = "none"
    if jit > p["op_jitter_max"] and p["remedy"] == "detune":
        Kc *= p["op_jitter_max"] / jit
        p["remedy_applied"] = "detuned"
    elif jit > p["op_jitter_max"] and p["remedy"] == "pv_filter":
        # first-order filter on white noise: variance times h / (2 Tf); kept below the delay
        tf = 0.5 * p["h"] * (jit / p["op_jitter_max"]) ** 2
        p["pv_filter"] = float(min(max(tf, p["pv_filter"]), max(th, 2 * p["h"])))
        p["remedy_applied"] = "pv_filter"
    p.update(K_fit=K_fit, tau_fit=tau_fit, theta_fit=th, tauc=tauc, Kc=Kc, Ti=Ti, Td=Td)


def _disturbances(rng, p, n, h):
    """Input load (flow %), output load (PV %), setpoint at the controller period."""
    t = np.arange(n) * h
    T = n * h
    load = np.zeros(n)
    if p["d_steps"]:
        k = rng.poisson(p["step_rate"] * T / (p["n_samples"] * p["T_hist"]))
        for tk in rng.uniform(0, T, k):
            load[t >= tk] += rng.normal(0.0, p["step_size"])
    if p["d_sine"]:
        load += p["sine_amp"] * np.sin(
            2 * np.pi * t / p["sine_period"] + rng.uniform(0, 2 * np.pi)
        )
    if p["d_ar"]:
        phi = math.exp(-h / p["ar_tau"])
        e = rng.normal(0.0, p["ar_sd"] * math.sqrt(1 - phi * phi), n)
        load += signal.lfilter([1.0], [1.0, -phi], e)
    if p["d_rw"]:
        rec_T = p["n_samples"] * p["T_hist"]
        load += np.cumsum(rng.normal(0.0, p["rw_total"] * math.sqrt(h / rec_T), n))
    din = np.zeros(n)
    dout = np.zeros(n)
    if p["load_at"] == "input":
        din = load
    else:
        a = math.exp(-h / p["load_tau"])
        scale = abs(p["gain"]) if p["plant"] != "integrating" else 1.0
        dout = scale * signal.lfilter([1 - a], [1.0, -a], load)
    sp = np.full(n, p["sp0"])
    if p["d_sp"]:
        k = max(1, rng.poisson(p["sp_moves"]))
        rec0 = n - int(p["n_samples"] * p["T_hist"] / h)
        for tk in np.sort(rng.integers(rec0, n, k)):
            new = np.clip(sp[tk] + rng.choice([-1, 1]) * p["sp_size"], 10.0, 90.0)
            sp[tk:] = new
    return din, dout, sp


def _noise(rng, p, n):
    df = p["noise_df"]
    z = rng.standard_t(df, n)
    return p["noise_sd"] * z / math.sqrt(df / (df - 2.0))


def _force_params(p):
    wn = 2 * np.pi * p["fn"]
    m = 1.0 / wn**2
    c = 2.0 * p["zeta"] / wn
    dt = min(0.3 / wn, p["h"] / 2)
    nsub = math.ceil(p["h"] / dt)
    dt = p["h"] / nsub
    pos = {"none": 0.0, "P": 1.0, "PI": 2.0}[p["positioner"]]
    return np.array(
        [
            p["Fs"],
            p["Fc"],
            p["vs"],
            m,
            c,
            p["Kp_pos"],
            max(p["Ti_pos"], 1e-6),
            pos,
            p["tau_a"],
            dt,
            float(nsub),
        ]
    )


def valve_ramp_test(p, amp=6.0, rate=0.02):
    """Apparent band and slip of a force-balance valve: a slow open-loop OP triangle."""
    fp = _force_params(p)
    h = p["h"]
    n_leg = int(amp / rate / h)
    u = p["op0"] + np.concatenate(
        [
            np.linspace(0, amp, n_leg),
            np.linspace(amp, -amp, 2 * n_leg),
            np.linspace(-amp, 0, n_leg),
        ]
    )
    st = np.zeros(8)
    st[0] = st[2] = u[0]
    st[4] = 1.0
    x = np.empty(len(u))
    for k in range(len(u)):
        x[k] = _force_valve(st, u[k], fp, True)
    # band: OP travel after the top reversal before the stem moves down by 0.01 %
    top = n_leg
    after = np.nonzero(x[top:] < x[top:].max() - 0.01)[0]
    band = (u[top] - u[top + after[0]]) if len(after) else np.nan
    # slip: the largest moves of the stem in one controller period (90th percentile of moves)
    dx = np.abs(np.diff(x))
    moving = dx[dx > 1e-6]
    jump = float(np.percentile(moving, 90)) if len(moving) else 0.0
    return float(band), jump


def _cycles(z, min_period=10, threshold=0.2):
    """(cycles, period in samples): the ACF's first positive lobe after its first zero.

    The signal is detrended and smoothed over 5 samples (white noise must not hide a
    cycle); it cycles when that lobe peaks above ``threshold`` at a lag of at least
    ``min_period`` samples and at most half the record (two cycles seen).
    """
    z = np.asarray(z, float)
    z = z[np.isfinite(z)]
    n = len(z)
    if n < 50 or np.std(z) == 0:
        return False, np.nan
    tt = np.arange(n)
    z = z - np.polyval(np.polyfit(tt, z, 1), tt)
    z = np.convolve(z, np.ones(5) / 5, mode="valid")
    n = len(z)
    f = np.fft.rfft(z, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[: n // 2]
    if acf[0] <= 0:
        return False, np.nan
    acf /= acf[0]
    neg = np.nonzero(acf < 0)[0]
    if len(neg) == 0:
        return False, np.nan
    pos = np.nonzero(acf[neg[0] :] > 0)[0]
    if len(pos) == 0:
        return False, np.nan
    p1 = neg[0] + pos[0]
    neg2 = np.nonzero(acf[p1:] < 0)[0]
    p2 = p1 + neg2[0] if len(neg2) else len(acf)
    k = p1 + int(np.argmax(acf[p1:p2]))
    return bool(acf[k] > threshold and k >= min_period and p2 < len(acf)), float(k)


def _record(p, t, v, dev):
    if p["recording"] == "sampled":
        return v
    keep = _swinging_door(t, v, dev, p["comp_max"])
    tk, vk = t[keep], v[keep]
    if p["recording"] == "sdc_interp":
        return np.interp(t, tk, vk)
    idx = np.searchsorted(tk, t, side="right") - 1
    return vk[idx]


def simulate(p, rng):
    """Simulate one drawn loop; returns (n_samples, 3) array and updates p with diagnostics."""
    h = p["h"]
    K_loc = _char(p["op0"] + 0.5, int(p["characteristic"] == "eq_pct"), p["R"], p["phi"]) - _char(
        p["op0"] - 0.5, int(p["characteristic"] == "eq_pct"), p["R"], p["phi"]
    )
    p["valve_gain"] = K_loc
    p["x_offset"] = rng.uniform(-1.0, 1.0) * max(p["band"], 2 * p["Fs"] / (1 + p["Kp_pos"]), 0.5)
    _tune(p, K_loc)
    t_loop = max(p["Ti"], p["tauc"] + p["theta_fit"])
    if p["record_rule"] == "covers_loop" and p["n_samples"] * p["T_hist"] < 20 * t_loop:
        need = 20 * t_loop
        p["T_hist"] = max(p["T_hist"], next((T for T in (1, 2, 3, 5, 10) if 8000 * T >= need), 10))
        p["n_samples"] = int(min(8000, max(p["n_samples"], math.ceil(need / p["T_hist"]))))
    p["record_in_loop_times"] = p["n_samples"] * p["T_hist"] / t_loop
    num, den = _plant_tf(p["plant"], p["gain"], p["tau1"], p["tau2"], p["tz"])
    A, B, C, Dm = signal.tf2ss(num, den)
    Ad, Bd, Cd, _, _ = signal.cont2discrete((A, B, C, Dm), h, method="zoh")
    nd = round(p["theta"] / h)
    m_rec = round(p["T_hist"] / h)
    n_rec = p["n_samples"]
    warm = float(np.clip(5 * (p["tau1"] + p["tau2"] + p["theta"]) + 10 * p["Ti"], 1500.0, 15000.0))
    p["warmup_s"] = warm
    rec_start = int(warm / h)
    n = rec_start + n_rec * m_rec
    din, dout, sp = _disturbances(rng, p, n, h)
    noise = _noise(rng, p, n)
    mode = 2 if p["pv_filter"] > 0 else {"PI": 0, "PID_Dpv": 1, "PID_filt": 2}[p["controller"]]
    ctl = np.array(
        [
            1.0 if p["gain"] > 0 else -1.0,
            p["Kc"],
            p["Ti"],
            p["Td"],
            p["N"],
            p["b"],
            mode,
            p["pv_filter"],
            0.0 if p["antiwindup"] == "clamp" else 1.0,
            max(np.sqrt(p["Ti"] * p["Td"]) if p["Td"] > 0 else 0.5 * p["Ti"], 2 * h),
            h,
        ]
    )
    vcode = p["valve_code"]
    if vcode == VALVE_HE:
        J, S = p["jump_frac"] * p["band"], p["band"]
        vp = np.array([(S + J) / 2, (S - J) / 2, 0.0])  # fs, fd
    elif vcode == VALVE_KANO:
        vp = np.array([p["band"], p["jump_frac"] * p["band"], 0.0])
    else:
        vp = np.zeros(3)
    if vcode != VALVE_FORCE:
        vp[2] = math.exp(-h / p["act_lag"]) if p["act_lag"] > 0 else 0.0
        fp = np.zeros(11)
    else:
        fp = _force_params(p)
        p["band_eff"], p["jump_eff"] = valve_ramp_test(p)
    if vcode in (VALVE_HE, VALVE_KANO):
        p["band_eff"], p["jump_eff"] = p["band"], p["band"] * p["jump_frac"]
    elif vcode == VALVE_IDEAL:
        p["band_eff"], p["jump_eff"] = 0.0, 0.0
    s_alpha = math.exp(-h / p["sensor_lag"]) if p["sensor_lag"] > 0 else 0.0
    pv, op, spr, xr, n_slips, sum_jump, n_sat = _simulate(
        Ad,
        Bd.ravel().copy(),
        Cd.ravel().copy(),
        nd,
        vcode,
        vp,
        fp,
        int(p["characteristic"] == "eq_pct"),
        p["R"],
        p["phi"],
        ctl,
        sp,
        din,
        dout,
        noise,
        s_alpha,
        p["quant"],
        rec_start,
        m_rec,
        n_rec,
        p["op0"],
        p["sp0"],
        p["x_offset"],
    )
    t = np.arange(n_rec) * float(p["T_hist"])
    out = np.column_stack(
        [
            _record(p, t, pv, p["compdev_pv"]),
            _record(p, t, op, p["compdev_op"]),
            _record(p, t, spr, 0.01),
        ]
    )
    p["n_slips"] = int(n_slips)
    p["mean_slip"] = sum_jump / n_slips if n_slips else 0.0
    p["slips_per_1000"] = 1000.0 * n_slips / n_rec
    p["sat_share"] = n_sat / n_rec
    p["op_cycles"], p["op_period"] = _cycles(out[:, 1])
    p["pv_cycles"], p["pv_period"] = _cycles(out[:, 0])
    p["valve_travel_sd"] = float(np.std(np.diff(xr)))
    p["op_noise"] = float(np.std(np.diff(op)) / np.sqrt(2))  # OP's sample-to-sample spread
    ok = np.all(np.isfinite(out)) and p["sat_share"] <= 0.05 and np.ptp(pv) < 200
    return out, ok


def make(n_loops=400, random_state=0, n_max=None, fixed=None):
    """Labelled loops of the third world.

    Returns X (n_loops, n_max, 3: PV, OP, SP as recorded, NaN-padded), y (1 = sticky),
    meta (pandas DataFrame: every drawn parameter and simulation diagnostics).
    ``fixed``: parameters to overwrite after each draw (for experiments; only keys that no
    other draw depends on, e.g. the d_* switches, controller, recording, noise_sd).
    """
    rng = np.random.default_rng(random_state)
    rows, loops = [], []
    y = (rng.random(n_loops) < 0.5).astype(int)
    for i in range(n_loops):
        redraws = 0
        while True:
            p = draw_loop(rng, y[i])
            p.update(fixed or {})
            out, ok = simulate(p, rng)
            if ok or redraws >= 20:
                break
            redraws += 1
        p["redraws"] = redraws
        rows.append(p)
        loops.append(out)
    n_max = n_max or max(len(o) for o in loops)
    X = np.full((n_loops, n_max, 3), np.nan)
    for i, o in enumerate(loops):
        X[i, : min(len(o), n_max)] = o[:n_max]
    meta = pd.DataFrame(rows)
    meta["cycles"] = meta["op_cycles"] | meta["pv_cycles"]
    meta["band_to_noise"] = meta["band_eff"] / meta["noise_sd"]
    meta["band_to_opnoise"] = meta["band_eff"] / meta["op_noise"]
    return X, y, meta


# --------------------------------------------------------------------------------------
# judging sktiction's pretrained model
# --------------------------------------------------------------------------------------


def _scores(y, pred):
    y = np.asarray(y)
    pred = np.asarray(pred)
    pos, neg = y == 1, y == 0
    rec = pred[pos].mean() if pos.any() else np.nan
    spec = 1 - pred[neg].mean() if neg.any() else np.nan
    ba = np.nanmean([rec, spec]) if pos.any() and neg.any() else np.nan
    return ba, rec, spec


def factor_table(meta, pred, col):
    rows = []
    for val, g in meta.groupby(col, observed=True):
        ba, rec, spec = _scores(g["sticky"], pred[g.index])
        rows.append(
            {
                col: val,
                "n": len(g),
                "n_sticky": int(g["sticky"].sum()),
                "recall": rec,
                "specificity": spec,
                "bal_acc": ba,
                "called_sticky": pred[g.index].mean(),
                "no_verdict": g["no_verdict"].mean(),
            }
        )
    return pd.DataFrame(rows)


def add_bins(meta):
    m = meta
    m["tuning"] = pd.cut(
        m["tauc_ratio"], [0, 1, 2, 10], labels=["aggressive<1", "simc1-2", "sluggish>2"]
    )
    m["band_bin"] = pd.cut(
        m["band_eff"],
        [-1, 0.1, 0.5, 1, 2, 100],
        labels=["<0.1(healthy)", "0.1-0.5", "0.5-1", "1-2", ">2"],
    )
    m["noise_bin"] = pd.cut(
        m["noise_sd"], [0, 0.05, 0.15, 0.4, 2], labels=["<0.05", "0.05-0.15", "0.15-0.4", ">0.4"]
    )
    m["b2n_bin"] = pd.cut(
        m["band_to_noise"],
        [-1, 0.5, 2, 5, 20, 1e9],
        labels=["<0.5", "0.5-2", "2-5", "5-20", ">20"],
    )
    m["record_bin"] = pd.cut(
        m["record_in_loop_times"],
        [0, 5, 20, 100, 1e9],
        labels=["<5 loop times", "5-20", "20-100", ">100"],
    )
    m["b2opn_bin"] = pd.cut(
        m["band_to_opnoise"], [-1, 1, 3, 10, 1e9], labels=["<1", "1-3", "3-10", ">10"]
    )
    if "pvop_corr" in m:
        m["corr_bin"] = pd.cut(m["pvop_corr"], [-0.01, 0.3, 0.6, 0.8, 0.9, 1.0])
        m["loop_gain_bin"] = pd.cut(
            m["loop_gain"],
            [0, 0.3, 0.6, 1, 2, 1e9],
            labels=["<0.3", "0.3-0.6", "0.6-1", "1-2", ">2"],
        )
    m["len_bin"] = pd.cut(m["n_samples"], [0, 2000, 4000, 9000], labels=["1-2k", "2-4k", "4-8k"])
    m["jump_bin"] = pd.cut(
        m["jump_eff"] / m["band_eff"].where(m["band_eff"] > 0),
        [-0.01, 0.25, 0.5, 0.75, 10],
        labels=["J/S<.25", ".25-.5", ".5-.75", ">.75"],
    )
    m["slips_bin"] = pd.cut(
        m["slips_per_1000"], [-1, 0.5, 5, 20, 1e9], labels=["<0.5", "0.5-5", "5-20", ">20"]
    )
    m["sensor"] = np.where(m["quant"] > 0, "quantised", "float") + np.where(
        m["sensor_lag"] > 0, "+lag", ""
    )
    dist = []
    for _, r in m.iterrows():
        parts = [k[2:] for k in ("d_steps", "d_sine", "d_ar", "d_rw", "d_sp") if r[k]]
        dist.append("+".join(parts) if parts else "none")
    m["disturbance"] = dist
    return m


FACTORS = [
    "valve",
    "positioner",
    "plant",
    "controller",
    "tuning",
    "remedy_applied",
    "antiwindup",
    "action",
    "characteristic",
    "d_steps",
    "d_sine",
    "d_ar",
    "d_rw",
    "d_sp",
    "load_at",
    "recording",
    "T_hist",
    "len_bin",
    "record_bin",
    "band_bin",
    "jump_bin",
    "noise_bin",
    "b2n_bin",
    "b2opn_bin",
    "slips_bin",
    "sensor",
    "cycles",
    "op_cycles",
    "loop_gain_bin",
    "corr_bin",
    "reason",
]


def score(X, y, meta, clf):
    rep = clf.diagnose(X)
    prob = rep["probability"].to_numpy(float)
    meta = meta.copy()
    meta["prob"] = prob
    meta["reason"] = rep["reason"].astype(str).str.split(":").str[0].to_numpy()
    meta["no_verdict"] = ~np.isfinite(prob)
    pred = (np.nan_to_num(prob, nan=0.0) >= 0.5).astype(int)
    # keep the model's own decision where it gives one
    if "prediction" in rep:
        pred = np.where(meta["no_verdict"], 0, rep["prediction"].to_numpy().astype(int))
    meta["pred"] = pred
    corr = []
    for L in np.asarray(X, float):
        L = L[np.isfinite(L[:, 0]) & np.isfinite(L[:, 1])]
        ok = len(L) > 2 and np.std(L[:, 0]) > 0 and np.std(L[:, 1]) > 0
        corr.append(abs(np.corrcoef(L[:, 0], L[:, 1])[0, 1]) if ok else np.nan)
    meta["pvop_corr"] = corr  # |corr(PV, OP)| as recorded
    meta["loop_gain"] = meta["Kc"] * meta["K_fit"].abs()  # Kc times the bump-test gain
    return add_bins(meta), pred


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--save", default=None, help="pickle the per-loop results here")
    ap.add_argument(
        "--no-model", action="store_true", help="only simulate and print sanity checks"
    )
    ap.add_argument(
        "--clean",
        action="store_true",
        help="no loads and no setpoint moves (sanity check of the valves)",
    )
    args = ap.parse_args(argv)
    pd.set_option("display.width", 200)
    pd.set_option("display.max_rows", 500)
    pd.set_option("display.float_format", lambda v: f"{v:.3f}")
    clf = None
    if not args.no_model:
        from sktiction import pretrained_classifier

        clf = pretrained_classifier()
    all_meta = []
    for seed in args.seeds:
        t0 = time.perf_counter()
        fixed = (
            {"d_steps": False, "d_sine": False, "d_ar": False, "d_rw": False, "d_sp": False}
            if args.clean
            else None
        )
        X, y, meta = make(args.n, random_state=seed, fixed=fixed)
        t_sim = time.perf_counter() - t0
        print(
            f"\n=== seed {seed}: {len(y)} loops ({y.sum()} sticky), simulated in {t_sim:.1f} s; "
            f"redraws {meta['redraws'].sum()} ==="
        )
        # sanity: sticky self-regulating PI loops with band well above noise should cycle
        s = meta[
            (meta.sticky == 1)
            & (meta.plant != "integrating")
            & (meta.controller == "PI")
            & (meta.band_to_noise > 5)
            & (meta.band_to_opnoise > 3)
        ]
        print(
            f"sanity: sticky self-regulating PI loops, band > 5 PV noise sd and > 3 OP noise sd: "
            f"{len(s)}, OP cycles in "
            f"{s.op_cycles.mean():.2f}, PV or OP cycles {s.cycles.mean():.2f}, "
            f"median slips/1000 samples {s.slips_per_1000.median():.1f}"
        )
        hh = meta[meta.sticky == 0]
        print(f"sanity: healthy loops cycling (OP or PV): {hh.cycles.mean():.2f}")
        if clf is None:
            meta["seed"] = seed
            all_meta.append(meta)
            continue
        t0 = time.perf_counter()
        meta, pred = score(X, y, meta, clf)
        ba, rec, spec = _scores(y, pred)
        print(
            f"model: balanced accuracy {ba:.3f}, recall {rec:.3f}, specificity {spec:.3f}; "
            f"no verdict {meta.no_verdict.sum()} ({meta.no_verdict.mean():.1%}; sticky "
            f"{meta.no_verdict[meta.sticky == 1].sum()}, healthy "
            f"{meta.no_verdict[meta.sticky == 0].sum()}), judged in "
            f"{time.perf_counter() - t0:.1f} s"
        )
        vis = (meta.sticky == 1) & (meta.band_to_noise > 3) & (meta.band_to_opnoise > 3)
        print(
            f"recall on sticky loops whose band exceeds 3 PV and 3 OP noise sd: "
            f"{meta.pred[vis].mean():.3f} ({vis.sum()} loops); of those that also cycle: "
            f"{meta.pred[vis & meta.cycles].mean():.3f} ({(vis & meta.cycles).sum()})"
        )
        meta["seed"] = seed
        all_meta.append(meta)
    meta = pd.concat(all_meta, ignore_index=True)
    if args.save:
        meta.to_pickle(args.save)
    if clf is None:
        return meta
    print("\n=== per factor, both seeds pooled (called_sticky = share predicted sticky) ===")
    for col in FACTORS:
        print()
        print(factor_table(meta, meta["pred"].to_numpy(), col).to_string(index=False))
    return meta


if __name__ == "__main__":
    main()
