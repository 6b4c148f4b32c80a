"""How the scan's stiction sizes and probabilities carry over to loops ``make_loops`` did not make.

``examples/stiction_size.py`` compares the sizes with the true band of ``make_loops``'
sticky valves, the world the fitted band's scale was set on
(:data:`sktiction.features.hysteresis.PLAY_BAND_RATIO`, default world, seeds 0-4). This
script asks the same of the two simulators written apart from it, whose valves and
bands are defined otherwise:

- the second simulator (``benchmarks/independent_world.py``, draw 2026, 400 loops of
  6,000 s): a force-balance valve with Karnopp friction, band ``S = 2 Fs``;
- the third simulator (``benchmarks/third_world.py``, draws 0 and 1, 400 loops each):
  He 2007, Kano 2004 and force-balance Stribeck valves, some behind a positioner; the
  truth is the band its own ramp test reads (``band_eff``);
- a default-world draw the scale was not set on (seed 5, 300 sticky loops).

Among the sticky loops the scan calls sticky, for each size: how many it sizes, the
median and quartiles of its ratio to the true band, the rank correlation and the share
within a factor of 2. ``fitted band, as fitted`` is the play operator's band before
the division by ``PLAY_BAND_RATIO`` (the same fit, so the two rows compare one run).

Then how sure the scan is: among all loops of each simulator written apart (sticky and
healthy), per bin of ``stiction_probability``, how many loops, their mean probability
and the share that is sticky. Loops without a probability (no verdict) are left out.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/sizes_and_confidence.py`` (a few minutes).
With ``--ratio``, only this: ``PLAY_BAND_RATIO`` measured again, the median of the fit as
made over the true band, per draw and pooled, among the sticky loops of the default
world's seeds 0-4 (300 each) that a scan calls sticky.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd

from sktiction.datasets import make_loops
from sktiction.features.hysteresis import PLAY_BAND_RATIO
from sktiction.reports import scan_loops

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
import independent_world  # noqa: E402
import third_world  # noqa: E402
from stiction_size import size_row  # noqa: E402  (the example's own measure)


def judges():
    """(name, X, labels (1 sticky), true band per loop: 0 for a healthy valve)."""
    X, y, meta = make_loops(300, n_samples=2000, stiction_fraction=1.0, random_state=5,
                            return_meta=True)  # fmt: skip
    yield "default world, seed 5", X, y, meta["S"].to_numpy(float)
    X, y, meta = independent_world.make_independent_loops(400, 6000, random_state=2026)
    yield "second simulator", X, y, meta["S"].to_numpy(float)
    for seed in (0, 1):
        X, y, meta = third_world.make(400, random_state=seed)
        yield f"third simulator, draw {seed}", X, y, np.where(y == 1, meta["band_eff"], 0.0)


def size_rows(name, report, S):
    called = (report["verdict"] == "stiction").to_numpy() & (S > 0)
    p2p = report["stiction_size_mean"].to_numpy(float)
    fit = report["stiction_band_fit"].to_numpy(float)
    return [
        {"judge": name, "size": label, **size_row(size, S, among)}
        for label, size, among in (
            ("shape library (OP peak-to-peak)", p2p, called),
            ("fitted band", fit, called),
            ("fitted band, as fitted", fit * PLAY_BAND_RATIO, called),
            ("fitted band, no peak-to-peak", fit, called & ~np.isfinite(p2p)),
        )
    ]


#: Bins of the stiction probability.
BINS = (0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0 + 1e-9)


def reliability(name, report, sticky):
    """Per probability bin: loops, mean probability, share sticky."""
    p = report["stiction_probability"].to_numpy(float)
    ok = np.isfinite(p)
    table = pd.DataFrame({"p": p[ok], "sticky": sticky[ok]})
    table["bin"] = pd.cut(table["p"], BINS, right=False)
    out = table.groupby("bin", observed=True).agg(
        loops=("p", "size"), mean_probability=("p", "mean"), sticky=("sticky", "mean")
    )
    return out.reset_index().assign(judge=name)


def play_band_ratio(seeds=range(5), n_loops=300):
    """The fit as made over the true band: medians per seed and pooled."""
    ratios = []
    for seed in seeds:
        X, _, meta = make_loops(n_loops, n_samples=2000, stiction_fraction=1.0,
                                random_state=seed, return_meta=True)  # fmt: skip
        report = scan_loops(X)
        fit = report["stiction_band_fit"].to_numpy(float) * PLAY_BAND_RATIO
        ok = (report["verdict"] == "stiction").to_numpy() & np.isfinite(fit) & (fit > 0)
        ratios.append(fit[ok] / meta["S"].to_numpy(float)[ok])
        print(f"seed {seed}: {ok.sum()} valves, median {np.median(ratios[-1]):.3f}", flush=True)
    pooled = np.concatenate(ratios)
    print(f"pooled: {pooled.size} valves, median {np.median(pooled):.3f} "
          f"(PLAY_BAND_RATIO = {PLAY_BAND_RATIO})")  # fmt: skip


def main():
    if "--ratio" in sys.argv[1:]:
        play_band_ratio()
        return
    rows, calibration = [], []
    for name, X, y, S in judges():
        report = scan_loops(X)
        rows += size_rows(name, report, S)
        if not name.startswith("default"):  # all its loops are sticky
            calibration.append(reliability(name, report, y == 1))
        print(f"scanned {name}", flush=True)
    pd.set_option("display.width", 200)
    fmt = "{:.2f}".format
    print(pd.DataFrame(rows).to_string(index=False, float_format=fmt))
    print("\nhow sure: per bin of stiction_probability, the share of loops that are sticky")
    table = pd.concat(calibration)
    print(table[["judge", "bin", "loops", "mean_probability", "sticky"]].to_string(
        index=False, float_format=fmt))  # fmt: skip


if __name__ == "__main__":
    main()
