"""Known answers of ``sktiction.realism.loop_statistics``: hand-built signals whose statistic
is computable on paper, the invariances the docstring claims, NaN handling and edge cases.

Every signal here is built by hand (seeded noise where noise is the point); tolerances on
noisy estimates are several standard errors of the estimate at the record length used.
"""

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from sklearn.utils import Bunch

from sktiction.realism import STATISTIC_COLUMNS, loop_statistics
from sktiction.realism import statistics as st

# robust noise sd from second differences: MAD of d2 times this
MAD_TO_SD = 1.4826 / np.sqrt(6.0)


def _loop(pv, op=None, sp=None):
    """One loop (1, n, 3) from its channels; absent channels are NaN."""
    n = len(pv)
    op = np.full(n, np.nan) if op is None else np.asarray(op, dtype=float)
    sp = np.full(n, np.nan) if sp is None else np.asarray(sp, dtype=float)
    return np.stack([np.asarray(pv, dtype=float), op, sp], axis=-1)[None]


def _stats(pv, op=None, sp=None, **kw):
    return loop_statistics(_loop(pv, op, sp), **kw).iloc[0]


def _span(x):
    lo, hi = np.percentile(x, [5, 95])
    return hi - lo


def _hold(x, starts, length):
    """Copy of ``x`` with ``x[s + 1 : s + 1 + length] = x[s]`` for each start (``length``
    repeats, i.e. a run of ``length`` True in ``diff == 0``)."""
    x = x.copy()
    for s in starts:
        x[s + 1 : s + 1 + length] = x[s]
    return x


# ---- helpers with answers on paper -----------------------------------------------------------


def test_acf_known_values_on_both_paths():
    # biased ACF of a constant without demeaning: (n - k) / n
    assert st._acf(np.ones(10), 3, demean=False) == pytest.approx([1.0, 0.9, 0.8, 0.7])
    # alternating +-1 (mean 0): r_k = (-1)^k (n - k) / n
    alt = np.array([1.0, -1.0] * 50)
    want = [(-1) ** k * (100 - k) / 100 for k in range(61)]
    assert st._acf(alt, 5) == pytest.approx(want[:6])  # direct dot products
    assert st._acf(alt, 60) == pytest.approx(want)  # FFT
    # the mean is removed unless told: a shift changes nothing
    assert st._acf(alt + 100.0, 5) == pytest.approx(want[:6])
    assert st._acf(alt + 100.0, 60) == pytest.approx(want)
    # AR(1) of coefficient 0.8: r_1 near 0.8 (sd of the estimate about 0.004 at n = 20000)
    rng = np.random.default_rng(0)
    ar = lfilter([1.0], [1.0, -0.8], rng.standard_normal(20000))
    assert st._acf(ar, 3)[1] == pytest.approx(0.8, abs=0.02)
    assert st._acf(ar, 3)[2] == pytest.approx(0.64, abs=0.03)
    # lags beyond the record are 0; a zero signal has no ACF (NaN at every lag asked for)
    short = st._acf(np.array([1.0, -1.0, 1.0]), 5, demean=False)
    assert short == pytest.approx([1, -2 / 3, 1 / 3, 0, 0, 0])
    for lag in (5, 60):
        r = st._acf(np.zeros(100), lag)
        assert r.shape == (lag + 1,) and np.isnan(r).all()


def test_xcorr_and_detrend_known_values():
    rng = np.random.default_rng(1)
    b = rng.standard_normal(500)
    a = np.roll(b, 3)  # a[k] = b[k - 3]
    xc = st._xcorr(a, b, 10)
    assert xc.shape == (21,)
    assert int(np.argmax(xc)) - 10 == 3 and xc[13] == pytest.approx(1.0, abs=0.02)
    flat = st._xcorr(np.ones(50), b[:50], 4)
    assert flat.shape == (9,) and np.isnan(flat).all()
    # a ramp's slope, and a single sample has none
    det, slope = st._detrend(3.0 + 0.25 * np.arange(40))
    assert slope == pytest.approx(0.25) and det == pytest.approx(np.zeros(40), abs=1e-12)
    det, slope = st._detrend(np.array([5.0]))
    assert slope == 0.0 and det == pytest.approx([0.0])


def test_noise_sd_of_known_second_differences():
    # second differences 0, 1, 2, 3, 4: median 2, MAD 1
    x = np.array([0.0, 1, 2, 4, 8, 15, 26])
    assert st._noise_sd(x, np.diff(x) == 0) == pytest.approx(MAD_TO_SD)
    # four second differences are too few for a noise level
    assert st._noise_sd(x[:6], np.diff(x[:6]) == 0) == 0.0


# ---- noise ------------------------------------------------------------------------------------


def test_white_noise_of_sd_2_on_a_slow_sine():
    """pv_noise near 2 (the MAD of 20000 second differences: sd of the estimate ~1 %);
    the slow sine shrinks to 1e-3 in the second difference."""
    rng = np.random.default_rng(2)
    t = np.arange(20000)
    pv = 10 * np.sin(2 * np.pi * t / 2000) + 2.0 * rng.standard_normal(len(t))
    s = _stats(pv, sp=np.zeros(len(t)))
    assert s["pv_noise"] == pytest.approx(2.0, rel=0.04)
    assert s["noise_level"] == s["pv_noise"] / s["error_span"]
    assert abs(s["noise_colour"]) < 0.08  # white: r1 of d2 = -2/3
    assert s["diff_acf_min"] > -0.1  # no averaging dip


def test_noise_of_held_samples_is_left_out():
    """White noise with 30 % of samples frozen in runs of 5: the noise level and colour are
    those of the fresh samples (frozen second differences would read as zeros)."""
    rng = np.random.default_rng(3)
    x = rng.standard_normal(20000)
    starts = range(100, 20000 - 10, 20)
    held = _hold(x, starts, 6)  # 6 of every 20 samples repeated
    s = _stats(held)
    assert s["pv_repeat_fraction"] == 6 * len(starts) / 19999  # 0.2985
    assert s["pv_noise"] == pytest.approx(1.0, rel=0.05)
    assert abs(s["noise_colour"]) < 0.1


def test_single_repeats_do_not_colour_white_noise():
    """One repeat every 5 samples (compression of white noise): second differences touching
    a repeat are left out, so the colour stays white (spread over seeds: sd 0.033 at this
    length; a mask that kept differences half-touching a repeat gives -0.36)."""
    rng = np.random.default_rng(21)
    x = rng.standard_normal(40000)
    for s in range(3, 40000 - 2, 5):
        x[s + 1] = x[s]
    s = _stats(x)
    assert s["pv_repeat_fraction"] == pytest.approx(0.2, abs=1e-3)
    assert abs(s["noise_colour"]) < 0.15
    assert s["pv_noise"] == pytest.approx(1.0, rel=0.05)


