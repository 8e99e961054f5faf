"""A 24 x 24 cloth dropped over a sphere: its particles as an (n, 3) array,
drawn with matplotlib, and the run recorded as a replay page (cloth.html).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/cloth.py [--out DIR]
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fulcrum  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for cloth.png and cloth.html")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

w = fulcrum.World()
w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", name="ground")
w.create_body(shape=fulcrum.Sphere(0.5), type="static", position=(0, 0.5, 0), name="sphere")
n, spacing = 24, 0.06
cloth = w.create_cloth(origin=(-0.5 * spacing * (n - 1), 1.3, -0.5 * spacing * (n - 1)), size=(n, n),
                       spacing=spacing, particle_mass=0.01, radius=0.02, bend_compliance=0.1, name="sheet")

recorder = fulcrum.Recorder(w, title="cloth over a sphere", capture_interval=1 / 30)
recorder.capture()
for _ in range(150):
    w.step(1 / 60)
    recorder.capture()
recorder.write(out / "cloth.html")

p = cloth.positions()                      # (n*n, 3): particle (i, j) is row j * n + i
report = cloth.report()
print(f"{cloth.particle_count} particles: lowest {p[:, 1].min():.3f} m, highest {p[:, 1].max():.3f} m, "
      f"max stretch {100 * report['max_stretch']:.2f} %, deepest penetration {1000 * report['max_penetration']:.2f} mm")

fig = plt.figure(figsize=(5, 5))
ax = fig.add_subplot(projection="3d")
grid = p.reshape(n, n, 3)
ax.plot_wireframe(grid[:, :, 0], grid[:, :, 2], grid[:, :, 1], linewidth=0.5)
ax.set_title("cloth after 2.5 s")
fig.savefig(out / "cloth.png", dpi=100, bbox_inches="tight")
print(f"wrote {out / 'cloth.png'} and {out / 'cloth.html'} ({recorder.frame_count} frames)")
