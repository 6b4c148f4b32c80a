"""Scan many loops at once: one row per loop, every verdict with its evidence and status.

Each chunk of loops is analysed once: one :class:`~sktiction.features._loops.LoopAnalysis`
per loop feeds the area-ratio rule, the shape library and (through a small adapter that
does not care which model is loaded) the learned classifier, so no signal's cycles are
computed twice.
"""

from __future__ import annotations

import copy
import pickle
import uuid
import warnings

import numpy as np
import pandas as pd
from joblib import Parallel, delayed, effective_n_jobs
from sklearn.pipeline import FeatureUnion, Pipeline

from .._cleaning import GAP_COLUMNS, in_step, repaired
from .._validation import (
    STATUS_EMPTY,
    STATUS_NAN_GAP,
    STATUS_OK,
    STATUS_TOO_SHORT,
    check_loops,
    check_max_gap,
    loop_status,
)
from ..classifiers import AreaRatioClassifier, ShapeLibraryClassifier, pretrained_classifier
from ..classifiers.shape_library import LOOP_TYPES
from ..features._loops import LoopTransformer, analyse_loops
from ..features.hysteresis import analysed_valve_band

REPORT_COLUMNS = [
    "status",
    "verdict",
    "stiction_probability",
    "area_ratio",
    "area_ratio_stiction",
    "shape_confidence",
    "shape_stiction",
    "shape_loop_type",
    "shape_reason",
    "n_cycles",
    "oscillating",
    "oscillation_index",
    "oscillation_period",
    "stiction_size_mean",
    "stiction_size_max",
    "stiction_band_fit",
    "startup_rows",
    "op_shift",
    "rows_per_sample",
    "reason",
]
#: Probability from which the learned classifier's verdict is "stiction".
STICTION_THRESHOLD = 0.5
VERDICT_STICTION, VERDICT_HEALTHY, NO_VERDICT = "stiction", "no_stiction", "no_verdict"


def _applicability_gate():
    """The input gate (:func:`~sktiction.classifiers.applicability.assess_applicability`),
    looked up when a scan starts so that a test can scan without it."""
    from ..classifiers.applicability import assess_applicability

    return assess_applicability


def _shared_features(est, loops, analyses, status):
    """Features of ``est`` (a loop transformer, or a union of them) from shared analyses.

    Returns None when ``est`` is anything else: the caller then runs it on the raw loops.
    """
    if isinstance(est, LoopTransformer):
        own = status if est._needs_op else None
        return est.transform_analysed(loops, analyses, own)
    if isinstance(est, FeatureUnion):
        config = getattr(est, "_sklearn_output_config", {}).get("transform", "default")
        if est.transformer_weights or config != "default":
            return None
        parts = []
        for _, step in est.transformer_list:
            part = _shared_features(step, loops, analyses, status)
            if part is None:
                return None
            parts.append(part)
        return np.hstack(parts)
    return None


def _one_process(classifier):
    """A copy of ``classifier`` with every ``n_jobs`` parameter set to 1.

    The scan already spreads chunks over workers; a model with workers of its own
    would start more processes in each of them (more memory, cores oversubscribed).
    The verdicts do not change: the model's parallel work is over loops.
    """
    try:
        params = classifier.get_params(deep=True)
    except (AttributeError, TypeError):
        return classifier
    single = {k: 1 for k, v in params.items() if k.split("__")[-1] == "n_jobs" and v != 1}
    if not single:
        return classifier
    classifier = copy.deepcopy(classifier)
    classifier.set_params(**single)
    return classifier


