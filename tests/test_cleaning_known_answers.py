"""Known answers of the historian repairs (sktiction._cleaning), worked out from the rules'
definitions on records built so that every threshold is a round number: the survivors of
a full mutation run of _cleaning.py (benchmarks/mutation.py, 885 of 1034 killed before).

Most spike records are a 0/1 flicker: every step is 1, so the steps' robust scale is 1,
the limit 6 x 1.4826 = 8.8956 (the 5-95 % spread, 1, gives only 0.6), and a sample is
"beyond the limit" or not by construction."""

import numpy as np
import pytest

from sktiction import clean_loops
from sktiction._cleaning import (
    GAP_COLUMNS,
    _controller_r2,
    as_judged,
    hold_step,
    in_step,
    looks_swapped,
    op_shift,
    repaired,
    startup_rows,
)
from sktiction.cycles._repairs import _spike_limit, placeholder_mask, spike_mask

L = 6.0 * 1.4826  # the spike limit of a record whose steps are all 1


def _flicker(n=1000):
    return (np.arange(n) % 2).astype(float)


def _col(name):
    return GAP_COLUMNS.index(name)


# --- the spike limit ------------------------------------------------------------------


def test_spike_limit_known_values():
    # nine samples (eight steps, the fewest read): |steps| 1,1,1,19,19,1,1,1, median 1;
    # 5-95 % of the samples -20 * 0 ... is 0 to 12.4, 0.6 of it 7.44 < 8.8956
    x = np.array([0, 1, 0, 1, 20, 1, 0, 1, 0], dtype=float)
    assert _spike_limit(x, np.diff(x)) == pytest.approx(L)
    assert np.flatnonzero(spike_mask(x)).tolist() == [4]
    assert _spike_limit(x[:8], np.diff(x[:8])) == np.inf  # seven steps: not read
    # steps alternately 1 and 3 in size (every step counts on a short record): 500 of 1,
    # 498 of 3, one of 40 and one of 37 (four rows 37 up): median 2
    d = np.tile([1.0, 3.0, -1.0, -3.0], 250)
    d[501], d[505] = 40.0, -37.0
    x = np.concatenate([[0.0], np.cumsum(d)])
    assert _spike_limit(x, d) == pytest.approx(2 * L)
    # a held record (most steps 0) is scaled by its typical change: three changes of
    # 0.5, 0.5 and 10 (median 0.5, limit 4.45) and the 5-95 % spread, 0 to 11: 6.6
    x = np.zeros(100)
    x[30:] += 0.5
    x[60:] += 0.5
    x[80:] += 10.0
    assert _spike_limit(x, np.diff(x)) == pytest.approx(6.6)
    # two changes only: nothing to scale by
    assert _spike_limit(x[:79], np.diff(x[:79])) == np.inf
    # a step of exactly the limit is not beyond it
    d = np.r_[np.ones(50), L, np.ones(49)] * np.tile([1, -1], 50)
    assert _spike_limit(np.cumsum(d), d) == np.inf


def test_a_spike_on_a_held_record_with_small_changes_is_found():
    """Changes of 0.5 on a record held most rows (median step 0): the limit is six robust
    sds of the changes (4.45), and a lone 10 is a spike."""
    x = np.repeat(np.tile([0.0, 0.5], 20), 10)  # 40 levels of 10 rows: 39 changes of 0.5
    x[105] = 10.0
    assert np.flatnonzero(spike_mask(x)).tolist() == [105]


# --- spikes ---------------------------------------------------------------------------


@pytest.mark.parametrize("sign", [1, -1])
def test_bad_first_rows_are_spikes_above_and_below(sign):
    for width in (1, 2, 3):
        x = _flicker()
        x[:width] = sign * 5 * L
        assert np.flatnonzero(spike_mask(x)).tolist() == list(range(width))
        x = _flicker()
        x[-width:] = sign * 5 * L
        assert np.flatnonzero(spike_mask(x)).tolist() == list(range(1000 - width, 1000))


