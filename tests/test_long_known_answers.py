"""Known answers of the long-export reader (``sktiction.datasets._long``): column roles,
quality flags, the grid step of recorded tags, held values and the pivoted table of small
hand-written exports, cell by cell."""

import warnings

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import read_loop_file
from sktiction.datasets._columns import _is_time
from sktiction.datasets._long import (
    _day_order,
    _held,
    _loop_spans,
    _own_span,
    _scan_step,
    bad_quality,
    long_columns,
    paired_table,
    pivot_long,
    time_owners,
)
from sktiction.datasets._readers import FileError, Table

START = pd.Timestamp("2026-01-05 08:00")


def _table(df):
    """A :class:`Table` of ``df`` (columns read by position, as the file readers give)."""
    return Table(list(df.columns), {"notes": []},
                 lambda pos, text: pd.DataFrame({p: df.iloc[:, p] for p in pos}))  # fmt: skip


def _to_numbers(col, tag):
    return pd.to_numeric(col, errors="coerce").to_numpy(dtype=float), []


def _pivot(df, **kwargs):
    """``pivot_long`` of ``df``: the wide names, every wide column, the notes."""
    table = _table(df)
    wide = pivot_long(table, long_columns(list(df.columns), _is_time), _to_numbers, **kwargs)
    return wide.names, wide.read(list(range(len(wide.names)))), table.info["notes"]


# ---------------------------------------------------------------- column roles


@pytest.mark.parametrize(
    "names, found",
    [
        # "Tag" is more telling than "Name", "Value" than "Average": those two unused; every
        # quality column is listed, an empty name is neither used nor unused
        (["Tag", "Name", "Time", "Value", "Average", "Quality", "Status", ""],
         {"time": 2, "date": None, "tag": 0, "value": 3, "parameter": None,
          "quality": [5, 6], "unused": [1, 4]}),
        # units and spaces are dropped from names before they are matched
        ([" TAG NAME ", "Time [s]", "Value (degC)", "Parameter"],
         {"time": 1, "date": None, "tag": 0, "value": 2, "parameter": 3, "quality": [],
          "unused": []}),
        # a date and a time of day (German)
        (["Tag", "Datum", "Zeit", "Wert"],
         {"time": 2, "date": 1, "tag": 0, "value": 3, "parameter": None, "quality": [],
          "unused": []}),
        # WinCC's Time_ms is not the time beside another time column, but is when alone
        (["Tag", "TimeString", "Value", "Time_ms"],
         {"time": 1, "date": None, "tag": 0, "value": 2, "parameter": None, "quality": [],
          "unused": [3]}),
        (["Tag", "Value", "Time_ms"],
         {"time": 2, "date": None, "tag": 0, "value": 1, "parameter": None, "quality": [],
          "unused": []}),
    ],
)  # fmt: skip
def test_long_column_roles_in_full(names, found):
    assert long_columns(names, _is_time) == found


@pytest.mark.parametrize(
    "names",
    [
        ["Tag", "Tag", "Time", "Value"],  # the tag twice: ask, do not guess
        ["Point", "Time", "Value", "Value"],  # the value twice
        ["Tag", "Date", "Time", "Timestamp", "Value"],  # three time columns
        ["Tag", "Time", "Reading 2"],  # no value column
    ],
)
def test_long_columns_refuse_ambiguous_names(names):
    assert long_columns(names, _is_time) is None


def test_channels_name_the_long_time_column():
    found = long_columns(["Tag", "When", "Value", "Other"], _is_time, {"time": "When"})
    assert (found["time"], found["tag"], found["value"], found["unused"]) == (1, 0, 2, [3])
    # a name that is no column is not used: without a time column it is no long layout
    assert long_columns(["Tag", "When", "Value"], _is_time, {"time": "Nope"}) is None


@pytest.mark.parametrize(
    "names, owners",
    [
        (["Time", "A", "Time", "B", "C"], {1: 0, 3: 2, 4: 2}),
        (["Time", "A", "", "Time", "B"], {1: 0, 4: 3}),  # an unnamed column is no tag
        (["A", "Time", "B"], None),  # the first column must be a time
        (["Time", "A", "Time"], None),  # the last time has no value column
        (["Time", "A"], None),  # one time column: a wide file
    ],
)
def test_time_owners_known_answers(names, owners):
    assert time_owners(names, _is_time) == owners


