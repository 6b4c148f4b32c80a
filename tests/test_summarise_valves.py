"""A scan's records pooled per valve: counts, shares, medians and the verdict per valve."""

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import load_plant_examples
from sktiction.reports import scan_loops, summarise_valves

NAN = np.nan


def report():
    """Four valves and a file that held no loop, with answers worked out by hand."""
    return pd.DataFrame({
        "file": ["a1.csv", "a2.csv", "a3.csv", "b1.csv", "b2.csv", "c1.csv", "c2.csv",
                 "x.csv", "notes.doc"],
        "tag": ["A", "A", "A", "B", "B", "C", "C", None, None],
        "status": ["ok"] * 8 + ["unreadable"],
        "verdict": ["stiction", "stiction", "no_stiction", "no_verdict", "no_verdict",
                    "stiction", "no_stiction", "stiction", "no_verdict"],
        "stiction_probability": [0.9, 0.6, 0.2, NAN, NAN, 0.8, 0.3, 0.7, NAN],
        "stiction_size_mean": [2.0, NAN, NAN, NAN, NAN, 1.0, NAN, NAN, NAN],
        "stiction_band_fit": [1.0, 3.0, 0.5, NAN, NAN, 2.0, 9.0, NAN, NAN],
        "start": ["2025-01-03", "2025-01-01", "2025-01-02", None, None, "2025-02-01",
                  "2025-02-02", None, None],
    })  # fmt: skip


def test_counts_shares_medians_and_verdicts_by_hand():
    valves = summarise_valves(report()).set_index("tag")
    # the unreadable file is no valve; the loop without a tag is a valve of its own
    assert sorted(valves.index) == ["A", "B", "C", "file x.csv"]
    a, b, c = valves.loc["A"], valves.loc["B"], valves.loc["C"]
    assert (a["n_records"], a["n_judged"], a["n_stiction"]) == (3, 3, 2)
    assert a["stiction_share"] == pytest.approx(2 / 3)
    assert a["probability_median"] == pytest.approx(0.6)  # of 0.9, 0.6, 0.2
    assert a["stiction_size_median"] == 2.0  # the sticky records' sizes only
    assert a["stiction_band_median"] == 2.0  # median of 1.0 and 3.0, not of 0.5
    assert a["first_start"] == pd.Timestamp("2025-01-01")
    assert a["last_start"] == pd.Timestamp("2025-01-03")
    assert a["verdict"] == "stiction"
    assert (b["n_records"], b["n_judged"], b["verdict"]) == (2, 0, "no_verdict")
    assert np.isnan(b["stiction_share"]) and np.isnan(b["probability_median"])
    assert pd.isna(b["first_start"])
    assert c["stiction_share"] == 0.5 and c["verdict"] == "stiction"  # half is enough
    assert c["stiction_band_median"] == 2.0
    # highest share first, the valve without a judged record last
    assert list(valves.index) == ["file x.csv", "A", "C", "B"]


def test_min_share_and_the_grouping_column():
    valves = summarise_valves(report(), min_share=1.0).set_index("tag")
    assert valves.loc["C", "verdict"] == "no_stiction"
    assert valves.loc["A", "verdict"] == "no_stiction"
    by_file = summarise_valves(report().rename(columns={"tag": "valve"}), by="valve")
    assert "valve" in by_file and by_file["n_records"].sum() == 8


def test_awkward_reports_keep_every_record():
    """Scans joined with pd.concat (repeated index labels), rows with neither tag nor
    file, tags of numbers with a gap and tags padded with spaces."""
    twice = pd.concat([report(), report()])
    valves = summarise_valves(twice).set_index("tag")
    assert valves.loc["A", "n_records"] == 6 and valves["n_records"].sum() == 16
    bare = pd.DataFrame({"tag": [101.0, np.nan, np.nan, " 101 "],
                         "verdict": ["stiction", "no_stiction", "stiction", "no_stiction"]})
    valves = summarise_valves(bare).set_index("tag")
    assert sorted(valves.index) == ["101", "row 1", "row 2"]
    assert valves.loc["101", "n_records"] == 2 and valves["n_records"].sum() == 4


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="'tag'"):
        summarise_valves(report().drop(columns="tag"))
    with pytest.raises(ValueError, match="'verdict'"):
        summarise_valves(report().drop(columns="verdict"))
    for bad in (0, 1.5, True, "0.5"):
        with pytest.raises(ValueError, match="min_share"):
            summarise_valves(report(), min_share=bad)
    with pytest.raises(ValueError, match="column of valve tags"):
        summarise_valves(report(), by="verdict")
    with pytest.raises(TypeError, match="DataFrame"):
        summarise_valves(report().to_dict())


def test_a_scan_pooled_per_valve_keeps_every_record():
    """The shipped plant windows, each twice as if two days were scanned: every valve
    has two records and the same verdict as its window, and no record is lost."""
    data = load_plant_examples()
    X = np.concatenate([data.X, data.X])
    meta = pd.concat([data.meta, data.meta], ignore_index=True)
    scan = scan_loops(X, meta)
    valves = summarise_valves(scan)
    assert len(valves) == len(data.meta) and (valves["n_records"] == 2).all()
    assert valves["n_stiction"].sum() == scan["verdict"].eq("stiction").sum()
    one = scan.iloc[: len(data.meta)].set_index("tag")["verdict"]
    assert (valves.set_index("tag")["verdict"] == one.reindex(valves["tag"])).all()