def test_three_bad_last_rows_of_a_nine_row_record():
    """Nine rows (the fewest with a limit): a jump of -21 into the last three, the only
    jump beyond the limit (0.6 x 21 = 12.6 here, the spread term), makes them a spike."""
    x = np.array([0, 1, 0, 1, 0, 1, -20, -20, -20], dtype=float)
    assert _spike_limit(x, np.diff(x)) == pytest.approx(12.6)
    assert np.flatnonzero(spike_mask(x)).tolist() == [6, 7, 8]


def test_a_slip_that_overshoots_by_more_than_a_limit_is_not_a_spike():
    """Up 2 limits, back 1.2 (both jumps beyond the limit), staying 0.8 limits higher:
    the value after is not within half a limit of the value before."""
    x = _flicker()
    x[500] = 2 * L
    x[501:] += 0.8 * L
    assert not spike_mask(x).any()
    x = _flicker()  # up 3, back 2, a limit higher: not a spike either
    x[500] = 3 * L
    x[501:] += L
    assert not spike_mask(x).any()


def test_a_downward_spike_of_a_few_limits_far_from_zero():
    x = 100.0 + _flicker()
    x[500] = 100.0 - 3 * L
    assert np.flatnonzero(spike_mask(x)).tolist() == [500]
    x[500] = 100.0 + 3 * L
    assert np.flatnonzero(spike_mask(x)).tolist() == [500]


@pytest.mark.parametrize("order", [1, -1])
def test_each_sample_of_a_spike_must_be_a_limit_from_its_neighbours_mean(order):
    """0, 3L, 0.7L, -0.4L: every jump beyond the limit and -0.4L within half a limit of 0,
    but 0.7L is 0.9L from the neighbours' mean -0.2L: no spike, in either direction."""
    x = _flicker()
    x[500:504] = [0.0, 3 * L, 0.7 * L, -0.4 * L][::order]
    assert not spike_mask(x).any()
    x[500:504] = [0.0, 3 * L, 2 * L, -0.4 * L][::order]  # both samples beyond: a spike
    assert np.flatnonzero(spike_mask(x)).tolist() == [501, 502]


def test_a_spike_is_alone_within_four_steps_either_side():
    """Two one-sample spikes 6 rows apart are both alone (rows r-5 .. r+4 of steps hold no
    other large jump); 5 rows apart, neither is."""
    x = _flicker()
    x[[300, 306]] = 5 * L
    assert np.flatnonzero(spike_mask(x)).tolist() == [300, 306]
    x = _flicker()
    x[[300, 305]] = 5 * L
    assert not spike_mask(x).any()
    x = _flicker()  # a bad first row and a spike in row 3: neither is alone
    x[[0, 3]] = 5 * L
    assert not spike_mask(x).any()


# --- placeholders ---------------------------------------------------------------------


def test_placeholders_are_found_beside_gaps():
    x = 50 + np.sin(np.arange(1000) / 10.0)
    x[100:105] = np.nan  # "Bad" as text
    x[500:520] = -9999.0  # and as a number
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(500, 520))


def test_four_values_are_enough_to_tell_a_code():
    assert placeholder_mask([50.0, 50.1, 50.2, -9999.0]).tolist() == [False] * 3 + [True]
    assert not placeholder_mask([50.0, 50.1, -9999.0]).any()


def test_a_code_more_than_ten_times_the_level_away():
    """A signal at 50-51 (level 50.5): a code 750 below it is more than ten times the
    level away, one 400 below is not."""
    x = 50 + (np.arange(1000) % 11) / 10.0
    x[300:320] = -700.0
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(300, 320))
    x[300:320] = -350.0
    assert not placeholder_mask(x).any()


