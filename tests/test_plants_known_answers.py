"""Known answers of the plant models in ``sktiction.simulation.plants``.

Continuous models are checked against their transfer functions (scipy's ``ss2tf``), the
discretisation against scipy's ``cont2discrete`` and the closed-form ZOH coefficients of a
first-order lag with a fractional delay, sampled responses against the analytic step
responses superposed for a staircase input (Erlang CDF of equal lags, the two-lag and the
integrator-with-lag responses), and the FOPTD approximations against the tangent at the
inflection point found numerically here and the docstrings' values.
"""

import math
import re

import numpy as np
import pytest
from scipy import optimize, signal, stats

from sktiction.simulation import FOPTD, SOPTD, IntegratingPlant, NthOrderLag
from sktiction.simulation.plants import _check_gain, _lag_chain, _phi_gamma, _Plant


def simulate(plant, ts, u):
    """The discretised plant driven by ``u`` (held over each sample), ``y[k] = C x[k]``."""
    A, B0, B1, C, m = plant.discretize(ts)
    x = np.zeros(len(B0))
    y = np.empty(len(u))
    for k in range(len(u)):
        y[k] = C @ x
        u0 = u[k - m] if k >= m else 0.0
        u1 = u[k - m - 1] if k >= m + 1 else 0.0
        x = A @ x + B0 * u0 + B1 * u1
    return y


def staircase_response(step, ts, delay, u):
    """Exact samples of the response to a held input: steps of ``u`` at ``j ts``, each
    seen through the unit step response ``step`` after the delay."""
    t = np.arange(len(u)) * ts
    du = np.diff(u, prepend=0.0)
    y = np.zeros(len(u))
    for j, d in enumerate(du):
        tau = t - j * ts - delay
        y += d * np.where(tau > 0, step(np.maximum(tau, 0.0)), 0.0)
    return y


def lag_step(T, n):
    """Unit step response of ``1 / (T s + 1)^n``: the Erlang(n, T) CDF."""
    return stats.gamma(n, scale=T).cdf


def two_lag_step(T1, T2):
    """Unit step response of ``1 / ((T1 s + 1)(T2 s + 1))``, ``T1 != T2``."""
    return lambda t: 1 - (T1 * np.exp(-t / T1) - T2 * np.exp(-t / T2)) / (T1 - T2)


def integrator_step(T):
    """Unit step response of ``1 / (s (T s + 1))`` (``T = 0``: ``t``)."""
    if T == 0:
        return lambda t: t
    return lambda t: t - T * (1 - np.exp(-t / T))


def tf(plant):
    """Numerator and denominator of the plant's continuous model, denominator monic."""
    A, B, C = plant.state_space()
    num, den = signal.ss2tf(A, B[:, None], C[None, :], np.zeros((1, 1)))
    return num[0] / den[0], den / den[0]


# ---------------------------------------------------------------- parameters


