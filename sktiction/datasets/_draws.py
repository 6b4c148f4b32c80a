"""Random draws that both simulated worlds make: log-uniform values, signs, weighted picks."""

from __future__ import annotations

import functools

import numpy as np


def _loguniform(rng, lo, hi):
    return float(np.exp(rng.uniform(_log(lo), _log(hi))))


@functools.lru_cache(maxsize=1024)
def _log(x):
    return np.log(x)


_SIGNS = np.array([-1.0, 1.0])


def _signs(rng, size=None):
    """``rng.choice([-1.0, 1.0], size)``: the same draws and values, without its overhead."""
    return _SIGNS[rng.integers(0, 2, size=size)]


def _pick(rng, options, p=None):
    """One of ``options``; ``p`` are weights (renormalised)."""
    if p is None:
        return options[rng.integers(len(options))]
    return options[int(np.searchsorted(_cumulative(tuple(p)), rng.random(), side="right"))]


@functools.lru_cache(maxsize=256)
def _cumulative(p):
    """Cumulative renormalised weights ``p`` (a tuple: loops share a few weightings)."""
    p = np.asarray(p, dtype=float)
    c = np.cumsum(p / p.sum())
    c.flags.writeable = False
    return c
