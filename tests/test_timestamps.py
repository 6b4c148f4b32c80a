"""Time columns: units told apart by range, text formats, and the regular grid."""

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets._timestamps import (
    TimeError,
    _numeric_unit,
    count,
    parse_times,
    regularise,
)

# 2024-10-17 21:55:00 UTC in each unit, and as an Excel serial day (1900 system)
EPOCH_S = pd.Timestamp("2024-10-17 21:55:00").value / 1e9
EXCEL = (pd.Timestamp("2024-10-17 21:55:00") - pd.Timestamp("1899-12-30")) / pd.Timedelta("1D")


def test_count():
    assert [count(n, "row") for n in (0, 1, 2)] == ["0 rows", "1 row", "2 rows"]


@pytest.mark.parametrize(
    ("scale", "unit"), [(1, "epoch_s"), (1e3, "epoch_ms"), (1e6, "epoch_us"), (1e9, "epoch_ns")]
)
def test_epoch_units_by_range(scale, unit):
    v = (EPOCH_S + np.array([0.0, 10, 20, np.nan])) * scale
    assert _numeric_unit(v) == unit
    t, start, notes = parse_times(pd.Series(v))
    np.testing.assert_allclose(t[:3], [0, 10, 20], atol=1e-3)
    assert np.isnan(t[3])
    assert abs(start - pd.Timestamp("2024-10-17 21:55:00")) < pd.Timedelta("1us")
    name = {"epoch_s": "seconds", "epoch_ms": "milliseconds", "epoch_us": "microseconds",
            "epoch_ns": "nanoseconds"}[unit]  # fmt: skip
    assert notes == [f"time read as epoch {name} (start 2024-10-17 21:55:00)"]


def test_epoch_range_is_1990_to_2100():
    first = pd.Timestamp("1990-01-01").value / 1e9
    last = pd.Timestamp("2100-01-01").value / 1e9
    assert _numeric_unit(np.array([first, first + 1])) == "epoch_s"
    assert _numeric_unit(np.array([last - 1, last])) == "epoch_s"
    assert _numeric_unit(np.array([first - 1, first])) == "s"  # 1989: seconds from anywhere
    assert _numeric_unit(np.array([last, last + 1])) == "s"


def test_excel_serial_days_sampled_within_a_day():
    v = EXCEL + np.arange(4) * 10 / 86400  # every 10 s
    assert _numeric_unit(v) == "excel"
    t, start, notes = parse_times(pd.Series(v))
    np.testing.assert_array_equal(t, [0.0, 10.0, 20.0, 30.0])  # rounded to the millisecond
    assert start == pd.Timestamp("2024-10-17 21:55:00")
    assert notes == ["time read as Excel serial days (start 2024-10-17 21:55:00)"]
    # daily steps, a single value, or a range outside 1990-2100: plain seconds
    assert _numeric_unit(EXCEL + np.arange(4.0)) == "s"
    assert _numeric_unit(np.array([EXCEL])) == "s"
    assert _numeric_unit(np.array([100.0, 100.5])) == "s"
    first = (pd.Timestamp("1990-01-01") - pd.Timestamp("1899-12-30")).days
    last = (pd.Timestamp("2100-01-01") - pd.Timestamp("1899-12-30")).days
    assert _numeric_unit(np.array([first, first + 0.5])) == "excel"
    assert _numeric_unit(np.array([last - 0.5, last])) == "excel"
    assert _numeric_unit(np.array([first - 0.5, first])) == "s"


def test_seconds_from_any_origin_and_a_forced_unit():
    t, start, notes = parse_times(pd.Series([5.0, 6.5, 8.0]))
    assert t.tolist() == [0.0, 1.5, 3.0] and pd.isna(start) and notes == []
    # epoch seconds read as plain seconds when the caller says so
    t, start, notes = parse_times(pd.Series([EPOCH_S, EPOCH_S + 2]), unit="s")
    assert t.tolist() == [0.0, 2.0] and pd.isna(start) and notes == []
    t, start, _ = parse_times(pd.Series([EXCEL, EXCEL + 1.0]), unit="excel")
    assert t.tolist() == [0.0, 86400.0] and start == pd.Timestamp("2024-10-17 21:55:00")


def test_numbers_as_text_and_the_odd_text_value():
    raw = pd.Series(["10", "20", "oops", "40", None], dtype=object)
    t, start, _ = parse_times(raw)
    np.testing.assert_array_equal(t, [0.0, 10.0, np.nan, 30.0, np.nan])
    assert pd.isna(start)


