"""Known answers of the PI tuning rules, the FOPTD approximation and the controller object.

The plant K = 2, tau = 3, L = 1 (r = L / tau = 1/3) gives round numbers for every rule; a
gain other than 1 and tau other than L catch a gain or a ratio put the wrong way up.
"""

import math

import numpy as np
import pytest
from scipy import stats

from sktiction.simulation import (
    FOPTD,
    SOPTD,
    IntegratingPlant,
    NthOrderLag,
    PIController,
    foptd_approximation,
    tune_pi,
    tune_pi_integrating,
)
from sktiction.simulation.controllers import INTEGRATING_RULES, TUNING_RULES

K, TAU, L = 2.0, 3.0, 1.0

# (Kc, Ti) for K = 2, tau = 3, L = 1, worked out by hand from the published formulas:
KNOWN = {
    # AMIGO (Astrom & Hagglund 2006, Eq. 7.6): K Kc = 0.15 + 0.35 tau / L - tau^2 / (L + tau)^2
    # = 0.15 + 1.05 - 9/16 = 0.6375; Ti = 0.35 L + 13 L tau^2 / (tau^2 + 12 L tau + 7 L^2)
    # = 0.35 + 117 / 52 = 2.6
    "amigo": (0.6375 / 2, 2.6),
    # Chien-Hrones-Reswick, setpoint, 0 % overshoot: K Kc = 0.35 tau / L, Ti = 1.2 tau
    "chr": (0.35 * 3 / 2, 3.6),
    # Ziegler-Nichols step response: K Kc = 0.9 tau / L, Ti = 3 L
    "zn": (1.35, 3.0),
    # Cohen-Coon: K Kc = tau / L (0.9 + L / (12 tau)) = 3 (0.9 + 1/36) = 2.7 + 1/12;
    # Ti = L (30 + 3 r) / (9 + 20 r) = 31 / (47 / 3) = 93 / 47
    "cc": ((2.7 + 1 / 12) / 2, 93 / 47),
}


@pytest.mark.parametrize("rule", TUNING_RULES)
def test_tune_pi_known_answers(rule):
    assert tune_pi(K, TAU, L, rule) == pytest.approx(KNOWN[rule], rel=1e-12)
    # the gain's sign does not matter; Kc scales as 1 / |K|, Ti not at all
    assert tune_pi(-K, TAU, L, rule) == pytest.approx(KNOWN[rule], rel=1e-12)
    kc, ti = tune_pi(4 * K, TAU, L, rule)
    assert (kc, ti) == pytest.approx((KNOWN[rule][0] / 4, KNOWN[rule][1]), rel=1e-12)


def test_tune_pi_default_rule_is_amigo_and_integer_arguments_are_accepted():
    assert tune_pi(K, TAU, L) == pytest.approx(KNOWN["amigo"], rel=1e-12)
    assert tune_pi(2, 3, 1, "zn") == pytest.approx(KNOWN["zn"], rel=1e-12)
    assert TUNING_RULES == ("amigo", "chr", "zn", "cc")


@pytest.mark.parametrize("rule", TUNING_RULES)
def test_tune_pi_is_scale_invariant_in_time(rule):
    """Every rule's Kc depends on tau / L only and its Ti scales with time."""
    kc, ti = tune_pi(K, TAU, L, rule)
    kc7, ti7 = tune_pi(K, 7 * TAU, 7 * L, rule)
    assert (kc7, ti7) == pytest.approx((kc, 7 * ti), rel=1e-12)


def test_amigo_and_cohen_coon_at_a_second_ratio():
    """tau = L = 2, K = 0.5 (r = 1): AMIGO K Kc = 0.15 + 0.35 - 1/4 = 0.25, Ti = 0.7 +
    13 * 2 * 4 / (4 + 48 + 28) = 0.7 + 1.3 = 2; Cohen-Coon K Kc = 0.9 + 1/12, Ti = 2 * 33 / 29."""
    assert tune_pi(0.5, 2.0, 2.0, "amigo") == pytest.approx((0.5, 2.0), rel=1e-12)
    assert tune_pi(0.5, 2.0, 2.0, "cc") == pytest.approx((2 * (0.9 + 1 / 12), 66 / 29), rel=1e-12)


@pytest.mark.parametrize(
    "rule, known",
    [
        # AMIGO for integrating plants: Kc = 0.35 / (Kv L), Ti = 13.4 L
        ("amigo", (0.35, 33.5)),
        # SIMC (Skogestad 2003) with tau_c = L: Kc = 1 / (Kv (tau_c + L)) = 0.5 / (Kv L),
        # Ti = 4 (tau_c + L) = 8 L
        ("simc", (0.5, 20.0)),
    ],
)
def test_tune_pi_integrating_known_answers(rule, known):
    # Kv = 0.4, L = 2.5: Kv L = 1
    assert tune_pi_integrating(0.4, 2.5, rule) == pytest.approx(known, rel=1e-12)
    assert tune_pi_integrating(-0.4, 2.5, rule) == pytest.approx(known, rel=1e-12)
    kc, ti = tune_pi_integrating(0.8, 5.0, rule)  # Kv L = 4, L doubled
    assert (kc, ti) == pytest.approx((known[0] / 4, 2 * known[1]), rel=1e-12)


