"""Compiled closed loop and its Python front ends.

One sample ``k`` of the loop (all loops start at steady state)::

    pv[k]   = pv_eq + C x[k] + output_load[k] + noise[k]     (measured PV)
    e[k]    = sp[k] - pv[k]
    op[k]   = clip(op[k-1] + s Kc ((e[k] - e[k-1]) + ts/Ti e[k] - Td/ts D2 pv[k]), 0, 100)
    v[k]    = valve(op[k])
    x[k+1]  = A x[k] + B0 w[k-m] + B1 w[k-m-1],   w = v + input_load - op_eq

``pv_eq`` is the initial setpoint and ``op_eq`` the initial OP (valve at rest
there), so with no disturbance nothing moves until the setpoint or a load does.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm
from sklearn.utils import Bunch

from .._validation import CHANNELS, check_positive, check_random_state_seed
from ._kernel import N_PARAMS, STATE_SIZE, _run_loops
from ._threads import single_blas_thread
from .controllers import PIController
from .effects import EXOGENOUS_KEYS, Effect
from .plants import _Plant
from .valves import _Valve

__all__ = ["simulate_loop", "simulate_loops"]

# Fallback reference for SNR-specified noise when the noise-free pilot PV does not move.
_DEFAULT_REFERENCE_STD = 1.0


def _as_list(obj, n, name):
    if not isinstance(obj, (list, tuple)):
        return [obj] * n
    seq = list(obj)
    if len(seq) != n:
        raise ValueError(f"{name} must be one object or a sequence of {n}; got {len(seq)}.")
    return seq


def _check_n_samples(n_samples):
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 2:
        raise ValueError(f"n_samples must be an integer >= 2; got {n_samples!r}.")
    return int(n_samples)


def _per_loop_effects(effects, n_loops):
    effects = list(effects)
    if all(isinstance(e, Effect) for e in effects):
        return [effects] * n_loops
    if len(effects) != n_loops:
        raise ValueError(
            f"effects must be a sequence of Effect objects or one such sequence per loop "
            f"({n_loops}); got {len(effects)} entries."
        )
    out = []
    for row in effects:
        row = [row] if isinstance(row, Effect) else list(row)
        if not all(isinstance(e, Effect) for e in row):
            raise ValueError("effects must contain Effect objects only.")
        out.append(row)
    return out


def _discretize_all(plants, ts):
    """Every plant's ``discretize(t)`` in the kernel's padded arrays.

    The library's plants share one discretisation; theirs is done here for all plants of
    one number of states at once: scipy's ``expm`` treats each matrix of a stack as it
    treats a matrix alone, so the numbers are the same.
    """
    mats = [None] * len(plants)
    groups = {}
    for j, (p, t) in enumerate(zip(plants, ts, strict=True)):
        if type(p).discretize is not _Plant.discretize:
            mats[j] = p.discretize(t)
            continue
        t = float(t)
        A, B, C = p.state_space()
        m = int(math.floor(p.delay / t + 1e-12))
        theta = max(p.delay - m * t, 0.0)
        groups.setdefault(A.shape[0], []).append((j, A, B, C, m, theta, t))
    for n, items in groups.items():
        E0 = _phi_gammas(n, [(A, B, t - theta) for _, A, B, _, _, theta, t in items])
        late = [k for k, item in enumerate(items) if item[5] > 0]
        E1 = _phi_gammas(n, [(items[k][1], items[k][2], items[k][5]) for k in late])
        E1 = dict(zip(late, E1, strict=True))
        for k, (j, _, _, C, m, _, _) in enumerate(items):
            Phi0, B0 = E0[k][:n, :n], E0[k][:n, n]
            if k in E1:
                Phi1, g1 = E1[k][:n, :n], E1[k][:n, n]
                mats[j] = (Phi0 @ Phi1, B0, Phi0 @ g1, C, m)
            else:
                mats[j] = (Phi0, B0, np.zeros_like(B0), C, m)
    nx = max(m[0].shape[0] for m in mats)
    n_loops = len(plants)
    A = np.zeros((n_loops, nx, nx))
    B0 = np.zeros((n_loops, nx))
    B1 = np.zeros((n_loops, nx))
    C = np.zeros((n_loops, nx))
    delay = np.zeros(n_loops, dtype=np.int64)
    nxs = np.zeros(n_loops, dtype=np.int64)
    for j, (Ad, b0, b1, c, m) in enumerate(mats):
        n = Ad.shape[0]
        nxs[j] = n
        A[j, :n, :n] = Ad
        B0[j, :n] = b0
        B1[j, :n] = b1
        C[j, :n] = c
        delay[j] = m
    return A, B0, B1, C, nxs, delay


def _phi_gammas(n, systems):
    """``expm`` of ``[[A t, B t], [0, 0]]`` for systems ``(A, B, t)`` of ``n`` states, in one
    call (``_phi_gamma`` of each: ``e^{A t}`` top left, ``int_0^t e^{A s} ds B`` right)."""
    M = np.zeros((len(systems), n + 1, n + 1))
    for k, (A, B, t) in enumerate(systems):
        M[k, :n, :n] = A * t
        M[k, :n, n] = B * t
    return expm(M) if len(systems) else M


def _loop_arrays(plants, controllers, valves, ts, op0):
    """The compiled kernel's per-loop parameters (plants discretised at ``ts``)."""
    A, B0, B1, C, nxs, delay = _discretize_all(plants, ts)
    signs = np.array([c.sign(p.gain) for c, p in zip(controllers, plants, strict=True)])
    kcs = signs * np.array([c.kc for c in controllers])
    ti = np.array([c.ti for c in controllers])
    td = np.array([c.td for c in controllers])
    op_lo = np.array([c.op_limits[0] for c in controllers])
    op_hi = np.array([c.op_limits[1] for c in controllers])
    op0 = np.clip(op0, op_lo, op_hi)
    kinds = np.array([v.kind for v in valves], dtype=np.int64)
    vpar = np.zeros((len(valves), N_PARAMS))
    vstate = np.zeros((len(valves), STATE_SIZE))
    for j, v in enumerate(valves):
        vpar[j] = v.params()
        vstate[j] = v.initial_state(op0[j])
    return (A, B0, B1, C, nxs, delay, kcs, ti, td, ts, op_lo, op_hi, op0), (kinds, vpar, vstate)


