"""The compiled closed loop and the valve step it inlines, in one module.

numba's on-disk cache checks only the file of the function it compiled: a kernel
cached in one file that inlines a function of another keeps the old code when only
the other file changes (the loop once kept a valve step without the He model). So
every compiled function the loop calls, the valve kinds and the state layout live
here; ``loop.py`` and ``valves.py`` import them.
"""

from __future__ import annotations

import numpy as np
from numba import njit

LINEAR, RELAY, CHOUDHURY, KANO, DEADBAND, HE = 0, 1, 2, 3, 4, 5
N_PARAMS = 2
STATE_SIZE = 6
_Y, _UPREV, _SPREV, _STUCK, _DIR, _USTICK = range(STATE_SIZE)


@njit(cache=True, inline="always")
def _sign(v):
    if v > 0:
        return 1.0
    if v < 0:
        return -1.0
    return 0.0


@njit(cache=True, inline="always")
def _valve_update(kind, p0, p1, y, uprev, sprev, stuck, direction, ustick, u):
    """One valve step on scalars: the parameters, the state ``[y, u_prev, du_sign_prev,
    stuck, direction, u_stick]`` and the input; returns the new position, ``du_sign_prev``,
    ``stuck``, ``direction`` and ``u_stick`` (``u_prev`` becomes ``u``).

    The closed-loop kernel keeps the state in local variables: no array is passed per
    sample (a call with array arguments costs more than most models' arithmetic).
    """
    if kind == LINEAR:
        y = u
    elif kind == RELAY:
        if abs(u - y) > p0:
            y = u
    elif kind == DEADBAND:
        half = 0.5 * p0
        if u - y > half:
            y = u - half
        elif y - u > half:
            y = u + half
    elif kind == CHOUDHURY:
        S = p0
        J = p1
        s = _sign(u - uprev)
        if s != sprev:
            # velocity changed sign or vanished: the valve sticks here
            stuck = 1.0
            ustick = uprev
        if stuck == 0.0:
            y = u - s * 0.5 * (S - J)
        elif s != 0.0:
            thr = J if s == direction else S
            if abs(u - ustick) > thr:
                y = u - s * 0.5 * (S - J)
                stuck = 0.0
                direction = s
        sprev = s
    elif kind == KANO:
        S = p0
        J = p1
        du = u - uprev
        if du * sprev <= 0.0 and stuck == 0.0:
            # a moving valve stops or reverses: remember where
            ustick = uprev
            stuck = 1.0
        d = direction
        if stuck == 0.0:
            y = u - d * 0.5 * (S - J)
        elif d == 0.0:
            if abs(u - ustick) > S:
                d = _sign(u - ustick)
                y = u - d * 0.5 * (S - J)
                stuck = 0.0
        elif -d * (u - ustick) > S:
            d = -d
            y = u - d * 0.5 * (S - J)
            stuck = 0.0
        elif d * (u - ustick) > J:
            y = u - d * 0.5 * (S - J)
            stuck = 0.0
        direction = d
        sprev = du
    elif kind == HE:
        # the residual force u - y moves the valve once it beats static friction
        r = u - y
        if abs(r) > p0:
            y = u - _sign(r) * p1
    y = min(max(y, 0.0), 100.0)
    return y, sprev, stuck, direction, ustick


@njit(cache=True)
def valve_step(kind, par, st, u):
    """Advance one valve by one sample; ``st`` is updated in place, returns the position."""
    y, sprev, stuck, direction, ustick = _valve_update(
        kind, par[0], par[1], st[_Y], st[_UPREV], st[_SPREV], st[_STUCK], st[_DIR],
        st[_USTICK], u,
    )  # fmt: skip
    st[_Y] = y
    st[_UPREV] = u
    st[_SPREV] = sprev
    st[_STUCK] = stuck
    st[_DIR] = direction
    st[_USTICK] = ustick
    return y


@njit(cache=True)
def _valve_run(kind, par, st, u):
    out = np.empty(u.shape[0])
    for k in range(u.shape[0]):
        out[k] = valve_step(kind, par, st, u[k])
    return out


