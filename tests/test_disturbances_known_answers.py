"""Known answers of the plant-operation disturbances in ``sktiction.simulation``.

Filters are checked against their difference equations written out here, stationary
statistics against closed forms (unit variance, lag-one correlation of equal first-order
lags, the resonator's AR(2) coefficients), and the deterministic ones against values
worked out by hand.
"""

import re

import numpy as np
import pytest

from sktiction.simulation import (
    BandLimitedNoise,
    CascadeSetpoint,
    ColouredLoad,
    Drift,
    LoadStep,
    NarrowbandDisturbance,
    PVVariation,
    SquareDisturbance,
)
from sktiction.simulation.disturbances import _impulse, _lag_power, _lowpass_unit


def rng(seed=0):
    return np.random.default_rng(seed)


def _lag1(x):
    return np.corrcoef(x[:-1], x[1:])[0, 1]


# ---------------------------------------------------------------- filters


def test_lag_power_is_the_binomial_expansion():
    a = 0.3
    np.testing.assert_allclose(_lag_power(a, 1), [1.0, -a])
    np.testing.assert_allclose(_lag_power(a, 2), [1.0, -2 * a, a * a])
    np.testing.assert_allclose(_lag_power(a, 3), [1.0, -3 * a, 3 * a * a, -(a**3)])
    np.testing.assert_allclose(_lag_power(a, 4), np.poly(np.full(4, a)))
    np.testing.assert_array_equal(_impulse(4), [1.0, 0.0, 0.0, 0.0])


def test_lowpass_unit_first_order_is_the_lag_recursion_scaled_to_unit_variance():
    cutoff, n = 0.05, 300
    a = np.exp(-2 * np.pi * cutoff)
    u = _lowpass_unit(n, cutoff, 1, rng(1))
    # y[k] = a y[k-1] + (1 - a) e[k]: so u[k] - a u[k-1] is white, of variance 1 - a^2
    # for unit variance of u
    e = u[1:] - a * u[:-1]
    e_long = (lambda v: v[1:] - a * v[:-1])(_lowpass_unit(100_000, cutoff, 1, rng(2)))
    assert np.abs(_lag1(e_long)) < 0.02  # white
    assert e_long.var() == pytest.approx(1 - a * a, rel=0.03)
    assert e.shape == (n - 1,)


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_lowpass_unit_has_unit_variance_and_its_lag_one_correlation(order):
    cutoff = 0.02
    a = np.exp(-2 * np.pi * cutoff)
    u = _lowpass_unit(200_000, cutoff, order, rng(order))
    assert u.var() == pytest.approx(1.0, abs=0.08)
    # lag-one correlation of (1 - a z^-1)^-m: sum_k h_k h_{k+1} / sum_k h_k^2 by closed
    # forms: a for one lag, 2a / (1 + a^2) for two
    expected = {1: a, 2: 2 * a / (1 + a * a)}
    if order in expected:
        assert _lag1(u) == pytest.approx(expected[order], abs=0.01)
    # more lags, smoother
    assert _lag1(u) > a - 0.01


def test_lowpass_unit_first_sample_is_already_stationary():
    g = rng(3)
    first = np.array([_lowpass_unit(2, 0.05, 2, g)[0] for _ in range(3000)])
    assert first.var() == pytest.approx(1.0, abs=0.1)
    assert abs(first.mean()) < 0.1


# ---------------------------------------------------------------- measurement noise


