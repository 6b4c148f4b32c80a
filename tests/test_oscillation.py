"""Oscillation detection per component: known answers, failure classes, the transformer."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from sktiction import OscillationFeatures
from sktiction.cycles import analyze_cycles, detect_oscillations
from sktiction.cycles._analysis import (
    CONFIRM_ACF,
    _above_shares,
    _bimodal,
    _fall_shares,
    _lopsided,
)

# the nearest benchmarks/ above this file (mutation testing runs a copy of tests/ one
# level further down)
BENCH = next(
    p / "benchmarks" / "bench_oscillation.py"
    for p in Path(__file__).resolve().parents
    if (p / "benchmarks" / "bench_oscillation.py").exists()
)


def _bench():
    spec = importlib.util.spec_from_file_location("bench_oscillation", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_pure_sinusoid_has_index_one_and_its_period():
    t = np.arange(3000)
    for period in (8.0, 37.5, 250.0):
        a = analyze_cycles(np.sin(2 * np.pi * t / period + 1.0))
        assert a.oscillating and a.oscillation_index > 0.99
        assert a.periods.size == 1 and a.periods[0] == pytest.approx(period, rel=0.01)
        assert a.regularities[0] > 1  # Thornhill: regular


def test_an_export_finer_than_stored_reads_its_spacing():
    from sktiction.cycles._oscillation import _fresh_spacing

    rng = np.random.default_rng(3)

    def drawn(pieces):  # lines between stored values of white noise, ``pieces`` apart
        knots = np.concatenate([[0], np.cumsum(pieces)])
        return np.interp(np.arange(knots[-1] + 1), knots, rng.normal(size=knots.size))

    assert _fresh_spacing(drawn(np.full(300, 3))) == 3
    # one piece in twenty of one sample: 1.95 samples per piece, median 2 (a bound that
    # skipped the median below 2 samples per piece would read 1)
    twos = np.full(400, 2)
    twos[::20] = 1
    assert _fresh_spacing(drawn(twos)) == 2
    assert _fresh_spacing(rng.normal(size=800)) == 1  # bent everywhere: as recorded


def test_white_noise_has_no_oscillation():
    hits = [analyze_cycles(np.random.default_rng(s).normal(size=2000)) for s in range(100)]
    assert sum(a.oscillating for a in hits) <= 2
    assert np.median([a.oscillation_index for a in hits]) < 0.1
    assert all(a.periods.size == int(a.oscillating) for a in hits if a.periods.size <= 1)


def test_two_sinusoids_give_two_components_with_their_periods():
    t = np.arange(4000)
    rng = np.random.default_rng(3)
    x = np.sin(2 * np.pi * t / 23) + 0.8 * np.sin(2 * np.pi * t / 140) + rng.normal(0, 0.3, t.size)
    a = analyze_cycles(x)
    assert a.oscillating
    assert np.sort(a.periods) == pytest.approx([23, 140], rel=0.03)


def test_harmonics_of_a_square_wave_are_not_components():
    t = np.arange(3000)
    a = analyze_cycles(np.sign(np.sin(2 * np.pi * t / 90)))
    assert a.periods == pytest.approx([90], rel=0.02)


def test_oscillation_under_a_strong_drift_is_found():
    rng = np.random.default_rng(0)
    t = np.arange(3000)
    walk = np.cumsum(rng.normal(size=t.size))
    drift = 8 * walk / np.ptp(walk) + 0.004 * t  # drift spans 8 times the cycle's swing
    a = analyze_cycles(np.sin(2 * np.pi * t / 60) + drift + rng.normal(0, 0.2, t.size))
    assert a.oscillating
    assert a.periods[0] == pytest.approx(60, rel=0.05)
    assert len(a.cycles) >= 30  # the cycles are localised too, on the detected period


def test_quarter_of_samples_repeated_still_found():
    bench = _bench()
    found = 0
    for seed in range(20):
        rng = np.random.default_rng(seed)
        period = rng.uniform(20, 120)
        t = np.arange(2000)
        x = np.sin(2 * np.pi * t / period) + rng.normal(0, 0.2, t.size)
        held = bench._hold(rng, x, 0.25)
        assert 0.15 < np.mean(np.diff(held) == 0) < 0.35
        a = analyze_cycles(held)
        found += a.oscillating and abs(a.periods[0] - period) < 0.1 * period
    assert found >= 19


def test_index_is_a_probability_like_score():
    rng = np.random.default_rng(1)
    t = np.arange(2000)
    indices = [
        detect_oscillations(np.sin(2 * np.pi * t / 50) * amp + rng.normal(size=t.size))[0].index
        for amp in (0.0, 0.1, 0.3, 1.0, 3.0)
    ]
    assert all(0.0 <= i <= 1.0 for i in indices)
    assert indices[0] < 0.5 < indices[-1]
    assert indices[-1] >= indices[-2] >= indices[-3]  # more cycle, more index


@pytest.mark.parametrize("k", [3, 5])
def test_an_export_finer_than_the_stored_record_adds_no_cycle(k):
    # k rows per stored value, held or interpolated: the stored record's Nyquist band
    # edge lies at 2k rows per cycle, where white noise read as a peak (50-73 % of
    # records at k = 3 and 5 before); a real cycle keeps its period in rows
    calls, found = 0, 0
    for seed in range(20):
        rng = np.random.default_rng(seed)
        noise = rng.normal(size=int(rng.integers(300, 1500)))
        rows = np.arange((noise.size - 1) * k + 1) / k
        for finer in (np.repeat(noise, k), np.interp(rows, np.arange(noise.size), noise)):
            calls += analyze_cycles(finer).oscillating
            period = rng.uniform(8, 60)
            cycle = np.sin(2 * np.pi * np.arange(noise.size) / period) + 0.3 * noise
            a = analyze_cycles(np.repeat(cycle, k))
            found += a.oscillating and abs(a.periods[0] / (k * period) - 1) < 0.1
    assert calls <= 1 and found >= 39


def test_cycles_drawn_between_their_corners_are_not_read_as_finer_exports():
    # piecewise straight records whose stored values cycle: their pieces are the cycle's
    rng = np.random.default_rng(1)
    corners = np.arange(0, 3100, 50)
    peaks = (-1.0) ** np.arange(corners.size) * (1 + 0.05 * rng.normal(size=corners.size))
    triangle = np.interp(np.arange(3000), corners, peaks)
    t = np.arange(4000)
    square = np.where((t // 60) % 2 == 0, 1.0, -1.0) * np.repeat(
        1 + 0.1 * rng.normal(size=t.size // 60 + 2), 60)[: t.size]
    kept, compressed = 0.0, square + 0.02 * rng.normal(size=t.size)
    for i in range(t.size):  # stored only when it moved more than 0.2 (a compression band)
        kept = compressed[i] if abs(compressed[i] - kept) > 0.2 else kept
        compressed[i] = kept
    stairs = np.repeat(np.tile([0.0, 1.0, 2.0], 40) + 0.05 * rng.normal(size=120), 40)
    for x in (triangle, triangle + 1e-4 * np.arange(3000), compressed, stairs):
        assert analyze_cycles(x).oscillating


def test_an_interpolated_export_written_with_few_decimals_adds_no_cycle():
    calls = 0
    for seed in range(20):
        noise = np.random.default_rng(seed).normal(size=600)
        rows = np.arange(3 * 599 + 1) / 3
        for decimals in (6, 3):
            finer = np.round(np.interp(rows, np.arange(600), noise), decimals)
            calls += analyze_cycles(finer).oscillating
    assert calls <= 1


def test_degenerate_signals_have_no_components():
    assert detect_oscillations(np.zeros(500)) == []
    assert detect_oscillations(np.arange(10.0)) == []
    assert detect_oscillations(np.r_[np.ones(100), np.nan]) == []
    assert not analyze_cycles(np.zeros(500)).oscillating
    assert analyze_cycles(np.zeros(500)).oscillation_index == 0.0


@pytest.mark.parametrize(
    "kind",
    [
        "irregular",
        "noise_driven",
        "two_frequencies",
        "drifting",
        "intermittent",
        "short_period",
        "few_slow_cycles",
        "compressed",
    ],
)
def test_failure_classes_are_found(kind):
    bench = _bench()
    rng = np.random.default_rng([99, bench.OSCILLATING.index(kind)])
    hits = sum(analyze_cycles(bench.make_signal(kind, rng)[0]).oscillating for _ in range(40))
    # 0.95 is the goal on the benchmark, 0.9 here for a small sample; a cycle under a
    # random walk 3-10 times its swing is found 0.91 of the time (benchmark), less in
    # short records, where the walk's own wiggles at the cycle's period can match it
    assert hits >= (34 if kind == "drifting" else 36)


@pytest.mark.parametrize(
    "kind",
    ["coloured_noise", "random_walk", "steps", "repeated_noise", "drift", "closed_loop",
     "stepped_noise", "saturated_noise", "skewed_noise"],  # fmt: skip
)
def test_quiet_counterparts_rarely_raise_alarms(kind):
    # closed_loop: PV or OP of an ordinarily tuned PI loop (gain margin 2-4), its own noise;
    # stepped_noise: coloured noise under 1-3 setpoint or load steps; saturated_noise and
    # skewed_noise: the same held at a limit, or through an exponential
    bench = _bench()
    rng = np.random.default_rng([99, 100 + bench.QUIET.index(kind)])
    hits = sum(analyze_cycles(bench.make_signal(kind, rng)[0]).oscillating for _ in range(40))
    assert hits <= 4  # goal 0.05 on the benchmark; 0.1 here for a small sample


def _in_manual(x, rng):
    length = int(0.3 * x.size)  # the operator holds OP for 30 % of the record
    start = rng.integers(x.size // 20, x.size - length - x.size // 20)
    x = x.copy()
    x[start : start + length] = x[start]
    return x


def _spiked(x, rng):
    x = x.copy()
    rows = rng.choice(x.size, 10, replace=False)
    x[rows] += rng.choice([-20.0, 20.0], 10) * np.std(x)
    return x


def _held_since_fresh(x, fresh):
    """``x`` with every row that is not ``fresh`` holding the last fresh row's value (the
    first row is always kept)."""
    return x[np.maximum.accumulate(np.where(fresh, np.arange(x.size), 0))]


def _on_off(x, h):
    """A relay with hysteresis: on above ``h``, off below ``-h``, as it was in between."""
    state = np.where(x > h, 1.0, np.where(x < -h, 0.0, np.nan))
    state[0] = float(x[0] > 0) if np.isnan(state[0]) else state[0]
    return _held_since_fresh(state, ~np.isnan(state))


#: what a plant record does to a signal: (name, distortion of a noisy unit-amplitude
#: cycle, or of white noise)
RECORDED = [
    ("clipped at half its amplitude", lambda x, rng: np.clip(x, -0.5, 0.5)),
    ("saturated at one end", lambda x, rng: np.minimum(x, 0.3)),
    ("held in manual for 30 %", _in_manual),
    ("ten spikes of 20 sd", _spiked),
    ("integers, 1 % of a 0-100 span", lambda x, rng: np.round(50 + 3 * x)),
    ("an on/off valve switched at +-0.5", lambda x, rng: _on_off(x, 0.5)),
]


@pytest.mark.parametrize("name,distort", RECORDED, ids=[r[0] for r in RECORDED])
def test_cycles_survive_what_a_plant_record_does_to_them(name, distort):
    # a plant window (751 samples) of a cycle of 20-100 samples under noise of 0.7 its
    # amplitude, saturated, held, spiked, gridded or switched: always found at its
    # period; the same done to white noise: never an oscillation
    rng = np.random.default_rng(7)
    t = np.arange(751)
    for _ in range(10):
        period = rng.uniform(20, 100)
        cycle = np.sin(2 * np.pi * t / period + rng.uniform(0, 2 * np.pi))
        found = analyze_cycles(distort(cycle + 0.7 * rng.normal(size=t.size), rng))
        assert found.oscillating, (name, period)
        assert np.min(np.abs(found.periods / period - 1)) < 0.1, (name, period, found.periods)
        assert not analyze_cycles(distort(rng.normal(size=t.size), rng)).oscillating, name


def _drawn_cycles(rng, shortest, longest, cycle, size=751):
    """Cycles whose length is drawn from ``shortest``-``longest`` samples each time and
    amplitude wanders by 10 %, shaped by ``cycle(period, amp)`` (which may draw more), with
    a little white noise."""
    cycles = []
    while sum(map(len, cycles)) < size:
        period, amp = int(rng.uniform(shortest, longest)), 1 + 0.1 * rng.normal()
        cycles.append(cycle(period, amp))
    return np.concatenate(cycles)[:size] + 0.03 * rng.normal(size=size)


def _saw_tooth(rng, shortest, longest, size=751):
    """A sticky valve's OP: teeth rising over 60-85 % of each cycle."""

    def tooth(period, amp):
        rise = int(period * rng.uniform(0.6, 0.85))
        return np.r_[np.linspace(-amp, amp, rise), np.linspace(amp, -amp, period - rise)]

    return _drawn_cycles(rng, shortest, longest, tooth, size)


