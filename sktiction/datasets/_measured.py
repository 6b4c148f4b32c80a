"""Read measured control loops (historian exports, CSV, Excel, Parquet) into loop arrays.

Three layers:

* :func:`list_loop_files` lists every file under some paths, readable or not, with a reason
  for each one that is not read.
* :func:`read_loop_file` reads one file into ``(n_loops_in_file, n_samples, 3)``: no more
  memory than that file needs, and never an exception for a bad file (a row with
  ``status != "ok"`` and a reason instead).
* :func:`read_loops` reads many files into one NaN-padded array (convenient for small sets;
  a scan of many or long files should call :func:`read_loop_file` per file).

File layouts are in :mod:`sktiction.datasets._readers`, time columns in
:mod:`sktiction.datasets._timestamps`, column names in :mod:`sktiction.datasets._columns`
and cell text in :mod:`sktiction.datasets._numbers`.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.utils import Bunch

from .._validation import CHANNELS, STATUS_OK, check_positive
from ._columns import _ALIASES, _accept, _is_time, _loop_of, _loop_type, _plan, _plans, channel_key
from ._long import long_columns, paired_table, pivot_long
from ._numbers import _channel_values, _mode, _numeric, _status_note
from ._readers import FileError, file_kind, open_tables
from ._timestamps import TIME_UNITS, TimeError, coarse_stamps, count, parse_times, regularise

__all__ = ["list_loop_files", "read_loop_file", "read_loops"]

STATUS_ERROR = "error"
STATUS_UNSUPPORTED = "unsupported"

_TIME_UNIT = re.compile(r"[\[(_ ](ms|min|h)[\])]?$")
_TIME_SCALE = {"ms": 1e-3, "min": 60.0, "h": 3600.0}
_META_COLUMNS = [
    "file", "path", "format", "tag", "isa", "loop_type", "ts", "n_samples", "n_nan",
    "auto_fraction", "start", "status", "reason",
]  # fmt: skip


class _Unsupported(FileError):
    """The file type is not read at all (as opposed to a readable type holding bad data)."""


# ---- listing -------------------------------------------------------------------------------


def list_loop_files(paths):
    """Every file under ``paths``, whether it will be read, and why not.

    Parameters
    ----------
    paths : str, Path or iterable of them
        Files or folders; folders are walked recursively (sub-folders included).

    Returns
    -------
    files : pandas.DataFrame
        One row per file, in path order within each folder: ``path`` (str),
        ``supported`` (bool), ``reason`` (empty when supported; else what to do, e.g.
        "old Excel format (.xls): save it as .xlsx or CSV"). A path that does not exist,
        and a folder holding no readable file, get a row of their own with
        ``supported=False``.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from sktiction.datasets import list_loop_files
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / "FIC101.csv").write_text("t,PV,OP\\n0,1,2\\n")
    >>> _ = (folder / "FIC102.dat").write_text("0 1 2\\n")
    >>> list_loop_files(folder)[["supported", "reason"]].to_dict("records")[1]["supported"]
    False
    """
    if isinstance(paths, str | os.PathLike):
        paths = [paths]
    rows = []
    for p in paths:
        p = Path(p)
        if p.is_dir():
            files = []
            for root, dirs, names in os.walk(p):
                dirs.sort()
                files.extend(Path(root) / n for n in sorted(names))
            found = [_file_row(f) for f in files]
            rows.extend(found)
            if not any(r["supported"] for r in found):
                what = f"{count(len(found), 'file')}, none readable" if found else "no files"
                reason = f"folder holds no readable loop file ({what})"
                rows.append({"path": str(p), "supported": False, "reason": reason})
        elif p.exists():
            rows.append(_file_row(p))
        else:
            what = "file" if p.suffix else "path"
            rows.append({"path": str(p), "supported": False, "reason": f"{what} does not exist"})
    return pd.DataFrame(rows, columns=["path", "supported", "reason"])


def _file_row(path):
    kind, reason = file_kind(path)
    return {"path": str(path), "supported": kind is not None, "reason": reason}


# ---- one file ------------------------------------------------------------------------------


def _check_args(ts, channels, time_unit):
    if ts is not None:
        ts = check_positive(ts, "ts")
    if channels is not None:
        if not isinstance(channels, dict) or set(channels) - set(_ALIASES):
            raise ValueError(
                f"channels must be a dict with keys among {sorted(_ALIASES)}; got {channels!r}."
            )
    if time_unit not in TIME_UNITS:
        raise ValueError(f"time_unit must be one of {TIME_UNITS}; got {time_unit!r}.")
    return ts


def _read_file(path, channels, ts, strict, time_unit, return_frames=False):
    """Read one file; return (X, rows, frames) or raise FileError / TimeError.

    A workbook may give several tables (a sheet per loop): their loops are stacked,
    NaN-padded at the end to the longest; a sheet that cannot be read is named in the
    reasons of the loops read (an error row of its own when no sheet could be read).
    """
    if path.is_dir():
        raise FileError("is a folder: read it with read_loops or list its files first")
    if not path.exists():
        raise FileError("file does not exist")
    kind, why = file_kind(path)
    if kind is None:
        raise _Unsupported(why)
    tables = open_tables(path, kind, accept=lambda names: _accept(names, channels))
    if len(tables) == 1:
        return _read_table(path, tables[0], channels, ts, strict, time_unit, return_frames)
    parts, failed = [], []  # the sheets read, the error rows of the others
    for table in tables:
        try:
            parts.append(_read_table(path, table, channels, ts, strict, time_unit,
                                     return_frames))  # fmt: skip
        except (FileError, TimeError) as exc:
            failed.append((table.info["sheet"], exc))
    if parts:
        # a sheet whose columns looked like a loop's but is not one (a tag list, a
        # snapshot) is no failure of the workbook: the loops read say it was left out
        left_out = [f"sheet {sheet!r} not read: {exc}" for sheet, exc in failed]
        for _, rows, _ in parts:
            for row in rows:
                row["reason"] = "; ".join(filter(None, [row["reason"], *left_out]))
    else:
        parts = [(np.full((1, 0, 3), np.nan), [{
            "format": "xlsx", "tag": str(sheet), "n_samples": 0, "status": STATUS_ERROR,
            "reason": f"sheet {sheet!r}: {exc}"}], [None]) for sheet, exc in failed]  # fmt: skip
    X = pad_loops([X for X, _, _ in parts])
    return X, [r for _, rows, _ in parts for r in rows], [f for *_, fr in parts for f in fr]


def _read_table(path, table, channels, ts, strict, time_unit, return_frames):
    """:func:`_read_file` of one table of ``path``."""
    long = None
    if not _plans(table.names, channels):
        long = long_columns(table.names, _is_time, channels)
        if long is None and not channels:
            paired = paired_table(table, _is_time)
            if paired is not None:
                table, long = paired, long_columns(paired.names, _is_time)
        if long is not None:
            decimal = "," if "decimal comma" in table.info["notes"] else "."

            def to_numbers(col, tag):
                if channel_key(tag) == "mode":
                    return _mode(col), []
                values, counts, note = _numeric(col, tag, decimal, strict,
                                                table.info.get("thousands"))  # fmt: skip
                return values, [note] * bool(note) + [_status_note(counts, tag)] * bool(counts)

            # the wide time column keeps its name where the wide readers know it (a unit
            # in it, "time [ms]", scales relative times), else it is "time"
            original = table.names[long["time"]]
            time_name = original if channel_key(original) == "time" else "time"
            table = pivot_long(table, long, to_numbers, loop_of=_loop_of, time_name=time_name,
                               ts=ts, time_unit=time_unit, strict=strict)  # fmt: skip
            if channels and "time" in channels:
                channels = {**channels, "time": time_name}
    info, names = table.info, table.names
    try:
        time_pos, loops, notes = _plan(names, channels)
    except FileError as exc:
        if long is None:
            raise
        raise FileError(f"long layout (a row per tag and time) pivoted to columns: {exc}") from exc
    positions = list(time_pos) + [p for _, g in loops for p in g.values()]
    frame = table.read(positions)
    notes = info["notes"] + notes
    n = len(frame)
    if n == 0:
        raise FileError("file has no data rows")
    decimal = "," if "decimal comma" in info["notes"] else "."
    values, loop_notes = _channel_values(frame, loops, names, decimal, strict,
                                         info.get("thousands"), info["format"])  # fmt: skip
    start, step = pd.NaT, None
    if time_pos:
        raw = frame[time_pos[0]]
        if len(time_pos) == 2:
            raw = raw.astype(str).str.strip() + " " + frame[time_pos[1]].astype(str).str.strip()
    del frame  # the channels are in ``values`` now; keep memory to one copy of the file
    if time_pos:
        label = " + ".join(names[i] for i in time_pos)
        if len(time_pos) == 2:
            notes.append(f"time from columns {label}")
        if strict and raw.isna().any():
            raise FileError(f"time column {label!r} has {int(raw.isna().sum())} empty values")
        t, start, time_notes = parse_times(raw, time_format=info["time_format"], unit=time_unit)
        unit = _TIME_UNIT.search(label.lower())
        if unit and pd.isna(start) and time_unit == "auto" and not time_notes:
            # Relative numeric times whose column name gives the unit: "time [ms]", "t_min".
            t = t * _TIME_SCALE[unit.group(1)]
            time_notes = [f"time in {unit.group(1)} (from the column name)"]
        notes += time_notes
        ok = ~np.isnan(t)
        if not ok.all():
            notes.append(f"{count(int((~ok).sum()), 'row')} without a readable time skipped")
            t, values, raw = t[ok], values[ok], raw[ok]
        coarse = coarse_stamps(t, values, ts=ts, strict=strict)
        if coarse is not None:
            t, note = coarse
            if pd.notna(start):
                start += pd.Timedelta(seconds=float(t[0]))
            t = t - t[0]
            notes.append(note)
        if strict:
            _strict_order(t, raw)
        hold = [4 * j + 3 for j in range(len(loops))]
        t, values, step, time_notes = regularise(t, values, hold=hold, strict=strict)
        notes += time_notes
        if len(t) and t[0] > 0 and pd.notna(start):  # a later stretch was kept
            start += pd.Timedelta(seconds=float(t[0]))
    if ts is not None:
        if step is not None and abs(step - ts) > 0.01 * ts:
            notes.append(f"ts={ts:g} given, timestamps say {step:g} s")
        step = ts
    if step is None:
        if n == 1:
            raise FileError("only one row of data")
        raise FileError("cannot determine the sampling time (no time column); pass ts=")
    if info["declared_rows"] is not None and info["declared_rows"] != n:
        notes.append(f"header declares {info['declared_rows']} rows, file has {n}")
    m = len(values)
    X = np.empty((len(loops), m, 3))
    for j in range(len(loops)):
        X[j] = values[:, 4 * j : 4 * j + 3]
    modes = values[:, 3::4].copy() if any("mode" in g for _, g in loops) else None
    del values
    rows, frames = [], []
    for j, (prefix, g) in enumerate(loops):
        # one loop without a tag prefix: the file's tag, else its sheet's name when the
        # workbook has several, else the file's name
        own = info["tag"] or info.get("sheet")
        tag = prefix or (own if len(loops) == 1 and own else path.stem)
        if info["format"] == "historian" and len(loops) == 1 and info["tag"]:
            tag = info["tag"]
        reason = notes + loop_notes[j]
        if "op" not in g:
            reason.append("no OP column")
        pv, op = X[j, :, 0], X[j, :, 1]
        if "op" in g and _fraction(op):
            reason.append("OP stays within 0-1 (a fraction of travel?): stiction sizes are in "
                          "OP's units, not %")  # fmt: skip
        status = STATUS_OK
        if np.isnan(pv).all():
            status = STATUS_ERROR
            reason.insert(0, f"PV column {names[g['pv']]!r} holds no numbers")
            X[j] = np.nan  # a loop in error carries no data, as in read_loops(on_error="skip")
        missing = np.isnan(pv) | (np.isnan(op) if "op" in g else False)
        isa, loop_type = _loop_type(tag)
        mode = modes[:, j] if modes is not None else np.full(m, np.nan)
        # MODE 0 / MAN: the controller was not closing the loop. Only where the column is
        # 0/1 (or text): other numeric codes are the DCS's own, and 0 may mean anything
        codes = np.unique(mode[np.isfinite(mode)])
        manual = (mode == 0) if np.isin(codes, (0.0, 1.0)).all() else np.zeros(m, bool)
        manual &= status == STATUS_OK
        if manual.any():
            reason.append(f"{count(int(manual.sum()), 'row')} in manual mode (MODE 0): a scan "
                          "reads them as gaps")  # fmt: skip
        rows.append({
            "format": info["format"], "tag": tag, "isa": isa, "loop_type": loop_type,
            "ts": step, "n_samples": m, "n_nan": int(missing.sum()),
            "auto_fraction": float(np.mean(mode == 1)) if "mode" in g else np.nan,
            "start": start, "status": status, "reason": "; ".join(reason),
            "manual_rows": manual,  # not a meta column: for the scan (see manual_gaps)
        })  # fmt: skip
        if return_frames:
            frames.append(
                pd.DataFrame({
                    "time": t if time_pos else np.arange(m) * step, "pv": pv, "op": op,
                    "sp": X[j, :, 2], "mode": mode,
                })
            )  # fmt: skip
    return X, rows, frames


def pad_loops(arrays, min_samples=0):
    """Loop arrays ``(n_i, m_i, 3)`` stacked into one, NaN-padded at the end to the
    longest (at least ``min_samples`` samples)."""
    m = max([min_samples] + [a.shape[1] for a in arrays])
    out = np.full((sum(len(a) for a in arrays), m, 3), np.nan)
    k = 0
    for a in arrays:
        out[k : k + len(a), : a.shape[1]] = a
        k += len(a)
    return out


def _fraction(op):
    """Whether OP moves and stays within [0, 1]: a valve position written as a fraction."""
    op = op[np.isfinite(op)]
    return op.size > 1 and op.min() >= 0 and op.max() <= 1 and op.max() > op.min()


def manual_gaps(X, rows):
    """``X`` with the rows :func:`read_loop_rows` found in manual mode as NaN gaps: no
    closed loop to diagnose there. A scan does this; :func:`read_loop_file` keeps the
    file's values (``meta["auto_fraction"]`` and ``reason`` tell)."""
    manual = [r.get("manual_rows") for r in rows]
    if not any(m is not None and m.any() for m in manual):
        return X
    X = X.copy()
    for j, m in enumerate(manual):
        if m is not None and m.any():
            X[j, m] = np.nan
    return X


