"""read_loops: both file layouts, every kind of bad input, and the shared measured data."""

import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import list_loop_files, read_loop_file, read_loops
from sktiction.datasets._timestamps import TimeError, parse_times, regularise

HEADER = (
    "PROCESSDATA\t{tag} Data\tyyyy-MM-dd HH:mm:ss\r\n"
    "8\t10\t2024-10-17 21:55:00\t{n}\r\n"
    "tagname\t{tag}.MV\t{tag}.PV\t{tag}.SV\t{tag}.MODE\tbOpOFL\tbPvOFL\tbSpOFL\tbAutOFL\r\n"
    "desc\t流量_OP\t流量_PV\t流量_SP\tAut\tbOpOFL\tbPvOFL\tbSpOFL\tbAutOFL\r\n"
    "fsMax=3.19\tfsMin=0\tfsGridNum=10\tfdMax=3.19\tfdMin=0\tfdGridNum=10\tv0GridNum=10\tL=24\r\n"
)


def historian_text(tag="2111FIC10201", rows=None, n=None):
    if rows is None:
        rows = [
            ("2024-10-17 21:55:00", "9.1", "48.1", "48.0", "1"),
            ("2024-10-17 21:55:10", "9.2", "48.2", "48.0", "1"),
            ("2024-10-17 21:55:20", "9.3", "48.3", "48.5", "0"),
            ("2024-10-17 21:55:30", "9.4", "48.4", "48.5", "1"),
        ]
    body = "".join("\t".join(r) + "\t0\t0\t0\t0\r\n" for r in rows)
    return HEADER.format(tag=tag, n=len(rows) if n is None else n) + body


def write(path, text, encoding="utf-8"):
    path.write_bytes(text.encode(encoding))
    return path


def test_historian_file(tmp_path):
    f = write(tmp_path / "a.txt", historian_text())
    data = read_loops(f, return_frames=True)
    assert data.X.shape == (1, 4, 3)
    # the third row is in manual mode (MODE 0): kept, counted in reason (a scan leaves it out)
    np.testing.assert_allclose(data.X[0, :, 0], [48.1, 48.2, 48.3, 48.4])  # PV
    np.testing.assert_allclose(data.X[0, :, 1], [9.1, 9.2, 9.3, 9.4])  # OP = MV
    np.testing.assert_allclose(data.X[0, :, 2], [48.0, 48.0, 48.5, 48.5])  # SP = SV
    row = data.meta.iloc[0]
    assert row["tag"] == "2111FIC10201" and row["isa"] == "FIC" and row["loop_type"] == "flow"
    assert row["ts"] == 10.0 and row["n_samples"] == 4 and row["format"] == "historian"
    assert row["auto_fraction"] == 0.75
    assert row["start"] == pd.Timestamp("2024-10-17 21:55:00")
    assert row["status"] == "ok"
    assert row["reason"] == "1 row in manual mode (MODE 0): a scan reads them as gaps"
    np.testing.assert_allclose(data.frames[0]["time"], [0, 10, 20, 30])


def test_historian_gbk_header_and_declared_rows(tmp_path):
    f = write(tmp_path / "gbk.txt", historian_text(n=9), encoding="gb18030")
    data = read_loops(f)
    assert data.meta.loc[0, "tag"] == "2111FIC10201"
    assert "declares 9 rows" in data.meta.loc[0, "reason"]


def test_csv_file_and_aliases(tmp_path):
    f = write(tmp_path / "chem.csv", "k,t_s,OP,PV\n0,0.0,1.0,2.0\n1,1.0,1.5,2.5\n2,2.0,,3.0\n")
    data = read_loops(f)
    assert data.X.shape == (1, 3, 3)
    np.testing.assert_allclose(data.X[0, :, 0], [2.0, 2.5, 3.0])
    np.testing.assert_array_equal(np.isnan(data.X[0, :, 1]), [False, False, True])  # gap kept
    assert np.isnan(data.X[0, :, 2]).all()  # no SP
    row = data.meta.iloc[0]
    assert row["tag"] == "chem" and row["loop_type"] == "unknown" and row["ts"] == 1.0
    assert row["n_nan"] == 1 and np.isnan(row["auto_fraction"])

    g = write(tmp_path / "x.csv", "Timestamp;LIC7.Y;LIC7.CO;LIC7.Setpoint\n"
              "2024-01-01 00:00:00;1;2;3\n2024-01-01 00:00:05;4;5;6\n")  # fmt: skip
    data = read_loops(g)
    np.testing.assert_allclose(data.X[0], [[1, 2, 3], [4, 5, 6]])
    assert data.meta.loc[0, "ts"] == 5.0


