"""Known answers of the valve models, open loop and inside the compiled closed loop.

Every expected sequence below is worked out by hand from the model's definition (the
docstrings of ``sktiction.simulation.valves``); steps are multiples of 1/4 so that the
arithmetic is exact in floating point and the boundary cases (input exactly at a band
edge) are tested as ties, not as rounding accidents.
"""

import numpy as np
import pytest

from sktiction.simulation import (
    FOPTD,
    ChoudhuryValve,
    DeadbandValve,
    HeValve,
    KanoValve,
    LinearValve,
    PIController,
    RelayValve,
    SetpointSteps,
    SinusoidalDisturbance,
    make_valve,
    simulate_loops,
)
from sktiction.simulation.valves import VALVE_MODELS

# ------------------------------------------------------------------ linear valve


def test_linear_valve_is_the_identity_within_the_travel():
    rng = np.random.default_rng(0)
    u = rng.uniform(0.0, 100.0, 200)
    assert np.array_equal(LinearValve().simulate(u), u)
    # the stem cannot travel beyond 0-100 %: the input is clipped
    assert LinearValve().simulate([-5.0, 50.0, 120.0, 100.0, 0.0]).tolist() == [
        0.0, 50.0, 100.0, 100.0, 0.0,
    ]  # fmt: skip


def test_any_numeric_input_is_read_as_float():
    # e.g. a column read as objects; the kernel itself takes float arrays only
    u = np.array([50, 53, 54.0, 51, 50], dtype=object)
    assert ChoudhuryValve(2.0, 1.0).simulate(u).tolist() == [50.0, 52.5, 53.5, 51.5, 50.5]


def test_initial_state_is_at_rest_with_no_previous_motion():
    # layout [y, u_prev, du_sign_prev, stuck, direction, u_stick] (module docstring)
    st = ChoudhuryValve(2.0, 1.0).initial_state(40.0)
    assert st.tolist() == [40.0, 40.0, 0.0, 1.0, 0.0, 40.0]


# ------------------------------------------------------------------ relay valve


def test_relay_valve_jumps_to_the_input_only_beyond_d():
    # y[t] = y[t-1] if |u[t] - y[t-1]| <= d else u[t]; d = 1: a gap of exactly 1 holds
    u = [0.0, 0.5, 1.0, 1.5, 1.75, 0.75, 0.5, 0.25, 1.25]
    y = RelayValve(1.0).simulate(u)
    assert y.tolist() == [0.0, 0.0, 0.0, 1.5, 1.5, 1.5, 1.5, 0.25, 0.25]
    # its output levels are only ever the previous level or the current input
    assert all(y[k] in (y[k - 1], u[k]) for k in range(1, len(u)))


def test_relay_valve_starts_at_the_initial_position():
    y = RelayValve(2.0).simulate([50.0, 51.0, 52.5, 51.0], initial_position=49.0)
    assert y.tolist() == [49.0, 49.0, 52.5, 52.5]
    # by default it rests at the first input: a move of 1 < d does not reach it
    assert RelayValve(2.0).simulate([50.0, 51.0]).tolist() == [50.0, 50.0]


# ------------------------------------------------------------------ deadband


def test_deadband_valve_lags_by_half_the_band_and_waits_on_reversal():
    # width 2: the stem follows u - 1 going up, u + 1 going down; a reversal takes up 2
    u = [50.0, 52.0, 51.5, 49.0, 49.0, 50.0, 51.0, 51.5, 52.5, 51.5, 50.5, 50.25]
    y = DeadbandValve(2.0).simulate(u)
    assert y.tolist() == [50.0, 51.0, 51.0, 50.0, 50.0, 50.0, 50.0, 50.5, 51.5, 51.5, 51.5,
                          51.25]  # fmt: skip
    # within the band the stem never moves; outside it sits exactly on the band's edge
    assert np.all(np.abs(np.asarray(u) - y) <= 1.0)


def test_deadband_valve_from_an_initial_position():
    y = DeadbandValve(1.0).simulate([50.0, 50.0, 50.25, 51.0], initial_position=49.0)
    assert y.tolist() == [49.5, 49.5, 49.75, 50.5]


# ------------------------------------------------------------------ Choudhury