def test_paired_table_reads_each_tag_with_the_time_column_to_its_left():
    df = pd.DataFrame([["2026-01-05 08:00:00", 1.0, "2026-01-05 08:00:00", 10.0],
                       ["2026-01-05 08:00:10", 2.0, "2026-01-05 08:00:30", 11.0],
                       ["2026-01-05 08:00:20", 3.0, None, None]],
                      columns=["Time", "F1.PV", "Time", "F1.OP"])  # fmt: skip
    long = paired_table(_table(df), _is_time)
    assert long.names == ["tag", "time", "value"]
    assert long.info["notes"] == ["a time column before each tag (2 tags): read as a long export"]
    frame = long.read([0, 1, 2])
    assert list(frame.columns) == [0, 1, 2] and list(frame.index) == [0, 1, 2, 3, 4]
    assert frame[0].tolist() == ["F1.PV"] * 3 + ["F1.OP"] * 2  # OP's blank row is no record
    assert frame[1].tolist() == ["2026-01-05 08:00:00", "2026-01-05 08:00:10",
                                 "2026-01-05 08:00:20", "2026-01-05 08:00:00",
                                 "2026-01-05 08:00:30"]  # fmt: skip
    assert frame[2].tolist() == [1.0, 2.0, 3.0, 10.0, 11.0]
    assert paired_table(_table(df.iloc[:, :2]), _is_time) is None  # one time column


# ---------------------------------------------------------------- quality


@pytest.mark.parametrize(
    "values, dtype, name, bad",
    [
        # WinCC Validity: 1 is valid, any other code (2: runtime markers) is not
        ([1, 0, 2, np.nan], float, "Validity", [0, 1, 1, 0]),
        ([1, 0, 2, 1], int, "Validity", [0, 1, 1, 0]),
        # flags: True is good in a quality column, bad in a questionable one (PI)
        ([True, False, True], bool, "Quality", [0, 1, 0]),
        ([True, False, True], bool, "Questionable", [1, 0, 1]),
        ([True, False, None], "boolean", "Questionable", [1, 0, 0]),  # Parquet's nullable
        ([True, False, None], "boolean", "Quality", [0, 1, 0]),
        ([1, 0, 1], int, "Quality", [0, 1, 0]),
        ([1, 0, 1], int, "Questionable", [1, 0, 1]),
        (["True", "false", " YES ", "no"], object, "Questionable", [1, 0, 1, 0]),
        (["True", "false", " YES ", "no"], object, "Quality", [0, 1, 0, 1]),
        # OPC codes: 192-255 good, below bad, when most rows are good codes
        ([192, 0, 192, 216, np.nan, 255], float, "Quality", [0, 1, 0, 0, 0, 0]),
        ([192, 0, 192, 216, 64], int, "Quality", [0, 1, 0, 0, 1]),
        # text: Good, OK, Valid, Normal (any case, spaces, a suffix) are good; blank is not bad
        (["Good", " GOOD ", "ok", "Valid", "Normal", "Bad", "Uncertain", None,
          "Good, Substituted", "not good"], object, "Status", [0, 0, 0, 0, 0, 1, 1, 0, 0, 1]),
        # a missing quality written out as text is blank, as in a flag column
        (["Good", "nan", "None", " ", "Bad"], object, "Quality", [0, 0, 0, 0, 1]),
        (["True", "nan", "None", " ", "False"], object, "Questionable", [1, 0, 0, 0, 0]),
    ],
)  # fmt: skip
def test_bad_quality_known_answers(values, dtype, name, bad):
    got, note = bad_quality(pd.Series(values, dtype=dtype), name)
    assert got.astype(int).tolist() == bad
    n = sum(bad)
    assert note == (f"{n} value{'s' * (n > 1)} of quality other than good read as NaN "
                    f"(column {name!r})")  # fmt: skip


def test_bad_quality_of_a_longer_name_reads_its_quality_word():
    got, note = bad_quality(pd.Series([1.0, 0.0, 1.0]), "FIC1.PV Validity", "Validity")
    assert got.tolist() == [False, True, False]
    assert note == "1 value of quality other than good read as NaN (column 'FIC1.PV Validity')"
    # all good: no note
    got, note = bad_quality(pd.Series(["Good", "Good"]), "Quality")
    assert got.tolist() == [False, False] and note == ""


@pytest.mark.parametrize(
    "values",
    [
        [0, 0, 0, 192],  # most rows below 192: not OPC codes
        [192, 192, 300],  # a code above 255
        [3, 3, 2],
        [1.0, 0.0, np.nan],  # a float 0/1 column is no flag (NaN) and no OPC code
        [np.nan, np.nan],
    ],
)
def test_numeric_quality_codes_of_unknown_meaning_are_not_used(values):
    got, note = bad_quality(pd.Series(values), "Quality")
    assert got is None
    assert note == "quality column 'Quality' not used (numeric codes of unknown meaning)"


