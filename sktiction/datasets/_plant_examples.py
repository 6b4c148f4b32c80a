"""Real plant windows shipped with the package, so a new user sees real data first.

Six historian windows of six valves of a chemical plant (Xue, Shang, Huang & Huang,
Control Engineering Practice 2025, doi:10.1016/j.conengprac.2025.106588; Apache-2.0, the
licence and a README with the citation sit beside the files in ``data/plant``).
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pandas as pd
from sklearn.utils import Bunch

PLANT_FOLDER = "plant"
_LOOP_TYPES = {"FIC": "flow", "LIC": "level", "PIC": "pressure", "PDIC": "pressure"}


def load_plant_examples():
    """Load the real plant windows shipped with sktiction, with their engineers' labels.

    Six two-hour windows (751 samples every 10 s) of six valves, as the plant
    historian exported them: two labelled stiction (two valves), four labelled no
    stiction (flow, level and pressure loops). They are examples for the demo and
    the HTML report, not a benchmark.

    Returns
    -------
    data : sklearn.utils.Bunch
        ``X`` float array (6, 751, 3), channels PV, OP, SP; ``y`` int (1 = the
        engineers labelled the window stiction); ``meta`` a DataFrame with one row
        per window: ``file``, ``tag``, ``label``, ``loop_type``, ``ts`` (s),
        ``status`` and ``reason`` (from the reader); ``citation`` (str) and
        ``license`` (str, the licence's name).

    Examples
    --------
    >>> from sktiction.datasets import load_plant_examples
    >>> data = load_plant_examples()
    >>> data.X.shape, int(data.y.sum())
    ((6, 751, 3), 2)
    >>> sorted(set(data.meta["loop_type"]))
    ['flow', 'level', 'pressure']
    """
    from . import read_loops

    folder = resources.files("sktiction.datasets") / "data" / PLANT_FOLDER
    with resources.as_file(folder) as path:
        index = pd.read_csv(path / "index.csv")
        data = read_loops([path / f for f in index["file"]], on_error="raise")
    read = data.meta.set_index("file").reindex(index["file"])
    meta = pd.DataFrame(
        {
            "file": index["file"].to_numpy(),
            "tag": index["tag"].to_numpy(),
            "label": index["label"].to_numpy(),
            "loop_type": index["loop_type"].map(_LOOP_TYPES).fillna("unknown").to_numpy(),
            "ts": index["Ts_s"].to_numpy(dtype=float),
            "status": read["status"].to_numpy(),
            "reason": read["reason"].fillna("").to_numpy(),
        }
    )
    order = [list(data.meta["file"]).index(f) for f in index["file"]]
    return Bunch(
        X=np.asarray(data.X[order], dtype=float),
        y=(index["label"] == "stiction").to_numpy(dtype=int),
        meta=meta,
        citation="Xue, Shang, Huang & Huang, StictionGPT, Control Engineering Practice "
        "(2025), doi:10.1016/j.conengprac.2025.106588",
        license="Apache-2.0",
    )
