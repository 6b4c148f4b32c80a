"""scan_files on a small site of short files: the report of scan_loops on the same loops, one
row per loop in file order, gaps bridged, and a row with the reason for every file or loop
that cannot be read. A stand-in model (probability a known function of PV) keeps it fast.
"""

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from sktiction._validation import repair_gaps
from sktiction.datasets import make_loops, read_loop_file
from sktiction.reports import _stream, scan_files, scan_loops
from sktiction.reports import scan as scan_module
from sktiction.reports.scan import REPORT_COLUMNS, _applicability_gate

GAP_COLUMNS = ["n_bridged", "n_gaps_split", "kept_start", "kept_stop"]


def square(a, n, period=100):
    """A sticking valve in a flow loop: PV a square wave of amplitude ``a``, OP its integral."""
    k = np.arange(n)
    pv = 10 + a * np.clip(8 * np.sin(2 * np.pi * k / period), -1, 1)
    return pv, 50 - 0.05 * np.cumsum(pv - 10)


class Spread:
    """Stand-in learned model: stiction probability PV peak-to-peak p over p + 2."""

    def predict_proba(self, X):
        ptp = np.nanmax(X[:, :, 0], axis=1) - np.nanmin(X[:, :, 0], axis=1)
        return np.column_stack([2 / (ptp + 2), ptp / (ptp + 2)])


def _csv(path, columns):
    pd.DataFrame(columns).to_csv(path, index=False)


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    folder = tmp_path_factory.mktemp("site")
    pv, op = square(3.0, 1200)
    _csv(folder / "FIC001.csv", {"t": np.arange(1200), "PV": pv, "OP": op, "SP": 10.0})
    pv, op = square(1.0, 1000)  # shorter: padded in the chunk
    _csv(folder / "FIC002.csv", {"t": np.arange(1000), "PV": pv, "OP": op})
    pv, op = square(2.0, 1200)
    pv[400:402] = op[400:402] = np.nan  # two samples missing: bridged, or a nan_gap
    _csv(folder / "FIC003.csv", {"t": np.arange(1200), "PV": pv, "OP": op})
    pv, op = square(0.5, 1100)
    _csv(folder / "LIC004.csv", {"t": np.arange(1100), "LIC4.PV": pv, "LIC4.OP": op,
                                 "TIC5.PV": "Bad", "TIC5.OP": op})  # fmt: skip
    pv, op = square(2.5, 900)
    _csv(folder / "PIC005.csv", {"PV": pv, "OP": op})  # no time column: needs ts
    (folder / "broken.csv").write_text("t,FOO,BAR\n0,1,2\n1,2,3\n")  # no PV column
    (folder / "notes.doc").write_text("not a loop file")
    return folder


FILES = ["FIC001.csv", "FIC002.csv", "FIC003.csv", "LIC004.csv", "LIC004.csv", "PIC005.csv",
         "broken.csv", "notes.doc"]  # fmt: skip


@pytest.fixture(autouse=True)
def no_gate(monkeypatch):
    # the applicability gate is scan_loops' (tested there); here the stream is under test
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: None)
    monkeypatch.setattr(_stream, "_applicability_gate", lambda: None)


