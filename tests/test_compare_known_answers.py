"""Known answers of ``sktiction.realism.compare`` on statistics tables built by hand.

``compare`` and ``domain_gap`` take tables of :func:`loop_statistics` as they are, so each
statistic can be set to values whose medians, Cliff's delta, Mann-Whitney p-value (normal
approximation with continuity correction), Holm adjustment and robust shift are worked
out by hand; a domain classifier given constant columns cannot tell the sets apart (AUC
exactly 0.5), one given a column that separates them can (AUC 1).
"""

import math

import numpy as np
import pandas as pd
import pytest

from sktiction.realism import EFFECTS, STATISTIC_COLUMNS, as_statistics, compare, domain_gap
from sktiction.realism.compare import _holm, _iqr, _one

NAMES = list(EFFECTS)
STAT = {name: e.statistic for name, e in EFFECTS.items()}


def _table(n, value=1.0, **columns):
    """A statistics table of ``n`` loops, every column ``value`` but those given."""
    t = pd.DataFrame({c: np.full(n, value) for c in STATISTIC_COLUMNS})
    for c, v in columns.items():
        t[c] = np.asarray(v, dtype=float)
    return t


def _p_separated(n):
    """Two-sided asymptotic Mann-Whitney p of n samples all above n others (no ties)."""
    mean, sd = n * n / 2, math.sqrt(n * n * (2 * n + 1) / 12)
    return math.erfc((n * n - mean - 0.5) / sd / math.sqrt(2))


def _pair():
    """Twenty loops a side, two statistics random, one of them shifted by 0.7 sd."""
    a = STAT["hold_last_value"]
    r = np.random.default_rng(0)
    sim = _table(20, **{a: r.normal(size=20), STAT["spikes"]: r.normal(size=20)})
    meas = _table(20, **{a: r.normal(0.7, 1, 20), STAT["spikes"]: r.normal(size=20)})
    return sim, meas


def test_holm_worked_by_hand():
    """Sorted p times (m, m-1, ...), made monotone, capped at 1; NaN left out of m."""
    np.testing.assert_allclose(_holm([0.01, 0.04, 0.03, 0.005]), [0.03, 0.06, 0.06, 0.02])
    np.testing.assert_allclose(_holm([np.nan, 0.2, 0.6]), [np.nan, 0.4, 0.6])
    np.testing.assert_allclose(_holm([0.5, 0.9]), [1.0, 1.0])
    np.testing.assert_allclose(_holm([0.3]), [0.3])
    assert np.isnan(_holm([np.nan, np.nan])).all() and _holm([]).shape == (0,)


def test_iqr_and_the_one_statistic_comparison():
    """Medians, Cliff's delta P(m > s) - P(m < s) (ties half), the asymptotic two-sided
    p-value and the shift |median difference| / mean IQR."""
    assert _iqr(np.array([1.0, 2, 3, 4, 5])) == 2.0 and _iqr(np.arange(1.0, 5)) == 1.5
    s, m = np.arange(1.0, 6), np.arange(6.0, 11)
    med_s, med_m, delta, p, shift = _one(s, m)
    assert (med_s, med_m, delta, shift) == (3.0, 8.0, 1.0, 2.5)
    assert p == pytest.approx(_p_separated(5), rel=1e-9)  # 0.0122; exact test: 0.0079
    assert _one(m, s)[2] == -1.0 and _one(m, s)[3] == pytest.approx(p, rel=1e-12)
    # ties count half: 10 pairs above, 3 tied, 3 below of 16
    assert _one(np.arange(1.0, 5), np.arange(2.0, 6))[2] == pytest.approx(7 / 16)
    # different spreads: IQRs 2 and 4, medians 2 and 14
    assert _one(np.arange(5.0), np.arange(10.0, 19, 2))[4] == pytest.approx(4.0)
    # NaN left out
    assert _one(np.array([1.0, np.nan, 2, 3, 4, 5]), m)[:3] == (3.0, 8.0, 1.0)


def test_one_statistic_edge_cases():
    """Fewer than 2 finite values: medians only; one constant value on both sides: no
    difference (delta 0, p 1, shift 0); zero IQRs: a floor of 1e-9 x the larger median."""
    nan = np.nan
    out = _one(np.array([4.0, nan]), np.array([1.0, 2.0, 3.0]))
    assert out[:2] == (4.0, 2.0) and np.isnan(out[2:]).all()
    out = _one(np.array([nan]), np.array([1.0, 5.0]))
    assert np.isnan(out[0]) and out[1] == 3.0 and np.isnan(out[2:]).all()
    out = _one(np.array([1.0, 2.0]), np.array([7.0]))
    assert out[:2] == (1.5, 7.0) and np.isnan(out[2:]).all()
    assert _one(np.arange(1.0, 6), np.array([6.0, 7.0]))[2] == 1.0  # two are enough
    assert _one(np.array([6.0, 7.0]), np.arange(1.0, 6))[2] == -1.0
    assert _one(np.full(3, 2.0), np.full(4, 2.0)) == (2.0, 2.0, 0.0, 1.0, 0.0)
    # one side constant, the other not: compared
    med_s, med_m, delta, p, shift = _one(np.full(5, 1.0), np.arange(1.0, 6))
    assert delta == pytest.approx(0.8) and p < 1.0 and shift == pytest.approx(2.0 / 1.0)
    # both constant at different values: separated, shift against the floor
    out = _one(np.full(4, 1.0), np.full(4, 3.0))
    assert out[2] == 1.0 and out[4] == pytest.approx(2.0 / 3e-9)
    out = _one(np.array([0.0, 0, 0, 0, 1]), np.array([0.0, 0, 0, 0, -1]))
    assert out[0] == out[1] == 0.0 and out[4] == 0.0  # 0 / 1e-300, not 0 / 0


