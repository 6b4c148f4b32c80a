"""Long exports (a row per tag and time) read as the same loops as the wide layout."""

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import make_loops, read_loop_file
from sktiction.datasets._long import long_columns

START = pd.Timestamp("2026-01-05 08:00")


def _wide_and_rows(n=300, ts=10.0, seed=0):
    """Two simulated loops as a wide table and as long rows, same values."""
    X, _ = make_loops(2, n_samples=n, random_state=seed)
    stamps = (START + pd.to_timedelta(np.arange(n) * ts, unit="s")).strftime("%Y-%m-%d %H:%M:%S")
    wide = pd.DataFrame({"time": stamps})
    rows = []
    for j, tag in enumerate(["FIC101", "LIC7"]):
        for c, ch in enumerate(["PV", "OP", "SP"]):
            wide[f"{tag}.{ch}"] = X[j, :, c]
            rows.append(pd.DataFrame({"Tag": tag, "Parameter": ch, "Timestamp": stamps,
                                      "Value": X[j, :, c]}))  # fmt: skip
    return X, wide, pd.concat(rows, ignore_index=True)


def test_long_rows_in_any_order_read_as_the_wide_file(tmp_path):
    X, wide, rows = _wide_and_rows()
    wide.to_csv(tmp_path / "wide.csv", index=False)
    rows.sample(frac=1, random_state=1).to_csv(tmp_path / "long.csv", index=False)
    a, b = read_loop_file(tmp_path / "wide.csv"), read_loop_file(tmp_path / "long.csv")
    np.testing.assert_array_equal(b.X, a.X)
    np.testing.assert_array_equal(b.X, X)  # CSV keeps every digit of a float
    assert b.meta["tag"].tolist() == ["FIC101", "LIC7"]
    assert (b.meta["ts"] == 10.0).all() and (b.meta["start"] == START).all()
    assert "6 tags pivoted to columns; shared times" in b.meta.loc[0, "reason"]


def test_tag_with_parameter_glued_and_separate_give_the_same_loop(tmp_path):
    _, _, rows = _wide_and_rows()
    glued = rows.assign(Tag=rows["Tag"] + "." + rows["Parameter"]).drop(columns="Parameter")
    rows.to_csv(tmp_path / "a.csv", index=False)
    glued.to_csv(tmp_path / "b.csv", index=False)
    np.testing.assert_array_equal(
        read_loop_file(tmp_path / "a.csv").X, read_loop_file(tmp_path / "b.csv").X
    )


