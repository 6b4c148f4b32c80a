"""Long records read whole and in windows: the learned model's ``long_record`` rule.

The default model learned records of 2,000 samples. A loop longer than ``long_record``
(10,000) samples, once a finer recording is read coarser, is read twice: whole, and in
``n // window`` equal windows of about ``window`` (3,000) samples, each read as a record of
its own; its probability is the mean of the two readings (the windows' reading being the
mean of the windows the model judges; :class:`~sktiction.classifiers.
LearnedStictionClassifier`). This script judges the same long loops whole
(``set_params(long_record=None)``) and with the rule, paired:

- the second simulator (``independent_world.py``, a force-balance valve, Euler plants,
  lambda or gain-margin tuning, historian sampling at 1, 2 or 5 s) recorded for 20,000 s
  (4,000-20,000 samples), three draws;
- the default world of ``make_loops`` at 20,000 samples, two draws, and at 8,640 (a day at
  10 s: no loop is touched, the rule's threshold lies above it);
- with ``--finer``, long records sampled ten times finer than their dynamics, where
  windows of 3,000 samples hold a tenth of the dynamics: the default world simulated ten
  times finer (20,000 samples, periods 80-3,000 samples), two draws, and the second
  simulator's 3,000 s records interpolated ten times finer with fresh noise
  (``sampling_rate.py``'s proxy), two draws.

Printed per judge: balanced accuracy whole -> with the rule ("no verdict" counts as no
stiction), recall and specificity, loops read in windows (as the model reads them: after
holds, the start-up step and a coarser reading, and not refused whole), verdicts changed
both ways; then per group of judges the change over all its loops pooled, with a 95 %
paired bootstrap interval, and the figures of the loops read in windows alone. The rule's
numbers were chosen on simulated judges only (``docs/realism.md``); the measured windows
(751 samples) and ISDB loops (at most 7,201) are all shorter than the threshold and so are
judged as before.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/long_records.py [--finer]`` (about 10 minutes
each on 2 cores once the default model is cached)
"""

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from independent_world import make_independent_loops  # noqa: E402
from measured_data import rates  # noqa: E402  (balanced accuracy, recall, specificity)
from sampling_rate import interpolated  # noqa: E402

from sktiction import pretrained_classifier  # noqa: E402
from sktiction._cleaning import as_judged  # noqa: E402
from sktiction._validation import check_loops, loop_lengths  # noqa: E402
from sktiction.datasets import make_loops  # noqa: E402

SECOND = (2026, 2027, 2028)
DEFAULT = ((777, 20000), (778, 20000), (777, 8640))


def judges(finer=False):
    if finer:
        for seed in (12345, 777):
            X, y = make_loops(300, n_samples=20000, period_range=(80.0, 3000.0),
                              random_state=seed)  # fmt: skip
            yield "ten times finer", f"default world, draw {seed}", X, y
        for seed in (2026, 2027):
            X, y, _ = make_independent_loops(300, 3000, random_state=seed)
            X = interpolated(X, 10, np.random.default_rng(seed))
            yield "ten times finer", f"second simulator, draw {seed}", X, y
        return
    for seed in SECOND:
        X, y, _ = make_independent_loops(400, 20000, random_state=seed)
        yield "second simulator", f"20,000 s, draw {seed}", X, y
    for seed, n in DEFAULT:
        X, y = make_loops(300, n_samples=n, random_state=seed)
        yield "default world", f"{n:,} samples, draw {seed}", X, y


def bootstrap(y, whole, windowed, rng, n_boot=2000):
    """95 % interval of the paired change in balanced accuracy, loops resampled."""
    idx = rng.integers(0, len(y), (n_boot, len(y)))
    diffs = [rates(y[i], windowed[i])[0] - rates(y[i], whole[i])[0] for i in idx]
    return np.percentile(diffs, [2.5, 97.5])


def main(finer=False):
    warnings.simplefilter("ignore")  # "cannot be judged" warnings: counted as no stiction
    windowed_model = pretrained_classifier()
    whole_model = pretrained_classifier().set_params(long_record=None)
    rng = np.random.default_rng(0)
    pooled = {}
    print("judge: balanced accuracy (recall / specificity) whole -> whole and in windows; "
          "loops touched; verdicts changed to sticky / to healthy")
    for world, name, X, y in judges(finer):
        X = check_loops(X)
        report = whole_model.diagnose(X)
        whole = report["prediction"].to_numpy(dtype=int)
        windowed = windowed_model.predict(X)
        a, b = rates(y, whole), rates(y, windowed)
        # what the rule reads in windows: as read (holds, start-up), coarser where finer,
        # and not refused whole
        n = loop_lengths(as_judged(X)) // report["rows_per_sample"].to_numpy()
        reason = report["reason"].astype(str)
        n[~((reason == "ok") | reason.str.startswith("out_of_domain")).to_numpy()] = 0
        touched = int((n > windowed_model.long_record).sum())
        print(f"{world}, {name:30s} {a[0]:.3f} ({a[1]:.2f} / {a[2]:.2f}) -> {b[0]:.3f} "
              f"({b[1]:.2f} / {b[2]:.2f})   touched {touched} of {len(y)}   changed "
              f"{int((windowed > whole).sum())} / {int((windowed < whole).sum())}", flush=True)
        part = pooled.setdefault(world, [[], [], [], []])
        for store, values in zip(part, (y, whole, windowed, n)):
            store.append(values)
    for world, part in pooled.items():
        y, whole, windowed, n = (np.concatenate(v) for v in part)
        change = rates(y, windowed)[0] - rates(y, whole)[0]
        lo, hi = bootstrap(y, whole, windowed, rng)
        print(f"{world}, all draws pooled: change {change:+.3f} (95 % interval "
              f"{lo:+.3f} to {hi:+.3f})")
        sel = n > windowed_model.long_record
        a, b = rates(y[sel], whole[sel]), rates(y[sel], windowed[sel])
        print(f"    the {int(sel.sum())} loops touched: {a[0]:.3f} ({a[1]:.2f} / {a[2]:.2f}) "
              f"-> {b[0]:.3f} ({b[1]:.2f} / {b[2]:.2f})")


if __name__ == "__main__":
    main(finer="--finer" in sys.argv)
