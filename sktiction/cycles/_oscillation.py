"""Oscillation detection by band-limited autocorrelation, one component per spectral peak."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.fft import irfft, next_fast_len, rfft

from ._level_shifts import read_without_shifts
from ._repairs import one_signal
from ._signal import lines_through_changes, unit_scaled


@dataclass
class OscillationComponent:
    """One oscillation component found by :func:`detect_oscillations`.

    Attributes
    ----------
    period : float
        Mean period in samples, from the zero crossings of the component's ACF.
    regularity : float
        Thornhill's regularity factor r of those crossings (mean period over three
        standard deviations); oscillations are regular when r > 1.
    index : float
        Oscillation index in [0, 1] (0.5 is the decision threshold).
    prominence : float
        Spectral peak power over the spectrum's background at that frequency.
    coherence : float
        Mean ACF peak of the band-limited component near one and two periods (about
        0.05 for white noise, 1 for a pure cycle).
    share : float
        Share of the detrended signal's power (above the slowest period searched) in
        the component's band.
    cycle_acf : float
        ACF at one period of the signal with its moving mean over one period removed
        (drift gone, the cycle and its harmonics kept) and nothing above the 5th
        harmonic: how well one cycle repeats the last, whatever its shape (0.1-0.3
        for coloured noise, 0.5-0.9 for a cycle).
    """

    period: float
    regularity: float
    index: float
    prominence: float
    coherence: float
    share: float
    cycle_acf: float = 0.0


def _fill_repeats(x):
    """Replace historian repeats (runs of equal samples) by straight lines between the
    samples where the value changed, when they are common (>= 5 % of the samples).
    Runs at the record's lowest or highest value stay flat when there are at least
    :data:`LIMIT_RUNS` of them: a limit that a cycle reaches (a saturated OP, a
    clipped PV) holds once per cycle, and a line would draw a pulse train's plateaus
    as ramps; a trip of OP to 0 holds a few times."""
    d = np.diff(x)
    if np.mean(d == 0) < 0.05 or np.count_nonzero(d) < 7:
        return x
    return lines_through_changes(x, hold_extremes=True, min_runs=LIMIT_RUNS)


def _fresh_spacing(y):
    """Samples per fresh value: k when ``y`` (its repeats filled with lines) is a record
    exported k times finer than it was stored, held or interpolated (straight pieces
    of k samples, or multiples of k where two stored values are equal), else 1. The
    spectrum of such an export ends at the stored record's Nyquist frequency, a band
    edge that reads as a peak at 2k samples per cycle. Read as it is: a record of few
    levels (on/off), and one whose stored values themselves cycle (a triangle or a
    square wave drawn between its corners, a staircase), whose pieces are its cycle's."""
    d2 = np.abs(np.diff(y, 2))
    gaps = np.diff(np.sort(y))
    gaps = gaps[gaps > 0]  # between the distinct values, in order
    # values written with few decimals: rounding bends an interpolated line by <= 2 steps
    step = gaps.min() if gaps.size else 0.0
    knots = np.flatnonzero(d2 > max(1e-9 * max(np.ptp(y), 1e-300), 2.5 * step))
    # a median piece of 2 samples or more needs 1.5 samples per piece on average: a
    # record bent more often (noise bends it almost everywhere) reads 1 without it
    if knots.size < 8 or 2 * (knots[-1] - knots[0]) < 3 * (knots.size - 1):
        return 1
    pieces = np.diff(knots)
    k = int(np.median(pieces))
    stored = y[knots + 1]
    if k < 2 or np.mean(pieces % k == 0) < 0.9 or np.unique(stored).size < 8:
        return 1
    s = stored - stored.mean()
    power = float(s @ s)
    if power > 0 and max(abs(s[j:] @ s[:-j]) for j in (1, 2, 3, 4)) > 0.8 * power:
        return 1
    return k


def _smooth_constant_q(p, q):
    """Moving average of ``p`` over +-q*k bins around bin k (at least one each side)."""
    lo, hi, width = _constant_q_windows(p.size, q)
    c = np.concatenate([[0.0], np.cumsum(p)])
    return (c[hi] - c[lo]) / width