def test_a_code_exactly_ten_ranges_away_is_not_beyond():
    """Values 0, 1, 2 (range 2, median 1): apart means more than 20 from them."""
    base = np.tile([0.0, 1.0, 2.0], 100)
    for code, found in ((-20.0, False), (-20.5, True), (22.0, False), (22.5, True),
                        (21.0, False)):  # fmt: skip
        x = base.copy()
        x[100:110] = code
        assert placeholder_mask(x).any() == found, code


def test_the_level_is_the_median_of_the_others():
    """20 codes at -95, then 220 samples at 10, one at 10.5, 279 at 11: the others'
    median sample is 11 (level 11, apart 110), so -95, 105 below 10, is no code; -105 is."""
    x = np.r_[np.full(20, -95.0), np.full(220, 10.0), 10.5, np.full(279, 11.0)]
    assert not placeholder_mask(x).any()
    x[:20] = -105.0
    assert placeholder_mask(x).sum() == 20
    # the median sample the first of a value's block: that value is the level
    y = np.r_[np.full(10, -2000.0), np.full(100, 10.0), np.full(100, 200.0), 205.0]
    # others: 201 samples, the median (index 100) the first 200: apart 10 x 200 = 2000,
    # -2000 lies 2010 below 10: a code; a level read at 10 would be apart 1950 too
    assert placeholder_mask(y).sum() == 10
    y[:10] = -1980.0  # 1990 below: within 2000, not a code
    assert not placeholder_mask(y).any()


def test_the_others_range_reaches_their_highest_value():
    """0, 0.5, 1 and one sample at 2: range 2, apart 20; a code at 21 (19 above 2) is no
    code, one at 23 is."""
    x = np.r_[np.tile([0.0, 0.5, 1.0], 100), 2.0, np.full(20, 21.0)]
    assert not placeholder_mask(x).any()
    x[-20:] = 23.0
    assert placeholder_mask(x).sum() == 20


def test_an_outage_of_exactly_the_largest_share_at_the_top():
    """45 % of the rows at +9999 (900 of 2000): the budget, read as placeholders."""
    x = 50 + np.sin(np.arange(2000) / 10.0)
    x[1100:] = 9999.0
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(1100, 2000))
    x[1099] = 9999.0  # 901: over the budget
    assert not placeholder_mask(x).any()
    # on 42 rows the budget is 18.9 rows: the last 18 at +9999 are read, the early exit
    # must take the others' range from data rows only
    x = 50 + np.sin(np.arange(42) / 3.0)
    x[24:] = 9999.0
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(24, 42))


def test_codes_at_both_ends_must_fit_the_budget_together():
    """-9999 on 30 % and +9999 on 30 %: each alone within 45 %, together the record's
    majority: nothing is read as a placeholder."""
    x = 50 + np.sin(np.arange(2000) / 10.0)
    x[:600], x[-600:] = -9999.0, 9999.0
    assert not placeholder_mask(x).any()


def test_at_most_two_code_values_at_one_end_and_three_other_values():
    x = 50 + np.sin(np.arange(1000) / 10.0)
    x[100:110], x[200:210] = -9999.0, -99999.0
    assert placeholder_mask(x).sum() == 20  # two codes
    x[300:310] = -999999.0
    assert not placeholder_mask(x).any()  # three distinct values are not codes
    x = 50 + np.sin(np.arange(1000) / 10.0)  # the same at the top
    x[100:110], x[200:210], x[300:310] = 9999.0, 99999.0, 999999.0
    assert not placeholder_mask(x).any()
    x[300:310] = 50.0
    assert placeholder_mask(x).sum() == 20
    # three other values (setpoint-like levels) and a code: found; two: not
    levels = np.repeat([50.0, 50.5, 51.0], 100)
    for code in (-9999.0, 9999.0):
        y = np.r_[levels, np.full(10, code)]
        assert placeholder_mask(y).sum() == 10
        y = np.r_[levels[:200], np.full(10, code)]
        assert not placeholder_mask(y).any()


# --- holds ----------------------------------------------------------------------------