def test_a_blank_quality_flag_is_neither_good_nor_bad(tmp_path):
    """A True/False flag column with a blank cell is still a flag column: the blank says
    nothing (with pandas 3, ``astype(str)`` keeps the blank missing, and the column was
    read as quality text, where "False" is not good: a questionable column then threw away
    every value *not* flagged questionable)."""
    flags = pd.Series(["True", None, "False"])  # pandas 3: dtype str
    assert bad_quality(flags, "Questionable")[0].tolist() == [True, False, False]
    assert bad_quality(flags, "Quality")[0].tolist() == [False, False, True]
    flags = pd.Series([True, np.nan, False], dtype=object)
    assert bad_quality(flags, "Questionable")[0].tolist() == [True, False, False]
    # end to end: one questionable PV value, one blank flag, 58 good values
    n = 30
    stamps = pd.date_range(START, periods=n, freq="10s").strftime("%Y-%m-%d %H:%M:%S")
    rows = pd.concat([pd.DataFrame({"Tag": f"FIC1.{c}", "Timestamp": stamps,
                                    "Value": np.arange(n) + 100.0 * j, "Questionable": "False"})
                      for j, c in enumerate(["PV", "OP"])], ignore_index=True)  # fmt: skip
    rows.loc[3, "Questionable"] = "True"
    rows.loc[7, "Questionable"] = ""
    rows.to_csv(tmp_path / "flags.csv", index=False)
    data = read_loop_file(tmp_path / "flags.csv")
    pv, op = data.X[0, :, 0], data.X[0, :, 1]
    assert np.flatnonzero(np.isnan(pv)).tolist() == [3] and np.isfinite(op).all()
    assert (
        "1 value of quality other than good read as NaN (column 'Questionable')"
        in (data.meta.loc[0, "reason"])
    )


# ---------------------------------------------------------------- grid step and spans


def _records(steps):
    return {"A": (np.r_[0.0, np.cumsum(steps)], None)}


@pytest.mark.parametrize(
    "steps, step",
    [
        ([5.0] * 20, 5.0),
        # records on the 1 s scans: 3 s and 10 s apart; their divisor is at least a fifth
        # of the typical short step 3 s
        ([3.0] * 2 + [10.0] * 20, 1.0),
        # the divisor 2 s of 10 s and 12 s steps is exactly a fifth of the short step 10 s
        ([10.0] * 6 + [12.0] * 2, 2.0),
        # divisor 0.5 s too small; 8 of 10 steps (exactly 80 %) whole multiples of 10 s
        ([10.0] * 4 + [20.0] * 4 + [15.5, 25.5], 10.0),
        # half the steps far from a multiple of 10 s: the median step
        ([10.0, 15.5] * 5, 12.75),
        # records 0.2 ms apart: no whole millisecond between them, no divisor
        ([0.0002] * 4, 0.0002),
        # one 3.5 s step among 10.5 s ones: the 5th percentile is a step that occurs (3.5 s),
        # not one interpolated between the two (near none: an empty median once); 0.5 s
        # divides both but is under a fifth of 3.5 s, and 10.5 s is 3 x 3.5 s
        ([3.5] + [10.5] * 10, 3.5),
    ],
)
def test_scan_step_known_answers(steps, step):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no mean of an empty slice
        assert _scan_step(_records(steps)) == pytest.approx(step, rel=1e-12)


def test_scan_step_of_tags_without_two_distinct_times_is_none():
    assert _scan_step({"A": (np.array([5.0]), None), "B": (np.array([1.0, 1.0]), None)}) is None


def test_held_values_at_and_between_records():
    t, v = np.array([0.0, 10.0, 20.0]), np.array([1.0, 2.0, 3.0])
    got = _held(t, v, np.array([-5.0, 0.0, 5.0, 10.0, 19.9, 20.0, 25.0]))
    np.testing.assert_array_equal(got, [np.nan, 1.0, 1.0, 2.0, 2.0, 3.0, 3.0])


@pytest.mark.parametrize(
    "tk, span",
    [
        (np.arange(9.0), None),  # fewer than 10 records: only sets values held
        (np.arange(10.0), (0.0, 9.0)),
        # a first record more than 10 times the rest's span (9) before the next: dropped
        (np.r_[0.0, 95 + np.arange(10.0)], (95.0, 104.0)),
        # exactly 10 times (90 before a span of 9): kept
        (np.r_[0.0, 90 + np.arange(10.0)], (0.0, 99.0)),
        # a last record 991 after the others' span of 9: dropped
        (np.r_[np.arange(10.0), 1000.0], (0.0, 9.0)),
        (np.r_[np.arange(10.0), 99.0], (0.0, 99.0)),  # 90 after a span of 9: kept
    ],
)
def test_own_span_known_answers(tk, span):
    assert _own_span(tk) == span


def test_each_loop_spans_from_its_last_start_to_its_last_record():
    records = {
        "A.PV": (np.arange(0.0, 100.0), None),
        "A.OP": (np.arange(20.0, 151.0), None),
        "B.PV": (np.arange(50.0, 61.0), None),
        "B.SP": (np.arange(6.0), None),  # 6 records: no span of its own
    }
    spans = _loop_spans(records, lambda tag: tag.split(".")[0])
    assert spans == {"A": (20.0, 150.0), "B": (50.0, 60.0)}


