"""What make_loops' meta says about each loop, checked in X, against its docstring and by an
independent computation: recording effects, plant families, how each loop is run and
tuned (the aggressive loops' gain margin from the plant and controller in meta), valve
parameters and disturbance periods.

The historian effects leave their own marks in the data: quantisation puts every value of
PV and OP on a grid, deadband compression freezes each tag on its own (off any grid),
hold-last-value freezes whole rows, interval averaging freezes nothing. A recording that
meta names but X does not show (or the other effect applied) fails here.
"""

import re

import numpy as np
import pytest
from scipy.optimize import brentq

from sktiction.datasets import make_loops


def _loops(recording, n=12, seed=0):
    return make_loops(n, 600, recording=(recording,), recording_fraction=1.0,
                      short_fraction=0.0, random_state=seed, return_meta=True)  # fmt: skip


def _off_grid(x):
    """How far the gaps between distinct values are from whole multiples of the smallest."""
    gaps = np.diff(np.unique(x))
    return float(np.max(np.abs(gaps / gaps.min() - np.round(gaps / gaps.min()))))


def _frozen(x):
    return np.diff(x) == 0


@pytest.mark.parametrize("recording", ["quantisation", "compression", "hold", "averaging"])
def test_each_recording_effect_leaves_its_mark_in_x(recording):
    X, _, meta = _loops(recording)
    assert (meta["recording"] == recording).all()
    for pv, op in zip(X[:, :, 0], X[:, :, 1], strict=True):
        on_grid = [_off_grid(x) < 1e-6 for x in (pv, op)]
        share = [_frozen(x).mean() for x in (pv, op)]
        same_rows = np.array_equal(_frozen(pv), _frozen(op))
        if recording == "quantisation":
            assert all(on_grid)
        else:  # noise in every loop keeps unquantised values off any grid
            assert not any(on_grid)
        if recording == "averaging":
            assert max(share) == 0
        elif recording == "hold":
            assert same_rows and share[0] > 0
        elif recording == "compression":
            assert min(share) > 0 and not same_rows  # each tag freezes on its own


def test_plant_family_names_the_plant():
    _, _, meta = make_loops(40, 300, random_state=1, return_meta=True)
    integrating = (meta["plant"] == "integrating").to_numpy()
    assert integrating.any() and not integrating.all()
    np.testing.assert_array_equal(meta["plant_family"] == "integrating", integrating)
    by_order = {1: "first_order", 2: "second_order"}
    for family, order in meta.loc[~integrating, ["plant_family", "order"]].itertuples(index=False):
        assert family == by_order.get(order, "higher_order")
    assert (meta.loc[~integrating, "order"] > 2).any()  # the higher-order family is reached


def test_meta_gives_aggressive_loops_their_ultimate_period_as_cycle():
    # meta only, checked against itself: a loop tuned to the edge of stability is drawn
    # to cycle at its phase crossover (in X the noise and the loads blur that period);
    # every loop is sampled at least 4 times per ultimate period (slower is not controlled)
    _, _, meta = make_loops(60, 300, random_state=3, return_meta=True)
    per_pu = meta["samples_per_ultimate_period"].to_numpy()
    assert per_pu.min() >= 4 - 1e-9
    aggressive = (meta["cause"] == "aggressive_tuning").to_numpy()
    assert aggressive.sum() >= 5
    np.testing.assert_allclose(meta["samples_per_cycle"][aggressive], per_pu[aggressive])
    stiction = (meta["cause"] == "stiction").to_numpy()  # a sticky valve slows the cycle
    assert (meta["samples_per_cycle"][stiction] > per_pu[stiction]).all()


def _default_world(n_loops):
    """Each test makes its own loops: mutation runs credit a shared fixture's make_loops
    call to the first test that uses it only."""
    return make_loops(n_loops, 200, random_state=0, return_meta=True)[2]


