"""The catalog of realism effects: effect, statistic that detects it, simulator side, fit.

Each entry is written in one place so that adding an effect is adding one entry: the column
of :func:`~sktiction.realism.loop_statistics` that detects it, what else could move that
column (the skeptic's list), the simulator effect that produces it and how
:func:`~sktiction.realism.calibrate` fits it. Two kinds:

* ``"recording"``: a historian or sensor effect of :mod:`sktiction.simulation.historian`.
  ``present`` says on which measured loops it shows, ``params`` reads its parameters from
  each loop's statistics and ``make`` builds the effect from them.
* ``"world"``: a property of the simulated loops themselves (noise, setpoint regime, dynamics).
  ``fit`` turns the measured statistics into keyword arguments of
  :func:`sktiction.datasets.make_loops` (``None`` when the catalog has none to offer).

The thresholds of ``present`` come from what the statistics mean, not from any data set:
a hold or a compression must freeze at least 2 % of the samples (lines drawn between
stored points: PV and OP together hold a quarter of the rows on them, which only
an export gives), quantisation must make 5 %
of the changes revisit a level (continuous values never do), an averaging dip must reach -0.3 of
the -0.5 a trailing mean gives and stand between two positive lobes as a trailing mean's does
(in PV and OP at the same lag, or in PV alone when no rows are held, since held rows leave
few fresh differences and chance minima),
a recorded drift must exceed 1.5 times the range of the detrended error (integral action
removes slow loads from the error).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..simulation import historian

__all__ = ["RealismEffect", "EFFECTS", "effect_names"]

_HOLD_MIN = 0.02
_FREEZE_MIN = 0.02
_LINES_MIN = 0.25
_REUSE_MIN = 0.05
_AVERAGING_DIP = -0.3
_AVERAGING_CONTRAST = -0.5
_DRIFT_MIN = 1.5
_OSCILLATING_ACF = 0.3
_CASCADE_SHARE = 0.2


@dataclass(frozen=True)
class RealismEffect:
    """One entry of :data:`EFFECTS`.

    Parameters
    ----------
    name : str
        Effect name, e.g. ``"hold_last_value"``.
    statistic : str
        Column of :func:`~sktiction.realism.loop_statistics` that detects it.
    kind : {"recording", "world"}
        Historian/sensor effect drawn per loop, or a property of the simulated world.
    simulator : str
        What produces it in the simulator (an effect class or ``make_loops`` arguments).
    confounders : str
        What else could move the statistic, and why it stays put (the skeptic's note).
    present : callable or None
        ``present(stats) -> bool array``: loops that show the effect (recording kind).
    params : callable or None
        ``params(stats) -> DataFrame``: the effect's parameters read from each loop.
    make : callable or None
        ``make(**params) -> Effect``.
    fit : callable or None
        ``fit(stats) -> dict`` of ``make_loops`` keyword arguments (world kind).

    Examples
    --------
    >>> from sktiction.realism import EFFECTS
    >>> entry = EFFECTS["hold_last_value"]
    >>> entry.statistic, entry.kind
    ('hold_fraction', 'recording')
    >>> entry.make(fraction=0.3, mean_run=4.0)
    HoldLastValue(fraction=0.3, mean_run=4.0, channels=('pv', 'op', 'sp'))
    """

    name: str
    statistic: str
    kind: str
    simulator: str
    confounders: str
    present: object = field(default=None, repr=False)
    params: object = field(default=None, repr=False)
    make: object = field(default=None, repr=False)
    fit: object = field(default=None, repr=False)


def _col(stats, name):
    return stats[name].to_numpy(dtype=float)


def _frame(**cols):
    return pd.DataFrame(cols)


def _per_noise(stats, share_of_span):
    """A size given as a share of the PV span, in units of the PV noise sd (NaN without noise)."""
    noise = _col(stats, "pv_noise")
    span = _col(stats, "pv_span")
    with np.errstate(divide="ignore", invalid="ignore"):
        out = share_of_span * span / noise
    return np.where(np.isfinite(out) & (noise > 0), out, np.nan)


def _band(stats):
    both = np.stack([_col(stats, "pv_band"), _col(stats, "op_band")])
    ok = np.isfinite(both)
    count = ok.sum(axis=0)
    return np.where(count > 0, np.where(ok, both, 0.0).sum(axis=0) / np.maximum(count, 1), np.nan)


def _hold_fraction(stats):
    """``HoldLastValue``'s ``fraction`` that holds the measured share of rows.

    Runs of one sample are left out of ``hold_fraction``: a share ``1 / L**2`` of the held
    rows at geometric runs of mean ``L``, put back here. ``HoldLastValue(fraction, L)`` holds
    a share ``L / (L / fraction + 1)`` of the rows (each run follows a stored row), so a held
    share ``H`` asks for ``fraction = H L / (L - H)``; shares above the ``L / (L + 1)`` it can
    reach ask for 1.
    """
    run = np.nan_to_num(_col(stats, "hold_run_length"), nan=2.0)
    held = _col(stats, "hold_fraction") / (1.0 - 1.0 / np.maximum(run, 1.5) ** 2)
    run = np.maximum(run, 1.0)
    held = np.minimum(held, run / (run + 1.0))
    return held * run / (run - held)


def snr_per_loop(stats):
    """First guess of each loop's SNR (dB) from its noise level (NaN without one).

    ``noise_level`` is the noise sd over the error's 5-95 % range; a Gaussian-like error
    spans about 3.3 sd, the rest of its variance is signal.
    """
    level = _col(stats, "noise_level")
    ok = np.isfinite(level) & (level > 0)
    level = np.where(ok, level, 1.0)
    err_sd = 1.0 / 3.3
    signal = np.sqrt(np.maximum(err_sd**2 - level**2, (0.1 * level) ** 2))
    return np.where(ok, np.clip(20 * np.log10(signal / level), -10.0, 60.0), np.nan)


def _fit_snr(stats):
    snr = snr_per_loop(stats)
    snr = snr[np.isfinite(snr)]
    if len(snr) == 0:
        return {}
    lo, hi = np.percentile(snr, [10, 90])
    return {"snr_db_range": (float(lo), float(max(hi, lo + 1.0)))}


def setpoint_regime_per_loop(stats):
    """Each loop's setpoint regime (``make_loops`` names), None without a recorded SP."""
    has_sp = stats["has_sp"].to_numpy(dtype=bool)
    share = _col(stats, "sp_change_fraction")
    steps = _col(stats, "sp_steps")
    out = np.full(len(stats), None, dtype=object)
    out[has_sp & (share == 0)] = "constant"
    out[has_sp & (steps == 1)] = "step"
    out[has_sp & (steps >= 2)] = "steps"
    out[has_sp & (share > _CASCADE_SHARE)] = "cascade"
    return out


def oscillating_per_loop(stats):
    """Loops that oscillate: an ACF peak of the error above 0.3 (NaN peak: not oscillating)."""
    return np.nan_to_num(_col(stats, "acf_peak")) > _OSCILLATING_ACF


def _fit_oscillating(stats):
    acf = _col(stats, "acf_peak")
    if np.isfinite(acf).sum() == 0:
        return {}
    return {"oscillating_fraction": float(oscillating_per_loop(stats)[np.isfinite(acf)].mean())}


def _fit_period(stats):
    acf = _col(stats, "acf_peak")
    period = _col(stats, "period")
    ok = (acf > _OSCILLATING_ACF) & np.isfinite(period) & (period > 2)
    if ok.sum() < 3:
        return {}
    lo, hi = np.percentile(period[ok], [10, 90])
    return {"period_range": (float(max(lo, 2.5)), float(max(hi, lo + 1.0)))}


def _fit_setpoint(stats):
    """Regime weights: the share of loops with SP in each regime, plus half a loop each (a
    regime not seen in a few loops is rare, not impossible)."""
    if "has_sp" not in stats or not stats["has_sp"].any():
        return {}
    regimes = setpoint_regime_per_loop(stats)
    regimes = regimes[[r is not None for r in regimes]]
    names = ("constant", "steps", "step", "cascade")
    counts = {r: float(np.sum(regimes == r)) + 0.5 for r in names}
    total = sum(counts.values())
    return {"setpoint_weights": {r: c / total for r, c in counts.items()}}


def _fit_colour(stats):
    colour = _col(stats, "noise_colour")
    colour = colour[np.isfinite(colour)]
    if len(colour) == 0:
        return {}
    if np.median(colour) < 0.2:
        return {"noise_colours": ("white",)}
    return {}


def _fit_length(stats):
    # records cut short: shorter than 90 % of the typical (median) record
    n = _col(stats, "n_samples")
    n = n[n > 0]
    if len(n) == 0:
        return {}
    short = n < 0.9 * np.median(n)
    out = {"short_fraction": float(short.mean())}
    if short.any():
        out["min_length"] = int(max(20, n[short].min()))
    return out


_ENTRIES = [
    # ---- recording effects, in the order the historian applies them ----------------------
    RealismEffect(
        "drift",
        "pv_drift",
        "recording",
        "SensorDrift(size): a linear ramp of size x span added to the recorded PV",
        "slow loads move OP, not the error (integral action); setpoint ramps are removed "
        "since the error is PV - SP; a loop too sluggish to follow a load also trends.",
        present=lambda s: _col(s, "pv_drift") > _DRIFT_MIN,
        params=lambda s: _frame(size=_col(s, "pv_drift")),
        make=lambda size: historian.SensorDrift(float(max(size, 1e-3))),
    ),
    RealismEffect(
        "interval_averaging",
        "diff_acf_min",
        "recording",
        "IntervalAveraging(window): trailing mean over window samples (PV and OP, or PV "
        "alone)",
        "white and AR(1) noise leave the third-difference ACF above -0.1 beyond lag 1; a PV "
        "filter (first order) does not dip; a moving average does, at its window.",
        present=lambda s: (_col(s, "diff_acf_min") < _AVERAGING_DIP)
        & (
            (_col(s, "averaging_contrast") < _AVERAGING_CONTRAST)
            | (
                (_col(s, "pv_averaging_contrast") < _AVERAGING_CONTRAST)
                & (np.nan_to_num(_col(s, "hold_fraction")) < _HOLD_MIN)
            )
        ),
        params=lambda s: _frame(
            window=_col(s, "averaging_lag"),
            pv_only=(~(_col(s, "averaging_contrast") < _AVERAGING_CONTRAST)).astype(float),
        ),
        make=lambda window, pv_only=0.0: historian.IntervalAveraging(
            int(max(2, round(window))), channels=("pv",) if pv_only else ("pv", "op")
        ),
    ),
    RealismEffect(
        "quantisation",
        "pv_level_reuse",
        "recording",
        "SpanQuantization(step): PV on a grid of step x span (calibrate: step in noise sd, "
        "so that values revisit levels as often on loops of other noise levels)",
        "holds and compression repeat values but land on new levels when they move; only "
        "a grid makes a signal revisit its levels.",
        present=lambda s: _col(s, "pv_level_reuse") > _REUSE_MIN,
        params=lambda s: _frame(
            step=_col(s, "pv_step"), step_noise=_per_noise(s, _col(s, "pv_step"))
        ),
        make=lambda step, step_noise=np.nan: (
            historian.SpanQuantization(float(min(max(step_noise, 1e-3), 100.0)), unit="noise")
            if np.isfinite(step_noise)
            else historian.SpanQuantization(float(min(max(step, 1e-4), 1.0)))
        ),
    ),
    RealismEffect(
        "deadband_compression",
        "independent_freeze",
        "recording",
        "DeadbandCompression(band): PV and OP each stored when they moved more than band x "
        "span (calibrate: band in noise sd)",
        "held rows freeze PV and OP on the same samples (not counted); quantised tags jump "
        "by whole grid steps (not counted); a stuck valve freezes the valve, not OP or PV.",
        present=lambda s: _col(s, "independent_freeze") > _FREEZE_MIN,
        params=lambda s: _frame(
            band=_band(s), band_noise=_per_noise(s, _col(s, "pv_band"))
        ),
        make=lambda band, band_noise=np.nan: (
            historian.DeadbandCompression(float(min(max(band_noise, 1e-3), 100.0)), unit="noise")
            if np.isfinite(band_noise)
            else historian.DeadbandCompression(float(min(max(band, 1e-4), 1.0)))
        ),
    ),
    RealismEffect(
        "swinging_door",
        "line_share",
        "recording",
        "SwingingDoorCompression(deviation): lines drawn between the points a swinging door "
        "stored (an interpolated export), deviation x span",
        "held rows, deadband compression and quantisation repeat values, they do not draw "
        "lines; interval averaging of held or quantised values draws short ramps; a clean "
        "noise-free signal's lines only turn at its corners (not counted).",
        present=lambda s: _col(s, "line_share") > _LINES_MIN,
        params=lambda s: _frame(deviation=_col(s, "line_deviation")),
        make=lambda deviation: historian.SwingingDoorCompression(
            float(min(max(deviation, 1e-4), 1.0))
        ),
    ),
    RealismEffect(
        "hold_last_value",
        "hold_fraction",
        "recording",
        "HoldLastValue(fraction, mean_run): whole rows frozen, then all tags jump",
        "per-tag compression freezes PV and OP on different samples (single coincident "
        "repeats are not counted); quantisation freezes PV alone.",
        present=lambda s: _col(s, "hold_fraction") > _HOLD_MIN,
        params=lambda s: _frame(
            fraction=_hold_fraction(s),
            mean_run=np.nan_to_num(_col(s, "hold_run_length"), nan=2.0),
        ),
        make=lambda fraction, mean_run: historian.HoldLastValue(
            float(min(max(fraction, 1e-3), 0.95)), float(max(mean_run, 1.0))
        ),
    ),
    RealismEffect(
        "spikes",
        "spike_rate",
        "recording",
        "Spikes(rate, amplitude): isolated wild samples of amplitude x span",
        "steps (holds, setpoint moves, slips) survive a 3-point median, so do not count; "
        "heavy-tailed noise beyond 8 sd does.",
        present=lambda s: _col(s, "spike_rate") > 0,
        params=lambda s: _frame(
            rate=_col(s, "spike_rate"), amplitude=np.nan_to_num(_col(s, "spike_size"), nan=0.5)
        ),
        make=lambda rate, amplitude: historian.Spikes(
            float(min(max(rate, 1e-5), 0.5)), float(max(amplitude, 0.05))
        ),
    ),
    # ---- properties of the simulated world -----------------------------------------------
    RealismEffect(
        "noise_level",
        "noise_level",
        "world",
        "measurement noise SNR (make_loops snr_db_range)",
        "fast oscillations (a few samples per cycle) add to second differences; holds and "
        "compression are left out of the estimate; averaging lowers it.",
        fit=_fit_snr,
    ),
    RealismEffect(
        "noise_colour",
        "noise_colour",
        "world",
        "white, AR(1) or band-limited noise (make_loops noise_colours)",
        "a smooth signal that dominates first differences pushes it to 1; averaging raises it.",
        fit=_fit_colour,
    ),
    RealismEffect(
        "setpoint_steps",
        "sp_steps",
        "world",
        "operator setpoint steps (make_loops setpoint_weights of 'step', 'steps')",
        "cascade setpoints are counted apart (more than 20 % of samples moving); absent SP "
        "gives NaN, not 0.",
        fit=_fit_setpoint,
    ),
    RealismEffect(
        "cascade_setpoint",
        "sp_change_fraction",
        "world",
        "remote setpoint moving on most samples (make_loops setpoint_weights of 'cascade')",
        "a noisy recorded SP would also move on most samples.",
        fit=_fit_setpoint,
    ),
    RealismEffect(
        "oscillation_regularity",
        "acf_peak",
        "world",
        "share of loops that oscillate at all (make_loops oscillating_fraction: quiet loops "
        "of every cause are noise- and load-driven); noise-driven, lightly damped loops "
        "(gain margin, noise colour)",
        "setpoint steps and drift are removed (error, detrended); short records give noisy "
        "ACFs; heavy noise or PV's own variation lowers the peak of a loop that does cycle.",
        fit=_fit_oscillating,
    ),
    RealismEffect(
        "pv_op_phase",
        "pv_op_corr",
        "world",
        "PV following OP in phase (averaging level control, slow loops); PV's own variation "
        "that OP does not explain lowers it (make_loops pv_own_share, PVVariation)",
        "a common slow trend correlates PV and OP (both detrended first); heavy white noise "
        "also lowers it (told apart by noise_level).",
    ),
    RealismEffect(
        "sampling",
        "decorrelation_lag",
        "world",
        "sample time against the loop's dynamics (make_loops period_range)",
        "heavy noise shortens it (noise decorrelates at once); averaging lengthens it.",
        fit=_fit_period,
    ),
    RealismEffect(
        "record_length",
        "n_samples",
        "world",
        "record length (make_loops n_samples, short_fraction, min_length)",
        "none: it is the length before the NaN padding.",
        fit=_fit_length,
    ),
    RealismEffect(
        "load_drift",
        "op_drift",
        "world",
        "slow loads the loop rejects: OP ramps over the record (make_loops drift draws)",
        "a setpoint ramp also moves OP; sensor drift moves OP only through the loop.",
    ),
    RealismEffect(
        "load_steps",
        "op_load_shifts",
        "world",
        "unannounced load steps (feed or supply changes) the loop rejects: OP moves to a new "
        "level while SP stays (make_loops load_step_fraction, LoadStep in the record)",
        "setpoint moves shift OP too (shifts near an SP shift are not counted); a cycle's "
        "swing and a ramp are not shifts; a square OP cycle slower than a tenth of the record "
        "is.",
    ),
    RealismEffect(
        "operating_offset",
        "sp_offset",
        "world",
        "PV held away from SP (saturated OP, sluggish integral action, P-only level control)",
        "a recorded SP that is not the one in use (another mode) looks the same.",
    ),
]

EFFECTS = {e.name: e for e in _ENTRIES}
"""Catalog of realism effects, keyed by name. Recording effects come in the order they act:
sensor drift, interval averaging, grid, per-tag compression (deadband, swinging door),
held rows, then spikes (glitches
of the stored values, which averaging would otherwise smooth away)."""


def effect_names(kind=None):
    """Names of the catalog's effects, optionally of one kind.

    Parameters
    ----------
    kind : {"recording", "world"} or None, default=None

    Returns
    -------
    names : list of str

    Examples
    --------
    >>> from sktiction.realism import effect_names
    >>> effect_names("recording")[-2:]
    ['hold_last_value', 'spikes']
    """
    if kind not in (None, "recording", "world"):
        raise ValueError(f"kind must be None, 'recording' or 'world'; got {kind!r}.")
    return [e.name for e in _ENTRIES if kind is None or e.kind == kind]
