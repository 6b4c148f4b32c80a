"""The measured-data reader's bookkeeping on tiny files whose reading is known: the listing,
MODE text, notes on status text, strict timestamp errors and read_loops' collection."""

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import _measured, list_loop_files, read_loop_file, read_loops


def _write(path, text):
    path.write_text(text)
    return path


def test_listing_names_its_columns_and_says_why_a_file_is_not_read(tmp_path):
    empty = list_loop_files([])
    assert empty.columns.tolist() == ["path", "supported", "reason"] and empty.empty
    _write(tmp_path / "FIC1.csv", "t,PV,OP\n0,1,2\n1,2,3\n")
    _write(tmp_path / "old.xls", "")
    files = list_loop_files(tmp_path)
    assert files["supported"].tolist() == [True, False]
    assert files["reason"].tolist()[0] == ""
    assert "old Excel format (.xls)" in files["reason"].tolist()[1]


def test_mode_text_and_numbers_give_the_share_in_automatic(tmp_path):
    f = _write(
        tmp_path / "FIC1.csv",
        "t,PV,OP,MODE\n0,1,5,AUTO\n1,2,6, man \n2,3,7,Cas\n3,4,8,1\n4,5,9,0\n5,6,10,x\n",
    )
    data = read_loop_file(f, return_frames=True)
    # automatic: AUTO, CAS and 1; manual: MAN and 0; unreadable: x
    np.testing.assert_array_equal(data.frames[0]["mode"], [1, 0, 1, 1, 0, np.nan])
    assert data.meta.loc[0, "auto_fraction"] == 0.5
    g = _write(tmp_path / "FIC2.csv", "t,PV,OP,MODE\n0,1,5,1\n1,2,6,\n2,3,7,0\n3,4,8,1\n")
    numeric = read_loop_file(g, return_frames=True)
    np.testing.assert_array_equal(numeric.frames[0]["mode"], [1, np.nan, 0, 1])
    assert numeric.meta.loc[0, "auto_fraction"] == 0.5
    h = _write(tmp_path / "FIC3.csv", "t,PV,OP\n0,1,5\n1,2,6\n")
    assert np.isnan(read_loop_file(h).meta.loc[0, "auto_fraction"])  # no MODE column


def test_status_text_is_summed_up_with_its_three_most_common_values(tmp_path):
    four = _write(tmp_path / "a.csv", "t,PV,OP\n0,1,5\n1,a,6\n2,b,7\n3,c,8\n4,d,9\n5,6,10\n")
    three = _write(tmp_path / "b.csv", "t,PV,OP\n0,1,5\n1,a,6\n2,b,7\n3,c,8\n4,a,9\n5,6,10\n")
    assert read_loop_file(four).meta.loc[0, "reason"] == (
        "4 text values in PV read as NaN ('a' x1, 'b' x1, 'c' x1, ...)"
    )
    assert read_loop_file(three).meta.loc[0, "reason"] == (
        "4 text values in PV read as NaN ('a' x2, 'b' x1, 'c' x1)"
    )


def test_strict_reading_names_the_row_where_time_goes_wrong(tmp_path):
    dup = _write(tmp_path / "dup.csv", "t,PV,OP\n0,1,5\n1,2,6\n2,3,7\n2,4,8\n3,5,9\n")
    back = _write(tmp_path / "back.csv", "t,PV,OP\n0,1,5\n1,2,6\n3,3,7\n2,4,8\n4,5,9\n")
    fine = _write(tmp_path / "fine.csv", "t,PV,OP\n0,1,5\n1,2,6\n2,3,7\n3,4,8\n4,5,9\n")
    # the fourth data row repeats (or goes back from) the third row's time
    assert read_loop_file(dup, strict=True).meta.loc[0, "reason"] == (
        "timestamps are duplicated at data row 4 (2 then 2)"
    )
    assert read_loop_file(back, strict=True).meta.loc[0, "reason"] == (
        "timestamps are not increasing (unsorted) at data row 4 (3 then 2)"
    )
    ok = read_loop_file(fine, strict=True).meta  # one-second steps are increasing
    assert ok.loc[0, "status"] == "ok" and ok.loc[0, "ts"] == 1.0


