"""Historian artefacts undone before any loop is analysed, by a scan (:func:`repaired`)
and by every classifier (:func:`as_judged`). The rules that read one record alone (spikes,
placeholders) are in :mod:`sktiction.cycles._repairs`, which ``analyze_cycles`` reads a
record with too.

- **Spikes**: one to three samples far from both neighbours, which agree with each other
  (a "Bad" value written as 0 or -9999, a transmitter glitch). A single one wrecks every
  least-squares statistic of the loop (the PV-OP coupling test read one zero in 751 rows
  as "PV and OP unrelated"). A valve's slip is a step, not a spike: after it the signal
  stays where it went, so it is never taken for one. In the first and last three rows,
  which have one neighbour, a run beyond the limit from it is a spike too: a slip there is
  cut short by a few samples, a "Bad" last row would set the record's span.
- **Regular holds**: every value written k times because the export grid is k times finer
  than the historian's storage interval. The record then looks like a valve that sticks
  for k - 1 samples out of k; read every k-th row, it is the loop as stored. OP alone on
  such a grid is a controller running k times slower than the record, PV alone a tag
  logged slower than OP; read at that tag's rows, the loop is what the slower side saw.
- **Placeholders**: a stretch of "no data" written as a number (-9999, 1e30, 3.4e38)
  instead of text. Longer than a spike, it is a step out and back that no statistic
  survives (20 rows of -9999 in PV and OP turned a sticky loop at p 1.0 into "outside the
  model's domain"). It is read as a gap, which gap repair then bridges or leaves out.
- **OP out of step with PV**: OP and PV are separate tags, and an export or a simulator
  may put OP a sample early or late. A controller's output moves with the error it has
  seen, now and one sample before; OP one row early, reacting to an error one row ahead,
  made the PV-OP coupling test call 15-27 % of loops "unrelated" and blurred the valve
  fits. OP is moved back in line where its increments fit a controller's clearly better.
- **A start-up transient**: a simulator started from rest, or a record that begins as a
  loop settles after a trip, opens with an excursion beyond the range the rest of the
  record keeps, decaying within its first rows. Healthy loops read as sticky through it;
  its rows are dropped (a second simulator recorded from rest: 0.750 -> 0.807 with the
  same records). A sticky valve's first slip in a slowly cycling record can look alike
  and be dropped with it (5 of 2,000 default-world loops as recorded lose their start, 2
  of them sticky; no verdict changed).
- **Gaps**: NaN inside a record, bridged when short; past a long one the longest stretch
  is kept (:func:`~sktiction._validation.repair_gaps`).
- **Tags exported stepped**: a compressing historian (deadband or swinging door) stores a
  tag only when it has moved, and an export that holds each stored value until the next
  one moves PV and OP at times of their own. Sample by sample the loop then looks as if
  PV ignored OP, and OP's flat stretches pass for a stuck valve: the third simulator's
  stepped exports were judged at balanced accuracy 0.51 with a quarter refused, its
  interpolated exports of the same points at 0.57. Such a tag (held on a fifth of its
  steps and on a tenth of those where the other tag moves, over many runs each at a level
  of its own, its levels on no grid: :func:`exported_stepped`) is redrawn through its
  stored points, as an interpolated export shows it, runs at its extremes kept flat
  (:func:`~sktiction.cycles._signal.lines_through_changes`).
"""

from __future__ import annotations

import numpy as np

from ._validation import (
    check_loops,
    check_max_gap,
    gap_free_lengths,
    loop_lengths,
    repair_gaps,
)
from .cycles._repairs import placeholder_mask, replace_spikes
from .cycles._signal import (
    fast_percentile,
    lines_through_changes,
    on_grid_share,
    robust_spread,
    true_runs,
)

