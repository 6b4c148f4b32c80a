"""Applicability before diagnosis: garbage is rejected, closed loops are not."""

import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from sklearn.utils import Bunch

from sktiction.classifiers import applicability
from sktiction.classifiers.applicability import (
    APPLICABILITY_COLUMNS,
    MIN_CHANGES,
    MIN_SAMPLES,
    assess_applicability,
)
from sktiction.cycles._signal import robust_spread
from sktiction.datasets import make_loops, read_loops
from sktiction.realism import loop_statistics
from sktiction.realism.statistics import _repeat_fractions

DATA = Path(os.environ.get("SKTICTION_DATA", Path(__file__).parents[2] / "shared" / "data"))

GARBAGE_KINDS = (
    "white_noise",
    "random_walks",
    "unrelated_loops",
    "unrelated_signals",
    "repeated_rows",
    "repeated_noise",
    "quantised",
    "snippet",
)


def _held(x, keep_share, rng):
    """Rows held by a historian: each row is new with probability ``keep_share``."""
    n = len(x)
    keep = rng.random(n) < keep_share
    keep[0] = True
    return x[np.maximum.accumulate(np.where(keep, np.arange(n), 0))]


def make_garbage(n=1000, n_samples=1000, random_state=0):
    """Loops no verdict should be given on, in random scale and offset, with their kind.

    White noise; two or three independent random walks; PV and SP of one simulated
    closed loop with the OP of another; a noisy sine against independent coloured
    noise; closed loops whose historian held 97-99.5 % of the rows; white noise with
    70-95 % repeated rows (the issue's 77 %); closed loops quantised to 1.5-3 times
    their interquartile range (two or three levels); snippets of 10-120 samples.
    """
    rng = np.random.default_rng(random_state)
    src = make_loops(
        2 * n // len(GARBAGE_KINDS) + 2,
        n_samples=n_samples,
        short_fraction=0.0,
        random_state=random_state,
    )[0]
    X = np.full((n, n_samples, 3), np.nan)
    kinds = np.array([GARBAGE_KINDS[i % len(GARBAGE_KINDS)] for i in range(n)])
    t = np.arange(n_samples)
    for i, kind in enumerate(kinds):
        j, k = rng.choice(len(src), 2, replace=False)
        if kind == "white_noise":
            x = rng.standard_normal((n_samples, 3))
        elif kind == "random_walks":
            x = np.cumsum(rng.standard_normal((n_samples, 3)), axis=0)
        elif kind == "unrelated_loops":
            x = src[j].copy()
            x[:, 1] = src[k][:, 1]
        elif kind == "unrelated_signals":
            pv = np.sin(2 * np.pi * t / rng.uniform(20, 200))
            pv += 0.2 * rng.standard_normal(n_samples)
            op = np.convolve(rng.standard_normal(n_samples + 19), np.ones(20) / 20, "valid")
            x = np.stack([pv, op, np.zeros(n_samples)], axis=1)
        elif kind == "repeated_rows":
            x = _held(src[j], rng.uniform(0.005, 0.03), rng)
        elif kind == "repeated_noise":
            x = _held(rng.standard_normal((n_samples, 3)), rng.uniform(0.05, 0.3), rng)
        elif kind == "quantised":
            x = src[j].copy()
            for c in range(3):
                lo, hi = np.percentile(x[:, c], [25, 75])
                q = (hi - lo) * rng.uniform(1.5, 3.0) if hi > lo else 1.0
                x[:, c] = np.round(x[:, c] / q) * q
        else:  # snippet
            m = int(rng.integers(10, 120))
            s = int(rng.integers(0, n_samples - m))
            x = np.full((n_samples, 3), np.nan)
            x[:m] = src[j][s : s + m]
        X[i] = x * 10.0 ** rng.uniform(-3, 3) + rng.uniform(-100, 100)
    return X, kinds