@pytest.mark.parametrize("shortest,longest,tried,found", [(50, 100, 20, 20), (40, 120, 30, 27)])
def test_a_stick_slip_saw_tooth_of_wandering_period_and_held_rows_is_found(
    shortest, longest, tried, found
):
    # a plant window (751 samples at 10 s) of a stick-slip saw-tooth whose cycles last
    # 50-100 or 40-120 samples (Thornhill's r of such timing about 1.7 and 1.1), 40 % of
    # its rows held by the historian: all found, or most where the timing is loosest.
    # Without the time-domain confirmation of regular cycles: 19 of 20 and 22 of 30;
    # 26 of 30 with it when the ACF alone may confirm, 29 now that lopsided cycles do
    rng = np.random.default_rng(11)
    hits = 0
    for _ in range(tried):
        fresh = rng.random(751) > 0.4  # the rows the historian stored anew
        held = _held_since_fresh(_saw_tooth(rng, shortest, longest), fresh)
        hits += analyze_cycles(held).oscillating
    assert hits >= found


@pytest.mark.parametrize("shape,found", [("sine", 19), ("triangle", 19), ("square", 19),
                                         ("saw", 18)])  # fmt: skip
def test_a_cycle_whose_period_doubles_across_the_record_is_found(shape, found):
    # a limit cycle whose load or operating point moves during the record: its period
    # doubles (or halves) from the first sample to the last, 8-15 cycles in 1,500-5,000
    # samples, white noise of 0.3 of the amplitude; 20 of 20 of each shape found (19 of
    # 20 saw-teeth at seed 6), each at a period within the cycle's range. Without the
    # time-domain confirmation 6 saw-teeth of 20 are found, with twice the few-cycles
    # penalty 7 (benchmarks/bench_oscillation.py --drifting-period: factors 1-3, pulses)
    assert _found_with_a_doubling_period(shape, 0.3) >= found


