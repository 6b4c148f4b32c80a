"""Time columns of measured loops: parse them to seconds, then put the samples on a regular grid.

Numeric time columns are told apart by their range: epoch seconds, milliseconds,
microseconds or nanoseconds between 1990 and 2100, Excel serial days in the same years
(1900 date system) when sampled more often than daily, else seconds from any origin.
The unit read is always named in the notes, so a wrong guess is visible and can be
overridden with ``time_unit``.
"""

from __future__ import annotations

import datetime
import warnings

import numpy as np
import pandas as pd

__all__ = ["TIME_UNITS", "coarse_stamps", "count", "parse_times", "regularise"]

TIME_UNITS = ("auto", "s", "epoch_s", "epoch_ms", "epoch_us", "epoch_ns", "excel")
_EXCEL_ORIGIN = pd.Timestamp("1899-12-30")  # serial day 0 of Excel's 1900 date system
_FIRST, _LAST = pd.Timestamp("1990-01-01"), pd.Timestamp("2100-01-01")
# Seconds per unit of an epoch time stamp; ranges of 1990-2100 do not overlap between units.
_EPOCH_SCALE = {"epoch_s": 1.0, "epoch_ms": 1e-3, "epoch_us": 1e-6, "epoch_ns": 1e-9}
_EPOCH_NAMES = {
    "epoch_s": "epoch seconds", "epoch_ms": "epoch milliseconds",
    "epoch_us": "epoch microseconds", "epoch_ns": "epoch nanoseconds",
}  # fmt: skip
# Text formats tried after the file's own format and ISO 8601: day-first before month-first
# (a record longer than 12 days settles the order; otherwise the ambiguity is noted).
# Milliseconds after a comma are German Excel's (``03.04.2024 22:00:00,000``); two-digit
# years are DCS exports' (``03.04.24``).
_TEXT_FORMATS = (
    "%d.%m.%Y %H:%M:%S.%f", "%d.%m.%Y %H:%M:%S,%f", "%d.%m.%Y %H:%M:%S", "%d.%m.%Y %H:%M",
    "%d.%m.%Y %I:%M:%S %p",
    "%d.%m.%y %H:%M:%S.%f", "%d.%m.%y %H:%M:%S,%f", "%d.%m.%y %H:%M:%S", "%d.%m.%y %H:%M",
    "%d/%m/%Y %H:%M:%S.%f", "%d/%m/%Y %H:%M:%S,%f", "%d/%m/%Y %H:%M:%S", "%d/%m/%Y %H:%M",
    "%d-%m-%Y %H:%M:%S.%f", "%d-%m-%Y %H:%M:%S,%f", "%d-%m-%Y %H:%M:%S", "%d-%m-%Y %H:%M",
    "%m/%d/%Y %H:%M:%S.%f", "%m/%d/%Y %H:%M:%S", "%m/%d/%Y %H:%M", "%m/%d/%Y %I:%M:%S %p",
    "%Y/%m/%d %H:%M:%S.%f", "%Y/%m/%d %H:%M:%S", "%Y%m%d %H:%M:%S",
)  # fmt: skip
_TIME_OF_DAY = r"\d{1,2}:\d{2}(:\d{2}([.,]\d+)?)?"
_SAMPLE = 200  # values used to choose a text format before parsing the whole column
_OFFSET = r"(?:Z|[+-]\d\d:?\d\d)$"  # an ISO 8601 UTC offset at the end of a stamp