def test_csv_with_byte_order_mark(tmp_path):
    f = write(tmp_path / "bom.csv", "\ufefftime,PV,OP\n0,1,2\n2,3,4\n")
    data = read_loops(f)
    np.testing.assert_allclose(data.X[0, :, :2], [[1, 2], [3, 4]])
    assert data.meta.loc[0, "ts"] == 2.0


def test_wide_quality_columns(tmp_path):
    """A wide file's quality columns blank the values they call not good, as long exports'
    do: a channel's own (text, OPC codes, WinCC Validity whose good code is 1), or the
    row's one Quality column; a Status column with no good value is not a quality."""
    head = "time,FIC1.PV,FIC1.PV Quality,FIC1.OP,FIC1.OP.Q,FIC1.SP,FIC1.SP Validity\n"
    rows = [(0, "Good", 192, 1), (1, "Bad", 192, 1), (2, "Good", 0, 1), (3, "Good", 192, 2)]
    body = "".join(f"{t},{40 + t},{q},{50 + t},{c},45,{v}\n" for t, q, c, v in rows)
    data = read_loops(write(tmp_path / "own.csv", head + body))
    np.testing.assert_array_equal(np.isnan(data.X[0]), [[0, 0, 0], [1, 0, 0], [0, 1, 0],
                                                        [0, 0, 1]])  # fmt: skip
    reason = data.meta.loc[0, "reason"]
    for col in ("FIC1.PV Quality", "FIC1.OP.Q", "FIC1.SP Validity"):
        assert f"1 value of quality other than good read as NaN (column '{col}')" in reason

    body = "".join(f"{t},{40 + t},{50 + t},{q}\n" for t, q, *_ in rows)
    data = read_loops(write(tmp_path / "row.csv", "time,PV,OP,Quality\n" + body))
    np.testing.assert_array_equal(np.isnan(data.X[0, :, :2]).any(1), [0, 1, 0, 0])
    assert data.meta.loc[0, "reason"].count("quality other than good") == 1

    # a bare Q beside a unit-suffixed channel is a flow, not the row's quality; PV's own
    # quality is found past the unit
    flow = [200, 200, 150, 200]  # read as OPC codes, 150 would blank OP's row 2
    body = "".join(f"{t},{40 + t},{q},{50 + t},{f}\n" for (t, q, *_), f in zip(rows, flow))
    data = read_loops(write(tmp_path / "q.csv", "time,PV [m3/h],PV Quality,OP,Q\n" + body))
    np.testing.assert_array_equal(np.isnan(data.X[0, :, :2]).any(1), [0, 1, 0, 0])
    assert "(column 'PV Quality')" in data.meta.loc[0, "reason"]

    body = "".join(f"{t},{40 + t},{50 + t},{m}\n" for t, m in enumerate("AAMA"))
    data = read_loops(write(tmp_path / "mode.csv", "time,PV,OP,Status\n" + body))
    assert not np.isnan(data.X[0, :, :2]).any()
    assert "column 'Status' not used as quality" in data.meta.loc[0, "reason"]


@pytest.mark.parametrize("day, noted", [("2026-10-25", True), ("2026-07-12", False)])
def test_an_hour_twice_in_a_file_sorted_by_local_time(tmp_path, day, noted):
    """Sorted by naive local time across the end of daylight saving time, every stamp of
    01:00-02:00 comes twice: its first pass is kept and the second is a gap of an hour,
    with a note; the same repeats on a July night are only duplicates."""
    t = pd.date_range(f"{day} 00:00", f"{day} 02:59", freq="1min")
    t = t.append(pd.date_range(f"{day} 01:00", f"{day} 01:59", freq="1min")).sort_values()
    x = np.arange(len(t), dtype=float)
    f = tmp_path / "dst.csv"
    pd.DataFrame({"time": t, "PV": x, "OP": 50 + x}).to_csv(f, index=False)
    data = read_loops(f)
    reason = data.meta.loc[0, "reason"]
    assert ("every stamp of " + day + " 01:00-02:00 twice" in reason) is noted
    assert "60 duplicated timestamps: kept the first row of each" in reason
    gap = np.isnan(data.X[0, :, 0])
    assert data.X.shape[1] == (240 if noted else 180) and gap.sum() == (60 if noted else 0)
    if noted:
        assert gap[120:180].all()