def _recorded(seed=0, n=600, ts=5.0):
    """A compressed export: each tag written only at some scans, each at its own times."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * ts
    truth = {"PV": np.sin(t / 100), "OP": 50 + 10 * np.cos(t / 70)}
    rows, records = [], {}
    for name, v in truth.items():
        k = np.union1d(rng.choice(n, n // 3, replace=False), [0, n - 1])
        k = np.union1d(k, np.minimum(k + 1, n - 1))  # consecutive scans while moving
        records[name] = (t[k], v[k])
        rows.append(pd.DataFrame({"TagName": "TIC5." + name,
                                  "TimeStamp": (START + pd.to_timedelta(t[k], unit="s")),
                                  "Value": v[k].astype(object), "Quality": "Good"}))  # fmt: skip
    return t, records, pd.concat(rows, ignore_index=True)


def _hold(grid, t, v):
    """The last record at or before each grid time."""
    return v[np.searchsorted(t, grid, side="right") - 1]


def test_own_times_held_at_each_tags_last_record(tmp_path):
    t, records, rows = _recorded()
    rows.to_csv(tmp_path / "rec.csv", index=False)
    data = read_loop_file(tmp_path / "rec.csv")
    assert data.meta.loc[0, "ts"] == 5.0  # the scan period, not the mean record interval
    assert data.X.shape == (1, len(t), 3)
    for c, name in enumerate(["PV", "OP"]):
        np.testing.assert_array_equal(data.X[0, :, c], _hold(t, *records[name]))
    reason = data.meta.loc[0, "reason"]
    assert "each held at its last record on a 5 s grid" in reason


def test_bad_records_stay_gaps_until_the_next_record(tmp_path):
    t, records, rows = _recorded()
    pv = np.flatnonzero(rows["TagName"] == "TIC5.PV")
    rows.loc[pv[10], "Value"] = "I/O Timeout"
    rows.loc[pv[20], "Quality"] = "Bad"
    rows.to_csv(tmp_path / "rec.csv", index=False)
    data = read_loop_file(tmp_path / "rec.csv")
    reason = data.meta.loc[0, "reason"]
    assert "'I/O Timeout' x1" in reason and "1 value of quality other than good" in reason
    pv_t = records["PV"][0]
    for i in (10, 20):
        gap = (t >= pv_t[i]) & (t < pv_t[i + 1])
        assert np.isnan(data.X[0, gap, 0]).all()
        assert np.isfinite(data.X[0, (t >= pv_t[i - 1]) & (t < pv_t[i]), 0]).all()
    assert np.isfinite(data.X[0, :, 1]).all()  # OP has no bad record


def test_ts_sets_the_grid_of_recorded_tags(tmp_path):
    t, records, rows = _recorded()
    rows.to_csv(tmp_path / "rec.csv", index=False)
    data = read_loop_file(tmp_path / "rec.csv", ts=15)
    grid = np.arange(0, t[-1] + 1e-9, 15.0)
    assert data.X.shape[1] == grid.size
    np.testing.assert_array_equal(data.X[0, :, 1], _hold(grid, *records["OP"]))


def test_compressed_records_keep_the_scan_period_and_look_held(tmp_path):
    """A deadband keeps a tenth of the scans; records fall on whole seconds: the grid is
    the 1 s scan, and the record between them is held (the compression check's look), not
    a straight line (which healthy compressed loops had made look sticky)."""
    X, _ = make_loops(1, n_samples=2000, random_state=3)
    x = X[0]
    stamps = START + pd.to_timedelta(np.arange(2000), unit="s")
    rows = []
    for c, name in enumerate(["PV", "OP"]):
        keep, last = [0], x[0, c]
        for i in range(1, 2000):
            if abs(x[i, c] - last) > 1.5 * np.std(x[:, c]):
                keep.append(i)
                last = x[i, c]
        keep = np.unique(keep + [1999])
        rows.append(pd.DataFrame({"Tag": f"FIC3.{name}", "Timestamp": stamps[keep],
                                  "Value": x[keep, c]}))  # fmt: skip
        assert np.diff(keep).min() == 1 and np.median(np.diff(keep)) > 3
    pd.concat(rows).to_csv(tmp_path / "deadband.csv", index=False)
    data = read_loop_file(tmp_path / "deadband.csv")
    assert data.meta.loc[0, "ts"] == 1.0 and data.X.shape[1] == 2000
    held = np.mean(np.diff(data.X[0, :, 0]) == 0)
    assert held > 0.5


def test_a_stray_early_record_does_not_stretch_the_grid(tmp_path):
    """A setpoint last written a month earlier (compression: it has not moved since)."""
    _, _, rows = _wide_and_rows(n=100)
    rows = rows[rows["Tag"] == "FIC101"]
    sp = rows[rows["Parameter"] == "SP"].iloc[[0]]
    sp = sp.assign(Timestamp=str(START - pd.Timedelta(days=30)), Value=42.0)
    rows = pd.concat([rows[rows["Parameter"] != "SP"], sp])
    rows.to_csv(tmp_path / "stray.csv", index=False)
    data = read_loop_file(tmp_path / "stray.csv")
    assert data.X.shape == (1, 100, 3) and data.meta.loc[0, "start"] == START
    assert (data.X[0, :, 2] == 42.0).all()  # held from its record
    assert "set only the values held" in data.meta.loc[0, "reason"]


def test_mode_tags_quality_codes_and_odd_time_names(tmp_path):
    _, _, rows = _wide_and_rows(n=60)
    rows = rows[rows["Tag"] == "FIC101"].rename(columns={"Timestamp": "TIME_STAMP"})
    mode = rows[rows["Parameter"] == "PV"].assign(Parameter="MODE", Value="AUTO")
    mode.iloc[40:, mode.columns.get_loc("Value")] = "MAN"
    rows = pd.concat([rows, mode]).assign(Quality=192)
    rows.iloc[5, rows.columns.get_loc("Quality")] = 0  # OPC: bad
    rows.to_csv(tmp_path / "mode.csv", index=False)
    data = read_loop_file(tmp_path / "mode.csv")
    meta = data.meta.loc[0]
    assert meta["status"] == "ok" and meta["auto_fraction"] == pytest.approx(40 / 60)
    assert "20 rows in manual mode" in meta["reason"]
    assert "1 value of quality other than good" in meta["reason"]
    assert np.isnan(data.X[0, 5, 0]) and np.isfinite(data.X[0, :5, 0]).all()


def test_naive_local_time_over_the_autumn_clock_change(tmp_path):
    """Each tag's rows are in time order: the repeated hour is read as in a wide file."""
    t = pd.date_range("2025-10-26 01:30", periods=40, freq="5min")  # UTC-free local clock
    local = t.where(t < pd.Timestamp("2025-10-26 03:00"), t - pd.Timedelta(hours=1))
    stamps = local.strftime("%Y-%m-%d %H:%M:%S")
    rows = pd.concat([pd.DataFrame({"Tag": f"FIC1.{c}", "Timestamp": stamps,
                                    "Value": np.arange(40.0) + j})
                      for j, c in enumerate(["PV", "OP"])])  # fmt: skip
    rows.to_csv(tmp_path / "dst.csv", index=False)
    data = read_loop_file(tmp_path / "dst.csv")
    assert data.X.shape == (1, 40, 3)
    np.testing.assert_array_equal(data.X[0, :, 0], np.arange(40.0))
    assert "clock set back an hour" in data.meta.loc[0, "reason"]


def test_repeated_tag_and_time_keeps_the_last_or_fails_strict(tmp_path):
    _, _, rows = _wide_and_rows(n=50)
    fix = rows.iloc[[3]].assign(Value=123.0)  # a later correction of one value
    pd.concat([rows, fix]).to_csv(tmp_path / "dup.csv", index=False)
    data = read_loop_file(tmp_path / "dup.csv")
    assert data.X[0, 3, 0] == 123.0
    assert "1 repeated tag and time: kept the last" in data.meta.loc[0, "reason"]
    strict = read_loop_file(tmp_path / "dup.csv", strict=True).meta
    assert strict.loc[0, "status"] == "error" and "more than once" in strict.loc[0, "reason"]


def test_unmatched_tags_say_so_and_channels_name_them(tmp_path):
    _, _, rows = _wide_and_rows(n=60)
    rows = rows[rows["Tag"] == "FIC101"]
    rows = rows.assign(Tag=rows["Parameter"].map({"PV": "FT101", "OP": "FY101", "SP": "FS101"}))
    rows.drop(columns="Parameter").to_csv(tmp_path / "odd.csv", index=False)
    meta = read_loop_file(tmp_path / "odd.csv").meta
    assert meta.loc[0, "status"] == "error"
    assert meta.loc[0, "reason"].startswith("long layout (a row per tag and time) pivoted")
    assert "'FT101'" in meta.loc[0, "reason"]  # the tags the user can name
    named = read_loop_file(tmp_path / "odd.csv", channels={"pv": "FT101", "op": "FY101"})
    assert named.meta.loc[0, "status"] == "ok"
    assert np.isfinite(named.X[0, :, :2]).all() and np.isnan(named.X[0, :, 2]).all()


def test_times_of_day_without_dates_are_refused(tmp_path):
    _, _, rows = _wide_and_rows(n=40)
    rows.assign(Timestamp=rows["Timestamp"].str[-8:]).to_csv(tmp_path / "tod.csv", index=False)
    meta = read_loop_file(tmp_path / "tod.csv").meta
    assert meta.loc[0, "status"] == "error"
    assert "times of day but no dates" in meta.loc[0, "reason"]


@pytest.mark.parametrize(
    "names, found",
    [
        (["Tag", "Timestamp", "Value"], (1, 0, 2)),
        (["NAME", "IP_TREND_TIME", "IP_TREND_VALUE", "IP_TREND_QSTATUS"], (1, 0, 2)),
        (["TagName", "Parameter", "TimeStamp", "Value", "Confidence"], (2, 0, 3)),
        (["time", "FIC1.PV", "FIC1.OP"], None),  # wide
        (["Tag", "Value"], None),  # no time
        (["Tag", "Time", "Timestamp", "Value"], None),  # two times: ask, do not guess
        (["Tag", "Time", "Date", "Value"], (1, 0, 3)),  # a date and a time of day: joined
        (["VarName", "TimeString", "VarValue", "Validity", "Time_ms"], (1, 0, 2)),  # WinCC
        (["Element", "Attribute", "Name", "DateTime UTC", "Value", "Average"], (3, 0, 4)),
        (["NAME", "TS", "VALUE"], (1, 0, 2)),  # IP.21 SQLplus
    ],
)
def test_long_columns_found_by_name(names, found):
    from sktiction.datasets._columns import _is_time

    cols = long_columns(names, _is_time)
    if found is None:
        assert cols is None
    else:
        assert (cols["time"], cols["tag"], cols["value"]) == found


def test_a_workbook_with_a_sheet_per_loop_gives_every_loop(tmp_path):
    """Every sheet with loop columns is read (a sheet per loop is a common way to gather
    loops); shorter loops are NaN-padded at the end; a sheet that cannot be read is named
    in the others' reasons, and gets an error row only when no sheet could be read."""
    X, _, _ = _wide_and_rows(n=120)
    path = tmp_path / "unit3.xlsx"
    with pd.ExcelWriter(path) as writer:
        cover = pd.DataFrame({"note": ["exported for the audit"]})
        cover.to_excel(writer, sheet_name="cover", index=False)
        for j, (name, n) in enumerate([("FIC101", 120), ("LIC2", 80)]):
            sheet = pd.DataFrame({"time": np.arange(n) * 5.0, "PV": X[j, :n, 0],
                                  "OP": X[j, :n, 1], "SP": X[j, :n, 2]})  # fmt: skip
            sheet.to_excel(writer, sheet_name=name, index=False)
        bad = pd.DataFrame({"time": ["soon"] * 5, "PV": np.arange(5.0), "OP": np.ones(5)})
        bad.to_excel(writer, sheet_name="bad", index=False)
    data = read_loop_file(path)
    meta = data.meta
    assert meta["tag"].tolist() == ["FIC101", "LIC2"]
    assert meta["status"].tolist() == ["ok", "ok"]
    assert meta["n_samples"].tolist() == [120, 80]
    assert data.X.shape == (2, 120, 3)
    np.testing.assert_allclose(data.X[0], X[0], rtol=1e-14)  # Excel keeps 15 digits
    np.testing.assert_allclose(data.X[1, :80], X[1, :80], rtol=1e-14)
    assert np.isnan(data.X[1, 80:]).all()
    assert meta.loc[0, "reason"].startswith(
        "sheet 'FIC101'; workbook has 4 sheets: read 'FIC101', 'LIC2', 'bad' (those with "
        "loop columns) only; sheet 'bad' not read: "
    )
    from sktiction.datasets import read_loops

    assert len(read_loops([path]).meta) == 2  # on_error="raise" has nothing to raise
    only_bad = tmp_path / "bad.xlsx"
    with pd.ExcelWriter(only_bad) as writer:
        bad.to_excel(writer, sheet_name="bad", index=False)
        bad.to_excel(writer, sheet_name="worse", index=False)
    meta = read_loop_file(only_bad).meta
    assert meta["status"].tolist() == ["error", "error"]
    assert meta["format"].tolist() == ["xlsx", "xlsx"]
    assert meta.loc[1, "reason"].startswith("sheet 'worse': ")


def test_relative_seconds_odd_names_unused_columns_and_rows_without_a_tag(tmp_path):
    """Numeric times from 0 (no date), a time column named by ``channels``, a unit
    column left out with a note, rows without a tag or time skipped and counted."""
    rows = pd.DataFrame({"Tag Name": ["A.PV", "A.OP"] * 50 + [None, "A.PV"],
                         "When": list(np.repeat(np.arange(50) * 2.0, 2)) + [200.0, "soon"],
                         "Value": np.arange(102.0), "Units": "%"})  # fmt: skip
    rows.to_csv(tmp_path / "rel.csv", index=False)
    assert read_loop_file(tmp_path / "rel.csv").meta.loc[0, "status"] == "error"  # no time
    data = read_loop_file(tmp_path / "rel.csv", channels={"time": "When"})
    meta = data.meta.loc[0]
    assert meta["status"] == "ok" and meta["ts"] == 2.0 and pd.isna(meta["start"])
    np.testing.assert_array_equal(data.X[0, :, 0], np.arange(0.0, 100, 2))
    np.testing.assert_array_equal(data.X[0, :, 1], np.arange(1.0, 100, 2))
    assert "2 rows without a tag or a readable time skipped" in meta["reason"]
    assert "columns ['Units'] not used" in meta["reason"]


def test_a_grid_too_fine_for_its_span_is_refused_with_advice(tmp_path):
    """30 records 1 ms apart, then one a day for a year, in every tag (a lone pair of
    close records does not set the step: see the stray-record test)."""
    t = np.r_[np.arange(30) * 0.001, np.arange(1, 366) * 86400.0]
    rows = pd.concat([pd.DataFrame({"Tag": f"A.{c}", "Time": t + j * 0.0005, "Value": t})
                      for j, c in enumerate(["PV", "OP"])])  # fmt: skip
    rows.to_csv(tmp_path / "sparse.csv", index=False)
    meta = read_loop_file(tmp_path / "sparse.csv").meta.loc[0]
    assert meta["status"] == "error" and "is too large; pass ts=" in meta["reason"]
    assert read_loop_file(tmp_path / "sparse.csv", ts=3600).meta.loc[0, "status"] == "ok"


def test_a_time_column_before_each_tag_is_read_as_a_long_export(tmp_path):
    """PI DataLink's compressed data: each tag with its own times, the shorter padded."""
    t, records, _ = _recorded()
    (tp, vp), (to, vo) = records["PV"], records["OP"]
    n = max(len(tp), len(to))

    def column(x):
        return pd.Series(x).reindex(range(n))

    stamps = [column((START + pd.to_timedelta(x, unit="s")).astype(str)) for x in (tp, to)]
    wide = pd.DataFrame({0: stamps[0], 1: column(vp), 2: stamps[1], 3: column(vo)})
    wide.columns = ["Timestamp", "TIC5.PV", "Timestamp", "TIC5.OP"]
    wide.to_csv(tmp_path / "datalink.csv", index=False)
    data = read_loop_file(tmp_path / "datalink.csv")
    assert data.meta.loc[0, "status"] == "ok" and data.meta.loc[0, "ts"] == 5.0
    np.testing.assert_array_equal(data.X[0, :, 0], _hold(t, tp, vp))
    np.testing.assert_array_equal(data.X[0, :, 1], _hold(t, to, vo))
    assert "a time column before each tag (2 tags)" in data.meta.loc[0, "reason"]


def test_workbook_time_of_day_cells_are_read_as_a_csv_reads_them(tmp_path):
    """Excel gives time-only cells as datetime.time; midnight passes are counted."""
    import datetime

    first = datetime.datetime(2026, 1, 1, 23, 30)
    times = [(first + datetime.timedelta(seconds=10 * i)).time() for i in range(400)]
    sheet = pd.DataFrame({"Time": times, "PV": np.sin(np.arange(400) / 5.0),
                          "OP": np.cos(np.arange(400) / 5.0)})  # fmt: skip
    sheet.to_excel(tmp_path / "tod.xlsx", index=False)
    meta = read_loop_file(tmp_path / "tod.xlsx").meta.loc[0]
    assert (meta["status"], meta["ts"], meta["n_samples"]) == ("ok", 10.0, 400)
    assert "midnight passes counted" in meta["reason"]


def test_the_grid_survives_a_stray_record_and_tags_agree_on_the_date_order(tmp_path):
    """A record 1 ms after another does not make a 1 ms grid; a tag with five records
    (whose dates allow either order) is read in the other tag's month-first order."""
    t, records, rows = _recorded()
    extra = rows.iloc[[3]].assign(TimeStamp=rows["TimeStamp"].iloc[3] + pd.Timedelta("1ms"))
    pd.concat([rows, extra]).to_csv(tmp_path / "stray.csv", index=False)
    assert read_loop_file(tmp_path / "stray.csv").meta.loc[0, "ts"] == 5.0
    hours = pd.date_range("2026-01-01", periods=200, freq="h")
    few = [0, 30, 90, 150, 199]
    rows = pd.concat([
        pd.DataFrame({"Tag": "F1.PV", "Time": hours.strftime("%m/%d/%Y %H:%M"),
                      "Value": np.arange(200.0)}),
        pd.DataFrame({"Tag": "F1.OP", "Time": hours[few].strftime("%m/%d/%Y %H:%M"),
                      "Value": np.array(few, dtype=float)}),
    ])  # fmt: skip
    rows.to_csv(tmp_path / "dates.csv", index=False)
    data = read_loop_file(tmp_path / "dates.csv")
    assert data.X.shape == (1, 200, 3)
    np.testing.assert_array_equal(data.X[0, few, 1], few)


def test_a_questionable_flag_and_a_tag_that_stops_early(tmp_path):
    t, records, rows = _recorded()
    rows = rows.drop(columns="Quality").assign(Questionable=False)
    pv = np.flatnonzero(rows["TagName"] == "TIC5.PV")
    rows.iloc[pv[10], rows.columns.get_loc("Questionable")] = True
    early = rows["TimeStamp"] < START + pd.Timedelta("1000s")
    rows = rows[(rows["TagName"] == "TIC5.PV") | early]  # OP's export cut at 1000 s
    rows.to_csv(tmp_path / "flags.csv", index=False)
    data = read_loop_file(tmp_path / "flags.csv")
    reason = data.meta.loc[0, "reason"]
    assert "1 value of quality other than good read as NaN (column 'Questionable')" in reason
    assert np.isnan(data.X[0, t == records["PV"][0][10], 0]).all()
    assert "TIC5.OP has no record for" in reason


def test_time_unit_reaches_a_long_exports_times(tmp_path):
    ms = 1.7e12 + 1000.0 * np.arange(50)  # epoch milliseconds, unless told otherwise
    rows = pd.concat([pd.DataFrame({"Tag": f"A.{c}", "Time": ms, "Value": np.arange(50.0)})
                      for c in ("PV", "OP")])  # fmt: skip
    rows.to_csv(tmp_path / "ms.csv", index=False)
    auto = read_loop_file(tmp_path / "ms.csv").meta.loc[0]
    assert auto["ts"] == 1.0 and auto["start"] == pd.Timestamp(1.7e12, unit="ms")
    told = read_loop_file(tmp_path / "ms.csv", time_unit="s").meta.loc[0]
    assert told["ts"] == 1000.0 and pd.isna(told["start"])


def test_a_hidden_sheet_is_read_and_said_to_be_hidden(tmp_path):
    from openpyxl import load_workbook

    path = tmp_path / "hidden.xlsx"
    with pd.ExcelWriter(path) as writer:
        for name in ("FIC1", "FIC2"):
            sheet = pd.DataFrame({"time": np.arange(200.0), "PV": np.sin(np.arange(200) / 5),
                                  "OP": np.cos(np.arange(200) / 5)})  # fmt: skip
            sheet.to_excel(writer, sheet_name=name, index=False)
    book = load_workbook(path)
    book["FIC2"].sheet_state = "hidden"
    book.save(path)
    meta = read_loop_file(path).meta
    assert meta["reason"].tolist() == ["sheet 'FIC1'", "sheet 'FIC2' (hidden in the workbook)"]


def test_workbook_sheets_with_a_time_column_before_each_tag_are_all_read(tmp_path):
    t, records, _ = _recorded()
    (tp, vp), (to, vo) = records["PV"], records["OP"]
    n = max(len(tp), len(to))
    path = tmp_path / "datalink.xlsx"
    with pd.ExcelWriter(path) as writer:
        for tag in ("TIC5", "TIC6"):
            sheet = pd.DataFrame({0: pd.Series(START + pd.to_timedelta(tp, unit="s")),
                                  1: pd.Series(vp), 2: pd.Series(START + pd.to_timedelta(
                                      to, unit="s")), 3: pd.Series(vo)}).reindex(range(n))
            sheet.columns = ["Time", f"{tag}.PV", "Time ", f"{tag}.OP"]
            sheet.to_excel(writer, sheet_name=tag, index=False)
    data = read_loop_file(path)
    assert data.meta["tag"].tolist() == ["TIC5", "TIC6"]
    np.testing.assert_allclose(data.X[1, :, 1], _hold(t, to, vo), rtol=1e-14)  # 15 digits


def test_jittered_stamps_a_stray_record_and_a_valve_that_stops_writing(tmp_path):
    """Stamps to 10 ms with +-30 ms jitter keep the 1 s scan (their 10 ms divisor is no
    period); a lone PV record a month early does not stretch a two-tag loop; OP written
    for the first 40 % only (it stopped moving) does not cut PV's last 60 %."""
    rng = np.random.default_rng(0)
    n = 2000
    t = np.round(np.arange(n) + rng.uniform(-0.03, 0.03, n), 2)
    stamps = (START + pd.to_timedelta(t, unit="s")).strftime("%Y-%m-%d %H:%M:%S.%f").str[:-4]
    pv = pd.DataFrame({"Tag": "F1.PV", "Time": stamps, "Value": np.arange(n, dtype=float)})
    stray = pd.DataFrame({"Tag": ["F1.PV"], "Time": [str(START - pd.Timedelta(days=30))],
                          "Value": [-1.0]})  # fmt: skip
    op = pd.DataFrame({"Tag": "F1.OP", "Time": stamps[:800], "Value": 5.0})
    pd.concat([pv, stray, op]).to_csv(tmp_path / "jitter.csv", index=False)
    data = read_loop_file(tmp_path / "jitter.csv")
    meta = data.meta.loc[0]
    assert abs(meta["ts"] - 1.0) < 0.01 and abs(data.X.shape[1] - n) <= 2
    assert meta["start"] >= START - pd.Timedelta("1s")
    assert np.nanmax(data.X[0, :, 0]) >= n - 3 and (data.X[0, -5:, 1] == 5.0).all()
    assert "F1.OP has no record for" in meta["reason"]


def test_pi_af_attribute_paths_as_tags(tmp_path):
    # \\server\database\element|attribute: "|" is no separator of the file and parts the
    # element (the loop) from its attribute (the channel)
    X, _, rows = _wide_and_rows()
    af = rows.assign(Tag="\\\\PIAF01\\Refinery\\Unit2\\" + rows["Tag"] + "|" + rows["Parameter"])
    af.drop(columns="Parameter").to_csv(tmp_path / "af.csv", index=False)
    data = read_loop_file(tmp_path / "af.csv")
    assert data.meta["status"].tolist() == ["ok", "ok"], data.meta["reason"].tolist()
    assert data.meta["tag"].str.endswith(("FIC101", "LIC7")).all()
    assert data.meta["isa"].tolist() == ["FIC", "LIC"]
    np.testing.assert_array_equal(data.X, X)


def test_date_and_time_columns_of_a_long_export_are_joined(tmp_path):
    X, _, rows = _wide_and_rows()
    stamps = pd.to_datetime(rows.pop("Timestamp"))
    rows.insert(2, "Date", stamps.dt.strftime("%d.%m.%Y"))
    rows.insert(3, "Time", stamps.dt.strftime("%H:%M:%S"))
    rows.to_csv(tmp_path / "long.csv", index=False)
    data = read_loop_file(tmp_path / "long.csv")
    assert data.meta["status"].tolist() == ["ok", "ok"], data.meta["reason"].tolist()
    np.testing.assert_array_equal(data.X, X)
    assert (data.meta["start"] == START).all() and (data.meta["ts"] == 10.0).all()
    assert "time from columns Date + Time" in data.meta.loc[0, "reason"]


def _wincc(X, invalid=(), markers=False):
    """Siemens WinCC archive export lines of one loop: ``VarName;TimeString;VarValue;
    Validity;Time_ms``, decimal comma, Time_ms in days since 1899-12-30 times 10^6."""
    lines = ["VarName;TimeString;VarValue;Validity;Time_ms"]
    for i in range(X.shape[0]):
        stamp = START + pd.Timedelta(seconds=10 * i)
        serial = (stamp - pd.Timestamp("1899-12-30")) / pd.Timedelta(days=1) * 1e6
        ms = f"{serial:.4f}".replace(".", ",")
        for c, ch in enumerate(["PV", "OP", "SP"]):
            value = f"{X[i, c]:.6f}".replace(".", ",")
            ok = int((i, c) not in invalid)
            lines.append(f'"LIC104_{ch}";"{stamp:%d.%m.%Y %H:%M:%S}";{value};{ok};{ms}')
        if markers and i == 100:
            lines += [f'"$RT_OFF$";"{stamp:%d.%m.%Y %H:%M:%S}";0;2;{ms}',
                      f'"$RT_ON$";"{stamp:%d.%m.%Y %H:%M:%S}";0;2;{ms}']  # fmt: skip
    return "\r\n".join(lines) + "\r\n"


def test_siemens_wincc_archive_export(tmp_path):
    X, _ = make_loops(1, n_samples=300, random_state=0)
    X = np.round(X[0], 6)
    (tmp_path / "wincc.csv").write_text(_wincc(X), encoding="cp1252")
    data = read_loop_file(tmp_path / "wincc.csv")
    assert data.meta["status"].tolist() == ["ok"], data.meta["reason"].tolist()
    assert data.meta.loc[0, "tag"] == "LIC104" and data.meta.loc[0, "ts"] == 10.0
    assert data.meta.loc[0, "start"] == START  # from TimeString, not Time_ms
    np.testing.assert_allclose(data.X[0], X, atol=1e-9)
    assert "columns ['Time_ms'] not used" in data.meta.loc[0, "reason"]


def test_wincc_validity_other_than_1_is_a_gap_runtime_markers_aside(tmp_path):
    X, _ = make_loops(1, n_samples=300, random_state=0)
    X = np.round(X[0], 6)
    text = _wincc(X, invalid={(50, 0), (51, 0), (200, 1)}, markers=True)
    (tmp_path / "wincc.csv").write_text(text, encoding="cp1252")
    data = read_loop_file(tmp_path / "wincc.csv")
    assert data.meta["status"].tolist() == ["ok"], data.meta["reason"].tolist()
    got = data.X[0]
    assert np.isnan(got[[50, 51], 0]).all() and np.isnan(got[200, 1])
    assert np.isnan(got).sum() == 3
    np.testing.assert_allclose(got[~np.isnan(got)], X[~np.isnan(got)], atol=1e-9)
    assert "values of quality other than good read as NaN (column 'Validity')" in (
        data.meta.loc[0, "reason"]
    )


def test_trailer_lines_after_a_long_export_are_skipped(tmp_path):
    X, _, rows = _wide_and_rows()
    rows["Tag"] += "." + rows.pop("Parameter")
    text = rows.to_csv(index=False) + "\nEnd of data\nRows: 1800\n"
    (tmp_path / "long.csv").write_text(text)
    data = read_loop_file(tmp_path / "long.csv")
    assert data.meta["status"].tolist() == ["ok", "ok"], data.meta["reason"].tolist()
    np.testing.assert_array_equal(data.X, X)
    assert "2 rows without a tag or a readable time skipped" in data.meta.loc[0, "reason"]


@pytest.mark.parametrize(
    "header",
    [
        "Name;Zeit;Wert", "Messstelle;Zeitstempel;Messwert", "Tag;Horodatage;Valeur",
        "Nom;Date;Valeur", "Nombre;Fecha;Valor", "Naam;Tijd;Waarde", "Tag;Tijdstempel;Waarde",
    ],
)  # fmt: skip
def test_long_exports_named_in_german_french_spanish_dutch(tmp_path, header):
    """Before, the value column was not known, the file was read as wide and had 'no PV'
    (and channels={'pv': 'Wert'} read every tag's values as one PV)."""
    stamps = pd.date_range("2024-04-03 22:00:00", periods=4, freq="10s")
    values = {"PV": [50.25, 50.5, 50.75, 51.0], "OP": [40.5, 41.0, 41.5, 42.0],
              "SP": [50.0, 50.0, 50.0, 50.0]}  # fmt: skip
    rows = [f"FIC101.{ch};{s:%d.%m.%Y %H:%M:%S};{str(v[i]).replace('.', ',')}"
            for ch, v in values.items() for i, s in enumerate(stamps)]  # fmt: skip
    f = tmp_path / "long.csv"
    f.write_text(header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    data = read_loop_file(f)
    meta = data.meta.iloc[0]
    assert meta["status"] == "ok" and meta["tag"] == "FIC101" and meta["ts"] == 10.0
    assert meta["start"] == stamps[0] and "long layout" in meta["reason"]
    np.testing.assert_array_equal(data.X[0], np.column_stack(list(values.values())))


@pytest.mark.parametrize(
    ("names", "found"),
    [
        (["Messstelle", "Datum", "Uhrzeit", "Messwert", "Qualität"],
         {"tag": 0, "date": 1, "time": 2, "value": 3, "quality": [4]}),
        (["Nombre", "Fecha", "Hora", "Valor", "Calidad"],
         {"tag": 0, "date": 1, "time": 2, "value": 3, "quality": [4]}),
        (["Naam", "Tijdstip", "Waarde", "Kwaliteit"],
         {"tag": 0, "date": None, "time": 1, "value": 2, "quality": [3]}),
    ],
)  # fmt: skip
def test_long_column_roles_in_other_languages(names, found):
    from sktiction.datasets._columns import _is_time

    cols = long_columns(names, _is_time)
    assert {k: cols[k] for k in found} == found


def test_numeric_tags_of_a_parquet_export_keep_their_names(tmp_path):
    """Parquet stores a column of tag numbers as floats: the loop is 101, not 101.0."""
    pytest.importorskip("pyarrow")
    X, _, rows = _wide_and_rows(n=120)
    rows["Tag"] = rows["Tag"].map({"FIC101": 101.0, "LIC7": 7.0})
    rows.to_parquet(tmp_path / "long.parquet", index=False)
    data = read_loop_file(tmp_path / "long.parquet")
    assert sorted(data.meta["tag"]) == ["101", "7"]
    order = np.argsort(data.meta["tag"].astype(int).to_numpy())
    np.testing.assert_array_equal(data.X[order], X[::-1])