def _held(values, k, channels=2):
    x = np.repeat(np.asarray(values, dtype=float), k)
    return np.column_stack([x] * channels + [np.full(x.size, np.nan)])


def test_hold_grid_bounds():
    # 21 values on 3 rows each: 20 changes, the fewest believed; 20 values: 19, not
    assert hold_step(_held(np.arange(21) ** 1.5, 3), 63) == (3, 0)
    assert hold_step(_held(np.arange(20) ** 1.5, 3), 60) == (1, 0)
    # 2 to 60 rows per value, not 61
    assert hold_step(_held(np.arange(30) ** 1.5, 2), 60) == (2, 0)
    assert hold_step(_held(np.arange(21) ** 1.5, 60), 1260) == (60, 0)
    assert hold_step(_held(np.arange(21) ** 1.5, 61), 1281) == (1, 0)


def test_a_hold_needs_98_percent_of_the_changes_on_its_phase():
    """50 values on 3 rows (49 changes on phase 0) and one change inside a block: 49 of
    50, exactly 98 %: a hold."""
    loop = _held(np.arange(50) ** 1.5, 3)
    loop[61:63, :2] = 1000.0  # row 60's value changes at row 61: one change off the grid
    assert hold_step(loop, 150) == (3, 0)
    loop[31:33, :2] = 2000.0  # two off the grid: 49 of 51
    assert hold_step(loop, 150) == (1, 0)


def test_no_grid_is_one_row_per_value_at_phase_zero():
    rng = np.random.default_rng(2)
    x = np.cumsum(rng.normal(size=300))
    keep = rng.random(300) < 0.4  # values repeated at random: no grid
    idx = np.flatnonzero(keep)
    x = x[idx[np.clip(np.searchsorted(idx, np.arange(300), side="right") - 1, 0, None)]]
    loop = np.column_stack([x, x * 2, np.full(300, np.nan)])
    assert hold_step(loop, 300) == (1, 0)
    # a two-level PV on a grid beside an OP that moves every row: not read as a grid
    pv = np.repeat(np.tile([0.0, 1.0], 50), 3)
    loop = np.column_stack([pv, rng.normal(size=300), np.full(300, np.nan)])
    assert hold_step(loop, 300) == (1, 0)


@pytest.mark.parametrize("k", [2, 3])
def test_a_channel_alone_on_a_grid_needs_eight_values_also_on_two_rows(k):
    rng = np.random.default_rng(0)
    n = 120 * k
    op = np.repeat(np.arange(120) % 7, k).astype(float)  # seven values
    loop = np.column_stack([rng.normal(size=n), op, np.full(n, np.nan)])
    assert hold_step(loop, n) == (1, 0)
    op = np.repeat(np.arange(120) % 8, k).astype(float)  # eight values
    loop[:, 1] = op
    assert hold_step(loop, n) == (k, 0)


def test_padding_is_no_level_of_a_channel_on_a_grid():
    """In a batch the shorter loop is NaN-padded: the padding is not an eighth value of
    an OP with seven on a grid."""
    rng = np.random.default_rng(0)
    X = np.full((1, 900, 3), np.nan)
    X[0, :600, 0] = rng.normal(size=600)
    X[0, :600, 1] = np.repeat(np.arange(200) % 7, 3)
    fixed, gaps = repaired(X, "auto")
    assert gaps[0, _col("rows_per_value")] == 1
    np.testing.assert_array_equal(fixed[0, :600, :2], X[0, :600, :2])


def test_a_two_fold_hold_is_read_one_row_in_two():
    rng = np.random.default_rng(1)
    stored = np.column_stack([rng.normal(size=300), rng.normal(size=300), np.zeros(300)])
    X = np.repeat(stored, 2, axis=0)[None]
    fixed, gaps = repaired(X, "auto")
    assert gaps[0, _col("rows_per_value")] == 2
    np.testing.assert_array_equal(fixed[0, :300], stored)
    assert np.isnan(fixed[0, 300:]).all()