def test_a_day_missing_between_two_shifts_keeps_the_longer_one(tmp_path):
    """Hours of 10 s data with a day between them: the longer stretch is read, from its own
    start, and the note says so (a grid over the missing day would be 96 % empty)."""
    times = np.r_[np.arange(200), 8640 + np.arange(300)] * 10.0
    stamps = pd.Timestamp("2024-03-04 06:00") + pd.to_timedelta(times, unit="s")
    lines = [f"{s:%Y-%m-%d %H:%M:%S},{i % 7},{i % 5}" for i, s in enumerate(stamps)]
    f = write(tmp_path / "FIC1.csv", "time,PV,OP\n" + "\n".join(lines) + "\n")
    data = read_loops(f)
    assert data.meta.loc[0, "n_samples"] == 300 and data.meta.loc[0, "ts"] == 10.0
    assert data.meta.loc[0, "start"] == pd.Timestamp("2024-03-05 06:00")
    np.testing.assert_array_equal(data.X[0, :, 0], np.arange(200, 500) % 7)
    assert "kept the longest stretch between time jumps" in data.meta.loc[0, "reason"]


def test_ts_argument_and_channels(tmp_path):
    f = write(tmp_path / "PIC3_run.csv", "level,valve\n1,2\n3,4\n")
    with pytest.raises(ValueError, match="PIC3_run.csv: no PV column"):
        read_loops(f, ts=2)
    with pytest.raises(ValueError, match="cannot determine the sampling time"):
        read_loops(f, channels={"pv": "level"})
    data = read_loops(f, ts=2, channels={"pv": "level", "op": "valve"})
    np.testing.assert_allclose(data.X[0, :, :2], [[1, 2], [3, 4]])
    assert data.meta.loc[0, "ts"] == 2.0 and data.meta.loc[0, "loop_type"] == "pressure"
    with pytest.raises(ValueError, match="channels must be a dict"):
        read_loops(f, channels={"flow": "level"})
    with pytest.raises(ValueError, match="ts must be"):
        read_loops(f, ts=-1)
    with pytest.raises(ValueError, match="on_error"):
        read_loops(f, on_error="ignore")


def test_directory_unequal_lengths(tmp_path):
    write(tmp_path / "a.csv", "t,pv,op\n0,1,1\n1,2,2\n2,3,3\n")
    write(tmp_path / "b.csv", "t,pv,op\n0,1,1\n1,2,2\n")
    write(tmp_path / "index.csv", "file,label\na.csv,stiction\n")
    write(tmp_path / "notes.md", "not data")
    data = read_loops(tmp_path)
    assert data.meta["file"].tolist() == ["a.csv", "b.csv"]
    assert data.X.shape == (2, 3, 3)
    assert np.isnan(data.X[1, 2]).all() and not np.isnan(data.X[1, 1, :2]).any()


@pytest.mark.parametrize(
    ("name", "text", "message", "strict"),
    [
        ("empty.csv", "", "empty", False),
        ("header_only.csv", "t,pv,op\n", "no data rows", False),
        ("nopv.csv", "t,op,sp\n0,1,1\n1,2,2\n", "no PV column", False),
        ("twopv.csv", "t,pv,y,op\n0,1,1,1\n1,2,2,2\n", "several columns could be PV", False),
        ("nonames.csv", "0,1,2\n1,2,3\n", "no column names", False),
        ("badtime.csv", "time,pv\nmonday,1\ntuesday,2\n", "not times", False),
        ("allbad.csv", "t,pv,op\n0,x,1\n1,y,2\n", "PV column 'pv' holds no numbers", False),
        # Repaired by default since issue 8; strict=True keeps rejecting them.
        ("text.csv", "t,pv,op\n0,1,1\n1,bad,2\n", "column 'pv' is not numeric: row 2", True),
        ("unsorted.csv", "t,pv,op\n0,1,1\n2,2,2\n1,3,3\n", "not increasing", True),
        ("dup.csv", "t,pv,op\n0,1,1\n1,2,2\n1,3,3\n", "duplicated", True),
    ],
)
def test_bad_input(tmp_path, name, text, message, strict):
    f = write(tmp_path / name, text)
    with pytest.raises(ValueError, match=f"{name}: .*{message}"):
        read_loops(f, strict=strict)
    data = read_loops([f], on_error="skip", strict=strict)
    assert data.X.shape[0] == 1 and np.isnan(data.X).all()
    assert (
        data.meta.loc[0, "status"] == "error"
        and message.split(":")[0] in data.meta.loc[0, "reason"]
    )
    one = read_loop_file(f, strict=strict)  # the per-file reader never raises
    assert one.X.shape[0] == len(one.meta) == 1 and one.meta.loc[0, "status"] == "error"


