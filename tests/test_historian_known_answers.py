"""Known answers of the recording effects in ``sktiction.simulation.historian``.

Records with a span worked out by hand (``arange(101)``: 5-95 % range 90), outputs from
each effect's definition (the value held, the band, the grid, the trailing mean, the
drift's ramp), and the swinging door against its definition: from each stored point,
the samples up to the next one fit one line within the deviation, and the sample after
does not (the kernel is ``@njit`` and not mutated: these tests are its check).
"""

import numpy as np
import pytest

from sktiction.simulation import (
    DeadbandCompression,
    HoldLastValue,
    IntervalAveraging,
    SensorDrift,
    ShortRecord,
    SpanQuantization,
    Spikes,
    SwingingDoorCompression,
)
from sktiction.simulation.historian import (
    _finite_length,
    _noise_sd,
    _span,
    _span_positions,
    _swinging_door,
    _unit,
)

RAMP = np.arange(101.0)  # its 5-95 % range: 95 - 5 = 90
EFFECTS = [
    HoldLastValue(0.3),
    DeadbandCompression(0.05),
    SwingingDoorCompression(0.05),
    IntervalAveraging(3),
    SpanQuantization(0.05),
    Spikes(0.05),
    SensorDrift(1.0),
    ShortRecord(50),
]


def rng(seed=0):
    return np.random.default_rng(seed)


def _signals(n=101):
    return {"pv": np.arange(float(n)), "op": 2.0 * np.arange(float(n)), "sp": np.ones(n)}


# ---------------------------------------------------------------- helpers


def test_span_is_numpys_percentile_range_at_every_interpolation_weight():
    """The 5-95 % range is ``np.percentile``'s to the bit, also where the weight is
    exactly 1/2 (lengths 11, 31, 51: numpy takes the upper formula there) and above it."""
    assert _span(RAMP) == 90.0
    assert _span(np.array([0.0, 1.0])) == pytest.approx(0.9)
    assert _span(np.array([3.0])) == 0.0 and _span(np.array([np.nan, 2.0, np.inf])) == 0.0
    r = rng(0)
    for n in [*range(2, 80), 11, 31, 51] * 8:
        x = r.standard_normal(n) * 1e3
        assert _span(x) == np.subtract(*np.percentile(x, [95, 5]))
    i, kth, t = _span_positions(11)
    assert t.tolist() == [0.5, 0.5] and not (i.flags.writeable or kth.flags.writeable)


def test_noise_sd_of_known_second_differences():
    """sd = 1.4826 * MAD(d2) / sqrt(6) over the non-zero second differences of the finite
    samples; fewer than 5 of them give 0."""
    d2 = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0])  # median 4, MAD 2
    x = np.concatenate([[0.0, 0.0], np.cumsum(np.cumsum(d2))])  # diff(x, 2) == d2
    expected = 1.4826 * 2.0 / np.sqrt(6.0)
    assert _noise_sd(x) == pytest.approx(expected, rel=1e-12)
    # frozen samples (zero second differences) and NaN are left out
    frozen = np.concatenate([x, np.full(6, x[-1]), [np.nan]])
    assert np.count_nonzero(np.diff(frozen[:-1], 2) == 0) >= 4
    assert _noise_sd(frozen) == pytest.approx(expected, rel=1e-12)
    five = np.concatenate([[0.0, 0.0], np.cumsum(np.cumsum([1.0, 2.0, 3.0, 4.0, 10.0]))])
    assert _noise_sd(five) == pytest.approx(1.4826 * 1.0 / np.sqrt(6.0), rel=1e-12)
    assert _noise_sd(five[:-1]) == 0.0  # four differences
    assert _noise_sd(np.full(50, 3.0)) == 0.0
    assert _unit(x, "noise") == _noise_sd(x) and _unit(RAMP, "span") == 90.0


def test_finite_length_counts_to_the_last_finite_pv():
    """Samples before the NaN padding, read from PV: a hole inside counts, OP is not read."""
    nan = np.nan
    assert _finite_length({"pv": np.array([1.0, nan, 3.0, nan, nan]), "op": np.ones(5)}) == 3
    assert _finite_length({"pv": np.array([1.0, 2.0])}) == 2
    assert _finite_length({"pv": np.array([5.0, nan])}) == 1
    assert _finite_length({"pv": np.full(4, nan), "op": np.ones(4)}) == 0