def test_gain_is_any_finite_nonzero_real_number_as_a_float():
    """Python and numpy ints and floats of either sign pass as floats; 0, NaN, inf,
    strings and None are refused with their messages."""
    for g, want in ((3, 3.0), (-2.5, -2.5), (np.float32(0.5), 0.5), (np.int64(-4), -4.0),
                    (np.float64(1e-3), 1e-3)):  # fmt: skip
        out = _check_gain(g)
        assert type(out) is float and out == want
    for bad in (np.nan, np.inf, -np.inf, "1.0", None, [1.0]):
        msg = f"gain must be a finite nonzero number; got {bad!r}."
        with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
            _check_gain(bad)
    for zero in (0, 0.0, -0.0, np.float64(0.0)):
        msg = "gain must be nonzero (any sign, != 0); got 0."
        with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
            _check_gain(zero)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: FOPTD(np.nan, 1.0), "gain must be a finite nonzero number; got nan."),
        (lambda: NthOrderLag(0, 1.0), "gain must be nonzero (any sign, != 0); got 0."),
        (lambda: SOPTD(np.inf), "gain must be a finite nonzero number; got inf."),
        (lambda: IntegratingPlant(0.0), "gain must be nonzero (any sign, != 0); got 0."),
        (lambda: NthOrderLag(1.0, 0.0), "time_constant must be a finite number > 0; got 0.0."),
        (lambda: NthOrderLag(1.0, 1.0, -1), "delay must be a finite number >= 0; got -1."),
        (lambda: NthOrderLag(1.0, 1.0, order=0), "order must be an integer >= 1; got 0."),
        (lambda: NthOrderLag(1.0, 1.0, order=2.0), "order must be an integer >= 1; got 2.0."),
        (lambda: NthOrderLag(1.0, 1.0, order="3"), "order must be an integer >= 1; got '3'."),
        (lambda: FOPTD(1.0, -1.0), "time_constant must be a finite number > 0; got -1.0."),
        (lambda: FOPTD(1.0, 1.0, np.inf), "delay must be a finite number >= 0; got inf."),
        (lambda: SOPTD(1.0, 0.0), "time_constant must be a finite number > 0; got 0.0."),
        (lambda: SOPTD(1.0, 1.0, -0.5), "delay must be a finite number >= 0; got -0.5."),
        (
            lambda: SOPTD(1.0, 1.0, 0.0, time_constant2=-2.0),
            "time_constant2 must be a finite number > 0; got -2.0.",
        ),
        (lambda: IntegratingPlant(1.0, -0.1), "delay must be a finite number >= 0; got -0.1."),
        (
            lambda: IntegratingPlant(1.0, 0.0, -1.0),
            "time_constant must be a finite number >= 0; got -1.0.",
        ),
        (lambda: FOPTD(1.0, 1.0).discretize(0.0), "ts must be a finite number > 0; got 0.0."),
        (lambda: FOPTD(1.0, 1.0).discretize(-1.0), "ts must be a finite number > 0; got -1.0."),
    ],
)
def test_bad_parameters_are_refused_with_their_message(call, message):
    """Each parameter check names the parameter, its bound and the value given."""
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        call()


def test_parameters_defaults_and_types():
    """The signatures' defaults (a unit plant, no delay, one lag, ``T2 = T1``, a pure
    integrator), parameters stored as floats and ints, and which plants integrate."""
    for plant in (NthOrderLag(), FOPTD()):
        assert (plant.gain, plant.time_constant, plant.delay, plant.order) == (1.0, 1.0, 0.0, 1)
    s = SOPTD()
    assert (s.gain, s.time_constant, s.delay, s.time_constant2, s.order) == (
        1.0, 1.0, 0.0, None, 2)  # fmt: skip
    i = IntegratingPlant()
    assert (i.gain, i.delay, i.time_constant, i.order) == (1.0, 0.0, 0.0, 1)
    assert IntegratingPlant(1.0, 0.0, 2.0).order == 2
    p = NthOrderLag(2, 3, 1, order=np.int64(4))
    assert (p.gain, p.time_constant, p.delay, p.order) == (2.0, 3.0, 1.0, 4)
    assert all(type(v) is float for v in (p.gain, p.time_constant, p.delay))
    assert type(p.order) is int
    assert type(SOPTD(1, 2, 0, time_constant2=3).time_constant2) is float
    assert (FOPTD.integrating, NthOrderLag.integrating, SOPTD.integrating) == (False,) * 3
    assert IntegratingPlant.integrating is True


def test_repr_names_the_class_and_every_parameter_and_reads_back():
    """``Name(param=value, ...)`` in the order of the signature; evaluated, it is the
    same plant."""
    plants = {
        "FOPTD(gain=2.0, time_constant=10.0, delay=3.0)": FOPTD(2, 10, 3),
        "NthOrderLag(gain=-1.5, time_constant=2.0, delay=0.5, order=3)":
            NthOrderLag(-1.5, 2.0, 0.5, order=3),
        "SOPTD(gain=1.0, time_constant=4.0, delay=0.0, time_constant2=None)": SOPTD(1, 4),
        "SOPTD(gain=1.0, time_constant=4.0, delay=1.0, time_constant2=2.0)":
            SOPTD(1, 4, 1, time_constant2=2),
        "IntegratingPlant(gain=0.1, delay=2.0, time_constant=1.0)":
            IntegratingPlant(0.1, 2.0, 1.0),
    }  # fmt: skip
    names = {"FOPTD": FOPTD, "SOPTD": SOPTD, "NthOrderLag": NthOrderLag,
             "IntegratingPlant": IntegratingPlant}  # fmt: skip
    for text, plant in plants.items():
        assert repr(plant) == text
        again = eval(text, names)
        assert type(again) is type(plant) and again._params() == plant._params()


def test_the_base_class_leaves_the_model_to_its_subclasses():
    """``_Plant`` has no model and no approximation of its own."""
    with pytest.raises(NotImplementedError):
        _Plant().state_space()
    with pytest.raises(NotImplementedError):
        _Plant().foptd()
    assert _Plant.integrating is False


