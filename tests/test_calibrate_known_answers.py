"""Known answers of ``calibrate`` and ``Realism`` (sktiction/realism/calibrate.py).

Statistics tables built by hand (``calibrate`` takes a table of ``loop_statistics`` columns as
it is), so each fitted value follows from the definition: the per-loop profile, the weights of
``groups``, the overrides, and the pilot refinements with ``_pilot`` replaced by a world whose
answer is known (a PV-OP correlation scaled by ``sqrt(1 - share)``, a noise level twice the
measured one, fixed shares of cycling loops). A few real loops (classic world, 300 samples)
check what the docs promise of scale and offset, loop types and the recording applied.
"""

import importlib
import warnings

import numpy as np
import pandas as pd
import pytest
from sklearn.utils import Bunch

from sktiction.datasets import make_loops
from sktiction.realism import (
    STATISTIC_COLUMNS,
    Realism,
    apply_effects,
    apply_recording,
    calibrate,
    effect_names,
    loop_statistics,
)
from sktiction.realism._catalog import snr_per_loop
from sktiction.simulation import historian

calibrate_module = importlib.import_module("sktiction.realism.calibrate")

RECORDING = effect_names("recording")

# a loop that shows no recording effect and no cycle, SP constant, PV-OP correlation 0.7
_NEUTRAL = {
    "n_samples": 500, "ts": 1.0, "has_op": True, "has_sp": True, "nan_fraction": 0.0,
    "pv_span": 1.0, "op_span": 1.0, "error_span": 1.0, "pv_noise": 0.02, "op_noise": 0.02,
    "noise_level": 0.02, "op_noise_level": 0.02, "noise_colour": 0.6, "diff_acf_min": 0.0,
    "averaging_lag": np.nan, "averaging_contrast": 0.0, "pv_averaging_contrast": 0.0,
    "pv_repeat_fraction": 0.0, "op_repeat_fraction": 0.0, "row_repeat_fraction": 0.0,
    "joint_repeat_excess": 0.0, "hold_fraction": 0.0, "hold_run_length": np.nan,
    "independent_freeze": 0.0, "line_share": 0.0, "line_deviation": np.nan,
    "pv_level_reuse": 0.0, "op_level_reuse": 0.0, "pv_step": np.nan, "pv_band": np.nan,
    "op_band": np.nan, "spike_rate": 0.0, "spike_size": np.nan, "pv_drift": 0.1,
    "op_drift": 0.0, "op_load_shifts": 0.0, "sp_change_fraction": 0.0, "sp_steps": 0.0,
    "sp_step_size": np.nan,
    "sp_offset": 0.0, "acf_peak": 0.1, "period": np.nan, "regularity": np.nan,
    "decorrelation_lag": 5.0, "pv_op_corr": 0.7, "pv_op_max_corr": 0.7, "pv_op_lag": 0.0,
    "op_saturation": 0.0,
}  # fmt: skip


def _table(n, **cols):
    """Statistics of ``n`` neutral loops; each keyword sets a column (scalar or per loop)."""
    assert set(_NEUTRAL) == set(STATISTIC_COLUMNS)
    data = {c: np.full(n, _NEUTRAL[c], dtype=type(_NEUTRAL[c])) for c in STATISTIC_COLUMNS}
    for c, v in cols.items():
        assert c in data, c
        data[c] = np.broadcast_to(np.asarray(v), (n,)).copy()
    return pd.DataFrame(data)


def _profiles(rows):
    """Profiles table with every recording effect off, one row per dict in ``rows``."""
    base = {"loop_type": "all", "snr_db": np.nan, "white_noise": False, "oscillating": 0.0,
            "setpoint_regime": None, "pv_own_share": np.nan}  # fmt: skip
    base.update(dict.fromkeys(RECORDING, False))
    return pd.DataFrame([{**base, **r} for r in rows])


def _no_pilot(*args, **kwargs):
    raise AssertionError("no pilot simulation expected here")


# ---- the per-loop profile --------------------------------------------------------------------


def test_own_share_lowers_the_correlation_by_sqrt_one_minus_share():
    own = calibrate_module._own_share
    assert own(0.35, 0.7) == pytest.approx(0.75)  # 0.35 = 0.7 sqrt(1 - 0.75)
    assert own(0.6, 0.75) == pytest.approx(1 - 0.64)
    assert own(-0.35, 0.7) == pytest.approx(0.75)  # squared: the sign does not matter
    assert own(0.7, 0.7) == 0.0
    assert own(0.9, 0.7) == 0.0  # more correlated than the reference: no own variation
    assert own(0.0, 0.7) == calibrate_module._MAX_SHARE == 0.9
    assert own(0.05, 0.7) == 0.9  # 0.995 clipped to the largest share
    assert own(np.nan, 0.7) == 0.0 and own(0.5, np.nan) == 0.0
    assert isinstance(own(0.35, 0.7), float)


def test_profile_of_each_loop_from_its_statistics():
    stats = _table(
        5,
        noise_level=[0.02, 0.05, np.nan, 0.0, 0.1],
        noise_colour=[0.1, 0.3, np.nan, -0.5, 0.29],
        acf_peak=[0.5, 0.3, np.nan, 0.31, 0.0],
        has_sp=[True, True, True, True, False],
        sp_change_fraction=[0.0, 0.01, 0.3, 0.01, 0.0],
        sp_steps=[0.0, 1.0, 5.0, 3.0, 0.0],
        pv_op_corr=[0.1, 0.35, np.nan, 0.6, 0.9],
    )
    realism = calibrate(stats, refine=False)
    prof = realism.profiles
    assert realism.statistics is stats
    assert prof["loop_type"].tolist() == ["all"] * 5 and "weight" not in prof
    np.testing.assert_array_equal(prof["snr_db"], snr_per_loop(stats))
    # the Gaussian first guess by hand: error sd 1 / 3.3 of its range, the rest is signal
    sd = 1 / 3.3
    assert prof.loc[0, "snr_db"] == pytest.approx(20 * np.log10(np.sqrt(sd**2 - 0.02**2) / 0.02))
    assert np.isnan(prof.loc[2, "snr_db"]) and np.isnan(prof.loc[3, "snr_db"])
    assert prof["white_noise"].tolist() == [True, False, False, True, True]  # colour < 0.3
    assert prof["oscillating"].tolist() == [1.0, 0.0, 0.0, 1.0, 0.0]  # ACF peak > 0.3
    assert prof["oscillating"].dtype == float
    regimes = prof["setpoint_regime"].tolist()
    assert regimes[:4] == ["constant", "step", "cascade", "steps"]
    assert not isinstance(regimes[4], str)  # no SP recorded: no regime
    np.testing.assert_array_equal(prof["pv_op_corr"], stats["pv_op_corr"])
    # the first guess of PV's own share: from the median correlation (0.475), the same for all
    first = 1 - (0.475 / calibrate_module._CORR_REFERENCE) ** 2
    np.testing.assert_allclose(prof["pv_own_share"], first)
    assert realism.overrides["pv_own_share"] == pytest.approx((first, first))
    assert realism.snr_shift == 0.0
    # no recording effect shows
    assert not prof[RECORDING].to_numpy().any()
    assert repr(realism) == "Realism(n_loops=5, no recording effects)"


