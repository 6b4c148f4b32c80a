"""The one-pass scan: the same report as the three classifiers run one by one, streamed
from files with bounded memory, and the same report on a dask cluster."""

import numpy as np
import pandas as pd
import pytest
from sklearn.ensemble import HistGradientBoostingClassifier
from sklearn.pipeline import FeatureUnion, Pipeline

from sktiction import AreaRatio, LoopDescriptors, StictionModelFit, TemplateDistances
from sktiction._cleaning import GAP_COLUMNS
from sktiction.classifiers import AreaRatioClassifier, ShapeLibraryClassifier
from sktiction.cycles import analyze_cycles
from sktiction.datasets import make_loops
from sktiction.features.hysteresis import valve_band
from sktiction.reports import scan as scan_module
from sktiction.reports import scan_loops


@pytest.fixture(scope="module")
def small_learned():
    """A learned pipeline of the package's transformers (the scan reads their features
    from its shared pass), fitted on a few simulated loops."""
    X, y = make_loops(80, n_samples=1000, slip_fraction=0.25, random_state=0)
    features = FeatureUnion(
        [
            ("area", AreaRatio()),
            ("templates", TemplateDistances()),
            ("descriptors", LoopDescriptors()),
            ("valve_model", StictionModelFit()),
        ]
    )
    model = HistGradientBoostingClassifier(max_iter=40, random_state=0)
    return Pipeline([("features", features), ("model", model)]).fit(X, y)


@pytest.fixture
def no_gate(monkeypatch):
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: None)


def reference_scan(X, loop_types, learned):
    """The scan as it was before the shared pass: each classifier on its own (reference)."""
    from sktiction._cleaning import align_op, drop_startup, repaired
    from sktiction._validation import check_loops, loop_lengths, loop_status

    # first repaired, a start-up transient dropped and OP in line with PV, as the scan
    # does (a learned pipeline need not)
    loops = repaired(check_loops(X), "auto")[0]
    loops, startup = drop_startup(loops, loop_lengths(loops))
    loops, shifts = align_op(loops, loop_lengths(loops))
    ar = AreaRatioClassifier().fit(loops).diagnose(loops)
    parts = []
    for lt in pd.unique(loop_types):
        idx = np.flatnonzero(loop_types == lt)
        part = ShapeLibraryClassifier(loop_type=lt).fit(loops[idx]).diagnose(loops[idx])
        parts.append(part.set_axis(idx))
    shape = pd.concat(parts).sort_index()
    status = loop_status(loops, require_op=True, check_swap=True)
    ok = status == "ok"
    proba = np.full(len(loops), np.nan)
    proba[ok] = learned.predict_proba(loops[ok])[:, 1]
    sticky = ok & (proba >= 0.5)
    size = np.array(shape[["stiction_size_mean", "stiction_size_max"]], dtype=float)
    size[~sticky] = np.nan
    band = [valve_band(x[:n, 0], x[:n, 1]) if s else np.nan
            for x, n, s in zip(loops, loop_lengths(loops), sticky)]  # fmt: skip
    index, period = np.full(len(loops), np.nan), np.full(len(loops), np.nan)
    oscillating = pd.array([pd.NA] * len(loops), dtype="boolean")
    for i, n in enumerate(loop_lengths(loops)):  # OP and PV on their own, the larger index
        if status[i] in ("empty", "too_short", "nan_gap"):
            continue
        signals = [loops[i, :n, c] for c in (1, 0)]
        read = [analyze_cycles(x) for x in signals if np.isfinite(x).all() and np.ptp(x) > 0]
        if read:
            best = max(read, key=lambda a: a.oscillation_index)
            oscillating[i], index[i] = best.oscillating, best.oscillation_index
            period[i] = best.periods[0] if best.oscillating else np.nan
    return pd.DataFrame(
        {
            "status": status,
            "verdict": np.where(ok, np.where(sticky, "stiction", "no_stiction"), "no_verdict"),
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
            "stiction_band_fit": np.asarray(band, dtype=float),
            "startup_rows": startup,
            "op_shift": shifts,
            "rows_per_sample": np.where(ok, 1.0, np.nan),  # a pipeline reads loops as given
            "reason": status,  # "ok" where the learned model judged the loop
        }
    )