def _strict_order(t, raw):
    """Today's strict behaviour: unsorted or duplicated timestamps are errors."""
    dt = np.diff(t)
    if len(dt) and (dt <= 0).any():
        i = int(np.flatnonzero(dt <= 0)[0])
        what = "duplicated" if dt[i] == 0 else "not increasing (unsorted)"
        a, b = (repr(v) if isinstance(v, str) else str(v) for v in raw.iloc[i : i + 2])
        raise FileError(f"timestamps are {what} at data row {i + 2} ({a} then {b})")


def _meta_frame(rows):
    """Meta table from row dicts, with fixed columns and dtypes (built in Python: fast)."""

    def value(row, key, default):
        v = row.get(key, default)
        return default if v is None or (isinstance(v, float) and np.isnan(v)) else v

    table = {col: [] for col in _META_COLUMNS}
    for row in rows:
        ok = row.get("status") == STATUS_OK
        for col in ("file", "path", "format", "tag", "isa", "status", "reason"):
            table[col].append(str(value(row, col, "")))
        table["loop_type"].append(value(row, "loop_type", "unknown") if ok else "unknown")
        for col in ("ts", "auto_fraction"):
            table[col].append(float(value(row, col, np.nan)))
        for col in ("n_samples", "n_nan"):
            table[col].append(int(value(row, col, 0)))
        table["start"].append(row.get("start", pd.NaT))
    meta = pd.DataFrame(table)
    meta["start"] = pd.to_datetime(meta["start"])
    return meta