def test_read_loops_collects_files_and_lists_the_skipped(tmp_path):
    _write(tmp_path / "FIC1.csv", "t,PV,OP\n0,1,5\n1,2,6\n2,3,7\n")
    _write(tmp_path / "notes.doc", "not a loop")
    data = read_loops(tmp_path)
    assert "frames" not in data  # only when asked
    assert data.skipped.to_dict("records") == [
        {"path": str(tmp_path / "notes.doc"), "reason": data.skipped.loc[0, "reason"]}
    ]
    assert data.skipped.loc[0, "reason"]
    only_bad = tmp_path / "bad"
    only_bad.mkdir()
    _write(only_bad / "notes.doc", "not a loop")
    with pytest.raises(ValueError, match="channels must be a dict"):
        read_loops(only_bad, channels={"flow": "F"})


def test_skip_gives_every_named_path_a_row_with_its_status(tmp_path):
    good = _write(tmp_path / "FIC1.csv", "t,PV,OP\n0,1,5\n1,2,6\n2,3,7\n")
    old = _write(tmp_path / "FIC2.xls", "")
    missing = tmp_path / "FIC3.csv"
    with pytest.raises(ValueError, match="FIC2.xls: old Excel format"):
        read_loops([good, old])
    data = read_loops([missing, old, good], on_error="skip")
    meta = data.meta
    assert meta["file"].tolist() == ["FIC3.csv", "FIC2.xls", "FIC1.csv"]
    assert meta["path"].tolist() == [str(missing), str(old), str(good)]
    assert meta["status"].tolist() == ["error", "unsupported", "ok"]
    assert meta["reason"][0] == "file does not exist" and "old Excel" in meta["reason"][1]
    assert meta["n_samples"].tolist() == [0, 0, 3]
    assert np.isnan(data.X[:2]).all() and data.X[2, :, 0].tolist() == [1, 2, 3]
    assert data.skipped.empty  # named directly: not skipped, reported
    assert data.skipped.columns.tolist() == ["path", "reason"]
    with pytest.raises(ValueError, match=r"paths holds no files to read: \[\]"):
        read_loops([])


def test_tags_with_dots_and_separators_and_without_isa_letters(tmp_path):
    f = _write(tmp_path / "unit3.csv", "t,U1.FIC1.PV,U1.FIC1.OP,LIC2_PV,LIC2_OP,TT 3 PV\n"
               "0,1,2,3,4,5\n1,2,3,4,5,6\n2,3,4,5,6,7\n")  # fmt: skip
    meta = read_loop_file(f).meta
    assert meta["tag"].tolist() == ["U1.FIC1", "LIC2", "TT 3"]  # the last separator splits
    assert meta["loop_type"].tolist() == ["flow", "level", "unknown"]
    assert meta["isa"].tolist() == ["FIC", "LIC", ""]
    g = _write(tmp_path / "plain.csv", "t,PV,OP\n0,1,2\n1,2,3\n")
    assert read_loop_file(g).meta.loc[0, ["tag", "isa", "loop_type"]].tolist() == [
        "plain", "", "unknown"
    ]  # fmt: skip


def test_channels_named_by_hand(tmp_path):
    f = _write(tmp_path / "a.csv", "stamp,level,OP,valve\n0,1,9,5\n5,2,8,6\n10,3,7,7\n")
    data = read_loop_file(f, channels={"time": "stamp", "pv": "level"})
    assert data.meta.loc[0, "ts"] == 5.0  # the named time column, not found by name
    np.testing.assert_array_equal(data.X[0], [[1, 9, np.nan], [2, 8, np.nan], [3, 7, np.nan]])
    moved = read_loop_file(f, channels={"op": "valve"}, ts=1.0)  # PV: no alias matches
    assert moved.meta.loc[0, "status"] == "error" and "no PV column" in moved.meta.loc[0, "reason"]
    bad = read_loop_file(f, channels={"pv": "flow"}).meta.loc[0, "reason"]
    assert (
        bad == "column 'flow' given in channels['pv'] is not in ['stamp', 'level', 'OP', 'valve']"
    )


def test_decimal_comma_and_missing_text_among_numbers(tmp_path):
    text = "time;PV;OP;SP\n0;1,5;40;2\n10;Bad;41;2\n20;NONE;42;2\n30;1,7;null;2\n"
    f = _write(tmp_path / "a.csv", text)
    data = read_loop_file(f)
    np.testing.assert_array_equal(data.X[0, :, 0], [1.5, np.nan, np.nan, 1.7])
    np.testing.assert_array_equal(data.X[0, :, 1], [40, 41, 42, np.nan])
    # NONE and null are how a historian writes "missing": read as NaN, not counted
    assert data.meta.loc[0, "reason"] == "decimal comma; 1 text value in PV read as NaN ('Bad' x1)"
    assert data.meta.loc[0, "n_nan"] == 3