def mixed_loops():
    X, _ = make_loops(14, n_samples=2500, random_state=11)
    Xs, _ = make_loops(6, n_samples=2500, stiction_fraction=1.0, random_state=12)
    X = np.concatenate([X, Xs])
    X[2, 300:340] = np.nan  # gap
    X[4, :, 1] = np.nan  # no OP
    X[6, 1500:] = np.nan  # shorter loop
    X[8, :, 0] = 3.0  # constant PV
    t = np.arange(X.shape[1])[:, None]  # loop 10 starts from rest: a start-up transient
    X[10, :, :2] += 4 * np.ptp(X[10, 500:, :2], axis=0) * np.exp(-t / 15)
    types = np.array(["auto", "flow", "level", "pressure", "auto"] * 4, dtype=object)
    return X, types


def test_one_pass_scan_equals_the_classifiers_run_one_by_one(small_learned, no_gate):
    X, types = mixed_loops()
    expected = reference_scan(X, types, small_learned)
    got = scan_loops(X, pd.DataFrame({"loop_type": types}), classifier=small_learned, chunk_size=7)
    assert got.loc[2, "n_bridged"] + got.loc[2, "n_gaps_split"] > 0  # its gap repaired
    assert got.loc[10, "startup_rows"] > 0 and (got["startup_rows"] > 0).sum() == 1
    got = got.drop(columns=["loop_type", *GAP_COLUMNS])
    assert set(got["verdict"]) == {"stiction", "no_stiction", "no_verdict"}
    assert (got["n_cycles"] > 0).sum() >= 4 and got["area_ratio"].notna().sum() >= 4
    pd.testing.assert_frame_equal(got, expected, check_dtype=False, rtol=1e-12)


def test_learned_model_is_asked_through_predict_proba_when_it_is_not_a_pipeline(no_gate):
    class Constant:
        """Any classifier: the scan must not depend on how it computes its features."""

        def predict_proba(self, X):
            return np.column_stack([np.full(len(X), 0.3), np.full(len(X), 0.7)])

    X, types = mixed_loops()
    report = scan_loops(X, classifier=Constant())
    ok = report["status"].eq("ok")
    assert report.loc[ok, "stiction_probability"].eq(0.7).all()
    assert report.loc[ok, "verdict"].eq("stiction").all()
    assert report.loc[~ok, "verdict"].eq("no_verdict").all()


def test_a_model_that_abstains_gives_no_verdict_with_its_reason(no_gate):
    class Abstaining:
        def predict_proba(self, X):
            return np.column_stack([np.zeros(len(X)), np.ones(len(X))])

        def diagnose(self, X):
            inside = np.arange(len(X)) % 2 == 0
            return pd.DataFrame(
                {
                    "probability": np.ones(len(X)),
                    "in_domain": inside,
                    "reason": np.where(inside, "ok", "unlike_training"),
                }
            )

    X, _ = make_loops(4, n_samples=1500, random_state=1)
    report = scan_loops(X, classifier=Abstaining())
    np.testing.assert_array_equal(report["stiction_probability"], [1.0, np.nan] * 2)
    assert report["verdict"].tolist() == ["stiction", "no_verdict"] * 2
    assert report["reason"].tolist()[1::2] == ["unlike_training"] * 2


def test_loops_the_gate_rejects_get_no_verdict_and_its_reason(small_learned, monkeypatch):
    def gate(loops, ts=None):
        first = np.arange(len(loops)) == 0
        return pd.DataFrame({"applicable": ~first, "reason": np.where(first, "quantised", "ok")})

    X, _ = make_loops(6, n_samples=1500, stiction_fraction=1.0, random_state=2)
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: lambda loops, ts=None:
                        pd.DataFrame({"applicable": np.ones(len(loops), bool), "reason": "ok"}))
    ungated = scan_loops(X, classifier=small_learned, chunk_size=3)
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: gate)
    report = scan_loops(X, classifier=small_learned, chunk_size=3)
    rejected = report.index.isin([0, 3])  # the first loop of each chunk
    assert report.loc[rejected, "verdict"].eq("no_verdict").all()
    assert report.loc[rejected, "reason"].eq("quantised").all()
    # no probability beside "no verdict": the gate says the model cannot judge these
    assert report.loc[rejected, "stiction_probability"].isna().all()
    assert report.loc[~rejected, "stiction_probability"].notna().all()
    assert report.loc[~rejected, "reason"].eq("ok").all()
    assert report.loc[rejected, "stiction_size_mean"].isna().all()
    # the others keep the verdicts they get when the gate lets every loop through
    assert ungated["verdict"].ne("no_verdict").all()
    pd.testing.assert_series_equal(report.loc[~rejected, "verdict"],
                                   ungated.loc[~rejected, "verdict"])  # fmt: skip


