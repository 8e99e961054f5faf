"""The arm of scenes/robot_arm.urdf, its base fixed and every joint held by a
position drive (implicit PD), turns its pan joint (the vertical axis at its
base) along a sine target; the other joints hold a reaching pose. It prints
the RMS tracking error beside the one the drive's linear model predicts, and
writes arm_sine_tracking.json (the traces) and, if matplotlib is installed,
arm_sine_tracking.png (target against actual). docs/robots.md, "Examples".

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/arm_sine_tracking.py [--out DIR]

The prediction: about the vertical axis gravity exerts no torque, so the pan
joint is a rotor of inertia I (the links beyond it, about the axis) under the
drive's torque kp (target - q) - kd q'. For a target A sin(w t) the steady
error is the target times (kd i w - I w^2) / (kp - I w^2 + kd i w): an
amplitude ratio |kd i w - I w^2| / |kp - I w^2 + kd i w|, so an RMS error of
A / sqrt(2) times that ratio (kd includes the URDF's joint damping, 0.1).
"""
import argparse
import json
import math
import pathlib

import numpy as np

import fulcrum

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="directory for arm_sine_tracking.json and .png")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

urdf = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "robot_arm.urdf"
world = fulcrum.World(gravity=(0, 0, -9.81))
arm = fulcrum.load_urdf(world, urdf, fixed_base=True)
names = arm.joint_names
pan = names.index("pan")
pose = np.zeros(len(names))
pose[names.index("shoulder")] = 0.7
pose[names.index("elbow")] = 0.9
pose[names.index("wrist_pitch")] = -0.4
kp = np.array([200.0, 4000, 2000, 300, 100, 50])  # N m/rad: the pan joint soft, so its lag shows
kd = np.array([20.0, 200, 100, 10, 5, 2])         # N m s/rad
arm.set_drive_gains(kp, kd)

dt, amplitude, period = 1 / 240, 0.5, 2.0
omega = 2 * math.pi / period
# Settle into the reaching pose (the pan target 0) before the sine starts.
arm.set_position_targets(pose)
for _ in range(int(2 / dt)):
    world.step(dt)

times, target, actual = [], [], []
for i in range(int(3 * period / dt)):
    t = (i + 1) * dt
    q = pose.copy()
    q[pan] = amplitude * math.sin(omega * t)
    arm.set_position_targets(q)
    world.step(dt)
    times.append(t)
    target.append(q[pan])
    actual.append(arm.joint_positions()[pan])
times, target, actual = np.array(times), np.array(target), np.array(actual)
# The last two periods: the start-up transient (decay rate kd / 2I, about 4.6/s) is gone.
steady = times > period
rms = float(np.sqrt(np.mean((target - actual)[steady] ** 2)))



def rotation(q):
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


# I: the links beyond the pan joint (all but the base) about the vertical axis
# through it (x = y = 0), in the pose they hold (at pan angle 0: the sine turns
# the arm about the axis, which leaves I unchanged).
inertia = 0.0
for link in arm.link_names:
    if link == "base_link":
        continue
    body = arm.body(link)
    r = rotation(body.orientation)
    cx, cy, _ = body.center_of_mass
    inertia += (r @ np.asarray(body.inertia) @ r.T)[2, 2] + body.mass * (cx * cx + cy * cy)
damping = kd[pan] + 0.1  # the drive's and the URDF's <dynamics damping>
ratio = abs(complex(-inertia * omega**2, damping * omega)) / abs(complex(kp[pan] - inertia * omega**2, damping * omega))
predicted = amplitude * ratio / math.sqrt(2)
print(f"pan joint: inertia about its axis {inertia:.4f} kg m^2, target {amplitude} rad sine of period {period} s")
print(f"RMS tracking error {rms:.4f} rad; the linear PD model predicts {predicted:.4f} rad")

data = out / "arm_sine_tracking.json"
data.write_text(json.dumps({"joint": "pan", "kp": kp[pan], "kd": damping, "inertia": inertia, "amplitude": amplitude,
                            "period": period, "rms_error": rms, "predicted_rms_error": predicted,
                            "time": times.tolist(), "target": target.tolist(), "actual": actual.tolist()}))
print(f"wrote {data}")

try:
    import matplotlib
except ImportError:
    print("matplotlib is not installed (Debian: python3-matplotlib): no plot")
else:
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(times, target, lw=3, alpha=0.35, label="pan target")
    ax.plot(times, actual, lw=1, label=f"pan actual (RMS error {rms:.3f} rad, model {predicted:.3f})")
    ax.set_xlabel("time since the sine started (s)")
    ax.set_ylabel("angle (rad)")
    ax.set_title(f"Arm pan joint under a PD drive (kp {kp[pan]:.0f}, kd {damping:.1f}) tracking a sine")
    ax.legend(fontsize=8)
    fig.tight_layout()
    plot = out / "arm_sine_tracking.png"
    fig.savefig(plot, dpi=100)
    print(f"wrote {plot}")