def count(n, noun):
    """``"1 row"``, ``"3 rows"``: a count for a note a person reads."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


class TimeError(ValueError):
    """The time column cannot be read; the message says why."""


def _numeric_unit(values):
    """Unit of a numeric time column judged from its range and step (see module docstring)."""
    finite = values[np.isfinite(values)]
    lo, hi = float(finite.min()), float(finite.max())
    for unit, scale in _EPOCH_SCALE.items():
        if _FIRST.value * 1e-9 / scale <= lo and hi <= _LAST.value * 1e-9 / scale:
            return unit
    first = (_FIRST - _EXCEL_ORIGIN).days
    last = (_LAST - _EXCEL_ORIGIN).days
    if first <= lo and hi <= last and len(finite) > 1:
        steps = np.abs(np.diff(finite))
        # of the steps that move: serials written with 2 decimals repeat over many rows
        step = np.median(steps[steps > 0]) if (steps > 0).any() else 0.0
        if 0 < step < 1:  # sub-daily sampling expressed in days
            return "excel"
    return "s"


def _numeric_times(values, unit):
    """Seconds from the earliest value, start time, note; inf is no time (NaN: the
    reader skips the row like a blank one)."""
    v = np.asarray(values, dtype=float)
    if np.isinf(v).any():
        v = np.where(np.isinf(v), np.nan, v)
    if unit == "auto":
        unit = _numeric_unit(v)
    v0 = np.nanmin(v)
    if unit == "excel":
        # Excel stores about 15 digits: round to the millisecond so steps stay exact.
        t = np.round((v - v0) * 86400.0, 3)
        start = _EXCEL_ORIGIN + pd.to_timedelta(round(v0 * 86400.0, 3), unit="s")
        t, note = _excel_resolution(t, v)
        return t, start, f"time read as Excel serial days (start {start}){note}"
    if unit in _EPOCH_SCALE:
        scale = _EPOCH_SCALE[unit]
        t = (v - v0) * scale
        start = pd.Timestamp(int(round(v0 * scale * 1e9)), unit="ns")
        return t, start, f"time read as {_EPOCH_NAMES[unit]} (start {start})"
    return v - v0, pd.NaT, ""


def _excel_resolution(t, v):
    """Seconds ``t`` of Excel serial days ``v`` written with few decimals (a cell in
    General format writes what it shows: 6 decimals are steps of 86.4 ms), and a note.
    Rounded so, 1 s samples were 0.95 or 1.04 s apart and read at 1.04 s; when every
    stamp lies within two resolutions of a regular series, the rows are read at their
    mean interval (rounded as far as the stamps allow)."""
    ok = np.isfinite(v)
    digits = next((d for d in range(8) if np.all(np.abs(v[ok] * 10.0**d
                   - np.round(v[ok] * 10.0**d)) < 1e-3)), None)  # fmt: skip
    tk = t[ok]
    if digits is None or tk.size < 3 or (np.diff(tk) <= 0).any():
        return t, ""  # written finely enough (1 ms or less), or not in order
    q = 86400.0 * 10.0**-digits
    n = tk.size
    step = (tk[-1] - tk[0]) / (n - 1)
    off = np.abs(tk - tk[0] - step * np.arange(n)).max()
    if off > 2 * q or off <= 1e-3:
        # gaps or irregular sampling: the stamps say more than their rounding; or a step
        # the decimals hold exactly (6 h: 0.25 days)
        return t, ""
    # the coarsest round step the stamps allow (1 s rather than 1.001 s)
    step = next((r for r in (round(step, k) for k in range(4)) if r > 0
                 and abs(r - step) * (n - 1) <= q), step)  # fmt: skip
    t = t.copy()
    t[ok] = tk[0] + step * np.arange(n)
    return t, (f"; written to {digits} decimals (a resolution of {q:g} s): rows read at "
               f"their mean interval, {step:g} s")  # fmt: skip


def _try_format(text, fmt, errors):
    with warnings.catch_warnings():
        # "Could not infer format" only concerns speed; the result is checked below.
        warnings.simplefilter("ignore", UserWarning)
        if fmt == "ISO8601-utc":
            return pd.to_datetime(text, format="ISO8601", utc=True, errors=errors)
        if fmt == "mixed":
            return pd.to_datetime(text, format="mixed", errors=errors)
        return pd.to_datetime(text, format=fmt, errors=errors)


def _is_text(value):
    return isinstance(value, str) or value is None


def _fits(sample, fmt):
    try:
        _try_format(sample, fmt, "raise")
    except (ValueError, TypeError, OverflowError):
        return False
    return True


def _parse_all(raw, fmt, clean):
    """Parse a whole column in chunks: the parser makes Python strings, a copy kept small."""
    chunk = 1 << 17
    return pd.concat(
        [_try_format(clean(raw.iloc[i : i + chunk]), fmt, "coerce")
         for i in range(0, len(raw), chunk)]
    )  # fmt: skip


def _parse_offsets(raw, fmt, clean):
    """:func:`_parse_all`, in UTC when the UTC offset changes inside the column (a
    daylight-saving change after the sample that chose the format)."""
    if fmt == "ISO8601":
        try:
            stamps = _parse_all(raw, fmt, clean)
            if stamps.dtype != object:
                return stamps
        except ValueError:  # pandas: "Mixed timezones detected"
            pass
    elif fmt != "ISO8601-utc":
        return _parse_all(raw, fmt, clean)
    # chunks with different offsets: UTC, if every stamp says its offset (one without is
    # local time of an unknown zone, and reading it as UTC would shift it silently)
    text = clean(raw.dropna()).astype(str)
    if not text.str.contains(_OFFSET).all():
        raise TimeError("some timestamps carry a UTC offset and some do not; export them "
                        "all in one form")  # fmt: skip
    return _parse_all(raw, "ISO8601-utc", clean)


def _steps(stamps):
    """``(ok, ns, dt)``: which stamps exist, their int64 nanoseconds and the steps between
    them in seconds."""
    ok = stamps.notna().to_numpy()
    ns = stamps.to_numpy(dtype="datetime64[ns]").astype(np.int64)[ok]
    return ok, ns, np.diff(ns) / 1e9


def _shift_from(stamps, i, hours):
    """``stamps`` with row ``i`` and every later row moved by ``hours``."""
    later = np.arange(len(stamps)) >= i
    return stamps.where(~later, stamps + pd.Timedelta(hours=hours))


def _fall_back_hour(at):
    """Whether a time ``at`` can be in the hour that naive local time repeats when daylight
    saving time ends: the small hours of a March or April (south) or an October or
    November (north) night."""
    return at.month in (3, 4, 10, 11) and at.hour < 4


def _clock_back(stamps, notes):
    """Naive local time repeats an hour when daylight saving time ends: one step back of
    an hour less a sample, in the small hours of a March, April, October or November
    night. Sorting would interleave the two hours and drop every repeated stamp; the rows
    after the step are read an hour later instead. Anything else stepping back (an
    overlapping export, a restart) is left to the sort."""
    ok, ns, dt = _steps(stamps)
    back = np.flatnonzero(dt < 0)
    if back.size != 1 or dt.size < 3:
        return stamps
    step = float(np.median(dt[dt > 0])) if (dt > 0).any() else 0.0
    at = pd.Timestamp(int(ns[back[0] + 1]))
    if not (0 < step < 900 and abs(dt[back[0]] + 3600 - step) <= 0.5 * step
            and _fall_back_hour(at)):  # fmt: skip
        return stamps
    stamps = _shift_from(stamps, np.flatnonzero(ok)[back[0] + 1], hours=1)
    notes.append(f"clock set back an hour at {at} (daylight saving time ending, local time "
                 "without offset): later rows read an hour later")  # fmt: skip
    return stamps


def _hour_twice(stamps, notes):
    """A file sorted by naive local time across the end of daylight saving time has the
    repeated hour's two passes interleaved: every stamp of one whole clock hour in the
    small hours of a March, April, October or November night twice, in time order, and no
    other stamp repeated. The passes cannot be told apart; the rows from the next hour on
    are read an hour later, so the hour's second pass is a gap (the first row of each
    repeated stamp is kept, as for any repeat) instead of an hour of process missing
    without a trace."""
    ok, ns, dt = _steps(stamps)
    same = np.flatnonzero(dt == 0)
    if same.size < 3 or (dt < 0).any():
        return stamps
    twice = ns[same]
    hour = pd.Timestamp(int(twice[0])).floor("h")
    later = hour + pd.Timedelta(hours=1)
    inside = (ns >= hour.value) & (ns < later.value)
    after = ns >= later.value
    if not (np.all((twice >= hour.value) & (twice < later.value)) and after.any()
            and same.size >= 0.9 * np.unique(ns[inside]).size
            and _fall_back_hour(hour)):  # fmt: skip
        return stamps
    stamps = _shift_from(stamps, np.flatnonzero(ok)[np.argmax(after)], hours=1)
    notes.append(f"every stamp of {hour:%Y-%m-%d %H:%M}-{later:%H:%M} twice (daylight saving "
                 "time ending, local time without offset, rows sorted by time): the hour's "
                 "two passes cannot be told apart, the first kept; later rows read an hour "
                 "later")  # fmt: skip
    return stamps


def _clock_forward(stamps, notes):
    """Naive local time skips an hour when daylight saving time starts: one step forward
    of an hour plus a sample over a whole clock hour (02:00-03:00), from the small hours
    of a Sunday in March, April (north),
    September or October (south), every other step regular. The rows after the jump are
    read an hour earlier, so the skipped hour is not a gap. Anything else (a jump on
    another day or hour, other gaps or steps back in the file) is left as it is: a real
    hour of missing data must stay a gap."""
    ok, ns, dt = _steps(stamps)
    if dt.size < 3 or (dt <= 0).any():
        return stamps
    step = float(np.median(dt))
    jump = np.flatnonzero(np.abs(dt - step) > 0.01 * step)
    if jump.size != 1 or not 0 < step < 900 or abs(dt[jump[0]] - 3600 - step) > 0.01 * step:
        return stamps
    before, at = pd.Timestamp(int(ns[jump[0]])), pd.Timestamp(int(ns[jump[0] + 1]))
    # the clock skips a whole hour of its face (02:00-03:00): a record that stops at 01:25
    # and goes on at 02:25 lost an hour of data instead
    skipped = at.floor("h") - pd.Timedelta(hours=1)
    if not (at.weekday() == 6 and at.month in (3, 4, 9, 10) and before.hour < 3
            and at.hour < 4 and before < skipped):  # fmt: skip
        return stamps
    stamps = _shift_from(stamps, np.flatnonzero(ok)[jump[0] + 1], hours=-1)
    notes.append(f"clock set forward an hour at {at} (daylight saving time starting, local "
                 "time without offset): later rows read an hour earlier")  # fmt: skip
    return stamps


def _irregular(stamps):
    """Steps of ``stamps`` that go back or differ from the median forward step by more
    than 1% (repeated stamps are left to the caller)."""
    dt = _steps(stamps)[2]
    forward = dt[dt > 0]
    if len(forward) == 0:
        return int((dt < 0).sum())
    step = np.median(forward)
    return int((dt < 0).sum() + (np.abs(forward - step) > 0.01 * step).sum())


def _day_month(fmt):
    """``"day"`` or ``"month"``: which a date format puts first when it starts with day
    and month (``%d.%m.%Y``, ``%m/%d/%Y``), else None."""
    for code, order in (("%d", "day"), ("%m", "month")):
        other = "%m" if code == "%d" else "%d"
        if fmt.startswith(code) and fmt[2:].lstrip(".-/ ").startswith(other):
            return order
    return None


def _swap_day_month(fmt):
    """``fmt`` with its leading day and month swapped (``%d.%m.%y`` -> ``%m.%d.%y``)."""
    return fmt.replace("%d", "\0").replace("%m", "%d").replace("\0", "%m")


def _text_times(raw, time_format):
    """Parse text (or datetime objects) to datetimes; return (stamps, notes)."""
    strings = isinstance(raw.dtype, pd.StringDtype) or raw.map(_is_text).all()

    day = ""

    def clean(part):
        if not strings:
            return part
        text = part if isinstance(part.dtype, pd.StringDtype) else part.astype("str")
        return day + text.str.strip() if day else text.str.strip()

    sample = clean(raw.dropna().iloc[:_SAMPLE])
    if len(sample) == 0:
        raise TimeError("time column is empty")
    time_only = strings and sample.str.fullmatch(_TIME_OF_DAY).all()
    if time_only:
        day = "1900-01-01 "  # ISO 8601 parsers would date bare times today
        sample = clean(raw.dropna().iloc[:_SAMPLE])
    candidates = [f for f in (time_format, "ISO8601", "ISO8601-utc") if f]
    candidates += [*_TEXT_FORMATS, "mixed"]
    fmt = next((f for f in candidates if _fits(sample, f)), None)
    if fmt is None:
        # A few bad values in the sample: take the format that reads most of it.
        read = [_try_format(sample, f, "coerce").notna().mean() for f in candidates[:-1]]
        best = int(np.argmax(read))
        if read[best] < 0.5:
            raise TimeError(
                f"values are not times (first: {sample.iloc[0]!r}); name the time column "
                f"with channels={{'time': ...}} or remove it and pass ts="
            )
        fmt = candidates[best]
    notes = []
    stamps = _parse_offsets(raw, fmt, clean)
    order = _day_month(fmt)
    if order is not None:
        # The sample may hold only days <= 12: the whole column settles the order, also
        # against a declared pattern that the data contradict. Where the data allow both
        # orders, a declared pattern is the file's word and needs no note.
        other = _swap_day_month(fmt)
        if stamps.isna().sum() > raw.isna().sum():
            swapped = _parse_all(raw, other, clean)
            if swapped.isna().sum() < stamps.isna().sum():
                if fmt == time_format:
                    missed = int(stamps.isna().sum() - raw.isna().sum())
                    notes.append(
                        f"the declared date pattern does not fit {missed} values: "
                        f"read {_day_month(other)} first"
                    )
                stamps, fmt = swapped, other
        elif fmt != time_format and _fits(sample, other):
            # the sample allows both orders; the whole column may not (a 13th day)
            swapped = _parse_all(raw, other, clean)
            if swapped.isna().sum() == stamps.isna().sum():  # both orders read every date
                if _irregular(swapped) < _irregular(stamps):
                    # one order would make every midnight a jump of a month (or a step
                    # back): the order giving the more regular time axis is the file's
                    notes.append(f"dates could be day/month or month/day: read "
                                 f"{_day_month(other)} first ({order} first gives an "
                                 "irregular time axis)")  # fmt: skip
                    stamps, fmt = swapped, other
                elif not swapped.equals(stamps):  # (03.03.: both orders give one date)
                    notes.append(f"dates could be day/month or month/day: read {order} first")
    if getattr(stamps.dt, "tz", None) is not None:
        stamps = stamps.dt.tz_convert("UTC").dt.tz_localize(None)
        notes.append("time zone offsets converted to UTC")
    elif not time_only:
        stamps = _clock_forward(_hour_twice(_clock_back(stamps, notes), notes), notes)
    if time_only:
        # Time of day only: a step back of more than 12 h is midnight passing.
        ns = stamps.to_numpy(dtype="datetime64[ns]").astype(np.int64)
        ok = ~stamps.isna().to_numpy()
        one_day = 86_400 * 10**9
        back = np.zeros(len(ns), dtype=np.int64)
        back[np.flatnonzero(ok)[1:]] = np.diff(ns[ok]) < -one_day // 2
        stamps = pd.Series(pd.to_datetime(ns + one_day * np.cumsum(back)), index=stamps.index)
        stamps[~ok] = pd.NaT
        notes.append("time of day without a date (midnight passes counted)")
    return stamps, notes


def parse_times(raw, *, time_format=None, unit="auto"):
    """Time column to seconds.

    Parameters
    ----------
    raw : pandas.Series
        Numbers, text or datetimes; missing values allowed.
    time_format : str or None, default=None
        strftime format declared by the file (tried first for text).
    unit : {"auto", "s", "epoch_s", "epoch_ms", "epoch_us", "epoch_ns", "excel"}, \
