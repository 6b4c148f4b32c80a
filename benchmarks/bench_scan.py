"""Plant-scale scan: a simulated site on disk, scanned as a stream and by the CLI.

Prints, for a site of N loops (10 s sampling, most loops one day = 8,640 samples, the
others 6 or 12 hours), over ``--runs`` runs (min / median / max, the machine is shared):

- loops/s and ms per loop of ``scan_files`` (streaming) and of ``sktiction scan`` (the
  command line), each in a fresh process, with the peak RSS of its process tree;
- the time ``pretrained_classifier()`` takes here (the scanning processes load the
  model from a file, so the scan is timed and not the model cache);
- peak RSS of scanning 4x as many files against scanning N/4 (goal <= 1.1x);
- the log-log slope of cost against record length (1k to 80k samples) for every
  feature, the applicability check, the learned model and the whole scan (goal <= 1.1);
- the share of a chunk's time per stage (read, cycle analyses, area-ratio rule, shape
  library, learned model, applicability check, the rest);
- the one-pass scan against the three classifiers run one by one (same report).

Goal (issue 10): 5,000 loops in < 2 min on 2 cores (<= 24 ms wall per loop).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_scan.py --n-loops 500 --n-jobs 2
(``--skip-stream``, ``--skip-cli``, ``--skip-slope``, ``--skip-memory``, ``--skip-stages``,
``--skip-share`` leave parts out).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import psutil

TS = 10.0
DAY = 8640
LENGTHS = (DAY // 4, DAY // 2, DAY)
LENGTH_P = (0.2, 0.2, 0.6)
TAGS = ("FIC", "LIC", "PIC", "TIC")


def write_site(folder, n_loops, *, lengths=LENGTHS, p=LENGTH_P, seed=0, batch=250):
    """``n_loops`` CSV files (time, PV, OP, SP) of simulated loops; kept between runs."""
    from sktiction.datasets import make_loops

    folder = Path(folder)
    done = folder.with_name(folder.name + ".complete.json")  # outside: not a loop file
    if done.exists() and json.loads(done.read_text()) == [n_loops, list(lengths), seed]:
        return folder
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    k = 0
    for start in range(0, n_loops, batch):
        m = min(batch, n_loops - start)
        X, _ = make_loops(m, n_samples=max(lengths), random_state=seed + start)
        for i in range(m):
            n = int(rng.choice(lengths, p=p))
            n = min(n, int(np.sum(~np.isnan(X[i, :, 0]))))
            data = np.column_stack([np.arange(n) * TS, X[i, :n]])
            name = folder / f"{TAGS[k % len(TAGS)]}{k:05d}.csv"
            np.savetxt(name, data, delimiter=",", fmt="%.6g", header="time,PV,OP,SP", comments="")
            k += 1
    done.write_text(json.dumps([n_loops, list(lengths), seed]))
    return folder


def run_measured(cmd, env=None, cpu=None):
    """Run ``cmd``; return (wall s, peak RSS of its process tree in MiB, stdout).

    ``cpu``, a list, receives the CPU time (user + system, s) of the process tree as last
    polled: unlike the wall time it hardly depends on what else the machine runs.
    """
    t0 = time.perf_counter()
    proc = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env, text=True
    )
    parent = psutil.Process(proc.pid)
    peak = 0
    used = {}
    while proc.poll() is None:
        try:
            procs = [parent, *parent.children(recursive=True)]
            peak = max(peak, sum(p.memory_info().rss for p in procs if p.is_running()))
            for p in procs:
                times = p.cpu_times()
                used[p.pid] = times.user + times.system
        except psutil.Error:
            pass
        time.sleep(0.05)
    out = proc.stdout.read()
    if proc.returncode not in (0, 1):  # the CLI exits 1 when some files fail
        raise RuntimeError(f"{cmd} failed with {proc.returncode}")
    if cpu is not None:
        cpu.append(sum(used.values()))
    return time.perf_counter() - t0, peak / 2**20, out


STREAM = """
import sys, time, json
t0 = time.perf_counter()
import joblib
from sktiction.reports import scan_files
clf = joblib.load({model!r})
t1 = time.perf_counter()
report = scan_files(sys.argv[1:], classifier=clf, n_jobs={n_jobs}, chunk_size={chunk})
t2 = time.perf_counter()
print(json.dumps({{"load": t1 - t0, "scan": t2 - t1, "rows": len(report),
                  "ok": int((report["status"] == "ok").sum())}}))
