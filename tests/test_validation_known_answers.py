"""Known answers of the input checks in ``sktiction._validation``.

Each expected value is read off the definitions in the docstrings (shapes, statuses,
lengths, the stretch repair_gaps keeps, the 1/16-period bridge) or computed here by an
independent route (the autocorrelation by ``np.correlate`` instead of an FFT).
"""

import re
import warnings

import numpy as np
import pandas as pd
import pytest
from sklearn.base import BaseEstimator

from sktiction._validation import (
    _bridge_limit,
    check_loops,
    check_max_gap,
    check_positive,
    check_random_state_seed,
    loop_lengths,
    loop_status,
    repair_gaps,
    validate_loops,
)

# ---------------------------------------------------------------- check_random_state_seed


def test_random_state_seed_accepts_none_ints_generators_and_random_states():
    assert isinstance(check_random_state_seed(None), np.random.Generator)
    a = check_random_state_seed(3).standard_normal(4)
    np.testing.assert_array_equal(a, np.random.default_rng(3).standard_normal(4))
    g = np.random.default_rng(5)
    assert check_random_state_seed(g) is g
    # a RandomState seeds a Generator: reproducibly, and different seeds give other draws
    one = check_random_state_seed(np.random.RandomState(7)).standard_normal(3)
    two = check_random_state_seed(np.random.RandomState(7)).standard_normal(3)
    np.testing.assert_array_equal(one, two)
    firsts = {check_random_state_seed(np.random.RandomState(s)).integers(2**62)
              for s in range(200)}  # fmt: skip
    assert len(firsts) == 200  # seeds drawn from a wide range, not a handful
    with pytest.raises(ValueError, match=r"random_state must be None, an int or a numpy "
                                         r"Generator; got 'a'\."):  # fmt: skip
        check_random_state_seed("a")


# ---------------------------------------------------------------- check_positive


def test_check_positive_known_answers_and_messages():
    assert check_positive(2.5, "x") == 2.5
    assert check_positive(3, "x") == 3.0 and type(check_positive(3, "x")) is float
    assert check_positive(np.int64(4), "x") == 4.0
    assert check_positive(0.0, "x", strict=False) == 0.0
    assert check_positive(0.5, "x", upper=0.5) == 0.5
    bad = [
        (0.0, {}, "x must be a finite number > 0; got 0.0."),
        (0, {}, "x must be a finite number > 0; got 0."),
        (-1.0, {"strict": False}, "x must be a finite number >= 0; got -1.0."),
        (float("inf"), {}, "x must be a finite number > 0; got inf."),
        (float("nan"), {"strict": False}, "x must be a finite number >= 0; got nan."),
        (np.float32("inf"), {}, "x must be a finite number > 0; got "),
        (0.6, {"upper": 0.5}, "x must be a finite number > 0 and <= 0.5; got 0.6."),
        (0.6, {"strict": False, "upper": 0.5}, "x must be a finite number >= 0 and <= 0.5"),
        ("a", {}, "x must be a finite number > 0; got 'a'."),
        (None, {}, "x must be a finite number > 0; got None."),
    ]
    for value, kwargs, message in bad:
        with pytest.raises(ValueError, match=re.escape(message)):
            check_positive(value, "x", **kwargs)


# ---------------------------------------------------------------- check_loops


def test_check_loops_pads_missing_channels_and_copies_as_float():
    X = np.arange(12, dtype=int).reshape(2, 3, 2)
    out = check_loops(X)
    assert out.shape == (2, 3, 3) and out.dtype == np.float64
    np.testing.assert_array_equal(out[..., :2], X)
    assert np.isnan(out[..., 2]).all()
    # three integer channels: float64 too, as documented
    assert check_loops(np.ones((1, 5, 3), dtype=int)).dtype == np.float64
    obj = np.ones((1, 5, 3)).astype(object)
    assert check_loops(obj).dtype == np.float64
    assert check_loops(np.ones((2, 5), dtype=object)).dtype == np.float64
    # a copy: writing to the result leaves the input alone
    Y = np.zeros((1, 4, 3))
    check_loops(Y)[0, 0, 0] = 5.0
    assert Y[0, 0, 0] == 0.0
    # one sample is not empty
    assert check_loops(np.ones((1, 1, 3))).shape == (1, 1, 3)