def test_garbage_is_rejected():
    X, kinds = make_garbage(1000, random_state=0)
    result = assess_applicability(X)
    accepted = result["applicable"].to_numpy()
    # at most one of 1,000 (the coherence test alone has a 0.1 % false-alarm rate per loop)
    assert accepted.sum() <= 1, pd.Series(kinds[accepted]).value_counts()
    reasons = pd.crosstab(kinds, result["reason"])
    assert reasons.loc["snippet", "too_short"] == (kinds == "snippet").sum()
    for kind in ("white_noise", "random_walks", "unrelated_signals"):
        assert reasons.loc[kind, "pv_op_unrelated"] >= (kinds == kind).sum() - 1
    assert reasons.loc["repeated_rows", "too_compressed"] >= 0.9 * (kinds == "repeated_rows").sum()
    on_a_grid = reasons.loc["quantised"].reindex(["quantised", "constant_pv", "constant_op"])
    assert on_a_grid.fillna(0).sum() >= 0.9 * (kinds == "quantised").sum()


@pytest.mark.parametrize("world", ["classic", "default"])
def test_closed_loops_are_accepted(world):
    """Simulated closed loops of every cause pass (at least 98 % of each cause).

    The default world is recorded as plants are, and some of its loops cannot be
    diagnosed: heavy historian compression (bands up to 15 % of span) keeps a quiet
    loop's OP frozen on all but a few dozen samples (``too_compressed``); a grid up to
    10 % of span (``quantised``); a recorded PV that is mostly noise the controller never
    saw (behind a PV filter, SNR down to 0 dB), or a short record (a quarter are cut to
    200-1,500 samples), shows no PV-OP relation (``pv_op_unrelated``). There the 98 %
    hold for the full-length loops recorded without historian effects, and 85 % for all,
    with only those reasons.
    """
    X, _, meta = make_loops(400, n_samples=1500, world=world, random_state=3, return_meta=True)
    result = assess_applicability(X)
    cause = meta["cause"].to_numpy()
    clean = np.ones(len(X), bool)
    if world == "default":
        clean = (meta["recording"].eq("none") & meta["record_length"].eq(1500)).to_numpy()
        by_cause = result["applicable"].groupby(cause).mean()
        assert (by_cause >= 0.85).all(), by_cause
        rejected = result[~result["applicable"]]
        assert set(rejected["reason"]) <= {"too_compressed", "pv_op_unrelated", "quantised"}
    by_cause = result["applicable"][clean].groupby(cause[clean]).mean()
    assert len(by_cause) == 4
    assert (by_cause >= 0.98).all(), by_cause


def test_scale_and_offset_never_change_the_outcome():
    X, _ = make_loops(60, n_samples=1000, random_state=5)
    base = assess_applicability(X)["reason"]
    for scale, offset in ((1e12, -3e12), (1e-12, 7e-12), (-2.5, 1e4)):
        assert assess_applicability(X * scale + offset)["reason"].equals(base)


def test_each_reason():
    X, _ = make_loops(1, n_samples=600, world="classic", stiction_fraction=1.0, random_state=1)
    loop = X[0]
    cases = {}
    cases["ok"] = loop
    short = np.full_like(loop, np.nan)
    short[: MIN_SAMPLES - 1] = loop[: MIN_SAMPLES - 1]
    cases["too_short"] = short
    cases["empty"] = np.full_like(loop, np.nan)
    no_op = loop.copy()
    no_op[:, 1] = np.nan
    cases["no_op"] = no_op
    gap = loop.copy()
    gap[100:110, 0] = np.nan
    cases["nan_gap"] = gap
    flat = loop.copy()
    flat[:, 1] = 42.0
    cases["constant_op"] = flat
    flat_pv = loop.copy()
    flat_pv[:, 0] = 3.0
    cases["constant_pv"] = flat_pv
    inf = loop.copy()
    inf[5, 0] = np.inf
    cases["not_finite"] = inf
    huge = loop.copy()
    huge[:, 0] = np.where(np.arange(len(loop)) % 2, 1.7e308, -1.7e308)  # spread overflows
    cases["not_finite "] = huge
    coarse = loop.copy()
    q = 2 * np.subtract(*np.percentile(loop[:, 0], [75, 25]))
    coarse[:, 0] = np.round(loop[:, 0] / q) * q
    cases["quantised"] = coarse
    rng = np.random.default_rng(0)
    cases["too_compressed"] = _held(loop, 0.1, rng)  # about 60 rows of 600 move
    unrelated = loop.copy()
    unrelated[:, 1] = rng.standard_normal(len(loop))
    cases["pv_op_unrelated"] = unrelated
    result = assess_applicability(np.stack(list(cases.values())))
    assert result["reason"].tolist() == [k.strip() for k in cases]
    assert result["applicable"].tolist() == [k == "ok" for k in cases]
    assert list(result.columns[: len(APPLICABILITY_COLUMNS)]) == list(APPLICABILITY_COLUMNS)