def test_repairs_by_default(tmp_path):
    # Three files strict mode rejects above, read with a note instead.
    text = read_loops(write(tmp_path / "text.csv", "t,pv,op\n0,1,1\n1,bad,2\n"))
    np.testing.assert_array_equal(text.X[0, :, 0], [1, np.nan])
    assert text.meta.loc[0, "reason"] == "1 text value in PV read as NaN ('bad' x1)"
    uns = read_loops(write(tmp_path / "uns.csv", "t,pv,op\n0,1,1\n2,2,2\n1,3,3\n"))
    np.testing.assert_array_equal(uns.X[0, :, 0], [1, 3, 2])
    assert uns.meta.loc[0, "reason"] == "rows not in time order (1 step back): sorted"
    dup = read_loops(write(tmp_path / "dup.csv", "t,pv,op\n0,1,1\n1,2,2\n1,3,3\n2,4,4\n"))
    np.testing.assert_array_equal(dup.X[0, :, 0], [1, 2, 4])  # the first of the pair kept
    assert dup.meta.loc[0, "reason"] == "1 duplicated timestamp: kept the first row of each"


def test_bad_historian_rows(tmp_path):
    rows = [
        ("2024-10-17 21:55:10", "9", "48", "48", "1"),
        ("2024-10-17 21:55:00", "9", "48", "48", "1"),
    ]
    f = write(tmp_path / "h.txt", historian_text(rows=rows))
    with pytest.raises(ValueError, match="h.txt: timestamps are not increasing"):
        read_loops(f, strict=True)
    assert read_loops(f).meta.loc[0, "start"] == pd.Timestamp("2024-10-17 21:55")
    rows = [
        ("2024-10-17 21:55:00", "9", "x", "1", "1"),
        ("2024-10-17 21:55:10", "9", "2", "1", "0"),
    ]
    g = write(tmp_path / "g.txt", historian_text(rows=rows))
    with pytest.raises(ValueError, match=r"g.txt: column '2111FIC10201.PV' is not numeric"):
        read_loops(g, strict=True)
    assert "1 text value in PV read as NaN ('x' x1)" in read_loops(g).meta.loc[0, "reason"]
    with pytest.raises(ValueError, match="missing.txt: file does not exist"):
        read_loops(tmp_path / "missing.txt")


def test_skip_keeps_good_files(tmp_path):
    good = write(tmp_path / "good.csv", "t,pv,op\n0,1,1\n1,2,2\n")
    bad = write(tmp_path / "bad.csv", "")
    data = read_loops([bad, good], on_error="skip")
    assert data.meta["status"].tolist() == ["error", "ok"]
    assert data.X.shape == (2, 2, 3) and np.isnan(data.X[0]).all()
    np.testing.assert_allclose(data.X[1, :, 0], [1, 2])


def test_irregular_sampling_is_reported(tmp_path):
    f = write(tmp_path / "gap.csv", "t,pv,op\n0,1,1\n10,2,2\n20,3,3\n40,4,4\n")
    data = read_loops(f)
    assert data.meta.loc[0, "ts"] == 10.0 and "irregular sampling" in data.meta.loc[0, "reason"]


# ---- the shared measured data, when present -------------------------------------------------


