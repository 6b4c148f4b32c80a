"""Open one export file as a table: column names first, then only the columns needed.

Layouts:

* **historian export** (text whose first line starts with ``PROCESSDATA``): five header
  lines, then tab-separated rows ``timestamp, <tag>.MV, <tag>.PV, <tag>.SV, <tag>.MODE,
  flags...``. Line 1 holds the time format, line 2 the start time and the declared row
  count, line 3 the column names, line 4 descriptions, line 5 grid settings.
* **delimited text** (``.csv``, ``.txt``, ``.tsv``): separator (tab, ``;``, ``|`` or ``,``)
  judged from the data rows, decimal mark from rows spread over the whole file; title or
  comment lines before the header row and a units row after it are skipped and noted; an
  Excel ``sep=;`` line is obeyed.
  Encodings: UTF-8 (with or without BOM), UTF-16 (BOM or not), GB18030 (Chinese
  historian descriptions), else latin-1.
* **Excel workbook** (``.xlsx``, needs openpyxl): every sheet holding loop columns (else
  the first holding data); title rows above the header are skipped.
* **Parquet** (``.parquet``, needs pyarrow): columns as stored.

Any of them may hold a long table (a row per tag and time): :mod:`._long` pivots it.
"""

from __future__ import annotations

import codecs
import csv
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from ._timestamps import count

__all__ = ["FileError", "file_kind", "open_table", "open_tables"]

TEXT_SUFFIXES = (".txt", ".csv", ".tsv")
SUFFIXES = {
    **dict.fromkeys(TEXT_SUFFIXES, "text"),
    ".xlsx": "xlsx", ".xlsm": "xlsx", ".parquet": "parquet", ".pq": "parquet",
}  # fmt: skip
INDEX_NAMES = ("index.csv", "index.txt")
_READABLE = ", ".join(SUFFIXES)
_UNSUPPORTED = {
    ".xls": "old Excel format (.xls): save it as .xlsx or CSV",
    ".dat": "'.dat' has no known layout: if it is delimited text, rename it to .csv",
    ".gz": "compressed file: unpack it first",
    ".zip": "compressed file: unpack it first",
    ".7z": "compressed file: unpack it first",
}
_HEAD_BYTES = 1 << 16
_SEPARATORS = ("\t", ";", "|", ",")  # preference when several split the rows evenly
_COMMENT = ("#", "//", "%", "!")
_DATE_LIKE = re.compile(r"\d{1,4}[-/.:]\d{1,2}[-/.:]\d{1,4}")
#: A unit in brackets ending a column name (``FIC1.PV [m3/h]``, ``OP (%)``).
UNIT_SUFFIX = re.compile(r"\s*[\[(][^\])]*[\])]$")
#: A unit without brackets ending a column name: a ``%`` (``OP %``, ``OP%``) or a common
#: process unit after a space (``PV degC``, ``FIC1.PV m3/h``, ``time min``).
BARE_UNIT = re.compile(
    r"(\s*%|\s+(deg\s?[CF]|°\s?[CF]|[CF]°|K|m?bar[ag]?|[kM]?Pa[ag]?|psi[ag]?|N?m3/[hs]|"
    r"[kK]g/[hs]|t/h|l/(h|min|s)|gpm|mm|cm|m|mA|V|rpm|Hz|ppm|ms|s|min|h))$",
    re.IGNORECASE,
)
_NUMBER = re.compile(r"^\s*[-+]?(\d+([.,]\d*)?|[.,]\d+)([eE][-+]?\d+)?\s*$")


class FileError(ValueError):
    """A problem with one file, in words a person can act on."""


def file_kind(path):
    """Reader kind of a file from its name: ``(kind, reason)``; kind None if unsupported.

    Examples
    --------
    >>> from sktiction.datasets._readers import file_kind
    >>> file_kind("FIC101.csv")
    ('text', '')
    >>> file_kind("FIC101.dat")[1]
    "'.dat' has no known layout: if it is delimited text, rename it to .csv"
    """
    path = Path(path)
    name = path.name.lower()
    if name in INDEX_NAMES:
        return None, "folder index (labels of the other files), not a loop"
    if name.startswith("~$"):
        return None, "Office lock file (the workbook is open somewhere), not a loop"
    suffix = path.suffix.lower()
    if suffix in SUFFIXES:
        return SUFFIXES[suffix], ""
    if not suffix:
        return None, f"no file extension: not read (readable: {_READABLE})"
    return None, _UNSUPPORTED.get(
        suffix, f"unsupported file type '{suffix}' (readable: {_READABLE})"
    )


