"""Oscillation detection on simulated signals with known truth, one class per failure mode.

Issue 9 lists how real oscillations are missed: irregular cycles (Thornhill's r 0.65-1.0:
the very_irregular class; the irregular class is milder), noise-driven (lightly damped)
oscillations, two frequencies at once, a drift hiding the first ACF lobe, intermittent
stretches, short periods (about 10 samples per cycle), long records with few slow cycles,
historian records with repeated or quantised samples, and regular cycles that an ACF
criterion rejects (the stick_slip class: a sticky valve's saw-tooth under noise and
holds; the unequal_halves class: cycles that spend 15-35 % of each period on one side
of their mean). Each class below
makes signals of that kind (truth: oscillating); each non-oscillating class is a matching
counterpart (coloured noise, random walk, steps, noise with repeated samples, drift alone,
the PV or OP of an ordinarily tuned PI loop holding its setpoint against a random-walk
load and measurement noise, and coloured noise under a few setpoint or load steps, held
at a limit, or with a skewed level) on which every detection is a false alarm. The generator is
this file's own, seeded.

Goal: recall >= 0.95 in every oscillating class, false alarms <= 5 % in every other class.
With ``--measured`` it also runs the detector on ../shared/data (skipped when absent) and
writes one figure per signal to ``--figures DIR``. With ``--compare`` it runs, on the same
signals, reference implementations of other method families (whole-signal ACF, EMD and
Morlet wavelets, each with Thornhill's regularity) instead.

With ``--speed`` it times, in CPU seconds (so that the load of a shared machine does not
count), all features of a 5,000-sample loop as ``benchmarks/bench_features.py`` defines
them (issue 3's budget: 20 ms), and ``analyze_cycles`` on its PV and OP.

Run: python benchmarks/bench_oscillation.py [--n 200] [--measured] [--figures DIR]
     python benchmarks/bench_oscillation.py --compare --n 100  (other method families)
     NUMBA_NUM_THREADS=1 python benchmarks/bench_oscillation.py --speed
     python benchmarks/bench_oscillation.py --gaussianity --n 300  (very irregular vs noise)
     python benchmarks/bench_oscillation.py --level-steps --n 300  (cycles under level shifts)
     python benchmarks/bench_oscillation.py --artefacts --n 200  (spikes, placeholders, trips)
     python benchmarks/bench_oscillation.py --drifting-period  (period changing in the record)
     python benchmarks/bench_oscillation.py --saturated --n 300  (cycles held at a limit)
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

from sktiction.cycles import analyze_cycles

# ---------------------------------------------------------------------------- generator


def _ar1(rng, n, phi, sd=1.0):
    e = rng.normal(0, sd, n)
    from scipy.signal import lfilter

    return lfilter([1.0], [1.0, -phi], e)


def _ar2(rng, n, period, zeta):
    """Noise through a second-order resonance of the given period and damping ratio."""
    from scipy.signal import lfilter

    w = 2 * np.pi / period
    rho = np.exp(-zeta * w / np.sqrt(max(1 - zeta**2, 1e-6)))
    a = [1.0, -2 * rho * np.cos(w), rho**2]
    burn = int(10 / max(1 - rho, 1e-3))
    y = lfilter([1.0], a, rng.normal(size=n + burn))[burn:]
    return y / y.std()


def _wandering(rng, n, period, wander=0.15, amp_wander=0.2, shape="sine", duty=0.5):
    """A cycle whose period and amplitude wander (log random AR(1) of one-cycle memory).
    A "pulse" spends ``duty`` of each period on its high side (height 1) and the rest on
    its low side, the mean zero."""
    mem = np.exp(-1.0 / period)  # wander correlates over about one period
    lp = _ar1(rng, n, mem, 1.0)
    lp = wander * lp / (lp.std() + 1e-12)
    la = _ar1(rng, n, mem, 1.0)
    la = amp_wander * la / (la.std() + 1e-12)
    phase = np.cumsum(2 * np.pi / (period * np.exp(lp))) + rng.uniform(0, 2 * np.pi)
    if shape == "sine":
        c = np.sin(phase)
    elif shape == "square":
        c = np.tanh(4 * np.sin(phase)) / np.tanh(4)
    elif shape == "saw":  # a ramp over the whole cycle, then a jump back
        c = (phase / np.pi) % 2 - 1
    elif shape == "pulse":
        c = np.where((phase / (2 * np.pi)) % 1.0 < duty, 1.0, -duty / (1.0 - duty))
    else:  # triangle
        c = 2 / np.pi * np.arcsin(np.sin(phase))
    return np.exp(la) * c


def _hold(rng, x, share):
    """Historian repeats: about ``share`` of the samples repeat the previous record, in
    runs of 1-3 samples (a record held over several samples), as compression and slow
    scans do. A run starts with probability q after a fresh sample; runs of mean length 2
    hold 2q / (1 + 2q) of the samples, hence q."""
    n = x.size
    held = np.zeros(n, dtype=bool)
    start = share / (2.0 * (1.0 - share))
    i = 1
    while i < n:
        if rng.random() < start:
            length = int(rng.integers(1, 4))
            held[i : i + length] = True
            i += length
        i += 1
    idx = np.maximum.accumulate(np.where(held, 0, np.arange(n)))
    return x[idx]


def _quantise(x, step):
    return np.round(x / step) * step


def _noise(rng, n, sd):
    return _ar1(rng, n, rng.uniform(0.0, 0.5), 1.0) * sd / np.sqrt(1.0) * 0.9


def _noisy(cycle, noise, info):
    """``cycle + noise``; ``info``, when given, gets ``cycle_to_noise``, the deviation of
    the cycle over that of the noise (below one, noise hides the cycle from the eye)."""
    if info is not None:
        info["cycle_to_noise"] = np.std(cycle) / np.std(noise)
    return cycle + noise


def band_snr(cycle, rest, period, width=0.2):
    """Power of ``cycle`` over that of ``rest`` (both detrended) within +-``width`` of
    the cycle's frequency: what no detector can separate, as the drift's own wiggles
    at the cycle's period look like the cycle."""
    n = cycle.size
    t = np.arange(n)
    f = np.fft.rfftfreq(n)
    band = np.abs(np.log(np.maximum(f, 1e-12) * period)) <= np.log1p(width)
    powers = []
    for y in (cycle, rest):
        y = y - np.polyval(np.polyfit(t, y, 1), t)
        powers.append(np.sum(np.abs(np.fft.rfft(y)[band]) ** 2))
    return powers[0] / max(powers[1], 1e-300)


def _coloured_noise(rng, n):
    """AR(1) noise or an AR(2) resonance of damping ratio 0.35-0.7 (half each), scaled to
    unit deviation, plus white noise of up to half that: (x, damping ratio or NaN)."""
    if rng.random() < 0.5:
        x, zeta = _ar1(rng, n, rng.uniform(0.0, 0.98)), np.nan
    else:
        period, zeta = rng.uniform(10, 150), rng.uniform(0.35, 0.7)
        x = _ar2(rng, n, period, zeta)
    return x / x.std() + _noise(rng, n, rng.uniform(0.0, 0.5)), zeta