def _found_with_a_doubling_period(shape, noise, count=20):
    """How many of ``count`` cycles (seeded) whose period doubles or halves across 8-15
    cycles in 1,500-5,000 samples, under white noise of sd ``noise``, are found at a
    period within the cycle's range."""
    chirped = _bench().chirped
    rng = np.random.default_rng(5)
    hits = 0
    for _ in range(count):
        n = int(rng.integers(1500, 5000))
        first = 2 * n / rng.uniform(8, 15) / 3  # the mean period n / cycles
        a, b = (first, 2 * first) if rng.random() < 0.5 else (2 * first, first)
        res = analyze_cycles(chirped(shape, n, a, b) + rng.normal(0, noise, n))
        hits += res.oscillating and 0.8 * min(a, b) <= res.periods[0] <= 1.2 * max(a, b)
    return hits


def test_a_pulse_train_whose_period_doubles_is_found_by_its_lopsided_cycles():
    # pulses high for a tenth of each cycle, whose period doubles (or halves) across the
    # record, under white noise of a tenth of their height: their harmonics smear into a
    # flat spectrum, and the regular cycles' time above their middle is what finds them.
    # 18 of 20 found at their period; 8 when lopsided cycles add no more evidence than
    # the ACF gate (LOPSIDED_EVIDENCE 0.5); chirped pulses are high for a tenth by default
    assert _found_with_a_doubling_period("pulse", 0.1) >= 15


def _pulse_train(rng, shortest, longest, size=751):
    """Cycles high (about 1) for 20-30 % of each and low (a third of that, negative) for
    the rest."""

    def pulse(period, amp):
        high = int(period * rng.uniform(0.2, 0.3))
        return np.r_[np.full(high, amp), np.full(period - high, -amp / 3)]

    return _drawn_cycles(rng, shortest, longest, pulse, size)


def _shape(name, period=80, size=2000):
    """A clean cycle of a known shape: a ramp with a fast return ("saw_up", mirrored in
    "saw_down"), high for a fifth of each cycle ("pulses", mirrored in "pulses_down"), a
    sine, a triangle, a square wave."""
    phase = 2 * np.pi * np.arange(size) / period
    ramp = (phase / np.pi) % 2 - 1
    pulses = np.where((phase / (2 * np.pi)) % 1 < 0.2, 1.0, -0.25)
    return {"saw_up": ramp, "saw_down": -ramp, "pulses": pulses, "pulses_down": -pulses,
            "sine": np.sin(phase), "triangle": 2 / np.pi * np.arcsin(np.sin(phase)),
            "square": np.sign(np.sin(phase))}[name]  # fmt: skip


