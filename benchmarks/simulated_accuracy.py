"""Balanced accuracy of the three classifiers on held-out simulated loops.

The learned classifier is trained by ``pretrained_classifier(random_state=0)``; the
test loops come from another seed with ``make_loops``' default ranges (the same draw
as ``tests/test_classifiers.py``), plus a set of sticky loops that only slip during
setpoint moves and hold no cycle. Per cause, the share of loops called sticky.

Run: python benchmarks/simulated_accuracy.py
"""

import pandas as pd
from sklearn.metrics import balanced_accuracy_score

from sktiction import AreaRatioClassifier, ShapeLibraryClassifier, pretrained_classifier
from sktiction.datasets import make_loops

X, y, meta = make_loops(400, n_samples=2000, random_state=12345, return_meta=True)
slips, y_slips = make_loops(
    200, n_samples=2000, stiction_fraction=1.0, slip_fraction=1.0, random_state=54321
)
classifiers = {
    "area ratio (d=0.5)": AreaRatioClassifier(),
    "shape library (auto)": ShapeLibraryClassifier(),
    "learned": pretrained_classifier(random_state=0),
}
rows, shares = [], {}
for name, clf in classifiers.items():
    if name != "learned":
        clf.fit(X, y)
    pred = clf.predict(X)
    shares[name] = pd.Series(pred).groupby(meta["cause"] + " / " + meta["plant"]).mean()
    rows.append({"classifier": name, "balanced_accuracy": balanced_accuracy_score(y, pred),
                 "recall_slip_only_sticky": clf.predict(slips).mean()})
print("held-out simulated loops (400, default ranges, seed 12345):")
print(pd.DataFrame(rows).round(3).to_string(index=False))
print("\nshare called sticky, per cause / plant:")
print(pd.DataFrame(shares).round(2).to_string())
