"""How far one simulated training draw moves the default model's figures.

The default model is ``make_learned_classifier(random_state=s)`` trained on
``make_loops(1500, n_samples=2000, random_state=s)`` with ``s = 0``. The booster's seed
changes nothing with the defaults (see ``LearnedStictionClassifier``), so ``s`` only picks
the simulated loops. This script trains the same recipe on several draws and judges each
on the same loops: the second simulator (``independent_world.py``, 400 loops), the
measured windows (``../shared/data``; per window and one vote per valve, as
``measured_data.py`` counts them) and 600 held-out loops of the default world. A single
draw's figure is one sample of this spread: compare recipes by their mean over draws.

Features are a pure function of each loop, so each evaluation set's features are
computed once and every model reads them (``_diagnose_features``, the method behind
``diagnose``).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/seed_spread.py [n_draws]`` (default 10;
10-30 s per draw on 2 idle cores).
"""

import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.metrics import balanced_accuracy_score

sys.path.insert(0, str(Path(__file__).parent))
from _measured_common import load_measured  # noqa: E402
from independent_world import make_independent_loops  # noqa: E402

from sktiction._validation import check_loops  # noqa: E402
from sktiction.classifiers import make_learned_classifier  # noqa: E402
from sktiction.classifiers.learned import normalise_loops  # noqa: E402
from sktiction.datasets import make_loops  # noqa: E402


def _evaluation_sets(clf):
    """name -> (checked loops, features, labels, valve groups or None)."""
    sets = {}
    X, y, _ = make_independent_loops(400, 6000, random_state=2026)
    sets["second simulator"] = (X, y, None)
    measured = load_measured()
    if measured is not None:
        Xm, ym, _, meta = measured
        sets["measured"] = (Xm, ym, meta["dataset"] + "/" + meta["tag"].astype(str))
    Xd, yd = make_loops(600, n_samples=2000, random_state=12345)
    sets["held-out default world"] = (Xd, yd, None)
    out = {}
    for name, (X, y, groups) in sets.items():
        loops = check_loops(X)
        feats = clf._features(normalise_loops(loops))
        # the shortcut must give what a user gets from diagnose()
        shortcut = clf._diagnose_features(loops[:20], feats.iloc[:20].reset_index(drop=True))
        pd.testing.assert_frame_equal(shortcut, clf.diagnose(X[:20]))
        out[name] = (loops, feats, np.asarray(y), groups)
    return out


def _scores(clf, sets):
    row = {}
    for name, (loops, feats, y, groups) in sets.items():
        pred = clf._diagnose_features(loops, feats)["prediction"].to_numpy(dtype=int)
        if groups is None:
            row[name] = balanced_accuracy_score(y, pred)
            continue
        row[f"{name} per window"] = balanced_accuracy_score(y, pred)
        votes = pd.DataFrame({"valve": groups, "y": y, "p": pred}).groupby("valve").mean()
        row[f"{name} per valve"] = balanced_accuracy_score(votes["y"] > 0, votes["p"] >= 0.5)
    return row


def main(n_draws=10):
    rows, sets = [], None
    for seed in range(n_draws):
        t0 = time.perf_counter()
        X, y = make_loops(1500, n_samples=2000, random_state=seed)
        clf = make_learned_classifier(random_state=seed, n_jobs=2).fit(X, y)
        if sets is None:
            sets = _evaluation_sets(clf)
        rows.append({"draw": seed, **_scores(clf, sets)})
        print(f"draw {seed}: trained and judged in {time.perf_counter() - t0:.0f} s", flush=True)
    table = pd.DataFrame(rows).set_index("draw")
    print(table.round(3).to_string())
    summary = table.agg(["mean", "min", "max"]).T
    summary["rank of draw 0 (1 = best)"] = table.rank(ascending=False, method="min").loc[0]
    print(summary.round(3).to_string())


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
