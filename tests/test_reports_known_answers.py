"""Known answers of the per-valve table (``summarise_valves``) and of the HTML report
(``write_html_report``), worked out by hand from reports of a few rows.

No model is fitted and, but for one loop, no figure is drawn: a loop of NaN gives the
"no figure" note without drawing, so the order and choice of figures is read cheaply.
"""

import base64
import re

import numpy as np
import pandas as pd
import pytest

from sktiction.reports.html import write_html_report
from sktiction.reports.valves import COLUMNS, several_records, summarise_valves

NAN = np.nan


def _valves(**columns):
    return summarise_valves(pd.DataFrame(columns)).set_index("tag")


# --------------------------------------------------------------------- summarise_valves


def test_a_record_without_a_verdict_counts_but_is_neither_judged_nor_sticky():
    valves = _valves(tag=["A", "A", "A"], verdict=["stiction", NAN, "no_stiction"],
                     stiction_probability=[0.8, 0.99, 0.4],
                     stiction_size_mean=[3.0, 7.0, 5.0],
                     stiction_band_fit=[1.0, 9.0, 4.0])  # fmt: skip
    a = valves.loc["A"]
    assert (a["n_records"], a["n_judged"], a["n_stiction"]) == (3, 2, 1)
    assert a["stiction_share"] == 0.5 and a["verdict"] == "stiction"  # 1 of 2 is half
    assert a["probability_median"] == pytest.approx(0.6)  # of 0.8 and 0.4, not 0.99
    # sizes of the sticky record only: not the unjudged 7 nor the healthy 5
    assert a["stiction_size_median"] == 3.0 and a["stiction_band_median"] == 1.0


def test_only_unreadable_rows_are_left_out():
    """A missing status, ``error`` and ``ok`` are records; ``unreadable`` is not."""
    valves = _valves(tag=["A", "A", "A", "A"], status=["ok", "unreadable", NAN, "error"],
                     verdict=["stiction", "no_verdict", "no_stiction", "no_verdict"])
    assert valves.loc["A", ["n_records", "n_judged", "n_stiction"]].tolist() == [3, 2, 1]
    gone = _valves(tag=["B"], status=["unreadable"], verdict=["stiction"])
    assert len(gone) == 0 and list(gone.columns) == list(COLUMNS)


def test_the_valve_of_each_row_is_its_tag_as_text_else_its_file_else_its_row():
    report = pd.DataFrame({
        "tag": ["FIC1", " FIC1 ", "", "  ", NAN, NAN, 101.0, "101", 7],
        "file": ["a.csv", "b.csv", "c.csv", "d.csv", "e.csv", NAN, "g.csv", "h.csv", " i "],
        "verdict": ["no_verdict"] * 9,
    })  # fmt: skip
    valves = summarise_valves(report)
    # no valve is judged: all tie on NaN and keep the order they first appear in
    assert valves["tag"].tolist() == ["FIC1", "file c.csv", "file d.csv", "file e.csv",
                                      "row 5", "101", "7"]  # fmt: skip
    assert valves["n_records"].tolist() == [2, 1, 1, 1, 1, 2, 1]
    assert (valves["verdict"] == "no_verdict").all() and valves["stiction_share"].isna().all()
    # without a file column the fallback is the row
    bare = pd.DataFrame({"tag": ["A", NAN, ""],
                         "verdict": ["stiction", "stiction", "no_stiction"]})
    assert summarise_valves(bare)["tag"].tolist() == ["A", "row 1", "row 2"]


def test_sorted_by_share_then_probability_with_nan_last():
    report = pd.DataFrame({
        "tag": ["D", "B", "B", "A", "A", "E", "E", "C"],
        "verdict": ["no_verdict", "stiction", "no_stiction", "stiction", "no_stiction",
                    "no_stiction", "stiction", "stiction"],
        "stiction_probability": [0.95, NAN, NAN, 0.9, 0.5, 0.8, 1.0, 0.6],
    })  # fmt: skip
    valves = summarise_valves(report)
    # C: 1 of 1; E, A, B: 1 of 2 with medians 0.9, 0.7 and none; D: nothing judged
    assert valves["tag"].tolist() == ["C", "E", "A", "B", "D"]
    assert valves["stiction_share"].tolist()[:4] == [1.0, 0.5, 0.5, 0.5]
    assert valves["probability_median"].tolist()[:3] == pytest.approx([0.6, 0.9, 0.7])
    assert np.isnan(valves["probability_median"].iloc[3])
    assert np.isnan(valves["probability_median"].iloc[4])  # 0.95 was not a judged record
    assert list(valves.columns) == ["tag", *COLUMNS]
    assert valves.index.tolist() == [0, 1, 2, 3, 4]


