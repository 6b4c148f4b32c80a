"""Per-cycle templates, DTW, and the TemplateDistances transformer (seed 001)."""

import numpy as np
import pandas as pd
import pytest
from tslearn.metrics import dtw

from sktiction import TemplateDistances, cycle_table
from sktiction.features import paired_dtw
from sktiction.features.templates import SHAPES, make_shape_cycles, match_cycles


@pytest.mark.parametrize("radius", [None, 0, 2, 7])
def test_paired_dtw_equals_tslearn(radius):
    rng = np.random.default_rng(radius or 0)
    A, B = rng.normal(size=(2, 30, 32))
    kw = {} if radius is None else {"global_constraint": "sakoe_chiba",
                                    "sakoe_chiba_radius": radius}
    expected = [dtw(a, b, **kw) for a, b in zip(A, B)]
    assert np.allclose(paired_dtw(A, B, sakoe_chiba_radius=radius), expected, atol=1e-9)


def test_paired_dtw_rejects_bad_input():
    with pytest.raises(ValueError, match="one shape"):
        paired_dtw(np.zeros((2, 5)), np.zeros((2, 6)))
    with pytest.raises(ValueError, match="NaN"):
        paired_dtw(np.full((1, 5), np.nan), np.zeros((1, 5)))
    with pytest.raises(ValueError, match="sakoe_chiba_radius"):
        paired_dtw(np.zeros((1, 5)), np.zeros((1, 5)), sakoe_chiba_radius=-1)


@pytest.mark.parametrize("snr_db, required", [(20.0, 0.95), (10.0, 0.85)])
def test_shapes_are_matched_to_their_true_shape(snr_db, required):
    # halves differing up to 2x in duration, amplitudes up to 50 %, period +-30 %
    correct = total = 0
    for k, shape in enumerate(SHAPES):
        for seed in range(10):
            x, bounds = make_shape_cycles(shape, 20, snr_db=snr_db, random_state=seed)
            best = match_cycles(x, bounds).argmin(axis=1)
            correct += np.sum(best == k)
            total += best.size
    assert correct / total >= required


def test_tslearn_backend_gives_the_same_distances():
    x, bounds = make_shape_cycles("trapezoidal", 5, random_state=0)
    assert np.allclose(match_cycles(x, bounds), match_cycles(x, bounds, backend="tslearn"))


def _flow_loop(n=3000, period=100, noise=0.0, seed=0):
    """Triangular OP, square PV a quarter period later: a sticky flow loop."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    op = 50 + 3 * np.abs((t % period) / (period / 2) - 1)
    pv = 40 + np.sign(np.sin(2 * np.pi * (t + period / 4) / period))
    return np.stack([pv + noise * rng.normal(size=n), op, np.full(n, 40.0)], axis=1)


def test_transformer_finds_triangular_op_and_square_pv():
    X = _flow_loop(noise=0.05)[None]
    out = TemplateDistances().set_output(transform="pandas").fit_transform(X)
    assert out.loc[0, "op_share_triangular"] >= 0.9
    assert out.loc[0, "pv_share_rectangular"] + out.loc[0, "pv_share_trapezoidal"] >= 0.9
    assert out.loc[0, "oscillating"] == 1 and out.loc[0, "n_cycles"] >= 25
    assert out.loc[0, "period"] == pytest.approx(100, rel=0.05)


def test_cycle_table_columns_and_peak_to_peak():
    table = cycle_table(_flow_loop()[None])
    for col in ["loop", "cycle", "start", "end", "period", "amplitude_pos", "amplitude_neg",
                "area_ratio", "op_shape", "pv_shape", "op_peak_to_peak", "op_dist_triangular",
                "pv_dist_rectangular"]:
        assert col in table.columns
    assert table["op_peak_to_peak"].median() == pytest.approx(3.0, rel=0.05)
    assert (table["end"] > table["start"]).all()


def test_unequal_lengths_and_bad_loops_in_one_batch():
    good = _flow_loop()
    X = np.full((4, 3000, 3), np.nan)
    X[0] = good
    X[1, :2000] = good[:2000]  # shorter loop, NaN-padded at the end
    X[2] = good
    X[2, 100:130, 1] = np.nan  # gap in OP
    X[3] = good
    X[3, :, 0] = 1.0  # constant PV
    out = TemplateDistances().set_output(transform="pandas").fit_transform(X)
    assert out["oscillating"].tolist() == [1.0, 1.0, 0.0, 0.0]
    assert out.loc[2:, "op_dist_triangular"].isna().all()
    assert out.loc[1, "n_cycles"] < out.loc[0, "n_cycles"]


def test_missing_op_is_named():
    X = _flow_loop()[None, :, :1]
    with pytest.raises(ValueError, match="needs the OP channel"):
        TemplateDistances().fit(X)
    out = TemplateDistances(signals=("pv",)).fit_transform(X)
    assert out.shape == (1, 4 + 4 + 3)


def test_feature_names_and_pandas_output():
    td = TemplateDistances().fit(_flow_loop()[None])
    names = td.get_feature_names_out()
    assert names[0] == "op_dist_rectangular" and names[-1] == "oscillating"
    out = td.set_output(transform="pandas").transform(_flow_loop()[None])
    assert isinstance(out, pd.DataFrame) and list(out.columns) == list(names)


@pytest.mark.parametrize(
    "params, match",
    [({"n_points": 4}, "n_points"), ({"signals": ("op", "sp")}, "signals"),
     ({"dtw_backend": "cuda"}, "dtw_backend"), ({"sakoe_chiba_radius": -2}, "radius")],
)
def test_bad_parameters(params, match):
    with pytest.raises(ValueError, match=match):
        TemplateDistances(**params).fit(_flow_loop()[None])


def _cycle_table_cycle_by_cycle(X):
    """The per-cycle loop the vectorised cycle table replaced (reference)."""
    from sktiction.cycles import analyze_cycles
    from sktiction.features.area_ratio import half_cycle_ratios

    td = TemplateDistances().fit(X)
    rows = []
    for i in range(len(X)):
        found = td._cycles(X, i, X.shape[1])
        if found is None:
            continue
        ana, bounds, _ = found["op"]
        err = analyze_cycles(X[i, :, 2] - X[i, :, 0])
        ratios, halves = half_cycle_ratios(err)
        mids = (err.crossings[halves] + err.crossings[halves + 1]) / 2
        for c, (a, _m, b) in enumerate(bounds):
            seg = ana.centred[int(np.floor(a)) : int(np.ceil(b)) + 1]
            r = ratios[(mids >= a) & (mids < b)]
            row = {"loop": i, "cycle": c, "amplitude_pos": seg.max(), "amplitude_neg": -seg.min(),
                   "area_ratio": np.nanmean(r) if np.isfinite(r).any() else np.nan}
            for s in ("op", "pv"):
                sana, sb, d = found[s]
                x = sana.centred[int(np.floor(sb[c, 0])) : int(np.ceil(sb[c, 2])) + 1]
                row[f"{s}_shape"] = SHAPES[int(np.argmin(d[c]))]
                row[f"{s}_peak_to_peak"] = np.ptp(x)
            rows.append(row)
    return pd.DataFrame(rows)


def test_cycle_table_equals_the_cycle_by_cycle_reference():
    from sktiction.datasets import make_loops

    X, _ = make_loops(10, n_samples=3000, stiction_fraction=0.7, random_state=9)
    table = cycle_table(X)
    ref = _cycle_table_cycle_by_cycle(X)
    assert len(table) == len(ref) > 50
    pd.testing.assert_frame_equal(table[ref.columns], ref, check_dtype=False, rtol=1e-12)