def _data_dir():
    env = os.environ.get("SKTICTION_DATA")
    path = Path(env) if env else Path(__file__).resolve().parents[2] / "shared" / "data"
    return path if (path / "plant" / "index.csv").is_file() else None


DATA = _data_dir()
needs_data = pytest.mark.skipif(DATA is None, reason="measured data folder not found")


@needs_data
def test_plant_files():
    index = pd.read_csv(DATA / "plant" / "index.csv")
    data = read_loops(DATA / "plant")
    assert data.X.shape == (47, 751, 3)
    meta = data.meta.merge(index, on="file", suffixes=("", "_index"))
    assert len(meta) == 47 and (meta["status"] == "ok").all()
    assert (meta["tag"] == meta["tag_index"]).all()
    assert (meta["isa"] == meta["loop_type_index"]).all()
    assert (meta["ts"] == 10.0).all() and (meta["n_samples"] == 751).all()
    assert not np.isnan(data.X).any()
    # Channel order against the raw text of one file (first and last data row).
    i = data.meta.index[data.meta["file"] == index.loc[0, "file"]][0]
    lines = (DATA / "plant" / index.loc[0, "file"]).read_text(encoding="utf-8").splitlines()
    for row, line in ((0, lines[5]), (750, lines[-1])):
        _, mv, pv, sv = line.split("\t")[:4]
        np.testing.assert_allclose(data.X[i, row], [float(pv), float(mv), float(sv)])


@needs_data
def test_isdb_files():
    index = pd.read_csv(DATA / "isdb" / "index.csv")
    data = read_loops(DATA / "isdb")
    meta = data.meta.merge(index, on="file", suffixes=("", "_index"))
    assert len(meta) == 9 and (meta["status"] == "ok").all()
    assert (meta["n_samples"] == meta["n_samples_index"]).all()
    np.testing.assert_allclose(meta["ts"], meta["Ts_s"])
    assert data.X.shape == (9, index["n_samples"].max(), 3)
    assert np.isnan(data.X[:, :, 2]).all()  # ISDB has no setpoint
    raw = pd.read_csv(DATA / "isdb" / "chemicals_loop1.csv")
    i = data.meta.index[data.meta["file"] == "chemicals_loop1.csv"][0]
    np.testing.assert_allclose(data.X[i, : len(raw), 0], raw["PV"])
    np.testing.assert_allclose(data.X[i, : len(raw), 1], raw["OP"])


# ---- the tricky exports of tests/data/exports (written by tests/data/make_exports.py) ------

EXPORTS = Path(__file__).resolve().parent / "data" / "exports"
START = pd.Timestamp("2024-10-17 21:55:00")
K = np.arange(12)
PV, OP = 50 + 0.5 * K, 30.0 + K