@lru_cache(maxsize=64)
def _constant_q_windows(size, q):
    """Window ends of :func:`_smooth_constant_q`: they depend on the length alone, and
    records of one length (a site's) share them."""
    k = np.arange(size)
    h = np.maximum(1, (q * k + 0.5).astype(int))
    lo = np.clip(k - h, 0, size)
    hi = np.clip(k + h + 1, 0, size)
    width = hi - lo
    for a in (lo, hi, width):
        a.flags.writeable = False
    return lo, hi, width


def _acf_crossings(r, max_crossings):
    """Fractional lags of the first zero crossings of an ACF (after lag 0)."""
    s = np.signbit(r)
    idx = np.flatnonzero(s[1:] != s[:-1])[:max_crossings]
    return idx + r[idx] / (r[idx] - r[idx + 1])


#: Score of a component (see :func:`detect_oscillations`) at which its index is 0.5.
SCORE_THRESHOLD = 1.3
#: Weights of the band-limited ACF's coherence and of the one-period ACF in the score.
COHERENCE_WEIGHT = 0.67
CYCLE_ACF_WEIGHT = 0.67
#: Highest harmonic kept in the one-period ACF.
CYCLE_HARMONICS = 5.0
#: Most score that :func:`~sktiction.cycles.analyze_cycles` adds from time-domain cycles
#: (lopsided ones; regular cycles under a clear ACF peak add 0.5).
MAX_CONFIRMATION = 0.7
#: Score change that moves the index from 0.5 to about 0.73.
SCORE_SCALE = 0.2
#: Evidence asked of a component per 1 / sqrt(cycles in the record).
FEW_CYCLES_PENALTY = 1.5
#: Lowest frequency (cycles per record) the spectrum background is read from.
LOWEST_BACKGROUND = 1.5
#: Runs held at a record's lowest or highest value from which they are read as a limit
#: that the cycle reaches once a cycle: more than the 1-3 of trips.
LIMIT_RUNS = 4
#: Band (sd in log frequency) in which a possible harmonic's period is read again: the
#: neighbours of a 2nd to 5th harmonic lie 0.18-0.69 away (ln 6/5 to ln 2).
HARMONIC_BANDWIDTH = 0.1