def test_tune_pi_integrating_default_rule_is_amigo():
    assert tune_pi_integrating(0.4, 2.5) == pytest.approx((0.35, 33.5), rel=1e-12)
    assert INTEGRATING_RULES == ("amigo", "simc")


@pytest.mark.parametrize("gain", [0, 0.0, math.nan, math.inf, -math.inf, "2", None, True])
@pytest.mark.parametrize(
    "call",
    [lambda g: tune_pi(g, 1.0, 0.5), lambda g: tune_pi_integrating(g, 0.5)],
    ids=["tune_pi", "tune_pi_integrating"],
)
def test_bad_gains_are_refused(call, gain):
    with pytest.raises(ValueError, match=r"gain must be a finite nonzero number; got "):
        call(gain)


def test_numpy_gains_tune_as_floats():
    # a gain read from an array (np.int64, np.float32) tunes as the same float does
    assert tune_pi(np.int64(2), 3.0, 1.0) == tune_pi(2.0, 3.0, 1.0)
    assert tune_pi_integrating(np.float32(0.5), 2.0, "simc") == (0.5, 16.0)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: tune_pi(1.0, 0.0, 0.5), r"^time_constant must be a finite number > 0"),
        (lambda: tune_pi(1.0, -1.0, 0.5), r"^time_constant must be a finite number > 0"),
        (lambda: tune_pi(1.0, 1.0, 0.0), r"^delay must be a finite number > 0"),
        (lambda: tune_pi_integrating(1.0, 0.0), r"^delay must be a finite number > 0"),
        (lambda: tune_pi(1.0, 1.0, 0.5, rule="AMIGO"),
         r"^rule must be one of \('amigo', 'chr', 'zn', 'cc'\); got 'AMIGO'\.$"),
        (lambda: tune_pi_integrating(1.0, 1.0, rule="zn"),
         r"^rule must be one of \('amigo', 'simc'\); got 'zn'\.$"),
    ],
)  # fmt: skip
def test_bad_tuning_arguments_are_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ---------------------------------------------------------------- FOPTD approximation


def test_foptd_approximation_of_three_lags_in_closed_form():
    """n = 3: the step response is 1 - e^{-x} (1 + x + x^2 / 2), x = t / T; at the
    inflection x = 2 it is 1 - 5 e^{-2} with slope 2 e^{-2}, so h / T = 2 - (e^2 - 5) / 2
    = (9 - e^2) / 2 and tau / T = 3 - h / T = (e^2 - 3) / 2; the delay adds to h only."""
    e2 = math.exp(2)
    h, tau = foptd_approximation(3, time_constant=2.0, delay=0.7)
    assert h == pytest.approx((9 - e2) + 0.7, rel=1e-12)
    assert tau == pytest.approx(e2 - 3, rel=1e-12)
    assert h + tau == pytest.approx(3 * 2.0 + 0.7, rel=1e-12)  # n T + L


@pytest.mark.parametrize("order", [2, 3, 4, 7, 20, 60, 200])
def test_foptd_approximation_is_the_erlang_tangent(order):
    """h / T = k - F(k) / f(k) at the inflection k = n - 1 of the Erlang(n) CDF F."""
    k = order - 1
    erlang = stats.gamma(order)
    h, tau = foptd_approximation(order)
    assert h == pytest.approx(k - erlang.cdf(k) / erlang.pdf(k), rel=1e-9)
    assert tau == pytest.approx(order - h, rel=1e-12)


def test_foptd_approximation_of_one_lag_is_exact():
    assert foptd_approximation(1, 2.5, 0.4) == (0.4, 2.5)
    assert foptd_approximation(1) == (0.0, 1.0)
    assert foptd_approximation(2) == pytest.approx((3 - math.e, math.e - 1), rel=1e-12)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"order": 0}, r"^order must be an integer >= 1; got 0\.$"),
        ({"order": 2.0}, r"^order must be an integer >= 1; got 2\.0\.$"),
        ({"order": True}, r"^order must be an integer >= 1; got True\.$"),
        ({"order": 2, "time_constant": 0.0}, r"^time_constant must be a finite number > 0"),
        ({"order": 2, "delay": -0.1}, r"^delay must be a finite number >= 0"),
    ],
)
def test_foptd_approximation_refuses_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        foptd_approximation(**kwargs)