def test_min_share_decides_at_its_bound():
    report = pd.DataFrame({"tag": ["A"] * 3 + ["B"] * 4,
                           "verdict": ["stiction", "no_stiction", "no_stiction",
                                       "stiction", "stiction", "stiction", "no_stiction"]})
    v = summarise_valves(report, min_share=1 / 3).set_index("tag")["verdict"]
    assert v.to_dict() == {"A": "stiction", "B": "stiction"}
    v = summarise_valves(report, min_share=0.75).set_index("tag")["verdict"]
    assert v.to_dict() == {"A": "no_stiction", "B": "stiction"}  # 3 of 4 is 0.75
    v = summarise_valves(report, min_share=0.76).set_index("tag")["verdict"]
    assert v.to_dict() == {"A": "no_stiction", "B": "no_stiction"}


def test_loop_type_is_the_first_one_given():
    valves = _valves(tag=["A", "A", "A", "B"], verdict=["stiction"] * 4,
                     loop_type=[NAN, "flow", "level", NAN])
    assert valves["loop_type"].to_dict() == {"A": "flow", "B": ""}
    assert _valves(tag=["A"], verdict=["stiction"])["loop_type"].tolist() == [""]


def test_columns_a_report_lacks_give_nan_and_nat():
    valves = _valves(tag=["A", "A"], verdict=["stiction", "no_stiction"])
    a = valves.loc["A"]
    assert np.isnan(a["probability_median"]) and np.isnan(a["stiction_size_median"])
    assert np.isnan(a["stiction_band_median"])
    assert a["first_start"] is pd.NaT and a["last_start"] is pd.NaT


def test_values_that_are_not_numbers_are_left_out_of_the_medians():
    """A report edited by hand: a dash where a probability was."""
    valves = _valves(tag=["A", "A", "A"], verdict=["stiction"] * 3,
                     stiction_probability=["0.9", "-", 0.5],
                     stiction_size_mean=pd.array([2.0, None, 4.0], dtype="Float64"))
    assert valves.loc["A", "probability_median"] == pytest.approx(0.7)
    assert valves.loc["A", "stiction_size_median"] == 3.0


def test_starts_without_an_offset_stay_local_and_unreadable_ones_are_left_out():
    valves = _valves(tag=["A", "A", "A", "B"], verdict=["stiction"] * 4,
                     start=["2025-01-02 06:00", "not a time", "2025-01-01 18:00", NAN])
    a = valves.loc["A"]
    assert a["first_start"] == pd.Timestamp("2025-01-01 18:00") and a["first_start"].tz is None
    assert a["last_start"] == pd.Timestamp("2025-01-02 06:00")
    assert valves.loc["B", "first_start"] is pd.NaT


def test_several_utc_offsets_are_read_in_utc_for_every_valve():
    """Daily scans over the switch to summer time: A's records carry +01:00 and
    +02:00, B's only +01:00; both valves' starts are in UTC, one column of one kind."""
    valves = _valves(tag=["A", "A", "A", "B"], verdict=["stiction"] * 4,
                     start=["2025-03-30 03:30+02:00", "2025-03-30 01:30+01:00", "n/a",
                            "2025-03-29 12:00+01:00"])  # fmt: skip
    assert valves.loc["A", "first_start"] == pd.Timestamp("2025-03-30 00:30", tz="UTC")
    assert valves.loc["A", "last_start"] == pd.Timestamp("2025-03-30 01:30", tz="UTC")
    assert valves.loc["B", "first_start"] == pd.Timestamp("2025-03-29 11:00", tz="UTC")
    for col in ("first_start", "last_start"):
        assert str(valves[col].dtype).startswith("datetime64") and valves[col].dt.tz is not None
        assert str(valves[col].dt.tz) == "UTC"
    assert valves["first_start"].min() == pd.Timestamp("2025-03-29 11:00", tz="UTC")


def test_leftover_index_columns_and_an_empty_report():
    report = pd.DataFrame({"tag": ["A", "A"], "verdict": ["stiction", "stiction"]})
    twice = report.reset_index().reset_index()  # columns level_0 and index
    assert summarise_valves(twice)["n_records"].tolist() == [2]
    empty = summarise_valves(report.iloc[:0])
    assert len(empty) == 0 and list(empty.columns) == ["tag", *COLUMNS]
    assert several_records(empty) is False


