"""Oscillation detection, zero crossings, half and full cycles, and where the signal oscillates."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numba import njit
from scipy.fft import irfft
from scipy.special import bdtrc

from ._level_shifts import read_without_shifts
from ._oscillation import MAX_CONFIRMATION, SCORE_SCALE, _components, _power_spectrum
from ._repairs import one_signal
from ._signal import (
    dominant_period,
    fast_median,
    fast_percentile,
    first_lobe,
    moving_average,
    noise_std,
    remove_mean,
    schmitt_crossings,
    true_runs,
    unit_scaled,
)

#: Thornhill et al. (2003): an oscillation is regular when the mean interval between
#: alternate zero crossings exceeds three times its standard deviation (r > 1).
REGULARITY_THRESHOLD = 1.0
#: Score (see :func:`~sktiction.cycles.detect_oscillations`) added to a component when
#: the time-domain cycles of its period are regular (r > 1) and the first ACF peak of
#: the signal exceeds :data:`CONFIRM_ACF`: two independent readings of one cycle.
CYCLE_EVIDENCE = 0.5
#: Score added instead when those cycles are lopsided (:func:`_lopsided`), a rarer sight
#: in noise than the ACF gate. On the oscillation benchmark's records with regular cycles
#: (seeds 3 and 4, 300 per class, a one-off count) the gate passed 4.8-5.6 % of the quiet
#: classes' readings and 76-79 % of the saw-teeth's and pulse trains', the lopsided test
#: 1.7-2.0 % and 87-88 %: a likelihood ratio 2.7-3.8 times the gate's, 0.20-0.26 more
#: score (SCORE_SCALE times its log); hence 0.5 + 0.2. It is the most the confirmation
#: adds (:data:`~sktiction.cycles._oscillation.MAX_CONFIRMATION`): the detector prunes
#: peaks that could not reach the threshold even with it.
LOPSIDED_EVIDENCE = MAX_CONFIRMATION
CONFIRM_ACF = 0.2
#: Lopsided cycles confirm instead of the ACF (see :func:`_lopsided`): a sign test of
#: the cycles' fall shares, or of their shares above the mean, against one half, each at
#: this two-sided level, ...
LOPSIDED_LEVEL = 0.05
#: ... with the median share more than this far from one half.
LOPSIDED_MARGIN = 0.1
#: Cycles are read about the middle of their swing (halfway between these percentiles
#: of the signal less its moving mean) instead of their mean ...
SWING_PERCENTILE = 5.0
#: ... when the two lie more than this share of the swing apart: a cycle lopsided in
#: level, not a symmetric one whose middle differs from its mean by noise alone.
MIDDLE_SHIFT = 0.03
#: Cycles lopsided in level confirm only on a record whose level is bimodal: Sarle's
#: bimodality coefficient above that of a uniform distribution (see :func:`_bimodal`).
BIMODAL = 5 / 9


@dataclass
class CycleAnalysis:
    """What :func:`analyze_cycles` found in one signal.

    Attributes
    ----------
    centred : ndarray
        The signal with its moving mean removed (and the middle of its swing, for
        cycles lopsided in level: see :func:`analyze_cycles`).
    smooth : ndarray
        ``centred`` lightly smoothed (used for crossings and peaks).
    crossings : ndarray of float
        Fractional sample indices of the confirmed zero crossings.
    signs : ndarray of int
        Sign entered at each crossing (+1: the half-cycle after it is positive).
    peaks : ndarray of int
        Index of the extreme of each half-cycle (between crossings k and k+1).
    cycles : ndarray of shape (n_cycles, 3)
        Full cycles in the oscillating stretches: crossing numbers (k, k+1, k+2).
    segments : list of (int, int)
        Sample ranges [start, end) that oscillate.
    period : float
        Median full-cycle period in samples (NaN when there is none).
    regularity : float
        Thornhill's regularity factor r of the full-cycle periods.
    acf_strength : float
        Height of the first ACF peak (0-1).
    oscillating : bool
        Whether the signal oscillates: some component of
        :func:`~sktiction.cycles.detect_oscillations` has an index above 0.5 (after
        the time-domain confirmation described in :func:`analyze_cycles`).
    oscillation_index : float
        Largest index of the components (0-1; 0.5 is the decision threshold).
    periods : ndarray of float
        Period (samples) of each oscillating component, strongest first.
    regularities : ndarray of float
        Thornhill's regularity r of each oscillating component's ACF zero crossings.
    components : list of OscillationComponent
        All components examined, oscillating or not, strongest index first.
    level_shifts : ndarray of int
        Samples where a level shift (an operator move, a load change) was taken out
        before the signal was read (see :func:`analyze_cycles`); empty when the record
        was read as it is. ``centred`` is then the record without them.
    fall_share : float
        How long the cycles fall: for each full cycle in segments, the time from its
        maximum to the minimum that follows as a share of the time to the next
        cycle's first extreme; the median over the cycles. About 0.5 for a symmetric
        cycle (a sine, a triangle, a square wave), near 0 or 1 for a saw-tooth,
        whose slip is fast; NaN when no cycle is followed by an extreme in the record.
    above_share : float
        How long the cycles stay above zero in ``centred``: for each full cycle in
        segments, its positive half's duration as a share of the cycle's; the median
        over the cycles. About 0.5 for a cycle as long above its mean as below (a sine,
        a triangle, a saw-tooth, a square wave), further from it for a pulse train or a
        valve that dwells longer on one side; NaN when there is no cycle.
    """

    centred: np.ndarray
    smooth: np.ndarray
    crossings: np.ndarray
    signs: np.ndarray
    peaks: np.ndarray
    cycles: np.ndarray = field(default_factory=lambda: np.empty((0, 3), dtype=int))
    segments: list = field(default_factory=list)
    period: float = np.nan
    regularity: float = np.nan
    acf_strength: float = 0.0
    oscillating: bool = False
    oscillation_index: float = 0.0
    periods: np.ndarray = field(default_factory=lambda: np.empty(0))
    regularities: np.ndarray = field(default_factory=lambda: np.empty(0))
    components: list = field(default_factory=list)
    level_shifts: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=int))
    fall_share: float = np.nan
    above_share: float = np.nan

    @property
    def half_cycles(self):
        """Half-cycles as rows (start, end) of fractional sample indices."""
        return np.column_stack([self.crossings[:-1], self.crossings[1:]])

    def __repr__(self):
        # the decision and what it rests on; the arrays are attributes, not a wall of numbers
        return (f"CycleAnalysis(oscillating={self.oscillating}, "
                f"oscillation_index={self.oscillation_index:.3f}, "
                f"periods={np.round(self.periods, 1).tolist()}, n_cycles={len(self.cycles)}, "
                f"period={self.period:.1f}, regularity={self.regularity:.2f}, "
                f"n_samples={self.centred.size}"
                + (f", level_shifts={self.level_shifts.tolist()}" if self.level_shifts.size
                   else "") + ")")  # fmt: skip


def _regular_runs(periods, tolerance):
    """Runs ``(start, stop)`` of consecutive cycles whose period is regular.

    A cycle is regular when its period lies within ``tolerance`` of the median of
    its neighbourhood (itself and two cycles either side), so slow changes of the
    period are followed while the random intervals of noise break the run.
    """
    n = len(periods)
    if n == 0:
        return []
    if n < 3:
        local = np.full(n, np.median(periods))
        regular = np.abs(periods - local) <= tolerance * local
        return list(zip(*true_runs(regular)))
    # reflect, so a stray first or last cycle is judged by its neighbours
    runs = _runs_of_regular(np.asarray(periods, dtype=float), float(tolerance))
    return [(int(a), int(b)) for a, b in runs]


@njit(cache=True, nogil=True)
def _runs_of_regular(periods, tolerance):
    """:func:`_regular_runs` of three or more periods: the median of five (reflected
    at the ends) is the middle of the five sorted, the value ``np.median`` gives."""
    n = periods.size
    padded = np.empty(n + 4)
    padded[2 : n + 2] = periods
    padded[0], padded[1] = periods[2], periods[1]
    padded[n + 2], padded[n + 3] = periods[n - 2], periods[n - 3]
    runs = np.empty((n, 2), dtype=np.int64)
    n_runs = 0
    inside = False
    for i in range(n):
        window = np.sort(padded[i : i + 5])
        local = 0.0 + window[2]
        if np.isnan(window).any():
            local = np.nan
        regular = abs(periods[i] - local) <= tolerance * local
        if regular and not inside:
            runs[n_runs, 0] = i
            inside = True
        elif not regular and inside:
            runs[n_runs, 1] = i
            n_runs += 1
            inside = False
    if inside:
        runs[n_runs, 1] = n
        n_runs += 1
    return runs[:n_runs]


@njit(cache=True, nogil=True)
def _median(x):
    """``np.median`` of a 1-D array (sorted middle, or the mean of the two middles)."""
    n = x.size
    if n == 0 or np.isnan(x).any():
        return np.nan
    s = np.sort(x)
    if n % 2:  # numpy's mean of the middle one or two: a sum from 0.0, then divided
        return 0.0 + s[n // 2]
    return (0.0 + s[n // 2 - 1] + s[n // 2]) / 2.0


@njit(cache=True, nogil=True)
def _peaks(centred, smooth, crossings, signs, width):
    """Extreme of each half-cycle: located on the smoothed signal, refined on the raw one.

    Smoothing keeps a noise spike from being taken for the peak, but it also moves a
    sharp, lopsided peak (the cusp of a stiction cycle) towards the flatter side; the
    raw extreme within one smoothing width of the smoothed one puts it back.
    """
    out = np.empty(max(crossings.size - 1, 0), dtype=np.int64)
    for k in range(out.size):
        a = int(np.ceil(crossings[k]))
        b = min(int(np.floor(crossings[k + 1])), smooth.size - 1)
        s = signs[k]
        p = a
        for i in range(a, b + 1):
            if s * smooth[i] > s * smooth[p]:
                p = i
        lo, hi = max(a, p - width), min(b, p + width)
        q = lo
        for i in range(lo, hi + 1):
            if s * centred[i] > s * centred[q]:
                q = i
        out[k] = q
    return out


def _segments(centred, crossings, peaks, kept):
    """Sample ranges covered by the kept full cycles, widened by one half-cycle at each
    end when that half swings like the stretch's own (at least half its median peak and
    at most 1.5 times its median duration): an oscillation seldom starts or stops on
    a zero crossing, and the partial cycle at its edge belongs to it."""
    bounds = _segment_bounds(centred, crossings, peaks, np.asarray(kept, dtype=np.int64))
    return [(int(a), int(b)) for a, b in bounds]


@njit(cache=True, nogil=True)
def _segment_bounds(centred, crossings, peaks, kept):
    """:func:`_segments` as an array of rows ``(start, end)``."""
    first_of = np.empty(kept.size, dtype=np.int64)
    last_of = np.empty(kept.size, dtype=np.int64)
    n_runs = 0
    for k in kept:  # group the kept cycles into runs of consecutive crossings
        if n_runs and k <= last_of[n_runs - 1]:
            last_of[n_runs - 1] = k + 2
        else:
            first_of[n_runs], last_of[n_runs] = k, k + 2
            n_runs += 1
    height = np.abs(centred[peaks])
    durations = crossings[1:] - crossings[:-1]
    out = np.empty((n_runs, 2), dtype=np.int64)
    for r in range(n_runs):
        first, last = first_of[r], last_of[r]
        ref_h, ref_d = _median(height[first:last]), _median(durations[first:last])
        start, end = crossings[first], crossings[last]
        if first > 0 and height[first - 1] >= 0.5 * ref_h and durations[first - 1] <= 1.5 * ref_d:
            start = crossings[first - 1]
        if last < peaks.size and height[last] >= 0.5 * ref_h and durations[last] <= 1.5 * ref_d:
            end = crossings[last + 1]
        out[r, 0] = int(np.floor(start))
        out[r, 1] = int(np.ceil(end)) + 1
    return out


def _fall_shares(peaks, signs, kept):
    """Share of each kept full cycle (crossings k, k+1, k+2) spent falling: the time
    from its maximum to the minimum that follows, over the time from its first extreme
    to the next cycle's first. A cycle whose next extreme the record does not hold is
    left out."""
    kept = np.asarray(kept, dtype=np.intp)
    k = kept[kept + 2 < peaks.size]
    rise_or_fall = (peaks[k + 1] - peaks[k]).astype(float)
    total = (peaks[k + 2] - peaks[k]).astype(float)
    falling = np.where(signs[k] > 0, rise_or_fall, total - rise_or_fall)
    ok = total > 0
    return falling[ok] / total[ok]


def _above_shares(crossings, signs, kept):
    """Share of each kept full cycle (crossings k, k+1, k+2) spent above the level its
    crossings were read at: its positive half's duration over the cycle's."""
    kept = np.asarray(kept, dtype=np.intp)
    first = crossings[kept + 1] - crossings[kept]
    total = crossings[kept + 2] - crossings[kept]
    return np.where(signs[kept] > 0, first, total - first) / total


def _lopsided(shares):
    """Whether the cycles' shares (of time falling, or of time above the mean) sit on
    one side of one half beyond chance. A stationary Gaussian process of any spectrum
    reads the same backwards and upside down, so its cycles fall as long as they rise
    and stay as long above their mean as below; a stick-slip saw-tooth (a slow ramp
    while the valve sticks, a fast slip) breaks the first symmetry, a pulse train or a
    valve that dwells longer on one side the second. Sign test of the shares against
    one half (two-sided, exact) at :data:`LOPSIDED_LEVEL`, and a median share more than
    :data:`LOPSIDED_MARGIN` from it (at level 0.05: six of six cycles on one side, seven
    of seven, eight of eight or of nine).

    Such cycles confirm a component when the signal's first ACF peak is low, as it is
    for a saw-tooth or a pulse train whose period wanders under broadband noise: the
    wandering period scrambles the harmonics' phase from cycle to cycle, and the noise
    adds to the ACF's lag 0, which scales every other lag down."""
    d = shares[shares != 0.5] - 0.5
    n = d.size
    if n < 3 or abs(np.median(shares) - 0.5) <= LOPSIDED_MARGIN:  # ties left out of n
        return False
    k = max(np.count_nonzero(d > 0), np.count_nonzero(d < 0))
    return 2 * bdtrc(k - 1, n, 0.5) < LOPSIDED_LEVEL  # P(k or more of n on one side)


