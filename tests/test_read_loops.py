"""read_loops: both file layouts, every kind of bad input, and the shared measured data."""

import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import read_loop_file, read_loops

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
    np.testing.assert_allclose(data.X[0, :, 0], [48.1, 48.2, 48.3, 48.4])  # PV
    np.testing.assert_allclose(data.X[0, :, 1], [9.1, 9.2, 9.3, 9.4])  # OP = MV
    np.testing.assert_allclose(data.X[0, :, 2], [48.0, 48.0, 48.5, 48.5])  # SP = SV
    row = data.meta.iloc[0]
    assert row["tag"] == "2111FIC10201" and row["isa"] == "FIC" and row["loop_type"] == "flow"
    assert row["ts"] == 10.0 and row["n_samples"] == 4 and row["format"] == "historian"
    assert row["auto_fraction"] == 0.75
    assert row["start"] == pd.Timestamp("2024-10-17 21:55:00")
    assert row["status"] == "ok" and row["reason"] == ""
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
    assert text.meta.loc[0, "reason"] == "1 text values in PV read as NaN ('bad' x1)"
    uns = read_loops(write(tmp_path / "uns.csv", "t,pv,op\n0,1,1\n2,2,2\n1,3,3\n"))
    np.testing.assert_array_equal(uns.X[0, :, 0], [1, 3, 2])
    assert uns.meta.loc[0, "reason"] == "rows not in time order (1 steps back): sorted"
    dup = read_loops(write(tmp_path / "dup.csv", "t,pv,op\n0,1,1\n1,2,2\n1,3,3\n2,4,4\n"))
    np.testing.assert_array_equal(dup.X[0, :, 0], [1, 2, 4])  # the first of the pair kept
    assert dup.meta.loc[0, "reason"] == "1 duplicated timestamps: kept the first row of each"


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
    assert "1 text values in PV read as NaN ('x' x1)" in read_loops(g).meta.loc[0, "reason"]
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
