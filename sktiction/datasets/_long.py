"""Long (narrow) exports: one row per tag and time, pivoted to one column per tag.

Historians and data lakes often export ``tag, time, value`` rows (OSIsoft PI, Aspen IP.21
``NAME, IP_TREND_TIME, IP_TREND_VALUE``, Honeywell PHD, Canary, a Parquet table), some with
a parameter column beside the tag (``FIC101, PV, ...``) and a quality column. Pivoted, the
tags become column names (``FIC101.PV``) that the wide readers already match.

Two kinds of time axis:

* **shared**: every tag has a value at every time (an interpolated or sampled export): the
  rows are put side by side and nothing is invented;
* **each tag's own times** (recorded values: compression or exception reporting writes a
  tag only when it moved): each tag is interpolated linearly between its own records, as
  the historian itself reconstructs compressed values, onto a regular grid at the commonest
  step between records. A record whose value is missing or bad stays a gap on both sides.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

from ._readers import FileError, Table
from ._timestamps import TimeError, count, parse_times

__all__ = ["long_columns", "pivot_long"]

_UNIT = re.compile(r"\s*[\[(][^\])]*[\])]$")
_TAG = {"tag", "tagname", "tag_name", "name", "point", "pointname", "point_name", "item",
        "itemid", "item_id", "itemname", "item_name", "tagpath", "tag_path", "signal",
        "variable", "series", "sensor"}  # fmt: skip
_PARAMETER = {"parameter", "param", "attribute", "field", "property"}
_VALUE = {"value", "val", "values", "_value", "ip_trend_value", "reading", "avg",
          "average", "mean"}  # fmt: skip
_QUALITY = {"quality", "status", "confidence", "ip_trend_qstatus", "ip_trend_qlevel",
            "q", "questionable"}  # fmt: skip
_TIME_EXTRA = {"ip_trend_time", "_time", "time_stamp", "sampletime", "sample_time"}
_GOOD = ("good", "ok", "valid", "normal")
_MAX_CELLS = 5e8  # 4 GB of float64: a grid step far below the records' (a stray stamp)


def _norm(name):
    return re.sub(r"[\s\-]+", "_", _UNIT.sub("", str(name).strip()).lower())


def long_columns(names, is_time, channels=None):
    """Positions of the long layout's columns, or None if ``names`` are not one.

    Returns a dict with ``time``, ``tag``, ``value`` (ints), ``parameter`` and
    ``quality`` (int or None) and ``unused`` (the other positions). ``is_time(name)``
    says whether a column may hold the time; ``channels["time"]`` names it instead.
    """
    norm = [_norm(n) for n in names]

    def one(kinds):
        hits = [i for i, n in enumerate(norm) if n in kinds]
        return hits[0] if len(hits) == 1 else None

    tag, value = one(_TAG), one(_VALUE)
    if tag is None or value is None:
        return None
    if channels and channels.get("time") in names:
        time = names.index(channels["time"])
    else:
        hits = [i for i, n in enumerate(names) if is_time(n) or norm[i] in _TIME_EXTRA]
        hits = [i for i in hits if i not in (tag, value)]
        if len(hits) != 1:
            return None
        time = hits[0]
    found = {"time": time, "tag": tag, "value": value,
             "parameter": one(_PARAMETER), "quality": one(_QUALITY)}  # fmt: skip
    used = {v for v in found.values() if v is not None}
    found["unused"] = [i for i in range(len(names)) if i not in used and names[i]]
    return found


def _keys(frame, cols):
    """Each row's column name after the pivot: the tag, or ``tag.parameter``."""
    tag = frame[cols["tag"]].astype(str).str.strip()
    if cols["parameter"] is not None:
        tag = tag + "." + frame[cols["parameter"]].astype(str).str.strip()
    return tag.where(frame[cols["tag"]].notna())


def _bad_quality(col):
    """Rows whose text quality says the value is not good (numeric codes are vendors')."""
    if col.dtype.kind in "fiub":
        return None
    text = col.astype(str).str.strip().str.lower()
    good = text.str.startswith(_GOOD) | col.isna().to_numpy()
    return ~good.to_numpy()


def _common_step(t, key):
    """Commonest positive step between one tag's consecutive records (the scan period:
    a compressed tag records on consecutive scans while it moves)."""
    steps = []
    for k in np.unique(key):
        tk = np.unique(t[key == k])
        steps.append(np.round(np.diff(tk), 3))
    steps = np.concatenate(steps)
    steps = steps[steps > 0]
    if steps.size == 0:
        return None
    values, counts = np.unique(steps, return_counts=True)
    return float(values[np.argmax(counts)])