def test_the_stream_gives_scan_loops_report_in_file_order(site):
    report = scan_files(site, classifier=Spread(), chunk_size=2, ts=1.0, max_gap=None)
    assert report["file"].tolist() == FILES
    assert report["tag"].tolist()[3:5] == ["LIC4", "TIC5"]  # the readable loop first
    assert report["status"].tolist() == ["ok", "ok", "nan_gap", "ok", "unreadable", "ok",
                                         "unreadable", "unreadable"]  # fmt: skip
    assert report["verdict"].tolist() == [
        "stiction",
        "stiction",
        "no_verdict",
        "no_stiction",
        "no_verdict",
        "stiction",
        "no_verdict",
        "no_verdict",
    ]
    bad = report["status"].eq("unreadable")
    assert report.loc[bad, "input_status"].tolist() == ["error", "error", "unsupported"]
    assert report.loc[bad, "reason"].tolist() == report.loc[bad, "input_reason"].tolist()
    assert "PV column 'TIC5.PV' holds no numbers" in report.loc[4, "reason"]
    assert report.loc[bad, ["stiction_probability", "area_ratio", "n_cycles"]].isna().all().all()
    # the reader's columns (its status and reason renamed), then the scan's
    assert report.columns.tolist() == [
        "file", "path", "format", "tag", "isa", "loop_type", "ts", "n_samples", "n_nan",
        "auto_fraction", "start", "input_status", "input_reason", *REPORT_COLUMNS,
    ]  # fmt: skip
    # the readable loops, read one by one, padded and scanned in memory
    datas = [read_loop_file(site / f, ts=1.0) for f in FILES[:4] + FILES[5:6]]
    X = np.full((6, 1200, 3), np.nan)
    k = 0
    for d in datas:
        X[k : k + len(d.X), : d.X.shape[1]] = d.X
        k += len(d.X)
    meta = pd.concat([d.meta for d in datas], ignore_index=True)
    keep = [0, 1, 2, 3, 5]  # without TIC5
    expected = scan_loops(X[keep], meta.iloc[keep], classifier=Spread(), max_gap=None)
    got = report.loc[~bad, expected.columns].reset_index(drop=True)
    pd.testing.assert_frame_equal(got, expected, check_dtype=False)
    assert got["loop_type"].tolist() == ["flow", "flow", "flow", "level", "pressure"]


def test_short_gaps_are_bridged_and_the_chunking_changes_nothing(site):
    one = scan_files(site, classifier=Spread(), chunk_size=1, ts=1.0)
    assert one["status"].tolist()[:4] == ["ok"] * 4
    gaps = one[GAP_COLUMNS]
    assert gaps.iloc[2].tolist() == [1, 0, 0, 1200]  # FIC003: one gap bridged, all kept
    assert gaps.iloc[[0, 1, 3, 5]]["n_bridged"].eq(0).all()
    assert gaps.iloc[[0, 1, 3, 5]]["kept_stop"].tolist() == [1200, 1000, 1100, 900]
    assert gaps.iloc[[4, 6, 7]].isna().all().all()  # unreadable: nothing to repair
    data = read_loop_file(site / "FIC003.csv", ts=1.0)
    repaired, _ = repair_gaps(data.X)
    alone = scan_loops(repaired, data.meta, classifier=Spread(), max_gap=None)
    pd.testing.assert_frame_equal(
        one.loc[[2], alone.columns].reset_index(drop=True), alone, check_dtype=False
    )
    for chunk_size in (3, 100):
        pd.testing.assert_frame_equal(
            scan_files(site, classifier=Spread(), chunk_size=chunk_size, ts=1.0), one
        )


def test_files_that_need_arguments_say_so(site, tmp_path):
    report = scan_files(site, classifier=Spread(), max_gap=None)
    row = report.iloc[5]
    assert row["file"] == "PIC005.csv" and row["status"] == "unreadable"
    assert "cannot determine the sampling time" in row["reason"]
    _csv(tmp_path / "unit.csv", {"t": np.arange(1200), "FLOW": square(3.0, 1200)[0],
                                 "VALVE": square(3.0, 1200)[1]})  # fmt: skip
    assert "no PV column" in scan_files(tmp_path, classifier=Spread()).loc[0, "reason"]
    named = scan_files(tmp_path, classifier=Spread(), channels={"pv": "FLOW", "op": "VALVE"})
    assert named.loc[0, ["status", "verdict"]].tolist() == ["ok", "stiction"]