def test_own_share_without_any_correlation_is_zero():
    realism = calibrate(_table(6, pv_op_corr=np.nan), refine=False)
    assert (realism.profiles["pv_own_share"] == 0.0).all()
    assert realism.overrides["pv_own_share"] == (0.0, 0.0)
    # correlations at the reference or above: no own variation either
    realism = calibrate(_table(6, pv_op_corr=[0.7, 0.8, 0.9, 0.95, 1.0, 0.75]), refine=False)
    assert realism.overrides["pv_own_share"] == (0.0, 0.0)


def test_recording_effects_and_their_parameters_per_loop():
    """Hold read from the held share (rows of runs of 1 left out: a share 1 / L**2 put back)
    and run length, spikes from their rate and size, drift from its size; a grid needs a
    readable step: a loop whose parameters cannot be read does not get the effect."""
    stats = _table(
        4,
        hold_fraction=[0.3, 0.0, 0.01, 0.3],
        hold_run_length=[5.0, np.nan, 4.0, 5.0],
        spike_rate=[0.0, 0.01, 0.0, 0.0],
        spike_size=[np.nan, 1.5, np.nan, np.nan],
        pv_level_reuse=[0.0, 0.0, 0.5, 0.5],
        pv_step=[np.nan, np.nan, 0.04, np.nan],
        pv_drift=[0.1, 2.5, 0.1, 0.1],
    )
    realism = calibrate(stats, refine=False)
    prof = realism.profiles
    assert prof["hold_last_value"].tolist() == [True, False, False, True]
    assert prof["spikes"].tolist() == [False, True, False, False]
    assert prof["drift"].tolist() == [False, True, False, False]
    assert prof["quantisation"].tolist() == [False, False, True, False]  # loop 3: no step
    assert prof["hold_last_value"].dtype == bool
    assert prof.loc[0, "hold_last_value.mean_run"] == 5.0
    assert prof.loc[1, "drift.size"] == 2.5
    assert prof.loc[2, "quantisation.step"] == 0.04
    assert prof.loc[2, "quantisation.step_noise"] == pytest.approx(0.04 / 0.02)
    # the effects of one loop in the historian's order, made with the fitted parameters
    effects = Realism._effects(prof.iloc[1])
    assert [type(e).__name__ for e in effects] == ["SensorDrift", "Spikes"]
    assert effects[0].size == 2.5
    hold = Realism._effects(prof.iloc[0])
    assert [type(e) for e in hold] == [historian.HoldLastValue]
    assert hold[0].mean_run == 5.0
    assert realism.share("hold_last_value") == 0.5 and realism.share("spikes") == 0.25
    assert repr(realism) == (
        "Realism(n_loops=4, drift=0.25, quantisation=0.25, hold_last_value=0.50, spikes=0.25)"
    )


def test_summary_shares_and_medians_per_loop_type():
    stats = _table(
        6,
        hold_fraction=[0.3, 0.1, 0.0, 0.0, 0.2, 0.0],
        hold_run_length=[5.0, 2.0, np.nan, np.nan, 3.0, np.nan],
    )
    types = ["level", "level", "level", "flow", "flow", "flow"]
    realism = calibrate(stats, loop_types=types, refine=False)
    table = realism.summary()
    assert list(table.columns) == ["loop_type", "effect", "share", "n_loops", "params"]
    assert table["loop_type"].unique().tolist() == ["all", "flow", "level"]
    hold = table[table["effect"] == "hold_last_value"].set_index("loop_type")
    assert hold["share"].to_dict() == pytest.approx({"all": 0.5, "flow": 1 / 3, "level": 2 / 3})
    assert hold["n_loops"].to_dict() == {"all": 6, "flow": 3, "level": 3}
    assert hold.loc["all", "params"]["mean_run"] == 3.0  # median of 5, 2, 3
    assert hold.loc["level", "params"]["mean_run"] == 3.5
    assert hold.loc["flow", "params"]["mean_run"] == 3.0
    spikes = table[table["effect"] == "spikes"].set_index("loop_type")
    assert (spikes["share"] == 0).all() and spikes.loc["all", "params"] == {}
    assert realism.share("hold_last_value", loop_type="level") == pytest.approx(2 / 3)
    assert realism.share("hold_last_value", loop_type="pressure") == 0.5  # unknown: all loops
    with pytest.raises(ValueError, match="recording effect.*'noise_level'"):
        realism.share("noise_level")


# ---- loop types, groups, overrides --------------------------------------------------------------


def test_loop_types_come_from_the_argument_or_the_bunch():
    X, _ = make_loops(4, 300, world="classic", random_state=0)
    meta = pd.DataFrame({"loop_type": ["level", "flow", "flow", "level"]})
    realism = calibrate(Bunch(X=X, meta=meta), refine=False)
    assert realism.profiles["loop_type"].tolist() == ["level", "flow", "flow", "level"]
    pd.testing.assert_frame_equal(realism.statistics, loop_statistics(X))
    other = calibrate(Bunch(X=X, meta=meta), loop_types=list("abcd"), refine=False)
    assert other.profiles["loop_type"].tolist() == list("abcd")
    # a Bunch without loop types: all loops are one type
    plain = calibrate(Bunch(X=X, meta=pd.DataFrame({"ts": np.ones(4)})), refine=False)
    assert plain.profiles["loop_type"].tolist() == ["all"] * 4
    with pytest.raises(
        ValueError, match=r"loop_types must have one entry per measured loop \(4\); got 3"
    ):
        calibrate(X, loop_types=["a", "b", "c"], refine=False)


