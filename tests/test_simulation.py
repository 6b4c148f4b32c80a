"""Tests of the closed-loop simulator: plants, tuning, valves, effects, loop."""

import math

import numpy as np
import pytest

from sktiction.simulation import (
    FOPTD,
    SOPTD,
    ARNoise,
    ChoudhuryValve,
    DeadbandValve,
    IntegratingPlant,
    KanoValve,
    LinearValve,
    NthOrderLag,
    PIController,
    Quantization,
    RandomWalkLoad,
    RelayValve,
    SetpointSteps,
    SinusoidalDisturbance,
    WhiteNoise,
    foptd_approximation,
    make_valve,
    simulate_loop,
    simulate_loops,
    tune_pi,
    tune_pi_integrating,
)


def open_loop_step(plant, ts, n):
    """Unit step applied at k = 0 to the discretised plant, y[k] = C x[k]."""
    A, B0, B1, C, m = plant.discretize(ts)
    x = np.zeros(len(B0))
    u = np.ones(n)
    y = np.empty(n)
    for k in range(n):
        y[k] = C @ x
        u0 = u[k - m] if k >= m else 0.0
        u1 = u[k - m - 1] if k >= m + 1 else 0.0
        x = A @ x + B0 * u0 + B1 * u1
    return y


def error_periods(e, ts):
    """Full periods from every other zero crossing of the mean-removed error."""
    e = e - e.mean()
    neg = np.signbit(e)
    zc = np.nonzero(neg[1:] != neg[:-1])[0]
    return np.diff(zc[::2]) * ts


# ---------------------------------------------------------------- tuning & plants


def test_foptd_approximation_reproduces_table_1():
    table = [0.0, 0.16, 0.37, 0.55, 0.72, 0.88, 1.03]  # Singhal & Salsbury 2005, Table 1
    lam = [round(h / tau, 2) for h, tau in (foptd_approximation(n) for n in range(1, 8))]
    assert lam == table


def test_foptd_approximation_soptd_closed_form_and_delay():
    h, tau = foptd_approximation(2, time_constant=3.0, delay=0.5)
    assert h == pytest.approx((3 - math.e) * 3.0 + 0.5, rel=1e-12)
    assert tau == pytest.approx((math.e - 1) * 3.0, rel=1e-12)
    # distinct lags converge to the equal-lag result
    K, tau2, h2 = SOPTD(1.0, 3.0, 0.5, time_constant2=3.0 * (1 + 1e-7)).foptd()
    assert (tau2, h2) == pytest.approx((tau, h), rel=1e-5)


def test_tuning_rules_known_values():
    # AMIGO, K = T = 1, L = 0.5: K Kc = 0.15 + (0.35 - 0.5/2.25) * 2, Ti = 0.175 + 6.5/8.75
    kc, ti = tune_pi(1.0, 1.0, 0.5, "amigo")
    assert kc == pytest.approx(0.15 + (0.35 - 0.5 / 2.25) * 2)
    assert ti == pytest.approx(0.175 + 6.5 / 8.75)
    assert tune_pi(2.0, 1.0, 0.5, "chr") == pytest.approx((0.35, 1.2))
    assert tune_pi(-2.0, 1.0, 0.5, "zn") == pytest.approx((0.9, 1.5))
    kc, ti = tune_pi(1.0, 1.0, 0.5, "cc")
    assert (kc, ti) == pytest.approx((2 * (0.9 + 0.5 / 12), 0.5 * 31.5 / 19))
    assert tune_pi_integrating(0.5, 2.0) == pytest.approx((0.35, 26.8))


@pytest.mark.parametrize(
    "plant, analytic",
    [
        # FOPTD with a fractional delay (2.3 samples): K (1 - exp(-(t - L)/T))
        (FOPTD(2.0, 5.0, 2.3), lambda t: 2.0 * (1 - np.exp(-(t - 2.3) / 5.0))),
        (
            SOPTD(1.5, 4.0, 1.7),
            lambda t: 1.5 * (1 - (1 + (t - 1.7) / 4.0) * np.exp(-(t - 1.7) / 4.0)),
        ),
        (
            SOPTD(1.0, 4.0, 0.4, time_constant2=2.0),
            lambda t: 1 - (4.0 * np.exp(-(t - 0.4) / 4.0) - 2.0 * np.exp(-(t - 0.4) / 2.0)) / 2.0,
        ),
        (IntegratingPlant(0.3, delay=1.6), lambda t: 0.3 * (t - 1.6)),
    ],
)
def test_zoh_discretisation_is_exact(plant, analytic):
    ts, n = 1.0, 60
    t = np.arange(n) * ts
    y = open_loop_step(plant, ts, n)
    expected = np.where(t >= plant.delay, analytic(np.maximum(t, plant.delay)), 0.0)
    assert np.max(np.abs(y - expected)) < 1e-9


