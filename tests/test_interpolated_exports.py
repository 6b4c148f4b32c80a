"""Interpolated exports of a compressing historian: straight lines drawn between the
points a swinging-door historian stored (PI's interpolated values). No noise is left on
the lines, so the noise level is read from the stored points; every other record reads
as before, to the bit."""

import numpy as np
import pytest

from sktiction.cycles import noise_std
from sktiction.cycles._signal import drawn_lines
from sktiction.datasets import make_loops


def _swinging_door(v, dev):
    """Rows a swinging-door historian stores: the last row before the signal leaves the
    band of +-``dev`` around every line from the last stored point (both ends kept)."""
    keep = [0]
    up, lo = -np.inf, np.inf
    for i in range(1, v.size):
        a = keep[-1]
        up = max(up, (v[i] - v[a] - dev) / (i - a))
        lo = min(lo, (v[i] - v[a] + dev) / (i - a))
        if up > lo:  # no line from the stored point keeps every row within the band
            keep.append(i - 1)
            up, lo = v[i] - v[i - 1] - dev, v[i] - v[i - 1] + dev
    return np.array(keep + [v.size - 1])


def _interpolated(v, dev):
    rows = _swinging_door(v, dev)
    return np.interp(np.arange(v.size), rows, v[rows]), rows


def _rows_noise(x):
    """The second-difference noise level as read from every row (the formula for
    sampled records)."""
    d2 = np.diff(x, 2)
    return 1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6)


def _noisy_sine(noise=0.1, n=3000, seed=0):
    rng = np.random.default_rng(seed)
    return np.sin(2 * np.pi * np.arange(n) / 300) + rng.normal(0, noise, n)


def test_the_stored_points_of_an_interpolated_export_are_found():
    export, rows = _interpolated(_noisy_sine(), 0.15)
    found = drawn_lines(export)
    assert found is not None
    assert np.isin(found, rows).all()  # a bend only where a point was stored
    assert np.isin(rows, found).mean() > 0.95  # and (nearly) every stored point bends


@pytest.mark.parametrize(
    "signal",
    ["sampled", "quantised", "stepped export", "triangle", "square", "short export"],
)
def test_other_records_are_no_interpolated_export(signal):
    x, t = _noisy_sine(), np.arange(3000)
    rows = _swinging_door(x, 0.15)
    record = {
        "sampled": x,
        "quantised": np.round(x / 0.25) * 0.25,  # held on a grid, not drawn
        "stepped export": x[rows[np.searchsorted(rows, t, side="right") - 1]],
        "triangle": np.abs((t % 100) / 50 - 1),  # lines that only turn at corners
        "square": np.sign(np.sin(2 * np.pi * (t + 0.5) / 100)),
        "short export": _interpolated(x[:300], 0.6)[0],  # fewer than 16 stored points
    }[signal]
    assert drawn_lines(record) is None
    assert noise_std(record) == pytest.approx(_rows_noise(record), rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("noise", [0.05, 0.1, 0.2])
def test_the_noise_of_an_interpolated_export_is_read_from_its_points(noise):
    """Read from the rows, the lines have no noise; read from the stored points, the
    scatter a swinging door leaves: where noise sets the points (a deviation of 1.5 noise
    sd), about twice the deviation, not the noise itself, which the export no longer holds."""
    dev = 1.5 * noise
    export, _ = _interpolated(_noisy_sine(noise), dev)
    assert _rows_noise(export) < 0.05 * noise
    assert 1.5 * dev < noise_std(export) < 2.5 * dev


@pytest.mark.parametrize(("scale", "shift"), [(1e-3, 0.0), (7.0, -3e3), (1e4, 50.0)])
def test_a_shifted_or_scaled_export_reads_alike(scale, shift):
    """Normalising a loop must not change what is read as an export (scans analyse raw
    loops, ``diagnose`` normalised ones)."""
    export, _ = _interpolated(_noisy_sine(), 0.15)
    moved = scale * export + shift
    np.testing.assert_array_equal(drawn_lines(moved), drawn_lines(export))
    assert noise_std(moved) == pytest.approx(scale * noise_std(export), rel=1e-9)


def test_an_interpolated_loop_keeps_a_noise_level():
    """The hidden effect: loops exported interpolated, every line drawn between two stored
    points counted as a move against a noise level of about 0. Read from the stored
    points, the level is at least the sampled record's."""
    X, y = make_loops(12, n_samples=3000, world="classic", random_state=4)
    for loop in X:
        for v in loop[:, :2].T:
            sampled = noise_std(v)
            export, _ = _interpolated(v, 1.5 * sampled)
            assert _rows_noise(export) < 0.1 * sampled
            assert noise_std(export) > sampled


def test_a_channel_drawn_through_a_handful_of_points_is_named_too_compressed():
    """PV drawn as lines through 20 points beside an unrelated OP: no judge can relate
    them, and both the gate and the learned classifier say why: the export. The same
    PV sampled (noise on every row) stays pv_op_unrelated."""
    from sktiction import pretrained_classifier
    from sktiction.classifiers.applicability import assess_applicability
    from sktiction.cycles._signal import stored_points

    rng = np.random.default_rng(3)
    n = 2000
    points = np.linspace(0, n - 1, 20).astype(int)
    lines = np.interp(np.arange(n), points, rng.normal(size=20).cumsum())
    op = rng.normal(size=n).cumsum()
    sampled = lines + rng.normal(0, 0.2, n)
    X = np.stack([np.stack([pv, op, np.zeros(n)], axis=1) for pv in (lines, sampled)])
    assert stored_points(lines) == 20 and stored_points(sampled) is None
    gate = assess_applicability(X)["reason"].tolist()
    assert gate == ["too_compressed", "pv_op_unrelated"]
    learned = pretrained_classifier().diagnose(X)["reason"].tolist()
    assert learned == ["too_compressed", "pv_op_unrelated"]
