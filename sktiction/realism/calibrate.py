"""Fit the catalog's parameters to measured loops: a calibrated world for ``make_loops``."""

from __future__ import annotations

import inspect

import numpy as np
import pandas as pd

from .._validation import CHANNELS, check_loops, check_random_state_seed
from ._catalog import (
    EFFECTS,
    effect_names,
    oscillating_per_loop,
    setpoint_regime_per_loop,
    snr_per_loop,
)
from .compare import as_statistics
from .statistics import loop_statistics

__all__ = ["Realism", "calibrate", "apply_effects", "apply_recording"]

# A simulated loop copies a measured loop's SNR within +- this many dB ...
_SNR_SPREAD = 3.0
# ... and its share of PV's own variation within +- this much.
_SHARE_SPREAD = 0.1
# Noise whose second differences are this white (noise_colour below) is white noise.
_WHITE = 0.3
# Median PV-OP correlation of make_loops' default world without PV's own variation; the
# reference when no pilot simulation measures it (refine=False).
_CORR_REFERENCE = 0.7
# Largest share of PV's own variation fitted (the rest of PV must still follow the loop).
_MAX_SHARE = 0.9
# Fewest measured loops of a type for settings fitted to that type alone.
_MIN_TYPE_LOOPS = 5


def _make_loops_arguments():
    from ..datasets import make_loops

    return set(inspect.signature(make_loops).parameters)