def test_scan_rejects_bad_chunk_size(small_learned):
    X, _ = make_loops(2, n_samples=1000, random_state=0)
    with pytest.raises(ValueError, match="chunk_size"):
        scan_loops(X, classifier=small_learned, chunk_size=0)


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """A small site on disk: CSV loops of mixed lengths, one with a gap, a broken file,
    a file that is not a loop file."""
    folder = tmp_path_factory.mktemp("site")
    X, _ = make_loops(7, n_samples=2000, stiction_fraction=0.5, random_state=21)
    lengths = [2000, 1500, 1800, 2000, 1200, 2000, 1600]
    X[3, 700:703] = np.nan  # a short gap, bridged by the repair
    for i, n in enumerate(lengths):
        pd.DataFrame(
            {"t": np.arange(n), "PV": X[i, :n, 0], "OP": X[i, :n, 1], "SP": X[i, :n, 2]}
        ).to_csv(folder / f"FIC{i:03d}.csv", index=False)
    (folder / "FIC050.csv").write_text("t,PV,OP\n0,1,abc\n")
    (folder / "readme.docx").write_bytes(b"PK\x03\x04 not a loop file")
    return folder


def test_scan_files_equals_scan_loops_on_the_same_loops(site, small_learned, no_gate):
    from sktiction.datasets import read_loop_file
    from sktiction.reports import scan_files

    report = scan_files(site, classifier=small_learned, chunk_size=3, max_gap=None)
    assert report["file"].tolist() == sorted(p.name for p in site.iterdir())
    unreadable = report["file"].isin(["FIC050.csv", "readme.docx"])
    assert report.loc[unreadable, "status"].eq("unreadable").all()
    assert report.loc[unreadable, "verdict"].eq("no_verdict").all()
    assert report.loc[unreadable, "reason"].str.len().gt(0).all()
    files = sorted(site.glob("FIC0[0-4]?.csv"))[:7]
    datas = [read_loop_file(f) for f in files]
    n = max(d.X.shape[1] for d in datas)
    X = np.full((len(datas), n, 3), np.nan)
    for i, d in enumerate(datas):
        X[i, : d.X.shape[1]] = d.X[0]
    meta = pd.concat([d.meta for d in datas], ignore_index=True)
    assert meta["loop_type"].eq("flow").all()  # from the tags: the flow row of the library
    expected = scan_loops(X, meta, classifier=small_learned, max_gap=None)
    got = report.loc[~unreadable, expected.columns].reset_index(drop=True)
    assert got.loc[3, "status"] == "nan_gap"  # no repair asked for
    pd.testing.assert_frame_equal(got, expected, check_dtype=False, rtol=1e-12)


def test_scan_files_bridges_short_gaps_and_does_not_depend_on_the_chunk(
    site, small_learned, no_gate
):
    from sktiction.reports import scan_files

    one = scan_files(site, classifier=small_learned, chunk_size=1, max_gap=5)
    four = scan_files(site, classifier=small_learned, chunk_size=4, n_jobs=2, max_gap=5)
    pd.testing.assert_frame_equal(one, four)
    gap = one[one["file"] == "FIC003.csv"].iloc[0]
    assert gap["status"] == "ok" and gap["n_bridged"] == 1