def test_loops_without_op_keep_their_setpoint_and_each_loop_its_mode(tmp_path):
    f = _write(tmp_path / "a.csv", "t,PV,SP\n0,1,5\n1,2,5\n2,3,6\n")
    data = read_loop_file(f)
    np.testing.assert_array_equal(data.X[0, :, 2], [5, 5, 6])
    assert data.meta.loc[0, "reason"] == "no OP column"
    g = _write(tmp_path / "b.csv", "t,FIC1.PV,FIC1.OP,FIC1.MODE,LIC2.PV,LIC2.OP,LIC2.MODE\n"
               "0,1,2,AUTO,3,4,MAN\n1,2,3,AUTO,4,5,AUTO\n")  # fmt: skip
    wide = read_loop_file(g)
    np.testing.assert_array_equal(wide.X[:, :, 0], [[1, 2], [3, 4]])
    np.testing.assert_array_equal(wide.X[:, :, 1], [[2, 3], [4, 5]])
    assert wide.meta["auto_fraction"].tolist() == [1.0, 0.5]


def test_nullable_integers_from_parquet(tmp_path):
    pytest.importorskip("pyarrow")
    frame = pd.DataFrame({"t": [0, 1, 2], "PV": pd.array([1, None, 3], dtype="Int64"),
                          "OP": pd.array([4, 5, 6], dtype="Int64")})  # fmt: skip
    frame.to_parquet(tmp_path / "FIC1.parquet")
    data = read_loop_file(tmp_path / "FIC1.parquet")
    np.testing.assert_array_equal(data.X[0, :, :2], [[1, 4], [np.nan, 5], [3, 6]])


def test_read_loops_passes_its_arguments_and_fills_its_bunch(tmp_path):
    f = _write(tmp_path / "FIC1.csv", "t,PV,OP\n0,1,5\n10,2,6\n20,3,7\n")
    data = read_loops(f, time_unit="epoch_ms")
    assert data.meta.loc[0, "ts"] == pytest.approx(0.01)
    assert data.channels == ("pv", "op", "sp")
    assert read_loops(f).meta.loc[0, "ts"] == 10.0


def test_which_columns_make_a_loop(tmp_path):
    two_times = _write(tmp_path / "a.csv", "t,time,PV,OP\n0,0,1,2\n1,1,2,3\n")
    assert read_loop_file(two_times).meta.loc[0, "reason"] == (
        "several columns could be the time: ['t', 'time']; choose one with channels={'time': ...}"
    )
    none = _write(tmp_path / "b.csv", "t,flow,valve\n0,1,2\n1,2,3\n")
    assert read_loop_file(none).meta.loc[0, "reason"] == (
        "no PV column (looked for pv/y/cv/meas/measurement/process_variable, also after a "
        "'<tag>.' prefix, in ['t', 'flow', 'valve']); name it with channels={'pv': ...}"
    )
    # loops in column order, not in tag order; an untagged OP beside a tagged one is left
    order = _write(tmp_path / "c.csv", "t,TIC9.PV,TIC9.OP,FIC1.PV,FIC1.OP,OP\n0,1,2,3,4,5\n"
                   "1,2,3,4,5,6\n")  # fmt: skip
    meta = read_loop_file(order).meta
    assert meta["tag"].tolist() == ["TIC9", "FIC1"]
    assert meta["reason"].tolist() == ["columns ['OP'] not used: no PV beside them"] * 2
    one = _write(tmp_path / "d.csv", "t,FIC1.PV,FIC1.OP,SP,OP\n0,1,2,3,4\n1,2,3,4,5\n")
    data = read_loop_file(one)
    np.testing.assert_array_equal(data.X[0, :, 1:], [[2, 3], [3, 4]])  # FIC1's OP, the SP
    assert data.meta.loc[0, "reason"] == "columns ['OP'] not used: no PV beside them"
    # a column named as one channel is not used again for another
    named = _write(tmp_path / "e.csv", "t,PV,OP,SP\n0,1,2,3\n1,2,3,4\n")
    data = read_loop_file(named, channels={"pv": "SP"})
    np.testing.assert_array_equal(data.X[0], [[3, 2, np.nan], [4, 3, np.nan]])


