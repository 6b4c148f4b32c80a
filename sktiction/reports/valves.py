"""One row per valve: a scan's records of the same tag, summed up.

A daily scan of a site gives one row per loop and file; a month of them gives thirty rows
per valve, and one valve's two-hour windows can disagree (in the plant windows of
``../shared/data``, one valve's fitted band reads 0.07-2.2 % from window to window). An
engineer decides per valve, so the verdict per valve is the share of its judged records
called sticky, the extension of Srinivasan et al.'s (2005) confidence, the share of sticky
cycles, to records. Records are pooled by their tag: a historian export names it; a plain
CSV file without tag names is tagged with its file name, so each such file is a valve.
"""

from __future__ import annotations

import numbers

import numpy as np
import pandas as pd

from ._stream import STATUS_UNREADABLE
from .scan import NO_VERDICT, VERDICT_HEALTHY, VERDICT_STICTION

#: Columns of :func:`summarise_valves`' table, after the grouping column.
COLUMNS = (
    "loop_type",
    "n_records",
    "n_judged",
    "n_stiction",
    "stiction_share",
    "probability_median",
    "stiction_size_median",
    "stiction_band_median",
    "first_start",
    "last_start",
    "verdict",
)


def _whole(v):
    """``v``, but a number as text and a whole float as the text of its integer: a tag
    column of numbers with a gap, read as floats, names the tag ``101``, not ``101.0``;
    missing values stay missing."""
    if isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, float) and np.isfinite(v):
        return str(int(v)) if v % 1 == 0 else str(v)
    return v


def _text(values):
    """Values as stripped text, whole numbers without a decimal point (a tag column of
    numbers with a gap reads 101, not 101.0); missing values stay missing."""
    # text, not int: map() would make ints and NaN floats again
    return pd.Series(values).astype(object).map(_whole).astype("string").str.strip()


def _label(report, by):
    """The valve of each loop row: its ``by`` value, else its file, else its row."""
    label = _text(report[by])
    rows = "row " + pd.Series(report.index, index=report.index).astype("string")
    if "file" in report:
        fallback = ("file " + _text(report["file"])).fillna(rows)
    else:
        fallback = rows
    return label.mask(label.isna() | label.eq(""), fallback)


def _starts(values):
    """Timestamps of ``start``; several UTC offsets are read in UTC rather than refused."""
    try:
        return pd.to_datetime(values, errors="coerce")
    except (ValueError, TypeError):
        return pd.to_datetime(values, errors="coerce", utc=True)


def _median(values):
    values = pd.to_numeric(values, errors="coerce").to_numpy(dtype=float)
    values = values[np.isfinite(values)]
    return float(np.median(values)) if values.size else np.nan


def several_records(valves):
    """Whether some valve of a :func:`summarise_valves` table has more than one record:
    when a per-valve verdict says more than the per-record ones (the HTML report and
    ``sktiction scan`` both ask this, of the same table)."""
    return bool(np.asarray(valves["n_records"]).max(initial=0) > 1)


