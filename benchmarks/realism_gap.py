"""What the simulated worlds get wrong on the measured loops, and how much calibration closes.

Reads ``../shared/data`` (plant historian windows and ISDB loops; see
``benchmarks/_measured_common.py``), compares loops of ``make_loops`` against them with
``sktiction.realism.compare`` and prints, for the classic world, the default world and the
default world calibrated on the measured loops (``make_loops(..., realism=calibrate(...))``):
the table, the number of significant effects and the domain AUC (one number for the gap).
Writes a figure of the largest differences of the default world.

Usage::

    python benchmarks/realism_gap.py [--n-simulated 300] [--figure realism_gap.png]
    python benchmarks/realism_gap.py --hidden 120   # hidden-effect rates, no measured data
    python benchmarks/realism_gap.py --speed        # loop_statistics time per loop

``--hidden N`` repeats the design of ``tests/test_realism.py`` over N draws per check (a
recording effect hidden in 16 loops of 400 samples compared with 16 others; pairs; nothing
hidden) in the classic and the default world, and prints the rates.

Loops are simulated with 751 samples, the plant windows' length (the ISDB loops are longer;
record length is reported in the table and left out of the domain AUC). No threshold of the
package is set from these files: calibration is the measurement being benchmarked.

The domain AUC is given twice: with folds by loop (as in ``compare``'s default) and with folds
by valve tag (``groups=``), since windows of one valve are near copies and folds by loop let
the classifier recognise a valve it has seen. Calibration is checked in-sample (fitted to all
measured loops) and out of sample: the tags of each loop type are split in two halves (three
random splits), ``calibrate`` sees one half, and the calibrated world is compared with the
other half, next to the default world compared with the same half.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _measured_common import load_measured  # noqa: E402

from sktiction.datasets import make_loops  # noqa: E402
from sktiction.realism import (  # noqa: E402
    calibrate,
    compare,
    domain_gap,
    loop_statistics,
    plot_compare,
)

N_SAMPLES = 751
COLUMNS = ["effect", "statistic", "simulated", "measured", "effect_size", "p_value", "significant"]


def _show(title, table):
    print(f"\n## {title}")
    print(
        f"domain AUC {table.attrs['domain_auc']:.3f} (folds by loop), "
        f"{table.attrs['domain_auc_by_tag']:.3f} (folds by tag); "
        f"significant effects {int(table['significant'].sum())} of {len(table)}"
    )
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(table[COLUMNS].round(3).to_string(index=False))


def _draw(name, rng):
    from sktiction.simulation import historian

    def loguniform(lo, hi):
        return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))

    return {
        "hold_last_value": lambda: historian.HoldLastValue(
            rng.uniform(0.1, 0.5), rng.uniform(2.0, 10.0)),
        "deadband_compression": lambda: historian.DeadbandCompression(loguniform(0.01, 0.1)),
        "swinging_door": lambda: historian.SwingingDoorCompression(loguniform(0.01, 0.05)),
        "interval_averaging": lambda: historian.IntervalAveraging(int(rng.integers(2, 11))),
        "quantisation": lambda: historian.SpanQuantization(loguniform(0.01, 0.1)),
        "spikes": lambda: historian.Spikes(loguniform(0.002, 0.02), rng.uniform(0.5, 2.0)),
        "drift": lambda: historian.SensorDrift(rng.uniform(1.0, 3.0)),
    }[name]()  # fmt: skip


def hidden_rates(n_draws, world, n_loops=16, n_samples=400):
    """Rates of the hidden-effect checks of tests/test_realism.py over more draws."""
    import itertools

    from sktiction.realism import apply_effects, effect_names

    names = effect_names("recording")
    X, _ = make_loops(2 * n_draws * n_loops, n_samples, world=world, random_state=7)
    stats = loop_statistics(X)

    def sets(k):
        a = slice(2 * k * n_loops, (2 * k + 1) * n_loops)
        b = slice((2 * k + 1) * n_loops, (2 * k + 2) * n_loops)
        return stats.iloc[a].reset_index(drop=True), X[b]

    first, top3, clean = [], [], []
    pairs = list(itertools.combinations(names, 2))
    for k in range(n_draws):
        rng = np.random.default_rng(k)
        sim, meas = sets(k)
        name = names[k % len(names)]
        table = compare(sim, apply_effects(meas, [_draw(name, rng)], random_state=rng),
                        domain=False)  # fmt: skip
        first.append(table.loc[0, "effect"] == name and bool(table.loc[0, "significant"]))
        a, b = pairs[k % len(pairs)]
        table = compare(sim, apply_effects(meas, [_draw(a, rng), _draw(b, rng)],
                                           random_state=rng), domain=False)  # fmt: skip
        top3.append({a, b} <= set(table["effect"][:3]))
        clean.append(not compare(sim, meas, domain=False)["significant"].any())
    print(f"{world} world, {n_draws} draws, {n_loops} vs {n_loops} loops of {n_samples} samples:")
    print(f"  hidden effect ranked first and significant: {np.mean(first):.3f}")
    print(f"  both effects of a pair in the top 3 (all {len(pairs)} pairs): {np.mean(top3):.3f}")
    print(f"  nothing hidden, no significant row: {np.mean(clean):.3f}")


def out_of_sample(measured, groups, loop_types, X_default, n, seed, n_splits=3):
    """Calibrate on half of the tags, compare with the other half; the default world too."""
    tag_type = dict(zip(groups, loop_types, strict=True))
    rows = []
    for split in range(n_splits):
        rng = np.random.default_rng(seed + split)
        # half of the tags of each loop type, so that both halves hold every type
        half = set()
        for lt in sorted(set(loop_types)):
            tags = rng.permutation(sorted(t for t, v in tag_type.items() if v == lt))
            half |= set(tags[: (len(tags) + int(rng.integers(2))) // 2])
        in_a = np.array([g in half for g in groups])
        for fit, test in ((in_a, ~in_a), (~in_a, in_a)):
            realism = calibrate(measured[fit].reset_index(drop=True), loop_types=loop_types[fit],
                                random_state=seed + split)  # fmt: skip
            Xr, _ = make_loops(n, N_SAMPLES, realism=realism, random_state=seed + split)
            held = measured[test].reset_index(drop=True)
            for world, Xs in (("default", X_default), ("calibrated", Xr)):
                table = compare(Xs, held, groups=groups[test], random_state=seed)
                rows.append({"split": split, "world": world,
                             "auc_by_tag": table.attrs["domain_auc"],
                             "significant": int(table["significant"].sum())})  # fmt: skip
    res = pd.DataFrame(rows)
    print(f"\n## out of sample: calibrated on half of the tags, compared with the other half "
          f"({n_splits} splits x 2 halves, {n} simulated loops each)")  # fmt: skip
    print(res.groupby("world")[["auc_by_tag", "significant"]].agg(["mean", "min", "max"])
          .round(3).to_string())  # fmt: skip
    return res


def speed(n_loops=200, n_samples=5000):
    """Median time of loop_statistics per loop (one run, on this machine)."""
    import time

    X, _ = make_loops(n_loops, n_samples, random_state=0)
    loop_statistics(X[:2])
    times, cpu = [], []
    for k in range(n_loops):
        t0, c0 = time.perf_counter(), time.process_time()
        loop_statistics(X[k : k + 1])
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    t0, c0 = time.perf_counter(), time.process_time()
    loop_statistics(X)
    batch_wall = (time.perf_counter() - t0) / n_loops
    batch_cpu = (time.process_time() - c0) / n_loops
    print(f"loop_statistics per {n_samples}-sample loop ({n_loops} default-world loops):\n"
          f"  one loop per call: wall median {1e3 * np.median(times):.2f} ms, 90 % "
          f"{1e3 * np.percentile(times, 90):.2f} ms; CPU median {1e3 * np.median(cpu):.2f} ms\n"
          f"  all loops in one call: wall {1e3 * batch_wall:.2f} ms, CPU {1e3 * batch_cpu:.2f} ms"
          " per loop (wall grows with the machine's load)")  # fmt: skip
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-simulated", type=int, default=300)
    parser.add_argument("--figure", default="realism_gap.png")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--hidden", type=int, default=0,
                        help="only the hidden-effect rates, over this many draws")
    parser.add_argument("--speed", action="store_true",
                        help="only the time of loop_statistics per 5,000-sample loop")
    args = parser.parse_args(argv)
    if args.speed:
        return speed()
    if args.hidden:
        for world in ("classic", "default"):
            hidden_rates(args.hidden, world)
        return 0

    data = load_measured()
    if data is None:
        print("measured data not found (../shared/data or $SKTICTION_DATA): skipped")
        return 0
    X, _, groups, meta = data
    loop_types = meta["loop_type"].fillna("unknown").to_numpy()
    measured = loop_statistics(X, ts=meta["ts"].to_numpy(dtype=float))
    print(
        f"measured: {len(measured)} loops ({(meta['dataset'] == 'plant').sum()} plant windows, "
        f"{(meta['dataset'] == 'isdb').sum()} ISDB), {len(set(groups))} tags"
    )

    n = args.n_simulated
    worlds = {}
    Xc, _ = make_loops(n, N_SAMPLES, world="classic", random_state=args.seed)
    worlds["classic world"] = Xc
    Xd, _ = make_loops(n, N_SAMPLES, random_state=args.seed)
    worlds["default world"] = Xd
    realism = calibrate(measured, loop_types=loop_types)
    print(f"\ncalibrated: {realism!r}")
    print(f"overrides: {realism.overrides}")
    with pd.option_context("display.width", 200):
        summary = realism.summary()
        print(summary[summary["share"] > 0].to_string(index=False))
    Xr, _ = make_loops(n, N_SAMPLES, realism=realism, random_state=args.seed)
    worlds["default world calibrated (in-sample)"] = Xr

    tables = {}
    for name, Xs in worlds.items():
        tables[name] = compare(Xs, measured, random_state=args.seed)
        tables[name].attrs["domain_auc_by_tag"] = domain_gap(
            Xs, measured, groups=groups, random_state=args.seed
        )
        _show(name, tables[name])

    print("\n## summary")
    print(f"{'world':40s} AUC by loop  AUC by tag  significant")
    for name, table in tables.items():
        print(
            f"{name:40s} {table.attrs['domain_auc']:11.3f} "
            f"{table.attrs['domain_auc_by_tag']:11.3f}  {int(table['significant'].sum()):2d} of "
            f"{len(table)}"
        )
    out_of_sample(measured, groups, loop_types, Xd, n, args.seed)

    try:
        import matplotlib

        matplotlib.use("Agg")
    except ImportError:
        print("matplotlib not installed: no figure")
        return 0
    fig = plot_compare(tables["default world"], worlds["default world"], measured, n_effects=6)
    fig.savefig(args.figure, dpi=110)
    print(f"figure: {args.figure}")
    return 0


if __name__ == "__main__":
    np.seterr(all="ignore")
    raise SystemExit(main())
