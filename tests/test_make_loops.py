"""Tests of make_loops: shapes, labels, meta data, reproducibility, validation."""

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import make_loops

META_COLUMNS = {
    "cause", "y", "plant", "order", "gain", "time_constant", "delay",
    "apparent_time_constant", "apparent_delay", "lambda", "valve", "S", "J", "rule",
    "gain_factor", "Kc", "Ti", "ts", "samples_per_cycle", "snr_db", "effects",
}  # fmt: skip


@pytest.fixture(scope="module")
def loops():
    return make_loops(60, 1500, random_state=0, return_meta=True)


def test_shapes_dtypes_and_labels(loops):
    X, y, meta = loops
    assert X.shape == (60, 1500, 3) and X.dtype == np.float64
    assert y.shape == (60,) and y.dtype.kind == "i"
    assert np.isfinite(X).all()
    assert int(y.sum()) == 30  # stiction_fraction = 0.5
    assert isinstance(meta, pd.DataFrame) and len(meta) == 60
    assert META_COLUMNS <= set(meta.columns)
    assert set(meta["cause"]) == {"stiction", "aggressive_tuning", "external_disturbance", "none"}
    assert np.array_equal(y, (meta["cause"] == "stiction").to_numpy().astype(int))
    # the 30 other loops split evenly over the three causes
    assert meta["cause"].value_counts().drop("stiction").tolist() == [10, 10, 10]
    # OP stays in % of span, SP starts at 50
    assert X[:, :, 1].min() >= 0 and X[:, :, 1].max() <= 100
    assert np.all(X[:, 0, 2] == 50.0)


def test_meta_describes_the_loops(loops):
    X, y, meta = loops
    sticky = meta[meta["cause"] == "stiction"]
    assert set(sticky["valve"]) <= {"relay", "choudhury", "kano"}
    assert (sticky["J"] <= sticky["S"]).all() and sticky["S"].between(0.5, 10).all()
    healthy = meta[meta["cause"] != "stiction"]
    assert (healthy["valve"] == "linear").all() and healthy["S"].isna().all()
    assert (meta.loc[meta["cause"] == "aggressive_tuning", "gain_factor"] > 1.5).all()
    assert (meta.loc[meta["cause"] != "aggressive_tuning", "gain_factor"] == 1.0).all()
    assert set(meta["plant"]) <= {"foptd", "soptd", "nthorderlag", "integrating"}
    lam = meta.loc[meta["plant"] != "integrating", "lambda"]
    assert lam.between(0.1, 1.0 + 1e-9).all()
    assert meta["lambda"][meta["plant"] == "integrating"].isna().all()
    assert meta["snr_db"].between(10, 40).all()
    assert meta["effects"].str.contains("Noise").all()
    assert (
        meta.loc[meta["cause"] == "external_disturbance", "effects"]
        .str.contains("SinusoidalDisturbance")
        .all()
    )


def oscillation_strength(e):
    """Height of the first autocorrelation peak after the first minimum (0 if none)."""
    e = e - e.mean()
    ac = np.correlate(e, e, "full")[len(e) - 1 :]
    ac = ac[: len(e) // 2] / ac[0]
    rising = np.nonzero(np.diff(ac) > 0)[0]
    return 0.0 if len(rising) == 0 else ac[rising[0] :].max()


def test_causes_oscillate_as_labelled(loops):
    X, y, meta = loops
    e = X[:, 750:, 2] - X[:, 750:, 0]
    strength = np.array([oscillation_strength(row) for row in e])
    by_cause = pd.Series(strength).groupby(meta["cause"]).median()
    # measured with random_state=0: stiction 0.86, external 0.86, aggressive 0.65, none 0.13
    assert by_cause["stiction"] > 0.6
    assert by_cause["external_disturbance"] > 0.8
    assert by_cause["aggressive_tuning"] > 0.4
    assert by_cause["none"] < 0.35


def test_reproducible_and_seed_dependent():
    a, ya = make_loops(6, 300, random_state=7)
    b, yb = make_loops(6, 300, random_state=7)
    c, _ = make_loops(6, 300, random_state=8)
    assert np.array_equal(a, b) and np.array_equal(ya, yb)
    assert not np.allclose(a, c)


def test_class_balance_and_cause_arguments():
    X, y, meta = make_loops(
        10, 200, stiction_fraction=0.0, causes=("none",), random_state=1, return_meta=True
    )
    assert y.sum() == 0 and set(meta["cause"]) == {"none"}
    X, y = make_loops(
        10, 200, stiction_fraction=1.0, orders=(2,), stiction_models=("kano",), random_state=1
    )
    assert y.sum() == 10
    _, _, meta = make_loops(
        9, 200, stiction_fraction=1 / 3, ts=10.0, random_state=2, return_meta=True
    )
    assert (meta["ts"] == 10.0).all() and meta["y"].sum() == 3


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_loops": 0}, "n_loops must be an integer >= 1"),
        ({"n_samples": 1}, "n_samples must be an integer >= 2"),
        ({"stiction_fraction": 1.5}, r"stiction_fraction must be a finite number >= 0 and <= 1"),
        ({"causes": ("gremlins",)}, "causes must be a non-empty subset"),
        ({"ts": 0.0}, "ts must be a finite number > 0"),
        ({"lambda_range": (0.0, 1.0)}, r"lambda_range must be \(low, high\) with 0.0 < low"),
        ({"lambda_range": (0.8, 0.2)}, "lambda_range"),
        ({"orders": (0,)}, "orders must hold integers 1-10"),
        ({"stiction_models": ("sticky",)}, "stiction_models must be among"),
        ({"S_range": (5.0, 1.0)}, r"S_range must be \(low, high\)"),
        ({"S_range": (1.0, 80.0)}, "<= 50"),
        ({"period_range": (1.0, 10.0)}, "period_range"),
    ],
)
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make_loops(**{"n_loops": 4, "n_samples": 100, **kwargs})