class LearnedAdapter:
    """The scan's one way to ask a learned classifier, whatever it is.

    In order of preference:

    - a classifier with ``diagnose_analysed(loops, analyses, status)`` or
      ``diagnose(X)`` returning a ``probability`` column gets asked that, once; an
      ``in_domain`` column says which loops it cannot judge (their ``reason`` is kept);
    - a fitted pipeline whose first step is one of the package's loop transformers
      (or a :class:`~sklearn.pipeline.FeatureUnion` of them) gets its features from
      the loops' shared analyses;
    - anything else is asked ``predict_proba(loops)[:, 1]``.

    Parameters
    ----------
    classifier : fitted classifier
        Anything with ``predict_proba`` on loops ``(n_loops, n_samples, 3)``.
    """

    def __init__(self, classifier):
        self.classifier = _one_process(classifier)

    def predict(self, loops, analyses, status):
        """Stiction probability per loop, and the model's reason where it abstains.

        Parameters
        ----------
        loops : ndarray of shape (n_loops, n_samples, 3)
            Checked loops.
        analyses : list of LoopAnalysis
            Their shared analyses.
        status : ndarray of str
            :func:`~sktiction._validation.loop_status` with ``require_op=True`` and
            ``check_swap=True``.

        Returns
        -------
        proba : ndarray of shape (n_loops,)
        abstain : ndarray of object, shape (n_loops,)
            ``None`` where the model judges the loop, its reason elsewhere.
        rows_per_sample : ndarray of shape (n_loops,)
            Rows the model averaged into one sample (the learned model's ``diagnose``
            column; 1 for a model that does not say).
        """
        clf = self.classifier
        abstain = np.full(len(loops), None, dtype=object)
        rows = np.ones(len(loops))
        report = None
        if callable(getattr(clf, "diagnose_analysed", None)):
            report = clf.diagnose_analysed(loops, analyses, status)
        elif callable(getattr(clf, "diagnose", None)):
            report = clf.diagnose(loops)
        if report is not None and "probability" in report:
            if "in_domain" in report:
                out = ~report["in_domain"].to_numpy(dtype=bool)
                reasons = report["reason"] if "reason" in report else "out_of_domain"
                abstain[out] = np.broadcast_to(np.asarray(reasons, dtype=object), out.shape)[out]
            if "rows_per_sample" in report:
                rows = report["rows_per_sample"].to_numpy(dtype=float)
            return report["probability"].to_numpy(dtype=float), abstain, rows
        if isinstance(clf, Pipeline) and len(clf.steps) >= 2:
            features = _shared_features(clf.steps[0][1], loops, analyses, status)
            if features is not None:
                for _, step in clf.steps[1:-1]:
                    if step is not None and step != "passthrough":
                        features = step.transform(features)
                return clf.steps[-1][1].predict_proba(features)[:, 1], abstain, rows
        return np.asarray(clf.predict_proba(loops))[:, 1], abstain, rows


class _Rules:
    """The fitted area-ratio rule and one shape library per loop type, built once."""

    def __init__(self, sample):
        self.area_ratio = AreaRatioClassifier().fit(sample)
        self.shape = {lt: ShapeLibraryClassifier(loop_type=lt).fit(sample) for lt in LOOP_TYPES}