def _is_number(text):
    return bool(_NUMBER.match(str(text)))


# ---- text --------------------------------------------------------------------------------


def _encoding(raw):
    """Encoding of a file from its first bytes; FileError for binary content."""
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return "utf-16"
    if raw.startswith(codecs.BOM_UTF8):
        return "utf-8-sig"
    if b"\x00" in raw:
        # UTF-16 without BOM: every other byte of ASCII text is zero.
        if raw[1::2].count(0) > 0.4 * len(raw) / 2:
            return "utf-16-le"
        if raw[0::2].count(0) > 0.4 * len(raw) / 2:
            return "utf-16-be"
        raise FileError("binary file (holds NUL bytes), not a text export")
    try:
        codecs.getincrementaldecoder("utf-8")().decode(raw, final=False)
        return "utf-8"
    except UnicodeDecodeError:
        pass
    # GBK characters are byte pairs >= 0x81; latin-1 accents are mostly single high bytes.
    runs = [len(m) for m in re.findall(rb"[\x80-\xff]+", raw)]
    if runs and all(n % 2 == 0 for n in runs):
        try:
            codecs.getincrementaldecoder("gb18030")().decode(raw, final=False)
            return "gb18030"
        except UnicodeDecodeError:
            pass
    return "latin-1"


def _fields(line, sep):
    if line and '"' not in line and "\0" not in line:
        return line.split(sep)  # what csv.reader gives for a line without quotes, 10x faster
    return next(csv.reader([line], delimiter=sep), [])


def _choose_separator(lines):
    """Separator splitting most of the last rows of the head into equal, >= 2 field counts,
    and whose header (its first row of that many fields) holds no date. A separator inside
    one field (the ``|`` of a PI AF path ``\\\\srv\\db\\FIC1|PV``) splits every data row
    alike but not the header, whose place a data row then takes; with no other such
    separator, the first (a file without a header gets its error)."""
    rows = [ln for ln in lines[-50:] if ln.strip() and not ln.lstrip().startswith(_COMMENT)]
    first = None
    for sep in _SEPARATORS:
        counts = [len(_fields(ln, sep)) for ln in rows]
        if not counts:
            break
        mode = max(set(counts), key=counts.count)
        if mode >= 2 and counts.count(mode) >= 0.6 * len(counts):
            if not _DATE_LIKE.search(_first_row(lines, sep, mode)):
                return sep, mode
            first = first or (sep, mode)
    return first or (",", 1)


def _first_row(lines, sep, n_fields):
    """The first line, not a comment, that ``sep`` splits into ``n_fields`` fields."""
    rows = (ln for ln in lines if not ln.lstrip().startswith(_COMMENT))
    return next((ln for ln in rows if len(_fields(ln, sep)) == n_fields), "")


class Table:
    """One file's column names, with a method to read some columns as a DataFrame.

    ``info`` holds ``format``, ``tag`` (from the file, else None), ``time_format``,
    ``declared_rows`` and ``notes`` (things the reader did, for ``meta.reason``); a text
    file's also ``thousands``: ``","`` when some of its numbers show US grouping
    (``1,500.25``: a comma between groups of three digits then groups thousands in every
    column), ``"."`` with a decimal comma, else None.
    """

    def __init__(self, names, info, reader):
        self.names = names
        self.info = info
        self._reader = reader

    def read(self, positions, text=()):
        """Columns at ``positions`` (a list of int), named by position, blank rows and
        repeated header rows counted. Those at ``text`` are read as the text a text file
        holds (tags: ``0101`` or ``101`` with a gap in the column, not 101.0)."""
        frame = self._reader(sorted(set(positions)), text)
        again = _repeated_header(frame, self.names)
        if again is not None:
            self.info["notes"].append(f"{count(int(again.sum()), 'repeated header row')} "
                                      "skipped (exports joined)")  # fmt: skip
            frame = frame.loc[~again].reset_index(drop=True)
        blank = _blank_rows(frame)
        if blank.any():
            # Rows without any value cannot be placed in time: drop them, say how many.
            self.info["notes"].append(f"{count(int(blank.sum()), 'blank row')} skipped")
            frame = frame.loc[~blank].reset_index(drop=True)
        return frame