def test_as_statistics_returns_a_statistics_table_as_it_is():
    t = _table(2)
    assert as_statistics(t) is t
    t["extra"] = 0.0
    assert as_statistics(t) is t
    loops = np.random.default_rng(0).normal(size=(2, 60, 3))
    pd.testing.assert_frame_equal(as_statistics(loops), as_statistics(as_statistics(loops)))
    with pytest.raises(ValueError):
        as_statistics(_table(2).drop(columns=STATISTIC_COLUMNS[0]))


def test_compare_table_worked_by_hand():
    """Four loops a side: one statistic all above (delta 1, shift 10 / 1.5), one all below
    by more (delta -1, shift 20 / 1.5, listed first), one overlapping (delta 7/16), one
    missing on the measured side (last, NaN, not significant), the rest equal (delta 0)."""
    a, b, c, d = (STAT[k] for k in ("hold_last_value", "spikes", "noise_level", "setpoint_steps"))
    base = np.arange(1.0, 5)
    sim = _table(4, **{a: base, b: base, c: base, d: base})
    meas = _table(4, **{a: base + 10, b: base - 20, c: base + 1, d: np.full(4, np.nan)})
    table = compare(sim, meas, domain=False)
    assert list(table.columns) == [
        "effect", "statistic", "simulated", "measured", "effect_size", "p_value",
        "significant", "shift", "kind", "n_simulated", "n_measured", "simulator",
    ]  # fmt: skip
    assert sorted(table["effect"]) == sorted(NAMES) and len(table) == len(NAMES)
    by = table.set_index("statistic")
    assert table["statistic"].tolist()[:3] == [b, a, c] and table["statistic"].iloc[-1] == d
    assert (by.loc[a, "simulated"], by.loc[a, "measured"]) == (2.5, 12.5)
    assert (by.loc[a, "effect_size"], by.loc[b, "effect_size"]) == (1.0, -1.0)
    assert by.loc[c, "effect_size"] == pytest.approx(7 / 16)
    assert by.loc[a, "shift"] == pytest.approx(10 / 1.5)
    assert by.loc[b, "shift"] == pytest.approx(20 / 1.5)
    # Holm over the finite p-values (every effect but d): the two smallest (equal) times
    # their number, 17 with the 18 effects of the catalog
    p, m = _p_separated(4), len(EFFECTS) - 1  # 0.0304
    assert by.loc[a, "p_value"] == pytest.approx(m * p, rel=1e-9)
    assert by.loc[b, "p_value"] == pytest.approx(m * p, rel=1e-9)
    assert not table["significant"].any()
    assert np.isnan(by.loc[d, ["measured", "effect_size", "p_value", "shift"]].astype(float)).all()
    assert by.loc[d, "simulated"] == 2.5
    assert (by.loc[d, "n_simulated"], by.loc[d, "n_measured"]) == (4, 0)
    assert by.loc[a, "n_measured"] == 4
    rest = by.drop(index=[a, b, c, d])
    assert (rest["effect_size"] == 0).all() and (rest["p_value"] == 1).all()
    assert (rest["shift"] == 0).all()
    for name, e in EFFECTS.items():
        row = table.set_index("effect").loc[name]
        assert (row["statistic"], row["kind"], row["simulator"]) == (e.statistic, e.kind,
                                                                      e.simulator)  # fmt: skip
    assert np.isnan(table.attrs["domain_auc"]) and table.attrs["alpha"] == 0.05


def test_compare_significance_at_the_given_alpha():
    """Ten loops a side all apart: raw p 1.827e-4, times the 18 effects 3.289e-3:
    significant at 0.05 and 0.00329, not at 0.00328; ``significant`` is ``p_value < alpha``."""
    a = STAT["hold_last_value"]
    sim, meas = _table(10, **{a: np.arange(10.0)}), _table(10, **{a: np.arange(10.0) + 10})
    p = len(EFFECTS) * _p_separated(10)
    assert 0.00328 < p < 0.00329
    for alpha, expected in [(0.05, True), (0.00329, True), (0.00328, False)]:
        table = compare(sim, meas, alpha=alpha, domain=False)
        row = table.iloc[0]
        assert row["statistic"] == a and row["p_value"] == pytest.approx(p, rel=1e-9)
        assert row["significant"] == expected and table["significant"].sum() == expected
        assert table.attrs["alpha"] == alpha
    # a p-value equal to alpha is not below it
    p_value = compare(sim, meas, domain=False).loc[0, "p_value"]
    assert not compare(sim, meas, alpha=p_value, domain=False)["significant"].any()