def _scan_chunk(loops, loop_types, learned, rules=None, ts=None, gate=None):
    """Verdicts of all three classifiers for one chunk of checked loops, one pass each."""
    if rules is None:
        rules = _Rules(loops[:1])
    if not isinstance(learned, LearnedAdapter):
        learned = LearnedAdapter(learned)
    loops, startup, shifts = in_step(loops)
    analyses = analyse_loops(loops)
    status = loop_status(loops, require_op=True, check_swap=True)
    ar = rules.area_ratio.diagnose_analysed(loops, analyses)
    parts = []
    for lt in pd.unique(loop_types):  # one shape-library row per loop type
        idx = np.flatnonzero(loop_types == lt)
        sub = [analyses[i] for i in idx]
        part = rules.shape[lt].diagnose_analysed(loops[idx], sub, status[idx])
        parts.append(part.set_axis(idx))
    shape = pd.concat(parts).sort_index()
    proba = np.full(len(loops), np.nan)
    rows = np.full(len(loops), np.nan)
    ok = status == STATUS_OK
    # reason explains the verdict: "ok" where the learned model judged the loop; the shape
    # library's own reason (e.g. not_oscillating beside a learned stiction) is shape_reason
    reason = status.astype(object)
    if ok.any():  # the learned model reads OP too: only loops that can be analysed
        idx = np.flatnonzero(ok)
        p, abstain, rows[idx] = learned.predict(
            loops[idx], [analyses[i] for i in idx], status[idx]
        )
        proba[idx] = p
        judged = np.array([a is None for a in abstain])
        reason[idx[~judged]] = abstain[~judged]
        ok[idx[~judged]] = False
        proba[idx[~judged]] = np.nan  # no probability beside "no verdict"
    if gate is not None and ok.any():
        idx = np.flatnonzero(ok)
        sub_ts = None if ts is None else np.asarray(ts, dtype=float)[idx]
        verdict = gate(loops[idx], ts=sub_ts)
        out = ~verdict["applicable"].to_numpy(dtype=bool)
        reason[idx[out]] = verdict["reason"].to_numpy(dtype=object)[out]
        ok[idx[out]] = False
        proba[idx[out]] = np.nan  # the gate says the model cannot be trusted on these
    sticky = ok & (proba >= STICTION_THRESHOLD)
    # a size is only meaningful for a valve that is called sticky
    size = np.array(shape[["stiction_size_mean", "stiction_size_max"]], dtype=float)
    size[~sticky] = np.nan
    band = _fitted_bands(analyses, sticky)
    oscillating, index, period = _oscillations(analyses, status)
    return pd.DataFrame(
        {
            "status": status,
            "verdict": np.where(ok, np.where(sticky, VERDICT_STICTION, VERDICT_HEALTHY),
                                NO_VERDICT),
            "stiction_probability": proba,
            "area_ratio": ar["area_ratio"].to_numpy(),
            "area_ratio_stiction": ar["prediction"].to_numpy(),
            "shape_confidence": shape["score"].to_numpy(dtype=float),
            "shape_stiction": shape["prediction"].to_numpy(dtype=int),
            "shape_loop_type": shape["loop_type"].to_numpy(),
            "shape_reason": shape["reason"].to_numpy(dtype=object),
            "n_cycles": shape["n_cycles"].to_numpy(dtype=int),
            "oscillating": oscillating,
            "oscillation_index": index,
            "oscillation_period": period,
            "stiction_size_mean": size[:, 0],
            "stiction_size_max": size[:, 1],
            "stiction_band_fit": band,
            "startup_rows": startup,
            "op_shift": shifts,
            "rows_per_sample": rows,
            "reason": reason,
        }
    )


def _oscillations(analyses, status):
    """Whether OP or PV oscillates (pandas' nullable boolean: NA where neither could be
    read), the larger of their indices (:func:`~sktiction.cycles.analyze_cycles`, as
    every classifier reads them) and the period in samples of the strongest oscillating
    component of the channel with that index. Read whatever the verdict's status (a
    swapped or constant channel leaves the other), except where the record is empty,
    too short or has a gap."""
    n = len(analyses)
    oscillating = pd.array([pd.NA] * n, dtype="boolean")
    index, period = np.full(n, np.nan), np.full(n, np.nan)
    unread = (STATUS_EMPTY, STATUS_TOO_SHORT, STATUS_NAN_GAP)
    for i in np.flatnonzero(~np.isin(status, unread)):
        read = []
        for name in ("op", "pv"):
            x = analyses[i].signal(name)
            if x.size >= 20 and np.isfinite(x).all() and np.ptp(x) > 0:
                read.append(analyses[i].cycles(name))
        if read:
            best = max(read, key=lambda a: a.oscillation_index)
            oscillating[i] = any(a.oscillating for a in read)
            index[i] = best.oscillation_index
            period[i] = best.periods[0] if best.oscillating else np.nan
    return oscillating, index, period


