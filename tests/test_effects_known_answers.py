"""Known answers of the composable effects in ``sktiction.simulation.effects``.

Noise draws are compared with the same seeded generator's standard normals put through
the documented definition (scale, AR(1) recursion, random walk), computed here sample
by sample; deterministic effects with values worked out by hand.
"""

import re

import numpy as np
import pytest

from sktiction.simulation import (
    ARNoise,
    Effect,
    Quantization,
    RandomWalkLoad,
    SetpointSteps,
    SinusoidalDisturbance,
    WhiteNoise,
)
from sktiction.simulation.effects import _lfilter, _noise_scale, _padded


def rng(seed=0):
    return np.random.default_rng(seed)


# ---------------------------------------------------------------- noise


def test_noise_scale_from_std_or_snr():
    assert _noise_scale(0.3, None) == (0.3, False)
    assert _noise_scale(None, 20) == (pytest.approx(0.1), True)  # 20 dB: a tenth
    assert _noise_scale(None, 0.0) == (1.0, True)
    assert _noise_scale(None, -20) == (pytest.approx(10.0), True)
    message = "give exactly one of std (> 0) or snr_db (finite, in dB)."
    for args in ((None, None), (1.0, 10.0)):
        with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
            _noise_scale(*args)
    with pytest.raises(ValueError, match=re.escape("std must be a finite number > 0; got -1.0.")):
        WhiteNoise(std=-1.0)
    with pytest.raises(
        ValueError, match=re.escape("snr_db must be a finite number of dB; got inf.")
    ):
        WhiteNoise(snr_db=np.inf)
    with pytest.raises(ValueError, match=re.escape("where must be 'loop' or 'record'; got 'x'.")):
        WhiteNoise(std=1.0, where="x")


def test_white_noise_signals_are_scaled_standard_normals():
    e = rng(1).standard_normal(50)
    sig = WhiteNoise(std=0.5).signals(50, 1.0, rng(1))
    assert list(sig) == ["noise"]
    np.testing.assert_array_equal(sig["noise"], 0.5 * e)
    rel = WhiteNoise(snr_db=40).signals(50, 1.0, rng(1))
    assert list(rel) == ["noise_relative"]
    np.testing.assert_allclose(rel["noise_relative"], 0.01 * e, rtol=1e-12)


def test_white_noise_on_the_record_adds_to_pv_only():
    n = 40
    pv = np.linspace(0.0, 3.0, n)
    signals = {"pv": pv.copy(), "op": np.arange(n, dtype=float), "sp": np.ones(n)}
    eff = WhiteNoise(std=0.25, where="record")
    assert eff.kind == "recording" and WhiteNoise(std=0.25).kind == "exogenous"
    out = eff.record(signals, 1.0, rng(2))
    e = rng(2).standard_normal(n)
    np.testing.assert_allclose(out["pv"], pv + 0.25 * e, rtol=0, atol=1e-15)
    assert out["op"] is signals["op"] and out["sp"] is signals["sp"]
    np.testing.assert_array_equal(signals["pv"], pv)  # the input is left alone
    assert set(out) == {"pv", "op", "sp"}


