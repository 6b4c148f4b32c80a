"""The default model on loops recorded finer than the loops it learned from.

A simulator or a historian may record a loop at any rate; ten times finer is the same loop.
The model's features include the period of the cycles in samples, and past the training
range a loop is outside the model's domain. The model now reads such a loop in block means
that bring its period to the training periods' upper quartile
(``LearnedStictionClassifier._coarsening``, column ``rows_per_sample`` of ``diagnose``).

Judges, each with that step off and on (the same model, nothing retrained):

* the default world of ``make_loops`` (seed 12345, 2,000 samples), and the same draws
  simulated ``k`` times finer (``period_range`` and ``n_samples`` times ``k``: the same
  loops, cycles ``k`` times as many samples long, noise drawn per sample);
* the second simulator (``independent_world.py``, seed 2026, 3,000 s), and its records
  interpolated ``k`` times finer with fresh white noise of 0.3 times the standard deviation
  of each record's increments over the square root of 2 (a proxy: its own code records
  at 1 s at the finest).

And one tag slower than the record, with the repair that reads such a loop at that tag's
rows (``_cleaning.hold_step`` on one channel alone) off and on: a controller 5 times slower
(the second simulator's records with PV interpolated 5 times finer, fresh noise as above,
and OP and SP held 5 rows each), and a PV logged 3 times slower than OP (each third PV
value held 3 rows, OP as recorded).

Printed per judge: balanced accuracy ("no verdict" counts as "no stiction"), the share of
loops the model judges and the share read coarser.

Then the other way: records kept at every second and third sample (a historian logging 2 or
3 times slower; nothing to repair), for the second simulator and the measured windows of
``../shared/data`` (when present): balanced accuracy and the verdicts that change against
the record as it is.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/sampling_rate.py [n_loops]`` (default 300)
"""

from __future__ import annotations

import contextlib
import sys
import warnings

import numpy as np
from _measured_common import load_measured
from independent_world import make_independent_loops
from sklearn.metrics import balanced_accuracy_score

from sktiction import _cleaning, pretrained_classifier
from sktiction._validation import check_loops, loop_lengths
from sktiction.classifiers import learned
from sktiction.datasets import make_loops

FINER = (3, 10)
COARSER = (2, 3)


def interpolated(X, k, rng, held=()):
    """Each record ``k`` times finer: straight lines between samples, plus white noise on PV
    and OP of 0.3 times the record's increment standard deviation over sqrt(2); channels in
    ``held`` are instead held ``k`` rows per value (a controller ``k`` times slower)."""
    X = check_loops(X)
    out = np.full((len(X), (X.shape[1] - 1) * k + 1, 3), np.nan)
    for i, n in enumerate(loop_lengths(X)):
        t, fine = np.arange(n), np.arange((n - 1) * k + 1) / k
        for c in range(3):
            x = X[i, :n, c]
            if np.isnan(x).all():
                continue
            if c in held:
                y = np.repeat(x, k)[: fine.size]
            else:
                y = np.interp(fine, t, x)
                if c < 2:
                    y = y + rng.normal(0.0, 0.3 * np.std(np.diff(x)) / np.sqrt(2), y.size)
            out[i, : y.size, c] = y
    return out


def pv_held(X, k):
    """Each ``k``-th PV value held ``k`` rows, OP and SP as recorded (PV logged slower)."""
    X = check_loops(X).copy()
    for i, n in enumerate(loop_lengths(X)):
        X[i, :n, 0] = np.repeat(X[i, :n:k, 0], k)[:n]
    return X


def coarsening_off():
    """Context: no loop is long enough to be read coarser."""
    return _patched(learned, "_MIN_COARSE_ROWS", 10**12)


def one_tag_grid_off():
    """Context: only whole rows held on a grid are read as stored, not one tag alone."""
    return _patched(_cleaning, "hold_step", lambda loop, n: _cleaning._hold_grid(loop[:n]))


@contextlib.contextmanager
def _patched(module, name, value):
    keep = getattr(module, name)
    setattr(module, name, value)
    try:
        yield
    finally:
        setattr(module, name, keep)


def judge(model, X, y):
    d = model.diagnose(X)
    ba = balanced_accuracy_score(y, d["prediction"].to_numpy(dtype=int))
    return ba, d["in_domain"].mean(), (d["rows_per_sample"] > 1).mean()


def coarser_records(model, name, X, y):
    """Balanced accuracy at every ``k``-th sample, and the verdicts that change."""
    base = model.predict(X)
    cells = [f"as recorded {balanced_accuracy_score(y, base):.3f}"]
    for k in COARSER:
        pred = model.predict(np.ascontiguousarray(X[:, ::k]))
        cells.append(f"every {k}: {balanced_accuracy_score(y, pred):.3f} "
                     f"({np.sum(pred != base)} of {len(y)} verdicts change)")  # fmt: skip
    print(f"{name:34s} " + "; ".join(cells), flush=True)


def main(n_loops=300):
    warnings.simplefilter("ignore", UserWarning)
    model = pretrained_classifier()
    rng = np.random.default_rng(0)
    judges = [("default world", *make_loops(n_loops, random_state=12345), coarsening_off)]
    for k in FINER:
        X, y = make_loops(n_loops, n_samples=2000 * k, period_range=(8.0 * k, 300.0 * k),
                          random_state=12345)  # fmt: skip
        judges.append((f"default world, {k}x finer", X, y, coarsening_off))
    Xi, yi, _ = make_independent_loops(n_loops, 3000, random_state=2026)
    judges.append(("second simulator", Xi, yi, coarsening_off))
    for k in FINER:
        judges.append((f"second simulator, {k}x finer", interpolated(Xi, k, rng), yi,
                       coarsening_off))  # fmt: skip
    slow = interpolated(Xi, 5, rng, held=(1, 2))
    judges.append(("second simulator, OP held 5 rows", slow, yi, one_tag_grid_off))
    judges.append(("second simulator, PV held 3 rows", pv_held(Xi, 3), yi, one_tag_grid_off))
    print(f"trained_period_ = {model.trained_period_:.1f} samples; balanced accuracy "
          "(judged, read coarser) without -> with the step (reading coarser; for a tag held, "
          "reading at that tag's rows)")  # fmt: skip
    for name, X, y, step_off in judges:
        with step_off():
            off = judge(model, X, y)
        on = judge(model, X, y)
        print(f"{name:34s} {off[0]:.3f} ({off[1]:.2f}) -> {on[0]:.3f} ({on[1]:.2f}, {on[2]:.2f})",
              flush=True)  # fmt: skip
    print("\nrecords logged slower (every k-th sample kept): balanced accuracy")
    coarser_records(model, "second simulator", Xi, yi)
    measured = load_measured()
    if measured is not None:
        coarser_records(model, "measured windows", measured[0], measured[1])


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