def read(name, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no pandas dtype or "loss of data" warnings
        data = read_loop_file(EXPORTS / name, **kwargs)
    assert data.X.shape[0] == len(data.meta)
    return data


def ok(name, n_loops=1, **kwargs):
    data = read(name, **kwargs)
    assert (data.meta["status"] == "ok").all(), data.meta["reason"].tolist()
    assert len(data.meta) == n_loops
    return data, data.meta.iloc[0]


def test_exports_nothing_dropped_silently():
    listed = list_loop_files(EXPORTS)
    files = sorted(str(p) for p in EXPORTS.rglob("*") if p.is_file())
    assert sorted(listed["path"]) == files  # every file, sub-folders included
    for row in listed.itertuples():
        if not row.supported:
            assert row.reason, row.path
            continue
        meta = read(row.path).meta
        assert ((meta["status"] == "ok") | (meta["reason"].str.len() > 10)).all(), row.path
    data = read_loops(EXPORTS, on_error="skip")
    assert len(set(data.meta["path"])) + len(data.skipped) == len(files)
    assert set(data.skipped["path"].map(lambda p: Path(p).name)) == {
        "index.csv",
        "legacy.dat",
        "old_workbook.xls",
    }
    assert "site_b" in data.meta.loc[data.meta["file"] == "FIC900.csv", "path"].iloc[0]


def test_export_duplicated_timestamp_keeps_first():
    data, row = ok("historian_duplicate.txt")
    np.testing.assert_allclose(data.X[0, :, 0], PV)  # the second row at 21:55:40 (99) dropped
    np.testing.assert_allclose(data.X[0, :, 1], OP)
    assert row["reason"] == "1 duplicated timestamp: kept the first row of each"
    assert row["ts"] == 10 and row["start"] == START and row["tag"] == "2111FIC10201"
    assert read("historian_duplicate.txt", strict=True).meta.loc[0, "status"] == "error"


def test_export_status_text():
    data, row = ok("historian_status.txt")
    np.testing.assert_array_equal(np.flatnonzero(np.isnan(data.X[0, :, 0])), [2, 3, 5, 7])
    np.testing.assert_array_equal(np.flatnonzero(np.isnan(data.X[0, :, 1])), [8])
    assert row["reason"] == (
        "4 text values in PV read as NaN ('Bad' x1, 'I/O Timeout' x1, 'Shutdown' x1, ...); "
        "1 text value in OP read as NaN ('Calc Failed' x1)"
    )
    assert row["n_nan"] == 5 and row["loop_type"] == "level"
    strict = read("historian_status.txt", strict=True).meta.iloc[0]
    assert strict["status"] == "error" and "'Bad'" in strict["reason"]


def test_export_historian_variants():
    data, row = ok("historian_trailing_tab.txt")
    np.testing.assert_allclose(data.X[0, :, :2], np.column_stack([PV, OP]))
    assert row["reason"] == "" and row["loop_type"] == "pressure"
    data, row = ok("historian_ms.txt")
    assert row["ts"] == 0.5 and row["start"] == START and row["n_samples"] == 12


def test_export_time_order_and_grid():
    data, row = ok("unsorted.csv")
    np.testing.assert_allclose(data.X[0, :, 0], PV)
    assert row["reason"] == "rows not in time order (2 steps back): sorted"
    data, row = ok("irregular.csv")
    # Samples at 0, 9, 20, 29, ... with PV = t / 10 land on the 10-s grid as PV = k;
    # the 40-s hole (110 -> 150 s) leaves grid points 120, 130, 140 s empty.
    assert row["ts"] == 10 and row["n_samples"] == 18
    expected = np.where((np.arange(18) >= 12) & (np.arange(18) <= 14), np.nan, np.arange(18.0))
    np.testing.assert_allclose(data.X[0, :, 0], expected)
    assert "resampled to 18 rows at 10 s" in row["reason"] and "(3 rows)" in row["reason"]


def test_export_text_layouts():
    data, row = ok("blank_rows.csv")
    np.testing.assert_allclose(data.X[0, :, 0], PV)
    assert row["reason"] == "3 blank rows skipped"
    data, row = ok("comments.csv")
    np.testing.assert_allclose(data.X[0], np.column_stack([PV, OP, np.full(12, 50)]))
    assert row["tag"] == "FIC300"
    assert row["reason"] == "3 lines before the header skipped (titles or comments)"
    data, row = ok("european_latin1.csv")
    np.testing.assert_allclose(data.X[0], np.column_stack([PV, OP + 0.25, np.full(12, 50)]))
    assert row["ts"] == 5 and row["start"] == START and row["loop_type"] == "temperature"
    assert row["reason"] == "encoding latin-1; decimal comma"
    data, row = ok("unicode_text.txt")
    np.testing.assert_allclose(data.X[0, :, 1], OP)
    assert row["ts"] == 60 and row["reason"] == "encoding utf-16" and row["tag"] == "LIC5"
    data, row = ok("units_row.csv", ts=None)
    np.testing.assert_allclose(data.X[0, :, 0], PV)
    assert row["ts"] == 1 and "units" in row["reason"]
    data, row = ok("date_and_time.csv")
    assert row["ts"] == 30 and row["start"] == START


def test_export_numeric_times():
    _, row = ok("epoch_ms.csv")
    assert row["start"] == START and row["ts"] == 0.25
    assert row["reason"] == "time read as epoch milliseconds (start 2024-10-17 21:55:00)"
    _, row = ok("epoch_s.csv")
    assert row["start"] == START and row["ts"] == 2
    _, row = ok("epoch_s.csv", time_unit="s")  # the user overrides the guess
    assert pd.isna(row["start"]) and row["ts"] == 2 and row["reason"] == ""
    _, row = ok("excel_serial.csv")
    assert row["start"] == START and row["ts"] == 10
    assert row["reason"].startswith("time read as Excel serial days")


def test_export_wide_file_and_channels():
    data, _ = ok("wide_two_loops.csv", n_loops=2)
    assert data.meta["tag"].tolist() == ["FIC1", "LIC2"]
    assert data.meta["loop_type"].tolist() == ["flow", "level"]
    np.testing.assert_allclose(data.X[1], np.column_stack([20 + K, 70 - K, np.full(12, 20)]))
    np.testing.assert_allclose(data.X[0, :, 0], PV)
    data, row = ok("wide_two_loops.csv", channels={"pv": "LIC2.PV", "op": "LIC2.MV"})
    assert row["tag"] == "LIC2" and np.isnan(data.X[0, :, 2]).all()


def test_export_excel_and_parquet():
    pytest.importorskip("openpyxl")
    data, row = ok("workbook.xlsx")
    assert np.flatnonzero(np.isnan(data.X[0, :, 0])).tolist() == [4]
    assert row["start"] == START and row["ts"] == 10 and row["tag"] == "FIC8"
    assert (
        row["reason"] == "2 rows above the header skipped; 1 text value in PV read as NaN "
        "('Bad' x1)"
    )
    pytest.importorskip("pyarrow")
    data, row = ok("table.parquet")
    np.testing.assert_allclose(data.X[0], np.column_stack([PV, OP, np.full(12, 50)]))
    assert row["start"] == START and row["format"] == "parquet"


def test_export_missing_extras(monkeypatch):
    monkeypatch.setitem(sys.modules, "openpyxl", None)  # import fails as if not installed
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    for name, extra in (("workbook.xlsx", "xlsx"), ("table.parquet", "parquet")):
        row = read(name).meta.iloc[0]
        assert row["status"] == "error" and f"pip install 'sktiction[{extra}]'" in row["reason"]


@pytest.mark.parametrize(
    ("name", "status", "reason"),
    [
        ("empty.csv", "error", "file is empty"),
        ("no_time.csv", "error", "no time column); pass ts="),
        ("no_pv.csv", "error", "name it with channels={'pv': ...}"),
        ("broken.xlsx", "error", "not a readable Excel workbook"),
        ("legacy.dat", "unsupported", "rename it to .csv"),
        ("old_workbook.xls", "unsupported", "save it as .xlsx or CSV"),
        ("index.csv", "unsupported", "folder index"),
    ],
)
def test_export_unreadable_files_say_why(name, status, reason):
    row = read(name).meta.iloc[0]
    assert row["status"] == status and reason in row["reason"]


def test_folder_with_nothing_readable(tmp_path):
    write(tmp_path / "a.dat", "1 2 3\n")
    listed = list_loop_files([tmp_path, tmp_path / "nope"])
    assert listed["supported"].tolist() == [False, False, False]
    assert listed["reason"].iloc[1] == "folder holds no readable loop file (1 file, none readable)"
    assert listed["reason"].iloc[2] == "path does not exist"
    with pytest.raises(ValueError, match="holds no readable loop file"):
        read_loops(tmp_path)
    empty = tmp_path / "empty"
    empty.mkdir()
    assert list_loop_files(empty)["reason"].tolist() == [
        "folder holds no readable loop file (no files)"
    ]


@needs_data
def test_every_shared_data_file_reads_ok():
    listed = list_loop_files(DATA)
    files = sorted(str(p) for p in DATA.rglob("*") if p.is_file())
    assert sorted(listed["path"]) == files
    # Only the folder descriptions are not loops, and each says so.
    skipped = listed.loc[~listed["supported"], "path"].map(lambda p: Path(p).name)
    assert set(skipped) <= {"README.md", "LICENSE", "index.csv"}
    assert listed.loc[~listed["supported"], "reason"].str.len().gt(0).all()
    for path in listed.loc[listed["supported"], "path"]:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            meta = read_loop_file(path).meta
        assert len(meta) == 1 and meta.loc[0, "status"] == "ok", (path, meta.loc[0, "reason"])
        assert meta.loc[0, "reason"] == "", (path, meta.loc[0, "reason"])  # clean files


# ---- time columns ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("values", "seconds", "start", "note"),
    [
        # day > 12 settles the order, in the sample or only later in the column
        (["13/01/2024 10:00:00", "14/01/2024 10:00:00"], [0, 86400], "2024-01-13 10:00", ""),
        ([f"01/{d:02d}/2024 10:00:00" for d in range(1, 20)], [0, 86400], "2024-01-01 10:00", ""),
        (
            ["01/02/2024 10:00:00", "01/03/2024 10:00:00"],
            [0, 29 * 86400],
            "2024-02-01 10:00",
            "dates could be day/month or month/day: read day first",
        ),
        (["17.10.2024 21:55:00", "17.10.2024 21:55:05"], [0, 5], "2024-10-17 21:55", ""),
        (
            ["2024-03-31T01:59:00+01:00", "2024-03-31T03:00:00+02:00"],
            [0, 60],
            "2024-03-31 00:59",
            "time zone offsets converted to UTC",
        ),
        (
            ["2024-01-01 00:00:00.250", "2024-01-01 00:00:00.500"],
            [0, 0.25],
            "2024-01-01 00:00:00.25",
            "",
        ),
        (
            ["23:59:50", "23:59:59.5", "00:00:10"],
            [0, 9.5, 20],
            None,
            "time of day without a date (midnight passes counted)",
        ),
        ([1.7e9, 1.7e9 + 1], [0, 1], "2023-11-14 22:13:20", "time read as epoch seconds"),
        ([0.0, 0.5, 1.0], [0, 0.5, 1.0], None, ""),
    ],
)
def test_parse_times(values, seconds, start, note):
    raw = pd.Series(values, dtype="str" if isinstance(values[0], str) else float)
    t, first, notes = parse_times(raw)
    np.testing.assert_allclose(t[: len(seconds)], seconds)
    assert (pd.isna(first) and start is None) or first == pd.Timestamp(start)
    assert "; ".join(notes).startswith(note) and (note or not notes)


