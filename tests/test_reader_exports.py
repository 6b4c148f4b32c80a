"""Exports seen in plants: US thousands, a Parquet time index, Foxboro and DeltaV names,
timestamps coarser than the rows, month-first dates and the spring DST change."""

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import read_loop_file
from sktiction.datasets._columns import _split


def _times(start, n, step="10s"):
    return pd.date_range(start, periods=n, freq=step)


def _frame(n=60, start="2024-06-03 23:55:00"):
    rng = np.random.default_rng(0)
    return pd.DataFrame({
        "Timestamp": _times(start, n).strftime("%Y-%m-%d %H:%M:%S"),
        "FIC1.PV": 990 + rng.normal(0, 20, n).cumsum() / 5, "FIC1.OP": np.linspace(40, 60, n),
    })  # fmt: skip


def _meta(path, **kw):
    data = read_loop_file(path, **kw)
    return data, data.meta.iloc[0]


# ---- 1. US thousands separators ------------------------------------------------------------


@pytest.mark.parametrize("sep", [",", ";", "\t"])
def test_us_thousands_separators_are_numbers(tmp_path, sep):
    df = _frame()
    plain = df["FIC1.PV"].round(3)
    df["FIC1.PV"] = [f"{v:,.3f}" for v in plain]
    df["FIC1.SP"] = "1,000.0"
    assert (plain > 1000).any() and (plain < 1000).any()
    path = tmp_path / "us.csv"
    df.to_csv(path, sep=sep, index=False)
    data, meta = _meta(path)
    assert meta["status"] == "ok" and meta["n_nan"] == 0
    np.testing.assert_allclose(data.X[0, :, 0], plain)
    np.testing.assert_allclose(data.X[0, :, 2], 1000.0)
    assert "thousands separators" in meta["reason"]


def test_decimal_comma_is_not_read_as_thousands(tmp_path):
    path = tmp_path / "eu.csv"
    path.write_text("t;PV;OP\n0;1,5;1,250\n10;1,6;1,375\n20;1.500,25;1,5\n")
    data, meta = _meta(path)
    np.testing.assert_allclose(data.X[0, :, 0], [1.5, 1.6, 1500.25])
    np.testing.assert_allclose(data.X[0, :, 1], [1.25, 1.375, 1.5])
    # comma-separated with quoted "1,500" only: could be a decimal comma, so not a number
    path = tmp_path / "quoted.csv"
    path.write_text('t,PV,OP\n0,"1,500",1\n10,"1,250",2\n20,"2,000",3\n')
    data, meta = _meta(path)
    assert np.isnan(data.X[0, :, 0]).all()


# ---- 2. Parquet with the time as index -----------------------------------------------------


@pytest.mark.parametrize("name", ["Timestamp", None])
def test_parquet_time_index_is_read_as_a_column(tmp_path, name):
    pytest.importorskip("pyarrow")
    df = _frame()
    df.index = pd.DatetimeIndex(pd.to_datetime(df.pop("Timestamp")), name=name)
    path = tmp_path / "dt.parquet"
    df.to_parquet(path)
    data, meta = _meta(path)
    assert meta["status"] == "ok", meta["reason"]
    assert meta["ts"] == 10.0 and meta["n_samples"] == 60
    assert meta["start"] == pd.Timestamp("2024-06-03 23:55:00")
    np.testing.assert_allclose(data.X[0, :, 0], df["FIC1.PV"])


# ---- 3. historian column names -------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("FIC101.SPT", ("FIC101", "sp")),
        ("LIC101/PID1/PV.CV", ("LIC101/PID1", "pv")),
        ("LIC101/PID1/OUT.CV", ("LIC101/PID1", "op")),
        ("LIC101/PID1/SP.CV", ("LIC101/PID1", "sp")),
        ("FIC101.PV.Value", ("FIC101", "pv")),
        ("FIC101.CV", ("FIC101", "pv")),
        ("FIC101:PV", ("FIC101", "pv")),
        ("FIC101:OP", ("FIC101", "op")),
    ],
)
def test_historian_channel_names(name, expected):
    assert _split(name) == expected


