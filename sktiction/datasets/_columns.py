"""Column names to loop channels: which columns hold the time, each loop's PV, OP, SP, MODE.

Columns are found by name, case-insensitively, also after a ``<tag>.``, ``<tag>_``,
``<tag> ``, ``<tag>:``, ``<tag>/`` or ``<tag>|`` prefix (a value field ``.CV`` or ``.Value``
after a channel name is dropped); a file with several prefixes (``FIC1.PV, FIC1.OP,
LIC2.PV, ...``) holds one loop per prefix. A quality column beside a channel (``FIC1.PV
Quality``, ``PV_Status``) or for the whole row (``Quality``) is paired with its channels.
The ISA letters of a tag (``FIC``) give the loop type.
"""

from __future__ import annotations

import re

from ._long import QUALITY_NAMES, long_columns, time_owners
from ._readers import BARE_UNIT, UNIT_SUFFIX, FileError

# Column-name aliases, compared lower-case. Order within a tuple does not matter.
_ALIASES = {
    "pv": ("pv", "y", "cv", "meas", "measurement", "process_variable"),
    "op": ("op", "mv", "out", "co", "output", "controller_output", "u"),
    "sp": ("sp", "sv", "spt", "setpoint", "set_point", "r", "ref"),
    "time": (
        "time", "t", "t_s", "time_s", "t_ms", "time_ms", "t_min", "time_min", "t_h", "time_h",
        "timestamp", "datetime", "date_time", "date",
        # German DCS exports (WinCC, PCS7): Zeitstempel, or Datum and Uhrzeit
        "zeit", "zeitstempel", "datum", "uhrzeit",
    ),
    "mode": ("mode", "aut", "auto"),
}  # fmt: skip
_DATE_NAMES = ("date", "datum")  # of a date column beside a time-of-day column
# Between a tag and a channel name: FIC1.PV, FIC1_PV, FIC1 PV, FIC1:PV, LIC1/PID1/PV, and
# a PI AF element and its attribute, \\srv\db\FIC1|PV.
_TAG_SEPARATORS = (".", "_", " ", ":", "/", "|")
# A value field after a channel name (DeltaV PV.CV, OUT.CV; PI PV.Value).
_FIELD = re.compile(r"[.:](cv|value)$", re.IGNORECASE)
_KEY_OF = {alias: key for key, aliases in _ALIASES.items() for alias in aliases}
_LOOP_KEYS = ("pv", "op", "sp", "mode")
# ISA controller letters inside a tag: first letter = measured variable, then optional
# D (differential), I/R (indicating/recording), C (controller), not glued to other letters.
_ISA = re.compile(r"(?<![A-Z])(PD|[FLPT])(IR|I|R)?C(?![A-Z])")
_LOOP_TYPES = {"F": "flow", "L": "level", "P": "pressure", "PD": "pressure", "T": "temperature"}


def _split(name):
    """(prefix, channel key) of a column name, or None: full name first, then suffixes.

    A unit in brackets at the end (``FIC1.PV [m3/h]``, ``OP (%)``) is ignored, and so is
    a bare unit (``OP %``, ``PV degC``: :data:`BARE_UNIT`) when the name without it is a
    channel's; ``Set Point`` is ``SETPOINT``.
    """
    name = UNIT_SUFFIX.sub("", str(name).strip())
    hit = _split_name(name)
    bare = BARE_UNIT.search(name)
    if hit is None and bare is not None and bare.start() > 0:
        hit = _split_name(name[: bare.start()].rstrip())
    return hit


def _split_name(name):
    """:func:`_split` of a name without a unit."""
    field = _FIELD.search(name)
    if field is not None:
        # DeltaV ``LIC101/PID1/OUT.CV``: the value field of the OUT channel, not a PV
        inner = _split(name[: field.start()])
        if inner is not None and inner[1] in _LOOP_KEYS:
            return inner
    # "Set Point", "FIC1 Set-Point": one word, as the aliases have it (same length)
    low = re.sub(r"set[ -]point$", "set_point", name.lower())
    if low in _KEY_OF:
        return "", _KEY_OF[low]
    for sep in _TAG_SEPARATORS:
        if sep in low:
            head, tail = low.rsplit(sep, 1)
            if tail.strip() in _KEY_OF:
                return name[: len(head)].strip(), _KEY_OF[tail.strip()]
    return None


def channel_key(name):
    """``"pv"``, ``"op"``, ``"sp"``, ``"time"`` or ``"mode"``: what a column named
    ``name`` holds for the readers, or ``None``."""
    hit = _split(name)
    return None if hit is None else hit[1]


def _plans(names, channels):
    """Whether :func:`_plan` finds a loop among ``names``."""
    try:
        _plan(names, channels)
    except FileError:
        return False
    return True


def _is_time(name):
    return channel_key(name) == "time"


def _loop_of(tag):
    """The loop a tag belongs to: its prefix (``FIC1`` of ``FIC1.PV``), else the tag."""
    hit = _split(tag)
    return hit[0] if hit is not None else str(tag)


def _loop_type(tag):
    """ISA letters found in ``tag`` (e.g. ``'FIC'``) and the loop type they imply."""
    m = _ISA.search(str(tag).upper())
    if m is None:
        return "", "unknown"
    return m.group(0), _LOOP_TYPES[m.group(1)]