#: Fewest value changes from which a hold grid is believed (a chance alignment of 20
#: changes on one phase of 2 has probability 2e-6).
MIN_HOLD_CHANGES = 20
#: Fewest distinct values for one channel alone on a grid to be a slower tag's record.
_MIN_LEVELS = 8
#: A tag exported stepped repeats its last value on at least this share of its steps ...
_STEPPED_HELD = 0.2
#: ... and on at least this share of the steps in which the other tag moves (a historian
#: holding whole rows holds both at once) ...
_STEPPED_APART = 0.1
#: ... and its levels lie on no grid: at most this share of them are a whole number of
#: its smallest jump from the first (a quantised tag's all are) ...
_STEPPED_ON_GRID = 0.5
#: ... over at least this many changes, ...
_STEPPED_CHANGES = 10
#: ... with no one run holding more than this share of the held steps, ...
_STEPPED_LONGEST = 0.5
#: ... and at most this share of its runs held at a level an earlier run held.
_STEPPED_REVISITS = 0.5


def remove_spikes(loop, n):
    """Replace the spikes of each channel of one loop (first ``n`` samples) by a straight
    line between their neighbours, in place; returns how many samples were replaced."""
    return sum(int(replace_spikes(loop[:n, c]).sum()) for c in range(loop.shape[1]))


def remove_placeholders(loop, n):
    """Set the placeholders (:func:`placeholder_mask`) of each channel of one loop (first
    ``n`` samples) to NaN, in place; returns how many samples were set."""
    count = 0
    for c in range(loop.shape[1]):
        mask = placeholder_mask(loop[:n, c])
        if mask.any():
            loop[:n, c][mask] = np.nan
            count += int(mask.sum())
    return count


def hold_step(loop, n):
    """``(k, phase)`` when every channel of one loop, or else OP alone, or else PV alone,
    changes value only on rows ``phase + j * k`` (2 <= k <= 60; at least 98 % of
    :data:`MIN_HOLD_CHANGES` or more changes; one channel alone with at least
    :data:`_MIN_LEVELS` values), else ``(1, 0)``: the largest such k.

    One tag on such a grid is recorded or computed k times slower than the record: OP, a
    controller slower than the record (a simulation logged at its fine step, a DCS block
    scanned slower than the historian logs); PV, a tag logged or measured slower (an
    analyser). Read at that tag's rows, the loop is what the slower side saw; as recorded,
    a held PV beside a moving OP looks like a stuck valve. On 300 of the second simulator's
    loops (benchmarks/sampling_rate.py) OP held 5 rows had taken the default model from
    0.807 to 0.727 (read at OP's rows, 0.803), PV held 3 rows to 0.68 (read, 0.82). No
    loop of 400 held-out default-world or classic-world loops, 400 second-simulator loops,
    56 measured windows or the default model's 1,421 training loops has such a grid.
    """
    step = _hold_grid(loop[:n])
    for c in (1, 0):  # OP alone, then PV alone
        if step[0] == 1:
            step = _hold_grid(loop[:n, c : c + 1])
            if step[0] > 1 and np.unique(loop[:n, c]).size < _MIN_LEVELS:
                step = 1, 0  # two levels on a grid: an on/off output or a square wave
    return step


