"""A pile of 200 boxes and spheres poured onto the ground, read back as NumPy
arrays: no per-body Python loop for the state, the statistics or the push.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/pile.py [--out DIR] [--threads N]
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fulcrum  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for pile.png")
parser.add_argument("--threads", type=int, default=2)
parser.add_argument("--count", type=int, default=200)
args = parser.parse_args()
pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)

rng = np.random.default_rng(7)
w = fulcrum.World(threads=args.threads)
w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", name="ground")
box, ball = fulcrum.Box((0.2, 0.2, 0.2)), fulcrum.Sphere(0.2)
# Layers of 5 x 5 on a jittered grid, 0.5 m apart: they fall, land and settle.
k = np.arange(args.count)
start = np.column_stack([0.5 * (k % 5 - 2) + rng.uniform(-0.1, 0.1, args.count),
                         0.4 + 0.5 * (k // 25),
                         0.5 * (k // 5 % 5 - 2) + rng.uniform(-0.1, 0.1, args.count)])
for i, p in enumerate(start):
    w.create_body(shape=box if i % 2 else ball, position=p, mass=1.0, name=f"piece{i}")

w.step(1 / 60, steps=240)                   # 4 s in C++, the GIL released
pos = w.positions()[1:]                      # (N, 3), creation order; row 0 is the ground
speed = np.linalg.norm(w.linear_velocities()[1:], axis=1)
print(f"{len(pos)} bodies: mean height {pos[:, 1].mean():.3f} m, highest {pos[:, 1].max():.3f} m, "
      f"max speed {speed.max():.4f} m/s, asleep {np.count_nonzero(~w.awake())}")

# Push every piece above 0.5 m sideways, in one call.
high = np.flatnonzero(w.positions()[:, 1] > 0.5)
w.set_linear_velocities(np.tile([2.0, 0.0, 0.0], (len(high), 1)), indices=high)
w.step(1 / 60, steps=60)
print(f"pushed {len(high)} pieces; mean x now {w.positions()[1:, 0].mean():+.3f} m")

fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.5))
a.scatter(pos[:, 0], pos[:, 2], c=pos[:, 1], s=8, cmap="viridis")
a.set_aspect("equal")
a.set_title("pile seen from above (colour: height)")
b.hist(pos[:, 1], bins=20)
b.set_xlabel("height (m)")
b.set_title("heights after 4 s")
out = pathlib.Path(args.out) / "pile.png"
fig.savefig(out, dpi=100, bbox_inches="tight")
print(f"wrote {out}")