@pytest.mark.parametrize(
    ("X", "error", "message"),
    [
        (np.ones((0, 5, 3)), ValueError, "loops is empty: shape (0, 5, 3)."),
        (np.ones((2, 0, 3)), ValueError, "loops is empty: shape (2, 0, 3)."),
        (np.ones((1, 5, 4)), ValueError,
         "loops must have 1 to 3 channels (PV, OP, SP in that order); got 4."),
        (np.ones((1, 5, 0)), ValueError, "loops must have 1 to 3 channels"),
        (np.ones((1, 5, 3)) * 1j, ValueError,
         "Complex data not supported: loops holds complex values."),
        (np.full((1, 5, 3), "a"), TypeError, "loops must hold numbers; got dtype <U1."),
    ],
)  # fmt: skip
def test_check_loops_refuses_with_a_message_naming_the_input(X, error, message):
    with pytest.raises(error, match=re.escape(message)):
        check_loops(X, name="loops")


def test_infinite_values_list_at_most_ten_loops():
    X = np.zeros((12, 5, 3))
    X[:10, 2, 0] = np.inf
    with pytest.raises(ValueError, match=re.escape(
            "(in 10 of 12 loops: 0, 1, 2, 3, 4, 5, 6, 7, 8, 9); ")):  # fmt: skip
        check_loops(X)
    X[10, 1, 1] = -np.inf
    with pytest.raises(ValueError, match=re.escape(
            "(in 11 of 12 loops: 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, ...); ")):  # fmt: skip
        check_loops(X)
    # 2-D: scikit-learn's check, naming the input
    with pytest.raises(ValueError, match="records"):
        check_loops(np.array([[1.0, np.inf]]), name="records")


def test_two_dimensional_input_warns_only_for_short_wide_records():
    def warned(shape):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_loops(np.zeros(shape))
        return [w for w in caught if issubclass(w.category, UserWarning)]

    assert len(warned((20, 3))) == 1 and len(warned((20, 1))) == 1
    assert not warned((19, 3)) and not warned((20, 4)) and not warned((100, 50))
    (w,) = warned((25, 2))
    assert "X is 2-D of shape (25, 2): read as 25 PV records of 2 sample(s)" in str(w.message)
    assert "is X[None] (shape (1, 25, 2))" in str(w.message)


def test_non_numeric_columns_are_named():
    df = pd.DataFrame({"a": [1.0, 2.0], "b": ["x", "y"], "c": [1, 2], "d": ["u", "v"]})
    with pytest.raises(TypeError, match=re.escape("loops has non-numeric columns: b, d.")):
        check_loops(df, name="loops")
    with pytest.raises(TypeError, match="^" + re.escape("X has non-numeric columns: b, d.")):
        validate_loops(BaseEstimator(), df, reset=True)
    # a numeric table of records is read as records
    ok = check_loops(pd.DataFrame({"a": [1.0, 2.0], "c": [1, 2]}))
    np.testing.assert_array_equal(ok[:, :, 0], [[1.0, 1.0], [2.0, 2.0]])
    # a Series is 1-D: scikit-learn's refusal, not an attribute error
    with pytest.raises(ValueError):
        check_loops(pd.Series([1.0, 2.0]))


def test_pandas_extension_dtypes_are_judged_not_crashed_on():
    """pandas 3 stores text as a ``str`` extension dtype and nullable numbers as
    ``Int64``/``Float64``: numpy cannot interpret them (a bare "Cannot interpret ... as a
    data type" TypeError before the fix); text and categories are named, numbers read."""
    text = pd.DataFrame({"a": [1.0, 2.0], "b": pd.array(["x", "y"], dtype="string")})
    with pytest.raises(TypeError, match=re.escape("X has non-numeric columns: b.")):
        check_loops(text)
    cats = pd.DataFrame({"a": [1.0, 2.0], "k": pd.Categorical(["x", "y"])})
    with pytest.raises(TypeError, match=re.escape("X has non-numeric columns: k.")):
        check_loops(cats)
    nullable = pd.DataFrame({"i": pd.array([1, None], dtype="Int64"),
                             "f": pd.array([1.5, 2.0], dtype="Float64")})  # fmt: skip
    out = check_loops(nullable)
    np.testing.assert_array_equal(out[:, :, 0], [[1.0, 1.5], [np.nan, 2.0]])
    assert out.shape == (2, 2, 3) and out.dtype == np.float64
    flags = pd.DataFrame({"a": [1.0, 2.0], "ok": pd.array([True, False], dtype="boolean")})
    with pytest.raises(TypeError, match=re.escape("X has non-numeric columns: ok.")):
        check_loops(flags)  # nullable booleans are named, as numpy booleans are


