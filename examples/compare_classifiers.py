"""Compare the three classifiers in a cross-validated benchmark on simulated loops.

Prints, per cause and per stiction model, the share of loops each classifier calls
sticky (recall for the sticky rows, false-alarm rate for the others), the balanced
accuracy of each, and saves a bar chart.

Run: python examples/compare_classifiers.py [n_loops] [figure.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from sklearn.metrics import balanced_accuracy_score  # noqa: E402
from sklearn.model_selection import StratifiedKFold, cross_val_predict  # noqa: E402

from sktiction import (  # noqa: E402
    AreaRatioClassifier,
    ShapeLibraryClassifier,
    make_learned_classifier,
)
from sktiction.datasets import make_loops  # noqa: E402

n_loops = int(sys.argv[1]) if len(sys.argv) > 1 else 800
figure = sys.argv[2] if len(sys.argv) > 2 else "compare_classifiers.png"

# the clean world the papers describe; pass world="default" for loops as historians record them
X, y, meta = make_loops(
    n_loops, n_samples=2000, world="classic", random_state=1, return_meta=True
)
cv = StratifiedKFold(n_splits=5, shuffle=True, random_state=0)
classifiers = {
    "area ratio (d=0.5)": AreaRatioClassifier(threshold=0.5),
    "shape library": ShapeLibraryClassifier(),
    "learned": make_learned_classifier(random_state=0),
}
pred = pd.DataFrame({name: cross_val_predict(clf, X, y, cv=cv, n_jobs=-1)
                     for name, clf in classifiers.items()})

group = np.where(meta["cause"] == "stiction", "stiction / " + meta["valve"].astype(str),
                 meta["cause"])
table = pred.groupby(group).mean()
table["n_loops"] = pd.Series(group).value_counts()
print("share of loops called sticky (recall on stiction rows, false alarms elsewhere):")
print(table.round(3).to_string())
print("\nbalanced accuracy, 5-fold cross-validated:")
for name in classifiers:
    print(f"  {name:20s} {balanced_accuracy_score(y, pred[name]):.3f}")

ax = table.drop(columns="n_loops").plot.barh(figsize=(8, 4.5))
ax.set_xlabel("share of loops called sticky")
ax.set_xlim(0, 1)
ax.set_title("Cross-validated verdicts on simulated loops")
plt.tight_layout()
plt.savefig(figure, dpi=120)
print(f"\nsaved {figure}")
