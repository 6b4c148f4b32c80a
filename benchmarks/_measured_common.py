"""Locate and load the measured loops (plant historian windows, ISDB) for benchmark scripts.

The data live outside the package in ``../shared/data`` (next to the repository) or wherever
the environment variable ``SKTICTION_DATA`` points. When neither exists, :func:`load_measured`
returns ``None`` so that a benchmark can skip cleanly.

Run ``python benchmarks/_measured_common.py`` to print the per-loop table of
``docs/measured_data.md``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd

from sktiction.datasets._measured import read_loops

DATASETS = ("plant", "isdb")


def data_dir():
    """Folder holding ``plant/`` and ``isdb/``, or ``None`` when it is absent.

    ``SKTICTION_DATA`` wins over the default ``<repo>/../shared/data``.
    """
    env = os.environ.get("SKTICTION_DATA")
    path = Path(env) if env else Path(__file__).resolve().parents[2] / "shared" / "data"
    return path if path.is_dir() else None


def load_measured(datasets=DATASETS):
    """Load measured loops with labels, ready for grouped cross-validation.

    Parameters
    ----------
    datasets : iterable of {"plant", "isdb"}, default=("plant", "isdb")
        Sub-folders to read; each must have an ``index.csv`` with ``file`` and ``label``.

    Returns
    -------
    result : tuple (X, y, groups, meta) or None
        ``X`` float (n_loops, max_len, 3) with channels PV, OP, SP; ``y`` int, 1 for a
        ``stiction`` label; ``groups`` the valve tag (split by it, never by file: windows
        of one valve are not independent); ``meta`` the reader's table plus ``dataset``
        and ``label`` (and the index's other columns, suffixed ``_index`` on clashes).
        ``None`` when the data folder is absent.
    """
    root = data_dir()
    if root is None:
        return None
    parts, metas = [], []
    for name in datasets:
        index = pd.read_csv(root / name / "index.csv")
        data = read_loops([root / name / f for f in index["file"]])
        meta = data.meta.merge(index, on="file", how="left", suffixes=("", "_index"))
        meta.insert(0, "dataset", name)
        parts.append(data.X)
        metas.append(meta)
    width = max(x.shape[1] for x in parts)
    X = np.concatenate([_pad_to(x, width) for x in parts])
    meta = pd.concat(metas, ignore_index=True)
    y = (meta["label"] == "stiction").to_numpy(dtype=int)
    groups = meta["tag"].to_numpy()
    return X, y, groups, meta


# ---- the per-loop description used in docs/measured_data.md -------------------------------


def _acf(x, max_lag):
    x = x - x.mean()
    f = np.fft.rfft(x, 2 * len(x))
    r = np.fft.irfft(f * np.conj(f))[: max_lag + 1]
    return r / r[0] if r[0] > 0 else np.zeros(max_lag + 1)


def _period(x):
    """Dominant period (samples) and regularity of a detrended signal.

    Period: lag of the highest autocorrelation in the first positive lobe after the ACF
    first crosses zero (later lobes would give multiples of the period). Regularity:
    Thornhill's r = mean / (3 std) of the intervals between alternate zero crossings of
    the mean-removed signal (r > 1: a regular oscillation).
    """
    n = len(x)
    t = np.arange(n)
    x = x - np.polyval(np.polyfit(t, x, 1), t)  # remove drift before looking for cycles
    r = _acf(x, n // 2)
    neg = np.flatnonzero(r < 0)
    period, peak = np.nan, np.nan
    if len(neg):
        pos = neg[0] + np.flatnonzero(r[neg[0] :] > 0)
        if len(pos):
            after = pos[0] + np.flatnonzero(r[pos[0] :] < 0)
            end = after[0] if len(after) else len(r)
            lag = pos[0] + int(np.argmax(r[pos[0] : end]))
            period, peak = float(lag), float(r[lag])
    zc = np.flatnonzero(np.diff(np.sign(x)) != 0)
    reg = np.nan
    if len(zc) >= 5:
        full = zc[2:] - zc[:-2]
        reg = float(full.mean() / (3 * full.std())) if full.std() > 0 else np.inf
    return period, peak, reg


def _noise_sd(x):
    """Noise sd from second differences (white noise: var = 6 sd**2), robust to outliers.

    Smooth oscillations hardly contribute: a sine of P samples per cycle is scaled by
    (2 pi / P)**2 in its second difference.
    """
    d2 = np.diff(x, 2)
    return 1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6)


def _pad_to(x, width):
    """NaN-pad loops ``(n, len, 3)`` at the end to ``width`` samples."""
    return np.pad(x, ((0, 0), (0, width - x.shape[1]), (0, 0)), constant_values=np.nan)


def _slips(pv, op, sp):
    """Count slips: sudden PV moves after OP has ramped, with SP still.

    A slip at ``k``: the 3-sample PV change ``pv[k+2] - pv[k-1]`` exceeds 30 % of the
    5-95 % PV swing and 5 times the median absolute 3-sample change, OP moved more than
    6 noise sd over the 10 samples before (a ramp, not a hold), OP was not frozen at
    ``k`` (the end of a historian hold also jumps) and SP did not change in
    ``[k-10, k+2]``. Events closer than 10 samples count once. A rough indicator, not a detector.
    """
    n = len(pv)
    if n < 20:
        return 0
    d3 = pv[3:] - pv[:-3]  # d3[j] = pv[j+3] - pv[j], k = j + 1
    lo, hi = np.percentile(pv, [5, 95])
    # Large against the swing and against the loop's typical 3-sample change (so that
    # fast, smooth oscillations and noise do not count).
    threshold = max(0.3 * (hi - lo), 5 * np.median(np.abs(d3)))
    op_sd = _noise_sd(op)
    if threshold == 0:
        return 0
    count, last = 0, -100
    for j in np.flatnonzero(np.abs(d3) > threshold):
        k = j + 1
        if k < 10 or k - last < 10 or op[k] == op[k - 1]:
            continue
        if abs(op[k] - op[k - 10]) <= 6 * op_sd:
            continue
        if not np.isnan(sp).all() and np.ptp(sp[k - 10 : k + 3]) > 0:
            continue
        count += 1
        last = k
    return count


def describe_loop(pv, op, sp, ts):
    """One row of measurements for one loop (NaN-free samples only).

    Oscillation period, regularity and drift are measured on the control error
    ``PV - SP`` when SP exists, so that setpoint moves do not pass for cycles.
    """
    row = {}
    has_sp = not np.isnan(sp).all()
    err = pv - sp if has_sp else pv
    for name, x in (("pv", pv), ("op", op)):
        if np.isnan(x).all():
            continue
        d = np.diff(x)
        nz = np.abs(d[d != 0])
        row[f"{name}_distinct"] = len(np.unique(x))
        row[f"{name}_repeat"] = float(np.mean(d == 0))
        row[f"{name}_step_pct"] = 100 * nz.min() / np.ptp(x) if len(nz) else np.nan
    row["both_repeat"] = float(np.mean((np.diff(pv) == 0) & (np.diff(op) == 0)))
    for name, x in (("pv", err), ("op", op)):
        lo, hi = np.percentile(x, [5, 95])
        row[f"{name}_p2p"] = hi - lo
        row[f"{name}_noise_pct"] = 100 * _noise_sd(x) / (hi - lo) if hi > lo else np.nan
        period, peak, reg = _period(x)
        row[f"{name}_period"] = period
        row[f"{name}_acf_peak"] = peak
        row[f"{name}_regularity"] = reg
        t = np.arange(len(x))
        slope = np.polyfit(t, x, 1)[0]
        row[f"{name}_drift_pct"] = 100 * slope * len(x) / (hi - lo) if hi > lo else np.nan
    mean_pv = abs(np.mean(pv))
    row["pv_p2p_pct_mean"] = 100 * row["pv_p2p"] / mean_pv if mean_pv > row["pv_p2p"] else np.nan
    # Saturation only means something when OP is in % (normalised ISDB loops are not).
    in_pct = np.min(op) >= -1 and np.max(op) <= 101 and np.mean(op) > 2
    row["op_sat"] = float(np.mean((op <= 0.5) | (op >= 99.5))) if in_pct else np.nan
    row["n_cycles"] = len(pv) / row["pv_period"] if row["pv_period"] > 0 else np.nan
    row["cycle_s"] = row["pv_period"] * ts
    if not has_sp:
        row["sp_kind"], row["sp_moves"], row["sp_move_pct"] = "none", np.nan, np.nan
        row["offset_pct"] = np.nan
    else:
        dsp = np.abs(np.diff(sp))
        moves = dsp[dsp > 1e-6 * max(1.0, np.abs(sp).max())]
        row["sp_moves"] = len(moves)
        row["sp_move_pct"] = 100 * moves.max() / np.ptp(pv) if len(moves) else 0.0
        # Many small changes: a remote (cascade) setpoint, not operator steps.
        kinds = ((0, "constant"), (20, "steps"))
        row["sp_kind"] = next((k for lim, k in kinds if len(moves) <= lim), "moving")
        row["offset_pct"] = 100 * abs(np.median(pv - sp)) / np.ptp(pv)
    row["slips"] = _slips(pv, op, sp)
    return row


def describe_loops(X, meta, *, print_table=True):
    """Per-loop table of recording and oscillation properties.

    Parameters
    ----------
    X : ndarray of shape (n_loops, n_samples, 3)
        Loops from :func:`load_measured` (PV, OP, SP; NaN-padded).
    meta : pandas.DataFrame
        Its ``meta`` (needs ``ts``; ``tag``, ``label``, ``loop_type_index`` or
        ``loop_type`` are copied when present).
    print_table : bool, default=True
        Print the main columns.

    Returns
    -------
    table : pandas.DataFrame
        One row per loop. ``*_repeat``: share of consecutive samples with no change;
        ``*_step_pct``: smallest non-zero step in % of the signal's range;
        ``*_noise_pct``: noise sd (around a 5-point moving median) in % of the 5-95 %
        peak-to-peak; ``*_period``: ACF period in samples; ``*_regularity``: Thornhill r;
        ``*_drift_pct``: linear trend over the window in % of peak-to-peak;
        ``sp_moves``: number of SP changes, ``sp_move_pct`` the largest in % of PV range;
        ``sp_kind``: none / constant / steps (<= 20 changes) / moving (remote SP);
        ``offset_pct``: median |PV - SP| in % of PV range; ``op_sat``: share of OP at
        <= 0.5 or >= 99.5 % (NaN when OP is not in %); ``slips``: see ``_slips``.
    """
    rows = []
    for i in range(len(X)):
        valid = ~np.isnan(X[i, :, 0])
        n = int(np.flatnonzero(valid)[-1] + 1) if valid.any() else 0
        x = X[i, :n]
        row = {"i": i}
        for col in ("dataset", "tag", "loop", "label", "loop_type_index", "loop_type"):
            if col in meta:
                row[col] = meta[col].iloc[i]
        row.update({"n": n, "ts": meta["ts"].iloc[i], "n_nan": int(np.isnan(x[:, :2]).sum())})
        row.update(describe_loop(x[:, 0], x[:, 1], x[:, 2], meta["ts"].iloc[i]))
        rows.append(row)
    table = pd.DataFrame(rows)
    if print_table:
        cols = [
            "tag", "label", "pv_repeat", "both_repeat", "pv_distinct", "pv_step_pct",
            "op_step_pct", "pv_noise_pct", "op_noise_pct", "pv_period", "op_period",
            "n_cycles", "pv_acf_peak", "pv_regularity", "op_p2p", "pv_p2p_pct_mean", "op_sat",
            "sp_kind", "sp_moves", "sp_move_pct", "offset_pct", "slips", "pv_drift_pct",
            "op_drift_pct",
        ]  # fmt: skip
        cols = [c for c in cols if c in table]
        with pd.option_context("display.width", 250, "display.max_rows", 500):
            print(table[cols].round(3).to_string())
    return table


if __name__ == "__main__":
    loaded = load_measured()
    if loaded is None:
        print("measured data not found: set SKTICTION_DATA or place it in ../shared/data")
    else:
        X, y, groups, meta = loaded
        table = describe_loops(X, meta)