def test_a_held_record_cut_inside_a_block_is_kept_whole():
    """Each value on 3 rows, the first block cut to one row (phase 1): the rows read stand
    for their blocks and the row before the first whole block for itself; the whole
    input is kept (kept_start 0, not the phase)."""
    rng = np.random.default_rng(3)
    stored = np.column_stack([rng.normal(size=200), rng.normal(size=200), np.zeros(200)])
    X = np.repeat(stored, 3, axis=0)[2:][None]  # 598 rows
    fixed, gaps = repaired(X, "auto")
    assert (gaps[0, _col("rows_per_value")], gaps[0, _col("kept_start")],
            gaps[0, _col("kept_stop")]) == (3, 0, 598)  # fmt: skip
    np.testing.assert_array_equal(fixed[0, :199], stored[1:])


def test_a_stretch_kept_from_the_second_row_starts_there():
    """max_gap=0: a missing first row splits the record; the stretch kept starts at row 1."""
    rng = np.random.default_rng(4)
    X = rng.normal(size=(1, 200, 3))
    X[0, 0, :] = np.nan
    X[0, 0, 0] = 1.0  # PV present, OP and SP missing in row 0
    fixed, gaps = repaired(X, 0)
    assert (gaps[0, _col("kept_start")], gaps[0, _col("kept_stop")]) == (1, 200)
    np.testing.assert_array_equal(fixed[0, :199], X[0, 1:])


def test_an_empty_loop_in_a_batch_keeps_nothing():
    X = np.full((2, 100, 3), np.nan)
    X[0] = np.random.default_rng(5).normal(size=(100, 3))
    gaps = repaired(X, "auto")[1]
    assert gaps[1, _col("kept_start")] == 0 and gaps[1, _col("kept_stop")] == 0
    assert gaps[0, _col("kept_stop")] == 100


# --- the controller fit, OP alignment, swaps ------------------------------------------


def _pure_i(n, seed=0):
    """PV = -e, SP = 0, OP += 0.5 e: OP's increments are exactly an I controller's."""
    e = np.random.default_rng(seed).normal(size=n)
    return -e, np.cumsum(0.5 * e), np.zeros(n)


def test_controller_fit_from_thirty_increments_and_a_constant_error():
    pv, op, sp = _pure_i(31)
    assert _controller_r2(pv, op, sp, True) == pytest.approx(1.0)
    assert np.isnan(_controller_r2(pv[:30], op[:30], sp[:30], True))  # 29 increments
    # without a setpoint the error is PV about its mean: the same fit here
    assert _controller_r2(pv, op, np.full(31, np.nan), False) == pytest.approx(1.0)
    # an error that never moves explains nothing (a singular fit): 0
    moving = np.cumsum(np.random.default_rng(1).normal(size=100))
    assert _controller_r2(np.full(100, 3.0), moving, np.full(100, 3.0), True) == 0.0


def _pi(n, seed=0):
    """PV = -e, SP = 0, OP += 0.8 (e - e_before) + 0.1 e: a PI controller's increments,
    which OP one row late no longer fits (it needs the error two rows back)."""
    e = np.random.default_rng(seed).normal(size=n)
    return -e, np.cumsum(0.8 * np.diff(e, prepend=0.0) + 0.1 * e), np.zeros(n)


def _early(pv, op, sp):
    """OP written one row early: row t holds OP[t + 1]."""
    return np.column_stack([pv[:-1], op[1:], sp[:-1]])


def test_op_shift_from_sixty_rows_with_and_without_a_setpoint():
    loop = _early(*_pure_i(61))
    assert op_shift(loop, 60) == -1
    assert op_shift(loop, 59) == 0  # too short to judge
    no_sp = loop.copy()
    no_sp[:, 2] = np.nan  # no setpoint: the error is PV about its mean
    assert op_shift(no_sp, 60) == -1
    flat = loop.copy()
    flat[:, 1] = 30.0  # OP never moves: nothing to fit, nothing moved
    assert op_shift(flat, 60) == 0