def _repeated_header(frame, names):
    """Rows that repeat the header (exports joined, each with its header): a boolean array,
    None if there are none. A row naming the columns in another order is an error: the
    rows after it hold other channels than the header says."""
    if len(frame.columns) < 2 or any(d.kind in "fiubmM" for d in frame.dtypes):
        return None  # a header row makes every column text
    known = {str(n).strip() for n in names}
    first = frame[frame.columns[0]]
    # the rows whose first cell is a name, then only those: a column as text is slow
    rows = np.flatnonzero(first.isin(known).to_numpy() | first.isin(names).to_numpy())
    if rows.size == 0:
        return None
    text = {p: frame[p].iloc[rows].astype(str).str.strip() for p in frame.columns}
    named = np.logical_and.reduce([t.isin(known).to_numpy() for t in text.values()])
    own = np.logical_and.reduce([(t == str(names[p]).strip()).to_numpy()
                                 for p, t in text.items()])  # fmt: skip
    if (named & ~own).any():
        i = int(np.flatnonzero(named & ~own)[0])
        row = [text[p].iloc[i] for p in frame.columns]
        raise FileError(f"data row {rows[i] + 1} is a header with the columns in another "
                        f"order ({row}): exports joined; split the file there")  # fmt: skip
    again = np.zeros(len(frame), bool)
    again[rows[own]] = True
    return again if again.any() else None


def _blank_rows(frame):
    """``frame.isna().all(axis=1)`` as an array, in numpy for columns of plain numbers."""
    kinds = {d.kind if isinstance(d, np.dtype) else "" for d in frame.dtypes}
    if kinds and kinds <= set("fiub"):
        if kinds != {"f"}:  # an integer or boolean column has a value in every row
            return np.zeros(len(frame), dtype=bool)
        return np.isnan(frame.to_numpy(dtype=float)).all(axis=1)
    return frame.isna().all(axis=1).to_numpy()


def _historian_header(lines):
    if len(lines) < 5:
        raise FileError("historian header is incomplete (fewer than 5 lines)")
    first = lines[0].lstrip("\ufeff").split("\t")
    names = [c.strip() for c in lines[2].split("\t")]
    if names[0].lower() != "tagname" or len(names) < 3:
        raise FileError(f"line 3 should start with 'tagname' and list columns; got {lines[2]!r}")
    names[0] = "time"
    # Line 1 names the loop ("<tag> Data"); line 3 may add a unit prefix ("LYCDU.<tag>.MV").
    tag = None
    if len(first) > 1 and first[1].strip():
        tag = first[1].strip().removesuffix(" Data").strip()
    info = {"format": "historian", "tag": tag, "time_format": None, "declared_rows": None}
    if len(first) > 2:
        info["time_format"] = _time_format(first[2].strip())
    second = lines[1].split("\t")
    if len(second) >= 4 and second[3].strip().isdigit():
        info["declared_rows"] = int(second[3])
    return names, info


def _time_format(java_format):
    """Translate a Java-style date pattern (``yyyy-MM-dd HH:mm:ss.SSS``) to strftime."""
    fmt = java_format
    for a, b in (("yyyy", "%Y"), ("MM", "%m"), ("dd", "%d"), ("HH", "%H"), ("mm", "%M")):
        fmt = fmt.replace(a, b)
    fmt = fmt.replace("ss", "%S").replace(".SSS", ".%f").replace(",SSS", ",%f")
    return fmt if "%" in fmt else None