def test_a_file_the_reader_chokes_on_gets_an_error_row(site, monkeypatch):
    real = _stream.read_loop_rows

    def choking(path, *args):
        if path.endswith("FIC002.csv"):
            raise RuntimeError("disk on fire")
        return real(path, *args)

    monkeypatch.setattr(_stream, "read_loop_rows", choking)
    report = scan_files(site, classifier=Spread(), chunk_size=4, ts=1.0)
    row = report.iloc[1]
    assert (row["file"], row["input_status"], row["status"], row["verdict"]) == (
        "FIC002.csv", "error", "unreadable", "no_verdict"
    )  # fmt: skip
    assert row["reason"] == "RuntimeError: disk on fire"
    assert row["path"] == str(site / "FIC002.csv")
    assert report["file"].tolist() == FILES
    assert report["status"].tolist()[:4] == ["ok", "unreadable", "ok", "ok"]


def test_bad_arguments_and_empty_folders(tmp_path):
    with pytest.raises(ValueError, match="chunk_size must be an integer >= 1"):
        scan_files(tmp_path, classifier=Spread(), chunk_size=0)
    with pytest.raises(ValueError, match="paths holds no files"):
        scan_files([], classifier=Spread())
    report = scan_files(tmp_path, classifier=Spread())
    assert report[["status", "verdict"]].values.tolist() == [["unreadable", "no_verdict"]]
    assert "folder holds no readable loop file" in report.loc[0, "reason"]


def test_no_classifier_means_the_pretrained_one(site, monkeypatch):
    monkeypatch.setattr(_stream, "pretrained_classifier", Spread)
    files = [site / "FIC001.csv", site / "notes.doc"]
    got = scan_files(files)
    pd.testing.assert_frame_equal(got, scan_files(files, classifier=Spread()))
    assert got.loc[0, "verdict"] == "stiction"


def test_progress_is_shown_per_file_only_when_asked(site, capsys):
    files = [site / "FIC001.csv", site / "notes.doc"]
    scan_files(files, classifier=Spread(), progress=True)
    err = capsys.readouterr().err
    assert "2/2" in err and re.search(r"[\d?]file/s", err)  # advanced per file
    scan_files(files, classifier=Spread())
    assert capsys.readouterr().err == ""


def test_a_dask_cluster_reads_and_scans_the_files(site, dask_client):
    from distributed import get_task_stream

    local = scan_files(site, classifier=Spread(), chunk_size=3, ts=1.0)
    with get_task_stream(dask_client) as stream:
        remote = scan_files(site, classifier=Spread(), chunk_size=3, ts=1.0, client=dask_client)
    # the chunks ran on the cluster, not here
    assert any(t["key"].startswith("sktiction-scan") for t in stream.data)
    pd.testing.assert_frame_equal(remote, local)
    assert list(local.columns[-len(REPORT_COLUMNS) :]) == REPORT_COLUMNS


def test_an_explicit_gap_limit_and_a_one_row_file(site, tmp_path):
    report = scan_files(site, classifier=Spread(), ts=1.0, max_gap=1)
    row = report.iloc[2]  # FIC003: two missing samples are more than 1: the record splits
    assert row[GAP_COLUMNS].tolist() == [0, 1, 402, 1200]
    assert row["status"] == "ok"
    (tmp_path / "FIC9.csv").write_text("PV,OP\n1,2\n")
    one = scan_files(tmp_path, classifier=Spread(), ts=1.0)
    assert one.loc[0, ["input_status", "status"]].tolist() == ["ok", "too_short"]


def test_the_applicability_gate_is_applied_to_files(tmp_path, monkeypatch):
    monkeypatch.setattr(scan_module, "_applicability_gate", _applicability_gate)
    monkeypatch.setattr(_stream, "_applicability_gate", _applicability_gate)
    rng = np.random.default_rng(0)
    pv, op = square(3.0, 1200)
    _csv(tmp_path / "FIC1.csv", {"t": np.arange(1200), "PV": pv, "OP": op})
    _csv(tmp_path / "FIC2.csv", {"t": np.arange(1200), "PV": rng.normal(size=1200),
                                 "OP": rng.normal(size=1200)})  # fmt: skip
    (tmp_path / "A_notes.doc").write_text("not a loop file, listed first")
    report = scan_files(tmp_path, classifier=Spread())
    assert report["file"].tolist() == ["A_notes.doc", "FIC1.csv", "FIC2.csv"]
    assert report["verdict"].tolist() == ["no_verdict", "stiction", "no_verdict"]
    assert report["reason"].tolist()[1:] == ["ok", "pv_op_unrelated"]


