"""Scan a site's files as a stream: reader, shared analysis, verdicts, report rows.

Files are grouped into work units; each unit reads its own files one at a time, scans
their loops in chunks and returns only report rows, so memory is bounded by a unit,
not by the site. Units run in this process, in joblib workers or on a dask cluster.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from .._validation import (
    STATUS_OK,
    check_loops,
)
from ..classifiers import pretrained_classifier
from ..datasets import list_loop_files
from ..datasets._measured import (
    _META_COLUMNS,
    _meta_frame,
    manual_gaps,
    pad_loops,
    read_loop_rows,
)
from .scan import (
    GAP_COLUMNS,
    REPORT_COLUMNS,
    LearnedAdapter,
    _applicability_gate,
    _Rules,
    _scan_safely,
    empty_rows,
    join_meta,
    loop_types_of,
    progress_bar,
    repaired,
    run_units,
    sampling_times,
)

#: Scan status of a file that could not be read or is not a loop file.
STATUS_UNREADABLE = "unreadable"


def _unreadable_rows(meta):
    """Report rows for loops the reader could not give (one per unreadable file)."""
    report = empty_rows(len(meta))
    report["status"] = STATUS_UNREADABLE
    report["reason"] = meta["reason"].to_numpy(dtype=object)
    return report


def _meta(rows):
    """Meta DataFrame of some files' loops (as read_loop_file's meta, concatenated), with
    the gap-repair columns when the rows hold them."""
    meta = _meta_frame(rows)
    if any(GAP_COLUMNS[0] in r for r in rows):
        gaps = {c: np.array([r.get(c, np.nan) for r in rows], dtype=float) for c in GAP_COLUMNS}
        meta = pd.concat([meta, pd.DataFrame(gaps)], axis=1)
    return meta


def _read(path, channels, ts, max_gap):
    """One file's loops and meta rows, short gaps bridged (``repair_gaps``) when asked."""
    X, rows, _ = read_loop_rows(path, channels, ts)
    X = manual_gaps(X, rows)  # no closed loop to diagnose in manual mode
    readable = np.array([r["status"] == STATUS_OK for r in rows]) & (X.shape[1] > 0)
    if max_gap is not None:
        X, gaps = repaired(X, max_gap, readable)
        for row, values in zip(rows, gaps.tolist()):
            row.update(zip(GAP_COLUMNS, values))
            _note_repairs(row)
    return X, rows, readable


def _note_repairs(row):
    """Say in the loop's input notes what the scan changed before analysing it: a hold
    undone (and the sample time it implies), spikes replaced, placeholders read as gaps,
    stepped tags redrawn, a stretch left out."""
    step, spikes = row["rows_per_value"], row["n_spikes"]
    start, stop, n = row["kept_start"], row["kept_stop"], row.get("n_samples", np.nan)
    notes = [row["reason"]] if row.get("reason") else []
    if step > 1:
        row["ts"] = row["ts"] * step
        notes.append(f"values repeated on {step:.0f} rows (an export grid finer than the "
                     "stored data, or one tag alone: logged or computed slower): read "
                     f"one row in {step:.0f}, sample time {row['ts']:g} s")
    if spikes > 0:
        notes.append(f"{spikes:.0f} spike sample{'s' if spikes > 1 else ''} (far from both "
                     "neighbours) replaced by a line between them")
    placeholders = row["n_placeholders"]
    if placeholders > 0:
        notes.append(f"{placeholders:.0f} sample{'s' if placeholders > 1 else ''} holding a "
                     "placeholder for missing data (a value far outside the others', such as "
                     "-9999) read as gaps")
    stepped = row.get("stepped_tags", 0)
    if stepped > 0:
        notes.append(f"{'PV and OP' if stepped > 1 else 'one tag'} exported stepped (held "
                     "between the points a compressing historian stored): redrawn as lines "
                     "through those points")
    if np.isfinite(start) and (start > 0 or stop < n):
        notes.append(f"analysed rows {start + 1:.0f}-{stop:.0f} of {n:.0f}: the longest "
                     "stretch between gaps too long to bridge")
    row["reason"] = "; ".join(notes)


def _scan_group(files, channels, ts, max_gap, learned, rules, gate, chunk_size):
    """Read and scan one work unit of files; return their report rows in file order."""
    out = []
    pending, pending_rows = [], []  # readable loops waiting to fill a chunk, their meta rows

    def flush():
        if not pending:
            return
        meta = _meta(pending_rows)
        loops = pad_loops(pending)  # checked by _scan_safely, which isolates a loop that fails
        report = _scan_safely(
            loops, loop_types_of(meta, len(meta)), learned, rules, sampling_times(meta), gate
        )
        out.append(join_meta(meta, report))
        pending.clear()
        pending_rows.clear()

    for path, supported, reason in files:
        if not supported:
            flush()
            meta = pd.DataFrame(
                {
                    "file": [Path(path).name],
                    "path": [path],
                    "status": ["unsupported"],
                    "reason": [reason],
                }
            )
            out.append(join_meta(meta, _unreadable_rows(meta)))
            continue
        try:
            X, rows, readable = _read(path, channels, ts, max_gap)
        except Exception as exc:  # noqa: BLE001 - one odd file must not stop the scan
            flush()
            meta = pd.DataFrame(
                {
                    "file": [Path(path).name],
                    "path": [path],
                    "status": ["error"],
                    "reason": [f"{type(exc).__name__}: {exc}"],
                }
            )
            out.append(join_meta(meta, _unreadable_rows(meta)))
            continue
        if not readable.all():
            flush()  # keep file order: rows of unreadable loops go where the file is
            if readable.any():
                pending.append(X[readable])
                pending_rows.extend(r for r, ok in zip(rows, readable) if ok)
                flush()
            bad = _meta([r for r, ok in zip(rows, readable) if not ok])
            out.append(join_meta(bad, _unreadable_rows(bad)))
            continue
        pending.append(X)
        pending_rows.extend(rows)
        if sum(len(p) for p in pending) >= chunk_size:
            flush()
    flush()
    return pd.concat(out, ignore_index=True) if out else pd.DataFrame()


