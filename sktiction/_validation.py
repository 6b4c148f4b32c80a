"""Input checks shared by every public entry point.

Loops travel through sktiction in tslearn's layout ``(n_loops, n_samples, n_channels)``
with channels in the order PV, OP, SP and unequal lengths NaN-padded at the end.
Everything here either returns such an array or raises an error that names the problem.
"""

from __future__ import annotations

import math
import numbers
import warnings

import numpy as np
from sklearn.utils import check_array
from sklearn.utils.validation import validate_data

CHANNELS = ("pv", "op", "sp")
PV, OP, SP = 0, 1, 2

# Per-loop status codes, in the order they are checked.
STATUS_OK = "ok"
STATUS_EMPTY = "empty"
STATUS_TOO_SHORT = "too_short"
STATUS_NAN_GAP = "nan_gap"
STATUS_CONSTANT = "constant"
STATUS_MISSING_OP = "missing_op"
STATUS_SWAPPED = "pv_op_swapped"


def check_random_state_seed(random_state):
    """Return a :class:`numpy.random.Generator` from ``None``, an int or a Generator."""
    if isinstance(random_state, np.random.Generator):
        return random_state
    if random_state is None or isinstance(random_state, numbers.Integral):
        return np.random.default_rng(random_state)
    if isinstance(random_state, np.random.RandomState):
        return np.random.default_rng(random_state.randint(0, 2**31 - 1))
    raise ValueError(
        f"random_state must be None, an int or a numpy Generator; got {random_state!r}."
    )


def _is_numeric(dtype):
    """A numpy number dtype, or a pandas extension dtype of numbers (nullable ``Int64``,
    ``Float64``); not bool, text (pandas 3 stores text as a ``str`` extension dtype, which
    numpy cannot interpret) or categories."""
    try:
        return np.issubdtype(dtype, np.number)
    except TypeError:
        from pandas.api.types import is_bool_dtype, is_numeric_dtype  # a pandas dtype

        return is_numeric_dtype(dtype) and not is_bool_dtype(dtype)


def _check_not_a_container(X, name):
    """Refuse what a ``make_*`` or ``read_*`` function returns around the loops: numpy's
    own message for a tuple (X, y) is about inhomogeneous shapes, and a Bunch reads as
    a 0-d object array."""
    if isinstance(X, dict) and "X" in X:
        raise TypeError(f"{name} is a Bunch (a read_loops or load_* result): pass its loops, "
                        f"{name}.X, and its .meta where a function takes them.")
    if isinstance(X, (tuple, list)) and len(X) in (2, 3) and getattr(X[0], "ndim", 0) == 3:
        raise TypeError(f"{name} is a {type(X).__name__} of {len(X)} items whose first is a "
                        "loop array: make_loops returns (X, y) or (X, y, meta); pass X "
                        "(X, y = make_loops(...)).")


def _check_numeric_columns(X, name):
    """Name the non-numeric columns of a DataFrame (sklearn's message does not)."""
    if hasattr(X, "dtypes") and hasattr(X, "columns"):
        bad = [str(c) for c, dt in zip(X.columns, X.dtypes) if not _is_numeric(dt)]
        if bad:
            raise TypeError(f"{name} has non-numeric columns: {', '.join(bad)}.")


def _check_not_one_loop_table(X, name):
    """A 2-D table with PV/OP/SP columns is one loop, not one PV record per row: read as
    rows it would silently become thousands of loops of three samples. Columns are named
    as the file readers name them (``FIC101.PV``, ``OP [%]``, ``MV``, ``y``)."""
    columns = getattr(X, "columns", None)
    if columns is None or np.ndim(X) != 2:
        return
    from .datasets._columns import channel_key  # the readers' names; imported late

    keys = {c: channel_key(c) for c in columns}
    if not any(k in ("pv", "op") for k in keys.values()):
        return
    named = [c for c, k in keys.items() if k in ("pv", "op", "sp")]
    # the first column of each channel, in the order PV, OP, SP
    order = [next(c for c in named if keys[c] == k) for k in ("pv", "op", "sp")
             if k in keys.values()]  # fmt: skip
    raise ValueError(
        f"{name} is a table with channel columns {named}: one loop, whereas 2-D input "
        f"means one PV record per row. Pass one loop as {name}[{order}].to_numpy()[None] "
        "(shape (1, n_samples, 2 or 3), channels PV, OP, SP), or read files with "
        "sktiction.datasets.read_loop_file."
    )