def _record_length(rng):
    """Samples in a record: log-uniform from a plant window (~750) to a long export."""
    return int(np.exp(rng.uniform(np.log(600), np.log(3000))))


def _at_limit(x, held, bottom=False):
    """``x`` held at a limit on the share ``held`` of its samples: at its top, or at its
    bottom (a valve fully open or shut, a clamped output)."""
    if bottom:
        return np.maximum(x, np.quantile(x, held))
    return np.minimum(x, np.quantile(x, 1 - held))


def _level_moves(rng, n, first, last, smallest):
    """1-3 operator or load moves between ``first`` and ``last`` of the record, each of
    ``smallest``-30 (either sign), half through a first-order lag of 2-30 samples, as
    such a response would record them: (level, where, lag or 0)."""
    level = np.zeros(n)
    where = rng.integers(int(first * n), int(last * n), int(rng.integers(1, 4)))
    for t in where:
        level[t:] += rng.uniform(smallest, 30) * rng.choice([-1, 1])
    lag = rng.uniform(2, 30) if rng.random() < 0.5 else 0.0
    if lag:
        level = np.asarray(_lag(level, lag))
    return level, where, lag


def make_signal(kind, rng, info=None):
    """One signal of class ``kind``: (x, truth, periods); truth 1 = oscillating.

    ``info`` (a dict), when given, gets ``band_snr`` for *drifting* signals (the
    cycle's power over the drift's near the cycle's frequency, :func:`band_snr`),
    ``cycle_to_noise`` for *very_irregular*, *stick_slip* and *unequal_halves* (the
    cycle's deviation over the noise's, :func:`_noisy`) and ``zeta`` for
    *coloured_noise* (the damping ratio of its resonance; NaN for AR(1) noise). Filling
    it draws no random numbers."""
    n = _record_length(rng)  # at least 6 cycles
    top = min(150.0, n / 6)
    shape = rng.choice(["sine", "sine", "triangle", "square"])
    if kind == "regular":
        p = rng.uniform(15, top)
        x = _wandering(rng, n, p, 0.03, 0.05, shape) + _noise(rng, n, rng.uniform(0.05, 0.5))
        return x, 1, [p]
    if kind == "irregular":
        p = rng.uniform(15, top)
        x = _wandering(rng, n, p, rng.uniform(0.1, 0.25), rng.uniform(0.15, 0.35), shape)
        return x + _noise(rng, n, rng.uniform(0.1, 0.6)), 1, [p]
    if kind == "very_irregular":  # Thornhill's r 0.65-1.1 on the clean cycle, as in plants
        p = rng.uniform(15, top)
        x = _wandering(rng, n, p, rng.uniform(0.35, 0.5), rng.uniform(0.3, 0.5), shape)
        return _noisy(x, _noise(rng, n, rng.uniform(0.1, 0.6)), info), 1, [p]
    if kind == "noise_driven":
        p = rng.uniform(15, top)
        x = _ar2(rng, n, p, rng.uniform(0.02, 0.08))
        return x + _noise(rng, n, rng.uniform(0.05, 0.4)), 1, [p]
    if kind == "two_frequencies":
        p1 = rng.uniform(12, min(50.0, top / 2.5))
        p2 = p1 * rng.uniform(2.5, min(6.0, top / p1))
        a2 = rng.uniform(0.5, 2.0)
        x = _wandering(rng, n, p1, 0.05, 0.15, shape) + a2 * _wandering(rng, n, p2, 0.05, 0.15)
        return x + _noise(rng, n, rng.uniform(0.05, 0.4)), 1, [p1, p2]
    if kind == "drifting":
        p = rng.uniform(15, top)
        x = _wandering(rng, n, p, 0.08, 0.15, shape) + _noise(rng, n, rng.uniform(0.05, 0.4))
        walk = np.cumsum(rng.normal(size=n))
        drift = walk / np.ptp(walk) * rng.uniform(3, 10)
        ramp = np.linspace(0, rng.uniform(-5, 5), n)
        if info is not None:
            info["band_snr"] = band_snr(x, drift, p)
        return x + drift + ramp, 1, [p]
    if kind == "intermittent":
        p = rng.uniform(15, min(100.0, n / 17))  # >= 5 cycles in the shortest stretch
        on = np.zeros(n, dtype=bool)
        length = int(rng.uniform(0.3, 0.6) * n)
        start = int(rng.integers(0, n - length))
        on[start : start + length] = True
        ramp = np.clip(np.minimum(np.arange(n) - start, start + length - np.arange(n)) / p, 0, 1)
        x = ramp * _wandering(rng, n, p, 0.05, 0.15, shape)
        return x + _noise(rng, n, rng.uniform(0.05, 0.3)), 1, [p]
    if kind == "short_period":
        p = rng.uniform(7, 13)
        x = _wandering(rng, n, p, rng.uniform(0.03, 0.1), 0.15, shape)
        return x + _noise(rng, n, rng.uniform(0.05, 0.4)), 1, [p]
    if kind == "few_slow_cycles":
        m = int(rng.uniform(2000, 5000))
        p = m / rng.uniform(4, 8)
        x = _wandering(rng, m, p, 0.08, 0.15, shape) + _noise(rng, m, rng.uniform(0.05, 0.4))
        walk = np.cumsum(rng.normal(size=m))
        return x + 0.5 * walk / np.ptp(walk), 1, [p]
    if kind == "compressed":
        p = rng.uniform(15, top)
        x = _wandering(rng, n, p, 0.08, 0.15, shape) + _noise(rng, n, rng.uniform(0.05, 0.3))
        x = _hold(rng, x, rng.uniform(0.15, 0.3))
        if rng.random() < 0.5:
            x = _quantise(x, rng.uniform(0.05, 0.3))
        return x, 1, [p]
    if kind == "stick_slip":  # a sticky valve's controller output: slow ramps, fast slips
        p = rng.uniform(20, top)
        x = _wandering(rng, n, p, rng.uniform(0.12, 0.25), rng.uniform(0.1, 0.25), "saw")
        x = rng.choice([-1, 1]) * x
        x = _noisy(x, _noise(rng, n, rng.uniform(0.1, 0.7)), info)
        if rng.random() < 0.5:
            x = _hold(rng, x, rng.uniform(0.15, 0.4))
        return x, 1, [p]
    if kind == "unequal_halves":  # a valve that dwells longer on one side; a pump on/off
        p = rng.uniform(20, top)
        x = _wandering(rng, n, p, rng.uniform(0.12, 0.25), rng.uniform(0.1, 0.25), "pulse",
                       rng.uniform(0.15, 0.35))  # fmt: skip
        if rng.random() < 0.5:  # through a first-order lag, as a process would pass it
            x = np.asarray(_lag(x, rng.uniform(0.05, 0.2) * p))
        x = rng.choice([-1, 1]) * x
        x = _noisy(x, _noise(rng, n, rng.uniform(0.1, 0.7)), info)
        if rng.random() < 0.5:
            x = _hold(rng, x, rng.uniform(0.15, 0.4))
        return x, 1, [p]
    if kind == "level_steps":  # operator or load moves, 3-30 times the cycle's amplitude
        p = rng.uniform(15, top)
        x = _wandering(rng, n, p, 0.08, 0.15, shape) + _noise(rng, n, rng.uniform(0.05, 0.4))
        level, where, lag = _level_moves(rng, n, 0.03, 0.97, 3)
        if info is not None:
            info.update(steps=where.size, lag=lag / n, edge=min(where.min(), n - where.max()) / n)
        return x + level, 1, [p]
    # ---- non-oscillating counterparts
    if kind == "coloured_noise":
        x, zeta = _coloured_noise(rng, n)
        if info is not None:
            info["zeta"] = zeta
        return x, 0, []
    if kind == "stepped_noise":  # the coloured noise above under 1-3 setpoint or load steps
        x = _coloured_noise(rng, n)[0]
        return x + _level_moves(rng, n, 0.05, 0.95, 5)[0], 0, []
    if kind == "saturated_noise":  # held at a limit: a valve fully open or shut
        x = _at_limit(_coloured_noise(rng, n)[0], rng.uniform(0.05, 0.4))
        return rng.choice([-1, 1]) * x, 0, []
    if kind == "skewed_noise":  # a log-normal level: skewness about 1 (0.3) to 6 (1.0)
        x = np.exp(rng.uniform(0.3, 1.0) * _coloured_noise(rng, n)[0])
        return rng.choice([-1, 1]) * x, 0, []
    if kind == "random_walk":
        m = int(np.exp(rng.uniform(np.log(600), np.log(5000))))
        walk = np.cumsum(rng.normal(size=m))
        return walk / np.ptp(walk) * 5 + _noise(rng, m, rng.uniform(0.05, 0.5)), 0, []
    if kind == "steps":
        k = int(rng.integers(2, 12))
        times = np.sort(rng.integers(0, n, k))
        levels = np.cumsum(rng.normal(0, 2, k))
        x = np.zeros(n)
        for t, v in zip(times, levels):
            x[t:] = v
        if rng.random() < 0.5:  # as a first-order response would record them
            x = np.asarray(_lag(x, rng.uniform(2, 30)))
        return x + _noise(rng, n, rng.uniform(0.05, 0.5)), 0, []
    if kind == "repeated_noise":
        x = _ar1(rng, n, rng.uniform(0.0, 0.95))
        x = _hold(rng, x / x.std(), rng.uniform(0.15, 0.3))
        if rng.random() < 0.5:
            x = _quantise(x, rng.uniform(0.1, 0.5))
        return x, 0, []
    if kind == "closed_loop":
        x = _closed_loop(rng, n)
        return x / x.std(), 0, []
    if kind == "drift":
        t = np.arange(n)
        slow = rng.uniform(1, 4) * np.sin(
            2 * np.pi * t / rng.uniform(1.2 * n, 4 * n) + rng.uniform(0, 6)
        )
        x = slow + np.linspace(0, rng.uniform(-5, 5), n)
        return x + _noise(rng, n, rng.uniform(0.05, 0.5)), 0, []
    raise ValueError(f"unknown kind {kind!r}")


