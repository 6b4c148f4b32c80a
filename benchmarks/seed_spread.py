"""How far one simulated training draw moves the default model's figures.

The default model is ``make_learned_classifier(random_state=s)`` trained on
``make_loops(1500, n_samples=2000, random_state=s)`` with ``s = 0``, without the sticky
loops whose slips stay inside the noise (``_pretrained._training_set``). The booster's seed
changes nothing with the defaults (see ``LearnedStictionClassifier``), so ``s`` only picks
the simulated loops. This script trains the same recipe on several draws and judges each
on the same loops: the second simulator (``independent_world.py``, 400 loops), the
third simulator (``third_world.py``, its two draws of 400 loops pooled), the measured
windows (``../shared/data``; per window and one vote per valve, as ``measured_data.py``
counts them) and 600 held-out loops of the default world. A single
draw's figure is one sample of this spread: compare recipes by their mean over draws.

Features are a pure function of each loop, so each evaluation set's features are
computed once and every model reads them (``_diagnose_features``, the method behind
``diagnose``).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/seed_spread.py [n_draws] [first_draw]
[--compare] [--control] [--second-simulator] [--third-simulator] [--loops=N]
[--without=PREFIX] [--monotone=PREFIX] [--evidence=T]`` (default 10
draws from 0; 10-30 s per draw on 2 idle cores).
``--compare`` also trains each draw on every loop, the sticky loops whose slips stay
inside the noise included (the recipe before they were left out), and prints the paired
change; it doubles the time. ``--control`` adds two controls of that change: as many
sticky loops whose slips show, left out at random, and the every-loop model with the
decision threshold that the recipe's class balance implies (the prior shift alone); it
triples the time. ``--second-simulator`` also trains each draw on the recipe's loops plus
600 loops of ``independent_world.py`` (seed ``500 + draw``, never the judging seed 2026) and
prints the change from the recipe alone: does a second simulator bring the model closer to
the plants? ``--third-simulator`` does the same with 600 loops of ``third_world.py`` (seed
``500 + draw``, never its judging seeds 0 and 1): a simulator in training, judged on the
other one left out. ``--loops=N`` also trains each draw's recipe on ``N`` simulated loops
instead of 1,500 and prints the paired change: does more of the simulator carry over?
``--without=PREFIX`` also trains each draw's recipe without the model columns whose names
start with ``PREFIX`` (e.g. ``valve_model__multiscale``; several prefixes separated by
commas, a name ending in ``$`` matched exactly) and prints the change from leaving them
out: what a group of features brings, draw by draw. ``--monotone=PREFIX`` (the same naming) also
trains each draw's recipe with its booster constrained to a probability of stiction that never
falls as those columns rise (``monotonic_cst``): domain knowledge of a feature's direction in
place of what the simulator teaches. ``--evidence=T`` also trains each draw's recipe without
its sticky loops whose record does not show how the valve moved (``make_loops``' meta
``valve_evidence`` of ``T`` or more), and, as a control, without as many of its sticky loops
picked at random; each model is judged as it predicts and called sticky at the recipe's class
balance (the probability the smaller sticky share implies).
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
from third_world import make as make_third_loops  # noqa: E402

from sktiction._cleaning import as_judged  # noqa: E402
from sktiction._validation import check_loops  # noqa: E402
from sktiction.classifiers import make_learned_classifier  # noqa: E402
from sktiction.classifiers._pretrained import _shows_its_label, _training_set  # noqa: E402
from sktiction.classifiers.learned import normalise_loops  # noqa: E402
from sktiction.datasets import make_loops  # noqa: E402
from sktiction.datasets._measured import pad_loops  # noqa: E402


def _evaluation_sets(clf):
    """name -> (checked loops, features, labels, valve groups or None)."""
    sets = {}
    X, y, _ = make_independent_loops(400, 6000, random_state=2026)
    sets["second simulator"] = (X, y, None)
    third = [make_third_loops(400, random_state=seed) for seed in (0, 1)]
    sets["third simulator"] = (
        pad_loops([X3 for X3, _, _ in third]), np.concatenate([y3 for _, y3, _ in third]), None
    )
    measured = load_measured()
    if measured is not None:
        Xm, ym, _, meta = measured
        sets["measured"] = (Xm, ym, meta["dataset"] + "/" + meta["tag"].astype(str))
    Xd, yd = make_loops(600, n_samples=2000, random_state=12345)
    sets["held-out default world"] = (Xd, yd, None)
    out = {}
    for name, (X, y, groups) in sets.items():
        loops = as_judged(check_loops(X))  # as diagnose reads them
        feats = clf._features(normalise_loops(loops))
        # the shortcut must give what a user gets from diagnose()
        shortcut = clf._diagnose_features(loops[:20], feats.iloc[:20].reset_index(drop=True))
        pd.testing.assert_frame_equal(shortcut, clf.diagnose(X[:20]))
        out[name] = (loops, feats, np.asarray(y), groups)
    return out


def _scores(clf, sets, threshold=None):
    """Balanced accuracy per judge; ``threshold``: call sticky from that probability on
    instead of ``predict``'s 0.5 (no probability, outside the domain: not sticky)."""
    row = {}
    for name, (loops, feats, y, groups) in sets.items():
        report = clf._diagnose_features(loops, feats)
        pred = report["prediction"].to_numpy(dtype=int)
        if threshold is not None:
            pred = (report["probability"].fillna(0.0).to_numpy() >= threshold).astype(int)
        if groups is None:
            row[name] = balanced_accuracy_score(y, pred)
            continue
        row[f"{name} per window"] = balanced_accuracy_score(y, pred)
        votes = pd.DataFrame({"valve": groups, "y": y, "p": pred}).groupby("valve").mean()
        row[f"{name} per valve"] = balanced_accuracy_score(votes["y"] > 0, votes["p"] >= 0.5)
    return row


