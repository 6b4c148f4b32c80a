"""repair_gaps: short gaps bridged, long gaps split the record, the longest stretch kept."""

import numpy as np
import pytest

from sktiction._validation import _bridge_limit, loop_status, repair_gaps


def sine(n=640, period=64.0, phase=0.3):
    k = np.arange(n)
    return np.stack([np.sin(2 * np.pi * k / period + phase), np.cos(2 * np.pi * k / period)], -1)


def test_complete_loops_are_unchanged():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(3, 200, 3))
    X[1, 150:] = np.nan  # padding, not a gap
    Xr, info = repair_gaps(X)
    np.testing.assert_array_equal(Xr, X)
    assert info[["n_bridged", "n_filled", "n_gaps_split"]].eq(0).all().all()
    assert info["kept_stop"].tolist() == [200, 150, 200] and info["usable"].all()


def test_auto_limit_is_a_sixteenth_of_the_period():
    for period in (32, 64, 160):
        assert _bridge_limit(sine(n=20 * period, period=period)[:, 0]) == period // 16 - 1
    noise = np.random.default_rng(1).normal(size=2000)
    assert _bridge_limit(noise) == 1
    # A drift under the oscillation does not stretch the limit.
    drifting = sine(n=1280)[:, 0] + np.linspace(0, 5, 1280)
    assert _bridge_limit(drifting) == 3


def test_short_gaps_bridged_by_straight_lines():
    X = sine()[None].copy()
    truth = X.copy()
    X[0, 100:103, 0] = np.nan  # 3 samples, a chord over 1/16 period: bridged
    X[0, 300:302, 1] = np.nan  # OP only
    Xr, info = repair_gaps(X)
    row = info.iloc[0]
    assert (row["n_bridged"], row["n_filled"], row["n_gaps_split"]) == (2, 5, 0)
    assert (row["kept_start"], row["kept_stop"], row["max_gap"]) == (0, 640, 3)
    # Values on the straight line between the neighbours...
    line = np.interp(np.arange(100, 103), [99, 103], truth[0, [99, 103], 0])
    np.testing.assert_allclose(Xr[0, 100:103, 0], line)
    np.testing.assert_allclose(
        Xr[0, 300:302, 1], np.interp([300, 301], [299, 302], truth[0, [299, 302], 1])
    )
    # ...within 2 % of the amplitude of the true sine, as documented.
    assert np.abs(Xr[..., :2] - truth).max() < 0.02
    assert np.isnan(Xr[0, :, 2]).all()  # an absent SP stays absent
    assert loop_status(Xr).tolist() == ["ok"] and loop_status(X).tolist() == ["nan_gap"]


def test_long_gap_splits_and_longest_stretch_moves_to_start():
    X = sine(n=600)[None].copy()
    truth = X[0].copy()
    X[0, :3] = np.nan  # missing at the start: cut, not a split
    X[0, 200:260, 0] = np.nan  # long: split
    X[0, 300, 1] = np.nan  # short, inside the kept stretch
    X[0, 590:, 1] = np.nan  # OP missing at the end: cut
    Xr, info = repair_gaps(X, max_gap=5)
    row = info.iloc[0]
    assert (row["kept_start"], row["kept_stop"], row["n_gaps_split"]) == (260, 590, 1)
    assert (row["n_bridged"], row["n_filled"]) == (1, 1)
    np.testing.assert_array_equal(Xr[0, :40, 0], truth[260:300, 0])
    assert np.isnan(Xr[0, 330:]).all() and not np.isnan(Xr[0, :330, :2]).any()


def test_unusable_only_when_no_stretch_is_long_enough():
    X = np.tile(np.arange(100.0), (2, 1))
    X[0, 10::15] = np.nan  # one-sample gaps: bridged, usable
    X[1, 10:20] = X[1, 30:40] = X[1, 50:60] = X[1, 75:85] = np.nan  # stretches of 10-15
    Xr, info = repair_gaps(X, max_gap=2, min_length=20)
    assert info["usable"].tolist() == [True, False]
    assert info.loc[1, "kept_stop"] - info.loc[1, "kept_start"] == 15
    np.testing.assert_array_equal(Xr[0, :, 0], np.arange(100.0))  # straight line restored


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"max_gap": -1}, "max_gap"),
        ({"max_gap": "long"}, "max_gap"),
        ({"min_length": 0}, "min_length"),
    ],
)
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        repair_gaps(np.zeros((1, 10)), **kwargs)
