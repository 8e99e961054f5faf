"""Which restitution makes a ball bounce once and land in a cup? A sweep of
worlds (fulcrum.distributed: threads here, a Dask cluster with --scheduler),
a finer sweep around the hits, and the answer against ballistics.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/cup_restitution.py [--out DIR]
        [--scheduler tcp://HOST:PORT] [--threads T]

The ball (radius r) starts at height y0 moving at vx along a frictionless
floor; it hits the floor after t1 = v0 / g, with v0 = sqrt(2 g (y0 - r)),
leaves it at e v0 and lands again 2 e v0 vx / g further on. So the restitution
that lands it at the cup's centre xc is e* = (xc - vx t1) g / (2 v0 vx), and the
cup (inner width 2 w) accepts e within +-(w - r) g / (2 v0 vx) of it.
"""
import argparse
import json
import math
import pathlib

import matplotlib

matplotlib.use("Agg")  # write a file; no window needed
import matplotlib.pyplot as plt  # noqa: E402

import fulcrum.distributed as fd  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for cup_restitution.png and .json")
parser.add_argument("--scheduler", default=None, help="a Dask scheduler address (default: run here)")
parser.add_argument("--threads", type=int, default=2, help="threads of a local run")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

g, r, y0, vx = 9.81, 0.1, 2.0, 1.0
v0 = math.sqrt(2 * g * (y0 - r))
t1 = v0 / g
e_star = 0.6
xc = vx * t1 + 2 * e_star * v0 * vx / g     # the cup is placed where e = 0.6 lands, by ballistics
w, wall = 0.25, 0.02                         # the cup: inner half-width, wall half-thickness
half_band = (w - r) * g / (2 * v0 * vx)      # restitutions whose landing point fits in the cup

scene = {
    "description": "A ball bounces once on a frictionless floor towards a cup of two walls.",
    "world": {"gravity": [0, -g, 0], "dt": 1 / 240, "sleeping": False},
    "bodies": [
        {"name": "floor", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}, "friction": 0},
        {"name": "near_wall", "type": "static", "shape": {"type": "box", "half_extents": [wall, 0.15, 1]},
         "position": [xc - w - wall, 0.15, 0], "friction": 0},
        {"name": "far_wall", "type": "static", "shape": {"type": "box", "half_extents": [wall, 0.15, 1]},
         "position": [xc + w + wall, 0.15, 0], "friction": 0},
        {"name": "ball", "shape": {"type": "sphere", "radius": r}, "mass": 0.1, "position": [0, y0, 0],
         "linear_velocity": [vx, 0, 0], "friction": 0, "restitution": 0.5},
    ],
}
steps = int(round((t1 + 2 * 1.0 * v0 / g + 0.5) * 240))  # long enough for the slowest (e = 1) landing


def sweep(restitutions):
    """1 where the ball ends inside the cup, else 0, for each restitution."""
    spec = fd.BatchSpec(scene, overrides=[{"bodies[ball].restitution": e} for e in restitutions], steps=steps)
    if args.scheduler:
        from dask.distributed import Client

        with Client(args.scheduler) as client:
            results = fd.run(spec, client)
    else:
        results = fd.run_local(spec, threads=args.threads)
    ball = results[0].body_names.index("ball")
    return [int(abs(res.positions[ball][0] - xc) < w and res.positions[ball][1] < 0.3) for res in results]


coarse = [i / 20 for i in range(21)]
hits = sweep(coarse)
inside = [e for e, h in zip(coarse, hits) if h]
if not inside:
    raise SystemExit("no restitution of the coarse sweep lands in the cup")
# A finer sweep between the coarse misses on either side of the hits.
lo, hi = max(0.0, min(inside) - 0.05), min(1.0, max(inside) + 0.05)
fine = [lo + (hi - lo) * i / 40 for i in range(41)]
fine_hits = sweep(fine)
band = [e for e, h in zip(fine, fine_hits) if h]
found = (min(band), max(band))
middle = (found[0] + found[1]) / 2
print(f"the ball lands in the cup for restitution {found[0]:.3f} .. {found[1]:.3f} (middle {middle:.3f})")
print(f"ballistics: {e_star - half_band:.3f} .. {e_star + half_band:.3f} (e* = {e_star})")
# The soft contact and the sub-steps shift the bounce a little, not the answer.
if abs(middle - e_star) > 0.05:
    raise SystemExit(f"the simulated middle {middle:.3f} is more than 0.05 from ballistics' {e_star}")

fig, ax = plt.subplots(figsize=(7, 3))
ax.step(fine, fine_hits, where="mid", label="simulated (fine sweep)")
ax.axvspan(e_star - half_band, e_star + half_band, color="tab:orange", alpha=0.2, label="ballistics")
ax.set_xlabel("restitution")
ax.set_ylabel("in the cup")
ax.legend(loc="upper right")
fig.tight_layout()
png = out / "cup_restitution.png"
fig.savefig(png, dpi=100)
result = out / "cup_restitution.json"
result.write_text(json.dumps({"found": found, "ballistics": [e_star - half_band, e_star + half_band]}, indent=2))
print(f"wrote {png} and {result}")