def detect_oscillations(
    x, *, max_components=3, min_period=5.0, min_cycles=3.5, bandwidth=0.5, threshold=0.5
):
    """Find the oscillation components of one signal, each from its band-limited ACF.

    After Thornhill, Huang & Zhang (2003): each spectral peak is a candidate
    component, and its autocorrelation is that of the signal band-pass filtered
    around the peak, so that several oscillations, drift and noise do not mix.

    1. Historian repeats (runs of equal samples, when >= 5 % of the samples) are
       replaced by straight lines between the samples where the value changed; runs
       at the lowest or highest value stay flat where there are at least
       :data:`LIMIT_RUNS` of them (a limit the cycle reaches).
    2. The signal is detrended (straight line); its periodogram, smoothed over +-4 %
       of each frequency, gives the candidate peaks between ``min_cycles`` cycles
       per record and ``min_period`` samples per cycle (``k * min_period`` rows in
       a record exported k times finer than it was stored, held or interpolated,
       whose spectrum ends in a band edge at 2k rows per cycle): the highest peaks of the
       spectrum, and of the spectrum times f**2 (that of the first difference),
       where a cycle that is only a shoulder on a steep drift spectrum peaks.
    3. Prominence: peak power over the background, the geometric mean of the
       periodogram's medians from 1.7 to 3 times the peak frequency and from 1/3 to
       1/1.7 of it, down to 1.5 cycles per record (exact for power laws, such as
       random walks and drift).
    4. The component's ACF comes from the same FFT through a band-pass of power
       weight ``exp(-(ln(f / f0) / bandwidth) ** 2)``, with the unbiased
       normalisation; its period is the mean interval between
       alternate zero crossings (Thornhill's Tp) and its regularity
       r = mean(Tp) / (3 sd(Tp)), over the first 21 zero crossings.
    5. Coherence: the mean of the ACF peaks near one and two periods (one alone when
       two do not fit in 60 % of the record). A filter this wide leaves white noise
       an ACF of about 0.1 and 0 there; a cycle that keeps its phase keeps it near 1.
    6. Cycle ACF: the ACF at one period of the signal with its moving mean over one
       period removed (drift gone, the cycle and its harmonics kept) and nothing
       above the 5th harmonic. No narrow filter makes it regular: coloured noise
       keeps its own short memory here (about 0.1), a cycle 0.5-0.9.
    7. Score = log10(prominence) + 0.67 (coherence + cycle ACF)
       - 1.5 / sqrt(cycles in the record): few cycles give noisy estimates, so they
       need more evidence. The index is the logistic function of
       (score - 1.3) / 0.2, so it lies in [0, 1] and is 0.5 at the decision
       threshold. The ACF terms let a cycle whose prominence a drift lowers (the
       drift's power lies next to the cycle's frequency) still be found; they weigh
       less than the prominence because an irregular cycle (period wandering by a
       third, Thornhill's r about 1) keeps little phase memory but still stands out
       of the spectrum. Thornhill's r is reported, not used to decide: the band
       filter makes the ACF crossings of noise regular too.
    8. When no component oscillates and the record holds level shifts (operator
       moves, load changes; see ``sktiction.cycles._level_shifts``), whose spectrum
       can bury a cycle many times smaller, steps 1-7 are run again with the shifts
       taken out, and those components are returned if one of them oscillates.

    The thresholds were set on simulated signals of the failure classes that
    ``benchmarks/bench_oscillation.py`` generates (never on measured loops).

    Parameters
    ----------
    x : array-like of shape (n_samples,)
        One signal; NaN padding is dropped, gaps repaired (as in
        :func:`~sktiction.cycles.analyze_cycles`).
    max_components : int, default=3
        Most components reported.
    min_period : float, default=5.0
        Shortest period searched, in stored samples: in a record exported k times
        finer than it was stored (see step 2 above), ``k * min_period`` rows.
    min_cycles : float, default=3.5
        Fewest cycles per record of the longest period searched.
    bandwidth : float, default=0.5
        Width of each component's band-pass filter (standard deviation in log frequency).
    threshold : float, default=0.5
        Index above which a component oscillates.

    Returns
    -------
    components : list of OscillationComponent
        Strongest index first; those with ``index > threshold`` oscillate. A
        component at the 2nd to 5th harmonic (within 2 %) of a slower oscillating one
        that carries more power is left out: it is part of that cycle's shape (two
        oscillations whose periods are in such a ratio are reported as one). When step
        8 applies, they are the components of the record without its level shifts
        (:func:`~sktiction.cycles.analyze_cycles` lists the shifts).

    References
    ----------
    Thornhill, N. F., Huang, B., Zhang, H. (2003). Detection of multiple oscillations
    in control loops. J. Process Control 13, 91-100.

    Examples
    --------
    >>> import numpy as np
    >>> from sktiction.cycles import detect_oscillations
    >>> t = np.arange(2000)
    >>> c = detect_oscillations(np.sin(2 * np.pi * t / 50) + 0.002 * t)
    >>> round(c[0].period), c[0].index > 0.99
    (50, True)
    >>> detect_oscillations(np.random.default_rng(0).normal(size=2000))[0].index < 0.1
    True
    """
    x = one_signal(x)
    if x.size < 4 * min_period or np.ptp(x) == 0:
        return []
    args = (max_components, min_period, min_cycles, bandwidth, threshold)
    return read_without_shifts(
        unit_scaled(x)[0],  # its spectrum's squares: no overflow near 1e300
        lambda y: _spectral_components(y, *args),
        lambda found: any(c.index > threshold for c in found),
    )[0]


def _spectral_components(x, max_components, min_period, min_cycles, bandwidth, threshold):
    power, m, _, spacing = _power_spectrum(x)
    return _components(
        power, m, x.size, max_components, min_period * spacing, min_cycles, bandwidth, threshold
    )