def test_choudhury_known_answer_on_a_reversing_staircase():
    # S = 2, J = 1: a moving stem lags the input by (S - J) / 2 = 0.5
    u = [50, 49.5, 49, 48.5, 48, 47.5, 47, 47.5, 48, 48.5, 49, 49.5, 50, 50, 50.5, 51,
         51.5, 52]  # fmt: skip
    y = ChoudhuryValve(2.0, 1.0).simulate(u)
    expected = [
        50, 50, 50, 50, 50,  # from rest the first slip needs more than S = 2 of travel
        48,  # 47.5 is 2.5 below x_ss = 50: slip to u + 0.5
        47.5,  # sliding down
        47.5, 47.5, 47.5, 47.5,  # reversal at 47: stuck until u - 47 > S (49 is a tie)
        49,  # 49.5: slip to u - 0.5, a jump of J plus one step
        49.5,  # sliding up
        49.5,  # input at rest: the valve sticks, x_ss = 50
        49.5, 49.5,  # same direction again: needs more than J = 1 (51 is a tie)
        51, 51.5,  # slip at 51.5, then slide
    ]  # fmt: skip
    assert y.tolist() == expected


def test_choudhury_with_zero_jump_is_a_deadband_on_a_slow_staircase():
    # J = 0: no stickband, no slip jump; a deadband of S with the stem lagging S / 2
    # (once moving: from rest Choudhury's first slip needs S, the deadband's S / 2)
    u = np.r_[np.arange(50.0, 54.01, 0.25), np.arange(53.75, 49.99, -0.25),
              np.arange(50.25, 53.01, 0.25)]  # fmt: skip
    y_ch = ChoudhuryValve(2.0, 0.0).simulate(u)
    y_db = DeadbandValve(2.0).simulate(u)
    first = 9  # u = 52.25: Choudhury's first slip
    assert y_ch[first - 1] == 50.0 and y_ch[first] == 51.25
    assert np.array_equal(y_ch[first:], y_db[first:])
    assert (y_ch[first:].max(), y_ch[first:].min()) == (53.0, 51.0)  # u - 1 at 54, u + 1 at 50


def test_choudhury_downward_slip_from_rest_in_both_directions():
    up = ChoudhuryValve(3.0, 1.0).simulate([50.0, 52.0, 53.0, 53.5, 54.0])
    assert up.tolist() == [50.0, 50.0, 50.0, 52.5, 53.0]
    down = ChoudhuryValve(3.0, 1.0).simulate([50.0, 48.0, 47.0, 46.5, 46.0])
    assert down.tolist() == [50.0, 50.0, 50.0, 47.5, 47.0]


def test_choudhury_as_published_slips_back_after_a_small_reversal_kano_does_not():
    # S = 2, J = 0.5: sliding up to 53.25 (lag 0.75), a reversal of 1 < S (stuck, x_ss = 54),
    # then up again: x_ss is reset to 53, and 53.75 is more than J past it, so Choudhury's
    # valve slips to 53.75 - 0.75 = 53.0, below where it stuck; Kano's keeps its stop at 54
    u = [50, 51, 52, 53, 54, 53, 53.75]
    assert ChoudhuryValve(2.0, 0.5).simulate(u).tolist()[-3:] == [53.25, 53.25, 53.0]
    assert KanoValve(2.0, 0.5).simulate(u).tolist()[-3:] == [53.25, 53.25, 53.25]


def test_choudhury_sticks_when_the_input_rests_in_either_direction():
    # S = 2, J = 1, lag 0.5: sliding down, the input rests one sample (velocity zero):
    # the valve sticks and needs more than J to move on (51.5 holds, 51 is a tie, 50.5 slips)
    u = [55.0, 52.5, 52.0, 52.0, 51.5, 51.0, 50.5, 50.0]
    y = ChoudhuryValve(2.0, 1.0).simulate(u)
    assert y.tolist() == [55.0, 53.0, 52.5, 52.5, 52.5, 52.5, 51.0, 50.5]


def test_choudhury_big_reversal_slips_within_one_sample():
    # the sample that reverses may already exceed S: stick and slip at once
    y = ChoudhuryValve(2.0, 1.0).simulate([50.0, 53.0, 54.0, 51.0, 50.0])
    assert y.tolist() == [50.0, 52.5, 53.5, 51.5, 50.5]


def test_choudhury_clips_the_stem_to_the_travel():
    y = ChoudhuryValve(2.0, 1.0).simulate([98.0, 101.0, 103.0, 2.0, -1.0, -3.0])
    assert y.tolist() == [98.0, 100.0, 100.0, 2.5, 0.0, 0.0]


# ------------------------------------------------------------------ Kano


def test_kano_known_answer_on_a_reversing_staircase():
    # on a clean staircase (no wiggles) Kano and Choudhury agree (same bands S, J)
    u = [50, 49.5, 49, 48.5, 48, 47.5, 47, 47.5, 48, 48.5, 49, 49.5, 50, 50, 50.5, 51,
         51.5, 52]  # fmt: skip
    expected = [50, 50, 50, 50, 50, 48, 47.5, 47.5, 47.5, 47.5, 47.5, 49, 49.5, 49.5,
                49.5, 49.5, 51, 51.5]  # fmt: skip
    assert KanoValve(2.0, 1.0).simulate(u).tolist() == expected


