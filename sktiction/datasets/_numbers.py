"""Cell text to numbers: decimal marks, thousands separators, status text and MODE words.

A channel's text that is no number (historian status such as ``Bad``) is read as NaN and
counted for the notes; values whose quality column calls them not good are blanked.
"""

from __future__ import annotations

import re
from collections import Counter

import numpy as np
import pandas as pd

from ._columns import _LOOP_KEYS, _quality_word
from ._long import bad_quality
from ._readers import SMALL_INT, US_INTEGER, US_SURE, FileError
from ._timestamps import count

_GROUPED = r"\s*[-+]?\d{1,3}(?:\.\d{3})+(?:,\d*)?\s*"  # 1.500,25 or 12.000
# 1 234,5 (French, also with a no-break space) or 1'234.5 (Swiss): never a decimal mark
_SPACED = r"\s*[-+]?\d{1,3}(?:['\u00a0\u202f ]\d{3})+(?:[.,]\d*)?\s*"
_US_GROUPED = r"\s*[-+]?\d{1,3}(?:,\d{3})+(?:\.\d*)?\s*"  # 1,500.25 or 12,000
# a number written with a decimal comma (50,036 or 1.500,25), left as text in a file read
# with decimal points
_COMMA_TEXT = re.compile(r"[-+]?(?:\d{1,3}(?:\.\d{3})+|\d*),\d+")
# Text in a MODE column: automatic (and cascade) count as closed loop.
_MODE_TEXT = {"auto": 1.0, "aut": 1.0, "cas": 1.0, "cascade": 1.0, "man": 0.0, "manual": 0.0}
# Text a historian writes for a missing value; read as NaN without being counted as status.
_MISSING_TEXT = ("", "nan", "na", "n/a", "null", "none")


def _numeric(col, name, decimal, strict, thousands=None):
    """Column as float; historian status text becomes NaN and is counted.

    ``thousands=","``: the file's other numbers show the comma to group thousands (see
    :func:`_us_grouping`). Returns ``(values, counts, note)`` with ``counts`` a Counter of
    the text values replaced and ``note`` saying how thousands separators were read (""
    if none).
    """
    if col.dtype.kind in "fiub":
        return col.to_numpy(dtype=float, na_value=np.nan), Counter(), ""
    text = col.astype(object)
    note = ""
    if decimal == ".":
        text, note = _us_grouping(col, name, sure=thousands == ",")
    if decimal == ",":
        text = col.astype(str)
        # with a decimal comma a point groups thousands (1.500,25): only where it does so
        grouped = text.str.fullmatch(_GROUPED)
        if grouped.any():
            text = text.where(~grouped, text.str.replace(".", "", regex=False))
        text = text.str.replace(",", ".", regex=False).where(col.notna(), None)
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=float)
    bad = np.isnan(values) & col.notna().to_numpy()
    if bad.any():
        values, bad, spaced = _spaced_grouping(col, values, bad, decimal, name)
        note = "; ".join(filter(None, [note, spaced]))
    if not bad.any():
        return values, Counter(), note
    idx = np.flatnonzero(bad)
    raw = col.iloc[idx].astype(str).str.strip()
    missing = raw.str.lower().isin(_MISSING_TEXT).to_numpy()
    idx, raw = idx[~missing], raw[~missing]
    if strict and len(idx):
        raise FileError(
            f"column {name!r} is not numeric: row {idx[0] + 1} of the data holds "
            f"{col.iloc[idx[0]]!r} ({len(idx)} such values)"
        )
    return values, Counter(raw.tolist()), note


def _spaced_grouping(col, values, bad, decimal, name):
    """``values`` with the cells ``bad`` (not numbers) whose thousands are grouped by a
    space or an apostrophe (``1 234,5`` in French, ``1'234.5`` in Swiss exports) read,
    ``bad`` without them, and a note. Neither mark can be a decimal one; before, each
    such cell was status text. Only the bad cells are looked at (a regex on every cell
    doubled the time of a file with status text)."""
    idx = np.flatnonzero(bad)
    text = col.iloc[idx].astype(str)
    grouped = text.str.fullmatch(_SPACED).to_numpy(dtype=bool, na_value=False)
    if not grouped.any():
        return values, bad, ""
    plain = text[grouped].str.replace(r"['\u00a0\u202f\s]", "", regex=True)
    number = pd.to_numeric(plain.str.replace(decimal, ".", regex=False), errors="coerce")
    read = idx[grouped][number.notna().to_numpy()]
    values, bad = values.copy(), bad.copy()
    values[read] = number.dropna().to_numpy(dtype=float)
    bad[read] = False
    n = count(int(read.size), "value")
    return (
        values,
        bad,
        f"thousands separators (space or ') in {name!r} removed ({n})" * (read.size > 0),
    )


