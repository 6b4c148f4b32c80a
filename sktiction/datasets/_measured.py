"""Read measured control loops (historian exports and plain CSV files) into loop arrays.

Two layouts are recognised from the first line of a file:

* **historian export** (first line starts with ``PROCESSDATA``): five header lines, then
  tab-separated rows ``timestamp, <tag>.MV, <tag>.PV, <tag>.SV, <tag>.MODE, flags...``.
  Line 1 holds the time format, line 2 the start time and the declared row count, line 3
  the column names, line 4 descriptions (UTF-8, GBK tolerated), line 5 grid settings.
* **delimited text** (anything else): one header row of column names, then rows separated
  by ``,``, ``;`` or tabs (whichever the header line uses most).

Columns are found by name, case-insensitively, also after a ``<tag>.`` or ``<tag>_`` prefix.
"""

from __future__ import annotations

import codecs
import re
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.utils import Bunch

from .._validation import CHANNELS, check_positive

__all__ = ["read_loops"]

# Column-name aliases, compared lower-case. Order within a tuple does not matter.
_ALIASES = {
    "pv": ("pv", "y", "cv", "meas", "measurement", "process_variable"),
    "op": ("op", "mv", "out", "co", "output", "controller_output", "u"),
    "sp": ("sp", "sv", "setpoint", "set_point", "r", "ref"),
    "time": ("time", "t", "t_s", "time_s", "timestamp", "datetime", "date_time", "date"),
    "mode": ("mode", "aut", "auto"),
}
_FILE_SUFFIXES = (".txt", ".csv", ".tsv")
_INDEX_NAMES = ("index.csv", "index.txt")
# ISA controller letters inside a tag: first letter = measured variable, then optional
# D (differential), I/R (indicating/recording), C (controller), not glued to other letters.
_ISA = re.compile(r"(?<![A-Z])(PD|[FLPT])(IR|I|R)?C(?![A-Z])")
_LOOP_TYPES = {"F": "flow", "L": "level", "P": "pressure", "PD": "pressure", "T": "temperature"}
_META_COLUMNS = [
    "file", "path", "format", "tag", "isa", "loop_type", "ts", "n_samples", "n_nan",
    "auto_fraction", "start", "status", "reason",
]  # fmt: skip


class _FileError(ValueError):
    """A problem with one file; the message is prefixed with the file name by the caller."""


def _loop_type(tag):
    """ISA letters found in ``tag`` (e.g. ``'FIC'``) and the loop type they imply."""
    m = _ISA.search(str(tag).upper())
    if m is None:
        return "", "unknown"
    return m.group(0), _LOOP_TYPES[m.group(1)]


def _expand_paths(paths):
    """List of files from one path, a directory or an iterable of paths."""
    if isinstance(paths, str | Path):
        paths = [paths]
    out = []
    for p in paths:
        p = Path(p)
        if p.is_dir():
            # index.csv files describe a folder (labels); they are not loops.
            out.extend(
                f
                for f in sorted(p.iterdir())
                if f.is_file()
                and f.suffix.lower() in _FILE_SUFFIXES
                and f.name.lower() not in _INDEX_NAMES
            )
        else:
            out.append(p)
    if not out:
        raise ValueError(f"paths holds no files to read: {paths!r}.")
    return out


def _decode(raw):
    """Decode the first bytes of a file; return (text, encoding).

    UTF-8 first, then GB18030 (a superset of GBK, for Chinese descriptions), then latin-1.
    An incremental decoder tolerates a character cut in two by the read size.
    """
    for enc in ("utf-8-sig", "gb18030"):
        try:
            return codecs.getincrementaldecoder(enc)().decode(raw, final=False), enc
        except UnicodeDecodeError:
            continue
    return raw.decode("latin-1"), "latin-1"


def _time_format(java_format):
    """Translate a Java-style date pattern (``yyyy-MM-dd HH:mm:ss``) to strftime."""
    fmt = java_format
    for a, b in (("yyyy", "%Y"), ("MM", "%m"), ("dd", "%d"), ("HH", "%H"), ("mm", "%M")):
        fmt = fmt.replace(a, b)
    fmt = fmt.replace("ss", "%S").replace(".SSS", ".%f")
    return fmt if "%" in fmt else None