def _on_grid(t, v, grid):
    """One tag's records (sorted, unique times) interpolated onto ``grid``; NaN outside
    its records' span and next to a missing record."""
    out = np.interp(grid, t, np.nan_to_num(v))
    missing = np.interp(grid, t, np.isnan(v).astype(float))
    out[(missing > 0) | (grid < t[0]) | (grid > t[-1])] = np.nan
    return out


def pivot_long(table, cols, to_numbers, *, ts=None, time_unit="auto", strict=False):
    """The long :class:`Table` ``table`` as a wide one: a time column, one column per tag.

    ``to_numbers(col, name)`` turns the value column into floats and returns
    ``(values, notes)``; the notes (status text read as NaN, ...) go to the table's.
    ``ts`` (seconds), when given, is the grid step for tags recorded at their own times.
    """
    positions = [cols[k] for k in ("time", "tag", "value", "parameter", "quality")
                 if cols[k] is not None]  # fmt: skip
    frame = table.read(positions)
    info, names = table.info, table.names
    notes = info["notes"]
    key = _keys(frame, cols)
    values, value_notes = to_numbers(frame[cols["value"]], names[cols["value"]])
    notes += value_notes
    if cols["quality"] is not None:
        bad = _bad_quality(frame[cols["quality"]])
        if bad is not None and bad.any():
            values = np.where(bad, np.nan, values)
            notes.append(f"{count(int(bad.sum()), 'value')} of quality other than good read "
                         f"as NaN (column {names[cols['quality']]!r})")  # fmt: skip
    try:
        t, start, time_notes = parse_times(frame[cols["time"]], unit=time_unit)
    except TimeError as exc:
        raise FileError(f"long layout: time column {names[cols['time']]!r}: {exc}") from exc
    if any(n.startswith("time of day") for n in time_notes):
        raise FileError("long layout with times of day but no dates: the tags' rows cannot "
                        "be placed against each other; export dates with the times")  # fmt: skip
    ok = key.notna().to_numpy() & ~np.isnan(t)
    if not ok.all():
        notes.append(f"{count(int((~ok).sum()), 'row')} without a tag or a readable time "
                     "skipped")  # fmt: skip
    key, t, values = key.to_numpy()[ok].astype(str), t[ok], values[ok]
    if key.size == 0:
        raise FileError("long layout: no row with a tag and a time")
    # last record of each (tag, time) wins, as a historian's later edit replaces a value
    order = np.lexsort((np.arange(key.size), t, key))
    key, t, values = key[order], t[order], values[order]
    dup = np.zeros(key.size, bool)
    dup[:-1] = (key[1:] == key[:-1]) & (t[1:] == t[:-1])
    if dup.any():
        if strict:
            raise FileError(f"long layout: {count(int(dup.sum()), 'tag and time')} appear "
                            "more than once")  # fmt: skip
        notes.append(f"{count(int(dup.sum()), 'repeated tag and time')}: kept the last")
        key, t, values = key[~dup], t[~dup], values[~dup]
    tags = np.unique(key)  # the order of the rows above
    times = np.unique(t)
    n_tags = len(tags)
    if key.size == n_tags * times.size:
        # every tag at every time: side by side, nothing interpolated
        grid = times
        wide = values.reshape(n_tags, times.size).T
        how = "shared times"
    else:
        step = ts if ts is not None else _common_step(t, key)
        if step is None:
            raise FileError("long layout: no tag has two distinct times")
        if (times[-1] - times[0]) / step * n_tags > _MAX_CELLS:
            raise FileError(f"long layout: a {step:g} s grid over {times[-1] - times[0]:g} s "
                            f"for {count(n_tags, 'tag')} is too large; pass ts=")  # fmt: skip
        grid = times[0] + step * np.arange(int(np.floor((times[-1] - times[0]) / step)) + 1)
        wide = np.empty((grid.size, n_tags))
        for j, k in enumerate(tags):
            sel = key == k
            wide[:, j] = _on_grid(t[sel], values[sel], grid)
        why = "ts" if ts is not None else "the commonest step between records"
        how = (f"tags recorded at their own times: each interpolated linearly between its "
               f"records onto a {step:g} s grid ({why})")  # fmt: skip
    layout = ", ".join(names[cols[k]] for k in ("tag", "time", "value"))
    notes.append(f"long layout ({layout}): {count(n_tags, 'tag')} pivoted to columns; {how}")
    if cols["unused"]:
        notes.append(f"columns {[names[i] for i in cols['unused']]} not used")
    stamp = (pd.Series(start + pd.to_timedelta(np.round(grid * 1e9).astype(np.int64)))
             if pd.notna(start) else pd.Series(grid))  # fmt: skip
    wide_names = [names[cols["time"]]] + [str(k) for k in tags]
    columns = {0: stamp, **{j + 1: wide[:, j] for j in range(n_tags)}}

    def reader(positions):
        return pd.DataFrame({p: columns[p] for p in positions})

    return Table(wide_names, info, reader)