def _power_spectrum(x):
    """Periodogram of the signal (historian repeats filled in, straight line removed),
    zero-padded to ``m >= 2 n`` so that its inverse FFT is the linear ACF; also whether
    repeats were filled in."""
    n = x.size
    filled = _fill_repeats(x)
    t = np.arange(n) - (n - 1) / 2.0
    y = filled - filled.mean() - t * (t @ filled) / (t @ t)  # straight-line detrend
    m = next_fast_len(2 * n, real=True)
    spec = rfft(y, m)
    return spec.real**2 + spec.imag**2, m, filled is not x, _fresh_spacing(filled)


def _components(power, m, n, max_components, min_period, min_cycles, bandwidth, threshold):
    """The body of :func:`detect_oscillations`, from the padded periodogram."""
    k_lo = max(int(np.ceil(min_cycles / n * m)), 2)
    k_hi = min(int(np.floor(m / min_period)), power.size - 2)
    if k_hi <= k_lo + 2:
        return []
    smooth = _smooth_constant_q(power[: k_hi + 2], 0.04)
    chosen = _candidates(smooth, k_lo, k_hi, max_components + 1)
    total = power[k_lo:].sum()
    k_min = LOWEST_BACKGROUND * m / n
    floor = max(power.max() * 1e-30, 1e-300)  # exact zeros (quantised records) stay finite
    log_cum = np.concatenate([[0.0], np.cumsum(np.log(np.maximum(power, floor)))])
    prominence = np.array([smooth[k] / _background(log_cum, k, k_min) for k in chosen])
    penalty = FEW_CYCLES_PENALTY / np.sqrt(n * np.asarray(chosen) / m)
    # the ACFs (the costly part) only for the few most prominent peaks and any peak
    # that reaches the threshold on its own, and each only while the peak could still
    # reach it (with the time-domain evidence analyze_cycles may add): the others keep
    # the index ACFs of 0 give
    evidence = np.log10(np.maximum(prominence, 1e-12)) - penalty
    reach = SCORE_THRESHOLD - MAX_CONFIRMATION
    out = []
    for rank, i in enumerate(np.argsort(-evidence)):
        k = chosen[i]
        found, cycle_acf = None, 0.0
        could = evidence[i] + COHERENCE_WEIGHT + CYCLE_ACF_WEIGHT >= reach
        if could and (rank <= max_components or evidence[i] >= reach):
            found = _band_acf(power, k, m, n, bandwidth)
            if found is None:  # no cycle there: the ACF follows another component
                continue
            if evidence[i] + COHERENCE_WEIGHT * found[2] + CYCLE_ACF_WEIGHT >= reach:
                cycle_acf = _cycle_acf(power, found[0], m, n)
        period, regularity, coherence, band_power = found or (m / k, np.nan, 0.0, 0.0)
        share = float(band_power / total) if total > 0 else 0.0
        o = _component(period, regularity, prominence[i], coherence, share, penalty[i], cycle_acf)
        out.append((o, k))
    out.sort(key=lambda pair: -pair[0].index)
    pairs = []  # one component per period: a side peak's ACF follows the main cycle's
    for o, k in out:
        if not any(_same(o, s) for s, _ in pairs):
            pairs.append((o, k))
    kept = [o for o, k in pairs if not _harmonic_of(o, k, pairs, power, m, n, threshold)]
    return kept[:max_components]


def _candidates(smooth, k_lo, k_hi, count):
    """Bins of the highest peaks of the spectrum, and of the spectrum times f**2 (that
    of the first difference, where a cycle riding on a steep drift spectrum peaks too),
    each the highest within +-15 % of its frequency; a peak may sit on a range end."""
    chosen = []
    k = np.arange(k_lo - 1, k_hi + 2)
    for spectrum in (smooth[k_lo - 1 : k_hi + 2], smooth[k_lo - 1 : k_hi + 2] * k**2.0):
        peaks = (
            np.flatnonzero((spectrum[1:-1] >= spectrum[:-2]) & (spectrum[1:-1] > spectrum[2:])) + 1
        )
        if peaks.size > 4 * count:  # the rest cannot make it
            peaks = peaks[np.argpartition(spectrum[peaks], -4 * count)[-4 * count :]]
        cand = k[peaks[np.argsort(spectrum[peaks])[::-1]]]
        # far[a][b]: candidate a lies more than 15 % (in log frequency) from candidate b
        far = (np.abs(np.log(cand[:, None] / cand[None, :])) > 0.15).tolist()
        mine = []
        for a in range(cand.size):
            if all(far[a][b] for b in mine):
                mine.append(a)
                if len(mine) >= count:
                    break
        new = cand[mine]
        if chosen and new.size:  # those of this spectrum are far from each other already
            ratio = new[:, None] / np.array(chosen)[None, :]
            new = new[(np.abs(np.log(ratio)) > 0.15).all(axis=1)]
        chosen.extend(int(j) for j in new)
    return chosen