_COMMA_DECIMAL = re.compile(r"\s*[-+]?(\d*|\d{1,3}(\.\d{3})+),\d+\s*")  # 0,5 or 1.500,25
_POINT_DECIMAL = re.compile(r"\s*[-+]?(\d*|\d{1,3}(,\d{3})+)\.\d+([eE][-+]?\d+)?\s*")
# 1.019 or 49,998: thousands grouped by the mark, or three decimals after it
_GROUPS_OF_3 = {mark: re.compile(rf"\s*[-+]?[1-9]\d{{0,2}}(\{mark}\d{{3}})+\s*") for mark in ".,"}
#: A number only US thousands grouping writes: ``1,500.25``, ``1,000,000``.
US_SURE = r"\s*[-+]?\d{1,3}(?:(?:,\d{3}){2,}(?:\.\d*)?|,\d{3}\.\d*)\s*"
#: An integer in US thousands grouping: ``1,019``, ``12,000``.
US_INTEGER = _GROUPS_OF_3[","].pattern
#: An integer below 1000 written without a mark: ``987``.
SMALL_INT = r"\s*[-+]?\d{1,3}\s*"
_SMALL_INT = re.compile(SMALL_INT)
_SPREAD = (16, 4096)  # chunks and bytes of each read across a long file for the decimal mark


def _past_summary_rows(lines, header, sep, n_fields):
    """The header row past summary rows above it (``Minimum;54,3;7,6``: the header's width,
    mostly numbers) when a row of names without a number follows within 20 lines; else
    ``header`` (numbers as column names, ``Time;101;102``, stay names)."""
    filled = [f for f in _fields(lines[header].lstrip("\ufeff"), sep) if f.strip()]
    if sum(_is_number(f) for f in filled) <= len(filled) / 2:
        return header
    for k in range(header + 1, min(header + 21, len(lines))):
        fields = _fields(lines[k], sep)
        if len(fields) == n_fields and not any(_is_number(f) for f in fields if f.strip()):
            return k
    return header


def _stamped_rows(lines, sep):
    """How many of ``lines`` (skipped above the header) hold a time and a number: data
    rows, not titles (two exports joined, the first of fewer columns)."""
    n = 0
    for ln in lines:
        fields = [f for f in _fields(ln, sep) if f.strip()]
        n += (len(fields) >= 2 and any(_DATE_LIKE.search(f) for f in fields)
              and any(_is_number(f) for f in fields))  # fmt: skip
    return n