def test_several_records():
    assert several_records(pd.DataFrame({"n_records": [1, 1, 1]})) is False
    assert several_records(pd.DataFrame({"n_records": [1, 2]})) is True


def test_bad_input_names_what_is_wrong():
    with pytest.raises(TypeError, match="got dict"):
        summarise_valves({"tag": ["A"], "verdict": ["stiction"]})
    with pytest.raises(ValueError, match=r"no 'verdict' or 'tag' column; it has \['x'\]"):
        summarise_valves(pd.DataFrame({"x": [1]}))
    wide = pd.DataFrame({f"c{i}": [0] for i in range(14)})
    with pytest.raises(ValueError, match=r"'c11'\]\. Pass by=<the column naming each valve>\.$"):
        summarise_valves(wide)
    report = pd.DataFrame({"tag": ["A"], "verdict": ["stiction"], "n_records": [1]})
    for by in ("n_records", "verdict"):
        with pytest.raises(ValueError, match=f"by='{by}' is a column of the summary"):
            summarise_valves(report, by=by)


# --------------------------------------------------------------------- write_html_report


def _page(report, tmp_path, X=None, **kwargs):
    return write_html_report(report, X, path=tmp_path / "r.html", **kwargs).read_text("utf-8")


def _rows(text):
    """{row id: [(class, data-value or None, text shown)]} of the table body."""
    body = text[text.index("<tbody>") : text.index("</tbody>")]
    rows = {}
    for i, cells in re.findall(r'<tr class="[^"]*" id="row-(\d+)">(.*?)</tr>', body):
        rows[int(i)] = [(c, v or None, s) for c, v, s in re.findall(
            r'<td class="([^"]*)"(?: data-value="([^"]*)")?>(.*?)</td>', cells)]
    return rows


def _heads(text):
    return re.findall(r'<th data-col="([^"]*)">(.*?)</th>', text)


def test_the_table_shows_the_report_columns_it_knows_in_a_fixed_order(tmp_path):
    report = pd.DataFrame({
        "reason": ["", "too short"], "area_ratio": [1.5, NAN], "foo": [1, 2],
        "verdict": ["stiction", "no_verdict"], "tag": ["A1", "B2"],
        "stiction_probability": [0.934, NAN], "file": ["a.csv", "b.csv"],
    })  # fmt: skip
    text = _page(report, tmp_path)
    # period is always a column (empty here: no figure, no scanned period); foo is not one
    assert _heads(text) == [("file", "file"), ("tag", "tag"), ("verdict", "verdict"),
                            ("stiction_probability", "p(stiction)"), ("period", "period"),
                            ("area_ratio", "area ratio"), ("reason", "reason")]  # fmt: skip
    assert text.count("<th ") == 7 and text.count("</th><th ") == 6
    rows = _rows(text)
    assert rows[0] == [("file", None, "a.csv"), ("tag", None, "A1"),
                       ("verdict", None, "stiction"), ("num", "0.934", "0.93"),
                       ("num", None, ""), ("num", "1.5", "1.50"), ("reason", None, "")]
    assert rows[1] == [("file", None, "b.csv"), ("tag", None, "B2"),
                       ("verdict", None, "no_verdict"), ("num", None, ""),
                       ("num", None, ""), ("num", None, ""), ("reason", None, "too short")]
    assert '<tr class="stiction" id="row-0">' in text
    assert '<tr class="no_verdict" id="row-1">' in text
    assert "<p class=\"summary\">2 loops. stiction: 1, no_verdict: 1. Click" in text


