"""Per-cycle templates, DTW, and the TemplateDistances transformer (seed 001)."""

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from tslearn.metrics import dtw

from sktiction import TemplateDistances, cycle_table
from sktiction._validation import check_loops, loop_status
from sktiction.features import paired_dtw
from sktiction.features._loops import analyse_loops
from sktiction.features.dtw import tslearn_paired_dtw
from sktiction.features.template_distances import _nearest_cycles
from sktiction.features.templates import (
    SHAPES,
    cycle_templates,
    make_shape_cycles,
    match_cycles,
    range_extrema,
    resample,
    unit_half,
)


@pytest.mark.parametrize("radius", [None, 0, 2, 7])
def test_paired_dtw_equals_tslearn(radius):
    rng = np.random.default_rng(radius or 0)
    A, B = rng.normal(size=(2, 30, 32))
    kw = (
        {}
        if radius is None
        else {"global_constraint": "sakoe_chiba", "sakoe_chiba_radius": radius}
    )
    expected = [dtw(a, b, **kw) for a, b in zip(A, B)]
    assert np.allclose(paired_dtw(A, B, sakoe_chiba_radius=radius), expected, atol=1e-9)


def test_paired_dtw_rejects_bad_input():
    with pytest.raises(ValueError, match="one shape"):
        paired_dtw(np.zeros((2, 5)), np.zeros((2, 6)))
    with pytest.raises(ValueError, match="NaN"):
        paired_dtw(np.full((1, 5), np.nan), np.zeros((1, 5)))
    with pytest.raises(ValueError, match="sakoe_chiba_radius"):
        paired_dtw(np.zeros((1, 5)), np.zeros((1, 5)), sakoe_chiba_radius=-1)


def test_paired_dtw_known_answers():
    rng = np.random.default_rng(3)
    A, B = rng.normal(size=(2, 5, 12))
    # a band of width 0 allows no warping: the Euclidean distance
    assert np.allclose(paired_dtw(A, B, sakoe_chiba_radius=0), np.linalg.norm(A - B, axis=1))
    free = paired_dtw(A, B)
    assert (free <= np.linalg.norm(A - B, axis=1) + 1e-12).all() and (free > 0).all()
    assert np.array_equal(paired_dtw(A, A), np.zeros(5))
    # a whole-number radius of any type, and integer series, are accepted
    for radius in (2.0, np.int64(2)):
        assert np.array_equal(paired_dtw(A, B, sakoe_chiba_radius=radius),
                              paired_dtw(A, B, sakoe_chiba_radius=2))  # fmt: skip
    assert paired_dtw([[0, 1, 2, 1]], [[0, 0, 1, 2]]).tolist() == [1.0]
    assert paired_dtw(np.empty((0, 4)), np.empty((0, 4))).shape == (0,)
    assert paired_dtw(np.empty((3, 0)), np.empty((3, 0))).shape == (3,)  # one per pair


def test_tslearn_reference_takes_the_band():
    rng = np.random.default_rng(4)
    A, B = rng.normal(size=(2, 6, 16))
    for radius in (None, 0, 3):
        assert np.allclose(tslearn_paired_dtw(A, B, sakoe_chiba_radius=radius),
                           paired_dtw(A, B, sakoe_chiba_radius=radius), atol=1e-9)  # fmt: skip


@pytest.mark.parametrize(
    "A, B, radius, match",
    [(np.zeros(5), np.zeros(5), None, "2-D"), (np.zeros((2, 5)), np.zeros((3, 5)), None, "2-D"),
     (np.zeros((1, 5)), np.full((1, 5), np.inf), None, "NaN"),
     (np.zeros((1, 5)), np.zeros((1, 5)), 1.5, "sakoe_chiba_radius")],
)  # fmt: skip
def test_paired_dtw_names_what_is_wrong(A, B, radius, match):
    with pytest.raises(ValueError, match=match):
        paired_dtw(A, B, sakoe_chiba_radius=radius)


def test_unit_half_shapes_at_known_positions():
    tau = np.array([0.0, 0.1, 0.25, 0.5, 0.9])
    assert np.allclose(unit_half("rectangular", tau), 1.0)
    assert np.allclose(unit_half("triangular", tau), [0, 0.2, 0.5, 1, 0.2])
    assert np.allclose(unit_half("sinusoidal", tau), np.sin(np.pi * tau))
    # ramps over the first and last fifth of the half
    assert np.allclose(unit_half("trapezoidal", tau), [0, 0.5, 1, 1, 0.5])
    with pytest.raises(ValueError, match="shape must be one of"):
        unit_half("square", tau)