def test_time_errors():
    with pytest.raises(TimeError, match="values are not times"):
        parse_times(pd.Series(["monday", "tuesday"], dtype="str"))
    # a hole 100x the records: the stretch before it is read, and the note says why
    grid, _, _, notes = regularise(np.array([0.0, 1, 2, 3, 500]), np.zeros(5))
    assert grid.tolist() == [0, 1, 2, 3] and "the records span 500 s" in notes[-1]


def test_per_file_reader_does_not_pad(tmp_path):
    k = np.arange(20_000)
    pd.DataFrame({"t": k, "PV": np.sin(k / 50), "OP": np.cos(k / 50)}).to_csv(
        tmp_path / "long.csv", index=False
    )
    write(tmp_path / "short.csv", "t,PV,OP\n0,1,2\n1,2,3\n2,3,4\n")
    shapes = [read_loop_file(p).X.shape for p in sorted(tmp_path.iterdir())]
    assert shapes == [(1, 20_000, 3), (1, 3, 3)]


def test_units_in_column_names(tmp_path):
    f = write(
        tmp_path / "u.csv", "time [ms],FIC1.PV [m3/h],FIC1.OP (%)\n0,1,2\n250,3,4\n500,5,6\n"
    )
    row = read_loop_file(f).meta.iloc[0]
    assert row["tag"] == "FIC1" and row["ts"] == 0.25
    assert row["reason"] == "time in ms (from the column name)"
    g = write(tmp_path / "g.csv", "t_min,PV,OP\n0,1,2\n1,3,4\n2,5,6\n")
    assert read_loop_file(g).meta.loc[0, "ts"] == 60


def test_historian_with_two_tags(tmp_path):
    # One PROCESSDATA export holding two controllers: one loop per tag.
    text = historian_text()
    lines = text.split("\r\n")
    lines[2] += "\tLIC7.MV\tLIC7.PV\tLIC7.SV"
    for i in range(5, 9):
        lines[i] += f"\t{i}\t{10 + i}\t15"
    data = read_loop_file(write(tmp_path / "two.txt", "\r\n".join(lines)))
    assert data.meta["tag"].tolist() == ["2111FIC10201", "LIC7"]
    assert data.meta["loop_type"].tolist() == ["flow", "level"]
    np.testing.assert_allclose(data.X[1], [[10 + i, i, 15] for i in range(5, 9)])
    np.testing.assert_allclose(data.X[0, :, 0], [48.1, 48.2, 48.3, 48.4])