def _us_grouping(col, name, sure=False):
    """Text column with US thousands separators (``1,003.729``) removed, and a note.

    Only where no cell can be a decimal comma: every cell holding a comma is grouped in
    threes (``d,ddd[.dd]``), and some cell shows both a comma and a decimal point
    (``1,003.7``) or several groups (``1,000,000``), in this column or, with ``sure``, in
    another of the file; or the comma cells are integers (``1,019``) beside integers
    below 1000 (``987``: 1.019 beside it would be a jump of a thousand times).
    ``"1,500"`` could be 1.5 written with a decimal comma, so otherwise a column whose
    only commas are such cells stays as it is (text).
    """
    text = col.astype(str)
    comma = text.str.contains(",", regex=False).to_numpy() & col.notna().to_numpy()
    if not comma.any():
        return col.astype(object), ""
    with_comma = text[comma]
    if not with_comma.str.fullmatch(_US_GROUPED).all():
        return col.astype(object), ""
    small = text[~comma & col.notna().to_numpy()].str.fullmatch(SMALL_INT).any()
    whole = with_comma.str.fullmatch(US_INTEGER).all()
    if not (sure or small and whole) and not with_comma.str.fullmatch(US_SURE).any():
        return col.astype(object), ""
    text = text.where(~comma, text.str.replace(",", "", regex=False)).where(col.notna(), None)
    n = count(int(comma.sum()), "value")
    return text, f"thousands separators ',' in {name!r} removed ({n})"


def _mode(col):
    if col.dtype.kind in "fiub":
        return col.to_numpy(dtype=float, na_value=np.nan)
    text = col.astype(str).str.strip().str.lower()
    mapped = text.map(_MODE_TEXT).astype(float)
    return mapped.fillna(pd.to_numeric(col, errors="coerce")).to_numpy(dtype=float)


def _status_note(counts, label):
    n = sum(counts.values())
    top = ", ".join(f"{v!r} x{c}" for v, c in counts.most_common(3))
    more = ", ..." if len(counts) > 3 else ""
    return f"{count(n, 'text value')} in {label} read as NaN ({top}{more})"


def _channel_values(frame, loops, names, decimal, strict, thousands=None, kind="csv"):
    """Every loop's pv, op, sp, mode side by side as floats, and notes per loop.

    ``thousands`` as in :func:`_numeric`; ``kind`` the file's format, for the advice when
    text values are numbers with a decimal comma (see :func:`_comma_text_note`).
    """
    values = np.full((len(frame), 4 * len(loops)), np.nan)
    loop_notes = [[] for _ in loops]
    for j, (_, g) in enumerate(loops):
        texts = Counter()
        for k, key in enumerate(_LOOP_KEYS):
            if key not in g:
                continue
            col = frame[g[key]]
            if key == "mode":
                values[:, 4 * j + k] = _mode(col)
                continue
            values[:, 4 * j + k], counts, note = _numeric(
                col, names[g[key]], decimal, strict, thousands
            )
            if note:
                loop_notes[j].append(note)
            quality = g.get(f"{key}_quality")
            if quality is not None:
                word = _quality_word(names[quality])[1]
                bad, note = bad_quality(frame[quality], names[quality], word)
                if bad is not None and bad.all():
                    # not one good value: rather a column of something else (a mode, an
                    # alarm state) than a tag bad for the whole export
                    bad, note = None, (f"column {names[quality]!r} not used as quality: "
                                       "none of its values reads good")  # fmt: skip
                if bad is not None:
                    values[bad, 4 * j + k] = np.nan
                if note and note not in loop_notes[j]:
                    loop_notes[j].append(note)
            if counts:
                loop_notes[j].append(_status_note(counts, key.upper()))
                texts += counts
        hint = _comma_text_note(texts, kind)
        if hint:
            loop_notes[j].insert(0, hint)
    return values, loop_notes


def _comma_text_note(counts, kind):
    """What to do when most text values (a Counter) are numbers written with a decimal
    comma in a file read with decimal points (quoted cells of a ``,``-separated file,
    text cells of a workbook): "" otherwise."""
    n = sum(counts.values())
    comma = [v for v in counts if _COMMA_TEXT.fullmatch(v)]
    if n == 0 or sum(counts[v] for v in comma) <= n / 2:
        return ""
    fixes = {
        "xlsx": "make the cells numbers (in Excel: Data > Text to Columns) or save the sheet "
                "as CSV with ';' between the columns",
        "csv": "export the file with ';' between the columns (which leaves the comma to the "
               "decimals) or with decimal points",
    }  # fmt: skip
    fix = fixes.get(kind, "write them with decimal points")
    return (f"text values such as {comma[0]!r} look like numbers with a decimal comma, in a "
            f"file whose decimal mark is a point: {fix}")  # fmt: skip
