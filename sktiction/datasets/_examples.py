"""The example loop set that ships with the package, and how to regenerate it."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.utils import Bunch

EXAMPLE_FILE = "example_loops.npz"
# world="classic" pins the simulated world the file was made in, whatever make_loops'
# default world becomes.
_EXAMPLE_ARGS = {"n_loops": 24, "n_samples": 2000, "random_state": 2024, "world": "classic"}


def load_example():
    """Load the shipped example: 24 simulated loops whose causes are known.

    Returns
    -------
    data : sklearn.utils.Bunch
        ``X`` float array (24, 2000, 3) with channels PV, OP, SP; ``y`` int (1 =
        stiction); ``meta`` a DataFrame with one row per loop (cause, plant, valve,
        controller, Ts, effects), as returned by ``make_loops(..., return_meta=True)``.

    Notes
    -----
    The file holds ``make_loops(24, 2000, world="classic", random_state=2024)`` in
    float32. Regenerating it on another machine gives the same loops up to float
    rounding, except that a loop with a sticky valve may drift out of phase: the
    last bit of ``numpy.exp``/``numpy.log`` depends on the CPU (numpy picks SIMD
    code at run time), and a stick-slip valve turns a one-ulp difference into a
    slip one sample earlier or later. Such a loop keeps its amplitude and period.

    Examples
    --------
    >>> from sktiction.datasets import load_example
    >>> data = load_example()
    >>> data.X.shape
    (24, 2000, 3)
    """
    path = resources.files("sktiction.datasets") / "data" / EXAMPLE_FILE
    with resources.as_file(path) as p, np.load(p, allow_pickle=False) as f:
        meta = pd.DataFrame({k[5:]: f[k] for k in f.files if k.startswith("meta_")})
        return Bunch(X=f["X"], y=f["y"], meta=meta)


def regenerate_example(path=None):
    """Write the example file again from :func:`make_loops` with fixed arguments.

    Parameters
    ----------
    path : str or Path or None, default=None
        Where to write; ``None`` writes into the package's data folder.

    Returns
    -------
    path : Path
        The file written.
    """
    from ._generators import make_loops

    X, y, meta = make_loops(**_EXAMPLE_ARGS, return_meta=True)
    if path is None:
        path = Path(__file__).parent / "data" / EXAMPLE_FILE
    # Plain arrays only (no pickles): object columns are stored as strings.
    cols = {
        f"meta_{c}": meta[c].to_numpy()
        if pd.api.types.is_numeric_dtype(meta[c])
        else meta[c].astype(str).to_numpy(dtype=str)
        for c in meta.columns
    }
    np.savez_compressed(path, X=X.astype(np.float32), y=y, **cols)
    return Path(path)


if __name__ == "__main__":
    print(regenerate_example())