@pytest.mark.parametrize(
    "columns, tag",
    [
        (["Timestamp", "LIC101/PID1/PV.CV", "LIC101/PID1/OUT.CV", "LIC101/PID1/SP.CV"],
         "LIC101/PID1"),  # DeltaV: CV is the value field, not a PV
        (["Timestamp", "PIC1.MEAS", "PIC1.OUT", "PIC1.SPT"], "PIC1"),  # Foxboro's setpoint
    ],
)
def test_historian_exports_make_one_loop_with_its_setpoint(tmp_path, columns, tag):
    df = _frame()
    df["SP"] = 5.0
    df.columns = columns
    path = tmp_path / "export.csv"
    df.to_csv(path, index=False)
    data, meta = _meta(path)
    assert data.X.shape == (1, 60, 3) and meta["tag"] == tag
    np.testing.assert_allclose(data.X[0, :, 2], 5.0)
    assert not np.isnan(data.X).any()


# ---- 4. timestamps coarser than the rows ---------------------------------------------------


def _no_seconds(tmp_path, skip=0, drop=()):
    df = _frame(n=90)
    t = _times("2024-06-03 23:55:00", 90)
    df["Timestamp"] = t.strftime("%d/%m/%Y %H:%M")
    df = df.iloc[skip:].drop(index=list(drop))
    path = tmp_path / "minutes.csv"
    df.to_csv(path, index=False)
    return path, df


def test_coarse_timestamps_read_rows_in_order(tmp_path):
    path, df = _no_seconds(tmp_path)
    data, meta = _meta(path)
    assert meta["status"] == "ok" and meta["ts"] == 10.0 and meta["n_samples"] == 90
    np.testing.assert_allclose(data.X[0, :, 0], df["FIC1.PV"])
    assert "about 6 rows per stamp" in meta["reason"]


def test_coarse_timestamps_partial_first_minute(tmp_path):
    path, df = _no_seconds(tmp_path, skip=3)
    data, meta = _meta(path)
    assert meta["ts"] == 10.0 and meta["n_samples"] == 87
    assert meta["start"] == pd.Timestamp("2024-06-03 23:55:30")


def test_coarse_timestamps_uneven_runs_are_an_error(tmp_path):
    path, _ = _no_seconds(tmp_path, drop=range(20, 24))
    data, meta = _meta(path)
    assert meta["status"] == "error"
    assert "coarser than the rows" in meta["reason"] and "ts=" in meta["reason"]
    data, meta = _meta(path, ts=10)
    assert meta["status"] == "ok" and meta["n_samples"] == 86


def test_rows_exported_twice_are_still_duplicates(tmp_path):
    df = _frame(n=30)
    path = tmp_path / "twice.csv"
    df.loc[df.index.repeat(2)].to_csv(path, index=False)
    data, meta = _meta(path)
    assert meta["n_samples"] == 30 and "duplicated timestamp" in meta["reason"]


# ---- 5. month-first dates ------------------------------------------------------------------


@pytest.mark.parametrize("pattern, order", [("%m/%d/%Y", "month"), ("%d/%m/%Y", "day")])
def test_ambiguous_dates_crossing_midnight_are_read_in_the_order_of_a_regular_axis(
    tmp_path, pattern, order
):
    """Every day <= 12: only midnight tells the orders apart (a month's jump or a day's)."""
    df = _frame()
    df["Timestamp"] = _times("2024-06-03 23:55:00", 60).strftime(f"{pattern} %H:%M:%S")
    path = tmp_path / "dates.csv"
    df.to_csv(path, index=False)
    _, meta = _meta(path)
    assert meta["status"] == "ok" and meta["ts"] == 10.0 and meta["n_samples"] == 60
    assert meta["start"] == pd.Timestamp("2024-06-03 23:55:00")
    assert f"read {order} first" in meta["reason"]


# ---- 6. spring-forward DST change ----------------------------------------------------------


def _dst(tmp_path, day):
    t = _times(f"{day} 01:50:00", 100)
    t = t.where(t < pd.Timestamp(f"{day} 02:00:00"), t + pd.Timedelta(hours=1))
    df = _frame(n=100)
    df["Timestamp"] = t.strftime("%Y-%m-%d %H:%M:%S")
    path = tmp_path / "dst.csv"
    df.to_csv(path, index=False)
    return path


@pytest.mark.parametrize("day", ["2024-03-31", "2024-03-10", "2024-10-06"])
def test_spring_forward_is_not_a_gap(tmp_path, day):
    data, meta = _meta(_dst(tmp_path, day))
    assert meta["status"] == "ok" and meta["n_samples"] == 100
    assert not np.isnan(data.X[0, :, 0]).any()
    assert "clock set forward an hour" in meta["reason"]


def test_hour_missing_on_a_weekday_stays_a_gap(tmp_path):
    _, meta = _meta(_dst(tmp_path, "2024-03-28"))  # a Thursday: data really missing
    assert "clock set forward" not in meta["reason"]
    # an hour of 10 s rows missing from 1,000 s of data: the 60 rows before it are read
    assert meta["status"] == "ok" and meta["n_samples"] == 60
    assert "kept the longest stretch between time jumps" in meta["reason"]