def test_datetimes_with_a_time_zone():
    stamps = pd.Series(pd.to_datetime(["2024-10-17 23:55:00", "2024-10-17 23:55:05"]))
    t, start, notes = parse_times(stamps.dt.tz_localize("Europe/Berlin"))
    assert t.tolist() == [0.0, 5.0] and start == pd.Timestamp("2024-10-17 21:55:00")
    assert notes == ["time zone converted to UTC"]
    t, start, notes = parse_times(stamps)  # naive: as they are
    assert start == pd.Timestamp("2024-10-17 23:55:00") and notes == []


def test_a_declared_format_is_used():
    raw = pd.Series(["17-10-2024 21h55m00", "17-10-2024 21h55m10"], dtype="str")
    t, start, _ = parse_times(raw, time_format="%d-%m-%Y %Hh%Mm%S")
    assert t.tolist() == [0.0, 10.0] and start == pd.Timestamp("2024-10-17 21:55:00")


def test_mostly_not_times_is_refused():
    good = [str(pd.Timestamp("2024-10-17 21:55:00") + pd.Timedelta(seconds=s)) for s in range(200)]
    # the first 200 values choose the format; the whole column is then mostly not times
    with pytest.raises(TimeError, match="most values are not times .first bad value: 'x'"):
        parse_times(pd.Series(good + ["x"] * 201, dtype="str"))
    t = parse_times(pd.Series(good + ["x"] * 200, dtype="str"))[0]  # half: accepted
    assert np.isnan(t[200:]).all() and t[199] == 199.0
    with pytest.raises(TimeError, match="values are not times .first: 'monday'"):
        parse_times(pd.Series(["monday"] * 3, dtype="str"))
    with pytest.raises(TimeError, match="empty"):
        parse_times(pd.Series([None, None], dtype=object))
    # a few bad values among times: the format that reads most of the sample wins
    t, start, _ = parse_times(pd.Series(good[:10] + ["x"], dtype="str"))
    assert np.isnan(t[-1]) and t[9] == 9.0 and start == pd.Timestamp("2024-10-17 21:55:00")


def test_month_first_when_the_days_say_so():
    raw = pd.Series(["10/13/2024 10:00:00", "10/14/2024 10:00:00"], dtype="str")
    t, start, notes = parse_times(raw)
    assert t.tolist() == [0.0, 86400.0] and start == pd.Timestamp("2024-10-13 10:00")
    assert notes == []


def test_times_of_day_over_two_midnights():
    # a step back of more than 12 h is a midnight; of less, a row out of order
    raw = pd.Series(["22:00:00", "09:00:00", "21:00:00", "08:00:00", None, "07:00"], dtype=object)
    t, start, notes = parse_times(raw)
    h = 3600.0
    np.testing.assert_array_equal(t, [0, 11 * h, 23 * h, 34 * h, np.nan, 33 * h])
    assert pd.isna(start) and notes == ["time of day without a date (midnight passes counted)"]


# ---- the regular grid ---------------------------------------------------------------------


def test_regular_samples_are_left_alone():
    t = np.arange(5) * 2.0 + 0.01 * np.array([0, 1, -1, 1, 0])  # within 1 % of the step
    grid, v, step, notes = regularise(t, np.arange(5.0))
    assert grid is t and v[:, 0].tolist() == list(range(5)) and step == 2.0 and notes == []


def test_one_sample_has_no_step():
    grid, v, step, notes = regularise(np.array([3.0, 3.0]), np.array([1.0, 2.0]))
    assert grid.tolist() == [3.0] and v.tolist() == [[1.0]] and step is None
    assert notes == ["1 duplicated timestamp: kept the first row of each"]


def test_unsorted_and_duplicated_rows():
    t = np.array([0.0, 20, 10, 10, 30, 30])
    v = np.array([0.0, 2, 1, 9, 3, 8])
    grid, out, step, notes = regularise(t, v)
    assert grid.tolist() == [0, 10, 20, 30] and out[:, 0].tolist() == [0, 1, 2, 3]
    assert notes == [
        "rows not in time order (1 step back): sorted",
        "2 duplicated timestamps: kept the first row of each",
    ]