def check_loops(X, *, name="X"):
    """Return loops as a float array ``(n_loops, n_samples, 3)``.

    Parameters
    ----------
    X : array-like or pandas.DataFrame
        ``(n_loops, n_samples, n_channels)`` with channels PV, OP, SP (1 to 3
        channels; missing trailing channels are filled with NaN), or
        ``(n_loops, n_samples)`` for PV alone.
    name : str, default="X"
        Name used in error messages.

    Returns
    -------
    loops : ndarray of shape (n_loops, n_samples, 3)
        Float64 copy; absent channels are all-NaN.

    Raises
    ------
    TypeError
        If the values are not numeric, X is sparse, or X is what a ``make_*`` or
        ``read_*`` function returns around the loops (a tuple (X, y), a Bunch).
    ValueError
        If X is 1-D or more than 3-D, empty, has more than three channels, holds
        infinite or complex values, or is a 2-D table with columns named PV, OP or SP
        (one loop, not one PV record per row).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._validation import check_loops
    >>> check_loops(np.zeros((2, 5))).shape
    (2, 5, 3)
    """
    _check_not_a_container(X, name)
    _check_numeric_columns(X, name)
    _check_not_one_loop_table(X, name)
    if np.ndim(X) != 3:
        # 2-D input goes through scikit-learn's own checks and messages
        arr = check_array(
            X, dtype=np.float64, ensure_all_finite="allow-nan", input_name=name
        )[:, :, None]
        rows, width = arr.shape[:2]
        if width <= 3 and rows >= 20:  # more likely one loop's columns than records this short
            warnings.warn(
                f"{name} is 2-D of shape {(rows, width)}: read as {rows} PV records of "
                f"{width} sample(s) each, too short to analyse. One loop with channels PV, "
                f"OP, SP in its columns is {name}[None] (shape (1, {rows}, {width})).",
                UserWarning, stacklevel=3,
            )
    else:
        arr = np.asarray(X)
        if np.iscomplexobj(arr):
            raise ValueError(f"Complex data not supported: {name} holds complex values.")
        try:
            arr = np.array(arr, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"{name} must hold numbers; got dtype {arr.dtype}.") from exc
    n_loops, n_samples, n_channels = arr.shape
    if n_loops == 0 or n_samples == 0:
        raise ValueError(f"{name} is empty: shape {arr.shape}.")
    if n_channels == 0 or n_channels > 3:
        raise ValueError(
            f"{name} must have 1 to 3 channels (PV, OP, SP in that order); got {n_channels}."
        )
    infinite = np.isinf(arr).any(axis=(1, 2))
    if infinite.any():
        where = np.flatnonzero(infinite)
        shown = ", ".join(map(str, where[:10])) + (", ..." if where.size > 10 else "")
        raise ValueError(f"{name} contains infinite values (in {where.size} of {n_loops} "
                         f"loops: {shown}); scan_loops gives those loops a status instead.")
    if n_channels < 3:
        pad = np.full((n_loops, n_samples, 3 - n_channels), np.nan)
        arr = np.concatenate([arr, pad], axis=2)
    return arr