def test_in_step_aligns_by_default_and_as_judged_aligns():
    loop = _early(*_pure_i(501))
    X = loop[None]
    assert in_step(X)[2].tolist() == [-1]
    expected = np.full_like(X, np.nan)
    expected[0, :499] = np.column_stack([loop[1:, 0], loop[:-1, 1], loop[1:, 2]])
    np.testing.assert_array_equal(in_step(X)[0], expected)
    np.testing.assert_array_equal(as_judged(X), clean_loops(X)[0])
    np.testing.assert_array_equal(as_judged(X), expected)


def test_a_start_up_transient_and_a_late_op_leave_the_loop_in_step():
    """A PI loop with OP one row late (as recorded its increments fit the controller with
    R^2 0.81 / 1.45 = 0.56, moved back 1) and PV 50 above in the first 10 rows: 20 rows
    dropped, OP moved by one; what is left is the loop's own rows 21 .. n-2, PV and OP
    on every row."""
    n = 1000
    pv, op, sp = _pi(n, seed=5)
    loop = np.column_stack([pv[1:], op[:-1], sp[:-1]])  # row t: PV[t + 1], OP[t]
    loop[:10, 0] += 50.0
    cleaned, report = clean_loops(loop[None])
    assert report.loc[0, ["startup_rows", "op_shift"]].tolist() == [20, 1]
    assert report.loc[0, ["n_spikes", "n_placeholders", "rows_per_value"]].tolist() == [0, 0, 1]
    expected = np.column_stack([pv[21 : n - 1], op[21 : n - 1], sp[21 : n - 1]])
    np.testing.assert_array_equal(cleaned[0, : n - 22], expected)
    assert np.isnan(cleaned[0, n - 22 :]).all()


def _swapped_example():
    """The looks_swapped docstring's loop (a flow at 120 m3/h, valve 35 % open)."""
    rng = np.random.default_rng(0)
    pv, op, sp = np.full(1000, 120.0), np.full(1000, 35.0), np.full(1000, 120.0)
    load = np.cumsum(rng.normal(0, 0.05, 1000))
    for t in range(1, 1000):
        pv[t] = 120 + load[t] + 0.5 * (op[t - 1] - 35) + rng.normal(0, 0.2)
        e, e1 = sp[t] - pv[t], sp[t - 1] - pv[t - 1]
        op[t] = op[t - 1] + 0.8 * (e - e1) + 0.1 * e
    return pv, op, sp


@pytest.mark.parametrize("scale", [0.01, 1.0, 100.0])
def test_a_swap_is_read_the_same_in_any_unit(scale):
    pv, op, sp = (scale * v for v in _swapped_example())
    assert looks_swapped(op, pv, sp) and not looks_swapped(pv, op, sp)


def test_a_loop_at_its_setpoint_is_no_swap_wherever_op_sits():
    """PV at the setpoint: not swapped, even with OP moved to the setpoint's value."""
    pv, op, sp = _swapped_example()
    rng = np.random.default_rng(1)
    op = op - np.median(op) + 120.0 + rng.normal(0, 0.5, op.size)  # OP near SP, noisy
    assert not looks_swapped(pv, op, sp)


def test_no_swap_when_op_is_not_at_the_setpoint():
    """The same swapped record with the setpoint 30 higher: the channel recorded as OP
    no longer sits at it, however well the increments fit the other way round."""
    pv, op, sp = _swapped_example()
    assert not looks_swapped(op, pv, sp + 30.0)


# --- start-up transients --------------------------------------------------------------


def _rest(n=2000):
    """PV alternating 0 and 1 (0.5-99.5 % range exactly [0, 1]), OP constant, SP 0."""
    return np.column_stack([_flicker(n), np.full(n, 50.0), np.zeros(n)])