def test_numbers_are_rounded_to_their_kind_and_sort_by_their_full_value(tmp_path):
    report = pd.DataFrame({
        "stiction_probability": [0.456, 1.0, 0.0, "n/a", np.inf],
        "stiction_size_mean": [2.26, 3, -0.4, None, -np.inf],
        "stiction_band_fit": [0.05, 12.349, NAN, 1e-5, 7.0],
        "period": [125.0, 0.5, NAN, 2.0, 3.0],
        "area_ratio": [1.005, 2.0, 1.0 / 3.0, NAN, 0.125],
        "oscillating": [True, False, NAN, None, 1],
        "cause": [NAN, None, "valve", "", "<b>"],
    })  # fmt: skip
    rows = _rows(_page(report, tmp_path))
    shown = {i: [(v, s) for _, v, s in rows[i]] for i in rows}
    # cause, probability (2 decimals), size and band (1), oscillates, period (1), R (2)
    assert shown[0] == [(None, ""), ("0.456", "0.46"), ("2.26", "2.3"),
                        ("0.05", "0.1"), (None, "yes"), ("125.0", "125.0"),
                        ("1.005", "1.00")]  # fmt: skip
    assert shown[1] == [(None, ""), ("1.0", "1.00"), ("3.0", "3.0"), ("12.349", "12.3"),
                        (None, "no"), ("0.5", "0.5"), ("2.0", "2.00")]  # fmt: skip
    assert shown[2] == [(None, "valve"), ("0.0", "0.00"), ("-0.4", "-0.4"), (None, ""),
                        (None, ""), (None, ""), (repr(1 / 3), "0.33")]  # fmt: skip
    # text where a number belongs is shown as it is, and sorts as text
    assert shown[3] == [(None, ""), (None, "n/a"), (None, ""), ("1e-05", "0.0"),
                        (None, ""), ("2.0", "2.0"), (None, "")]  # fmt: skip
    assert shown[4] == [(None, "&lt;b&gt;"), (None, ""), (None, ""), ("7.0", "7.0"),
                        (None, "yes"), ("3.0", "3.0"), ("0.125", "0.12")]  # fmt: skip
    assert [c for c, _, _ in rows[0]] == ["cause", "num", "num", "num", "oscillating",
                                          "num", "num"]  # fmt: skip


def test_names_reasons_and_the_title_are_escaped(tmp_path):
    tag = "<FIC&1 \"x\" 'y'>"
    report = pd.DataFrame({"file": ["a&b<c>.csv", "q\"'.csv"], "tag": [tag, NAN],
                           "verdict": ["stiction", "no_stiction"],
                           "reason": ["PV < 0 & OP > 100", "ok"]})  # fmt: skip
    text = _page(report, tmp_path, title="scan <A&B>")
    assert "<title>scan &lt;A&amp;B&gt;</title>" in text
    assert "<h1>scan &lt;A&amp;B&gt;</h1>" in text
    rows = _rows(text)
    assert rows[0][0] == ("file", None, "a&amp;b&lt;c&gt;.csv")
    assert rows[0][1] == ("tag", None, "&lt;FIC&amp;1 &quot;x&quot; &#x27;y&#x27;&gt;")
    assert rows[0][4] == ("reason", None, "PV &lt; 0 &amp; OP &gt; 100")
    assert rows[1][0] == ("file", None, "q&quot;&#x27;.csv")
    assert rows[1][1] == ("tag", None, "")
    assert tag not in text and "a&b" not in text


def test_the_valve_sentence_names_the_valves_sticky_in_half_their_records(tmp_path):
    report = pd.DataFrame({
        "tag": ["A&1", "B", "A&1", "B", "C", "C", "D", "E"],
        "verdict": ["stiction", "stiction", "stiction", "no_stiction", "no_stiction",
                    "no_stiction", "no_verdict", "no_stiction"],
    })  # fmt: skip
    text = _page(report, tmp_path)
    # A&1 2 of 2 (share 1) before B 1 of 2; C 0 of 2, D (nothing judged), E 0 of 1 unnamed
    assert ('<p class="summary">8 loops. no_stiction: 4, stiction: 3, no_verdict: 1. '
            "5 valves; called sticky in at least half of their judged records: 2, "
            "A&amp;1 (2 of 2), B (1 of 2). Click") in text
    calm = report.assign(verdict=["no_stiction"] * 4 + ["stiction"] + ["no_stiction"] * 3)
    assert ("8 loops. no_stiction: 7, stiction: 1. 5 valves; called sticky in at least half "
            "of their judged records: 1, C (1 of 2). Click") in _page(calm, tmp_path)
    calm = report.assign(verdict=["no_stiction"] * 8)
    assert ("8 loops. no_stiction: 8. 5 valves; called sticky in at least half of their "
            "judged records: 0. Click") in _page(calm, tmp_path)
    # no sentence without tags or verdicts, nor when every valve has one record
    assert ('<p class="summary">8 loops. no_stiction: 4, stiction: 3, no_verdict: 1. Click'
            in _page(report.rename(columns={"tag": "name"}), tmp_path))
    assert "valves;" not in _page(report.drop(columns="verdict"), tmp_path)
    assert "valves;" not in _page(report.iloc[[0, 1, 4, 6]], tmp_path)