@njit(cache=True)
def _run_loops(
    A, B0, B1, C, nxs, delay, kcs, ti, td, ts, op_lo, op_hi, op0, pv_eq,
    kinds, vpar, vstate, sp, out_load, in_load, noise, noise_rel, ref, rows, start, X, valve,
):  # fmt: skip
    """Simulate loops ``rows``: loop ``rows[r]`` into ``X[r]`` and ``valve[r]``.

    Inputs are indexed by loop, outputs by position in ``rows``. The loop runs
    ``start + X.shape[1]`` samples and stores those from ``start`` on (``valve`` may
    have no columns: not stored). The measurement noise is ``noise + noise_rel * ref``.
    """
    n_rows = rows.shape[0]
    n = start + X.shape[1]
    keep_valve = valve.shape[1] > 0
    x = np.zeros(A.shape[1])
    xn = np.zeros(A.shape[1])
    # exogenous inputs are (n_loops, n) or (n_loops, 1): step 1 or 0 through time
    dsp = 1 if sp.shape[1] > 1 else 0
    dol = 1 if out_load.shape[1] > 1 else 0
    dil = 1 if in_load.shape[1] > 1 else 0
    dno = 1 if noise.shape[1] > 1 else 0
    dnr = 1 if noise_rel.shape[1] > 1 else 0
    for r in range(n_rows):
        j = rows[r]
        nx = nxs[j]
        x[:] = 0.0
        m = delay[j]
        nb = m + 2
        buf = np.zeros(nb)
        head = 0  # buf[head] receives w[k]; buf[(head + m) % nb] holds w[k-m]
        # the valve's parameters and state in local variables (see _valve_update)
        kind = kinds[j]
        p0 = vpar[j, 0]
        p1 = vpar[j, 1]
        yv = vstate[j, _Y]
        uprev = vstate[j, _UPREV]
        sprev = vstate[j, _SPREV]
        stuck = vstate[j, _STUCK]
        direction = vstate[j, _DIR]
        ustick = vstate[j, _USTICK]
        kp = kcs[j]
        ki = kcs[j] * ts[j] / ti[j]
        kd = kcs[j] * td[j] / ts[j]
        lo = op_lo[j]
        hi = op_hi[j]
        u = op0[j]
        ueq = op0[j]
        peq = pv_eq[j]
        scale = ref[j]
        # steady state before the first sample: zero error, PV at equilibrium
        e1 = 0.0
        pv1 = peq
        pv2 = peq
        for k in range(n):
            y = 0.0
            for i in range(nx):
                y += C[j, i] * x[i]
            nz = noise[j, k * dno] + noise_rel[j, k * dnr] * scale
            p = peq + y + out_load[j, k * dol] + nz
            e = sp[j, k * dsp] - p
            u += kp * (e - e1) + ki * e - kd * (p - 2.0 * pv1 + pv2)
            if u > hi:
                u = hi
            elif u < lo:
                u = lo
            yv, sprev, stuck, direction, ustick = _valve_update(
                kind, p0, p1, yv, uprev, sprev, stuck, direction, ustick, u
            )
            uprev = u
            v = yv
            if k >= start:
                X[r, k - start, 0] = p
                X[r, k - start, 1] = u
                X[r, k - start, 2] = sp[j, k * dsp]
                if keep_valve:
                    valve[r, k - start] = v
            e1 = e
            pv2 = pv1
            pv1 = p
            buf[head] = v + in_load[j, k * dil] - ueq
            i0 = head + m
            if i0 >= nb:
                i0 -= nb
            i1 = i0 + 1
            if i1 >= nb:
                i1 -= nb
            # samples before the start were at equilibrium (zeros in buf)
            w0 = buf[i0]
            w1 = buf[i1]
            for i in range(nx):
                acc = B0[j, i] * w0 + B1[j, i] * w1
                for q in range(nx):
                    acc += A[j, i, q] * x[q]
                xn[i] = acc
            for i in range(nx):
                x[i] = xn[i]
            head -= 1
            if head < 0:
                head += nb
