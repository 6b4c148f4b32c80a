"""OP recorded a row out of step with PV: what it costs the verdicts, and what re-aligning saves.

PV and OP are separate historian tags, and a simulator or an export may put OP one row early
(the row of PV at t holds the output computed at t + 1) or late. Both simulators this project
has (``make_loops`` and ``benchmarks/independent_world.py``) record the output computed from the
PV of the same row. Each judge's loops are read three ways: as recorded, with OP one row early
and with OP one row late; the default model's balanced accuracy is printed for each, with the
re-alignment the package does before a verdict (:func:`sktiction._cleaning.align_op`) and
without it (the same model, the alignment switched off), all in this one run. "No verdict"
counts as "no stiction". Nothing was tuned to these judges: the search's margin was set on
other simulated draws.

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/op_alignment.py [n_loops]
"""

import sys

import numpy as np
from independent_world import make_independent_loops
from sklearn.metrics import balanced_accuracy_score

from sktiction import _cleaning, pretrained_classifier
from sktiction._cleaning import _paired, align_op
from sktiction._validation import check_loops, loop_lengths
from sktiction.datasets import make_loops

N_LOOPS = int(sys.argv[1]) if len(sys.argv) > 1 else 400


def shifted(X, s):
    """Each loop with ``OP[t + s]`` on the row of ``PV[t]`` (s = 1: OP one row early)."""
    X = check_loops(X)
    out = np.full_like(X, np.nan)
    for i, n in enumerate(loop_lengths(X)):
        rows = _paired(X[i], int(n), s)
        out[i, : len(rows)] = rows
    return out


def score(model, X, y):
    pred = model.diagnose(X)["prediction"].to_numpy(dtype=int)
    return balanced_accuracy_score(y, pred)


def main():
    model = pretrained_classifier()
    Xd, yd = make_loops(N_LOOPS, random_state=12345)
    Xi, yi, _ = make_independent_loops(N_LOOPS, 6000, random_state=2026)
    print("judge / OP as recorded, one row early, one row late: balanced accuracy of the "
          "default model without / with re-alignment; share of loops moved")
    search = _cleaning.align_op
    for name, X, y in (("default world, held out", Xd, yd), ("second simulator", Xi, yi)):
        for label, s in (("as recorded", 0), ("OP one row early", 1), ("OP one row late", -1)):
            Xs = shifted(X, s) if s else check_loops(X)
            # the same model without the search
            _cleaning.align_op = lambda loops, lengths: (loops, np.zeros(len(loops), int))
            try:
                before = score(model, Xs, y)
            finally:
                _cleaning.align_op = search
            after = score(model, Xs, y)
            moved = np.mean(align_op(Xs, loop_lengths(Xs))[1] != 0)
            print(f"{name:24s} {label:17s} {before:.3f} -> {after:.3f}   moved {moved:.3f}")


if __name__ == "__main__":
    main()