class Realism:
    """A calibrated world: recording effects per loop and ``make_loops`` arguments.

    Made by :func:`calibrate`; pass it as ``make_loops(..., realism=...)`` or use
    :func:`apply_recording` on loops already simulated.

    Attributes
    ----------
    profiles : pandas.DataFrame
        One row per measured loop: ``loop_type`` and, for each recording effect of the
        catalog, whether it shows (``<effect>``, bool) and its fitted parameters
        (``<effect>.<param>``). A simulated loop copies the recording of one measured loop
        drawn at random (of its loop type when asked), so effects that go together in the
        plant go together in the simulation and loops without any effect stay clean.
        World settings of each loop, copied by :meth:`loop_profile`: ``snr_db`` (before the
        common ``snr_shift``), ``white_noise``, ``pv_own_share``, ``oscillating`` (probability
        that the copy's cycle has its drive on), ``setpoint_regime`` (None without SP),
        ``pv_op_corr`` (measured), and ``weight`` when :func:`calibrate` got ``groups``.
    snr_shift : float
        dB added to every profile's SNR (fitted by pilot simulations).
    overrides : dict
        Keyword arguments of :func:`sktiction.datasets.make_loops` fitted to the measured loops
        (only names ``make_loops`` takes; at least ``snr_db_range`` when a noise level could
        be measured).
    statistics : pandas.DataFrame
        The measured loops' :func:`~sktiction.realism.loop_statistics`.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.realism import apply_effects, calibrate
    >>> from sktiction.simulation import HoldLastValue
    >>> X, _ = make_loops(10, 400, world="classic", random_state=0)
    >>> realism = calibrate(apply_effects(X, [HoldLastValue(0.3)], random_state=0), refine=False)
    >>> realism.share("hold_last_value")
    1.0
    >>> [type(e).__name__ for e in realism.recording_effects(np.random.default_rng(0))]
    ['HoldLastValue']
    """

    def __init__(self, profiles, overrides, statistics, snr_shift=0.0):
        self.profiles = profiles
        self.overrides = dict(overrides)
        self.statistics = statistics
        self.snr_shift = float(snr_shift)

    def _pool(self, loop_type):
        if loop_type is not None:
            sub = self.profiles[self.profiles["loop_type"] == loop_type]
            if len(sub):
                return sub
        return self.profiles

    def loop_profile(self, rng):
        """One simulated loop's profile, copied from a measured loop drawn at random.

        ``make_loops(..., realism=...)`` calls it once per loop: the measured loop's type sets
        the simulated plant's type (level: integrating; flow, pressure: first or second
        order; others: any), its world settings (noise level and
        colour, PV's own variation, oscillating or quiet, setpoint regime) and its recording
        effects are the simulated loop's. Drawn without regard to the cause, so sticky and
        healthy loops get the same mix.

        Parameters
        ----------
        rng : numpy.random.Generator, int or None

        Returns
        -------
        profile : dict
            ``loop_type`` (str), ``settings`` (dict of ``make_loops`` arguments for this
            loop; ``setpoint_regime`` names the regime itself) and ``recording`` (list of
            Effect).
        """
        rng = check_random_state_seed(rng)
        if len(self.profiles) == 0:
            return {"loop_type": None, "settings": {}, "recording": []}
        w = self.profiles["weight"].to_numpy(dtype=float) if "weight" in self.profiles else None
        if w is None or not np.isfinite(w).all() or w.sum() <= 0:
            row = self.profiles.iloc[int(rng.integers(len(self.profiles)))]
        else:
            idx = int(np.searchsorted(np.cumsum(w / w.sum()), rng.random(), side="right"))
            row = self.profiles.iloc[min(idx, len(w) - 1)]
        settings = {}
        snr = row.get("snr_db", np.nan)
        if np.isfinite(snr):
            snr += self.snr_shift
            settings["snr_db_range"] = (snr - _SNR_SPREAD, snr + _SNR_SPREAD)
        if row.get("white_noise", False):
            settings["noise_colours"] = ("white",)
        share = row.get("pv_own_share", np.nan)
        if np.isfinite(share):
            settings["pv_own_share"] = (
                float(max(share - _SHARE_SPREAD, 0.0)), float(min(share + _SHARE_SPREAD, 0.95))
            )
        if np.isfinite(row.get("oscillating", np.nan)):
            settings["oscillating_fraction"] = float(row["oscillating"])
        if isinstance(row.get("setpoint_regime"), str):
            settings["setpoint_regime"] = row["setpoint_regime"]
        return {
            "loop_type": row["loop_type"],
            "settings": settings,
            "recording": self._effects(row),
        }

    def recording_effects(self, rng, loop_type=None):
        """Recording effects for one simulated loop, copied from a random measured loop.

        Parameters
        ----------
        rng : numpy.random.Generator, int or None
        loop_type : str or None, default=None
            Draw among measured loops of this type (all loops when None or unknown).

        Returns
        -------
        effects : list of Effect
            In the historian's order (sensor, averaging, grid, compression, holds); empty
            when the drawn loop shows none.
        """
        rng = check_random_state_seed(rng)
        pool = self._pool(loop_type)
        if len(pool) == 0:
            return []
        return self._effects(pool.iloc[int(rng.integers(len(pool)))])

    @staticmethod
    def _effects(row):
        out = []
        for name in effect_names("recording"):
            if not bool(row[name]):
                continue
            entry = EFFECTS[name]
            params = {
                k.split(".", 1)[1]: float(row[k])
                for k in row.index
                if k.startswith(name + ".")
            }
            out.append(entry.make(**params))
        return out

    def share(self, effect, loop_type=None):
        """Share of measured loops (of a loop type) that show a recording effect."""
        if effect not in effect_names("recording"):
            raise ValueError(
                f"effect must be a recording effect of the catalog "
                f"{effect_names('recording')}; got {effect!r}."
            )
        return float(self._pool(loop_type)[effect].mean())

    def summary(self):
        """Share and median parameters of each recording effect, per loop type and overall.

        Returns
        -------
        table : pandas.DataFrame
            Columns ``loop_type``, ``effect``, ``share``, ``n_loops``, ``params`` (medians
            over the loops that show it).
        """
        rows = []
        types = ["all"] + sorted(set(self.profiles["loop_type"]) - {"all"})
        for lt in types:
            pool = self._pool(None if lt == "all" else lt)
            for name in effect_names("recording"):
                on = pool[pool[name]]
                cols = [c for c in pool.columns if c.startswith(name + ".")]
                params = {c.split(".", 1)[1]: float(on[c].median()) for c in cols if len(on)}
                rows.append(
                    {
                        "loop_type": lt,
                        "effect": name,
                        "share": float(pool[name].mean()) if len(pool) else np.nan,
                        "n_loops": len(pool),
                        "params": {k: round(v, 4) for k, v in params.items()},
                    }
                )
        return pd.DataFrame(rows)

    def __repr__(self):
        shares = ", ".join(
            f"{n}={self.share(n):.2f}" for n in effect_names("recording") if self.share(n) > 0
        )
        return f"Realism(n_loops={len(self.profiles)}, {shares or 'no recording effects'})"