def test_record_snr_is_relative_to_the_second_half_of_pv():
    n = 400
    pv = np.zeros(n)
    pv[: n // 2] = 50.0 * np.sin(np.arange(n // 2))  # a loud first half: not the reference
    pv[n // 2 :] = 0.5 * np.where(np.arange(n // 2) % 2 == 0, 1.0, -1.0)  # std 0.5
    out = WhiteNoise(snr_db=20, where="record").record({"pv": pv}, 1.0, rng(3))
    e = rng(3).standard_normal(n)
    np.testing.assert_allclose(out["pv"] - pv, 0.1 * 0.5 * e, rtol=1e-9, atol=1e-12)
    # a PV that does not move: a reference of 1 PV unit
    flat = np.full(n, 7.0)
    out = WhiteNoise(snr_db=20, where="record").record({"pv": flat}, 1.0, rng(3))
    np.testing.assert_allclose(out["pv"] - flat, 0.1 * e, rtol=1e-9, atol=1e-12)


def test_ar_noise_is_the_stationary_ar1_recursion():
    phi, n = 0.7, 60
    g = rng(4)
    e = g.standard_normal(n) * np.sqrt(1 - phi**2)
    z = g.standard_normal()
    expected = np.empty(n)
    prev = z  # the state before the first sample: one unit-variance draw
    for k in range(n):
        expected[k] = prev = phi * prev + e[k]
    got = ARNoise(phi, std=2.0).signals(n, 1.0, rng(4))["noise"]
    np.testing.assert_allclose(got, 2.0 * expected, rtol=1e-12, atol=1e-14)
    # phi = 0 is white noise; the AR noise can sit on the record too
    white = ARNoise(0.0, std=1.0).signals(n, 1.0, rng(4))["noise"]
    np.testing.assert_allclose(white, rng(4).standard_normal(n), rtol=1e-12)
    assert ARNoise(0.5, std=1.0, where="record").kind == "recording"
    for phi in (1.0, -0.1, "0.5"):
        with pytest.raises(ValueError, match="phi must be a number with 0 <= phi < 1"):
            ARNoise(phi, std=1.0)


def test_ar_noise_has_unit_variance_and_lag_one_correlation_phi():
    u = ARNoise(0.9, std=1.0).signals(200_000, 1.0, rng(5))["noise"]
    assert u.var() == pytest.approx(1.0, abs=0.05)
    assert np.corrcoef(u[:-1], u[1:])[0, 1] == pytest.approx(0.9, abs=0.01)


def test_padded_and_lfilter_against_the_difference_equation():
    b, a = _padded([0.5], [1.0, -0.5, 0.25])
    np.testing.assert_array_equal(b, [0.5, 0.0, 0.0])
    assert a.dtype == np.float64
    x = np.array([1.0, 0.0, 0.0, 2.0])
    y = _lfilter(b, a, x, np.zeros(2))
    # y[k] = 0.5 x[k] + 0.5 y[k-1] - 0.25 y[k-2]
    np.testing.assert_allclose(y, [0.5, 0.25, 0.0, 1.0 - 0.0625 + 0.0])


# ---------------------------------------------------------------- loads and setpoints


def test_random_walk_starts_at_zero_and_steps_by_scaled_normals():
    stale = np.ones(30)  # freed memory that np.empty may hand back: walk[0] must be set
    del stale
    load = RandomWalkLoad(0.2).signals(30, 1.0, rng(6))
    assert list(load) == ["output_load"]
    w = load["output_load"]
    assert w[0] == 0.0
    np.testing.assert_allclose(np.diff(w), 0.2 * rng(6).standard_normal(29), rtol=1e-12)
    assert list(RandomWalkLoad(0.2, where="input").signals(5, 1.0, rng(6))) == ["input_load"]
    with pytest.raises(ValueError, match=re.escape("std must be a finite number > 0; got 0.")):
        RandomWalkLoad(0)
    with pytest.raises(ValueError, match=re.escape("where must be 'output' or 'input'; got 'x'.")):
        RandomWalkLoad(0.1, where="x")


def test_setpoint_steps_known_answers():
    # t = 0, 0.5, 1, ..., 3: a step of 5 at t = 1 acts from the third sample
    sp = SetpointSteps([1.0], [5.0]).signals(7, 0.5, None)["setpoint"]
    np.testing.assert_array_equal(sp, [0, 0, 5, 5, 5, 5, 5])
    # steps add up; one between samples acts from the next sample
    sp = SetpointSteps([2.0, 3.5, 0.0], [1.0, -3.0, 0.5]).signals(6, 1.0, None)["setpoint"]
    np.testing.assert_array_equal(sp, [0.5, 0.5, 1.5, 1.5, -1.5, -1.5])
    # a step time a rounding error past a sample time acts from that sample, at any ts
    for ts in (0.1, 1e5):
        t0 = np.nextafter(3 * ts, np.inf)
        sp = SetpointSteps([t0], [1.0]).signals(6, ts, None)["setpoint"]
        np.testing.assert_array_equal(sp, [0, 0, 0, 1, 1, 1])
    assert SetpointSteps(0.0, 2.0).times == (0.0,)  # t = 0 is allowed
    with pytest.raises(ValueError, match=re.escape("times must be finite and >= 0; got [-1.0].")):
        SetpointSteps([-1.0], [1.0])
    with pytest.raises(ValueError, match="times must be finite"):
        SetpointSteps([np.inf], [1.0])
    with pytest.raises(ValueError, match=re.escape("got 2 and 1")):
        SetpointSteps([1.0, 2.0], [1.0])


def test_sinusoidal_disturbance_known_answers():
    # a quarter period per sample, phase pi/2: a cosine
    wave = SinusoidalDisturbance(2.0, 4.0, phase=np.pi / 2).signals(5, 1.0, None)["output_load"]
    np.testing.assert_allclose(wave, [2.0, 0.0, -2.0, 0.0, 2.0], atol=1e-12)
    # ts scales time: period 8 time units at ts = 2 is again four samples
    wave = SinusoidalDisturbance(1.0, 8.0, where="input").signals(3, 2.0, None)
    assert list(wave) == ["input_load"]
    np.testing.assert_allclose(wave["input_load"], [0.0, 1.0, 0.0], atol=1e-12)
    for kwargs, message in [
        ({"amplitude": 0.0, "period": 1.0}, "amplitude must be a finite number > 0"),
        ({"amplitude": 1.0, "period": -2.0}, "period must be a finite number > 0"),
        ({"amplitude": 1.0, "period": 2.0, "where": "x"},
         "where must be 'output' or 'input'; got 'x'."),
    ]:  # fmt: skip
        with pytest.raises(ValueError, match=re.escape(message)):
            SinusoidalDisturbance(**kwargs)


# ---------------------------------------------------------------- recording


def test_quantization_rounds_to_multiples_of_the_step():
    signals = {"pv": np.array([1.2, 1.3, -0.74, 0.74]), "op": np.array([0.26, 10.1]),
               "sp": np.array([0.3, 0.3])}  # fmt: skip
    out = Quantization(0.5, ("pv", "op")).record(signals, 1.0, None)
    np.testing.assert_allclose(out["pv"], [1.0, 1.5, -0.5, 0.5])
    np.testing.assert_allclose(out["op"], [0.5, 10.0])
    assert out["sp"] is signals["sp"]
    np.testing.assert_array_equal(signals["pv"], [1.2, 1.3, -0.74, 0.74])
    out = Quantization(0.2).record({"pv": np.array([0.29, 0.31, 1.0])}, 1.0, None)
    np.testing.assert_allclose(out["pv"], [0.2, 0.4, 1.0])
    with pytest.raises(ValueError, match=re.escape("channels must be among ('pv', 'op', "
                                                   "'sp'); got ['mv'].")):  # fmt: skip
        Quantization(1.0, ("pv", "mv"))
    with pytest.raises(ValueError, match=re.escape("step must be a finite number > 0")):
        Quantization(0.0)


def test_base_effect_changes_nothing():
    eff = Effect()
    assert eff.kind == "exogenous" and eff.signals(5, 1.0, None) == {}
    signals = {"pv": np.ones(3)}
    assert eff.record(signals, 1.0, None) is signals
    assert repr(eff) == "Effect()"
