"""``sktiction compare MEASURED ...``: what the simulated world gets wrong on measured loops."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd

EXIT_OK = 0
EXIT_USAGE = 2
_SUFFIXES = (".txt", ".csv", ".tsv")
_COLUMNS = ["effect", "statistic", "simulated", "measured", "effect_size", "p_value",
            "significant"]  # fmt: skip


def add_compare_parser(subparsers):
    """Add the ``compare`` sub-command to an :mod:`argparse` sub-parser set.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        From ``parser.add_subparsers()``.

    Returns
    -------
    parser : argparse.ArgumentParser
        The ``compare`` parser; its default ``func`` is :func:`run_compare`.

    Examples
    --------
    >>> import argparse
    >>> from sktiction.realism._cli import add_compare_parser
    >>> parser = argparse.ArgumentParser(prog="sktiction")
    >>> _ = add_compare_parser(parser.add_subparsers(dest="command"))
    >>> args = parser.parse_args(["compare", "data/", "--n-simulated", "50"])
    >>> args.measured, args.n_simulated, args.figure
    (['data/'], 50, 'sktiction_compare.png')
    """
    parser = subparsers.add_parser(
        "compare",
        help="compare measured loops with the simulated world: which effects differ, "
        "how much (domain AUC), with a figure",
        description="Compare measured loops (files or folders, searched recursively) with "
        "loops of make_loops: one row per effect of sktiction.realism.EFFECTS, most evident "
        "first, and the cross-validated AUC of a classifier telling the two apart.",
    )
    parser.add_argument("measured", nargs="+", help="files or folders of measured loops")
    parser.add_argument("--figure", default="sktiction_compare.png",
                        help="figure of the largest differences (default: %(default)s; '' "
                        "for none)")  # fmt: skip
    parser.add_argument("--n-simulated", type=int, default=300,
                        help="simulated loops (default: %(default)s)")  # fmt: skip
    parser.add_argument("--n-samples", type=int, default=None,
                        help="samples per simulated loop (default: the measured median, "
                        "at most 5000)")  # fmt: skip
    parser.add_argument("--world", choices=("default", "classic"), default="default",
                        help="simulated world of make_loops (default: %(default)s)")
    parser.add_argument("--calibrate", action="store_true",
                        help="also compare make_loops(..., realism=calibrate(measured)) "
                        "(in-sample: fitted to the same loops)")  # fmt: skip
    parser.add_argument("--ts", type=float, default=None,
                        help="sampling time in seconds, for files without a time column")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    parser.set_defaults(func=run_compare)
    return parser


def _files(paths):
    out = []
    for p in map(Path, paths):
        if p.is_dir():
            found = sorted(
                f for f in p.rglob("*")
                if f.is_file() and f.suffix.lower() in _SUFFIXES
                and f.stem.lower() != "index"
            )  # fmt: skip
            out.extend(found)
        else:
            out.append(p)
    return out


def _print_table(title, table, out):
    print(f"\n{title}", file=out)
    print(
        f"domain AUC {table.attrs['domain_auc']:.3f}; significant effects "
        f"{int(table['significant'].sum())} of {len(table)} (Holm, alpha "
        f"{table.attrs['alpha']})",
        file=out,
    )
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(table[_COLUMNS].round(4).to_string(index=False), file=out)


def run_compare(args, out=None):
    """Run ``sktiction compare``: read, simulate, compare, print, draw.

    Parameters
    ----------
    args : argparse.Namespace
        From the parser of :func:`add_compare_parser`.
    out : file-like or None, default=None
        Where to print (standard output when None).

    Returns
    -------
    code : int
        0 when the table was printed; 2 for a missing path, bad numbers, or no readable loop.

    Examples
    --------
    >>> import argparse, tempfile
    >>> from pathlib import Path
    >>> import numpy as np, pandas as pd
    >>> from sktiction.realism._cli import add_compare_parser, run_compare
    >>> folder = Path(tempfile.mkdtemp())
    >>> rng = np.random.default_rng(0)
    >>> for k in range(6):
    ...     pv = np.sin(np.arange(300) / 8) + 0.1 * rng.standard_normal(300)
    ...     pd.DataFrame({"t": np.arange(300.0), "PV": pv, "OP": 50 + 3 * pv}).to_csv(
    ...         folder / f"loop{k}.csv", index=False)
    >>> parser = argparse.ArgumentParser()
    >>> _ = add_compare_parser(parser.add_subparsers())
    >>> args = parser.parse_args(["compare", str(folder), "--n-simulated", "20",
    ...                           "--world", "classic", "--figure", ""])
    >>> import io
    >>> buffer = io.StringIO()
    >>> run_compare(args, out=buffer)
    0
    >>> "domain AUC" in buffer.getvalue()
    True
    """
    from ..datasets import make_loops, read_loops
    from . import calibrate, compare, loop_statistics, plot_compare

    out = out or sys.stdout
    missing = [p for p in args.measured if not Path(p).exists()]
    if missing:
        print(f"sktiction compare: error: no such file or folder: {', '.join(missing)}",
              file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    if args.n_simulated < 10:
        print("sktiction compare: error: --n-simulated must be at least 10.", file=sys.stderr)
        return EXIT_USAGE
    files = _files(args.measured)
    if not files:
        print("sktiction compare: error: no .txt, .csv or .tsv files found.", file=sys.stderr)
        return EXIT_USAGE
    data = read_loops(files, ts=args.ts, on_error="skip")
    ok = (data.meta["status"] == "ok").to_numpy()
    for _, row in data.meta[~ok].iterrows():
        print(f"skipped {row['file']}: {row['reason']}", file=out)
    # a loop with inf has no statistics (a reader keeps such values; they are not gaps)
    infinite = ok & np.isinf(data.X).any(axis=(1, 2))
    for name in data.meta.loc[infinite, "file"]:
        print(f"skipped {name}: infinite values", file=out)
    ok = ok & ~infinite
    if ok.sum() < 2:
        print("sktiction compare: error: fewer than 2 readable loops.", file=sys.stderr)
        return EXIT_USAGE
    meta = data.meta[ok].reset_index(drop=True)
    measured = loop_statistics(data.X[ok], ts=meta["ts"].to_numpy(dtype=float))
    n_samples = args.n_samples or int(min(5000, max(50, np.median(measured["n_samples"]))))
    print(
        f"measured: {len(measured)} loops from {len(files)} files; simulated: "
        f"{args.n_simulated} loops of {n_samples} samples, world {args.world!r}",
        file=out,
    )
    sim, _ = make_loops(args.n_simulated, n_samples, world=args.world,
                        random_state=args.seed)  # fmt: skip
    table = compare(sim, measured, random_state=args.seed)
    _print_table(f"make_loops(world={args.world!r}) against the measured loops", table, out)
    if args.calibrate:
        if args.world != "default":
            print("--calibrate needs the default world; skipped", file=out)
        else:
            types = meta["loop_type"].fillna("unknown").to_numpy()
            realism = calibrate(measured, loop_types=types, random_state=args.seed)
            print(f"\ncalibrated: {realism!r}; overrides {realism.overrides}", file=out)
            sim_c, _ = make_loops(args.n_simulated, n_samples, realism=realism,
                                  random_state=args.seed)  # fmt: skip
            table_c = compare(sim_c, measured, random_state=args.seed)
            _print_table("calibrated world (in-sample) against the measured loops", table_c,
                         out)  # fmt: skip
    if args.figure:
        try:
            import matplotlib

            matplotlib.use("Agg")
        except ImportError:
            print("matplotlib is not installed: no figure (pip install matplotlib)", file=out)
            return EXIT_OK
        fig = plot_compare(table, sim, measured)
        fig.savefig(args.figure, dpi=110)
        print(f"\nwrote the figure to {args.figure}", file=out)
    return EXIT_OK