def _band_acf(power, k, m, n, bandwidth):
    """Period, regularity, coherence and power of the component around bin ``k``.

    The ACF is the inverse FFT of the band-weighted power. The band weighs less than
    1e-3 beyond a factor exp(2.63 bandwidth) of its centre's frequency (3.7 at the
    default bandwidth of 0.5), so only bins within a factor 4 of it are weighted and
    only bins up to 4 times it transformed: the ACF comes out on a coarser lag grid (8
    points per period), and a slow component costs little.
    """
    top = min(power.size - 1, int(np.ceil(4 * k)))
    low = max(1, int(k / 4))
    bp = np.zeros(top + 1)
    bins = np.arange(low, top + 1)
    bp[low:] = power[low : top + 1] * np.exp(-((np.log(bins / k) / bandwidth) ** 2))
    size = next_fast_len(2 * top, real=True)
    step = m / size  # original samples per lag of the coarse ACF
    acf = irfft(bp, size)
    if acf[0] <= 0:
        return None
    lags = np.arange(min(acf.size, int(0.6 * n / step) + 1))
    acf = acf[: lags.size] / acf[0] * (n / (n - lags * step))
    cross = _acf_crossings(acf, 21) * step
    if cross.size < 3:
        return None
    tp = cross[2:] - cross[:-2]
    period = float(tp.mean())
    if abs(np.log(period * k / m)) > 0.3:  # the ACF follows another (slower) component
        return None
    sd = tp.std()
    regularity = float(period / (3 * sd)) if sd > 0 else np.inf
    # coherence: mean ACF peak near one and two periods (one alone when two do not fit)
    peaks = []
    for j in (1, 2):
        lo, hi = int((j - 0.25) * period / step), int((j + 0.25) * period / step) + 1
        if lo < hi <= acf.size:
            peaks.append(acf[lo:hi].max())
    if not peaks:
        return None
    # np.mean of one or two values, as numpy sums and divides them
    mean = peaks[0] if len(peaks) == 1 else (peaks[0] + peaks[1]) / 2.0
    coherence = float(min(max(mean, 0.0), 1.0))
    return period, regularity, coherence, float(bp.sum())


def _moving_mean_response(f, period):
    """Frequency response of a centred moving average over ``period`` samples at
    frequencies ``f`` (cycles per sample, 0 < f <= 0.5): 1 at 0, 0 at k / period."""
    return np.sin(np.pi * f * period) / (period * np.sin(np.pi * f))


def _cycle_acf(power, period, m, n):
    """ACF at one period (its peak within +-25 %) of the signal whose power spectrum is
    ``power`` after removing its moving mean over one period and all above the 5th
    harmonic.

    The moving average over one period passes drift and slow moves and has zeros at
    the cycle's frequency and harmonics, so subtracting it (power weight
    ``(1 - H)**2``, ``H`` its frequency response) keeps the whole cycle, whatever its
    shape, while a random walk or trend that hides the plain ACF's first lobe goes.
    Unlike the band-limited ACF this one is not made regular by a narrow filter:
    coloured noise keeps its own short memory here.
    """
    top = min(power.size - 1, int(np.ceil(CYCLE_HARMONICS * m / period)))
    bp = np.zeros(top + 1)
    h = _moving_mean_response(np.arange(1, top + 1) / m, period)
    bp[1:] = power[1 : top + 1] * (1.0 - h) ** 2
    size = next_fast_len(2 * top, real=True)
    step = m / size  # original samples per lag of the coarse ACF
    acf = irfft(bp, size)
    hi = int(1.25 * period / step) + 1
    if acf[0] <= 0 or hi >= min(acf.size, 0.6 * n / step):
        return 0.0
    lags = np.arange(int(0.75 * period / step), hi)
    return float(np.max(acf[lags] / acf[0] * (n / (n - lags * step))))