def _gain_margin(row):
    """Gain margin of a sampled PI loop around a lag plant (order n, equal time constants,
    dead time), the zero-order hold counted as half a sample of delay."""
    k, t, n = abs(row["gain"]) * abs(row["Kc"]), row["time_constant"], row["order"]
    ti, delay = row["Ti"], row["delay"] + row["ts"] / 2

    def phase(w):  # of the loop, plus pi: zero at the phase crossover
        return np.pi / 2 + np.arctan(w * ti) - n * np.arctan(w * t) - w * delay

    w = np.geomspace(1e-6, 1e3, 4000) / (delay + t)
    p = phase(w)
    j = np.flatnonzero((p[:-1] > 0) & (p[1:] <= 0))[0]
    w180 = brentq(phase, w[j], w[j + 1])
    return float((w180 * ti) / (k * np.hypot(1, w180 * ti)) * (1 + (w180 * t) ** 2) ** (n / 2))


def test_aggressive_loops_have_the_gain_margin_meta_states():
    # docstring: Kc is set so that the gain margin is log-uniform in gain_margin_range
    meta = _default_world(150)
    aggressive = meta[(meta["cause"] == "aggressive_tuning") & (meta["plant"] != "integrating")]
    assert len(aggressive) >= 10
    for _, row in aggressive.iterrows():
        assert _gain_margin(row) == pytest.approx(row["gain_margin"], rel=2e-3)
        assert 1.1 <= row["gain_margin"] <= 2.5
    assert meta.loc[meta["cause"] != "aggressive_tuning", "gain_margin"].isna().all()


def test_how_each_loop_is_run():
    # docstring: averaging level control for half of the integrating plants (Kc x 0.1-0.5,
    # Ti x 2-10), sluggish integral action (Ti x 3-20) for a share slip_fraction of the
    # others, standard otherwise; sticky loops that are not standard slip
    meta = _default_world(60)
    kind = meta["loop_kind"]
    assert set(kind) == {"standard", "averaging", "sluggish"}
    averaging = meta[kind == "averaging"]
    assert (averaging["plant"] == "integrating").all()
    assert averaging["kc_factor"].between(0.1, 0.5).all()
    assert averaging["ti_factor"].between(2, 10).all()
    assert meta.loc[kind == "sluggish", "ti_factor"].between(3, 20).all()
    standard = meta[kind == "standard"]
    assert (standard[["kc_factor", "ti_factor"]] == 1.0).all().all()
    sticky = meta[meta["cause"] == "stiction"]
    expected = np.where(sticky["loop_kind"] == "standard", "limit_cycle", "slips")
    assert sticky["scenario"].tolist() == expected.tolist()
    assert (meta.loc[meta["cause"] != "stiction", "scenario"] == "").all()
    _, _, none_slow = make_loops(30, 200, slip_fraction=0.0, random_state=2, return_meta=True)
    assert "sluggish" not in set(none_slow["loop_kind"])


def test_valve_bands_and_disturbances_follow_the_docstring():
    meta = _default_world(150)
    sticky = meta[meta["cause"] == "stiction"]
    ratio = (sticky["J"] / sticky["S"]).to_numpy()
    relay = (sticky["valve"] == "relay").to_numpy()
    np.testing.assert_array_equal(ratio[relay], 1.0)
    assert np.all((ratio[~relay] >= 0.1) & (ratio[~relay] <= 1.0))  # J / S 0.1-1
    assert ratio[~relay].min() < 0.4 and ratio[~relay].max() > 0.7
    # external disturbances: sine, narrow-band or square, period 0.7-20 ultimate periods
    external = meta[meta["cause"] == "external_disturbance"]
    assert set(external["disturbance"]) == {"sine", "narrowband", "square"}
    names = {"sine": "SinusoidalDisturbance", "narrowband": "NarrowbandDisturbance",
             "square": "SquareDisturbance"}  # fmt: skip
    for kind, effects in zip(external["disturbance"], external["effects"], strict=True):
        assert names[kind] in effects
    periods = external["samples_per_cycle"] / external["samples_per_ultimate_period"]
    assert periods.between(0.7, 20).all()