def test_band_limited_noise_is_scaled_lowpass_noise():
    n = 500
    sig = BandLimitedNoise(0.1, std=2.0).signals(n, 1.0, rng(4))
    assert list(sig) == ["noise"]
    np.testing.assert_allclose(sig["noise"], 2.0 * _lowpass_unit(n, 0.1, 2, rng(4)))
    rel = BandLimitedNoise(0.1, snr_db=20, order=3).signals(n, 1.0, rng(4))
    np.testing.assert_allclose(rel["noise_relative"], 0.1 * _lowpass_unit(n, 0.1, 3, rng(4)))
    assert BandLimitedNoise(0.1, std=1.0, where="record").kind == "recording"
    b = BandLimitedNoise(0.25, std=1.0, order=4)
    assert (b.cutoff, b.order) == (0.25, 4)
    for kwargs, message in [
        ({"cutoff": 0.0}, "cutoff must be a number with 0 < cutoff < 0.5; got 0.0."),
        ({"cutoff": 0.5}, "cutoff must be a number with 0 < cutoff < 0.5; got 0.5."),
        ({"cutoff": "0.1"}, "cutoff must be a number"),
        ({"cutoff": 0.1, "order": 5}, "order must be 1, 2, 3 or 4; got 5."),
        ({"cutoff": 0.1, "order": 0}, "order must be 1, 2, 3 or 4; got 0."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            BandLimitedNoise(std=1.0, **kwargs)


def test_pv_variation_takes_its_share_of_the_variance():
    p = PVVariation(0.2, 0.05)
    assert p.kind == "recording" and p.order == 1 and p.where == "record"
    # share s: SNR 10 log10((1 - s) / s) dB, 4 : 1 in power for s = 0.2
    assert p.snr_db == pytest.approx(10 * np.log10(4.0))
    assert repr(p) == "PVVariation(share=0.2, cutoff=0.05, where='record', order=1)"
    n = 1000
    pv = np.sin(np.arange(n) / 7.0) * np.linspace(1, 3, n)
    out = p.record({"pv": pv}, 1.0, rng(5))
    ref = pv[n // 2 :].std()
    expected = np.sqrt(0.2 / 0.8) * ref * _lowpass_unit(n, 0.05, 1, rng(5))
    np.testing.assert_allclose(out["pv"] - pv, expected, rtol=1e-9, atol=1e-12)
    loop = PVVariation(0.5, 0.1, where="loop", order=2)
    assert loop.kind == "exogenous" and loop.snr_db == pytest.approx(0.0)
    sig = loop.signals(n, 1.0, rng(5))
    np.testing.assert_allclose(sig["noise_relative"], _lowpass_unit(n, 0.1, 2, rng(5)))
    for share in (0.0, 1.0, "0.5"):
        with pytest.raises(ValueError, match="share must be a number with 0 < share < 1"):
            PVVariation(share, 0.1)


# ---------------------------------------------------------------- loads


def test_coloured_load_is_scaled_lowpass_noise_at_the_output_or_input():
    n = 400
    load = ColouredLoad(3.0, 0.02).signals(n, 1.0, rng(6))
    assert list(load) == ["output_load"]
    np.testing.assert_allclose(load["output_load"], 3.0 * _lowpass_unit(n, 0.02, 1, rng(6)))
    load = ColouredLoad(0.5, 0.2, order=3, where="input").signals(n, 1.0, rng(6))
    assert list(load) == ["input_load"]
    np.testing.assert_allclose(load["input_load"], 0.5 * _lowpass_unit(n, 0.2, 3, rng(6)))
    for args, kwargs, message in [
        ((0.0, 0.1), {}, "std must be a finite number > 0; got 0.0."),
        ((1.0, 0.6), {}, "cutoff must be a number with 0 < cutoff < 0.5; got 0.6."),
        ((1.0, 0.1), {"order": 5}, "order must be 1, 2, 3 or 4; got 5."),
        ((1.0, 0.1), {"where": "x"}, "where must be 'output' or 'input'; got 'x'."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            ColouredLoad(*args, **kwargs)


def _assert_resonator(y, period, zeta, atol):
    """``y`` is AR(2) with poles r exp(+-i w sqrt(1 - zeta^2)), r = exp(-zeta w), w = 2 pi /
    period: its least-squares AR(2) coefficients are 2 r cos(w sqrt(1 - zeta^2)) and -r^2."""
    w = 2 * np.pi / period
    r = np.exp(-zeta * w)
    A = np.column_stack([y[1:-1], y[:-2]])
    coef = np.linalg.lstsq(A, y[2:], rcond=None)[0]
    np.testing.assert_allclose(coef, [2 * r * np.cos(w * np.sqrt(1 - zeta**2)), -r * r],
                               atol=atol)  # fmt: skip


def test_narrowband_disturbance_is_the_resonator_it_says():
    period, zeta = 25.0, 0.05
    d = NarrowbandDisturbance(2.0, period, damping=zeta).signals(200_000, 1.0, rng(7))
    y = d["output_load"]
    _assert_resonator(y, period, zeta, atol=2e-3)
    # amplitude = sqrt(2) times the standard deviation
    assert y.std() == pytest.approx(2.0 / np.sqrt(2), rel=0.1)
    # the same disturbance in other time units: period and ts scale together
    a = NarrowbandDisturbance(1.0, 30.0, 0.2, where="input").signals(300, 1.0, rng(8))
    b = NarrowbandDisturbance(1.0, 60.0, 0.2, where="input").signals(300, 2.0, rng(8))
    assert list(a) == ["input_load"]
    np.testing.assert_allclose(a["input_load"], b["input_load"], rtol=1e-9, atol=1e-12)


def test_narrowband_first_sample_is_stationary_and_arguments_are_checked():
    g = rng(9)
    eff = NarrowbandDisturbance(1.0, 10.0, damping=0.3)
    first = np.array([eff.signals(1, 1.0, g)["output_load"][0] for _ in range(3000)])
    assert first.std() == pytest.approx(1 / np.sqrt(2), rel=0.1)
    with pytest.raises(ValueError, match=re.escape("period must exceed 2 ts = 2.0; got 2.0.")):
        NarrowbandDisturbance(1.0, 2.0).signals(10, 1.0, g)
    NarrowbandDisturbance(1.0, 2.1).signals(10, 1.0, g)  # just above: fine
    for kwargs, message in [
        ({"damping": 0.0}, "damping must be a number with 0 < damping < 1; got 0.0."),
        ({"damping": 1.0}, "damping must be a number with 0 < damping < 1; got 1.0."),
        ({"where": "x"}, "where must be 'output' or 'input'; got 'x'."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            NarrowbandDisturbance(1.0, 10.0, **kwargs)
    with pytest.raises(ValueError, match=re.escape("amplitude must be a finite number > 0")):
        NarrowbandDisturbance(-1.0, 10.0)
    with pytest.raises(ValueError, match=re.escape("period must be a finite number > 0")):
        NarrowbandDisturbance(1.0, 0.0)


def test_square_disturbance_known_answers():
    def wave(*args, n=6, ts=1.0, **kwargs):
        sig = SquareDisturbance(*args, **kwargs).signals(n, ts, rng(0))
        return sig[next(iter(sig))]

    np.testing.assert_array_equal(wave(1.0, 4.0), [1, 1, -1, -1, 1, 1])
    np.testing.assert_array_equal(wave(2.0, 4.0, phase=np.pi), [-2, -2, 2, 2, -2, -2])
    # a quarter period late: edges at -1, 1, 3, 5
    np.testing.assert_array_equal(wave(1.0, 4.0, phase=np.pi / 2), [1, -1, -1, 1, 1, -1])
    np.testing.assert_array_equal(wave(1.0, 4.0, phase=2 * np.pi), [1, 1, -1, -1, 1, 1])
    np.testing.assert_array_equal(wave(1.0, 8.0, ts=2.0), [1, 1, -1, -1, 1, 1])
    np.testing.assert_array_equal(wave(1.0, 6.0), [1, 1, 1, -1, -1, -1])
    sig = SquareDisturbance(1.0, 4.0, where="input").signals(3, 1.0, rng(0))
    assert list(sig) == ["input_load"]
    # through a first-order lag of time constant 2: y[k] = a y[k-1] + (1 - a) x[k],
    # a = exp(-ts / lag), starting at rest on the first value
    a = np.exp(-1.0 / 2.0)
    x = [1.0, 1.0, -1.0, -1.0, 1.0, 1.0]
    y, prev = [], x[0]
    for xk in x:
        prev = a * prev + (1 - a) * xk
        y.append(prev)
    np.testing.assert_allclose(wave(1.0, 4.0, lag=2.0), y, rtol=1e-12)


def test_square_disturbance_jitter_varies_the_half_periods():
    n, half = 20_000, 10
    regular = SquareDisturbance(1.0, 2.0 * half).signals(n, 1.0, rng(1))["output_load"]
    jittered = SquareDisturbance(1.0, 2.0 * half, jitter=0.3).signals(n, 1.0, rng(1))
    jittered = jittered["output_load"]

    def runs(w):
        edges = np.flatnonzero(np.diff(w) != 0)
        return np.diff(edges)

    assert set(runs(regular)) == {half}
    r = runs(jittered)
    assert r.mean() == pytest.approx(half, rel=0.05)
    assert r.std() / half == pytest.approx(0.3, abs=0.06)
    # with the largest jitter the wave still switches up to the end of the record
    wide = SquareDisturbance(1.0, 2.0 * half, jitter=0.5).signals(n, 1.0, rng(2))
    tail = wide["output_load"][-10 * half :]
    assert set(np.unique(tail)) == {-1.0, 1.0}
    for kwargs, message in [
        ({"jitter": 0.6}, "jitter must be a finite number >= 0 and <= 0.5; got 0.6."),
        ({"jitter": -0.1}, "jitter must be a finite number >= 0 and <= 0.5"),
        ({"lag": -1.0}, "lag must be a finite number >= 0; got -1.0."),
        ({"where": "x"}, "where must be 'output' or 'input'; got 'x'."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            SquareDisturbance(1.0, 4.0, **kwargs)
    assert SquareDisturbance(1.0, 4.0, lag=0.0, jitter=0.5).jitter == 0.5


# ---------------------------------------------------------------- drift, setpoint, steps


def test_drift_goes_straight_between_random_knots_from_zero():
    z = rng(3).standard_normal(3)
    d = Drift(2.0, n_segments=3).signals(7, 1.0, rng(3))
    assert list(d) == ["output_load"]
    knots = 2.0 * np.concatenate([[0.0], np.cumsum(z)])
    # seven samples over three segments: the knots at samples 0, 2, 4, 6, midpoints between
    np.testing.assert_allclose(d["output_load"][::2], knots, rtol=1e-12)
    np.testing.assert_allclose(d["output_load"][1::2], (knots[:-1] + knots[1:]) / 2)
    one = Drift(1.0, n_segments=1, where="input").signals(5, 1.0, rng(4))["input_load"]
    z1 = rng(4).standard_normal(1)[0]
    np.testing.assert_allclose(one, z1 * np.linspace(0, 1, 5))
    assert Drift(1.0).n_segments == 2 and Drift(1.0, np.int64(3)).n_segments == 3
    for kwargs, message in [
        ({"n_segments": 0}, "n_segments must be an integer >= 1; got 0."),
        ({"n_segments": 1.5}, "n_segments must be an integer >= 1; got 1.5."),
        ({"where": "x"}, "where must be 'output' or 'input'; got 'x'."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            Drift(1.0, **kwargs)
    with pytest.raises(ValueError, match=re.escape("amplitude must be a finite number > 0")):
        Drift(0.0)


def test_cascade_setpoint_is_ar1_plus_white_from_zero():
    n, std, phi, jitter = 50, 2.0, 0.9, 0.3
    g = rng(5)
    e = g.standard_normal(n) * np.sqrt(1 - phi**2)
    prev = g.standard_normal()
    slow = np.empty(n)
    for k in range(n):
        slow[k] = prev = phi * prev + e[k]
    white = g.standard_normal(n)
    expected = std * (slow + jitter * white)
    expected -= expected[0]
    sp = CascadeSetpoint(std, phi=phi, jitter=jitter).signals(n, 1.0, rng(5))
    assert list(sp) == ["setpoint"]
    np.testing.assert_allclose(sp["setpoint"], expected, rtol=1e-12, atol=1e-12)
    c = CascadeSetpoint(1.0)
    assert (c.phi, c.jitter) == (0.98, 0.2)
    long = CascadeSetpoint(1.0, phi=0.5, jitter=0.0).signals(100_000, 1.0, rng(6))["setpoint"]
    assert long[0] == 0.0 and _lag1(long) == pytest.approx(0.5, abs=0.01)
    assert long.std() == pytest.approx(1.0, rel=0.03)
    CascadeSetpoint(1.0, phi=0.0)  # allowed
    for kwargs, message in [
        ({"phi": 1.0}, "phi must be a number with 0 <= phi < 1; got 1.0."),
        ({"phi": -0.5}, "phi must be a number with 0 <= phi < 1; got -0.5."),
        ({"jitter": -0.1}, "jitter must be a finite number >= 0; got -0.1."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            CascadeSetpoint(1.0, **kwargs)
    with pytest.raises(ValueError, match=re.escape("std must be a finite number > 0; got 0.0.")):
        CascadeSetpoint(0.0)


def test_load_step_known_answers():
    def load(*args, n=5, ts=1.0, **kwargs):
        sig = LoadStep(*args, **kwargs).signals(n, ts, None)
        return list(sig), sig[next(iter(sig))].tolist()

    assert load(2.0) == (["input_load"], [0.0, 2.0, 2.0, 2.0, 2.0])  # at 0: the second sample
    assert load(2.0, 2.0)[1] == [0.0, 0.0, 2.0, 2.0, 2.0]
    assert load(-1.0, 2.5)[1] == [0.0, 0.0, 0.0, -1.0, -1.0]  # between samples: the next
    assert load(1.0, 4.0, ts=2.0)[1] == [0.0, 0.0, 1.0, 1.0, 1.0]
    assert load(1.0, 0.1 * 3, ts=0.1)[1] == [0.0, 0.0, 0.0, 1.0, 1.0]  # 0.3 / 0.1 > 3
    assert load(1.0, 9.0)[1] == [0.0] * 5  # after the record
    assert load(1.0, 1.0, where="output")[0] == ["output_load"]
    for args, kwargs, message in [
        ((np.inf,), {}, "size must be a finite number; got inf."),
        ((1.0, -1.0), {}, "time must be a finite number >= 0; got -1.0."),
        ((1.0,), {"where": "x"}, "where must be 'output' or 'input'; got 'x'."),
    ]:
        with pytest.raises(ValueError, match=re.escape(message)):
            LoadStep(*args, **kwargs)


# ---------------------------------------------------------------- survivors of the first run


def test_a_fourth_order_lowpass_starts_stationary_too():
    g = rng(11)  # four lags at 0.01 cycles per sample: a long transient to burn
    first = np.array([_lowpass_unit(1, 0.01, 4, g)[0] for _ in range(2000)])
    assert first.var() == pytest.approx(1.0, abs=0.12)


def test_narrowband_of_a_long_period_starts_stationary():
    g = rng(12)
    eff = NarrowbandDisturbance(1.0, 100.0, damping=0.3)
    first = np.array([eff.signals(1, 1.0, g)["output_load"][0] for _ in range(2000)])
    assert first.std() == pytest.approx(1 / np.sqrt(2), rel=0.1)


def test_narrowband_heavily_damped_poles_and_the_two_sample_limit_in_time_units():
    zeta, period = 0.3, 10.0
    y = NarrowbandDisturbance(1.0, period, damping=zeta).signals(200_000, 1.0, rng(13))
    _assert_resonator(y["output_load"], period, zeta, atol=5e-3)
    with pytest.raises(ValueError, match=re.escape("period must exceed 2 ts = 4.0; got 3.0.")):
        NarrowbandDisturbance(1.0, 3.0).signals(10, 2.0, rng(0))


def test_coloured_load_bounds_and_orders():
    for cutoff in (0.0, 0.5):
        with pytest.raises(ValueError, match="cutoff must be a number with 0 < cutoff < 0.5"):
            ColouredLoad(1.0, cutoff)
    for order in (1, 2, 3, 4):
        assert ColouredLoad(1.0, 0.1, order=order).order == order


def test_square_disturbance_defaults_lag_and_messages():
    # phase 0 by default: a half period of 10 samples starts at the first sample
    w = SquareDisturbance(1.0, 20.0).signals(12, 1.0, rng(0))["output_load"]
    np.testing.assert_array_equal(w, [1.0] * 10 + [-1.0] * 2)
    # a lag under one time unit still filters; the lag starts at rest on the first value
    a = np.exp(-1.0 / 0.5)
    x = 2.0 * np.array([1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
    y, prev = [], x[0]
    for xk in x:
        prev = a * prev + (1 - a) * xk
        y.append(prev)
    got = SquareDisturbance(2.0, 4.0, lag=0.5, phase=np.pi / 2).signals(6, 1.0, rng(0))
    np.testing.assert_allclose(got["output_load"], y, rtol=1e-12)
    with pytest.raises(ValueError, match=re.escape("amplitude must be a finite number > 0")):
        SquareDisturbance(0.0, 4.0)
    with pytest.raises(ValueError, match=re.escape("period must be a finite number > 0")):
        SquareDisturbance(1.0, 0.0)


def test_square_disturbance_half_periods_never_shrink_below_a_fifth():
    # each jittered half period is at least 0.2 of its length: 2 samples here
    wide = SquareDisturbance(1.0, 20.0, jitter=0.5).signals(20_000, 1.0, rng(14))
    edges = np.flatnonzero(np.diff(wide["output_load"]) != 0)
    assert np.diff(edges).min() >= 2


def test_load_step_default_time_is_zero():
    assert LoadStep(2.0).time == 0.0
    sig = LoadStep(2.0).signals(4, 0.5, None)["input_load"]
    np.testing.assert_array_equal(sig, [0.0, 2.0, 2.0, 2.0])