def _paired(rows, base="every loop"):
    """Mean change (and its standard error) from training the ``base`` way to each other way."""
    table = pd.DataFrame(rows).set_index(["draw", "training"])
    every = table.xs(base, level="training")
    for training in table.index.get_level_values("training").unique().drop(base):
        diff = table.xs(training, level="training") - every
        out = pd.DataFrame({
            base: every.mean(),
            training: table.xs(training, level="training").mean(),
            "change": diff.mean(),
            "std. error": diff.std() / np.sqrt(len(diff)),
            "draws up": (diff > 0).sum(),
            "draws down": (diff < 0).sum(),
        })  # fmt: skip
        print(f"\n{training} against {base}, {len(diff)} draws:")
        print(out.round(3).to_string())


def _controls(seed, sets, X, y, left_out):
    """What the recipe's gain would be without anything specific to the loops it leaves
    out: as many sticky loops whose slips show, left out at random, and the every-loop
    model called sticky from the probability that the recipe's class balance implies
    (``1 - sticky share``: the prior shift alone)."""
    shown = np.flatnonzero((y == 1) & ~left_out)
    rng = np.random.default_rng(1000 + seed)
    drop = np.zeros(len(y), dtype=bool)
    drop[rng.choice(shown, int(left_out.sum()), replace=False)] = True
    clf = make_learned_classifier(random_state=seed, n_jobs=2).fit(X[~drop], y[~drop])
    row = {"draw": seed, "training": "random sticky loops left out", **_scores(clf, sets)}
    return row, 1.0 - y[~left_out].mean()


def _with_simulator(make, seed, X, y, n_loops=600):
    """The recipe's loops plus ``n_loops`` of another simulator (``make(n_loops, seed)``
    returns its loops and labels first), NaN-padded alike."""
    X2, y2 = make(n_loops, 500 + seed)[:2]
    return pad_loops([X, X2]), np.concatenate([y, y2])


#: simulators that ``--second-simulator`` and ``--third-simulator`` add to training
OTHER_SIMULATORS = {
    "second": lambda n, seed: make_independent_loops(n, 6000, random_state=seed),
    "third": lambda n, seed: make_third_loops(n, random_state=seed),
}