# ---------------------------------------------------------------- parameters


def test_parameters_are_kept_and_shown():
    """Defaults as documented; the repr lists each parameter."""
    assert repr(HoldLastValue(0.3)) == (
        "HoldLastValue(fraction=0.3, mean_run=5.0, channels=('pv', 'op', 'sp'))"
    )
    assert repr(DeadbandCompression(0.05)) == (
        "DeadbandCompression(unit='span', band=0.05, channels=('pv', 'op'))"
    )
    assert repr(SwingingDoorCompression(0.02)) == (
        "SwingingDoorCompression(deviation=0.02, channels=('pv', 'op'))"
    )
    assert repr(IntervalAveraging(4)) == "IntervalAveraging(window=4, channels=('pv', 'op'))"
    assert repr(SpanQuantization(0.1, unit="noise")) == (
        "SpanQuantization(unit='noise', step=0.1, channels=('pv',))"
    )
    assert repr(Spikes(0.01)) == "Spikes(rate=0.01, amplitude=1.0, channels=('pv',))"
    assert repr(SensorDrift(2)) == "SensorDrift(size=2.0, channels=('pv',))"
    assert repr(ShortRecord(2)) == "ShortRecord(n_samples=2)"
    assert type(IntervalAveraging(np.int64(3)).window) is int
    assert type(ShortRecord(np.int32(7)).n_samples) is int
    assert all(e.kind == "recording" for e in EFFECTS)


@pytest.mark.parametrize(
    "make, name, ok, bad",
    [
        (HoldLastValue, "fraction", [1e-6, 1.0], [0.0, 1.01, np.nan]),
        (lambda v: HoldLastValue(0.3, v), "mean_run", [1, 1.0, 30.0], [0.99, 0.5, "5"]),
        (DeadbandCompression, "band", [1e-6, 1.0], [0.0, 1.5]),
        (lambda v: DeadbandCompression(v, unit="noise"), "band", [1.5, 100.0], [0.0, 100.5]),
        (SwingingDoorCompression, "deviation", [1e-6, 1.0], [0.0, 1.5]),
        (IntervalAveraging, "window", [2, 3], [1, 2.0, 3.0]),
        (SpanQuantization, "step", [1e-6, 1.0], [0.0, 1.5]),
        (lambda v: SpanQuantization(v, unit="noise"), "step", [1.5, 100.0], [0.0, 100.5]),
        (Spikes, "rate", [1e-6, 0.5], [0.0, 0.6]),
        (lambda v: Spikes(0.01, v), "amplitude", [1e-6, 50.0], [0.0, -1.0, np.inf]),
        (SensorDrift, "size", [1e-6, 50.0], [0.0, -1.0]),
        (ShortRecord, "n_samples", [2, 3], [1, 2.0]),
    ],
)
def test_bounds_of_each_parameter(make, name, ok, bad):
    """Each parameter's documented range (shares up to 1, or up to 100 noise sd; a rate
    up to 0.5; integer windows and lengths from 2; runs from 1): its bounds accepted,
    values past them refused with an error naming it."""
    for v in ok:
        make(v)
    for v in bad:
        with pytest.raises(ValueError, match=f"^{name} must be"):
            make(v)


def test_channels_and_unit_are_checked():
    assert SwingingDoorCompression(0.1, channels=["sp"]).channels == ("sp",)
    for bad in [("pv", "xx"), ("PV",), ()]:
        with pytest.raises(ValueError, match="channels must be a non-empty subset"):
            DeadbandCompression(0.1, channels=bad)
    for bad in ["Noise", "sd", None]:
        with pytest.raises(ValueError, match="unit must be 'span' or 'noise'"):
            SpanQuantization(0.1, unit=bad)
    assert DeadbandCompression(0.1, unit="noise").unit == "noise"