def calibrate(measured, *, loop_types=None, groups=None, refine=True, random_state=None):
    """Fit the catalog's recording effects and world settings to measured loops.

    Each measured loop's statistics say which recording effects of
    :data:`~sktiction.realism.EFFECTS` it shows and with which parameters (each effect's
    ``present`` and ``params``: per-loop estimates, so one odd loop moves nothing but its own
    profile); world effects give ``make_loops`` arguments (noise level as an SNR range from
    the 10-90 % quantiles, setpoint regimes seen, oscillation periods, record lengths).

    Parameters
    ----------
    measured : array-like (n_loops, n_samples, n_channels), Bunch or DataFrame
        Measured loops, a ``read_loops`` Bunch (its ``meta.loop_type`` gives the loop
        types), or their :func:`~sktiction.realism.loop_statistics`.
    loop_types : array-like of str or None, default=None
        Loop type of each measured loop (overrides the Bunch's); profiles can then be drawn
        per type with ``Realism.recording_effects(rng, loop_type=...)``.
    groups : array-like or None, default=None
        Group of each measured loop, e.g. its valve tag: ``loop_profile`` then draws every
        group equally often (each loop with weight ``1 / loops in its group``), so that a
        valve recorded in many windows does not set the world alone.
    refine : bool, default=True
        Refine with pilot simulations of ``make_loops(..., realism=...)`` (a few seconds;
        needs its ``realism`` argument): the mix of noise colours whose simulated
        ``noise_colour`` is closest to the measured one (seven mixes of 60 loops), then the
        SNR range, shifted twice (80 loops each) so that the simulated median noise level
        matches the measured one.
    random_state : None, int or numpy.random.Generator, default=None
        Seed of the pilot simulation (the per-loop fit itself is deterministic).

    Returns
    -------
    realism : Realism

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.realism import apply_effects, calibrate
    >>> from sktiction.simulation import DeadbandCompression
    >>> X, _ = make_loops(10, 500, world="classic", random_state=0)
    >>> realism = calibrate(apply_effects(X, [DeadbandCompression(0.05)], random_state=0))
    >>> table = realism.summary().set_index("effect")
    >>> round(table.loc["deadband_compression", "params"]["band"], 2)
    0.05
    >>> "snr_db_range" in realism.overrides
    True
    """
    check_random_state_seed(random_state)
    bunch_types = None
    if hasattr(measured, "X") and hasattr(measured, "meta") and "loop_type" in measured.meta:
        bunch_types = measured.meta["loop_type"].to_numpy()
    stats = as_statistics(measured)
    if loop_types is None:
        loop_types = bunch_types
    if loop_types is None:
        loop_types = np.full(len(stats), "all", dtype=object)
    loop_types = np.asarray(loop_types, dtype=object)
    if len(loop_types) != len(stats):
        raise ValueError(
            f"loop_types must have one entry per measured loop ({len(stats)}); "
            f"got {len(loop_types)}."
        )
    profiles = pd.DataFrame({"loop_type": loop_types})
    if groups is not None:
        groups = np.asarray(groups).astype(str)
        if len(groups) != len(stats):
            raise ValueError(
                f"groups must have one entry per measured loop ({len(stats)}); "
                f"got {len(groups)}."
            )
        _, inverse, counts = np.unique(groups, return_inverse=True, return_counts=True)
        profiles["weight"] = 1.0 / counts[inverse]
    # world settings of each measured loop, copied with its recording by loop_profile
    profiles["snr_db"] = snr_per_loop(stats)
    colour = stats["noise_colour"].to_numpy(dtype=float)
    profiles["white_noise"] = np.isfinite(colour) & (colour < _WHITE)
    # probability that a simulated loop copying this one has its cycle's drive on (1 or 0
    # until the pilot simulations correct it for loops that cycle without showing it)
    profiles["oscillating"] = oscillating_per_loop(stats).astype(float)
    profiles["setpoint_regime"] = setpoint_regime_per_loop(stats)
    profiles["pv_op_corr"] = stats["pv_op_corr"].to_numpy(dtype=float)
    # first guess (refined per loop type by a pilot): the median correlation lowered from
    # the default world's
    corr = profiles["pv_op_corr"].to_numpy()
    first = _own_share(np.nanmedian(corr), _CORR_REFERENCE) if np.isfinite(corr).any() else 0.0
    profiles["pv_own_share"] = float(first)
    for name in effect_names("recording"):
        entry = EFFECTS[name]
        on = np.asarray(entry.present(stats), dtype=bool)
        params = entry.params(stats)
        # a loop whose parameters cannot be read does not get the effect
        on &= np.isfinite(params.to_numpy(dtype=float)).all(axis=1)
        profiles[name] = on
        for col in params.columns:
            profiles[f"{name}.{col}"] = params[col].to_numpy(dtype=float)
    allowed = _make_loops_arguments()
    overrides = {}
    for name in effect_names("world"):
        fit = EFFECTS[name].fit
        if fit is not None:
            overrides.update({k: v for k, v in fit(stats).items() if k in allowed})
    realism = Realism(profiles, overrides, stats)
    if refine and "realism" in allowed:
        rng = check_random_state_seed(random_state)
        _refine_snr(realism, rng)
        _refine_own_share(realism, rng)
        _refine_snr(realism, rng, n_steps=1)
        _refine_oscillating(realism, rng)
    share = realism.profiles["pv_own_share"].to_numpy(dtype=float)
    if "pv_own_share" in allowed and np.isfinite(share).any():
        lo, hi = np.nanpercentile(share, [10, 90])
        realism.overrides["pv_own_share"] = (float(lo), float(hi))
    return realism