def summarise_valves(report, *, by="tag", min_share=0.5):
    """One row per valve of a scan report: how many of its records were judged, the share
    called sticky, the median probability and sizes, and a verdict per valve.

    Parameters
    ----------
    report : pandas.DataFrame
        The report of :func:`~sktiction.reports.scan_loops` or
        :func:`~sktiction.reports.scan_files` (or ``sktiction scan -o``, read back), with
        at least ``verdict`` and the ``by`` column. Rows of files that held no loop
        (``status`` ``unreadable``) are not records of a valve and are left out; every
        other row counts, with or without a verdict.
    by : str, default="tag"
        Column naming the valve (read as text, stripped of spaces). A row without it
        (empty or NaN) is a valve of its own, named ``file <file>`` (``row <position>``
        without a file), so that nothing is pooled by accident.
    min_share : float, default=0.5
        A valve whose judged records are called sticky at least this often gets the
        verdict ``stiction``; one with no judged record gets ``no_verdict``.

    Returns
    -------
    valves : pandas.DataFrame
        Columns ``by`` and :data:`COLUMNS`: ``n_records`` (rows of the valve),
        ``n_judged`` (rows with a verdict), ``n_stiction``, ``stiction_share``
        (``n_stiction / n_judged``, NaN without a judged record), ``probability_median``
        (median ``stiction_probability`` of the judged records), ``stiction_size_median``
        and ``stiction_band_median`` (medians of ``stiction_size_mean`` and
        ``stiction_band_fit`` over the records called sticky), ``first_start`` and
        ``last_start`` (the earliest and latest ``start``, when the report has one; in
        UTC when the report's starts carry several UTC offsets),
        ``verdict``. Sorted by ``stiction_share`` then ``probability_median``, highest
        first.

    Raises
    ------
    TypeError
        If ``report`` is not a DataFrame.
    ValueError
        If ``report`` lacks ``verdict`` or the ``by`` column, ``by`` names a column of
        the summary, or ``min_share`` is not a number in (0, 1].

    Examples
    --------
    >>> import pandas as pd
    >>> from sktiction.reports import summarise_valves
    >>> report = pd.DataFrame({
    ...     "tag": ["FIC1", "FIC1", "FIC1", "LIC2"],
    ...     "verdict": ["stiction", "stiction", "no_stiction", "no_verdict"],
    ...     "stiction_probability": [0.9, 0.7, 0.2, float("nan")],
    ... })
    >>> valves = summarise_valves(report)
    >>> valves[["tag", "n_records", "n_judged", "stiction_share", "verdict"]]
        tag  n_records  n_judged  stiction_share     verdict
    0  FIC1          3         3        0.666667    stiction
    1  LIC2          1         0             NaN  no_verdict
    """
    if not isinstance(report, pd.DataFrame):
        raise TypeError(f"report must be a pandas DataFrame; got {type(report).__name__}.")
    missing = [c for c in ("verdict", by) if c not in report]
    if missing:
        raise ValueError(f"report has no {' or '.join(map(repr, missing))} column; it has "
                         f"{list(report.columns)[:12]}. Pass by=<the column naming each "
                         "valve>.")  # fmt: skip
    if by in COLUMNS or by == "verdict":
        raise ValueError(f"by={by!r} is a column of the summary; name the column of valve "
                         "tags.")  # fmt: skip
    if (isinstance(min_share, bool) or not isinstance(min_share, numbers.Real)
            or not 0 < min_share <= 1):  # fmt: skip
        raise ValueError(f"min_share must be a number in (0, 1]; got {min_share!r}.")
    if "status" in report:
        report = report[report["status"].astype("string").ne(STATUS_UNREADABLE).fillna(True)]
    report = report.reset_index(drop=True)  # concatenated scans repeat index labels
    verdict = report["verdict"].astype("string")
    frame = pd.DataFrame({
        by: _label(report, by),
        "judged": verdict.isin([VERDICT_STICTION, VERDICT_HEALTHY]).fillna(False),
        "sticky": verdict.eq(VERDICT_STICTION).fillna(False),
    }, index=report.index)  # fmt: skip
    # read once for the whole report: one valve's several offsets put every valve in UTC
    all_starts = _starts(report["start"]) if "start" in report else pd.Series(pd.NaT, report.index)
    rows = []
    for valve, part in frame.groupby(by, sort=False, dropna=False):
        rec = report.loc[part.index]
        judged, sticky = part["judged"].to_numpy(), part["sticky"].to_numpy()
        n_judged, n_sticky = int(judged.sum()), int(sticky.sum())
        share = n_sticky / n_judged if n_judged else np.nan
        types = rec["loop_type"].dropna().astype(str) if "loop_type" in rec else pd.Series()
        starts = all_starts.loc[part.index]
        rows.append({
            by: valve,
            "loop_type": types.iloc[0] if len(types) else "",
            "n_records": len(part),
            "n_judged": n_judged,
            "n_stiction": n_sticky,
            "stiction_share": share,
            "probability_median": _median(rec.get("stiction_probability",
                                                  pd.Series(np.nan, rec.index))[judged]),
            "stiction_size_median": _median(rec.get("stiction_size_mean",
                                                    pd.Series(np.nan, rec.index))[sticky]),
            "stiction_band_median": _median(rec.get("stiction_band_fit",
                                                    pd.Series(np.nan, rec.index))[sticky]),
            "first_start": starts.min(),  # NaT when none is known
            "last_start": starts.max(),
            "verdict": (NO_VERDICT if not n_judged else
                        VERDICT_STICTION if share >= min_share else VERDICT_HEALTHY),
        })  # fmt: skip
    valves = pd.DataFrame(rows, columns=[by, *COLUMNS])
    return valves.sort_values(["stiction_share", "probability_median"], ascending=False,
                              na_position="last", kind="stable").reset_index(drop=True)