def test_periods_status_and_sample_times_come_from_the_report(tmp_path):
    report = pd.DataFrame({
        "tag": list("abcde"), "oscillation_period": [10.0, 10.0, 10.0, 10.0, NAN],
        "ts": [2.0, -1.0, NAN, 0.0, 3.0], "input_ts": [5.0] * 5,
        "input_status": ["ok", "error", "ok", "ok", NAN],
    }, index=[7, 3, 9, 1, 0])  # fmt: skip

    def periods(text):
        return [float(r[1][1]) if r[1][1] else None for _, r in sorted(_rows(text).items())]

    text = _page(report, tmp_path)
    assert sorted(_rows(text)) == [0, 1, 2, 3, 4]  # rows by position, not index labels
    # samples times the sample time; a sample time that is not positive counts as 1
    assert periods(text) == [20.0, 10.0, 10.0, 10.0, None]
    assert _rows(text)[4][1] == ("num", None, "")  # no period shown: empty, not "None"
    assert [r[2][2] for _, r in sorted(_rows(text).items())] == ["ok", "error", "ok", "ok", ""]
    assert periods(_page(report.drop(columns="ts"), tmp_path)) == [50.0] * 4 + [None]
    assert periods(_page(report.drop(columns=["ts", "input_ts"]), tmp_path)) == [10.0] * 4 + [None]
    assert periods(_page(report, tmp_path, ts=0.5)) == [5.0] * 4 + [None]
    assert periods(_page(report, tmp_path, ts=[1, 2, 3, 4, 5])) == [10, 20, 30, 40, None]
    # the report's own period and status are kept as they are
    own = report.assign(period=[1.0, 2.0, 3.0, 4.0, 5.0], status=["x"] * 5)
    text = _page(own, tmp_path)
    assert periods(text) == [1.0, 2.0, 3.0, 4.0, 5.0]
    assert {r[2][2] for r in _rows(text).values()} == {"x"}


def test_figures_go_to_sticky_loops_first_and_each_row_links_its_own(tmp_path):
    report = pd.DataFrame({
        "file": ["f0.csv", "f1.csv", "f2.csv", "f3.csv", "f4.csv"],
        "tag": ["T<0>", "T1", NAN, "T3", ""],
        "verdict": ["no_stiction", "stiction", "no_verdict", "stiction", "no_stiction"],
        "reason": ["r0", "r&1", "r2", "r3", "r4"],
    })  # fmt: skip
    X = np.full((5, 60, 3), np.nan)  # nothing to draw: a note instead of a figure

    def sections(text):
        return re.findall(r'<section class="loop" id="loop-(\d+)"><h2>(.*?)</h2>'
                          r'<p class="summary">(.*?)</p>(.*?)</section>', text)

    # no progress bar here: its thread hangs mutmut's forked runs (docs/mutation.md)
    text = _page(report, tmp_path, X, max_figures=3)
    # the two sticky loops, then the first other one; shown in the table's order
    assert sections(text) == [
        ("0", "T&lt;0&gt;: no_stiction", "r0", '<p class="note">no figure: no data</p>'),
        ("1", "T1: stiction", "r&amp;1", '<p class="note">no figure: no data</p>'),
        ("3", "T3: stiction", "r3", '<p class="note">no figure: no data</p>'),
    ]
    rows = _rows(text)
    for i in (0, 1, 3):
        assert rows[i][0][2].startswith(f'<a href="#loop-{i}">f{i}.csv</a>')
        assert rows[i][1][2].startswith(f'<a href="#loop-{i}">')
    assert rows[0][1][2] == '<a href="#loop-0">T&lt;0&gt;</a>'
    assert rows[2][:2] == [("file", None, "f2.csv"), ("tag", None, "")]
    assert "<a " not in "".join(c[2] for c in rows[4])
    # a row without a tag is named by its file; sticky loops first even with one figure
    assert [s[:2] for s in sections(_page(report, tmp_path, X, max_figures=1))] == [
        ("1", "T1: stiction")]
    assert [s[1] for s in sections(_page(report, tmp_path, X))] == [
        "T&lt;0&gt;: no_stiction", "T1: stiction", "f2.csv: no_verdict", "T3: stiction",
        "f4.csv: no_stiction"]  # fmt: skip
    assert sections(_page(report, tmp_path, X, max_figures=0)) == []
    # without a verdict column: the first loops, named "loop i" without tag or file
    bare = pd.DataFrame({"x": [1, 2, 3]})
    text = _page(bare, tmp_path, X[:3], max_figures=2)
    assert [s[:3] for s in sections(text)] == [("0", "loop 0: ", ""), ("1", "loop 1: ", "")]
    assert text.count('<tr class="" id="row-') == 3
    assert '<p class="summary">3 loops. ' in text


