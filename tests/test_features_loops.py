"""The per-loop plumbing every transformer shares (``features/_loops.py``)."""

import re
import warnings

import numpy as np
import pandas as pd
import pytest
from sklearn.exceptions import NotFittedError

from sktiction._validation import check_loops
from sktiction.cycles import analyze_cycles
from sktiction.datasets import make_loops
from sktiction.features._loops import (
    LoopAnalysis,
    LoopTransformer,
    analyse_loops,
    control_error,
    has_channel,
)


class _Spread(LoopTransformer):
    """The smallest transformer: PV's range and OP's (an OP reader), and a flag."""

    feature_names = ("pv_range", "op_range", "oscillating")
    _needs_op = True

    def _transform_loop(self, loops, i, n):
        return [np.ptp(loops[i, :n, 0]), np.ptp(loops[i, :n, 1]), 1.0]


class _PVOnly(_Spread):
    _needs_op = False


def _loop(n=200, period=40.0):
    t = np.arange(n)
    pv = np.sin(2 * np.pi * t / period)
    return np.stack([pv, 2 * pv + 50, np.full(n, 0.5)], axis=1)


def test_control_error_is_sp_minus_pv_or_minus_pv():
    X = np.full((2, 6, 3), np.nan)
    X[:, :5, 0] = [1.0, 2, 3, 4, 5]
    X[0, :5, 2] = 10.0
    loops = check_loops(X)
    assert control_error(loops, 0, 5).tolist() == [9, 8, 7, 6, 5]
    assert control_error(loops, 1, 5).tolist() == [-1, -2, -3, -4, -5]
    assert control_error(loops, 0, 3).tolist() == [9, 8, 7]


def test_has_channel_sees_a_single_value():
    X = np.full((2, 10, 3), np.nan)
    X[:, :, 0] = 1.0
    assert not has_channel(X, 1)
    X[1, 7, 1] = 3.0
    assert has_channel(X, 1) and has_channel(X, 0) and not has_channel(X, 2)


def test_loop_analysis_signals_and_cycles_are_kept_per_setting():
    X = np.full((2, 300, 3), np.nan)
    X[1, :250] = _loop(250)
    loops = check_loops(X)
    a = LoopAnalysis(loops, 1, 250)
    assert a.signal("pv").shape == (250,) and np.array_equal(a.signal("op"), X[1, :250, 1])
    assert np.array_equal(a.signal("error"), 0.5 - X[1, :250, 0])
    assert a.signal("error") is a.signal("error")
    three = a.cycles("pv")
    assert three is a.cycles("pv", 3) and three is a.cycles("pv", 3.0)
    seven = a.cycles("pv", min_cycles=7)
    assert seven is not three and seven is a.cycles("pv", 7)
    # each setting's analysis is analyze_cycles' own
    assert len(three.cycles) == len(analyze_cycles(X[1, :250, 0], min_cycles=3).cycles) > 0
    assert len(seven.cycles) == len(analyze_cycles(X[1, :250, 0], min_cycles=7).cycles) == 0
    assert a.cycles("op") is not three
    assert a.memo("x", lambda: 1) == 1 and a.memo("x", lambda: 2) == 1


def test_analyse_loops_gives_each_loop_its_length():
    X = np.full((3, 50, 3), np.nan)
    X[0, :50, 0] = 1.0
    X[1, :35, 0] = 1.0
    X[2, :21, 0] = 2.0
    analyses = analyse_loops(check_loops(X))
    assert [(a.i, a.n) for a in analyses] == [(0, 50), (1, 35), (2, 21)]


def test_transformer_gives_nan_rows_and_no_oscillation_for_bad_loops():
    X = np.stack([_loop(), _loop(), _loop(), _loop()])
    X[1, :, 0] = 3.0  # constant PV
    X[2, 50:60, 1] = np.nan  # a gap in OP
    X[3, :, 1] = 7.0  # constant OP: bad only for a transformer that reads OP
    got = _Spread().fit(X[:1]).transform(X)
    assert np.allclose(got[0], [2, 4, 1])
    assert np.isnan(got[1:, :2]).all() and (got[1:, 2] == 0).all()
    got = _PVOnly().fit(X).transform(X)
    assert np.allclose(got[[0, 3]], [[2, 4, 1], [2, 0, 1]])
    assert (got[1:3, 2] == 0).all()
    # a loop NaN-padded at the end is read up to its own length
    padded = np.full((2, 300, 3), np.nan)
    padded[:, :200] = X[:2]
    padded[0, :150] = _loop(150, period=30) * 3
    padded[0, 150:] = np.nan
    got = _Spread().fit(padded).transform(padded)
    short = _loop(150, period=30) * 3
    assert np.allclose(got[0], [np.ptp(short[:, 0]), np.ptp(short[:, 1]), 1])
    assert np.isnan(got[1, :2]).all()


def test_transformer_without_an_oscillating_column_is_all_nan_on_bad_loops():
    class Range(_PVOnly):
        feature_names = ("pv_range", "op_range")

        def _transform_loop(self, loops, i, n):
            return super()._transform_loop(loops, i, n)[:2]

    X = np.stack([_loop(), _loop()])
    X[1, :, 0] = 3.0
    got = Range().fit_transform(X)
    assert np.allclose(got[0], [2, 4]) and np.isnan(got[1]).all()