def test_groups_weigh_each_group_alike():
    stats = _table(6)
    realism = calibrate(stats, groups=["a", "a", 7, "b", 7, 7], refine=False)
    np.testing.assert_allclose(realism.profiles["weight"], [0.5, 0.5, 1 / 3, 1.0, 1 / 3, 1 / 3])
    # every group gets the same total weight
    w = realism.profiles.groupby(np.array(["a", "a", "7", "b", "7", "7"]))["weight"].sum()
    np.testing.assert_allclose(w, 1.0)
    with pytest.raises(
        ValueError, match=r"groups must have one entry per measured loop \(6\); got 2"
    ):
        calibrate(stats, groups=["a", "b"], refine=False)


def test_overrides_only_name_arguments_of_make_loops(monkeypatch):
    # three loops cycle (period 40, 50, 60 samples), noise white in the median, SP constant
    stats = _table(6, noise_colour=[0.1, 0.1, 0.1, 0.1, 0.5, 0.5],
                   acf_peak=[0.5, 0.5, 0.5, 0.1, 0.1, 0.1],
                   period=[40.0, 50.0, 60.0, np.nan, np.nan, np.nan])  # fmt: skip
    full = calibrate(stats, refine=False).overrides
    assert full["noise_colours"] == ("white",)
    assert full["oscillating_fraction"] == 0.5
    assert full["setpoint_weights"]["constant"] == pytest.approx(6.5 / 8)
    assert full["snr_db_range"][0] == pytest.approx(snr_per_loop(stats)[0])
    assert "period_range" in full and "pv_own_share" in full
    monkeypatch.setattr(calibrate_module, "_make_loops_arguments", lambda: {"noise_colours"})
    monkeypatch.setattr(calibrate_module, "_pilot", _no_pilot)
    # without make_loops' realism argument no pilot runs, even when asked
    only = calibrate(stats, refine=True, random_state=0)
    assert only.overrides == {"noise_colours": ("white",)}
    assert only.snr_shift == 0.0


def test_calibrate_refuses_a_bad_seed():
    with pytest.raises(ValueError, match="random_state"):
        calibrate(_table(3), refine=False, random_state="zero")


def test_refine_runs_its_pilots_in_order_and_summarises_the_share(monkeypatch):
    calls = []

    def fake(name, shares=None):
        def run(realism, rng, **kwargs):
            assert isinstance(rng, np.random.Generator)
            calls.append((name, kwargs))
            if shares is not None:
                realism.profiles["pv_own_share"] = shares

        return run

    shares = np.linspace(0.0, 0.9, 10)
    monkeypatch.setattr(calibrate_module, "_refine_snr", fake("snr"))
    monkeypatch.setattr(calibrate_module, "_refine_own_share", fake("share", shares))
    monkeypatch.setattr(calibrate_module, "_refine_oscillating", fake("oscillating"))
    realism = calibrate(_table(10), random_state=0)
    assert calls == [("snr", {}), ("share", {}), ("snr", {"n_steps": 1}), ("oscillating", {})]
    assert realism.overrides["pv_own_share"] == pytest.approx(
        tuple(np.percentile(shares, [10, 90]))
    )
    calls.clear()
    calibrate(_table(10), refine=False)
    assert calls == []


# ---- drawing profiles ---------------------------------------------------------------------------


def test_loop_profile_copies_a_measured_loop_settings():
    prof = _profiles([
        {"loop_type": "flow", "snr_db": 20.0, "white_noise": True, "pv_own_share": 0.05,
         "oscillating": 0.25, "setpoint_regime": "steps"},
    ])  # fmt: skip
    realism = Realism(prof, {}, None, snr_shift=3.0)
    out = realism.loop_profile(0)
    assert out["loop_type"] == "flow" and out["recording"] == []
    s = out["settings"]
    assert s["snr_db_range"] == pytest.approx((20.0 + 3.0 - 3.0, 20.0 + 3.0 + 3.0))
    assert s["noise_colours"] == ("white",)
    assert s["pv_own_share"] == pytest.approx((0.0, 0.15))  # 0.05 +- 0.1, not below 0
    assert s["oscillating_fraction"] == 0.25
    assert s["setpoint_regime"] == "steps"
    assert set(s) == {"snr_db_range", "noise_colours", "pv_own_share", "oscillating_fraction",
                      "setpoint_regime"}  # fmt: skip
    # nothing readable: no settings
    bare = Realism(_profiles([{"oscillating": np.nan}]), {}, None).loop_profile(0)
    assert bare["settings"] == {} and bare["loop_type"] == "all"
    high = Realism(_profiles([{"pv_own_share": 0.9}]), {}, None).loop_profile(0)
    assert high["settings"]["pv_own_share"] == pytest.approx((0.8, 0.95))  # not above 0.95
    mid = Realism(_profiles([{"pv_own_share": 0.4}]), {}, None).loop_profile(0)
    assert mid["settings"]["pv_own_share"] == pytest.approx((0.3, 0.5))
    assert all(isinstance(v, float) for v in mid["settings"]["pv_own_share"])
    empty = Realism(_profiles([]).iloc[:0], {}, None)
    assert empty.loop_profile(0) == {"loop_type": None, "settings": {}, "recording": []}
    assert empty.recording_effects(0) == []


def test_loop_profile_of_a_profile_without_world_settings():
    """Profiles made elsewhere may hold only the loop type and the recording: no settings."""
    prof = pd.DataFrame({"loop_type": ["flow"], **{n: [False] for n in RECORDING}})
    assert Realism(prof, {}, None).loop_profile(0) == {
        "loop_type": "flow",
        "settings": {},
        "recording": [],
    }


def test_loop_profile_carries_the_recording():
    prof = _profiles([{"hold_last_value": True, "hold_last_value.fraction": 0.25,
                       "hold_last_value.mean_run": 4.0}])  # fmt: skip
    (hold,) = Realism(prof, {}, None).loop_profile(np.random.default_rng(1))["recording"]
    assert isinstance(hold, historian.HoldLastValue)
    assert (hold.fraction, hold.mean_run) == (0.25, 4.0)