def test_a_loop_read_again_that_fails_or_is_missing_gets_a_note(tmp_path):
    report = pd.DataFrame({"tag": ["A", "B"], "verdict": ["stiction", "stiction"]})

    def loop(i):
        if i == 0:
            raise OSError("<moved> & gone")
        return None

    text = _page(report, tmp_path, loop)
    assert '<p class="note">no figure: error: OSError: &lt;moved&gt; &amp; gone</p>' in text
    assert text.count('<p class="note">no figure: no data</p>') == 1


def test_a_drawn_figure_gives_the_period_of_its_cycles(tmp_path):
    """A sine of 40 samples a period, sampled every 0.5 s: a period of 20 s."""
    t = np.arange(400)
    X = np.stack([np.sin(2 * np.pi * t / 40), np.sin(2 * np.pi * (t - 5) / 40),
                  np.zeros(400)], axis=-1)[None]  # fmt: skip
    report = pd.DataFrame({"tag": ["a<b"], "verdict": ["stiction"], "ts": [0.5]})
    text = _page(report, tmp_path, X)
    assert float(_rows(text)[0][2][1]) == pytest.approx(20.0, rel=1e-3)
    assert text.count('src="data:image/png;base64,') == 1
    assert 'alt="PV, SP and OP of a&lt;b with its cycles' in text



def test_rows_and_sections_follow_each_other_and_the_file_is_utf8(tmp_path):
    report = pd.DataFrame({"tag": ["FIC-\u00b51 \u00b0C", 101, 2.5], "verdict": ["stiction"] * 3})
    text = write_html_report(report, np.full((3, 20, 3), np.nan), path=tmp_path / "r.html",
                             title="\u00e9tat").read_bytes().decode("utf-8")
    assert [r[0][2] for r in _rows(text).values()] == [
        '<a href="#loop-0">FIC-\u00b51 \u00b0C</a>', '<a href="#loop-1">101</a>',
        '<a href="#loop-2">2.5</a>']  # fmt: skip
    assert text.count("</tr><tr ") == 2 and text.count("</section><section ") == 2
    assert "<h1>\u00e9tat</h1>" in text
    # numeric tags head their sections as in the table (they had read "loop 2")
    assert '<section class="loop" id="loop-2"><h2>2.5: stiction</h2>' in text
    ints = write_html_report(report.assign(tag=[101, 7, 8]), np.full((3, 20, 3), np.nan),
                             path=tmp_path / "i.html").read_text(encoding="utf-8")  # fmt: skip
    assert '<section class="loop" id="loop-1"><h2>7: stiction</h2>' in ints
    # leftover index columns of a report reset twice do not matter
    again = report.reset_index().reset_index()
    assert _rows(_page(again, tmp_path)) == _rows(_page(report, tmp_path))


