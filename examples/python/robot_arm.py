"""The six-joint arm of scenes/robot_arm.urdf, held by its position drives
(implicit PD), tracks a sine on its shoulder and elbow: target against actual
angle, and the drives' torques (docs/robots.md).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/robot_arm.py [--out DIR]
"""
import argparse
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fulcrum  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for robot_arm.png")
args = parser.parse_args()
pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)

urdf = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "robot_arm.urdf"
world = fulcrum.World(gravity=(0, 0, -9.81))
arm = fulcrum.load_urdf(world, urdf, fixed_base=True)
n = len(arm.joint_names)
arm.set_drive_gains(np.full(n, 4000.0), np.full(n, 150.0))

dt, period = 1 / 240, 2.0
times, target, actual, torque = [], [], [], []
for i in range(int(4 / dt)):
    t = (i + 1) * dt
    q = np.zeros(n)
    q[1] = 0.6 * math.sin(2 * math.pi * t / period)        # shoulder
    q[2] = 0.8 + 0.4 * math.sin(2 * math.pi * t / period)  # elbow
    arm.set_position_targets(q)
    world.step(dt)
    times.append(t)
    target.append(q[1:3])
    actual.append(arm.joint_positions()[1:3])
    torque.append(arm.joint_efforts()[1:3])
target, actual, torque = np.array(target), np.array(actual), np.array(torque)
lag = np.abs(target - actual)[len(times) // 2:].max(axis=0)

fig, (ax, bx) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
for k, name in enumerate(["shoulder", "elbow"]):
    ax.plot(times, target[:, k], color=f"C{k}", lw=3, alpha=0.35, label=f"{name} target")
    ax.plot(times, actual[:, k], color=f"C{k}", lw=1, label=f"{name} actual (worst gap {lag[k]:.3f} rad)")
    bx.plot(times, torque[:, k], color=f"C{k}", lw=1, label=f"{name} drive torque")
ax.set_ylabel("angle (rad)")
ax.legend(fontsize=8)
bx.set_xlabel("time (s)")
bx.set_ylabel("torque (N m)")
bx.legend(fontsize=8)
ax.set_title("Six-joint arm: PD drives tracking a sine")
fig.tight_layout()
out = pathlib.Path(args.out) / "robot_arm.png"
fig.savefig(out, dpi=100)
print(f"shoulder and elbow follow their targets within {lag.max():.3f} rad; wrote {out}")
