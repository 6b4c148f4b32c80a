"""The scan on a few short loops whose verdicts are known, with stand-in learned models.

Fast (about a second per scan): loops built here (square waves behind a sticking valve,
control errors of known area ratio, noise, gaps), and in place of the learned classifier
small objects whose stiction probability is a known function of the loop. What is checked:
each column of the report against the classifier it comes from, every way the scan may
ask a model, the gate, bad loops and failing loops, and that neither the chunking nor
the way the model is asked changes the report.
"""

import functools
import re

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone
from sklearn.compose import ColumnTransformer
from sklearn.ensemble import HistGradientBoostingClassifier
from sklearn.impute import SimpleImputer
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import FeatureUnion, Pipeline
from sklearn.preprocessing import FunctionTransformer, StandardScaler

from sktiction import AreaRatio, AreaRatioClassifier, ShapeLibraryClassifier
from sktiction.features._loops import LoopTransformer
from sktiction.reports import scan as scan_module
from sktiction.reports import scan_loops as scan_repaired
from sktiction.reports.scan import REPORT_COLUMNS, LearnedAdapter

# these tests are about the scan's statuses and verdicts on loops read as given (one of
# them has a gap it must isolate); repair is tested in test_scan.py and test_cleaning.py
scan_loops = functools.partial(scan_repaired, max_gap=None)

N = 1200  # 12 cycles of 100 samples


def square(a, period=100):
    """PV a square wave of amplitude ``a`` (a valve that jumps), OP its integral: a
    sticking valve in a flow loop (OP triangular, PV rectangular). The OP peak-to-peak
    over a half-cycle is 0.05 * a * period / 2 = 2.5 a; ``a`` may change along the record."""
    k = np.arange(N)
    pv = 10 + a * np.clip(8 * np.sin(2 * np.pi * k / period), -1, 1)
    return np.stack([pv, 50 - 0.05 * np.cumsum(pv - 10), np.full(N, 10.0)], -1)