@pytest.mark.parametrize("split", [0.3, 0.5, 0.8])
def test_templates_keep_each_half_s_duration_and_area(split):
    n = 2000
    temps = cycle_templates(split, 2.0, -0.5, n)
    assert temps.shape == (len(SHAPES), n)
    k = int(split * n)
    assert np.allclose(temps[:, :k].mean(axis=1), 2.0, rtol=1e-4)
    assert np.allclose(temps[:, k:].mean(axis=1), -0.5, rtol=1e-4)
    assert (temps[:, :k] >= 0).all() and (temps[:, k:] <= 0).all()
    # one value per cycle: a stack of the templates of each
    many = cycle_templates([split, 0.5], [2.0, 1.0], [-0.5, -1.0], n)
    assert many.shape == (2, len(SHAPES), n) and np.array_equal(many[0], temps)


def test_templates_of_a_cycle_with_one_half():
    # a cycle that is all second half (split 0) or all first half (split 1)
    assert np.allclose(cycle_templates(0.0, 2.0, -1.0, 1000).mean(axis=1), -1.0, rtol=1e-4)
    assert np.allclose(cycle_templates(1.0, 2.0, -1.0, 1000).mean(axis=1), 2.0, rtol=1e-4)


def test_resample_averages_over_bins():
    x = np.arange(10.0)
    # sample i covers [i - 0.5, i + 0.5): bins of two samples each
    assert np.allclose(resample(x, -0.5, 9.5, 5), [0.5, 2.5, 4.5, 6.5, 8.5])
    # half of sample 0, all of sample 1, half of sample 2
    assert np.allclose(resample(x, 0, 2, 1), [1.0])
    rows = resample(x, np.array([-0.5, 4.5]), np.array([3.5, 8.5]), 2)
    assert np.allclose(rows, [[0.5, 2.5], [5.5, 7.5]])
    c = np.concatenate([[0.0], np.cumsum(x)])
    assert np.array_equal(resample(x, 0.2, 7.9, 4, cumulative=c), resample(x, 0.2, 7.9, 4))


def test_range_extrema_of_lists_and_empty_ranges():
    top, bottom = range_extrema([4, -2, 7, 1], [0, 1, 3, 2], [2, 4, 3, 9])
    assert top.tolist() == [4, 7, -np.inf, 7] and bottom.tolist() == [-2, -2, np.inf, 1]
    # bounds from np.floor / np.ceil (whole floats) index the same
    top, bottom = range_extrema([4, -2, 7, 1], np.array([0.0, 1, 3, 2]), np.array([2.0, 4, 3, 9]))
    assert top.tolist() == [4, 7, -np.inf, 7] and bottom.tolist() == [-2, -2, np.inf, 1]


def test_cycle_distances_do_not_depend_on_amplitude_or_offset_of_time():
    x, bounds = make_shape_cycles("sinusoidal", 6, snr_db=15, random_state=5)
    d = match_cycles(x, bounds)
    assert np.allclose(match_cycles(7.5 * x, bounds), d)
    assert np.allclose(match_cycles(np.r_[np.zeros(40), x], bounds + 40), d)
    assert match_cycles(x, np.empty((0, 3))).shape == (0, len(SHAPES))
    # a flat cycle matches every (flat) template exactly
    assert np.array_equal(match_cycles(np.zeros(300), [[0, 100, 200]]), np.zeros((1, 4)))


@pytest.mark.parametrize("shape", SHAPES)
def test_clean_cycles_are_nearest_their_own_template(shape):
    x, bounds = make_shape_cycles(shape, 8, snr_db=np.inf, random_state=6)
    d = match_cycles(x, bounds)
    assert (d.argmin(axis=1) == SHAPES.index(shape)).all()
    for params in ({"n_points": 16}, {"sakoe_chiba_radius": None}, {"backend": "tslearn"}):
        assert (match_cycles(x, bounds, **params).argmin(axis=1) == SHAPES.index(shape)).all()


def test_a_half_of_one_bin_is_matched_by_its_area():
    # 32 samples on 32 bins: the first half is one sample of height 3, the second -1
    x = np.r_[3.0, -np.ones(31)]
    d = match_cycles(x, [[-0.5, 0.5, 31.5]], sakoe_chiba_radius=0)
    assert d[0, SHAPES.index("rectangular")] == pytest.approx(0.0, abs=1e-12)
    # and the mirror: a second half of one sample of height -3
    d = match_cycles(-x[::-1], [[-0.5, 30.5, 31.5]], sakoe_chiba_radius=0)
    assert d[0, SHAPES.index("rectangular")] == pytest.approx(0.0, abs=1e-12)


