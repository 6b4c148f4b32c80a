"""Scan exports as historians write them: long tables, a sheet per loop, "-9999" outages.

Writes a small site of three files from simulated loops whose cause is known, then scans
it as ``sktiction scan`` would and prints what the readers and the scan's repairs did:

- ``unit1_pi_compressed.csv``: a PI-style long export (``Tag, Timestamp, Value, Status``),
  each tag written only when it moved by more than a deadband, one record "Bad Input";
  the reader pivots it to one column per tag and holds each tag's last record on the scan
  period's grid;
- ``unit2_loops.xlsx``: a workbook with a cover sheet and a sheet per loop (needs
  ``pip install -e ".[xlsx]"``; skipped without openpyxl);
- ``unit3_outage.csv``: a wide file in which the historian wrote -9999 for 30 rows of
  PV and OP; the scan reads them as a gap and analyses the longest stretch.

The last column gives each loop's probability scanned as an array before it was exported:
the readers and repairs should give it back (the model's own errors on these four loops
are the model's, not the files'). Last, ``clean_loops`` makes the scan's repairs on the
loops as read, as one would before fitting a model on measured loops.

Run: python examples/historian_exports.py [folder]  (default: a temporary folder)
"""

import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from sktiction import clean_loops
from sktiction.datasets import make_loops, read_loop_file, read_loops
from sktiction.reports import scan_files, scan_loops

folder = Path(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="exports_"))
folder.mkdir(parents=True, exist_ok=True)
X, y, meta = make_loops(4, n_samples=2000, random_state=5, return_meta=True)
truth = meta["cause"].tolist()
start = pd.Timestamp("2026-11-02 06:00")
stamps = start + pd.to_timedelta(np.arange(2000) * 2.0, unit="s")  # 2 s scan


def deadband(x, band):
    """Indices a compressing historian keeps: a value whenever it moved by > band."""
    keep, last = [0], x[0]
    for i in range(1, len(x)):
        if abs(x[i] - last) > band:
            keep.append(i)
            last = x[i]
    return np.unique(keep + [len(x) - 1])


# 1. a long, compressed PI export of loop 0
rows = []
for c, name in enumerate(["PV", "OP", "SP"]):
    x = X[0, :, c]
    keep = deadband(x, 0.05 * np.std(x) if np.std(x) > 0 else 1.0)
    rows.append(pd.DataFrame({"Tag": f"FIC101.{name}", "Timestamp": stamps[keep],
                              "Value": x[keep].astype(object), "Status": "Good"}))  # fmt: skip
long = pd.concat(rows, ignore_index=True)
long.loc[10, ["Value", "Status"]] = ["Bad Input", "Bad"]
long.sample(frac=1, random_state=0).to_csv(folder / "unit1_pi_compressed.csv", index=False)

# 2. a workbook with a sheet per loop (loops 1 and 2)
try:
    with pd.ExcelWriter(folder / "unit2_loops.xlsx") as book:
        pd.DataFrame({"note": ["exported for the audit"]}).to_excel(
            book, sheet_name="cover", index=False)  # fmt: skip
        for j, tag in ((1, "LIC201"), (2, "TIC202")):
            sheet = pd.DataFrame({"time": stamps, "PV": X[j, :, 0], "OP": X[j, :, 1],
                                  "SP": X[j, :, 2]})  # fmt: skip
            sheet.to_excel(book, sheet_name=tag, index=False)
except ImportError:
    print("openpyxl is not installed: the workbook is left out")

# 3. a wide file with an outage written as -9999 (loop 3)
wide = pd.DataFrame({"time": stamps, "PIC301.PV": X[3, :, 0], "PIC301.OP": X[3, :, 1],
                     "PIC301.SP": X[3, :, 2]})  # fmt: skip
wide.loc[1200:1229, ["PIC301.PV", "PIC301.OP"]] = -9999.0
wide.to_csv(folder / "unit3_outage.csv", index=False)

print(f"site in {folder}\n\nwhat the readers did:")
for path in sorted(folder.iterdir()):
    for _, row in read_loop_file(path).meta.iterrows():
        print(f"  {path.name} [{row['tag']}] ts {row['ts']:g} s: {row['reason'] or 'as is'}")

report = scan_files(folder)
order = {"FIC101": 0, "LIC201": 1, "TIC202": 2, "PIC301": 3}
loop = report["tag"].map(order)
report["truth"] = loop.map(dict(enumerate(truth)))
# the same loops scanned as arrays, before any export: what the files should give back
# (the outage's loop as the stretch the scan keeps)
clean = scan_loops(X, meta=pd.DataFrame({"ts": np.full(4, 2.0)}))["stiction_probability"]
clean[3] = scan_loops(X[3:, :1200], meta=pd.DataFrame({"ts": [2.0]}))["stiction_probability"][0]
report["p_before_export"] = loop.map(clean)
columns = ["file", "tag", "truth", "verdict", "stiction_probability", "p_before_export",
           "n_placeholders", "kept_start", "kept_stop"]  # fmt: skip
print("\nthe scan (truth: the simulated cause; p_before_export: the loop scanned as an array")
print("before it was exported, which the readers and repairs should give back):")
print(report[columns].to_string(index=False, float_format="%.2f"))

# the same repairs on loops in memory (e.g. before fitting a model on measured loops)
site = read_loops(folder)
loops, repairs = clean_loops(site.X)
repairs.insert(0, "tag", site.meta["tag"].to_numpy())
print("\nclean_loops on the loops as read (what a classifier is given):")
print(repairs.to_string(index=False))