@pytest.mark.parametrize("phi", [0.0, 0.5, 0.9])
def test_noise_colour_of_ar1_noise(phi):
    """colour = 6 (r1 + 2/3), r1 the lag-1 ACF of the second difference of AR(1) noise. On
    paper (d2 = x_t - 2 x_{t-1} + x_{t-2}, ACF of x phi^k): var 6 - 8 phi + 2 phi^2, lag-1
    covariance -4 + 7 phi - 4 phi^2 + phi^3: r1 = -2/3 (phi 0), -0.55 (phi 0.5), -0.502
    (phi 0.9): colour 0, 0.70, 0.986."""
    rng = np.random.default_rng(4)
    e = lfilter([1.0], [1.0, -phi], rng.standard_normal(20000))
    r1 = (-4 + 7 * phi - 4 * phi**2 + phi**3) / (6 - 8 * phi + 2 * phi**2)
    want = 6 * (r1 + 2 / 3)
    assert want == pytest.approx({0.0: 0.0, 0.5: 0.7, 0.9: 0.98571}[phi], abs=1e-4)
    s = _stats(e)
    assert s["noise_colour"] == pytest.approx(want, abs=0.06)
    if phi == 0.0:
        assert s["decorrelation_lag"] == 1  # white: ACF below 0.5 from lag 1


def test_decorrelation_lag_of_ar1():
    # phi = 0.6: ACF 0.6 at lag 1, 0.36 at lag 2 (estimate sd ~0.01)
    rng = np.random.default_rng(5)
    e = lfilter([1.0], [1.0, -0.6], rng.standard_normal(20000))
    assert _stats(e)["decorrelation_lag"] == 2


def _avg_acf(m, lags):
    """ACF of the third difference of a trailing mean of m white samples (on paper: the
    autocorrelation of the filter ones(m) * [1, -3, 3, -1])."""
    h = np.convolve(np.ones(m), [1.0, -3.0, 3.0, -1.0])
    a = np.correlate(h, h, "full")[len(h) - 1 :]
    a = np.concatenate([a, np.zeros(lags + 2)])
    return a / a[0]


@pytest.mark.parametrize("m", [2, 3, 5])
def test_interval_averaging_dip(m):
    """A trailing mean of m samples: the third difference's ACF dips at lag m (-0.4 for
    m = 2, -0.5 from m = 3), between lobes at m - 1 and m + 1 (m = 3: 0.5 and 1/3; m = 5:
    1/3 and 1/3); at the first lag searched (m = 2) only the lobe after it counts (the
    lag-1 value, -0.4, belongs to the differencing)."""
    rng = np.random.default_rng(10 + m)
    pv = lfilter(np.ones(m) / m, [1.0], rng.standard_normal(20000))
    r = _avg_acf(m, 14)
    assert r[m] == pytest.approx(-0.4 if m == 2 else -0.5)
    s = _stats(pv)
    assert s["averaging_lag"] == m
    assert s["diff_acf_min"] == pytest.approx(r[m], abs=0.03)
    if m == 2:
        want = r[2] - r[3]  # -0.8 (with the lag-1 value it would be 0)
    else:
        want = r[m] - (r[m - 1] + r[m + 1]) / 2  # -0.917 for m = 3, -0.833 for m = 5
    assert s["pv_averaging_contrast"] == pytest.approx(want, abs=0.04)
    assert s["averaging_contrast"] == s["pv_averaging_contrast"]  # no OP: PV's


def test_averaging_contrast_needs_pv_and_op_at_the_same_lag():
    rng = np.random.default_rng(20)
    n = 20000
    pv = lfilter(np.ones(4) / 4, [1.0], rng.standard_normal(n))
    op4 = 50 + lfilter(np.ones(4) / 4, [1.0], rng.standard_normal(n))
    op7 = 50 + lfilter(np.ones(7) / 7, [1.0], rng.standard_normal(n))
    alone = _stats(pv)["pv_averaging_contrast"]
    op_alone = _stats(op4)["pv_averaging_contrast"]  # OP's own contrast, read as a PV
    s = _stats(pv, op4)
    assert s["pv_averaging_contrast"] == alone
    assert s["averaging_contrast"] == max(alone, op_alone)  # the weaker of the two
    s = _stats(pv, op7)
    assert s["pv_averaging_contrast"] == alone and s["averaging_contrast"] == 0.0


# ---- repeats, holds, grid, compression ---------------------------------------------------------


def test_repeat_fractions_are_exact_shares():
    """1001 samples, 300 of the 1000 differences zero: pv_repeat_fraction 0.3; OP frozen on
    100 others, 50 shared: row repeats 0.05."""
    rng = np.random.default_rng(6)
    n = 1001
    pv, op = rng.standard_normal(n), 50 + rng.standard_normal(n)
    pv_rep = np.zeros(n - 1, dtype=bool)
    pv_rep[rng.choice(n - 1, 300, replace=False)] = True
    pv_idx = np.flatnonzero(pv_rep)
    op_rep = np.zeros(n - 1, dtype=bool)
    op_rep[pv_idx[:50]] = True
    op_rep[rng.choice(np.flatnonzero(~pv_rep), 50, replace=False)] = True
    for k in range(n - 1):  # sample k + 1 repeats sample k
        if pv_rep[k]:
            pv[k + 1] = pv[k]
        if op_rep[k]:
            op[k + 1] = op[k]
    s = _stats(pv, op)
    assert s["pv_repeat_fraction"] == 0.3
    assert s["op_repeat_fraction"] == 0.1
    assert s["row_repeat_fraction"] == 0.05
    assert s["joint_repeat_excess"] == pytest.approx(0.05 - 0.3 * 0.1)
    assert st._repeat_fractions(_loop(pv, op)[0]) == (0.3, 0.1)
    assert st._repeat_fractions(_loop(pv)[0])[0] == 0.3
    assert np.isnan(st._repeat_fractions(_loop(pv)[0])[1])