# ---------------------------------------------------------------- the pivoted table


def test_shared_times_pivot_side_by_side_in_tag_order():
    df = pd.DataFrame({"Tag": ["B", "A", "B", "A"],
                       "Timestamp": ["2026-01-05 08:00:10", "2026-01-05 08:00:10",
                                     "2026-01-05 08:00:00", "2026-01-05 08:00:00"],
                       "Value": [1, 2, 3, 4]})  # fmt: skip
    names, frame, notes = _pivot(df)
    assert names == ["time", "A", "B"]
    assert frame[0].tolist() == [START, START + pd.Timedelta("10s")]
    assert frame[1].tolist() == [4.0, 2.0] and frame[2].tolist() == [3.0, 1.0]
    assert notes == ["long layout (Tag, Timestamp, Value): 2 tags pivoted to columns; "
                     "shared times"]  # fmt: skip


def test_own_times_held_on_the_scan_grid_cell_by_cell():
    """PV every 10 s (21 records), OP every 30 s (7 records: it sets values only), a bad
    quality row, a repeated (tag, time) whose last value wins, times in seconds."""
    rows = [("F1.PV", 10.0 * i, float(i), "Good") for i in range(21)]
    rows += [("F1.OP", 30.0 * i, 100.0 + i, "Good") for i in range(7)]
    rows[5] = ("F1.PV", 50.0, 5.0, "Bad")
    rows.append(("F1.OP", 60.0, 222.0, "Good"))  # a later edit of OP at 60 s
    df = pd.DataFrame(rows, columns=["Tag", "Time", "Value", "Quality"])
    names, frame, notes = _pivot(df, time_unit="s")
    assert names == ["time", "F1.OP", "F1.PV"]
    np.testing.assert_array_equal(frame[0], np.arange(0.0, 201.0, 10.0))
    op = [100.0] * 3 + [101.0] * 3 + [222.0] * 3 + [103.0] * 3 + [104.0] * 3 + [105.0] * 3
    np.testing.assert_array_equal(frame[1], op + [106.0] * 3)
    pv = np.arange(21.0)
    pv[5] = np.nan  # bad until the next record
    np.testing.assert_array_equal(frame[2], pv)
    assert notes == [
        "1 value of quality other than good read as NaN (column 'Quality')",
        "1 repeated tag and time: kept the last",
        "long layout (Tag, Time, Value): 2 tags pivoted to columns; tags recorded at their "
        "own times: each held at its last record on a 10 s grid (the scan period the records "
        "fall on; 0% of the grid's rows without a record of any tag)",
    ]  # OP's 30 s between records are its own pace (3 scans), not a silence