def _groups(files, chunk_size):
    rows = list(files[["path", "supported", "reason"]].itertuples(index=False, name=None))
    return [rows[s : s + chunk_size] for s in range(0, len(rows), chunk_size)]


def scan_files(
    paths,
    *,
    channels=None,
    classifier=None,
    chunk_size=64,
    n_jobs=None,
    client=None,
    progress=False,
    ts=None,
    max_gap="auto",
):
    """Scan every loop file under ``paths`` as a stream, memory bounded by the chunk.

    Files are listed (:func:`~sktiction.datasets.list_loop_files`), grouped into work
    units of ``chunk_size`` files, and each unit reads its own files one at a time
    (:func:`~sktiction.datasets.read_loop_file`), bridges short gaps
    (:func:`~sktiction._validation.repair_gaps`), scans its loops like
    :func:`scan_loops` and returns only report rows. The site is never held in memory:
    the scan's memory is that of one unit per worker.

    Parameters
    ----------
    paths : str, Path or iterable of them
        Files or folders (walked recursively).
    channels : dict or None, default=None
        Column names, e.g. ``{"pv": "FIC101.PV", "op": "FIC101.OP", "sp": "FIC101.SP"}``
        (see :func:`~sktiction.datasets.read_loop_file`).
    classifier : fitted classifier or None, default=None
        Learned classifier; ``None`` uses :func:`~sktiction.pretrained_classifier`.
    chunk_size : int, default=64
        Files per work unit, and loops per scanned chunk.
    n_jobs : int or None, default=None
        Parallel joblib workers over units (ignored with ``client``).
    client : dask.distributed.Client or None, default=None
        Run the units on this dask cluster (``pip install "sktiction[dask]"``); the
        workers read their own files, so the paths must be readable there. The
        report is the same as a local scan's.
    progress : bool, default=False
        Progress bar over files with rate and ETA on standard error (tqdm).
    ts : float or None, default=None
        Sampling time in seconds for files without a time column.
    max_gap : "auto", int or None, default="auto"
        Longest NaN gap bridged (:func:`~sktiction._validation.repair_gaps`), after a
        regular hold is read one row in k, spikes are replaced and placeholders (-9999
        for a stretch) read as gaps (:func:`~sktiction._cleaning.repaired`); ``None``
        repairs nothing (loops with
        gaps then get ``status = "nan_gap"``).

    Returns
    -------
    report : pandas.DataFrame
        One row per loop, in file order, reader's columns first (its ``status`` and
        ``reason`` as ``input_status``, ``input_reason``, which also says what was
        repaired; with repair also ``n_bridged``, ``n_gaps_split``, ``kept_start``,
        ``kept_stop`` (input rows), ``n_spikes``, ``rows_per_value``,
        ``n_placeholders`` and ``stepped_tags``, and ``ts`` is
        the sample time of the rows read), then the
        columns of :func:`scan_loops`. A file that cannot be read, or is not a loop
        file, gets one row with ``status = "unreadable"`` and the reader's reason.

    See Also
    --------
    scan_loops : the same scan on loops already in memory.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import pandas as pd
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.reports import scan_files
    >>> from sktiction import pretrained_classifier
    >>> folder = Path(tempfile.mkdtemp())
    >>> X, _ = make_loops(2, n_samples=1200, random_state=0)
    >>> for i in range(2):
    ...     pd.DataFrame({"t": range(1200), "PV": X[i, :, 0], "OP": X[i, :, 1]}).to_csv(
    ...         folder / f"FIC10{i}.csv", index=False)
    >>> _ = (folder / "notes.doc").write_text("not a loop")
    >>> clf = pretrained_classifier(n_loops=60, n_samples=1000)
    >>> scan_files(folder, classifier=clf)[["file", "status"]].to_dict("list")
    {'file': ['FIC100.csv', 'FIC101.csv', 'notes.doc'], 'status': ['ok', 'ok', 'unreadable']}
    """
    chunk_size = int(chunk_size)
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be an integer >= 1; got {chunk_size!r}.")
    files = list_loop_files(paths)
    if files.empty:
        raise ValueError(f"paths holds no files: {paths!r}.")
    learned = LearnedAdapter(classifier if classifier is not None else pretrained_classifier())
    rules = _Rules(check_loops(np.zeros((1, 30, 3))))
    gate = _applicability_gate()
    groups = _groups(files, chunk_size)
    units = [(g, channels, ts, max_gap) for g in groups]
    with progress_bar(len(files), progress, unit="file") as bar:
        parts = run_units(
            _scan_unit,
            units,
            (learned, rules, gate, chunk_size),
            n_jobs=n_jobs,
            client=client,
            bar=bar,
            sizes=[len(g) for g in groups],
        )
    return _in_column_order(pd.concat(parts, ignore_index=True))


def _in_column_order(report):
    """The report's columns in one order, whichever kind of file came first (an
    unreadable file's rows have fewer meta columns, and concat keeps first-seen order)."""
    meta = [f"input_{c}" if c in REPORT_COLUMNS else c for c in _META_COLUMNS]
    order = [c for c in (*meta, *GAP_COLUMNS, *REPORT_COLUMNS) if c in report]
    return report[order + [c for c in report if c not in order]]


def _scan_unit(files, channels, ts, max_gap, learned, rules, gate, chunk_size):
    return _scan_group(files, channels, ts, max_gap, learned, rules, gate, chunk_size)