@pytest.mark.parametrize(
    "effect", [*EFFECTS, SpanQuantization(0.05, channels=("pv", "sp"))], ids=repr
)
def test_integer_records_come_back_as_float_and_inputs_untouched(effect):
    """Integer-valued records give the float record's output, as float arrays on every
    channel the effect records (a constant one included), and the arrays passed in are
    not changed."""
    ints = {"pv": (np.arange(101) * 3) % 37, "op": (np.arange(101) * 5) % 37,
            "sp": np.full(101, 4)}  # fmt: skip
    floats = {c: v.astype(float) for c, v in ints.items()}
    copies = {c: v.copy() for c, v in floats.items()}
    a = effect.record(ints, 1.0, rng(3))
    b = effect.record(floats, 1.0, rng(3))
    for c in getattr(effect, "channels", ints):
        assert a[c].dtype == np.float64
    for c in ints:
        np.testing.assert_array_equal(a[c], b[c])
        np.testing.assert_array_equal(floats[c], copies[c])


# ---------------------------------------------------------------- hold last value


def test_hold_share_and_run_lengths():
    """Runs are geometric with mean ``mean_run``; every run follows a stored row, so the
    share held is mean_run / (mean_run / fraction + 1) (fraction capped at 0.99): 0.2830
    for (0.3, 5), 0.8264 for (1.0, 5), 0.4 for (0.5, 2)."""
    for (fraction, mean_run), share, tol in [
        ((0.3, 5.0), 5.0 / (5.0 / 0.3 + 1.0), 0.01),
        ((1.0, 5.0), 5.0 / (5.0 / 0.99 + 1.0), 0.002),
        ((0.5, 2.0), 0.4, 0.004),
    ]:
        held = HoldLastValue(fraction, mean_run).mask(200_000, rng(1))
        assert not held[0]
        assert held.mean() == pytest.approx(share, abs=tol)
        edges = np.diff(np.concatenate([[0], held.astype(int), [0]]))
        runs = np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)
        assert runs.mean() == pytest.approx(mean_run, rel=0.05)
        assert np.mean(runs == 1) == pytest.approx(1.0 / mean_run, abs=0.02)


def test_hold_repeats_the_stored_row_on_every_channel_and_keeps_the_padding():
    """Held rows repeat the row before on PV, OP and SP alike; other rows are the
    record's; the NaN padding stays NaN (no held value carried into it)."""
    n, pad = 400, 60
    sig = _signals(n)
    for c in sig:
        sig[c][n - pad :] = np.nan
    effect = HoldLastValue(0.9, 3.0)
    held = effect.mask(n, rng(2))
    assert held[1] and held[n - pad :].any()  # the first row is repeated; runs reach the padding
    out = effect.record(sig, 1.0, rng(2))
    for c in ("pv", "op", "sp"):
        x, y = sig[c], out[c]
        for k in range(1, n - pad):
            assert y[k] == (y[k - 1] if held[k] else x[k])
        assert y[0] == x[0] and np.isnan(y[n - pad :]).all()


def test_hold_leaves_other_channels_and_absent_ones():
    sig = {"pv": np.arange(300.0), "op": np.arange(300.0)}
    out = HoldLastValue(0.5, channels=("pv", "sp")).record(sig, 1.0, rng(0))
    assert out["op"] is sig["op"] and "sp" not in out
    assert (np.diff(out["pv"]) == 0).mean() > 0.3


# ---------------------------------------------------------------- deadband


def _deadband_by_hand(x, band):
    out, last = [], np.nan
    for v in x:
        if np.isfinite(v) and (not np.isfinite(last) or abs(v - last) > band):
            last = v
        out.append(v if not np.isfinite(v) else last)
    return np.array(out)


def test_deadband_of_a_ramp_in_span_units():
    """A band of 0.015 x 90 = 1.35 on a unit ramp: a value is stored every second
    sample, so the record reads 0, 0, 2, 2, 4, ...; SP (not a default channel) is kept."""
    sig = _signals()
    out = DeadbandCompression(0.015).record(sig, 1.0, None)
    k = np.arange(101.0)
    np.testing.assert_array_equal(out["pv"], k - k % 2)
    # OP moves 2 per sample against a band of 0.015 x 180 = 2.7: every second sample too
    np.testing.assert_array_equal(out["op"], 2 * (k - k % 2))
    assert out["sp"] is sig["sp"]


