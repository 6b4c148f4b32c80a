"""Balanced accuracy on measured loops (plant historian windows, ISDB), trained on simulation.

Nothing here is fitted to the labels of the measured files. The learned classifier is
trained on simulated loops only, from three worlds:

- ``classic``: ``make_loops``' clean world of sktiction 0.1 (``pretrained_classifier(
  world="classic")``, as the 0.1 model was trained);
- ``default``: the richer default world (loops as historians record them);
- ``calibrated``: ``make_loops(realism=calibrate(measured))``, where ``calibrate`` sees
  only the *training* tags' loops (no labels): tags are split into grouped folds, and
  each fold's tags are judged by a model whose world was calibrated on the other folds
  (trained, like the default model, without the sticky loops whose slips hide in the noise).

The rules (area ratio, shape library) keep their published thresholds and are listed
for context. Windows of one valve are not independent (23 of the 26 sticky plant
windows come from one valve), so figures are given per window and per valve (one vote
per tag: the share of its windows called sticky, thresholded at 0.5). "No verdict"
(outside the model's domain, or a rule that abstains) counts as "no stiction";
``judged`` is the share of windows that got a verdict. Skips cleanly when
``../shared/data`` is absent.

Run: python benchmarks/measured_data.py [--n-cal N] [--folds K] [--no-calibrated] [--per-loop]
[--pv-op-look]
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.model_selection import GroupKFold

sys.path.insert(0, str(Path(__file__).parent))
from _measured_common import load_measured  # noqa: E402

from sktiction import AreaRatioClassifier, ShapeLibraryClassifier  # noqa: E402
from sktiction.classifiers import make_learned_classifier, pretrained_classifier  # noqa: E402
from sktiction.classifiers._pretrained import _shows_its_label  # noqa: E402
from sktiction.datasets import make_loops  # noqa: E402


def rates(y, pred):
    """Balanced accuracy, recall (sticky found) and specificity (healthy cleared)."""
    y, pred = np.asarray(y, bool), np.asarray(pred, bool)
    recall = pred[y].mean() if y.any() else np.nan
    spec = (~pred[~y]).mean() if (~y).any() else np.nan
    return np.nanmean([recall, spec]), recall, spec


def learned_verdicts(clf, X):
    report = clf.diagnose(X)
    return report["prediction"].to_numpy(dtype=int), report["in_domain"].to_numpy(), report


def calibrated_verdicts(X, meta, groups, n_loops, folds):
    """Verdicts of models whose world is calibrated on the other folds' tags only."""
    from sktiction.realism import calibrate

    pred = np.zeros(len(X), dtype=int)
    judged = np.zeros(len(X), dtype=bool)
    reasons = np.empty(len(X), dtype=object)
    proba = np.full(len(X), np.nan)
    for k, (train, test) in enumerate(GroupKFold(n_splits=folds).split(X, groups=groups)):
        t0 = time.perf_counter()
        assert not set(groups[train]) & set(groups[test])
        realism = calibrate(X[train], loop_types=meta["loop_type"].to_numpy()[train])
        Xs, ys, ms = make_loops(
            n_loops, n_samples=2000, realism=realism, random_state=k, return_meta=True
        )
        keep = _shows_its_label(ms)  # the default model's recipe
        clf = make_learned_classifier(random_state=0, n_jobs=2).fit(Xs[keep], ys[keep])
        p, j, report = learned_verdicts(clf, X[test])
        pred[test], judged[test] = p, j
        reasons[test] = report["reason"].to_numpy()
        proba[test] = report["probability"].to_numpy()
        print(
            f"  fold {k + 1}/{folds}: calibrated on {len(set(groups[train]))} tags, "
            f"trained in {time.perf_counter() - t0:.0f} s, judged {len(set(groups[test]))} tags"
        )
    return pred, judged, pd.DataFrame({"reason": reasons, "probability": proba})


def table(report, names, by):
    rows = []
    for key, part in report.groupby(by):
        for name in names:
            bal, rec, spec = rates(part["y"], part[name])
            rows.append(
                {
                    **dict(zip(by, key if isinstance(key, tuple) else (key,))),
                    "classifier": name,
                    "n": len(part),
                    "n_sticky": int(part["y"].sum()),
                    "judged": part[f"{name} judged"].mean(),
                    "balanced_acc": bal,
                    "recall": rec,
                    "specificity": spec,
                }
            )
    return pd.DataFrame(rows)