def test_scans_on_a_dask_cluster_give_the_local_report(site, small_learned):
    distributed = pytest.importorskip("distributed")
    from sktiction.reports import scan_files

    local = scan_files(site, classifier=small_learned, chunk_size=2)
    # one in-process worker over TCP on loopback: light, and the real transport
    with (
        distributed.LocalCluster(
            n_workers=1,
            threads_per_worker=1,
            processes=False,
            protocol="tcp://",
            host="127.0.0.1",
            dashboard_address=":0",
            worker_dashboard_address=None,
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        remote = scan_files(site, classifier=small_learned, chunk_size=2, client=client)
        X, types = mixed_loops()
        meta = pd.DataFrame({"loop_type": types})
        in_memory = scan_loops(X, meta, classifier=small_learned, chunk_size=6, client=client)
    pd.testing.assert_frame_equal(remote, local)
    pd.testing.assert_frame_equal(in_memory, scan_loops(X, meta, classifier=small_learned))


def test_the_model_runs_in_one_process_inside_the_scan_workers(small_learned, no_gate):
    from sklearn.base import clone

    from sktiction.reports.scan import LearnedAdapter

    parallel = clone(small_learned).set_params(features__n_jobs=2)
    X, _ = make_loops(3, n_samples=1500, random_state=3)
    y = np.array([0, 1, 0])
    parallel.fit(np.concatenate([X] * 4), np.tile(y, 4))
    adapter = LearnedAdapter(parallel)
    assert adapter.classifier.get_params()["features__n_jobs"] == 1
    assert parallel.get_params()["features__n_jobs"] == 2  # the caller's model is untouched
    np.testing.assert_array_equal(
        scan_loops(X, classifier=parallel)["stiction_probability"], parallel.predict_proba(X)[:, 1]
    )


def test_shared_models_are_unpickled_once_per_worker_and_scan():
    blob = scan_module._SharedBlob([{"model": 1}, [2]])
    first = blob.load()
    assert first == ({"model": 1}, [2])
    assert blob.load() is first  # cached: not unpickled again
    other = scan_module._SharedBlob(["next scan"])
    assert other.load() == ("next scan",)
    assert list(scan_module._WORKER_SHARED) == [other.token]  # one scan's models kept
    result = scan_module._with_shared(lambda a, b, c: (a, b, c), (1, 2), other)
    assert result == (1, 2, "next scan")


def test_a_band_fit_that_fails_costs_the_size_not_the_verdict(monkeypatch, small_learned):
    def fail(analysis):
        raise np.linalg.LinAlgError("singular")

    monkeypatch.setattr(scan_module, "analysed_valve_band", fail)
    X, _ = make_loops(6, n_samples=1500, stiction_fraction=1.0, world="classic",
                      random_state=4)  # fmt: skip
    report = scan_loops(X, classifier=small_learned)
    assert (report["status"] == "ok").all() and (report["verdict"] == "stiction").any()
    assert report["stiction_band_fit"].isna().all()


def test_a_loop_with_infinite_values_gets_its_own_status(small_learned, no_gate):
    """inf is not a gap: that loop gets not_finite, naming the channel; the rest are scanned."""
    X, _ = make_loops(4, n_samples=1500, random_state=0)
    clean = scan_loops(X, classifier=small_learned, chunk_size=3)
    X[1, 100, 1] = np.inf
    X[0, 5, 2] = -np.inf  # the first loop too: it must not be what the rules are built on
    report = scan_loops(X, classifier=small_learned, chunk_size=3)
    assert report["status"].tolist()[:2] == ["not_finite"] * 2
    assert report.loc[1, "reason"] == "not_finite: infinite values in OP"
    assert report.loc[0, "reason"] == "not_finite: infinite values in SP"
    assert report.loc[1, "verdict"] == "no_verdict"
    others = [2, 3]
    pd.testing.assert_frame_equal(report.loc[others], clean.loc[others], check_dtype=False)


def test_scan_loops_bridges_gaps_as_scan_files_does_unless_told_not_to(small_learned, no_gate):
    from sktiction._validation import repair_gaps

    X, _ = make_loops(4, n_samples=1500, world="classic", random_state=3)  # full lengths
    X[0, 700:702] = np.nan  # short: bridged
    X[1, 400:700] = np.nan  # long: the longest stretch is kept
    X[2, 10, 1] = np.inf  # left alone: not_finite
    plain = scan_loops(X, classifier=small_learned, max_gap=None)
    assert plain["status"].tolist()[:3] == ["nan_gap", "nan_gap", "not_finite"]
    report = scan_loops(X, classifier=small_learned, chunk_size=3)  # max_gap="auto"
    assert list(report.columns[:8]) == ["n_bridged", "n_gaps_split", "kept_start", "kept_stop",
                                        "n_spikes", "rows_per_value", "n_placeholders",
                                        "stepped_tags"]  # fmt: skip
    assert report["status"].tolist() == ["ok", "ok", "not_finite", "ok"]
    assert report.loc[0, "n_bridged"] == 1 and report.loc[1, "kept_start"] == 700
    assert np.isnan(report.loc[2, "n_bridged"])
    fixed, _ = repair_gaps(np.delete(X, 2, axis=0))
    expected = scan_loops(fixed, classifier=small_learned, max_gap=None)
    kept = report.drop(index=2).drop(columns=report.columns[:8]).reset_index(drop=True)
    pd.testing.assert_frame_equal(kept, expected, check_dtype=False)
    with pytest.raises(ValueError):
        scan_loops(X, classifier=small_learned, max_gap=-1)


def test_a_scan_that_leaves_gaps_says_how_to_bridge_them(small_learned, no_gate):
    X, types = mixed_loops()  # loop 2 has a gap of 40 rows
    with pytest.warns(UserWarning, match=r"of 20 loops have NaN gaps .* max_gap='auto'") as w:
        report = scan_loops(X, classifier=small_learned, max_gap=None)
    gaps = report["status"].eq("nan_gap").sum()
    assert gaps >= 1 and str(w[0].message).startswith(f"{gaps} of 20 loops")
    assert report.loc[2, "status"] == "nan_gap"