def test_deadband_in_noise_units():
    """With ``unit="noise"`` the band is ``band`` noise sd: on a record of known noise sd
    the held values are the exception-deviation definition's."""
    x = np.cumsum(np.cumsum(rng(5).standard_normal(300)))
    x[40:45] = np.nan
    band = 3.0 * _noise_sd(x)
    assert band > 0
    out = DeadbandCompression(3.0, channels=("pv",), unit="noise").record({"pv": x}, 1.0, None)
    np.testing.assert_array_equal(out["pv"], _deadband_by_hand(x, band))
    span = DeadbandCompression(0.05, channels=("pv",)).record({"pv": x}, 1.0, None)
    np.testing.assert_array_equal(span["pv"], _deadband_by_hand(x, 0.05 * _span(x)))


# ---------------------------------------------------------------- swinging door


def _fits(x, p, q, dev):
    """Is there a line through (p, x[p]) within ``dev`` of every sample p+1..q?"""
    j = np.arange(p + 1, q + 1)
    return np.max((x[j] - x[p] - dev) / (j - p)) <= np.min((x[j] - x[p] + dev) / (j - p))


def _knots(out, scale):
    """Rows where the drawn lines bend (stored points), with both ends."""
    bend = np.flatnonzero(np.abs(np.diff(out, 2)) > 1e-9 * scale) + 1
    return np.concatenate([[0], bend, [len(out) - 1]])


def test_swinging_door_small_records_worked_by_hand():
    """[0, 1, 0.2, 5] with deviation 0.6: from 0 the slopes 0.4..0.4 still fit sample 2,
    sample 3 needs 4.4 / 3: sample 2 is stored and the line 0 -> 0.2 is drawn (sample 1
    ends 0.9 off it: the door bounds the line from the stored point, the chord drawn to
    the next one can be off by up to twice the deviation)."""
    np.testing.assert_allclose(_swinging_door(np.array([0, 1, 0.2, 5.0]), 0.6), [0, 0.1, 0.2, 5])
    zigzag = np.array([0, 1, 0, 1, 0.0])
    np.testing.assert_array_equal(_swinging_door(zigzag, 1.0), np.zeros(5))  # all within 1
    np.testing.assert_array_equal(_swinging_door(zigzag, 0.5), zigzag)  # every turn stored
    np.testing.assert_array_equal(_swinging_door(np.array([4.0, 7.0]), 10.0), [4.0, 7.0])