def test_match_cycles_defaults():
    x, bounds = make_shape_cycles("trapezoidal", 6, snr_db=5, random_state=9)
    d = match_cycles(x, bounds)
    assert np.array_equal(d, match_cycles(x, bounds, n_points=32, sakoe_chiba_radius=2))
    assert not np.allclose(d, match_cycles(x, bounds, sakoe_chiba_radius=3))
    assert not np.allclose(d, match_cycles(x, bounds, n_points=31))


def test_shape_cycles_have_the_asked_periods_halves_heights_and_noise():
    kw = {"period": 80, "period_jitter": 0.2, "half_ratio": 1.5, "amplitude_ratio": 2.0}
    clean, bounds = make_shape_cycles("rectangular", 200, snr_db=np.inf, random_state=7, **kw)
    assert bounds.shape == (200, 3) and clean.size == bounds[-1, 2]
    assert bounds[0, 0] == 0 and np.array_equal(bounds[1:, 0], bounds[:-1, 2])
    periods = bounds[:, 2] - bounds[:, 0]
    assert periods.min() >= 80 * 0.8 - 1 and periods.max() <= 80 * 1.2 + 1
    assert periods.min() < 80 * 0.85 and periods.max() > 80 * 1.15  # the whole range is used
    ratio = (bounds[:, 1] - bounds[:, 0]) / (bounds[:, 2] - bounds[:, 1])
    assert ratio.min() > 1 / 1.5 - 0.05 and ratio.max() < 1.5 + 0.05
    assert ratio.min() < 1 / 1.4 and ratio.max() > 1.4  # both halves may be the longer
    first = clean[bounds[:, 0].astype(int)]  # the height of each first half
    second = clean[bounds[:, 1].astype(int)]
    assert np.allclose(first * second, -1.0)  # heights h and -1 / h
    assert first.min() >= 0.5 and first.max() <= 2.0 and first.min() < 0.6 and first.max() > 1.8
    # each half sampled at the centres of its samples: symmetric, never at its zeros
    tri, _ = make_shape_cycles("triangular", 5, snr_db=np.inf, random_state=7, **kw)
    for a, m, b in bounds[:5].astype(int):
        for half in (tri[a:m], tri[m:b]):
            assert np.allclose(half, half[::-1]) and np.abs(half).min() > 0
    noisy, same = make_shape_cycles("rectangular", 200, snr_db=10, random_state=7, **kw)
    assert np.array_equal(same, bounds)
    snr = 10 * np.log10(np.mean(clean**2) / np.mean((noisy - clean) ** 2))
    assert snr == pytest.approx(10, abs=0.2)


def test_shape_cycles_defaults():
    x, bounds = make_shape_cycles("rectangular", random_state=8)
    assert bounds.shape == (20, 3)
    periods = bounds[:, 2] - bounds[:, 0]
    assert 70 - 1 <= periods.min() and periods.max() <= 130 + 1 and np.ptp(periods) > 30
    ratio = (bounds[:, 1] - bounds[:, 0]) / (bounds[:, 2] - bounds[:, 1])
    assert ratio.min() > 0.5 - 0.05 and ratio.max() < 2 + 0.05 and np.ptp(np.log(ratio)) > 0.8
    clean, _ = make_shape_cycles("rectangular", snr_db=np.inf, random_state=8)
    heights = clean[bounds[:, 0].astype(int)]
    assert heights.min() >= 1 / 1.5 and heights.max() <= 1.5 and np.ptp(heights) > 0.5
    snr = 10 * np.log10(np.mean(clean**2) / np.mean((x - clean) ** 2))
    assert snr == pytest.approx(20, abs=0.5)
    assert np.array_equal(make_shape_cycles("rectangular", random_state=8)[0], x)
    # over many cycles the periods fill 100 +- 30 %, and no more
    many = make_shape_cycles("rectangular", 2000, random_state=8)[1]
    periods = many[:, 2] - many[:, 0]
    assert periods.min() == 70 and periods.max() == 130


