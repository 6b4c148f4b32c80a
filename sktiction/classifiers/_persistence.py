"""A user cache for trained models: build once, load in a new process, never trust blindly.

Each entry is two files in the cache folder: ``<name>.joblib`` (the pickled model) and
``<name>.json`` (the key it was built for and the SHA-256 of the model file). An entry
is used only when its key equals the one asked for (package version, training
arguments, a hash of the training code's source, the numpy / scikit-learn / Python
versions that pickles depend on) and the model file's checksum matches; anything else
(missing, truncated, corrupt, stale, unreadable) is rebuilt and overwritten. Files are
written to a temporary name and renamed, so a reader never sees half a file.

Why joblib and not skops: the cache holds only what this package trained on this
machine, so skops' protection against loading untrusted pickles buys nothing here,
while it would add a dependency and a list of trusted types to maintain for every
estimator in the pipeline. joblib ships with scikit-learn and loads the model in
well under a second. The checksum protects against corruption (a killed write, a
full disk), not against someone who can write to your cache folder: such a person
could as well edit the installed package.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import sys
import warnings
from pathlib import Path

import joblib

ENV_CACHE = "SKTICTION_CACHE"


def cache_dir():
    """Cache folder: ``$SKTICTION_CACHE``, else ``$XDG_CACHE_HOME/sktiction``,
    else ``~/.cache/sktiction``.

    Examples
    --------
    >>> from sktiction.classifiers._persistence import cache_dir
    >>> cache_dir().name in ("sktiction",) or True
    True
    """
    env = os.environ.get(ENV_CACHE)
    if env:
        return Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "sktiction"


def source_hash(root, parts):
    """SHA-256 of the source files under ``root`` named by ``parts`` (files, or folders
    whose ``*.py`` are all read), in a fixed order: any change to the training code
    changes the key.

    Examples
    --------
    >>> from pathlib import Path
    >>> import sktiction
    >>> from sktiction.classifiers._persistence import source_hash
    >>> len(source_hash(Path(sktiction.__file__).parent, ["features"]))
    64
    """
    root = Path(root)
    h = hashlib.sha256()
    for part in parts:
        p = root / part
        files = sorted(p.rglob("*.py")) if p.is_dir() else [p] if p.is_file() else []
        for f in files:
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()


def runtime_versions():
    """Versions that decide whether a pickle can be read back correctly."""
    import numpy
    import sklearn

    return {
        "python": ".".join(map(str, sys.version_info[:2])),
        "numpy": numpy.__version__,
        "sklearn": sklearn.__version__,
    }


def _paths(name, folder):
    folder = Path(folder)
    return folder / f"{name}.joblib", folder / f"{name}.json"


def _write_atomic(path, data):
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def load(name, key, folder=None):
    """The cached object for ``key``, or ``(None, why)`` when it cannot be trusted.

    Returns
    -------
    obj : object or None
    why : str
        ``"ok"``, ``"missing"``, ``"stale"`` (built for another key), ``"corrupt"``
        (checksum mismatch or unreadable).
    """
    model_path, meta_path = _paths(name, folder or cache_dir())
    if not model_path.exists() or not meta_path.exists():
        return None, "missing"
    try:
        meta = json.loads(meta_path.read_text())
    except (OSError, ValueError):
        return None, "corrupt"
    if not isinstance(meta, dict) or meta.get("key") != json.loads(json.dumps(key)):
        return None, "stale"
    try:
        data = model_path.read_bytes()
    except OSError:
        return None, "corrupt"
    if hashlib.sha256(data).hexdigest() != meta.get("sha256"):
        return None, "corrupt"
    try:
        return joblib.load(io.BytesIO(data)), "ok"
    except Exception:  # a pickle that passes the checksum but does not load: rebuild
        return None, "corrupt"


def save(name, key, obj, folder=None):
    """Write ``obj`` and its key; returns the model file's path (``None`` if not writable)."""
    folder = Path(folder or cache_dir())
    model_path, meta_path = _paths(name, folder)
    buffer = io.BytesIO()
    joblib.dump(obj, buffer, compress=3)
    data = buffer.getvalue()
    meta = {"key": key, "sha256": hashlib.sha256(data).hexdigest()}
    try:
        folder.mkdir(parents=True, exist_ok=True)
        _write_atomic(model_path, data)
        _write_atomic(meta_path, json.dumps(meta, indent=1, sort_keys=True).encode())
    except OSError as exc:
        warnings.warn(f"could not write the model cache in {folder}: {exc}", stacklevel=3)
        return None
    return model_path


def load_or_build(name, key, build, folder=None):
    """Load the entry ``name`` if it was built for ``key`` and is intact, else build it.

    Parameters
    ----------
    name : str
        File stem of the entry (one slot per name: a stale entry is overwritten).
    key : dict
        JSON-serialisable description of what was built; must match exactly.
    build : callable
        ``build()`` returns the object to cache.
    folder : path-like or None, default=None
        Cache folder; :func:`cache_dir` by default.

    Returns
    -------
    obj : object
    status : str
        ``"loaded"`` or ``"built (<why>)"`` with why ``missing``, ``stale`` or ``corrupt``.

    Examples
    --------
    >>> import tempfile
    >>> from sktiction.classifiers._persistence import load_or_build
    >>> with tempfile.TemporaryDirectory() as d:
    ...     first = load_or_build("demo", {"v": 1}, lambda: [1, 2], folder=d)
    ...     again = load_or_build("demo", {"v": 1}, lambda: [3], folder=d)
    >>> first, again
    (([1, 2], 'built (missing)'), ([1, 2], 'loaded'))
    """
    obj, why = load(name, key, folder)
    if why == "ok":
        return obj, "loaded"
    if why == "corrupt":
        warnings.warn(f"model cache entry {name!r} is corrupt; rebuilding it", stacklevel=2)
    obj = build()
    save(name, key, obj, folder)
    return obj, f"built ({why})"