def test_swinging_door_straight_lines_and_zero_deviation():
    """A straight line stores only its ends (the drawn line is the line); with deviation 0
    every sample where an integer-valued record bends is stored (the record comes back);
    a deviation wider than the range draws one line from the first to the last sample."""
    line = 3.0 + 0.25 * np.arange(50)
    np.testing.assert_allclose(_swinging_door(line, 0.01), line, rtol=0, atol=1e-12)
    bent = np.array([0, 1, 2, 3, 2, 1, 0, 0, 0, 5, 10, 15, 14.0])
    np.testing.assert_array_equal(_swinging_door(bent, 0.0), bent)
    x = np.sin(np.arange(200) / 9.0)
    np.testing.assert_allclose(_swinging_door(x, 2.5), np.linspace(x[0], x[-1], 200), atol=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_swinging_door_stores_where_its_definition_does(seed):
    """On noisy curves: the ends are kept, the stored points (where the lines bend) are
    samples of the record, from each the samples up to the next fit one line within the
    deviation and the sample after does not, and no sample is twice the deviation off."""
    r = rng(seed)
    n = int(r.integers(50, 400))
    x = np.cumsum(r.standard_normal(n)) + r.normal(0, 0.3, n)
    dev = float(r.uniform(0.05, 2.0))
    out = _swinging_door(x, dev)
    knots = _knots(out, np.ptp(x))
    assert out[0] == x[0] and out[-1] == x[-1]
    np.testing.assert_array_equal(out[knots], x[knots])
    assert len(knots) < n  # it compresses
    for p, q in zip(knots[:-1], knots[1:]):
        assert _fits(x, p, q, dev)
        if q < n - 1:
            assert not _fits(x, p, q + 1, dev)
        k = np.arange(p, q + 1)
        np.testing.assert_allclose(out[k], x[p] + (x[q] - x[p]) * (k - p) / (q - p), atol=1e-9)
    assert np.max(np.abs(out - x)) <= 2 * dev


def test_swinging_door_record_uses_the_span_and_skips_nan():
    """The deviation is a share of the span; NaN samples stay NaN and the door runs over
    the finite ones; 3 finite samples are enough, 2 are left alone."""
    zigzag = np.tile([0.0, 1.0], 51)[:101]  # span 1 (50 zeros, 51 ones)
    wide = SwingingDoorCompression(1.0, channels=("pv",)).record({"pv": zigzag}, 1.0, None)
    np.testing.assert_array_equal(wide["pv"], np.zeros(101))
    tall = SwingingDoorCompression(1.0, channels=("pv",)).record({"pv": 10 * zigzag}, 1.0, None)
    np.testing.assert_array_equal(tall["pv"], np.zeros(101))  # span 10: a door of 10
    narrow = SwingingDoorCompression(0.4).record({"pv": zigzag, "op": zigzag}, 1.0, None)
    np.testing.assert_array_equal(narrow["pv"], zigzag)
    np.testing.assert_array_equal(narrow["op"], zigzag)
    holed = zigzag.copy()
    holed[[3, 10, 11]] = np.nan
    out = SwingingDoorCompression(1.0, channels=("pv",)).record({"pv": holed}, 1.0, None)
    assert np.array_equal(np.isnan(out["pv"]), np.isnan(holed))
    assert np.all(out["pv"][np.isfinite(holed)] == 0.0)
    # three samples: span 0.9 (5 %: 0, 95 %: 0.9), the middle one is 1 - 0.9 = 0.1 inside
    three = np.array([0.0, 1.0, 0.0, np.nan])
    out = SwingingDoorCompression(1.0, channels=("pv",)).record({"pv": three}, 1.0, None)
    np.testing.assert_array_equal(out["pv"], [0.0, 0.0, 0.0, np.nan])
    two = {"pv": np.array([0.0, np.nan, 1.0])}
    out = SwingingDoorCompression(1.0, channels=("pv",)).record(two, 1.0, None)
    np.testing.assert_array_equal(out["pv"], two["pv"])
    sp = np.sin(np.arange(100.0))
    assert SwingingDoorCompression(1.0).record({"pv": zigzag, "sp": sp}, 1.0, None)["sp"] is sp


# ---------------------------------------------------------------- averaging, grid


def test_interval_averages_worked_by_hand():
    """Window 3 on 3, 6, 9, 12: the first samples average what exists so far."""
    sig = {"pv": np.array([3.0, 6.0, 9.0, 12.0]), "op": np.array([0.0, 0, 3, 3]),
           "sp": np.array([1.0, 2, 3, 4])}  # fmt: skip
    out = IntervalAveraging(3).record(sig, 1.0, None)
    np.testing.assert_allclose(out["pv"], [3.0, 4.5, 6.0, 9.0])
    np.testing.assert_allclose(out["op"], [0.0, 0.0, 1.0, 2.0])
    assert out["sp"] is sig["sp"]
    out = IntervalAveraging(2, channels=("sp",)).record(sig, 1.0, None)
    np.testing.assert_allclose(out["sp"], [1.0, 1.5, 2.5, 3.5])
    assert out["pv"] is sig["pv"]


def test_span_quantisation_worked_by_hand():
    """Step 0.1 of a span of 90 is a grid of 9: 4 -> 0, 5 -> 9, 13 -> 9, 14 -> 18;
    a constant channel (span 0) is left as it is."""
    sig = {"pv": RAMP.copy(), "op": RAMP.copy(), "sp": np.full(101, 7.5)}
    out = SpanQuantization(0.1, channels=("pv", "sp")).record(sig, 1.0, None)
    np.testing.assert_allclose(out["pv"], np.round(RAMP / 9.0) * 9.0)
    assert out["pv"][[4, 5, 13, 14]].tolist() == [0.0, 9.0, 9.0, 18.0]
    np.testing.assert_array_equal(out["sp"], sig["sp"])
    assert out["op"] is sig["op"]


def test_span_quantisation_in_noise_units():
    """With ``unit="noise"`` the grid step is ``step`` noise sd."""
    x = 100.0 + np.cumsum(np.cumsum(rng(4).standard_normal(400)))
    q = 2.0 * _noise_sd(x)
    out = SpanQuantization(2.0, unit="noise").record({"pv": x}, 1.0, None)["pv"]
    np.testing.assert_allclose(out, np.round(x / q) * q)
    assert np.max(np.abs(out - x)) <= q / 2 + 1e-9


# ---------------------------------------------------------------- spikes, drift, short


def test_spikes_sizes_signs_and_rate():
    """About ``rate`` of the finite samples are hit, by 0.5-1.5 x amplitude x span with
    either sign; the other samples and the NaN padding are as they were."""
    n, pad = 20_000, 500
    x = np.concatenate([np.arange(float(n - pad)), np.full(pad, np.nan)])
    span = _span(x)
    out = Spikes(0.01, amplitude=0.1, channels=("pv", "op")).record(
        {"pv": x, "op": x, "sp": x}, 1.0, rng(0)
    )
    assert out["sp"] is x and np.isnan(out["pv"][n - pad :]).all()
    for c in ("pv", "op"):
        d = out[c][: n - pad] - x[: n - pad]
        hit = d != 0
        assert 150 <= hit.sum() <= 250  # 195 expected, sd 14
        size = np.abs(d[hit]) / (0.1 * span)
        assert 0.5 <= size.min() < 0.55 and 1.45 < size.max() <= 1.5
        assert size.mean() == pytest.approx(1.0, abs=0.06)
        assert 0.35 < np.mean(d[hit] > 0) < 0.65
    assert not np.array_equal(out["pv"], out["op"])  # drawn for each channel


def test_spike_size_follows_the_amplitude():
    x = np.sin(np.arange(3000) / 30.0)
    a = Spikes(0.02, amplitude=1.0).record({"pv": x}, 1.0, rng(1))["pv"] - x
    b = Spikes(0.02, amplitude=3.0).record({"pv": x}, 1.0, rng(1))["pv"] - x
    np.testing.assert_allclose(b, 3.0 * a)


def test_drift_is_a_ramp_of_size_times_span():
    """The drift grows linearly from 0 on the first sample to +-size x span on the last
    finite one, with one sign for all channels, both signs over seeds; padding stays."""
    n = 101
    pad = np.full(20, np.nan)
    sig = {"pv": np.concatenate([RAMP, pad]), "op": np.concatenate([2 * RAMP, pad]),
           "sp": np.ones(n + 20)}  # fmt: skip
    signs = set()
    for seed in range(12):
        out = SensorDrift(2.0, channels=("pv", "op")).record(sig, 1.0, rng(seed))
        d_pv = out["pv"][:n] - RAMP
        d_op = out["op"][:n] - 2 * RAMP
        sign = np.sign(d_pv[-1])
        np.testing.assert_allclose(d_pv, sign * 180.0 * np.linspace(0, 1, n), atol=1e-9)
        np.testing.assert_allclose(d_op, sign * 360.0 * np.linspace(0, 1, n), atol=1e-9)
        assert np.isnan(out["pv"][n:]).all() and out["sp"] is sig["sp"]
        signs.add(sign)
    assert signs == {-1.0, 1.0}


def test_drift_of_two_and_one_finite_samples():
    """Two samples 0, 1 (span 0.9): the second moves by size x 0.9; one sample (span 0)
    does not move."""
    out = SensorDrift(1.0).record({"pv": np.array([0.0, 1.0])}, 1.0, rng(0))
    assert out["pv"][0] == 0.0 and abs(out["pv"][1] - 1.0) == pytest.approx(0.9)
    out = SensorDrift(1.0).record({"pv": np.array([5.0, np.nan])}, 1.0, rng(0))
    np.testing.assert_array_equal(out["pv"], [5.0, np.nan])


def test_short_record_pads_every_channel():
    sig = {"pv": np.arange(6.0), "op": np.ones(6), "sp": np.zeros(6), "extra": np.arange(6)}
    out = ShortRecord(4).record(sig, 1.0, None)
    for c, x in sig.items():
        np.testing.assert_array_equal(out[c], np.concatenate([x[:4], [np.nan] * 2]))
    assert not np.isnan(sig["pv"]).any()
    np.testing.assert_array_equal(ShortRecord(10).record(sig, 1.0, None)["op"], sig["op"])