def read_loop_file(
    path, *, channels=None, ts=None, strict=False, time_unit="auto", return_frames=False
):
    """Read the loops of one file (historian export, CSV, Excel or Parquet).

    Memory is that of this file alone: no padding to other files' lengths. Problems with
    the file never raise: they give ``status != "ok"`` and a reason.

    Parameters
    ----------
    path : str or Path
        One file. Historian exports (first line ``PROCESSDATA``, columns
        ``<tag>.MV/.PV/.SV/.MODE``), delimited text with a header row (``,``, ``;``, tab or
        ``|``; decimal comma; comment or title lines before the header; UTF-8, UTF-16,
        GB18030 or latin-1), ``.xlsx`` (needs openpyxl; every sheet with loop columns,
        a sheet without a tag prefix named after its sheet) and ``.parquet`` (needs
        pyarrow).
        Long tables (a tag, a time and a value column, optionally a parameter such as
        ``PV`` beside the tag and a quality column; English, German, French, Spanish or
        Dutch names such as ``Name, Zeit, Wert``) are pivoted to one column per tag
        (``tag`` or ``tag.parameter``); tags recorded at their own times hold their last
        record on a grid at the scan period their records fall on (or ``ts``).
    channels : dict or None, default=None
        Column names to use instead of the automatic match, keyed by ``"pv"``, ``"op"``,
        ``"sp"``, ``"time"``, ``"mode"``, e.g. ``{"pv": "FIC101.PV", "op": "FIC101.OP"}``;
        the file then gives one loop. Automatic matching compares names
        case-insensitively, also after a ``<tag>.``, ``<tag>_``, ``<tag> ``, ``<tag>:`` or
        ``<tag>/`` prefix (a field ``.CV`` or ``.Value`` after a channel is dropped:
        ``LIC1/PID1/OUT.CV`` is the OP of ``LIC1/PID1``): PV from PV/Y/CV, OP from
        OP/MV/OUT/CO, SP from SP/SV/SPT/SETPOINT, time from
        TIME/T/T_S/TIMESTAMP/DATETIME/DATE or German ZEIT/ZEITSTEMPEL/DATUM/UHRZEIT (a
        DATE or DATUM and a TIME or UHRZEIT column are joined), mode from MODE. A unit in
        brackets ending a name is ignored (``FIC1.PV [m3/h]``), and so is a bare one
        (``OP %``, ``PV degC``; ``Set Point`` is SETPOINT), except that relative times
        named in ``[ms]``, ``[min]``, ``[h]`` (or ``_ms``, ``_min``, ``_h``) are scaled to
        seconds. Several prefixes with a PV each give one loop per
        prefix; untagged columns beside a single tagged loop belong to it.
    ts : float or None, default=None
        Sampling time in seconds. Needed for files without a time column; when given it
        overrides the timestamps (a disagreement is noted in the reason); for a long
        table of tags recorded at their own times it is the grid step.
    strict : bool, default=False
        Reject instead of repair: text values in a channel (historian status such as
        ``Bad``, ``I/O Timeout``, ``#VALUE!``), empty times, unsorted or duplicated
        timestamps make the file an error, and irregular sampling is only reported.
    time_unit : {"auto", "s", "epoch_s", "epoch_ms", "epoch_us", "epoch_ns", "excel"}, \
default="auto"
        Unit of a numeric time column. ``"auto"`` tells epoch seconds/milliseconds/...
        and Excel serial days from their range (between 1990 and 2100) and names the
        unit it chose in the reason; anything else is seconds.
    return_frames : bool, default=False
        Also return each loop's table (``time`` in seconds from the start, ``pv``,
        ``op``, ``sp``, ``mode``).

    Returns
    -------
    data : sklearn.utils.Bunch
        ``X`` : ndarray of shape (n_loops_in_file, n_samples, 3)
            Channels PV, OP, SP on a regular time grid; absent channels all-NaN, NaN
            where a value was missing or status text. ``X.shape[0] == len(meta)`` always
            (``(1, 0, 3)`` for a file that could not be read).
        ``meta`` : pandas.DataFrame, one row per loop
            ``file``, ``path``, ``format`` (historian/csv/xlsx/parquet), ``tag`` (from the
            header or column prefix, else the file stem), ``isa``, ``loop_type`` (flow,
            level, pressure, temperature or unknown, from the ISA letters of the tag),
            ``ts`` (s), ``n_samples``, ``n_nan`` (rows with PV, or OP when present,
            missing), ``auto_fraction`` (share of rows with MODE == 1, NaN without MODE;
            manual rows, MAN or 0 in a column of 0/1, are counted in ``reason`` and kept in
            ``X``; :func:`~sktiction.reports.scan_files` reads them as gaps),
            ``start`` (first timestamp or NaT), ``status`` (``ok``, ``error`` or
            ``unsupported``), ``reason`` (the error, or notes separated by ``"; "``: rows
            sorted, duplicated timestamps kept the first, resampled to the median step,
            n text values read as NaN, n blank rows skipped, time unit, encoding, ...).
        ``frames`` : list of DataFrame or None, only with ``return_frames=True``.

    Raises
    ------
    ValueError
        Only for bad arguments (``ts``, ``channels``, ``time_unit``).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from sktiction.datasets import read_loop_file
    >>> f = Path(tempfile.mkdtemp()) / "unit3.csv"
    >>> _ = f.write_text("time;FIC1.PV;FIC1.OP;LIC2.PV;LIC2.OP\\n"
    ...                  "0;1,5;40;7;20\\n10;Bad;41;7,5;21\\n20;1,7;42;8;22\\n")
    >>> data = read_loop_file(f)
    >>> data.X.shape
    (2, 3, 3)
    >>> data.X[0, :, 0].tolist()
    [1.5, nan, 1.7]
    >>> data.meta[["tag", "loop_type", "ts", "status"]].to_dict("records")[0]
    {'tag': 'FIC1', 'loop_type': 'flow', 'ts': 10.0, 'status': 'ok'}
    >>> data.meta.loc[0, "reason"]
    "decimal comma; 1 text value in PV read as NaN ('Bad' x1)"
    """
    X, rows, frames = read_loop_rows(path, channels, ts, strict, time_unit, return_frames)
    data = Bunch(X=X, meta=_meta_frame(rows), channels=CHANNELS)
    if return_frames:
        data["frames"] = frames
    return data