def asymmetric(peak_at, a=1.0, period=100):
    """Control error of triangular half-cycles: area ratio ``peak_at / (1 - peak_at)``."""
    h = period // 2
    half = np.interp(np.arange(h), [0, peak_at * h, h], [0, a, 0])
    e = np.tile(np.concatenate([half, -half]), N // period)
    return np.stack([10 - e, 50 + 0.05 * np.cumsum(e), np.full(N, 10.0)], -1)


def spread_probability(X):
    """The stand-ins' stiction probability: PV's peak-to-peak p over p + 2."""
    X = np.asarray(X, dtype=float)
    ptp = np.nanmax(X[:, :, 0], axis=1) - np.nanmin(X[:, :, 0], axis=1)
    return ptp / (ptp + 2)


class Spread:
    """Any classifier with ``predict_proba`` (no diagnose, no pipeline)."""

    def predict_proba(self, X):
        p = spread_probability(X)
        return np.column_stack([1 - p, p])


def known_loops():
    rng = np.random.default_rng(0)
    gap = square(2.0)
    gap[300:320] = np.nan
    no_op = square(2.0)
    no_op[:, 1] = np.nan
    X = np.stack([
        square(np.where(np.arange(N) < N / 2, 3.0, 2.0)),  # p = 0.75: stiction; flow: sticky
        square(1.0),  # p = 0.5 exactly: stiction (from 0.5 on); level row: not sticky
        square(0.3),  # p = 0.23: no stiction, although the flow row says sticky
        asymmetric(0.75, a=2.5),  # R = 3: the area-ratio rule says sticky; p = 0.71
        gap,
        rng.normal(size=(N, 3)),  # PV and OP unrelated: the gate says so
        no_op,
        asymmetric(0.5, a=0.5),  # R = 1, p = 1/3
    ])  # fmt: skip
    types = np.array(["flow", "level", "flow", "auto", "auto", "flow", "auto", "steam"], object)
    return X, types


@pytest.fixture(scope="module")
def loops():
    return known_loops()


@pytest.fixture(scope="module")
def report(loops):
    X, types = loops
    return scan_loops(X, pd.DataFrame({"loop_type": types}), classifier=Spread(), chunk_size=3)


def test_each_loop_gets_the_verdict_its_signals_call_for(loops, report):
    X, types = loops
    assert list(report.columns) == ["loop_type", *REPORT_COLUMNS]
    assert report["status"].tolist() == ["ok"] * 4 + ["nan_gap", "ok", "missing_op", "ok"]
    assert report["verdict"].tolist() == (
        ["stiction", "stiction", "no_stiction", "stiction"] + ["no_verdict"] * 3 + ["no_stiction"]
    )
    assert report["reason"].tolist() == (
        ["ok"] * 4 + ["nan_gap", "pv_op_unrelated", "missing_op", "ok"]
    )
    p = spread_probability(X)
    judged = report["verdict"].ne("no_verdict").to_numpy()
    np.testing.assert_allclose(report["stiction_probability"][judged], p[judged], rtol=1e-12)
    assert report["stiction_probability"][~judged].isna().all()  # none beside no verdict
    # the rules' columns are the rules' own answers
    ar = AreaRatioClassifier().fit(X).diagnose(X)
    read = report["status"].ne("nan_gap").to_numpy()  # on its own the rule bridges the gap
    np.testing.assert_array_equal(report["area_ratio"][read], ar["area_ratio"][read])
    np.testing.assert_array_equal(report["area_ratio_stiction"][read], ar["prediction"][read])
    assert report.loc[3, "area_ratio"] == pytest.approx(3.0, rel=0.1)
    assert report["area_ratio_stiction"].tolist() == [0, 0, 0, 1, 0, 0, 0, 0]
    # the shape library's row follows the loop type; unknown types are inferred
    assert report["shape_loop_type"].tolist()[:3] == ["flow", "level", "flow"]
    assert report.loc[7, "shape_loop_type"] != "steam"
    assert report["shape_stiction"].tolist()[:3] == [1, 0, 1]
    for i, lt in enumerate(types):
        if not read[i]:
            continue
        lt = lt if lt != "steam" else "auto"
        one = ShapeLibraryClassifier(loop_type=lt).fit(X).diagnose(X[i : i + 1]).iloc[0]
        assert report.loc[i, "shape_confidence"] == one["score"]
        assert report.loc[i, "n_cycles"] == one["n_cycles"]
    # a size only for a valve called sticky: OP's peak-to-peak over a sticky cycle
    # (half the cycles at amplitude 3, half at 2: OP swings 7.5 and 5)
    assert report.loc[0, "stiction_size_max"] == pytest.approx(7.5, rel=0.1)
    assert 5.0 < report.loc[0, "stiction_size_mean"] < report.loc[0, "stiction_size_max"] - 0.5
    assert report.loc[1:, ["stiction_size_mean", "stiction_size_max"]].isna().all().all()


def test_the_oscillation_columns_say_which_loops_cycle_and_at_what_period(report):
    # loops 0-3 and 7 cycle every 100 samples; loop 5 is white noise; loop 6 has no OP,
    # so its PV is read (it cycles too); loop 4 keeps a gap (max_gap=None): not read
    assert str(report["oscillating"].dtype) == "boolean"
    cycling = [0, 1, 2, 3, 6, 7]
    assert report["oscillating"].tolist() == [i in cycling for i in range(4)] + [
        pd.NA, False, True, True]  # fmt: skip
    np.testing.assert_allclose(report.loc[cycling, "oscillation_period"], 100, rtol=0.03)
    assert (report.loc[cycling, "oscillation_index"] > 0.9).all()
    assert report.loc[5, "oscillation_index"] < 0.2
    assert np.isnan(report.loc[5, "oscillation_period"])
    assert report.loc[4, ["oscillation_index", "oscillation_period"]].isna().all()


def test_the_report_does_not_depend_on_the_chunks_or_the_input_type(loops, report):
    X, types = loops
    meta = pd.DataFrame({"loop_type": types})
    for chunk_size in (1, 2.0):
        pd.testing.assert_frame_equal(
            scan_loops(X, meta, classifier=Spread(), chunk_size=chunk_size), report
        )
    # nested lists are checked like arrays; two channels are PV and OP with no SP
    few = report.iloc[[0, 3]].reset_index(drop=True)
    as_list = scan_loops(X[[0, 3]].tolist(), meta.iloc[[0, 3]], classifier=Spread())
    pd.testing.assert_frame_equal(as_list, few)
    no_sp = X[[0, 3]].copy()
    no_sp[:, :, 2] = np.nan
    pd.testing.assert_frame_equal(
        scan_loops(X[[0, 3], :, :2], classifier=Spread()),
        scan_loops(no_sp, classifier=Spread()),
    )
    whole = np.round(X[[0, 3]] * 1000)  # an integer array scans like its float copy
    pd.testing.assert_frame_equal(
        scan_loops(whole.astype(np.int64), classifier=Spread()),
        scan_loops(whole, classifier=Spread()),
    )


def test_mixed_loop_types_in_one_chunk_keep_their_own_shapes(monkeypatch):
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: None)
    rng = np.random.default_rng(1)
    quiet = np.stack([10 + 0.01 * rng.normal(size=N), 50 + 0.01 * rng.normal(size=N),
                      np.full(N, 10.0)], -1)  # fmt: skip
    X = np.stack([square(3.0), square(3.0), quiet])
    meta = pd.DataFrame({"loop_type": ["level", "flow", "flow"]})
    one_by_one = scan_loops(X, meta, classifier=Spread(), chunk_size=1)
    assert one_by_one["n_cycles"].tolist()[1:] == [11, 0]
    assert one_by_one["shape_stiction"].tolist()[1:] == [1, 0]
    pd.testing.assert_frame_equal(
        scan_loops(X, meta, classifier=Spread(), chunk_size=3), one_by_one
    )


