"""The valve-model fit: the normal-equation grid search gives the least-squares answer."""

import numpy as np
import pytest

from sktiction._validation import loop_lengths
from sktiction.datasets import make_loops
from sktiction.features import StictionModelFit
from sktiction.features.stiction_model import (
    _chance_gain,
    _grid_normal_equations,
    _play,
    band_curve,
    block_means,
    fit_stiction_band,
    fit_stiction_band_multiscale,
)

# plain-numpy references: the design matrix and its least squares


def _design(pv, x, n_lags):
    """Rows t >= n_lags of [pv[t-1], pv[t-2], x[t-1..t-n_lags], 1] for ARX."""
    n = pv.size
    cols = [pv[n_lags - 1 : n - 1], pv[n_lags - 2 : n - 2]]
    cols += [x[n_lags - k : n - k] for k in range(1, n_lags + 1)]
    cols.append(np.ones(n - n_lags))
    return np.column_stack(cols)


def _sse(pv, x, n_lags):
    """Residual sum of squares of the ARX fit by least squares on the design matrix."""
    A = _design(pv, x, n_lags)
    b = pv[n_lags:]
    coef, *_ = np.linalg.lstsq(A, b, rcond=None)
    r = b - A @ coef
    return float(r @ r)


def lstsq_grid(pv, op, n_lags=8):
    """The fit as it was: one least-squares fit of the design per band (reference)."""
    n_lags = int(min(n_lags, max(2, pv.size // 20)))
    span = float(np.ptp(op))
    fracs = np.geomspace(0.002, 0.6, 24)
    base = _sse(pv, op, n_lags)
    sses = np.array([_sse(pv, _play(op, f * span), n_lags) for f in fracs])
    best = int(np.argmin(sses))
    if sses[best] >= base:
        return 0.0, 0.0
    return 1.0 - sses[best] / base, fracs[best] * span


def test_normal_equations_equal_the_design_products():
    rng = np.random.default_rng(0)
    pv, op = rng.normal(size=80), np.cumsum(rng.normal(size=80))
    bands = np.array([0.0, 0.7, 3.0])
    Gs, hs, bb = _grid_normal_equations(pv, op, bands, 5)
    for G, h, d in zip(Gs, hs, bands):
        A, b = _design(pv, _play(op, d), 5), pv[5:]
        np.testing.assert_allclose(G, A.T @ A, rtol=1e-12, atol=1e-10)
        np.testing.assert_allclose(h, A.T @ b, rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(bb, pv[5:] @ pv[5:])


def test_grid_search_gives_the_least_squares_gain_and_band():
    X, _ = make_loops(30, n_samples=4000, slip_fraction=0.25, random_state=3)
    n = loop_lengths(X)
    pairs = [(X[i, : n[i], 0], X[i, : n[i], 1]) for i in range(len(X))]
    rng = np.random.default_rng(1)
    for band in (0.5, 2.0, 5.0):  # PV driven through a known dead band
        op = 50 + np.cumsum(rng.normal(0, 0.3, 3000))
        pv = np.convolve(_play(op, band), [0.0, 0.0, 0.5, 0.3, 0.2])[:3000]
        pairs.append((pv + rng.normal(0, 0.05, 3000), op))
    gains = []
    for pv, op in pairs:
        gain, band = fit_stiction_band(pv, op)
        ref_gain, ref_band = lstsq_grid(pv, op)
        np.testing.assert_allclose([gain, band], [ref_gain, ref_band], rtol=1e-8, atol=1e-10)
        gains.append(gain)
    assert max(gains) > 0.5 and min(gains) < 0.01  # clear and absent valve models


def test_a_large_offset_changes_nothing(valve_walk):
    # the fit centres PV and OP first: an offset of 1e6 on a signal moving by tens
    # would otherwise cost the normal equations about twelve digits
    pv, op = valve_walk()
    got = fit_stiction_band(pv + 1e6, op - 1e6)
    np.testing.assert_allclose(got, fit_stiction_band(pv, op), rtol=1e-6)
    assert got[0] > 0.5 and 1.6 < got[1] < 2.4


def test_collinear_valve_positions_give_the_least_squares_fit():
    # OP a ramp: every lag of the valve position is the intercept plus a multiple of
    # another, so the design has rank 4 of 11 and only the least-norm fit is defined
    op = np.linspace(0.0, 30.0, 800)
    pv = np.sin(np.arange(800) / 40.0) + 0.01 * np.random.default_rng(0).normal(size=800)
    np.testing.assert_allclose(fit_stiction_band(pv, op), lstsq_grid(pv, op), rtol=1e-6, atol=1e-9)


def test_short_records(valve_walk):
    pv, op = valve_walk(n=80)
    # 4 * (n_lags + 3) samples at least, with n_lags cut to max(2, n // 20)
    assert np.isnan(fit_stiction_band(pv[:19], op[:19])).all()
    assert np.isfinite(fit_stiction_band(pv[:20], op[:20])).all()
    for n in (50, 60, 79):  # 2, 3 and 3 lags
        np.testing.assert_allclose(
            fit_stiction_band(pv[:n], op[:n]), lstsq_grid(pv[:n], op[:n]), rtol=1e-8, atol=1e-10
        )


def test_flat_signals_give_nan_and_a_unit_span_does_not(valve_walk):
    pv, op = valve_walk()
    assert np.isnan(fit_stiction_band(pv, np.full_like(op, 3.0))).all()
    assert np.isnan(fit_stiction_band(np.full_like(pv, 3.0), op)).all()
    unit_pv, unit_op = (pv - pv.min()) / np.ptp(pv), (op - op.min()) / np.ptp(op)
    assert np.ptp(unit_pv) == 1.0 and np.ptp(unit_op) == 1.0
    gain, band = fit_stiction_band(unit_pv, unit_op)
    assert gain > 0.5 and band == pytest.approx(2.0 / np.ptp(op), rel=0.2)


def test_a_given_grid_is_searched(valve_walk):
    pv, op = valve_walk(band=2.0)
    span = np.ptp(op)
    gain, band = fit_stiction_band(pv, op, grid=[2.0 / span])  # the true band only
    assert band == pytest.approx(2.0) and gain > 0.5
    far = fit_stiction_band(pv, op, grid=[0.5])  # a band of half the span
    assert far[1] in (0.0, pytest.approx(0.5 * span)) and far[0] < gain


def test_band_curve_reads_eight_lags_by_default_and_fits_each_band_by_least_squares(
        valve_walk):  # fmt: skip
    # the curve that hysteresis.valve_fit averages over block phases, with no n_lags given
    pv, op = valve_walk(n=400)
    pv_c, op_c, n_lags, bands, _, sses = band_curve(pv, op)
    assert n_lags == 8  # 400 // 20 = 20 lags allowed, the default 8 used
    np.testing.assert_allclose(bands, np.r_[0.0, np.geomspace(0.002, 0.6, 24) * np.ptp(op)])
    ref = [_sse(pv - pv.mean(), _play(op - op.mean(), d), 8) for d in bands]
    np.testing.assert_allclose(sses, ref, rtol=1e-8)


def test_an_op_that_moves_only_in_its_last_two_samples_is_fitted_like_lstsq():
    # OP 0 but for +1, -1 at the end: its mean is exactly 0, so the valve position sits
    # at exactly 0 in every row of the lags beyond the first, and those columns of the
    # design are all zeros (a zero diagonal the column scaling must leave alone)
    op = np.zeros(200)
    op[-2:] = 1.0, -1.0
    pv = np.random.default_rng(0).normal(size=200)
    A = _design(pv, op, 8)
    assert not A[:, 3:10].any() and A[:, 2].any()
    # nothing in OP's two moves explains PV's noise better than the linear model
    assert fit_stiction_band(pv, op) == lstsq_grid(pv, op) == (0.0, 0.0)


def test_float32_records_and_grids_are_fitted_in_double_precision(valve_walk):
    pv, op = valve_walk()
    pv32, op32 = pv.astype(np.float32), op.astype(np.float32)
    # the same values in float64 give the same fit to the last bit
    pv64, op64 = pv32.astype(float), op32.astype(float)
    assert fit_stiction_band(pv32, op32) == fit_stiction_band(pv64, op64)
    span = float(np.ptp(op))
    grid = np.float32([1.0 / span, 2.0 / span])  # fractions not exact in float32
    gain, band = fit_stiction_band(pv, op, grid=grid)
    assert band in (float(grid[0]) * span, float(grid[1]) * span)  # float64 products
    assert (gain, band) == fit_stiction_band(pv, op, grid=grid.astype(float))


def _valve_loops(valve_walk, n=1500):
    pv, op = valve_walk(n=n)
    return pv, op, np.stack([pv, op, np.full(pv.size, 50.0)], axis=1)[None]


def test_transformer_uses_n_lags_and_rejects_bad_values(valve_walk):
    pv, op, X = _valve_loops(valve_walk)
    default = StictionModelFit().fit_transform(X)[0]
    np.testing.assert_array_equal(default, StictionModelFit(n_lags=8).fit_transform(X)[0])
    two = StictionModelFit(n_lags=2).fit_transform(X)[0]
    np.testing.assert_allclose(two[:2], fit_stiction_band(pv, op, n_lags=2))
    assert two[2] == pytest.approx(two[1] / np.ptp(op))
    assert not np.allclose(two, default)
    for bad in (0, 1, 1.5):
        with pytest.raises(ValueError, match="n_lags must be an integer >= 2"):
            StictionModelFit(n_lags=bad).fit(X)


def test_the_smallest_allowed_n_lags_works(valve_walk):
    # two PV lags in every ARX row: one valve lag was accepted once and then crashed
    pv, op, X = _valve_loops(valve_walk)
    assert np.isfinite(StictionModelFit(n_lags=2).fit_transform(X)).all()
    with pytest.raises(ValueError, match="n_lags must be an integer >= 2"):
        fit_stiction_band(pv, op, n_lags=1)


def _slow_valve_loop(band, n=4000, delay=20, tau=20.0, noise=0.2, seed=0):
    """PV from a random-walk OP through a dead band, a first-order lag and a delay that
    the one-step fit's eight lags do not reach."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    op = 50 + np.cumsum(rng.normal(0, 0.3, n))
    a = np.exp(-1.0 / tau)
    lagged = lfilter([1 - a], [1, -a], _play(op, band) - op[0])
    return np.r_[np.zeros(delay), lagged[:-delay]] + rng.normal(0, noise, n), op


def test_multiscale_fit_finds_a_band_the_one_step_fit_misses():
    pv, op = _slow_valve_loop(4.0)
    assert fit_stiction_band(pv, op)[0] < 0.05
    gain, share, scale = fit_stiction_band_multiscale(pv, op)
    assert gain > 0.3 and scale in (4, 8, 16)
    # the best scale's own fit, less what a band gains by chance on its 4000 // scale rows,
    # and its band over the span of OP's block means there
    g, b = fit_stiction_band(block_means(pv, scale), block_means(op, scale))
    m = 4000 // scale
    assert gain == pytest.approx(g - (1 - m ** (-1 / m)), rel=1e-12)
    assert share == b / np.ptp(block_means(op, scale))
    assert 0.5 < share * np.ptp(op) / 4.0 < 1.5  # the band, within the fit's bias
    # a linear valve: one step ahead the two read alike (gain 0.03 both); on block means
    # the dead band explains 0.6 of the linear model's residual, under 0.1 for the linear one
    pv0, op0 = _slow_valve_loop(0.0)
    assert abs(fit_stiction_band(pv0, op0)[0] - fit_stiction_band(pv, op)[0]) < 0.01
    gain0, share0, _ = fit_stiction_band_multiscale(pv0, op0)
    assert gain0 < 0.1 and gain0 < gain / 5


def test_chance_gain_is_the_bic_penalty_of_one_parameter():
    # m ln(1 / (1 - g)) = ln m: 150 rows need a gain of 3.3 %, 4000 rows 0.2 %
    for m in (150, 600, 4000):
        g = _chance_gain(m)
        assert m * np.log(1 / (1 - g)) == pytest.approx(np.log(m), rel=1e-12)
    assert 0.032 < _chance_gain(150) < 0.034 and 0.002 < _chance_gain(4000) < 0.0021


def test_multiscale_fit_tries_only_scales_with_enough_blocks_and_reuses_the_first():
    pv, op = _slow_valve_loop(4.0, n=1000)
    fits = {k: fit_stiction_band(block_means(pv, k), block_means(op, k)) for k in (1, 2, 4, 8)}
    excess = {k: fits[k][0] - _chance_gain(1000 // k) for k in fits}
    gain, share, scale = fit_stiction_band_multiscale(pv, op)  # 1000 // 8 = 125 < 150
    assert scale == max((1, 2, 4), key=excess.get) and gain == excess[scale]
    gain8, _, scale8 = fit_stiction_band_multiscale(pv, op, min_blocks=100)
    assert scale8 == max(excess, key=excess.get) and gain8 == excess[scale8]
    # the caller's first fit is used as given at block length 1
    m = pv.size
    assert fit_stiction_band_multiscale(pv, op, scales=(1,), first=(0.123, 1.0)) == (
        0.123 - _chance_gain(m), 1.0 / np.ptp(op), 1)
    # no more than chance: no band, no scale; nothing to fit: NaN
    assert fit_stiction_band_multiscale(pv, op, scales=(1,), first=(0.0001, 1.0)) == (0, 0, 0)
    assert np.isnan(fit_stiction_band_multiscale(pv[:100], op[:100])[0])
    gain, share, scale = fit_stiction_band_multiscale(pv, np.full(pv.size, 3.0))
    assert np.isnan(gain) and np.isnan(share) and scale == 0


def test_block_means_average_whole_blocks_and_drop_the_rest():
    x = np.arange(11.0)  # blocks of 3: (0, 1, 2), (3, 4, 5), (6, 7, 8); 9 and 10 dropped
    np.testing.assert_array_equal(block_means(x, 3), [1.0, 4.0, 7.0])
    np.testing.assert_array_equal(block_means(x[:8], 4), [1.5, 5.5])  # no partial block
    np.testing.assert_array_equal(block_means(x, 1), x)
    assert block_means(x, 12).shape == (0,)  # not even one whole block


def test_chance_gain_known_values():
    # 1 - m**(-1/m) = 1 - exp(-ln(m) / m): ln 150 = 5.0106, / 150 = 0.033404, and
    # 1 - exp(-0.033404) = 0.033404 - 0.033404**2 / 2 + ... = 0.032852; ln 4000 = 8.2941,
    # / 4000 = 0.0020735, less its half square 2.1e-6: 0.0020714
    assert _chance_gain(150) == pytest.approx(0.032852, abs=2e-6)
    assert _chance_gain(4000) == pytest.approx(0.0020714, abs=2e-7)
    assert _chance_gain(150) > _chance_gain(600) > _chance_gain(4000)  # fewer rows, more


def _excess(pv, op, k, n_lags=8):
    """Scale k by hand: the fit on its block means less the chance gain of its
    ``n // k`` whole blocks, and the band over the span of OP's block means."""
    pk, ok = block_means(pv, k), block_means(op, k)
    gain, band = fit_stiction_band(pk, ok, n_lags=n_lags)
    return gain - _chance_gain(pv.size // k), band / np.ptp(ok)


def test_multiscale_fit_counts_whole_blocks_and_tries_a_scale_at_exactly_min_blocks():
    # 1001 samples: 500 whole blocks of 2 (not 500.5), the chance gain of 500 rows
    pv, op = _slow_valve_loop(4.0, n=1001)
    excess, share = _excess(pv, op, 2)
    assert excess > 0 and _chance_gain(500) - _chance_gain(500.5) > 1e-6
    gain, got_share, scale = fit_stiction_band_multiscale(pv, op, scales=(2,))
    assert (gain, got_share, scale) == (pytest.approx(excess, rel=1e-12), share, 2)
    # 1000 samples are 250 blocks of 4: tried at min_blocks=250, not at 251
    pv, op = _slow_valve_loop(4.0, n=1000)
    excess, share = _excess(pv, op, 4)
    assert excess > 0
    got = fit_stiction_band_multiscale(pv, op, scales=(4,), min_blocks=250)
    assert got == (pytest.approx(excess, rel=1e-12), share, 4)
    got = fit_stiction_band_multiscale(pv, op, scales=(4,), min_blocks=251)
    assert np.isnan(got[:2]).all() and got[2] == 0


def test_multiscale_fit_uses_n_lags_at_every_scale():
    pv, op = _slow_valve_loop(4.0, n=1000)
    for n_lags in (3, 8):
        excess = {k: _excess(pv, op, k, n_lags=n_lags) for k in (1, 2, 4)}
        best = max(excess, key=lambda k: excess[k][0])
        assert excess[best][0] > 0
        got = fit_stiction_band_multiscale(pv, op, n_lags=n_lags, scales=(1, 2, 4))
        assert got == (pytest.approx(excess[best][0], rel=1e-12), excess[best][1], best)
    # the two lag counts do give different fits (else this would check nothing)
    assert _excess(pv, op, 4, n_lags=3)[0] != pytest.approx(_excess(pv, op, 4)[0], rel=1e-3)


def test_multiscale_fit_skips_a_scale_it_cannot_fit_and_needs_more_than_chance():
    pv, op = _slow_valve_loop(4.0, n=1000)
    n = pv.size
    # a first fit of NaN (the record could not be fitted at block length 1) is skipped,
    # and the coarser scales still read
    got = fit_stiction_band_multiscale(pv, op, scales=(1, 2, 4), first=(np.nan, np.nan))
    assert got == fit_stiction_band_multiscale(pv, op, scales=(2, 4))
    assert np.isfinite(got[0]) and got[2] in (2, 4)
    # a first fit of exactly the chance gain is no evidence: excess 0, no band, no scale
    first = (_chance_gain(n), 1.0)
    assert fit_stiction_band_multiscale(pv, op, scales=(1,), first=first) == (0.0, 0.0, 0)
    # the first fit is used at block length 1 only: block length 2 is fitted on its means
    # (an excess of 1e-3 at block length 1 with a band of half OP's span: the scale with
    # the larger excess wins, not the one whose excess beats the other's band share)
    first = (_chance_gain(n) + 1e-3, 0.5 * np.ptp(op))
    excess2, share2 = _excess(pv, op, 2)
    assert 1e-3 < excess2 < 0.5
    got = fit_stiction_band_multiscale(pv, op, scales=(1, 2), first=first)
    assert got == (pytest.approx(excess2, rel=1e-12), share2, 2)


def test_multiscale_fit_of_a_band_below_chance_at_every_scale_is_zero():
    # PV white noise, unrelated to OP: some band lowers every scale's residual a little,
    # not by the chance gain of its rows in this draw (0.76, 0.48 and 0.62 of it; other
    # draws pass it at some scale: the grid searches 24 bands, not one)
    rng = np.random.default_rng(4)
    op = 50 + np.cumsum(rng.normal(0, 0.3, 1000))
    pv = rng.normal(size=1000)
    for k in (1, 2, 4):
        gain = fit_stiction_band(block_means(pv, k), block_means(op, k))[0]
        assert 0 < gain < _chance_gain(1000 // k)
    assert fit_stiction_band_multiscale(pv, op) == (0.0, 0.0, 0)


def test_transformer_passes_n_lags_to_the_multiscale_fit():
    pv, op = _slow_valve_loop(4.0, n=1500)
    X = np.stack([pv, op, np.zeros(pv.size)], axis=-1)[None]
    two = StictionModelFit(n_lags=2).fit_transform(X)[0]
    gain, share, _ = fit_stiction_band_multiscale(pv, op, n_lags=2)
    assert (two[3], two[4]) == (gain, share)
    assert gain != pytest.approx(fit_stiction_band_multiscale(pv, op)[0], rel=1e-3)


def test_transformer_reports_the_multiscale_columns():
    pv, op = _slow_valve_loop(4.0)
    X = np.stack([pv, op, np.zeros(pv.size)], axis=-1)[None]
    est = StictionModelFit().fit(X)
    got = dict(zip(est.get_feature_names_out(), est.transform(X)[0]))
    gain, share, _ = fit_stiction_band_multiscale(pv, op)
    assert got["multiscale_fit_gain"] == gain and got["multiscale_fit_band_share"] == share
    assert got["multiscale_fit_gain"] > got["stiction_fit_gain"] + 0.3


def test_a_noise_free_pv_that_its_own_lags_predict_gains_nothing():
    """A sine PV is exact for two PV lags (x[t] = 2 cos(w) x[t-1] - x[t-2]): both residuals
    are rounding, and their ratio must not pass for a band's gain."""
    rng = np.random.default_rng(3)
    t = np.arange(3000)
    gains = []
    for period in (37.0, 61.0, 113.0, 250.0):
        pv = np.sin(2 * np.pi * t / period)
        for _ in range(5):
            op = np.cumsum(rng.normal(0, 1, t.size))
            gains.append(fit_stiction_band(pv, op)[0])
            gains.append(fit_stiction_band_multiscale(pv, op)[0])
    assert gains == [0.0] * len(gains)
    # with noise 1e-6 of its amplitude the fit is a fit again, and finds no band
    pv = np.sin(2 * np.pi * t / 61.0) + rng.normal(0, 1e-6, t.size)
    assert fit_stiction_band(pv, np.cumsum(rng.normal(0, 1, t.size)))[0] < 0.05


def test_normal_equations_are_solved_by_cholesky_where_well_posed_else_least_norm():
    """Well-conditioned normal equations: Cholesky's answer is the least-squares one;
    collinear columns fail a pivot and get a least-squares answer by the pseudo-inverse
    (least norm in the scaled columns), whose fit is ``lstsq``'s."""
    from sktiction.features.stiction_model import _cholesky_solve, _solve_normal

    rng = np.random.default_rng(7)
    A = rng.normal(size=(200, 5)) * [1.0, 1e3, 1e-3, 5.0, 1.0]  # columns of any scale
    b = rng.normal(size=200)
    B = A.copy()
    B[:, 4] = 2.0 * B[:, 0] - B[:, 3]  # a column the others make
    Gs, hs = np.stack([A.T @ A, B.T @ B]), np.stack([A.T @ b, B.T @ b])
    coefs, ok = _cholesky_solve(Gs, hs, 1e-6)
    assert ok.tolist() == [True, False]
    assert np.allclose(coefs[0], np.linalg.lstsq(A, b, rcond=None)[0], rtol=1e-9, atol=1e-12)
    both = _solve_normal(Gs, hs)
    assert np.array_equal(both[0], coefs[0])  # the well-posed band keeps Cholesky's answer
    assert np.allclose(B @ both[1], B @ np.linalg.lstsq(B, b, rcond=None)[0], atol=1e-9)