def _match_columns(columns, channels):
    """Map channel -> column name, from ``channels`` overrides and the alias table."""
    mapping = {}
    channels = dict(channels or {})
    for key, col in channels.items():
        if col not in columns:
            raise _FileError(f"column {col!r} given in channels[{key!r}] is not in {columns}")
        mapping[key] = col
    for key, aliases in _ALIASES.items():
        if key in mapping:
            continue
        # Full name first, then the part after a '<tag>.' or '<tag>_' prefix.
        for strip in (lambda c: c, lambda c: c.rsplit(".", 1)[-1], lambda c: c.rsplit("_", 1)[-1]):
            hits = [c for c in columns if strip(str(c).strip().lower()) in aliases]
            hits = [c for c in hits if c not in mapping.values()]
            if len(hits) > 1:
                raise _FileError(
                    f"several columns could be {key.upper()}: {hits}; choose one with "
                    f"channels={{{key!r}: ...}}"
                )
            if hits:
                mapping[key] = hits[0]
                break
    return mapping


def _read_historian(path, head, encoding):
    """Parse a ``PROCESSDATA`` historian export; return (frame, info)."""
    lines = head.splitlines()
    if len(lines) < 5:
        raise _FileError("historian header is incomplete (fewer than 5 lines)")
    first = lines[0].split("\t")
    names = [c.strip() for c in lines[2].split("\t")]
    if names[0].lower() != "tagname" or len(names) < 3:
        raise _FileError(f"line 3 should start with 'tagname' and list columns; got {lines[2]!r}")
    names[0] = "time"
    # Line 1 names the loop ("<tag> Data"); line 3 may add a unit prefix ("LYCDU.<tag>.MV").
    if len(first) > 1 and first[1].strip():
        tag = first[1].strip().removesuffix(" Data").strip()
    else:
        tag = names[1].rsplit(".", 1)[0]
    info = {"tag": tag, "format": "historian", "time_format": None, "declared_rows": None}
    if len(first) > 2:
        info["time_format"] = _time_format(first[2].strip())
    second = lines[1].split("\t")
    if len(second) >= 4 and second[3].strip().isdigit():
        info["declared_rows"] = int(second[3])
    frame = pd.read_csv(
        path, sep="\t", skiprows=5, header=None, names=names, index_col=False,
        dtype=str, encoding=encoding, encoding_errors="replace", skip_blank_lines=True,
    )  # fmt: skip
    return frame, info


def _read_delimited(path, head, encoding):
    """Parse a delimited text file with a header row; return (frame, info)."""
    header = head.splitlines()[0]
    sep = max((",", ";", "\t"), key=header.count)
    frame = pd.read_csv(
        path, sep=sep, dtype=str, encoding=encoding, encoding_errors="replace", index_col=False
    )
    frame.columns = [str(c).strip() for c in frame.columns]
    if all(_is_number(c) for c in frame.columns):
        raise _FileError("first line has no column names (it holds numbers)")
    return frame, {"tag": path.stem, "format": "csv", "time_format": None, "declared_rows": None}


def _is_number(text):
    try:
        float(text)
    except ValueError:
        return False
    return True


def _to_numeric(frame, col):
    """Column as float; NaN for blanks and standard NA tokens, error for other text."""
    values = pd.to_numeric(frame[col], errors="coerce")
    raw = frame[col]
    bad = (
        values.isna() & raw.notna() & ~raw.str.strip().str.lower().isin(["", "nan", "na", "null"])
    )
    if bad.any():
        i = int(np.flatnonzero(bad.to_numpy())[0])
        raise _FileError(
            f"column {col!r} is not numeric: row {i + 1} of the data holds {raw.iloc[i]!r} "
            f"({int(bad.sum())} such values)"
        )
    return values.to_numpy(dtype=float)


def _seconds(frame, col, time_format):
    """Time column as seconds from the first row, plus the start timestamp (or NaT)."""
    raw = frame[col]
    if raw.isna().any():
        raise _FileError(f"time column {col!r} has {int(raw.isna().sum())} empty values")
    numeric = pd.to_numeric(raw, errors="coerce")
    if numeric.notna().all():
        return numeric.to_numpy(dtype=float), pd.NaT
    # The header's format first, then ISO 8601 (fast), then per-value parsing (slow).
    stamps = None
    for fmt in (time_format, "ISO8601", "mixed"):
        if fmt is None:
            continue
        try:
            stamps = pd.to_datetime(raw.str.strip(), format=fmt)
            break
        except (ValueError, TypeError) as exc:
            error = exc
    if stamps is None:
        raise _FileError(f"time column {col!r} holds values that are not times: {error}")
    t = (stamps - stamps.iloc[0]).dt.total_seconds().to_numpy()
    return t, stamps.iloc[0]


