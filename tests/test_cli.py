"""The command line: exit codes, the console table, outputs and the HTML report."""

import json
import shutil
import subprocess
import sys
from importlib import resources

import numpy as np
import pandas as pd
import pytest

from sktiction import cli
from sktiction.datasets import make_loops

PLANT = resources.files("sktiction.datasets") / "data" / "plant"


@pytest.fixture(scope="module")
def tiny_classifier():
    from sktiction import pretrained_classifier

    return pretrained_classifier(random_state=0, n_loops=60, n_samples=800)


@pytest.fixture
def no_training(monkeypatch):
    """Fail the test if the CLI gets as far as the model."""

    def boom():
        raise AssertionError("the model was trained or loaded")

    monkeypatch.setattr(cli, "_classifier", boom)


@pytest.fixture
def quick(monkeypatch, tiny_classifier):
    monkeypatch.setattr(cli, "_classifier", lambda: tiny_classifier)


@pytest.fixture
def folder(tmp_path):
    """Two real plant windows and one CSV without a PV column."""
    for name in sorted(p.name for p in PLANT.iterdir() if p.name.startswith("stic_"))[:2]:
        shutil.copy(PLANT / name, tmp_path / name)
    (tmp_path / "broken.csv").write_text("time,foo\n0,1\n1,2\n")
    return tmp_path


def test_missing_path_exits_2_at_once(no_training, tmp_path, capsys):
    assert cli.main(["scan", str(tmp_path / "no_such_folder")]) == 2
    assert "no such file or folder" in capsys.readouterr().err