def validate_loops(estimator, X, *, reset):
    """:func:`check_loops` for an estimator, recording what scikit-learn expects.

    Two-dimensional input (one PV record per row) goes through
    :func:`sklearn.utils.validation.validate_data`, which sets and checks
    ``n_features_in_`` (the record length) and ``feature_names_in_``; 3-D loops
    may have any length, so they set neither.
    """
    _check_not_a_container(X, "X")
    if np.ndim(X) == 3:
        if reset:
            for attr in ("n_features_in_", "feature_names_in_"):
                if hasattr(estimator, attr):
                    delattr(estimator, attr)
        return check_loops(X)
    _check_numeric_columns(X, "X")
    X = validate_data(
        estimator, X, reset=reset, dtype=np.float64, ensure_all_finite="allow-nan"
    )
    return check_loops(X)


def loop_lengths(loops):
    """Number of samples of each loop before its trailing NaN padding (from PV).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._validation import loop_lengths
    >>> loop_lengths(np.array([[[1.0], [2.0], [np.nan]]]))
    array([2])
    """
    valid = ~np.isnan(loops[:, :, PV])
    n = valid.shape[1]
    # index of the last valid sample + 1 (0 when nothing is valid)
    last = n - np.argmax(valid[:, ::-1], axis=1)
    return np.where(valid.any(axis=1), last, 0)


def loop_status(loops, *, min_samples=20, require_op=False, check_swap=False):
    """Per-loop status codes: why a loop cannot be analysed, or ``"ok"``.

    Parameters
    ----------
    loops : ndarray of shape (n_loops, n_samples, 3)
        Output of :func:`check_loops`.
    min_samples : int, default=20
        Fewer valid samples than this gives ``"too_short"``.
    require_op : bool, default=False
        When True a loop without an OP channel gives ``"missing_op"``.
    check_swap : bool, default=False
        When True a loop with OP and SP whose OP tracks the setpoint, whose PV does
        not, and whose record fits a controller better read the other way round gives
        ``"pv_op_swapped"`` (:func:`~sktiction._cleaning.looks_swapped`): every
        verdict asks, the feature transformers do not (a feature is a number, not a
        verdict).

    Returns
    -------
    status : ndarray of str, shape (n_loops,)
        One of ``ok``, ``empty``, ``too_short``, ``nan_gap`` (NaN inside the
        record, not only as end padding, in PV, or in OP or SP where the loop has
        them), ``constant`` (PV, or OP when required, never moves), ``missing_op``
        and ``pv_op_swapped``.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._validation import check_loops, loop_status
    >>> X = check_loops(np.vstack([np.sin(np.arange(50.0)), np.ones(50)]))
    >>> loop_status(X).tolist()
    ['ok', 'constant']
    """
    if check_swap:
        from ._cleaning import looks_swapped  # _cleaning builds on this module
    lengths = loop_lengths(loops)
    out = np.empty(len(loops), dtype=object)
    for i, n in enumerate(lengths):
        pv = loops[i, :n, PV]
        op = loops[i, :n, OP]
        sp = loops[i, :n, SP] if loops.shape[2] > SP else pv[:0]
        has_op = not np.isnan(loops[i, :, OP]).all()
        # a setpoint with holes is a gap too: the control error would silently become -PV
        has_sp = not np.isnan(sp).all() if sp.size else False
        if n == 0:
            out[i] = STATUS_EMPTY
        elif n < min_samples:
            out[i] = STATUS_TOO_SHORT
        elif (np.isnan(pv).any() or (has_op and np.isnan(op).any())
              or (has_sp and np.isnan(sp).any())):  # fmt: skip
            out[i] = STATUS_NAN_GAP
        elif require_op and not has_op:
            out[i] = STATUS_MISSING_OP
        elif np.ptp(pv) == 0 or (require_op and np.ptp(op) == 0):
            out[i] = STATUS_CONSTANT
        elif check_swap and has_op and has_sp and looks_swapped(pv, op, sp):
            out[i] = STATUS_SWAPPED
        else:
            out[i] = STATUS_OK
    return out.astype(str)