def _exogenous(effects, n_samples, ts, rng, work):
    """Exogenous arrays of a group of loops, drawn loop by loop in order.

    A key nobody uses is ``(n_loops, 1)`` zeros so the kernel reads a constant; the others
    are rows of the buffers in ``work`` (key -> array), allocated once and reused.
    """
    n = len(effects)
    exo = dict.fromkeys(EXOGENOUS_KEYS)
    for j, row in enumerate(effects):
        for eff in row:
            if eff.kind != "exogenous":
                continue
            for key, arr in eff.signals(n_samples, ts[j], rng).items():
                if exo[key] is None:
                    if key not in work:
                        work[key] = np.empty((n, n_samples))
                    exo[key] = work[key][:n]
                    exo[key].fill(0.0)
                exo[key][j] += arr
    return {key: np.zeros((n, 1)) if arr is None else arr for key, arr in exo.items()}


# Loops simulated together: the exogenous arrays of a chunk are a few MB, reused from one
# chunk to the next (fresh memory is slow to fault in, very slow in some virtual machines).
_CHUNK = 64


def _simulate(loops, sp, effects, n_samples, rng, X, valve=None, start=0, on_chunk=None):
    """Simulate loops chunk by chunk into ``X`` (samples from ``start`` on).

    ``loops`` comes from :func:`_loop_arrays`, ``sp`` is the base setpoint,
    ``(n_loops, 1)`` or ``(n_loops, n_samples)``. The valve positions go to ``valve``
    when given, else to a buffer passed as ``on_chunk(lo, hi, valve_chunk)``. The
    random draws happen in the order of the loops, as one pass over all loops would
    make them.
    """
    params, (kinds, vpar, vstate) = loops
    ts = params[9]
    n_store = n_samples - start
    work = {}
    for lo in range(0, len(effects), _CHUNK):
        hi = min(lo + _CHUNK, len(effects))
        exo = _exogenous(effects[lo:hi], n_samples, ts[lo:hi], rng, work)
        sp_c = sp[lo:hi]
        pv_eq = sp_c[:, 0].copy()
        if exo["setpoint"].shape[1] > 1:
            exo["setpoint"] += sp_c  # in place: large fresh arrays are costly to fault in
            sp_c = exo["setpoint"]
        args = (
            *(a[lo:hi] for a in params), pv_eq, kinds[lo:hi], vpar[lo:hi], vstate[lo:hi],
            sp_c, exo["output_load"], exo["input_load"],
        )  # fmt: skip
        ref = np.zeros(hi - lo)
        if exo["noise_relative"].shape[1] > 1:
            # SNR-specified noise: scale by the PV spread over the second half of a
            # noise-free pilot run, run only for the loops that have such noise
            rows = np.flatnonzero(exo["noise_relative"].any(axis=1))
            half = n_samples // 2
            if "pilot" not in work:
                work["pilot"] = np.empty((hi - lo, n_samples - half, 3))
            pilot = work["pilot"][: rows.size]
            zeros = np.zeros((hi - lo, 1))
            _run_loops(*args, zeros, zeros, ref, rows, half, pilot, np.empty((rows.size, 0)))
            ref[:] = _DEFAULT_REFERENCE_STD
            ref[rows] = pilot[:, :, 0].std(axis=1)
            ref = np.where(ref > 1e-12, ref, _DEFAULT_REFERENCE_STD)
        if valve is None and "valve" not in work:
            work["valve"] = np.empty((hi - lo, n_store))
        vbuf = valve[lo:hi] if valve is not None else work["valve"][: hi - lo]
        _run_loops(
            *args, exo["noise"], exo["noise_relative"], ref, np.arange(hi - lo), start,
            X[lo:hi], vbuf,
        )  # fmt: skip
        if on_chunk is not None:
            on_chunk(lo, hi, vbuf)


