"""The learned classifier reads its features from the scan's shared analyses of raw loops.

``LearnedStictionClassifier.diagnose`` analyses normalised loops; in a scan the raw
loops are already analysed once for all classifiers, and ``diagnose_analysed`` reuses
those analyses. Normalisation shifts and scales each channel, so the two must agree:
the same verdicts, and the same probabilities except where a decision inside a cycle
analysis sits exactly on its threshold (quantised records), where rounding decides.
"""

import copy

import numpy as np
import pytest

from sktiction._cleaning import align_op, as_judged
from sktiction._validation import check_loops, loop_lengths, loop_status
from sktiction.classifiers import LearnedStictionClassifier
from sktiction.datasets import make_loops
from sktiction.features import _loops
from sktiction.features._loops import analyse_loops
from sktiction.reports import scan as scan_module
from sktiction.reports import scan_loops


@pytest.fixture(scope="module")
def model():
    X, y = make_loops(80, n_samples=1000, random_state=0)
    return LearnedStictionClassifier(max_iter=60, cv=2, random_state=0).fit(X, y)


@pytest.fixture(scope="module")
def loops():
    # default world: historian quantisation and holds, setpoint moves, mixed lengths
    X, _ = make_loops(60, n_samples=1500, random_state=5)
    X[::4, 1000:] = np.nan
    return check_loops(X)


def test_same_verdicts_and_probabilities_as_diagnose(model, loops):
    expected = model.diagnose(loops)
    read = as_judged(loops)  # as a scan reads them (a compressed tag redrawn, ...)
    status = loop_status(read, require_op=True, check_swap=True)
    got = model.diagnose_analysed(read, analyse_loops(read), status)
    assert got.columns.tolist() == expected.columns.tolist()
    np.testing.assert_array_equal(got["prediction"], expected["prediction"])
    np.testing.assert_array_equal(got["in_domain"], expected["in_domain"])
    np.testing.assert_array_equal(got["reason"], expected["reason"])
    judged = expected["in_domain"].to_numpy()
    assert judged.sum() >= 40
    p, q = got["probability"].to_numpy(), expected["probability"].to_numpy()
    assert np.isnan(p[~judged]).all()
    # measured on 673 default- and classic-world loops: 15 differ, by at most 0.032,
    # each through a threshold tie in a quantised record's cycle analysis
    same = np.abs(p[judged] - q[judged]) <= 1e-9
    assert same.mean() >= 0.9


def test_features_in_op_units_are_rescaled(model, loops):
    """The fitted band is in OP units; scaling OP must not change the verdicts."""
    scaled = loops.copy()
    scaled[:, :, 1] = 1e4 * scaled[:, :, 1] - 3e3
    a = model.diagnose_analysed(loops, analyse_loops(loops))
    b = model.diagnose_analysed(scaled, analyse_loops(scaled))
    np.testing.assert_array_equal(a["reason"], b["reason"])
    both = a["in_domain"].to_numpy()
    close = np.abs(a["probability"].to_numpy()[both] - b["probability"].to_numpy()[both]) <= 1e-9
    assert close.mean() >= 0.9


def test_reuses_the_shared_analyses(model, loops, monkeypatch):
    """With the scan's cycle analyses done, the learned model analyses no signal again."""
    analyses = analyse_loops(loops)
    for a in analyses:
        for name in ("error", "op", "pv"):
            a.cycles(name)
    expected = model.diagnose_analysed(loops, analyse_loops(loops))

    def no_more(*args, **kwargs):
        raise AssertionError("a signal was analysed again")

    monkeypatch.setattr(_loops, "_analyze_cycles", no_more)
    got = model.diagnose_analysed(loops, analyses)
    np.testing.assert_array_equal(got["probability"], expected["probability"])


def test_scan_asks_the_shared_path(model, loops, monkeypatch):
    """The scan's probabilities are ``diagnose_analysed``'s; ``diagnose`` is never run."""
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: None)
    loops = loops.copy()
    n = int(loop_lengths(loops[:1])[0])
    loops[0, : n - 1, 1] = loops[0, 1:n, 1]  # OP one row early in the first loop
    loops[0, n - 1] = np.nan
    aligned, shifts = align_op(loops, loop_lengths(loops))
    assert shifts[0] == -1  # the scan must judge it moved back
    # as the scan reads them: repaired (a spike replaced in some loops), then in step; a
    # loop read unrepaired agreed only while no tree split fell between the two readings
    judged_loops = as_judged(loops)
    np.testing.assert_array_equal(judged_loops[0], as_judged(aligned)[0])
    expected = model.diagnose_analysed(judged_loops, analyse_loops(judged_loops))

    def no_diagnose(self, X):
        raise AssertionError("the scan analysed normalised loops again")

    monkeypatch.setattr(LearnedStictionClassifier, "diagnose", no_diagnose)
    report = scan_loops(loops, classifier=model, chunk_size=16)
    judged = expected["in_domain"].to_numpy()
    np.testing.assert_allclose(
        report["stiction_probability"].to_numpy()[judged],
        expected["probability"].to_numpy()[judged],
        rtol=0,
        atol=1e-12,
    )
    np.testing.assert_array_equal(report["verdict"] == "no_verdict", ~judged)


def test_long_records_are_read_in_the_same_windows_as_diagnose(model, loops, monkeypatch):
    """A record longer than ``long_record`` is also read in windows analysed afresh (the
    scan's analyses are of the whole record): the same windows in a scan as in
    ``diagnose``, so the same probabilities (to rounding: a whole record's features agree
    with the normalised copy's to the last bits, and a model trained in 2026-11 put a
    split of a late, small tree between them for one loop, 2e-12 off)."""
    monkeypatch.setattr(scan_module, "_applicability_gate", lambda: None)
    clf = copy.deepcopy(model).set_params(window=400, long_record=1200)
    long = loop_lengths(as_judged(loops)) > 1200
    assert long.sum() >= 30 and (~long).sum() >= 10
    expected = clf.diagnose(loops)
    report = scan_loops(loops, classifier=clf, chunk_size=16)
    np.testing.assert_allclose(
        report["stiction_probability"].to_numpy()[long],
        expected["probability"].to_numpy()[long],
        rtol=0,
        atol=1e-9,
    )
    judged = expected["in_domain"].to_numpy()
    assert judged[long].sum() >= 25
    np.testing.assert_array_equal((report["verdict"] == "no_verdict")[long], ~judged[long])