@pytest.mark.parametrize(
    "share,shape,low,high",
    [("fall_share", "saw_up", 0.0, 0.1), ("fall_share", "saw_down", 0.9, 1.0),
     ("fall_share", "sine", 0.45, 0.55), ("fall_share", "triangle", 0.45, 0.55),
     ("fall_share", "square", 0.35, 0.65),
     ("above_share", "pulses", 0.15, 0.35), ("above_share", "pulses_down", 0.65, 0.85),
     ("above_share", "sine", 0.45, 0.55), ("above_share", "triangle", 0.45, 0.55),
     ("above_share", "saw_up", 0.45, 0.55)],
)  # fmt: skip
def test_cycle_shares_of_known_shapes(share, shape, low, high):
    # of its 80 samples a ramp with a fast return falls for a few, a sine and a triangle
    # for half (a square wave's extremes sit anywhere on its flat tops); crossings read
    # about the middle of the swing put a fifth of a pulse train high for a fifth above
    # it (0.21; about the moving mean a quarter, 0.26), and half of a sine, a triangle or
    # a saw-tooth
    x = _shape(shape)
    a = analyze_cycles(x + 0.05 * np.random.default_rng(0).normal(size=x.size))
    assert a.oscillating and len(a.cycles) >= 20
    assert low <= getattr(a, share) <= high


def test_a_pulse_train_is_read_about_the_middle_of_its_swing():
    # high for 15 % of each cycle of 50-70 samples, white noise of a quarter of its
    # height: about its moving mean, which lies near its low side, the noise of the long
    # low stretches crossed too, and the 20 records read 3-20 of their about 33 cycles
    # (median 12.5) and a third of each cycle high (0.32); about the middle of the swing,
    # 30-34 and 0.18
    def pulse(period, amp):
        high = int(round(0.15 * period))
        return np.r_[np.full(high, amp), np.zeros(period - high)]

    rng = np.random.default_rng(3)
    shares = []
    for _ in range(20):
        a = analyze_cycles(_drawn_cycles(rng, 50, 70, pulse, 2000) + 0.25 * rng.normal(size=2000))
        assert a.oscillating and len(a.cycles) >= 28
        shares.append(a.above_share)
    assert 0.12 <= np.median(shares) <= 0.22


@pytest.mark.parametrize(
    "cycles,noise,share,low_acf_at_least,found",
    [(_saw_tooth, 0.5, "fall_share", 15, 21), (_pulse_train, 0.4, "above_share", 20, 11)],
)
def test_lopsided_cycles_confirm_under_broadband_noise(
    cycles, noise, share, low_acf_at_least, found
):
    # cycles of 40-120 samples under white noise (half a saw-tooth's amplitude, rising
    # over 60-85 % of each; 0.4 of a pulse train's height, high for 20-30 % of each): the
    # noise adds to the ACF's lag 0 and the wandering period scrambles the harmonics'
    # phase, so the first ACF peak stays at or below CONFIRM_ACF in most (21 and 24 of
    # 30); the saw-teeth still rise slower than they fall, the pulses stay shorter above
    # their mean than below (the median share under one half in every record with
    # cycles), which noise does
    # not do. Found: 23 and 15 of 30 (13 pulse trains while crossings were read about
    # the moving mean); 13 and 6 without the test of that share, then
    rng = np.random.default_rng(11)
    hits = low_acf = 0
    for _ in range(30):
        a = analyze_cycles(cycles(rng, 40, 120) + noise * rng.normal(size=751))
        hits += a.oscillating
        low_acf += a.acf_strength <= CONFIRM_ACF
        assert not len(a.cycles) or getattr(a, share) < 0.5
    assert low_acf >= low_acf_at_least
    assert hits >= found


def test_noise_of_any_spectrum_seldom_reads_lopsided():
    # a stationary Gaussian process reads the same backwards and upside down, so its
    # cycles fall as long as they rise and stay as long above their mean as below: the
    # two sign tests at LOPSIDED_LEVEL (two-sided) with the margin pass 2.5 % at most of
    # the benchmark's coloured and held noise whose cycles they read (5 of 318 today:
    # 3 by their fall, 2 by their time above the mean; 11 without the margin)
    bench = _bench()
    read = lopsided = 0
    for kind in ("coloured_noise", "repeated_noise"):
        stream = 100 + bench.QUIET.index(kind)
        for s in range(200, 400):
            a = analyze_cycles(bench.make_signal(kind, np.random.default_rng([s, stream]))[0])
            if len(a.cycles):
                read += 1
                kept = a.cycles[:, 0]
                lopsided += _lopsided(_fall_shares(a.peaks, a.signs, kept)) or _lopsided(
                    _above_shares(a.crossings, a.signs, kept)
                )
    assert read >= 250
    assert lopsided <= 0.025 * read


def test_bimodal_levels_of_known_distributions():
    # Sarle's coefficient (skewness squared + 1) / kurtosis above 5/9, a uniform
    # distribution's: 1 for two values in any proportion, 2/3 for a sine's arcsine law;
    # 1/3 for Gaussian noise, and below 5/9 for noise skewed (log-normal: 0.41 at a
    # log-sd of 0.3, 0.47 at 1) or held at a limit on 20 % of its samples (0.51; on 30 %,
    # 0.57: the limit is a second mode then)
    rng = np.random.default_rng(0)
    noise = rng.normal(size=20_000)
    t = np.arange(20_000)
    assert _bimodal(np.where(t % 50 < 10, 1.0, 0.0)) and _bimodal(np.sin(2 * np.pi * t / 50))
    assert not _bimodal(noise)
    assert not _bimodal(np.exp(0.3 * noise)) and not _bimodal(np.exp(noise))
    assert not _bimodal(np.minimum(noise, np.quantile(noise, 0.8)))
    assert _bimodal(np.minimum(noise, np.quantile(noise, 0.7)))
    assert not _bimodal(np.zeros(100))


