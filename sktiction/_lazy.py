"""Public names of a package that are imported on first use (PEP 562).

``import sktiction`` then costs almost nothing, and loading the cached learned model in
a new process imports only what that model needs, not the plots, reports, realism
tools or the other classifiers (the heavy libraries behind them: matplotlib, dask,
tslearn, most of pandas' I/O).
"""

from __future__ import annotations

import importlib


def attach(package, submodules):
    """``__getattr__``, ``__dir__`` and ``__all__`` for ``package``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    submodules : dict of str to list of str
        Relative module name (``".learned"``) to the public names it defines.

    Returns
    -------
    getattr, dir : callable
        The package's module-level ``__getattr__`` and ``__dir__``.
    names : list of str
        Its ``__all__``.

    Examples
    --------
    >>> import sys
    >>> from sktiction._lazy import attach
    >>> getattr_, dir_, names = attach("sktiction.cycles", {"._signal": ["noise_std"]})
    >>> getattr_("noise_std").__name__, names
    ('noise_std', ['noise_std'])
    """
    where = {name: module for module, names in submodules.items() for name in names}

    def __getattr__(name):
        if name not in where:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(where[name], package), name)
        setattr(importlib.import_module(package), name, value)  # found directly next time
        return value

    def __dir__():
        return sorted(set(vars(importlib.import_module(package))) | set(where))

    return __getattr__, __dir__, list(where)
