#!/usr/bin/env python3
"""Fulcrum beside DART (Debian's python3-dartpy) on the same URDF robots
(docs/robots.md, "Beside DART"): free fall from the zero pose for 1 s with the
drives and joint limits off, the joint efforts that hold a pose, and inverse
dynamics along a sine trajectory. scripts/bench_dart.py times both engines.

Usage: PYTHONPATH=build/release/python scripts/compare_dart.py ROBOTS_DIR [--plot DIR]
ROBOTS_DIR holds kr5/kr5_sixx_r650.urdf (the public robot files); the double
pendulum comes from tests/robots/. Prints one table per robot; --plot writes
SVG figures of the joint angles over time.
"""
import argparse
import pathlib
import sys
import tempfile
import warnings
import xml.etree.ElementTree as ET

import numpy as np

import dartpy as dart
import fulcrum

REPO = pathlib.Path(__file__).resolve().parents[1]
DT = 1 / 1000          # the sampling of the free fall
DART_DT = 1e-4         # DART's own step: at 1 ms its wrist angles move 2 % of their range from its 0.1 ms ones
FULCRUM_DT = 2.5e-4


def dart_skeleton(path):
    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    options.mDefaultRootJointType = dart.utils.DartLoaderRootJointType.FIXED
    loader.setOptions(options)
    skel = loader.parseSkeleton(str(path))
    if skel is None:
        sys.exit(f"DART could not load {path}")
    return skel


def dart_dofs(skel, names):
    return [skel.getJoint(n).getIndexInSkeleton(0) for n in names]