def test_loop_profile_draws_by_weight():
    rows = [{"loop_type": t} for t in ("a", "b", "c")]
    rng = np.random.default_rng(0)
    only_b = _profiles(rows).assign(weight=[0.0, 2.0, 0.0])
    assert {Realism(only_b, {}, None).loop_profile(rng)["loop_type"] for _ in range(50)} == {"b"}
    last = _profiles(rows).assign(weight=[0.0, 0.0, 5.0])
    assert {Realism(last, {}, None).loop_profile(rng)["loop_type"] for _ in range(50)} == {"c"}
    first = _profiles(rows).assign(weight=[1.0, 0.0, 0.0])
    assert {Realism(first, {}, None).loop_profile(rng)["loop_type"] for _ in range(50)} == {"a"}
    skewed = Realism(_profiles(rows).assign(weight=[1.0, 3.0, 0.0]), {}, None)
    draws = [skewed.loop_profile(rng)["loop_type"] for _ in range(800)]
    assert np.mean(np.array(draws) == "b") == pytest.approx(0.75, abs=0.05)  # 3 sd
    # weights that cannot be read, or all zero: every loop alike
    for bad in ([np.nan, 1.0, 1.0], [0.0, 0.0, 0.0]):
        even = Realism(_profiles(rows).assign(weight=bad), {}, None)
        draws = np.array([even.loop_profile(rng)["loop_type"] for _ in range(900)])
        for t in "abc":
            assert np.mean(draws == t) == pytest.approx(1 / 3, abs=0.05)  # 3 sd
    # the same seed, the same draw (20 draws among 7 loops: chance agreement 7**-20)
    seven = _profiles([{"loop_type": t} for t in "abcdefg"])
    for prof in (seven, seven.assign(weight=1.0)):
        realism = Realism(prof, {}, None)
        draws = [realism.loop_profile(seed)["loop_type"] for seed in range(20)]
        assert draws == [realism.loop_profile(seed)["loop_type"] for seed in range(20)]
        assert len(set(draws)) > 1


def test_recording_effects_draw_within_a_loop_type():
    prof = _profiles([
        {"loop_type": "level", "hold_last_value": True, "hold_last_value.fraction": 0.3,
         "hold_last_value.mean_run": 5.0},
        {"loop_type": "flow"},
        {"loop_type": "flow"},
    ])  # fmt: skip
    realism = Realism(prof, {}, None)
    rng = np.random.default_rng(0)
    assert all(len(realism.recording_effects(rng, loop_type="level")) == 1 for _ in range(20))
    assert all(realism.recording_effects(rng, loop_type="flow") == [] for _ in range(20))
    # an unknown type or none: any measured loop (a third of them hold)
    for lt in (None, "pressure"):
        held = [bool(realism.recording_effects(rng, loop_type=lt)) for _ in range(600)]
        assert np.mean(held) == pytest.approx(1 / 3, abs=0.06)  # 3 sd


# ---- pilot refinements, with a world of known answers ----------------------------------------


def _fake_world(monkeypatch, answer):
    """Replace the pilot simulation: ``answer(realism, n_loops)`` gives its statistics and
    meta; the calls are counted."""
    calls = []

    def pilot(realism, rng, n_loops=80, n_samples=600, **kwargs):
        assert isinstance(rng, np.random.Generator)
        calls.append({"n_loops": n_loops, "n_samples": n_samples, **kwargs})
        return answer(realism, n_loops)

    monkeypatch.setattr(calibrate_module, "_pilot", pilot)
    return calls


def _corr_world(scale=0.7, seen=1.0):
    """Loops of the measured types in turn; PV-OP correlation ``scale sqrt(1 - seen share)``."""

    def answer(realism, n_loops):
        prof = realism.profiles
        idx = np.arange(n_loops) % len(prof)
        share = prof["pv_own_share"].to_numpy(dtype=float)[idx]
        stats = _table(n_loops, pv_op_corr=scale * np.sqrt(1 - seen * share))
        return stats, pd.DataFrame({"loop_type": prof["loop_type"].to_numpy()[idx]})

    return answer


def test_refine_own_share_per_loop_type_matches_the_median_correlation(monkeypatch):
    calls = _fake_world(monkeypatch, _corr_world())
    types = ["level"] * 6 + ["flow"] * 6 + ["temperature"] * 3
    corr = [0.3] * 5 + [np.nan] + [0.7, 0.7, 0.7, 0.65, 0.75, 0.6] + [0.9, 0.9, 0.9]
    realism = Realism(_profiles([{"loop_type": t} for t in types]).assign(pv_op_corr=corr),
                      {}, _table(len(types)))  # fmt: skip
    calibrate_module._refine_own_share(realism, np.random.default_rng(0), n_loops=60)
    assert len(calls) == 3 and all(c["n_loops"] == 60 for c in calls)
    share = realism.profiles.groupby("loop_type")["pv_own_share"].agg(["min", "max"])
    assert (share["min"] == share["max"]).all()  # one share per type
    share = share["min"]
    assert share["level"] == pytest.approx(1 - (0.3 / 0.7) ** 2)  # median 0.3 of 5 finite
    assert share["flow"] == pytest.approx(0.0)  # median 0.7
    # 3 loops: the overall median (0.675 over 14 finite), not their own 0.9 (share 0)
    assert np.nanmedian(corr) == pytest.approx(0.675)
    assert share["temperature"] == pytest.approx(1 - (0.675 / 0.7) ** 2)


def test_refine_own_share_corrects_a_world_that_shows_part_of_it(monkeypatch):
    """Only 80 % of the share lowers the simulated correlation: each step applies the
    docstring's ``1 - s <- (1 - s) (measured / simulated)**2``, and comes closer."""
    _fake_world(monkeypatch, _corr_world(seen=0.8))
    realism = Realism(_profiles([{}] * 8).assign(pv_op_corr=0.5), {}, _table(8))
    for n_steps in (0, 1, 2, 4):
        calibrate_module._refine_own_share(realism, np.random.default_rng(0), n_steps=n_steps)
        s = 1 - (0.5 / 0.7) ** 2
        for _ in range(n_steps):
            simulated = 0.7 * np.sqrt(1 - 0.8 * s)
            s = 1 - (1 - s) * (0.5 / simulated) ** 2
        np.testing.assert_allclose(realism.profiles["pv_own_share"], s, rtol=1e-9)
    target = (1 - (0.5 / 0.7) ** 2) / 0.8
    assert abs(s - target) < 0.01 < abs(1 - (0.5 / 0.7) ** 2 - target)


def test_refine_own_share_needs_enough_loops(monkeypatch):
    # fewer than 5 measured correlations: nothing simulated, nothing changed
    _fake_world(monkeypatch, _no_pilot)
    prof = _profiles([{"pv_own_share": 0.2}] * 6).assign(pv_op_corr=[0.3] * 4 + [np.nan] * 2)
    calibrate_module._refine_own_share(Realism(prof, {}, None), np.random.default_rng(0))
    assert (prof["pv_own_share"] == 0.2).all()
    # a pilot with fewer than 10 finite correlations stops at the shares it tried
    calls = _fake_world(
        monkeypatch,
        lambda r, n: (_table(n, pv_op_corr=np.nan), pd.DataFrame({"loop_type": ["all"] * n})),
    )
    prof = _profiles([{"pv_own_share": 0.2}] * 6).assign(pv_op_corr=0.35)
    calibrate_module._refine_own_share(Realism(prof, {}, None), np.random.default_rng(0))
    assert len(calls) == 1 and (prof["pv_own_share"] == 0.0).all()