@pytest.mark.parametrize(
    ("columns", "order"),
    [(["PV", "SP"], ["PV", "SP"]), (["OP", "SP"], ["OP", "SP"]), (["x", "PV"], ["PV"])],
)
def test_a_table_with_one_of_pv_or_op_is_one_loop(columns, order):
    df = pd.DataFrame(np.ones((30, len(columns))), columns=columns)
    with pytest.raises(ValueError) as err:
        check_loops(df, name="T")
    message = str(err.value)
    assert f"T[{order}].to_numpy()[None]" in message
    assert "(shape (1, n_samples, 2 or 3), channels PV, OP, SP), or read files with " \
           "sktiction.datasets.read_loop_file." in message  # fmt: skip


def test_a_table_without_pv_or_op_columns_is_records():
    df = pd.DataFrame(np.ones((3, 30)), columns=[f"t{i}" for i in range(30)])
    assert check_loops(df).shape == (3, 30, 3)


# ---------------------------------------------------------------- validate_loops


class _Records(BaseEstimator):
    pass


def test_validate_loops_records_features_for_records_and_forgets_them_for_loops():
    est = _Records()
    df = pd.DataFrame(np.ones((3, 25)), columns=[f"t{i}" for i in range(25)])
    df.iloc[0, 3] = np.nan  # NaN is allowed in a record
    out = validate_loops(est, df, reset=True)
    assert out.shape == (3, 25, 3) and np.isnan(out[0, 3, 0])
    assert est.n_features_in_ == 25 and list(est.feature_names_in_) == list(df.columns)
    validate_loops(est, np.ones((2, 40, 3)), reset=True)
    assert not hasattr(est, "n_features_in_") and not hasattr(est, "feature_names_in_")


# ---------------------------------------------------------------- loop_lengths, loop_status


def test_loop_lengths_of_padded_and_empty_loops():
    X = np.ones((3, 6, 3))
    X[1, 4:, 0] = np.nan  # padded: 4
    X[2, :, 0] = np.nan  # no PV at all: 0
    X[0, 2, 0] = np.nan  # a hole is not the end: 6
    assert loop_lengths(X).tolist() == [6, 4, 0]
    assert loop_lengths(X).dtype.kind == "i"


def _pi_loop(n=1000, seed=0):
    """A flow loop under PI control (the example of ``looks_swapped``)."""
    rng = np.random.default_rng(seed)
    pv, op, sp = np.full(n, 120.0), np.full(n, 35.0), np.full(n, 120.0)
    load = np.cumsum(rng.normal(0, 0.05, n))
    for t in range(1, n):
        pv[t] = 120 + load[t] + 0.5 * (op[t - 1] - 35) + rng.normal(0, 0.2)
        e, e1 = sp[t] - pv[t], sp[t - 1] - pv[t - 1]
        op[t] = op[t - 1] + 0.8 * (e - e1) + 0.1 * e
    return pv, op, sp


def test_loop_status_of_each_kind():
    t = np.arange(60.0)
    wave = np.sin(t / 3)
    X = np.full((8, 60, 3), np.nan)
    X[0, :, 0] = wave  # ok: no OP needed by default
    X[1, :20, 0] = wave[:20]  # exactly min_samples: ok
    X[2, :19, 0] = wave[:19]  # one fewer: too short
    X[3, :, 0] = 2.0  # constant PV
    X[4, :, 0], X[4, :, 1] = wave, 1.0  # constant OP: only when OP is required
    X[5, :, 0], X[5, :, 1] = wave, wave
    X[5, 30, 1] = np.nan  # a hole in OP
    X[6, :, 0], X[6, :, 2] = wave, 0.0  # SP present and whole
    # X[7] has no PV: empty
    assert loop_status(X).tolist() == [
        "ok",
        "ok",
        "too_short",
        "constant",
        "ok",
        "nan_gap",
        "ok",
        "empty",
    ]
    assert loop_status(X, require_op=True).tolist() == [
        "missing_op", "missing_op", "too_short", "missing_op", "constant", "nan_gap",
        "missing_op", "empty"]  # fmt: skip
    assert loop_status(X, min_samples=21).tolist()[1] == "too_short"


