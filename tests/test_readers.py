"""The file layer of the readers: file kinds, encodings, separators and historian headers."""

import codecs
import csv
import sys

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import read_loop_file
from sktiction.datasets._readers import (
    FileError,
    _blank_rows,
    _choose_separator,
    _delimited_header,
    _encoding,
    _fields,
    _historian_header,
    _time_format,
    file_kind,
    open_table,
)

READABLE = ".txt, .csv, .tsv, .xlsx, .xlsm, .parquet, .pq"


@pytest.mark.parametrize(
    ("name", "kind"),
    [("FIC1.csv", "text"), ("a.TXT", "text"), ("b.tsv", "text"), ("c.xlsx", "xlsx"),
     ("d.xlsm", "xlsx"), ("e.parquet", "parquet"), ("f.PQ", "parquet")],
)  # fmt: skip
def test_file_kinds(name, kind):
    assert file_kind(name) == (kind, "")


def test_files_that_are_not_loops_say_why():
    assert file_kind("site/INDEX.csv") == (
        None,
        "folder index (labels of the other files), not a loop",
    )
    assert file_kind("index.txt")[0] is None
    assert file_kind("~$book.xlsx") == (
        None, "Office lock file (the workbook is open somewhere), not a loop"
    )  # fmt: skip
    assert file_kind("README") == (None, f"no file extension: not read (readable: {READABLE})")
    assert file_kind("old.XLS") == (None, "old Excel format (.xls): save it as .xlsx or CSV")
    assert file_kind("x.zip") == (None, "compressed file: unpack it first")
    assert file_kind("x.json") == (None, f"unsupported file type '.json' (readable: {READABLE})")


TEXT = "time,PV,OP\n0,1.5,2\n1,température,3\n"


@pytest.mark.parametrize(
    ("raw", "encoding"),
    [
        (codecs.BOM_UTF16_LE + TEXT.encode("utf-16-le"), "utf-16"),
        (codecs.BOM_UTF16_BE + TEXT.encode("utf-16-be"), "utf-16"),
        (codecs.BOM_UTF8 + TEXT.encode("utf-8"), "utf-8-sig"),
        (TEXT.encode("utf-16-le"), "utf-16-le"),  # no BOM: every other byte is 0
        (TEXT.encode("utf-16-be"), "utf-16-be"),
        (TEXT.encode("utf-8"), "utf-8"),
        (TEXT.encode("utf-8")[:-8] + "é".encode()[:1], "utf-8"),  # a head cut mid-character
        (TEXT.encode("latin-1"), "latin-1"),  # single high bytes
        ("time,温度,OP\n0,1,2\n".encode("gbk"), "gb18030"),  # byte pairs
        (b"time,PV\n0,\x80\x80\n", "latin-1"),  # pairs, but not GB18030
        (b"\x80\x80", "latin-1"),
    ],
)
def test_encodings(raw, encoding):
    assert _encoding(raw) == encoding


def test_utf16_needs_zeros_in_more_than_40_percent_of_its_half():
    # 5 of 10 odd bytes zero: UTF-16-LE; 4 of 10: not (binary)
    assert _encoding(b"a\x00" * 5 + b"ab" * 5) == "utf-16-le"
    assert _encoding(b"\x00a" * 5 + b"ab" * 5) == "utf-16-be"
    with pytest.raises(
        FileError,
        match="^binary file .holds NUL bytes.$|^binary file .holds NUL bytes., not a text export$",
    ):
        _encoding(b"a\x00" * 4 + b"ab" * 6)
    with pytest.raises(FileError, match="binary file"):
        _encoding(b"\x00" + b"a" * 20)


