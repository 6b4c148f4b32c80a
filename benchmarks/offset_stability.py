"""Does a verdict depend on where a measured window starts or ends?

Each plant window (``../shared/data/plant``, 751 samples at 10 s) is scanned again with 0-9
samples cut off its start, then off its end (at most 90 s of two hours). Printed per side:
how many windows change verdict over the ten offsets, the range of the number called sticky
and of balanced accuracy against the labels, and the probability swing (largest minus
smallest over the offsets) at the median window and at most.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/offset_stability.py`` (about a minute once
the default model is cached).
"""

import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.metrics import balanced_accuracy_score

sys.path.insert(0, str(Path(__file__).parent))
from _measured_common import data_dir  # noqa: E402

from sktiction import pretrained_classifier  # noqa: E402
from sktiction.datasets import read_loops  # noqa: E402
from sktiction.reports import scan_loops  # noqa: E402


def main(offsets=range(10)):
    root = data_dir()
    if root is None:
        print("no measured data (../shared/data or $SKTICTION_DATA)")
        return
    loops = read_loops(root / "plant")
    labels = pd.read_csv(root / "plant" / "index.csv")
    y = (loops.meta.merge(labels, on="file", how="left")["label"] == "stiction").to_numpy(int)
    clf = pretrained_classifier()
    width = loops.X.shape[1]
    for side in ("start", "end"):
        verdicts, probs = [], []
        for k in offsets:
            X = loops.X[:, k:] if side == "start" else loops.X[:, : width - k]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                report = scan_loops(X, loops.meta, classifier=clf, max_gap="auto")
            verdicts.append(report["verdict"].to_numpy())
            probs.append(report["stiction_probability"].to_numpy())
        verdicts, probs = np.array(verdicts), np.array(probs)
        changed = (verdicts != verdicts[0]).any(axis=0)
        sticky = (verdicts == "stiction").sum(axis=1)
        acc = [balanced_accuracy_score(y, v == "stiction") for v in verdicts]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            swing = np.nanmax(probs, axis=0) - np.nanmin(probs, axis=0)
        print(f"cut from the {side}, {len(offsets)} offsets: verdict changes on {changed.sum()} "
              f"of {len(y)} windows; called sticky {sticky.min()}-{sticky.max()}; balanced "
              f"accuracy {min(acc):.2f}-{max(acc):.2f} ({acc[0]:.2f} uncut); probability "
              f"swing median {np.nanmedian(swing):.3f}, max {np.nanmax(swing):.2f}")


if __name__ == "__main__":
    main()