def _component(period, regularity, prominence, coherence, share, penalty, cycle_acf):
    score = (
        np.log10(max(prominence, 1e-12))
        + COHERENCE_WEIGHT * coherence
        + CYCLE_ACF_WEIGHT * cycle_acf
        - penalty
    )
    index = 1.0 / (1.0 + np.exp(-(score - SCORE_THRESHOLD) / SCORE_SCALE))
    return OscillationComponent(
        float(period),
        float(regularity),
        float(index),
        float(prominence),
        coherence,
        share,
        float(cycle_acf),
    )


def _same(o, stronger):
    return bool(abs(np.log(o.period / stronger.period)) < 0.25)


def _harmonic_of(o, k, kept, power, m, n, threshold):
    """Whether component ``o`` (spectral peak at bin ``k``) is a harmonic of a slower
    component of ``kept`` (pairs of component and bin). Its band holds its neighbours
    too (a square wave's 3rd and 7th harmonics about its 5th), whose mixed ACF period
    lies between theirs, so the period is read in a narrow band as well."""
    # _harmonic's own conditions first, so the narrow band is read only where they hold
    slower = [
        s for s, _ in kept if s.index > threshold and s.period > o.period and s.share >= o.share
    ]
    if not slower:
        return False
    if any(_harmonic(o, o.period, s, threshold) for s in slower):
        return True
    narrow = _band_acf(power, k, m, n, HARMONIC_BANDWIDTH)
    return narrow is not None and any(_harmonic(o, narrow[0], s, threshold) for s in slower)


def _harmonic(o, period, slower, threshold):
    """Whether ``o``, of period ``period``, is the 2nd to 5th harmonic (within 2 %) of
    a slower oscillating component that carries more of the signal: part of that
    cycle's shape."""
    if slower.index <= threshold or not o.period < slower.period or o.share > slower.share:
        return False
    ratio = slower.period / period
    k = round(ratio)
    return 2 <= k <= 5 and abs(ratio - k) <= 0.02 * k


def _background(log_cum, k, k_min):
    """Spectrum background at bin ``k``: geometric mean of the periodogram over bins
    [k/3, k/1.7] and [1.7 k, 3 k], from the running sum ``log_cum`` of its logarithm.
    The two sides cancel the slope of a power law (random walks, drift). When the
    lower side leaves the range [k_min, end] (a peak of fewer than 4.5 cycles per
    record), the slope is read from [1.7 k, 3 k] and [3 k, 5.3 k] instead and
    extrapolated to ``k`` (never below the upper side): the upper side alone would
    put the background of a falling spectrum too low and make any slow bump stand
    out. The log of an exponential variable averages ln(mean) - Euler's gamma, hence
    the correction; the log keeps a peak in a side band from raising the background
    much."""

    def side(a, b):
        a, b = int(np.ceil(a)), int(np.floor(b)) + 1
        if a >= k_min and b < log_cum.size and b - a >= 3:
            return (log_cum[b] - log_cum[a]) / (b - a)
        return None

    low, high = side(k / 3.0, k / 1.7), side(1.7 * k, 3.0 * k)
    if low is not None and high is not None:
        level = 0.5 * (low + high)
    elif high is not None:
        further = side(3.0 * k, 5.3 * k)
        level = high
        if further is not None:  # centres of the two bands: 2.26 k and 3.99 k
            slope = (high - further) / np.log(3.99 / 2.26)
            level = max(high, high + slope * np.log(2.26))
    elif low is not None:
        level = low
    else:
        a = int(np.ceil(k_min))
        level = (log_cum[-1] - log_cum[a]) / (log_cum.size - 1 - a)
    return float(np.exp(level + np.euler_gamma))