@pytest.mark.parametrize(
    ("lines", "expected"),
    [
        (["a\tb\tc", "1\t2\t3", "4\t5\t6"], ("\t", 3)),
        (["a;b", "1,5;2", "3,5;4"], (";", 2)),  # ";" before "," (a decimal comma)
        (["a|b|c|d", "1|2|3|4"], ("|", 4)),
        (["a,b", "1,2", "", "# note", "3,4"], (",", 2)),  # blank and comment lines ignored
        (["single", "1", "2"], (",", 1)),
        ([], (",", 1)),
        # 3 of 5 rows (60 %) agree: enough; 2 of 5: not, the next separator is tried
        (["a;b", "1;2", "3;4", "5", "6"], (";", 2)),
        (["a;b", "1;2", "3", "4", "5,6"], (",", 1)),
        # "|" in a PI AF path splits the data rows alike, not the header: a data row is
        # no header, the next separator is taken
        (["Tag,Time,Value"] + [r"\\S\DB\FIC1|PV,2026-01-05 08:00:00,1.5"] * 3, (",", 3)),
        # no header under any separator: the first, whose error says so
        (["27.11.2026 08:00:00;1,5;2,5", "27.11.2026 08:00:01;1,6;2,4"], (";", 3)),
    ],
)
def test_separator(lines, expected):
    assert _choose_separator(lines) == expected


def test_separator_reads_the_last_50_rows():
    lines = ["title;with;semicolons"] * 60 + ["a,b"] + ["1,2"] * 49
    assert _choose_separator(lines) == (",", 2)


def _historian(first="PROCESSDATA\t2111FIC10201 Data\tyyyy-MM-dd HH:mm:ss.SSS",
               second="Start\t2024-10-17\t21:55:00\t12", names="TagName\tPV\tOP\tSP"):  # fmt: skip
    return [first, second, names, "descriptions", "grid"]


def test_historian_header():
    names, info = _historian_header(_historian())
    assert names == ["time", "PV", "OP", "SP"]
    assert info == {"format": "historian", "tag": "2111FIC10201",
                    "time_format": "%Y-%m-%d %H:%M:%S.%f", "declared_rows": 12}  # fmt: skip
    names, info = _historian_header(_historian(first="\ufeffPROCESSDATA", second="Start\t1\t2"))
    assert info["tag"] is None and info["time_format"] is None
    assert info["declared_rows"] is None
    _, info = _historian_header(
        _historian(first="PROCESSDATA\t \tdd.MM.yyyy", second="a\tb\tc\tx")
    )
    assert info["tag"] is None and info["time_format"] == "%d.%m.%Y"
    assert info["declared_rows"] is None
    _, info = _historian_header(_historian(first="PROCESSDATA\tFIC1 Data"))  # no time format
    assert info["tag"] == "FIC1" and info["time_format"] is None
    names, _ = _historian_header(_historian(names=" tagname \t PV \tOP"))
    assert names == ["time", "PV", "OP"]


def test_historian_header_errors():
    with pytest.raises(FileError, match="^historian header is incomplete .fewer than 5 lines.$"):
        _historian_header(_historian()[:4])
    with pytest.raises(FileError, match="line 3 should start with 'tagname'"):
        _historian_header(_historian(names="time\tPV\tOP"))
    with pytest.raises(FileError, match="list columns; got 'TagName\\\\tPV'"):
        _historian_header(_historian(names="TagName\tPV"))


def test_java_time_formats():
    assert _time_format("yyyy-MM-dd HH:mm:ss") == "%Y-%m-%d %H:%M:%S"
    assert _time_format("dd/MM/yyyy HH:mm:ss,SSS") == "%d/%m/%Y %H:%M:%S,%f"
    assert _time_format("HH:mm") == "%H:%M"
    assert _time_format("unknown") is None


def _header(lines):
    notes = []
    return (*_delimited_header(lines, notes)[:5], notes)  # without the thousands mark


def test_excel_sep_line_is_obeyed():
    lines = ["sep=;", "time;PV;OP", "0;1,5;2", "1;2,5;3"]
    assert _header(lines) == (";", ",", 1, ["time", "PV", "OP"], 0, ["decimal comma"])
    # a BOM and capitals; the field count is read from the lines after it
    sep, _, header, names, _, notes = _header(["\ufeffSEP=|", "a|b", "1|2", "3|4"])
    assert (sep, header, names, notes) == ("|", 1, ["a", "b"], [])
    # "sep=" alone is not a separator line: the separator is judged from the rows
    sep, _, header, names, _, notes = _header(["sep=", "a,b", "1,2", "3,4"])
    assert (sep, header, names) == (",", 1, ["a", "b"])
    assert notes == ["1 line before the header skipped (titles or comments)"]


