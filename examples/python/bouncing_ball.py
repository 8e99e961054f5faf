"""A ball dropped on the ground with restitution 0.8: its height over time,
plotted with matplotlib, and each bounce's apex against h0 e^(2n).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/bouncing_ball.py [--out DIR]
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # write a file; no window needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fulcrum  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for bouncing_ball.png")
args = parser.parse_args()
pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)

e, h0, r = 0.8, 2.0, 0.1
w = fulcrum.World(sleeping=False)
w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", restitution=e, name="ground")
ball = w.create_body(shape=fulcrum.Sphere(r), mass=1, position=(0, h0 + r, 0), restitution=e, name="ball")

times, heights = [], []
for _ in range(60 * 4):
    w.step(1 / 60)
    times.append(w.time)
    heights.append(ball.position[1] - r)
heights = np.array(heights)

# Apexes: where the height stops rising.
apex = [heights[i] for i in range(1, len(heights) - 1) if heights[i - 1] < heights[i] >= heights[i + 1]]
for n, h in enumerate(apex[:3], start=1):
    print(f"bounce {n}: apex {h:.3f} m, h0 e^(2n) = {h0 * e ** (2 * n):.3f} m")

fig, ax = plt.subplots(figsize=(7, 3.5))
ax.plot(times, heights, label="simulated")
for n in range(1, 4):
    ax.axhline(h0 * e ** (2 * n), color="grey", lw=0.6, ls="--")
ax.set_xlabel("time (s)")
ax.set_ylabel("height of the ball's bottom (m)")
ax.set_title(f"Bouncing ball, restitution {e}: apexes at h0 e^(2n)")
ax.legend()
out = pathlib.Path(args.out) / "bouncing_ball.png"
fig.savefig(out, dpi=100, bbox_inches="tight")
print(f"wrote {out}")
