"""What the Python binding adds to the engine's own cost (docs/benchmarks.md,
"Python binding"). Wall-clock on a noisy machine: every figure is the best of
several rounds, and the per-call overhead is a difference of two runs of the
same C++ steps (one step() call each vs one call for all of them).

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python/bench_binding.py [--cli build/release/apps/fulcrum/fulcrum]
"""
import argparse
import json
import pathlib
import subprocess
import time

import numpy as np

import fulcrum

REPO = pathlib.Path(__file__).resolve().parents[2]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--cli", default=REPO / "build" / "release" / "apps" / "fulcrum" / "fulcrum")
parser.add_argument("--rounds", type=int, default=7)
args = parser.parse_args()


def best(fn, rounds=args.rounds):
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def ten_bodies():
    w = fulcrum.World(sleeping=False, gravity=(0, 0, 0))   # free bodies: no contacts, no sleep; the step is small
    for i in range(10):
        w.create_body(shape=fulcrum.Sphere(0.1), mass=1, position=(2.0 * i, 0, 0), linear_velocity=(0, 0.1 * i, 0))
    return w


# 1. Per step() call: K calls of step(dt) against one call of step(dt, steps=K), same steps in C++.
K = 20000
dt = 1 / 60
a, b = ten_bodies(), ten_bodies()
step = a.step


def one_by_one():
    for _ in range(K):
        step(dt)


per_call = best(one_by_one) / K
batched = best(lambda: b.step(dt, steps=K)) / K
print(f"10-body world: step() per call {per_call * 1e6:.2f} us, inside step(dt, steps={K}) {batched * 1e6:.2f} us "
      f"per step: the binding adds {(per_call - batched) * 1e6:.2f} us per call")

# 2. 10,000 bodies' positions as one array.
big = fulcrum.World()
for i in range(10000):
    big.create_body(shape=fulcrum.Sphere(0.1), mass=1, position=(i % 100, 1 + i // 100, 0))
reps = 200
read = best(lambda: [big.positions() for _ in range(reps)]) / reps
setv = np.zeros((10000, 3))
write = best(lambda: [big.set_linear_velocities(setv) for _ in range(reps)]) / reps
print(f"10,000 bodies: positions() {read * 1e6:.1f} us, set_linear_velocities() {write * 1e6:.1f} us")

# 3. step(dt, steps=600) of a scene against `fulcrum run` (its wall_seconds: the step loop alone).
for scene in ("box_stack.json", "chain.json"):
    path = REPO / "scenes" / scene
    cli = min(json.loads(subprocess.run([str(args.cli), "run", str(path), "--json", "--steps", "600"], check=True,
                                        capture_output=True, text=True).stdout)["wall_seconds"]
              for _ in range(args.rounds))

    def python_run():
        w = fulcrum.load_scene(path)
        t0 = time.perf_counter()
        w.step(w.scene_dt, steps=600)
        return time.perf_counter() - t0

    py = min(python_run() for _ in range(args.rounds))
    print(f"{scene}: 600 steps from Python {py * 1e3:.2f} ms, fulcrum run {cli * 1e3:.2f} ms ({100 * (py / cli - 1):+.1f} %)")