def test_meta_columns_go_in_front_and_never_shadow_the_report(loops):
    X, types = loops
    meta = pd.DataFrame(
        {"tag": [f"FIC{i}" for i in range(8)], "status": "read", "reason": "file notes",
         "ts": ["1", "2", "n/a", "4", "5", "6", "7", "8"]},
        index=np.arange(100, 108),
    )  # fmt: skip
    got = scan_loops(X, meta, classifier=Spread(), chunk_size=3)
    assert list(got.columns) == ["tag", "input_status", "input_reason", "ts", *REPORT_COLUMNS]
    assert got["tag"].tolist() == meta["tag"].tolist() and got.index.tolist() == list(range(8))
    assert got["input_status"].eq("read").all() and got["status"].iloc[4] == "nan_gap"
    # no loop_type column: every loop's library row is inferred (rectangular PV: flow)
    assert got["shape_loop_type"].iloc[:3].tolist() == ["flow"] * 3
    with pytest.raises(ValueError, match="meta has 3 rows but X has 8 loops"):
        scan_loops(X, meta.iloc[:3], classifier=Spread())


def test_the_gate_sees_each_judged_loop_with_its_sampling_time(loops, monkeypatch):
    X, types = loops
    gate = scan_module._applicability_gate()
    assert gate is not None
    seen = []

    def recording(loops, ts=None):
        seen.append(ts)
        return gate(loops, ts=ts)

    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: recording)
    meta = pd.DataFrame({"loop_type": types, "ts": ["1", "2", "3", "4", "5", "6", "x", "8"]})
    got = scan_loops(X, meta, classifier=Spread(), chunk_size=4)
    # chunks [0-3] and [4-7]; loops 4 (gap) and 6 (no OP) never reach the gate
    np.testing.assert_array_equal(np.concatenate(seen), [1, 2, 3, 4, 6, 8])
    assert got["reason"].iloc[5] == "pv_op_unrelated"
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: None)
    ungated = scan_loops(X, meta, classifier=Spread(), chunk_size=4)
    assert ungated.loc[5, "verdict"] == "stiction"  # p(noise) >= 0.5 without the gate
    assert ungated.drop(index=5).equals(got.drop(index=5))


def test_a_loop_that_breaks_the_model_gets_an_error_row(loops):
    X, types = loops

    class Fussy(Spread):
        def predict_proba(self, X):
            if np.nanmax(X[:, :, 0]) > 100:
                raise ValueError("PV above 100")
            return super().predict_proba(X)

    bad = X[:6].copy()
    bad[2, :, 0] += 200
    ts = pd.DataFrame({"ts": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]})
    got = scan_loops(bad, ts, classifier=Fussy(), chunk_size=6).drop(columns="ts")
    row = got.iloc[2]
    assert (row["status"], row["verdict"], row["reason"]) == (
        "error",
        "no_verdict",
        "ValueError: PV above 100",
    )
    assert row[["stiction_probability", "area_ratio", "n_cycles"]].isna().all()
    # the chunk was scanned loop by loop: the others as alone, the gate still applied
    alone = scan_loops(X[[0, 1, 3, 4, 5]], classifier=Fussy())
    pd.testing.assert_frame_equal(
        got.drop(index=2).reset_index(drop=True), alone, check_dtype=False
    )
    assert got.loc[5, "reason"] == "pv_op_unrelated"


# ---- the ways the scan asks a learned model ------------------------------------------------


class Diagnosing(Spread):
    """A model with its own report: probability, and where it abstains (in_domain)."""

    def __init__(self, reasons=True, in_domain=True):
        self.reasons, self.in_domain = reasons, in_domain

    def diagnose(self, X):
        p = spread_probability(X)
        out = pd.DataFrame({"probability": p})
        if self.in_domain:
            out["in_domain"] = p < 0.74  # the largest swings are outside its training
        if self.reasons:
            out["reason"] = np.where(p < 0.74, "ok", "pv_swing_unseen")
        return out

    def predict_proba(self, X):
        raise AssertionError("a model with a probability in its report is asked once")