def _own_share(corr, reference):
    """Share of PV's own variation that lowers a PV-OP correlation from ``reference`` to
    ``corr``: a component uncorrelated with OP carrying a share ``s`` of the PV variance scales
    the correlation by ``sqrt(1 - s)``. A reference of 0 (a pilot whose median loop shows
    no correlation) leaves nothing to lower: 0, as for NaN."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # numpy's division: by 0 (or nearly) it gives inf or NaN, share 0 below; Python's
        # raises ZeroDivisionError (OverflowError)
        share = 1.0 - (np.float64(corr) / np.float64(reference)) ** 2
    return float(np.clip(share, 0.0, _MAX_SHARE)) if np.isfinite(share) else 0.0


def _pilot(realism, rng, n_loops=80, n_samples=600, **kwargs):
    from ..datasets import make_loops

    X, _, meta = make_loops(
        n_loops, n_samples, realism=realism, random_state=rng, return_meta=True, **kwargs
    )
    return loop_statistics(X), meta


def _refine_oscillating(realism, rng, n_loops=150):
    """Fit the share of loops whose cycle's drive is on (``oscillating_fraction``).

    A loop with its drive on need not show a cycle (a healthy loop without a disturbance
    never does, noise hides others) and a quiet one may ring. Two pilots, every drive on and
    every drive off, give the shares ``p1`` and ``p0`` of loops whose ACF peak passes 0.3;
    the measured share ``m`` then asks for ``f = (m - p0) / (p1 - p0)`` (clipped to 0-1).
    Each measured loop that cycles turns the drive on with probability ``min(1, f / m)``,
    each quiet one with ``max(0, (f - m) / (1 - m))``, so that the shares add up to ``f``.
    """
    prof = realism.profiles
    measured = oscillating_per_loop(realism.statistics)
    if "oscillating_fraction" not in realism.overrides or len(prof) < 5:
        return
    m = float(measured.mean())
    saved = prof["oscillating"].copy()
    p = []
    try:
        for drive in (1.0, 0.0):
            prof["oscillating"] = drive
            stats, _ = _pilot(realism, rng, n_loops=n_loops)
            p.append(float(oscillating_per_loop(stats).mean()))
    finally:
        prof["oscillating"] = saved
    p1, p0 = p
    if p1 - p0 < 0.05:  # the pilots cannot tell drives apart: keep the measured share
        return
    f = float(np.clip((m - p0) / (p1 - p0), 0.0, 1.0))
    on = min(1.0, f / m) if m > 0 else 0.0
    off = max(0.0, (f - m) / (1.0 - m)) if m < 1 else 0.0
    prof["oscillating"] = np.where(measured, on, off)
    realism.overrides["oscillating_fraction"] = f


def _type_medians(values, types, wanted, overall):
    """Median of ``values`` per loop type in ``wanted`` where at least ``_MIN_TYPE_LOOPS``
    finite values of that type exist, else ``overall``."""
    ok = np.isfinite(values)
    out = {}
    for lt in wanted:
        here = ok & (types == lt)
        out[lt] = float(np.median(values[here])) if here.sum() >= _MIN_TYPE_LOOPS else overall
    return out


def _refine_own_share(realism, rng, n_loops=120, n_steps=2):
    """Fit the share of PV's own variation per loop type from pilot simulations.

    The first pilot (``n_loops`` loops of the calibrated world, own variation set to zero,
    which the profiles' spread widens to at most 0.1) gives the
    PV-OP correlation each loop type has in simulation; the type's share lowers the median of
    that reference to the measured median (medians, so that loops whose correlation is low
    for other reasons move nothing; per loop type where both sides hold at least
    ``_MIN_TYPE_LOOPS`` loops of it, else over all loops). Detrending and the noise take part
    of the component away, so ``n_steps`` further pilots correct the share,
    ``1 - s <- (1 - s) (measured / simulated)**2``, until the medians agree.
    """
    prof = realism.profiles
    corr = prof["pv_op_corr"].to_numpy(dtype=float)
    if np.isfinite(corr).sum() < 5:
        return
    types = prof["loop_type"].to_numpy()
    wanted = sorted(set(types))
    measured = _type_medians(corr, types, wanted, float(np.nanmedian(corr)))
    share = dict.fromkeys(wanted, 0.0)
    for step in range(n_steps + 1):
        prof["pv_own_share"] = [share[lt] for lt in types]
        stats, meta = _pilot(realism, rng, n_loops=n_loops)
        sim = stats["pv_op_corr"].to_numpy(dtype=float)
        if np.isfinite(sim).sum() < 10:
            break
        simulated = _type_medians(sim, meta["loop_type"].to_numpy(), wanted,
                                  float(np.nanmedian(sim)))  # fmt: skip
        for lt in wanted:
            keep = 1.0 - share[lt] if step else 1.0
            share[lt] = _own_share(np.sqrt(keep) * measured[lt], simulated[lt])
    prof["pv_own_share"] = [share[lt] for lt in types]


def _refine_snr(realism, rng, n_loops=80, n_samples=600, n_steps=2):
    """Shift every loop's SNR so that the simulated median noise level matches the measured.

    The first guess maps each loop's noise level (noise sd over the error's 5-95 % range) to
    an SNR as if the error were Gaussian; in the simulated world loads, setpoint moves, the
    noise path, PV's own variation and recording change that ratio. Each step simulates
    ``n_loops`` loops of the calibrated world and moves every loop's SNR (and the
    ``snr_db_range`` override) by the dB between the simulated and measured median levels.
    """
    measured = realism.statistics["noise_level"].to_numpy(dtype=float)
    measured = measured[np.isfinite(measured) & (measured > 0)]
    if len(measured) < 5 or "snr_db_range" not in realism.overrides:
        return
    for _ in range(n_steps):
        stats, _ = _pilot(realism, rng, n_loops=n_loops, n_samples=n_samples)
        level = stats["noise_level"].to_numpy(dtype=float)
        level = level[np.isfinite(level) & (level > 0)]
        if len(level) < 5:
            return
        shift = float(np.clip(20 * np.log10(np.median(level) / np.median(measured)), -20, 20))
        realism.snr_shift += shift
        lo, hi = realism.overrides["snr_db_range"]
        lo, hi = float(np.clip(lo + shift, -20, 60)), float(np.clip(hi + shift, -20, 60))
        realism.overrides["snr_db_range"] = (lo, max(hi, lo + 1.0))


def apply_effects(X, effects, *, ts=1.0, random_state=None):
    """Apply the same recording effects to every loop of ``X`` (a copy).

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP.
    effects : sequence of Effect
        Recording effects (``kind == "recording"``), applied in order.
    ts : float, default=1.0
        Sample time handed to the effects.
    random_state : None, int or numpy.random.Generator, default=None

    Returns
    -------
    X_recorded : ndarray of shape (n_loops, n_samples, 3)

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.realism import apply_effects
    >>> from sktiction.simulation import SpanQuantization
    >>> X = np.linspace(0, 1, 30).reshape(1, 30, 1)
    >>> len(np.unique(apply_effects(X, [SpanQuantization(0.25)])[0, :, 0]))
    5
    """
    effects = list(effects)
    bad = [e for e in effects if getattr(e, "kind", None) != "recording"]
    if bad:
        raise ValueError(f"effects must be recording effects; got {bad!r}.")
    return _apply(X, lambda rng, j: effects, ts, random_state)


def apply_recording(X, realism, *, ts=1.0, loop_types=None, random_state=None):
    """Apply a calibrated world's recording effects to simulated loops (a copy).

    Each loop gets ``realism.recording_effects(rng, loop_type)``: the recording of one
    measured loop drawn at random. The same effects ``make_loops(..., realism=realism)``
    draws, for loops simulated without them.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
    realism : Realism
    ts : float, default=1.0
    loop_types : array-like of str or None, default=None
        Loop type of each simulated loop (draw profiles of that type).
    random_state : None, int or numpy.random.Generator, default=None

    Returns
    -------
    X_recorded : ndarray of shape (n_loops, n_samples, 3)

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.realism import apply_effects, apply_recording, calibrate
    >>> from sktiction.simulation import HoldLastValue
    >>> X, _ = make_loops(6, 300, world="classic", random_state=0)
    >>> realism = calibrate(apply_effects(X, [HoldLastValue(0.4)], random_state=0), refine=False)
    >>> Xr = apply_recording(X, realism, random_state=0)
    >>> bool((Xr[:, 1:, 0] == Xr[:, :-1, 0]).mean() > 0.2)
    True
    """
    loops = check_loops(X)
    if loop_types is not None and len(loop_types) != len(loops):
        raise ValueError(
            f"loop_types must have one entry per loop ({len(loops)}); got {len(loop_types)}."
        )

    def draw(rng, j):
        lt = None if loop_types is None else loop_types[j]
        return realism.recording_effects(rng, loop_type=lt)

    return _apply(loops, draw, ts, random_state)


def _apply(X, draw, ts, random_state):
    loops = check_loops(X).copy()
    rng = check_random_state_seed(random_state)
    for j in range(len(loops)):
        effects = draw(rng, j)
        if not effects:
            continue
        sig = {c: loops[j, :, i].copy() for i, c in enumerate(CHANNELS)}
        for eff in effects:
            sig = eff.record(sig, ts, rng)
        for i, c in enumerate(CHANNELS):
            loops[j, :, i] = sig[c]
    return loops
