"""The model cache: where it lives, what its key hashes, which entries it trusts, and what
it does when it cannot write."""

import json
import sys
import warnings

import numpy as np
import pytest
import sklearn

from sktiction.classifiers import _persistence as persistence


def test_cache_folder_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("SKTICTION_CACHE", "~/my-cache")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert persistence.cache_dir() == persistence.Path("~/my-cache").expanduser()
    monkeypatch.delenv("SKTICTION_CACHE")
    assert persistence.cache_dir() == tmp_path / "xdg" / "sktiction"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert persistence.cache_dir() == tmp_path / "home" / ".cache" / "sktiction"


def test_source_hash_changes_with_any_source_file(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "a.py").write_text("x = 1\n")
    (pkg / "sub" / "b.py").write_text("y = 2\n")
    (pkg / "notes.txt").write_text("not code")
    (pkg / "single.py").write_text("z = 3\n")
    first = persistence.source_hash(tmp_path, ["pkg"])
    assert first == persistence.source_hash(str(tmp_path), ["pkg", "missing"])
    (pkg / "notes.txt").write_text("changed, but not code")
    assert persistence.source_hash(tmp_path, ["pkg"]) == first
    (pkg / "sub" / "b.py").write_text("y = 3\n")  # a file deep in the folder
    changed = persistence.source_hash(tmp_path, ["pkg"])
    assert changed != first
    (pkg / "sub" / "b.py").rename(pkg / "sub" / "c.py")  # same bytes, another name
    assert persistence.source_hash(tmp_path, ["pkg"]) != changed
    # a file named alone is read too; the order of the parts is part of the key
    one = persistence.source_hash(tmp_path, ["pkg/single.py"])
    assert one != persistence.source_hash(tmp_path, [])
    (pkg / "single.py").write_text("z = 4\n")
    assert persistence.source_hash(tmp_path, ["pkg/single.py"]) != one
    both = persistence.source_hash(tmp_path, ["pkg/a.py", "pkg/single.py"])
    assert both != persistence.source_hash(tmp_path, ["pkg/single.py", "pkg/a.py"])


def test_runtime_versions_are_this_interpreters():
    v = persistence.runtime_versions()
    assert v == {
        "python": f"{sys.version_info.major}.{sys.version_info.minor}",
        "numpy": np.__version__,
        "sklearn": sklearn.__version__,
    }


def test_an_entry_needs_both_files(tmp_path):
    persistence.save("m", {"v": 1}, [1, 2], folder=tmp_path)
    assert persistence.load("m", {"v": 1}, tmp_path) == ([1, 2], "ok")
    (tmp_path / "m.json").unlink()
    assert persistence.load("m", {"v": 1}, tmp_path) == (None, "missing")
    persistence.save("m", {"v": 1}, [1, 2], folder=tmp_path)
    (tmp_path / "m.joblib").unlink()
    assert persistence.load("m", {"v": 1}, tmp_path) == (None, "missing")


def test_unreadable_files_are_corrupt(tmp_path):
    persistence.save("m", {"v": 1}, [1, 2], folder=tmp_path)
    (tmp_path / "m.joblib").unlink()
    (tmp_path / "m.joblib").mkdir()  # exists, cannot be read as a file
    assert persistence.load("m", {"v": 1}, tmp_path) == (None, "corrupt")
    other = tmp_path / "other"
    persistence.save("m", {"v": 1}, [1, 2], folder=other)
    (other / "m.json").unlink()
    (other / "m.json").mkdir()
    assert persistence.load("m", {"v": 1}, other) == (None, "corrupt")
    (other / "m.json").rmdir()
    (other / "m.json").write_text("[1, 2]")  # valid JSON, not an entry's description
    assert persistence.load("m", {"v": 1}, other) == (None, "stale")


def test_saved_entry_is_compressed_and_described(tmp_path):
    key = {"version": 1, "args": [3, 40]}
    path = persistence.save("m", key, np.zeros(100_000), folder=tmp_path / "new" / "folder")
    assert path == tmp_path / "new" / "folder" / "m.joblib"  # parent folders made
    assert path.stat().st_size < 10_000  # 800 kB of zeros, compressed
    meta = json.loads((path.parent / "m.json").read_text())
    assert meta["key"] == key
    assert meta["sha256"] == persistence.hashlib.sha256(path.read_bytes()).hexdigest()
    assert sorted(p.name for p in path.parent.iterdir()) == ["m.joblib", "m.json"]  # no temp


def test_a_cache_that_cannot_be_written_warns_at_the_caller_and_still_builds(tmp_path):
    blocked = tmp_path / "a-file"
    blocked.write_text("a file where the cache folder should be")
    with pytest.warns(UserWarning, match="could not write the model cache") as record:
        obj, status = persistence.load_or_build("m", {"v": 1}, lambda: [7], folder=blocked / "c")
    assert (obj, status) == ([7], "built (missing)")
    # attributed to the code that asked for the model, not to the cache's own lines
    # (not compared with this file's name: mutmut's trampoline adds a frame)
    assert record[0].filename != persistence.__file__


def test_the_corrupt_entry_warning_points_at_the_caller(tmp_path):
    persistence.save("m", {"v": 1}, [1], folder=tmp_path)
    (tmp_path / "m.joblib").write_bytes(b"garbage")
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        assert persistence.load_or_build("m", {"v": 1}, lambda: [2], folder=tmp_path) == (
            [2],
            "built (corrupt)",
        )
    assert len(record) == 1 and record[0].filename != persistence.__file__
    assert "'m' is corrupt" in str(record[0].message)