# ---------------------------------------------------------------- continuous models


def test_lag_chain_is_the_chain_of_first_order_lags():
    """``dx_i/dt = (x_{i-1} - x_i) / T_i`` with ``x_0 = u``, ``y = x_n``."""
    T = [2.0, 0.5, 4.0]
    A, B, C = _lag_chain(T)
    want_A = np.array([[-1 / 2.0, 0, 0], [1 / 0.5, -1 / 0.5, 0], [0, 1 / 4.0, -1 / 4.0]])
    np.testing.assert_array_equal(A, want_A)
    np.testing.assert_array_equal(B, [1 / 2.0, 0.0, 0.0])
    np.testing.assert_array_equal(C, [0.0, 0.0, 1.0])
    A1, B1, C1 = _lag_chain([5.0])
    np.testing.assert_array_equal(A1, [[-0.2]])
    np.testing.assert_array_equal(B1, [0.2])
    np.testing.assert_array_equal(C1, [1.0])


@pytest.mark.parametrize(
    "plant, num, den",
    [
        # K / (T s + 1)^n, monic: (K / T^n) / (s + 1/T)^n
        (FOPTD(2.0, 5.0, 1.0), [2.0 / 5.0], [1.0, 1 / 5.0]),
        (NthOrderLag(-1.5, 2.0, 0.0, order=3), [-1.5 / 8.0], np.poly([-0.5] * 3)),
        (SOPTD(3.0, 2.0), [3.0 / 4.0], np.poly([-0.5, -0.5])),
        (SOPTD(3.0, 4.0, 0.0, time_constant2=0.5), [3.0 / 2.0], np.poly([-0.25, -2.0])),
        # K / (s (T s + 1)) = (K / T) / (s (s + 1/T)); K / s
        (IntegratingPlant(0.2, 0.0, 4.0), [0.2 / 4.0], [1.0, 0.25, 0.0]),
        (IntegratingPlant(-0.7), [-0.7], [1.0, 0.0]),
    ],
)
def test_state_space_is_the_documented_transfer_function(plant, num, den):
    """``C (sI - A)^-1 B`` is the transfer function in the class docstring, gain included."""
    got_num, got_den = tf(plant)
    np.testing.assert_allclose(got_den, den, rtol=1e-12, atol=1e-14)
    num = np.concatenate([np.zeros(len(den) - len(num)), num])  # a constant numerator
    np.testing.assert_allclose(got_num, num, rtol=1e-12, atol=1e-14)
    A, B, C = plant.state_space()
    assert A.shape == (plant.order, plant.order) and B.shape == C.shape == (plant.order,)


def test_integrating_state_space_matrices():
    """Pure integrator ``dx/dt = K u``; with a lag ``dx1/dt = (K u - x1) / T``,
    ``dx2/dt = x1``, ``y = x2``."""
    A, B, C = IntegratingPlant(0.3).state_space()
    np.testing.assert_array_equal(A, [[0.0]])
    np.testing.assert_array_equal(B, [0.3])
    np.testing.assert_array_equal(C, [1.0])
    A, B, C = IntegratingPlant(0.3, 1.0, 2.0).state_space()
    np.testing.assert_array_equal(A, [[-0.5, 0.0], [1.0, 0.0]])
    np.testing.assert_array_equal(B, [0.15, 0.0])
    np.testing.assert_array_equal(C, [0.0, 1.0])


# ---------------------------------------------------------------- discretisation