def _fitted_bands(analyses, sticky):
    """:func:`~sktiction.features.hysteresis.valve_band` of the loops called sticky (NaN
    elsewhere): a size that needs no cycle, beside the shape library's peak-to-peak. The
    package's learned model has usually fitted it already on the same analyses."""
    band = np.full(len(analyses), np.nan)
    for i in np.flatnonzero(sticky):
        try:
            band[i] = analysed_valve_band(analyses[i])
        except (np.linalg.LinAlgError, ValueError, FloatingPointError):
            pass  # no size rather than no verdict: the size is evidence, not the answer
    return band


#: Status of a loop holding inf (NaN is a gap; inf is a broken value no analysis can use).
STATUS_NOT_FINITE = "not_finite"


def empty_rows(n):
    """``n`` report rows of no verdict and no values, typed as a scan's rows are (the
    nullable boolean ``oscillating`` stays boolean once such rows are joined)."""
    rows = pd.DataFrame({c: [np.nan] * n for c in REPORT_COLUMNS})
    rows["oscillating"] = pd.array([pd.NA] * n, dtype="boolean")
    rows["verdict"] = NO_VERDICT
    return rows


def _error_row(exc, loop=None):
    row = empty_rows(1)
    if loop is not None and np.isinf(np.asarray(loop, dtype=float)).any():
        bad = [c for c, x in zip(("PV", "OP", "SP"), np.moveaxis(np.asarray(loop), -1, 0))
               if np.isinf(x).any()]  # fmt: skip
        row["status"] = STATUS_NOT_FINITE
        row["reason"] = f"{STATUS_NOT_FINITE}: infinite values in {', '.join(bad)}"
        return row
    row["status"] = "error"
    row["reason"] = f"{type(exc).__name__}: {exc}"
    return row


def _scan_safely(loops, loop_types, learned, rules=None, ts=None, gate=None):
    """One chunk; if it fails, loop by loop, so one bad loop never aborts a scan."""
    infinite = np.isinf(np.asarray(loops, dtype=float)).any(axis=(1, 2))
    if infinite.any() and not infinite.all():
        # the others as one chunk: loop by loop costs a chunk about four times as much
        good, bad = np.flatnonzero(~infinite), np.flatnonzero(infinite)
        part = _scan_safely(np.asarray(loops)[good], loop_types[good], learned, rules,
                            None if ts is None else np.asarray(ts)[good], gate)  # fmt: skip
        errors = pd.concat([_error_row(None, loops[i]) for i in bad], ignore_index=True)
        both = pd.concat([part.set_axis(good), errors.set_axis(bad)])
        return both.sort_index().reset_index(drop=True)
    try:
        loops = check_loops(loops)
        return _scan_chunk(loops, loop_types, learned, rules, ts, gate)
    except Exception:  # noqa: BLE001 - isolate the loop that fails, report it below
        rows = []
        for i in range(len(loops)):
            one_ts = None if ts is None else np.asarray(ts)[i : i + 1]
            try:
                one = check_loops(loops[i : i + 1])
                rows.append(_scan_chunk(one, loop_types[i : i + 1], learned, rules, one_ts, gate))
            except Exception as exc:  # noqa: BLE001 - becomes that loop's status
                rows.append(_error_row(exc, loops[i]))
        return pd.concat(rows, ignore_index=True)


def loop_types_of(meta, n):
    """Shape-library row of each loop: ``meta["loop_type"]`` when known, else ``auto``."""
    loop_types = np.full(n, "auto", dtype=object)
    if meta is not None and "loop_type" in meta:
        known = meta["loop_type"].isin(LOOP_TYPES).to_numpy()
        loop_types[known] = meta["loop_type"].to_numpy()[known]
    return loop_types


def sampling_times(meta):
    """Per-loop sampling time from ``meta["ts"]``, or None."""
    if meta is None or "ts" not in meta:
        return None
    return pd.to_numeric(meta["ts"], errors="coerce").to_numpy(dtype=float)


