"""The shape library pinned to Srinivasan, Rengaswamy & Miller (2005), Table 1.

Loops are built here from ideal cycles of known OP and PV shape (not with the
package's own template generator), and the expected verdict of every (OP shape,
PV shape) pair, in both orders, is written out below from the paper, not read from
``SHAPE_LIBRARY``: a row swapped or dropped in the code fails here.
"""

import numpy as np
import pytest

from sktiction import ShapeLibraryClassifier

SHAPES = ("rectangular", "triangular", "sinusoidal", "trapezoidal")

# Srinivasan et al. (2005), Table 1 (OP shape, PV shape) for a sticky valve, and the
# rows the package adds, each with its source. Written out literally on purpose.
STICKY = {
    "flow": {
        ("triangular", "rectangular"),  # Table 1: fast process, integral-dominant (square PV)
        ("rectangular", "rectangular"),  # Table 1: fast process, proportional-dominant
        ("triangular", "trapezoidal"),  # Table 3: flow loops 1, 4, 5 (PV trapezoidal)
    },
    "pressure": {
        ("triangular", "sinusoidal"),  # Table 1: slow process (pressure and temperature)
        ("triangular", "triangular"),  # Table 3: pressure loop 6 (PV triangular)
    },
    "temperature": {
        ("triangular", "sinusoidal"),  # Table 1: slow process (pressure and temperature)
        ("triangular", "triangular"),  # as pressure
    },
    "level": {
        ("triangular", "triangular"),  # Table 1: integrating process (level)
        ("triangular", "sinusoidal"),  # Table 1: level under PI, PV parabolic (no template;
        #                                its nearest template is sinusoidal)
    },
}
# loop_type="auto" reads the row off the PV shape (README, ShapeLibraryClassifier docs)
AUTO_ROW = {
    "rectangular": "flow",
    "trapezoidal": "flow",
    "sinusoidal": "pressure",
    "triangular": "level",
}
PAIRS = [(op, pv) for op in SHAPES for pv in SHAPES]

PERIOD = 80
N_CYCLES = 15
OP_AMPLITUDE = 3.0  # % of span: the OP peak-to-peak is 6 %
PV_AMPLITUDE = 2.0


def half_wave(shape, n):
    """One positive half-cycle of ``shape`` on ``n`` samples, peak 1 (independent of
    the package's templates)."""
    tau = (np.arange(n) + 0.5) / n
    if shape == "rectangular":
        return np.ones(n)
    if shape == "triangular":
        return np.interp(tau, [0.0, 0.5, 1.0], [0.0, 1.0, 0.0])
    if shape == "sinusoidal":
        return np.sin(np.pi * tau)
    if shape == "trapezoidal":  # ramps over the first and last fifth of the half
        return np.interp(tau, [0.0, 0.2, 0.8, 1.0], [0.0, 1.0, 1.0, 0.0])
    raise AssertionError(shape)