"""


def stats(values):
    v = np.asarray(values, dtype=float)
    return f"{v.min():.3g} / {np.median(v):.3g} / {v.max():.3g}"


def bench_stream(paths, n_jobs, chunk, runs, model, cpus=None):
    code = STREAM.format(n_jobs=n_jobs, chunk=chunk, model=str(model))
    walls, rss, scans, loads, rows = [], [], [], [], None
    cpu = [] if cpus is None else cpus
    for _ in range(runs):
        wall, peak, out = run_measured([sys.executable, "-c", code, *map(str, paths)], cpu=cpu)
        info = json.loads(out.strip().splitlines()[-1])
        walls.append(wall)
        rss.append(peak)
        scans.append(info["scan"])
        loads.append(info["load"])
        rows = info
    return walls, rss, scans, loads, rows


def slope_table(runs, clf):
    """Log-log slope of per-loop cost against record length, per stage."""
    from sktiction import AreaRatio, LoopDescriptors, StictionModelFit, TemplateDistances
    from sktiction.datasets import make_loops
    from sktiction.reports import scan_loops
    from sktiction.reports.scan import _applicability_gate

    gate = _applicability_gate()
    lengths = (1000, 5000, 20000, 80000)
    n_per = {1000: 16, 5000: 8, 20000: 4, 80000: 2}
    stages = {
        "AreaRatio": lambda X: AreaRatio().fit(X).transform(X),
        "TemplateDistances": lambda X: TemplateDistances().fit(X).transform(X),
        "LoopDescriptors": lambda X: LoopDescriptors().fit(X).transform(X),
        "StictionModelFit": lambda X: StictionModelFit().fit(X).transform(X),
        "learned model": lambda X: clf.predict_proba(X),
        "scan_loops": lambda X: scan_loops(X, classifier=clf),
    }
    if gate is not None:
        stages["applicability"] = lambda X: gate(X)
    # one seed for all lengths: the same loops (plants, valves, periods), only longer
    data = {
        n: make_loops(n_per[n], n_samples=n, stiction_fraction=0.6, random_state=0)[0]
        for n in lengths
    }
    for X in data.values():
        for fn in stages.values():
            fn(X[:1])  # compile
    print(f"\ncost against record length {lengths} (ms per loop, median of {runs}):")
    print(
        f"{'stage':<20}"
        + "".join(f"{n:>10}" for n in lengths)
        + "   slope (all)  slope (last two)"
    )
    for name, fn in stages.items():
        per = []
        for n in lengths:
            X = data[n]
            times = []
            for _ in range(runs):
                t0 = time.perf_counter()
                fn(X)
                times.append((time.perf_counter() - t0) / len(X))
            per.append(np.median(times))
        slope = np.polyfit(np.log(lengths), np.log(per), 1)[0]
        last = np.log(per[-1] / per[-2]) / np.log(lengths[-1] / lengths[-2])
        print(
            f"{name:<20}"
            + "".join(f"{1e3 * t:>10.2f}" for t in per)
            + f"   {slope:11.2f}  {last:16.2f}"
        )


def stage_shares(folder, classifier, n_files=64):
    """Share of one chunk's time per stage, as the scan runs them."""
    from sktiction._validation import check_loops, loop_status
    from sktiction.datasets import read_loop_file
    from sktiction.features._loops import analyse_loops
    from sktiction.reports.scan import LearnedAdapter, _applicability_gate, _Rules, _scan_chunk

    clf = LearnedAdapter(classifier)
    gate = _applicability_gate()
    files = sorted(Path(folder).glob("*.csv"))[:n_files]
    t = {}
    t0 = time.perf_counter()
    datas = [read_loop_file(f) for f in files]
    t["read files"] = time.perf_counter() - t0
    n = max(d.X.shape[1] for d in datas)
    X = np.full((len(datas), n, 3), np.nan)
    for i, d in enumerate(datas):
        X[i, : d.X.shape[1]] = d.X[0]
    loops = check_loops(X)
    rules = _Rules(loops[:1])
    _scan_chunk(loops[:2], np.array(["auto"] * 2, dtype=object), clf, rules)  # compile
    t0 = time.perf_counter()
    _scan_chunk(loops, np.array(["auto"] * len(loops), dtype=object), clf, rules, None, gate)
    total = time.perf_counter() - t0
    analyses = analyse_loops(loops)
    status = loop_status(loops, require_op=True, check_swap=True)
    t0 = time.perf_counter()
    for a in analyses:
        a.cycles("error"), a.cycles("op"), a.cycles("pv")
    t["cycle analyses"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rules.area_ratio.diagnose_analysed(loops, analyses)
    t["area-ratio rule"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rules.shape["auto"].diagnose_analysed(loops, analyses, status)
    t["shape library (DTW)"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    clf.predict(loops, analyses, status)
    t["learned model"] = time.perf_counter() - t0
    if gate is not None:
        t0 = time.perf_counter()
        gate(loops)
        t["applicability check"] = time.perf_counter() - t0
    stages = sum(v for k, v in t.items() if k != "read files")
    t["rest (status, report)"] = max(0.0, total - stages)
    whole = total + t["read files"]
    print(
        f"\nshare of time per stage ({len(files)} files, {1e3 * whole / len(files):.1f} ms per "
        "loop on one core):"
    )
    for k, v in t.items():
        print(f"  {k:<24} {100 * v / whole:5.1f} %   {1e3 * v / len(files):7.2f} ms/loop")


def shared_pass(runs, n_loops=24):
    """The one-pass scan against the three classifiers run one by one (the scan before
    the shared analysis, kept as the reference in tests/test_scan.py), same report."""
    import pandas as pd
    from sklearn.ensemble import HistGradientBoostingClassifier
    from sklearn.pipeline import FeatureUnion, Pipeline

    from sktiction import AreaRatio, LoopDescriptors, StictionModelFit, TemplateDistances
    from sktiction.datasets import make_loops
    from sktiction.reports import scan as scan_module

    sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
    from test_scan import reference_scan

    # a learned pipeline of the package's transformers, so that all three classifiers
    # can share the analysis (a model that computes its own features cannot)
    Xt, yt = make_loops(150, n_samples=1000, slip_fraction=0.25, random_state=0)
    union = FeatureUnion(
        [
            ("area", AreaRatio()),
            ("templates", TemplateDistances()),
            ("descriptors", LoopDescriptors()),
            ("valve_model", StictionModelFit()),
        ]
    )
    model = HistGradientBoostingClassifier(max_iter=100, random_state=0)
    clf = Pipeline([("features", union), ("model", model)]).fit(Xt, yt)
    X, _ = make_loops(n_loops, n_samples=DAY, random_state=1)
    types = np.array(["auto"] * n_loops, dtype=object)
    gate = scan_module._applicability_gate
    scan_module._applicability_gate = lambda: None  # like for like: the reference has none
    try:
        scan_module.scan_loops(X[:2], classifier=clf)
        old, new = [], []
        for _ in range(runs):
            t0 = time.perf_counter()
            expected = reference_scan(X, types, clf)
            old.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            got = scan_module.scan_loops(X, classifier=clf)
            new.append(time.perf_counter() - t0)
    finally:
        scan_module._applicability_gate = gate
    pd.testing.assert_frame_equal(got, expected, check_dtype=False)
    old, new = np.array(old), np.array(new)
    print(
        f"\none pass vs the classifiers one by one ({n_loops} loops of {DAY} samples, "
        "same report, one core):"
    )
    print(
        f"  one by one {stats(1e3 * old / n_loops)} ms per loop, one pass "
        f"{stats(1e3 * new / n_loops)} ms per loop; ratio {stats(old / new)}"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-loops", type=int, default=500)
    parser.add_argument("--n-jobs", type=int, default=2)
    parser.add_argument("--chunk-size", type=int, default=64)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument(
        "--workdir", default=os.path.join(tempfile.gettempdir(), "sktiction_bench_scan")
    )
    parser.add_argument(
        "--model", help="a fitted classifier saved with joblib (default: pretrained_classifier())"
    )
    for part in ("stream", "cli", "slope", "memory", "stages", "share"):
        parser.add_argument(f"--skip-{part}", action="store_true")
    args = parser.parse_args()
    work = Path(args.workdir)
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at start")
    t0 = time.perf_counter()
    site = write_site(work / f"site_{args.n_loops}", args.n_loops)
    print(
        f"site: {args.n_loops} CSV files, 10 s sampling, 60 % one day ({DAY} samples), "
        f"20 % 12 h, 20 % 6 h; written or found in {time.perf_counter() - t0:.0f} s"
    )

    # the model is trained (or found in the user cache) once here, and the scanning
    # processes load it from a file: the scan is timed, not the model cache
    import joblib

    from sktiction import pretrained_classifier

    t0 = time.perf_counter()
    if args.model:
        clf = joblib.load(args.model)
    else:
        clf = pretrained_classifier()
        print(f"pretrained_classifier() here: {time.perf_counter() - t0:.1f} s")
    model = work / "model.joblib"
    joblib.dump(clf, model)
    n = args.n_loops
    if not args.skip_stream:
        cpus = []
        walls, rss, scans, loads, info = bench_stream(
            [site], args.n_jobs, args.chunk_size, args.runs, model, cpus
        )
        n = info["rows"]
        print(f"\nscan_files, n_jobs={args.n_jobs}, {args.runs} runs (min / median / max):")
        print(f"  rows {n} ({info['ok']} status ok)")
        print(f"  imports + model file load      {stats(loads)} s")
        print(f"  scan wall                      {stats(scans)} s")
        print(f"  ms per loop (wall)             {stats(1e3 * np.array(scans) / n)}   goal <= 24")
        print(f"  loops/s                        {stats(n / np.array(scans))}")
        print(
            f"  5,000 loops would take         {stats(5000 * np.array(scans) / n / 60)} min"
            "   goal < 2"
        )
        print(f"  whole process wall             {stats(walls)} s")
        cpu = np.array(cpus)
        print(
            f"  CPU time of the process tree   {stats(cpu)} s: {stats(1e3 * cpu / n)} ms per "
            f"loop, i.e. {stats(1e3 * cpu / n / args.n_jobs)} ms wall per loop on "
            f"{args.n_jobs} idle cores (start-up included)"
        )
        print(f"  peak RSS of the process tree   {stats(rss)} MiB")

    if not args.skip_cli:
        cli_walls, cli_rss = [], []
        for _ in range(args.runs):
            out = work / "cli_report.csv"
            wall, peak, _ = run_measured(
                [
                    sys.executable,
                    "-m",
                    "sktiction",
                    "scan",
                    str(site),
                    "-o",
                    str(out),
                    "-q",
                    "-j",
                    str(args.n_jobs),
                ]
            )
            cli_walls.append(wall)
            cli_rss.append(peak)
        print(
            f"\nsktiction scan (CLI), -j {args.n_jobs}: wall {stats(cli_walls)} s "
            f"({stats(1e3 * np.array(cli_walls) / n)} ms per loop including model load), "
            f"peak RSS {stats(cli_rss)} MiB"
        )

    if not args.skip_memory:
        small = write_site(work / "mem_500", 500, lengths=(2000,), p=(1.0,), seed=1)
        more = write_site(work / "mem_1500", 1500, lengths=(2000,), p=(1.0,), seed=2)
        _, rss_small, _, _, _ = bench_stream(
            [small], args.n_jobs, args.chunk_size, args.runs, model
        )
        _, rss_big, _, _, _ = bench_stream(
            [small, more], args.n_jobs, args.chunk_size, args.runs, model
        )
        ratio = np.array(rss_big) / np.median(rss_small)
        print(
            f"\nmemory: peak RSS 500 files {stats(rss_small)} MiB, 2,000 files "
            f"{stats(rss_big)} MiB; ratio {stats(ratio)} (goal <= 1.1)"
        )

    if not args.skip_stages:
        stage_shares(site, clf)
    if not args.skip_share:
        shared_pass(args.runs)
    if not args.skip_slope:
        slope_table(args.runs, clf)
    print(
        f"\nload average at the end: {' / '.join(f'{v:.1f}' for v in os.getloadavg())} "
        "(1 / 5 / 15 min)"
    )


if __name__ == "__main__":
    main()