def test_irregular_samples_are_interpolated_and_held():
    t = np.array([0.0, 10, 21, 30, 40])
    v = np.array([[0.0, 0], [10, 1], [21, 2], [30, 3], [40, 4]])
    grid, out, step, notes = regularise(t, v, hold=[1])
    assert grid.tolist() == [0, 10, 20, 30, 40] and step == 10.0
    np.testing.assert_allclose(out[:, 0], [0, 10, 20, 30, 40])  # linear in t
    assert out[:, 1].tolist() == [0, 1, 1, 3, 4]  # held: the sample before 20 s
    assert notes == [
        "irregular sampling: 2 intervals differ from 10 s (min 9, max 11); "
        "resampled to 5 rows at 10 s"
    ]
    # strict: reported, not resampled
    same, kept, step, notes = regularise(t, v, strict=True)
    assert same.tolist() == t.tolist() and kept.tolist() == v.tolist() and step == 10.0
    assert notes == ["irregular sampling: 2 intervals differ from 10 s (min 9, max 11)"]
    # a wider tolerance: regular
    assert regularise(t, v, tolerance=0.11)[3] == []


def test_a_sample_on_the_grid_keeps_its_value_next_to_nan():
    t = np.array([0.0, 10, 20, 31, 40])
    v = np.array([0.0, np.nan, 2, 3, 4])
    grid, out, _, _ = regularise(t, v)
    assert np.isnan(out[1, 0]) and out[0, 0] == 0.0 and out[2, 0] == 2.0
    assert out[3, 0] == pytest.approx(2 + 10 / 11)


def test_time_gaps_are_left_empty():
    t = np.array([0.0, 10, 20, 60, 70, 80, 85])
    grid, out, step, notes = regularise(t, t.copy())
    assert grid.tolist() == [0, 10, 20, 30, 40, 50, 60, 70, 80] and step == 10.0
    np.testing.assert_array_equal(np.isnan(out[:, 0]), [0, 0, 0, 1, 1, 1, 0, 0, 0])
    assert notes[0].endswith("; 1 time gap longer than 3 steps left as NaN (3 rows)")
    # a gap of three steps is bridged
    t = np.array([0.0, 10, 20, 50, 60, 70, 75])
    out = regularise(t, t.copy())[1]
    np.testing.assert_allclose(out[:, 0], [0, 10, 20, 30, 40, 50, 60, 70])
    assert not np.isnan(
        regularise(np.array([0.0, 10, 20, 60, 70, 80, 85]), t, gap_steps=4)[1]
    ).any()


def test_a_hole_far_longer_than_the_record_keeps_the_longest_stretch():
    grid, out, step, notes = regularise(np.r_[np.arange(9.0), 40.0], np.arange(10.0))
    assert grid.tolist() == list(range(9)) and out[:, 0].tolist() == list(range(9))
    assert notes[-1].endswith("41 steps of 1 s for 10 rows: kept the longest stretch between "
                              "time jumps of more than 3 steps (9 rows from 0 s)")
    grid = regularise(np.r_[np.arange(9.0), 39.0], np.zeros(10))[0]  # 40 steps: 4x, allowed
    assert len(grid) == 40
    # a day missing between two shifts of 10 s data: the longer shift, from its own start
    t = np.r_[10.0 * np.arange(300), 86400 + 10.0 * np.arange(400)]
    grid, out, step, _ = regularise(t, t.copy())
    assert step == 10.0 and grid[0] == 86400 and len(grid) == 400
    np.testing.assert_array_equal(out[:, 0], grid)


def test_a_scan_rate_that_drops_tenfold_keeps_the_fast_rows():
    t = np.r_[np.arange(900.0), 899 + 10.0 * np.arange(1, 601)]
    grid, out, step, notes = regularise(t, np.sin(t)[:, None])
    assert step == 1.0 and grid.tolist() == list(range(900))
    np.testing.assert_allclose(out[:, 0], np.sin(np.arange(900.0)))


# ---- edge cases found by mutation testing ------------------------------------------------


def test_excel_fractions_of_a_second_and_a_repeated_value():
    v = EXCEL + np.array([0.5, 0.7504, 1.0]) / 86400  # 0.2504 s rounds to 0.250
    t, start, _ = parse_times(pd.Series(v))
    np.testing.assert_array_equal(t, [0.0, 0.25, 0.5])
    assert start == pd.Timestamp("2024-10-17 21:55:00.5")
    assert _numeric_unit(np.array([EXCEL, EXCEL])) == "s"  # no step: not days


