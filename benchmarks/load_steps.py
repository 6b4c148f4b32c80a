"""Unannounced load steps: how often the default model calls a healthy loop that rejects
them sticky, why, and how often measured loops hold them.

The default world draws no load step in the record; ``make_loops(...,
load_step_fraction=1.0)`` gives every loop 1-4 (feed or supply changes the loop rejects:
PV leaves its setpoint, OP moves to a new level, PV returns). The same seed is drawn
with and without them and judged by ``pretrained_classifier()``; "no verdict" counts as
"not sticky", as in the other accuracy benchmarks. Printed:

* false alarms per healthy cause and recall on sticky loops, without and with the steps;
* the medians, over healthy loops, of the model columns that move most (the valve fits
  read the new OP level, which PV does not follow, as a dead band);
* the share of loops with at least one OP level shift away from every setpoint move
  (``loop_statistics(...)["op_load_shifts"]``, the catalog's ``load_steps`` effect) in the
  default world with and without the steps and in the measured windows of
  ``../shared/data``: do measured loops ask for them?

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/load_steps.py [n_loops]`` (about 1 min).
"""

import sys
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).parent))
from _measured_common import load_measured  # noqa: E402

from sktiction import pretrained_classifier  # noqa: E402
from sktiction._cleaning import as_judged  # noqa: E402
from sktiction._validation import check_loops  # noqa: E402
from sktiction.classifiers.learned import normalise_loops  # noqa: E402
from sktiction.datasets import make_loops  # noqa: E402
from sktiction.realism import loop_statistics  # noqa: E402

COLUMNS = (
    "hysteresis__valve_fit_band_share",
    "valve_model__multiscale_fit_gain",
    "hysteresis__hysteresis_fill",
    "templates__op_dist_triangular",
)


def _shifted(X):
    return loop_statistics(X)["op_load_shifts"].to_numpy() >= 1


def main(n_loops=600, seed=4242):
    clf = pretrained_classifier()
    verdicts, medians, shifted = {}, {}, {}
    for name, frac in (("without steps", 0.0), ("with 1-4 steps", 1.0)):
        X, y, meta = make_loops(n_loops, n_samples=2000, random_state=seed,
                                load_step_fraction=frac, return_meta=True)  # fmt: skip
        report = clf.diagnose(X)
        called = report["probability"].fillna(0.0).to_numpy() >= 0.5
        healthy = meta["cause"] != "stiction"
        rates = pd.Series(called[healthy]).groupby(meta["cause"][healthy].to_numpy()).mean()
        verdicts[name] = pd.concat([
            rates.rename(lambda c: f"false alarms, {c}"),
            pd.Series({"false alarms, all healthy": called[healthy].mean(),
                       "recall, sticky": called[~healthy].mean()}),
        ])  # fmt: skip
        # the model's columns as diagnose computes them
        feats = clf._features(normalise_loops(as_judged(check_loops(X))))
        medians[name] = feats.loc[healthy.to_numpy(), list(COLUMNS)].median()
        shifted[f"default world, {name}"] = _shifted(X).mean()
    measured = load_measured()
    if measured is not None:
        shifted[f"measured windows ({len(measured[1])})"] = _shifted(measured[0]).mean()
    pd.set_option("display.width", 160)
    print(f"default model on {n_loops} default-world loops (seed {seed}), called sticky:")
    print(pd.DataFrame(verdicts).round(3).to_string())
    print("\nmedian over healthy loops of the model columns that move most:")
    print(pd.DataFrame(medians).round(3).to_string())
    print("\nshare of loops with an OP level shift away from every setpoint move:")
    print(pd.Series(shifted).round(3).to_string())


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 600)