def test_noise_lopsided_in_level_is_not_taken_for_a_pulse_train():
    # the benchmark's coloured noise skewed (a log-normal level) or held at a limit on
    # 5-40 % of its samples stays longer on one side of its crossing level in every cycle,
    # as a pulse train does, and the test of the cycles' time above that level took it
    # for one; its level is unimodal, a pulse train's bimodal. Called oscillating: 12 of
    # 150 skewed and 8 of 150 held records (37 and 20 without the bimodality check);
    # pulse trains resting at a limit between their pulses, still bimodal: 58 of 60 found
    # (51 without the test of their time above the crossing level)
    bench = _bench()
    skewed, held = (np.random.default_rng([7, s]) for s in (3200, 3201))
    alarms = [
        sum(bench.read_quietly(bench.make_signal(kind, rng)[0]).oscillating for _ in range(150))
        for kind, rng in (("skewed_noise", skewed), ("saturated_noise", held))
    ]
    pulses = "pulses_resting_at_a_limit"
    resting = np.random.default_rng([7, 3100 + bench.SATURATED.index(pulses)])
    found = sum(
        bench.read_quietly(bench.make_saturated(pulses, resting)[0]).oscillating
        for _ in range(60)
    )
    assert alarms[0] <= 18 and alarms[1] <= 13
    assert found >= 55


def test_coloured_noise_with_a_resonance_bump_is_not_an_oscillation():
    # AR(1) and AR(2) noise (damping ratio 0.35-0.7) of the benchmark, one signal per
    # seed: at most the goal's 5 % called oscillating (8 of these 200 are; an irregular
    # cycle and a resonance of damping 0.35 look alike, so this is where the threshold
    # sits)
    bench = _bench()
    c = 100 + bench.QUIET.index("coloured_noise")
    signals = [
        bench.make_signal("coloured_noise", np.random.default_rng([s, c]))[0]
        for s in range(200, 400)
    ]
    assert sum(analyze_cycles(x).oscillating for x in signals) <= 10


def test_very_irregular_cycles_are_found_in_a_third():
    # period and amplitude wander by 35-50 % (Thornhill's r about 0.7-1.1, as the
    # issue measured on real loops): such a cycle is a narrow-band random process
    # much like a resonance of damping 0.35, so only the clearest are found
    # (0.38 on the benchmark)
    bench = _bench()
    rng = np.random.default_rng([99, bench.STREAM["very_irregular"]])
    signals = [bench.make_signal("very_irregular", rng)[0] for _ in range(80)]
    assert sum(analyze_cycles(x).oscillating for x in signals) >= 22


def test_trips_are_bridged_for_the_second_reading():
    # OP tripping to 0 for 4-20 samples, 1-3 times (the benchmark's --artefacts): taken
    # out by a line, the trips leave the lopsided cycles readable; clipped to Tukey's
    # inner fence, as before, each left a rectangle 2.8 amplitudes deep (81 of 120 found)
    bench = _bench()
    spoil = np.random.default_rng([7, 1004])
    found = 0
    for kind in ("stick_slip", "unequal_halves"):
        rng = np.random.default_rng([7, bench.STREAM[kind]])
        for _ in range(60):
            y = bench._trips(spoil, bench.make_signal(kind, rng)[0])
            found += bool(bench.read_quietly(y).oscillating)
    assert found >= 88  # 92 bridged


def test_cycle_acf_sees_through_drift_and_not_through_noise():
    rng = np.random.default_rng(5)
    t = np.arange(1500)
    walk = np.cumsum(rng.normal(size=t.size))
    cycle = np.sign(np.sin(2 * np.pi * t / 75))
    drifting = cycle + 10 * walk / np.ptp(walk) + rng.normal(0, 0.1, t.size)
    main = max(detect_oscillations(drifting), key=lambda c: c.cycle_acf)
    assert main.period == pytest.approx(75, rel=0.05)
    # the moving mean over one period took the walk away: the clean cycle's is 1.0,
    # and the walk's own wiggles at the cycle's period take less than 0.2 of it
    assert main.cycle_acf > 0.8
    bench = _bench()
    noise = [bench._ar2(np.random.default_rng(s), 1500, 60, 0.5) for s in range(20)]
    acfs = [max((c.cycle_acf for c in detect_oscillations(x)), default=0.0) for x in noise]
    assert np.median(acfs) < 0.35  # coloured noise keeps only its short memory


def test_shipped_plant_window_with_a_square_wave_oscillates():
    # 2111FIC46005, 2 h at 10 s: square-wave PV and saw-tooth OP, about 13 cycles whose
    # period wanders between about 50 and 70 samples (counted on the figure)
    from sktiction.datasets import load_plant_examples

    d = load_plant_examples()
    i = int(np.flatnonzero(d.meta["file"].str.contains("2111FIC46005_0902"))[0])
    for channel in (0, 1):
        a = analyze_cycles(d.X[i, :, channel])
        assert a.oscillating
        assert 45 <= a.periods[0] <= 75
        assert len(a.cycles) >= 8


