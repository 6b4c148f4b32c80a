"""The HTML report: one self-contained file that a real browser shows without errors."""

import os
import re
import shutil
import subprocess

import matplotlib
import matplotlib.style
import numpy as np
import pandas as pd
import pytest

matplotlib.use("Agg")

from sktiction.datasets import make_loops  # noqa: E402
from sktiction.reports import write_html_report  # noqa: E402


def _chromium():
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None and os.path.exists("/usr/bin/chromium"):
        path = "/usr/bin/chromium"
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is missing in CI: .ci/run installs the Debian package")
        pytest.skip("chromium not installed (apt-get install chromium); CI installs it")
    return path


def _browse(page, tmp_path, *args, fragment=""):
    """Open ``page`` in headless Chromium; return (stdout, console lines)."""
    cmd = [
        _chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", f"--user-data-dir={tmp_path / 'profile'}", "--enable-logging=stderr",
        "--v=0", "--virtual-time-budget=10000", *args, page.resolve().as_uri() + fragment,
    ]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    console = [line for line in run.stderr.splitlines() if ":CONSOLE" in line]
    return run.stdout, console


@pytest.fixture(scope="module")
def report_and_loops():
    X, y = make_loops(4, n_samples=800, world="classic", random_state=0)
    X = np.concatenate([X, np.full((1, 800, 3), np.nan)])  # a file that could not be read
    report = pd.DataFrame({
        "file": [f"loop_{i}.csv" for i in range(5)],
        "tag": ["FIC101", "LIC202", "PIC303", "TIC404", ""],
        "verdict": ["stiction", "no_stiction", "stiction", "no_verdict", "no_verdict"],
        "stiction_probability": [0.93, 0.12, 0.71, np.nan, np.nan],
        "stiction_size_mean": [3.2, np.nan, 1.1, np.nan, np.nan],
        "area_ratio": [2.4, 1.1, 1.9, np.nan, np.nan],
        "status": ["ok", "ok", "ok", "ok", "error"],
        "reason": ["", "", "", "pv_op_unrelated", "no PV column in loop_4.csv"],
    })
    return report, X


def test_file_is_self_contained(report_and_loops, tmp_path):
    report, X = report_and_loops
    path = write_html_report(report, X, path=tmp_path / "r.html")
    text = path.read_text(encoding="utf-8")
    # no resource from the network: every src is inline data
    assert not re.search(r'(src|href)="(https?:)?//', text)
    assert text.count('src="data:image/png;base64,') == 4  # the unreadable one has none
    assert "no figure" in text
    for tag in ("FIC101", "LIC202", "PIC303", "TIC404", "no PV column in loop_4.csv"):
        assert tag in text
    assert text.count("<tr ") == 5


def test_figures_on_two_processes_make_the_same_file(report_and_loops, tmp_path, capsys):
    report, X = report_and_loops
    with matplotlib.style.context("ggplot"):  # the caller's style does not reach workers
        one = write_html_report(report, X, path=tmp_path / "one.html", progress=True)
    assert "figures" in capsys.readouterr().err  # the progress bar names its work
    two = write_html_report(report, X, path=tmp_path / "two.html", n_jobs=2)
    assert one.read_bytes() == two.read_bytes()


def test_a_loop_that_cannot_be_read_again_costs_only_its_figure(report_and_loops, tmp_path):
    report, X = report_and_loops

    def loop(i):
        if i == 1:
            raise OSError("the file was moved")
        return X[i]

    text = write_html_report(report, loop, path=tmp_path / "r.html").read_text()
    assert text.count('src="data:image/png;base64,') == 3
    assert "no figure: error: OSError: the file was moved" in text


def test_report_rows_must_match_loops(report_and_loops, tmp_path):
    report, X = report_and_loops
    with pytest.raises(ValueError, match="5 rows"):
        write_html_report(report, X[:3], path=tmp_path / "r.html")