def test_loop_status_sees_a_swap_only_when_asked():
    pv, op, sp = _pi_loop()
    right = np.stack([pv, op, sp], axis=1)[None]
    swapped = np.stack([op, pv, sp], axis=1)[None]
    assert loop_status(swapped).tolist() == ["ok"]  # check_swap defaults to False
    assert loop_status(swapped, check_swap=True).tolist() == ["pv_op_swapped"]
    assert loop_status(right, check_swap=True).tolist() == ["ok"]


# ---------------------------------------------------------------- gaps


def _reference_limit(pv):
    """The documented bridge limit, by direct sums: least-squares line, linear (not
    circular) autocorrelation of the residual with the missing samples as 0, first lag
    at or below 0 taken as a quarter period, 1/16 period as a chord of gap + 1 intervals."""
    n = len(pv)
    ok = ~np.isnan(pv)
    if ok.sum() < 4:
        return 1
    k = np.arange(n, dtype=float)
    A = np.column_stack([k[ok], np.ones(ok.sum())])
    slope, icpt = np.linalg.lstsq(A, pv[ok], rcond=None)[0]
    x = np.where(ok, pv - (slope * k + icpt), 0.0)
    r = np.correlate(x, x, "full")[n - 1 :]
    if r[0] <= 0:
        return 1
    quarter = int(np.flatnonzero(r <= 0)[0])
    return max(1, min(quarter // 4 - 1, int(0.05 * n)))


def test_bridge_limit_is_the_documented_sixteenth_of_a_period():
    k = np.arange(3000.0)
    signals = {
        "sine 100": np.sin(2 * np.pi * k / 100),
        "sine 150 tiny": 1e-6 * np.sin(2 * np.pi * k / 150) + 3.0,
        "sine 90 plus ramp": np.sin(2 * np.pi * k / 90) + k / 50,
        "sine 200 plus parabola": np.sin(2 * np.pi * k / 200) + (k / 3000) ** 2,
    }
    for name, pv in signals.items():
        assert _bridge_limit(pv) == _reference_limit(pv), name
    # 2.2 periods in the record: the autocorrelation is linear, not circular (an FFT of
    # the record's own length would wrap the end onto the start and read 18)
    short = np.sin(2 * np.pi * np.arange(640) / 290)
    assert _bridge_limit(short) == _reference_limit(short) == 16
    # hand-checked: a quarter period of 25, 37.5 and 22.5 samples
    assert _bridge_limit(signals["sine 100"]) == 25 // 4 - 1
    assert _bridge_limit(signals["sine 150 tiny"]) == 38 // 4 - 1  # units do not matter
    # a parabola after its straight line: the residual u^2 - u + 1/6 (u = k / n) has its
    # autocorrelation's first zero at u = 0.221 (by quadrature), a quarter period of
    # 0.221 n, so the bridge 0.221 n / 4 - 1 > 0.05 n: the 5 % cap
    for n in (400, 1000):
        assert _bridge_limit((np.arange(n) / n) ** 2) == int(0.05 * n)


def test_bridge_limit_leaves_missing_samples_out():
    k = np.arange(2000.0)
    pv = 100.0 + 1e-3 * np.sin(2 * np.pi * k / 120)
    pv[[100, 500, 501, 1300]] = np.nan
    pv[1500:1700] = np.nan  # a long hole adds nothing to the autocorrelation
    assert _bridge_limit(pv) == _reference_limit(pv) == 30 // 4 - 1
    # three samples: too few to read a period, single-sample bridges
    few = np.full(200, np.nan)
    few[[0, 100, 199]] = [1.0, 5.0, 2.0]
    assert _bridge_limit(few) == 1
    _, info = repair_gaps(few[None])
    assert info.loc[0, "max_gap"] == 1


def test_max_gap_zero_bridges_nothing():
    check_max_gap(0)  # allowed: no bridge
    k = np.arange(200.0)
    X = np.sin(2 * np.pi * k / 100)[None].copy()
    X[0, 120] = np.nan  # one sample: "auto" would bridge it
    Xr, info = repair_gaps(X, max_gap=0)
    row = info.iloc[0]
    assert (row["n_bridged"], row["n_gaps_split"], row["max_gap"]) == (0, 1, 0)
    assert (row["kept_start"], row["kept_stop"]) == (0, 120)
    _, auto = repair_gaps(X)
    assert (auto.loc[0, "n_bridged"], auto.loc[0, "n_gaps_split"]) == (1, 0)


def test_min_length_one_and_the_default_of_twenty():
    X = np.full((1, 60), np.nan)
    X[0, :20] = np.arange(20.0)
    _, info = repair_gaps(X)
    assert info.loc[0, "usable"]  # 20 samples: usable by default
    _, info = repair_gaps(X, min_length=21)
    assert not info.loc[0, "usable"]
    _, info = repair_gaps(X[:, :5], min_length=1)
    assert info.loc[0, "usable"]


def test_missing_samples_at_the_start_are_cut_however_long():
    X = np.tile(np.arange(100.0), (1, 1))
    X[0, :10] = np.nan  # longer than max_gap, but at the start: cut, not split
    Xr, info = repair_gaps(X, max_gap=3)
    row = info.iloc[0]
    assert (row["n_gaps_split"], row["kept_start"], row["kept_stop"]) == (0, 10, 100)
    np.testing.assert_array_equal(Xr[0, :90, 0], np.arange(10.0, 100.0))
    # a long gap that starts at the second sample is inside the record: a split
    Y = np.tile(np.arange(100.0), (1, 1))
    Y[0, 1:8] = np.nan
    row = repair_gaps(Y, max_gap=3)[1].iloc[0]
    assert (row["n_gaps_split"], row["kept_start"], row["kept_stop"]) == (1, 8, 100)


def _record(stretches, gap=10, lead=0):
    """PV 0, 1, 2, ... with ``lead`` missing samples first and a long gap between
    stretches of the given lengths."""
    n = lead + sum(stretches) + gap * (len(stretches) - 1)
    pv = np.arange(float(n))
    pv[:lead] = np.nan
    at = lead
    for s in stretches[:-1]:
        at += s
        pv[at : at + gap] = np.nan
        at += gap
    return pv[None]


@pytest.mark.parametrize(
    ("stretches", "lead", "start", "stop"),
    [
        ([20, 21], 0, 30, 51),  # the longer second
        ([20, 20], 0, 0, 20),  # ties: the first
        ([21, 20], 0, 0, 21),
        ([20, 25, 27], 0, 65, 92),  # the third, longest
        ([30, 25, 27], 0, 0, 30),  # the first, longest
        ([20, 22], 5, 35, 57),  # missing samples before the first do not count
        ([22, 20], 5, 5, 27),  # ... nor move it
    ],
)
def test_the_longest_stretch_is_kept(stretches, lead, start, stop):
    X = _record(stretches, lead=lead)
    Xr, info = repair_gaps(X, max_gap=3)
    row = info.iloc[0]
    assert (row["kept_start"], row["kept_stop"]) == (start, stop)
    assert row["n_gaps_split"] == len(stretches) - 1
    np.testing.assert_array_equal(Xr[0, : stop - start, 0], np.arange(start, stop, dtype=float))
    assert np.isnan(Xr[0, stop - start :]).all()


def test_a_loop_without_pv_gives_an_empty_stretch():
    X = np.ones((2, 30, 3))
    X[1] = np.nan
    Xr, info = repair_gaps(X)
    assert info[["kept_start", "kept_stop"]].to_numpy().tolist() == [[0, 30], [0, 0]]
    assert info["usable"].tolist() == [True, False]
    assert np.isnan(Xr[1]).all()


def test_what_a_make_or_read_function_returns_is_refused_with_what_to_pass():
    from sklearn.utils import Bunch

    from sktiction import OscillationFeatures

    X = np.zeros((2, 60, 3))
    for wrapped, says in (((X, np.zeros(2)), r"make_loops returns \(X, y\)"),
                          ((X, np.zeros(2), pd.DataFrame()), "tuple of 3 items"),
                          ([X, np.zeros(2)], "list of 2 items"),
                          (Bunch(X=X, meta=pd.DataFrame()), r"pass its loops, X\.X")):  # fmt: skip
        with pytest.raises(TypeError, match=says):
            check_loops(wrapped)
        with pytest.raises(TypeError, match=says):
            OscillationFeatures().fit(wrapped)
    # a tuple that is the loops themselves (nested sequences) is read as before
    assert check_loops(tuple(tuple(tuple(r) for r in loop) for loop in X)).shape == (2, 60, 3)