def test_what_a_file_without_loops_says(tmp_path):
    assert read_loop_file(tmp_path).meta.loc[0, "reason"] == (
        "is a folder: read it with read_loops or list its files first"
    )
    assert read_loop_file(tmp_path / "gone.csv").meta.loc[0, "reason"] == "file does not exist"
    one = _write(tmp_path / "one.csv", "PV,OP\n1,2\n")
    assert read_loop_file(one).meta.loc[0, "reason"] == "only one row of data"
    gap = _write(tmp_path / "gap.csv", "t,PV,OP\n0,1,2\n,2,3\n2,3,4\n")
    assert read_loop_file(gap, strict=True).meta.loc[0, "reason"] == (
        "time column 't' has 1 empty values"
    )


def test_date_and_time_columns_and_the_historians_time_format(tmp_path):
    f = _write(tmp_path / "a.csv", "Date,Time,PV,OP\n2024-01-01,10:00:00,1,2\n"
               "2024-01-01,10:00:05,2,3\n2024-01-01,10:00:10,3,4\n")  # fmt: skip
    meta = read_loop_file(f).meta
    assert meta.loc[0, "ts"] == 5.0 and "time from columns Date + Time" in meta.loc[0, "reason"]
    assert str(meta.loc[0, "start"]) == "2024-01-01 10:00:00"
    # the header's Java pattern says month first: 01/02 is the 2nd of January
    text = (
        "PROCESSDATA\tFIC7 Data\tMM/dd/yyyy HH:mm:ss\r\n8\t10\t01/02/2024 10:00:00\t3\r\n"
        "tagname\tFIC7.MV\tFIC7.PV\r\ndesc\tflow_OP\tflow_PV\r\nfsMax=3\tfsMin=0\r\n"
        "01/02/2024 10:00:00\t1\t2\r\n01/02/2024 10:00:10\t2\t3\r\n01/02/2024 10:00:20\t3\t4\r\n"
    )
    hist = _write(tmp_path / "FIC7.txt", text)
    meta = read_loop_file(hist).meta
    assert meta.loc[0, "status"] == "ok", meta.loc[0, "reason"]
    assert str(meta.loc[0, "start"]) == "2024-01-02 10:00:00" and meta.loc[0, "ts"] == 10.0
    # a declared day-first pattern is the file's word: read day first, without the note
    # that the order was guessed
    hist = _write(tmp_path / "FIC8.txt", text.replace("MM/dd/yyyy", "dd/MM/yyyy"))
    meta = read_loop_file(hist).meta
    assert str(meta.loc[0, "start"]) == "2024-02-01 10:00:00", meta.loc[0, "reason"]
    assert "day/month or month/day" not in meta.loc[0, "reason"]


def test_a_declared_day_first_pattern_the_dates_contradict_is_overruled_with_a_note():
    from sktiction.datasets._timestamps import parse_times

    # hourly stamps written month first under a day-first header: from the 13th of
    # January on the declared pattern cannot read them, and the whole column settles it
    stamps = pd.date_range("2024-01-01", periods=480, freq="h")
    raw = pd.Series(stamps.strftime("%m/%d/%Y %H:%M:%S"))
    t, start, notes = parse_times(raw, time_format="%d/%m/%Y %H:%M:%S")
    assert np.array_equal(t, 3600.0 * np.arange(480))
    assert str(start) == "2024-01-01 00:00:00"
    assert notes == ["the declared date pattern does not fit 192 values: read month first"]