def test_skipped_lines_are_counted_from_the_sep_line():
    lines = ["sep=;", "Report", "t;PV", "(s);(m3/h)", "0;1", "1;2"]
    sep, _, header, names, skip, notes = _header(lines)
    assert (sep, header, names, skip) == (";", 2, ["t", "PV"], 1)
    assert notes == [
        "1 line before the header skipped (titles or comments)",
        "1 row after the header skipped (units or descriptions)",
    ]


def test_header_after_titles_and_comments():
    lines = ["Report of FIC1", "# exported", "", "time\tPV\tOP", "0\t1.5\t2", "1\t2.5\t3"]
    sep, decimal, header, names, skip, notes = _header(lines)
    assert (sep, decimal, header, names, skip) == ("\t", ".", 3, ["time", "PV", "OP"], 0)
    assert notes == ["3 lines before the header skipped (titles or comments)"]
    lines = ["\ufefftime,PV", "0,1", "1,2"]
    assert _header(lines)[2:4] == (0, ["time", "PV"])


def test_units_row_and_decimal_marks():
    sep, decimal, header, names, skip, notes = _header(["t;PV", "s;m3/h", "0;1,5", "1;2,5"])
    assert (sep, decimal, header, skip) == (";", ",", 0, 1)
    assert notes == ["decimal comma", "1 row after the header skipped (units or descriptions)"]
    # a date in the first row is data, not units
    assert _header(["t;PV", "17.10.2024 21:55;1,5", "17.10.2024 21:56;2,5"])[4] == 0
    # commas separate: no decimal comma; points win when more fields use them
    assert _header(["a,b", "1,2", "3,4"])[1] == "."
    assert _header(["a\tb", "1.5\t2,5", "3.5\t4"])[1] == "."


def test_headers_that_cannot_be_read():
    with pytest.raises(FileError, match="^first line has no column names .it holds numbers.$"):
        _header(["1,2,3", "4,5,6"])
    with pytest.raises(FileError, match="no header row of 1 columns found in the first lines"):
        _header(["# only", "# comments", ""])


# ---- opening whole files -------------------------------------------------------------------


def test_text_files(tmp_path):
    path = tmp_path / "units.csv"
    path.write_bytes(codecs.BOM_UTF8 + b"t;PV;OP\ns;m3/h;%\n0;1,5;2\n1;2,5;3\n")
    table = open_table(path, "text")
    assert table.names == ["t", "PV", "OP"] and table.info["format"] == "csv"
    assert table.info["notes"] == [
        "decimal comma", "1 row after the header skipped (units or descriptions)"
    ]  # fmt: skip
    frame = table.read([1])  # only the column asked for, numbers with a decimal comma
    assert frame.shape == (2, 1) and frame[1].tolist() == [1.5, 2.5]
    historian = tmp_path / "h.txt"
    historian.write_bytes(
        codecs.BOM_UTF8 + "\r\n".join([*_historian(), "2024-10-17\t1\t2\t3"]).encode()
    )
    assert open_table(historian, "text").info["format"] == "historian"


def test_text_file_longer_than_its_head(tmp_path):
    # 64 KiB are read to find the layout; a byte that is not UTF-8 further on is replaced
    path = tmp_path / "long.csv"
    rows = "".join(f"{i},{i / 10:.1f}\n" for i in range(8000))
    path.write_bytes(b"t,PV\n" + rows.encode() + b"8000,\xe9\n")
    table = open_table(path, "text")
    frame = table.read([0, 1])
    assert len(frame) == 8001 and frame[0].iloc[-1] == 8000
    assert table.info["notes"] == ["bytes that are not utf-8 replaced"]


def test_long_text_file_with_a_decimal_comma(tmp_path):
    # the layout is judged from the head's whole lines, not from its first one alone
    path = tmp_path / "long.csv"
    rows = "".join(f"{i};{i / 10:.1f};{i % 7};ok\n".replace(".", ",") for i in range(8000))
    path.write_bytes(b"t;PV;OP;note\n" + rows.encode() + b"8000;800,0;1;caf\xe9\n")
    table = open_table(path, "text")
    frame = table.read([0, 2])  # after the bytes that are not UTF-8: still two columns
    assert frame.shape == (8001, 2) and frame[2].iloc[:8].tolist() == [0, 1, 2, 3, 4, 5, 6, 0]
    assert table.read([1])[1].iloc[15] == 1.5
    assert table.info["notes"][0] == "decimal comma"