def join_meta(meta, report):
    """``meta`` columns in front of the report; the reader's ``status``/``reason`` (per
    file) become ``input_status``/``input_reason`` so they do not shadow the scan's."""
    if meta is None:
        return report
    meta = meta.rename(columns={c: f"input_{c}" for c in meta.columns if c in REPORT_COLUMNS})
    return pd.concat([meta.reset_index(drop=True), report.reset_index(drop=True)], axis=1)


def _as_batch(X):
    """Loops to slice in chunks without copying the whole batch (checked per chunk)."""
    if isinstance(X, np.ndarray) and X.ndim == 3 and np.issubdtype(X.dtype, np.number):
        if 0 in X.shape:
            raise ValueError(f"X is empty: shape {X.shape}.")
        if X.shape[2] > 3:
            raise ValueError(
                f"X must have 1 to 3 channels (PV, OP, SP in that order); got {X.shape[2]}."
            )
        return X
    return check_loops(X)


def progress_bar(total, enabled, unit="loop", desc="scan"):
    """A tqdm progress bar on standard error with rate and ETA (disabled when not wanted)."""
    from tqdm.auto import tqdm

    return tqdm(total=total, unit=unit, disable=not enabled, desc=desc, leave=True,
                dynamic_ncols=True)


def run_units(fn, units, shared, *, n_jobs=None, client=None, bar=None, sizes=None):
    """``[fn(*unit, *shared) for unit in units]`` in order, locally (joblib) or on dask.

    ``shared`` arguments (the models) go to each dask worker once; results arrive as
    they finish and ``bar`` advances by ``sizes[k]`` for unit k.
    """
    out = [None] * len(units)
    sizes = [1] * len(units) if sizes is None else sizes
    if client is None:
        if effective_n_jobs(n_jobs) > 1:
            # the models once as bytes, unpickled once per worker: pickled with every
            # work unit they cost the parent about 3 ms of CPU per loop
            blob = _SharedBlob(shared)
            jobs = (delayed(_with_shared)(fn, unit, blob) for unit in units)
        else:
            jobs = (delayed(fn)(*unit, *shared) for unit in units)
        for k, part in enumerate(Parallel(n_jobs=n_jobs, return_as="generator")(jobs)):
            out[k] = part
            if bar is not None:
                bar.update(sizes[k])
        return out
    from distributed import as_completed

    remote = client.scatter(list(shared), broadcast=True)
    run = uuid.uuid4().hex
    futures = [client.submit(fn, *unit, *remote, pure=False, key=f"sktiction-scan-{run}-{k}")
               for k, unit in enumerate(units)]
    index = {f.key: k for k, f in enumerate(futures)}
    for future in as_completed(futures):
        k = index[future.key]
        out[k] = future.result()
        future.release()
        if bar is not None:
            bar.update(sizes[k])
    return out


class _SharedBlob:
    """Objects pickled once, with a token that names them in a worker's cache."""

    def __init__(self, objects):
        self.token = uuid.uuid4().hex
        self.data = pickle.dumps(tuple(objects), protocol=pickle.HIGHEST_PROTOCOL)

    def load(self):
        objects = _WORKER_SHARED.get(self.token)
        if objects is None:
            objects = pickle.loads(self.data)
            _WORKER_SHARED.clear()  # one scan's models at a time
            _WORKER_SHARED[self.token] = objects
        return objects


#: In a worker process: the last scan's shared objects by token (see :class:`_SharedBlob`).
_WORKER_SHARED = {}


def _with_shared(fn, unit, blob):
    return fn(*unit, *blob.load())


def _scan_unit(loops, loop_types, ts, learned, rules, gate, max_gap=None):
    if max_gap is None:
        return _scan_safely(loops, loop_types, learned, rules, ts, gate)
    loops, gaps = repaired(loops, max_gap)
    if ts is not None:  # a hold undone: every k-th row read, so k times the sample time
        ts = np.asarray(ts, dtype=float) * np.nan_to_num(gaps[:, 5], nan=1.0)
    report = _scan_safely(loops, loop_types, learned, rules, ts, gate)
    return pd.concat([pd.DataFrame(gaps, columns=list(GAP_COLUMNS)), report], axis=1)