def _closed_loop(rng, n, warm=500):
    """PV or OP (half each) of an ordinarily tuned PI loop that holds its setpoint: a
    first-order plant with dead time (time constant 5-60 samples, 1-10 samples of delay),
    the integral time the plant's time constant and the gain set for a gain margin of 2-4
    (peak sensitivity about 1.4-2.2), a random-walk load at the plant's input and white
    measurement noise the controller sees (load to noise 0.003-1 per sample). A loop's own
    noise, unlike the AR(2) resonances above, has no power at zero frequency in PV."""
    tau, delay = rng.uniform(5, 60), int(rng.integers(1, 11))
    a = np.exp(-1.0 / tau)
    z = np.exp(-1j * np.linspace(1e-3, np.pi, 4000))  # z^-1 on the unit circle
    loop = (1 - a) * z ** (delay + 1) / (1 - a * z) * (1 - z + 1 / tau) / (1 - z)  # Kc = 1
    cross = np.flatnonzero(np.diff(np.unwrap(np.angle(loop)) <= -np.pi))[0]
    kc = 1.0 / abs(loop[cross]) / rng.uniform(2, 4)
    m = n + warm
    load = np.cumsum(rng.normal(0, np.exp(rng.uniform(np.log(0.003), 0.0)), m))
    noise = rng.normal(0, 1, m)
    y, u, e_prev = 0.0, np.zeros(m), 0.0
    pv = np.zeros(m)
    for t in range(m):
        y = a * y + (1 - a) * (u[t - delay - 1] if t > delay else 0.0) + (1 - a) * load[t]
        pv[t] = y + noise[t]
        e = -pv[t]
        u[t] = (u[t - 1] if t else 0.0) + kc * (e - e_prev + e / tau)
        e_prev = e
    return (pv if rng.random() < 0.5 else u)[warm:]


def _lag(x, tau):
    from scipy.signal import lfilter

    c = np.exp(-1.0 / tau)
    return lfilter([1 - c], [1, -c], x - x[0]) + x[0]


OSCILLATING = (
    "regular",
    "irregular",
    "noise_driven",
    "two_frequencies",
    "drifting",
    "intermittent",
    "short_period",
    "few_slow_cycles",
    "compressed",
    "very_irregular",
    "level_steps",
    "stick_slip",
    "unequal_halves",
)
QUIET = ("coloured_noise", "random_walk", "steps", "repeated_noise", "drift", "closed_loop",
         "stepped_noise", "saturated_noise", "skewed_noise")  # fmt: skip
#: Random stream of each class (a class added later gets a new one, so that the others
#: keep their signals).
STREAM = {kind: i for i, kind in enumerate(
    OSCILLATING[:-4] + QUIET[:5] + OSCILLATING[-4:-3] + QUIET[5:6] + OSCILLATING[-3:] + QUIET[6:]
)}


def read_quietly(x):
    """``analyze_cycles(x)`` without the warnings that say what it repaired: on records
    made without artefacts a repair is the spike rule taking a fast edge of 1-3 samples
    for a glitch, as a scan would (``--artefacts`` counts repairs instead)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="x: ", category=UserWarning)
        return analyze_cycles(x)


def period_found(analysis, periods, tol=0.2):
    """Whether every true period is among the detected components' periods."""
    found = np.asarray(analysis.periods, dtype=float)
    if found.size == 0:
        return False
    return all(np.min(np.abs(found - p) / p) <= tol for p in periods)