def test_text_files_that_cannot_be_read(tmp_path):
    empty = tmp_path / "empty.csv"
    empty.write_text("  \n")
    with pytest.raises(FileError, match="^file is empty$"):
        open_table(empty, "text")
    header_only = tmp_path / "header.csv"
    header_only.write_text("t,PV\n")
    with pytest.raises(FileError, match="^file has no data rows$"):
        open_table(header_only, "text").read([0, 1])
    ragged = tmp_path / "ragged.csv"
    ragged.write_text('t,PV\n0,1\n1,"2\n')  # a quote never closed
    with pytest.raises(FileError, match="^rows could not be parsed"):
        open_table(ragged, "text").read([0, 1])


def test_workbooks(tmp_path):
    path = tmp_path / "book.xlsx"
    with pd.ExcelWriter(path) as writer:
        pd.DataFrame().to_excel(writer, sheet_name="empty", index=False)
        rows = [["Export of FIC1", None, None], ["time", "PV", "OP"], [0, 1.5, 7], [1, 2.5, 8]]
        pd.DataFrame(rows).to_excel(writer, sheet_name="data", index=False, header=False)
    table = open_table(path, "xlsx")
    assert table.names == ["time", "PV", "OP"]
    assert table.info == {"format": "xlsx", "tag": None, "time_format": None,
                          "declared_rows": None, "sheet": None,
                          "notes": table.info["notes"]}  # fmt: skip
    assert table.info["notes"] == [
        "workbook has 2 sheets: read 'data' only", "1 row above the header skipped"
    ]  # fmt: skip
    frame = table.read([1])
    assert frame.shape == (2, 1) and frame[1].tolist() == [1.5, 2.5]
    single = tmp_path / "single.xlsx"
    pd.DataFrame({"t": [0, 1], "PV": [1, 2]}).to_excel(single, index=False)
    assert open_table(single, "xlsx").info["notes"] == []


def test_a_workbook_is_read_from_the_sheet_with_loop_columns(tmp_path):
    """A cover sheet first: the loop's sheet is found, and the note says which."""
    path = tmp_path / "book.xlsx"
    with pd.ExcelWriter(path) as writer:
        cover = pd.DataFrame({"note": ["exported by the historian"]})
        cover.to_excel(writer, sheet_name="info", index=False)
        pd.DataFrame({"t": [0, 1, 2], "PV": [1.0, 2, 3], "OP": [4.0, 5, 6]}).to_excel(
            writer, sheet_name="data", index=False)  # fmt: skip
    data = read_loop_file(path)
    assert data.meta.loc[0, "status"] == "ok"
    np.testing.assert_array_equal(data.X[0, :, 0], [1, 2, 3])
    assert data.meta.loc[0, "reason"] == (
        "workbook has 2 sheets: read 'data' (the one with loop columns) only")
    # without an accept rule, or when no sheet has a loop: the first sheet with data
    assert open_table(path, "xlsx").names == ["note"]
    assert open_table(path, "xlsx", accept=lambda names: False).names == ["note"]


def test_workbooks_that_cannot_be_read(tmp_path, monkeypatch):
    empty = tmp_path / "empty.xlsx"
    pd.DataFrame().to_excel(empty, index=False)
    with pytest.raises(FileError, match="^workbook holds no data$"):
        open_table(empty, "xlsx")
    numbers = tmp_path / "numbers.xlsx"
    pd.DataFrame([[1, 2], [3, 4]]).to_excel(numbers, index=False, header=False)
    with pytest.raises(FileError, match="^no header row .a row of column names. in the first 50"):
        open_table(numbers, "xlsx")
    broken = tmp_path / "broken.xlsx"
    broken.write_bytes(b"not a zip")
    with pytest.raises(FileError, match="^not a readable Excel workbook .BadZipFile: "):
        open_table(broken, "xlsx")
    monkeypatch.setitem(sys.modules, "openpyxl", None)
    with pytest.raises(FileError, match="^reading xlsx files needs openpyxl: pip install"):
        open_table(empty, "xlsx")