def test_plants_tune_through_their_approximation():
    """NthOrderLag(n = 3) is tuned on its apparent delay and time constant."""
    e2 = math.exp(2)
    plant = NthOrderLag(K, 2.0, 0.7, order=3)
    assert plant.foptd() == pytest.approx((K, e2 - 3, 9 - e2 + 0.7), rel=1e-12)
    ctrl = PIController.from_plant(plant, "zn")
    assert (ctrl.kc, ctrl.ti) == pytest.approx(tune_pi(K, e2 - 3, 9.7 - e2, "zn"), rel=1e-12)
    assert SOPTD(K, 2.0, 0.7).foptd() == pytest.approx(
        (K, 2 * (math.e - 1), 2 * (3 - math.e) + 0.7), rel=1e-12
    )


# ---------------------------------------------------------------- PIController


def test_from_plant_adds_half_a_sample_to_the_delay():
    # L = 0.75 + 0.5 / 2 = 1: the plant K = 2, tau = 3, L = 1 of KNOWN
    plant = FOPTD(K, TAU, 0.75)
    for rule in TUNING_RULES:
        ctrl = PIController.from_plant(plant, rule, ts=0.5)
        assert (ctrl.kc, ctrl.ti) == pytest.approx(KNOWN[rule], rel=1e-12)
        assert ctrl.rule == rule
    # without ts the delay is the plant's
    ctrl = PIController.from_plant(FOPTD(K, TAU, L))
    assert (ctrl.kc, ctrl.ti) == pytest.approx(KNOWN["amigo"], rel=1e-12)
    assert ctrl.rule == "amigo"


def test_from_plant_gain_factor_scales_kc_only_and_passes_the_options():
    ctrl = PIController.from_plant(FOPTD(K, TAU, L), "zn", gain_factor=3,
                                   action="direct", op_limits=(10, 90))  # fmt: skip
    assert ctrl.kc == pytest.approx(3 * 1.35, rel=1e-12) and ctrl.ti == pytest.approx(3.0)
    assert ctrl.action == "direct" and ctrl.op_limits == (10.0, 90.0) and ctrl.td == 0.0
    with pytest.raises(ValueError, match="^gain_factor must be a finite number > 0"):
        PIController.from_plant(FOPTD(K, TAU, L), gain_factor=-1.0)
    with pytest.raises(ValueError, match="^ts must be a finite number > 0"):
        PIController.from_plant(FOPTD(K, TAU, L), ts=0.0)


def test_from_plant_of_an_integrating_plant():
    # Kv = 0.4, delay 1.5 + lag 0.5 + ts 1.0 / 2 = 2.5: AMIGO (0.35, 33.5), SIMC (0.5, 20)
    plant = IntegratingPlant(-0.4, delay=1.5, time_constant=0.5)
    amigo = PIController.from_plant(plant, ts=1.0)
    simc = PIController.from_plant(plant, "simc", ts=1.0)
    assert (amigo.kc, amigo.ti) == pytest.approx((0.35, 33.5), rel=1e-12)
    assert (simc.kc, simc.ti) == pytest.approx((0.5, 20.0), rel=1e-12)
    with pytest.raises(ValueError, match="rule must be one of"):
        PIController.from_plant(plant, "chr")


def test_controller_sign_follows_action_and_plant_gain():
    auto = PIController(1.0, 1.0)
    assert auto.action == "auto"
    assert (auto.sign(2.0), auto.sign(-0.5)) == (1.0, -1.0)
    reverse = PIController(1.0, 1.0, action="reverse")
    direct = PIController(1.0, 1.0, action="direct")
    for gain in (2.0, -0.5):
        assert (reverse.sign(gain), direct.sign(gain)) == (1.0, -1.0)


def test_controller_attributes_and_repr():
    ctrl = PIController(2, 5, 0.5, action="reverse", op_limits=(-10, 110), rule="chr")
    assert (ctrl.kc, ctrl.ti, ctrl.td) == (2.0, 5.0, 0.5)
    assert all(type(v) is float for v in (ctrl.kc, ctrl.ti, ctrl.td, *ctrl.op_limits))
    assert repr(ctrl) == (
        "PIController(kc=2.0, ti=5.0, td=0.5, action='reverse', op_limits=(-10.0, 110.0), "
        "rule='chr')"
    )
    default = PIController(1.0, 1.0)
    assert (default.td, default.op_limits, default.rule) == (0.0, (0.0, 100.0), None)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"kc": 0.0}, r"^kc must be a finite number > 0"),
        ({"ti": 0.0}, r"^ti must be a finite number > 0"),
        ({"ti": math.inf}, r"^ti must be a finite number > 0"),
        ({"td": -0.1}, r"^td must be a finite number >= 0"),
        ({"action": "up"},
         r"^action must be 'auto', 'reverse' or 'direct'; got 'up'\.$"),
        ({"op_limits": (50.0, 50.0)},
         r"^op_limits must be \(low, high\) with low < high; got \(50\.0, 50\.0\)\.$"),
        ({"op_limits": (100, 0)}, r"^op_limits must be \(low, high\) with low < high"),
    ],
)  # fmt: skip
def test_controller_refuses_bad_settings(kwargs, match):
    args = {"kc": 1.0, "ti": 1.0, **kwargs}
    with pytest.raises(ValueError, match=match):
        PIController(**args)