def test_held_rows_count_runs_of_two_or_more():
    """Rows held (PV and OP together) for 1 and for 3 extra samples, 10 of each, in 1000
    samples: hold_fraction counts only the runs of 2 or more: 30 / 999; their mean length
    over all coincident runs is 2."""
    rng = np.random.default_rng(7)
    n = 1000
    x = np.stack([rng.standard_normal(n), 50 + rng.standard_normal(n)], axis=-1)
    for s in range(50, 450, 40):
        x[s + 1] = x[s]
    for s in range(500, 900, 40):
        x[s + 1 : s + 4] = x[s]
    stats = _stats(x[:, 0], x[:, 1])
    assert stats["hold_fraction"] == pytest.approx(30 / 999)
    assert stats["hold_run_length"] == pytest.approx(2.0)
    assert stats["row_repeat_fraction"] == pytest.approx(40 / 999)
    assert stats["independent_freeze"] == 0.0
    # only runs of 2 repeats: all counted
    y = np.stack([rng.standard_normal(n), rng.standard_normal(n)], axis=-1)
    for s in range(50, 950, 30):
        y[s + 1 : s + 3] = y[s]
    stats = _stats(y[:, 0], y[:, 1])
    assert stats["hold_fraction"] == pytest.approx(60 / 999)
    assert stats["hold_run_length"] == 2.0


def test_quantised_signal_on_a_half_grid():
    rng = np.random.default_rng(8)
    t = np.arange(3000)
    raw = 5 * np.sin(2 * np.pi * t / 300) + 0.7 * rng.standard_normal(len(t))
    pv = 0.5 * np.round(raw / 0.5)
    op = 50 + rng.standard_normal(len(t))
    s = _stats(pv, op)
    assert s["pv_step"] == pytest.approx(0.5 / _span(pv))
    same = np.diff(pv) == 0
    distinct = len(np.unique(pv))
    assert s["pv_level_reuse"] == pytest.approx(1 - distinct / ((~same).sum() + 1))
    assert s["pv_level_reuse"] > 0.9
    assert s["independent_freeze"] == 0.0  # jumps are whole steps: a grid, not compression
    assert s["op_level_reuse"] == 0.0  # continuous: every value new
    # the smallest change ignores float dust below 1e-12 of the range
    dusty = pv.copy()
    dusty[::7] += 1e-14
    assert _stats(dusty, op)["pv_step"] == pytest.approx(0.5 / _span(pv), rel=1e-9)


def test_level_reuse_of_a_triangle_over_three_levels():
    pv = np.array([0.0, 1.0, 2.0, 1.0] * 25)  # 99 changes, 3 distinct values
    assert _stats(pv)["pv_level_reuse"] == 1 - 3 / 100


def test_compression_band_and_independent_freeze():
    """Blocks of 5 equal samples at levels 0, 1, 2.7, 1 (repeating): 99 runs of 4 repeats end
    by jumps 1, 1.7, 1.7, 1, ...; the smallest change is 1, so the 50 runs ended by 1.7 are off
    the grid (compression), the 49 ended by 1 on it. Span 2.7."""
    levels = np.array([0.0, 1.0, 2.7, 1.0])
    pv = np.repeat(np.tile(levels, 25), 5)
    rng = np.random.default_rng(9)
    op = 50 + rng.standard_normal(len(pv))  # moves on every sample: no runs
    s = _stats(pv, op)
    assert _span(pv) == pytest.approx(2.7)
    assert s["pv_band"] == pytest.approx(1.0 / 2.7)  # 10th percentile of the ending jumps
    assert s["op_band"] == 0.0  # fewer than 3 runs
    assert s["pv_step"] == pytest.approx(1.0 / 2.7)
    assert s["independent_freeze"] == pytest.approx(0.5 * 4 * 50 / 499)
    assert s["hold_fraction"] == 0.0 and np.isnan(s["hold_run_length"])
    assert s["spike_rate"] == 0.0  # steps are no spikes
    # equal jumps only: all on the grid
    pv2 = np.repeat(np.tile([0.0, 1.0, 2.0, 1.0], 25), 5)
    assert _stats(pv2, op)["independent_freeze"] == 0.0
    assert _stats(pv2, op)["pv_band"] == pytest.approx(1.0 / 2.0)
    # two frozen runs only: no band
    pv3 = rng.standard_normal(300)
    pv3 = _hold(pv3, [50, 200], 5)
    assert _stats(pv3)["pv_band"] == 0.0


def test_off_grid_tolerance_is_a_thousandth_of_the_step():
    """Runs ended by jumps of 1 and of 1.0015 (0.15 % off the grid of the smallest change,
    above the 0.1 % tolerance): the latter count as compression."""
    levels = np.array([0.0, 1.0, 2.0015, 1.0015])  # jumps 1, 1.0015, -1, -1.0015
    pv = np.repeat(np.tile(levels, 25), 5)  # 99 ended runs of 4 repeats, 49 by 1.0015
    op = 50 + np.random.default_rng(22).standard_normal(len(pv))
    assert _stats(pv, op)["independent_freeze"] == pytest.approx(0.5 * 4 * 49 / 499)
    on_grid = np.repeat(np.tile([0.0, 1.0, 2.0005, 1.0005], 25), 5)  # 0.05 %: on the grid
    assert _stats(on_grid, op)["independent_freeze"] == 0.0


# ---- spikes ---------------------------------------------------------------------------------


def test_one_spike_of_50_sd_is_counted_once():
    rng = np.random.default_rng(11)
    n = 2000
    t = np.arange(n)
    base = 10 * np.sin(2 * np.pi * t / 400) + rng.standard_normal(n)
    op = 50 + 5 * np.sin(2 * np.pi * t / 400) + 0.5 * rng.standard_normal(n)
    clean = _stats(base, op)
    assert clean["spike_rate"] == 0.0 and np.isnan(clean["spike_size"])
    pv = base.copy()
    pv[1000] += 50.0
    s = _stats(pv, op)
    assert s["spike_rate"] == 1 / n
    med = np.median(pv[999:1002])
    assert s["spike_size"] == pytest.approx((pv[1000] - med) / s["pv_span"])
    assert s["spike_size"] == pytest.approx(50 / s["pv_span"], rel=0.1)
    # the spike is replaced before the noise is measured
    assert s["pv_noise"] == pytest.approx(clean["pv_noise"], rel=0.01)
    assert s["op_noise"] == pytest.approx(0.5, rel=0.1)
    assert s["op_noise_level"] == s["op_noise"] / s["op_span"]
    # one in OP as well: two spikes
    op2 = op.copy()
    op2[300] -= 40.0
    assert _stats(pv, op2)["spike_rate"] == 2 / n
    # a step (a setpoint move) of the same height is no spike
    step = base + 50.0 * (t >= 1000)
    assert _stats(step, op)["spike_rate"] == 0.0


