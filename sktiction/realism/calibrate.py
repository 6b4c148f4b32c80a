"""Fit the catalog's parameters to measured loops: a calibrated world for ``make_loops``."""

from __future__ import annotations

import inspect

import numpy as np
import pandas as pd

from .._validation import CHANNELS, check_loops, check_random_state_seed
from ._catalog import EFFECTS, effect_names
from .compare import as_statistics
from .statistics import loop_statistics

__all__ = ["Realism", "calibrate", "apply_effects", "apply_recording"]


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

    def __init__(self, profiles, overrides, statistics):
        self.profiles = profiles
        self.overrides = dict(overrides)
        self.statistics = statistics

    def _pool(self, loop_type):
        if loop_type is not None:
            sub = self.profiles[self.profiles["loop_type"] == loop_type]
            if len(sub):
                return sub
        return self.profiles

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
        row = pool.iloc[int(rng.integers(len(pool)))]
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


def calibrate(measured, *, loop_types=None, refine=True, random_state=None):
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
        if "noise_colours" in allowed:
            _refine_colours(realism, random_state)
        if "snr_db_range" in overrides:
            _refine_snr(realism, random_state)
    return realism


# Noise colour mixes tried by the pilot simulations (names of make_loops' noise_colours).
_COLOUR_MIXES = (
    ("white",),
    ("white", "ar1"),
    ("white", "ar1", "bandlimited"),
    ("white", "bandlimited"),
    ("ar1",),
    ("ar1", "bandlimited"),
    ("bandlimited",),
)


def _cliff(a, b):
    from scipy.stats import mannwhitneyu

    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if len(a) < 5 or len(b) < 5:
        return np.inf
    return abs(2.0 * mannwhitneyu(a, b).statistic / (len(a) * len(b)) - 1.0)


def _refine_colours(realism, random_state, n_loops=60, n_samples=600):
    """Pick the noise-colour mix whose simulated ``noise_colour`` is closest to the measured.

    One pilot simulation per mix of :data:`_COLOUR_MIXES`; closeness is |Cliff's delta|.
    """
    from ..datasets import make_loops

    measured = realism.statistics["noise_colour"].to_numpy(dtype=float)
    if np.isfinite(measured).sum() < 5:
        return
    rng = check_random_state_seed(random_state)
    best, best_d = None, np.inf
    for mix in _COLOUR_MIXES:
        trial = Realism(realism.profiles, {**realism.overrides, "noise_colours": mix},
                        realism.statistics)  # fmt: skip
        try:
            X, _ = make_loops(n_loops, n_samples, realism=trial, random_state=rng)
        except ValueError:  # a colour this make_loops does not know
            continue
        d = _cliff(loop_statistics(X)["noise_colour"].to_numpy(dtype=float), measured)
        if d < best_d:
            best, best_d = mix, d
    if best is not None:
        realism.overrides["noise_colours"] = best


def _refine_snr(realism, random_state, n_loops=80, n_samples=600, n_steps=2):
    """Shift the SNR range so that the simulated median noise level matches the measured one.

    The first guess maps each loop's noise level (noise sd over the error's 5-95 % range) to
    an SNR as if the error were Gaussian; in the simulated world loads, setpoint moves, the
    noise path and recording change that ratio. Each step simulates ``n_loops`` loops with the
    current settings and moves both ends of the range by the dB between the simulated and
    the measured median noise levels.
    """
    from ..datasets import make_loops

    measured = realism.statistics["noise_level"].to_numpy(dtype=float)
    measured = measured[np.isfinite(measured) & (measured > 0)]
    if len(measured) < 5:
        return
    rng = check_random_state_seed(random_state)
    for _ in range(n_steps):
        X, _ = make_loops(n_loops, n_samples, realism=realism, random_state=rng)
        level = loop_statistics(X)["noise_level"].to_numpy(dtype=float)
        level = level[np.isfinite(level) & (level > 0)]
        if len(level) < 5:
            return
        shift = 20 * np.log10(np.median(level) / np.median(measured))
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
