"""What the HTML report's figures cost next to the scan, and next to the recipe they replaced.

A site scan writes at most ``max_figures`` (200) figures. Each shows a day of one loop
(8,640 samples at 10 s), its cycles shaded and labelled, PV against OP and R per cycle.
Until this benchmark the figure used a constrained layout, one shaded span and one label per
cycle and legends placed by search ("best"); that recipe is rebuilt here as the reference.
Printed, all from this one run in CPU seconds (the machine is shared): the scan per loop,
each recipe per figure, and their ratios.

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_report.py [n_loops]
"""

import sys
import time

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from sktiction.datasets import make_loops  # noqa: E402
from sktiction.reports import scan_loops  # noqa: E402
from sktiction.reports.html import _figure_png, _render  # noqa: E402
from sktiction.reports.plots import loop_cycles, plot_area_ratios  # noqa: E402

N_LOOPS = int(sys.argv[1]) if len(sys.argv) > 1 else 30


def reference_figure(one, cycles):
    """The figure as drawn before: constrained layout, an artist per cycle, legends by search."""
    fig = plt.figure(figsize=(12, 4.2), layout="constrained")
    grid = fig.add_gridspec(2, 3, width_ratios=[3.2, 1.2, 1.2])
    trend = fig.add_subplot(grid[0, 0])
    op_ax = fig.add_subplot(grid[1, 0], sharex=trend)
    t = np.arange(one.shape[1])
    trend.plot(t, one[0, :, 0], lw=0.9, label="PV")
    trend.plot(t, one[0, :, 2], lw=0.9, ls="--", label="SP")
    op_ax.plot(t, one[0, :, 1], lw=0.9, color="C2", label="OP")
    for k, row in enumerate(cycles.itertuples()):
        for a in (trend, op_ax):
            a.axvspan(row.start, row.end, alpha=0.08 if k % 2 else 0.16, color="C1")
        op_ax.annotate(f"{str(row.op_shape)[:4]}/{str(row.pv_shape)[:4]}",
                       ((row.start + row.end) / 2, 1.0), xycoords=("data", "axes fraction"),
                       ha="center", va="bottom", fontsize=7)
    for a in (trend, op_ax):
        a.legend(loc="upper right", fontsize=8)
    ax = fig.add_subplot(grid[:, 1])
    ax.plot(one[0, :, 1], one[0, :, 0], lw=0.5, color="0.6")
    if len(cycles):
        a, b = int(cycles["start"].min()), int(cycles["end"].max())
        ax.plot(one[0, a:b, 1], one[0, a:b, 0], lw=0.8, color="C0", label="analysed cycles")
        ax.legend(loc="best", fontsize=7)
    plot_area_ratios(cycles, ax=fig.add_subplot(grid[:, 2]))
    fig.suptitle("reference", fontsize=10)
    return fig


def cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def main():
    X, _ = make_loops(N_LOOPS, n_samples=8640, random_state=3)
    scan_loops(X[:2])  # the model loaded and the kernels compiled before timing
    scan, _ = cpu(lambda: scan_loops(X))
    loops = [X[i : i + 1] for i in range(N_LOOPS)]
    _render(loops[:1], [10.0], ["warm-up"], 72)
    now, drawn = cpu(lambda: _render(loops, [10.0] * N_LOOPS, ["loop"] * N_LOOPS, 72))
    cycles = [loop_cycles(one) for one in loops]

    def before():
        with matplotlib.rc_context({"font.size": 8}):
            return [_figure_png(reference_figure(one, c), 72) for one, c in zip(loops, cycles)]

    ref, _ = cpu(before)
    size = np.mean([len(png) for png, _ in drawn]) / 1e3
    n_cycles = np.array([len(c) for c in cycles])
    print(f"{N_LOOPS} loops of 8,640 samples; analysed cycles per loop: median "
          f"{np.median(n_cycles):.0f}, max {n_cycles.max()}")
    print(f"scan: {1e3 * scan / N_LOOPS:.0f} ms CPU per loop")
    print(f"figure now: {1e3 * now / N_LOOPS:.0f} ms CPU ({size:.0f} kB of base64 PNG), "
          f"{now / scan:.1f} x the scan per loop")
    print(f"figure as drawn before: {1e3 * ref / N_LOOPS:.0f} ms CPU, {ref / scan:.1f} x the scan "
          f"per loop; now / before = {now / ref:.2f}")
    print(f"a site report (200 figures): {200 * now / N_LOOPS:.0f} s CPU now, "
          f"{200 * ref / N_LOOPS:.0f} s before")


if __name__ == "__main__":
    main()