def test_kano_keeps_the_stop_point_through_wiggles():
    # S = 2, J = 0.5, lag (S - J) / 2 = 0.75. Up-slip, then the input steps back 1 and
    # forward 0.75: Kano's u_s stays at 54 (the valve did not move), so neither band is
    # crossed and the stem holds; it slips once d (u - u_s) > J.
    u = [50.0, 51.0, 52.0, 53.0, 54.0, 53.0, 53.75, 54.5, 55.0]
    y = KanoValve(2.0, 0.5).simulate(u)
    assert y.tolist() == [50.0, 50.0, 50.0, 52.25, 53.25, 53.25, 53.25, 53.25, 54.25]
    # reversal: -d (u - u_s) > S with d = +1 and u_s = 55
    u2 = u + [54.0, 53.0, 52.75, 52.5]
    y2 = KanoValve(2.0, 0.5).simulate(u2)
    assert y2.tolist()[-4:] == [54.25, 54.25, 53.5, 53.25]


def test_kano_remembers_where_a_slip_stopped():
    # S = 2, J = 0.5, lag 0.75. The stop point u_s is the input where a moving valve
    # stops or reverses, also right after the first slip from rest or after a reversal
    # slip: the next reversal is measured from there, not from an older stop.
    y = KanoValve(2.0, 0.5).simulate([50.0, 51.0, 52.0, 53.0, 52.0, 51.5, 51.0, 50.75])
    assert y.tolist() == [50.0, 50.0, 50.0, 52.25, 52.25, 52.25, 52.25, 51.5]
    u = [50.0, 51.0, 52.0, 53.0, 54.0, 55.0, 54.0, 53.0, 52.75, 53.0, 53.5, 54.0, 54.75,
         55.0]  # fmt: skip
    y = KanoValve(2.0, 0.5).simulate(u)
    assert y.tolist()[-6:] == [53.5, 53.5, 53.5, 53.5, 53.5, 54.25]  # 54.75: a tie


def test_kano_first_slip_from_rest_needs_s_in_either_direction():
    assert KanoValve(3.0, 1.0).simulate([50.0, 52.0, 53.0, 53.5]).tolist() == [
        50.0, 50.0, 50.0, 52.5,
    ]  # fmt: skip
    assert KanoValve(3.0, 1.0).simulate([50.0, 48.0, 47.0, 46.5]).tolist() == [
        50.0, 50.0, 50.0, 47.5,
    ]  # fmt: skip


def test_kano_clips_the_stem_to_the_travel():
    y = KanoValve(2.0, 1.0).simulate([98.0, 101.0, 103.0])
    assert y.tolist() == [98.0, 100.0, 100.0]


# ------------------------------------------------------------------ He


def test_he_valve_sticks_and_slips_by_the_residual_force():
    # fs = 1.5, fd = 0.5 (= S 2, J 1): moves when |u - y| > fs, to u - sign(u - y) fd
    u = [50, 49.5, 49, 48.5, 48, 47.5, 47, 47.5, 48, 48.5, 49, 49.5, 50, 50, 50.5, 51,
         51.5, 52]  # fmt: skip
    y = HeValve(1.5, 0.5).simulate(u)
    assert y.tolist() == [50, 50, 50, 50, 48.5, 48.5, 48.5, 48.5, 48.5, 48.5, 48.5, 48.5,
                          48.5, 48.5, 50, 50, 50, 51.5]  # fmt: skip


def test_he_valve_moving_slowly_sticks_and_slips_by_j():
    # a slow ramp: each slip moves the stem by fs - fd = J, then it sticks again
    u = np.arange(50.0, 60.001, 0.25)
    y = HeValve(1.5, 0.5).simulate(u)
    # (J plus one step: the residual reaches fs exactly, a tie, one step before the slip)
    jumps = np.diff(y)[np.diff(y) != 0]
    assert np.all(jumps == 1.25) and len(jumps) == 7
    assert y[7] == 51.25 and y[6] == 50.0  # first slip: u = 51.75 beats fs = 1.5 from 50
    assert np.all((u - y <= 1.5) & (u - y >= 0.0))


def test_he_from_sj_is_fs_and_fd():
    v = HeValve.from_sj(3.0, 1.0)
    assert (v.fs, v.fd) == (2.0, 1.0)
    assert repr(v) == "HeValve(fs=2.0, fd=1.0)"
    with pytest.raises(ValueError, match="J must satisfy"):
        HeValve.from_sj(1.0, 2.0)
    with pytest.raises(ValueError, match="S must be"):
        HeValve.from_sj(0.0, 0.0)
    # the reversal band is S = fs + fd and the slip jump J = fs - fd
    y = v.simulate([50.0, 52.5, 53.0, 51.0, 50.0, 49.5, 49.25])
    assert y.tolist() == [50.0, 51.5, 51.5, 51.5, 51.5, 51.5, 50.25]


