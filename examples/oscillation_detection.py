"""Which signals oscillate, at what period, and how sure is the detector?

``analyze_cycles`` is the one oscillation decision every classifier of sktiction uses.
This example reads it three ways:

1. the six shipped plant windows (``load_plant_examples``): for PV and OP, the decision,
   the oscillation index (0-1, 0.5 is the threshold), the period(s) and Thornhill's
   regularity r of each component, and the cycles' fall share and above share (0.5 for a
   symmetric cycle; the fall share near 0 or 1 for a stick-slip saw-tooth, which ramps
   slowly and slips fast, the above share far from 0.5 for cycles that dwell on one side);
2. a cycle of 1 % of OP's span under two operator moves of 15 % and 25 %: read as it is
   the moves bury the cycle; read again without them it is found, and
   ``CycleAnalysis.level_shifts`` says where they were;
3. ``OscillationFeatures`` per channel in a pipeline, as a pandas table.

A figure shows the signal of part 2 with its oscillating stretches shaded and the level
shifts marked.

Run: python examples/oscillation_detection.py [figure.png]
"""

import sys

import numpy as np
import pandas as pd

from sktiction import OscillationFeatures
from sktiction.cycles import analyze_cycles
from sktiction.datasets import load_plant_examples, make_loops


def describe(x):
    """One row: decision, index, periods and regularities of a signal."""
    a = analyze_cycles(x)
    return {
        "oscillating": a.oscillating,
        "index": round(a.oscillation_index, 2),
        "periods": np.round(a.periods, 1).tolist(),
        "regularity r": np.round(a.regularities, 2).tolist(),
        "fall share": round(a.fall_share, 2),
        "above share": round(a.above_share, 2),
    }


def plant_table():
    plant = load_plant_examples()
    rows = []
    for loop, label, file in zip(plant.X, plant.y, plant.meta["file"]):
        for channel, name in ((0, "PV"), (1, "OP")):
            x = loop[np.isfinite(loop[:, channel]), channel]
            rows.append({"file": file[:30], "sticky": label, "channel": name, **describe(x)})
    return pd.DataFrame(rows)


def moved_cycle(seed=0):
    """OP of a loop cycling by +-0.5 % of span every 120 samples, moved by an operator
    by +15 % at sample 900 and -25 % at sample 2,100 (through a 10-sample lag)."""
    rng = np.random.default_rng(seed)
    t = np.arange(3000)
    moves = 15.0 * (t >= 900) - 25.0 * (t >= 2100)
    lagged = np.zeros_like(moves)
    for k in range(1, t.size):
        lagged[k] = lagged[k - 1] + (moves[k] - lagged[k - 1]) / 10.0
    return 50.0 + lagged + 0.5 * np.sin(2 * np.pi * t / 120) + rng.normal(0, 0.05, t.size)


def main(figure=None):
    pd.set_option("display.width", 160)
    print("1. Shipped plant windows (751 samples at 10 s):")
    print(plant_table().to_string(index=False))

    x = moved_cycle()
    a = analyze_cycles(x)
    print("\n2. A 1 % cycle under operator moves of 15 % and 25 %:")
    print(f"   oscillating={a.oscillating}, index={a.oscillation_index:.2f}, "
          f"period={a.period:.0f} samples, level shifts taken out at {a.level_shifts.tolist()}")

    X, _ = make_loops(6, n_samples=1500, random_state=0)
    features = OscillationFeatures().set_output(transform="pandas").fit_transform(X)
    print("\n3. OscillationFeatures of six simulated loops:")
    print(features.round(2).to_string())

    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(10, 3.2), constrained_layout=True)
        ax.plot(x, lw=0.7, color="tab:red", label="OP (%)")
        for start, end in a.segments:
            ax.axvspan(start, end, color="tab:green", alpha=0.15, lw=0)
        for s in a.level_shifts:
            ax.axvline(s, color="k", ls="--", lw=0.8)
        ax.set_xlabel("sample")
        ax.set_title(f"oscillating (index {a.oscillation_index:.2f}, period {a.period:.0f}); "
                     "green: oscillating stretches, dashed: level shifts taken out")  # fmt: skip
        ax.legend(loc="upper right")
        fig.savefig(figure, dpi=110)
        print(f"\nfigure written to {figure}")
    return a


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
