"""Generate labelled sets of simulated oscillating control loops."""

from __future__ import annotations

import numbers

import numpy as np
import pandas as pd

from .._validation import check_positive, check_random_state_seed
from ..simulation._threads import single_blas_thread
from ..simulation.loop import _loop_arrays, _record, _simulate
from ._classic_world import _draw_classic
from ._default_world import (
    _RECORDING_NAMES,
    _REGIME_WEIGHTS,
    _RULES_INT,
    _RULES_SELF,
    NOISE_COLOURS,
    RECORDING_EFFECTS,
    RULES,
    SETPOINT_REGIMES,
    _simulate_default,
)

__all__ = ["make_loops"]

CAUSES = ("stiction", "aggressive_tuning", "external_disturbance", "none")
STICTION_MODELS = ("relay", "choudhury", "kano")


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


WORLDS = ("default", "classic")
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
        noise's standard deviation; NaN otherwise), ``stiction_visible`` (True when
        ``slip_snr >= 1``: the slips can be seen above the noise) and
        ``valve_evidence`` (sticky loops, before recording effects: the share of PV's
        variance left unexplained by OP that stays unexplained when the true valve
        position is added, in linear fits over lags of up to half a cycle, 10-40
        samples; near 0 when the record shows how the valve moved, near 1 when OP
        explains all that the valve would, as for a smooth cycle through a slow plant
        or slips inside the noise; NaN otherwise).

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