def read_loop_rows(path, channels=None, ts=None, strict=False, time_unit="auto",
                   return_frames=False):  # fmt: skip
    """:func:`read_loop_file` with its meta as row dicts: ``(X, rows, frames)``.

    For a scan that builds one meta table per chunk of files instead of one per file
    (a one-row DataFrame cost a third of reading a file). ``rows`` go to
    :func:`_meta_frame` as they are; a file that cannot be read gets one row with its
    status and reason, never an exception (bad arguments still raise).
    """
    ts = _check_args(ts, channels, time_unit)
    path = Path(path)
    base = {"file": path.name, "path": str(path)}
    try:
        X, rows, frames = _read_file(path, channels, ts, strict, time_unit, return_frames)
    except (FileError, TimeError, OSError) as exc:
        status = STATUS_UNSUPPORTED if isinstance(exc, _Unsupported) else STATUS_ERROR
        message = str(exc) if not isinstance(exc, OSError) else f"cannot open: {exc.strerror}"
        X, frames = np.full((1, 0, 3), np.nan), [None]
        rows = [{"n_samples": 0, "status": status, "reason": message}]
    except Exception as exc:  # noqa: BLE001 - one odd file must not stop a scan of thousands
        X, frames = np.full((1, 0, 3), np.nan), [None]
        reason = f"could not be read ({type(exc).__name__}: {exc}); please report this file"
        rows = [{"n_samples": 0, "status": STATUS_ERROR, "reason": reason}]
    return X, [{**base, **r} for r in rows], frames