def test_held_grid_share_of_rows_without_a_record_and_ts():
    """PV every 20 s, OP every 30 s (both 11 or more records): on their 10 s grid the rows
    at 10, 50, 70, 110, ... have no record of either."""
    rows = [("F1.PV", 20.0 * i, float(i)) for i in range(16)]  # 0-300 s
    rows += [("F1.OP", 30.0 * i, 100.0 + i) for i in range(11)]  # 0-300 s
    df = pd.DataFrame(rows, columns=["Tag", "Time", "Value"])
    names, frame, notes = _pivot(df, time_unit="s")
    grid = np.arange(0.0, 301.0, 10.0)
    np.testing.assert_array_equal(frame[0], grid)
    without = ~(np.isin(grid, 20.0 * np.arange(16)) | np.isin(grid, 30.0 * np.arange(11)))
    assert without.sum() == 10
    assert (
        f"on a 10 s grid (the scan period the records fall on; {10 / 31:.0%} of the grid's"
        in (notes[-1])
    )
    assert "no record for" not in notes[-1]
    names, frame, notes = _pivot(df, time_unit="s", ts=15.0)
    np.testing.assert_array_equal(frame[0], np.arange(0.0, 301.0, 15.0))
    np.testing.assert_array_equal(frame[1], 100.0 + np.arange(0.0, 301.0, 15.0) // 30)
    assert "each held at its last record on a 15 s grid (ts; " in notes[-1]


def test_a_stray_first_record_far_off_does_not_set_the_grid_cells():
    """A PV record 1e9 s before the rest: the grid runs over the rest (20 cells), not over
    1e9 s (which would be refused as too large)."""
    tp = np.r_[0.0, 1e9 + np.arange(20.0)]
    to = 1e9 + 2 * np.arange(10.0)
    df = pd.DataFrame({"Tag": ["A"] * 21 + ["B"] * 10, "Time": np.r_[tp, to],
                       "Value": np.r_[-1.0, np.arange(20.0), 100 + np.arange(10.0)]})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s")
    np.testing.assert_array_equal(frame[0], 1e9 + np.arange(20.0))
    np.testing.assert_array_equal(frame[1], np.arange(20.0))
    np.testing.assert_array_equal(frame[2], 100 + np.minimum(np.arange(20) // 2, 9))
    assert "(19 s of 1e+09 s)" in notes[-1]


def test_each_loop_keeps_its_own_span():
    """Loop A recorded 0-100 s, loop B 50-150 s: each is NaN outside its own span."""
    rows = [(f"A.{c}", float(t), float(t)) for c in ("PV", "OP") for t in range(0, 101, 5)]
    rows += [(f"B.{c}", float(t), -float(t)) for c in ("PV", "OP") for t in range(50, 151, 5)]
    df = pd.DataFrame(rows, columns=["Tag", "Time", "Value"])
    names, frame, notes = _pivot(df, time_unit="s", loop_of=lambda tag: tag.split(".")[0])
    assert names == ["time", "A.OP", "A.PV", "B.OP", "B.PV"]
    grid = np.arange(0.0, 151.0, 5.0)
    np.testing.assert_array_equal(frame[0], grid)
    np.testing.assert_array_equal(frame[1], np.where(grid <= 100, grid, np.nan))
    np.testing.assert_array_equal(frame[4], np.where(grid >= 50, -grid, np.nan))


def test_pivot_long_defaults_read_epoch_milliseconds_and_keep_the_last_repeat():
    df = pd.DataFrame({"Tag": ["A"] * 3 + ["B"] * 3, "Time": [1.7e12, 1.7e12 + 1000,
                       1.7e12 + 2000] * 2, "Value": np.arange(6.0)})  # fmt: skip
    names, frame, notes = _pivot(df)
    assert frame[0].tolist() == list(pd.to_datetime(1.7e12 + 1000 * np.arange(3), unit="ms"))
    assert notes[0] == "time read as epoch milliseconds (start 2023-11-14 22:13:20)"
    df = pd.DataFrame({"Tag": ["A", "A", "A"], "Time": [0.0, 1.0, 1.0], "Value": [1.0, 2.0, 3.0]})
    names, frame, notes = _pivot(df, time_unit="s")
    assert frame[1].tolist() == [1.0, 3.0]
    with pytest.raises(FileError, match=r"^long layout: 1 tag and time appear more than once$"):
        _pivot(df, time_unit="s", strict=True)


@pytest.mark.parametrize(
    "tags, times",
    [
        (["A", "B"], [0.0, 1.0]),  # each tag a single time
        (["A"] * 3 + ["B"] * 2, [0.0, 1.0, 2.0, 0.0, 2.0]),  # no tag of 10 records
    ],
)
def test_tags_without_a_span_are_refused(tags, times):
    df = pd.DataFrame({"Tag": tags, "Time": times, "Value": 1.0})
    with pytest.raises(FileError, match=r"^long layout: no tag has two distinct times$"):
        _pivot(df, time_unit="s")


def test_a_grid_too_fine_is_refused_with_its_size():
    t = np.r_[np.arange(30) * 0.001, np.arange(1, 366) * 86400.0]
    df = pd.DataFrame({"Tag": ["A"] * t.size + ["B"] * (t.size - 1), "Time": np.r_[t, t[1:]],
                       "Value": 0.0})  # fmt: skip
    with pytest.raises(FileError, match=r"^long layout: a 0\.001 s grid over 3\.1536e\+07 s "
                                        r"for 2 tags is too large; pass ts=$"):  # fmt: skip
        _pivot(df, time_unit="s")


def test_rows_without_a_tag_or_time_are_counted_and_a_layout_without_rows_refused():
    df = pd.DataFrame({"Tag": ["A", None, "A", "A"], "Time": [0.0, 1.0, np.nan, 2.0],
                       "Value": [1.0, 2.0, 3.0, 4.0]})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s")
    assert frame[1].tolist() == [1.0, 4.0]
    assert "2 rows without a tag or a readable time skipped" in notes
    with pytest.raises(FileError, match=r"^long layout: no row with a tag and a time$"):
        _pivot(df.assign(Tag=None), time_unit="s")


def test_text_times_are_parsed_tag_by_tag_over_the_autumn_clock_change():
    """Times as Python strings (object dtype, as a workbook or Parquet gives them): each
    tag's rows are in order, so the repeated hour is read as in a wide file."""
    t = pd.date_range("2025-10-26 01:30", periods=40, freq="5min")
    local = t.where(t < pd.Timestamp("2025-10-26 03:00"), t - pd.Timedelta(hours=1))
    stamps = list(local.strftime("%Y-%m-%d %H:%M:%S"))
    df = pd.DataFrame({"Tag": ["A"] * 40 + ["B"] * 40,
                       "Timestamp": pd.Series(stamps * 2, dtype=object),
                       "Value": np.r_[np.arange(40.0), 100 + np.arange(40.0)]})  # fmt: skip
    names, frame, notes = _pivot(df)
    assert frame[0].tolist() == list(t)
    np.testing.assert_array_equal(frame[1], np.arange(40.0))
    np.testing.assert_array_equal(frame[2], 100 + np.arange(40.0))
    assert notes[0].startswith("clock set back an hour at 2025-10-26 02:00:00")


def test_millisecond_stamps_are_kept_to_the_nanosecond():
    stamps = (START + pd.to_timedelta([0, 1, 3, 7], unit="ms")).strftime(
        "%Y-%m-%d %H:%M:%S.%f")  # fmt: skip
    df = pd.DataFrame({"Tag": ["A"] * 4 + ["B"] * 4, "Time": list(stamps) * 2,
                       "Value": np.arange(8.0)})  # fmt: skip
    names, frame, notes = _pivot(df)
    assert frame[0].tolist() == list(START + pd.to_timedelta([0, 1, 3, 7], unit="ms"))
    assert notes[-1].endswith("shared times")


def test_times_of_day_of_a_single_tag_are_refused():
    df = pd.DataFrame({"Tag": ["A"] * 5, "Time": [f"08:00:{s:02d}" for s in range(0, 50, 10)],
                       "Value": np.arange(5.0)})  # fmt: skip
    with pytest.raises(FileError, match="^long layout with times of day but no dates"):
        _pivot(df)


def test_a_small_hand_written_export_reads_cell_by_cell(tmp_path):
    """Four scans of a loop, rows in any order, a parameter column, a date and a time."""
    text = """Tag,Parameter,Date,Time,Value,Quality
FIC7,OP,05.01.2026,08:00:10,41.5,Good
FIC7,PV,05.01.2026,08:00:00,50.25,Good
FIC7,SP,05.01.2026,08:00:00,50,Good
FIC7,OP,05.01.2026,08:00:00,40.5,Good
FIC7,PV,05.01.2026,08:00:10,50.5,Bad
FIC7,SP,05.01.2026,08:00:10,50,Good
FIC7,PV,05.01.2026,08:00:20,50.75,Good
FIC7,OP,05.01.2026,08:00:20,42.5,Good
FIC7,SP,05.01.2026,08:00:20,51,Good
FIC7,PV,05.01.2026,08:00:30,51,Good
FIC7,OP,05.01.2026,08:00:30,43.5,Good
FIC7,SP,05.01.2026,08:00:30,51,Good
"""
    (tmp_path / "fic7.csv").write_text(text)
    data = read_loop_file(tmp_path / "fic7.csv")
    meta = data.meta.loc[0]
    assert (meta["status"], meta["tag"], meta["ts"], meta["n_samples"]) == ("ok", "FIC7", 10.0, 4)
    assert meta["start"] == START
    expect = [[50.25, 40.5, 50.0], [np.nan, 41.5, 50.0], [50.75, 42.5, 51.0], [51.0, 43.5, 51.0]]
    np.testing.assert_array_equal(data.X[0], expect)
    assert "time from columns Date + Time" in meta["reason"]
    assert "1 value of quality other than good read as NaN (column 'Quality')" in meta["reason"]
    assert (
        "long layout (Tag, Time, Value): 3 tags pivoted to columns; shared times"
        in (meta["reason"])
    )


# ---------------------------------------------------------------- edges the first tests left


def test_paired_table_keeps_a_time_without_a_value_as_a_missing_record():
    """A stamp with a blank value is a record (of a missing value); a row blank in both is
    padding below a shorter tag; a value without a time is kept for pivot_long to count."""
    df = pd.DataFrame([["2026-01-05 08:00:00", 1.0, "2026-01-05 08:00:00", 10.0],
                       ["2026-01-05 08:00:10", None, None, 11.0],
                       ["2026-01-05 08:00:20", 3.0, None, None]],
                      columns=["Time", "F1.PV", "Time", "F1.OP"])  # fmt: skip
    frame = paired_table(_table(df), _is_time).read([0, 1, 2])
    assert frame[0].tolist() == ["F1.PV"] * 3 + ["F1.OP"] * 2
    assert frame[1].isna().tolist() == [False, False, False, False, True]
    np.testing.assert_array_equal(frame[2], [1.0, np.nan, 3.0, 10.0, 11.0])


@pytest.mark.parametrize(
    "values, name, bad",
    [
        # blank flags written out as text say nothing either
        (["True", "NaN", "None", "", "False"], "Questionable", [1, 0, 0, 0, 0]),
    ],
)
def test_blank_flags_written_as_text(values, name, bad):
    got, _ = bad_quality(pd.Series(values, dtype=object), name)
    assert got.astype(int).tolist() == bad


def test_nullable_integer_quality_codes():
    """Parquet's nullable integers: a missing code is not bad."""
    got, _ = bad_quality(pd.Series([1, 0, None], dtype="Int64"), "Validity")
    assert got.tolist() == [False, True, False]
    got, _ = bad_quality(pd.Series([192, 0, None, 192], dtype="Int64"), "Quality")
    assert got.tolist() == [False, True, False, False]


def test_opc_codes_stop_at_255():
    got, note = bad_quality(pd.Series([192, 192, 256]), "Quality")
    assert got is None and "not used" in note


@pytest.mark.parametrize(
    "steps, step",
    [
        # a step exactly 25 % longer than the short one is not near it: with the odd 37.3 s
        # step fewer than 80 % are multiples of 10 s, so the median step
        ([10.0] * 3 + [12.5] * 3 + [37.3], 12.5),
        # 1 ms and 4 ms apart: the 1 ms scan
        ([0.001] * 5 + [0.004] * 5, 0.001),
    ],
)
def test_scan_step_boundaries(steps, step):
    assert _scan_step(_records(steps)) == pytest.approx(step, rel=1e-12)


@pytest.mark.parametrize(
    "tk, span",
    [
        (np.r_[np.arange(10.0), 104.0], (0.0, 9.0)),  # 95 after a span of 9: dropped
        # a stray first and last: the last is judged against the span without the first
        (np.r_[-1000.0, 100 + np.arange(10.0), 200.0], (100.0, 109.0)),
    ],
)
def test_own_span_of_a_stray_last_record(tk, span):
    assert _own_span(tk) == span


def test_day_order_of_a_time_note():
    assert _day_order("dates could be day/month or month/day: read month first") == "month"
    assert _day_order("dates could be day/month or month/day: read day first") == "day"
    assert _day_order("clock set back an hour at 2025-10-26 02:00:00") is None


def test_a_tag_without_times_before_the_others_is_skipped():
    df = pd.DataFrame({"Tag": ["Report", "A", "A", "B", "B"],
                       "Time": [None, "2026-01-05 08:00:00", "2026-01-05 08:00:10",
                                "2026-01-05 08:00:00", "2026-01-05 08:00:10"],
                       "Value": [np.nan, 1.0, 2.0, 3.0, 4.0]})  # fmt: skip
    names, frame, notes = _pivot(df)
    assert names == ["time", "A", "B"]
    assert frame[0].tolist() == [START, START + pd.Timedelta("10s")]
    assert frame[1].tolist() == [1.0, 2.0] and frame[2].tolist() == [3.0, 4.0]
    assert notes[0] == "1 row without a tag or a readable time skipped"


def test_an_unreadable_stamp_of_one_tag_is_a_skipped_row():
    stamps = [str(START + pd.Timedelta(seconds=10 * i)) for i in range(12)]
    a = stamps.copy()
    a[4] = "soon"
    df = pd.DataFrame({"Tag": ["A"] * 12 + ["B"] * 12, "Time": a + stamps,
                       "Value": np.r_[np.arange(12.0), 100 + np.arange(12.0)]})  # fmt: skip
    names, frame, notes = _pivot(df)
    assert frame[0].tolist() == [pd.Timestamp(s) for s in stamps]
    expect = np.arange(12.0)
    expect[4] = 3.0  # held from the record before
    np.testing.assert_array_equal(frame[1], expect)
    np.testing.assert_array_equal(frame[2], 100 + np.arange(12.0))
    assert "1 row without a tag or a readable time skipped" in notes


def test_an_unreadable_time_column_names_itself():
    df = pd.DataFrame({"Tag": ["A"] * 4, "Time": ["x", "y", "z", "w"], "Value": 1.0})
    with pytest.raises(FileError, match=r"^long layout: time column 'Time': values are not "
                                        r"times \(first: 'x'\)"):  # fmt: skip
        _pivot(df)


def test_pivoted_values_are_floats():
    df = pd.DataFrame({"Tag": ["A", None, "A", "B", "B"], "Time": [0.0, 0.5, 1.0, 0.0, 1.0],
                       "Value": [1, 2, 3, 4, 5]})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s")
    assert [frame[j].dtype for j in (1, 2)] == [np.float64, np.float64]
    assert frame[1].tolist() == [1.0, 3.0] and frame[2].tolist() == [4.0, 5.0]


def test_the_grid_size_limit(monkeypatch):
    """At most ``_MAX_CELLS`` cells (grid rows times tags): exactly the limit is read,
    more refused, with the span measured without a stray first record."""
    from sktiction.datasets import _long

    monkeypatch.setattr(_long, "_MAX_CELLS", 100)

    def rows(end, stray=False):
        t = np.arange(0.0, end + 1)  # a record a second; B without its second record
        tags = ["A"] * t.size + ["B"] * (t.size - 1)
        times = np.r_[t, np.delete(t, 1)]
        if stray:
            tags, times = ["A", "B"] + tags, np.r_[-1e6, -1e6, times]
        return pd.DataFrame({"Tag": tags, "Time": times, "Value": 1.0})

    names, frame, notes = _pivot(rows(50), time_unit="s")  # 50 s / 1 s * 2 tags = 100
    assert len(frame) == 51
    for stray in (False, True):
        with pytest.raises(FileError, match=r"^long layout: a 1 s grid over 51 s for 2 tags "
                                            r"is too large; pass ts=$"):  # fmt: skip
            _pivot(rows(51, stray), time_unit="s")


def test_loop_spans_cut_each_loops_columns_to_the_step():
    """0.5 s records: loop A's PV from 0 s, its OP from 20 s to 100 s; loop B 0-150 s. A's
    columns hold from 20 s (all of A's tags begun) to 100 s, not half a step beyond;
    every grid row has a record of some tag."""
    t = np.arange(0.0, 150.5, 0.5)
    a_pv, a_op = t[t <= 100], t[(t >= 20) & (t <= 100)]
    df = pd.DataFrame({"Tag": ["A.PV"] * a_pv.size + ["A.OP"] * a_op.size
                       + ["B.PV"] * t.size + ["B.OP"] * t.size,
                       "Time": np.r_[a_pv, a_op, t, t],
                       "Value": np.r_[a_pv, a_op, -t, -t]})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s", loop_of=lambda tag: tag.split(".")[0])
    assert names == ["time", "A.OP", "A.PV", "B.OP", "B.PV"]
    np.testing.assert_array_equal(frame[0], t)
    inside = (t >= 20) & (t <= 100)
    np.testing.assert_array_equal(frame[1], np.where(inside, t, np.nan))
    np.testing.assert_array_equal(frame[2], np.where(inside, t, np.nan))
    np.testing.assert_array_equal(frame[4], -t)
    assert (
        "on a 0.5 s grid (the scan period the records fall on; 0% of the grid's rows "
        in (notes[-1])
    )
    assert "records outside" not in notes[-1]  # A.PV's early records are on the grid


def test_notes_of_a_stray_record_and_of_a_silence():
    tp = np.r_[0.0, 1e9 + np.arange(20.0)]
    to = 1e9 + 2 * np.arange(10.0)
    df = pd.DataFrame({"Tag": ["A"] * 21 + ["B"] * 10, "Time": np.r_[tp, to],
                       "Value": np.r_[-1.0, np.arange(20.0), 100 + np.arange(10.0)]})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s")
    assert notes[-1].endswith(
        "2 tags pivoted to columns; tags recorded at their own times: each held at its last "
        "record on a 1 s grid (the scan period the records fall on; 0% of the grid's rows "
        "without a record of any tag); records outside the time all of a loop's tags cover "
        "set only the values held (19 s of 1e+09 s)"
    )  # B's 2 s between records (every other scan) are more than a tenth of 19 s, no silence
    # a silence of 3 s in a 9 s span (more than a tenth of it and more than three scans)
    t = np.arange(0.0, 9.0 + 1e-9, 0.125)
    op = t[(t <= 3) | (t >= 6)]
    df = pd.DataFrame({"Tag": ["F1.PV"] * t.size + ["F1.OP"] * op.size, "Time": np.r_[t, op],
                       "Value": 1.0})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s")
    assert notes[-1].endswith("; F1.OP has no record for 3 s of 9 s (held)")


def test_share_of_grid_rows_without_a_record_is_matched_to_the_millisecond():
    """A setpoint written at 0 s and 0.5 s, PV and OP at 0.25 + 0.5 k s: the grid runs on
    the loop's records (0.25 + 0.5 k), every row with a record. A tag whose odd-second
    stamps are 0.4 ms late has its records on a 1 s grid too (to the millisecond)."""
    t = 0.25 + 0.5 * np.arange(41)
    df = pd.DataFrame({"Tag": ["SP"] * 2 + ["PV"] * 41 + ["OP"] * 40,
                       "Time": np.r_[0.0, 0.5, t, t[1:]], "Value": 1.0})  # fmt: skip
    names, frame, notes = _pivot(df, time_unit="s")
    np.testing.assert_array_equal(frame[0], t[1:])
    assert (
        "on a 0.5 s grid (the scan period the records fall on; 0% of the grid's rows"
        in (notes[-1])
    )
    k = np.arange(21.0)
    a = np.where(k % 2 == 1, k + 0.0004, k)
    df = pd.DataFrame({"Tag": ["A"] * 21 + ["B"] * 11, "Time": np.r_[a, k[::2]], "Value": 1.0})
    notes = _pivot(df, time_unit="s")[2]
    assert (
        "on a 1 s grid (the scan period the records fall on; 0% of the grid's rows" in (notes[-1])
    )