def _named(columns, spec):
    """Columns named by ``spec``: comma-separated prefixes; one ending in ``$`` names a
    column exactly (``hysteresis__stuck_share$`` without ``hysteresis__stuck_share_slow``)."""
    parts = [p for p in spec.split(",") if p]
    return [c for c in columns
            if any(c == p[:-1] if p.endswith("$") else c.startswith(p) for p in parts)]


def _without(prefix, seed):
    """The recipe's classifier, untrained, whose model columns named by ``prefix`` (see
    :func:`_named`) are blanked (0 everywhere: a constant neither the booster nor the
    logistic model can use; an all-NaN column would stop the booster's binning) in
    training and in every verdict, the evaluation sets' shared features included."""
    recipe = make_learned_classifier(random_state=seed, n_jobs=2)

    def blank(feats):
        feats = feats.copy()
        feats[_named(feats.columns, prefix)] = 0.0
        return feats

    class Without(type(recipe)):
        def _features(self, loops):
            return blank(super()._features(loops))

        def _diagnose_features(self, loops, feats):
            return super()._diagnose_features(loops, blank(feats))

    return Without(**recipe.get_params())


def _monotone(spec, seed):
    """The recipe's classifier, untrained, whose booster may only raise the probability of
    stiction as a column named by ``spec`` (see :func:`_named`) rises."""
    recipe = make_learned_classifier(random_state=seed, n_jobs=2)

    class Monotone(type(recipe)):
        def _make_model(self):  # fit sets feature_names_ just before it asks for the model
            rising = _named(list(self.feature_names_), spec)
            cst = [int(c in rising) for c in self.feature_names_]
            return super()._make_model().set_params(boosting__estimator__monotonic_cst=cst)

    return Monotone(**recipe.get_params())


def _evidence(seed, sets, threshold):
    """The recipe without its sticky loops whose valve motion the record does not show
    (``meta["valve_evidence"] >= threshold``: adding the true valve position to OP
    explains less than ``1 - threshold`` of what OP leaves of PV), and, as a control, the
    recipe without as many of its sticky loops at random."""
    X, y, meta = make_loops(1500, n_samples=2000, random_state=seed, return_meta=True)
    recipe = _shows_its_label(meta)
    shown = recipe & ((y == 0) | (meta["valve_evidence"].to_numpy() < threshold))
    rng = np.random.default_rng(2000 + seed)
    drop = np.zeros(len(y), dtype=bool)
    drop[rng.choice(np.flatnonzero(recipe & (y == 1)), int((recipe & ~shown).sum()),
                    replace=False)] = True  # fmt: skip
    rows = []
    for name, keep in ((f"valve evidence < {threshold}", shown),
                       ("as many at random", recipe & ~drop)):  # fmt: skip
        clf = make_learned_classifier(random_state=seed, n_jobs=2).fit(X[keep], y[keep])
        rows.append({"draw": seed, "training": name, **_scores(clf, sets)})
        # the same model called sticky where the recipe's class balance would put it
        odds = y[keep].mean() / (1 - y[keep].mean()) * (1 - y[recipe].mean()) / y[recipe].mean()
        rows.append({"draw": seed, "training": f"{name}, the recipe's prior",
                     **_scores(clf, sets, odds / (1 + odds))})  # fmt: skip
    print(f"draw {seed}: {int((recipe & ~shown).sum())} of {int((recipe & (y == 1)).sum())} "
          "sticky loops left out", flush=True)  # fmt: skip
    return rows