@pytest.mark.parametrize("snr_db, required", [(20.0, 0.95), (10.0, 0.85)])
def test_shapes_are_matched_to_their_true_shape(snr_db, required):
    # halves differing up to 2x in duration, amplitudes up to 50 %, period +-30 %
    correct = total = 0
    for k, shape in enumerate(SHAPES):
        for seed in range(10):
            x, bounds = make_shape_cycles(shape, 20, snr_db=snr_db, random_state=seed)
            best = match_cycles(x, bounds).argmin(axis=1)
            correct += np.sum(best == k)
            total += best.size
    assert correct / total >= required


def test_tslearn_backend_gives_the_same_distances():
    x, bounds = make_shape_cycles("trapezoidal", 5, random_state=0)
    assert np.allclose(match_cycles(x, bounds), match_cycles(x, bounds, backend="tslearn"))


def _flow_loop(n=3000, period=100, noise=0.0, seed=0):
    """Triangular OP, square PV a quarter period later: a sticky flow loop."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    op = 50 + 3 * np.abs((t % period) / (period / 2) - 1)
    pv = 40 + np.sign(np.sin(2 * np.pi * (t + period / 4) / period))
    return np.stack([pv + noise * rng.normal(size=n), op, np.full(n, 40.0)], axis=1)


def test_transformer_finds_triangular_op_and_square_pv():
    X = _flow_loop(noise=0.05)[None]
    out = TemplateDistances().set_output(transform="pandas").fit_transform(X)
    assert out.loc[0, "op_share_triangular"] >= 0.9
    assert out.loc[0, "pv_share_rectangular"] + out.loc[0, "pv_share_trapezoidal"] >= 0.9
    assert out.loc[0, "oscillating"] == 1 and out.loc[0, "n_cycles"] >= 25
    assert out.loc[0, "period"] == pytest.approx(100, rel=0.05)


def test_cycle_table_columns_and_peak_to_peak():
    table = cycle_table(_flow_loop()[None])
    for col in [
        "loop",
        "cycle",
        "start",
        "end",
        "period",
        "amplitude_pos",
        "amplitude_neg",
        "area_ratio",
        "op_shape",
        "pv_shape",
        "op_peak_to_peak",
        "op_dist_triangular",
        "pv_dist_rectangular",
    ]:
        assert col in table.columns
    assert table["op_peak_to_peak"].median() == pytest.approx(3.0, rel=0.05)
    assert (table["end"] > table["start"]).all()


def test_unequal_lengths_and_bad_loops_in_one_batch():
    good = _flow_loop()
    X = np.full((4, 3000, 3), np.nan)
    X[0] = good
    X[1, :2000] = good[:2000]  # shorter loop, NaN-padded at the end
    X[2] = good
    X[2, 100:130, 1] = np.nan  # gap in OP
    X[3] = good
    X[3, :, 0] = 1.0  # constant PV
    out = TemplateDistances().set_output(transform="pandas").fit_transform(X)
    assert out["oscillating"].tolist() == [1.0, 1.0, 0.0, 0.0]
    assert out.loc[2:, "op_dist_triangular"].isna().all()
    assert out.loc[1, "n_cycles"] < out.loc[0, "n_cycles"]


def test_missing_op_is_named():
    X = _flow_loop()[None, :, :1]
    with pytest.raises(ValueError, match="needs the OP channel"):
        TemplateDistances().fit(X)
    out = TemplateDistances(signals=("pv",)).fit_transform(X)
    assert out.shape == (1, 4 + 4 + 3)


def test_feature_names_and_pandas_output():
    td = TemplateDistances().fit(_flow_loop()[None])
    names = td.get_feature_names_out()
    assert names[0] == "op_dist_rectangular" and names[-1] == "oscillating"
    out = td.set_output(transform="pandas").transform(_flow_loop()[None])
    assert isinstance(out, pd.DataFrame) and list(out.columns) == list(names)


@pytest.mark.parametrize(
    "params, match",
    [({"n_points": 4}, "n_points"), ({"n_points": 7}, "n_points"),
     ({"signals": ("op", "sp")}, "signals"), ({"dtw_backend": "cuda"}, "dtw_backend"),
     ({"sakoe_chiba_radius": -2}, "radius"), ({"min_cycles": 0}, "min_cycles"),
     ({"min_cycles": 1.5}, "min_cycles")],
)  # fmt: skip
def test_bad_parameters(params, match):
    with pytest.raises(ValueError, match=match):
        TemplateDistances(**params).fit(_flow_loop()[None])


@pytest.mark.parametrize("params", [{"n_points": 8}, {"sakoe_chiba_radius": 0}, {"min_cycles": 1}])
def test_smallest_allowed_parameters(params):
    out = TemplateDistances(**params).fit_transform(_flow_loop()[None])
    assert out[0, -1] == 1.0


# ---- pairing of PV cycles with OP cycles --------------------------------------------


def _crossings(c):
    """A signal's crossings ``c``, alternating in sign from upwards."""
    c = np.asarray(c, dtype=float)
    return SimpleNamespace(crossings=c, signs=np.where(np.arange(c.size) % 2 == 0, 1, -1))