def test_a_model_that_abstains_says_why(loops, report):
    X, _ = loops
    got = scan_loops(X, classifier=Diagnosing(), chunk_size=3)
    assert got.loc[0, "verdict"] == "no_verdict" and got.loc[0, "reason"] == "pv_swing_unseen"
    same = [1, 2, 3, 4, 6, 7]
    assert got.loc[same, "verdict"].tolist() == report.loc[same, "verdict"].tolist()
    unnamed = scan_loops(X, classifier=Diagnosing(reasons=False))
    assert unnamed.loc[0, "reason"] == "out_of_domain"
    always = scan_loops(X, classifier=Diagnosing(reasons=False, in_domain=False))
    assert always.loc[0, "verdict"] == "stiction"


def test_the_shared_analyses_are_handed_to_a_model_that_takes_them(loops):
    X, _ = loops
    calls = []

    class Shared(Diagnosing):
        def diagnose_analysed(self, loops, analyses, status):
            calls.append((len(loops), len(analyses), list(status)))
            return Diagnosing.diagnose(self, loops)

        def diagnose(self, X):
            raise AssertionError("diagnose_analysed comes first")

    got = scan_loops(X, classifier=Shared(in_domain=False), chunk_size=4)
    assert calls == [(4, 4, ["ok"] * 4), (2, 2, ["ok"] * 2)]  # only loops it can judge
    pd.testing.assert_frame_equal(got, scan_loops(X, classifier=Spread()))


def test_a_report_without_probability_falls_back_to_predict_proba(loops, report):
    X, _ = loops

    class Labels(Spread):
        def diagnose(self, X):
            return pd.DataFrame({"prediction": np.zeros(len(X), int)})

    got = scan_loops(X, classifier=Labels())
    assert got["stiction_probability"].equals(report["stiction_probability"])


@pytest.fixture(scope="module")
def pipelines(loops):
    X, _ = loops
    y = np.array([1, 0, 0, 1, 0, 0, 1, 0])

    def make(first):
        # every middle step counts: without the filling NaN reaches the model, without
        # the scaling its weights mean other things
        steps = [first, ("fill", SimpleImputer(keep_empty_features=True)),
                 ("skip", "passthrough"), ("scale", StandardScaler()),
                 ("model", LogisticRegression(C=0.1, max_iter=5000))]  # fmt: skip
        return Pipeline(steps).fit(X, y)

    parts = [("area", AreaRatio()), ("filtered", AreaRatio(filter="horch"))]
    shared = make(("features", FeatureUnion(parts)))
    single = make(("area", AreaRatio()))
    weighted = make(("features", FeatureUnion(parts, transformer_weights={"area": 50.0})))
    raw = FunctionTransformer(lambda Z: Z[:, :3, 0])  # three PV samples, no loop analysis
    mixed = make(("features", FeatureUnion([("area", AreaRatio()), ("raw", raw)])))
    # two steps: the features and a model that takes NaN
    booster = HistGradientBoostingClassifier(max_iter=5, min_samples_leaf=1)
    short = Pipeline([("features", FeatureUnion(parts)), ("model", booster)]).fit(X, y)
    # a step that picks features by name needs the union's pandas output
    pick = ColumnTransformer([("ratio", "passthrough", ["area__area_ratio"])])
    steps = [("features", FeatureUnion(parts).set_output(transform="pandas")),
             ("pick", pick), ("fill", SimpleImputer(keep_empty_features=True)),
             ("model", LogisticRegression())]  # fmt: skip
    named = Pipeline(steps).fit(X, y)
    return {"shared": shared, "single": single, "short": short, "weighted": weighted,
            "mixed": mixed, "named": named}  # fmt: skip


def _probability(pipe, X, **kwargs):
    got = scan_loops(X, classifier=pipe, **kwargs)
    ok = got["verdict"].ne("no_verdict").to_numpy()  # no probability beside no verdict
    return got["stiction_probability"].to_numpy(), ok


