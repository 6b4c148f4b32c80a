"""Known values of the cycle-free loop descriptors (``features/descriptors.py``)."""

import numpy as np
import pytest

from sktiction.features import LoopDescriptors
from sktiction.features.descriptors import _ccf_features, _jump_share, _saturated_share


def _describe(pv, op=None, **params):
    X = np.stack([pv, op], axis=1)[None] if op is not None else np.asarray(pv)[None]
    est = LoopDescriptors(**params).fit(X)
    return dict(zip(est.get_feature_names_out(), est.transform(X)[0]))


@pytest.mark.parametrize(
    "n_moves, expected",
    [
        (110, 3 / 110),  # the top 2 % of 110 moves is 2.2, rounded up to 3
        (1000, 0.02),  # a ramp spreads its travel evenly
        (10, 0.1),  # at least one move, however short the record
    ],
)
def test_jump_share_of_a_ramp(n_moves, expected):
    assert _jump_share(0.5 * np.arange(n_moves + 1.0)) == pytest.approx(expected)


def test_jump_share_of_slips_and_of_a_still_signal():
    x = np.repeat([0.0, 1.0, 3.0], 200)  # two slips carry all the travel
    assert _jump_share(x) == pytest.approx(1.0)
    assert _jump_share(-x) == pytest.approx(1.0)  # absolute moves
    assert np.isnan(_jump_share(np.full(50, 2.0)))
    assert _jump_share(np.array([0.0, 0.25, 1.0])) == 0.75  # a travel of exactly 1


def test_saturated_share_counts_both_edges_within_the_tolerance():
    t = np.arange(1000)
    op = 50 + 9 * np.sin(2 * np.pi * t / 100)  # moving, inside the range 40-60
    op[:300] = 60.0  # pinned at the top
    op[300:400] = 60 - 0.0005 * 20  # within 0.1 % of the range: still pinned
    op[400:500] = 40.0  # pinned at the bottom
    op[500:600] = 40 + 0.0009 * 20
    op[600:700] = 60 - 0.0015 * 20  # outside the tolerance: moving
    assert _saturated_share(op) == pytest.approx(0.6)
    assert _saturated_share(op * 1e3 - 7) == pytest.approx(0.6)  # units do not matter


def test_saturated_share_ignores_a_few_touches():
    t = np.arange(1000.0)
    ramp = t % 100  # touches 0 and 99 ten times each: 2 %
    assert _saturated_share(ramp) == pytest.approx(0.02)
    ramp[np.flatnonzero(ramp == 99)[1:]] = 98.5  # one touch at the top, ten at the bottom
    assert _saturated_share(ramp) == pytest.approx(0.011)
    ramp[np.flatnonzero(ramp == 0)[2:]] = 0.5  # 1 + 2 touches: under 1 %
    assert _saturated_share(ramp) == 0.0


def test_ccf_of_a_reverse_acting_loop_and_a_pv_that_leads():
    t = np.arange(3000)
    op = 50 + 5 * np.sin(2 * np.pi * t / 200)
    got = _describe(100 - op, op)  # PV falls as OP rises: the CCF is -1 at lag 0
    assert got["ccf_zero_lag"] == pytest.approx(-1.0)
    assert got["ccf_peak_lag"] == 0.0
    got = _describe(np.roll(op, -20), op)  # PV 20 samples ahead of OP
    assert got["ccf_peak_lag"] == pytest.approx(-0.2)
    assert got["ccf_zero_lag"] == pytest.approx(np.cos(2 * np.pi * 20 / 200), abs=0.03)


def test_ccf_lags_are_capped_at_a_quarter_of_the_loop():
    t = np.arange(200)
    op = 50 + 5 * np.sin(2 * np.pi * t / 400) + np.random.default_rng(0).normal(0, 0.5, t.size)
    got = _describe(np.roll(op, 45), op, max_lag=100)  # lags up to 50, not 100
    assert got["ccf_peak_lag"] == pytest.approx(45 / 50)


def test_ccf_of_signals_with_offsets_and_of_a_constant_pv():
    rng = np.random.default_rng(2)
    op = rng.normal(size=500)
    pv = 1000 + 3 * np.roll(op, 7)  # offsets and scale do not matter
    zero, peak = _ccf_features(pv, op + 200, 10)
    assert peak == pytest.approx(0.7)
    assert zero == pytest.approx(np.corrcoef(pv, op)[0, 1] / np.corrcoef(pv[7:], op[:-7])[0, 1],
                                 abs=0.01)  # fmt: skip
    assert np.isnan(_ccf_features(np.full(500, 3.0), op, 10)).all()


def test_loops_without_a_moving_op_keep_only_the_pv_column():
    t = np.arange(1000)
    pv = np.repeat(np.arange(10.0), 100) + 0.001 * t
    for op in (None, np.full(t.size, 40.0)):
        got = _describe(pv, op)
        assert got["pv_jump_share"] == pytest.approx(_jump_share(pv))
        assert np.isnan([v for k, v in got.items() if k != "pv_jump_share"]).all()


def test_jump_ratio_reads_pv_slips_while_op_ramps():
    t = np.arange(2000)
    op = 50 + 5 * np.abs((t % 200) / 100 - 1)  # triangular OP
    pv = np.floor(op)  # PV moves in steps of 1 while OP ramps
    got = _describe(pv, op)
    assert got["pv_op_jump_ratio"] == pytest.approx(got["pv_jump_share"] / got["op_jump_share"])
    assert got["pv_op_jump_ratio"] > 10


@pytest.mark.parametrize("max_lag", [0, 2.5, -3])
def test_max_lag_must_be_a_positive_integer(max_lag):
    with pytest.raises(ValueError, match="max_lag"):
        LoopDescriptors(max_lag=max_lag).fit(np.ones((1, 100, 2)))


def test_the_smallest_max_lag():
    t = np.arange(400)
    op = np.sin(2 * np.pi * t / 50)
    assert _describe(np.roll(op, 1), op, max_lag=1)["ccf_peak_lag"] == 1.0
    # a delay beyond max_lag is read at max_lag, the largest lag looked at
    assert _describe(np.roll(op, 2), op, max_lag=1)["ccf_peak_lag"] == 1.0


def test_ccf_zero_lag_is_relative_to_the_peak_of_a_noisy_pv():
    t = np.arange(4000)
    op = 50 + 5 * np.sin(2 * np.pi * t / 200)
    noise = np.random.default_rng(5).normal(0, 3.5, t.size)  # about as strong as the cycle
    got = _describe(np.roll(op, 20) + noise, op)
    # noise lowers every lag alike: the ratio is still that of the clean cycle
    assert got["ccf_zero_lag"] == pytest.approx(np.cos(2 * np.pi * 20 / 200), abs=0.05)
    assert got["ccf_peak_lag"] == pytest.approx(0.2, abs=0.03)
