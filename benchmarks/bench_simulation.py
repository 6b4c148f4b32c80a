"""Throughput of the compiled closed loop, in loop-samples per second on one core.

Goal (GitHub issue 2): >= 1e7 loop-samples/s/core, i.e. 10,000 loops of 5,000
samples in <= 5 s. The loops mix plant orders 1-4 and integrating plants with
healthy, relay, Choudhury and Kano valves; each is started by a setpoint step.
Loops are simulated in chunks to bound memory. Three figures: the compiled
kernel alone (output buffers reused), ``simulate_loops`` end to end (fresh
output arrays, discretisation, effects), and everything including building the
plant and controller objects. Fresh memory is slow to fault in on some
sandboxes, which is what separates the first two figures.

Run: ``NUMBA_NUM_THREADS=1 python benchmarks/bench_simulation.py [n_loops n_samples]``
"""

from __future__ import annotations

import sys
import time

import numpy as np

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


def main(n_loops=10_000, n_samples=5_000, chunk=250):
    rng = np.random.default_rng(0)
    warm = build(4, rng)
    simulate_loops(*warm, 100, 1.0, effects=[SetpointSteps([5.0], [1.0])])  # compile / load cache
    samples = n_loops * n_samples
    print(f"{n_loops} loops x {n_samples} samples = {samples:.3g} loop-samples")
    report("compiled kernel", kernel_time(n_loops, n_samples, chunk, rng), samples)
    start = time.perf_counter()
    sim = 0.0
    for lo in range(0, n_loops, chunk):
        n = min(chunk, n_loops - lo)
        loops = build(n, rng)
        t0 = time.perf_counter()
        simulate_loops(*loops, n_samples, 1.0, effects=[SetpointSteps([5.0], [1.0])])
        sim += time.perf_counter() - t0
    total = time.perf_counter() - start
    report("simulate_loops", sim, samples)
    report("incl. building objects", total, samples)


def report(label, seconds, samples):
    rate = samples / seconds
    print(
        f"{label:>24}: {seconds:6.2f} s -> {rate:.3g} loop-samples/s/core "
        f"({rate / GOAL:.2f} x the 1e7 goal)"
    )


def kernel_time(n_loops, n_samples, chunk, rng):
    """Time ``_run_loops`` alone on prepared inputs, reusing the output buffers."""
    from sktiction.simulation.loop import _discretize_all, _run_loops
    from sktiction.simulation.valves import N_PARAMS, STATE_SIZE

    X = np.empty((chunk, n_samples, 3))
    valve = np.empty((chunk, n_samples))
    sp = np.full((chunk, n_samples), 50.0)
    sp[:, 5:] += 1.0
    zeros = np.zeros((chunk, 1))
    elapsed = 0.0
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
        t0 = time.perf_counter()
        _run_loops(*args)
        elapsed += time.perf_counter() - t0
    return elapsed


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    main(*args)
