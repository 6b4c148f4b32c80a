"""Known answers of the signal helpers behind the cycle analysis (``cycles/_signal.py``)."""

import numpy as np
import pytest

from sktiction.cycles import (
    autocorrelation,
    dominant_period,
    horch_filter,
    moving_average,
    noise_std,
    remove_mean,
)
from sktiction.cycles._signal import first_lobe, unit_scaled


def test_noise_std_of_white_noise_and_of_records_too_short():
    rng = np.random.default_rng(0)
    # the MAD of 100 000 second differences is within 2 % of its limit
    assert noise_std(rng.normal(0, 0.3, 100_000)) == pytest.approx(0.3, rel=0.02)
    # a straight line has no second differences but zeros; a step only one large one
    assert noise_std(5 + 2 * np.arange(50)) == 0.0
    assert noise_std(np.r_[np.zeros(50), np.ones(50)]) == 0.0
    assert noise_std([1.0, 2.0]) == 0.0  # no second difference at all
    # constant curvature is a trend, not noise
    assert noise_std(0.01 * np.arange(500.0) ** 2) == pytest.approx(0.0, abs=1e-12)


def test_autocorrelation_is_the_normalised_lagged_product():
    rng = np.random.default_rng(1)
    x = rng.normal(size=64) + 3.0
    d = x - x.mean()
    direct = [np.dot(d[: d.size - k], d[k:]) / np.dot(d, d) for k in range(11)]
    r = autocorrelation(x, 10)
    assert r.shape == (11,) and r[0] == pytest.approx(1.0)
    assert np.allclose(r, direct)
    assert np.array_equal(autocorrelation(np.full(20, 4.0), 5), np.zeros(6))
    # a negative first lag, and a tiny amplitude, are normalised like any other
    alternating = (-1.0) ** np.arange(100)
    assert autocorrelation(alternating, 2)[1] == pytest.approx(-0.99)
    assert np.allclose(autocorrelation(1e-4 * x, 10), r)


@pytest.mark.parametrize(
    "r, expected",
    [
        ([1.0, 0.5, -0.2, 0.3, 0.6, 0.4, -0.1, 0.9], (4.0, 0.6)),  # later lobes ignored
        ([1.0, -0.5, 0.2, 0.7], (3.0, 0.7)),  # the lobe runs to the last lag
        ([1.0, 0.0, -0.5, 0.0, 0.3], (4.0, 0.3)),  # zeros are neither sign
        ([1.0, 0.5, 0.0, 0.4, -0.3, 0.6], (5.0, 0.6)),  # a touch of zero is no crossing
        ([1.0, -0.5, 0.3, 0.0, 0.6, -0.2], (4.0, 0.6)),  # nor the end of a lobe
        ([1.0, 0.5, 0.2], (np.nan, 0.0)),  # never below zero
        ([1.0, 0.5, -0.2, 0.0], (np.nan, 0.0)),  # never back above zero
    ],
)
def test_first_lobe_of_known_acfs(r, expected):
    lag, height = first_lobe(np.array(r))
    assert np.isnan(lag) if np.isnan(expected[0]) else lag == expected[0]
    assert height == expected[1]


def test_dominant_period_after_detrending_and_up_to_half_the_record():
    t = np.arange(2000)
    # a trend 100 times the oscillation keeps the raw ACF positive at every lag
    period, strength = dominant_period(np.sin(2 * np.pi * t / 80) + 0.05 * t)
    assert period == pytest.approx(80, abs=1) and strength > 0.9
    # lags up to half the record: a period of 0.4 n is still found
    period, _ = dominant_period(np.sin(2 * np.pi * np.arange(300) / 120))
    assert period == pytest.approx(120, abs=2)
    assert np.isnan(dominant_period(np.arange(100.0))[0])  # a line, detrended, is zero


