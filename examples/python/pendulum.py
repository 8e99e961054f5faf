"""A pendulum on a hinge against its analytic period: T = 4 sqrt(L/g) K(sin(theta0/2))
for a point mass, with the equivalent length (L^2 + 2/5 r^2) / L of a solid
sphere's compound pendulum.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/pendulum.py [--out DIR]
"""
import argparse
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fulcrum  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for pendulum.png")
parser.add_argument("--amplitude", type=float, default=30.0, help="release angle, degrees")
args = parser.parse_args()
pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)


def elliptic_k(k):
    """Complete elliptic integral of the first kind, by the arithmetic-geometric mean."""
    a, b = 1.0, math.sqrt(1 - k * k)
    while abs(a - b) > 1e-15 * a:
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (2 * a)


g, length, r = 9.81, 1.0, 0.1
theta0 = math.radians(args.amplitude)
w = fulcrum.World(gravity=(0, -g, 0), substeps=4, sleeping=False)
bob = w.create_body(shape=fulcrum.Sphere(r), mass=1,
                    position=(length * math.sin(theta0), -length * math.cos(theta0), 0), name="bob")
w.create_hinge_joint(None, bob, anchor=(0, 0, 0), axis=(0, 0, 1), name="pivot")

dt, times, angles, crossings = 1 / 60, [], [], []
prev = bob.position[0]
for i in range(60 * 10):
    w.step(dt)
    x, y = bob.position[0], bob.position[1]
    times.append(w.time)
    angles.append(math.degrees(math.atan2(x, -y)))
    if prev < 0 <= x:  # upward zero crossing, interpolated
        crossings.append((i + prev / (prev - x)) * dt)
    prev = x

measured = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
equivalent = (length ** 2 + 0.4 * r * r) / length
analytic = 4 * math.sqrt(equivalent / g) * elliptic_k(math.sin(theta0 / 2))
print(f"period: simulated {measured:.4f} s, analytic {analytic:.4f} s "
      f"({100 * (measured / analytic - 1):+.2f} %); small-angle formula {2 * math.pi * math.sqrt(equivalent / g):.4f} s")

fig, ax = plt.subplots(figsize=(7, 3.5))
ax.plot(times, angles)
ax.set_xlabel("time (s)")
ax.set_ylabel("angle (degrees)")
ax.set_title(f"Pendulum from {args.amplitude:g} deg: T = {measured:.4f} s (analytic {analytic:.4f} s)")
out = pathlib.Path(args.out) / "pendulum.png"
fig.savefig(out, dpi=100, bbox_inches="tight")
print(f"wrote {out}")
