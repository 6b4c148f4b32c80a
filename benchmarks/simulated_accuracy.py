"""Accuracy and reliability of the classifiers on held-out simulated loops, across worlds.

The learned classifier is trained on one world of ``make_loops`` (``pretrained_classifier``:
the default world, loops as historians record them, or sktiction 0.1's classic world)
and tested on held-out loops of both worlds (seed 12345, other loops than training),
so each model is also judged on loops made differently from its training set. The
rules keep their published thresholds.

Printed per (model, test world): balanced accuracy with "no verdict" counted as "no
stiction" (what a user gets), the share of loops the model judges (in its domain)
and the balanced accuracy on those; on the default world also the balanced accuracy on
identifiable loops (healthy ones and sticky ones whose slips move PV by at least one
noise standard deviation: ``meta["stiction_visible"]``); recall on sticky loops that
only slip during setpoint moves (classic world, no cycle); for the learned models the
Brier score and a reliability table of the calibrated probabilities (loops in its domain).

Run: python benchmarks/simulated_accuracy.py [n_test]
"""

import sys
import time

import numpy as np
import pandas as pd
from sklearn.metrics import balanced_accuracy_score, brier_score_loss

from sktiction import AreaRatioClassifier, ShapeLibraryClassifier, pretrained_classifier
from sktiction.classifiers._pretrained import _shows_its_label
from sktiction.datasets import make_loops

N_TEST = int(sys.argv[1]) if len(sys.argv) > 1 else 400
TEST_SEED, SLIP_SEED = 12345, 54321
WORLDS = {"default": {}, "classic": {"world": "classic"}}


def reliability(y, p, bins=(0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0)):
    """Observed share of sticky loops per bin of predicted probability."""
    cut = pd.cut(p, bins, include_lowest=True)
    table = pd.DataFrame({"y": y, "p": p, "bin": cut}).groupby("bin", observed=True)
    return table.agg(n=("y", "size"), mean_predicted=("p", "mean"), observed=("y", "mean"))


def main():
    tests, identifiable = {}, {}
    for w, kw in WORLDS.items():
        X, y, meta = make_loops(N_TEST, n_samples=2000, random_state=TEST_SEED,
                                return_meta=True, **kw)
        tests[w] = X, y
        if "stiction_visible" in meta:
            identifiable[w] = _shows_its_label(meta)
            sticky = meta[meta["y"] == 1]
            print(f"{w} world: {sticky['stiction_visible'].mean():.1%} of sticky test loops "
                  "have slips visible above the noise (median slip / noise sd "
                  f"{sticky['slip_snr'].median():.1f})")
    slips, _ = make_loops(200, n_samples=2000, world="classic", stiction_fraction=1.0,
                          slip_fraction=1.0, random_state=SLIP_SEED)
    models = {}
    for world in ("default", "classic"):
        t0 = time.perf_counter()
        models[f"learned ({world} world)"] = pretrained_classifier(random_state=0, world=world)
        print(f"learned classifier, {world} world: ready in {time.perf_counter() - t0:.1f} s")
    rows, tables = [], {}
    for test_world, (X, y) in tests.items():
        rules = {"area ratio (d=0.5)": AreaRatioClassifier().fit(X, y),
                 "shape library (auto)": ShapeLibraryClassifier().fit(X, y)}
        for name, clf in {**rules, **models}.items():
            if hasattr(clf, "diagnose") and "in_domain" in clf.diagnose(X[:1]):
                report = clf.diagnose(X)
                judged = report["in_domain"].to_numpy()
                pred = report["prediction"].to_numpy(dtype=int)
                p = report["probability"].to_numpy()
                brier = brier_score_loss(y[judged], p[judged])
                tables[(name, test_world)] = reliability(y[judged], p[judged])
            else:
                pred = clf.predict(X)
                judged = clf.diagnose(X)["reason"].eq("ok").to_numpy()
                brier = np.nan
            rows.append({
                "classifier": name, "test world": test_world,
                "balanced_acc": balanced_accuracy_score(y, pred),
                "judged": judged.mean(),
                "balanced_acc_judged": balanced_accuracy_score(y[judged], pred[judged]),
                "balanced_acc_identifiable": (
                    balanced_accuracy_score(y[identifiable[test_world]],
                                            pred[identifiable[test_world]])
                    if test_world in identifiable else np.nan
                ),
                "brier": brier,
                "recall_slip_only": (
                    clf.predict(slips).mean() if test_world == "classic" else np.nan
                ),
            })
    pd.set_option("display.width", 160)
    print(f"\nheld-out simulated loops ({N_TEST} per world, seed {TEST_SEED}); "
          "no verdict counts as no stiction in balanced_acc")
    print(pd.DataFrame(rows).to_string(index=False, float_format="{:.3f}".format))
    for (name, world), table in tables.items():
        print(f"\nreliability, {name} on the {world} world (loops in its domain):")
        print(table.to_string(float_format="{:.3f}".format))
    return 0


if __name__ == "__main__":
    sys.exit(main())