def test_moving_average_known_values():
    x = np.array([0.0, 0, 0, 3, 0, 0, 0])
    assert np.allclose(moving_average(x, 3), [0, 0, 1, 1, 1, 0, 0])
    assert np.allclose(moving_average(x, 2.6), [0, 0, 1, 1, 1, 0, 0])  # rounded to 3
    # an even window takes one sample more before than after
    assert np.allclose(moving_average(x, 2), [0, 0, 0, 1.5, 1.5, 0, 0])
    # edge values are repeated, not zeros
    assert np.allclose(moving_average(np.array([3.0, 0, 0, 0, 6]), 3), [2, 1, 0, 2, 4])
    one = moving_average(x, 0.4)  # windows under 1 sample leave the signal as it is
    assert np.array_equal(one, x) and one is not x
    assert moving_average([1, 2, 3], 1).dtype == moving_average([1, 2, 3], 2).dtype == float


def test_remove_mean_uses_the_moving_mean_from_two_samples_to_half_the_record():
    t = np.arange(100)
    alternating = (-1.0) ** t
    step = np.where(t < 50, 0.0, 10.0)
    # period 2: the moving mean follows the step and leaves the alternation
    centred = remove_mean(step + alternating, 2)
    assert np.allclose(np.abs(np.delete(centred, [0, 50])), 1.0)
    # no usable period (NaN, under 2, over half the record): the least-squares line goes
    x = 3.0 + 0.2 * t + alternating
    line = np.polyval(np.polyfit(t, x, 1), t)
    for period in (np.nan, 1.9, 50.5, np.inf):
        assert np.allclose(remove_mean(x, period), x - line)
    assert np.allclose(remove_mean(x, 50), x - moving_average(x, 50))  # half the record
    assert np.array_equal(remove_mean([5.0], np.nan), [0.0])  # one sample has no slope
    assert np.allclose(remove_mean([1.0, 3.0], np.nan), [0.0, 0.0])  # two make a line


def test_horch_filter_gain_is_that_of_eq_23_run_twice():
    period = 200
    t = np.arange(20 * period)
    c = np.exp(-3 * 2 * np.pi / period)  # cut-off at three times the oscillation frequency
    w = 2 * np.pi / period
    gain = (1 - c) ** 2 / (1 - 2 * c * np.cos(w) + c**2)  # |H|^2: forwards and backwards
    y = horch_filter(np.sin(w * t) + 7.0, period)
    middle = slice(5 * period, 15 * period)
    assert np.ptp(y[middle]) / 2 == pytest.approx(gain, rel=1e-3)
    assert np.mean(y[middle]) == pytest.approx(7.0, abs=1e-3)  # unit gain at zero frequency
    x = np.sin(w * t)
    steps = np.repeat([0, 10, 3], 100)  # integers are filtered as numbers, not truncated
    assert np.allclose(horch_filter(steps, 20), horch_filter(steps.astype(float), 20))
    for no_period in (np.nan, 0, -5):
        assert np.array_equal(horch_filter(x, no_period), x)


