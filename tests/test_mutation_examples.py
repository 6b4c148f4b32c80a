"""The shipped real plant windows: each row is its own file, with the labels and tags of the
folder's index (written for the mutation run of ``datasets/_plant_examples.py``)."""

from importlib import resources

import numpy as np
import pandas as pd
import pytest

from sktiction.datasets import load_plant_examples, read_loops


@pytest.fixture(scope="module")
def plant():
    folder = resources.files("sktiction.datasets") / "data" / "plant"
    with resources.as_file(folder) as path:
        index = pd.read_csv(path / "index.csv")
        files = [path / f for f in index["file"]]
        licence = (path / "LICENSE").read_text()
        one_by_one = [read_loops([f], on_error="raise").X[0] for f in files]
    return load_plant_examples(), index, one_by_one, licence


def test_each_row_is_the_file_the_index_names(plant):
    data, index, one_by_one, _ = plant
    assert data.X.shape == (len(index), 751, 3) and data.X.dtype == np.float64
    assert data.meta["file"].tolist() == index["file"].tolist()
    for x, alone in zip(data.X, one_by_one, strict=True):
        np.testing.assert_array_equal(x, alone[:751])
    # the tag is part of each file name
    assert all(t in f for t, f in zip(data.meta["tag"], data.meta["file"], strict=True))


def test_labels_loop_types_and_provenance(plant):
    data, index, _, licence = plant
    assert data.y.tolist() == (index["label"] == "stiction").astype(int).tolist()
    assert data.meta["label"].tolist() == index["label"].tolist()
    assert data.y.sum() == 2 and data.y.dtype.kind == "i"
    # ISA letters of the tag: F(low), L(evel), P(ressure)D(ifference) controllers
    letters = data.meta["tag"].str.extract(r"\d([A-Z]+)IC")[0]
    expected = letters.map({"F": "flow", "L": "level", "PD": "pressure", "P": "pressure"})
    assert data.meta["loop_type"].tolist() == expected.tolist()
    assert (data.meta["ts"] == 10.0).all() and data.meta["ts"].dtype == float
    assert (data.meta["status"] == "ok").all() and (data.meta["reason"] == "").all()
    assert "10.1016/j.conengprac.2025.106588" in data.citation
    assert data.license == "Apache-2.0" and "Apache License" in licence
    assert "Version 2.0" in licence
