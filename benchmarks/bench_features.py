"""Time to compute all features of one 5,000-sample loop, and the DTW share of it.

Goal (GitHub issue 3): all features (AreaRatio + TemplateDistances, every cycle
analysed) of a 5,000-sample loop in <= 20 ms median on one core, and the whole
transform within 1.5x of tslearn's bare ``cdist_dtw`` on the same cells (one call
per cycle and signal, the cycle against its four templates, same bins and band).
Seed 001 reports about 3 minutes in MATLAB for one such loop with 10 cycles.

Loops are simulated sticky flow-like loops (FOPTD, relay valve, AMIGO PI, noise)
with 25 to 125 samples per cycle, so 40 to 200 cycles are analysed per loop.
All figures come from this one run; the machine is shared, so compare ratios.

The valve-model fit (``StictionModelFit``) is timed against the least-squares grid
it replaced (one ``lstsq`` of the ARX design per band), with the largest difference
in gain and the share of loops where the two pick the same band.

Run: NUMBA_NUM_THREADS=1 python benchmarks/bench_features.py
"""

import time

import numpy as np
from tslearn.metrics import cdist_dtw

from sktiction import AreaRatio, TemplateDistances, pretrained_classifier
from sktiction._validation import loop_lengths
from sktiction.datasets import make_loops
from sktiction.features.stiction_model import _play, fit_stiction_band
from sktiction.features.templates import SHAPES, cycle_templates, resample
from sktiction.reports import scan_loops

N_SAMPLES = 5000