def _noise_world(factor, finite=None):
    """Pilot noise levels ``factor`` times the measured median (NaN from loop ``finite`` on)."""

    def answer(realism, n_loops):
        measured = realism.statistics["noise_level"].to_numpy(dtype=float)
        measured = measured[np.isfinite(measured) & (measured > 0)]
        level = np.full(n_loops, factor * np.median(measured))
        if finite is not None:
            level[finite:] = np.nan
        return _table(n_loops, noise_level=level), None

    return answer


def test_refine_snr_shifts_by_the_db_between_the_median_noise_levels(monkeypatch):
    calls = _fake_world(monkeypatch, _noise_world(2.0))
    stats = _table(7, noise_level=[0.01, 0.02, 0.03, np.nan, 0.0, 0.04, 0.05])
    realism = Realism(_profiles([{}] * 7), {"snr_db_range": (5.0, 25.0)}, stats, snr_shift=1.0)
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_loops=30, n_samples=200)
    # the pilot is twice as noisy every time: up 20 log10(2) dB per step, two steps
    step = 20 * np.log10(2.0)
    assert realism.snr_shift == pytest.approx(1.0 + 2 * step)
    assert realism.overrides["snr_db_range"] == pytest.approx((5.0 + 2 * step, 25.0 + 2 * step))
    assert calls == [{"n_loops": 30, "n_samples": 200}] * 2
    # a quieter pilot: down; the range is kept within -20..60 dB and at least 1 dB wide
    _fake_world(monkeypatch, _noise_world(0.5))
    realism.overrides["snr_db_range"] = (-15.0, -14.5)
    realism.snr_shift = 0.0
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert realism.snr_shift == pytest.approx(-step)
    assert realism.overrides["snr_db_range"] == pytest.approx((-20.0, -19.0))
    _fake_world(monkeypatch, _noise_world(2.0))
    realism.overrides["snr_db_range"] = (50.0, 58.0)
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert realism.overrides["snr_db_range"] == pytest.approx((50.0 + step, 60.0))


def test_refine_snr_shift_is_at_most_20_db_a_step(monkeypatch):
    _fake_world(monkeypatch, _noise_world(1000.0))  # 60 dB
    stats = _table(5, noise_level=0.01)
    realism = Realism(_profiles([{}] * 5), {"snr_db_range": (0.0, 10.0)}, stats)
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert realism.snr_shift == 20.0 and realism.overrides["snr_db_range"] == (20.0, 30.0)
    _fake_world(monkeypatch, _noise_world(1e-3))
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert realism.snr_shift == 0.0 and realism.overrides["snr_db_range"] == (0.0, 10.0)


def test_refine_snr_needs_enough_noise_levels(monkeypatch):
    calls = _fake_world(monkeypatch, _noise_world(2.0))
    # 4 measured levels: nothing simulated
    few = Realism(_profiles([{}] * 5), {"snr_db_range": (0.0, 10.0)},
                  _table(5, noise_level=[0.01, 0.01, 0.01, 0.01, 0.0]))  # fmt: skip
    calibrate_module._refine_snr(few, np.random.default_rng(0))
    # no SNR range to move: nothing simulated
    none = Realism(_profiles([{}] * 5), {}, _table(5))
    calibrate_module._refine_snr(none, np.random.default_rng(0))
    assert calls == [] and few.snr_shift == 0.0 and none.overrides == {}
    # a pilot with 4 noise levels stops without a shift
    _fake_world(monkeypatch, _noise_world(2.0, finite=4))
    realism = Realism(_profiles([{}] * 5), {"snr_db_range": (0.0, 10.0)}, _table(5))
    calibrate_module._refine_snr(realism, np.random.default_rng(0))
    assert realism.snr_shift == 0.0 and realism.overrides["snr_db_range"] == (0.0, 10.0)
    # ... and with 5 it shifts
    _fake_world(monkeypatch, _noise_world(2.0, finite=5))
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert realism.snr_shift == pytest.approx(20 * np.log10(2.0))


def _cycling_world(p_on, p_off, seen=None):
    """A share ``p_on`` of the pilot's loops cycle when every drive is on, ``p_off`` when
    every one is off."""

    def answer(realism, n_loops):
        drive = realism.profiles["oscillating"].to_numpy(dtype=float)
        assert np.all(drive == drive[0])
        if seen is not None:
            seen.append(drive[0])
        p = p_on if drive[0] == 1.0 else p_off
        cycling = np.arange(n_loops) < round(p * n_loops)
        return _table(n_loops, acf_peak=np.where(cycling, 0.6, 0.1)), None

    return answer


def _cycling_realism(acf):
    stats = _table(len(acf), acf_peak=acf)
    realism = calibrate(stats, refine=False)
    return realism, realism.profiles["oscillating"].to_numpy().copy()


@pytest.mark.parametrize(
    "m_cycling, p_on, p_off, f, on, off",
    [
        (3, 0.8, 0.1, (0.3 - 0.1) / 0.7, (0.2 / 0.7) / 0.3, 0.0),  # f < m: some cyclers quiet
        (2, 0.5, 0.0, 0.4, 1.0, 0.2 / 0.8),  # f > m: some quiet loops get the drive
        (1, 0.6, 0.2, 0.0, 0.0, 0.0),  # fewer cycle than in the quiet pilot
        (9, 0.5, 0.0, 1.0, 1.0, 1.0),  # more than in the all-on pilot
        (0, 0.5, 0.0, 0.0, 0.0, 0.0),  # no measured loop cycles
        (10, 0.9, 0.2, 1.0, 1.0, 0.0),  # every measured loop cycles
    ],
)
def test_refine_oscillating_shares_the_drive(monkeypatch, m_cycling, p_on, p_off, f, on, off):
    seen = []
    calls = _fake_world(monkeypatch, _cycling_world(p_on, p_off, seen))
    acf = np.where(np.arange(10) < m_cycling, 0.5, 0.1)
    realism, _ = _cycling_realism(acf)
    calibrate_module._refine_oscillating(realism, np.random.default_rng(0), n_loops=100)
    assert seen == [1.0, 0.0] and [c["n_loops"] for c in calls] == [100, 100]
    assert realism.overrides["oscillating_fraction"] == pytest.approx(f)
    expected = np.where(acf > 0.3, on, off)
    np.testing.assert_allclose(realism.profiles["oscillating"], expected, atol=1e-12)
    # the drives add up to the fitted share
    assert realism.profiles["oscillating"].mean() == pytest.approx(f)