def test_an_hour_missing_off_the_clock_hour_on_a_spring_sunday_stays_a_gap(tmp_path):
    """01:25 -> 02:25 skips no whole hour of the clock's face: an outage, not DST."""
    t = _times("2024-04-14 01:15:00", 100)
    t = t.where(t < pd.Timestamp("2024-04-14 01:25:00"), t + pd.Timedelta(hours=1))
    df = _frame(n=100)
    df["Timestamp"] = t.strftime("%Y-%m-%d %H:%M:%S")
    df.to_csv(tmp_path / "outage.csv", index=False)
    _, meta = _meta(tmp_path / "outage.csv")
    assert "clock set forward" not in meta["reason"]


def test_an_op_written_as_a_fraction_of_travel_is_noted(tmp_path):
    """Sizes are in OP's units: an OP of 0-1 makes a 0.6 % band read 0.006."""
    t = np.arange(300)
    op = 0.5 + 0.1 * np.sin(t / 10)
    pd.DataFrame({"t": t, "PV": 20 + op, "OP": op}).to_csv(tmp_path / "frac.csv", index=False)
    pd.DataFrame({"t": t, "PV": 20 + op, "OP": 100 * op}).to_csv(tmp_path / "pct.csv",
                                                                 index=False)
    assert "OP stays within 0-1" in read_loop_file(tmp_path / "frac.csv").meta.loc[0, "reason"]
    assert "0-1" not in read_loop_file(tmp_path / "pct.csv").meta.loc[0, "reason"]


# ---- decimal commas where the file's mark is a point; US thousands on integers -------------


def test_quoted_decimal_commas_say_what_they_are(tmp_path):
    """Before: 'PV column holds no numbers; 3 text values ...', never 'decimal comma'."""
    path = tmp_path / "FIC1.csv"
    path.write_text('Time,PV,OP\n2024-04-03 10:00:00,"50,036","49,5"\n'
                    '2024-04-03 10:00:10,"50,125","49,75"\n')  # fmt: skip
    data, meta = _meta(path)
    assert meta["status"] == "error" and np.isnan(data.X).all()
    assert meta["reason"].startswith(
        "PV column 'PV' holds no numbers; text values such as '50,036' look like numbers "
        "with a decimal comma, in a file whose decimal mark is a point: export the file "
        "with ';' between the columns"
    )


def test_text_cells_with_decimal_commas_in_a_workbook_say_what_they_are(tmp_path):
    pytest.importorskip("openpyxl")
    path = tmp_path / "FIC1.xlsx"
    pd.DataFrame({"Zeit": _times("2024-04-03 10:00", 3), "PV": ["50,036", "50,125", "50,5"],
                  "OP": [40.5, 41.0, 41.5]}).to_excel(path, index=False)  # fmt: skip
    _, meta = _meta(path)
    assert meta["status"] == "error"
    assert "text values such as '50,036' look like numbers with a decimal comma" in meta["reason"]
    assert "make the cells numbers" in meta["reason"]


def test_a_status_word_is_no_decimal_comma(tmp_path):
    path = tmp_path / "FIC1.csv"
    path.write_text("t,PV,OP\n0,Bad,1\n10,2.5,2\n20,\"1,5\",3\n30,Bad,4\n")
    _, meta = _meta(path)
    assert "decimal comma" not in meta["reason"]


@pytest.mark.parametrize(
    ("pv", "other", "read"),
    [
        # 1,019 beside 987 in the column: 1.019 would be a thousandfold jump
        (['"987"', '"1,019"', '"1,063"'], "49.875", [987, 1019, 1063]),
        # only 1,019 in the column, but 1,810.25 elsewhere shows the file's US grouping
        (['"1,019"', '"1,020"', '"1,063"'], '"1,810.25"', [1019, 1020, 1063]),
    ],
)  # fmt: skip
def test_us_thousands_on_integers(tmp_path, pv, other, read):
    path = tmp_path / "FIC1.csv"
    path.write_text("Time,PV,OP\n" + "".join(
        f"2024-04-03 10:00:{10 * i:02d},{v},{other}\n" for i, v in enumerate(pv)))  # fmt: skip
    data, meta = _meta(path)
    np.testing.assert_array_equal(data.X[0, :, 0], read)
    assert "thousands separators ',' in 'PV' removed" in meta["reason"]
    assert meta["n_nan"] == 0