def test_a_pipeline_of_loop_transformers_reads_the_shared_analyses(loops, pipelines, monkeypatch):
    X, _ = loops
    expected = {name: pipe.predict_proba(X)[:, 1] for name, pipe in pipelines.items()}

    def no_transform(self, X):
        raise AssertionError("features recomputed from the raw loops")

    monkeypatch.setattr(LoopTransformer, "transform", no_transform)
    for name in ("shared", "single", "short"):
        p, ok = _probability(pipelines[name], X, chunk_size=5)
        assert ok.sum() == 5  # no loop failed in the model's steps (one gated)
        np.testing.assert_allclose(p[ok], expected[name][ok], rtol=1e-9)
        assert len(set(np.round(p[ok], 6))) >= 2  # the features reach the model
    # weights, a step that is not a loop transformer, or pandas output (a later step may
    # pick columns by name): the pipeline runs on the loops
    for name in ("weighted", "mixed", "named"):
        p, _ = _probability(pipelines[name], X)
        assert np.isnan(p).all()  # every loop's own transform failed (no_transform)
    monkeypatch.undo()
    for name in ("weighted", "mixed", "named"):
        p, ok = _probability(pipelines[name], X)
        assert ok.sum() == 5  # all but the gap, the missing OP and the gated one
        np.testing.assert_allclose(p[ok], expected[name][ok], rtol=1e-9)


def test_the_model_is_copied_to_one_process_only_when_needed(pipelines):
    pipe = clone(pipelines["shared"]).set_params(features__n_jobs=1, model__n_jobs=1)
    assert LearnedAdapter(pipe).classifier is pipe  # no n_jobs to change: no copy
    parallel = clone(pipe).set_params(features__n_jobs=2)
    adapter = LearnedAdapter(parallel)
    assert adapter.classifier.get_params()["features__n_jobs"] == 1
    assert parallel.get_params()["features__n_jobs"] == 2
    plain = Spread()
    assert LearnedAdapter(plain).classifier is plain


def test_no_classifier_means_the_pretrained_one(loops, report, monkeypatch):
    X, types = loops
    monkeypatch.setattr(scan_module, "pretrained_classifier", Spread)
    got = scan_loops(X, pd.DataFrame({"loop_type": types}))
    pd.testing.assert_frame_equal(got, report)


@pytest.mark.parametrize(
    ("X", "kwargs", "match"),
    [
        (np.zeros((0, 100, 3)), {}, "X is empty"),
        (np.zeros((2, 100, 4)), {}, "1 to 3 channels"),
        (np.zeros((2, 100, 3)), {"chunk_size": 0}, "chunk_size must be an integer >= 1"),
    ],
)
def test_bad_input_is_refused(X, kwargs, match):
    with pytest.raises(ValueError, match=match):
        scan_loops(X, classifier=Spread(), **kwargs)


def test_the_progress_bar_is_shown_only_when_asked(loops, capsys):
    X, _ = loops
    scan_loops(X[:2], classifier=Spread())
    assert capsys.readouterr().err == ""
    scan_loops(X[:2], classifier=Spread(), progress=True)
    err = capsys.readouterr().err
    assert "scan" in err and "2/2" in err
    assert re.search(r"[\d?]loop/s", err)  # the rate in loops per second


def test_a_dask_cluster_gives_the_local_report(loops, report, dask_client):
    from distributed import get_task_stream

    X, types = loops
    with get_task_stream(dask_client) as stream:
        got = scan_loops(X, pd.DataFrame({"loop_type": types}), classifier=Spread(),
                         chunk_size=3, client=dask_client, progress=True)  # fmt: skip
    # the chunks ran on the cluster, not here
    assert any(t["key"].startswith("sktiction-scan") for t in stream.data)
    pd.testing.assert_frame_equal(got, report)


def test_a_loop_that_does_not_cycle_gets_the_shape_librarys_reason():
    # a first-order plant under PI control, with a drifting disturbance: closed, no cycle
    rng = np.random.default_rng(0)
    pv, op = np.zeros(N), np.zeros(N)
    drift, x, integral = np.cumsum(rng.normal(0, 0.05, N)), 0.0, 0.0
    for t in range(1, N):
        x = 0.9 * x + 0.1 * op[t - 1]
        pv[t] = x + drift[t] + rng.normal(0, 0.01)
        integral -= pv[t]
        op[t] = 0.5 * (integral / 10 - pv[t])
    X = np.stack([pv, op, np.zeros(N)], -1)[None]
    report = scan_loops(X, classifier=Spread())
    assert report.loc[0, ["status", "n_cycles", "shape_reason"]].tolist() == [
        "ok", 0, "not_oscillating"]  # fmt: skip
    assert report.loc[0, "reason"] == "ok"  # the verdict's reason: the model judged it
    p = spread_probability(X)[0]  # judged all the same, by the model
    assert report.loc[0, "verdict"] == ("stiction" if p >= 0.5 else "no_stiction")