def test_parquet(tmp_path, monkeypatch):
    path = tmp_path / "loop.parquet"
    pd.DataFrame({"t": [0.0, 1.0], "PV": [1.5, 2.5], "OP": [3.0, 4.0]}).to_parquet(path)
    table = open_table(path, "parquet")
    assert table.names == ["t", "PV", "OP"]
    assert table.info == {"format": "parquet", "tag": None, "time_format": None,
                          "declared_rows": None, "notes": []}  # fmt: skip
    frame = table.read([2])
    assert list(frame.columns) == [2] and frame[2].tolist() == [3.0, 4.0]
    broken = tmp_path / "broken.parquet"
    broken.write_bytes(b"PAR1 not really")
    with pytest.raises(FileError, match="^not a readable Parquet file .Arrow"):
        open_table(broken, "parquet")
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    with pytest.raises(FileError, match="^reading parquet files needs pyarrow: pip install"):
        open_table(path, "parquet")


@pytest.mark.parametrize(
    "line",
    ["a,b;c|d\te", "1,,2,", ";x;", "\ufeffname,v", "'q',x", 'a,"b,c",d', '"a";b', "a\0,b", " , "],
)
@pytest.mark.parametrize("sep", [",", ";", "|", "\t"])
def test_fields_as_the_csv_module_splits_them(line, sep):
    assert _fields(line, sep) == next(csv.reader([line], delimiter=sep), [])


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r", "mixed"])
def test_text_file_line_ends(tmp_path, end):
    lines = ["# title", "time,PV,OP", "0,1,2", "", "1,2,3", "2,3,4"]
    ends = ["\r\n", "\n", "\r", "\n", "\r\n", "\n"] if end == "mixed" else [end] * 6
    path = tmp_path / "loop.csv"
    path.write_bytes("".join(a + b for a, b in zip(lines, ends)).encode())
    table = open_table(path, "text")
    assert table.names == ["time", "PV", "OP"]
    assert table.read([0, 1, 2]).values.tolist() == [[0, 1, 2], [1, 2, 3], [2, 3, 4]]
    assert table.info["notes"][:1] == ["1 line before the header skipped (titles or comments)"]


@pytest.mark.parametrize(
    "columns",
    [
        {0: [1.0, np.nan, np.inf], 1: [np.nan, np.nan, 2.0]},
        {0: [1, 2, 3], 1: [np.nan, np.nan, np.nan]},
        {0: [True, False, True], 1: [np.nan, np.nan, 2.0]},
        {0: ["a", None, "c"], 1: [np.nan, np.nan, 2.0]},
        {0: pd.array([1, None, 3], dtype="Int64"), 1: [np.nan, np.nan, 2.0]},
        {0: np.array([1.0, np.nan, 2.0], dtype=np.float32), 1: [np.nan, np.nan, np.nan]},
    ],
)
def test_blank_rows_as_pandas_finds_them(columns):
    frame = pd.DataFrame(columns)
    np.testing.assert_array_equal(_blank_rows(frame), frame.isna().all(axis=1).to_numpy())


@pytest.mark.parametrize(
    ("head", "times", "encoding"),
    [
        # Excel "Unicode text": UTF-16 with BOM, tabs, CRLF
        ("Zeit\tTIC1.PV [°C]\tTIC1.OP [%]", ["27.11.2026 08:00:{:02d}"], "utf-16"),
        ("Zeitstempel;TIC1.PV [°C];TIC1.OP [%]", ["27.11.2026 08:00:{:02d}"], "cp1252"),
        ("Datum;Uhrzeit;TIC1.PV [µS/cm];TIC1.OP [%]", ["27.11.2026", "08:00:{:02d}"], "cp1252"),
    ],
)
def test_german_time_column_names(tmp_path, head, times, encoding):
    sep = "\t" if "\t" in head else ";"
    rows = [sep.join([t.format(2 * i) for t in times] + [f"{50 + i},5", f"{40 - i},25"])
            for i in range(10)]  # fmt: skip
    text = "\r\n".join([head, *rows]) + "\r\n"
    (tmp_path / "loop.csv").write_bytes(text.encode(encoding))
    data = read_loop_file(tmp_path / "loop.csv")
    assert data.meta.loc[0, "status"] == "ok", data.meta.loc[0, "reason"]
    assert data.meta.loc[0, "ts"] == 2.0
    assert data.meta.loc[0, "start"] == pd.Timestamp("2026-11-27 08:00:00")
    np.testing.assert_array_equal(data.X[0, :, 0], 50.5 + np.arange(10))
    np.testing.assert_array_equal(data.X[0, :, 1], 40.25 - np.arange(10))


