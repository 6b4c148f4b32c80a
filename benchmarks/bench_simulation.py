"""Throughput of the simulator, in loop-samples per second on one core.

Goals: the compiled closed loop >= 1e7 loop-samples/s/core (GitHub issue 2), and
``make_loops(2000, n_samples=5000)`` end to end >= 1e7 loop-samples/s/core with
default thread settings (issue 10), i.e. about 1 s of CPU for 2000 x 5000.

Figures, for ``n_loops`` loops of ``n_samples`` samples:

* the compiled kernel alone (output buffers reused) on loops mixing plant orders
  1-4 and integrating plants with healthy, relay, Choudhury and Kano valves,
  each started by a setpoint step; then ``simulate_loops`` end to end (fresh
  output arrays, discretisation, effects) and everything including building the
  plant and controller objects, in chunks to bound memory;
* the first touch of a fresh output array as large as ``make_loops``' (memory the
  process has not used yet: every call returns such an array);
* ``make_loops`` end to end for the default and the classic world, 3 runs each
  (seeds 0-2): min / median / max of the rate in CPU time of this process
  (``time.process_time``; the machine may be shared, which wall time shows) and
  in wall time, and the median CPU rate over the kernel's. The default world
  simulates a warm-up (``max(300, n_samples // 5)`` samples) before each record
  and, for loops with SNR-specified noise in the loop, a noise-free pilot run
  first, so its loops cost more kernel samples than they return;
* the ceiling of ``make_loops`` with the same outputs: the CPU time spent inside
  the compiled kernel during those runs, with the kernel samples it ran per sample
  returned. The rate ``make_loops`` would reach if everything but the kernel cost
  nothing is the number of samples returned over that time.

Fresh memory is slow to fault in on some sandboxes (virtual machines that hand
freed memory back to the host), which is what separates the first two figures.

Run: ``python benchmarks/bench_simulation.py [n_loops n_samples]`` (default 2000 5000)
"""

from __future__ import annotations

import sys
import time

import numpy as np

from sktiction.datasets import make_loops
from sktiction.simulation import (
    ChoudhuryValve,
    IntegratingPlant,
    KanoValve,
    LinearValve,
    NthOrderLag,
    PIController,
    RelayValve,
    SetpointSteps,
    simulate_loops,
)

GOAL = 1e7
RUNS = 3


def build(n_loops, rng):
    plants, ctrls, valves = [], [], []
    for _ in range(n_loops):
        order = int(rng.integers(1, 6))
        if order == 5:
            plant = IntegratingPlant(0.05, delay=5.0, time_constant=10.0)
        else:
            plant = NthOrderLag(1.0, 10.0, float(rng.uniform(1, 10)), order=order)
        plants.append(plant)
        ctrls.append(PIController.from_plant(plant, "amigo", ts=1.0))
        valves.append(
            [LinearValve(), RelayValve(2.0), ChoudhuryValve(3.0, 1.0), KanoValve(3.0, 1.0)][
                int(rng.integers(4))
            ]
        )
    return plants, ctrls, valves


def main(n_loops=2000, n_samples=5000, chunk=250):
    rng = np.random.default_rng(0)
    warm = build(4, rng)
    simulate_loops(*warm, 100, 1.0, effects=[SetpointSteps([5.0], [1.0])])  # compile / load cache
    samples = n_loops * n_samples
    print(f"{n_loops} loops x {n_samples} samples = {samples:.3g} loop-samples")
    kernel_wall, kernel_cpu = kernel_time(n_loops, n_samples, chunk, rng)
    report("compiled kernel", kernel_wall, kernel_cpu, samples)
    start = time.perf_counter(), time.process_time()
    sim = [0.0, 0.0]
    for lo in range(0, n_loops, chunk):
        n = min(chunk, n_loops - lo)
        loops = build(n, rng)
        t0 = time.perf_counter(), time.process_time()
        simulate_loops(*loops, n_samples, 1.0, effects=[SetpointSteps([5.0], [1.0])])
        sim[0] += time.perf_counter() - t0[0]
        sim[1] += time.process_time() - t0[1]
    total = time.perf_counter() - start[0], time.process_time() - start[1]
    report("simulate_loops", *sim, samples)
    report("incl. building objects", *total, samples)
    kernel_rate = samples / kernel_cpu
    # every make_loops call returns a fresh (n_loops, n_samples, 3) array: its first touch
    t0 = time.perf_counter(), time.process_time()
    np.empty((n_loops, n_samples, 3)).fill(0.0)
    report("touching a fresh output", time.perf_counter() - t0[0], time.process_time() - t0[1],
           samples)  # fmt: skip
    for world in ("default", "classic"):
        make_loops(4, 200, world=world, random_state=0)  # compile / load cache
        wall, cpu, inside = [], [], []
        for seed in range(RUNS):
            with KernelClock() as clock:
                t0 = time.perf_counter(), time.process_time()
                make_loops(n_loops, n_samples, world=world, random_state=seed)
                wall.append(time.perf_counter() - t0[0])
                cpu.append(time.process_time() - t0[1])
            inside.append((clock.cpu, clock.samples / samples))
        report_runs(f"make_loops {world}", wall, cpu, samples, kernel_rate)
        report_ceiling(world, inside, cpu, samples)