def test_nth_order_lag_steady_state_gain():
    y = open_loop_step(NthOrderLag(-1.7, 2.0, 1.0, order=4), 0.5, 400)
    assert y[-1] == pytest.approx(-1.7, rel=1e-9)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: FOPTD(1.0, 0.0), "time_constant must be a finite number > 0"),
        (lambda: FOPTD(1.0, -2.0), "time_constant"),
        (lambda: FOPTD(1.0, 1.0, -0.1), r"delay must be a finite number >= 0"),
        (lambda: FOPTD(0.0, 1.0), "gain must be nonzero"),
        (lambda: NthOrderLag(1.0, 1.0, order=0), "order must be an integer >= 1"),
        (lambda: SOPTD(1.0, 1.0, time_constant2=0.0), "time_constant2"),
        (lambda: IntegratingPlant(1.0, delay=-1.0), "delay"),
        (lambda: foptd_approximation(0), "order"),
        (lambda: tune_pi(1.0, 1.0, 0.0), r"delay must be a finite number > 0"),
        (lambda: tune_pi(1.0, 1.0, 0.5, rule="magic"), "rule must be one of"),
        (lambda: tune_pi_integrating(1.0, 1.0, rule="zn"), "rule must be one of"),
        (lambda: PIController(-1.0, 1.0), "kc must be a finite number > 0"),
        (lambda: PIController(1.0, 1.0, action="up"), "action"),
        (lambda: PIController.from_plant(FOPTD(1, 1, 1), gain_factor=0), "gain_factor"),
        (lambda: RelayValve(0.0), "d must be a finite number > 0"),
        (lambda: ChoudhuryValve(2.0, 3.0), r"J must satisfy 0 <= J <= S"),
        (lambda: KanoValve(2.0, -1.0), "J must be a finite number >= 0"),
        (lambda: ChoudhuryValve(0.0, 0.0), "S must be a finite number > 0"),
        (lambda: DeadbandValve(200.0), r"deadband must be a finite number > 0 and <= 100"),
        (lambda: make_valve("sticky", S=1.0, J=0.5), "valve model must be one of"),
        (lambda: WhiteNoise(), "exactly one of std"),
        (lambda: ARNoise(1.0, std=1.0), "phi"),
        (lambda: Quantization(0.0), "step"),
        (lambda: SetpointSteps([1.0, 2.0], [1.0]), "same length"),
    ],
)
def test_bad_arguments_name_argument_and_range(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_bad_loop_arguments():
    plant = FOPTD(1.0, 1.0, 0.5)
    ctrl = PIController.from_plant(plant)
    with pytest.raises(ValueError, match="ts must be a finite number > 0"):
        simulate_loop(plant, ctrl, LinearValve(), 100, 0.0)
    with pytest.raises(ValueError, match="n_samples must be an integer >= 2"):
        simulate_loop(plant, ctrl, LinearValve(), 1, 0.1)
    with pytest.raises(ValueError, match="setpoint must be"):
        simulate_loop(plant, ctrl, LinearValve(), 10, 0.1, setpoint=np.ones(3))
    with pytest.raises(ValueError, match="initial_op must be within 0-100"):
        simulate_loop(plant, ctrl, LinearValve(), 10, 0.1, initial_op=120.0)


# ---------------------------------------------------------------- valves, open loop


def ramp_down_up(start=50.0, low=40.0, high=60.0, step=0.01):
    down = np.arange(start, low - step / 2, -step)
    up = np.arange(low + step, high + step / 2, step)
    return np.r_[down, up], len(down) - 1  # input, index of the reversal point


@pytest.mark.parametrize("cls", [ChoudhuryValve, KanoValve])
def test_stiction_models_on_slow_ramp(cls):
    S, J, step = 4.0, 1.5, 0.01
    u, i_rev = ramp_down_up(step=step)
    y = cls(S, J).simulate(u)
    # sliding down before the reversal: slope 1, lagging the input by (S - J) / 2
    slide = slice(i_rev - 300, i_rev + 1)
    assert np.allclose(y[slide] - u[slide], (S - J) / 2)
    # deadband + stickband: no motion until the input has risen more than S
    moved = i_rev + 1 + np.nonzero(np.diff(y[i_rev:]) != 0)[0][0]
    travel = u[moved] - u[i_rev]
    assert S < travel <= S + step + 1e-9
    assert np.all(y[i_rev:moved] == y[i_rev])
    # slip jump of J (plus at most one ramp step)
    jump = y[moved] - y[moved - 1]
    assert J < jump <= J + step + 1e-9
    # sliding up afterwards: slope 1
    after = slice(moved + 1, len(u))
    assert np.allclose(np.diff(y[after]), step)
    assert np.allclose(y[after] - u[after], -(S - J) / 2)


def test_kano_ignores_wiggles_that_freeze_choudhury():
    # A noisy ramp: Choudhury re-sticks at every reversal, Kano keeps the stop point.
    rng = np.random.default_rng(0)
    u = 50 + np.linspace(0, 10, 500) + 0.05 * rng.standard_normal(500)
    y_ch = ChoudhuryValve(3.0, 1.0).simulate(u)
    y_ka = KanoValve(3.0, 1.0).simulate(u)
    assert np.ptp(y_ch) == 0.0  # never slips: each wiggle resets x_ss
    assert np.ptp(y_ka) > 8.0  # follows the ramp in slips


def test_choudhury_with_j_equal_s_equals_relay_for_large_moves():
    # Every input move exceeds S: each sample is a slip in both models, outputs equal u.
    rng = np.random.default_rng(1)
    sign = (-1.0) ** np.arange(300)
    u = 50 + sign * rng.uniform(1.5, 20, 300)
    assert np.all(np.abs(np.diff(u)) > 3.0)
    y_ch = ChoudhuryValve(2.0, 2.0).simulate(u, initial_position=40.0)
    y_re = RelayValve(2.0).simulate(u, initial_position=40.0)
    assert np.array_equal(y_ch, y_re) and np.array_equal(y_ch[1:], u[1:])


def test_choudhury_with_j_equal_s_matches_relay_in_closed_loop_at_lambda_zero():
    # Singhal & Salsbury (2005, Sec. 3.2): for lambda = 0 the Choudhury model is a relay
    # with hysteresis; the limit cycles agree in period and amplitude.
    ts = 0.005
    plant = FOPTD(1.0, 1.0, 0.0)
    ctrl = PIController.from_plant(plant, "chr", ts=ts)
    res = {}
    for name, valve in [("relay", RelayValve(2.0)), ("choudhury", ChoudhuryValve(2.0, 2.0))]:
        r = simulate_loop(plant, ctrl, valve, 12000, ts, effects=[SetpointSteps([0.1], [1.0])])
        e = (r.sp - r.pv)[6000:]
        res[name] = (error_periods(e, ts).mean(), np.ptp(r.valve[6000:]), np.ptp(e))
    assert res["choudhury"] == pytest.approx(res["relay"], rel=0.01)


def test_deadband_and_linear_valves():
    u = np.r_[np.linspace(50, 55, 51), np.linspace(55, 50, 51)]
    y = DeadbandValve(2.0).simulate(u)
    assert y.max() == pytest.approx(54.0)  # lags by half the band
    assert np.all(np.diff(y[51:71]) == 0)  # reversal: band of 2 taken up over 20 steps of 0.1
    assert np.array_equal(LinearValve().simulate(u), u)


# ---------------------------------------------------------------- closed loop


def python_loop(plant, ctrl, valve, n, ts, sp):
    """Straightforward reference implementation of the documented loop."""
    A, B0, B1, C, m = plant.discretize(ts)
    s = ctrl.sign(plant.gain)
    x = np.zeros(len(B0))
    w = np.zeros(n)
    u, e1, pv_eq = 50.0, 0.0, sp[0]
    pv = np.empty(n)
    st = valve.initial_state(50.0)
    from sktiction.simulation.valves import _valve_run

    for k in range(n):
        pv[k] = pv_eq + C @ x
        e = sp[k] - pv[k]
        u = min(max(u + s * ctrl.kc * ((e - e1) + ts / ctrl.ti * e), 0.0), 100.0)
        e1 = e
        w[k] = _valve_run(valve.kind, valve.params(), st, np.array([u]))[0] - 50.0
        x = A @ x + B0 * (w[k - m] if k >= m else 0) + B1 * (w[k - m - 1] if k > m else 0)
    return pv


@pytest.mark.parametrize("valve", [LinearValve(), KanoValve(2.0, 0.5)])
def test_compiled_loop_matches_reference_implementation(valve):
    plant = SOPTD(-1.3, 3.0, 2.7)
    ctrl = PIController.from_plant(plant)
    sp = np.r_[np.full(20, 50.0), np.full(380, 53.0)]
    res = simulate_loop(plant, ctrl, valve, 400, 0.4, setpoint=sp)
    assert np.max(np.abs(res.pv - python_loop(plant, ctrl, valve, 400, 0.4, sp))) < 1e-9


@pytest.mark.parametrize(
    "plant, ts",
    [
        (FOPTD(1.0, 10.0, 5.0), 0.5),
        (FOPTD(-2.0, 10.0, 1.0), 0.5),  # direct acting
        (SOPTD(1.0, 10.0, 3.0), 0.5),
        (NthOrderLag(0.5, 5.0, 2.0, order=4), 0.5),
        (IntegratingPlant(0.05, delay=3.0, time_constant=5.0), 0.5),
    ],
)
def test_healthy_amigo_loop_settles_after_setpoint_step(plant, ts):
    step = 5.0
    ctrl = PIController.from_plant(plant, "amigo", ts=ts)
    eff = [SetpointSteps([5.0], [step])]
    res = simulate_loop(plant, ctrl, LinearValve(), 4000, ts, effects=eff)
    e = res.sp - res.pv
    assert np.max(np.abs(e[-1000:])) < 0.01 * step
    assert res.t[1] == ts and res.X.shape == (4000, 3)


@pytest.mark.parametrize(
    "plant, valve, ts, step",
    [
        (FOPTD(1.0, 10.0, 5.0), RelayValve(2.0), 0.2, 0.7),  # lambda = 0.5
        (FOPTD(1.0, 10.0, 2.0), ChoudhuryValve(3.0, 1.0), 0.1, 0.7),  # lambda = 0.2
        (FOPTD(1.0, 10.0, 5.0), KanoValve(3.0, 1.0), 0.2, 2.0),
        (SOPTD(1.0, 10.0, 2.0), RelayValve(1.0), 0.1, 0.7),
        (IntegratingPlant(0.05, delay=3.0, time_constant=5.0), ChoudhuryValve(2.0, 0.5), 0.5, 2.0),
    ],
)
def test_sticky_valve_gives_regular_limit_cycle(plant, valve, ts, step):
    ctrl = PIController.from_plant(plant, ts=ts)
    # Steps are not multiples of the band (a slip exactly onto equilibrium ends the cycle).
    # With J < S and lambda >= 0.5 a small kick can end in a monotone slide to equilibrium,
    # hence the larger kick for the Kano case.
    res = simulate_loop(plant, ctrl, valve, 20000, ts, effects=[SetpointSteps([1.0], [step])])
    e = (res.sp - res.pv)[10000:]
    periods = error_periods(e, ts)
    assert len(periods) >= 5
    assert (periods.max() - periods.min()) / periods.mean() < 0.10
    assert np.ptp(e) > 0.1  # sustained, not decaying to zero


def test_aggressive_tuning_oscillates_healthy_valve():
    plant, ts = FOPTD(1.0, 1.0, 0.5), 0.02
    eff = [SetpointSteps([0.1], [1.0])]
    good = simulate_loop(
        plant, PIController.from_plant(plant, ts=ts), LinearValve(), 3000, ts, effects=eff
    )
    # AMIGO has a gain margin of 7.55 here (2 pi / 3.03 s ultimate period): 6.9 leaves 1.09
    hot = PIController.from_plant(plant, ts=ts, gain_factor=6.9)
    bad = simulate_loop(plant, hot, LinearValve(), 3000, ts, effects=eff)
    e_good, e_bad = good.sp - good.pv, bad.sp - bad.pv
    # the well-tuned loop does not overshoot; the aggressive one keeps ringing
    assert e_good.min() > -0.02
    assert np.ptp(e_bad[1500:]) > 0.05
    periods = error_periods(e_bad[100:], ts)
    assert len(periods) >= 10 and np.std(periods) / np.mean(periods) < 0.05


def test_external_sinusoid_sets_the_period():
    plant, ts = FOPTD(1.0, 10.0, 3.0), 0.5
    ctrl = PIController.from_plant(plant, ts=ts)
    res = simulate_loop(
        plant, ctrl, LinearValve(), 4000, ts, effects=[SinusoidalDisturbance(2.0, 40.0)]
    )
    periods = error_periods((res.sp - res.pv)[2000:], ts)
    assert np.mean(periods) == pytest.approx(40.0, rel=0.01)


# ---------------------------------------------------------------- effects


def test_noise_by_snr_uses_pilot_run():
    # Controller too weak to react: PV = 50 + sinusoid (std 1/sqrt 2) + noise.
    plant = FOPTD(1.0, 1.0, 0.5)
    ctrl = PIController(1e-12, 1e12)
    sine = SinusoidalDisturbance(1.0, 25.0)
    res = simulate_loop(
        plant,
        ctrl,
        LinearValve(),
        20000,
        1.0,
        effects=[sine, WhiteNoise(snr_db=20)],
        random_state=0,
    )
    noise = res.pv - 50 - sine.signals(20000, 1.0, None)["output_load"]
    assert noise.std() == pytest.approx(10 ** (-1) / math.sqrt(2), rel=0.03)


def test_ar_noise_is_coloured_with_unit_shape():
    eff = ARNoise(0.8, std=2.0)
    n = eff.signals(50000, 1.0, np.random.default_rng(0))["noise"]
    assert n.std() == pytest.approx(2.0, rel=0.05)
    assert np.corrcoef(n[1:], n[:-1])[0, 1] == pytest.approx(0.8, abs=0.02)


def test_recording_effects_and_reprs():
    plant = FOPTD(1.0, 10.0, 2.0)
    ctrl = PIController.from_plant(plant)
    eff = [SetpointSteps([5.0], [3.0]), RandomWalkLoad(0.01), Quantization(0.25, ("pv", "op"))]
    res = simulate_loop(plant, ctrl, LinearValve(), 500, 0.5, effects=eff, random_state=1)
    assert np.allclose(res.pv / 0.25, np.round(res.pv / 0.25))
    assert np.allclose(res.op / 0.25, np.round(res.op / 0.25))
    assert not np.allclose(res.valve / 0.25, np.round(res.valve / 0.25))  # not recorded
    assert repr(eff[2]) == "Quantization(step=0.25, channels=('pv', 'op'))"
    assert repr(SinusoidalDisturbance(1.0, 2.0)) == (
        "SinusoidalDisturbance(amplitude=1.0, period=2.0, phase=0.0, where='output')"
    )
    assert "S=3.0, J=1.0" in repr(ChoudhuryValve(3.0, 1.0))
    rec = WhiteNoise(std=0.1, where="record")
    assert rec.kind == "recording" and WhiteNoise(std=0.1).kind == "exogenous"


def test_same_seed_same_loops_different_seed_different():
    plant = FOPTD(1.0, 10.0, 4.0)
    ctrl = PIController.from_plant(plant)
    eff = [ARNoise(0.5, snr_db=20), RandomWalkLoad(0.01), SetpointSteps([3.0], [2.0])]
    a = simulate_loop(plant, ctrl, KanoValve(2.0, 1.0), 800, 0.5, effects=eff, random_state=3)
    b = simulate_loop(plant, ctrl, KanoValve(2.0, 1.0), 800, 0.5, effects=eff, random_state=3)
    c = simulate_loop(plant, ctrl, KanoValve(2.0, 1.0), 800, 0.5, effects=eff, random_state=4)
    assert np.array_equal(a.X, b.X)
    assert not np.allclose(a.X, c.X)


def test_batch_equals_single_loops():
    plants = [FOPTD(1.0, 10.0, 4.0), NthOrderLag(2.0, 3.0, 1.0, order=3)]
    ctrls = [PIController.from_plant(p, "chr") for p in plants]
    valves = [RelayValve(1.0), DeadbandValve(1.0)]
    eff = [SetpointSteps([2.0], [1.0])]
    batch = simulate_loops(plants, ctrls, valves, 300, [0.5, 0.25], effects=eff)
    for j in range(2):
        one = simulate_loop(plants[j], ctrls[j], valves[j], 300, [0.5, 0.25][j], effects=eff)
        assert np.array_equal(batch.X[j], one.X)
        assert np.array_equal(batch.valve[j], one.valve)
    assert batch.t.shape == (2, 300)


# ---------------------------------------------------------------- fast paths vs plain ones


def test_chunked_batch_with_pilot_and_recording_does_not_depend_on_the_chunk(monkeypatch):
    """Loops run in chunks: the same loops one at a time (chunks of 1) give the same bits,
    SNR noise (pilot run), setpoint and load arrays and recording effects included."""
    from sktiction.simulation import loop

    rng = np.random.default_rng(0)
    plants = [FOPTD(1.0, float(rng.uniform(2, 20)), float(rng.uniform(0, 5))) for _ in range(70)]
    ctrls = [PIController.from_plant(p) for p in plants]
    valves = [[LinearValve(), RelayValve(2.0), KanoValve(3.0, 1.0)][j % 3] for j in range(70)]
    effects = [
        [SetpointSteps([3.0], [2.0]), RandomWalkLoad(0.01)]
        + ([WhiteNoise(snr_db=20)] if j % 2 else [WhiteNoise(snr_db=10, where="record")])
        for j in range(70)
    ]

    def run():
        return simulate_loops(plants, ctrls, valves, 400, 1.0, effects=effects, random_state=5)

    batch = run()
    monkeypatch.setattr(loop, "_CHUNK", 1)
    single = run()
    assert np.array_equal(batch.X, single.X) and np.array_equal(batch.valve, single.valve)


def test_kernel_stores_from_start_and_runs_the_rows_asked_for():
    """``_run_loops`` with ``start`` stores the tail of the full run; ``rows`` picks loops."""
    from sktiction.simulation.loop import _loop_arrays, _run_loops

    plants = [FOPTD(1.0, 5.0, 2.0), SOPTD(-2.0, 3.0, 1.5), IntegratingPlant(0.1, 2.0, 3.0)]
    ctrls = [PIController.from_plant(p) for p in plants]
    valves = [RelayValve(1.0), LinearValve(), ChoudhuryValve(2.0, 1.0)]
    params, (kinds, vpar, vstate) = _loop_arrays(
        plants, ctrls, valves, np.ones(3), np.full(3, 50.0)
    )
    sp = np.full((3, 300), 50.0)
    sp[:, 10:] += 2.0
    noise = np.random.default_rng(0).standard_normal((3, 300)) * 0.1
    rel = np.random.default_rng(1).standard_normal((3, 300))
    ref = np.array([0.5, 0.0, 2.0])
    z = np.zeros((3, 1))
    inputs = (*params, sp[:, 0].copy(), kinds, vpar, vstate, sp, z, z)

    def run(rows, start):
        X = np.empty((len(rows), 300 - start, 3))
        valve = np.empty((len(rows), 300 - start))
        _run_loops(*inputs, noise, rel, ref, np.asarray(rows), start, X, valve)
        return X, valve

    X, valve = run([0, 1, 2], 0)
    # the measurement noise is noise + rel * ref, as if added beforehand
    X2 = np.empty_like(X)
    _run_loops(*inputs, noise + rel * ref[:, None], z, ref, np.arange(3), 0, X2, np.empty((3, 0)))
    assert np.array_equal(X, X2)
    Xt, vt = run([2, 0], 120)
    assert np.array_equal(Xt, X[[2, 0], 120:]) and np.array_equal(vt, valve[[2, 0], 120:])


def test_hold_mask_draws_like_one_run_at_a_time():
    """The vectorised mask equals drawing gap, run, gap, ... one by one, and leaves the
    generator in the same state."""
    from sktiction.simulation import HoldLastValue

    def one_at_a_time(fraction, mean_run, n, rng):
        f = min(fraction, 0.99)
        mean_gap = mean_run * (1.0 - f) / f
        held = np.zeros(n, dtype=bool)
        k = int(rng.geometric(1.0 / (1.0 + mean_gap)))
        while k < n:
            run = int(rng.geometric(1.0 / mean_run))
            held[k : k + run] = True
            k += run + int(rng.geometric(1.0 / (1.0 + mean_gap)))
        return held

    draw = np.random.default_rng(0)
    cases = [(seed, draw.uniform(0.01, 1.0), draw.uniform(1.0, 30.0), 1 + seed * 40)
             for seed in range(60)]  # fmt: skip
    # seed 10 draws runs the first batch does not cover: the batch is drawn again, larger
    cases.append((10, 0.5, 20.0, 5000))
    for seed, fraction, mean_run, n in cases:
        a, b = np.random.default_rng(seed), np.random.default_rng(seed)
        assert np.array_equal(HoldLastValue(fraction, mean_run).mask(n, a),
                              one_at_a_time(fraction, mean_run, n, b))  # fmt: skip
        assert a.random() == b.random()


def test_span_and_lowpass_coefficients_equal_numpys_to_the_bit():
    from sktiction.simulation.disturbances import _lag_power
    from sktiction.simulation.historian import _span

    rng = np.random.default_rng(0)
    for n in [1, 2, 3, 7, 20, 101, 1000, 4097]:
        x = np.round(rng.standard_normal(n) * 30.0, n % 3)
        x[rng.random(n) < 0.1] = np.nan
        finite = x[np.isfinite(x)]
        expected = np.subtract(*np.percentile(finite, [95, 5])) if len(finite) else 0.0
        assert _span(x) == expected
    for a in rng.uniform(0.0, 1.0, 50):
        for order in (1, 2, 3, 4):
            assert np.array_equal(_lag_power(a, order), np.poly(np.full(order, a)))


def test_trailing_mean_equals_the_cumsum_formula_to_the_bit():
    from sktiction.simulation.historian import _trailing_mean

    rng = np.random.default_rng(0)
    for n, m in [(0, 2), (1, 3), (7, 10), (500, 2), (3000, 7)]:
        x = rng.standard_normal(n) * 40.0 + 300.0
        x[n - n // 10 :] = np.nan  # the padding stays NaN
        c0 = np.concatenate([[0.0], np.cumsum(x)])
        k = np.arange(1, n + 1)
        lo = np.maximum(k - m, 0)
        assert np.array_equal(_trailing_mean(x, m), (c0[k] - c0[lo]) / (k - lo), equal_nan=True)


def test_batched_discretisation_equals_each_plants_own():
    """``_discretize_all`` (one ``expm`` call per number of states) gives every plant's own
    ``discretize`` to the bit: whole and fractional delays, no delay, a pure integrator."""
    from sktiction.simulation.loop import _discretize_all

    plants = [
        FOPTD(1.0, 10.0, 2.0), FOPTD(-2.0, 3.0, 2.3), SOPTD(1.5, 4.0, 0.0),
        SOPTD(1.0, 2.0, 1.7, time_constant2=0.5), NthOrderLag(0.7, 2.0, 3.1, order=4),
        IntegratingPlant(0.1, 2.5, 3.0), IntegratingPlant(0.2, 1.0), NthOrderLag(1.0, 1.0, 0.4, 3),
    ]  # fmt: skip
    ts = np.array([1.0, 0.7, 0.5, 0.3, 1.0, 0.8, 0.6, 0.25])
    A, B0, B1, C, nxs, delay = _discretize_all(plants, ts)
    for j, (plant, t) in enumerate(zip(plants, ts, strict=True)):
        Ad, b0, b1, c, m = plant.discretize(t)
        n = len(b0)
        assert nxs[j] == n and delay[j] == m
        assert np.array_equal(A[j, :n, :n], Ad) and np.array_equal(B0[j, :n], b0)
        assert np.array_equal(B1[j, :n], b1) and np.array_equal(C[j, :n], c)
        assert not A[j, n:].any() and not B0[j, n:].any()
