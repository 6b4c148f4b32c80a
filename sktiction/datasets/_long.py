"""Long (narrow) exports: one row per tag and time, pivoted to one column per tag.

Historians and data lakes often export ``tag, time, value`` rows (OSIsoft PI, Aspen IP.21
``NAME, IP_TREND_TIME, IP_TREND_VALUE``, Honeywell PHD, Canary, Siemens WinCC ``VarName,
TimeString, VarValue, Validity``, a Parquet table), some with a parameter column beside the
tag (``FIC101, PV, ...``), the date and the time of day in two columns, and quality columns.
Pivoted, the tags become column names (``FIC101.PV``) that the wide readers already match.

Two kinds of time axis:

* **shared**: every tag has a value at every time (an interpolated or sampled export): the
  rows are put side by side and nothing is invented;
* **each tag's own times** (recorded values: compression or exception reporting writes a
  tag only when it moved): each tag holds its last record until the next, on a regular
  grid at the scan period. Held, not interpolated: a straight line between sparse records
  looks like a smooth loop to every feature (healthy compressed loops were called sticky),
  while held values are what the package's compression check and simulated world know.
  Each loop (the tags of one prefix) runs from when all of its tags have begun to the
  last record of any (a valve that stops moving stops writing while its PV goes on); a
  lone record ten times further off than the rest span, or a tag of fewer than ten records,
  only sets the values held.

Times in text are parsed tag by tag: each tag's rows are in time order, so daylight saving
in naive local time (an hour repeated or skipped) is read as in a wide file.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

from ._readers import UNIT_SUFFIX, FileError, Table
from ._timestamps import TimeError, count, parse_times

__all__ = ["long_columns", "paired_table", "pivot_long", "time_owners"]

# Column names of each role, most telling first: with a "Tag" and a "Name" (a description)
# the tag is "Tag", with a "Value" and an "Average" the value is "Value". German, French,
# Spanish and Dutch names follow the English ones.
_TAG = ("tag", "tagname", "tag_name", "tagpath", "tag_path", "pointname", "point_name",
        "point", "itemid", "item_id", "itemname", "item_name", "item", "element", "name",
        "signal", "variable", "series", "sensor", "varname",
        "messstelle", "variablenname", "nom", "nombre", "naam")  # fmt: skip
_PARAMETER = ("parameter", "param", "attribute", "field", "property", "parametre",
              "parámetro", "parametro")  # fmt: skip
_VALUE = ("value", "ip_trend_value", "_value", "val", "values", "reading", "avg", "average",
          "mean", "varvalue",
          "wert", "messwert", "istwert", "valeur", "valor", "waarde", "meetwaarde",
          "mittelwert", "moyenne", "promedio", "gemiddelde")  # fmt: skip
QUALITY_NAMES = {"quality", "status", "confidence", "ip_trend_qstatus", "ip_trend_qlevel",
                 "q", "questionable", "validity",
                 "qualität", "qualitaet", "qualitat", "qualité", "qualite", "calidad",
                 "kwaliteit", "statut", "estado"}  # fmt: skip
_TIME_EXTRA = {"ip_trend_time", "_time", "time_stamp", "sampletime", "sample_time", "ts",
               "datetime_utc", "timestamp_utc", "time_utc", "zeitstempel", "horodatage",
               "timestring",
               "zeitpunkt", "date_heure", "heure", "temps", "fecha", "fecha_hora", "hora",
               "tiempo", "marca_de_tiempo", "tijd", "tijdstip", "tijdstempel"}  # fmt: skip
# Siemens WinCC writes Time_ms beside its TimeString: days since 1899-12-30 times 10^6, not
# milliseconds. Beside another time column it is not the time.
_TIME_SHADOW = {"time_ms"}
_GOOD = ("good", "ok", "valid", "normal")
_TRUE, _FALSE = ("true", "1", "yes"), ("false", "0", "no")
_TIME_OF_DAY = ("long layout with times of day but no dates: the tags' rows cannot be "
                "placed against each other; export dates with the times")
_OPC_GOOD = 192  # OPC quality codes: 192-255 good, below uncertain or bad
# Quality columns whose name says the one good code: WinCC's Validity is 1 for a valid value
# (0 invalid; its $RT_OFF$ / $RT_ON$ runtime markers carry other codes).
_GOOD_CODE = {"validity": 1}
_MAX_CELLS = 5e8  # 4 GB of float64: a grid step far below the records' (a stray stamp)


def _norm(name):
    return re.sub(r"[\s\-]+", "_", UNIT_SUFFIX.sub("", str(name).strip()).lower())


def long_columns(names, is_time, channels=None):
    """Positions of the long layout's columns, or None if ``names`` are not one.

    Returns a dict with ``time``, ``tag``, ``value`` (ints), ``parameter`` and ``date``
    (int or None: a date column whose values go before the time's), ``quality`` and
    ``unused`` (lists of the other positions). ``is_time(name)`` says whether a column may
    hold the time; ``channels["time"]`` names it instead.
    """
    norm = [_norm(n) for n in names]

    def one(kinds):
        """The column of the most telling name in ``kinds``; None if absent or twice."""
        for kind in kinds:
            hits = [i for i, n in enumerate(norm) if n == kind]
            if hits:
                return hits[0] if len(hits) == 1 else None
        return None

    tag, value = one(_TAG), one(_VALUE)
    if tag is None or value is None:
        return None
    date = None
    if channels and channels.get("time") in names:
        time = names.index(channels["time"])
    else:
        hits = [i for i, n in enumerate(names) if is_time(n) or norm[i] in _TIME_EXTRA]
        hits = [i for i in hits if i not in (tag, value)]
        if len(hits) > 1:
            hits = [i for i in hits if norm[i] not in _TIME_SHADOW]
        date, hits = _date_column(norm, hits)
        if len(hits) != 1:
            return None
        time = hits[0]
    found = {"time": time, "date": date, "tag": tag, "value": value,
             "parameter": one(_PARAMETER),
             "quality": [i for i, n in enumerate(norm) if n in QUALITY_NAMES]}  # fmt: skip
    used = {time, date, tag, value, found["parameter"], *found["quality"]} - {None}
    found["unused"] = [i for i in range(len(names)) if i not in used and names[i]]
    return found


def _date_column(norm, hits):
    """``(date, others)``: of two time columns, a date and a time of day (``Tag, Date,
    Time, Value``), the date's position and the other; else ``(None, hits)``."""
    dates = [i for i in hits if norm[i].endswith(("date", "datum", "fecha"))]
    if len(hits) == 2 and len(dates) == 1:
        return dates[0], [i for i in hits if i != dates[0]]
    return None, hits


def time_owners(names, is_time):
    """``{value column: its time column}`` when every value column has a time column of
    its own before it (and every time column a value column after it), else None."""
    times = [i for i, n in enumerate(names) if is_time(n)]
    if len(times) < 2 or times[0] != 0:
        return None
    owner = {i: max(j for j in times if j < i)
             for i in range(len(names)) if i not in times and names[i]}  # fmt: skip
    return owner if set(owner.values()) == set(times) else None


def paired_table(table, is_time):
    """A wide table whose every tag has its own time column before it (PI DataLink's
    compressed data: ``Time, FIC1.PV, Time, FIC1.OP``) as a long one, or None.

    Such a file is a long export laid out side by side: each value column is read with the
    time column nearest to its left, and blank cells below a shorter tag are not records.
    """
    names = table.names
    owner = time_owners(names, is_time)
    if owner is None:
        return None
    times = sorted(set(owner.values()))

    def reader(positions, text):  # the tags are the column names: text
        frame = table.read(sorted(set(owner) | set(times)))
        parts = [pd.DataFrame({0: names[i], 1: frame[owner[i]], 2: frame[i]}) for i in owner]
        long = pd.concat(parts, ignore_index=True)
        blank = long[1].isna() & long[2].isna()
        return long.loc[~blank, positions].reset_index(drop=True)

    info = table.info
    info["notes"].append(f"a time column before each tag ({count(len(owner), 'tag')}): read "
                         "as a long export")  # fmt: skip
    return Table(["tag", "time", "value"], info, reader)


def _text(col):
    """A key column as text; whole floats as their integer (a Parquet or workbook column
    of numeric tags holds 101.0 for the tag 101)."""
    if col.dtype.kind == "f":
        col = col.map(lambda v: str(int(v)) if np.isfinite(v) and v % 1 == 0 else str(v))
    return col.astype(str).str.strip()


def _keys(frame, cols):
    """Each row's column name after the pivot: the tag, or ``tag.parameter``."""
    tag = _text(frame[cols["tag"]])
    if cols["parameter"] is not None:
        tag = tag + "." + _text(frame[cols["parameter"]])
    return tag.where(frame[cols["tag"]].notna())


def bad_quality(col, name, word=None):
    """Rows whose quality says the value is not good, and a note: text other than good
    (Good, OK, Valid), True in a column named questionable (PI), a code other than 1 in
    one named validity (WinCC), or OPC codes below 192;
    other numeric codes are the vendor's own and are not read (the note says so).
    ``word``: the quality word of a longer ``name`` (``Validity`` of ``FIC1.PV Validity``)."""
    kind = col.dtype.kind
    word = _norm(name if word is None else word)
    if kind in "fiu" and word in _GOOD_CODE:
        q = col.to_numpy(dtype=float)
        bad = np.isfinite(q) & (q != _GOOD_CODE[word])
        return bad, _quality_note(bad, name)
    flag = None  # True / False flags, as bools, integers 0 / 1 or text
    if kind == "b":
        flag = col.fillna(False).to_numpy(dtype=bool)
    elif kind in "iu" and np.isin(col.to_numpy(), (0, 1)).all():
        flag = col.to_numpy() == 1
    elif kind not in "fiu":
        # a blank cell is "" (pandas 3's astype(str) keeps it missing, pandas 2 writes "nan")
        text = col.astype(str).str.strip().str.lower().fillna("")
        if text.isin(_TRUE + _FALSE + ("nan", "none", "")).all():
            flag = text.isin(_TRUE).to_numpy()
    if flag is not None:
        bad = flag if word == "questionable" else ~flag & col.notna().to_numpy()
        return bad, _quality_note(bad, name)
    if kind in "fiu":
        q = col.to_numpy(dtype=float)
        finite = q[np.isfinite(q)]
        codes, counts = np.unique(finite, return_counts=True)
        if finite.size and codes[np.argmax(counts)] >= _OPC_GOOD and finite.max() <= 255:
            bad = np.isfinite(q) & (q < _OPC_GOOD)
            return bad, _quality_note(bad, name)
        return None, f"quality column {name!r} not used (numeric codes of unknown meaning)"
    # a missing quality written out as text reads as blank, as in a flag column
    blank = text.isin(("nan", "none", "")).to_numpy() | col.isna().to_numpy()
    bad = ~(text.str.startswith(_GOOD).to_numpy() | blank)
    return bad, _quality_note(bad, name)


def _quality_note(bad, name):
    n = int(bad.sum())
    return f"{count(n, 'value')} of quality other than good read as NaN (column {name!r})" * (
        n > 0
    )


def _scan_step(records):
    """The grid step of tags recorded at their own times: the scan period the records fall
    on. The typical short step is the median of the steps near the 5th percentile (stamps
    may jitter); the steps' greatest common divisor (to the millisecond) is the period when
    it is at least a fifth of that (a compressed tag writes on some scans only; a divisor
    from jittered or rounded stamps is far smaller), else the typical short step when
    nearly all steps are close to whole multiples of it, else the median step."""
    steps = np.concatenate([np.diff(tk) for tk, _ in records.values()])
    steps = steps[steps > 0]
    if steps.size == 0:
        return None
    # a step that occurs (not one interpolated between two clusters of steps, near none)
    short = float(np.percentile(steps, 5, method="lower"))
    short = float(np.median(steps[np.abs(steps / short - 1) < 0.25]))
    ms = np.round(steps * 1000).astype(np.int64)
    common = np.gcd.reduce(ms[ms > 0]) / 1000 if (ms > 0).any() else 0.0
    if common >= 0.2 * short:
        return float(common)
    ratio = steps / short
    if np.mean(np.abs(ratio - np.round(ratio)) <= 0.2) >= 0.8:
        return short
    return float(np.median(steps))


def _held(t, v, grid):
    """One tag's records (sorted, unique times ``t``) on ``grid``: each grid point holds
    the last record at or before it (NaN before the first; a bad record is NaN until the
    next)."""
    i = np.searchsorted(t, grid, side="right") - 1
    return np.where(i >= 0, v[np.maximum(i, 0)], np.nan)


def _own_span(tk):
    """A tag's records' span (sorted unique times ``tk``) without a lone first or last
    record ten times further from its neighbour than the rest of the records span (a stray
    stamp a month off); None for a tag of fewer than 10 records (a setpoint written on its
    few changes), which only sets the values held."""
    if tk.size < 10:
        return None
    lo, hi = tk[0], tk[-1]
    if tk[1] - tk[0] > 10 * (tk[-1] - tk[1]):
        lo = tk[1]
    if tk[-1] - tk[-2] > 10 * (tk[-2] - lo):
        hi = tk[-2]
    return lo, hi


def _loop_spans(records, loop_of):
    """Each loop's grid bounds, ``{loop: (lo, hi)}``: from when all of its tags have begun
    (each its own span) to the last record of any of them (a valve that stops moving
    stops writing, while its PV goes on)."""
    spans = {}
    for k, (tk, _) in records.items():
        own = _own_span(tk)
        if own is not None:
            spans.setdefault(loop_of(k), []).append(own)
    return {loop: (max(lo for lo, _ in s), max(hi for _, hi in s)) for loop, s in spans.items()}


def _day_order(note):
    """"month" or "day" when a time note says which order dates were read in."""
    for order in ("month", "day"):
        if f"read {order} first" in note:
            return order
    return None


def _times(raw, key, time_unit):
    """Seconds from the earliest time, its timestamp and notes. Text is parsed per tag
    (each tag's rows are in time order, which a clock change in naive local time needs)."""
    text = not (isinstance(raw.dtype, np.dtype) and raw.dtype.kind in "fiuM")
    if text:  # numbers written as text (a stray word in the column) are numbers
        text = pd.to_numeric(raw, errors="coerce").notna().mean() <= 0.5
    if not text or len(np.unique(key.dropna())) < 2:
        return parse_times(raw, unit=time_unit)
    ns = np.zeros(len(raw), dtype=np.int64)  # integers: a tag's time equals another's
    valid = np.zeros(len(raw), dtype=bool)
    notes = []
    for idx in key.groupby(key, sort=False).indices.values():
        if raw.iloc[idx].isna().all():
            continue  # a "tag" without times: a trailer line (End of data), skipped below
        t, start, tag_notes = parse_times(raw.iloc[idx], unit=time_unit)
        if pd.isna(start):  # times of day
            raise FileError(_TIME_OF_DAY)
        ok = ~np.isnan(t)
        ns[idx[ok]] = start.value + np.round(t[ok] * 1e9).astype(np.int64)
        valid[idx[ok]] = True
        notes += [n for n in tag_notes if n not in notes]
    if len({_day_order(n) for n in notes} - {None}) > 1:
        # tags read in different day/month orders (a tag with few records allows both):
        # one order for the whole column, whatever the clock changes
        return parse_times(raw, unit=time_unit)
    first = ns[valid].min()
    t = np.where(valid, (ns - first) / 1e9, np.nan)
    return t, pd.Timestamp(int(first), unit="ns"), notes


def pivot_long(table, cols, to_numbers, *, loop_of=lambda tag: "", time_name="time",
               ts=None, time_unit="auto", strict=False):  # fmt: skip
    """The long :class:`Table` ``table`` as a wide one: a time column, one column per tag.

    ``to_numbers(col, tag)`` turns one tag's values into floats and returns ``(values,
    notes)``; the notes (status text read as NaN, ...) go to the table's. The wide time
    column is named ``time_name``. ``ts`` (seconds), when given, is the grid step for tags
    recorded at their own times; ``loop_of(tag)`` names the loop a tag belongs to (each
    loop's tags share a span).
    """
    positions = [cols["time"], cols["tag"], cols["value"], *cols["quality"]]
    positions += [cols[k] for k in ("parameter", "date") if cols[k] is not None]
    # tags as the file writes them: numbers with a gap in the column would read 101.0
    text = [cols[k] for k in ("tag", "parameter") if cols[k] is not None]
    frame = table.read(positions, text=text)
    info, names = table.info, table.names
    notes = info["notes"]
    key = _keys(frame, cols)
    raw = frame[cols["time"]]
    if cols["date"] is not None:
        raw = frame[cols["date"]].astype(str).str.strip() + " " + raw.astype(str).str.strip()
        notes.append(f"time from columns {names[cols['date']]} + {names[cols['time']]}")
    try:
        t, start, time_notes = _times(raw, key, time_unit)
    except TimeError as exc:
        raise FileError(f"long layout: time column {names[cols['time']]!r}: {exc}") from exc
    if any(n.startswith("time of day") for n in time_notes):
        raise FileError(_TIME_OF_DAY)
    notes += time_notes
    values = np.full(len(frame), np.nan)
    for k, idx in key.groupby(key, sort=False).indices.items():
        values[idx], tag_notes = to_numbers(frame[cols["value"]].iloc[idx], str(k))
        notes += tag_notes
    for q in cols["quality"]:
        bad, note = bad_quality(frame[q], names[q])
        if bad is not None:
            values[bad] = np.nan
        notes += [note] * bool(note)
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
    tags = np.unique(key)  # alphabetical, as the rows are sorted above
    times = np.unique(t)
    n_tags = len(tags)
    if key.size == n_tags * times.size:
        # every tag at every time: side by side, nothing interpolated
        grid = times
        wide = values.reshape(n_tags, times.size).T
        how = "shared times"
    else:
        # each tag's rows are one run of the sorted rows: its times, sorted and unique
        bounds = np.searchsorted(key, tags, side="right")
        starts = np.r_[0, bounds[:-1]]
        records = {k: (t[a:b], values[a:b]) for k, a, b in zip(tags, starts, bounds)}
        grid, wide, how = _held_grid(records, ts, loop_of)
    layout = ", ".join(names[cols[k]] for k in ("tag", "time", "value"))
    notes.append(f"long layout ({layout}): {count(n_tags, 'tag')} pivoted to columns; {how}")
    if cols["unused"]:
        notes.append(f"columns {[names[i] for i in cols['unused']]} not used")
    stamp = (pd.Series(start + pd.to_timedelta(np.round(grid * 1e9).astype(np.int64)))
             if pd.notna(start) else pd.Series(grid))  # fmt: skip
    wide_names = [time_name] + [str(k) for k in tags]
    columns = {0: stamp, **{j + 1: wide[:, j] for j in range(n_tags)}}

    def reader(positions, text):  # the values are numbers, the times timestamps
        return pd.DataFrame({p: columns[p] for p in positions})

    return Table(wide_names, info, reader)


def _held_grid(records, ts, loop_of):
    """Tags recorded at their own times (``records``: tag -> sorted unique times and their
    values) on one regular grid: ``(grid, wide, note)``. Each tag holds its last record
    within its loop's span (NaN outside it)."""
    step = ts if ts is not None else _scan_step(records)
    if step is None:
        raise FileError("long layout: no tag has two distinct times")
    spans = _loop_spans(records, loop_of)
    if not spans:
        raise FileError("long layout: no tag has two distinct times")
    lo = min(a for a, _ in spans.values())
    hi = max(b for _, b in spans.values())
    if (hi - lo) / step * len(records) > _MAX_CELLS:
        raise FileError(f"long layout: a {step:g} s grid over {hi - lo:g} s for "
                        f"{count(len(records), 'tag')} is too large; pass ts=")  # fmt: skip
    grid = lo + step * np.arange(int(np.floor((hi - lo) / step + 1e-9)) + 1)
    wide = np.full((grid.size, len(records)), np.nan)
    notes = []
    for j, (k, (tk, vk)) in enumerate(records.items()):
        a, b = spans.get(loop_of(k), (lo, hi))
        inside = (grid >= a - 1e-9) & (grid <= b + 1e-9)
        wide[inside, j] = _held(tk, vk, grid[inside])
        # a long silence: unchanged (compression), an outage or a cut-off export (a row
        # limit); the records cannot tell, so say it (a tenth of the span and more than a
        # few scans: a short export recorded at every scan has no silence)
        within = tk[(tk >= a) & (tk <= b)]
        gaps = np.diff(np.r_[a, within, b])
        if gaps.size and gaps.max() > max(0.1 * (b - a), 3 * step) and b > a:
            notes.append(f"{k} has no record for {gaps.max():g} s of {b - a:g} s (held)")
    why = "ts" if ts is not None else "the scan period the records fall on"
    t = np.concatenate([tk for tk, _ in records.values()])
    held = 1.0 - np.isin(np.round(grid, 3), np.round(t, 3)).mean()
    note = (f"tags recorded at their own times: each held at its last record on a {step:g} s "
            f"grid ({why}; {held:.0%} of the grid's rows without a record of any tag)")
    if np.min(t) < lo or np.max(t) > hi:
        note += (f"; records outside the time all of a loop's tags cover set only the values "
                 f"held ({hi - lo:g} s of {np.ptp(t):g} s)")
    return grid, wide, "; ".join([note, *notes])