def test_resampling_holds_the_mode_and_strict_only_reports(tmp_path):
    f = _write(tmp_path / "a.csv", "t,PV,OP,MODE\n0,1,10,1\n1,2,20,1\n2,3,30,0\n3.5,4,40,1\n"
               "4,5,50,1\n5,6,60,1\n6,7,70,1\n")  # fmt: skip
    data = read_loop_file(f, return_frames=True)
    frame = data.frames[0]
    assert frame["time"].tolist() == [0, 1, 2, 3, 4, 5, 6]
    # t = 3 lies a third of the way from t = 2 to t = 3.5: values on the line, MODE held
    assert frame.loc[3, "op"] == pytest.approx(30 + 10 / 1.5)
    assert frame.loc[3, "mode"] == 0.0
    assert data.meta.loc[0, "reason"].endswith(
        "resampled to 7 rows at 1 s; 2 rows in manual mode (MODE 0): a scan reads them as "
        "gaps")  # fmt: skip
    strict = read_loop_file(f, strict=True, return_frames=True)
    assert strict.frames[0]["time"].tolist() == [0, 1, 2, 3.5, 4, 5, 6]  # reported only
    assert strict.meta.loc[0, "reason"] == (
        "irregular sampling: 2 intervals differ from 1 s (min 0.5, max 1.5); 1 row in manual "
        "mode (MODE 0): a scan reads them as gaps"
    )


def test_rows_without_a_time_and_times_in_a_named_unit(tmp_path):
    f = _write(tmp_path / "a.csv", "t,PV,OP\n0,1,2\nabc,2,3\n2,3,4\n3,4,5\n")
    data = read_loop_file(f)
    assert data.meta.loc[0, "reason"].startswith("1 row without a readable time skipped; ")
    np.testing.assert_array_equal(data.X[0, :, 0], [1, 2.5, 4])  # 0, 1.5, 3 s: row 2 gone
    minutes = _write(tmp_path / "b.csv", "t_min,PV,OP\n0,1,2\n1,2,3\n2,3,4\n")
    meta = read_loop_file(minutes).meta
    assert (meta.loc[0, "ts"], meta.loc[0, "reason"]) == (
        60.0,
        "time in min (from the column name)",
    )
    # dates in a column named in minutes: the dates decide, no scaling
    dated = _write(tmp_path / "c.csv", "time_min,PV,OP\n2024-01-01 10:00:00,1,2\n"
                   "2024-01-01 10:01:00,2,3\n2024-01-01 10:02:00,3,4\n")  # fmt: skip
    assert read_loop_file(dated).meta.loc[0, "ts"] == 60.0
    # a given ts wins; a disagreement of more than 1 % is noted
    assert read_loop_file(minutes, ts=60).meta.loc[0, "reason"] == (
        "time in min (from the column name)"
    )
    assert read_loop_file(minutes, ts=60.5).meta.loc[0, "reason"] == (
        "time in min (from the column name)"
    )
    late = read_loop_file(minutes, ts=61).meta
    assert late.loc[0, "ts"] == 61.0
    assert late.loc[0, "reason"].endswith("; ts=61 given, timestamps say 60 s")
    no_time = _write(tmp_path / "d.csv", "PV,OP\n1,2\n2,3\n")
    assert read_loop_file(no_time).meta.loc[0, "reason"] == (
        "cannot determine the sampling time (no time column); pass ts="
    )


def test_the_error_of_a_loop_comes_before_its_notes(tmp_path):
    f = _write(tmp_path / "a.csv", "t,PV\n0,a\n1,b\n")
    data = read_loop_file(f)
    assert data.meta.loc[0, "reason"] == (
        "PV column 'PV' holds no numbers; 2 text values in PV read as NaN ('a' x1, 'b' x1); "
        "no OP column"
    )
    assert data.meta.loc[0, "status"] == "error" and np.isnan(data.X).all()


def test_a_historians_header_names_its_loop(tmp_path):
    text = (
        "PROCESSDATA\tFIC7 Data\tyyyy-MM-dd HH:mm:ss\r\n8\t10\t2024-01-01 10:00:00\t3\r\n"
        "tagname\tUNIT1.FIC7.MV\tUNIT1.FIC7.PV\r\ndesc\tflow_OP\tflow_PV\r\nfsMax=3\tfsMin=0\r\n"
        "2024-01-01 10:00:00\t1\t2\r\n2024-01-01 10:00:10\t2\t3\r\n2024-01-01 10:00:20\t3\t4\r\n"
    )
    meta = read_loop_file(_write(tmp_path / "export.txt", text)).meta
    assert meta.loc[0, ["tag", "loop_type"]].tolist() == ["FIC7", "flow"]