def test_refine_oscillating_keeps_the_measured_share_when_pilots_agree(monkeypatch):
    _fake_world(monkeypatch, _cycling_world(0.34, 0.3))
    realism, before = _cycling_realism(np.where(np.arange(10) < 3, 0.5, 0.1))
    calibrate_module._refine_oscillating(realism, np.random.default_rng(0))
    assert realism.overrides["oscillating_fraction"] == 0.3
    np.testing.assert_array_equal(realism.profiles["oscillating"], before)
    # 0.06 apart: they can tell
    _fake_world(monkeypatch, _cycling_world(0.36, 0.3))
    calibrate_module._refine_oscillating(realism, np.random.default_rng(0))
    assert realism.overrides["oscillating_fraction"] == 0.0


def test_refine_oscillating_needs_five_loops_and_the_override(monkeypatch):
    _fake_world(monkeypatch, _no_pilot)
    realism, before = _cycling_realism([0.5, 0.1, 0.1, 0.1])
    calibrate_module._refine_oscillating(realism, np.random.default_rng(0))
    np.testing.assert_array_equal(realism.profiles["oscillating"], before)
    realism, before = _cycling_realism(np.full(6, np.nan))  # no ACF: no override
    assert "oscillating_fraction" not in realism.overrides
    calibrate_module._refine_oscillating(realism, np.random.default_rng(0))
    # a pilot that fails leaves the drives as they were
    realism, before = _cycling_realism([0.5, 0.1, 0.1, 0.1, 0.1])

    def boom(realism, n_loops):
        raise RuntimeError("pilot failed")

    _fake_world(monkeypatch, boom)
    with pytest.raises(RuntimeError):
        calibrate_module._refine_oscillating(realism, np.random.default_rng(0))
    np.testing.assert_array_equal(realism.profiles["oscillating"], before)


def test_pilot_simulates_the_calibrated_world():
    realism = calibrate(_table(6), refine=False)
    stats, meta = calibrate_module._pilot(realism, np.random.default_rng(0), n_loops=3,
                                          n_samples=150)  # fmt: skip
    assert len(stats) == 3 and (stats["n_samples"] == 150).all()
    assert len(meta) == 3 and "loop_type" in meta
    # 600 samples unless told, and the generator handed on: the same seed, the same pilot
    a, _ = calibrate_module._pilot(realism, np.random.default_rng(1), n_loops=2)
    b, _ = calibrate_module._pilot(realism, np.random.default_rng(1), n_loops=2)
    assert (a["n_samples"] == 600).all()
    pd.testing.assert_frame_equal(a, b)


# ---- real loops: scale and offset, loop types, the recording applied --------------------------


@pytest.fixture(scope="module")
def held_loops():
    X, _ = make_loops(8, 300, world="classic", random_state=4)
    return X, apply_effects(X, [historian.HoldLastValue(0.3, 4.0)], random_state=0)


def test_scale_and_offset_of_pv_and_op_change_nothing_fitted(held_loops):
    """Every statistic calibrate reads is relative to a tag's span or a correlation: PV (and
    SP with it) and OP in other units give the same profiles and overrides."""
    _, X = held_loops
    Y = X.copy()
    Y[..., 0] = 40.0 * X[..., 0] + 300.0
    Y[..., 2] = 40.0 * X[..., 2] + 300.0
    Y[..., 1] = 0.5 * X[..., 1] - 7.0
    a = calibrate(X, refine=False)
    b = calibrate(Y, refine=False)
    assert a.profiles["hold_last_value"].all()
    cols = [c for c in a.profiles.columns if c != "setpoint_regime"]
    pd.testing.assert_frame_equal(a.profiles[cols], b.profiles[cols], rtol=1e-6)
    assert a.profiles["setpoint_regime"].tolist() == b.profiles["setpoint_regime"].tolist()
    assert a.overrides.keys() == b.overrides.keys()
    for k, v in a.overrides.items():
        assert b.overrides[k] == (pytest.approx(v, rel=1e-6) if k != "setpoint_weights" else v)


def test_apply_recording_per_loop_type_and_leaves_its_input_alone(held_loops):
    X, held = held_loops
    types = ["level"] * 4 + ["flow"] * 4
    realism = calibrate(np.concatenate([held[:4], X[4:]]), loop_types=types, refine=False)
    before = X.copy()
    out = apply_recording(X, realism, loop_types=types[::-1], random_state=0)
    np.testing.assert_array_equal(X, before)
    frozen = loop_statistics(out)["hold_fraction"].to_numpy()
    assert (frozen[:4] == 0).all() and (frozen[4:] > 0.1).all()
    np.testing.assert_array_equal(out[:4], X[:4])  # flow loops: nothing recorded
    # the same seed, the same recording
    np.testing.assert_array_equal(out, apply_recording(X, realism, loop_types=types[::-1],
                                                       random_state=0))  # fmt: skip
    with pytest.raises(ValueError, match=r"loop_types must have one entry per loop \(8\); got 2"):
        apply_recording(X, realism, loop_types=["level", "flow"])


def test_apply_effects_in_order_with_the_sample_time():
    X = np.tile(np.linspace(0.0, 9.0, 10)[None, :, None], (2, 1, 3))
    # a grid of 2 over the 5-95 % range of 8.1 (step 0.2 x 8.1 = 1.62), then a hold
    out = apply_effects(X, [historian.SpanQuantization(0.2)])
    step = 0.2 * (np.percentile(X[0, :, 0], 95) - np.percentile(X[0, :, 0], 5))
    np.testing.assert_allclose(out[0, :, 0], np.round(X[0, :, 0] / step) * step, atol=1e-9)
    np.testing.assert_array_equal(out[0, :, 1], X[0, :, 1])  # PV only
    assert out.dtype == float and out is not X

    seen = []

    class Seen(historian.SpanQuantization):
        def record(self, signals, ts, rng):
            seen.append(ts)
            return super().record(signals, ts, rng)

    apply_effects(X, [Seen(0.2)], ts=2.5)
    assert seen == [2.5, 2.5]
    with pytest.raises(ValueError, match="effects must be recording effects"):
        apply_effects(X, [historian.SpanQuantization(0.2), object()])
    np.testing.assert_array_equal(apply_effects(X, []), X)