def test_each_cycle_is_paired_with_the_nearest_in_time():
    # PV cycles (25, 75, 125), (125, 175, 225), (225, 275, 325): centres 75, 175, 275
    pv = _crossings([25, 75, 125, 175, 225, 275, 325])
    own = np.array([[25, 75, 125], [125, 175, 225], [225, 275, 325]], dtype=float)
    reference = np.array(
        [
            [20, 30, 60],  # centre 40: before the first PV centre -> the first
            [60, 70, 190],  # centre 125: a tie between 75 and 175 -> the earlier
            [100, 110, 180],  # centre 140 (not 145, the mid of its second half) -> 175
            [250, 260, 350],  # centre 300: after the last -> the last
        ],
        dtype=float,
    )
    np.testing.assert_array_equal(_nearest_cycles(reference, pv), own[[0, 0, 1, 2]])
    # two PV cycles, a reference beyond both
    two = _crossings([25, 75, 125, 175, 225])
    np.testing.assert_array_equal(
        _nearest_cycles(np.array([[200.0, 210, 300]]), two), [[125, 175, 225]]
    )
    # one PV cycle: every reference cycle gets it
    one = _crossings([25, 75, 125])
    np.testing.assert_array_equal(_nearest_cycles(reference[:2], one), [[25, 75, 125]] * 2)
    # no full PV cycle: the reference bounds are kept
    np.testing.assert_array_equal(_nearest_cycles(reference, _crossings([25, 75])), reference)


def _phase_loop(n=3000, lag=10):
    """Triangular OP (crossings at 25 and 75 mod 100), square PV crossing at 90 - lag."""
    t = np.arange(n)
    op = 50 + 3 * np.abs((t % 100) / 50 - 1)
    pv = 40 + np.sign(np.sin(2 * np.pi * (t + lag) / 100))
    return np.stack([pv, op, np.full(n, 40.0)], axis=1)[None]


def test_cycles_are_located_on_op_and_on_pv_without_op():
    X = _phase_loop()
    on_op = cycle_table(X)
    assert len(on_op) >= 25
    np.testing.assert_allclose(on_op["start"].iloc[1:] % 100, 25, atol=1)
    np.testing.assert_allclose(on_op["period"].iloc[1:], 100, atol=1)  # the first starts early
    np.testing.assert_allclose(on_op["end"] - on_op["start"], on_op["period"])
    on_pv = cycle_table(X, signals=("pv",))
    np.testing.assert_allclose(on_pv["start"].iloc[1:] % 100, 40, atol=1)
    assert "op_shape" not in on_pv and on_pv["pv_shape"].eq("rectangular").all()
    out = TemplateDistances(signals=("pv",)).set_output(transform="pandas").fit_transform(X)
    assert out.loc[0, "n_cycles"] == len(on_pv) and out.loc[0, "period"] == pytest.approx(100)
    # PV regular for its first 10 cycles only: the cycles are still OP's 29
    X[0, 1000:, 0] = 40 + 0.05 * np.random.default_rng(0).normal(size=2000)
    out = TemplateDistances().set_output(transform="pandas").fit_transform(X)
    assert out.loc[0, "n_cycles"] == len(on_op) == 29


# ---- the transformer's columns -------------------------------------------------------


def test_mean_distances_and_shares_of_a_triangular_op():
    out = TemplateDistances().set_output(transform="pandas").fit_transform(_phase_loop())
    shares = out.filter(like="op_share_").iloc[0]
    assert shares.sum() == pytest.approx(1.0) and shares["op_share_triangular"] == 1.0
    assert out.filter(like="pv_share_").iloc[0].sum() == pytest.approx(1.0)
    dist = out.filter(like="op_dist_").iloc[0]
    assert (
        dist.idxmin() == "op_dist_triangular" and dist.min() < 0.5 * dist.drop(dist.idxmin()).min()
    )