def test_features_per_channel():
    t = np.arange(2500)
    rng = np.random.default_rng(0)
    op = 50 + 4 * np.sin(2 * np.pi * t / 45)
    pv = 20 + np.cumsum(rng.normal(size=t.size)) * 0.1
    X = np.stack([pv, op, np.full(t.size, 20.0)], axis=1)[None]
    ft = OscillationFeatures().set_output(transform="pandas").fit(X)
    f = ft.transform(X).iloc[0]
    assert list(ft.get_feature_names_out()) == list(f.index)
    assert f["op_oscillating"] == 1 and f["op_n_components"] == 1
    assert f["op_period"] == pytest.approx(45, rel=0.02) and np.isnan(f["op_period_2"])
    assert f["op_osc_index"] > 0.99 and f["op_regularity"] > 1
    assert f["op_coherence"] > 0.95  # a pure cycle keeps its phase
    assert f["pv_oscillating"] == 0 and np.isnan(f["pv_period"])
    assert 0 <= f["pv_osc_index"] < 0.5


def test_features_missing_op_and_bad_loops_are_nan():
    t = np.arange(800)
    good = np.stack([np.sin(t / 10.0), np.full(t.size, np.nan)], axis=1)
    flat = np.stack([np.zeros(t.size), np.zeros(t.size)], axis=1)
    X = np.stack([good, flat])
    f = OscillationFeatures(signals=("pv", "op")).fit(X).transform(X)
    n = len(f[0]) // 2
    assert f[0, 1] == 1 and np.isnan(f[0, n:]).all()  # PV oscillates, OP absent
    assert np.isnan(f[1]).all()  # constant loop: loop_status rejects it


def test_bad_signals_parameter_is_refused():
    with pytest.raises(ValueError, match="signals"):
        OscillationFeatures(signals=("sp",)).fit(np.zeros((1, 50, 3)))


def test_relay_record_of_booleans_is_read_as_zero_and_one():
    # an on/off valve logged as True/False: a square wave of range exactly 1
    t = np.arange(2000)
    components = detect_oscillations(np.sin(2 * np.pi * t / 64) > 0)
    assert components[0].period == pytest.approx(64, rel=0.01)
    assert components[0].index > 0.99


def test_defaults_are_those_analyze_cycles_uses():
    # on noise no time-domain cycle confirms a component, so both report the same
    from scipy.signal import lfilter

    for seed in range(3):
        x = lfilter([1.0], [1.0, -0.8], np.random.default_rng(seed).normal(size=3000))
        found = [(c.period, c.index, c.coherence) for c in detect_oscillations(x)]
        assert found == [(c.period, c.index, c.coherence) for c in analyze_cycles(x).components]
        assert len(found) == 3


def test_harmonics_are_dropped_by_detect_oscillations_too():
    t = np.arange(3000)
    found = [
        c.period for c in detect_oscillations(np.sign(np.sin(2 * np.pi * t / 90))) if c.index > 0.5
    ]
    assert found == pytest.approx([90], rel=0.02)


def test_cycle_acf_of_a_noisy_sinusoid_is_its_share_of_the_kept_power():
    # white noise keeps (1 - H)**2 of its power up to the 5th harmonic (H the moving
    # average's response) and has no correlation at one period, so the cycle ACF is
    # 0.5 / (0.5 + sigma**2 * 2 * integral of (1 - H)**2 up to 5 / P)
    from sktiction.cycles._oscillation import _moving_mean_response

    period, n = 100, 40000
    rng = np.random.default_rng(0)
    x = np.sin(2 * np.pi * np.arange(n) / period) + rng.normal(size=n)
    f = np.linspace(1e-7, 5 / period, 100001)
    kept = 2 * np.trapezoid((1 - _moving_mean_response(f, period)) ** 2, f)
    main = detect_oscillations(x)[0]
    assert main.period == pytest.approx(period, rel=0.01)
    assert main.cycle_acf == pytest.approx(0.5 / (0.5 + kept), abs=0.02)


def test_cycle_acf_of_few_cycles_and_of_random_walks():
    # 3.6 clean cycles repeat exactly (unbiased ACF: about 1); a random walk's moving
    # mean over any period takes its slow part, and the rest has short memory
    short = detect_oscillations(np.sin(2 * np.pi * np.arange(360) / 100))[0]
    assert short.period == pytest.approx(100, rel=0.02) and short.cycle_acf > 0.9
    assert short.coherence == 1.0  # the unbiased ACF exceeds 1 at the last lags: clipped
    walks = [np.cumsum(np.random.default_rng(s).normal(size=1500)) for s in range(20)]
    acfs = [max((c.cycle_acf for c in detect_oscillations(w)), default=0.0) for w in walks]
    assert np.median(acfs) < 0.35


def test_features_of_two_oscillations_and_of_an_on_off_signal():
    # OP: two sinusoids; PV: an on/off signal of range exactly 1 (0 or 1)
    t = np.arange(4000)
    op = np.sin(2 * np.pi * t / 23) + 0.8 * np.sin(2 * np.pi * t / 140)
    pv = (np.sin(2 * np.pi * t / 70) > 0).astype(float)
    X = np.stack([pv, op], axis=1)[None]
    f = OscillationFeatures().set_output(transform="pandas").fit(X).transform(X).iloc[0]
    assert f["op_n_components"] == 2
    assert sorted([f["op_period"], f["op_period_2"]]) == pytest.approx([23, 140], rel=0.03)
    assert f["pv_oscillating"] == 1 and f["pv_period"] == pytest.approx(70, rel=0.02)
    assert np.isnan(f["pv_period_2"])


def test_units_and_offset_do_not_change_the_components():
    t = np.arange(3000)
    x = np.sin(2 * np.pi * t / 40) + 0.5 * np.random.default_rng(2).normal(size=t.size)
    for y in (1e-6 * x + 5e3, 1e4 * x):
        for a, b in zip(detect_oscillations(x), detect_oscillations(y), strict=True):
            assert (b.period, b.index, b.cycle_acf, b.coherence, b.share) == pytest.approx(
                (a.period, a.index, a.cycle_acf, a.coherence, a.share), rel=1e-6
            )