def check_positive(value, name, *, strict=True, upper=None):
    """Raise ``ValueError`` naming ``name`` unless ``value`` is a finite number in range."""
    if type(value) is float:  # the common case, ~45 calls per simulated loop: skip the ABC
        ok = math.isfinite(value)
    else:
        ok = isinstance(value, numbers.Real) and np.isfinite(value)
    ok = ok and (value > 0 if strict else value >= 0)
    if ok and upper is not None:
        ok = value <= upper
    if not ok:
        lo = "> 0" if strict else ">= 0"
        rng = f"{lo}" + (f" and <= {upper}" if upper is not None else "")
        raise ValueError(f"{name} must be a finite number {rng}; got {value!r}.")
    return float(value)


# A bridge spans at most this fraction of the loop's period: over 1/16 of a sine a straight
# line departs from the curve by under 2 % of the amplitude (1 - cos(pi / 16)), less than
# the half-width of one of the 32 bins the shape templates average a cycle into.
GAP_PERIOD_FRACTION = 1 / 16
# ... and never more than this fraction of the record, for loops with a very long period.
GAP_RECORD_FRACTION = 0.05


def _bridge_limit(pv):
    """Longest gap (samples) to bridge in one record: a chord over at most 1/16 period.

    The period is read from the autocorrelation of the detrended record, which first
    crosses zero at a quarter period for an oscillation and after about one lag for
    white noise, so noisy records get single-sample bridges only.
    """
    ok = ~np.isnan(pv)
    n = len(pv)
    if ok.sum() < 4:
        return 1
    k = np.arange(n)
    trend = np.polyval(np.polyfit(k[ok], pv[ok], 1), k)
    x = np.where(ok, pv - trend, 0.0)
    spectrum = np.fft.rfft(x, 2 * n)
    r = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    if r[0] <= 0:
        return 1
    below = np.flatnonzero(r <= 0)
    quarter = below[0] if len(below) else n
    # g missing samples make a chord over g + 1 intervals
    limit = int(4 * quarter * GAP_PERIOD_FRACTION) - 1
    return max(1, min(limit, int(GAP_RECORD_FRACTION * n)))


def missing_samples(loop, n):
    """The channels one loop has (not all NaN) and which of its first ``n`` samples miss a
    value (NaN) in one of them: what :func:`repair_gaps` bridges, splits or cuts."""
    present = ~np.isnan(loop).all(axis=0)
    return present, np.isnan(loop[:n, present]).any(axis=1)


def gap_free_lengths(X):
    """Lengths of ``X``'s loops if none misses a value (NaN or inf) before its end in a
    channel it has, else None: then :func:`repair_gaps` has nothing to bridge, split or
    cut."""
    lengths = loop_lengths(X)
    for x, n in zip(X, lengths):
        if missing_samples(x, n)[1].any() or np.isinf(x[:n]).any():
            return None
    return lengths


def check_max_gap(max_gap):
    """Raise ``ValueError`` unless ``max_gap`` is ``"auto"`` or an integer >= 0."""
    integer = isinstance(max_gap, numbers.Integral) and not isinstance(max_gap, bool)
    if not (max_gap == "auto" or (integer and max_gap >= 0)):
        raise ValueError(f"max_gap must be 'auto' or an integer >= 0; got {max_gap!r}.")