def _delimited_header(lines, notes, spread=()):
    """Separator, decimal mark, header row index, names, rows to skip after it and the
    thousands separator (None if not known). ``spread``: rows from further on in the
    file, which the decimal mark is judged on too (see :func:`_decimal_mark`)."""
    start = 0
    if lines and lines[0].lstrip("\ufeff").lower().startswith("sep=") and len(lines[0]) >= 5:
        sep, n_fields, start = lines[0].lstrip("\ufeff")[4], None, 1
        counts = [len(_fields(ln, sep)) for ln in lines[1:] if ln.strip()]
        n_fields = max(set(counts), key=counts.count) if counts else 1
    else:
        sep, n_fields = _choose_separator(lines)
    header = None
    for i in range(start, len(lines)):
        line = lines[i].lstrip("\ufeff")
        if not line.strip() or line.lstrip().startswith(_COMMENT):
            continue
        fields = _fields(line, sep)
        if len(fields) != n_fields:
            continue
        if all(_is_number(f) for f in fields if f.strip()):
            raise FileError("first line has no column names (it holds numbers)")
        header = i
        break
    if header is None:
        raise FileError(f"no header row of {n_fields} columns found in the first lines")
    header = _past_summary_rows(lines, header, sep, n_fields)
    if header > start:
        stamped = _stamped_rows(lines[start:header], sep)
        if stamped >= 3:
            raise FileError(f"{count(stamped, 'line')} above the header (line {header + 1}) "
                            "hold times and numbers: exports of other columns joined? Split "
                            f"the file at line {header + 1}")  # fmt: skip
        skipped = count(header - start, "line")
        notes.append(f"{skipped} before the header skipped (titles or comments)")
    names = [f.strip().strip("\ufeff") for f in _fields(lines[header].lstrip("\ufeff"), sep)]
    data = [ln for ln in lines[header + 1 :] if ln.strip()]
    data = data[:: -(-len(data) // 200) or 1] + list(spread)  # 200 rows over the head
    # with comma-separated fields the decimal mark can only be a point
    decimal, thousands = _decimal_mark(data, sep) if sep != "," else (".", None)
    if sep == "," or decimal == ".":
        # a number only US grouping writes (1,500.25, 1,000,000): the comma groups thousands
        # in the file's other cells too (1,019)
        # such a number holds a comma, which a comma-separated line has inside quotes only
        us = re.compile(US_SURE)
        sure = any(us.fullmatch(f) for ln in data if "," in ln and (sep != "," or '"' in ln)
                   for f in _fields(ln, sep))  # fmt: skip
        thousands = "," if sure else None
    if decimal == ",":
        notes.append("decimal comma")
    skip_after = 0
    after = next((i for i in range(header + 1, len(lines)) if lines[i].strip()), None)
    if after is not None:
        first = [f for f in _fields(lines[after], sep) if f.strip()]
        if first and not any(_is_number(f) or _DATE_LIKE.search(f) for f in first):
            skip_after = after - header  # a units or description row
            notes.append("1 row after the header skipped (units or descriptions)")
    return sep, decimal, header, names, skip_after, thousands


def _decimal_mark(rows, sep):
    """``(decimal, thousands)`` of the data ``rows`` of a file whose fields ``sep`` splits.

    Numbers that can only be read one way vote: ``0,5``, ``50,0134`` or ``1.500,25`` for
    the comma, ``0.5``, ``50.25`` or ``1,500.25`` for the point. With no majority (often
    no such number at all), a column holding integers below 1000 beside ``1.019`` and
    nothing else (the German format ``#.##0``: 1019 kg/h) shows the point to group
    thousands, and so the comma to be the decimal mark; else the numbers with one mark
    before groups of three digits (``1.019``, ``49,998``) vote, and a tie is a point.
    With a decimal comma the point groups thousands (a cell ``49.998`` is 49998: the
    European reading).
    """
    votes = {",": 0, ".": 0}  # numbers of one reading only
    grouped = {",": 0, ".": 0}  # numbers of a mark before groups of three digits
    columns = {}  # column -> kinds of cells seen in it
    for ln in rows:
        for i, f in enumerate(_fields(ln, sep)):
            if _GROUPS_OF_3["."].fullmatch(f):
                kind = "."
            elif _GROUPS_OF_3[","].fullmatch(f):
                kind = ","
            elif _COMMA_DECIMAL.fullmatch(f) or _POINT_DECIMAL.fullmatch(f):
                kind = "sure"
                votes["," if "," in f.rsplit(".", 1)[-1] else "."] += 1
            elif _SMALL_INT.fullmatch(f):
                kind = "int"
            else:
                continue
            columns.setdefault(i, set()).add(kind)
            if kind in grouped:
                grouped[kind] += 1
    if votes[","] != votes["."]:
        decimal = "," if votes[","] > votes["."] else "."
    elif any(kinds == {".", "int"} for kinds in columns.values()):
        decimal = ","  # 987 beside 1.019: the point groups thousands
    else:
        decimal = "," if grouped[","] > grouped["."] else "."
    return decimal, ("." if decimal == "," else None)


def _spread_rows(path, raw, encoding):
    """Lines read from a few places spread over the file after its first ``raw`` bytes,
    each whole (the cut lines at both ends of a read dropped): a sample of the whole file,
    at the cost of some small reads."""
    size = path.stat().st_size
    n, chunk = _SPREAD
    if size <= len(raw) + chunk:
        return []
    if encoding == "utf-16":  # the BOM says the byte order; reads inside have none
        encoding = "utf-16-le" if raw.startswith(codecs.BOM_UTF16_LE) else "utf-16-be"
    encoding = "utf-8" if encoding == "utf-8-sig" else encoding
    step = 2 if encoding.startswith("utf-16") else 1
    rows = []
    with open(path, "rb") as fh:
        for k in range(1, n + 1):
            at = len(raw) + (size - len(raw) - chunk) * k // n
            fh.seek(at - at % step)
            text = fh.read(chunk).decode(encoding, errors="replace")
            text = text.replace("\r\n", "\n") if "\r" in text else text
            lines = text.split("\n") if "\r" not in text else re.split(r"\r|\n", text)
            rows += [ln for ln in lines[1:-1] if ln.strip()]
    return rows


def _open_text(path):
    with open(path, "rb") as fh:
        raw = fh.read(_HEAD_BYTES)
        more = bool(fh.read(1))
    if not raw.strip():
        raise FileError("file is empty")
    encoding = _encoding(raw)
    head = codecs.getincrementaldecoder(encoding)(errors="replace").decode(raw, final=False)
    # Only the line ends the C parser knows: str.splitlines also splits at \x0c or \x85.
    # str.split when the ends are all \n or all \r\n: the same lines, 10x faster than re.
    text = head.replace("\r\n", "\n") if "\r" in head else head
    lines = text.split("\n") if "\r" not in text else re.split(r"\r\n|\r|\n", head)
    if lines and lines[-1] == "":
        lines.pop()
    if more and len(lines) > 1:
        lines = lines[:-1]  # the last line may be cut by the read size
    notes = []
    if encoding not in ("utf-8", "utf-8-sig"):
        notes.append(f"encoding {encoding}")
    if lines and lines[0].lstrip("\ufeff").startswith("PROCESSDATA"):
        names, info = _historian_header(lines)
        sep, decimal, skip = "\t", ".", 5
        notes.clear()  # GB18030 descriptions are normal for these exports
    else:
        spread = _spread_rows(path, raw, encoding) if more else []
        sep, decimal, header, names, skip_after, thousands = _delimited_header(
            lines, notes, spread
        )
        info = {"format": "csv", "tag": None, "time_format": None, "declared_rows": None,
                "thousands": thousands}  # fmt: skip
        skip = header + 1 + skip_after
    info["notes"] = notes

    def read_csv(positions, text, errors):
        with warnings.catch_warnings():
            # Mixed numbers and status text in one column are expected and handled later.
            warnings.simplefilter("ignore", pd.errors.DtypeWarning)
            return pd.read_csv(
                path, sep=sep, header=None, skiprows=skip, usecols=positions,
                encoding=encoding, encoding_errors=errors, decimal=decimal,
                skip_blank_lines=False, index_col=False, engine="c",
                dtype=dict.fromkeys(text, str) or None,
            )  # fmt: skip

    def reader(positions, text):
        try:
            try:
                # Strict decoding stays in the C parser; "replace" doubles the memory.
                return read_csv(positions, text, "strict")
            except UnicodeDecodeError:
                notes.append(f"bytes that are not {encoding} replaced")
                return read_csv(positions, text, "replace")
        except pd.errors.EmptyDataError as exc:
            raise FileError("file has no data rows") from exc
        except (pd.errors.ParserError, ValueError) as exc:
            raise FileError(f"rows could not be parsed ({exc})") from exc

    return Table(names, info, reader)


# ---- Excel and Parquet ---------------------------------------------------------------------


def _missing_extra(kind, module):
    return FileError(
        f"reading {kind} files needs {module}: pip install 'sktiction[{kind}]' "
        f"(or export the file as CSV)"
    )


def _sheet_table(frame):
    """(names, body, rows skipped above the header) of one sheet's cells."""
    filled = frame.iloc[:50].notna().sum(axis=1)
    for i in range(len(filled)):
        cells = [c for c in frame.iloc[i] if pd.notna(c)]
        if len(cells) == filled.max() and any(isinstance(c, str) for c in cells):
            names = ["" if pd.isna(c) else str(c).strip() for c in frame.iloc[i]]
            body = frame.iloc[i + 1 :].reset_index(drop=True)
            body.columns = range(body.shape[1])
            return names, body, i
    raise FileError("no header row (a row of column names) in the first 50 rows")


def _open_xlsx(path, accept=None):
    """Every sheet of a workbook that ``accept`` takes (a sheet per loop is a common way
    to gather loops), else the first sheet holding data, whose columns then say what is
    missing. With several, each table's ``info["sheet"]`` names its sheet."""
    try:
        import openpyxl  # noqa: F401
    except ImportError as exc:
        raise _missing_extra("xlsx", "openpyxl") from exc
    try:
        book = pd.ExcelFile(path, engine="openpyxl")
    except Exception as exc:  # zip or XML errors: the message is all we can pass on
        raise FileError(f"not a readable Excel workbook ({type(exc).__name__}: {exc})") from exc
    first, chosen = None, []
    with book:
        # hidden sheets are read all the same, and said to be: nothing is left out unsaid
        hidden = {ws.title for ws in getattr(book.book, "worksheets", [])
                  if getattr(ws, "sheet_state", "visible") != "visible"}  # fmt: skip
        for name in book.sheet_names:
            frame = pd.read_excel(book, sheet_name=name, header=None, dtype=object)
            frame = frame.dropna(how="all", axis=1)
            if not frame.notna().any().any():
                continue
            try:
                table = (name, *_sheet_table(frame))
            except FileError:
                first = first or (name, None, None, None)
                continue
            first = first or table
            if accept is not None and accept(table[1]):
                chosen.append(table)
    if first is None:
        raise FileError("workbook holds no data")
    sheets = chosen or [first]
    if sheets[0][1] is None:
        raise FileError("no header row (a row of column names) in the first 50 rows")
    n_sheets = len(book.sheet_names)
    read = ", ".join(repr(sheet) for sheet, *_ in sheets)
    which = ""
    if len(chosen) > 1:
        which = " (those with loop columns)"
    elif chosen and chosen[0] is not first:
        which = " (the one with loop columns)"
    tables = []
    for sheet, names, body, header in sheets:
        shown = f"sheet {sheet!r}" + " (hidden in the workbook)" * (sheet in hidden)
        notes = [shown] if len(sheets) > 1 or sheet in hidden else []
        if n_sheets > len(sheets):
            notes.append(f"workbook has {n_sheets} sheets: read {read}{which} only")
        if header:
            notes.append(f"{count(header, 'row')} above the header skipped")
        # the sheet names its loop only when the workbook gives several tables
        info = {"format": "xlsx", "tag": None, "time_format": None, "declared_rows": None,
                "sheet": sheet if len(sheets) > 1 else None, "notes": notes}  # fmt: skip
        # cells as the workbook holds them: a whole number is an int, its text "101"
        tables.append(Table(names, info,
                            lambda positions, text, body=body: body[positions].copy()))
    return tables


def _open_parquet(path):
    try:
        import pyarrow.parquet as pq
    except ImportError as exc:
        raise _missing_extra("parquet", "pyarrow") from exc
    try:
        schema = pq.read_schema(path)
    except Exception as exc:  # pyarrow raises its own error types for corrupt files
        raise FileError(f"not a readable Parquet file ({type(exc).__name__}: {exc})") from exc
    stored = list(schema.names)
    names, notes = _parquet_index(schema, stored)

    def reader(positions, text):  # the types stored: text columns are text already
        # pyarrow without the pandas metadata: an index (``df.set_index("time")``) is then
        # a column like the others instead of being set aside, which the positions need
        table = pq.read_table(path, columns=[stored[p] for p in positions])
        frame = table.to_pandas(ignore_metadata=True)
        frame.columns = positions
        return frame

    info = {"format": "parquet", "tag": None, "time_format": None, "declared_rows": None}
    info["notes"] = notes
    return Table(names, info, reader)


def _parquet_index(schema, names):
    """Column names of a Parquet file with its pandas index read as a column: an unnamed
    datetime index (``__index_level_0__``) is named ``time``; a named one keeps its name."""
    try:
        index = (schema.pandas_metadata or {}).get("index_columns", [])
    except Exception:  # noqa: BLE001 - metadata of another writer: the names as stored
        return names, []
    index = [c for c in index if isinstance(c, str) and c in names]
    if not index:
        return names, []
    names, read = list(names), []
    for col in index:
        i = names.index(col)
        if col.startswith("__index_level_") and str(schema.field(i).type).startswith("timestamp"):
            if "time" not in [n.lower() for n in names]:
                names[i] = "time"
        read.append(names[i])
    return names, [f"index {', '.join(read)} read as a column"]


def open_tables(path, kind, accept=None):
    """Open ``path`` as a list of :class:`Table` of the given kind (from :func:`file_kind`).

    ``accept(names)`` says whether a workbook sheet's columns will do: a workbook gives
    every sheet it accepts (else its first sheet holding data); text and Parquet files
    have one table only.
    """
    if kind == "xlsx":
        return _open_xlsx(Path(path), accept)
    return [{"text": _open_text, "parquet": _open_parquet}[kind](Path(path))]


def open_table(path, kind, accept=None):
    """The first table of :func:`open_tables`."""
    return open_tables(path, kind, accept)[0]