def scan_loops(
    X, meta=None, *, classifier=None, chunk_size=64, n_jobs=None, progress=False, client=None,
    max_gap="auto",
):  # fmt: skip
    """Diagnose every loop of a batch; bad loops get a status, never an exception.

    Runs the three classifiers on each loop: the learned classifier gives the
    ``verdict`` and ``stiction_probability``; the area-ratio rule and the shape
    library give their own verdicts, and the shape library the stiction size (OP
    peak-to-peak over the sticky cycles, in OP units; NaN unless the verdict is
    stiction). ``stiction_band_fit`` is a second size that needs no cycle: the dead
    band of a valve model fitted to PV and OP
    (:func:`~sktiction.features.hysteresis.valve_band`, OP units; NaN unless the
    verdict is stiction), so a valve that slips without oscillating is sized too,
    scaled so that its median meets the true band on the default world's sticky
    valves: median 1.10 of the true band in ``make_loops``' classic world, 0.87-1.06 on
    four other draws of its default world, 0.79 and 1.01-1.10 in two simulators written
    apart (``examples/stiction_size.py``, ``benchmarks/sizes_and_confidence.py``).
    Each loop's signals are
    analysed once and the analysis shared by the three. ``reason`` explains the
    verdict: ``"ok"`` where the learned classifier judged the loop; loops that cannot
    be analysed get ``status`` and ``reason`` and ``verdict = "no_verdict"``; so do
    loops the learned classifier cannot judge and loops the applicability check
    (:func:`~sktiction.classifiers.applicability.assess_applicability`) rejects, with
    its reason (and then no ``stiction_probability``).
    ``shape_reason`` is the shape library's own (e.g. ``not_oscillating``: no size from
    it). ``oscillating``, ``oscillation_index`` and ``oscillation_period`` (samples) say
    whether OP or PV oscillates, as every classifier reads them
    (:func:`~sktiction.cycles.analyze_cycles`: the larger of the two indices, 0.5 the
    threshold, and the period of the strongest oscillating component), whatever the
    cause: a plant-wide oscillation survey comes with the scan.
    ``startup_rows`` is the number of rows (as read) of a start-up transient dropped
    from the start (0: none; see :func:`~sktiction.clean_loops`), ``op_shift`` the number of rows
    OP was moved to line up with PV before anything else (0: as recorded; see
    :func:`~sktiction._cleaning.align_op`).
    ``rows_per_sample`` is the number of rows, as read, that the learned classifier
    averaged into one sample: 1, or more for a loop recorded much finer than its
    training loops, read in block means
    (:meth:`~sktiction.LearnedStictionClassifier.diagnose`); after a hold was undone
    (``rows_per_value`` k), each row read stands for k rows of the input.

    Parameters
    ----------
    X : array-like of shape (n_loops, n_samples, n_channels)
        Loops, channels PV, OP, SP, NaN-padded at the end. A numeric array is
        checked and copied one chunk at a time, so the scan holds one extra chunk.
    meta : pandas.DataFrame or None, default=None
        One row per loop (e.g. from :func:`~sktiction.datasets.read_loops`); its
        columns are copied in front of the report (those named like a report
        column get the prefix ``input_``, e.g. the reader's ``input_status``), a
        ``loop_type`` column (flow, pressure, temperature, level) selects the
        shape-library row and a ``ts`` column (s) is passed to the applicability check.
    classifier : fitted classifier or None, default=None
        Learned classifier; ``None`` uses :func:`~sktiction.pretrained_classifier`.
    chunk_size : int, default=64
        Loops per work unit.
    n_jobs : int or None, default=None
        Parallel workers (joblib) over chunks.
    progress : bool, default=False
        Show a progress bar with rate and ETA on standard error (tqdm).
    client : dask.distributed.Client or None, default=None
        Run the chunks on this dask cluster (``pip install "sktiction[dask]"``; the
        chunks are sent to the workers). For files, :func:`scan_files` lets the
        workers read their own. The report is the same as a local scan's.
    max_gap : "auto", int or None, default="auto"
        ``"auto"`` or a number of samples repairs as :func:`scan_files` and every
        classifier do (:func:`~sktiction._cleaning.repaired`): a regular hold is read one
        row in k, spikes are replaced, placeholders (-9999 for a stretch) read as gaps,
        short gaps bridged (up to ``max_gap`` samples; ``"auto"``: 1/16 of the loop's
        period), the longest stretch kept and tags exported stepped redrawn through their
        stored points; the report then has ``n_bridged``, ``n_gaps_split``,
        ``kept_start``, ``kept_stop`` (input rows), ``n_spikes``, ``rows_per_value``,
        ``n_placeholders`` and ``stepped_tags``, and a ``ts`` column from ``meta`` is
        the sample time of the rows read. ``None`` repairs nothing: NaN gaps inside a
        record stay (the loop gets ``nan_gap``, with a warning).

    Returns
    -------
    report : pandas.DataFrame
        One row per loop, in input order.

    See Also
    --------
    scan_files : the same scan streamed from files, memory bounded by the chunk.

    Examples
    --------
    >>> from sktiction.datasets import make_loops
    >>> from sktiction.reports import scan_loops
    >>> from sktiction import pretrained_classifier
    >>> X, y = make_loops(4, n_samples=1500, random_state=0)
    >>> clf = pretrained_classifier(n_loops=60, n_samples=1000)
    >>> scan_loops(X, classifier=clf)["status"].tolist()
    ['ok', 'ok', 'ok', 'ok']
    """
    batch = _as_batch(X)
    n = len(batch)
    if meta is not None and len(meta) != n:
        raise ValueError(f"meta has {len(meta)} rows but X has {n} loops; they must match.")
    chunk_size = int(chunk_size)
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be an integer >= 1; got {chunk_size!r}.")
    loop_types = loop_types_of(meta, n)
    ts = sampling_times(meta)
    learned = LearnedAdapter(classifier if classifier is not None else pretrained_classifier())
    rules = _Rules(check_loops(np.zeros((1, 30, 3))))  # neutral: batch[0] may hold inf
    gate = _applicability_gate()
    if max_gap is not None:
        check_max_gap(max_gap)  # a bad max_gap fails here, once
    starts = range(0, n, chunk_size)
    units = [
        (batch[s : s + chunk_size], loop_types[s : s + chunk_size],
         None if ts is None else ts[s : s + chunk_size])
        for s in starts
    ]
    with progress_bar(n, progress) as bar:
        parts = run_units(_scan_unit, units, (learned, rules, gate, max_gap), n_jobs=n_jobs,
                          client=client, bar=bar, sizes=[len(u[1]) for u in units])
    gap_columns = list(GAP_COLUMNS) if max_gap is not None else []
    report = pd.concat(parts, ignore_index=True)[gap_columns + REPORT_COLUMNS]
    gaps = int(report["status"].eq("nan_gap").sum())
    if gaps and max_gap is None:
        warnings.warn(
            f"{gaps} of {n} loops have NaN gaps inside the record and got no verdict "
            "(status nan_gap, as max_gap=None asks); the default max_gap='auto' bridges "
            "short gaps and keeps the longest stretch, as scan_files does.", UserWarning,
            stacklevel=2,
        )
    if meta is not None and "ts" in meta and max_gap is not None:
        meta = meta.copy()  # a hold undone: the rows read are k times further apart
        step = report["rows_per_value"].fillna(1.0).to_numpy()
        meta["ts"] = sampling_times(meta) * step  # unreadable times stay NaN
    return join_meta(meta, report)
