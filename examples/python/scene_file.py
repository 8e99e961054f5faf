"""A scene file driven from Python: load scenes/box_stack.json, run it as
`fulcrum run` would, knock the stack over with an impulse, plot the boxes'
heights, and save the final state as a new scene file.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/scene_file.py [--out DIR] [--scene FILE]
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fulcrum  # noqa: E402

repo = pathlib.Path(__file__).resolve().parents[2]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for scene_file.png and knocked_over.json")
parser.add_argument("--scene", default=repo / "scenes" / "box_stack.json")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

w = fulcrum.load_scene(args.scene)
print(f"loaded {args.scene}: {w.body_count} bodies, dt {w.scene_dt:.5f} s, {w.scene_steps} steps")
names = [b.name for b in w.bodies()]
dynamic = np.array([b.type == "dynamic" for b in w.bodies()])

heights = []
for step in range(240):
    if step == 60:  # after 1 s, hit the top box sideways
        top = w.bodies()[int(np.argmax(np.where(dynamic, w.positions()[:, 1], -np.inf)))]
        top.apply_impulse((3.0, 0, 0))
        print(f"t = {w.time:.2f} s: hit {top.name!r}")
    w.step(w.scene_dt)
    heights.append(w.positions()[dynamic, 1])
heights = np.array(heights)

w.save_scene(out / "knocked_over.json")
again = fulcrum.load_scene(out / "knocked_over.json")
assert np.array_equal(again.positions(), w.positions())
print(f"saved {out / 'knocked_over.json'}; energy now {w.energy()['total']:.2f} J")

fig, ax = plt.subplots(figsize=(7, 3.5))
t = (np.arange(len(heights)) + 1) * w.scene_dt
for k, name in enumerate(np.array(names)[dynamic]):
    ax.plot(t, heights[:, k], label=name)
ax.set_xlabel("time (s)")
ax.set_ylabel("height (m)")
ax.set_title("box stack, hit at t = 1 s")
ax.legend(fontsize="small", ncol=2)
fig.savefig(out / "scene_file.png", dpi=100, bbox_inches="tight")
print(f"wrote {out / 'scene_file.png'}")