def test_status_given_is_used():
    X = np.stack([_loop(), _loop()])
    loops = check_loops(X)
    est = _Spread().fit(X)
    got = est.transform_analysed(loops, analyse_loops(loops), status=np.array(["ok", "constant"]))
    assert np.allclose(got[0], [2, 4, 1]) and np.isnan(got[1, :2]).all() and got[1, 2] == 0


def test_op_readers_refuse_loops_without_op_and_name_it():
    pv_only = _loop()[None, :, :1]
    with pytest.raises(ValueError, match=r"_Spread needs the OP channel \(X\[:, :, 1\]\)"):
        _Spread().fit(pv_only)
    with pytest.raises(ValueError, match=r"Pass loops with channels PV, OP, SP, or use signals"):
        _Spread().fit(pv_only)
    est = _Spread().fit(_loop()[None])
    with pytest.raises(ValueError, match="needs the OP channel"):
        est.transform(pv_only)
    got = _PVOnly().fit_transform(pv_only)
    assert got[0, 0] == pytest.approx(2) and np.isnan(got[0, 1]) and got[0, 2] == 1


def test_fit_records_channels_and_names_need_a_fit():
    assert _Spread().fit(_loop()[None]).n_channels_in_ == 3
    assert _Spread().fit(_loop()[None, :, :2]).n_channels_in_ == 2
    assert _PVOnly().fit(_loop()[None, :, 0]).n_channels_in_ == 1
    with pytest.raises(NotFittedError):
        _Spread().get_feature_names_out()
    with pytest.raises(NotFittedError):
        _Spread().transform(_loop()[None])
    # one PV record per row: its length is checked as scikit-learn's n_features_in_
    est = _PVOnly().fit(_loop()[None, :, 0])
    assert est.n_features_in_ == 200
    assert est.transform(_loop()[None, :, 0]).shape == (1, 3)
    with pytest.raises(ValueError, match="features"):
        est.transform(_loop(250)[None, :, 0])
    assert not hasattr(est.fit(_loop()[None]), "n_features_in_")  # 3-D loops: any length
    names = _Spread().fit(_loop()[None]).get_feature_names_out()
    assert names.dtype == object and names.tolist() == list(_Spread.feature_names)


def test_tags_allow_nan_padded_three_dimensional_loops():
    tags = _Spread().__sklearn_tags__()
    assert tags.input_tags.allow_nan and tags.input_tags.three_d_array
    assert LoopTransformer()._validate_params() is None


def test_a_table_with_channel_columns_is_refused_as_many_loops():
    """One loop as a DataFrame must not become thousands of 3-sample PV records."""
    X, _ = make_loops(1, n_samples=300, random_state=0)
    one = pd.DataFrame(X[0], columns=["PV", "OP", "SP"])
    with pytest.raises(ValueError, match=r"channel columns \['PV', 'OP', 'SP'\]"):
        check_loops(one)
    assert check_loops(one.to_numpy()[None]).shape == (1, 300, 3)  # as the message says
    assert check_loops(pd.DataFrame(X[:, :, 0])).shape == (1, 300, 3)  # PV rows still fine


def test_one_loop_as_a_plain_array_is_read_as_records_with_a_warning():
    X, _ = make_loops(1, n_samples=300, random_state=0)
    with pytest.warns(UserWarning, match=r"2-D of shape \(300, 3\): read as 300 PV records .* "
                                         r"X\[None\] \(shape \(1, 300, 3\)\)"):
        assert check_loops(X[0]).shape == (300, 3, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # PV records of a usable length: no warning
        assert check_loops(X[:, :, 0]).shape == (1, 300, 3)
        assert check_loops(np.zeros((10, 3))).shape == (10, 3, 3)


@pytest.mark.parametrize(
    "columns, order",
    [
        (["FIC101.PV", "FIC101.OP", "FIC101.SP"], ["FIC101.PV", "FIC101.OP", "FIC101.SP"]),
        (["SV", "OUT", "PV [m3/h]"], ["PV [m3/h]", "OUT", "SV"]),
        (["time", "y", "u"], ["y", "u"]),
    ],
)
def test_a_table_with_the_readers_channel_names_is_refused_with_its_own_columns(columns, order):
    """Historian names (tag prefixes, units, aliases) mark a one-loop table too, and the
    message names the table's own columns in the order PV, OP, SP."""
    X, _ = make_loops(1, n_samples=200, random_state=0)
    with pytest.raises(ValueError, match=re.escape(f"X[{order}].to_numpy()[None]")):
        check_loops(pd.DataFrame(X[0], columns=columns))
    # columns that name no channel (or only the time and a setpoint) are PV records
    for names in (["a", "b", "c"], ["t", "sp", "x"]):
        assert check_loops(pd.DataFrame(X[0], columns=names)).shape == (200, 3, 3)


def test_infinite_values_are_refused_naming_the_loops_that_hold_them():
    X, _ = make_loops(12, n_samples=100, random_state=0)
    X[[3, 11], 50, 1] = np.inf
    with pytest.raises(ValueError, match=r"infinite values \(in 2 of 12 loops: 3, 11\)"):
        check_loops(X)
