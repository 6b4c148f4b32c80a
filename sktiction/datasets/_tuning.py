"""Plants of a chosen apparent lambda, their PI settings, and the phase crossover of many
sampled loops at once: the dynamics both simulated worlds are built on.
"""

from __future__ import annotations

import functools

import numpy as np

from ..simulation import (
    FOPTD,
    SOPTD,
    IntegratingPlant,
    NthOrderLag,
    PIController,
    foptd_approximation,
)


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