def test_defaults_title_path_and_the_number_of_figures(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    n = 250
    report = pd.DataFrame({"verdict": ["stiction" if i % 3 == 0 else "no_stiction"
                                       for i in range(n)]})  # fmt: skip
    reads = []

    def loop(i):
        reads.append(i)
        return None

    path = write_html_report(report, loop)
    assert path == tmp_path / "sktiction_report.html" or str(path) == "sktiction_report.html"
    text = (tmp_path / "sktiction_report.html").read_text("utf-8")
    assert "<title>sktiction report</title>" in text
    assert capsys.readouterr().err == ""  # no progress bar unless asked
    sticky = [i for i in range(n) if i % 3 == 0]  # 84
    others = [i for i in range(n) if i % 3]
    shown = [int(i) for i in re.findall(r'<section class="loop" id="loop-(\d+)">', text)]
    assert shown == sorted(sticky + others[:116])  # 200 figures at most, sticky first
    assert reads == shown  # each loop read once, in order
    text = _page(report, tmp_path, loop, max_figures=100)
    shown = [int(i) for i in re.findall(r'<section class="loop" id="loop-(\d+)">', text)]
    # the others in the table's order: the first 16
    assert shown == sorted(sticky + others[:16])


def test_figures_in_chunks_keep_each_loop_with_its_own_note(tmp_path):
    """40 loops: more than the 4 chunks of 8 read at a time."""
    reads = []

    def loop(i):
        reads.append(i)
        if i % 2:
            raise OSError(f"gone {i}")
        return None

    report = pd.DataFrame({"tag": [f"T{i}" for i in range(40)]})
    text = _page(report, tmp_path, loop)
    notes = re.findall(r'<section class="loop" id="loop-(\d+)"><h2>T(\d+): </h2>'
                       r'<p class="summary"></p><p class="note">no figure: (.*?)</p>', text)
    assert notes == [(str(i), str(i), f"error: OSError: gone {i}" if i % 2 else "no data")
                     for i in range(40)]  # fmt: skip
    assert reads == list(range(40))
    with pytest.raises(ValueError, match=r"^X has 2 loops but the report has 40 rows; they "
                                         r"must match\.$"):
        _page(report, tmp_path, np.zeros((2, 20, 3)))


def test_each_figure_gets_its_loop_sample_time_cycles_title_and_dpi(tmp_path, monkeypatch):
    """The drawing stood in for: what it is handed, the period of its cycle table
    (median 20 samples), the PNG's size (a 2 x 1 inch figure), its errors."""
    import matplotlib.pyplot as plt

    import sktiction.reports.plots as plots

    cycles = pd.DataFrame({"period": [10.0, 30.0, 20.0]})
    calls = []

    def plot(one, *, ts, cycles, title):
        calls.append((one.shape, ts, cycles, title))
        if title.startswith("d"):
            raise ValueError("bad <axis>")
        return plt.figure(figsize=(2, 1))

    # loop b has no cycle: its figure is drawn all the same, without a period
    monkeypatch.setattr(plots, "loop_cycles",
                        lambda one: pd.DataFrame() if one[0, 0, 0] == 2 else cycles)
    monkeypatch.setattr(plots, "plot_loop_summary", plot)
    X = np.ones((5, 30, 3))
    X[1] = 2.0
    X[2, :, 0] = np.nan  # no PV: nothing to draw, OP alone is not enough
    report = pd.DataFrame({"tag": list("abcde"), "ts": [0.5, 3.0, 1.0, 1.0, 3.0],
                           "verdict": ["stiction", "no_stiction", "stiction", "no_verdict",
                                       "no_stiction"],
                           "stiction_probability": [0.912, NAN, 0.5, NAN, NAN]})  # fmt: skip

    def sizes(text):
        pngs = re.findall(r'src="data:image/png;base64,([^"]+)"', text)
        return [(int.from_bytes(b[16:20], "big"), int.from_bytes(b[20:24], "big"))
                for b in map(base64.b64decode, pngs)]  # fmt: skip

    text = _page(report, tmp_path, X)
    assert [(c[0], c[1], len(c[2]), c[3]) for c in calls] == [
        ((1, 30, 3), 0.5, 3, "a, stiction (p = 0.91)"),
        ((1, 30, 3), 3.0, 0, "b, no stiction"),
        ((1, 30, 3), 1.0, 3, "d, no verdict"),
        ((1, 30, 3), 3.0, 3, "e, no stiction"),
    ]
    assert all(c[2] is cycles for c in calls if len(c[2]))
    assert sizes(text) == [(144, 72)] * 3  # 72 dpi
    assert [r[3][1:] for r in _rows(text).values()] == [
        ("10.0", "10.0"), (None, ""), (None, ""), (None, ""), ("60.0", "60.0")]
    assert '<p class="note">no figure: no data</p>' in text
    assert '<p class="note">no figure: error: ValueError: bad &lt;axis&gt;</p>' in text
    assert sizes(_page(report, tmp_path, X, dpi=36)) == [(72, 36)] * 3


def test_the_summary_without_verdicts_has_no_empty_sentence(tmp_path):
    report = pd.DataFrame({"tag": ["A", "B"], "area_ratio": [1.5, 2.0]})
    assert '<p class="summary">2 loops. Click' in _page(report, tmp_path)
    assert '<p class="summary">0 loops. Click' in _page(report.iloc[:0], tmp_path)
    # verdicts all missing, one valve twice: the valve sentence alone
    unjudged = pd.DataFrame({"tag": ["A", "A"], "verdict": [NAN, NAN]})
    assert ('<p class="summary">2 loops. 1 valve; called sticky in at least half of their '
            "judged records: 0. Click") in _page(unjudged, tmp_path)
    assert ". ." not in _page(unjudged, tmp_path)


def test_numbers_that_round_to_zero_show_no_minus_sign(tmp_path):
    report = pd.DataFrame({"stiction_probability": [-0.001, 0.004],
                           "stiction_size_mean": [-0.04, -0.06], "stiction_band_fit": [-0.0, 0.0],
                           "area_ratio": [-0.004, -0.005]})  # fmt: skip
    rows = _rows(_page(report, tmp_path))
    # shown rounded, without "-0.0"; sorted by the full value, sign and all
    assert [(v, s) for _, v, s in rows[0]] == [("-0.001", "0.00"), ("-0.04", "0.0"),
                                               ("-0.0", "0.0"), (None, ""), ("-0.004", "0.00")]
    assert [s for _, _, s in rows[1]] == ["0.00", "-0.1", "0.0", "", "-0.01"]


def test_a_figure_title_shows_no_minus_zero(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    import sktiction.reports.plots as plots

    titles = []

    def plot(one, *, ts, cycles, title):
        titles.append(title)
        return plt.figure(figsize=(1, 1))

    monkeypatch.setattr(plots, "loop_cycles", lambda one: pd.DataFrame())
    monkeypatch.setattr(plots, "plot_loop_summary", plot)
    report = pd.DataFrame({"tag": ["a"], "stiction_size_mean": [-0.001],
                           "stiction_band_fit": [-0.006]})  # fmt: skip
    _page(report, tmp_path, np.ones((1, 30, 3)))
    assert titles == ["a, peak-to-peak 0.00 %, fitted band -0.01 %"]


def test_tags_read_as_floats_show_and_pool_as_written(tmp_path):
    """A report read back from a file whose tag column holds numbers and a gap (a file
    that held no loop) has tags 101.0: the page shows 101, as the file says."""
    report = pd.DataFrame({"file": ["a.csv", "b.csv", "c.csv", "d.csv"],
                           "tag": [101.0, 101.0, NAN, 2.5],
                           "verdict": ["stiction", "stiction", "no_verdict", "no_stiction"]})
    text = _page(report, tmp_path, np.full((4, 20, 3), NAN))
    assert [r[1][2] for _, r in sorted(_rows(text).items())] == [
        '<a href="#loop-0">101</a>', '<a href="#loop-1">101</a>', '<a href="#loop-2"></a>',
        '<a href="#loop-3">2.5</a>']  # fmt: skip
    assert "101.0" not in text
    assert '<section class="loop" id="loop-0"><h2>101: stiction</h2>' in text
    assert ("4 loops. stiction: 2, no_verdict: 1, no_stiction: 1. 3 valves; called sticky "
            "in at least half of their judged records: 1, 101 (2 of 2). Click") in text
    valves = summarise_valves(report)
    assert valves["tag"].tolist() == ["101", "2.5", "file c.csv"]  # by share, NaN last
    assert valves["n_records"].tolist() == [2, 1, 1]
    # text tags are left as they are
    text = _page(report.assign(tag=["101.0", "101", "", " F 1 "]), tmp_path)
    assert [r[1][2] for _, r in sorted(_rows(text).items())] == ["101.0", "101", "", " F 1 "]


def test_a_long_export_with_number_tags_names_them_as_written(tmp_path):
    """Tags 101 and 007 in a long export, a trailer line without a tag: the tag column is
    read as text, so the loops are 101 (not 101.0) and 007 (not 7)."""
    from sktiction.datasets import read_loop_file

    t = pd.date_range("2024-01-01", periods=200, freq="10s").strftime("%Y-%m-%d %H:%M:%S")
    x = np.sin(np.arange(200) / 10)
    lines = ["Tag,Parameter,Time,Value"]
    for tag in ("101", "007"):
        lines += [f"{tag},{p},{s},{v:.6f}" for p in ("PV", "OP") for s, v in zip(t, x)]
    (tmp_path / "long.csv").write_text("\n".join([*lines, ",,End of data,"]) + "\n")
    meta = read_loop_file(tmp_path / "long.csv").meta
    assert sorted(meta["tag"]) == ["007", "101"] and (meta["status"] == "ok").all()