def test_chromium_renders_table_and_figures(report_and_loops, tmp_path):
    report, X = report_and_loops
    page = write_html_report(report, X, path=tmp_path / "report.html", title="test scan")
    dom, console = _browse(page, tmp_path, "--dump-dom")
    assert console == [], console  # no error, no warning, nothing logged
    # the page's own script ran: it counts the table rows and the decoded images
    assert 'data-ready="1"' in dom
    assert 'data-rows="5"' in dom
    assert 'data-images-ok="4"' in dom
    assert dom.count("<img") == 4
    assert "FIC101" in dom and "stiction" in dom

    shot = tmp_path / "shot.png"
    _browse(page, tmp_path, f"--screenshot={shot}", "--window-size=1200,1400")
    image = matplotlib.image.imread(shot)[..., :3]
    assert image.shape[:2] == (1400, 1200)
    ink = (image.mean(axis=2) < 0.85).mean()  # share of non-white pixels
    assert 0.02 < ink < 0.6, ink
    assert image.std() > 0.05


def test_console_check_can_fail(tmp_path):
    """The console check above would see a script error."""
    page = tmp_path / "bad.html"
    page.write_text("<html><body><script>noSuchFunction();</script></body></html>")
    _, console = _browse(page, tmp_path, "--dump-dom")
    assert any("noSuchFunction" in line for line in console)


@pytest.mark.parametrize("how", ["name", "-name", "index"])
def test_table_sorts_in_the_browser(report_and_loops, tmp_path, how):
    report, X = report_and_loops
    page = write_html_report(report, X, path=tmp_path / "report.html")
    header = re.search(r"<thead><tr>(.*?)</tr></thead>", page.read_text()).group(1)
    column = re.findall(r"<th[^>]*>(.*?)</th>", header).index("p(stiction)")
    fragment = {"name": "#sort=stiction_probability", "-name": "#sort=-stiction_probability",
                "index": f"#sort={column}"}[how]  # fmt: skip
    dom, console = _browse(page, tmp_path, "--dump-dom", fragment=fragment)
    assert console == []
    body = dom[dom.index("<tbody>"):dom.index("</tbody>")]
    order = [int(i) for i in re.findall(r'id="row-(\d+)"', body)]
    # probability 0.12, 0.71, 0.93 ascending (descending with "-"), then loops without one
    assert order[:3] == ([0, 2, 1] if how == "-name" else [1, 2, 0])
    assert sorted(order[3:]) == [3, 4]


def test_valves_with_several_records_are_summed_up_on_the_page(tmp_path):
    """Two records of FIC1 (one sticky), one of LIC2: the page names FIC1 as sticky in
    1 of 2 records; with one record per tag the sentence is left out."""
    report = pd.DataFrame({"tag": ["FIC1", "FIC1", "LIC2"],
                           "verdict": ["stiction", "no_stiction", "no_stiction"]})
    text = write_html_report(report, path=tmp_path / "r.html").read_text()
    assert ("2 valves; called sticky in at least half of their judged records: 1, "
            "FIC1 (1 of 2)") in text
    text = write_html_report(report.iloc[1:], path=tmp_path / "s.html").read_text()
    assert "valves;" not in text


def test_a_scans_oscillation_columns_fill_the_table_for_every_loop(report_and_loops, tmp_path):
    report, X = report_and_loops
    report = report.assign(oscillating=[True, False, True, np.nan, np.nan],
                           oscillation_period=[50.0, np.nan, 80.0, np.nan, np.nan],
                           ts=[2.0, 2.0, 0.5, 1.0, 1.0])  # fmt: skip
    path = write_html_report(report, X, path=tmp_path / "r.html", max_figures=0)
    text = path.read_text(encoding="utf-8")
    # the period cell follows the oscillation cell: samples times the sample time, for
    # every loop although no figure is drawn
    cells = re.findall(r'<td class="oscillating">(\w*)</td><td class="num"'
                       r'(?: data-value="([^"]+)")?>', text)  # fmt: skip
    assert [c[0] for c in cells] == ["yes", "no", "yes", "", ""]
    assert [float(c[1]) if c[1] else None for c in cells] == [100.0, None, 40.0, None, None]
