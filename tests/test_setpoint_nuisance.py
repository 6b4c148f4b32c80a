"""Setpoint moves are nuisance: no stiction feature may read them as evidence."""

import numpy as np
import pytest

from sktiction.features import PVOPHysteresis
from sktiction.features.hysteresis import hysteresis_fill


def _step_response(n=3000, t0=1500, seed=0):
    """A healthy flow loop answering one setpoint step: OP ramps to its new value,
    PV follows OP in phase (a line in the PV-OP plot); SP jumps at once."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    op = 30 + 3 * np.clip((t - t0) / 40, 0, 1) + rng.normal(0, 0.02, n)
    pv = 50 + 2 * (op - 30) + rng.normal(0, 0.02, n)
    sp = np.where(t < t0, 50.0, 56.0)
    return pv, op, sp


def test_a_setpoint_step_sweeps_no_hysteresis_area():
    pv, op, sp = _step_response()
    row = PVOPHysteresis().fit_transform(np.stack([pv, op, sp], axis=1)[None])[0]
    names = list(PVOPHysteresis().fit(np.zeros((1, 10, 3))).get_feature_names_out())
    fill = row[names.index("hysteresis_fill")]
    fill_slow = row[names.index("hysteresis_fill_slow")]
    assert fill < 0.1 and fill_slow < 0.1
    # the control error's plane reads the same step as a wide loop: that is why
    # the fill is taken against PV
    assert hysteresis_fill(sp - pv, op, 5, np.nan) > 0.3


def test_fill_ignores_the_setpoint_when_it_is_constant():
    pv, op, _ = _step_response()
    for w in (3, 12):
        expected = hysteresis_fill(50.0 - pv, op, w, np.nan)
        assert hysteresis_fill(-pv, op, w, np.nan) == pytest.approx(expected, rel=1e-9)