def test_two_oscillations_a_factor_three_apart_are_two_components():
    t = np.arange(3000)
    x = np.sin(2 * np.pi * t / 25) + np.sin(2 * np.pi * t / 80)
    x += 0.3 * np.random.default_rng(2).normal(size=t.size)
    found = [c.period for c in detect_oscillations(x) if c.index > 0.5]
    assert sorted(found) == pytest.approx([25, 80], rel=0.02)


def test_held_samples_are_filled_by_straight_lines():
    from sktiction.cycles._oscillation import _fill_repeats

    ramp = np.arange(40.0)
    held = np.repeat(ramp, 2)  # every value recorded twice: half the samples repeat
    filled = _fill_repeats(held)
    assert filled[:-1] == pytest.approx(np.arange(79) / 2)  # the last has no next change
    few = np.r_[held[:6], 3 + np.arange(74.0)]  # 3 repeats among 79 steps (3.8 %)
    assert _fill_repeats(few) is few  # left alone
    few = np.r_[held[:8], 4 + np.arange(73.0)]  # 4 repeats among 80 steps (5 %): filled
    assert _fill_repeats(few)[:8] == pytest.approx(np.arange(8) / 2)
    eight = np.repeat(np.arange(8.0), 3)  # eight changes are enough to draw lines through
    assert _fill_repeats(eight)[:-3] == pytest.approx(np.arange(21) / 3)
    assert np.array_equal(_fill_repeats(eight[:-3]), eight[:-3])  # seven: left as recorded
    # the top value visited eight times but held once: a visit is no run, so no limit
    often = np.insert(np.tile([0.0, 1.0, 1.0, 2.0, 1.0, 1.0], 8), 22, 2.0)  # 2 on rows 21-22
    assert _fill_repeats(often)[22] == pytest.approx(1.5)


@pytest.mark.parametrize("limit", ["top", "bottom"])
def test_a_limit_reached_every_cycle_stays_flat(limit):
    # a pulse train clipped at a limit: the runs there are the process's, not the
    # historian's, and drawn as lines they would make its plateaus ramps; held a few
    # times only (a trip of OP to 0) they are drawn
    from sktiction.cycles._oscillation import LIMIT_RUNS, _fill_repeats

    rng = np.random.default_rng(3)
    one = np.r_[np.zeros(14), np.ones(6)]  # high for 6 of 20 samples
    sign = 1 if limit == "top" else -1
    for cycles in (LIMIT_RUNS, LIMIT_RUNS - 1):
        x = sign * np.minimum(2 * np.tile(one, cycles) + 0.1 * rng.normal(size=20 * cycles), 1)
        held = x == x.max() if limit == "top" else x == x.min()
        filled = _fill_repeats(x)
        if cycles >= LIMIT_RUNS:
            np.testing.assert_array_equal(filled[held], x[held])
        else:  # each run but the last drawn as a line: 5 of its 6 samples move
            assert np.count_nonzero(filled[held] != x[held]) == 5 * (cycles - 1)


def test_harmonics_of_a_saw_tooth_are_not_components():
    # every harmonic (2nd, 3rd, ...) of a saw-tooth, as a sticky valve's OP draws it
    t = np.arange(3000)
    saw = (t % 90) / 90 + 0.05 * np.random.default_rng(0).normal(size=t.size)
    assert [c.period for c in detect_oscillations(saw) if c.index > 0.5] == pytest.approx(
        [90], rel=0.01
    )


def test_an_oscillation_six_times_faster_is_not_a_harmonic():
    # beyond the 5th harmonic a faster cycle is a second oscillation, even when weaker
    t = np.arange(3000)
    x = np.sin(2 * np.pi * t / 120) + 0.5 * np.sin(2 * np.pi * t / 20)
    found = [c.period for c in detect_oscillations(x) if c.index > 0.5]
    assert sorted(found) == pytest.approx([20, 120], rel=0.01)


def test_a_cycle_with_a_strong_fifth_harmonic_is_one_component():
    t = np.arange(3000)
    x = np.sin(2 * np.pi * t / 100) + 0.4 * np.sin(2 * np.pi * t / 20)
    assert [c.period for c in detect_oscillations(x) if c.index > 0.5] == pytest.approx(
        [100], rel=0.01
    )


def test_a_cycle_is_no_harmonic_of_resonant_noise():
    # a cycle of 20 samples on noise resonating near 60; in these two draws the noise's
    # component lands within 2 % of three times the cycle's period, yet it does not
    # oscillate, so the cycle is not part of its shape
    bench = _bench()
    t = np.arange(3000)
    for seed in (8, 18):
        noise = bench._ar2(np.random.default_rng(seed), t.size, 60, 0.5)
        components = detect_oscillations(0.4 * np.sin(2 * np.pi * t / 20) + noise)
        slow = [c for c in components if abs(c.period / 60 - 1) < 0.02]
        assert slow and slow[0].index < 0.5
        assert [c.period for c in components if c.index > 0.5] == pytest.approx([20], rel=0.01)


def test_regularity_of_a_noisy_sinusoid_is_finite_and_large():
    # Thornhill's r = mean / (3 sd) of the ACF's crossing intervals: large for a cycle,
    # infinite only when the intervals are exactly equal
    t = np.arange(3000)
    x = np.sin(2 * np.pi * t / 50) + 0.3 * np.random.default_rng(0).normal(size=t.size)
    r = detect_oscillations(x)[0].regularity
    assert np.isfinite(r) and r > 100