def _same_values(a, b):
    """Equal values (a zero's sign aside: see fast_median), NaN in the same places, and
    the same dtype."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and np.array_equal(a, b, equal_nan=True)


def test_fast_median_is_numpys_median():
    from sktiction.cycles._signal import fast_median

    rng = np.random.default_rng(0)
    cases = [
        [7.5],  # one sample
        [2.0, -1.0],  # two: the mean of both
        [3.0, 1.0, 2.0],  # odd: the middle
        [4.0, 1.0, 3.0, 2.0],  # even: the mean of the two middles
        [0.1, 0.2, 0.3, 0.7],  # a mean that rounds (0.2 + 0.3) / 2
        [1.0, 1.0, 1.0, 5.0, 5.0],  # ties
        [-3.0, -2.0, 1e300, 1e300],  # the two middles' sum overflows: inf, as numpy
        rng.normal(size=101),
        rng.normal(size=100),
        np.round(rng.normal(size=1000), 1),  # many ties, as a quantised record
    ]
    for x in cases:
        x = np.asarray(x, dtype=float)
        with np.errstate(over="ignore"):
            assert _same_values(fast_median(x), np.median(x)), x
            assert _same_values(fast_median(-x), np.median(-x)), x
    # integers are averaged as floats (numpy's dtype), float32 stays float32
    for x in ([3, 1, 2], [4, 1, 3, 2], [2**53 + 1, 1, 2**53 + 1, 5]):
        x = np.asarray(x)
        assert _same_values(fast_median(x), np.median(x)), x
    x = np.asarray([0.1, 0.2, 0.3, 0.7], dtype=np.float32)
    assert _same_values(fast_median(x), np.median(x))
    assert fast_median(x).dtype == np.float32
    # NaN anywhere gives NaN (numpy's answer); an empty array NaN with numpy's warning
    assert np.isnan(fast_median([1.0, np.nan, 3.0]))
    assert np.isnan(fast_median([np.nan, 1.0]))
    with pytest.warns(RuntimeWarning):
        assert np.isnan(fast_median(np.array([])))


def test_fast_percentile_is_numpys_linear_percentile():
    from sktiction.cycles._signal import fast_percentile

    rng = np.random.default_rng(1)
    qs = [1, 5, 25, 50, 75, 95, 99, 0.5, 99.5, 100 / 3]
    cases = [
        [2.0, -1.0],  # two samples: a straight interpolation
        [3.0, 1.0, 2.0],  # q = 25 and 75 fall half-way (t = 0.5: numpy's upper branch)
        [0.1, 0.7, 0.3, 0.2],
        [1.0, 1.0, 1.0, 5.0, 5.0],  # ties
        rng.normal(size=7),
        rng.normal(size=100),
        rng.normal(size=1001) * 1e3,
        np.round(rng.normal(size=500), 1),
    ]
    for x in cases:
        x = np.asarray(x, dtype=float)
        got = fast_percentile(x, qs)
        assert got.shape == (len(qs),)
        assert _same_values(got, np.percentile(x, qs)), x
        lo, hi = fast_percentile(x, [5, 95])
        assert lo <= hi
    # t = 0.5 exactly, where numpy's two formulas round differently: b - d / 2, not a + d / 2
    x = np.array([0.1, 0.7, 1e16 + 2.0])
    for q in (25, 75):
        assert _same_values(fast_percentile(x, [q]), np.percentile(x, [q]))
    # one sample, integers, float32 and NaN: numpy's own answer
    for x in ([4.0], [3, 1, 2, 10], np.array([0.1, 0.2, 0.7], dtype=np.float32), [1.0, np.nan]):
        assert _same_values(fast_percentile(x, [5, 50, 95]), np.percentile(x, [5, 50, 95])), x
    # NaN anywhere makes every percentile NaN, not only those read next to it
    assert np.isnan(fast_percentile([1.0, 2.0, 3.0, np.nan, 4.0], [5, 50, 95])).all()


def test_noise_std_of_integers_is_that_of_their_values():
    # small integer types (ADC counts) would wrap in their second differences
    x = np.array([0, 120, -120, 100, -110, 90, 0, 127, -128, 5] * 20, dtype=np.int8)
    assert noise_std(x) == noise_std(x.astype(float)) > 0


def test_unit_scaled_only_moves_records_beyond_two_to_the_200():
    x = np.array([-3.0, 0.5, 2.0])
    # 3 * 2**198 = 0.75 * 2**200, frexp exponent 200: still within the range
    for ordinary in (x, x * 2.0**198, x * 2.0**-199, np.zeros(3), np.array([])):
        scaled, unit = unit_scaled(ordinary)
        assert scaled is ordinary and unit == 1.0  # read as given, to the bit
    # 3 * 2**300 lies in [2**301, 2**302): divided by 2**302, its largest magnitude 0.75
    scaled, unit = unit_scaled(x * 2.0**300)
    assert unit == 2.0**302 and np.array_equal(scaled, x / 4)
    scaled, unit = unit_scaled(x * 2.0**-300)
    assert unit == 2.0**-298 and np.array_equal(scaled, x / 4)
    big = np.array([1e300, np.inf])  # not finite: left to the caller's checks
    assert unit_scaled(big)[1] == 1.0
