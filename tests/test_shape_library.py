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