def test_start_up_bounds():
    # fifty rows (a head of ten) are enough; 49 are not
    loop = _rest(50)
    loop[0, 0] = 10.0
    assert startup_rows(loop, 50) == 2
    assert startup_rows(loop[:49], 49) == 0
    # an excursion beginning at 3 % of the record (row 60 of 2000) counts, at row 61 not
    loop = _rest()
    loop[60:80, 0] = 10.0
    assert startup_rows(loop, 2000) == 160
    loop = _rest()
    loop[61:81, 0] = 10.0
    assert startup_rows(loop, 2000) == 0
    # rows exactly half a range beyond are not beyond
    loop = _rest()
    loop[0, 0], loop[1:61, 0] = 10.0, 1.5
    assert startup_rows(loop, 2000) == 2


def test_a_setpoint_step_just_after_the_dropped_rows_does_not_keep_them():
    """40 rows at 3 drop 80 rows; the setpoint window is rows 0-80: a step of 1 at row 81
    is after it, at row 80 within it (a setpoint response: kept)."""
    loop = _rest()
    loop[:40, 0] = 3.0
    loop[81:, 2] = 1.0
    assert startup_rows(loop, 2000) == 80
    loop[80, 2] = 1.0
    assert startup_rows(loop, 2000) == 0


def test_a_channel_without_range_after_its_head_says_nothing():
    # OP moved in its first rows, then constant: no range to compare with
    loop = _rest()
    loop[:5, 1] = 80.0
    assert startup_rows(loop, 2000) == 0
    # PV constant after its head: OP's transient is still read
    loop = _rest()
    loop[:, 0] = 7.0
    loop[:, 1] = 50.0 + _flicker(2000)
    loop[:20, 1] = 60.0
    assert startup_rows(loop, 2000) == 40


def test_a_high_code_on_the_last_40_percent_of_a_flow_is_read_as_a_placeholder():
    """A flow of 750-1000 kg/h (median 875) whose transmitter wrote +9999 for the last 40 %
    of the export: the code lies 8,999 above the others, more than ten times their level
    (8,750) and range (2,500): placeholders by the rule. (The O(n) early exit took the
    level from the 45th percentile of all the rows, 963 here, the data's 75th: 9,630 >
    9,249, the whole span, and read the code as data.)"""
    t = np.arange(2000)
    x = 875 + 125 * np.sin(t / 20.0)
    x[1200:] = 9999.0
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(1200, 2000))
    # the same code on 875-1000 kg/h (median 937.5, apart 9,375 > 8,999): data
    x[:1200] = 937.5 + 62.5 * np.sin(t[:1200] / 20.0)
    assert not placeholder_mask(x).any()


def test_the_early_exit_never_hides_codes_the_rule_reads():
    """Records where the O(n) early exit must not decide: the rule (codes more than ten
    times the others' range and median level away) reads every code here."""
    # the flow above, negative (a vacuum of -750 to -1000 mbar), -9999 on the last 40 %:
    # 8,999 below the others, median level 875
    t = np.arange(2000)
    x = -(875 + 125 * np.sin(t / 20.0))
    x[1200:] = -9999.0
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(1200, 2000))
    # 40 % at -900 beside two levels, 95 (301 rows) and 105 (298 rows), and one 100: the
    # others' median is 95, so apart is 950 and -900 lies 995 below them; a level read
    # from the upper rows (105) would put apart at 1,050, above the whole span
    x = np.r_[np.full(400, -900.0), np.full(301, 95.0), 100.0, np.full(298, 105.0)]
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(400))
    # 10 of 26 rows at +9999 beside a signal of 50 +- 1: plainly codes
    x = 50 + np.sin(np.arange(26) / 3.0)
    x[16:] = 9999.0
    assert np.flatnonzero(placeholder_mask(x)).tolist() == list(range(16, 26))