def _bimodal(y):
    """Whether the level of ``y`` sits at two values more than it spreads between them:
    Sarle's bimodality coefficient, skewness squared plus one over kurtosis (Pearson's
    inequality puts it at most 1, reached by a distribution on two points; a uniform
    distribution gives 5/9, a Gaussian 1/3) above :data:`BIMODAL`.

    A pulse train dwells at its two levels; noise lopsided in level, skewed or held at a
    limit, stays unimodal (up to a limit held on about a quarter of the samples, which
    becomes a second mode). The test of the cycles' time above their crossing level
    (:func:`_lopsided`) rests on the symmetry of a Gaussian process upside down, which
    such noise breaks: its cycles stay longer on one side too."""
    d = y - y.mean()
    m2 = np.mean(d * d)
    if m2 <= 0:
        return False
    m3, m4 = np.mean(d**3), np.mean(d**4)
    return bool((m3 * m3 / m2**3 + 1) * m2 * m2 > BIMODAL * m4)


def _set_detection(analysis, components, threshold, min_acf):
    """Fill the detection fields of ``analysis`` from the components."""
    found = [c for c in components if c.index > threshold]
    analysis.components = components
    analysis.oscillating = bool(found) and analysis.acf_strength >= min_acf
    analysis.oscillation_index = max((c.index for c in components), default=0.0)
    analysis.periods = np.array([c.period for c in found])
    analysis.regularities = np.array([c.regularity for c in found])