def test_an_unreadable_file_has_one_empty_row_and_typed_meta(tmp_path):
    data = read_loop_file(tmp_path / "FIC1.csv")
    assert data.X.shape == (1, 0, 3) and data.X.dtype == np.float64 and "frames" not in data
    assert data.channels == ("pv", "op", "sp")
    row = data.meta.iloc[0]
    assert data.meta.columns.tolist() == [
        "file", "path", "format", "tag", "isa", "loop_type", "ts", "n_samples", "n_nan",
        "auto_fraction", "start", "status", "reason",
    ]  # fmt: skip
    assert row[["file", "path", "format", "tag", "isa", "loop_type"]].tolist() == [
        "FIC1.csv", str(tmp_path / "FIC1.csv"), "", "", "", "unknown"
    ]  # fmt: skip
    assert row[["n_samples", "n_nan", "status"]].tolist() == [0, 0, "error"]
    assert np.isnan(row["ts"]) and np.isnan(row["auto_fraction"]) and row["start"] is pd.NaT
    assert str(data.meta["start"].dtype).startswith("datetime64")
    with pytest.raises(ValueError, match="channels must be a dict"):
        read_loop_file(tmp_path / "FIC1.csv", channels={"flow": "F"})
    # a loop in error says unknown whatever its tag says
    bad = read_loop_file(_write(tmp_path / "FIC9.csv", "t,PV,OP\n0,a,1\n1,b,2\n")).meta
    assert bad.loc[0, ["tag", "isa", "loop_type", "status"]].tolist() == [
        "FIC9", "FIC", "unknown", "error"
    ]  # fmt: skip


def test_frames_of_a_file_without_times_and_missing_values_counted(tmp_path):
    f = _write(tmp_path / "FIC1.csv", "PV,SP\n1,5\n,5\n3,6\n")
    data = read_loop_file(f, ts=2.0, return_frames=True)
    frame = data.frames[0]
    assert frame.columns.tolist() == ["time", "pv", "op", "sp", "mode"]
    assert frame["time"].tolist() == [0.0, 2.0, 4.0]
    np.testing.assert_array_equal(frame["pv"], [1, np.nan, 3])
    np.testing.assert_array_equal(frame["sp"], [5, 5, 6])
    assert frame["op"].isna().all() and frame["mode"].isna().all()
    assert data.meta.loc[0, "n_nan"] == 1  # no OP column: only PV's gap counts


def test_unexpected_failures_become_the_files_reason(tmp_path, monkeypatch):
    f = _write(tmp_path / "FIC1.csv", "t,PV,OP\n0,1,2\n1,2,3\n")

    def broken(path, kind, accept=None):
        raise RuntimeError("parser fell over")

    monkeypatch.setattr(_measured, "open_tables", broken)
    data = read_loop_file(f)
    assert data.X.shape == (1, 0, 3) and data.X.dtype == np.float64
    assert data.meta.loc[0, ["status", "n_samples", "reason"]].tolist() == [
        "error", 0, "could not be read (RuntimeError: parser fell over); please report this file"
    ]  # fmt: skip

    def denied(path, kind, accept=None):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(_measured, "open_tables", denied)
    reason = read_loop_file(f).meta.loc[0, "reason"]
    assert reason == "cannot open: Permission denied"


def test_odd_values_and_bounds(tmp_path):
    with pytest.raises(ValueError, match="time_unit must be one of"):
        read_loop_file(tmp_path / "x.csv", time_unit="weeks")
    # a comma in a file whose decimal mark is a point is no decimal mark
    f = _write(tmp_path / "a.csv", 't,PV,OP\n0,"1,234",1\n1,Bad,2\n2,3.5,3\n')
    data = read_loop_file(f)
    np.testing.assert_array_equal(data.X[0, :, 0], [np.nan, np.nan, 3.5])
    # exactly 1 % apart is not "more than 1 %"
    g = _write(tmp_path / "b.csv", "t,PV,OP\n0,1,2\n101,2,3\n202,3,4\n")
    assert read_loop_file(g, ts=100.0).meta.loc[0, "reason"] == ""
    # text times are quoted in a strict error
    h = _write(tmp_path / "c.csv", "t,PV,OP\n2024-01-01 10:00,1,2\n2024-01-01 10:00,2,3\n")
    assert read_loop_file(h, strict=True).meta.loc[0, "reason"] == (
        "timestamps are duplicated at data row 2 ('2024-01-01 10:00' then '2024-01-01 10:00')"
    )