@pytest.mark.parametrize("slope", [1.0, 2.0])
def test_background_of_a_power_law_is_the_power_law(slope):
    # random walks and drift have power-law spectra: the background read around a bin is
    # the spectrum there, from both sides, or (for a slow bin whose lower side is out of
    # range) extrapolated from two upper bands; times exp(Euler's gamma), the log-average
    # of an exponential variable's periodogram lying that much below its mean
    from sktiction.cycles._oscillation import _background

    bins = np.arange(1, 2001.0)
    power = np.r_[1.0, bins**-slope]
    log_cum = np.concatenate([[0.0], np.cumsum(np.log(power))])
    for k, k_min in ((60, 3.0), (30, 12.0)):  # both sides; lower side below k_min
        expected = k**-slope * np.exp(np.euler_gamma)
        assert _background(log_cum, k, k_min) == pytest.approx(expected, rel=0.1)


def test_components_stay_within_the_searched_periods():
    # 5 samples to 3.5 cycles per record, each component's ACF period within a factor
    # exp(0.3) of its spectral peak's: cycles outside the range give no component there
    n = 2000
    t = np.arange(n)
    noise = 0.01 * np.random.default_rng(0).normal(size=n)
    for cycles_per_record in (2.2, n / 3):  # too slow; too fast (3 samples per cycle)
        x = np.sin(2 * np.pi * t * cycles_per_record / n) + noise
        for c in detect_oscillations(x):
            assert 5 / np.exp(0.3) <= c.period <= n / 3.5 * np.exp(0.3)
    for seed in range(3):  # also the components whose ACFs were not computed
        for c in detect_oscillations(np.random.default_rng(seed).normal(size=n)):
            assert 5 / np.exp(0.3) <= c.period <= n / 3.5 * np.exp(0.3)
    sine = detect_oscillations(np.sin(2 * np.pi * t / 40))
    assert len(sine) == 1 and 0.95 < sine[0].share <= 1  # all its power in its band


def _spectrum(peaks, size=400):
    """A flat spectrum with one-bin peaks {bin: height}."""
    s = np.full(size, 1e-3)
    for k, height in peaks.items():
        s[k] = height
    return s


def test_candidates_are_peaks_of_the_spectrum_and_of_its_slope():
    from sktiction.cycles._oscillation import _candidates

    # the ripples of one broad peak (within 15 %) are one candidate; the next peaks count,
    # highest first
    ripples = _spectrum({300: 10.0, 310: 9.0, 320: 8.0, 100: 5.0, 200: 1.0})
    assert _candidates(ripples, 20, 390, 2) == [300, 100]
    # the highest peak, and the highest peak times f**2 (the first difference's spectrum):
    # 10 * 100**2 beats 40 * 40**2 and 0.5 * 300**2
    three = _spectrum({40: 40.0, 100: 10.0, 300: 0.5})
    assert _candidates(three, 20, 390, 1) == [40, 100]


def test_background_sides_start_at_k_min_and_the_fallback_is_the_mean_above_it():
    # exact log-averages (the running sum log_cum[j] is the sum of log power[:j])
    from sktiction.cycles._oscillation import _background

    power = np.random.default_rng(5).exponential(size=200)
    log_cum = np.concatenate([[0.0], np.cumsum(np.log(power))])
    gamma = np.euler_gamma
    # records of 1000 samples: spectrum of 2000 points, k_min = 1.5 * 2000 / 1000 = 3 bins
    # exactly; at k = 9 the lower side is bins 3-5 (k/3 to k/1.7, three bins: enough), the
    # upper one bins 16-27 (1.7 k to 3 k)
    low, high = np.log(power[3:6]).mean(), np.log(power[16:28]).mean()
    assert _background(log_cum, 9, 3.0) == pytest.approx(np.exp(0.5 * (low + high) + gamma))
    # a short spectrum with neither side in range: the mean from k_min to the end
    short = log_cum[:10]
    assert _background(short, 4, 3.0) == pytest.approx(np.exp(np.log(power[3:9]).mean() + gamma))


def test_a_harmonic_must_carry_less_than_its_fundamental():
    # _harmonic's docstring: the 2nd-5th harmonic (within 2 %) of a slower oscillating
    # component that carries more of the signal; a faster one that carries more is its own
    from types import SimpleNamespace

    from sktiction.cycles._oscillation import _harmonic

    slow = SimpleNamespace(index=0.9, period=90.0, share=0.6)
    third = SimpleNamespace(index=0.8, period=30.0, share=0.2)
    assert _harmonic(third, 30.0, slow, 0.5)
    assert not _harmonic(SimpleNamespace(index=0.8, period=30.0, share=0.7), 30.0, slow, 0.5)
    assert not _harmonic(SimpleNamespace(index=0.8, period=31.0, share=0.2), 31.0, slow, 0.5)
    assert not _harmonic(third, 30.0, SimpleNamespace(index=0.5, period=90.0, share=0.6), 0.5)
    assert not _harmonic(SimpleNamespace(index=0.8, period=15.0, share=0.2), 15.0, slow, 0.5)
    # the period tested is the one given (the narrow band's, when the ACF's is mixed)
    mixed = SimpleNamespace(index=0.9, period=21.0, share=0.1)  # 90 / 21 = 4.3
    assert _harmonic(mixed, 18.0, slow, 0.5)
    assert not _harmonic(mixed, 21.0, slow, 0.5)


@pytest.mark.parametrize("noise", [0.0, 0.01, 0.03])
def test_a_square_wave_is_one_oscillation(noise):
    # an on/off signal: the band about its 5th harmonic holds the 3rd and the 7th,
    # whose mixed ACF period (about 16 of 70) is no harmonic's; read in a narrow band
    # it is the 5th's. Held at its two values (no noise) the record is all repeats at
    # its extremes, which stay flat
    t = np.arange(4000)
    rng = np.random.default_rng(1)
    for period in (33, 40, 55, 64, 70, 90, 120, 150):
        x = (np.sin(2 * np.pi * (t + 0.5) / period) > 0) + noise * rng.normal(size=t.size)
        found = [c.period for c in detect_oscillations(x) if c.index > 0.5]
        assert found == pytest.approx([period], rel=0.01)