# ---- hold-last-value: the calibrated world holds the measured share ----------------------------


def _runs_of_two_or_more(mask):
    """Share of rows in runs of True of 2 or more: ``hold_fraction``'s definition."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    lengths = np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)
    return lengths[lengths >= 2].sum() / len(mask)


@pytest.mark.parametrize(
    "held, run", [(0.3, 5.0), (0.45, 5.0), (0.2, 2.0), (0.4, 3.0), (0.1, 8.0)]
)
def test_calibrated_hold_holds_the_measured_share(held, run):
    """A measured ``hold_fraction`` (rows in held runs of 2 or more) and run length: the
    ``HoldLastValue`` calibrate makes holds that share again, read by the statistic's
    definition on its mask over 200,000 rows (within 0.004; the held share of so many runs
    varies by about 0.001). ``HoldLastValue(fraction, L)`` holds ``L / (L / fraction + 1)``
    of the rows, less than ``fraction``: read as the share itself (before the fix), the
    statistic of the calibrated hold came out 0.018-0.052 below the measured one for the first
    four cases here (0.001 for the last)."""
    realism = calibrate(_table(5, hold_fraction=held, hold_run_length=run), refine=False)
    (effect,) = realism.recording_effects(0)
    assert isinstance(effect, historian.HoldLastValue) and effect.mean_run == run
    mask = effect.mask(200_000, np.random.default_rng(0))
    assert _runs_of_two_or_more(mask) == pytest.approx(held, abs=0.004)
    # all held rows: runs of one sample put back (a share 1 / L**2 at geometric runs)
    assert mask.mean() == pytest.approx(held / (1 - 1 / run**2), abs=0.004)


# ---- edges the first mutation runs asked for ----------------------------------------------------


class _Fixed(np.random.Generator):
    """A generator whose ``random()`` is a given number (the draw of a profile)."""

    def __init__(self, value):
        super().__init__(np.random.PCG64(0))
        self.value = value

    def random(self, *args, **kwargs):
        return self.value


def test_loop_profile_draw_at_the_ends_of_the_unit_interval():
    rows = [{"loop_type": t} for t in "abcdefg"]
    # a draw of exactly 0 skips the loops of weight 0 before the first weighted one
    zero_first = Realism(_profiles(rows[:3]).assign(weight=[0.0, 1.0, 0.0]), {}, None)
    assert zero_first.loop_profile(_Fixed(0.0))["loop_type"] == "b"
    # seven weights of 3: their normalised sum rounds to 1 - 2e-16, below the largest draw
    even = _profiles(rows).assign(weight=3.0)
    assert np.cumsum(even["weight"] / even["weight"].sum()).iloc[-1] < 1 - 2**-53
    assert Realism(even, {}, None).loop_profile(_Fixed(1 - 2**-53))["loop_type"] == "g"


def test_summary_of_loops_of_the_default_type_and_mixed_types():
    stats = _table(4, hold_fraction=[0.3, 0.0, 0.3, 0.3],
                   hold_run_length=[3.123456, np.nan, 5.0, 6.0])  # fmt: skip
    one = calibrate(stats, refine=False).summary()
    assert one["loop_type"].tolist() == ["all"] * len(RECORDING)  # "all" once
    assert one.set_index("effect").loc["hold_last_value", "share"] == 0.75
    # types "all" and "level" side by side: the overall row still counts every loop
    mixed = calibrate(stats, loop_types=["all", "all", "level", "level"], refine=False)
    table = mixed.summary()
    hold = table[table["effect"] == "hold_last_value"].set_index("loop_type")
    assert table["loop_type"].unique().tolist() == ["all", "level"]
    assert hold["n_loops"].to_dict() == {"all": 4, "level": 2}
    # medians rounded to 4 decimals
    assert hold.loc["all", "params"]["mean_run"] == 5.0
    only = calibrate(stats.iloc[[0]].reset_index(drop=True), refine=False).summary()
    params = only.set_index("effect").loc["hold_last_value", "params"]
    assert params["mean_run"] == 3.1235


def test_share_names_the_recording_effects_only():
    realism = calibrate(_table(2), refine=False)
    with pytest.raises(ValueError) as err:
        realism.share("noise_level")
    assert str(err.value) == (
        f"effect must be a recording effect of the catalog {effect_names('recording')}; "
        "got 'noise_level'."
    )


def test_a_table_of_object_columns_calibrates_like_the_float_table(monkeypatch):
    """Statistics read back from a file with gaps may come as object columns."""
    stats = _table(6, noise_colour=[0.1, 0.1, 0.1, 0.1, 0.5, np.nan],
                   pv_op_corr=[0.35, 0.35, 0.35, 0.5, np.nan, 0.6])  # fmt: skip
    a = calibrate(stats, refine=False)
    b = calibrate(stats.astype(object), refine=False)
    pd.testing.assert_frame_equal(a.profiles, b.profiles)
    assert a.overrides == b.overrides
    calls = _fake_world(monkeypatch, _noise_world(2.0))
    realism = Realism(_profiles([{}] * 6), {"snr_db_range": (0.0, 10.0)}, stats.astype(object))
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert len(calls) == 1 and realism.snr_shift == pytest.approx(20 * np.log10(2.0))


def test_no_warning_without_any_correlation():
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        realism = calibrate(_table(6, pv_op_corr=np.nan), refine=False)
    assert realism.overrides["pv_own_share"] == (0.0, 0.0)


def test_calibrate_seeds_and_sizes_of_its_pilots(monkeypatch):
    """The pilots, in order (2 SNR steps of 80 loops of 600 samples, 3 own-share pilots of 120,
    one more SNR step, 2 cycling pilots of 150), each handed the calibrated world and a
    generator seeded by ``random_state``."""
    seen = []

    def pilot(realism, rng, n_loops=80, n_samples=600, **kwargs):
        assert isinstance(realism, Realism) and not kwargs
        seen.append((n_loops, n_samples, rng.random()))
        n = np.arange(n_loops)
        corr = 0.7 * np.sqrt(1 - realism.profiles["pv_own_share"].to_numpy()[n % 12])
        acf = np.where(n < n_loops * realism.profiles["oscillating"].iloc[0], 0.6, 0.1)
        stats = _table(n_loops, noise_level=0.04, pv_op_corr=corr, acf_peak=acf)
        return stats, pd.DataFrame({"loop_type": ["all"] * n_loops})

    monkeypatch.setattr(calibrate_module, "_pilot", pilot)
    stats = _table(12, pv_op_corr=0.35, acf_peak=np.where(np.arange(12) < 3, 0.5, 0.1))
    realism = calibrate(stats, random_state=3)
    sizes = [(n, s) for n, s, _ in seen]
    assert sizes == [(80, 600)] * 2 + [(120, 600)] * 3 + [(80, 600)] + [(150, 600)] * 2
    draws = [d for _, _, d in seen]
    seen.clear()
    again = calibrate(stats, random_state=3)
    assert [d for _, _, d in seen] == draws  # the same seed, the same pilots
    assert len(set(draws)) == len(draws)  # one generator, drawn on
    rng = np.random.default_rng(3)
    assert draws[0] == rng.random()
    # what the world of known answers asks for
    assert realism.snr_shift == pytest.approx(3 * 20 * np.log10(2.0))
    assert realism.overrides["pv_own_share"] == pytest.approx((0.75, 0.75))
    assert realism.overrides["oscillating_fraction"] == pytest.approx(0.25)
    pd.testing.assert_frame_equal(realism.profiles, again.profiles)


def test_refine_own_share_at_its_bounds(monkeypatch):
    # exactly 5 measured correlations: refined
    calls = _fake_world(monkeypatch, _corr_world())
    prof = _profiles([{}] * 6).assign(pv_op_corr=[0.35] * 5 + [np.nan])
    calibrate_module._refine_own_share(Realism(prof, {}, None), np.random.default_rng(0))
    assert len(calls) == 3 and prof["pv_own_share"].to_numpy() == pytest.approx(0.75)

    # a pilot with exactly 10 finite correlations: used
    def ten(realism, n_loops):
        corr = np.where(np.arange(n_loops) < 10, 0.7, np.nan)
        return _table(n_loops, pv_op_corr=corr), pd.DataFrame({"loop_type": ["all"] * n_loops})

    calls = _fake_world(monkeypatch, ten)
    prof = _profiles([{}] * 6).assign(pv_op_corr=0.35)
    calibrate_module._refine_own_share(Realism(prof, {}, None), np.random.default_rng(0))
    assert len(calls) == 3
    # a type simulated fewer than 5 times takes the simulated median over all loops
    _fake_world(monkeypatch, _corr_world())
    types = ["level"] * 6 + ["flow"] * 6 + ["temperature"] * 3
    corr = [0.3] * 5 + [np.nan] + [0.7, 0.7, 0.7, 0.65, 0.75, 0.6] + [0.9, 0.9, 0.9]
    prof = _profiles([{"loop_type": t} for t in types]).assign(pv_op_corr=corr)
    calibrate_module._refine_own_share(Realism(prof, {}, None), np.random.default_rng(0),
                                       n_loops=15, n_steps=0)  # fmt: skip
    assert prof.loc[14, "pv_own_share"] == pytest.approx(1 - (0.675 / 0.7) ** 2)


def test_refine_snr_leaves_out_zero_levels_and_clips_the_top(monkeypatch):
    def zeros(realism, n_loops):  # 4 levels and lines (level 0)
        return _table(n_loops, noise_level=np.where(np.arange(n_loops) < 4, 0.04, 0.0)), None

    _fake_world(monkeypatch, zeros)
    realism = Realism(_profiles([{}] * 5), {"snr_db_range": (0.0, 10.0)}, _table(5))
    calibrate_module._refine_snr(realism, np.random.default_rng(0))
    assert realism.snr_shift == 0.0 and realism.overrides["snr_db_range"] == (0.0, 10.0)
    # both ends above 60 dB: the range is 60-61
    _fake_world(monkeypatch, _noise_world(2.0))
    realism.overrides["snr_db_range"] = (57.0, 59.0)
    calibrate_module._refine_snr(realism, np.random.default_rng(0), n_steps=1)
    assert realism.overrides["snr_db_range"] == (60.0, 61.0)


def test_refine_oscillating_at_a_gap_of_exactly_005(monkeypatch):
    _fake_world(monkeypatch, _cycling_world(0.1, 0.05))
    realism, _ = _cycling_realism(np.where(np.arange(10) < 1, 0.5, 0.1))
    calibrate_module._refine_oscillating(realism, np.random.default_rng(0), n_loops=100)
    assert realism.overrides["oscillating_fraction"] == pytest.approx(1.0)  # (0.1-0.05)/0.05


def test_apply_hands_on_sample_time_and_seed():
    X = np.tile(np.linspace(0.0, 9.0, 40)[None, :, None], (2, 1, 3))
    seen = []

    class Seen(historian.SpanQuantization):
        def record(self, signals, ts, rng):
            seen.append(ts)
            return super().record(signals, ts, rng)

    class Stub:
        def recording_effects(self, rng, loop_type=None):
            return [Seen(0.2)]

    apply_effects(X, [Seen(0.2)])
    apply_recording(X, Stub())
    apply_recording(X, Stub(), ts=4.0)
    assert seen == [1.0] * 4 + [4.0] * 2
    hold = [historian.HoldLastValue(0.4, 3.0)]
    np.testing.assert_array_equal(apply_effects(X, hold, random_state=1),
                                  apply_effects(X, hold, random_state=1))  # fmt: skip


def test_own_share_from_a_reference_without_correlation_is_zero():
    """A pilot whose median loop shows no PV-OP correlation (0, or nearly) leaves none to
    lower: share 0, as for NaN, not ZeroDivisionError (nor OverflowError)."""
    own = calibrate_module._own_share
    assert own(0.35, 0.0) == 0.0 and own(0.0, 0.0) == 0.0 and own(0.35, -0.0) == 0.0
    assert own(np.float64(0.35), 0.0) == 0.0 and own(0.5, 1e-200) == 0.0
    assert isinstance(own(0.35, 0.0), float)


def test_calibrate_with_pilots_that_show_no_correlation(monkeypatch):
    def pilot(realism, rng, n_loops=80, n_samples=600, **kwargs):
        stats = _table(n_loops, noise_level=0.04, pv_op_corr=0.0)
        return stats, pd.DataFrame({"loop_type": ["all"] * n_loops})

    monkeypatch.setattr(calibrate_module, "_pilot", pilot)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        realism = calibrate(_table(12, pv_op_corr=0.35), random_state=0)
    # the first guess (0.75 from the default world's 0.7) is refined to 0 by every pilot
    assert (realism.profiles["pv_own_share"] == 0.0).all()
    assert realism.overrides["pv_own_share"] == (0.0, 0.0)