# ---- many files ----------------------------------------------------------------------------


def read_loops(
    paths, *, ts=None, channels=None, on_error="raise", return_frames=False, strict=False,
    time_unit="auto",
):  # fmt: skip
    """Read measured control loops from historian exports, CSV, Excel or Parquet files.

    Built on :func:`list_loop_files` and :func:`read_loop_file` (see it for layouts,
    column matching and repairs); all loops are padded to the longest, so for many or
    long files call :func:`read_loop_file` per file instead.

    Parameters
    ----------
    paths : str, Path or iterable of them
        Files, or folders whose readable files (``.txt``, ``.csv``, ``.tsv``, ``.xlsx``,
        ``.parquet``) are all read, sub-folders included, in path order.
        ``index.csv`` / ``index.txt`` describe a folder and are not read. Files of other
        types inside a folder are listed in ``skipped``; a file named directly must be
        readable.
    ts : float or None, default=None
        Sampling time in seconds (see :func:`read_loop_file`).
    channels : dict or None, default=None
        Column names keyed by ``"pv"``, ``"op"``, ``"sp"``, ``"time"``, ``"mode"``
        (see :func:`read_loop_file`).
    on_error : {"raise", "skip"}, default="raise"
        ``"raise"``: a bad file raises ``ValueError`` naming the file and the problem.
        ``"skip"``: the file gets ``status="error"`` (or ``"unsupported"``) and the
        message in ``meta.reason`` and an all-NaN row in ``X``; it is never dropped
        silently.
    return_frames : bool, default=False
        Also return each loop's table.
    strict : bool, default=False
        Reject text values, unsorted or duplicated timestamps instead of repairing
        them (see :func:`read_loop_file`).
    time_unit : str, default="auto"
        Unit of numeric time columns (see :func:`read_loop_file`).

    Returns
    -------
    data : sklearn.utils.Bunch
        ``X`` : ndarray of shape (n_loops, max_len, 3)
            Channels PV, OP, SP, NaN-padded at the end; one row per loop (a wide file
            gives several).
        ``meta`` : pandas.DataFrame, one row per loop
            As in :func:`read_loop_file`.
        ``skipped`` : pandas.DataFrame
            Files inside the folders that were not read, with ``path`` and ``reason``.
        ``channels`` : tuple
            ``("pv", "op", "sp")``.
        ``frames`` : list of DataFrame or None, only with ``return_frames=True``.

    Raises
    ------
    ValueError
        For a bad argument, a path that does not exist, a folder with nothing to read, or
        (with ``on_error="raise"``) a file that cannot be read. The message names the file.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from sktiction.datasets import read_loops
    >>> folder = Path(tempfile.mkdtemp())
    >>> text = "t_s,OP,PV\\n0,40.0,50.1\\n10,41.0,50.3\\n20,42.0,50.2\\n"
    >>> _ = (folder / "FIC101.csv").write_text(text)
    >>> data = read_loops(folder)
    >>> data.X.shape
    (1, 3, 3)
    >>> data.X[0, :, 0].tolist()  # PV
    [50.1, 50.3, 50.2]
    >>> data.meta[["tag", "loop_type", "ts", "status"]].to_dict("records")
    [{'tag': 'FIC101', 'loop_type': 'flow', 'ts': 10.0, 'status': 'ok'}]
    """
    if on_error not in ("raise", "skip"):
        raise ValueError(f"on_error must be 'raise' or 'skip'; got {on_error!r}.")
    ts = _check_args(ts, channels, time_unit)
    if isinstance(paths, str | os.PathLike):
        paths = [paths]
    items, skipped = [], []  # items: (path, None) to read or (path, reason) unreadable
    for p in paths:
        in_folder = Path(p).is_dir()
        for row in list_loop_files(p).itertuples(index=False):
            if row.supported:
                items.append((Path(row.path), None))
            elif in_folder and Path(row.path) != Path(p):
                skipped.append({"path": row.path, "reason": row.reason})
            else:
                items.append((Path(row.path), row.reason))
    if not items:
        raise ValueError(f"paths holds no files to read: {paths!r}.")
    for path, reason in items:
        if on_error == "raise" and reason is not None:
            raise ValueError(f"{path.name}: {reason}.")
    parts, rows, frames = [], [], []
    for path, reason in items:
        if reason is not None:
            status = STATUS_ERROR if "exist" in reason else STATUS_UNSUPPORTED
            rows.append({"file": path.name, "path": str(path), "n_samples": 0,
                         "status": status, "reason": reason})  # fmt: skip
            parts.append(np.full((1, 0, 3), np.nan))
            frames.append(None)
            continue
        data = read_loop_file(
            path, channels=channels, ts=ts, strict=strict, time_unit=time_unit,
            return_frames=return_frames,
        )  # fmt: skip
        bad = data.meta["status"] != STATUS_OK
        if on_error == "raise" and bad.any():
            raise ValueError(f"{path.name}: {data.meta.loc[bad.idxmax(), 'reason']}.")
        parts.append(data.X)
        rows.extend(data.meta.to_dict("records"))
        if return_frames:
            frames.extend(data.frames)
    X = pad_loops(parts, min_samples=1)
    meta = _meta_frame(rows)
    skipped = pd.DataFrame(skipped, columns=["path", "reason"])
    data = Bunch(X=X, meta=meta, skipped=skipped, channels=CHANNELS)
    if return_frames:
        data["frames"] = frames
    return data
