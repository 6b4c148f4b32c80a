"""Accuracy on measured loops (plant historian windows, ISDB), trained on simulation only.

Nothing here is fitted to the measured files: the learned classifier is trained on
``make_loops`` alone and the rules keep their published thresholds. Figures are given
per data set and per loop type, per window and per valve (tag): windows of one valve
are not independent (23 of the 26 sticky plant windows come from one valve), so the
per-valve figures are the honest ones. Skips cleanly when ``../shared/data`` is absent.

Run: python benchmarks/measured_data.py [--per-loop]
"""

import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).parent))
from _measured_common import load_measured  # noqa: E402

from sktiction import pretrained_classifier  # noqa: E402
from sktiction.reports import scan_loops  # noqa: E402

VERDICTS = {
    "area ratio": "area_ratio_stiction",
    "shape library": "shape_stiction",
    "learned": "learned_stiction",
}


def rates(y, pred):
    """Balanced accuracy, recall (sticky found) and specificity (healthy cleared)."""
    y, pred = np.asarray(y, bool), np.asarray(pred, bool)
    recall = pred[y].mean() if y.any() else np.nan
    spec = (~pred[~y]).mean() if (~y).any() else np.nan
    bal = np.nanmean([recall, spec])
    return bal, recall, spec


def table(report, by):
    rows = []
    for key, part in report.groupby(by):
        for name, col in VERDICTS.items():
            bal, rec, spec = rates(part["y"], part[col])
            rows.append({**dict(zip(by, key if isinstance(key, tuple) else (key,))),
                         "classifier": name, "n": len(part), "n_sticky": int(part["y"].sum()),
                         "balanced_acc": bal, "recall": rec, "specificity": spec})
    return pd.DataFrame(rows)


def per_valve(report):
    """One vote per valve: the share of its windows called sticky, thresholded at 0.5."""
    agg = {col: "mean" for col in VERDICTS.values()}
    valves = report.groupby(["dataset", "tag"]).agg({"y": "max", **agg}).reset_index()
    for col in VERDICTS.values():
        valves[col] = (valves[col] >= 0.5).astype(int)
    valves["all"] = "all valves"
    return table(valves, ["all"])


def main():
    loaded = load_measured()
    if loaded is None:
        print("measured data folder not found (../shared/data or $SKTICTION_DATA): skipped")
        return 0
    X, y, groups, meta = loaded
    t0 = time.perf_counter()
    clf = pretrained_classifier(random_state=0)
    t1 = time.perf_counter()
    report = scan_loops(X, meta[["dataset", "file", "tag", "loop_type"]], classifier=clf)
    t2 = time.perf_counter()
    report["y"] = y
    report["learned_stiction"] = (report["verdict"] == "stiction").astype(int)
    print(f"trained on simulation in {t1 - t0:.1f} s; scanned {len(X)} measured loops "
          f"in {t2 - t1:.1f} s\n")
    pd.set_option("display.width", 160)
    fmt = {"float_format": "{:.2f}".format, "index": False}
    print("== per data set (windows) ==")
    print(table(report, ["dataset"]).to_string(**fmt))
    print("\n== per data set and loop type (windows) ==")
    print(table(report, ["dataset", "loop_type"]).to_string(**fmt))
    print("\n== per valve (one vote per tag, both data sets) ==")
    print(per_valve(report).to_string(**fmt))
    wrong = report[report["learned_stiction"] != report["y"]]
    print(f"\n== loops the learned classifier gets wrong: {len(wrong)} of {len(report)} ==")
    cols = ["dataset", "tag", "loop_type", "y", "status", "stiction_probability", "area_ratio",
            "shape_confidence", "n_cycles", "reason"]
    print(wrong[cols].to_string(**fmt))
    if "--per-loop" in sys.argv:
        print("\n== every loop ==")
        print(report[cols + list(VERDICTS.values())].to_string(**fmt))
    return 0


if __name__ == "__main__":
    sys.exit(main())