def test_gap_free_files_skip_repair_gaps_with_its_answer():
    """A file without a missing value gets repair_gaps' own info without running it; one
    with a gap, a leading NaN, or an inf in a channel it has goes through repair_gaps."""
    from sktiction._validation import gap_free_lengths

    X, _ = make_loops(3, n_samples=300, random_state=0)
    X[1, 250:] = np.nan  # a shorter loop (padding)
    X[2, :, 2] = np.nan  # a loop without SP
    lengths = gap_free_lengths(X)
    _, info = repair_gaps(X)
    assert lengths.tolist() == info["kept_stop"].tolist() == [300, 250, 300]
    assert (info[["n_bridged", "n_gaps_split", "kept_start"]] == 0).all().all()
    for where in ((0, 100, 0), (1, 0, 1), (2, 10, 1)):
        bad = X.copy()
        bad[where] = np.nan
        assert gap_free_lengths(bad) is None
    bad = X.copy()
    bad[0, 5, 1] = np.inf
    assert gap_free_lengths(bad) is None


@pytest.mark.parametrize("ts", [None, 2.0])
def test_the_stream_reads_what_read_loop_file_reads(ts):
    # the stream builds one meta table per chunk from row dicts: the same as read_loop_file
    exports = Path(__file__).resolve().parent / "data" / "exports"
    paths = sorted(p for p in exports.rglob("*") if p.is_file()) + [exports / "missing.csv"]
    rows, metas = [], []
    for path in paths:
        X, file_rows, _ = _stream.read_loop_rows(str(path), None, ts)
        data = read_loop_file(str(path), ts=ts)
        np.testing.assert_array_equal(X, data.X)
        rows += file_rows
        metas.append(data.meta)
    assert len({r["status"] for r in rows}) == 3  # ok, error and unsupported files
    pd.testing.assert_frame_equal(_stream._meta(rows), pd.concat(metas, ignore_index=True))
    with pytest.raises(ValueError, match="ts must be"):
        _stream.read_loop_rows(str(paths[0]), None, -1.0)


def test_a_file_with_an_infinite_value_is_read_and_its_loop_says_not_finite(site, tmp_path):
    """inf is no gap for repair_gaps: the file is read, its loop gets not_finite."""
    good = sorted(p for p in site.iterdir() if p.suffix == ".csv")[:2]
    frame = pd.read_csv(good[0])
    frame.loc[20, frame.columns[1]] = np.inf
    bad = tmp_path / "INF001.csv"
    frame.to_csv(bad, index=False)
    for files in ([bad, good[1]], [good[1], bad]):  # in one chunk, either order
        report = scan_files(files, classifier=Spread(), ts=1.0)
        report = report.set_index("file").loc[[bad.name, good[1].name]]
        assert report["input_status"].tolist() == ["ok", "ok"]
        assert report["status"].tolist() == ["not_finite", "ok"]
        assert report["reason"].iloc[0].startswith("not_finite: infinite values in")
        assert report["kept_stop"].tolist()[1] > 0 and np.isnan(report["kept_stop"].iloc[0])


def test_report_columns_do_not_depend_on_which_file_comes_first(site, tmp_path):
    """An unreadable file's rows have fewer meta columns: the order must not follow them."""
    good = sorted(p for p in site.iterdir() if p.suffix == ".csv")[0]
    bad = tmp_path / "AAA.csv"
    bad.write_text("foo,bar\n1,2\n")
    first = scan_files([bad, good], classifier=Spread(), ts=1.0)
    last = scan_files([good, bad], classifier=Spread(), ts=1.0)
    assert list(first.columns) == list(last.columns)
    assert list(first.columns[:4]) == ["file", "path", "format", "tag"]
    pd.testing.assert_frame_equal(first.iloc[[1, 0]].reset_index(drop=True), last,
                                  check_dtype=False)  # fmt: skip