def _with_evidence(component, extra):
    """``component`` with ``extra`` added to its score (the index's logit scale); an index
    already within 1e-12 of 1 stays (the logit's clamp would otherwise lower it)."""
    if component.index >= 1 - 1e-12 and extra >= 0:
        return component
    i = min(max(component.index, 1e-12), 1 - 1e-12)
    score = np.log(i / (1 - i)) + extra / SCORE_SCALE
    return replace(component, index=float(1 / (1 + np.exp(-score))))


def analyze_cycles(
    x, *, min_cycles=3, hysteresis=3.0, tolerance=0.5, min_acf=0.0, threshold=0.5, dominant=None
):
    """Detect and time-localise the oscillation of one signal, cycle by cycle.

    Detection: :func:`~sktiction.cycles.detect_oscillations` (default parameters)
    splits the signal into components around its spectral peaks and scores each from
    its band-limited autocorrelation (Thornhill, Huang & Zhang, 2003); the signal
    oscillates when a component's index exceeds ``threshold``. This finds irregular
    and noise-driven cycles, two oscillations at once, cycles under drift, short
    periods and records of a few slow cycles, and it reads through historian repeats.

    Localisation: (1) dominant period from the autocorrelation of the detrended
    signal, or the period of the strongest detected component when it disagrees
    with all of them (drift or a second oscillation hides the first ACF lobe);
    (2) mean removal by a moving average over that period (robust to drift and
    setpoint moves, see :func:`~sktiction.cycles.remove_mean`), and, when the middle
    of the swing (halfway between its 5th and 95th percentiles) lies more than
    :data:`MIDDLE_SHIFT` of the swing from that mean, as it does for a pulse train,
    removal of that middle too, so that the noise of the long low stretches does not
    cross; (3) zero crossings by a Schmitt trigger at ``hysteresis`` times the noise
    standard deviation on a lightly smoothed copy, so noise cannot multiply them;
    (4) half-cycles between crossings, their peaks, and full cycles (three
    consecutive crossings);
    (5) stretches of at least ``min_cycles`` consecutive full cycles whose periods
    lie within ``tolerance`` of their local median (the cycle and two neighbours
    either side) are the oscillating segments. ``period`` and ``regularity`` (Thornhill's
    r, :data:`REGULARITY_THRESHOLD`) describe the cycles in segments.

    Both readings are combined: when the cycles in segments are regular (r > 1) and
    either the first ACF peak exceeds :data:`CONFIRM_ACF` or the cycles are lopsided
    (they rise faster than they fall or the reverse, as a stick-slip saw-tooth does, or
    stay longer on one side of their mean than on the other, as a pulse train does,
    beyond chance: :data:`LOPSIDED_LEVEL`, :data:`LOPSIDED_MARGIN`, ``fall_share``,
    ``above_share``, the latter on a record whose level is bimodal, :data:`BIMODAL`, as a
    pulse train's is and skewed or saturated noise's is not), the component of their period
    gets :data:`CYCLE_EVIDENCE` added to its score (:data:`LOPSIDED_EVIDENCE` when
    lopsided; so a record of three to six
    clean slow cycles, which the spectrum alone cannot tell from a random walk, is
    still found), and the decision is read again.

    Level shifts: when the record as it is shows no oscillation but holds level shifts
    (operator moves, load changes; see ``sktiction.cycles._level_shifts``), whose
    spectrum can bury a cycle many times smaller, it is read again with the shifts
    taken out, and that reading is kept if it finds an oscillation
    (``level_shifts`` lists them). A record that oscillates as it is keeps its reading.

    Parameters
    ----------
    x : array-like of shape (n_samples,)
        One signal. NaN padding at either end (a shorter record in a loop array) is
        dropped; NaN or infinite values inside the record are repaired as a scan
        repairs them, with a warning: gaps of at most 1 % of the record bridged, past a
        longer one the longest stretch kept (see
        :func:`~sktiction.cycles._repairs.one_signal`).
    min_cycles : int, default=3
        Fewest consecutive regular full cycles that make an oscillating stretch.
    hysteresis : float, default=3.0
        Crossing thresholds, in noise standard deviations.
    tolerance : float, default=0.5
        Relative period deviation allowed within an oscillating stretch.
    min_acf : float, default=0.0
        Smallest first ACF peak (``acf_strength``) of an oscillating signal, on top of
        the detection (0: no such condition).
    threshold : float, default=0.5
        Oscillation index above which a component oscillates.
    dominant : callable or None, default=None
        Returns :func:`~sktiction.cycles.dominant_period` of ``x`` when asked: a
        caller that keeps it for other uses (a shared loop analysis) passes it, so it
        is computed once. ``None`` computes it here when needed.

    Returns
    -------
    analysis : CycleAnalysis

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles import analyze_cycles
    >>> t = np.arange(1000)
    >>> a = analyze_cycles(np.sign(np.sin(2 * np.pi * t / 100)) + 0.01 * t)
    >>> a.oscillating, len(a.cycles), round(a.period)
    (True, 9, 100)
    >>> a.oscillation_index > 0.99, np.round(a.periods)
    (True, array([100.]))
    """
    return _analyze_cycles(one_signal(x), min_cycles, hysteresis, tolerance, min_acf, threshold,
                           dominant)