def test_spike_inside_a_frozen_run_does_not_break_it():
    rng = np.random.default_rng(12)
    pv = rng.standard_normal(1000)
    pv = _hold(pv, [400], 20)  # 20 repeats
    base_rep = _stats(pv)["pv_repeat_fraction"]
    assert base_rep == pytest.approx(20 / 999)
    pv[410] += 100.0
    s = _stats(pv)
    assert s["spike_rate"] == 1 / 1000
    assert s["pv_repeat_fraction"] == base_rep


# ---- drift, setpoint, oscillation, PV-OP ----------------------------------------------------


def test_drift_of_a_ramp_on_a_symmetric_cosine():
    """x = a t + cos(2 pi (t - tc) / P), even about the centre tc: the fitted slope is a, the
    detrended signal the cosine, whose 5-95 % range is 2 cos(0.05 pi)."""
    n, a = 4000, 0.002
    t = np.arange(n)
    c = np.cos(2 * np.pi * (t - (n - 1) / 2) / 200)
    s = _stats(a * t + c, 50 - 3 * a * t + c, np.zeros(n))
    want = a * n / (2 * np.cos(0.05 * np.pi))
    assert s["pv_drift"] == pytest.approx(want, rel=0.01)
    assert s["op_drift"] == pytest.approx(3 * want, rel=0.01)
    s = _stats(c, 50 + c, np.zeros(n))
    assert s["pv_drift"] == pytest.approx(0.0, abs=1e-9)
    assert s["op_drift"] == pytest.approx(0.0, abs=1e-9)


def test_setpoint_steps_size_and_offset():
    rng = np.random.default_rng(13)
    n = 1001
    pv = rng.standard_normal(n)
    sp = np.zeros(n)
    for k in (200, 400, 600, 800):  # four moves of 2
        sp[k:] += 2.0 if k != 600 else -2.0
    s = _stats(pv + sp + 0.5, 50 + pv, sp)
    span = s["pv_span"]
    assert s["sp_change_fraction"] == 4 / 1000
    assert s["sp_steps"] == 4.0
    assert s["sp_step_size"] == pytest.approx(2.0 / span)
    assert s["sp_offset"] == pytest.approx((np.median(pv) + 0.5) / span)
    # a fixed setpoint: no moves, size 0
    s = _stats(pv, 50 + pv, np.full(n, 3.0))
    assert s["sp_change_fraction"] == 0.0 and s["sp_steps"] == 0.0 and s["sp_step_size"] == 0.0
    # exactly 20 % of samples changed: still steps; above: a cascade setpoint (NaN)
    sp20 = np.zeros(101)
    sp20[1:] = np.cumsum(np.arange(100) % 5 == 0)  # 20 changes in 100 differences
    s = _stats(rng.standard_normal(101), sp=sp20)
    assert s["sp_change_fraction"] == 0.2 and s["sp_steps"] == 20.0
    # round-off on a large setpoint (1e-10 of its size) is no move
    big = 1e6 + np.zeros(1001)
    big[::3] += 1e-4
    s = _stats(1e6 + rng.standard_normal(1001), sp=big)
    assert s["sp_change_fraction"] == 0.0 and s["sp_steps"] == 0.0
    sp21 = sp20.copy()
    sp21[50:] += 0.5 * (np.arange(51) % 5 == 2)  # more changes
    s = _stats(rng.standard_normal(101), sp=sp21)
    assert s["sp_change_fraction"] > 0.2 and np.isnan(s["sp_steps"])


def _square(halves, start=1.0):
    """+-1 square wave from a list of half-period lengths."""
    sign = start * (-1.0) ** np.arange(len(halves))
    return np.repeat(sign, halves)


def test_oscillation_of_a_square_wave():
    """A +-1 square wave of period 40 symmetric about its centre (mean 0, no trend, 400
    samples): r_40 = 360 / 400 = 0.9; r_k = (400 - 41 k) / 400 for k <= 10, below 0.5 first at
    k = 5; zero crossings every 20 samples: regularity 10 (no spread)."""
    x = _square([10] + [20] * 19 + [10])
    assert len(x) == 400 and x.sum() == 0
    s = _stats(x, sp=np.zeros(400))
    assert s["period"] == 40.0
    assert s["acf_peak"] == pytest.approx(0.9)
    assert s["decorrelation_lag"] == 5.0
    assert s["regularity"] == 10.0


def test_regularity_of_irregular_half_periods():
    """Half periods 10, 20, 30 (repeated 10 times): full periods between alternate crossings
    30, 50, 40, ...: mean 40, sd sqrt(200 / 3); r = 40 / (3 sd)."""
    halves = [10, 20, 30] * 10
    x = _square(halves)
    zc = np.cumsum(halves)[:-1]
    full = zc[2:] - zc[:-2]
    assert full.mean() == 40 and full.std() == pytest.approx(np.sqrt(200 / 3))
    s = _stats(x)
    assert s["regularity"] == pytest.approx(40 / (3 * np.sqrt(200 / 3)))


def test_regularity_of_nearly_regular_half_periods():
    """Half periods 20, 20, 21: full periods 40, 41, 41, ...: mean 40.67, sd 0.471 (below one
    sample, still a spread): r = 40.67 / 1.414 = 28.8."""
    halves = [20, 20, 21] * 10
    zc = np.cumsum(halves)[:-1]
    full = zc[2:] - zc[:-2]
    assert full.std() == pytest.approx(np.sqrt(2) / 3)
    s = _stats(_square(halves))
    assert s["regularity"] == pytest.approx(full.mean() / (3 * full.std()))


def test_oscillation_statistics_ignore_a_ramp():
    """White noise: no positive lobe of note, ACF below 0.5 from lag 1; a ramp and an offset
    added to the error are detrended away (the oscillation columns do not move)."""
    rng = np.random.default_rng(14)
    e = rng.standard_normal(4000)
    s = _stats(e)
    assert s["acf_peak"] < 0.1 and s["decorrelation_lag"] == 1
    ramped = _stats(e + 0.01 * np.arange(4000) - 30.0)
    for col in ("acf_peak", "period", "regularity", "decorrelation_lag"):
        assert ramped[col] == pytest.approx(s[col], rel=1e-6, nan_ok=True), col
    # slope 0.01 over 4000 samples (plus the noise's own chance slope, ~1e-5)
    assert ramped["pv_drift"] == pytest.approx(40.0 / s["error_span"], rel=0.01)


