"""How big is the stiction? The scan's two sizes against the true band of simulated valves.

A scan reports two sizes for a loop it calls sticky:

- ``stiction_size_mean``: the shape library's (Srinivasan et al. 2005) mean OP peak-to-peak
  over the cycles that match a sticky shape; it needs a cycle;
- ``stiction_band_fit``: the dead band of a valve model fitted to PV and OP
  (``sktiction.features.hysteresis.valve_band``); it needs no cycle, so it also sizes a
  valve that slips without oscillating.

Sticky loops of ``make_loops`` carry their true band ``S`` (% of travel). For each world
this prints, among the loops the scan calls sticky (and, for the fitted band, among those
the shape library gives no size), how many each size covers, the median and quartiles of
its ratio to ``S``, its rank correlation with ``S`` and the share within a factor of 2,
and saves a log-log scatter of both sizes against ``S``.

Run: python examples/stiction_size.py [n_loops] [figure.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from scipy.stats import spearmanr  # noqa: E402

from sktiction.datasets import make_loops  # noqa: E402
from sktiction.reports import scan_loops  # noqa: E402

SIZES = {"stiction_size_mean": "shape library (OP peak-to-peak)",
         "stiction_band_fit": "fitted dead band"}  # fmt: skip


def size_row(size, truth, among):
    """How close ``size`` comes to ``truth`` over the loops ``among`` that it sizes."""
    ok = among & np.isfinite(size) & (size > 0)
    ratio = size[ok] / truth[ok]
    some = ok.sum() > 2
    return {
        "among": int(among.sum()),
        "sized": int(ok.sum()),
        "ratio q25": np.quantile(ratio, 0.25) if some else np.nan,
        "ratio median": np.median(ratio) if some else np.nan,
        "ratio q75": np.quantile(ratio, 0.75) if some else np.nan,
        "rank corr.": spearmanr(size[ok], truth[ok])[0] if some else np.nan,
        "within x2": np.mean((ratio > 0.5) & (ratio < 2.0)) if some else np.nan,
    }


def main(n_loops=300, figure="stiction_size.png"):
    rows = []
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5), sharex=True, sharey=True)
    for ax, world in zip(axes, ("classic", "default")):
        X, y, meta = make_loops(n_loops, n_samples=2000, world=world, stiction_fraction=1.0,
                                random_state=0, return_meta=True)  # fmt: skip
        report = scan_loops(X)
        called = (report["verdict"] == "stiction").to_numpy()
        S = meta["S"].to_numpy()
        no_cycle_size = ~np.isfinite(report["stiction_size_mean"].to_numpy(dtype=float))
        for column, label, among in (*((c, lab, called) for c, lab in SIZES.items()),
                                     ("stiction_band_fit", "fitted band, no peak-to-peak",
                                      called & no_cycle_size)):  # fmt: skip
            size = report[column].to_numpy(dtype=float)
            rows.append({"world": world, "size": label, **size_row(size, S, among)})
            if among is called:
                ok = among & np.isfinite(size) & (size > 0)
                ax.loglog(S[ok], size[ok], ".", alpha=0.6, label=label)
        ax.loglog([0.2, 20], [0.2, 20], "k--", lw=0.8, label="size = S")
        ax.set(title=f"{world} world", xlabel="true band S, % of travel")
    axes[0].set_ylabel("estimated size, % of travel")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=100)

    pd.set_option("display.width", 160)
    print(pd.DataFrame(rows).to_string(index=False, float_format="{:.2f}".format))
    print(f"saved {figure}")


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 300,
        sys.argv[2] if len(sys.argv) > 2 else "stiction_size.png",
    )