def test_nothing_readable_exits_2_before_training(no_training, tmp_path, capsys):
    (tmp_path / "a.csv").write_text("foo,bar\n1,2\n")
    (tmp_path / "b.csv").write_text("")
    assert cli.main(["scan", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "no file could be read" in err
    assert "a.csv" in err and "b.csv" in err  # each file named with its reason
    assert "--channels pv=COLUMN" in err and "channels={" not in err  # this command's words


def test_empty_folder_exits_2(no_training, tmp_path, capsys):
    (tmp_path / "sub").mkdir()
    assert cli.main(["scan", str(tmp_path / "sub")]) == 2


def test_bad_channels_is_a_usage_error(no_training, folder, capsys):
    assert cli.main(["scan", str(folder), "--channels", "pv"]) == 2
    assert "--channels" in capsys.readouterr().err
    assert cli.main(["scan", str(folder), "--channels", "flow=A"]) == 2
    assert "unknown channel 'flow'" in capsys.readouterr().err


@pytest.mark.parametrize(
    "extra, message",
    [
        (["-o", "{tmp}/no_such_folder/x.csv"], "no folder"),
        (["--report", "{tmp}/no_such_folder/r.html"], "no folder"),
        (["-o", "{tmp}"], "is a folder"),
        (["-o", "{tmp}/no_such_folder/"], "is a folder"),
        (["-o", "{tmp}/report.xlsx"], "no writer for .xlsx"),
        (["--valves", "{tmp}/valves.xlsx"], "--valves"),
        (["--valves", "{tmp}/v.csv", "--format", "json"], "not be what its name says"),
        (["-o", "{tmp}/a.csv", "--valves", "{tmp}/a.csv"], "name the same file"),
        (["--valves", "{tmp}/no_such_folder/v.csv"], "no folder"),
        (["-j", "0"], "must not be 0"),
        (["--ts", "0"], "positive number of seconds"),
        (["--ts", "-1"], "positive number of seconds"),
    ],
)
def test_bad_outputs_and_options_exit_2_before_the_scan(no_training, folder, tmp_path, capsys,
                                                        extra, message):
    """Found after the scan, they would cost the whole scan (and gave a traceback)."""
    args = [a.format(tmp=tmp_path) for a in extra]
    assert cli.main(["scan", str(folder), "-q", *args]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "report.xlsx").exists()


def test_files_that_are_not_loops_are_listed_not_failures(quick, folder, tmp_path, capsys):
    (folder / "broken.csv").unlink()
    (folder / "LICENSE").write_text("not a loop")
    out = tmp_path / "out.csv"
    assert cli.main(["scan", str(folder), "-q", "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "LICENSE" in captured.out and "unsupported" in captured.out
    assert "verdicts of 2 loops" in captured.err and "1 file is not" in captured.err
    assert pd.read_csv(out)["file"].tolist().count("LICENSE") == 1
    # an .xls export may hold a loop the scan could not read: a failure, exit 1
    (folder / "FIC9.xls").write_bytes(b"\xd0\xcf\x11\xe0")
    assert cli.main(["scan", str(folder), "-q"]) == 1


def test_files_of_one_name_in_two_folders_are_told_apart_on_the_console(quick, folder,
                                                                       capsys):
    (folder / "broken.csv").unlink()
    name = sorted(p.name for p in folder.iterdir())[0]
    for unit in ("unit1", "unit2"):
        (folder / unit).mkdir()
        shutil.copy(folder / name, folder / unit / name)
    assert cli.main(["scan", str(folder / "unit1"), str(folder / "unit2"), "-q"]) == 0
    out = capsys.readouterr().out
    assert f"unit1/{name}" in out and f"unit2/{name}" in out
    assert cli.main(["scan", str(folder / "unit1"), "-q"]) == 0  # one folder: names alone
    assert "unit1/" not in capsys.readouterr().out


def test_a_report_written_into_the_scanned_folder_is_not_a_failure_next_time(quick, folder,
                                                                             capsys):
    (folder / "broken.csv").unlink()
    out = folder / "report.csv"
    assert cli.main(["scan", str(folder), "-q", "-o", str(out)]) == 0
    assert cli.main(["scan", str(folder), "-q", "-o", str(out)]) == 0  # reads its report
    assert "an earlier scan's report" in capsys.readouterr().err
    assert pd.read_csv(out)["file"].tolist().count("report.csv") == 1
    out.unlink()
    for fmt in ("json", "parquet"):
        report = folder / f"report.{fmt}"
        assert cli.main(["scan", str(folder), "-q", "-o", str(report), "--format", fmt]) == 0
        assert cli.main(["scan", str(folder), "-q", "-o", str(report), "--format", fmt]) == 0
        report.unlink()


def test_outputs_with_home_and_compression_are_written(quick, folder, tmp_path, monkeypatch):
    (folder / "broken.csv").unlink()
    home = tmp_path / "home"
    home.mkdir()
    monkeypatch.setenv("HOME", str(home))
    args = ["scan", str(folder), "-q", "-o", "~/out.csv.gz", "--report=~/r.html"]
    assert cli.main(args) == 0
    assert len(pd.read_csv(home / "out.csv.gz")) == 2 and (home / "r.html").exists()


def test_some_files_fail_exit_1_and_the_table_says_why(quick, folder, tmp_path, capsys):
    out = tmp_path / "out.json"
    report = tmp_path / "report.html"
    code = cli.main(["scan", str(folder), "-q", "-o", str(out), "--format", "json",
                     "--report", str(report)])
    assert code == 1
    stdout = capsys.readouterr().out
    lines = stdout.splitlines()
    broken = [line for line in lines if "broken.csv" in line]
    assert len(broken) == 1 and "no PV column" in broken[0]
    assert "--channels pv=COLUMN" in broken[0]  # the console gives this command's options
    for name in (p.name for p in folder.iterdir() if p.name.startswith("stic_")):
        row = [line for line in lines if name in line]
        assert len(row) == 1
        tag = name.split("_")[1]
        assert tag in row[0]
    rows = json.loads(out.read_text())
    assert len(rows) == 3
    text = report.read_text()
    assert text.count('src="data:image/png;base64,') == 2 and "broken.csv" in text


def test_all_read_exits_0_and_writes_csv(quick, folder, tmp_path, capsys):
    (folder / "broken.csv").unlink()
    out = tmp_path / "out.csv"
    assert cli.main(["scan", str(folder), "-q", "-o", str(out)]) == 0
    table = pd.read_csv(out)
    assert len(table) == 2
    assert set(table["verdict"]) <= {"stiction", "no_stiction", "no_verdict"}


def test_valves_option_writes_one_row_per_tag(quick, tmp_path, capsys):
    """Three records of two valves (one window copied under another name: its header
    names the same tag): two rows, each valve's records counted, and the console says
    how many valves got each verdict."""
    first, second = sorted(p.name for p in PLANT.iterdir() if p.name.startswith("stic_"))[:2]
    shutil.copy(PLANT / first, tmp_path / first)
    shutil.copy(PLANT / first, tmp_path / ("again_" + first))
    shutil.copy(PLANT / second, tmp_path / second)
    out = tmp_path / "valves.csv"
    assert cli.main(["scan", str(tmp_path), "-q", "--valves", str(out)]) == 0
    valves = pd.read_csv(out)
    assert sorted(valves["n_records"]) == [1, 2]
    assert valves.loc[valves["n_records"].eq(2), "tag"].item() == first.split("_")[1]
    assert "verdicts of 2 valves" in capsys.readouterr().err


def test_channels_option_names_the_columns(quick, tmp_path, capsys):
    X, _ = make_loop()
    frame = pd.DataFrame({"t": np.arange(len(X)), "flow": X[:, 0], "valve": X[:, 1],
                          "target": X[:, 2]})
    frame.to_csv(tmp_path / "FIC7.csv", index=False)
    assert cli.main(["scan", str(tmp_path / "FIC7.csv"), "-q"]) == 2  # no PV column found
    assert "no file could be read" in capsys.readouterr().err
    code = cli.main(["scan", str(tmp_path / "FIC7.csv"), "-q", "--channels",
                     "pv=flow,op=valve,sp=target"])
    assert code == 0


def make_loop():
    from sktiction.datasets import make_loops

    X, y = make_loops(1, n_samples=600, world="classic", random_state=4)
    return X[0], y[0]


def test_parquet_needs_pyarrow_or_works(quick, folder, tmp_path, capsys):
    out = tmp_path / "out.parquet"
    code = cli.main(["scan", str(folder), "-q", "-o", str(out)])
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        assert code == 2 and "pyarrow" in capsys.readouterr().err
    else:
        assert code == 1 and len(pd.read_parquet(out)) == 3


def test_python_m_sktiction(tmp_path):
    run = subprocess.run([sys.executable, "-m", "sktiction", "scan", str(tmp_path / "nope")],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 2
    assert "no such file or folder" in run.stderr
    run = subprocess.run([sys.executable, "-m", "sktiction", "--help"], capture_output=True,
                         text=True, timeout=120, check=False)
    assert run.returncode == 0
    assert "Exit codes" in run.stdout and "scan" in run.stdout and "demo" in run.stdout


def test_scheduler_runs_the_scan_on_a_dask_cluster(quick, folder, tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    out = tmp_path / "out.csv"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        code = cli.main(["scan", str(folder), "-q", "-o", str(out), "--scheduler",
                         cluster.scheduler_address])
    assert code == 1  # broken.csv
    table = pd.read_csv(out)
    assert len(table) == 3 and table["verdict"].notna().all()


def test_demo_writes_the_report_with_real_plant_windows(quick, tmp_path, capsys,
                                                       monkeypatch):
    from sklearn.utils import Bunch

    from sktiction import datasets

    full = datasets.load_example()
    few = Bunch(X=full.X[:3], y=full.y[:3], meta=full.meta.iloc[:3].reset_index(drop=True))
    monkeypatch.setattr(datasets, "load_example", lambda: few)  # a faster demo
    report = tmp_path / "demo.html"
    assert cli.main(["demo", "--report", str(report)]) == 0
    out = capsys.readouterr().out
    assert "3 simulated loops and 6 real plant windows" in out
    assert "plant: stiction found in" in out
    text = report.read_text()
    for tag in ("2111FIC46005", "2411FIC20102", "2111LIC44001", "2411PDIC10321"):
        assert tag in text
    assert text.count("<tr ") == 9
    assert text.count('src="data:image/png;base64,') == 9


def test_compare_is_wired_to_realism(no_training, tmp_path, capsys):
    pytest.importorskip("sktiction.realism._cli")
    assert cli.main(["compare", str(tmp_path / "nope")]) == 2
    assert "no such file or folder" in capsys.readouterr().err


def test_top_keeps_the_most_likely_sticky_rows_and_every_unread_file():
    table = pd.DataFrame({
        "file": ["a", "b", "c", "d", "e"],
        "read": ["ok", "ok", "ok", "error", "ok"],
        "verdict": ["stiction", "no_stiction", "stiction", "no_verdict", "stiction"],
        "p_stiction": [0.6, 0.2, 0.9, np.nan, 0.7],
    })  # fmt: skip
    assert cli._top(table, 2)["file"].tolist() == ["c", "e", "d"]
    assert cli._top(table, 10)["file"].tolist() == ["c", "e", "a", "d"]
    report = table.rename(columns={"p_stiction": "stiction_probability"})
    assert cli._verdict_counts(report) == (
        "verdicts of 5 loops: 3 stiction, 1 no_stiction, 1 no_verdict"
    )
    report["reason"] = ["ok", "ok", "ok", "pv_op_swapped", "ok"]
    more = pd.DataFrame({"verdict": "no_verdict", "reason": [
        "pv_op_swapped", "out_of_domain:templates__period", "out_of_domain:area__area_ratio",
        "out_of_domain:templates__period; shapes: not_oscillating", "ValueError: bad loop",
    ]})  # fmt: skip
    assert cli._verdict_counts(pd.concat([report, more])) == (
        "verdicts of 10 loops: 3 stiction, 1 no_stiction, 6 no_verdict "
        "(3 out_of_domain, 2 pv_op_swapped, 1 ValueError)"
    )
    # a scan's oscillation column: how many loops cycle, and how many of those are sticky
    report["oscillating"] = [True, True, False, np.nan, True]
    assert cli._verdict_counts(report).endswith("; 3 oscillate, 2 of them called sticky")


def test_top_option_on_the_command_line(quick, folder, tmp_path, capsys):
    out = tmp_path / "out.csv"
    assert cli.main(["scan", str(folder), "-q", "--top", "1", "-o", str(out)]) == 1
    captured = capsys.readouterr()
    full = pd.read_csv(out)
    assert len(full) == 3  # the file keeps every row
    shown = [line for line in captured.out.splitlines()[1:] if line.strip()]
    assert len(shown) == min(1, int((full["verdict"] == "stiction").sum())) + 1
    assert "broken.csv" in captured.out
    assert "verdicts of 2 loops" in captured.err  # broken.csv holds no loop
    assert cli.main(["scan", str(folder), "--top", "0"]) == 2  # a usage error


def test_compare_skips_a_loop_with_infinite_values_and_names_it(no_training, tmp_path, capsys):
    """One broken value must not abort the comparison of the others."""
    pytest.importorskip("sktiction.realism._cli")
    X, _ = make_loops(3, n_samples=400, random_state=0)
    X[0, 10, 0] = np.inf
    for i, x in enumerate(X):
        frame = pd.DataFrame({"time": np.arange(len(x)), "PV": x[:, 0], "OP": x[:, 1],
                              "SP": x[:, 2]})  # fmt: skip
        frame.to_csv(tmp_path / f"loop{i}.csv", index=False)
    code = cli.main(["compare", str(tmp_path), "--n-simulated", "10", "--n-samples", "300",
                     "--figure", str(tmp_path / "gap.png")])  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0
    assert "skipped loop0.csv: infinite values" in out
    assert "measured: 2 loops" in out


def test_manual_mode_rows_are_left_out_of_the_diagnosis(quick, tmp_path, capsys):
    """MODE 0 rows are no closed loop: the scan judges the automatic stretch and says so."""
    X, _ = make_loops(1, n_samples=2000, random_state=0)
    mode = np.where(np.arange(2000) < 800, "MAN", "AUTO")
    frame = pd.DataFrame({"time": np.arange(2000.0), "PV": X[0, :, 0], "OP": X[0, :, 1],
                          "SP": X[0, :, 2], "MODE": mode})  # fmt: skip
    frame.to_csv(tmp_path / "FIC1.csv", index=False)
    out = tmp_path / "out.csv"
    assert cli.main(["scan", str(tmp_path / "FIC1.csv"), "-q", "-o", str(out)]) == 0
    row = pd.read_csv(out).iloc[0]
    assert "800 rows in manual mode (MODE 0): a scan reads them as gaps" in row["input_reason"]
    assert (row["kept_start"], row["kept_stop"]) == (800, 2000)
    assert row["auto_fraction"] == 0.6 and row["status"] == "ok"


def test_console_and_html_pool_the_same_records_per_valve(capsys):
    """One rule for "some valve has several records": tags that differ only by spaces
    name one valve on the console as on the page (the console compared raw tags)."""
    from sktiction.reports.html import _valve_summary

    report = pd.DataFrame({
        "file": ["a.csv", "b.csv", "c.csv"],
        "tag": [" FIC1", "FIC1 ", "LIC2"],
        "verdict": ["stiction", "stiction", "no_verdict"],
    })  # fmt: skip
    assert cli._valves(report, None, None)
    assert "verdicts of 2 valves" in capsys.readouterr().err
    assert _valve_summary(report).startswith(". 2 valves")
    alone = report.assign(tag=["FIC1", "FIC2", None])  # every valve once
    assert cli._valves(alone, None, None)
    assert capsys.readouterr().err == ""
    assert _valve_summary(alone) == ""


def test_console_table_shows_float_tags_as_written_and_no_minus_zero(capsys):
    """A report read back with a tag column of numbers and a gap (floats), and numbers
    that round to 0 from below: the console shows 101 and 0.00, not 101.0 and -0.00."""
    report = pd.DataFrame({
        "file": ["a.csv", "b.csv", "c.csv"], "tag": [101.0, np.nan, 2.5],
        "verdict": ["stiction", "no_verdict", "no_stiction"],
        "stiction_probability": [0.9, np.nan, 0.2], "stiction_band_fit": [-0.001, np.nan, -0.5],
    })  # fmt: skip
    table = cli._console_table(report)
    assert table["tag"].tolist() == ["101", "", "2.5"]
    cli._print_table(table)
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].split()[:6] == ["a.csv", "101", "ok", "stiction", "0.90", "0.00"]
    assert lines[3].split()[:6] == ["c.csv", "2.5", "ok", "no_stiction", "0.20", "-0.50"]
    assert "-0.00" not in "\n".join(lines) and "101.0" not in "\n".join(lines)
    assert cli._console_table(report.assign(tag=["101.0", None, " F1"]))["tag"].tolist() == [
        "101.0", "", " F1"]  # text tags as they are