@pytest.mark.parametrize("delay", [0, 4, -3])
def test_pv_op_lag_of_a_delayed_copy(delay):
    """PV[t] = OP[t - delay] (PV after OP: positive lag), OP a slow smooth random signal."""
    rng = np.random.default_rng(15)
    n = 3000
    u = lfilter([0.1], [1.0, -0.9], rng.standard_normal(n + 20))
    op = 50 + u[10 : 10 + n]
    pv = u[10 - delay : 10 - delay + n]
    s = _stats(pv, op, np.zeros(n))
    assert s["pv_op_lag"] == delay
    assert s["pv_op_max_corr"] == pytest.approx(1.0, abs=5e-3)  # edges: n - |delay| pairs
    if delay == 0:
        assert s["pv_op_corr"] == pytest.approx(1.0)
    else:
        assert s["pv_op_corr"] < s["pv_op_max_corr"]
    anti = _stats(pv, 50 - (op - 50), np.zeros(n))  # reverse acting: |corr| still 1
    assert anti["pv_op_max_corr"] == pytest.approx(1.0, abs=5e-3)
    assert anti["pv_op_lag"] == delay


def test_op_saturation_share():
    rng = np.random.default_rng(16)
    n = 1000
    op = 30 + 20 * rng.random(n)
    op[:100] = 0.0  # 10 % closed
    op[500:540] = 100.0  # 4 % open
    op[600:610] = 99.7  # 1 % within 0.5 of open
    s = _stats(rng.standard_normal(n), op)
    assert s["op_saturation"] == pytest.approx(0.15)
    # OP not in percent (outside -1..101): no saturation share
    assert np.isnan(_stats(rng.standard_normal(n), 1000 + op)["op_saturation"])
    assert np.isnan(_stats(rng.standard_normal(n), op - 50)["op_saturation"])
    # the percent test allows 1 % over-range: 100.8 is still percent, 101.5 not
    # (3 samples: a single one would be a spike, replaced before the share is taken)
    over = op.copy()
    over[700:703] = 100.8
    assert _stats(rng.standard_normal(n), over)["op_saturation"] == pytest.approx(0.153)
    over[700:703] = 101.5
    assert np.isnan(_stats(rng.standard_normal(n), over)["op_saturation"])


# ---- invariances ----------------------------------------------------------------------------

# columns in units of a span, a share of samples, samples, or a correlation
DIMENSIONLESS = [
    "noise_level", "op_noise_level", "noise_colour", "diff_acf_min", "averaging_lag",
    "averaging_contrast", "pv_averaging_contrast", "pv_repeat_fraction", "op_repeat_fraction",
    "row_repeat_fraction", "joint_repeat_excess", "hold_fraction", "hold_run_length",
    "independent_freeze", "pv_level_reuse", "op_level_reuse", "pv_step", "pv_band", "op_band",
    "spike_rate", "spike_size", "pv_drift", "op_drift", "sp_change_fraction", "sp_steps",
    "sp_step_size", "sp_offset", "acf_peak", "period", "regularity", "decorrelation_lag",
    "pv_op_corr", "pv_op_max_corr", "pv_op_lag",
]  # fmt: skip


def _busy_loop():
    """A loop with a bit of everything: oscillation, drift, grid PV, compressed OP, held
    rows, spikes, setpoint steps."""
    rng = np.random.default_rng(17)
    n = 3000
    t = np.arange(n)
    sp = 2.0 * (t >= 1000) - 1.0 * (t >= 2200)
    pv = sp + np.sin(2 * np.pi * t / 150) + 0.001 * t + 0.1 * rng.standard_normal(n)
    pv = 0.05 * np.round(pv / 0.05)
    op = 40 + 5 * np.sin(2 * np.pi * (t - 20) / 150) + 0.2 * rng.standard_normal(n)
    last = op[0]
    for k in range(n):  # deadband compression of OP
        if abs(op[k] - last) > 0.3:
            last = op[k]
        op[k] = last
    x = np.stack([pv, op, sp], axis=-1)
    for s in range(300, 2800, 250):  # held rows
        x[s + 1 : s + 6] = x[s]
    x[1500, 0] += 8.0  # spikes
    x[700, 1] -= 30.0
    return x


@pytest.mark.parametrize("scale, shift", [(1e-3, 7.0), (1e-7, 0.0), (250.0, -40.0)])
def test_scale_and_shift_leave_relative_statistics(scale, shift):
    x = _busy_loop()
    base = loop_statistics(x[None]).iloc[0]
    y = x.copy()
    y[:, [0, 2]] = scale * x[:, [0, 2]] + shift  # PV and SP share units
    y[:, 1] = 0.3 * scale * x[:, 1] - shift
    s = loop_statistics(y[None]).iloc[0]
    for col in DIMENSIONLESS:
        assert s[col] == pytest.approx(base[col], rel=1e-6, abs=1e-9, nan_ok=True), col
    for col in ("pv_span", "error_span", "pv_noise"):
        assert s[col] == pytest.approx(scale * base[col], rel=1e-6), col
    for col in ("op_span", "op_noise"):
        assert s[col] == pytest.approx(0.3 * scale * base[col], rel=1e-6), col
    # the loop's statistics are not trivial
    assert base["spike_rate"] == 2 / 3000 and base["hold_fraction"] > 0.001
    assert base["independent_freeze"] > 0.05 and base["sp_steps"] == 2
    assert base["period"] == pytest.approx(150, abs=3)


# ---- NaN, short and constant records, input forms --------------------------------------------


def test_nan_gap_is_bridged_linearly_and_counted():
    rng = np.random.default_rng(18)
    n = 500
    t = np.arange(n)
    pv = np.sin(2 * np.pi * t / 50) + 0.1 * rng.standard_normal(n)
    op = 50 + np.sin(2 * np.pi * t / 50) + 0.1 * rng.standard_normal(n)
    gappy_pv, gappy_op = pv.copy(), op.copy()
    gappy_pv[100:110] = np.nan
    gappy_op[300:305] = np.nan
    filled_pv, filled_op = pv.copy(), op.copy()
    filled_pv[100:110] = np.linspace(pv[99], pv[110], 12)[1:-1]
    filled_op[300:305] = np.linspace(op[299], op[305], 7)[1:-1]
    sp = np.zeros(n)
    gappy = _stats(gappy_pv, gappy_op, sp)
    filled = _stats(filled_pv, filled_op, sp)
    assert gappy["nan_fraction"] == 15 / 1000 and filled["nan_fraction"] == 0.0
    for col in STATISTIC_COLUMNS:
        if col != "nan_fraction":
            assert gappy[col] == pytest.approx(filled[col], rel=1e-9, nan_ok=True), col