def free_fall(path, seconds=1.0):
    """Joint angles every DT in both engines, from the zero pose, drives and limits off."""
    skel = dart_skeleton(path)
    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    world.setTimeStep(DART_DT)
    world.addSkeleton(skel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fw = fulcrum.World(gravity=(0, 0, -9.81), substeps=4, joint_hertz=250)
        robot = fulcrum.load_urdf(fw, path, fixed_base=True)
    names = robot.joint_names
    idx = dart_dofs(skel, names)
    for n in names:
        robot.joint(n).set_limits(None)
        robot.joint(n).set_spring(0, 0, 0)
    qf, qd = [], []
    for _ in range(int(round(seconds / DT))):
        for _ in range(int(round(DT / FULCRUM_DT))):
            fw.step(FULCRUM_DT)
        for _ in range(int(round(DT / DART_DT))):
            world.step()
        qf.append(robot.joint_positions())
        qd.append(np.array(skel.getPositions())[idx])
    return names, np.array(qf), np.array(qd)


def holding_efforts(path, pose):
    """The efforts that hold `pose`: Fulcrum's stiff drives after settling; DART's gravity forces."""
    skel = dart_skeleton(path)
    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    world.addSkeleton(skel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # Stiff joint rows (a short step, more sub-steps): the soft rows give a
        # little under the arm's weight, and the pose they sag to is not DART's.
        fw = fulcrum.World(gravity=(0, 0, -9.81), substeps=8, joint_hertz=480)
        robot = fulcrum.load_urdf(fw, path, fixed_base=True)
    n = len(robot.joint_names)
    idx = dart_dofs(skel, robot.joint_names)
    robot.set_drive_gains(np.full(n, 5000.0), np.full(n, 200.0))
    robot.set_position_targets(pose)
    for _ in range(2400):
        fw.step(1 / 240)
    # Hold DART at the pose Fulcrum's drives settled at (they sag a little).
    q = np.array(skel.getPositions())
    q[idx] = robot.joint_positions()
    skel.setPositions(q)
    skel.setVelocities(np.zeros_like(q))
    gravity = np.array(skel.getGravityForces())[idx]  # the generalised force gravity needs held: tau = g(q)
    return robot.joint_names, robot.joint_efforts(), gravity


def inverse_dynamics(path, samples=41, seconds=2.0):
    """Both engines' inverse dynamics (Fulcrum's Robot.inverse_dynamics, DART's
    Skeleton.computeInverseDynamics) along a sine trajectory of every joint:
    the worst difference per joint and the largest effort."""
    skel = dart_skeleton(path)
    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    world.addSkeleton(skel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fw = fulcrum.World(gravity=(0, 0, -9.81))
        robot = fulcrum.load_urdf(fw, path, fixed_base=True)
    names = robot.joint_names
    n = len(names)
    idx = dart_dofs(skel, names)
    amp, freq, phase = np.linspace(0.4, 0.9, n), np.linspace(1.0, 3.0, n), np.linspace(0.0, 1.5, n)
    worst, largest = np.zeros(n), np.zeros(n)
    for t in np.linspace(0.0, seconds, samples):
        q = amp * np.sin(freq * t + phase)
        qd = amp * freq * np.cos(freq * t + phase)
        qdd = -amp * freq ** 2 * np.sin(freq * t + phase)
        full = [np.zeros(skel.getNumDofs()) for _ in range(3)]
        for values, full_values in zip((q, qd, qdd), full):
            full_values[idx] = values
        skel.setPositions(full[0])
        skel.setVelocities(full[1])
        skel.setAccelerations(full[2])
        skel.computeInverseDynamics(False, False, False)
        d = np.array(skel.getForces())[idx]
        f = robot.inverse_dynamics(q, qd, qdd)
        worst = np.maximum(worst, np.abs(f - d))
        largest = np.maximum(largest, np.abs(d))
    return names, worst, largest


def without_meshes(path, folder):
    """A copy of the URDF without its visual and collision elements (the KR5's
    meshes are not in the public copy, and DART refuses a missing mesh)."""
    tree = ET.parse(path)
    for link in tree.getroot().iter("link"):
        for tag in ("visual", "collision"):
            for e in link.findall(tag):
                link.remove(e)
    out = pathlib.Path(folder) / (path.stem + "_no_meshes.urdf")
    tree.write(out)
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("robots", type=pathlib.Path)
    parser.add_argument("--plot", type=pathlib.Path)
    args = parser.parse_args()
    folder = tempfile.mkdtemp()
    cases = [("double pendulum", REPO / "tests" / "robots" / "double_pendulum.urdf", [0.3, -0.5]),
             ("KUKA KR5", without_meshes(args.robots / "kr5" / "kr5_sixx_r650.urdf", folder),
              [0.3, 0.6, -0.4, 0.2, 0.5, 0.1])]
    for label, path, pose in cases:
        names, qf, qd = free_fall(path)
        span = qd.max(axis=0) - qd.min(axis=0)
        worst = np.abs(qf - qd).max(axis=0) / np.maximum(span, 1e-9)
        print(f"{label}: free fall 1 s from the zero pose, worst angle difference / range swept (DART)")
        for n, w, s in zip(names, worst, span):
            print(f"  {n:16s} range {s:8.4f} rad   worst difference {100 * w:7.3f} %")
        names, ef, ed = holding_efforts(path, pose)
        print(f"{label}: efforts holding {pose} (N m); difference of each, and over the largest")
        largest = np.abs(ed).max()
        for n, a, b in zip(names, ef, ed):
            rel = abs(a - b) / max(abs(b), 1e-9)
            print(f"  {n:16s} Fulcrum {a:10.4f}   DART {b:10.4f}   difference {100 * rel:7.3f} %  "
                  f"({100 * abs(a - b) / largest:.4f} % of the largest)")
        names, worst, largest = inverse_dynamics(path)
        print(f"{label}: inverse dynamics along a sine trajectory of every joint (41 samples over 2 s): "
              f"worst difference, and the largest effort (N m)")
        for n, w, big in zip(names, worst, largest):
            print(f"  {n:16s} worst difference {w:.2e}   largest effort {big:9.4f}   "
                  f"(relative to it {w / max(big, 1e-12):.1e}; to the robot's largest {w / largest.max():.1e})")
        if args.plot:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            args.plot.mkdir(parents=True, exist_ok=True)
            t = np.arange(1, len(qf) + 1) * DT
            fig, ax = plt.subplots(figsize=(7, 4))
            for k, n in enumerate(names):
                ax.plot(t, qd[:, k], color=f"C{k}", lw=3, alpha=0.35, label=f"{n} (DART)")
                ax.plot(t, qf[:, k], color=f"C{k}", lw=1, ls="--", label=f"{n} (Fulcrum)")
            ax.set_xlabel("time (s)")
            ax.set_ylabel("joint angle (rad)")
            ax.set_title(f"{label}: free fall, Fulcrum (dashed) beside DART")
            ax.legend(fontsize=6, ncol=2)
            fig.tight_layout()
            fig.savefig(args.plot / (label.lower().replace(" ", "_") + "_free_fall.svg"), metadata={"Date": None})


if __name__ == "__main__":
    main()