def _read_one(path, ts, channels):
    """Read one file into a standard frame (time, pv, op, sp, mode, ...) and a meta dict."""
    if not path.is_file():
        raise _FileError("file does not exist")
    with open(path, "rb") as fh:
        raw = fh.read(8192)
    if not raw.strip():
        raise _FileError("file is empty")
    head, encoding = _decode(raw)
    try:
        if head.lstrip("\ufeff").startswith("PROCESSDATA"):
            frame, info = _read_historian(path, head, encoding)
        else:
            frame, info = _read_delimited(path, head, encoding)
    except pd.errors.EmptyDataError as exc:
        raise _FileError("file has no data rows") from exc
    except pd.errors.ParserError as exc:
        raise _FileError(f"rows could not be parsed ({exc})") from exc
    frame = frame.dropna(how="all")
    if len(frame) == 0:
        raise _FileError("file has no data rows")
    cols = list(frame.columns)
    mapping = _match_columns(cols, channels)
    if "pv" not in mapping:
        raise _FileError(f"no PV column (looked for {'/'.join(_ALIASES['pv'])} in {cols})")
    reasons = []
    out = {
        key: _to_numeric(frame, mapping[key])
        for key in ("pv", "op", "sp", "mode")
        if key in mapping
    }
    if "op" not in mapping:
        reasons.append("no OP column")
    start = pd.NaT
    file_ts = None
    if "time" in mapping:
        t, start = _seconds(frame, mapping["time"], info["time_format"])
        dt = np.diff(t)
        if len(dt) and (dt <= 0).any():
            i = int(np.flatnonzero(dt <= 0)[0])
            what = "duplicated" if dt[i] == 0 else "not increasing (unsorted)"
            raise _FileError(
                f"timestamps are {what} at data row {i + 2} ({frame[mapping['time']].iloc[i]!r} "
                f"then {frame[mapping['time']].iloc[i + 1]!r})"
            )
        if len(dt):
            file_ts = float(np.median(dt))
            # Gaps and jitter are reported, not repaired: resampling would invent data.
            off = np.abs(dt - file_ts) > 0.01 * file_ts
            if off.any():
                reasons.append(
                    f"irregular sampling: {int(off.sum())} intervals differ from {file_ts:g} s "
                    f"(min {dt.min():g}, max {dt.max():g})"
                )
        out["time"] = t
    if ts is not None:
        if file_ts is not None and abs(file_ts - ts) > 0.01 * ts:
            reasons.append(f"ts={ts:g} given, timestamps say {file_ts:g} s")
        file_ts = ts
    if file_ts is None:
        raise _FileError("cannot determine the sampling time (no time column); pass ts=")
    if info["declared_rows"] is not None and info["declared_rows"] != len(frame):
        reasons.append(f"header declares {info['declared_rows']} rows, file has {len(frame)}")
    n = len(frame)
    std = pd.DataFrame({"time": out.pop("time", np.arange(n) * file_ts)})
    for key in ("pv", "op", "sp", "mode"):
        std[key] = out.get(key, np.full(n, np.nan))
    used = {mapping[k] for k in mapping}
    for c in cols:
        if c not in used:
            std[c] = frame[c].to_numpy()
    isa, loop_type = _loop_type(info["tag"])
    mode = std["mode"].to_numpy()
    meta = {
        "format": info["format"],
        "tag": info["tag"],
        "isa": isa,
        "loop_type": loop_type,
        "ts": file_ts,
        "n_samples": n,
        "n_nan": int(np.isnan(std[["pv", "op"]].to_numpy()).any(axis=1).sum()),
        "auto_fraction": float(np.mean(mode == 1)) if "mode" in mapping else np.nan,
        "start": start,
        "status": "ok",
        "reason": "; ".join(reasons),
    }
    return std, meta