def test_nan_at_the_record_edges_is_no_frozen_run():
    """White noise whose first 100 rows (PV and OP) are missing: nothing repeats, as for the
    same gap inside the record (bridged linearly: no repeats, no hold). Extended flat, as
    they once were, the missing rows gave 100 repeats in both tags, hold_fraction 0.1 and
    hold_run_length 100 (a historian hold), and the applicability check's repeat shares
    (_repeat_fractions) 0.1. Missing edge rows (OP's last ones too) leave every statistic
    but the record's length and NaN share as the record without them gives."""
    rng = np.random.default_rng(23)
    n = 1000
    x = np.stack([rng.standard_normal(n), 50 + rng.standard_normal(n), np.zeros(n)], -1)
    inner = x.copy()
    inner[400:500, :2] = np.nan
    s = loop_statistics(inner[None]).iloc[0]
    assert s["pv_repeat_fraction"] == 0.0 and s["hold_fraction"] == 0.0
    lead = x.copy()
    lead[:100, :2] = np.nan
    s = loop_statistics(lead[None]).iloc[0]
    assert s["nan_fraction"] == 0.1
    assert st._repeat_fractions(lead) == (0.0, 0.0)
    assert s["pv_repeat_fraction"] == 0.0 and s["op_repeat_fraction"] == 0.0
    assert s["hold_fraction"] == 0.0
    tail = lead.copy()
    tail[-50:, 1] = np.nan  # OP's transmitter lost for the last 50 rows
    assert st._repeat_fractions(tail) == (0.0, 0.0)
    with_edges = loop_statistics(tail[None]).iloc[0]
    without = loop_statistics(x[None, 100:-50]).iloc[0]
    assert with_edges["n_samples"] == n and with_edges["nan_fraction"] == 0.125
    for col in STATISTIC_COLUMNS:
        if col not in ("n_samples", "nan_fraction"):
            assert with_edges[col] == pytest.approx(without[col], rel=1e-12, nan_ok=True), col


def test_constant_and_short_loops():
    x = np.full((6, 100, 3), np.nan)
    x[0, :, :] = [5.0, 40.0, 5.0]  # every channel constant (100 samples: FFT path of the ACF)
    x[1, :5] = np.arange(15.0).reshape(5, 3)  # 5 samples: too short for statistics
    # x[2]: empty (all NaN)
    x[3, :60, 0] = np.arange(60.0)  # a ramp PV: no noise, no repeats
    x[4, :8] = [[0, 50, 0], [3, 52, 0], [1, 49, 0], [4, 51, 0], [2, 50, 0], [5, 53, 0],
                [0, 48, 0], [6, 50, 0]]  # fmt: skip
    x[5, :7] = x[4, :7]  # one sample fewer than the 8 needed
    with np.errstate(all="raise"):
        s = loop_statistics(x, ts=2.0)
    assert s["n_samples"].tolist() == [100, 5, 0, 60, 8, 7]
    assert s["ts"].tolist() == [2.0] * 6  # reported for every loop, empty ones too
    assert s["has_op"].dtype == bool and s["has_sp"].dtype == bool
    assert s["has_op"].tolist() == [True, True, False, False, True, True]
    assert s["has_sp"].tolist() == [True, True, False, False, True, True]
    c = s.iloc[0]
    assert c["pv_repeat_fraction"] == 1.0 and c["op_repeat_fraction"] == 1.0
    assert c["row_repeat_fraction"] == 1.0 and c["pv_span"] == 0.0
    assert c["pv_noise"] == 0.0 and c["spike_rate"] == 0.0 and np.isnan(c["spike_size"])
    assert np.isnan(c["pv_level_reuse"]) and np.isnan(c["pv_step"]) and np.isnan(c["pv_band"])
    assert np.isnan(c["noise_level"]) and np.isnan(c["op_noise_level"])
    assert np.isnan(c["noise_colour"]) and np.isnan(c["pv_op_corr"])
    assert np.isnan(c["acf_peak"]) and np.isnan(c["decorrelation_lag"])  # no ACF of zeros
    assert c["sp_steps"] == 0.0 and c["sp_offset"] != c["sp_offset"]  # span 0: NaN
    stat_cols = [col for col in STATISTIC_COLUMNS if col not in
                 ("n_samples", "ts", "has_op", "has_sp", "nan_fraction")]  # fmt: skip
    for i in (1, 2, 5):  # too short / empty: only the length and flags
        assert s.loc[i, stat_cols].astype(float).isna().all()
    assert s[stat_cols].dtypes.map(lambda d: d.kind == "f").all()
    assert s.loc[1, "nan_fraction"] == 0.0
    r = s.iloc[3]
    assert r["pv_noise"] == 0.0 and r["pv_repeat_fraction"] == 0.0
    assert r["pv_drift"] != r["pv_drift"]  # nothing left after the trend: NaN
    assert np.isnan(r["noise_colour"])  # zero second differences: no colour
    assert r["pv_step"] == pytest.approx(1.0 / _span(np.arange(60.0)))
    assert r["pv_level_reuse"] == 0.0
    # 8 samples are enough: PV 0 3 1 4 2 5 0 6
    e = s.iloc[4]
    assert e["pv_repeat_fraction"] == 0.0 and e["pv_level_reuse"] == pytest.approx(1 - 7 / 8)
    assert e["pv_span"] == pytest.approx(_span(x[4, :8, 0]))


def test_flat_line_with_one_glitch_and_signed_zeros():
    """A flat line (zero 5-95 % span) with one glitch: no spike is measured (its size would be
    a share of a zero span) and nothing divides by zero; a zero signal mixing +0.0 and -0.0
    has a plain +0.0 span."""
    pv = np.full(200, 3.0)
    pv[100] = 8.0
    with np.errstate(all="raise"):
        s = _stats(pv, np.full(200, 40.0), np.full(200, 3.0))
    assert s["pv_span"] == 0.0 and s["spike_rate"] == 0.0 and np.isnan(s["spike_size"])
    z = np.zeros(26)
    z[[3, 4, 7, 8, 9, 11, 14, 16, 18, 20, 22, 23, 24]] = -0.0
    s = _stats(z, 50 + z, z)
    for col in ("pv_span", "error_span"):
        assert s[col] == 0.0 and not np.signbit(s[col]), col


