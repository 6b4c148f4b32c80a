"""The shipped examples: each plant window is its own file, with the labels and tags of the
folder's index, and the simulated example file is rewritten as the shipped one (written for
the mutation runs of ``datasets/_plant_examples.py`` and ``datasets/_examples.py``; each test
loads what it checks itself: mutmut credits a shared fixture to its first test only)."""

from importlib import resources

import numpy as np
import pandas as pd

from sktiction.datasets import _examples, load_example, load_plant_examples, read_loops


def _index():
    folder = resources.files("sktiction.datasets") / "data" / "plant"
    with resources.as_file(folder) as path:
        index = pd.read_csv(path / "index.csv")
        return index, [path / f for f in index["file"]], (path / "LICENSE").read_text()


def test_each_row_is_the_file_the_index_names():
    data = load_plant_examples()
    index, files, _ = _index()
    assert data.X.shape == (len(index), 751, 3) and data.X.dtype == np.float64
    assert data.meta["file"].tolist() == index["file"].tolist()
    for x, f in zip(data.X, files, strict=True):
        np.testing.assert_array_equal(x, read_loops([f], on_error="raise").X[0][:751])
    # the tag is part of each file name
    assert all(t in f for t, f in zip(data.meta["tag"], data.meta["file"], strict=True))


def test_labels_loop_types_and_provenance():
    data = load_plant_examples()
    index, _, licence = _index()
    assert data.meta.columns.tolist() == ["file", "tag", "label", "loop_type", "ts", "status",
                                          "reason"]  # fmt: skip
    assert data.y.tolist() == (index["label"] == "stiction").astype(int).tolist()
    assert data.meta["label"].tolist() == index["label"].tolist()
    assert data.y.sum() == 2 and data.y.dtype.kind == "i"
    # ISA letters of the tag: F(low), L(evel), P(ressure)D(ifference) controllers
    letters = data.meta["tag"].str.extract(r"\d([A-Z]+)IC")[0]
    expected = letters.map({"F": "flow", "L": "level", "PD": "pressure", "P": "pressure"})
    assert data.meta["loop_type"].tolist() == expected.tolist()
    assert (data.meta["ts"] == 10.0).all() and data.meta["ts"].dtype == float
    assert (data.meta["status"] == "ok").all() and (data.meta["reason"] == "").all()
    assert data.citation.startswith("Xue, Shang, Huang & Huang")
    assert data.citation.endswith("doi:10.1016/j.conengprac.2025.106588")
    assert data.license == "Apache-2.0" and "Apache License" in licence
    assert "Version 2.0" in licence


def test_regenerated_example_is_stored_without_pickles_as_shipped(tmp_path, monkeypatch):
    # path=None writes into the module's data folder: here a copy's, not the installed one
    (tmp_path / "data").mkdir()
    monkeypatch.setattr(_examples, "__file__", str(tmp_path / "_examples.py"))
    path = _examples.regenerate_example()
    assert path == tmp_path / "data" / _examples.EXAMPLE_FILE
    shipped = load_example()
    with np.load(path, allow_pickle=False) as f:  # every array, meta included
        arrays = {k: f[k] for k in f.files}
    assert {k[5:] for k in arrays if k.startswith("meta_")} == set(shipped.meta.columns)
    for c in shipped.meta.columns:
        got, want = arrays[f"meta_{c}"], shipped.meta[c].to_numpy()
        text = {got.dtype.kind, want.dtype.kind} <= set("OU")  # str arrays, read as objects
        assert got.dtype.kind == want.dtype.kind or text, c  # numbers stay numbers
        if got.dtype.kind in "fiub":
            np.testing.assert_allclose(got, want, rtol=1e-9, equal_nan=True)