def test_phi_gamma_is_the_matrix_exponential_and_its_integral():
    """``e^{A t}`` and ``int_0^t e^{A s} ds B = A^-1 (e^{A t} - I) B`` for an invertible A,
    ``t B`` for ``A = 0``."""
    A = np.array([[-0.5, 0.0], [2.0, -1.0 / 3.0]])
    B = np.array([0.7, -0.2])
    for t in (0.3, 1.0, 2.5):
        phi, gamma = _phi_gamma(A, B, t)
        w, V = np.linalg.eig(A)
        want_phi = (V * np.exp(w * t)) @ np.linalg.inv(V)
        np.testing.assert_allclose(phi, want_phi, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(gamma, np.linalg.solve(A, (want_phi - np.eye(2)) @ B),
                                   rtol=1e-12, atol=1e-15)  # fmt: skip
    phi, gamma = _phi_gamma(np.zeros((1, 1)), np.array([0.4]), 2.5)
    np.testing.assert_allclose(phi, [[1.0]])
    np.testing.assert_allclose(gamma, [1.0], rtol=1e-14)


@pytest.mark.parametrize(
    "plant, ts",
    [
        (FOPTD(2.0, 5.0), 0.7),
        (NthOrderLag(-1.2, 1.5, 0.0, order=4), 0.4),
        (SOPTD(1.0, 3.0, 0.0, time_constant2=0.8), 1.3),
        (IntegratingPlant(0.25, 0.0, 2.0), 0.5),
        (IntegratingPlant(0.25), 2.0),
    ],
)
def test_without_delay_discretize_is_scipys_zoh(plant, ts):
    """No delay: ``(A_d, B0)`` is scipy's ZOH ``cont2discrete``, ``B1 = 0`` and ``m = 0``."""
    A, B, C = plant.state_space()
    Ad, Bd, *_ = signal.cont2discrete((A, B[:, None], C[None, :], 0.0), ts, method="zoh")
    A_, B0, B1, C_, m = plant.discretize(ts)
    np.testing.assert_allclose(A_, Ad, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(B0, Bd[:, 0], rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(B1, np.zeros_like(B0))
    np.testing.assert_array_equal(C_, C)
    assert m == 0 and type(m) is int


@pytest.mark.parametrize(
    "delay, ts, m",
    [
        (0.0, 1.0, 0), (0.4, 1.0, 0), (1.0, 1.0, 1), (2.3, 1.0, 2), (2.0, 0.5, 4),
        (1.99, 0.5, 3), (0.3, 0.1, 3), (0.7, 0.1, 7), (3.0, 0.3, 10), (1e-9, 1.0, 0),
    ],
)  # fmt: skip
def test_dead_time_in_whole_samples(delay, ts, m):
    """``m = floor(L / ts)``, also where ``L / ts`` is a whole number that floating point
    puts just below it (0.3 / 0.1 = 2.9999999999999996, 0.7 / 0.1 = 6.999999999999999)."""
    *_, got = FOPTD(1.0, 2.0, delay).discretize(ts)
    assert got == m and type(got) is int


@pytest.mark.parametrize("K, T, L, ts", [(2.0, 5.0, 2.3, 1.0), (-0.5, 1.5, 0.35, 0.2),
                                         (1.0, 3.0, 0.25, 1.0), (1.5, 2.0, 0.3, 0.1),
                                         (1.0, 0.8, 1.5, 0.5)])  # fmt: skip
def test_foptd_coefficients_in_closed_form(K, T, L, ts):
    """First-order lag, ``L = m ts + theta``: ``A_d = e^{-ts/T}``,
    ``B0 = K (1 - e^{-(ts - theta)/T})``, ``B1 = K e^{-(ts - theta)/T} (1 - e^{-theta/T})``
    (the modified z-transform)."""
    m = math.floor(L / ts + 1e-9)  # 0.3 / 0.1 is 3 samples, not 2.9999999999999996
    theta = L - m * ts
    theta = 0.0 if abs(theta) < 1e-12 else theta
    A, B0, B1, C, got_m = FOPTD(K, T, L).discretize(ts)
    assert got_m == m
    assert A[0, 0] == pytest.approx(math.exp(-ts / T), rel=1e-13)
    assert B0[0] == pytest.approx(K * (1 - math.exp(-(ts - theta) / T)), rel=1e-12)
    assert B1[0] == pytest.approx(
        K * math.exp(-(ts - theta) / T) * (1 - math.exp(-theta / T)), rel=1e-12, abs=1e-15
    )
    np.testing.assert_array_equal(C, [1.0])


@pytest.mark.parametrize(
    "plant, ts",
    [
        (FOPTD(2.0, 5.0, 2.3), 1.0),
        (SOPTD(-1.5, 3.0, 1.7, time_constant2=1.2), 0.5),
        (IntegratingPlant(0.1, 2.5, 3.0), 0.8),
        (NthOrderLag(0.7, 2.0, 3.1, order=4), 1.0),
    ],
)
def test_delayed_input_vectors_split_the_whole_samples_zoh(plant, ts):
    """``B0 + B1`` is the delay-free ZOH input vector and ``B0`` the ZOH vector over
    ``ts - theta`` (scipy's ``cont2discrete`` at that sample time); ``A_d`` is ``e^{A ts}``."""
    A, B, C = plant.state_space()
    m = math.floor(plant.delay / ts)
    theta = plant.delay - m * ts
    sys = (A, B[:, None], C[None, :], 0.0)
    Ad, Bd, *_ = signal.cont2discrete(sys, ts, method="zoh")
    _, Bpart, *_ = signal.cont2discrete(sys, ts - theta, method="zoh")
    A_, B0, B1, _, got_m = plant.discretize(ts)
    assert got_m == m
    np.testing.assert_allclose(A_, Ad, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(B0 + B1, Bd[:, 0], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(B0, Bpart[:, 0], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize(
    "plant, step",
    [
        (FOPTD(2.0, 5.0, 2.3), lambda t: 2.0 * lag_step(5.0, 1)(t)),
        (NthOrderLag(-1.7, 2.0, 1.4, order=3), lambda t: -1.7 * lag_step(2.0, 3)(t)),
        (SOPTD(1.5, 4.0, 0.6), lambda t: 1.5 * lag_step(4.0, 2)(t)),
        (SOPTD(0.8, 1.0, 2.7, time_constant2=3.0), lambda t: 0.8 * two_lag_step(1.0, 3.0)(t)),
        (IntegratingPlant(0.3, 1.6), lambda t: 0.3 * integrator_step(0.0)(t)),
        (IntegratingPlant(-0.2, 0.9, 2.5), lambda t: -0.2 * integrator_step(2.5)(t)),
        (FOPTD(1.0, 3.0, 1.5), lambda t: lag_step(3.0, 1)(t)),
    ],
)
def test_sampled_response_to_a_staircase_is_exact(plant, step):
    """The discretised plant driven by a random held input gives, at every sample, the
    continuous response: the analytic step responses superposed at each input change,
    each delayed by ``L`` (whole and fractional parts alike)."""
    ts = 0.5
    u = np.random.default_rng(3).uniform(-1, 1, 80)
    y = simulate(plant, ts, u)
    want = staircase_response(step, ts, plant.delay, u)
    np.testing.assert_allclose(y, want, rtol=0, atol=1e-10 * max(1.0, np.abs(want).max()))


def test_steady_state_gain_and_dead_time_of_a_step():
    """A unit step settles at ``K`` for every lag plant, and nothing moves before the
    dead time: the first sample that moves is the first after ``L``."""
    ts = 0.5
    for plant in (FOPTD(-2.5, 1.0, 1.2), SOPTD(0.4, 1.0, 0.5), NthOrderLag(3.0, 0.5, 2.0, 5),
                  SOPTD(1.2, 0.5, 1.0, time_constant2=1.5)):  # fmt: skip
        y = simulate(plant, ts, np.ones(200))
        assert y[-1] == pytest.approx(plant.gain, rel=1e-9)
        first = math.floor(plant.delay / ts) + 1
        assert not y[:first].any() and y[first] != 0.0


def test_integrating_plant_ramps_at_its_gain_and_lags_by_delay_plus_lag():
    """A unit step ramps at ``K`` per second; the ramp's asymptote ``K (t - L - T)`` crosses
    zero at ``L + T``, the delay ``foptd`` reports."""
    ts, n = 0.25, 400
    for K, L, T in ((0.3, 1.6, 0.0), (-0.05, 2.0, 3.0), (2.0, 0.3, 0.7)):
        plant = IntegratingPlant(K, L, T)
        y = simulate(plant, ts, np.ones(n))
        t = np.arange(n) * ts
        assert np.diff(y)[-1] == pytest.approx(K * ts, rel=1e-9)
        assert y[-1] == pytest.approx(K * (t[-1] - L - T), rel=1e-9)
        assert plant.foptd() == (K, math.inf, L + T)


# ---------------------------------------------------------------- FOPTD approximations


def test_foptd_of_one_lag_is_the_plant_itself():
    """``FOPTD(K, T, L).foptd() == (K, T, L)``, the docstring's (2, 10, 3) among them."""
    assert FOPTD(2.0, 10.0, 3.0).foptd() == (2.0, 10.0, 3.0)
    assert NthOrderLag(-0.5, 4.0, 1.5, order=1).foptd() == (-0.5, 4.0, 1.5)


@pytest.mark.parametrize("K, T, L, n", [(1.0, 1.0, 0.0, 2), (-2.0, 3.0, 0.5, 3),
                                        (0.7, 0.5, 2.0, 5), (4.0, 2.0, 1.0, 8)])  # fmt: skip
def test_foptd_of_equal_lags_is_the_tangent_at_the_inflection(K, T, L, n):
    """The Erlang step response ``F`` has its inflection at ``t = (n - 1) T``; the tangent
    there crosses zero at ``h = t - F / F'``; ``(K, n T - h, h + L)``."""
    ti = (n - 1) * T
    erlang = stats.gamma(n, scale=T)
    h = ti - erlang.cdf(ti) / erlang.pdf(ti)
    gain, tau, delay = NthOrderLag(K, T, L, order=n).foptd()
    assert gain == K
    assert tau == pytest.approx(n * T - h, rel=1e-9)
    assert delay == pytest.approx(h + L, rel=1e-9)


def test_docstring_approximations_of_two_equal_lags():
    """Two unit lags: ``h = 3 - e`` (0.282) and ``tau = e - 1`` (1.718), for ``NthOrderLag``
    and for ``SOPTD`` with ``T2`` left out or equal to ``T1``."""
    want = (1.0, math.e - 1, 3 - math.e)
    assert NthOrderLag(1.0, 1.0, order=2).foptd() == pytest.approx(want, rel=1e-12)
    assert SOPTD(1.0, 1.0).foptd() == pytest.approx(want, rel=1e-12)
    assert SOPTD(1.0, 1.0, 0.0, time_constant2=1.0).foptd() == pytest.approx(want, rel=1e-12)
    K, T, L = -3.0, 2.5, 0.4
    scaled = (K, (math.e - 1) * T, (3 - math.e) * T + L)
    assert SOPTD(K, T, L).foptd() == pytest.approx(scaled, rel=1e-12)
    assert SOPTD(K, T, L, time_constant2=T).foptd() == pytest.approx(scaled, rel=1e-12)


def _tangent_of_two_lags(T1, T2):
    """Apparent delay of ``1 / ((T1 s + 1)(T2 s + 1))`` found numerically: the inflection
    is the maximum of the slope (the impulse response), located with a bounded search."""
    y = two_lag_step(T1, T2)
    slope = lambda t: (np.exp(-t / T1) - np.exp(-t / T2)) / (T1 - T2)  # noqa: E731
    res = optimize.minimize_scalar(lambda t: -slope(t), bounds=(0.0, 10 * (T1 + T2)),
                                   method="bounded", options={"xatol": 1e-12})  # fmt: skip
    ti = res.x
    return ti - y(ti) / slope(ti)


@pytest.mark.parametrize("T1, T2", [(4.0, 2.0), (2.0, 4.0), (1.0, 3.0), (5.0, 0.5),
                                    (1.0, 1.5), (0.3, 0.2)])  # fmt: skip
def test_foptd_of_two_distinct_lags_is_the_tangent_at_the_inflection(T1, T2):
    """Distinct lags: the apparent delay is where the tangent at the inflection of the step
    response crosses zero, the same whichever lag comes first; ``tau = T1 + T2 - h``."""
    K, L = -1.3, 0.7
    h = _tangent_of_two_lags(T1, T2)
    gain, tau, delay = SOPTD(K, T1, L, time_constant2=T2).foptd()
    assert gain == K
    assert delay == pytest.approx(h + L, rel=1e-6)
    assert tau == pytest.approx(T1 + T2 - h, rel=1e-6)
    assert tau + delay == pytest.approx(T1 + T2 + L, rel=1e-12)
    swapped = SOPTD(K, T2, L, time_constant2=T1).foptd()
    assert swapped == pytest.approx((gain, tau, delay), rel=1e-12)


def test_foptd_of_two_lags_tends_to_one_lag_when_one_vanishes():
    """``T2 -> 0`` leaves a first-order lag: ``h -> 0`` and ``tau -> T1``."""
    K, T1, L = 2.0, 4.0, 1.0
    gain, tau, delay = SOPTD(K, T1, L, time_constant2=1e-6).foptd()
    assert gain == K
    assert tau == pytest.approx(T1, abs=1e-4)
    assert delay == pytest.approx(L, abs=1e-4)


def test_foptd_of_an_integrating_plant():
    """Integrating plants: velocity gain, infinite time constant, delay plus lag (the
    docstring's ``(0.1, inf, 3.0)``)."""
    assert IntegratingPlant(0.1, delay=2.0, time_constant=1.0).foptd() == (0.1, math.inf, 3.0)
    assert IntegratingPlant(-0.4, delay=1.5).foptd() == (-0.4, math.inf, 1.5)