def test_text_formats_pandas_has_to_guess():
    # two layouts in one column: only the mixed parser reads both
    mixed = pd.Series(["2024-10-17 21:55:00", "17 Oct 2024 21:55:05"], dtype="str")
    assert parse_times(mixed)[0].tolist() == [0.0, 5.0]
    padded = pd.Series(["  2024-10-17 21:55:00 ", " 2024-10-17 21:55:05"], dtype="str")
    assert parse_times(padded)[0].tolist() == [0.0, 5.0]
    # a bad value in the sample: the format that reads most of it (not the first tried)
    t = parse_times(pd.Series(["17.10.2024 21:55:00", "17.10.2024 21:55:05", "x"], dtype="str"))[0]
    np.testing.assert_array_equal(t, [0.0, 5.0, np.nan])
    t = parse_times(pd.Series(["17.10.2024 21:55:00", "x"], dtype="str"))[0]  # half: enough
    np.testing.assert_array_equal(t, [0.0, np.nan])
    with pytest.raises(TimeError, match="first: 'monday'"):
        parse_times(pd.Series(["monday", "tuesday"], dtype="str"))
    with pytest.raises(TimeError, match="first bad value: 'x0'"):
        good = [str(pd.Timestamp("2024-10-17") + pd.Timedelta(seconds=s)) for s in range(200)]
        parse_times(pd.Series(good + [f"x{i}" for i in range(201)], dtype="str"))
    # half numbers, half words: not a numeric time column, and not times
    with pytest.raises(TimeError, match="values are not times"):
        parse_times(pd.Series(["10", "20", "x", "y"], dtype=object))


def test_month_first_settled_after_the_sample():
    # every 84 min from 1 January: the first 200 rows have days <= 12, day 13 comes later
    start = pd.Timestamp("2024-01-01")
    rows = [
        (start + pd.Timedelta(minutes=84 * i)).strftime("%m/%d/%Y %H:%M:%S") for i in range(250)
    ]
    t, first, notes = parse_times(pd.Series(rows, dtype="str"))
    np.testing.assert_array_equal(t, 84 * 60.0 * np.arange(250))
    assert first == start and notes == []


def test_the_declared_format_beats_a_guess():
    raw = pd.Series(["03-04-2024 10:00:00", "03-05-2024 10:00:00"], dtype="str")
    t, start, _ = parse_times(raw, time_format="%d-%m-%Y %H:%M:%S")  # 3 April, 3 May
    assert t.tolist() == [0.0, 30 * 86400.0] and start == pd.Timestamp("2024-04-03 10:00")


def test_a_step_back_of_up_to_12_hours_is_not_midnight():
    h = 3600.0
    assert parse_times(pd.Series(["22:00:00", "12:00:00"], dtype="str"))[0].tolist() == [10 * h, 0]
    assert parse_times(pd.Series(["22:00:00", "10:00:00"], dtype="str"))[0].tolist() == [12 * h, 0]


def test_grid_from_a_late_start():
    t = 1000.0 + np.array([0.0, 10, 21, 30, 40])
    grid, out, step, _ = regularise(t, t - 1000.0)
    assert grid.tolist() == [1000, 1010, 1020, 1030, 1040]
    np.testing.assert_allclose(out[:, 0], [0, 10, 20, 30, 40])
    grid, _, _, notes = regularise(100.0 + np.r_[np.arange(9.0), 40.0], np.zeros(10))
    assert grid.tolist() == list(range(100, 109)) and "the records span 40 s" in notes[-1]


def test_file_order_decides_among_many_duplicates():
    t = np.r_[np.arange(50, 0, -1), np.arange(50, 0, -1)].astype(float)
    grid, out, _, notes = regularise(t, np.arange(100.0))
    assert grid.tolist() == list(range(1, 51))
    np.testing.assert_array_equal(out[:, 0], np.arange(49, -1, -1))  # the first rows' values
    assert notes[1] == "50 duplicated timestamps: kept the first row of each"


def test_last_sample_on_the_grid_next_to_nan_and_gap_counts():
    grid, out, _, _ = regularise(np.array([0.0, 10, 21, 30]), np.array([0.0, 1, np.nan, 3]))
    assert out[-1, 0] == 3.0 and np.isnan(out[2, 0])
    # one interval of exactly 3 steps (bridged), one of 4 (a gap)
    t = np.array([0.0, 10, 20, 50, 60, 100, 110, 115])
    notes = regularise(t, t.copy())[3]
    assert notes[0].endswith("; 1 time gap longer than 3 steps left as NaN (3 rows)")