def _hold_grid(x):
    """:func:`hold_step` of the channels of ``x`` (samples, channels) together."""
    n = len(x)
    if _changed_rows(x[:400]).sum() > 0.51 * min(n, 400):  # most records change on most rows
        return 1, 0
    rows = np.flatnonzero(_changed_rows(x)) + 1
    if rows.size < MIN_HOLD_CHANGES or rows.size > 0.51 * n:  # a hold of 2 changes <= n / 2
        return 1, 0
    for k in range(min(60, n // rows.size + 1), 1, -1):  # k rows per value: <= n / changes
        counts = np.bincount(rows % k, minlength=k)
        if counts.max() >= 0.98 * rows.size:
            return k, int(np.argmax(counts))
    return 1, 0


def _changed_rows(x):
    """Whether some channel of ``x`` (samples, channels) takes a new value at each row
    after the first (NaN: no value, so no change)."""
    d = np.diff(x, axis=0)
    return ((d != 0) & ~np.isnan(d)).any(axis=1)


#: Rows by which OP may be moved to line up with PV: one historian scan either way. Two
#: rows back fitted a plant's answer to OP as well as a controller's output in 1.25 % of
#: loops recorded in step (a filtered PV), and were not kept.
OP_SHIFTS = (-1, 0, 1)
#: How much better (times the R^2 as recorded) a shifted OP must fit a controller's
#: increments to be moved: set on simulated loops; it moves none of 400 held-out loops
#: recorded in step (10 of the 1,500 the default model learns from) and 62-72 % of
#: those with OP a row out of step.
_SHIFT_MARGIN = 1.5
#: Least R^2 of a shifted fit to be believed: below it OP hardly follows the error at all.
_SHIFT_MIN_R2 = 0.05


def _controller_r2(pv, op, sp, has_sp):
    """R^2 of OP's increments on the control error now and one row before (a PI
    controller's velocity form), over rows where all are finite; NaN if too few. The
    error is ``SP - PV`` when the loop has a setpoint (decided once for all shifts, so
    that their R^2 compare), else PV about its mean."""
    err = sp - pv if has_sp else -(pv - np.nanmean(pv))
    y, e0, e1 = np.diff(op), err[1:], err[:-1]
    ok = np.isfinite(y) & np.isfinite(e0) & np.isfinite(e1)
    if not ok.all():
        y, e0, e1 = y[ok], e0[ok], e1[ok]
    if y.size < 30 or np.ptp(y) == 0:
        return np.nan
    # least squares with an intercept from centred sums: a 2 x 2 solve, no design matrix
    y, e0, e1 = y - y.mean(), e0 - e0.mean(), e1 - e1.mean()
    gram = np.array([[e0 @ e0, e0 @ e1], [e0 @ e1, e1 @ e1]])
    rhs = np.array([e0 @ y, e1 @ y])
    sst = float(y @ y)
    try:
        coef = np.linalg.solve(gram, rhs)
    except np.linalg.LinAlgError:  # a constant or perfectly repeating error
        return 0.0
    return float(coef @ rhs) / sst


#: PV and OP swapped (:func:`looks_swapped`): PV this many of its spreads off the setpoint,
#: OP within this share of its spread of it, OP's spread under this share of PV's distance.
_SWAP_PV_OFF, _SWAP_OP_NEAR, _SWAP_OP_SPREAD = 2.0, 0.5, 0.25


def looks_swapped(pv, op, sp):
    """Whether PV and OP are swapped: OP tracks the setpoint, PV does not, and the
    record reads as a controller's the other way round.

    Integral action keeps PV's median at the setpoint's, so PV more than
    ``_SWAP_PV_OFF`` of its spreads away says PV is not the controlled variable; OP
    within ``_SWAP_OP_NEAR`` of its spread of SP, its whole spread under
    ``_SWAP_OP_SPREAD`` of PV's distance, says OP is. Those alone also fit a loop off
    its setpoint whose OP sits at the setpoint's value by chance (a P-only level loop
    at its bias, a loop in manual at a round 50 %, a saturated one): so the increments
    of the channel recorded as PV must also fit a PI controller's velocity form on the
    error ``SP - OP`` (:func:`_controller_r2`, at least :data:`_SHIFT_MIN_R2`) better than
    OP's fit on ``SP - PV``. Asking more (1.1 or 1.5 times better, as :func:`op_shift`
    does) lost a third to four fifths of the swaps found: a plant's answer to OP fits a
    controller's form almost as well. So a P-only loop whose OP sits at the setpoint's
    value by chance and is recorded with noise of its own can still read as swapped. A
    setpoint exported in OP's units (% of range) beside a PV in engineering units is not
    a swap: OP still fits a controller on ``SP - PV`` (an offset in the error changes
    no increment), and a verdict reads the loop's dynamics, not its setpoint's units.

    Parameters
    ----------
    pv, op, sp : ndarray of shape (n_samples,)
        One loop's record as given, without NaN.

    Returns
    -------
    swapped : bool

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._cleaning import looks_swapped
    >>> rng = np.random.default_rng(0)
    >>> pv, op, sp = np.full(1000, 120.0), np.full(1000, 35.0), np.full(1000, 120.0)
    >>> load = np.cumsum(rng.normal(0, 0.05, 1000))  # a flow at 120 m3/h, valve 35 % open
    >>> for t in range(1, 1000):                     # a PI controller rejects the load
    ...     pv[t] = 120 + load[t] + 0.5 * (op[t - 1] - 35) + rng.normal(0, 0.2)
    ...     e, e1 = sp[t] - pv[t], sp[t - 1] - pv[t - 1]
    ...     op[t] = op[t - 1] + 0.8 * (e - e1) + 0.1 * e
    >>> looks_swapped(pv, op, sp), looks_swapped(op, pv, sp)
    (False, True)
    """
    pv_off = abs(np.median(sp - pv))
    if not pv_off > _SWAP_PV_OFF * robust_spread(pv):  # PV at its setpoint: most loops stop here
        return False
    op_spread = robust_spread(op)
    if not (op_spread < _SWAP_OP_SPREAD * pv_off
            and abs(np.median(sp - op)) < _SWAP_OP_NEAR * op_spread):  # fmt: skip
        return False
    as_given = np.nan_to_num(_controller_r2(pv, op, sp, True))  # NaN: too few rows
    exchanged = _controller_r2(op, pv, sp, True)
    # a tie (a P-only controller fits exactly both ways) is no evidence of a swap
    return bool(exchanged >= _SHIFT_MIN_R2 and exchanged > as_given + 1e-6)


def _rows(loop, n, s):
    """``PV[t], OP[t + s], SP[t]`` (views) over the first ``n`` rows where both exist."""
    a, b = max(0, -s), n - max(0, s)
    return loop[a:b, 0], loop[a + s : b + s, 1], loop[a:b, 2]


def _paired(loop, n, s):
    """The loop as rows ``PV[t], OP[t + s], SP[t]`` (a copy)."""
    return np.column_stack(_rows(loop, n, s))


def op_shift(loop, n):
    """Rows by which OP leads PV in ``loop`` (first ``n`` rows; channels PV, OP, SP), or 0.

    The shift whose OP increments a PI controller's velocity form explains best, when
    it explains them at least :data:`_SHIFT_MARGIN` times better than OP as recorded.
    """
    if n < 60:
        return 0
    has_sp = bool(np.isfinite(loop[:n, 2]).any())
    r2 = np.array([_controller_r2(*_rows(loop, n, s), has_sp) for s in OP_SHIFTS])
    if np.isnan(r2).all():
        return 0
    best = OP_SHIFTS[int(np.nanargmax(r2))]
    top, now = np.nanmax(r2), np.nan_to_num(r2[OP_SHIFTS.index(0)])
    return best if top >= _SHIFT_MIN_R2 and top > _SHIFT_MARGIN * max(now, 0.0) else 0


def put_record(loops, i, rows):
    """Loop ``i`` of ``loops`` becomes ``rows`` (at most as long), NaN-padded, in place."""
    loops[i] = np.nan
    loops[i, : len(rows)] = rows


def align_op(loops, lengths):
    """``loops`` with each OP moved in line with its PV (:func:`op_shift`), and the shifts.

    Returns a new NaN-padded array of the same shape (a moved loop is ``|shift|`` rows
    shorter) and the shift of each loop; ``loops`` itself is left as it is.
    """
    shifts = np.array([op_shift(loops[i], int(n)) for i, n in enumerate(lengths)])
    if not shifts.any():
        return loops, shifts
    out = np.array(loops, dtype=float)
    for i in np.flatnonzero(shifts):
        n = int(lengths[i])
        put_record(out, i, _paired(loops[i], n, int(shifts[i])))
    return out, shifts


#: Share of a record searched for a start-up transient; the rest sets the record's range.
STARTUP_HEAD = 0.2
#: The transient's rows: beyond the rest's 0.5-99.5 % range by more than this share of it.
_STARTUP_OUT = 0.5
#: ... reaching beyond it by more than the whole range at least once,
_STARTUP_PEAK = 1.0
#: ... starting within this share of the record and over within the next.
_STARTUP_BEGINS, _STARTUP_ENDS = 0.03, 0.05
#: Rows dropped per row of the excursion: its tail settles inside the range.
_STARTUP_TAIL = 2
#: Most rows dropped, as a share of the record.
MAX_STARTUP_SHARE = 0.1


def startup_rows(loop, n):
    """Rows of a start-up transient at the beginning of ``loop`` (first ``n`` rows), or 0.

    A transient is a PV or OP excursion beyond the range the record keeps after its
    first fifth (0.5-99.5 %) by more than half that range, reaching more than a whole
    range beyond it, which begins in the first 3 % of the rows and is over by 5 %. Twice
    its rows are dropped (the tail settles inside the range), at most a tenth of the
    record. Rows across which a recorded setpoint moves by more than half PV's range are
    a setpoint response, which is operation, and are kept (without a setpoint channel
    such a response cannot be told from a transient).
    """
    head = int(STARTUP_HEAD * n)
    if head < 10:
        return 0
    last, pv_range = -1, np.nan
    for c in (0, 1):
        x = loop[:n, c]
        if not np.isfinite(x).all():
            return 0
        lo, hi = fast_percentile(x[head:], [0.5, 99.5])
        if c == 0:
            pv_range = hi - lo
        if not hi > lo:
            continue
        excess = np.maximum(lo - x[:head], x[:head] - hi) / (hi - lo)
        out = np.flatnonzero(excess > _STARTUP_OUT)
        if (out.size and out[0] <= _STARTUP_BEGINS * n and out[-1] <= _STARTUP_ENDS * n
                and excess.max() > _STARTUP_PEAK):  # fmt: skip
            last = max(last, int(out[-1]))
    if last < 0:
        return 0
    rows = min(_STARTUP_TAIL * (last + 1), int(MAX_STARTUP_SHARE * n))
    sp = loop[: rows + 1, 2]
    if np.isfinite(sp).any() and np.nanmax(sp) - np.nanmin(sp) > 0.5 * pv_range:
        return 0
    return rows


def drop_startup(loops, lengths):
    """``loops`` without the rows of their start-up transients (:func:`startup_rows`),
    and those rows per loop. A new array when any loop changes; ``loops`` is left as is."""
    rows = np.array([startup_rows(loops[i], int(n)) for i, n in enumerate(lengths)])
    if not rows.any():
        return loops, rows
    out = np.array(loops, dtype=float)
    for i in np.flatnonzero(rows):
        put_record(out, i, loops[i, rows[i] : int(lengths[i])])
    return out, rows


def in_step(loops, align=True):
    """Checked, repaired ``loops`` without start-up transients (:func:`drop_startup`),
    then with OP in line with PV (:func:`align_op`; not without ``align``): the loops,
    the rows dropped and the OP shifts. The last steps of reading a loop, shared by
    scans and classifiers."""
    lengths = loop_lengths(loops)
    loops, startup = drop_startup(loops, lengths)
    if not align:
        return loops, startup, np.zeros(len(loops), dtype=int)
    # a loop whose start was dropped had PV on every row: it is that much shorter
    loops, shifts = align_op(loops, lengths - startup)
    return loops, startup, shifts


#: What input repair (:func:`repaired`) reports per loop: gap repair's
#: (:func:`~sktiction._validation.repair_gaps`; ``kept_start``, ``kept_stop`` index the
#: input's rows), spike samples replaced, rows per stored value (a regular hold undone),
#: placeholder samples read as gaps and tags redrawn through their stored points.
GAP_COLUMNS = (
    "n_bridged", "n_gaps_split", "kept_start", "kept_stop", "n_spikes", "rows_per_value",
    "n_placeholders", "stepped_tags",
)  # fmt: skip


def exported_stepped(x, other):
    """Whether tag ``x`` (1-D, finite) was exported stepped by a compressing historian,
    next to ``other``, the loop's other tag (same length): held on a fifth of its steps
    and on a tenth of those in which ``other`` moves, over many runs (no one run holds half
    of the held steps: a manual stretch is not an export), each run at a level of its own
    (a noise-free square cycle holds a few in turn), its levels on no grid (a quantised
    tag's are a whole number of grid steps apart).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction._cleaning import exported_stepped
    >>> rng = np.random.default_rng(0)
    >>> walk = np.cumsum(rng.normal(size=400))
    >>> stepped = np.repeat(walk[::4], 4)  # each stored value held for 4 rows
    >>> bool(exported_stepped(stepped, walk)), bool(exported_stepped(walk, stepped))
    (True, False)
    >>> bool(exported_stepped(np.round(stepped), walk))  # on a grid of 1: quantised
    False
    """
    held = np.diff(x) == 0
    if held.mean() < _STEPPED_HELD:
        return False
    other_moves = np.diff(other) != 0
    if not other_moves.any() or held[other_moves].mean() < _STEPPED_APART:
        return False
    jumps = np.abs(np.diff(x))[~held]
    if jumps.size < _STEPPED_CHANGES:
        return False
    # one stretch held for most of the record (manual mode, a trip) is no export's doing
    starts, stops = true_runs(held)
    if np.max(stops - starts) > _STEPPED_LONGEST * held.sum():
        return False
    # each run held at a level of its own: a noise-free square cycle holds a few in turn
    run_levels = x[starts]
    if 1.0 - np.unique(run_levels).size / run_levels.size > _STEPPED_REVISITS:
        return False
    levels = x[1:][~held]
    return on_grid_share(levels - levels[0], jumps.min()) <= _STEPPED_ON_GRID


def _redraw_stepped(loops, idx):
    """Redraw, in place, the PV and OP of loops ``idx`` that were exported stepped
    (:func:`exported_stepped`) as lines through their stored points, runs at a tag's
    lowest or highest value kept flat; the number of tags redrawn per loop (0-2)."""
    counts = np.zeros(len(idx))
    for j, (i, n) in enumerate(zip(idx, loop_lengths(loops[idx]))):
        pv, op = loops[i, :n, 0], loops[i, :n, 1]
        if n < 3 or not (np.isfinite(pv).all() and np.isfinite(op).all()):
            continue
        stepped = exported_stepped(pv, op), exported_stepped(op, pv)
        for channel, redraw in enumerate(stepped):
            if redraw:
                # runs at the extremes stay flat: a saturated OP is no export's doing
                loops[i, :n, channel] = lines_through_changes(loops[i, :n, channel], True)
        counts[j] = sum(stepped)
    return counts


def _undo_artefacts(loops, idx, lengths):
    """Undo regular holds, remove spikes and read placeholders as gaps in loops ``idx``
    (of ``lengths`` samples), in place. Returns rows per value, the hold grid's phase,
    spike and placeholder samples per loop. Spikes go first: a lone -9999 is a spike,
    replaced by a line, not a gap."""
    out = np.zeros((len(idx), 4), dtype=int)
    for j, (i, n) in enumerate(zip(idx, lengths)):
        step, phase = hold_step(loops[i], n)
        if step > 1:  # each value written ``step`` times: read the rows as stored
            rows = loops[i, phase:n:step].copy()
            put_record(loops, i, rows)
            n = len(rows)
        spikes = remove_spikes(loops[i], n)
        out[j] = step, phase, spikes, remove_placeholders(loops[i], n)
    return out


def repaired(loops, max_gap, usable=None):
    """Loops as they are read before any analysis, and what was done, one row of
    :data:`GAP_COLUMNS` per loop (NaN where nothing was looked at). Both scans and every
    classifier (:func:`as_judged`) repair this way:

    1. a regular hold (every value on ``k`` rows: an export grid finer than the stored
       data; or one tag's alone, :func:`hold_step`) is read every ``k``-th row (the
       sample time is then ``k`` times longer);
    2. spikes (1-3 samples far from both neighbours) are replaced by a straight line;
    3. placeholders for missing data written as numbers (-9999 for a stretch) become gaps;
    4. short gaps are bridged and the longest stretch kept
       (:func:`~sktiction._validation.repair_gaps`);
    5. a tag exported stepped by a compressing historian is redrawn through its stored
       points (:func:`exported_stepped`).

    Loops that hold inf (they get not_finite) or are not ``usable`` are left as they are;
    gap-free loops skip ``repair_gaps`` with the answer it would give.
    """
    loops = np.array(loops, dtype=float)  # a copy: spikes are replaced in place
    n, m, k = loops.shape
    if k < 3:
        loops = np.concatenate([loops, np.full((n, m, 3 - k), np.nan)], axis=2)
    gaps = np.full((n, len(GAP_COLUMNS)), np.nan)
    ok = ~np.isinf(loops).any(axis=(1, 2))
    idx = np.flatnonzero(ok if usable is None else ok & usable)
    if not idx.size:
        return loops, gaps
    lengths_in = loop_lengths(loops[idx])
    step, phase, spikes, placeholders = _undo_artefacts(loops, idx, lengths_in).T
    lengths = gap_free_lengths(loops[idx])
    if lengths is not None:  # most records: what repair_gaps would say, without its work
        info = {"n_bridged": 0, "n_gaps_split": 0, "kept_start": 0, "kept_stop": lengths}
    else:
        fixed, info = repair_gaps(loops[idx], max_gap=max_gap)
        loops[idx] = fixed[:, :m]
    for j, col in enumerate(GAP_COLUMNS[:4]):
        gaps[idx, j] = np.asarray(info[col], dtype=float)
    # the kept stretch in the input's rows, where each row read stands for its block of
    # ``step`` rows (the rows before the first whole block hold the value before it)
    start, stop = gaps[idx, 2], gaps[idx, 3]
    gaps[idx, 2] = np.where(start > 0, phase + step * start, 0)
    gaps[idx, 3] = np.where(stop > start, np.minimum(phase + step * stop, lengths_in),
                            gaps[idx, 2])
    gaps[idx, 4], gaps[idx, 5], gaps[idx, 6] = spikes, step, placeholders
    gaps[idx, 7] = _redraw_stepped(loops, idx)
    return loops, gaps


def clean_loops(X, *, max_gap="auto", align=True):
    """Loops as a scan and every classifier read them, and what was done to each.

    The repairs a file scan makes before any analysis, for loops you hold in memory
    (to fit :class:`~sktiction.LearnedStictionClassifier` on measured loops, to look at
    what a classifier saw, or to store cleaned records):

    1. a regular hold (each stored value written on ``k`` rows: an export grid finer
       than the historian's storage, a controller or PV tag logged slower than the
       record) read one row in ``k``;
    2. spikes of 1-3 samples replaced by a straight line;
    3. placeholders for missing data written as numbers (-9999 for a stretch) read as gaps;
    4. short gaps bridged and, past a long one, the longest stretch kept;
    5. PV or OP exported stepped by a compressing historian (held on many rows, moving
       at times of its own, its levels on no grid) redrawn as straight lines through
       the stored points, as an interpolated export shows them;
    6. a start-up transient dropped: an excursion of PV or OP at the record's start,
       beyond the 0.5-99.5 % range of the rest by more than that range and over within
       the first 5 % of the rows, as in a simulator started from rest (at most a tenth
       of the record; kept when a recorded setpoint moves across those rows, as in a
       setpoint response);
    7. with ``align``, OP moved one row back in line with PV where its increments fit a
       controller's clearly better that way. One row at most: an OP one row out of step
       is moved back, and a second call leaves it; one two or more rows out is not
       reliably aligned.

    Every scan and every classifier's ``predict``, ``predict_proba`` and ``diagnose``
    make these repairs themselves: the loops returned are what they read. The learned
    model's ``fit`` does not (it repairs gaps only): clean measured loops with this
    before fitting on them.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP, NaN-padded at the end.
    max_gap : "auto" or int, default="auto"
        Longest gap bridged, in samples (``0``: none; the longest stretch without gaps is
        kept); ``"auto"`` as :func:`sktiction.reports.scan_loops` reads it: per loop, a gap
        whose bridge spans at most 1/16 of PV's period, at most 5 % of the record.
    align : bool, default=True
        Move OP in line with PV (step 7).

    Returns
    -------
    loops : ndarray of shape (n_loops, n_samples, 3)
        The cleaned loops, NaN-padded at the end (a loop read one row in ``k`` or cut to
        its longest stretch is shorter); ``X`` itself is not changed.
    report : pandas.DataFrame
        One row per loop: ``n_bridged``, ``n_gaps_split``, ``kept_start`` and
        ``kept_stop`` (the stretch gap repair kept, in ``X``'s rows; moving OP leaves
        out one more row at one end), ``n_spikes`` (samples
        replaced, all channels), ``rows_per_value`` (``k``; 1 when nothing was held),
        ``n_placeholders``, ``stepped_tags`` (PV and OP redrawn: 0-2), ``startup_rows``
        (rows of a start-up transient dropped from the start, counted after a hold is
        undone: rows as read, each ``k`` of
        ``X``'s; 0 when none) and ``op_shift`` (rows OP was moved; 0 when not).

    Raises
    ------
    ValueError, TypeError
        On input that is not loops (see :func:`sktiction.reports.scan_loops` for a
        per-loop status instead).

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction import clean_loops
    >>> t = np.arange(600)
    >>> loop = np.column_stack([np.sin(t / 9), np.cos(t / 9), np.zeros(600)])
    >>> loop[300, :2] = -9999.0  # a "Bad" value written as a number, in PV and OP
    >>> loops, report = clean_loops(loop[None])
    >>> bool(np.abs(loops[0, :, :2]).max() <= 1.0), report.loc[0, "n_spikes"].item()
    (True, 2)
    """
    import pandas as pd

    check_max_gap(max_gap)
    loops, done, startup, shifts = _repaired_in_step(check_loops(X), max_gap, align)
    # check_loops refused inf, so every loop was looked at: whole counts
    report = pd.DataFrame(done.astype(int), columns=list(GAP_COLUMNS))
    report["startup_rows"] = startup
    report["op_shift"] = shifts
    return loops, report


def _repaired_in_step(loops, max_gap, align=True):
    """:func:`repaired`, then :func:`in_step` (without ``align``, OP stays where it is):
    the loops, what the repair did, the start-up rows dropped and the OP shifts. What
    :func:`clean_loops` and :func:`as_judged` read."""
    loops, done = repaired(loops, max_gap)
    loops, startup, shifts = in_step(loops, align)
    return loops, done, startup, shifts


def as_judged(loops, *, training=False):
    """Checked ``loops`` as every classifier reads them, as a file scan does.

    :func:`repaired` with ``max_gap="auto"`` (a regular hold read one row in k, spikes
    replaced, placeholders read as gaps, short gaps bridged and, past a long one, the
    longest stretch kept: two glitches per loop had left the learned model 4 % of its
    verdicts, one lost sample a loop its verdict), then a start-up transient dropped and
    each OP moved in line with its PV (:func:`in_step`). ``loops`` itself is left as it is.

    With ``training``, only gaps are repaired and stepped exports redrawn: simulated
    training loops are otherwise read as made. In the default model's 1,420 the spike rule
    finds a spike in 7 and the alignment would move 10, none of them real. Stepped tags
    are redrawn in training too, so that the model learns compressed loops as it reads
    them.
    """
    if training:
        loops = loops if gap_free_lengths(loops) is not None else repair_gaps(loops)[0]
        redrawn = np.array(loops, dtype=float)
        return redrawn if _redraw_stepped(redrawn, np.arange(len(loops))).any() else loops
    return _repaired_in_step(loops, "auto")[0]