def test_two_dimensional_input_is_pv_only():
    X, _ = make_loops(2, n_samples=400, random_state=0)
    assert assess_applicability(X[:, :, 0])["reason"].tolist() == ["no_op", "no_op"]


def test_coherence_chance_level_holds_for_independent_noise(monkeypatch):
    """The chance level is a false-alarm rate: check it by Monte Carlo at alpha = 5 %."""
    monkeypatch.setattr(applicability, "ALPHA", 0.05)
    rng = np.random.default_rng(42)
    for n in (300, 1500):
        trials = 1000
        hits = sum(
            applicability._coherence([(rng.standard_normal(n), rng.standard_normal(n))], n)[1]
            > 1.0
            for _ in range(trials)
        )
        # binomial(1000, 0.05): mean 50, sd 7; the level must not be exceeded more often
        assert hits <= 50 + 3 * 7, (n, hits)
        assert hits >= 5, (n, hits)  # and not absurdly conservative


def test_closed_loop_is_coherent_far_above_chance():
    X, _ = make_loops(1, n_samples=2000, world="classic", random_state=2)
    result = assess_applicability(X)
    assert result.loc[0, "coherence_ratio"] > 1.5


@pytest.mark.skipif(not DATA.is_dir(), reason="measured data not available")
def test_labelled_measured_loops_are_all_applicable():
    """The 56 labelled plant and ISDB loops are closed loops an engineer diagnosed."""
    data = read_loops([DATA / "plant", DATA / "isdb"], on_error="skip")
    result = assess_applicability(data.X)
    assert len(result) == 56
    bad = data.meta.loc[~result["applicable"].to_numpy(), "file"].tolist()
    assert not bad, result.loc[~result["applicable"], "reason"].tolist()


@pytest.mark.skipif(not DATA.is_dir(), reason="measured data not available")
def test_measured_loops_with_pv_and_op_swapped_are_told_apart():
    """The plant windows have a setpoint: as recorded, PV tracks it; written OP first,
    OP does, and the loop gets pv_op_swapped instead of a verdict on the wrong signals."""
    from sktiction._validation import check_loops, loop_status

    loops = check_loops(read_loops(DATA / "plant", on_error="skip").X)
    assert len(loops) == 47
    assert not (loop_status(loops, require_op=True, check_swap=True) == "pv_op_swapped").any()
    swapped = loop_status(loops[:, :, [1, 0, 2]], require_op=True, check_swap=True)
    assert (swapped == "pv_op_swapped").mean() >= 0.75
    assert (loop_status(loops[:, :, [1, 0, 2]], require_op=True) == "ok").all()  # asked only


def test_scan_calls_no_garbage_loop_sticky():
    """Through the scan, whatever the learned model says, garbage gets no stiction verdict."""
    from sktiction import pretrained_classifier
    from sktiction.reports import scan_loops

    X, kinds = make_garbage(200, random_state=7)
    clf = pretrained_classifier(random_state=0, n_loops=60, n_samples=800)
    report = scan_loops(X, classifier=clf)
    assert report["verdict"].eq("stiction").sum() <= 1, pd.crosstab(kinds, report["verdict"])


# ---- the building blocks: known answers ------------------------------------------------


def test_chance_level_is_carters_bonferroni_level():
    # K = 12 segments count as 10: P(C > c) = (1 - c)^9 = 1e-3 at c = 1 - 10^(-1/3)
    assert applicability._chance_level(1, 12) == pytest.approx(1 - 10 ** (-1 / 3), rel=1e-12)
    assert applicability._chance_level(5, 12, 0.05) == pytest.approx(1 - 0.01 ** (1 / 9))
    # no frequency tested, or one independent segment or fewer: nothing is above chance
    assert applicability._chance_level(0, 12) == 1.0
    assert applicability._chance_level(3, 1.2) == 1.0 and applicability._chance_level(3, 1) == 1.0