def test_numeric_columns_of_any_numpy_dtype_and_all_missing():
    # ints, floats with NaN and inf: read as numbers, as through the general branch (inf:
    # no time, like NaN)
    t, start, notes = parse_times(pd.Series([3, 5, 9]))
    assert t.tolist() == [0.0, 2.0, 6.0] and pd.isna(start) and notes == []
    t = parse_times(pd.Series([2.0, np.nan, 4.0, np.inf]))[0]
    np.testing.assert_array_equal(t, [0.0, np.nan, 2.0, np.nan])
    t = parse_times(pd.Series(["2", "", "4", "inf"]))[0]
    np.testing.assert_array_equal(t, [0.0, np.nan, 2.0, np.nan])
    with pytest.raises(TimeError, match="time column is empty"):
        parse_times(pd.Series([np.nan, np.nan]))


def test_offsets_that_change_after_the_sample_are_read_in_utc():
    """A daylight-saving change far into the file: every row read, in UTC, evenly spaced."""
    stamps = pd.date_range("2024-03-31 00:00", periods=2000, freq="10s", tz="Europe/Berlin")
    raw = pd.Series(stamps.map(lambda s: s.isoformat()))
    assert raw.iloc[0].endswith("+01:00") and raw.iloc[-1].endswith("+02:00")
    t, start, notes = parse_times(raw)
    np.testing.assert_array_equal(t, 10.0 * np.arange(2000))
    assert str(start) == "2024-03-30 23:00:00" and "time zone offsets converted to UTC" in notes


def _local(start, n, back_at, back=3600):
    """Naive local stamps every 10 s that step back ``back`` s at row ``back_at``."""
    t = 10.0 * np.arange(n) - back * (np.arange(n) >= back_at)
    return pd.Series((pd.Timestamp(start) + pd.to_timedelta(t, unit="s"))
                     .strftime("%Y-%m-%d %H:%M:%S"))  # fmt: skip


def test_local_time_set_back_an_hour_keeps_every_row_in_order():
    """Autumn's repeated hour in naive local time: later rows shifted, not sorted and cut."""
    raw = _local("2024-10-27 02:00:00", 1000, 360)  # 02:59:50, then 02:00:00 again
    t, _, notes = parse_times(raw)
    np.testing.assert_array_equal(t, 10.0 * np.arange(1000))
    assert notes == ["clock set back an hour at 2024-10-27 02:00:00 (daylight saving time "
                     "ending, local time without offset): later rows read an hour later"]


@pytest.mark.parametrize("start, back", [
    ("2024-06-15 02:00:00", 3600),  # two exports overlapping by an hour in June
    ("2024-10-27 12:00:00", 3600),  # at noon: no clock change
    ("2024-10-27 02:00:00", 1800),  # not an hour
])  # fmt: skip
def test_other_steps_back_are_sorted_as_before(start, back):
    t, _, notes = parse_times(_local(start, 1000, 360, back))
    assert np.all(np.diff(t)[:359] == 10.0) and not any("clock" in n for n in notes)
    assert (np.diff(t) < 0).sum() == 1  # left to regularise, which sorts and notes it


def test_stamps_with_and_without_offset_are_refused():
    raw = pd.Series(["2024-03-31T00:00:00", "2024-03-31T00:00:10+01:00"] * 150)
    with pytest.raises(TimeError, match="some timestamps carry a UTC offset"):
        parse_times(raw)


def test_day_first_note_only_when_the_whole_column_allows_both_orders():
    late = pd.Series(pd.date_range("2024-01-01", periods=2000, freq="10min")
                     .strftime("%d/%m/%Y %H:%M"))  # fmt: skip
    assert parse_times(late)[2] == []  # 13/01 settles it, though the sample does not
    early = pd.Series(pd.date_range("2024-01-02", periods=100, freq="10min")
                      .strftime("%d/%m/%Y %H:%M"))  # fmt: skip
    assert parse_times(early)[2] == ["dates could be day/month or month/day: read day first"]
    # 01/01: both orders give the same dates, so there is nothing to say
    same = pd.Series(pd.date_range("2024-01-01", periods=100, freq="10min")
                     .strftime("%d/%m/%Y %H:%M"))  # fmt: skip
    assert parse_times(same)[2] == []


