"""PV and OP swapped: how often the check (``pv_op_swapped``) finds it, and how often it
cries wolf on loops as recorded.

A loop whose OP tracks the setpoint, whose PV does not, and whose record fits a
controller better read the other way round has its channels swapped (an export that lists
OP first, as ISDB's files do). Every verdict would then read the wrong signals. For each
data set: loops flagged as recorded (false flags), loops flagged with PV and OP swapped
(found), and what a scan of swapped default-world loops says with the check and without it
(verdicts read from the wrong signals).

Data sets: the default and classic worlds of ``make_loops``, the second simulator of
``independent_world.py`` and the plant windows of ``../shared/data`` (skipped when absent;
the ISDB loops have no setpoint, so the check does not apply to them).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/swapped_channels.py``
"""

import contextlib
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).parent))
from _measured_common import load_measured  # noqa: E402
from independent_world import make_independent_loops  # noqa: E402

from sktiction._validation import check_loops, loop_status  # noqa: E402
from sktiction.classifiers import _base as base_module  # noqa: E402
from sktiction.classifiers import learned as learned_module  # noqa: E402
from sktiction.datasets import make_loops  # noqa: E402
from sktiction.reports import scan as scan_module  # noqa: E402
from sktiction.reports import scan_loops  # noqa: E402

SWAP = [1, 0, 2]


def flagged(X):
    status = loop_status(check_loops(X), require_op=True, check_swap=True)
    return status == "pv_op_swapped"


def main():
    warnings.filterwarnings("ignore", category=UserWarning)
    sets = {
        "default world (1,000)": make_loops(1000, n_samples=2000, random_state=3)[0],
        "classic world (500)": make_loops(500, n_samples=2000, world="classic",
                                          random_state=3)[0],  # fmt: skip
        "second simulator (400)": make_independent_loops(400, 6000, 0)[0],
    }
    measured = load_measured(("plant",))
    if measured is not None:
        sets[f"plant windows ({len(measured[0])})"] = measured[0]
    rows = [{"loops": name, "flagged as recorded": int(flagged(X).sum()),
             "found swapped": round(float(flagged(X[:, :, SWAP]).mean()), 3)}
            for name, X in sets.items()]  # fmt: skip
    print(pd.DataFrame(rows).to_string(index=False))

    X, y = make_loops(200, n_samples=2000, random_state=3)
    label = np.where(y == 1, "sticky", "healthy")
    for when, check in (("with the check", True), ("without it", False)):
        with _swap_check(check):
            report = scan_loops(X[:, :, SWAP])
        said = report["verdict"].where(report["status"].ne("pv_op_swapped"), "pv_op_swapped")
        print(f"\nscan of 200 default-world loops with PV and OP swapped, {when}:")
        print(pd.crosstab(pd.Series(label, name="true label"), said.rename("scan says")))


@contextlib.contextmanager
def _swap_check(on):
    """Every verdict's loop_status with the swap check on (as shipped) or off."""
    modules = (scan_module, learned_module, base_module)
    saved = [m.loop_status for m in modules]
    def status(*args, **kwargs):
        return loop_status(*args, **{**kwargs, "check_swap": kwargs.get("check_swap") and on})

    for m in modules:
        m.loop_status = status
    try:
        yield
    finally:
        for m, f in zip(modules, saved):
            m.loop_status = f

if __name__ == "__main__":
    main()