def _joined(head_a, head_b, n=20):
    """Two exports of one loop joined, each with its header; the second from row 10."""
    rows = [f"2026-11-27 08:00:{i:02d},{50 + i}.5,{40 - i}.25" for i in range(n)]
    return "\n".join([head_a, *rows[:10], head_b, *rows[10:]]) + "\n"


def test_a_repeated_header_is_skipped_and_said(tmp_path):
    (tmp_path / "loop.csv").write_text(_joined("Time,PV,OP", "Time,PV,OP"))
    data = read_loop_file(tmp_path / "loop.csv")
    assert data.meta.loc[0, "status"] == "ok"
    reason = data.meta.loc[0, "reason"]
    assert reason == "1 repeated header row skipped (exports joined)"  # no text value read
    np.testing.assert_array_equal(data.X[0, :, 0], 50.5 + np.arange(20))


def test_a_header_in_another_order_is_an_error_not_swapped_channels(tmp_path):
    # the second export lists OP first: its rows read under the first header had PV and OP
    # swapped from row 11 on, status ok
    (tmp_path / "loop.csv").write_text(_joined("Time,PV,OP", "Time,OP,PV"))
    meta = read_loop_file(tmp_path / "loop.csv").meta
    assert meta.loc[0, "status"] == "error"
    assert meta.loc[0, "reason"].startswith("data row 11 is a header with the columns in "
                                            "another order (['Time', 'OP', 'PV'])")  # fmt: skip


def test_a_long_export_joined_with_its_header_repeated(tmp_path):
    rows = [f"FIC1.{ch},2026-11-27 08:00:{i:02d},{i + c}.5"
            for c, ch in enumerate(["PV", "OP"]) for i in range(20)]  # fmt: skip
    text = "\n".join(["Tag,Timestamp,Value", *rows[:25], "Tag,Timestamp,Value", *rows[25:]])
    (tmp_path / "long.csv").write_text(text + "\n")
    data = read_loop_file(tmp_path / "long.csv")
    assert data.meta.loc[0, "status"] == "ok", data.meta.loc[0, "reason"]
    np.testing.assert_array_equal(data.X[0, :, 1], 1.5 + np.arange(20))


@pytest.mark.parametrize(("ts", "decimals"), [(1.0, 6), (1.0, 5), (10.0, 4), (0.5, 6)])
def test_excel_serial_days_written_with_few_decimals(tmp_path, ts, decimals):
    # a time column in General format: Excel writes what the cell shows; at 6 decimals
    # (86.4 ms steps) 1 s samples were read 1.036 s apart and resampled
    day0 = (pd.Timestamp("2026-11-27 08:00:00") - pd.Timestamp("1899-12-30")).days
    serial = day0 + (8 * 3600 + ts * np.arange(300)) / 86400
    rows = [f"{d:.{decimals}f},{50 + i % 7}.5" for i, d in enumerate(serial)]
    (tmp_path / "loop.csv").write_text("\n".join(["Time,PV", *rows]) + "\n")
    data = read_loop_file(tmp_path / "loop.csv")
    assert data.meta.loc[0, "status"] == "ok", data.meta.loc[0, "reason"]
    assert data.meta.loc[0, "ts"] == ts and data.X.shape == (1, 300, 3)
    np.testing.assert_array_equal(data.X[0, :, 0], 50.5 + np.arange(300) % 7)
    assert f"written to {decimals} decimals" in data.meta.loc[0, "reason"]


def test_excel_serial_days_with_a_gap_keep_their_stamps(tmp_path):
    # a gap of 30 rows: not a regular series whose stamps were rounded, read as before
    day0 = (pd.Timestamp("2026-11-27") - pd.Timestamp("1899-12-30")).days
    serial = day0 + np.delete(np.arange(300), range(100, 130)) / 86400
    rows = [f"{d:.10f},{i % 7}" for i, d in enumerate(serial)]
    (tmp_path / "loop.csv").write_text("\n".join(["Time,PV", *rows]) + "\n")
    data = read_loop_file(tmp_path / "loop.csv")
    assert data.meta.loc[0, "ts"] == 1.0 and data.X.shape == (1, 300, 3)
    assert "written to" not in data.meta.loc[0, "reason"]