default="auto"
        Unit of numeric times: ``"s"`` seconds from any origin, ``"epoch_*"`` seconds,
        milliseconds, ... since 1970-01-01, ``"excel"`` Excel serial days (1900 system).
        ``"auto"`` judges from the range (see the module docstring).

    Returns
    -------
    t : ndarray of float
        Seconds from the earliest time; NaN where a value is missing or not a time.
    start : pandas.Timestamp
        Earliest time, NaT for relative seconds.
    notes : list of str
        How the column was read (unit, format, conversions).

    Raises
    ------
    TimeError
        If no value is a time or most values are not.

    Examples
    --------
    >>> import pandas as pd
    >>> from sktiction.datasets._timestamps import parse_times
    >>> t, start, notes = parse_times(pd.Series([1.7e12, 1.7e12 + 500.0]))
    >>> t.tolist(), str(start)
    ([0.0, 0.5], '2023-11-14 22:13:20')
    >>> notes[0].split(" (")[0]
    'time read as epoch milliseconds'
    """
    if isinstance(raw.dtype, np.dtype) and raw.dtype.kind in "fiu":
        # Plain numbers, the usual case: the branch below in numpy, without pandas' overhead.
        values = raw.to_numpy(dtype=float)
        if np.isfinite(values).any():
            t, start, note = _numeric_times(values, unit)
            return t, start, [note] if note else []
    first = raw.dropna().iloc[:1] if raw.dtype == object else ()
    if len(first) and isinstance(first.iloc[0], datetime.time):
        # Excel time-of-day cells arrive as datetime.time: read them as a CSV's text
        raw = raw.map(lambda v: v.isoformat() if isinstance(v, datetime.time) else v)
    if pd.api.types.is_datetime64_any_dtype(raw):
        stamps, notes = pd.Series(raw), []
        if stamps.dt.tz is not None:
            stamps = stamps.dt.tz_convert("UTC").dt.tz_localize(None)
            notes.append("time zone converted to UTC")
    else:
        present = raw.notna().to_numpy()
        numeric = raw
        if raw.dtype.kind not in "fiu":
            # Look at a sample first: converting a million date strings to numbers is slow.
            head = pd.to_numeric(raw[present][:_SAMPLE], errors="coerce")
            numeric = pd.to_numeric(raw, errors="coerce") if head.notna().mean() > 0.5 else None
        # Mostly numbers: numeric times, the odd text value a row without a time.
        if numeric is not None and numeric.notna().sum() > 0.5 * present.sum():
            t, start, note = _numeric_times(numeric.to_numpy(dtype=float), unit)
            return t, start, [note] if note else []
        stamps, notes = _text_times(raw, time_format)
    ok = stamps.notna().to_numpy()
    if ok.sum() < 0.5 * max(1, raw.notna().sum()):
        bad = raw[raw.notna().to_numpy() & ~ok]
        raise TimeError(f"most values are not times (first bad value: {bad.iloc[0]!r})")
    ns = stamps.to_numpy(dtype="datetime64[ns]").view(np.int64)
    first = ns[ok].min()
    t = np.where(ok, (ns - first) / 1e9, np.nan)
    if any(n.startswith("time of day") for n in notes):
        return t, pd.NaT, notes  # no date: the 1900-01-01 of the parser is not a start
    return t, pd.Timestamp(first, unit="ns"), notes


def coarse_stamps(t, values, ts=None, strict=False):
    """Times of rows whose timestamps are coarser than the rows, or None.

    An export that writes 10 s samples as ``hh:mm`` gives runs of about six rows per
    stamp. De-duplicating would keep one row in six and call the file 60 s data, so when
    most rows share their stamp with a neighbour, in time order, and are not copies of
    each other (a row exported twice is a duplicate, left to :func:`regularise`):

    * with ``ts`` given, the rows are read in order at ``ts``;
    * else, when every step between stamps is the same and the runs between the first
      and the last are of equal length (within one row), the rows are read in order at
      the mean interval, which is what the stamps say once their resolution is taken
      into account; only the phase within the first stamp is unknown, which moves the
      start by less than one stamp and does not change the samples or their spacing;
    * else (uneven runs: irregular or missing rows, which reading in order would hide)
      a :class:`TimeError` names the cause and asks for ``ts``.

    Returns ``(t, note)``, or None when the stamps are not coarse; ``t[0]`` is after 0
    when the first stamp holds fewer rows than the others (it was cut at its start).
    With ``strict=True`` coarse stamps are an error.
    """
    n = len(t)
    dt = np.diff(t)
    if n < 4 or (dt < 0).any() or (dt == 0).mean() <= 0.5:
        return None
    same = dt == 0
    v = np.asarray(values, dtype=float).reshape(n, -1)
    copies = ((v[1:] == v[:-1]) | (np.isnan(v[1:]) & np.isnan(v[:-1]))).all(axis=1)
    if copies[same].mean() >= 0.5 or (same.all() and ts is None):
        return None  # rows exported twice (not finer samples), or a single stamp
    starts = np.concatenate([[0], np.flatnonzero(~same) + 1])
    runs = np.diff(np.append(starts, n))
    steps = dt[~same]
    k = float(np.median(runs))
    res = float(np.median(steps)) if len(steps) else 0.0
    what = (f"timestamps have a resolution of {res:g} s, coarser than the rows "
            f"(about {k:g} rows per stamp)")  # fmt: skip
    if ts is not None:
        return ts * np.arange(n), f"{what}: rows read in order at ts={ts:g} s"
    inner = runs[1:-1]
    even = (
        len(inner) >= 2 and inner.max() - inner.min() <= 1
        and np.abs(steps - res).max() <= 0.01 * res and runs[0] <= inner.max()
        and runs[-1] <= inner.max()
    )  # fmt: skip
    if strict or not even:
        raise TimeError(f"{what}, {'' if even else 'with uneven runs, '}so the time of each "
                        "row is unknown: pass ts= to read the rows in order")  # fmt: skip
    fine = (t[starts[-1]] - t[starts[1]]) / (starts[-1] - starts[1])
    t = t[starts[1]] + fine * (np.arange(n) - starts[1])
    return t, f"{what}: rows read in order at {fine:g} s"


def regularise(t, values, *, hold=(), strict=False, tolerance=0.01, gap_steps=3.0):
    """Sort, de-duplicate and resample samples onto a regular time grid.

    Parameters
    ----------
    t : ndarray of shape (n,)
        Seconds; no NaN.
    values : ndarray of shape (n, k)
        Channels sampled at ``t``.
    hold : sequence of int, default=()
        Columns of ``values`` held (previous sample) instead of interpolated, e.g. a mode.
    strict : bool, default=False
        Report irregular sampling without resampling (duplicates and unsorted rows are
        the caller's to reject in strict mode).
    tolerance : float, default=0.01
        Intervals within this fraction of the median interval count as regular.
    gap_steps : float, default=3.0
        Intervals longer than this many median steps are time gaps: grid points inside
        them are NaN rather than interpolated (a straight line over missing minutes would
        invent data; :func:`sktiction._validation.repair_gaps` decides what to bridge).

    When a grid over the whole span would hold more than four times as many rows as the
    samples (a day missing from hours of data, a scan rate that drops tenfold), only the
    longest stretch between time jumps of more than ``gap_steps`` steps is kept and
    resampled, and a note says which.

    Returns
    -------
    t : ndarray of shape (m,)
        Regular grid (or the sorted unique times when nothing was resampled); it starts
        after 0 when a later stretch was kept.
    values : ndarray of shape (m, k)
    step : float or None
        Median interval in seconds, None with fewer than two distinct times.
    notes : list of str

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.datasets._timestamps import regularise
    >>> t, v, step, notes = regularise(np.array([0, 10, 10, 21, 30.0]),
    ...                                np.array([[0], [1], [9], [2], [3.0]]))
    >>> t.tolist(), v[:, 0].round(2).tolist(), step
    ([0.0, 10.0, 20.0, 30.0], [0.0, 1.0, 1.91, 3.0], 10.0)
    >>> notes[0]
    '1 duplicated timestamp: kept the first row of each'
    """
    notes = []
    values = np.asarray(values, dtype=float).reshape(len(t), -1)
    dt = np.diff(t)
    if (dt < 0).any():
        order = np.argsort(t, kind="stable")  # stable: file order decides among duplicates
        notes.append(f"rows not in time order ({count(int((dt < 0).sum()), 'step')} back): sorted")
        t, values = t[order], values[order]
        dt = np.diff(t)
    if (dt == 0).any():
        keep = np.concatenate([[True], dt != 0])
        dups = count(int((~keep).sum()), "duplicated timestamp")
        notes.append(f"{dups}: kept the first row of each")
        t, values = t[keep], values[keep]
        dt = np.diff(t)
    if len(t) < 2:
        return t, values, None, notes
    step = float(np.median(dt))
    off = np.abs(dt - step) > tolerance * step
    if not off.any():
        return t, values, step, notes
    note = (
        f"irregular sampling: {count(int(off.sum()), 'interval')} differ from {step:g} s "
        f"(min {dt.min():g}, max {dt.max():g})"
    )
    if strict:
        return t, values, step, [*notes, note]
    n_grid = int(np.floor((t[-1] - t[0]) / step + 1e-9)) + 1
    if n_grid > 4 * len(t):
        # A grid over days missing from hours of data (or over a slower scan rate's rows)
        # would be mostly NaN: keep the longest stretch between the jumps instead, as
        # gap repair does past a long gap (at least two rows: half the steps are short).
        cuts = np.concatenate([[0], np.flatnonzero(dt > gap_steps * step) + 1, [len(t)]])
        longest = int(np.argmax(np.diff(cuts)))
        a, b = int(cuts[longest]), int(cuts[longest + 1])
        note += (
            f"; the records span {t[-1] - t[0]:g} s, {n_grid} steps of {step:g} s for "
            f"{len(t)} rows: kept the longest stretch between time jumps of more than "
            f"{gap_steps:g} steps ({b - a} rows from {t[a]:g} s)"
        )
        grid, out, step, more = regularise(
            t[a:b], values[a:b], hold=hold, tolerance=tolerance, gap_steps=gap_steps
        )
        return grid, out, step, [*notes, note, *more]
    grid = t[0] + step * np.arange(n_grid)
    j = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 2)
    left, right = t[j], t[j + 1]
    w = (grid - left) / (right - left)
    out = values[j] * (1 - w)[:, None] + values[j + 1] * w[:, None]
    # A grid point on a sample takes that sample, so a NaN neighbour does not spread.
    at_left, at_right = w < 1e-6, w > 1 - 1e-6
    out[at_left] = values[j[at_left]]
    out[at_right] = values[j[at_right] + 1]
    for col in hold:
        out[:, col] = np.where(w > 1 - 1e-6, values[j + 1, col], values[j, col])
    inside_gap = (right - left > gap_steps * step) & ~at_left & ~at_right
    out[inside_gap] = np.nan
    note += f"; resampled to {n_grid} rows at {step:g} s"
    if inside_gap.any():
        n_gaps = int((dt > gap_steps * step).sum())
        note += (
            f"; {count(n_gaps, 'time gap')} longer than {gap_steps:g} steps left as NaN "
            f"({count(int(inside_gap.sum()), 'row')})"
        )
    return grid, out, step, [*notes, note]
