"""Tags exported stepped by a compressing historian are read as lines through their
stored points; quantised tags, held rows and plain records are read as they are."""

import numpy as np
import pytest

from sktiction import clean_loops
from sktiction._cleaning import as_judged, exported_stepped
from sktiction.cycles._signal import lines_through_changes
from sktiction.datasets import make_loops


def _deadband(x, band):
    """``x`` as a deadband-compressing historian exports it stepped: a value is stored when
    it moves more than ``band`` from the last one stored, and held until the next."""
    out = np.empty_like(x)
    kept = x[0]
    for t, v in enumerate(x):
        if abs(v - kept) > band:
            kept = v
        out[t] = kept
    return out


def _loop(n=1500, seed=0):
    """A noisy cycle in PV and OP (OP leads by a quarter period) and a flat setpoint."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    pv = np.sin(2 * np.pi * t / 120) + 0.05 * rng.normal(size=n)
    op = 50 + 5 * np.cos(2 * np.pi * t / 120) + 0.2 * rng.normal(size=n)
    return np.column_stack([pv, op, np.zeros(n)])


def test_tags_exported_stepped_are_redrawn_through_their_stored_points():
    loop = _loop()
    stepped = loop.copy()
    stepped[:, 0] = _deadband(loop[:, 0], 0.15)
    stepped[:, 1] = _deadband(loop[:, 1], 0.8)
    assert exported_stepped(stepped[:, 0], stepped[:, 1])
    assert exported_stepped(stepped[:, 1], stepped[:, 0])
    cleaned, report = clean_loops(stepped[None], align=False)
    assert report.loc[0, "stepped_tags"] == 2
    for c in (0, 1):
        np.testing.assert_array_equal(cleaned[0, :, c], lines_through_changes(stepped[:, c], True))
    # the lines pass through the stored points and stay within the band of the record
    assert np.abs(cleaned[0, :, 0] - loop[:, 0]).max() < 0.15 * 2 + 0.25
    # one tag alone
    one = stepped.copy()
    one[:, 1] = loop[:, 1]
    cleaned, report = clean_loops(one[None], align=False)
    assert report.loc[0, "stepped_tags"] == 1
    np.testing.assert_array_equal(cleaned[0, :, 1], loop[:, 1])


def test_quantised_tags_held_rows_and_plain_records_are_read_as_they_are():
    loop = _loop(seed=1)
    quantised = loop.copy()
    quantised[:, 0] = np.round(loop[:, 0] / 0.25) * 0.25  # a grid: levels revisited
    assert not exported_stepped(quantised[:, 0], quantised[:, 1])
    held = loop.copy()
    rows = np.arange(len(held))
    frozen = (rows // 7) % 2 == 1  # whole rows frozen together, on half the record
    for t in np.flatnonzero(frozen):
        held[t, :2] = held[t - 1, :2]
    assert not exported_stepped(held[:, 0], held[:, 1])
    assert not exported_stepped(loop[:, 0], loop[:, 1])
    _, report = clean_loops(np.stack([quantised, held, loop]), align=False)
    assert report["stepped_tags"].tolist() == [0, 0, 0]


def test_exported_stepped_thresholds():
    rng = np.random.default_rng(2)
    walk = np.cumsum(rng.normal(size=1000))
    # held on every other step (half its steps), levels on no grid
    stepped = np.repeat(walk[::2], 2)
    assert exported_stepped(stepped, walk)
    # held on under a fifth of the steps: a record with a few repeats
    sparse = walk.copy()
    sparse[1:390:2] = sparse[0:389:2]  # 195 repeats of 999 steps
    assert not exported_stepped(sparse, walk)
    sparse[1:410:2] = sparse[0:409:2]  # 205: just over a fifth
    assert exported_stepped(sparse, walk)
    # the other tag held on the same steps: whole rows held, not a tag on its own
    assert not exported_stepped(stepped, stepped + 1.0)
    # fewer than ten changes: too few to tell
    assert not exported_stepped(np.repeat(walk[:9], 100), walk[:900])
    # levels on a grid: a quantised tag, also one whose every change is one grid step
    grid = np.repeat(np.round(walk[::2] / 5.0) * 5.0, 2)
    assert not exported_stepped(grid, walk)
    ramp = np.repeat(0.1 * np.arange(500) + 3.0, 2)
    assert not exported_stepped(ramp, walk)
    # a noise-free square cycle holds two levels in turn: the signal's own flats
    k = np.arange(2000)
    square = np.clip(8 * np.sin(2 * np.pi * k / 100), -1, 1)
    assert not exported_stepped(square, np.cumsum(square))
    # one long hold (a manual stretch) in a record that moves on every other row
    manual = walk.copy()
    manual[300:700] = manual[300]
    assert not exported_stepped(manual, walk)
    # a deadband whose every jump is just past the band: levels drift off any grid
    smooth = np.sin(np.arange(2000) / 200.0)
    assert exported_stepped(_deadband(smooth, 0.05), walk[:1000].repeat(2))


def test_training_reads_stepped_exports_as_lines_too():
    X = make_loops(6, 600, recording=("compression",), recording_fraction=1.0,
                   random_state=3)[0]  # fmt: skip
    read = as_judged(X, training=True)
    redrawn = [
        any(not np.array_equal(read[i, :, c], X[i, :, c], equal_nan=True) for c in (0, 1))
        for i in range(len(X))
    ]
    assert any(redrawn)
    for i in np.flatnonzero(redrawn):
        for c in (0, 1):
            if not np.array_equal(read[i, :, c], X[i, :, c], equal_nan=True):
                ok = np.isfinite(X[i, :, c])
                np.testing.assert_array_equal(read[i, ok, c],
                                              lines_through_changes(X[i, ok, c], True))
    assert X is not read  # the caller's loops are left as they are


@pytest.mark.parametrize("seed", [0, 1])
def test_a_stepped_export_is_judged_as_its_lines(seed):
    """Redrawing is all a stepped export gets: judged as is, it gets the verdicts of its
    redrawn lines (which nothing redraws again)."""
    from sktiction import pretrained_classifier

    loop = _loop(seed=seed)
    stepped = loop.copy()
    stepped[:, 0] = _deadband(loop[:, 0], 0.15)
    stepped[:, 1] = _deadband(loop[:, 1], 0.8)
    lines = stepped.copy()
    for c in (0, 1):
        lines[:, c] = lines_through_changes(stepped[:, c], True)
    assert not exported_stepped(lines[:, 0], lines[:, 1])
    clf = pretrained_classifier()
    a, b = clf.diagnose(stepped[None]), clf.diagnose(lines[None])
    assert a["reason"].tolist() == b["reason"].tolist()
    np.testing.assert_allclose(a["probability"], b["probability"], rtol=1e-12)


@pytest.mark.parametrize("tags, says", [(0, None), (1, "one tag"), (2, "PV and OP")])
def test_a_file_scan_says_which_tags_it_redrew(tags, says):
    from sktiction.reports._stream import _note_repairs

    row = {"rows_per_value": 1.0, "n_spikes": 0.0, "n_placeholders": 0.0, "kept_start": 0.0,
           "kept_stop": 100.0, "n_samples": 100, "reason": "", "stepped_tags": float(tags)}
    _note_repairs(row)
    if says is None:
        assert row["reason"] == ""
    else:
        assert row["reason"].startswith(says + " exported stepped")
        assert "redrawn as lines through those points" in row["reason"]


def test_a_saturated_stretch_of_a_stepped_op_stays_flat():
    """Runs at OP's limits are kept as they are: lines would turn a saturation into ramps."""
    loop = _loop(seed=3)
    op = _deadband(loop[:, 1], 0.8)
    op[200:260] = op.max() + 5.0  # driven to its limit twice
    op[900:950] = op.max()
    stepped = loop.copy()
    stepped[:, 1] = op
    cleaned, report = clean_loops(stepped[None], align=False)
    assert report.loc[0, "stepped_tags"] == 1
    np.testing.assert_array_equal(cleaned[0, 200:260, 1], op[200:260])
    np.testing.assert_array_equal(cleaned[0, 900:950, 1], op[900:950])
    np.testing.assert_array_equal(cleaned[0, :, 1], lines_through_changes(op, True))
    # drawn plainly, the saturations would have become ramps
    assert np.ptp(lines_through_changes(op)[200:260]) > 0