def _accept(names, channels):
    """Whether a workbook sheet's columns hold loops: wide, long, or a time column before
    each tag."""
    return (_plans(names, channels) or long_columns(names, _is_time, channels) is not None
            or (not channels and time_owners(names, _is_time) is not None))  # fmt: skip


def _plan(names, channels):
    """Which columns hold time and each loop's channels.

    Returns ``(time, loops, notes)``: ``time`` a list of 0, 1 or 2 (date, time) positions,
    ``loops`` a list of ``(prefix, {key: position})`` with a PV each, ``notes`` strings.
    """
    channels = dict(channels or {})
    fixed = {}
    for key, col in channels.items():
        if col not in names:
            raise FileError(f"column {col!r} given in channels[{key!r}] is not in {names}")
        fixed[key] = names.index(col)
    found = {}  # (prefix, key) -> positions
    for i, name in enumerate(names):
        if i in fixed.values():
            continue
        hit = _split(name)
        if hit is not None:
            found.setdefault(hit, []).append(i)
    # Time: one column shared by all loops, or a date column and a time-of-day column.
    if "time" in fixed:
        time = [fixed.pop("time")]
    else:
        cand = [i for (prefix, key), pos in found.items() if key == "time" for i in pos]
        dates = [i for i in cand if names[i].strip().lower().endswith(_DATE_NAMES)]
        if len(cand) == 2 and len(dates) == 1:
            time = [dates[0], next(i for i in cand if i != dates[0])]
        elif len(cand) > 1:
            raise FileError(
                f"several columns could be the time: {[names[i] for i in cand]}; choose one "
                f"with channels={{'time': ...}}"
            )
        else:
            time = cand
    if fixed:
        # Explicit channels make one loop; missing keys fall back to the unprefixed match.
        loop = dict(fixed)
        for key in _LOOP_KEYS:
            pos = found.get(("", key), [])
            if key not in loop and len(pos) == 1 and pos[0] not in loop.values():
                loop[key] = pos[0]
        if "pv" not in loop:
            raise FileError(f"no PV column: add 'pv' to channels (columns: {names})")
        prefix = _split(names[loop["pv"]]) or ("", "")
        loops = [(prefix[0], loop)]
        _add_quality(names, loops, time)
        return time, loops, []
    groups = {}
    for (prefix, key), pos in found.items():
        if key == "time":
            continue
        if len(pos) > 1:
            raise FileError(
                f"several columns could be {key.upper()}: {[names[i] for i in pos]}; "
                f"choose one with channels={{{key!r}: ...}}"
            )
        groups.setdefault(prefix, {})[key] = pos[0]
    loops = [(prefix, g) for prefix, g in groups.items() if "pv" in g]
    if len(loops) == 1 and loops[0][0] and "" in groups:
        # One tagged loop beside untagged columns (FIC1.PV, FIC1.OP, SP): they belong to it.
        shared = groups.pop("")
        loops[0][1].update({k: v for k, v in shared.items() if k not in loops[0][1]})
        groups[""] = {k: v for k, v in shared.items() if v not in loops[0][1].values()}
    if not loops:
        raise FileError(
            f"no PV column (looked for {'/'.join(_ALIASES['pv'])}, also after a "
            f"'<tag>.' prefix, in {names}); name it with channels={{'pv': ...}}"
        )
    notes = [
        f"columns {[names[i] for i in g.values()]} not used: no PV beside them"
        for prefix, g in groups.items()
        if g and "pv" not in g
    ]
    loops = sorted(loops, key=lambda item: min(item[1].values()))
    _add_quality(names, loops, time)
    return time, loops, notes


def _quality_word(name):
    """``(channel column, quality word)`` of a quality column's name (``("FIC1.PV",
    "Quality")``, ``("", "Status")`` for a column of the whole row), else ``(name, None)``."""
    text = UNIT_SUFFIX.sub("", str(name).strip())
    if text.lower() in QUALITY_NAMES - {"q"}:  # a bare "Q" is as often a flow
        return "", text
    for sep in _TAG_SEPARATORS:
        head, _, tail = text.rpartition(sep)
        if head.strip() and tail.strip().lower() in QUALITY_NAMES:
            return head.strip(), tail.strip()
    return text, None


def _add_quality(names, loops, time):
    """Give each channel of ``loops`` its quality column, as ``"<key>_quality"``.

    A channel's own (its column's name, a separator and a quality word: ``FIC1.PV
    Quality``, ``PV_Status``, ``OP.Q``), else the file's one column named by a quality word
    alone (``Quality``: the whole row's). Values whose quality is not good are read as NaN
    (:func:`~sktiction.datasets._long.bad_quality` says what counts as good), as in long exports.
    """
    used = set(time) | {p for _, g in loops for p in g.values()}
    own, shared = {}, []
    for i, name in enumerate(names):
        head, word = _quality_word(name)
        if i in used or word is None:
            continue
        if head:
            own.setdefault(head.lower(), i)
        else:
            shared.append(i)
    for _, g in loops:
        for key in ("pv", "op", "sp"):
            if key not in g:
                continue
            q = own.get(UNIT_SUFFIX.sub("", str(names[g[key]]).strip()).lower())
            if q is None and len(shared) == 1:
                q = shared[0]
            if q is not None:
                g[f"{key}_quality"] = q