def run_simulated(n_per_class, seed=0):
    """Per class: rate of oscillating calls, over all records and over records shorter
    than 1,000 samples (a plant window), the share with every true period found, and
    Thornhill's r of the cycles :func:`analyze_cycles` finds (the issue's r); also the
    drifting records' cycle-to-drift power (:func:`band_snr`), the cycle-to-noise
    deviation of the classes that record it, the coloured-noise records' damping ratio,
    every record's index, and the CPU time per 5,000 samples."""
    rows, times = [], []
    extra = {"band_snr": [], "zeta": [], "index": {}, "cycle_to_noise": {}}
    for kind in OSCILLATING + QUIET:
        rng = np.random.default_rng([seed, STREAM[kind]])
        hits, short, periods_ok, regularity, index = [], [], 0, [], []
        for _ in range(n_per_class):
            info = {}
            x, truth, periods = make_signal(kind, rng, info)
            t0 = time.process_time()  # CPU time: the load of a shared machine does not count
            a = read_quietly(x)
            times.append((time.process_time() - t0) / x.size * 5000)
            hits.append(bool(a.oscillating))
            index.append(a.oscillation_index)
            regularity.append(a.regularity if len(a.cycles) else np.nan)
            if x.size < 1000:
                short.append(bool(a.oscillating))
            if truth:
                periods_ok += bool(a.oscillating) and period_found(a, periods)
            for key in ("band_snr", "zeta"):
                if key in info:
                    extra[key].append((info[key], bool(a.oscillating)))
            if "cycle_to_noise" in info:
                extra["cycle_to_noise"].setdefault(kind, []).append(
                    (info["cycle_to_noise"], bool(a.oscillating))
                )
        extra["index"][kind] = np.array(index)
        rows.append(
            (
                kind,
                truth,
                np.mean(hits),
                np.mean(short) if short else np.nan,
                len(short),
                periods_ok / n_per_class,
                np.array(regularity),
            )
        )
    extra["band_snr"] = np.array(extra["band_snr"]).reshape(-1, 2)
    extra["zeta"] = np.array(extra["zeta"]).reshape(-1, 2)
    return rows, float(np.median(times)), extra


def print_snr(snr, edges=(0, 2, 4, 10, np.inf)):
    """Recall of the drifting class by the cycle's power over the drift's within
    +-20 % of its frequency (:func:`band_snr`)."""
    cells = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (snr[:, 0] >= lo) & (snr[:, 0] < hi)
        if sel.any():
            cells.append(f"{lo:g}-{hi:g}: {snr[sel, 1].mean():.2f} ({sel.sum()})")
    print(
        "drifting, recall by cycle-to-drift power within 20 % of the cycle's frequency: "
        + "; ".join(cells)
    )
    seen = snr[:, 0] >= 4
    print(
        f"drifting, cycle at least 4 times the drift's power near its frequency: recall "
        f"{snr[seen, 1].mean():.2f} ({seen.sum()} of {len(snr)})"
    )


def print_visibility(cycle_to_noise, edges=(0, 1, 1.5, 2, 3, np.inf)):
    """Recall by the cycle's deviation over the noise's, per class that records it: where
    the misses of a class lie (below 1 the noise hides the cycle from the eye)."""
    for kind, pairs in cycle_to_noise.items():
        pairs = np.array(pairs)
        cells = []
        for lo, hi in zip(edges[:-1], edges[1:]):
            sel = (pairs[:, 0] >= lo) & (pairs[:, 0] < hi)
            if sel.any():
                cells.append(f"{lo:g}-{hi:g}: {pairs[sel, 1].mean():.2f} ({sel.sum()})")
        seen = pairs[:, 0] >= 1
        print(
            f"{kind}, recall by the cycle's deviation over the noise's: "
            + "; ".join(cells)
            + f"; at least 1: {pairs[seen, 1].mean():.2f} ({seen.sum()} of {len(pairs)})"
        )


def print_zeta(zeta):
    """False alarms on coloured noise: AR(1) noise, and AR(2) resonances by damping."""
    ar1 = np.isnan(zeta[:, 0])
    cells = [f"AR(1) {zeta[ar1, 1].mean():.2f} ({ar1.sum()})"]
    for lo, hi in ((0.35, 0.45), (0.45, 0.55), (0.55, 0.7)):
        sel = (zeta[:, 0] >= lo) & (zeta[:, 0] < hi)
        if sel.any():
            cells.append(f"AR(2) damping {lo:g}-{hi:g} {zeta[sel, 1].mean():.2f} ({sel.sum()})")
    print("coloured_noise, false alarms: " + "; ".join(cells))


def print_tradeoff(index, thresholds=(0.1, 0.2, 0.3, 0.5, 0.7)):
    """Recall of very irregular cycles and the worst false alarms (coloured noise) at
    other thresholds on the index: the balance ``analyze_cycles(x, threshold=...)``
    moves."""
    cells = []
    for t in thresholds:
        worst = max(np.mean(index[k] > t) for k in QUIET)
        cells.append(f"{t:g}: {np.mean(index['very_irregular'] > t):.2f} / {worst:.2f} / "
                     f"{np.mean(index['closed_loop'] > t):.2f}")
    print("threshold on the index: very_irregular recall / worst false alarms / false alarms "
          "on closed_loop: " + "; ".join(cells))


def print_table(rows, n_per_class):
    print(
        "| class | truth | signals | called oscillating | of which < 1,000 samples |"
        " period(s) found within 20 % | r of the cycles found, median (10-90 %) |"
    )
    print("|---|---|---|---|---|---|---|")
    for kind, truth, rate, short, n_short, per, regularity in rows:
        label = "oscillating" if truth else "not oscillating"
        what = "recall" if truth else "false alarms"
        pcol = f"{per:.2f}" if truth else ""
        scol = f"{short:.2f} ({n_short})" if n_short else "-"
        r = regularity[np.isfinite(regularity)]
        rcol = (
            "-"
            if r.size == 0
            else "{:.2f} ({:.2f}-{:.2f})".format(*np.percentile(r, [50, 10, 90]))
        )
        print(
            f"| {kind} | {label} | {n_per_class} | {what} {rate:.2f} | {scol} | {pcol} | {rcol} |"
        )


# ------------------------------------------------------------ other method families
# Light reference implementations, for the comparison table only (``--compare``).