def test_domain_gap_of_constant_and_separating_columns():
    """Constant columns: AUC 0.5; a column that separates the sets: 1; the record length
    is left out unless ``exclude`` lets it in."""
    n_samples = STAT["record_length"]
    a = STAT["hold_last_value"]
    sim, meas = _table(20), _table(20)
    assert domain_gap(sim, meas, cv=2) == 0.5
    apart = _table(20, **{a: np.arange(20.0) + 100})
    assert domain_gap(sim, apart, cv=2) == 1.0
    longer = _table(20, **{n_samples: np.full(20, 2000.0)})
    assert domain_gap(sim, longer, cv=2) == 0.5
    assert domain_gap(sim, longer, exclude=(), cv=2) == 1.0
    assert domain_gap(sim, apart, exclude=(a,), cv=2) == 0.5


def test_domain_gap_without_loops_or_columns():
    """Under 2 loops a side or no column: NaN; fewer loops than folds: the folds shrink to
    the smaller set (too few loops to split on: 0.5)."""
    a = STAT["hold_last_value"]
    sim, apart = _table(20), _table(20, **{a: np.arange(20.0) + 100})
    assert np.isnan(domain_gap(sim.iloc[:1], apart))
    assert np.isnan(domain_gap(sim, apart.iloc[:1]))
    assert np.isnan(domain_gap(sim, apart, exclude=list(STAT.values())))
    assert domain_gap(sim.iloc[:3], apart.iloc[:2], cv=5) == 0.5


def test_domain_gap_leaves_out_statistics_missing_far_more_on_one_side():
    """A statistic missing on 2 of 20 measured loops (10 points more than on the
    simulated ones) still enters the classifier; on 3 of 20 it is left out; missing on
    half of the loops of each side it enters."""
    a = STAT["hold_last_value"]
    sim = _table(20, **{a: np.zeros(20)})
    two = _table(20, **{a: np.r_[np.full(18, 100.0), np.nan, np.nan]})
    assert domain_gap(sim, two) > 0.9
    three = _table(20, **{a: np.r_[np.full(17, 100.0), np.full(3, np.nan)]})
    assert domain_gap(sim, three) == 0.5
    # missing as often on both sides (half the loops): it enters, and its values separate
    half = np.r_[np.zeros(10), np.full(10, np.nan)]
    assert domain_gap(_table(20, **{a: half}), _table(20, **{a: half + 100})) > 0.8


def test_domain_gap_groups_and_settings_reach_the_folds():
    """Groups must be one per measured loop and at least two; the folds shrink to the
    number of groups; a seed drawn from a generator is reproducible."""
    sim, meas = _pair()
    with pytest.raises(ValueError, match=r"^groups must have one entry per measured loop "
                                         r"\(20\); got 3\.$"):  # fmt: skip
        domain_gap(sim, meas, groups=["a", "b", "c"])
    with pytest.raises(ValueError, match="^groups must hold at least 2 groups"):
        domain_gap(sim, meas, groups=["a"] * 20)
    two = np.repeat(["u", "v"], 10)
    auc = domain_gap(sim, meas, cv=5, groups=two, random_state=3)  # two folds only
    assert 0.0 <= auc <= 1.0
    same = domain_gap(sim, meas, random_state=np.random.default_rng(7))
    assert same == domain_gap(sim, meas, random_state=np.random.default_rng(7))


def test_compare_hands_the_domain_settings_on():
    """``compare``'s domain AUC is ``domain_gap``'s with the same cv, groups and seed (each
    of which changes it here)."""
    sim, meas = _pair()
    groups = np.repeat([f"v{i}" for i in range(5)], 4)
    expected = domain_gap(sim, meas, cv=2, groups=groups, random_state=4)
    table = compare(sim, meas, cv=2, groups=groups, random_state=4)
    assert table.attrs["domain_auc"] == expected
    # what it would be with compare's default cv, groups or seed
    others = [domain_gap(sim, meas, cv=5, groups=groups, random_state=4),
              domain_gap(sim, meas, cv=2, random_state=4),
              domain_gap(sim, meas, cv=2, groups=groups, random_state=0)]  # fmt: skip
    assert all(o != expected for o in others)


def test_compare_defaults_to_five_folds_and_seed_zero():
    sim, meas = _pair()
    assert compare(sim, meas).attrs["domain_auc"] == domain_gap(sim, meas, cv=5, random_state=0)


def test_domain_gap_defaults_to_five_folds_and_seed_zero():
    sim, meas = _pair()
    assert domain_gap(sim, meas) == domain_gap(sim, meas, cv=5, random_state=0)