def _record(X, effects, ts, rng):
    """Apply each loop's recording effects to its record in ``X``, loop by loop, in place."""
    for j, row in enumerate(effects):
        rec = [eff for eff in row if eff.kind == "recording"]
        if not rec:
            continue
        sig = {"pv": X[j, :, 0].copy(), "op": X[j, :, 1].copy(), "sp": X[j, :, 2].copy()}
        for eff in rec:
            sig = eff.record(sig, ts[j], rng)
        for c, key in enumerate(CHANNELS):
            X[j, :, c] = sig[key]


@single_blas_thread
def simulate_loops(
    plants,
    controllers,
    valves,
    n_samples,
    ts,
    *,
    setpoint=50.0,
    effects=(),
    initial_op=None,
    random_state=None,
):
    """Simulate many closed loops in one compiled call.

    Parameters
    ----------
    plants, controllers, valves : object or sequence
        One object shared by all loops, or one per loop (equal lengths).
    n_samples : int
        Samples per loop (>= 2).
    ts : float or sequence of float
        Sample time(s) (> 0), in the time unit of the plant parameters.
    setpoint : float, array of shape (n_samples,) or (n_loops, n_samples), default=50.0
        Base setpoint; the PV starts at equilibrium at its first value.
        Setpoint effects are added to it.
    effects : sequence of Effect, or one such sequence per loop, default=()
        Exogenous and recording effects (:mod:`sktiction.simulation.effects`).
    initial_op : float, sequence of float or None, default=None
        OP (and valve position) at the start, where the plant is at
        equilibrium; ``None`` means 50 %.
    random_state : None, int or numpy.random.Generator, default=None
        Seeds the effects.

    Returns
    -------
    result : sklearn.utils.Bunch
        ``pv`` (measured, with noise), ``op``, ``sp`` (views into ``X``),
        ``valve`` (stem position = plant input without input load): arrays
        ``(n_loops, n_samples)``;
        ``t``: ``(n_samples,)`` for a common ``ts``, else ``(n_loops, n_samples)``;
        ``X``: ``(n_loops, n_samples, 3)`` with channels PV, OP, SP (after
        recording effects).

    Examples
    --------
    >>> from sktiction.simulation import (FOPTD, PIController, RelayValve, LinearValve,
    ...     SetpointSteps, simulate_loops)
    >>> plant = FOPTD(1.0, 10.0, 2.0)
    >>> res = simulate_loops(plant, PIController.from_plant(plant), [LinearValve(),
    ...     RelayValve(2.0)], 500, 0.5, effects=[SetpointSteps([5.0], [1.0])])
    >>> res.X.shape
    (2, 500, 3)
    """
    n_samples = _check_n_samples(n_samples)
    n_loops = None
    for obj in (plants, controllers, valves):
        if isinstance(obj, (list, tuple)):
            n_loops = len(obj)
            break
    n_loops = 1 if n_loops is None else n_loops
    if n_loops < 1:
        raise ValueError("at least one loop is needed; got empty sequences.")
    plants = _as_list(plants, n_loops, "plants")
    controllers = _as_list(controllers, n_loops, "controllers")
    valves = _as_list(valves, n_loops, "valves")
    for c in controllers:
        if not isinstance(c, PIController):
            raise ValueError(f"controllers must be PIController objects; got {c!r}.")
    for v in valves:
        if not isinstance(v, _Valve):
            raise ValueError(f"valves must be valve objects from sktiction.simulation; got {v!r}.")
    ts_arr = np.broadcast_to(np.asarray(ts, dtype=float), (n_loops,)).copy()
    for t in ts_arr:
        check_positive(float(t), "ts")
    if initial_op is None:
        initial_op = 50.0
    op0 = np.broadcast_to(np.asarray(initial_op, dtype=float), (n_loops,)).copy()
    if not np.all((op0 >= 0) & (op0 <= 100)):
        raise ValueError(f"initial_op must be within 0-100 %; got {initial_op!r}.")
    sp = np.asarray(setpoint, dtype=float)
    if sp.ndim == 0:
        sp = np.full((n_loops, 1), float(sp))
    elif sp.shape == (n_samples,):
        sp = np.tile(sp, (n_loops, 1))
    elif sp.shape != (n_loops, n_samples):
        raise ValueError(
            f"setpoint must be a number or have shape ({n_samples},) or "
            f"({n_loops}, {n_samples}); got {sp.shape}."
        )
    if not np.all(np.isfinite(sp)):
        raise ValueError("setpoint must be finite.")
    effects = _per_loop_effects(effects, n_loops)
    rng = check_random_state_seed(random_state)

    loops = _loop_arrays(plants, controllers, valves, ts_arr, op0)
    # PV and OP are written straight into the (n_loops, n_samples, 3) output
    X = np.empty((n_loops, n_samples, 3))
    valve = np.empty((n_loops, n_samples))
    _simulate(loops, sp, effects, n_samples, rng, X, valve=valve)

    t = np.arange(n_samples) * ts_arr[0]
    if np.any(ts_arr != ts_arr[0]):
        t = np.arange(n_samples)[None, :] * ts_arr[:, None]
    _record(X, effects, ts_arr, rng)
    return Bunch(pv=X[:, :, 0], op=X[:, :, 1], sp=X[:, :, 2], valve=valve, t=t, X=X)