def test_a_loop_that_does_not_oscillate_is_said_so():
    rng = np.random.default_rng(0)
    X = np.stack([rng.normal(size=3000), rng.normal(size=3000), np.zeros(3000)], axis=1)[None]
    assert loop_status(X, require_op=True)[0] == "ok"
    out = TemplateDistances().fit_transform(X)
    assert out[0, -1] == 0.0 and np.isnan(out[0, :-1]).all()
    assert cycle_table(X).empty


def test_min_cycles_is_used():
    X = _phase_loop()  # 30 cycles
    assert TemplateDistances(min_cycles=20).fit_transform(X)[0, -1] == 1.0
    assert TemplateDistances(min_cycles=40).fit_transform(X)[0, -1] == 0.0


def test_defaults_and_dtw_settings_are_used():
    X = _phase_loop() + np.random.default_rng(1).normal(0, 0.1, (1, 3000, 3))
    default = TemplateDistances().fit_transform(X)
    explicit = TemplateDistances(n_points=32, sakoe_chiba_radius=2, dtw_backend="numba")
    np.testing.assert_array_equal(default, explicit.fit_transform(X))
    # a wider band can only shorten the warping path's cost
    d = {r: cycle_table(X, sakoe_chiba_radius=r).filter(like="_dist_") for r in (0, 2, None)}
    assert (d[0] >= d[2] - 1e-12).all().all() and (d[2] >= d[None] - 1e-12).all().all()
    assert (d[0] > d[2] + 1e-3).any().any()
    coarse = TemplateDistances(n_points=8).fit_transform(X)
    assert not np.allclose(coarse[0, :8], default[0, :8])


def test_shared_analyses_keep_settings_apart():
    # the scan shares one analysis per loop between transformers: results are memoised
    # per setting, never handed to a transformer with other settings
    X = _phase_loop() + np.random.default_rng(2).normal(0, 0.1, (1, 3000, 3))
    loops = check_loops(X)
    shared = analyse_loops(loops)
    for params in ({}, {"sakoe_chiba_radius": None}, {"sakoe_chiba_radius": 0}, {"n_points": 8}):
        td = TemplateDistances(**params).fit(X)
        np.testing.assert_array_equal(td.transform_analysed(loops, shared), td.transform(X))


def test_cycle_table_skips_loops_that_cannot_be_analysed():
    good = _flow_loop()
    X = np.stack([good, good, good])
    X[1, 100:130, 1] = np.nan  # a gap in OP
    X[2, :, 1] = np.nan  # no OP
    X = np.concatenate([X, good[None]])
    X[3, :, 0] = 40.0  # constant PV: OP alone would give cycles
    table = cycle_table(X)
    assert set(table["loop"]) == {0}


def _cycle_table_cycle_by_cycle(X):
    """The per-cycle loop the vectorised cycle table replaced (reference)."""
    from sktiction.cycles import analyze_cycles
    from sktiction.features.area_ratio import half_cycle_ratios

    td = TemplateDistances().fit(X)
    rows = []
    for i in range(len(X)):
        found = td._cycles(X, i, X.shape[1])
        if found is None:
            continue
        ana, bounds, _ = found["op"]
        err = analyze_cycles(X[i, :, 2] - X[i, :, 0])
        ratios, halves = half_cycle_ratios(err)
        mids = (err.crossings[halves] + err.crossings[halves + 1]) / 2
        for c, (a, _m, b) in enumerate(bounds):
            seg = ana.centred[int(np.floor(a)) : int(np.ceil(b)) + 1]
            r = ratios[(mids >= a) & (mids < b)]
            row = {
                "loop": i,
                "cycle": c,
                "amplitude_pos": seg.max(),
                "amplitude_neg": -seg.min(),
                "area_ratio": np.nanmean(r) if np.isfinite(r).any() else np.nan,
            }
            for s in ("op", "pv"):
                sana, sb, d = found[s]
                x = sana.centred[int(np.floor(sb[c, 0])) : int(np.ceil(sb[c, 2])) + 1]
                row[f"{s}_shape"] = SHAPES[int(np.argmin(d[c]))]
                row[f"{s}_peak_to_peak"] = np.ptp(x)
            rows.append(row)
    return pd.DataFrame(rows)


def test_cycle_table_equals_the_cycle_by_cycle_reference():
    from sktiction.datasets import make_loops

    X, _ = make_loops(10, n_samples=3000, stiction_fraction=0.7, random_state=9)
    table = cycle_table(X)
    ref = _cycle_table_cycle_by_cycle(X)
    assert len(table) == len(ref) > 50
    pd.testing.assert_frame_equal(table[ref.columns], ref, check_dtype=False, rtol=1e-12)
