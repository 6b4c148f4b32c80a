"""The measured-data reader's bookkeeping on tiny files whose reading is known: the listing,
MODE text, notes on status text, strict timestamp errors and read_loops' collection."""

import re

import numpy as np
import pytest

from sktiction.datasets import list_loop_files, read_loop_file, read_loops


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
    value = r"(np\.int64\()?{}\)?"  # the raw value, however numpy spells it
    reason = read_loop_file(dup, strict=True).meta.loc[0, "reason"]
    pattern = r"timestamps are duplicated at data row 4 \({} then {}\)"
    assert re.fullmatch(pattern.format(value.format(2), value.format(2)), reason)
    reason = read_loop_file(back, strict=True).meta.loc[0, "reason"]
    pattern = r"timestamps are not increasing \(unsorted\) at data row 4 \({} then {}\)"
    assert re.fullmatch(pattern.format(value.format(3), value.format(2)), reason)
    ok = read_loop_file(fine, strict=True).meta  # one-second steps are increasing
    assert ok.loc[0, "status"] == "ok" and ok.loc[0, "ts"] == 1.0


def test_strict_errors_quote_the_times_as_written(tmp_path):
    dup = _write(tmp_path / "dup.csv", "t,PV,OP\n0,1,5\n1,2,6\n2,3,7\n2,4,8\n3,5,9\n")
    reason = read_loop_file(dup, strict=True).meta.loc[0, "reason"]
    assert reason.endswith("at data row 4 (2 then 2)")


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
    with pytest.raises(ValueError, match=r"paths holds no files to read: \[\]"):
        read_loops([])