def test_coherence_is_scipys_at_the_better_resolution():
    from scipy.signal import coherence

    rng = np.random.default_rng(0)
    n = 1200
    a = rng.standard_normal(n)
    b = np.convolve(a, np.ones(5) / 5, "same") + rng.standard_normal(n)
    best, ratio = applicability._coherence([(a, b)], n)
    found = []
    for nperseg in (n // 12, n // 4):  # 100 and 300 samples
        f, c = coherence(a, b, window="hann", nperseg=nperseg, detrend="linear")
        k = (n - nperseg) // (nperseg // 2) + 1
        level = 1 - (applicability.ALPHA / 2 / (len(f) - 1)) ** (1 / (k / 1.2 - 1))
        found.append((c[1:].max(), c[1:].max() / level))
    assert found[0][1] > found[1][1]  # the short segments stand higher above chance here
    np.testing.assert_allclose([best, ratio], found[0], rtol=1e-9)
    # with a second pair (SP - PV against OP) the largest over both pairs counts
    best2, ratio2 = applicability._coherence([(rng.standard_normal(n), b), (a, b)], n)
    assert best2 == pytest.approx(best) and ratio2 < ratio  # more frequencies tested


def test_segments_lose_their_straight_line():
    x = 3.0 + 0.5 * np.arange(100.0)
    seg = applicability._segments(x, 20)
    assert seg.shape == (9, 20)  # half-overlapping: starts 0, 10, ..., 80
    np.testing.assert_allclose(seg, 0.0, atol=1e-12)
    wave = np.sin(np.arange(100.0))
    np.testing.assert_allclose(
        applicability._segments(x + wave, 20), applicability._segments(wave, 20), atol=1e-12
    )


def test_quantisation_snr_of_known_grids():
    t = np.arange(2000)
    x = np.round(4 * np.sin(t / 10)) / 4  # grid 0.25, interquartile range 1.5
    sd = 1.5 / 1.349
    expected = 10 * np.log10(12 * sd**2 / 0.25**2)
    assert applicability._quantisation_snr_db(x) == pytest.approx(expected, rel=1e-9)
    assert applicability._quantisation_snr_db(np.sin(t / 10)) == np.inf  # on no grid
    assert applicability._quantisation_snr_db(np.r_[np.zeros(50), 1.0]) == -np.inf  # one step
    spikes = np.zeros(200)
    spikes[[50, 120]] = 1.0  # on a grid, but no spread: all grid
    assert applicability._quantisation_snr_db(spikes) == -np.inf


def test_robust_spread():
    x = np.random.default_rng(0).normal(0, 2.0, 20000)
    assert robust_spread(x) == pytest.approx(2.0, rel=0.03)
    mostly = np.r_[np.zeros(90), np.full(10, 10.0)]  # interquartile range 0: the sd
    assert robust_spread(mostly) == pytest.approx(3.0)


def test_bad_input_is_refused_with_the_reason():
    with pytest.raises(ValueError, match="Complex"):
        assess_applicability(np.ones((1, 200, 3)) * 1j)
    with pytest.raises(TypeError, match="must hold numbers"):
        assess_applicability(np.full((1, 200, 3), "a"))
    with pytest.raises(ValueError, match="3-D"):
        assess_applicability(np.ones((1, 2, 200, 3)))
    with pytest.raises(ValueError, match="empty"):
        assess_applicability(np.ones((0, 200, 3)))
    with pytest.raises(ValueError, match="empty"):
        assess_applicability(np.ones((2, 0, 3)))
    with pytest.raises(ValueError, match="1 to 3 channels"):
        assess_applicability(np.ones((1, 200, 4)))
    with pytest.raises(ValueError, match="1 to 3 channels"):
        assess_applicability(np.ones((1, 200, 0)))


def test_lengths_sample_time_and_statistics_reached():
    X, _ = make_loops(3, n_samples=600, world="classic", random_state=1)
    X[1, 400:] = np.nan  # NaN-padded to 400 samples
    X[2, :, 1] = 5.0  # constant OP: no statistics
    result = assess_applicability(X, ts=2.0)
    assert result["n_samples"].tolist() == [600, 400, 600]
    assert result["ts"].tolist() == [2.0, 2.0, 2.0]
    assert result["reason"].tolist() == ["ok", "ok", "constant_op"]
    assert result.loc[2, APPLICABILITY_COLUMNS[2:]].drop("n_samples").isna().all()
    assert result.loc[:1, "n_informative_rows"].tolist() == [600, 400]
    assert result.loc[:1, "n_changes"].tolist() == [599, 399]
    # a read_loops Bunch: X and the sample times of its meta
    bunch = Bunch(X=X[:2], meta=pd.DataFrame({"ts": [0.5, 3.0]}))
    assert assess_applicability(bunch)["ts"].tolist() == [0.5, 3.0]
    assert np.isnan(assess_applicability(X[:1])["ts"]).all()


def test_held_rows_are_counted():
    X, _ = make_loops(1, n_samples=1200, world="classic", random_state=1)
    held = X[0].copy()
    held[1::2] = held[::2]  # every other row repeats the one before
    row = assess_applicability(held[None]).iloc[0]
    assert row["n_informative_rows"] == 600  # rows 0, 2, ..., 1198
    assert row["pv_repeat_fraction"] == pytest.approx(600 / 1199)  # rows 1, 3, ..., 1199
    assert row["op_repeat_fraction"] == pytest.approx(600 / 1199)
    assert row["n_changes"] == 599
    # PV held alone: OP moves, so every row is informative
    pv_held = X[0].copy()
    pv_held[1::2, 0] = pv_held[::2, 0]
    row = assess_applicability(pv_held[None]).iloc[0]
    assert row["n_informative_rows"] == 1200 and row["n_changes"] == 599
    assert row["op_repeat_fraction"] == 0.0


def test_thresholds_at_their_bounds():
    X, _ = make_loops(1, n_samples=600, world="classic", stiction_fraction=1.0, random_state=1)
    loops = np.full((2, 600, 3), np.nan)
    loops[0, :MIN_SAMPLES] = X[0, :MIN_SAMPLES]
    loops[1, : MIN_SAMPLES - 1] = X[0, : MIN_SAMPLES - 1]
    reasons = assess_applicability(loops)["reason"].tolist()
    assert reasons[0] != "too_short" and reasons[1] == "too_short"
    # 31 and 32 changes of OP (every other row of a 600-sample loop moving is plenty)
    few = []
    for n_changes in (MIN_CHANGES - 1, MIN_CHANGES):
        x = X[0].copy()
        keep = np.zeros(600, bool)
        keep[np.linspace(0, 599, n_changes + 1).astype(int)] = True
        x[:, 1] = x[np.maximum.accumulate(np.where(keep, np.arange(600), 0)), 1]
        few.append(x)
    result = assess_applicability(np.stack(few))
    assert result["n_changes"].tolist() == [MIN_CHANGES - 1, MIN_CHANGES]
    assert result.loc[0, "reason"] == "too_compressed"
    assert result.loc[1, "reason"] != "too_compressed"


def test_control_error_is_a_second_pair_only_when_sp_moves():
    X, _ = make_loops(1, n_samples=1500, world="classic", random_state=4)
    pv, op, sp = X[0].T
    flat = X[0].copy()
    flat[:, 2] = sp[0]
    step = flat.copy()  # one SP step of half PV's spread: it moves, however little
    step[750:, 2] += 0.5 * robust_spread(pv)
    got = assess_applicability(np.stack([step, flat]))
    cols = ["pv_op_coherence", "coherence_ratio"]
    both = applicability._coherence([(pv, op), (step[:, 2] - pv, op)], 1500)
    np.testing.assert_allclose(got.loc[0, cols], both, rtol=1e-6)
    alone = applicability._coherence([(pv, op)], 1500)
    np.testing.assert_allclose(got.loc[1, cols], alone, rtol=1e-6)
    assert both[1] != pytest.approx(alone[1])  # twice the frequencies tested


def test_coherence_of_unrelated_signals_is_below_chance():
    from scipy.signal import coherence

    rng = np.random.default_rng(3)
    n = 4000  # segments of 333 -> 332 and 1000 -> 512 samples
    a, b = rng.standard_normal((2, n))
    best, ratio = applicability._coherence([(a, b)], n)
    found = []
    for nperseg in (332, 512):
        f, c = coherence(a, b, window="hann", nperseg=nperseg, detrend="linear")
        k = (n - nperseg) // (nperseg // 2) + 1
        level = 1 - (applicability.ALPHA / 2 / (len(f) - 1)) ** (1 / (k / 1.2 - 1))
        found.append((c[1:].max(), c[1:].max() / level))
    np.testing.assert_allclose([best, ratio], max(found, key=lambda v: v[1]), rtol=1e-9)
    assert ratio < 1
    # a short record: segments of at least 32 samples, an even number (300 // 4 = 75 -> 74)
    a, b = a[:300], b[:300]
    best, ratio = applicability._coherence([(a, b)], 300)
    found = []
    for nperseg in (32, 74):
        f, c = coherence(a, b, window="hann", nperseg=nperseg, detrend="linear")
        k = (300 - nperseg) // (nperseg // 2) + 1
        level = 1 - (applicability.ALPHA / 2 / (len(f) - 1)) ** (1 / (k / 1.2 - 1))
        found.append((c[1:].max(), c[1:].max() / level))
    np.testing.assert_allclose([best, ratio], max(found, key=lambda v: v[1]), rtol=1e-9)


def test_edge_cases_of_the_checks():
    X, _ = make_loops(1, n_samples=600, world="classic", stiction_fraction=1.0, random_state=1)
    loop = X[0]
    cases = []
    once = loop.copy()
    once[1:, 0] = once[1, 0]  # PV moves once, at the start: not constant
    cases.append(once)
    once_op = loop.copy()
    once_op[1:, 1] = once_op[1, 1]
    cases.append(once_op)
    tiny = loop.copy()  # a finite spread whose normalised values overflow
    tiny[:, 0] = np.random.default_rng(0).normal(size=600) * 1e-300
    tiny[10, 0] = 1e10
    cases.append(tiny)
    exact = np.full_like(loop, np.nan)
    exact[:MIN_SAMPLES] = loop[:MIN_SAMPLES]  # 128 informative rows, coherence ratio 1.1
    cases.append(exact)
    got = assess_applicability(np.stack(cases))
    assert got.loc[0, "reason"] != "constant_pv" and got.loc[1, "reason"] != "constant_op"
    assert got.loc[2, "reason"] == "not_finite"
    assert got.loc[3, "reason"] == "ok" and 1.0 < got.loc[3, "coherence_ratio"] < 2.0
    assert assess_applicability(np.ones((1, 1, 3)))["reason"].tolist() == ["too_short"]
    # PV and OP only (no SP column): diagnosable
    assert assess_applicability(loop[None, :, :2])["reason"].tolist() == ["ok"]


def test_quantisation_snr_bounds():
    snr = applicability._quantisation_snr_db
    # two steps of one grid: sd = IQR / 1.349 = 2 / 1.349
    assert snr(np.repeat([0.0, 1, 2], 50)) == pytest.approx(10 * np.log10(12 * (2 / 1.349) ** 2))
    x = 0.5 * np.arange(100)  # IQR 37.125 - 12.375
    assert snr(x) == pytest.approx(10 * np.log10(12 * (24.75 / 1.349) ** 2 / 0.25))
    # nine of ten steps on the grid of the smallest (1.5 is off it): on a grid (90 %)
    assert np.isfinite(snr(np.r_[0, np.cumsum(np.r_[np.ones(9), 1.5])]))
    assert snr(np.r_[0, np.cumsum(np.r_[np.ones(8), 1.5, 1.5])]) == np.inf  # 80 %: no grid
    assert applicability._chance_level(1, 2) == pytest.approx(1 - 1e-3 ** (1 / (2 / 1.2 - 1)))


def test_result_columns_and_types():
    X, _ = make_loops(2, n_samples=600, world="classic", random_state=1)
    X[1, :, 1] = 5.0  # constant OP
    got = assess_applicability(X, ts=[1, 2])
    assert list(got.columns) == [*APPLICABILITY_COLUMNS, "ts"]
    assert got["applicable"].dtype == bool and got["n_samples"].dtype == np.int64
    assert got["ts"].dtype == float and got["pv_op_coherence"].dtype == float
    assert got.loc[0, ["pv_op_coherence", "coherence_ratio"]].notna().all()
    # an explicit ts wins over the Bunch's; integer sample times become float
    bunch = Bunch(X=X, meta=pd.DataFrame({"ts": [3, 4]}))
    assert assess_applicability(bunch, ts=9.0)["ts"].tolist() == [9.0, 9.0]
    assert assess_applicability(bunch)["ts"].dtype == float


REPEATS = ["pv_repeat_fraction", "op_repeat_fraction"]


def _badly_recorded(n_loops=24, n_samples=1500, random_state=0):
    """Closed loops with held rows, quantised tags and single-sample spikes, some of them
    inside held runs (where replacing the spike first changes the repeat count)."""
    rng = np.random.default_rng(random_state)
    X, _ = make_loops(n_loops, n_samples=n_samples, short_fraction=0.0, random_state=random_state)
    for i in range(n_loops):
        if i % 3 != 2:
            X[i] = _held(X[i], rng.uniform(0.1, 0.6), rng)
        for c in (0, 1):
            if i % 2:
                q = np.std(X[i, :, c]) * rng.uniform(0.05, 0.5)
                X[i, :, c] = np.round(X[i, :, c] / q) * q
            hit = rng.choice(np.arange(2, n_samples - 2), int(rng.integers(1, 15)), replace=False)
            X[i, hit, c] += rng.choice([-1, 1], len(hit)) * rng.uniform(3, 10) * np.std(X[i, :, c])
    return X


def test_gate_repeat_fractions_are_loop_statistics():
    """The gate's repeat shares are loop_statistics' on the loops it measures, to the bit
    (one definition: spikes are replaced before repeats are counted)."""
    X = _badly_recorded()
    gate = assess_applicability(X)
    reached = gate["pv_repeat_fraction"].notna().to_numpy()
    assert reached.sum() >= 20 and gate["reason"][reached].nunique() >= 2
    normalised = np.full_like(X, np.nan)  # each loop as the gate measures it
    for i in np.flatnonzero(reached):
        reason, normalised[i] = applicability._prepare(X[i])
        assert reason is None
    stats = loop_statistics(normalised[reached])
    np.testing.assert_array_equal(gate.loc[reached, REPEATS].to_numpy(), stats[REPEATS].to_numpy())
    # the spikes matter: counted before they are replaced, the shares would differ
    raw = [(np.diff(x[:, :2], axis=0) == 0).mean(axis=0) for x in normalised[reached]]
    assert (np.array(raw) != gate.loc[reached, REPEATS].to_numpy()).any(axis=1).sum() >= 5


def test_repeat_fractions_are_loop_statistics_with_gaps_and_missing_channels():
    """NaN exactly where loop_statistics has none to give (short loop, no PV, no OP)."""
    X = _badly_recorded(12, n_samples=600, random_state=1)
    X[0, 300:] = np.nan  # padding
    X[1, 100:140, 0] = np.nan  # gaps bridged
    X[2, :20, 1] = np.nan
    X[3, :, 1] = np.nan  # no OP
    X[4, 7:] = np.nan  # 7 samples: no statistics
    X[5, 8:] = np.nan  # 8 samples: statistics
    X[6, :, 0] = np.nan  # no PV
    X[7, :, 2] = np.nan  # no SP
    stats = loop_statistics(X)
    got = [_repeat_fractions(x[:n]) for x, n in zip(X, stats["n_samples"])]
    np.testing.assert_array_equal(np.array(got), stats[REPEATS].to_numpy())
    assert np.isnan(np.array(got)[[3, 4, 6]]).sum() == 5  # OP only; both; both