@pytest.mark.parametrize("raw", [[0.0, 1.0, np.inf, 3.0], ["0", "1", "-inf", "3"]])
def test_an_infinite_time_is_a_row_without_a_time(raw):
    t, _, _ = parse_times(pd.Series(raw))
    np.testing.assert_array_equal(t, [0, 1, np.nan, 3])  # skipped by the reader, with a note


# ---- day-first formats of European exports ---------------------------------------------------

_MIDNIGHT = pd.date_range("2024-04-03 23:58:00", periods=30, freq="10s")  # into 04.04.


@pytest.mark.parametrize(
    ("fmt", "suffix", "first"),
    [
        ("%d.%m.%y %H:%M:%S", "", "03.04.24 23:58:00"),  # German DCS, two-digit year
        ("%d.%m.%Y %H:%M:%S", ",000", "03.04.2024 23:58:00,000"),  # German Excel
        ("%d/%m/%Y %H:%M:%S", ",000", "03/04/2024 23:58:00,000"),
        ("%d-%m-%Y %H:%M:%S", "", "03-04-2024 23:58:00"),
        ("%d.%m.%Y %I:%M:%S %p", "", "03.04.2024 11:58:00 PM"),
    ],
)  # fmt: skip
def test_day_first_formats_crossing_midnight_are_read_day_first(fmt, suffix, first):
    """Before, these went to pandas' month-first guess: 03.04. was the 4th of March, and
    midnight a jump of a month that the reader refused as a gap."""
    raw = pd.Series([x.strftime(fmt) + suffix for x in _MIDNIGHT])
    assert raw[0] == first
    t, start, notes = parse_times(raw)
    np.testing.assert_array_equal(t, 10.0 * np.arange(30))
    assert start == pd.Timestamp("2024-04-03 23:58:00")
    assert all("month first" not in n for n in notes)


def test_milliseconds_after_a_comma_are_read():
    raw = pd.Series(["03.04.2024 23:59:59,250", "03.04.2024 23:59:59,750",
                     "04.04.2024 00:00:00,250"])  # fmt: skip
    t, start, _ = parse_times(raw)
    np.testing.assert_allclose(t, [0.0, 0.5, 1.0])
    assert start == pd.Timestamp("2024-04-03 23:59:59.250")


@pytest.mark.parametrize(
    ("values", "start", "notes"),
    [
        # within one day, both orders read: day first, and the note says so
        (["03.04.24 08:00:00", "03.04.24 08:00:10"], "2024-04-03 08:00:00",
         ["dates could be day/month or month/day: read day first"]),
        (["03-04-2024 08:00:00", "03-04-2024 08:00:10"], "2024-04-03 08:00:00",
         ["dates could be day/month or month/day: read day first"]),
        # a 13th day settles it; 03.03. reads alike either way: no note
        (["13.04.24 08:00:00", "13.04.24 08:00:10"], "2024-04-13 08:00:00", []),
        (["03.03.24 08:00:00", "03.03.24 08:00:10"], "2024-03-03 08:00:00", []),
    ],
)  # fmt: skip
def test_day_month_order_of_a_file_within_one_day_is_noted(values, start, notes):
    t, got, got_notes = parse_times(pd.Series(values))
    np.testing.assert_array_equal(t, [0.0, 10.0])
    assert got == pd.Timestamp(start) and got_notes == notes


def test_a_13th_day_late_in_the_column_settles_a_dashed_date():
    """The order check runs for every day-month format, not only for slashes: a sample of
    days <= 12 in a month-first dashed column (read day first at first) is corrected."""
    stamps = pd.date_range("2024-01-12 00:00", periods=400, freq="5min")
    raw = pd.Series(stamps.strftime("%m-%d-%Y %H:%M"))  # 01-13-2024 from row 289 on
    assert raw[287] == "01-12-2024 23:55" and raw[288] == "01-13-2024 00:00"
    t, start, notes = parse_times(raw)
    np.testing.assert_array_equal(t, 300.0 * np.arange(400))
    assert start == stamps[0] and notes == []


def test_month_first_with_am_pm_crossing_midnight():
    raw = pd.Series([f"{x.month}/{x.day}/{x.year} {(x.hour % 12) or 12}:{x.minute:02d}:"
                     f"{x.second:02d} {x:%p}" for x in _MIDNIGHT])  # fmt: skip
    t, start, notes = parse_times(raw)
    np.testing.assert_array_equal(t, 10.0 * np.arange(30))
    assert start == pd.Timestamp("2024-04-03 23:58:00")
    assert notes == ["dates could be day/month or month/day: read month first"]