def test_he_valve_clips_the_stem_to_the_travel():
    assert HeValve(1.0, 0.0).simulate([99.0, 101.0, 1.0, -2.0]).tolist() == [
        99.0, 100.0, 1.0, 0.0,
    ]  # fmt: skip


# ------------------------------------------------------------------ parameters


@pytest.mark.parametrize(
    "make, text",
    [
        (lambda: RelayValve(100.5), r"d must be a finite number > 0 and <= 100\.0"),
        (lambda: ChoudhuryValve(100.5, 1.0), r"S must be a finite number > 0 and <= 100\.0"),
        (lambda: KanoValve(2.0, float("nan")), r"J must be a finite number >= 0;"),
        (lambda: DeadbandValve(100.5), r"deadband must be a finite number > 0 and <= 100"),
        (lambda: HeValve(100.5, 1.0), r"fs must be a finite number > 0 and <= 100\.0"),
        (lambda: HeValve(0.0, 0.0), r"fs must be a finite number > 0"),
        (lambda: HeValve(2.0, -0.5), r"fd must be a finite number >= 0;"),
        (lambda: HeValve(2.0, 2.5), r"fd must satisfy 0 <= fd <= fs \(fs=2\.0\); got fd=2\.5"),
        (lambda: HeValve("2", 1.0), r"fs must be a finite number"),
        (lambda: HeValve(2.0, None), r"fd must be a finite number"),
    ],
)
def test_bad_parameters_are_refused(make, text):
    with pytest.raises(ValueError, match=text):
        make()


def test_band_edges_are_accepted():
    assert RelayValve(100.0).d == 100.0
    assert DeadbandValve(100).deadband == 100.0
    assert (ChoudhuryValve(100.0, 0.0).S, ChoudhuryValve(100.0, 0.0).J) == (100.0, 0.0)
    assert ChoudhuryValve(2.0, 2.0).J == 2.0
    assert (HeValve(100.0, 0.0).fs, HeValve(100.0, 0.0).fd) == (100.0, 0.0)
    assert HeValve(2.0, 2.0).fd == 2.0


@pytest.mark.parametrize(
    "model, params, text",
    [
        ("linear", {}, "LinearValve()"),
        ("relay", {"d": 2.0}, "RelayValve(d=2.0)"),
        ("choudhury", {"S": 3.0, "J": 1.0}, "ChoudhuryValve(S=3.0, J=1.0)"),
        ("kano", {"S": 3.0, "J": 1.0}, "KanoValve(S=3.0, J=1.0)"),
        ("deadband", {"deadband": 2.0}, "DeadbandValve(deadband=2.0)"),
        ("he", {"fs": 2.0, "fd": 0.5}, "HeValve(fs=2.0, fd=0.5)"),
    ],
)
def test_make_valve_and_repr(model, params, text):
    v = make_valve(model, **params)
    assert type(v) is VALVE_MODELS[model] and v.name == model
    assert repr(v) == text


# ------------------------------------------------------------------ compiled closed loop


def _loop_valves():
    return [
        LinearValve(),
        RelayValve(1.5),
        ChoudhuryValve(3.0, 1.0),
        KanoValve(3.0, 1.0),
        DeadbandValve(2.0),
        HeValve(2.0, 0.5),
        HeValve.from_sj(2.5, 2.0),
        ChoudhuryValve(2.0, 0.5),
    ]


def test_closed_loop_valve_is_the_open_loop_model_of_the_recorded_op():
    # simulate_loops (the kernel make_loops uses) inlines the valve step with the state
    # in local variables: the stem it records must be the valve model applied to the OP
    # it records, from rest at the initial OP.
    valves = _loop_valves()
    n = len(valves)
    plant = FOPTD(1.5, 8.0, 3.0)
    ctrl = PIController.from_plant(plant, ts=0.5)
    op0 = np.linspace(30.0, 65.0, n)
    eff = [SetpointSteps([5.0, 150.0], [3.0, -4.0]), SinusoidalDisturbance(0.8, 60.0)]
    res = simulate_loops([plant] * n, [ctrl] * n, valves, 600, 0.5, effects=eff,
                         initial_op=op0)  # fmt: skip
    for j, v in enumerate(valves):
        y = v.simulate(res.op[j], initial_position=op0[j])
        assert np.array_equal(res.valve[j], y), v
        moves = np.count_nonzero(np.diff(res.valve[j]))
        assert moves > 5, v  # the valve did move: the comparison is not vacuous
        if v.kind != LinearValve.kind:
            # a sticky valve or a deadband holds for a while at least once
            assert moves < 599, v
