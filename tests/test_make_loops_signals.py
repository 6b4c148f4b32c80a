"""What make_loops puts in X, measured from X, checked against what meta says.

``meta`` can list an effect that never reached the signals (noise dropped, a wrong
stiction band, a setpoint step lost); these tests measure each effect in X itself.
"""

import ast
import re
from math import comb

import numpy as np
import pytest
from scipy.stats import spearmanr

from sktiction.datasets import make_loops

# the clean world of sktiction 0.1, which these checks were written for
CLASSIC = {"world": "classic"}


def _ar_phi(effects):
    """AR(1) coefficient of the loop's measurement noise (0 for white noise)."""
    m = re.search(r"ARNoise\(phi=([0-9.eE+-]+)", effects)
    return float(m.group(1)) if m else 0.0


def measured_snr_db(pv, phi, order=3):
    """SNR of PV's measurement noise, from PV alone (second half, as ``snr_db`` is defined).

    The ``order``-th difference removes the slow signal and keeps the noise, whose
    variance through that filter is known for AR(1) noise of coefficient ``phi``; a
    median absolute deviation ignores the few large differences of valve slips.
    """
    half = pv[len(pv) // 2 :]
    c = np.array([(-1) ** i * comb(order, i) for i in range(order + 1)], dtype=float)
    lags = np.abs(np.subtract.outer(np.arange(order + 1), np.arange(order + 1)))
    gain = c @ (phi**lags) @ c  # variance of the filtered unit AR(1) noise
    d = np.convolve(half, c, "valid")
    noise_var = (np.median(np.abs(d - np.median(d))) / 0.6745) ** 2 / gain
    return 10 * np.log10(max(half.var() - noise_var, 1e-300) / noise_var)


@pytest.mark.parametrize("seed", [0, 1])
def test_measured_noise_matches_snr_db(seed):
    # Oscillating loops with 10-30 dB noise: there the noise is what the highest
    # frequencies of PV hold (in quiet healthy loops the random-walk load's increments
    # are as large as the noise, and the SNR cannot be read from PV alone).
    X, _, meta = make_loops(
        40, 2000, causes=("external_disturbance",), snr_db_range=(10.0, 30.0),
        random_state=seed, return_meta=True, **CLASSIC,
    )  # fmt: skip
    measured = np.array([measured_snr_db(X[i, :, 0], _ar_phi(e)) for i, e in
                         enumerate(meta["effects"])])  # fmt: skip
    err = measured - meta["snr_db"].to_numpy()
    # measured on seeds 0 and 1: every loop within 2.3 dB, median within 0.2 dB
    assert np.abs(err).max() < 4.0, np.round(err, 1)
    assert abs(np.median(err)) < 1.0
    # noise ten times too small would read 20 dB high
    assert spearmanr(measured, meta["snr_db"])[0] > 0.9


def test_op_swing_of_sticky_loops_follows_the_stiction_band():
    """In a stiction limit cycle OP must travel through the band S to move the valve."""
    X, _, meta = make_loops(
        40, 2000, stiction_fraction=1.0, random_state=0, return_meta=True, **CLASSIC
    )
    op = X[:, 1000:, 1]
    swing = np.quantile(op, 0.98, axis=1) - np.quantile(op, 0.02, axis=1)
    ratio = swing / meta["S"].to_numpy()
    # measured on seeds 0-2: ratio 0.95-1.8 (one outlier of 120 at 6), median 1.1
    assert np.mean((ratio > 0.85) & (ratio < 2.5)) >= 0.9, np.round(ratio, 2)
    assert 0.95 < np.median(ratio) < 1.5
    assert spearmanr(meta["S"], swing)[0] > 0.9


def _steps(effects):
    """(times, sizes) of the SetpointSteps listed in a meta ``effects`` string."""
    m = re.search(r"SetpointSteps\(times=(\([^)]*\)|\[[^\]]*\]), sizes=(\([^)]*\)|\[[^\]]*\])",
                  effects)  # fmt: skip
    if m is None:
        return np.array([]), np.array([])
    return np.atleast_1d(ast.literal_eval(m.group(1))), np.atleast_1d(ast.literal_eval(m.group(2)))


def test_setpoint_steps_are_in_sp_where_meta_lists_them():
    X, _, meta = make_loops(
        30, 1500, slip_fraction=0.5, random_state=3, return_meta=True, **CLASSIC
    )
    n_with_steps = 0
    for i, (effects, ts) in enumerate(zip(meta["effects"], meta["ts"])):
        sp = X[i, :, 2]
        times, sizes = _steps(effects)
        times, sizes = times[times < len(sp) * ts], sizes[times < len(sp) * ts]
        jumps = np.flatnonzero(np.abs(np.diff(sp)) > 1e-9) + 1  # first sample after a jump
        if len(times) == 0:
            assert len(jumps) == 0, (i, effects)
            continue
        n_with_steps += 1
        # steps at distinct samples: one jump each, at the step time, of the step size
        at = np.ceil(times / ts - 1e-9).astype(int)
        assert len(jumps) == len(np.unique(at)), (i, effects, jumps)
        assert np.all(np.abs(jumps - np.unique(at)) <= 1), (i, jumps, at)
        expected = [sizes[at == k].sum() for k in np.unique(at)]
        assert np.allclose(sp[jumps] - sp[jumps - 1], expected, rtol=1e-9, atol=1e-9)
    # the draw has loops with and without steps (every sticky loop and half the quiet ones)
    assert 10 <= n_with_steps < len(X)


# ---- default-world knobs of PV's own variation, quiet loops, setpoint regimes, loop type ----


def _loop_stats(X):
    from sktiction.realism import loop_statistics

    return loop_statistics(X)


def test_pv_own_share_lowers_the_pv_op_correlation():
    """A component OP does not explain carrying a share s of the PV variance scales the PV-OP
    correlation by about sqrt(1 - s) (0.63 for s = 0.6; detrending takes some of the slow
    component away, so a little less)."""
    kw = {"stiction_fraction": 0.5, "random_state": 5}
    corr = [
        _loop_stats(make_loops(80, 600, pv_own_share=(s, s), **kw)[0])["pv_op_corr"].median()
        for s in (0.0, 0.6)
    ]
    ratio = corr[1] / corr[0]
    # measured on seeds 5-6: 0.62-0.63 (sqrt(0.4) = 0.63)
    assert 0.5 < ratio < 0.75, corr


def test_quiet_loops_do_not_cycle_for_either_label():
    """oscillating_fraction=0: loops of every cause are quiet (error ACF peak <= 0.3)."""
    shares = {}
    for frac in (1.0, 0.0):
        X, y = make_loops(120, 600, oscillating_fraction=frac, random_state=8)
        cycling = np.nan_to_num(_loop_stats(X)["acf_peak"].to_numpy()) > 0.3
        shares[frac] = (cycling[y == 1].mean(), cycling[y == 0].mean())
    # measured on seed 8: sticky 0.58 -> 0.07, healthy 0.50 -> 0.12 (seed 9: 0.27 -> 0.10,
    # 0.48 -> 0.18)
    for label in (0, 1):
        assert shares[0.0][label] <= 0.2, shares
        assert shares[1.0][label] - shares[0.0][label] >= 0.15, shares


@pytest.mark.parametrize(
    "weights, check",
    [
        ({"constant": 1.0}, lambda s: (s["sp_change_fraction"] == 0).all()),
        ({"cascade": 1.0}, lambda s: (s["sp_change_fraction"] > 0.2).all()),
        ({"steps": 1.0}, lambda s: ((s["sp_steps"] >= 1) & (s["sp_change_fraction"] < 0.2)).all()),
    ],
    ids=["constant", "cascade", "steps"],
)
def test_setpoint_weights_set_the_regime_seen_in_sp(weights, check):
    # full records: a step late in a record cut short is not in it
    X, _ = make_loops(20, 400, setpoint_weights=weights, short_fraction=0.0, random_state=2)
    assert check(_loop_stats(X))


def test_loop_type_reaches_the_recording_effects():
    """A calibrated world's recording is drawn per loop type: level loops (integrating plants)
    held, the others clean."""
    from sktiction.simulation import HoldLastValue

    class LevelHolds:
        overrides = {}

        def recording_effects(self, rng, loop_type=None):
            return [HoldLastValue(0.4, 5.0)] if loop_type == "level" else []

    X, _, meta = make_loops(30, 400, realism=LevelHolds(), random_state=0, return_meta=True)
    held = _loop_stats(X)["hold_fraction"].to_numpy() > 0.1
    level = (meta["plant"] == "integrating").to_numpy()
    assert level.any() and (~level).any()
    assert held[level].all() and not held[~level].any()


class _ProfileWorld:
    """A calibrated world stand-in: every loop copies one quiet, very clean profile."""

    overrides = {}

    def loop_profile(self, rng):
        settings = {"snr_db_range": (50.0, 50.0), "oscillating_fraction": 0.0}
        return {"loop_type": None, "settings": settings, "recording": []}

    def recording_effects(self, rng, loop_type=None):
        return []


def test_explicit_arguments_win_over_a_calibrated_worlds_profile():
    _, _, meta = make_loops(8, n_samples=600, realism=_ProfileWorld(), random_state=0,
                            return_meta=True)  # fmt: skip
    assert (meta["snr_db"] == 50.0).all()
    _, _, meta = make_loops(8, n_samples=600, realism=_ProfileWorld(), snr_db_range=(0.0, 1.0),
                            random_state=0, return_meta=True)  # fmt: skip
    assert meta["snr_db"].between(0.0, 1.0).all()


def test_load_steps_move_op_to_new_levels_for_either_label():
    """load_step_fraction=1: every loop's record holds load steps that OP answers with a
    new level, sticky and healthy loops alike; 0 (the default) draws none and changes no
    other draw."""
    kw = {"short_fraction": 0.0, "random_state": 7, "return_meta": True}
    X0, y0, meta0 = make_loops(120, 1000, **kw)
    X1, y1, meta1 = make_loops(120, 1000, load_step_fraction=1.0, **kw)
    assert (meta0["load_steps"] == 0).all()
    assert meta1["load_steps"].between(1, 4).all()
    np.testing.assert_array_equal(X0, make_loops(120, 1000, load_step_fraction=0.0, **kw)[0])
    free0 = _loop_stats(X0)["op_load_shifts"].to_numpy() >= 1
    free1 = _loop_stats(X1)["op_load_shifts"].to_numpy() >= 1
    # measured (1,000 samples): healthy 0.03 -> 0.42, sticky 0.10 -> 0.47 on seed 7;
    # seeds 8-9: healthy +0.23 and +0.26, sticky +0.40 and +0.32
    for label in (0, 1):
        assert free0[y0 == label].mean() <= 0.15
        assert free1[y1 == label].mean() - free0[y0 == label].mean() >= 0.2


@pytest.mark.parametrize("value", [-0.1, 1.5, "a"])
def test_load_step_fraction_must_be_a_share(value):
    with pytest.raises((ValueError, TypeError), match="load_step_fraction"):
        make_loops(2, 200, load_step_fraction=value)