def repair_gaps(X, max_gap="auto", *, min_length=20):
    """Bridge short NaN gaps; split records at long ones and keep the longest stretch.

    A gap is a run of samples where any channel the loop has (PV, OP, SP that are not
    all-NaN) is missing, inside the record (trailing NaN padding is not a gap). Gaps of
    at most ``max_gap`` samples are filled by a straight line between their neighbours,
    channel by channel. Longer gaps split the record; the longest stretch between them
    (ties: the first) is kept, moved to the start and NaN-padded at the end, so the result
    stays in tslearn's layout. Missing samples at the two ends of that stretch are cut,
    not filled.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops as accepted by :func:`check_loops`.
    max_gap : "auto" or int, default="auto"
        Longest gap bridged, in samples. ``"auto"``: per loop, the gap whose bridge (a
        chord over gap + 1 intervals) spans at most 1/16 of the period read from the
        first zero of the PV autocorrelation (a quarter period for an oscillation); at
        least 1, at most 5 % of the record. Over 1/16 of a sine a chord stays within 2 %
        of the amplitude, so cycle shapes and areas are kept; a noise-like record gets
        single-sample bridges only.
    min_length : int, default=20
        A loop whose longest stretch is shorter is marked ``usable = False`` (its
        stretch is still returned; :func:`loop_status` will call it ``too_short``).

    Returns
    -------
    X_repaired : ndarray of shape (n_loops, n_samples, 3)
    info : pandas.DataFrame, one row per loop
        ``n_bridged`` (gaps filled in the kept stretch), ``n_filled`` (samples filled),
        ``n_gaps_split`` (gaps too long to bridge, anywhere in the record),
        ``kept_start``, ``kept_stop`` (the kept stretch ``[start, stop)`` in the input's
        sample index), ``max_gap`` (the limit used), ``usable`` (kept stretch at least
        ``min_length`` samples).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._validation import repair_gaps
    >>> pv = np.arange(30.0)
    >>> pv[5:10] = np.nan        # long gap: splits the record
    >>> pv[[20, 21]] = np.nan    # short gap: bridged
    >>> Xr, info = repair_gaps(pv[None, :], max_gap=3)
    >>> Xr[0, :20, 0].tolist() == list(range(10, 30))  # the longer stretch, moved to the start
    True
    >>> info.to_dict("records")
    [{'n_bridged': 1, 'n_filled': 2, 'n_gaps_split': 1, 'kept_start': 10, 'kept_stop': 30, \
'max_gap': 3, 'usable': True}]
    """
    import pandas as pd  # pandas only for the info table; keeps this module light to import

    check_max_gap(max_gap)
    if not (isinstance(min_length, numbers.Integral) and min_length >= 1):
        raise ValueError(f"min_length must be an integer >= 1; got {min_length!r}.")
    X = check_loops(X)
    out = np.full_like(X, np.nan)
    lengths = loop_lengths(X)
    rows = []
    for i, n in enumerate(lengths):
        rec = X[i, :n]
        present, missing = missing_samples(X[i], n)
        limit = _bridge_limit(rec[:, PV]) if max_gap == "auto" else int(max_gap)
        edges = np.diff(np.concatenate([[0], missing.astype(np.int8), [0]]))
        starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        inside = (starts > 0) & (stops < n)
        long = inside & (stops - starts > limit)
        # Stretches between long gaps, each trimmed of missing samples at its ends.
        cuts = np.concatenate([[0], np.column_stack([starts[long], stops[long]]).ravel(), [n]])
        best = (0, 0)
        for a, b in cuts.reshape(-1, 2):
            ok = np.flatnonzero(~missing[a:b])
            if len(ok) and ok[-1] + 1 - ok[0] > best[1] - best[0]:
                best = (a + ok[0], a + ok[-1] + 1)
        a, b = best
        stretch = rec[a:b].copy()
        gaps = (starts >= a) & (stops <= b)
        idx = np.arange(b - a)
        for c in np.flatnonzero(present):
            y = stretch[:, c]
            nan = np.isnan(y)
            if nan.any():
                y[nan] = np.interp(idx[nan], idx[~nan], y[~nan])
        out[i, : b - a] = stretch
        rows.append({
            "n_bridged": int(gaps.sum()), "n_filled": int((stops - starts)[gaps].sum()),
            "n_gaps_split": int(long.sum()), "kept_start": int(a), "kept_stop": int(b),
            "max_gap": limit, "usable": bool(b - a >= min_length),
        })  # fmt: skip
    return out, pd.DataFrame(rows)