def wave(shape, n_cycles=N_CYCLES, period=PERIOD):
    half = half_wave(shape, period // 2)
    return np.tile(np.concatenate([half, -half]), n_cycles)


def make_loop(op_shape, pv_shape, rng):
    """One loop: OP and PV cycles of the given shapes, 1 % noise, constant SP."""
    op = 50.0 + OP_AMPLITUDE * wave(op_shape)
    pv = 20.0 + PV_AMPLITUDE * wave(pv_shape)
    op = op + 0.01 * OP_AMPLITUDE * rng.standard_normal(op.size)
    pv = pv + 0.01 * PV_AMPLITUDE * rng.standard_normal(pv.size)
    return np.stack([pv, op, np.full(pv.size, 20.0)], axis=-1)


@pytest.fixture(scope="module")
def loops():
    rng = np.random.default_rng(0)
    return np.stack([make_loop(op, pv, rng) for op, pv in PAIRS])


def expected(loop_type, op, pv):
    row = AUTO_ROW[pv] if loop_type == "auto" else loop_type
    return int((op, pv) in STICKY[row])


def test_the_synthetic_cycles_have_the_shapes_they_are_built_with(loops):
    table = ShapeLibraryClassifier(loop_type="flow").fit(loops).cycle_table(loops)
    for k, (op, pv) in enumerate(PAIRS):
        cycles = table[table["loop"] == k]
        assert len(cycles) >= N_CYCLES - 3, (op, pv)
        assert (cycles["op_shape"] == op).mean() >= 0.9, (op, pv, cycles["op_shape"].tolist())
        assert (cycles["pv_shape"] == pv).mean() >= 0.9, (op, pv, cycles["pv_shape"].tolist())


@pytest.mark.parametrize("loop_type", [*STICKY, "auto"])
def test_verdicts_follow_table_1(loops, loop_type):
    report = ShapeLibraryClassifier(loop_type=loop_type).fit(loops).diagnose(loops)
    want = np.array([expected(loop_type, op, pv) for op, pv in PAIRS])
    got = report["prediction"].to_numpy()
    wrong = [(PAIRS[k], int(want[k])) for k in np.flatnonzero(got != want)]
    assert not wrong, f"{loop_type}: (OP, PV) pairs with the wrong verdict (expected): {wrong}"
    assert (report["reason"] == "ok").all()
    # every cycle has the same shapes, so the confidence (share of sticky cycles) is
    # near 1 or near 0, not just on the right side of 0.5
    score = report["score"].to_numpy()
    assert (score[want == 1] >= 0.9).all() and (score[want == 0] <= 0.1).all()
    if loop_type == "auto":
        rows = [AUTO_ROW[pv] for _, pv in PAIRS]
        assert report["loop_type"].tolist() == rows


@pytest.mark.parametrize("op, pv", [("triangular", "rectangular"), ("rectangular", "triangular")])
def test_both_orders_of_the_fast_flow_row(op, pv):
    """Table 1's first row and its reverse: the swap the issue planted."""
    X = make_loop(op, pv, np.random.default_rng(1))[None]
    clf = ShapeLibraryClassifier(loop_type="flow").fit(X)
    assert clf.predict(X)[0] == int(op == "triangular")


def test_stiction_size_is_the_op_peak_to_peak(loops):
    """Size = OP peak-to-peak over the sticky cycles (section 5.2), here 2 x 3 % of span."""
    report = ShapeLibraryClassifier(loop_type="level").fit(loops).diagnose(loops)
    sticky = report["prediction"] == 1
    assert sticky.sum() == 2
    size = report.loc[sticky, ["stiction_size_mean", "stiction_size_max"]].to_numpy()
    # 1 % noise on a 6 % swing: the measured peak-to-peak is within 10 % of it
    assert np.allclose(size, 2 * OP_AMPLITUDE, rtol=0.1), size
    assert report.loc[~sticky, "stiction_size_mean"].isna().all()


REPORT_COLUMNS = {
    "prediction", "score", "reason", "loop_type", "n_cycles", "n_sticky_cycles",
    "stiction_size_mean", "stiction_size_max",
}  # fmt: skip


def test_diagnose_reports_its_documented_columns_consistently(loops):
    clf = ShapeLibraryClassifier().fit(loops)
    report = clf.diagnose(loops)
    assert set(report.columns) == REPORT_COLUMNS
    for c in ("prediction", "n_cycles", "n_sticky_cycles"):
        assert report[c].dtype.kind == "i", c
    # confidence = share of sticky cycles (Srinivasan et al. 2005, step 17)
    assert np.allclose(report["score"], report["n_sticky_cycles"] / report["n_cycles"])
    assert np.array_equal(clf.predict_proba(loops)[:, 1], report["score"].to_numpy(dtype=float))
    size = clf.stiction_size(loops)
    assert list(size.columns) == ["stiction_size_mean", "stiction_size_max"]
    assert size.equals(report[["stiction_size_mean", "stiction_size_max"]])
    # the default row is read off the PV shape, as loop_type="auto"
    assert report.equals(ShapeLibraryClassifier(loop_type="auto").fit(loops).diagnose(loops))


def test_confidence_and_cycle_thresholds_are_inclusive():
    X = make_loop("triangular", "triangular", np.random.default_rng(2))[None]
    report = ShapeLibraryClassifier(loop_type="level").fit(X).diagnose(X)
    n = int(report.loc[0, "n_cycles"])
    assert report.loc[0, "score"] == 1.0
    # every cycle sticky: confidence 1 reaches min_confidence=1
    assert ShapeLibraryClassifier(loop_type="level", min_confidence=1.0).fit(X).predict(X)[0] == 1
    # exactly min_cycles cycles are enough; one more required gives no verdict
    assert ShapeLibraryClassifier(loop_type="level", min_cycles=n).fit(X).predict(X)[0] == 1
    few = ShapeLibraryClassifier(loop_type="level", min_cycles=n + 1).fit(X).diagnose(X)
    assert few.loc[0, "prediction"] == 0 and few.loc[0, "score"] == 0
    assert few.loc[0, "reason"] == "too_few_cycles"


def test_a_loop_without_cycles_gets_no_row_of_the_library():
    rng = np.random.default_rng(4)
    noise = np.stack([20 + rng.standard_normal(1200), 50 + rng.standard_normal(1200),
                      np.full(1200, 20.0)], axis=-1)[None]  # fmt: skip
    for loop_type, shown in [("auto", "unknown"), ("flow", "flow")]:
        report = ShapeLibraryClassifier(loop_type=loop_type).fit(noise).diagnose(noise)
        assert report.loc[0, "reason"] == "not_oscillating"
        assert report.loc[0, "loop_type"] == shown and report.loc[0, "prediction"] == 0
        assert report.loc[0, "n_cycles"] == 0 and np.isnan(report.loc[0, "stiction_size_max"])


def test_the_template_matcher_given_is_the_one_used(loops):
    from sktiction import TemplateDistances

    default = ShapeLibraryClassifier().fit(loops).cycle_table(loops)
    coarse = ShapeLibraryClassifier(templates=TemplateDistances(n_points=8)).fit(loops)
    table = coarse.cycle_table(loops)
    assert not np.allclose(table["op_dist_triangular"], default["op_dist_triangular"])


@pytest.mark.parametrize(
    "params, match",
    [
        ({"loop_type": "steam"}, "loop_type must be one of"),
        ({"min_confidence": 0.0}, r"min_confidence must be in \(0, 1\]"),
        ({"min_confidence": 1.5}, r"min_confidence must be in \(0, 1\]"),
        ({"min_cycles": 0}, "min_cycles must be an integer >= 1"),
        ({"min_cycles": 2.5}, "min_cycles must be an integer >= 1"),
    ],
)
def test_bad_parameters_are_named(loops, params, match):
    with pytest.raises(ValueError, match=match):
        ShapeLibraryClassifier(**params).fit(loops[:1])


def test_boundary_parameters_are_accepted(loops):
    for params in ({"min_confidence": 1.0}, {"min_cycles": 1}):
        assert ShapeLibraryClassifier(**params).fit(loops[:1]).predict(loops[:1]).shape == (1,)


def test_loops_without_a_verdict_carry_no_evidence():
    rng = np.random.default_rng(0)
    X = np.stack([make_loop("triangular", "triangular", rng) for _ in range(4)])
    X[1, 15:] = np.nan  # too short: 15 samples
    X[2, :, 1] = 40.0  # OP stuck
    X[3] = np.stack([20 + rng.standard_normal(X.shape[1]), 50 + rng.standard_normal(X.shape[1]),
                     np.full(X.shape[1], 20.0)], axis=-1)  # fmt: skip
    report = ShapeLibraryClassifier().fit(X).diagnose(X)
    assert report["reason"].tolist()[:2] == ["ok", "too_short"]
    assert "constant" in report.loc[2, "reason"] and report.loc[3, "reason"] == "not_oscillating"
    assert report.loc[3, "loop_type"] == "unknown"
    evidence = report.loc[1:, ["prediction", "score", "n_cycles", "n_sticky_cycles"]]
    assert (evidence == 0).all().all()
    assert report.loc[1:, "stiction_size_max"].isna().all()


def test_cycle_table_of_a_batch_without_cycles_is_empty_with_the_verdict_columns():
    rng = np.random.default_rng(5)
    noise = np.stack([20 + rng.standard_normal(1200), 50 + rng.standard_normal(1200),
                      np.full(1200, 20.0)], axis=-1)[None]  # fmt: skip
    table = ShapeLibraryClassifier().fit(noise).cycle_table(noise)
    assert len(table) == 0 and {"loop_type", "sticky"} <= set(table.columns)
    assert table["sticky"].dtype == bool