def test_excel_serial_days_with_two_decimals_are_days(tmp_path):
    # shown with 2 decimals (14.4 min) most rows share a stamp: still Excel days, and the
    # error gives the stamps' resolution in seconds as it is (it said 0.01 s)
    day0 = (pd.Timestamp("2026-11-27") - pd.Timestamp("1899-12-30")).days
    serial = day0 + (8 * 3600 + np.arange(3000)) / 86400
    rows = [f"{d:.2f},{i % 7}" for i, d in enumerate(serial)]
    (tmp_path / "loop.csv").write_text("\n".join(["Time,PV", *rows]) + "\n")
    meta = read_loop_file(tmp_path / "loop.csv").meta
    assert meta.loc[0, "status"] == "error"
    assert "a resolution of 864 s" in meta.loc[0, "reason"]


def test_summary_rows_above_the_header_are_skipped():
    # a DCS report: minimum, maximum, mean of each column above the header; the first of
    # them had been taken for the header (columns 'Minimum', '54,3', ...: no PV)
    lines = ["Minimum;54,3;7,6", "Maximum;63,6;43,0", "", "Zeit;FIC1.PV;FIC1.OP",
             "27.11.2026 08:00:00;55,1;20,5", "27.11.2026 08:00:01;55,2;20,4"]  # fmt: skip
    sep, decimal, header, names, skip, notes = _header(lines)
    assert (sep, decimal, header, names) == (";", ",", 3, ["Zeit", "FIC1.PV", "FIC1.OP"])
    assert notes[0] == "3 lines before the header skipped (titles or comments)"
    # numbers as column names stay names when no row of names follows
    assert _header(["Time;101;102", "0;1,5;2", "1;2,5;3"])[2:4] == (0, ["Time", "101", "102"])


def test_data_rows_above_the_header_are_an_error_not_titles():
    # two exports joined, the second with a column more: the separator's field count is the
    # second's, so its header was taken and the first export's rows skipped as titles
    first = ["Time,PV,OP"] + [f"2026-11-27 08:00:{i:02d},{i}.5,40" for i in range(5)]
    second = ["Time,PV,OP,MODE"] + [f"2026-11-27 08:01:{i:02d},{i}.5,40,AUTO" for i in range(60)]
    with pytest.raises(FileError, match=r"^5 lines above the header \(line 7\) hold times and "
                       "numbers: exports of other columns joined"):  # fmt: skip
        _header(first + second)
    # a title with a date and a number is a title
    lines = ["Report 27.11.2026 08:00, 2 loops", "Time,PV,OP", "2026-11-27 08:00:00,1.5,40"]
    assert _header(lines)[2] == 1


# ---- decimal mark of ';' files ---------------------------------------------------------------


def _stamped(n, start="2024-04-03 22:00:00"):
    return pd.date_range(start, periods=n, freq="10s").strftime("%d.%m.%Y %H:%M:%S")


@pytest.mark.parametrize("n", [1500, 4000])  # within the first 64 KiB read, and beyond it
def test_decimal_comma_judged_over_the_whole_file(tmp_path, n):
    """A plant down at the start (PV 0, OP 100, integers) and decimal commas later: the
    first 200 rows alone said 'point', and every later value was status text."""
    k = np.arange(n)
    pv = np.where(k < n - 600, 0.0, 40 + (k % 61) / 8)  # exact in binary: 40.000, 40.125
    op = np.where(k < n - 600, 100.0, 50 + (k % 7) / 8)
    fmt = lambda v: f"{v:.0f}" if v.is_integer() else f"{v:.3f}".replace(".", ",")  # noqa: E731
    rows = [f"{s};{fmt(a)};{fmt(b)}" for s, a, b in zip(_stamped(n), pv, op, strict=True)]
    f = tmp_path / "FIC1.csv"
    f.write_text("Zeit;PV;OP\n" + "\n".join(rows) + "\n")
    assert (f.stat().st_size > 1 << 16) == (n == 4000)
    data = read_loop_file(f)
    np.testing.assert_array_equal(data.X[0, :, 0], pv)
    np.testing.assert_array_equal(data.X[0, :, 1], op)
    assert data.meta.loc[0, "reason"].startswith("decimal comma")