def read_loops(paths, *, ts=None, channels=None, on_error="raise", return_frames=False):
    """Read measured control loops from historian exports or CSV files.

    Parameters
    ----------
    paths : str, Path or iterable of them
        Files, or directories whose ``.txt``, ``.csv`` and ``.tsv`` files are all read in
        name order (``index.csv`` / ``index.txt`` are skipped: they describe a folder).
        Each file is one loop. The layout is detected from the first line: a historian
        export starting with ``PROCESSDATA`` (columns ``<tag>.MV/.PV/.SV/.MODE``), or
        delimited text with a header row (``,``, ``;`` or tab).
    ts : float or None, default=None
        Sampling time in seconds. Needed for files without a time column; when given it
        overrides the timestamps (a disagreement is noted in ``meta.reason``).
    channels : dict or None, default=None
        Column names to use instead of the automatic match, keyed by ``"pv"``, ``"op"``,
        ``"sp"``, ``"time"``, ``"mode"``. Automatic matching compares names
        case-insensitively, also after a ``<tag>.`` or ``<tag>_`` prefix: PV from
        PV/Y/CV, OP from OP/MV/OUT/CO, SP from SP/SV/SETPOINT, time from
        TIME/T/T_S/TIMESTAMP/DATETIME, mode from MODE. Numeric times are seconds;
        text times are parsed as dates.
    on_error : {"raise", "skip"}, default="raise"
        ``"raise"``: a bad file raises ``ValueError`` naming the file and the problem.
        ``"skip"``: the file gets ``status="error"`` and the message in ``meta.reason``
        and an all-NaN row in ``X``; it is never dropped silently.
    return_frames : bool, default=False
        Also return each file's parsed table.

    Returns
    -------
    data : sklearn.utils.Bunch
        ``X`` : ndarray of shape (n_files, max_len, 3)
            Channels PV, OP, SP, NaN-padded at the end; SP (or OP) all-NaN when the file
            has none. NaN gaps inside a record are kept.
        ``meta`` : pandas.DataFrame, one row per file
            ``file``, ``path``, ``format`` (``historian``/``csv``), ``tag`` (from the
            header, else the file stem), ``isa`` (controller letters found in the tag,
            e.g. ``FIC``), ``loop_type`` (``flow``, ``level``, ``pressure``,
            ``temperature`` or ``unknown``), ``ts`` (s), ``n_samples``, ``n_nan`` (rows
            with PV or OP missing), ``auto_fraction`` (share of rows with MODE == 1, NaN
            without MODE), ``start`` (first timestamp or NaT), ``status`` (``ok`` or
            ``error``), ``reason`` (error message or notes such as irregular sampling).
        ``channels`` : tuple
            ``("pv", "op", "sp")``.
        ``frames`` : list of DataFrame or None, only with ``return_frames=True``
            Columns ``time`` (s from the first row), ``pv``, ``op``, ``sp``, ``mode``,
            then the file's other columns as text; ``None`` for files in error.

    Raises
    ------
    ValueError
        For a bad argument, or (with ``on_error="raise"``) a file that is empty, has
        no PV column, non-numeric values, unsorted or duplicated timestamps, or no way
        to know its sampling time. The message names the file.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from sktiction.datasets._measured import read_loops
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
    if ts is not None:
        ts = check_positive(ts, "ts")
    if channels is not None:
        if not isinstance(channels, dict) or set(channels) - set(_ALIASES):
            raise ValueError(
                f"channels must be a dict with keys among {sorted(_ALIASES)}; got {channels!r}."
            )
    files = _expand_paths(paths)
    frames, rows = [], []
    for path in files:
        try:
            frame, meta = _read_one(path, ts, channels)
        except _FileError as exc:
            message = f"{path.name}: {exc}."
            if on_error == "raise":
                raise ValueError(message) from exc
            frame, meta = None, {"n_samples": 0, "status": "error", "reason": message}
        frames.append(frame)
        rows.append({"file": path.name, "path": str(path), **meta})
    max_len = max([1] + [len(f) for f in frames if f is not None])
    X = np.full((len(files), max_len, 3), np.nan)
    for i, f in enumerate(frames):
        if f is not None:
            X[i, : len(f)] = f[list(CHANNELS)].to_numpy(dtype=float)
    meta = pd.DataFrame(rows).reindex(columns=_META_COLUMNS)
    meta["n_samples"] = meta["n_samples"].astype(int)
    meta["start"] = pd.to_datetime(meta["start"])
    for col in ("format", "tag", "isa", "loop_type"):
        meta[col] = meta[col].astype(object).where(meta[col].notna(), "")
    meta.loc[meta["status"] == "error", "loop_type"] = "unknown"
    data = Bunch(X=X, meta=meta, channels=CHANNELS)
    if return_frames:
        data["frames"] = frames
    return data
