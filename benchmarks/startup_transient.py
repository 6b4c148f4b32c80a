"""Records that start with a start-up transient: what it costs the verdicts, and what
dropping it saves.

A simulator started from rest, or a record that begins while a loop settles, opens with
an excursion far outside what the rest of the record does. The second simulator
(``independent_world.py``) settles each loop for 1,500 s before recording; recorded from
rest (``warmup=0``) or after 200 s, its healthy loops read as sticky much more often.
``make_loops(..., warmup=0)`` does the same to the default world. Each judge is read by the
default model with the transient dropped (:func:`sktiction._cleaning.drop_startup`, in every
classifier and scan) and without (the same model, the step switched off), in this one run;
"no verdict" counts as "no stiction". Also printed: the share of loops whose start was
dropped, how many verdicts changed, the healthy loops called sticky per cause, and for the
second simulator from rest the verdicts of a scan (``scan_loops``, whose applicability gate
has its own say) and of the two rules. As recorded (the first row of each world and the
measured windows), no loop should be touched. The rule's limits were set on the default
world as recorded and the second simulator as recorded, before it was run on the others.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/startup_transient.py [n_loops]``
"""

import sys
import warnings

import numpy as np
import pandas as pd
from _measured_common import load_measured
from independent_world import make_independent_loops
from sklearn.metrics import balanced_accuracy_score

from sktiction import AreaRatioClassifier, ShapeLibraryClassifier, _cleaning, pretrained_classifier
from sktiction._validation import check_loops, loop_lengths
from sktiction.datasets import make_loops

N_LOOPS = int(sys.argv[1]) if len(sys.argv) > 1 else 400


def off_and_on(verdicts):
    """``verdicts()`` with the start-up step switched off, then on (the same model)."""
    step = _cleaning.drop_startup
    _cleaning.drop_startup = lambda loops, lengths: (loops, np.zeros(len(loops), int))
    try:
        before = verdicts()
    finally:
        _cleaning.drop_startup = step
    return before, verdicts()


def predictions(model, X):
    """The model's verdicts without and with the start-up step."""
    return off_and_on(lambda: model.diagnose(X)["prediction"].fillna(0).to_numpy(dtype=int))


def scanned(X):
    """Stiction verdicts of ``scan_loops`` without and with the start-up step."""
    from sktiction.reports import scan_loops

    return off_and_on(lambda: scan_loops(X)["verdict"].eq("stiction").to_numpy(dtype=int))


def per_valve(groups, y, pred):
    votes = pd.DataFrame({"g": groups, "y": y, "p": pred}).groupby("g").mean()
    return balanced_accuracy_score(votes["y"].round(), votes["p"] >= 0.5)


def judges():
    for warmup in (1500, 200, 0):
        X, y, meta = make_independent_loops(N_LOOPS, 6000, random_state=2026, warmup=warmup)
        yield f"second simulator, warm-up {warmup} s", X, y, meta["cause"]
    for warmup in (None, 0):
        X, y, meta = make_loops(N_LOOPS, n_samples=2000, random_state=12345, warmup=warmup,
                                return_meta=True)
        yield f"default world, warm-up {'default' if warmup is None else 0}", X, y, meta["cause"]
    measured = load_measured()
    if measured is not None:
        X, y, _, meta = measured
        yield "measured windows", X, y, (meta["dataset"] + "/" + meta["tag"].astype(str))


def by_cause(causes, y, before, after):
    """Share of each healthy cause's loops called sticky, without -> with the step."""
    t = pd.DataFrame({"cause": causes, "y": y, "before": before, "after": after})
    healthy = t[t["y"] == 0].groupby("cause")[["before", "after"]].mean()
    return ", ".join(f"{c} {b:.2f} -> {a:.2f}" for c, (b, a) in healthy.iterrows())


def main():
    warnings.simplefilter("ignore")  # "cannot be judged" warnings: counted as no stiction
    model = pretrained_classifier()
    print("judge: balanced accuracy of the default model without -> with the start-up "
          "step; share of loops whose start was dropped; verdicts changed")
    for name, X, y, groups in judges():
        X = check_loops(X)
        causes = None if name.startswith("measured") else groups
        groups = groups if name.startswith("measured") else None
        before, after = predictions(model, X)
        dropped = np.mean(_cleaning.drop_startup(X, loop_lengths(X))[1] > 0)
        line = (f"{name:36s} {balanced_accuracy_score(y, before):.3f} -> "
                f"{balanced_accuracy_score(y, after):.3f}")
        if groups is not None:
            line += (f" (per valve {per_valve(groups, y, before):.3f} -> "
                     f"{per_valve(groups, y, after):.3f})")
        print(f"{line}   dropped {dropped:.3f}   changed {int((before != after).sum())}",
              flush=True)
        if causes is not None:
            print(f"    healthy loops called sticky: {by_cause(causes, y, before, after)}")
    X, y, _ = make_independent_loops(N_LOOPS, 6000, random_state=2026, warmup=0)
    before, after = scanned(X)
    print(f"second simulator, warm-up 0 s, scan_loops (with its applicability gate): "
          f"{balanced_accuracy_score(y, before):.3f} -> {balanced_accuracy_score(y, after):.3f}")
    for rule in (AreaRatioClassifier(), ShapeLibraryClassifier()):
        before, after = (balanced_accuracy_score(y, p) for p in predictions(rule.fit(X), X))
        print(f"second simulator, warm-up 0 s, {type(rule).__name__}: {before:.3f} -> {after:.3f}")


if __name__ == "__main__":
    main()