def simulate_loop(
    plant,
    controller,
    valve,
    n_samples,
    ts,
    *,
    setpoint=50.0,
    effects=(),
    initial_op=None,
    random_state=None,
):
    """Simulate one closed loop: plant, PI(D) controller, valve and effects.

    Parameters
    ----------
    plant : FOPTD, SOPTD, NthOrderLag or IntegratingPlant
    controller : PIController
    valve : LinearValve, RelayValve, ChoudhuryValve, KanoValve or DeadbandValve
    n_samples : int
        Number of samples (>= 2).
    ts : float
        Sample time (> 0), same time unit as the plant.
    setpoint : float or array of shape (n_samples,), default=50.0
        Base setpoint; the loop starts at steady state with PV at its first
        value and OP (valve) at ``initial_op``.
    effects : sequence of Effect, default=()
        Exogenous effects (setpoint steps, loads, noise) and recording effects
        (e.g. :class:`Quantization`).
    initial_op : float or None, default=None
        Steady-state OP at the start (0-100 %); ``None`` means 50 %.
    random_state : None, int or numpy.random.Generator, default=None
        Seeds the random effects.

    Returns
    -------
    result : sklearn.utils.Bunch
        ``pv``, ``op``, ``sp``, ``valve``, ``t``: arrays ``(n_samples,)``;
        ``X``: ``(n_samples, 3)`` with columns PV, OP, SP.

    Examples
    --------
    >>> from sktiction.simulation import (FOPTD, PIController, ChoudhuryValve,
    ...     SetpointSteps, simulate_loop)
    >>> plant = FOPTD(gain=1.0, time_constant=10.0, delay=5.0)
    >>> ctrl = PIController.from_plant(plant, rule="amigo")
    >>> res = simulate_loop(plant, ctrl, ChoudhuryValve(S=3.0, J=1.0), 2000, 0.5,
    ...                     effects=[SetpointSteps([10.0], [2.0])])
    >>> res.X.shape
    (2000, 3)
    >>> bool(res.pv[-500:].std() > 0.1)  # stiction keeps the loop cycling
    True
    """
    if isinstance(plant, (list, tuple)):
        raise ValueError("plant must be a single plant; use simulate_loops for several.")
    res = simulate_loops(
        [plant],
        controller,
        valve,
        n_samples,
        ts,
        setpoint=np.asarray(setpoint, dtype=float),
        effects=list(effects),
        initial_op=initial_op,
        random_state=random_state,
    )
    out = Bunch(**{k: v[0] for k, v in res.items() if k != "t"})
    out.t = res.t if res.t.ndim == 1 else res.t[0]
    return out