def median_time(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def tslearn_cells(td, X):
    """The (cycle, template) pairs of X as tslearn would be asked for them."""
    cells = []
    for i in range(len(X)):
        found = td._cycles(X, i, X.shape[1])
        if found is None:
            continue
        for s in td.signals:
            analysis, bounds, _ = found[s]
            for a, m, b in bounds:
                cyc = resample(analysis.centred, a, b, td.n_points)
                split = (m - a) / (b - a)
                first = (np.arange(td.n_points) + 0.5) / td.n_points < split
                temps = cycle_templates(split, cyc[first].mean(), cyc[~first].mean(),
                                        td.n_points)
                cells.append((cyc[None, :, None], temps[:, :, None]))
    return cells


def _lstsq_sse(pv, x, n_lags):
    """Residual sum of squares of the least-squares ARX fit whose rows t >= n_lags are
    ``[pv[t-1], pv[t-2], x[t-1..t-n_lags], 1]`` against ``pv[t]``: the design the package
    solves from its normal equations, built whole as the replaced grid did."""
    rows = np.arange(n_lags, pv.size)
    A = np.column_stack(
        [pv[rows - 1], pv[rows - 2]] + [x[rows - k] for k in range(1, n_lags + 1)]
        + [np.ones(rows.size)]
    )
    coef, *_ = np.linalg.lstsq(A, pv[rows], rcond=None)
    r = pv[rows] - A @ coef
    return float(r @ r)


def lstsq_grid(pv, op, n_lags=8):
    """The valve-model fit as it was: one least-squares fit of the design per band."""
    n_lags = int(min(n_lags, max(2, pv.size // 20)))
    span = float(np.ptp(op))
    fracs = np.geomspace(0.002, 0.6, 24)
    base = _lstsq_sse(pv, op, n_lags)
    sses = np.array([_lstsq_sse(pv, _play(op, f * span), n_lags) for f in fracs])
    best = int(np.argmin(sses))
    if sses[best] >= base:
        return 0.0, 0.0
    return 1.0 - sses[best] / base, fracs[best] * span


def valve_model_fit(n_loops=60, n_samples=8640):
    """Speed and agreement of the normal-equation grid against the least-squares grid."""
    X, _ = make_loops(n_loops, n_samples=n_samples, slip_fraction=0.25, random_state=5)
    n = loop_lengths(X)
    pairs = [(X[i, : n[i], 0], X[i, : n[i], 1]) for i in range(n_loops)]
    fit_stiction_band(*pairs[0])  # compile
    new, old, gain_diff, same_band = [], [], [], []
    for pv, op in pairs:
        t0 = time.perf_counter()
        g_new, b_new = fit_stiction_band(pv, op)
        t1 = time.perf_counter()
        g_old, b_old = lstsq_grid(pv, op)
        t2 = time.perf_counter()
        new.append(t1 - t0)
        old.append(t2 - t1)
        gain_diff.append(abs(g_new - g_old))
        same_band.append(np.isclose(b_new, b_old))
    ratio = np.array(old) / np.array(new)
    print(f"StictionModelFit on {n_loops} loops of up to {n_samples} samples: "
          f"{1e3 * np.median(new):.1f} ms per loop median (least-squares grid "
          f"{1e3 * np.median(old):.1f} ms): {np.median(ratio):.1f}x faster "
          f"(min {ratio.min():.1f}x, max {ratio.max():.1f}x); largest gain difference "
          f"{max(gain_diff):.1e}, same band in {100 * np.mean(same_band):.0f} % of loops")


def main():
    valve_model_fit()
    X, _ = make_loops(
        12, n_samples=N_SAMPLES, stiction_fraction=1.0, orders=(1,), period_range=(25, 125),
        stiction_models=("relay",), random_state=0,
    )
    td, ar = TemplateDistances().fit(X), AreaRatio().fit(X)
    td.transform(X[:1])
    ar.transform(X[:1])  # compile
    per_loop, dtw_only, cycles = [], [], []
    radius = td.sakoe_chiba_radius
    for i in range(len(X)):
        one = X[i : i + 1]
        n_cycles = td.transform(one)[0, -3]
        if not np.isfinite(n_cycles):
            continue
        t_all = median_time(lambda one=one: (td.transform(one), ar.transform(one)), 7)
        cells = tslearn_cells(td, one)
        t_tsl = median_time(
            lambda cells=cells: [
                cdist_dtw(c, t, global_constraint="sakoe_chiba", sakoe_chiba_radius=radius)
                for c, t in cells
            ],
            3,
        )
        per_loop.append(t_all)
        dtw_only.append(t_tsl)
        cycles.append(n_cycles)
    per_loop, dtw_only, cycles = map(np.array, (per_loop, dtw_only, cycles))
    ratio = per_loop / dtw_only
    print(f"loops: {len(per_loop)} of {N_SAMPLES} samples, {cycles.min():.0f}-{cycles.max():.0f} "
          f"cycles each ({len(SHAPES)} templates x 2 signals per cycle)")
    print(f"all features per loop, median: {1e3 * np.median(per_loop):.1f} ms "
          f"(goal <= 20 ms; {1e3 * np.median(per_loop) / 20:.2f}x the goal)")
    print(f"tslearn cdist_dtw on the same cells, median: {1e3 * np.median(dtw_only):.1f} ms")
    print(f"whole transform / tslearn cdist_dtw: median {np.median(ratio):.3f}x "
          f"(goal <= 1.5x), worst {ratio.max():.3f}x")
    print(f"speed-up on seed 001's ~180 s per loop (10 cycles, MATLAB): "
          f"{180 / np.median(per_loop):,.0f}x")
    slope = np.polyfit(cycles, per_loop * 1e3, 1)
    print(f"cost ~ {slope[1]:.2f} ms + {slope[0]:.3f} ms per cycle (fit over these loops)")
    # a whole plant scan runs all three classifiers (features of the learned one included)
    clf = pretrained_classifier(n_loops=200, n_samples=1000)
    scan_loops(X[:1], classifier=clf)
    t_scan = median_time(lambda: scan_loops(X, classifier=clf), 3) / len(X)
    print(f"scan_loops, all three classifiers: {1e3 * t_scan:.1f} ms per loop, so 5,000 loops "
          f"in {5000 * t_scan / 60:.1f} min on one core")


if __name__ == "__main__":
    main()