def test_sample_time_from_argument_bunch_or_nothing():
    rng = np.random.default_rng(19)
    X = rng.standard_normal((2, 100, 3))
    assert loop_statistics(X)["ts"].isna().all()
    assert loop_statistics(X)["ts"].dtype == np.float64
    assert loop_statistics(X, ts=2.5)["ts"].tolist() == [2.5, 2.5]
    assert loop_statistics(X, ts=[1.0, 3.0])["ts"].tolist() == [1.0, 3.0]
    bunch = Bunch(X=X, meta=pd.DataFrame({"ts": [0.5, 4.0]}))
    from_bunch = loop_statistics(bunch)
    assert from_bunch["ts"].tolist() == [0.5, 4.0]
    assert loop_statistics(bunch, ts=9.0)["ts"].tolist() == [9.0, 9.0]
    pd.testing.assert_frame_equal(
        from_bunch.drop(columns="ts"), loop_statistics(X).drop(columns="ts")
    )
    no_ts = Bunch(X=X, meta=pd.DataFrame({"name": ["a", "b"]}))
    assert loop_statistics(no_ts)["ts"].isna().all()


# ---- more known answers: error, SP gaps, bands, colour limits, oscillation shapes ----------


def test_error_is_pv_minus_sp():
    """PV tracks an SP of large steps plus white noise: the error is the noise (its span
    about 2 * 1.645 sd), not PV's range; noise_level is pv_noise over that span."""
    rng = np.random.default_rng(30)
    n = 4000
    sp = 20.0 * (np.arange(n) // 1000 % 2)
    noise = rng.standard_normal(n)
    s = _stats(sp + noise, sp=sp)
    assert s["error_span"] == pytest.approx(_span(noise))
    assert s["error_span"] == pytest.approx(2 * 1.645, rel=0.05)
    assert s["pv_span"] > 20
    assert s["noise_level"] == pytest.approx(s["pv_noise"] / _span(noise))
    assert abs(s["pv_drift"]) < 0.2 and s["decorrelation_lag"] == 1


def test_nan_in_sp_and_a_pv_only_loop():
    rng = np.random.default_rng(31)
    n = 600
    pv = rng.standard_normal(n)
    sp = 3.0 * (np.arange(n) >= 300)
    gappy = sp.copy()
    gappy[290:310] = np.nan  # the step falls inside the gap: bridged linearly
    s = _stats(pv, 50 + pv, gappy)
    assert s["sp_change_fraction"] == 21 / 599  # the bridge moves on 21 samples
    assert s["sp_steps"] == 21.0 and s["sp_step_size"] == pytest.approx(3 / 21 / s["pv_span"])
    assert s["nan_fraction"] == 0.0  # SP gaps are not counted
    # without OP, nan_fraction is PV's share alone
    only = pv.copy()
    only[:60] = rng.standard_normal(60)
    only[100:160] = np.nan
    assert _stats(only)["nan_fraction"] == 0.1


def test_sp_step_size_of_a_flat_pv_is_zero():
    pv = np.full(300, 4.0)
    sp = 4.0 + (np.arange(300) >= 150)
    with np.errstate(all="raise"):
        s = _stats(pv, np.full(300, 30.0), sp)
    assert s["sp_steps"] == 1.0 and s["sp_step_size"] == 0.0 and np.isnan(s["sp_offset"])


def test_op_percent_detection_and_saturation_bounds():
    """OP in percent: min >= -1, max <= 101, mean > 2; saturated at <= 0.5 or >= 99.5 (both
    bounds included). Plateaus of 3 samples (one sample would be a spike)."""
    rng = np.random.default_rng(32)
    n = 1000
    pv = rng.standard_normal(n)
    op = 40 + 10 * rng.random(n)
    op[100:103] = 0.5  # counted
    op[200:203] = 99.5  # counted
    op[300:303] = 1.0  # not counted
    assert _stats(pv, op)["op_saturation"] == pytest.approx(0.006)
    for lo, hi, pct in [(-1.0, 50, True), (-1.5, 50, False), (10, 101.0, True)]:
        o = op.copy()
        o[500:503], o[600:603] = lo, hi
        got = _stats(pv, o)["op_saturation"]
        assert np.isfinite(got) == pct, (lo, hi)
    # a valve closed most of the time: mean 2.5 % is percent, mean exactly 2 % is not
    closed = np.zeros(n)
    closed[:25] = 100.0
    assert _stats(pv, closed)["op_saturation"] == 1.0
    closed[20:25] = 0.0
    assert np.isnan(_stats(pv, closed)["op_saturation"])


def test_pv_op_lag_searched_within_three_periods_or_a_quarter_record():
    """Without oscillation (a bump) the lag is searched up to n / 4: a delay of 90 in 400
    samples is found. With a period P the search stops at 3 P: a sine of period 40 plus a
    bump, PV delayed by 130 (beyond 120), gives the in-window alignment 90 (130 - 40)."""
    n = 400
    t = np.arange(n)

    def bump(c):
        return np.exp(-(((t - c) / 15) ** 2))

    s = _stats(bump(240), 50 + bump(150), np.zeros(n))
    assert np.isnan(s["period"])
    assert s["pv_op_lag"] == 90 and s["pv_op_max_corr"] > 0.95
    n = 2000
    t = np.arange(n)

    def u(d):
        return np.sin(2 * np.pi * (t - d) / 40) + 3 * np.exp(-(((t - d - 900) / 30) ** 2))

    s = _stats(u(130), 50 + u(0), np.zeros(n))
    assert s["period"] == 40 and s["pv_op_lag"] == 90


def test_xcorr_removes_means_and_detrend_of_two_samples():
    rng = np.random.default_rng(33)
    a, b = rng.standard_normal(300), rng.standard_normal(300)
    assert st._xcorr(a + 5.0, b - 100.0, 6) == pytest.approx(st._xcorr(a, b, 6))
    _, slope = st._detrend(np.array([1.0, 3.0]))
    assert slope == 2.0


def test_level_reuse_of_a_single_step():
    # one change, two values: 1 - 2 / 2 = 0
    assert _stats(np.repeat([0.0, 1.0], 50))["pv_level_reuse"] == 0.0


def test_band_of_known_jumps():
    """White noise frozen in 10 runs of 5, each ended by a jump of 1, 2, ..., 10: the 10th
    percentile of the jumps is 1.9 (linear between the two smallest); the first sample is
    fresh. Three runs are enough for a band."""

    def frozen(x, starts, jumps):
        x = x.copy()
        for s, jump in zip(starts, jumps, strict=True):
            x[s + 1 : s + 6] = x[s]
            x[s + 6 :] += x[s] + jump - x[s + 6]  # a level shift: no spike
        return x

    rng = np.random.default_rng(34)
    x = frozen(rng.standard_normal(1200), range(100, 1100, 100), range(1, 11))
    assert _stats(x)["pv_band"] == pytest.approx(1.9 / _span(x))
    y = frozen(rng.standard_normal(600), (100, 250, 400), (2.0, 2.0, 2.0))
    assert _stats(y)["pv_band"] == pytest.approx(2.0 / _span(y))


def test_multi_step_jumps_keep_a_relative_tolerance():
    """Jumps of 1 and 5.002 steps: 0.002 off, within 1e-3 of 5 steps: on the grid."""
    levels = np.array([0.0, 1.0, 6.002, 5.002])  # jumps 1, 5.002, -1, -5.002
    pv = np.repeat(np.tile(levels, 25), 5)
    op = 50 + np.random.default_rng(35).standard_normal(len(pv))
    assert _stats(pv, op)["independent_freeze"] == 0.0


def test_tiny_units_keep_the_grid():
    """A quantised PV in units of 1e-13 keeps its step (the rounding floor is relative)."""
    rng = np.random.default_rng(36)
    pv = 0.5 * np.round(rng.standard_normal(500) * 3 / 0.5)
    s = _stats(pv)
    tiny = _stats(1e-13 * pv)
    assert tiny["pv_step"] == pytest.approx(s["pv_step"]) and s["pv_step"] == pytest.approx(
        0.5 / _span(pv)
    )
    assert tiny["pv_level_reuse"] == s["pv_level_reuse"]


def test_noise_colour_ignores_a_constant_curvature():
    """White noise on a parabola: the second difference is noise plus a constant 0.5, which
    the median takes out; the colour stays white."""
    rng = np.random.default_rng(37)
    n = 20000
    t = np.arange(n)
    s = _stats(rng.standard_normal(n) + 0.25 * (t - n / 2) ** 2)
    assert abs(s["noise_colour"]) < 0.08
    assert s["pv_noise"] == pytest.approx(1.0, rel=0.05)


def test_noise_colour_is_clipped_to_plus_minus_one():
    """AR(1) with phi = -0.9: r1 of d2 = -0.963 (formula above), colour -1.78, clipped to -1.
    Integrated AR(1) with phi = 0.9: d2 is the first difference of the AR(1), r1 = -(1 - phi)
    / 2 = -0.05, colour 3.7, clipped to 1."""
    rng = np.random.default_rng(38)
    e = rng.standard_normal(20000)
    assert _stats(lfilter([1.0], [1.0, 0.9], e))["noise_colour"] == -1.0
    assert _stats(np.cumsum(lfilter([1.0], [1.0, -0.9], e)))["noise_colour"] == 1.0


def test_fresh_bursts_between_long_holds():
    """Bursts of 5 fresh samples between runs of 15 repeats: two fresh third differences
    per burst (each spans 3 fresh first differences), 20 samples apart: no pairs at lags
    2-13, so no averaging dip (NaN), and no division warnings; the colour still has its
    pairs within the bursts."""
    rng = np.random.default_rng(39)
    bursts = rng.standard_normal((60, 5))
    pv = np.concatenate([np.concatenate([b, np.full(15, b[-1])]) for b in bursts])
    with np.errstate(all="raise"):
        s = _stats(pv)
    assert s["pv_repeat_fraction"] == pytest.approx(15 * 60 / (len(pv) - 1), abs=1e-3)
    assert np.isnan(s["averaging_lag"]) and np.isnan(s["diff_acf_min"])
    assert np.isfinite(s["noise_colour"])
    # 14 apart (two fresh third differences per burst): pairs at lags 1, 13, 14 and 15, none
    # at the lags searched (2-12): still no dip, and no error
    pv = np.concatenate([np.concatenate([b, np.full(9, b[-1])]) for b in bursts])
    with np.errstate(all="raise"):
        s = _stats(pv)
    assert np.isnan(s["averaging_lag"]) and np.isnan(s["pv_averaging_contrast"])


def test_averaging_needs_48_fresh_third_differences():
    """4 x the longest lag (12): 51 samples give 48 third differences, 50 give 47."""
    rng = np.random.default_rng(40)
    x = rng.standard_normal(51)
    assert np.isfinite(_stats(x)["averaging_lag"]) and np.isfinite(_stats(x)["noise_colour"])
    assert np.isnan(_stats(x[:50])["averaging_lag"]) and np.isnan(_stats(x[:50])["noise_colour"])


def test_averaging_dip_at_the_longest_lags():
    rng = np.random.default_rng(41)
    pv = lfilter(np.ones(11) / 11, [1.0], rng.standard_normal(20000))
    s = _stats(pv)
    assert s["averaging_lag"] == 11 and s["diff_acf_min"] == pytest.approx(-0.5, abs=0.04)


def test_period_in_the_first_positive_lobe():
    """cos(2 pi t / 80) + sqrt(2) cos(2 pi t / 40): ACF (cos(2 pi k / 80) + 2 cos(2 pi k / 40))
    / 3: a first lobe peaking at 40 (1/3, times the (n - k) / n of the biased estimate) and
    a higher one at 80; the period is the first's."""
    n = 800
    t = np.arange(n) - (n - 1) / 2
    s = _stats(np.cos(2 * np.pi * t / 80) + np.sqrt(2) * np.cos(2 * np.pi * t / 40))
    assert s["period"] == 40 and s["acf_peak"] == pytest.approx((1 / 3) * (1 - 40 / n))


def test_period_up_to_half_the_record():
    """A square wave of period 160 in 440 samples (2.75 cycles): found at 160."""
    x = np.repeat([1.0, -1, 1, -1, 1, -1, 1], [20, 80, 80, 80, 80, 80, 20])
    assert _stats(x)["period"] == 160


def test_a_bump_has_no_oscillation():
    """A Gaussian bump: its ACF falls below zero and never comes back: acf_peak 0, no period,
    fewer than 5 zero crossings: no regularity."""
    t = np.arange(400)
    s = _stats(np.exp(-(((t - 200) / 20) ** 2)))
    assert s["acf_peak"] == 0.0 and np.isnan(s["period"]) and np.isnan(s["regularity"])


def test_regularity_from_five_zero_crossings():
    """Half periods 10, 20, 30, 10, 20, 30: 5 crossings, full periods 50, 40, 30: r = 40 /
    (3 sqrt(200/3)); four crossings give none."""
    s = _stats(_square([10, 20, 30, 10, 20, 30]))
    assert s["regularity"] == pytest.approx(40 / (3 * np.sqrt(200 / 3)))
    assert np.isnan(_stats(_square([10, 20, 30, 10, 20]))["regularity"])
