"""Command line: ``sktiction demo`` and ``sktiction scan FILES``."""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
import pandas as pd

SUMMARY_COLUMNS = [
    "verdict",
    "stiction_probability",
    "area_ratio",
    "shape_confidence",
    "stiction_size_mean",
    "n_cycles",
    "reason",
]


def _print_table(df, columns):
    with pd.option_context("display.width", 160, "display.max_columns", 20,
                           "display.float_format", "{:.2f}".format):
        print(df[columns].to_string())


def _demo(args):
    from . import pretrained_classifier
    from .datasets import load_example
    from .reports import scan_loops

    data = load_example()
    t0 = time.perf_counter()
    clf = pretrained_classifier(random_state=0)
    t1 = time.perf_counter()
    report = scan_loops(data.X, data.meta[["cause"]], classifier=clf)
    t2 = time.perf_counter()
    print(f"sktiction demo: {len(data.X)} simulated loops shipped with the package "
          f"(causes known)\n")
    _print_table(report, ["cause", *SUMMARY_COLUMNS])
    found = report["verdict"].eq("stiction").to_numpy()
    truth = data.y.astype(bool)
    print(f"\nstiction found in {found.sum()} loops; {np.sum(found & truth)} of {truth.sum()} "
          f"sticky loops caught, {np.sum(found & ~truth)} false alarms.")
    print(f"trained the learned classifier on simulated loops in {t1 - t0:.1f} s; "
          f"scanned {len(data.X)} loops in {t2 - t1:.2f} s.")
    return 0


def _scan(args):
    from . import pretrained_classifier
    from .datasets import read_loops
    from .reports import scan_loops

    data = read_loops(args.paths, ts=args.ts, on_error="skip")
    report = scan_loops(
        data.X, data.meta, classifier=pretrained_classifier(random_state=0),
        n_jobs=args.n_jobs, progress=not args.quiet,
    )
    if args.output:
        report.to_csv(args.output, index=False)
        print(f"wrote {len(report)} rows to {args.output}", file=sys.stderr)
    _print_table(report.set_index("tag") if "tag" in report else report, SUMMARY_COLUMNS)
    return 0


def main(argv=None):
    """Entry point of the ``sktiction`` command.

    Parameters
    ----------
    argv : list of str or None, default=None
        Arguments; ``None`` reads ``sys.argv``.

    Returns
    -------
    code : int
        Exit status.
    """
    parser = argparse.ArgumentParser(
        prog="sktiction",
        description="Is this control loop oscillating because its valve sticks?",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="scan the simulated example loops shipped with sktiction")
    demo.set_defaults(func=_demo)
    scan = sub.add_parser("scan", help="scan historian exports or CSV files, one loop each")
    scan.add_argument("paths", nargs="+", help="files or folders (.txt historian, .csv)")
    scan.add_argument("-o", "--output", help="write the full report to this CSV file")
    scan.add_argument("--ts", type=float, default=None,
                      help="sampling time in seconds, for files without a time column")
    scan.add_argument("-j", "--n-jobs", type=int, default=None, help="parallel workers")
    scan.add_argument("-q", "--quiet", action="store_true", help="no progress output")
    scan.set_defaults(func=_scan)
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