def _acf_regularity(x, crossings=11):
    """Thornhill, Huang & Zhang (2003) on the whole signal: regularity r of the first
    zero crossings of the ACF of the detrended signal (r > 1: oscillating), and the
    period (mean interval between alternate crossings)."""
    n = x.size
    t = np.arange(n)
    y = x - np.polyval(np.polyfit(t, x, 1), t)
    f = np.fft.rfft(y - y.mean(), 2 * n)
    r = np.fft.irfft(f * np.conj(f))[: n // 2]
    if r[0] <= 0:
        return 0.0, np.nan
    s = np.signbit(r)
    idx = np.flatnonzero(s[1:] != s[:-1])[:crossings]
    if idx.size < 5:
        return 0.0, np.nan
    z = idx + r[idx] / (r[idx] - r[idx + 1])
    tp = z[2:] - z[:-2]
    return (tp.mean() / (3 * tp.std()) if tp.std() > 0 else np.inf), tp.mean()


def _regularity(x):
    """Thornhill's r when the ACF's period lies in the range this package searches
    (5 samples to 3.5 cycles per record), else 0: no detector is credited for cycles
    outside it."""
    r, period = _acf_regularity(x)
    return float(r) if 5.0 <= period <= x.size / 3.5 else 0.0


def acf_detector(x):
    """Thornhill et al. (2003) on the whole signal: r (oscillating when r > 1)."""
    return _regularity(x)


def _extrema(h):
    d = np.diff(h)
    up = np.flatnonzero((d[:-1] > 0) & (d[1:] <= 0)) + 1
    down = np.flatnonzero((d[:-1] < 0) & (d[1:] >= 0)) + 1
    return up, down


def emd(x, max_imfs=8, max_sift=10):
    """Empirical mode decomposition (Huang et al. 1998): intrinsic mode functions by
    sifting with cubic-spline envelopes (ends held at the end values), fastest first,
    and the residue."""
    from scipy.interpolate import CubicSpline

    n = x.size
    t = np.arange(n)
    residue = x - x.mean()
    imfs = []
    for _ in range(max_imfs):
        h = residue.copy()
        for _ in range(max_sift):
            up, down = _extrema(h)
            if up.size < 3 or down.size < 3:
                break
            knots_u, knots_d = np.r_[0, up, n - 1], np.r_[0, down, n - 1]
            upper = CubicSpline(knots_u, np.r_[h[up[0]], h[up], h[up[-1]]])(t)
            lower = CubicSpline(knots_d, np.r_[h[down[0]], h[down], h[down[-1]]])(t)
            mean = 0.5 * (upper + lower)
            h = h - mean
            if np.sum(mean**2) < 0.01 * np.sum(h**2):
                break
        up, down = _extrema(h)
        if up.size < 3 or down.size < 3:
            break
        imfs.append(h)
        residue = residue - h
    return imfs, residue


def emd_detector(x, min_share=0.1):
    """Srinivasan, Rengaswamy & Miller (2007): the signal is decomposed by EMD; the
    largest Thornhill r of the intrinsic mode functions that hold at least
    ``min_share`` of the IMFs' power (oscillating when r > 1)."""
    imfs, _ = emd(np.asarray(x, dtype=float))
    power = np.array([np.sum(h**2) for h in imfs])
    return max(
        (_regularity(h) for h, p in zip(imfs, power) if p >= min_share * power.sum()), default=0.0
    )


def wavelet_detector(x, min_share=0.1, voices=4):
    """After Naghoosi & Huang (2014): continuous wavelet transform (complex Morlet,
    w0 = 6, ``voices`` scales per octave from 5 samples to a quarter of the record);
    the scales of local maxima of the time-averaged wavelet power that hold at least
    ``min_share`` of the peak power are candidate oscillations; the largest Thornhill r
    of their real coefficients' ACF (oscillating when r > 1)."""
    x = np.asarray(x, dtype=float)
    n = x.size
    t = np.arange(n)
    y = x - np.polyval(np.polyfit(t, x, 1), t)
    m = 2 * n
    spec = np.fft.rfft(y, m)
    freq = np.arange(spec.size) / m
    periods = 5.0 * 2.0 ** (np.arange(int(voices * np.log2(n / 20.0)) + 1) / voices)
    w0 = 6.0
    power, coeffs = [], []
    for period in periods:
        f0 = 1.0 / period
        window = np.exp(-0.5 * (w0 * (freq / f0 - 1.0)) ** 2)  # Morlet, analytic
        c = np.fft.irfft(spec * window, m)[:n]
        coeffs.append(c)
        power.append(np.mean(c**2))
    power = np.array(power)
    peaks = [
        i
        for i in range(1, power.size - 1)
        if power[i] >= power[i - 1]
        and power[i] > power[i + 1]
        and power[i] >= min_share * power.max()
    ]
    return max((_regularity(coeffs[i]) for i in peaks), default=0.0)


#: name: (statistic of one signal, the threshold its authors use)
DETECTORS = {
    "band-limited ACF (this package)": (lambda x: analyze_cycles(x).oscillation_index, 0.5),
    "ACF regularity (Thornhill 2003)": (acf_detector, 1.0),
    "EMD + ACF regularity (Srinivasan 2007)": (emd_detector, 1.0),
    "Morlet CWT + ACF regularity": (wavelet_detector, 1.0),
}


def run_comparison(n_per_class, seed=0, fa_goal=0.05):
    """Call rates per class of every detector in :data:`DETECTORS` on the same signals
    as :func:`run_simulated` (the first ``n_per_class`` of each class): at the
    threshold its authors use, and at the lowest threshold whose false alarms stay
    within ``fa_goal`` in every quiet class (chosen on these signals, in each
    detector's favour); and the median time per 5,000 samples."""
    kinds = OSCILLATING + QUIET
    stats = {name: [] for name in DETECTORS}
    times = {name: [] for name in DETECTORS}
    for kind in kinds:
        rng = np.random.default_rng([seed, STREAM[kind]])
        signals = [make_signal(kind, rng)[0] for _ in range(n_per_class)]
        for name, (statistic, _) in DETECTORS.items():
            values = []
            for x in signals:
                t0 = time.perf_counter()
                values.append(statistic(x))
                times[name].append((time.perf_counter() - t0) / x.size * 5000)
            stats[name].append(np.array(values))
    k = len(OSCILLATING)
    columns = []
    for name, (_, published) in DETECTORS.items():
        quiet = np.concatenate(stats[name][k:])
        matched = min(
            (
                t
                for t in np.unique(quiet)
                if t >= published and all(np.mean(v > t) <= fa_goal for v in stats[name][k:])
            ),
            default=np.inf,
        )
        if all(np.mean(v > published) <= fa_goal for v in stats[name][k:]):
            matched = published
        columns.append((name, published, matched))
    head = []
    for name, published, matched in columns:
        head.append(f"{name}, > {published:g}")
        if matched != published:
            head.append(f"{name}, > {matched:.2f} (false alarms <= {fa_goal:g})")
    print("| class | truth | " + " | ".join(head) + " |")
    print("|---|---|" + "---|" * len(head))
    for c, kind in enumerate(kinds):
        what = "recall" if c < k else "false alarms"
        cells = []
        for name, published, matched in columns:
            cells.append(f"{np.mean(stats[name][c] > published):.2f}")
            if matched != published:
                cells.append(f"{np.mean(stats[name][c] > matched):.2f}")
        print(f"| {kind} | {what} | " + " | ".join(cells) + " |")
    worst, cost = [], []
    for name, published, matched in columns:
        for t in [published] if matched == published else [published, matched]:
            worst.append(
                f"{min(np.mean(v > t) for v in stats[name][:k]):.2f} / "
                f"{max(np.mean(v > t) for v in stats[name][k:]):.2f}"
            )
            cost.append(f"{1e3 * np.median(times[name]):.1f}")
    print("| worst recall / worst false alarms | | " + " | ".join(worst) + " |")
    print("| median ms per 5,000 samples | | " + " | ".join(cost) + " |")


def _describe(x):
    a = analyze_cycles(x)
    periods = "/".join(f"{p:.0f}" for p in a.periods) or "-"
    return a, f"{a.oscillation_index:.2f} {periods}"


def run_measured(figures=None):
    """Detector on the measured loops: ISDB loops (all oscillate) and plant windows."""
    from _measured_common import load_measured

    found = load_measured()
    if found is None:
        print("\nmeasured data not found (../shared/data): skipped")
        return
    X, y, groups, meta = found
    rows = []
    for i in range(len(X)):
        n = int(meta["n_samples"].iloc[i]) if "n_samples" in meta else X.shape[1]
        n = int(np.sum(np.isfinite(X[i, :, 1]))) or n
        op, pv = X[i, :n, 1], X[i, :n, 0]
        a_op, d_op = _describe(op)
        a_pv, d_pv = _describe(pv)
        rows.append(
            (
                meta["dataset"].iloc[i],
                str(meta["file"].iloc[i]),
                str(groups[i]),
                meta["label"].iloc[i],
                n,
                a_op,
                d_op,
                a_pv,
                d_pv,
            )
        )
    print(
        "\n| dataset | # | tag | label | samples | OP index, periods | PV index, periods |"
        " OP oscillating |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for k, (ds, _f, tag, label, n, a_op, d_op, _a_pv, d_pv) in enumerate(rows):
        print(
            f"| {ds} | {k} | {tag} | {label} | {n} | {d_op} | {d_pv} | {int(a_op.oscillating)} |"
        )
    for ds in ("isdb", "plant"):
        sel = [r for r in rows if r[0] == ds]
        print(
            f"{ds}: OP oscillating in {sum(r[5].oscillating for r in sel)} of {len(sel)} "
            f"loops; PV in {sum(r[7].oscillating for r in sel)}"
        )
    if figures:
        _figures(rows, X, Path(figures))


def _figures(rows, X, folder, per_page=12):
    """Pages of OP (blue) and PV (orange), each scaled to its range, titled with the
    detector's index and periods, for judging by eye which windows cycle."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder.mkdir(parents=True, exist_ok=True)
    for page in range(0, len(rows), per_page):
        fig, axes = plt.subplots(per_page // 3, 3, figsize=(15, 2.2 * per_page // 3))
        for ax, k in zip(axes.flat, range(page, page + per_page)):
            ax.axis("off")
            if k >= len(rows):
                continue
            ds, _f, tag, label, n, a_op, d_op, a_pv, d_pv = rows[k]
            ax.axis("on")
            for c, colour in ((1, "tab:blue"), (0, "tab:orange")):
                x = X[k, :n, c]
                span = np.ptp(x) or 1.0
                ax.plot((x - np.min(x)) / span, color=colour, lw=0.7)
            ax.set_title(f"{k} {ds} {tag} {label[:2]} | OP {d_op} | PV {d_pv}", fontsize=8)
            ax.set_yticks([])
            ax.tick_params(labelsize=6)
        fig.tight_layout()
        fig.savefig(folder / f"measured_{page // per_page:02d}.png", dpi=70)
        plt.close(fig)
    print(f"figures in {folder}")


def cpu_median(fn, repeats):
    """Median CPU time (``time.process_time``) of ``repeats`` calls of ``fn``."""
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return float(np.median(times))


def run_speed(n_loops=12, repeats=7):
    """CPU time of all features (TemplateDistances + AreaRatio) of one 5,000-sample loop,
    on the loops ``benchmarks/bench_features.py`` times, and of ``analyze_cycles`` on
    the loop's PV and OP; each call on a fresh copy, so no cached analysis is reused."""
    from sktiction import AreaRatio, TemplateDistances
    from sktiction.datasets import make_loops

    X, _ = make_loops(
        n_loops,
        n_samples=5000,
        stiction_fraction=1.0,
        orders=(1,),
        period_range=(25, 125),
        stiction_models=("relay",),
        random_state=0,
    )
    td, ar = TemplateDistances().fit(X), AreaRatio().fit(X)
    td.transform(X[:1])
    ar.transform(X[:1])  # compile
    features, cycles = [], []
    for i in range(n_loops):
        one = X[i : i + 1]
        features.append(
            cpu_median(
                lambda one=one: (td.transform(one.copy()), ar.transform(one.copy())), repeats
            )
        )
        cycles.append(
            cpu_median(
                lambda one=one: [analyze_cycles(one[0, :, c].copy()) for c in (0, 1)], repeats
            )
        )
    print(
        f"all features of a 5,000-sample loop, median CPU time over {n_loops} loops: "
        f"{1e3 * np.median(features):.1f} ms (goal <= 20 ms; range "
        f"{1e3 * np.min(features):.1f}-{1e3 * np.max(features):.1f})"
    )
    print(f"analyze_cycles on its PV and OP: {1e3 * np.median(cycles):.1f} ms")


def _band_passed(x, period):
    """``x`` band-passed around ``period`` with the detector's weight
    ``exp(-(ln(f / f0) / 0.5)^2)``, straight line removed."""
    t = np.arange(x.size)
    y = x - np.polyval(np.polyfit(t, x, 1), t)
    f = np.fft.rfftfreq(x.size)
    w = np.zeros_like(f)
    w[1:] = np.exp(-((np.log(f[1:] * period) / 0.5) ** 2))
    return np.fft.irfft(np.fft.rfft(y) * w, x.size)


def band_kurtosis(x, period):
    """Excess kurtosis of ``x`` band-passed around ``period``: a sustained cycle of
    steady amplitude gives -1.5 (a sine), Gaussian narrow-band noise 0."""
    from scipy.stats import kurtosis

    return float(kurtosis(_band_passed(x, period)))


def band_regularity(x, period):
    """Thornhill's r (mean over three standard deviations) of the intervals between
    alternate zero crossings of ``x`` band-passed around ``period``: how regular the
    timing of its cycles is once the filter has taken out what lies far from the
    period. Band-passed noise has one too (the filter gives it a period)."""
    y = _band_passed(x, period)
    z = np.flatnonzero(np.signbit(y[1:]) != np.signbit(y[:-1]))
    tp = z[2:] - z[:-2]
    return float(tp.mean() / (3 * tp.std())) if tp.size > 2 and tp.std() > 0 else np.nan


def run_gaussianity(n_per_class, seed=0):
    """Whether very irregular cycles differ from resonant noise in anything but the
    spectrum: the signal band-passed at the true period (for noise, at the peak of its
    spectrum smoothed over 9 bins), per class: its excess kurtosis (amplitude) and
    Thornhill's r of its zero crossings (timing); white noise band-passed at a period
    drawn as the cycles' are is the reference for r."""
    rows = {}
    for kind in ("irregular", "very_irregular", "noise_driven", "coloured_noise"):
        rng = np.random.default_rng([seed, STREAM[kind]])
        for _ in range(n_per_class):
            info = {}
            x, _, periods = make_signal(kind, rng, info)
            zeta = info.get("zeta", 0.0)
            if not np.isfinite(zeta):
                continue  # AR(1) noise: no period
            if not periods:
                power = np.convolve(np.abs(np.fft.rfft(x - x.mean())) ** 2, np.ones(9), "same")
                periods = [x.size / (3 + np.argmax(power[3:]))]
            band = "" if kind != "coloured_noise" else (
                " damping 0.35-0.45" if zeta < 0.45 else " damping 0.45-0.7")  # fmt: skip
            k, r = band_kurtosis(x, periods[0]), band_regularity(x, periods[0])
            rows.setdefault(kind + band, []).append((k, r))
    rng = np.random.default_rng([seed, 1000])
    for _ in range(n_per_class):
        n = _record_length(rng)
        x, p = rng.normal(size=n), rng.uniform(15, min(150.0, n / 6))
        rows.setdefault("white noise", []).append((np.nan, band_regularity(x, p)))
    for col, name in ((0, "excess kurtosis"), (1, "Thornhill's r of the zero crossings")):
        print(f"{name} of the signal band-passed at its period: 5 / 25 / 50 / 75 / 95 %")
        for kind, got in rows.items():
            v = np.array([g[col] for g in got])
            v = v[np.isfinite(v)]
            if v.size:
                q = " / ".join(f"{a:.2f}" for a in np.percentile(v, [5, 25, 50, 75, 95]))
                print(f"  {kind} ({v.size}): {q}")


def chirped(shape, n, first, last, duty=0.1):
    """A cycle whose period changes linearly from ``first`` to ``last`` samples over
    ``n`` samples (a limit cycle whose load or operating point moves during the record);
    a "pulse" is high (1) for ``duty`` of each cycle and 0 otherwise."""
    phase = np.cumsum(1.0 / np.linspace(first, last, n)) % 1.0  # share of the cycle done
    if shape == "sine":
        return np.sin(2 * np.pi * phase)
    if shape == "saw":
        return 2 * phase - 1
    if shape == "square":
        return np.where(phase < 0.5, 1.0, -1.0)
    if shape == "triangle":
        return 1 - 4 * np.abs(phase - 0.5)
    return (phase < duty).astype(float)


def run_drifting_period(seed=0, per_cell=30):
    """Cycles whose period changes by a factor across the record (either way), 8-15
    cycles in 1,500-5,000 samples, white noise: share found, per shape, factor and noise
    (in units of the cycle's amplitude: half its peak-to-peak; a pulse train's height 1)."""
    rng = np.random.default_rng([seed, 3000])
    ratios = (1.0, 1.3, 1.6, 2.0, 3.0)
    print(f"{per_cell} signals per cell; period changing by a factor of " +
          ", ".join(f"{r:g}" for r in ratios))  # fmt: skip
    shapes = [("sine", 0.5), ("triangle", 0.5), ("square", 0.5), ("saw", 0.5),
              ("pulse", 0.05), ("pulse", 0.1), ("pulse", 0.2)]  # fmt: skip
    for noise in (0.1, 0.3):
        for shape, duty in shapes:
            cells = []
            for ratio in ratios:
                got = []
                for _ in range(per_cell):
                    n = int(rng.uniform(1500, 5000))
                    first = 2 * n / rng.uniform(8, 15) / (1 + ratio)  # mean period n / cycles
                    a, b = (first, ratio * first) if rng.random() < 0.5 else (ratio * first, first)
                    x = chirped(shape, n, a, b, duty) + rng.normal(0, noise, n)
                    got.append(read_quietly(x).oscillating)  # short pulses read as spikes
                cells.append(f"{np.mean(got):.2f}")
            name = shape if shape != "pulse" else f"pulse, high {duty:.0%} of each cycle"
            print(f"| {name} | {noise:g} | " + " | ".join(cells) + " |")


#: Cycles held at a limit (``--saturated``; the noise held at one is a main quiet class).
SATURATED = ("saturated_cycles", "pulses_reaching_a_limit", "pulses_resting_at_a_limit")


def make_saturated(kind, rng):
    """Cycles held at a limit, top or bottom at random: (x, 1). *saturated_cycles*: a
    sine, triangle or saw-tooth of 20-150 samples (period wander 12-25 %, amplitude
    10-25 %, noise 0.1-0.7) held on 5-40 % of its samples. Pulse trains high for 15-35 %
    of each cycle under the same wander and noise, *reaching* a limit with their pulses
    (held on 50-100 % of their high side) or *resting* at one between them (30-90 % of
    their low side)."""
    n = _record_length(rng)
    p = rng.uniform(20, min(150.0, n / 6))
    wander = (rng.uniform(0.12, 0.25), rng.uniform(0.1, 0.25))
    if kind == "saturated_cycles":
        shape, duty = rng.choice(["sine", "triangle", "saw"]), 0.5
        held = rng.uniform(0.05, 0.4)
    else:
        shape, duty = "pulse", rng.uniform(0.15, 0.35)
        if kind == "pulses_reaching_a_limit":
            held = duty * rng.uniform(0.5, 1.0)
        else:
            held = (1 - duty) * rng.uniform(0.3, 0.9)
    x = _wandering(rng, n, p, *wander, shape, duty) + _noise(rng, n, rng.uniform(0.1, 0.7))
    x = _at_limit(x, held, bottom=kind == "pulses_resting_at_a_limit")
    return rng.choice([-1, 1]) * x, 1


def run_saturated(n_per_class, seed=0):
    """Share called oscillating of each class of :func:`make_saturated`."""
    for i, kind in enumerate(SATURATED):
        rng = np.random.default_rng([seed, 3000 + i])
        hits = [read_quietly(make_saturated(kind, rng)[0]).oscillating for _ in range(n_per_class)]
        print(f"{kind}: recall {np.mean(hits):.2f} ({n_per_class} signals)")


def run_level_steps(n_per_class, seed=0, per_cell=40):
    """Cycles under level shifts, read as they are and with the second reading: a grid
    of one step (size in cycle amplitudes x period), then the *level_steps* class by
    number of steps, lag and distance of the nearest step from the record's ends."""
    from sktiction.cycles._analysis import _read_cycles

    def as_is(x):
        return _read_cycles(x, 3, 3.0, 0.5, 0.0, 0.5, None).oscillating

    print(f"one step at 20-80 % of 1,000-3,000 samples, {per_cell} signals per cell: "
          "found as is / with the second reading")  # fmt: skip
    rng = np.random.default_rng([seed, 2000])
    for lo, hi in ((2, 5), (5, 10), (10, 20), (20, 50)):
        cells = []
        for p_lo, p_hi in ((15, 40), (40, 100), (100, 250)):
            got = []
            for _ in range(per_cell):
                n = int(rng.uniform(1000, 3000))
                x = _wandering(rng, n, rng.uniform(p_lo, p_hi), 0.08, 0.15) + _noise(rng, n, 0.2)
                x[int(rng.uniform(0.2, 0.8) * n) :] += rng.uniform(lo, hi) * rng.choice([-1, 1])
                got.append((as_is(x), analyze_cycles(x).oscillating))
            a, b = np.mean(got, axis=0)
            cells.append(f"period {p_lo}-{p_hi}: {a:.2f} / {b:.2f}")
        print(f"  step {lo}-{hi} amplitudes: " + "; ".join(cells))
    rng = np.random.default_rng([seed, STREAM["level_steps"]])
    rows = []
    for _ in range(n_per_class):
        info = {}
        x = make_signal("level_steps", rng, info)[0]
        rows.append((info["steps"], info["lag"], info["edge"], analyze_cycles(x).oscillating))
    rows = np.array(rows, dtype=float)
    print(f"level_steps ({n_per_class} signals): found {rows[:, 3].mean():.2f}")
    groups = {
        "1 / 2 / 3 steps": [rows[:, 0] == k for k in (1, 2, 3)],
        "no lag / lag under 1/40 of the record / over it": [
            rows[:, 1] == 0, (rows[:, 1] > 0) & (rows[:, 1] < 1 / 40), rows[:, 1] >= 1 / 40],
        "nearest step within 7.5 % of an end / further": [rows[:, 2] < 0.075, rows[:, 2] >= 0.075],
    }  # fmt: skip
    for name, masks in groups.items():
        parts = [f"{rows[m, 3].mean():.2f} ({int(m.sum())})" for m in masks]
        print(f"  {name}: " + " / ".join(parts))


def _spikes(rng, x, low, high):
    y = x.copy()
    k = int(rng.integers(2, 9))
    y[rng.integers(0, x.size, k)] += rng.choice([-1, 1], k) * rng.uniform(low, high, k) * np.ptp(x)
    return y


def _placeholders(rng, x):
    y = x + 50 - x.mean()  # an operating point, then an outage written as -9999
    length = max(1, int(rng.uniform(0.005, 0.05) * x.size))
    start = int(rng.integers(0, x.size - length))
    y[start : start + length] = -9999.0
    return y


def _trips(rng, x):
    y = x + 50 - x.mean()  # an operating point, then OP to 0 for 4-20 samples, 1-3 times
    for _ in range(int(rng.integers(1, 4))):
        length = int(rng.integers(4, 21))
        start = int(rng.integers(0, x.size - length))
        y[start : start + length] = 0.0
    return y


#: What a historian, a transmitter or an interlock does to a record, by name.
ARTEFACTS = {
    "none": lambda rng, x: x,
    "spikes": lambda rng, x: _spikes(rng, x, 5, 20),  # 2-8 "Bad" samples, 5-20 ranges off
    "mild_spikes": lambda rng, x: _spikes(rng, x, 1, 3),
    "placeholders": _placeholders,  # 0.5-5 % of the record
    "trips": _trips,
}


def _as_before(y):
    """``analyze_cycles`` as it read ``y`` at b473a64: no spike or
    placeholder repair, and excursions clipped for a second reading only when more than
    0.5 % of the record lay beyond the far-out fences."""
    from sktiction.cycles import _level_shifts
    from sktiction.cycles._analysis import _analyze_cycles

    now = _level_shifts.EXCURSION_SHARE
    _level_shifts.EXCURSION_SHARE = 0.005
    try:
        return _analyze_cycles(y)
    finally:
        _level_shifts.EXCURSION_SHARE = now


def run_artefacts(n_per_class, seed=0):
    """Rate of oscillating calls per class with each artefact of :data:`ARTEFACTS`, as
    ``analyze_cycles`` reads the record (spikes replaced, placeholders read as missing,
    as a scan reads them; a trip clipped for a second reading) and as it read the record
    before those changes (:func:`_as_before`)."""

    kinds = ("regular", "irregular", "stick_slip", "unequal_halves",
             "coloured_noise", "random_walk", "closed_loop")  # fmt: skip
    print("| class | truth | " + " | ".join(f"{a}: now / before" for a in ARTEFACTS) + " |")
    print("|---|---|" + "---|" * len(ARTEFACTS))
    for kind in kinds:
        cells = []
        for k, harm in enumerate(ARTEFACTS.values()):
            rng = np.random.default_rng([seed, STREAM[kind]])
            spoil = np.random.default_rng([seed, 1000 + k])
            now, before = [], []
            for _ in range(n_per_class):
                x, truth, _ = make_signal(kind, rng)
                y = harm(spoil, x)
                now.append(read_quietly(y).oscillating)  # each repair counted, not said
                before.append(_as_before(y).oscillating)
            cells.append(f"{np.mean(now):.2f} / {np.mean(before):.2f}")
        print(f"| {kind} | {'oscillating' if truth else 'quiet'} | " + " | ".join(cells) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=200, help="signals per class")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--measured", action="store_true")
    parser.add_argument("--figures", default=None)
    parser.add_argument(
        "--compare",
        action="store_true",
        help="compare with other method families (EMD, wavelets, plain ACF)",
    )
    parser.add_argument("--speed", action="store_true", help="CPU time of all features")
    parser.add_argument(
        "--level-steps",
        action="store_true",
        help="cycles under level shifts: found as read and with the second reading",
    )
    parser.add_argument(
        "--gaussianity",
        action="store_true",
        help="band-passed kurtosis and regularity per class: very irregular cycles against "
        "resonant noise",
    )
    parser.add_argument(
        "--artefacts",
        action="store_true",
        help="spikes, placeholders for missing data, trips: found now and as before",
    )
    parser.add_argument(
        "--saturated",
        action="store_true",
        help="cycles held at a limit (a valve fully open or shut)",
    )
    parser.add_argument(
        "--drifting-period",
        action="store_true",
        help="cycles whose period changes by a factor across the record",
    )
    args = parser.parse_args()
    if args.saturated:
        run_saturated(args.n, args.seed)
        return
    if args.drifting_period:
        run_drifting_period(args.seed)
        return
    if args.artefacts:
        run_artefacts(args.n, args.seed)
        return
    if args.speed:
        run_speed()
        return
    if args.level_steps:
        run_level_steps(args.n, args.seed)
        return
    if args.gaussianity:
        run_gaussianity(args.n, args.seed)
        return
    if args.compare:
        run_comparison(args.n, args.seed)
        return
    rows, per5000, extra = run_simulated(args.n, args.seed)
    print_table(rows, args.n)
    print()
    print_snr(extra["band_snr"])
    print_visibility(extra["cycle_to_noise"])
    print_zeta(extra["zeta"])
    print_tradeoff(extra["index"])
    worst_recall = min(r[2] for r in rows if r[1])
    worst_fa = max(r[2] for r in rows if not r[1])
    print(
        f"\nworst recall {worst_recall:.2f} (goal >= 0.95); "
        f"worst false-alarm rate {worst_fa:.2f} (goal <= 0.05)"
    )
    print(f"analyze_cycles per 5,000 samples, median CPU time: {1e3 * per5000:.2f} ms")
    if args.measured:
        run_measured(args.figures)


if __name__ == "__main__":
    main()