@pytest.mark.parametrize("op_text", ["50", "49,875"])
def test_points_grouping_integers_in_a_decimal_comma_file(tmp_path, op_text):
    """German '#.##0' flows (1.019 kg/h is 1019) beside integers below 1000 or an OP with
    decimal commas: before, PV was read 1000 times too small and the OP was lost."""
    text = ("Zeit;FIC1.PV;FIC1.OP;FIC1.SP\n"
            f"03.04.2024 22:00:00;987;{op_text};1.000\n"
            f"03.04.2024 22:00:10;1.019;{op_text};1.000\n"
            f"03.04.2024 22:00:20;1.063;{op_text};1.000\n"
            f"03.04.2024 22:00:30;999;{op_text};1.000\n")  # fmt: skip
    f = tmp_path / "FIC1.csv"
    f.write_text(text)
    data = read_loop_file(f)
    np.testing.assert_array_equal(data.X[0, :, 0], [987, 1019, 1063, 999])
    np.testing.assert_array_equal(data.X[0, :, 1], float(op_text.replace(",", ".")))
    np.testing.assert_array_equal(data.X[0, :, 2], 1000.0)
    assert data.meta.loc[0, "reason"].startswith("decimal comma")


@pytest.mark.parametrize(
    ("rows", "decimal"),
    [
        (["1;0,5;2", "2;0,25;3"], ","),  # decimal commas only
        (["1;0.5;2", "2;0.25;3"], "."),  # decimal points only
        (["1;1.019;987", "2;1.063;999"], "."),  # 1.019 in a column of its own: a point
        (["1;1.019;5", "2;987;6"], ","),  # beside 987: the point groups thousands
        (["1;49,998;50,125", "2;50,000;50,0"], ","),  # three decimals beside a sure comma
        (["1;50,0134;49.998", "2;50,0130;49.999"], ","),  # 49.998 is 49998 there
        (["1;47,903;0", "2;48,371;100"], ","),  # groups of three only: the comma votes
        (["1;1,019.5;2", "2;987.25;3"], "."),  # US grouping with decimals
    ],
)  # fmt: skip
def test_decimal_mark_of_a_file(rows, decimal):
    from sktiction.datasets._readers import _decimal_mark

    assert _decimal_mark(rows, ";")[0] == decimal


# ---- column names with a bare unit -----------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "key"),
    [
        ("OP %", "op"), ("OP%", "op"), ("Output %", "op"), ("PV degC", "pv"), ("PV °C", "pv"),
        ("SP %", "sp"), ("FIC1.PV m3/h", "pv"), ("FIC1.SP kg/h", "sp"), ("TIC1 PV K", "pv"),
        ("Set Point", "sp"), ("Setpoint", "sp"), ("Set-Point", "sp"), ("FIC1 Set Point", "sp"),
        ("Set Point %", "sp"), ("OP (%)", "op"), ("time min", "time"),
        # not channels: a mode, a quality, a level, a name that only ends like a unit
        ("OP_MODE", "mode"), ("PV_QUALITY", None), ("PV QUALITY", None), ("Level %", None),
        ("PV_QUALITY %", None), ("OPs", None), ("SPAN", None), ("%", None),
    ],
)  # fmt: skip
def test_channel_names_with_a_bare_unit(name, key):
    from sktiction.datasets._columns import channel_key

    assert channel_key(name) == key


def test_bare_units_and_set_point_in_a_file(tmp_path):
    f = tmp_path / "FIC1.csv"
    f.write_text("Time,PV degC,OP %,Set Point,OP_MODE,PV_QUALITY\n"
                 "2024-04-03 10:00:00,50.5,40.25,51,1,192\n"
                 "2024-04-03 10:00:10,50.75,40.5,51,1,192\n")  # fmt: skip
    data = read_loop_file(f)
    np.testing.assert_array_equal(data.X[0], [[50.5, 40.25, 51], [50.75, 40.5, 51]])
    assert data.meta.loc[0, "status"] == "ok" and "no OP" not in data.meta.loc[0, "reason"]