def test_an_empty_table_has_no_data_rows(tmp_path):
    pytest.importorskip("pyarrow")
    pd.DataFrame({"t": [], "PV": [], "OP": []}).to_parquet(tmp_path / "FIC1.parquet")
    assert read_loop_file(tmp_path / "FIC1.parquet").meta.loc[0, "reason"] == (
        "file has no data rows"
    )


def test_each_loop_of_a_wide_file_holds_its_own_mode_when_resampled(tmp_path):
    f = _write(tmp_path / "a.csv", "t,FIC1.PV,FIC1.OP,FIC1.MODE,FIC2.PV,FIC2.OP,FIC2.MODE\n"
               "0,1,10,1,1,10,1\n1,2,20,1,2,20,1\n2,3,30,0,3,30,0\n3.5,4,40,1,4,40,1\n"
               "4,5,50,1,5,50,1\n5,6,60,1,6,60,1\n")  # fmt: skip
    frames = read_loop_file(f, return_frames=True).frames
    assert [fr.loc[3, "mode"] for fr in frames] == [0.0, 0.0]
    assert [fr.loc[3, "op"] for fr in frames] == pytest.approx([30 + 10 / 1.5] * 2)


def test_manual_rows_become_gaps_only_where_mode_is_zero_or_one(tmp_path):
    """0 means manual only in a 0/1 (or text) column; other DCS codes leave the data alone.
    The reader keeps the values; the scan's manual_gaps blanks the manual rows."""
    body = "t,PV,OP,MODE\n" + "".join(f"{i},{i},{i},{m}\n" for i, m in enumerate([1, 1, 0, 1]))
    X, rows, _ = _measured.read_loop_rows(_write(tmp_path / "a.csv", body))
    np.testing.assert_array_equal(X[0, :, 0], [0, 1, 2, 3])
    np.testing.assert_array_equal(_measured.manual_gaps(X, rows)[0, :, 0], [0, 1, np.nan, 3])
    np.testing.assert_array_equal(X[0, :, 0], [0, 1, 2, 3])  # a copy, not the reader's X
    coded = _write(tmp_path / "b.csv", body.replace("\n1,1,1,1", "\n1,1,1,2"))
    X, rows, _ = _measured.read_loop_rows(coded)
    np.testing.assert_array_equal(_measured.manual_gaps(X, rows)[0, :, 0], [0, 1, 2, 3])
    assert "manual" not in rows[0]["reason"]


def test_points_that_group_thousands_beside_a_decimal_comma(tmp_path):
    """1.500,25 is one thousand five hundred: a European export, not a missing value."""
    f = _write(tmp_path / "FIC1.csv", "t;PV;OP\n0;1.500,25;49,9\n1;1.499,75;50,1\n"
               "2;12.000;50,0\n3;999,5;50,2\n")  # fmt: skip
    data = read_loop_file(f)
    np.testing.assert_allclose(data.X[0, :, 0], [1500.25, 1499.75, 12000.0, 999.5])
    np.testing.assert_allclose(data.X[0, :, 1], [49.9, 50.1, 50.0, 50.2])
    assert data.meta.loc[0, "reason"] == "decimal comma"


@pytest.mark.parametrize(
    ("text", "note"),
    [
        # French: a space (or a no-break space) groups thousands, a comma is the decimal
        ("t;PV;OP\n0;1 500,25;49,9\n1;1\u00a0499,75;50,1\n2;12 000;50,0\n3;999,5;50,2\n",
         "decimal comma; thousands separators (space or ') in 'PV' removed (3 values)"),
        # Swiss: an apostrophe groups thousands, a point is the decimal
        ("t,PV,OP\n0,1'500.25,49.9\n1,1'499.75,50.1\n2,12'000,50.0\n3,999.5,50.2\n",
         "thousands separators (space or ') in 'PV' removed (3 values)"),
    ],
)  # fmt: skip
def test_spaces_and_apostrophes_that_group_thousands(tmp_path, text, note):
    """Before, each grouped value was status text read as NaN: half a pressure loop lost."""
    f = tmp_path / "PIC1.csv"
    f.write_text(text, encoding="utf-8")
    data = read_loop_file(f)
    np.testing.assert_allclose(data.X[0, :, 0], [1500.25, 1499.75, 12000.0, 999.5])
    np.testing.assert_allclose(data.X[0, :, 1], [49.9, 50.1, 50.0, 50.2])
    assert data.meta.loc[0, "reason"] == note
