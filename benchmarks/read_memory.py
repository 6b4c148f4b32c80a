"""Peak memory of reading one 1e6-row historian export, alone and among 300 small ones.

Run ``python benchmarks/read_memory.py [n_rows]``. Writes the files to a temporary folder,
then in fresh processes measures the peak resident set size (RSS) above the RSS right
after ``import sktiction``:

* ``read_loop_file`` on the long file;
* ``read_loop_file`` on every file of the folder in turn (what a streaming scan does);

and prints what ``read_loops`` on the folder would allocate for its padded array (it pads
every loop to the longest, so it is not run here).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

HEADER = (
    "PROCESSDATA\t{tag} Data\tyyyy-MM-dd HH:mm:ss\r\n8\t10\t2024-10-17 21:55:00\t{n}\r\n"
    "tagname\t{tag}.MV\t{tag}.PV\t{tag}.SV\t{tag}.MODE\tbOpOFL\tbPvOFL\tbSpOFL\tbAutOFL\r\n"
    "desc\tOP\tPV\tSP\tAut\tbOpOFL\tbPvOFL\tbSpOFL\tbAutOFL\r\nfsMax=1\tfsMin=0\r\n"
)

CHILD = """
import resource, sys, time
from pathlib import Path
import sktiction.datasets as ds
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
t0 = time.perf_counter()
paths = [Path(p) for p in sys.argv[1:]]
n = 0
for p in sorted(paths[0].iterdir()) if paths[0].is_dir() else paths:
    data = ds.read_loop_file(p)
    assert (data.meta["status"] == "ok").all(), data.meta["reason"].tolist()
    n += data.X.shape[1]
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(n, (peak - base) / 1024, time.perf_counter() - t0)
"""


def write_export(path, n, rng, tag="FIC1"):
    t = pd.date_range("2024-10-17 21:55:00", periods=n, freq="10s").strftime("%Y-%m-%d %H:%M:%S")
    frame = pd.DataFrame({
        "t": t, "mv": rng.normal(40, 5, n).round(6), "pv": rng.normal(50, 5, n).round(6),
        "sv": 50, "mode": 1, "a": 0, "b": 0, "c": 0, "d": 0,
    })  # fmt: skip
    with open(path, "w", newline="") as fh:
        fh.write(HEADER.format(tag=tag, n=n))
        frame.to_csv(fh, sep="\t", header=False, index=False, lineterminator="\r\n")


def measure(*paths):
    out = subprocess.run(
        [sys.executable, "-c", CHILD, *map(str, paths)], capture_output=True, text=True, check=True
    ).stdout.split()
    return int(out[0]), float(out[1]), float(out[2])


def main(n_rows=1_000_000, n_small=300, small_rows=751):
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "exports"
        folder.mkdir()
        big = folder / "FIC1_long.txt"
        write_export(big, n_rows, rng)
        for i in range(n_small):
            write_export(folder / f"FIC{i + 2}.txt", small_rows, rng, tag=f"FIC{i + 2}")
        size = big.stat().st_size / 2**20
        x_mib = n_rows * 3 * 8 / 2**20
        rows, peak, secs = measure(big)
        print(f"one file of {n_rows} rows ({size:.0f} MiB of text, X {x_mib:.0f} MiB):")
        print(f"  read_loop_file: peak RSS +{peak:.0f} MiB above the import "
              f"({peak / size:.1f} x the file, {peak / x_mib:.1f} x X), {secs:.1f} s")
        rows, peak_all, secs = measure(folder)
        print(f"that file among {n_small} files of {small_rows} rows, read one by one:")
        print(f"  read_loop_file per file: peak RSS +{peak_all:.0f} MiB "
              f"({peak_all / peak:.2f} x the long file alone), {secs:.1f} s, {rows} samples")
        padded = (n_small + 1) * n_rows * 3 * 8 / 2**30
        print(f"read_loops on the folder would pad to ({n_small + 1}, {n_rows}, 3): "
              f"{padded:.1f} GiB (not run)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