def per_valve(report, names):
    """One vote per valve: the share of its windows called sticky, thresholded at 0.5."""
    agg = {"y": "max", **{n: "mean" for n in names}, **{f"{n} judged": "mean" for n in names}}
    valves = report.groupby(["dataset", "tag"]).agg(agg).reset_index()
    for name in names:
        valves[name] = (valves[name] >= 0.5).astype(int)
    valves["all"] = "all valves"
    return table(valves, names, ["all"])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-cal", type=int, default=1000, help="loops per calibrated world")
    parser.add_argument("--folds", type=int, default=3, help="grouped folds over tags")
    parser.add_argument("--no-calibrated", action="store_true")
    parser.add_argument("--per-loop", action="store_true")
    parser.add_argument(
        "--pv-op-look", action="store_true",
        help="unlabelled: slow-scale PV-OP columns here and in the default world",
    )  # fmt: skip
    args = parser.parse_args(argv)
    loaded = load_measured()
    if loaded is None:
        print("measured data folder not found (../shared/data or $SKTICTION_DATA): skipped")
        return 0
    X, y, groups, meta = loaded
    report = meta[["dataset", "file", "tag", "loop_type"]].copy()
    report["y"] = y
    names = []
    for name, clf in (
        ("area ratio", AreaRatioClassifier()),
        ("shape library", ShapeLibraryClassifier()),
    ):
        d = clf.fit(X).diagnose(X)
        report[name], report[f"{name} judged"] = d["prediction"].to_numpy(), d["reason"].eq("ok")
        names.append(name)
    for world in ("classic", "default"):
        t0 = time.perf_counter()
        clf = pretrained_classifier(random_state=0, world=world)
        name = f"learned, {world} world"
        pred, judged, d = learned_verdicts(clf, X)
        report[name], report[f"{name} judged"] = pred, judged
        report[f"{name} reason"], report[f"{name} p"] = d["reason"], d["probability"]
        names.append(name)
        print(f"{name}: ready and scanned in {time.perf_counter() - t0:.1f} s")
    try:
        import sktiction.realism  # noqa: F401

        have_realism = True
    except ImportError:
        have_realism = False
    if have_realism and not args.no_calibrated:
        name = "learned, calibrated world"
        print(f"{name}: {args.folds} grouped folds over tags, {args.n_cal} loops each")
        pred, judged, d = calibrated_verdicts(X, meta, groups, args.n_cal, args.folds)
        report[name], report[f"{name} judged"] = pred, judged
        report[f"{name} reason"], report[f"{name} p"] = d["reason"], d["probability"]
        names.append(name)
    pd.set_option("display.width", 200)
    fmt = {"float_format": "{:.2f}".format, "index": False}
    print("\n== per data set (windows) ==")
    print(table(report, names, ["dataset"]).to_string(**fmt))
    print("\n== all windows ==")
    report["all"] = "all windows"
    print(table(report, names, ["all"]).to_string(**fmt))
    print("\n== per valve (one vote per tag, both data sets) ==")
    print(per_valve(report, names).to_string(**fmt))
    learned = [n for n in names if n.startswith("learned")]
    for name in learned:
        counts = report[f"{name} reason"].value_counts().to_dict()
        print(f"\n{name}: reasons {counts}")
    if args.per_loop:
        cols = ["dataset", "tag", "loop_type", "y"] + [
            c for n in learned for c in (n, f"{n} p", f"{n} reason")
        ]
        print("\n== every loop ==")
        print(report[cols].to_string(**fmt))
    if args.pv_op_look:
        pv_op_look(X, y, groups)
    return 0


# PVOPHysteresis at OP's own time scale (the columns that call a healthy loop compensating
# a slow load sticky in benchmarks/independent_world.py)
_SLOW = ("stuck_share_slow", "moving_share_slow", "hysteresis_fill_slow")


def pv_op_look(X, y, groups, n_sim=300):
    """How often PV stays put while OP moves, measured against the default world.

    Medians of the learned model's slow-scale hysteresis columns and the share of loops with
    the "stuck look" (stuck share > 0.35, OP moving in > 70 % of windows, fill > 0.4), on the
    measured loops (no labels) and on ``n_sim`` default-world loops of 751 samples (seed 0),
    each class. Then, with the measured labels, what the look means there: windows and valves
    with and without it, and how many of them are sticky (reported, not used to choose).
    """
    clf = pretrained_classifier(random_state=0)
    Xs, ys = make_loops(n_sim, n_samples=751, random_state=0)
    rows = {}
    for name, A, keep in (("measured (all, no labels)", X, None),
                          ("default world, healthy", Xs, ys == 0),
                          ("default world, sticky", Xs, ys == 1)):  # fmt: skip
        F = clf.loop_features(A if keep is None else A[keep])
        F = F[[f"hysteresis__{c}" for c in _SLOW]]
        F.columns = list(_SLOW)
        look = (F["stuck_share_slow"] > 0.35) & (F["moving_share_slow"] > 0.7)
        look &= F["hysteresis_fill_slow"] > 0.4
        rows[name] = {**F.median().to_dict(), "stuck look": float(look.mean()), "n": len(F)}
        if keep is None:
            measured_look = look.to_numpy()
    print("\n== PV steady while OP moves, at OP's own time scale (medians) ==")
    print(pd.DataFrame(rows).T.to_string(float_format="{:.2f}".format))
    windows = pd.DataFrame({"look": measured_look, "sticky": y, "valve": groups})
    valves = windows.groupby("valve").max()  # a valve shows the look in any of its windows
    print("\n== the look on the measured loops, with their labels ==")
    for name, t in (("windows", windows), ("valves", valves)):
        counts = t.groupby("look")["sticky"].agg(["size", "sum"])
        for look, (n, sticky) in counts.iterrows():
            print(f"{name} {'with' if look else 'without'} the look: {n}, {sticky} sticky")


if __name__ == "__main__":
    sys.exit(main())