def test_pv_variation_corner_follows_the_ultimate_frequency():
    # docstring: corner at 0.1-1 times the loop's ultimate frequency, at most 0.05 cycles per
    # sample; quiet loops' process variation: corner at 0.05-0.5 times the ultimate frequency
    _, _, meta = make_loops(60, 200, pv_own_share=(0.2, 0.5), oscillating_fraction=0.5,
                            random_state=4, return_meta=True)  # fmt: skip
    ultimate = 1 / meta["samples_per_ultimate_period"].to_numpy()
    own = np.array([float(re.search(r"PVVariation\(share=[^,]+, cutoff=([^,]+),", e)[1])
                    for e in meta["effects"]])  # fmt: skip
    capped = own >= 0.05 - 1e-12
    assert (~capped).sum() >= 30 and (own <= 0.05 + 1e-12).all()
    ratio = own[~capped] / ultimate[~capped]
    assert np.all((ratio >= 0.1 - 1e-9) & (ratio <= 1 + 1e-9))
    assert ratio.max() > 0.5  # the whole range is drawn
    quiet = ~meta["oscillating"].to_numpy(dtype=bool)
    assert quiet.sum() >= 10
    load = np.array([float(re.search(r"ColouredLoad\(std=[^,]+, cutoff=([^,]+),", e)[1])
                     for e in meta["effects"]])  # fmt: skip
    ratio = load[quiet] / ultimate[quiet]
    assert np.all((ratio >= 0.05 - 1e-9) & ((ratio <= 0.5 + 1e-9) | (load[quiet] >= 0.45)))
    assert ratio.max() > 0.25


# the default world's meta columns, as make_loops' docstring lists them
DOCUMENTED = """cause y plant order gain time_constant delay apparent_time_constant apparent_delay
lambda valve S J rule gain_factor Kc Ti ts samples_per_cycle snr_db scenario effects
plant_family action loop_kind kc_factor ti_factor gain_margin samples_per_ultimate_period
noise_colour loop_type pv_own_share oscillating noise_path drift disturbance setpoint_regime
recording record_length initial_op pv_scale pv_center warmup pv_per_valve slip_snr
stiction_visible valve_evidence""".split()


def test_default_world_meta_has_the_documented_columns():
    meta = _default_world(20)
    assert set(DOCUMENTED) <= set(meta.columns)
    # a positive process gain needs a reverse-acting controller
    np.testing.assert_array_equal(meta["action"] == "reverse", meta["gain"] > 0)
    assert set(meta["action"]) == {"reverse", "direct"}


def test_documented_defaults_and_bounds_of_the_record():
    # warmup None means max(300, n_samples // 5); min_length may be as short as 20
    _, _, meta = make_loops(2, 300, random_state=0, return_meta=True)
    assert (meta["warmup"] == 300).all()
    _, _, meta = make_loops(2, 2000, random_state=0, return_meta=True)
    assert (meta["warmup"] == 400).all()
    _, _, meta = make_loops(6, 100, min_length=20, short_fraction=1.0, random_state=0,
                            return_meta=True)  # fmt: skip
    assert meta["record_length"].between(20, 100).all()
    with pytest.raises(ValueError, match="min_length"):
        make_loops(2, 100, min_length=19)
    with pytest.raises(ValueError, match="positive weight to one of"):
        make_loops(2, 100, setpoint_weights={"constant": 0.0, "steps": 0.0, "step": 0.0,
                                             "cascade": 0.0})  # fmt: skip
    with pytest.raises(ValueError, match="for self-regulating plants"):
        make_loops(2, 100, rules=("simc",), orders=(1,))


class _HeldProfiles:
    """A calibrated world whose every loop copies a profile recorded with a held historian."""

    overrides = {}

    def loop_profile(self, rng):
        from sktiction.simulation import HoldLastValue

        return {"loop_type": None, "settings": {},
                "recording": [HoldLastValue(0.5, mean_run=5.0)]}  # fmt: skip

    def recording_effects(self, rng, loop_type=None):
        return []


def test_a_profiles_recording_reaches_the_loops():
    X, _, meta = make_loops(6, 400, realism=_HeldProfiles(), short_fraction=0.0,
                            random_state=0, return_meta=True)  # fmt: skip
    assert (meta["recording"] == "HoldLastValue").all()
    for pv, op in zip(X[:, :, 0], X[:, :, 1], strict=True):
        assert np.array_equal(_frozen(pv), _frozen(op)) and _frozen(pv).mean() > 0.2
