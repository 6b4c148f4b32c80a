"""Command line: ``sktiction scan``, ``sktiction demo`` and ``sktiction compare``.

Exit codes (``sktiction scan``):

- ``0``: every file was read and every loop scanned (a loop may still get
  ``no_verdict`` with its reason: that is an answer, not a failure);
- ``1``: some files or loops could not be read; the others were scanned, and the
  table and the output name each failure with its reason (files that are not loop
  files, such as a README or a folder index, are listed as ``unsupported`` but are
  not failures);
- ``2``: usage error, a path that does not exist, or no file could be read at all.
  These exit at once, before any model is trained or loaded.

Environment: ``SKTICTION_TRAIN_LOOPS`` and ``SKTICTION_TRAIN_SAMPLES`` set the size of
the simulated training set of the learned classifier (for quick trials and tests; the
defaults are those of :func:`sktiction.pretrained_classifier`).
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

EXIT_OK = 0
EXIT_READ_FAILURES = 1
EXIT_USAGE = 2

FORMATS = ("csv", "parquet", "json")
CHANNEL_KEYS = ("pv", "op", "sp", "time", "mode")

# What the console shows, in this order, when the report has it.
TABLE_COLUMNS = [
    "file",
    "tag",
    "read",
    "verdict",
    "stiction_probability",
    "stiction_size_mean",
    "stiction_band_fit",
    "period",
    "area_ratio",
    "reason",
]


EXIT_CODES = (
    "Exit codes: 0 all files read and scanned (a loop may still get no_verdict, with its "
    "reason); 1 some files or loops could not be read (each named with its reason); 2 usage "
    "error, missing path, or no file readable (before any model is trained or loaded)."
)


class UsageError(Exception):
    """A problem the user can fix on the command line (exit code 2)."""


def _parse_channels(text):
    """``pv=COL,op=COL,sp=COL`` -> dict; a clear message for anything else."""
    if text is None:
        return None
    out = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        key, value = key.strip().lower(), value.strip()
        if not sep or not value:
            raise UsageError(
                f"--channels: expected NAME=COLUMN pairs like pv=FIC101.PV,op=FIC101.OP; "
                f"got {part!r}."
            )
        if key not in CHANNEL_KEYS:
            raise UsageError(
                f"--channels: unknown channel {key!r}; use {', '.join(CHANNEL_KEYS)}."
            )
        out[key] = value
    return out


_COMPRESSION = (".gz", ".bz2", ".zip", ".xz", ".zst")  # pandas infers these from the name


def _output_format(args, path=None, flag="-o"):
    """Format of the file ``path`` (default: ``-o``'s): ``--format``, else its suffix."""
    path = args.output if path is None else path
    fmt = args.format
    if path:
        name = Path(path)
        if name.suffix.lower() in _COMPRESSION:  # report.csv.gz: the format is csv
            name = name.with_suffix("")
        suffix = name.suffix.lower().lstrip(".")
        if fmt is not None and suffix in FORMATS and suffix != fmt:
            raise UsageError(f"{flag} {path}: a .{suffix} name with --format {fmt}; the "
                             "file would not be what its name says.")  # fmt: skip
    if fmt is None and path:
        if suffix and suffix not in FORMATS:
            # writing CSV text into report.xlsx would give a file its program cannot open
            raise UsageError(f"{flag} {path}: no writer for .{suffix} files; use a "
                             f".{', .'.join(FORMATS)} name or say --format "
                             f"{{{','.join(FORMATS)}}}.")  # fmt: skip
        fmt = suffix or "csv"
    fmt = fmt or "csv"
    if fmt == "parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError as exc:
            raise UsageError(
                "--format parquet needs pyarrow: pip install pyarrow (or use csv or json)."
            ) from exc
    return fmt


def _check_writable(*paths):
    """Output files must go to existing folders: found after a long scan, it would lose
    the scan."""
    for path in paths:
        if not path:
            continue
        folder = Path(path).resolve().parent
        if Path(path).is_dir() or str(path).endswith(("/", os.sep)):
            raise UsageError(f"{path} is a folder; give a file name to write to.")
        if not folder.is_dir():
            raise UsageError(f"cannot write {path}: no folder {folder}.")
        if not os.access(folder, os.W_OK):
            raise UsageError(f"cannot write {path}: folder {folder} is not writable.")


def _write_table(report, path, fmt):
    if fmt == "parquet":
        report.to_parquet(path, index=False)
    elif fmt == "json":
        report.to_json(path, orient="records", indent=1, date_format="iso")
    else:
        report.to_csv(path, index=False)


def _classifier():
    """The learned classifier; its training set size can be set from the environment."""
    from . import pretrained_classifier

    kwargs = {}
    for env, key in (("SKTICTION_TRAIN_LOOPS", "n_loops"), ("SKTICTION_TRAIN_SAMPLES",
                                                             "n_samples")):
        if os.environ.get(env):
            kwargs[key] = int(os.environ[env])
    return pretrained_classifier(random_state=0, **kwargs)


def _read_status(report):
    """Per-row reader status: ``ok`` or why the file or loop could not be read."""
    read = pd.Series("", index=report.index)
    for col in ("input_status", "read_status"):
        if col in report:
            read = report[col].fillna("").astype(str)
            break
    if "status" in report:  # scan_files: files it could not read or that hold no loop
        unreadable = report["status"].astype(str).eq("unreadable")
        read = read.where(~(unreadable & read.isin(["", "ok"])), "unreadable")
    return read.where(read != "", "ok")


_DOCUMENTS = (".md", ".rst", ".pdf", ".doc", ".docx", ".html", ".htm", ".png", ".jpg",
              ".jpeg", ".svg", ".json", ".yaml", ".yml", ".toml", ".ini", ".py", ".log")


def _not_loop_files(report, table):
    """Rows of files that are not loop data: unsupported, and a folder index, a file
    without an extension or a document by its suffix."""
    if "path" not in report:
        return pd.Series(False, index=table.index)
    names = report["path"].fillna("").astype(str).map(lambda p: Path(p).name)
    suffix = names.map(lambda n: Path(n).suffix.lower())
    from .datasets._readers import INDEX_NAMES

    index = names.str.lower().isin(INDEX_NAMES)
    plain = (suffix == "") | suffix.isin(_DOCUMENTS) | index
    ours = table["read"] != "ok"  # among the failures: a scan's own output, scanned again
    ours[ours] = report.loc[ours, "path"].map(_is_report).astype(bool)
    return ((table["read"] == "unsupported") & plain) | ours


def _is_report(path):
    """Whether ``path`` is a scan's report (CSV, JSON or Parquet whose columns are ours)."""
    try:
        if str(path).lower().endswith(".parquet"):
            import pyarrow.parquet as pq

            header = " ".join(pq.read_schema(path).names)
        else:
            with open(path, "rb") as f:
                header = f.read(4096).decode("utf-8", errors="replace")
    except Exception:  # noqa: BLE001 - unreadable here too: not ours to vouch for
        return False
    return "stiction_probability" in header and "verdict" in header


def _console_table(report):
    """File, tag, reader status, verdict and one reason per row, for people."""
    table = pd.DataFrame(index=report.index)
    table["file"] = _file_labels(report) if "file" in report else ""
    if "tag" in report:  # a tag column of numbers read as floats: 101, not 101.0
        from .reports.valves import _whole

        table["tag"] = report["tag"].astype(object).map(_whole).fillna("").astype(str)
    else:
        table["tag"] = ""
    table["read"] = _read_status(report)
    for col in TABLE_COLUMNS[3:-1]:
        if col in report:
            table[col] = report[col]
    reason = report["reason"].fillna("").astype(str) if "reason" in report else ""
    if "shape_reason" in report:  # a verdict the shape library could not back, and why
        shape = report["shape_reason"].fillna("").astype(str)
        weak = (reason == "ok") & ~shape.isin(["", "ok"])
        reason = reason.where(~weak, "ok; shapes: " + shape)
    if "input_reason" in report:
        notes = report["input_reason"].fillna("").astype(str)
        failed = table["read"] != "ok"
        reason = np.where(failed, notes, np.where(notes != "", reason + "; " + notes, reason))
    table["reason"] = pd.Series(reason, index=table.index).map(_as_options)
    table = table.rename(columns={"stiction_probability": "p_stiction",
                                  "stiction_size_mean": "size_%",
                                  "stiction_band_fit": "band_%"})
    return table


def _file_labels(report):
    """File names, or where two files share a name (``unit1/FIC1.csv``, ``unit2/FIC1.csv``)
    their paths below the folder all files share."""
    names = report["file"].fillna("").astype(str)
    if "path" not in report:
        return names
    files = pd.DataFrame({"name": names, "path": report["path"]}).drop_duplicates("path")
    if not files.loc[files["name"] != "", "name"].duplicated().any():  # a file's loops
        return names
    paths = report["path"].fillna("").astype(str)
    known = paths[paths != ""]
    try:
        root = os.path.commonpath([os.path.dirname(os.path.abspath(p)) for p in known])
    except ValueError:  # paths on different drives: nothing in common to leave out
        return paths.where(paths != "", names)
    rel = known.map(lambda p: os.path.relpath(os.path.abspath(p), root))
    return rel.reindex(names.index).fillna(names)


_ARGUMENTS = re.compile(r"channels=\{'(\w+)': \.\.\.\}")


def _as_options(reason):
    """The readers' advice in this command's words: ``--channels pv=COLUMN``, ``--ts``."""
    reason = _ARGUMENTS.sub(lambda m: f"--channels {m.group(1)}=COLUMN", str(reason))
    return reason.replace("pass ts=", "pass --ts SECONDS")


def _positive_int(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer; got {text}")
    return value


def _n_jobs(text):
    value = int(text)
    if value == 0:
        raise argparse.ArgumentTypeError("must not be 0 (1 for one process, -1 for every "
                                         "core, N for N workers)")  # fmt: skip
    return value


def _positive_float(text):
    value = float(text)
    if not (np.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds; got {text}")
    return value


def _top(table, n):
    """The ``n`` rows most likely sticky (verdict stiction, by probability), then every
    row that could not be read: what a site scan's console should show first."""
    sticky = table[table["verdict"] == "stiction"]
    if "p_stiction" in sticky:
        sticky = sticky.sort_values("p_stiction", ascending=False, kind="stable")
    return pd.concat([sticky.head(n), table[table["read"] != "ok"]])


def _verdict_counts(report):
    """One line: how many loops got each verdict (rows of files that gave no loop are not
    loops), and the commonest reasons for no verdict: a site where most loops say
    ``pv_op_swapped`` or ``too_short`` has a mapping or export to fix, not loops."""
    loops = report
    if "status" in report:
        loops = report[report["status"].astype(str).ne("unreadable")]
    counts = loops["verdict"].value_counts()
    parts = [f"{counts.get(v, 0)} {v}" for v in ("stiction", "no_stiction", "no_verdict")]
    line = f"verdicts of {len(loops)} loops: " + ", ".join(parts)
    if counts.get("no_verdict", 0) and "reason" in loops:
        why = loops.loc[loops["verdict"].eq("no_verdict"), "reason"].astype(str)
        # the code before any detail: "out_of_domain:<feature>", "ok; shapes: ..."
        top = why.str.split(r"[;:]", regex=True).str[0].str.strip().value_counts().head(3)
        line += " (" + ", ".join(f"{n} {reason}" for reason, n in top.items()) + ")"
    if "oscillating" in loops:  # whatever the cause: the survey an engineer starts from
        osc = loops["oscillating"].eq(True).fillna(False).astype(bool)
        sticky = osc & loops["verdict"].eq("stiction")
        line += f"; {int(osc.sum())} oscillate, {int(sticky.sum())} of them called sticky"
    return line


def _valves(report, path, fmt):
    """Write the per-valve table to ``path`` when asked, and say what it holds when asked
    or when some valve has several records; False if the table was asked for and could
    not be made (the scan and its other outputs stand)."""
    if not path and "tag" not in report:
        return True
    try:
        from .reports.valves import several_records, summarise_valves

        valves = summarise_valves(report)
        if not path and not several_records(valves):
            return True
        if path:
            _write_table(valves, path, fmt)
    except (ValueError, TypeError, OSError) as exc:
        print(f"\nno table per valve: {exc}", file=sys.stderr)
        return not path
    if path:
        print(f"wrote {len(valves)} valves to {path} ({fmt})", file=sys.stderr)
        if (valves["n_records"] == 1).all():
            print("each valve has one record: records are pooled by tag, and a file "
                  "without tag names is tagged with its file name.", file=sys.stderr)
    counts = valves["verdict"].value_counts()
    parts = [f"{counts.get(v, 0)} {v}" for v in ("stiction", "no_stiction", "no_verdict")]
    print(f"verdicts of {len(valves)} valves (stiction when at least half of a valve's "
          f"judged records say so): " + ", ".join(parts), file=sys.stderr)  # fmt: skip
    return True


def _print_table(table, file=None):
    from .reports.html import _decimals

    with pd.option_context("display.width", 200, "display.max_columns", 20,
                           "display.max_colwidth", 70, "display.float_format",
                           lambda x: _decimals(x, 2)):
        print(table.to_string(index=False), file=file)


def _unreadable_table(listing, channels, ts):
    """Read files until one holds a loop: (True, None), or (False, table of every reason)."""
    from .datasets import read_loop_file

    rows = []
    for row in listing.itertuples():
        if not row.supported:
            rows.append({"file": Path(row.path).name, "tag": "", "status": "unsupported",
                         "reason": row.reason})
            continue
        meta = read_loop_file(row.path, channels=channels, ts=ts).meta
        if meta["status"].astype(str).eq("ok").any():
            return True, None
        rows.extend(meta.reindex(columns=["file", "tag", "status", "reason"]).to_dict("records"))
    failures = pd.DataFrame(rows).fillna("")
    failures["reason"] = failures["reason"].map(_as_options)  # in this command's words
    return False, failures


class _FileLoops:
    """Loop ``i`` of a streamed report, read again from its file (one file kept at a time),
    with its gaps bridged as the scan bridged them; for the HTML report's figures."""

    def __init__(self, report, channels, ts):
        self.paths = report["path"].astype(str).to_numpy() if "path" in report else None
        self.ok = report["status"].astype(str).ne("unreadable").to_numpy()
        self.channels, self.ts = channels, ts
        self._path, self._X = None, None

    def __call__(self, i):
        if self.paths is None or not self.ok[i]:
            return None
        from .datasets import read_loop_file

        path = self.paths[i]
        if path != self._path:
            self._path = path
            self._X = read_loop_file(path, channels=self.channels, ts=self.ts).X
        k = int(np.sum(self.paths[:i] == path))  # rows of one file are its loops in order
        if k >= len(self._X):
            return None
        one = self._X[k : k + 1]
        try:
            from ._validation import repair_gaps

            one = repair_gaps(one)[0]
        except ImportError:
            pass
        return one[0]


def _expand(path):
    """``~`` expanded once, so that the check and the writing see the same file (a shell
    leaves ``--report=~/r.html`` as it is)."""
    return os.path.expanduser(path) if path else path


def _scan(args):
    channels = _parse_channels(args.channels)
    args.output, args.report = _expand(args.output), _expand(args.report)
    args.valves = _expand(args.valves)
    fmt = _output_format(args)
    valves_fmt = _output_format(args, args.valves, "--valves") if args.valves else None
    _check_writable(args.output, args.report, args.valves)
    outputs = [Path(p).resolve() for p in (args.output, args.report, args.valves) if p]
    if len(set(outputs)) < len(outputs):
        raise UsageError("-o, --report and --valves name the same file; give each its own.")
    missing = [p for p in args.paths if not Path(p).exists()]
    if missing:
        raise UsageError("no such file or folder: " + ", ".join(missing))
    from .datasets import list_loop_files
    from .reports import scan_files

    listing = list_loop_files(args.paths)
    if not listing["supported"].any():
        _print_table(listing.assign(file=listing["path"])[["file", "reason"]], file=sys.stderr)
        raise UsageError(f"no loop file found under {', '.join(args.paths)} (listed above).")
    # Nothing readable means no model is trained or loaded at all.
    readable, failures = _unreadable_table(listing, channels, args.ts)
    if not readable:
        _print_table(failures, file=sys.stderr)
        raise UsageError("no file could be read (reasons above).")
    client = None
    if args.scheduler:
        try:
            from dask.distributed import Client
        except ImportError as exc:
            raise UsageError("--scheduler needs dask.distributed: pip install "
                             "'sktiction[dask]'.") from exc
        try:
            client = Client(args.scheduler, timeout=30)
        except (OSError, TimeoutError) as exc:
            raise UsageError(f"--scheduler: cannot reach {args.scheduler} ({exc}).") from exc
    try:
        report = scan_files(
            args.paths, channels=channels, classifier=_classifier(), n_jobs=args.n_jobs,
            client=client, progress=not args.quiet, ts=args.ts,
        )
    finally:
        if client is not None:
            client.close()
    if args.output:
        _write_table(report, args.output, fmt)
        print(f"wrote {len(report)} rows to {args.output} ({fmt})", file=sys.stderr)
    if args.report:
        from .reports.html import write_html_report

        write_html_report(report, _FileLoops(report, channels, args.ts), path=args.report,
                          title="sktiction scan", n_jobs=args.n_jobs, progress=not args.quiet)
        print(f"wrote the HTML report to {args.report}", file=sys.stderr)
    table = _console_table(report)
    _print_table(table if args.top is None else _top(table, args.top))
    print("\n" + _verdict_counts(report), file=sys.stderr)
    valves_failed = not _valves(report, args.valves, valves_fmt)
    # a README or a folder index beside the loop files is listed, not a failure; an .xls
    # or .dat file may hold a loop the scan could not read: that is one
    other = _not_loop_files(report, table)
    if other.any():
        n = int(other.sum())
        print(f"{n} {'files are' if n > 1 else 'file is'} not loop data (a folder index, "
              "documents, files without an extension or an earlier scan's report; listed "
              "with the reason).",
              file=sys.stderr)  # fmt: skip
    failed = int(((table["read"] != "ok") & ~other).sum())
    if failed:
        print(f"\n{failed} of {len(table)} files or loops could not be read (see 'read' and "
              f"'reason'); exit code {EXIT_READ_FAILURES}.", file=sys.stderr)
        return EXIT_READ_FAILURES
    return EXIT_READ_FAILURES if valves_failed else EXIT_OK


def _demo(args):
    args.report = _expand(args.report)
    _check_writable(args.report)
    from .datasets import load_example
    from .reports import scan_loops

    data = load_example()
    X, meta = data.X, data.meta[["cause"]].assign(source="simulated", ts=1.0)
    meta.insert(0, "file", [f"simulated_{i:02d}" for i in range(len(X))])
    meta["tag"] = ""
    truth = data.y.astype(bool)
    try:
        from .datasets import load_plant_examples

        plant = load_plant_examples()
    except (ImportError, FileNotFoundError):
        plant = None
    if plant is not None:
        pmeta = plant.meta.assign(source="plant", cause=plant.meta["label"], ts=plant.meta["ts"])
        pmeta = pmeta[["file", "tag", "cause", "source", "ts"]]
        n = max(X.shape[1], plant.X.shape[1])
        pad = lambda a: np.pad(a, ((0, 0), (0, n - a.shape[1]), (0, 0)),  # noqa: E731
                               constant_values=np.nan)
        X = np.concatenate([pad(X), pad(plant.X)])
        meta = pd.concat([meta, pmeta], ignore_index=True)
        truth = np.concatenate([truth, plant.y.astype(bool)])
    t0 = time.perf_counter()
    clf = _classifier()
    t1 = time.perf_counter()
    report = scan_loops(X, meta, classifier=clf)
    t2 = time.perf_counter()
    n_sim = int((meta["source"] == "simulated").sum())
    print(f"sktiction demo: {n_sim} simulated loops and {len(X) - n_sim} real plant windows "
          f"shipped with the package (causes known)\n")
    table = _console_table(report)
    table.insert(2, "cause", meta["cause"].to_numpy())
    _print_table(table.drop(columns=["read"]))
    found = report["verdict"].eq("stiction").to_numpy()
    for source in ("simulated", "plant"):
        s = (meta["source"] == source).to_numpy()
        if s.any():
            alarms = int(np.sum(found & ~truth & s))
            print(f"\n{source}: stiction found in {found[s].sum()} of {s.sum()} loops; "
                  f"{np.sum(found & truth & s)} of {np.sum(truth & s)} sticky loops caught, "
                  f"{alarms} false alarm{'' if alarms == 1 else 's'}.", end="")
    print(f"\n\nlearned classifier ready in {t1 - t0:.1f} s; scanned {len(X)} loops in "
          f"{t2 - t1:.2f} s.")
    if args.report:
        from .reports.html import write_html_report

        write_html_report(report, X, path=args.report, title="sktiction demo")
        print(f"wrote the HTML report to {args.report}")
    return EXIT_OK


def _compare(args):
    try:
        from .realism import _cli as realism_cli
    except ImportError as exc:
        raise UsageError(f"sktiction compare is not available in this version ({exc}).") from exc
    return realism_cli.run_compare(args)


def _add_compare(sub):
    try:
        from .realism import _cli as realism_cli
    except ImportError:
        realism_cli = None
    if realism_cli is not None and hasattr(realism_cli, "add_compare_parser"):
        parser = realism_cli.add_compare_parser(sub)
    else:
        parser = sub.add_parser("compare", help="compare measured loops with the simulated "
                                "world (needs sktiction.realism)")
        parser.add_argument("measured", nargs="*", help="folder of measured loops")
    parser.set_defaults(func=_compare)


def build_parser():
    """The argument parser of the ``sktiction`` command."""
    parser = argparse.ArgumentParser(
        prog="sktiction",
        description="Is this control loop oscillating because its valve sticks?",
        epilog=EXIT_CODES,
    )
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="scan the example loops shipped with sktiction "
                          "(simulated and real plant windows) and write an HTML report")
    demo.add_argument("--report", default="sktiction_demo.html",
                      help="HTML report to write (default: %(default)s; '' for none)")
    demo.set_defaults(func=_demo)
    scan = sub.add_parser("scan", help="scan historian exports or CSV files",
                          description="Scan every loop file under PATHS: one row per loop "
                          "(and per file that could not be read, with the reason).",
                          epilog=EXIT_CODES)
    scan.add_argument("paths", nargs="+", help="files or folders")
    scan.add_argument("-o", "--output", help="write the full report to this file")
    scan.add_argument("--format", choices=FORMATS, default=None,
                      help="format of --output and --valves (default: from each "
                      "suffix, else csv)")
    scan.add_argument("--report", help="also write a self-contained HTML report here")
    scan.add_argument("--valves", help="also write one row per valve (tag) here: its "
                      "records, the share called sticky, median probability and sizes, "
                      "a verdict per valve")
    scan.add_argument("--channels", help="column names, e.g. pv=FIC101.PV,op=FIC101.OP,"
                      "sp=FIC101.SP (also time=..., mode=...)")
    scan.add_argument("--ts", type=_positive_float, default=None,
                      help="sampling time in seconds, for files without a time column")
    scan.add_argument("-j", "--n-jobs", type=_n_jobs, default=None,
                      help="parallel workers (-1: every core)")
    scan.add_argument("--scheduler", default=None,
                      help="address of a dask.distributed scheduler to scan on")
    scan.add_argument("-q", "--quiet", action="store_true", help="no progress output")
    scan.add_argument("--top", type=_positive_int, default=None, metavar="N",
                      help="show only the N loops most likely sticky (and every file that "
                           "could not be read); the -o/--report files keep every row")
    scan.set_defaults(func=_scan)
    _add_compare(sub)
    return parser


def main(argv=None):
    """Entry point of the ``sktiction`` command.

    Parameters
    ----------
    argv : list of str or None, default=None
        Arguments; ``None`` reads ``sys.argv``.

    Returns
    -------
    code : int
        Exit status: 0 all read and scanned, 1 some files or loops could not be
        read, 2 usage error or nothing readable.

    Examples
    --------
    >>> from sktiction.cli import main
    >>> main(["scan", "no/such/folder"])  # the message goes to standard error
    2
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse has printed its message
        return int(exc.code or 0)
    try:
        return args.func(args)
    except UsageError as exc:
        print(f"sktiction: error: {exc}", file=sys.stderr)
        return EXIT_USAGE


if __name__ == "__main__":
    sys.exit(main())
