"""Oscillation detection and time localisation, mean removal, noise-proof zero crossings."""

import numpy as np
import pytest

from sktiction.cycles import (
    analyze_cycles,
    dominant_period,
    horch_filter,
    noise_std,
    remove_mean,
    schmitt_crossings,
)

STRETCH = 1000


def intermittent(seed):
    """A sinusoid on a drifting mean that oscillates in stretches 2 and 4 of 4."""
    rng = np.random.default_rng(seed)
    n = 4 * STRETCH
    t = np.arange(n)
    period = rng.uniform(50, 120)
    on = ((t >= STRETCH) & (t < 2 * STRETCH)) | (t >= 3 * STRETCH)
    drift = 0.002 * t + 0.5 * np.sin(2 * np.pi * t / 3000 + rng.uniform(0, 6))
    x = np.where(on, np.sin(2 * np.pi * t / period), 0.0) + drift + rng.normal(0, 0.05, n)
    return x, on, period


@pytest.mark.parametrize("seed", range(20))
def test_intermittent_oscillation_is_localised(seed):
    x, on, period = intermittent(seed)
    a = analyze_cycles(x)
    assert a.oscillating
    assert np.min(np.abs(a.periods - period)) < 0.05 * period  # the component's period
    found = np.zeros(x.size, dtype=bool)
    for start, end in a.segments:
        found[start:end] = True
    overlap = (found & on).sum() / (found | on).sum()
    assert overlap >= 0.90
    mids = a.crossings[a.cycles][:, [0, 2]].mean(axis=1)
    counts = np.histogram(mids, bins=np.arange(5) * STRETCH)[0]
    expected = np.array([0, 1, 0, 1]) * np.floor(STRETCH / period)  # whole cycles that fit
    assert np.all(np.abs(counts - expected) <= 1), (counts, expected)


def test_noise_and_random_walks_rarely_called_oscillating():
    white = walks = 0
    for seed in range(200):
        rng = np.random.default_rng(seed)
        white += analyze_cycles(rng.normal(size=2000)).oscillating
        walks += analyze_cycles(np.cumsum(rng.normal(size=2000))).oscillating
    assert white <= 10 and walks <= 10  # <= 5 % of 200 seeds each


def test_noisy_oscillations_are_found():
    found = 0
    for seed in range(50):
        rng = np.random.default_rng(seed)
        period = rng.uniform(20, 200)
        t = np.arange(2000)
        x = np.sin(2 * np.pi * t / period) + rng.normal(0, 0.22, t.size)  # about 10 dB
        a = analyze_cycles(x + np.cumsum(rng.normal(0, 0.02, t.size)))
        found += a.oscillating and abs(a.period - period) < 0.1 * period
    assert found >= 48


def test_schmitt_trigger_does_not_multiply_crossings():
    rng = np.random.default_rng(1)
    t = np.arange(3000)
    x = np.sin(2 * np.pi * t / 300) + rng.normal(0, 0.1, t.size)
    naive = np.count_nonzero(np.diff(np.sign(x)))
    crossings, signs = schmitt_crossings(x, 3 * noise_std(x))
    assert crossings.size in (19, 20, 21) and naive > 2 * crossings.size
    assert np.all(np.diff(signs) != 0)  # alternate up and down


def test_mean_removal_follows_drift_and_setpoint_moves():
    t = np.arange(4000)
    mean = 0.003 * t + np.where(t > 2000, 5.0, 0.0)
    x = mean + np.sign(np.sin(2 * np.pi * t / 100))
    centred = remove_mean(x, 100)
    away = np.abs(t - 2000) > 100  # one period either side of the step
    assert np.abs(centred[away].mean()) < 0.02
    assert np.allclose(np.abs(centred[away][50:-50]), 1.0, atol=0.05)


def test_dominant_period_and_noise_level():
    t = np.arange(3000)
    rng = np.random.default_rng(0)
    x = np.sin(2 * np.pi * t / 73) + rng.normal(0, 0.2, t.size)
    period, strength = dominant_period(x)
    assert abs(period - 73) <= 1 and strength > 0.5
    assert noise_std(x) == pytest.approx(0.2, rel=0.1)


def test_horch_filter_cuts_noise_keeps_the_oscillation():
    t = np.arange(4000)
    rng = np.random.default_rng(0)
    clean = np.sin(2 * np.pi * t / 200)
    noisy = clean + rng.normal(0, 0.3, t.size)
    filtered = horch_filter(noisy, 200)
    assert np.std(filtered - clean) < 0.3 * 0.35
    # zero-phase: the peak does not move
    assert abs(np.argmax(filtered[:200]) - np.argmax(clean[:200])) <= 3


def test_short_and_flat_signals_do_not_oscillate():
    assert not analyze_cycles(np.zeros(500)).oscillating
    assert not analyze_cycles(np.sin(np.arange(30) / 3)).oscillating
