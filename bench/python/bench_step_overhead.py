"""What driving nmdp from Python costs, and what threads buy a rollout (a benchmark, not a test).

1. Per-step overhead of sim.step() from Python against the C++ step loop, on a cheap scene (a foot
   resting on sand, about 12 µs a step, every step the same work): n calls of sim.step() against
   one sim.step(n), which loops in C++, from the same state; the difference per step is what a
   Python call adds (binding, GIL release, the StepStats object). Target: under 5 µs.
   A second estimate: the time a sim.step() call takes in Python minus the step's own wall_time.
2. Rollout throughput with threads=2 against threads=1 on a 2-core machine (runs per second of a
   floating-base trot). Target: at least 1.8x.

Run:  PYTHONPATH=build/python /usr/bin/python3 bench/python/bench_step_overhead.py [--quick]
Run it alone on the machine (under the build lock): the numbers are wall-clock times.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

import nmdp

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "models", "scenes")


def resting_foot():
    """A foot dropped on sand and come to rest: every later step is the same small amount of work."""
    sim = nmdp.Simulation(nmdp.Scene.load(os.path.join(SCENES, "quadruped_foot_drop_sand.json"), {"duration": 1e6}))
    sim.step(200)
    return sim


def step_overhead(n, repeats):
    """Per-step seconds: (n single calls − one call of n steps) / n, repeated on fresh pairs; and
    the per-call time minus the step's own wall_time."""
    differences, beside_wall = [], []
    for _ in range(repeats):
        single, batch = resting_foot(), resting_foot()
        start = time.perf_counter()
        wall = 0.0
        for _ in range(n):
            wall += single.step().wall_time
        t_single = time.perf_counter() - start
        start = time.perf_counter()
        batch.step(n)
        t_batch = time.perf_counter() - start
        assert np.array_equal(single.q, batch.q), "the two runs must do the same work"
        differences.append((t_single - t_batch) / n)
        beside_wall.append((t_single - wall) / n)
    return t_batch / n, statistics.median(differences), statistics.median(beside_wall)


def rollout_throughput(batch, steps, repeats):
    """Runs per second of nmdp.rollout with 1 and 2 threads (the best of `repeats`)."""
    scene = nmdp.Scene.load(os.path.join(SCENES, "quadruped_trot_flat.json"))
    sim = nmdp.Simulation(scene)
    start = np.tile(np.concatenate([sim.q, sim.qdot]), (batch, 1))
    start[:, 0] += np.linspace(0.0, 0.01, batch)  # distinct entries
    rates = {}
    results = {}
    for threads in (1, 2):
        best = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            results[threads] = nmdp.rollout(scene, start, steps, threads=threads)
            best = min(best, time.perf_counter() - t0)
        rates[threads] = batch / best
    same = np.array_equal(results[1], results[2], equal_nan=True)
    return rates, same


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats (a smoke run)")
    args = parser.parse_args()
    n, repeats = (2000, 3) if args.quick else (20000, 9)

    per_step, overhead, beside_wall = step_overhead(n, repeats)
    print(f"step overhead (resting foot on sand, {n} steps, median of {repeats}):")
    print(f"  C++ loop sim.step({n}):         {per_step * 1e6:8.2f} µs/step")
    print(f"  sim.step() from Python, extra:  {overhead * 1e6:8.2f} µs/step   (target < 5 µs)")
    print(f"  per call minus stats.wall_time: {beside_wall * 1e6:8.2f} µs/step")

    if not hasattr(nmdp, "rollout"):
        print("rollout: nmdp.rollout is not built", file=sys.stderr)
        return
    batch, steps = (8, 10) if args.quick else (32, 20)
    rates, same = rollout_throughput(batch, steps, 2 if args.quick else 3)
    print(f"rollout (floating-base trot, {batch} entries x {steps} steps, best of repeats):")
    print(f"  threads=1: {rates[1]:8.2f} runs/s")
    print(f"  threads=2: {rates[2]:8.2f} runs/s   speed-up {rates[2] / rates[1]:.2f}x (target >= 1.8x)"
          f"; results {'identical' if same else 'DIFFER'}")


if __name__ == "__main__":
    main()