def main(n_draws=10, first=0, compare=False, control=False, others=(), loops=None,
         without=None, monotone=None, evidence=None):
    rows, paired, mixed, bigger, ablated, sets = [], [], [], [], [], None
    constrained, shown = [], []
    for seed in range(first, first + n_draws):
        t0 = time.perf_counter()
        X, y = _training_set(seed, 1500, 2000, "default")
        clf = make_learned_classifier(random_state=seed, n_jobs=2).fit(X, y)
        if sets is None:
            sets = _evaluation_sets(clf)
        rows.append({"draw": seed, **_scores(clf, sets)})
        if compare or control:  # the same draw with every loop, as the recipe was before
            Xa, ya, meta = make_loops(1500, n_samples=2000, random_state=seed, return_meta=True)
            every = make_learned_classifier(random_state=seed, n_jobs=2).fit(Xa, ya)
            paired.append({"draw": seed, "training": "every loop", **_scores(every, sets)})
            paired.append({**rows[-1], "training": "recipe"})
        if control:
            left_out = ~_shows_its_label(meta)
            row, threshold = _controls(seed, sets, Xa, ya, left_out)
            paired.append(row)
            paired.append({"draw": seed, "training": "every loop, prior-shifted threshold",
                           **_scores(every, sets, threshold)})  # fmt: skip
        if others:
            mixed.append({**rows[-1], "training": "recipe"})
        for other in others:
            Xb, yb = _with_simulator(OTHER_SIMULATORS[other], seed, X, y)
            both = make_learned_classifier(random_state=seed, n_jobs=2).fit(Xb, yb)
            mixed.append({"draw": seed, "training": f"recipe + {other} simulator",
                          **_scores(both, sets)})  # fmt: skip
        if loops:
            Xn, yn = _training_set(seed, loops, 2000, "default")
            more = make_learned_classifier(random_state=seed, n_jobs=2).fit(Xn, yn)
            bigger.append({**rows[-1], "training": "recipe"})
            bigger.append({"draw": seed, "training": f"recipe on {loops} loops",
                           **_scores(more, sets)})  # fmt: skip
        if without:
            less = _without(without, seed).fit(X, y)
            assert _named(less.feature_names_, without), without
            ablated.append({**rows[-1], "training": "recipe"})
            ablated.append({"draw": seed, "training": f"recipe without {without}*",
                            **_scores(less, sets)})  # fmt: skip
        if monotone:
            mono = _monotone(monotone, seed).fit(X, y)
            assert _named(list(mono.feature_names_), monotone), monotone
            constrained.append({**rows[-1], "training": "recipe"})
            constrained.append({"draw": seed, "training": "recipe, monotone",
                                **_scores(mono, sets)})  # fmt: skip
        if evidence:
            shown += [{**rows[-1], "training": "recipe"}, *_evidence(seed, sets, evidence)]
        print(f"draw {seed}: trained and judged in {time.perf_counter() - t0:.0f} s", flush=True)
    table = pd.DataFrame(rows).set_index("draw")
    print(table.round(3).to_string())
    summary = table.agg(["mean", "min", "max"]).T
    if 0 in table.index:
        summary["rank of draw 0 (1 = best)"] = table.rank(ascending=False, method="min").loc[0]
    print(summary.round(3).to_string())
    if paired:
        _paired(paired)
    if mixed:
        _paired(mixed, base="recipe")
    if bigger:
        _paired(bigger, base="recipe")
    if ablated:
        _paired(ablated, base=f"recipe without {without}*")
    if constrained:
        _paired(constrained, base="recipe")
    if shown:
        _paired(shown, base="recipe")


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(
        int(args[0]) if args else 10,
        int(args[1]) if len(args) > 1 else 0,
        compare="--compare" in sys.argv,
        control="--control" in sys.argv,
        others=[o for o in OTHER_SIMULATORS if f"--{o}-simulator" in sys.argv],
        loops=next((int(a.split("=")[1]) for a in sys.argv if a.startswith("--loops=")), None),
        without=next((a.split("=", 1)[1] for a in sys.argv if a.startswith("--without=")), None),
        monotone=next((a.split("=", 1)[1] for a in sys.argv if a.startswith("--monotone=")), None),
        evidence=next((float(a.split("=")[1]) for a in sys.argv if a.startswith("--evidence=")),
                      None),
    )