def _analyze_cycles(x, min_cycles=3, hysteresis=3.0, tolerance=0.5, min_acf=0.0, threshold=0.5,
                    dominant=None):
    """:func:`analyze_cycles` of a signal the caller has checked (inside a loop, a gap
    gives NaN features rather than an error)."""
    # read in units near 1 (no overflow in a spectrum's squares near 1e300), exactly
    x, unit = unit_scaled(np.asarray(x, dtype=float))
    args = (min_cycles, hysteresis, tolerance, min_acf, threshold)
    analysis, shifts = read_without_shifts(
        x,  # the caller's dominant period is that of the record as it is
        # a second reading is kept only if it oscillates
        lambda y: _read_cycles(y, *args, dominant if y is x else None, y is not x),
        lambda a: a.oscillating,
    )
    analysis.centred, analysis.smooth = analysis.centred * unit, analysis.smooth * unit
    analysis.level_shifts = shifts
    return analysis


def _read_cycles(
    x, min_cycles, hysteresis, tolerance, min_acf, threshold, dominant, needs_oscillation=False
):
    """One reading of :func:`_analyze_cycles`: the record as it is given. With
    ``needs_oscillation``, a reading whose components cannot oscillate even with the
    time-domain confirmation stops at its spectrum (an empty, non-oscillating reading)."""
    if dominant is None:
        dominant = lambda: dominant_period(x)  # noqa: E731
    components, p0, strength = [], np.nan, 0.0
    spectral = x.size >= 20 and np.ptp(x) > 0  # one spectrum for the ACF and the components
    if spectral:
        power, m, filled, spacing = _power_spectrum(x)
        # cycles of at least 5 fresh values: a finer export adds none
        components = _components(power, m, x.size, 3, 5.0 * spacing, 3.5, 0.5, threshold)
    if needs_oscillation and not any(  # as is, or with the confirmation's evidence
        c.index > threshold or _with_evidence(c, MAX_CONFIRMATION).index > threshold
        for c in components
    ):
        empty = np.empty(0, dtype=int)
        return CycleAnalysis(x, x, np.empty(0), empty, empty)
    if spectral and not filled:
        acf = irfft(power, m)[: x.size // 2 + 1]
        p0, strength = first_lobe(acf / acf[0]) if acf[0] > 0 else (np.nan, 0.0)
    elif x.size > 2:  # repeats filled in (the ACF of the record as recorded), or no spectrum
        p0, strength = dominant()
    found = [c for c in components if c.index > threshold]
    if found:
        main = max(found, key=lambda c: c.share)
        if not (np.isfinite(p0) and any(abs(np.log(p0 / c.period)) < 0.25 for c in found)):
            p0 = main.period
    centred = remove_mean(x, p0)
    # smoothing for crossings and peaks, as wide as the noise needs and at most a
    # tenth of a period (which keeps shapes); none on clean signals, so peaks stay put
    sigma = noise_std(centred)
    top, bottom, high, low = fast_percentile(centred, [99, 1, 100 - SWING_PERCENTILE,
                                                       SWING_PERCENTILE])  # fmt: skip
    amp = 0.5 * (top - bottom)
    middle = 0.5 * (high + low)
    shifted = abs(middle) > MIDDLE_SHIFT * (high - low)
    if shifted:
        # about the middle of the swing, as a comparator reads it: a cycle lopsided in
        # level (a pulse train) crosses its mean near its low side, where the noise of
        # the long low stretches makes crossings of its own
        centred = centred - middle
    rel = min(0.1, 2 * sigma / amp) if amp > 0 else 0.0
    width = max(1, int(round(rel * p0))) if np.isfinite(p0) else 1
    smooth = moving_average(centred, width) if sigma > 0 else centred
    h = max(hysteresis * sigma / np.sqrt(width), 1e-12 * max(np.ptp(centred), 1e-300))
    # a stretch on the moving mean (a hold drawn as a line) is rounding noise about zero,
    # whose sign changes, not the signal, would place its crossing: read it as zero
    eps = 1e-10 * np.ptp(smooth) if smooth.size else 0.0
    crossings, signs = schmitt_crossings(np.where(np.abs(smooth) <= eps, 0.0, smooth), h)
    if shifted:
        # a stretch that sat on the moving mean (a hold drawn as a line: rounding noise
        # about it) now lies off the crossing level, a half-cycle of its own whose extreme
        # rounding would pick: look for extremes on a grid of 1e-9 of the range, so the
        # first of equal values is taken at any scale
        grid = 1e-9 * max(np.ptp(smooth), 1e-300)
        peaks = _peaks(np.round(centred / grid), np.round(smooth / grid), crossings, signs, width)
    else:
        peaks = _peaks(centred, smooth, crossings, signs, width)
    analysis = CycleAnalysis(centred, smooth, crossings, signs, peaks, acf_strength=strength)
    _set_detection(analysis, components, threshold, min_acf)
    if crossings.size < 3:
        return analysis
    periods = crossings[2:] - crossings[:-2]  # full cycle starting at crossing k
    # full cycles start at every other crossing (those of the first crossing's sign),
    # so the halves of all cycles of a signal come in the same order
    start_ok = signs[:-2] == signs[0]
    idx = np.flatnonzero(start_ok)
    kept = []
    for a, b in _regular_runs(periods[idx], tolerance):
        if b - a >= min_cycles:
            kept.extend(idx[a:b].tolist())
    if not kept:
        return analysis
    kept = np.array(kept)
    cyc = np.column_stack([kept, kept + 1, kept + 2])
    p = periods[kept]
    regularity = p.mean() / (3 * p.std()) if p.std() > 0 else np.inf
    segments = _segments(centred, crossings, peaks, kept)
    analysis.cycles = cyc
    analysis.segments = segments
    analysis.period = float(fast_median(p))
    analysis.regularity = float(regularity)
    falls, aboves = _fall_shares(peaks, signs, kept), _above_shares(crossings, signs, kept)
    analysis.fall_share = float(np.median(falls)) if falls.size else np.nan
    analysis.above_share = float(np.median(aboves))
    evidence = 0.0  # only regular cycles confirm: the tests are not run for the others
    if regularity > REGULARITY_THRESHOLD:
        if _lopsided(falls) or (_lopsided(aboves) and _bimodal(smooth)):
            evidence = LOPSIDED_EVIDENCE
        elif strength > CONFIRM_ACF:
            evidence = CYCLE_EVIDENCE
    if evidence > 0:
        # regular cycles in the time domain confirm the component of their period
        boosted = [
            _with_evidence(c, evidence)
            if abs(np.log(c.period / analysis.period)) < 0.25
            else c
            for c in analysis.components
        ]
        # the boost can lift a weaker component above another: keep strongest first
        boosted.sort(key=lambda c: -c.index)
        _set_detection(analysis, boosted, threshold, min_acf)
    return analysis