def report(label, wall, cpu, samples):
    rate = samples / cpu
    print(
        f"{label:>24}: {cpu:6.2f} s CPU -> {rate:.3g} loop-samples/s/core "
        f"({rate / GOAL:.2f} x the 1e7 goal); wall {wall:.2f} s -> {samples / wall:.3g}/s"
    )


def report_runs(label, wall, cpu, samples, kernel_rate):
    """Min / median / max rate of ``RUNS`` runs, CPU and wall, and the CPU median's share
    of the kernel's rate."""

    def rates(seconds):
        r = np.sort(samples / np.asarray(seconds))
        return r[0], np.median(r), r[-1]

    lo, med, hi = rates(cpu)
    wlo, wmed, whi = rates(wall)
    print(
        f"{label:>24}: CPU {lo:.3g} / {med:.3g} / {hi:.3g} loop-samples/s/core "
        f"(min / median / max of {len(cpu)}; median {med / GOAL:.2f} x the 1e7 goal, "
        f"{med / kernel_rate:.2f} x the kernel alone); "
        f"wall {wlo:.3g} / {wmed:.3g} / {whi:.3g}/s"
    )


class KernelClock:
    """Counts the CPU time and the samples of every kernel call ``make_loops`` makes.

    ``make_loops`` reaches the kernel through ``sktiction.simulation.loop._run_loops``;
    the clock stands in for that name while it is open.
    """

    def __enter__(self):
        from sktiction.simulation import loop

        self._loop, self._run = loop, loop._run_loops
        self.cpu, self.samples = 0.0, 0

        def timed(*args):
            rows, start, X = args[-4], args[-3], args[-2]
            c0 = time.process_time()
            self._run(*args)
            self.cpu += time.process_time() - c0
            self.samples += len(rows) * (start + X.shape[1])

        loop._run_loops = timed
        return self

    def __exit__(self, *exc):
        self._loop._run_loops = self._run


def report_ceiling(world, inside, cpu, samples):
    """The kernel's share of ``make_loops``' CPU time and the rate with all else free."""
    kernel = np.array([k for k, _ in inside])
    per_sample = np.median([r for _, r in inside])
    ceiling = np.sort(samples / kernel)
    print(
        f"{'kernel in ' + world:>24}: {np.median(kernel / np.asarray(cpu)):.0%} of the CPU "
        f"(median), {per_sample:.2f} kernel samples per sample returned; with everything "
        f"else free, {ceiling[0]:.3g} / {np.median(ceiling):.3g} / {ceiling[-1]:.3g} "
        f"loop-samples/s/core ({np.median(ceiling) / GOAL:.2f} x the goal)"
    )


def kernel_time(n_loops, n_samples, chunk, rng):
    """Wall and CPU time of ``_run_loops`` alone on prepared inputs, output buffers reused."""
    from sktiction.simulation.loop import _discretize_all, _run_loops
    from sktiction.simulation.valves import N_PARAMS, STATE_SIZE

    X = np.empty((chunk, n_samples, 3))
    valve = np.empty((chunk, n_samples))
    sp = np.full((chunk, n_samples), 50.0)
    sp[:, 5:] += 1.0
    zeros = np.zeros((chunk, 1))
    wall = cpu = 0.0
    for lo in range(0, n_loops, chunk):
        plants, ctrls, valves = build(chunk, rng)
        A, B0, B1, C, nxs, delay = _discretize_all(plants, np.ones(chunk))
        kcs = np.array([c.kc * c.sign(p.gain) for c, p in zip(ctrls, plants, strict=True)])
        ti = np.array([c.ti for c in ctrls])
        vpar = np.zeros((chunk, N_PARAMS))
        vstate = np.zeros((chunk, STATE_SIZE))
        for j, v in enumerate(valves):
            vpar[j] = v.params()
            vstate[j] = v.initial_state(50.0)
        kinds = np.array([v.kind for v in valves], dtype=np.int64)
        ones = np.ones(chunk)
        args = (
            A,
            B0,
            B1,
            C,
            nxs,
            delay,
            kcs,
            ti,
            0 * ones,
            ones,
            0 * ones,
            100 * ones,
            50 * ones,
            50 * ones,
            kinds,
            vpar,
            vstate,
            sp,
            zeros,
            zeros,
            zeros,
            zeros,
            0 * ones,
            np.arange(chunk),
            0,
            X,
            valve,
        )
        if lo == 0:
            _run_loops(*args)  # compile or load from cache outside the timing
        t0, c0 = time.perf_counter(), time.process_time()
        _run_loops(*args)
        wall += time.perf_counter() - t0
        cpu += time.process_time() - c0
    return wall, cpu


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    main(*args)
