#!/usr/bin/env python3
"""Fulcrum beside DART (Debian's python3-dartpy) on the same URDF robots
(docs/robots.md, "Beside DART"): free fall from the zero pose for 1 s with the
drives and joint limits off, the joint efforts that hold a pose, and inverse
dynamics along a sine trajectory: fixed base, with joint damping, and with a
floating base (the base wrench for a prescribed base acceleration, and the
free base's acceleration under DART's forward dynamics). scripts/bench_dart.py
times both engines.

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


def dart_skeleton(path, floating=False):
    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    root = dart.utils.DartLoaderRootJointType
    options.mDefaultRootJointType = root.FLOATING if floating else root.FIXED
    loader.setOptions(options)
    skel = loader.parseSkeleton(str(path))
    if skel is None:
        sys.exit(f"DART could not load {path}")
    return skel


def dart_dofs(skel, names):
    return [skel.getJoint(n).getIndexInSkeleton(0) for n in names]


def both_engines(path, floating=False, dart_dt=None, **fulcrum_world):
    """The URDF in a DART world and a Fulcrum world (gravity -z in both; the
    Fulcrum world's settings as given): (skeleton, DART world, Fulcrum world, robot)."""
    skel = dart_skeleton(path, floating)
    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    if dart_dt is not None:
        world.setTimeStep(dart_dt)
    world.addSkeleton(skel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fw = fulcrum.World(gravity=(0, 0, -9.81), **fulcrum_world)
        robot = fulcrum.load_urdf(fw, path, fixed_base=not floating)
    return skel, world, fw, robot


def sine(n, t):
    """Every joint's sine trajectory at time t: q, qd, qdd."""
    amp, freq, phase = np.linspace(0.4, 0.9, n), np.linspace(1.0, 3.0, n), np.linspace(0.0, 1.5, n)
    return (amp * np.sin(freq * t + phase), amp * freq * np.cos(freq * t + phase),
            -amp * freq ** 2 * np.sin(freq * t + phase))


def free_fall(path, seconds=1.0):
    """Joint angles every DT in both engines, from the zero pose, drives and limits off."""
    skel, world, fw, robot = both_engines(path, dart_dt=DART_DT, substeps=4, joint_hertz=250)
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
    # Stiff joint rows (a short step, more sub-steps): the soft rows give a
    # little under the arm's weight, and the pose they sag to is not DART's.
    skel, world, fw, robot = both_engines(path, substeps=8, joint_hertz=480)
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


def inverse_dynamics(path, samples=41, seconds=2.0, damping=False):
    """Both engines' inverse dynamics (Fulcrum's Robot.inverse_dynamics, DART's
    Skeleton.computeInverseDynamics) along a sine trajectory of every joint:
    the worst difference per joint and the largest effort. damping: the
    URDF's joint damping included in both (DART's withDampingForces, which
    is d (qd + qdd h) for its step h: that term is added to Fulcrum's d qd)."""
    skel, world, fw, robot = both_engines(path)
    names = robot.joint_names
    n = len(names)
    idx = dart_dofs(skel, names)
    # DART's damping force is implicit in its time step h: d (qd + qdd h), not d qd.
    h = world.getTimeStep()
    d_coeff = np.array([skel.getJoint(name).getDampingCoefficient(0) for name in names])
    worst, largest = np.zeros(n), np.zeros(n)
    for t in np.linspace(0.0, seconds, samples):
        q, qd, qdd = sine(n, t)
        full = [np.zeros(skel.getNumDofs()) for _ in range(3)]
        for values, full_values in zip((q, qd, qdd), full):
            full_values[idx] = values
        skel.setPositions(full[0])
        skel.setVelocities(full[1])
        skel.setAccelerations(full[2])
        skel.computeInverseDynamics(False, damping, False)
        d = np.array(skel.getForces())[idx]
        f = robot.inverse_dynamics(q, qd, qdd, damping=damping, friction=False)
        if damping:
            f = f + d_coeff * qdd * h
        worst = np.maximum(worst, np.abs(f - d))
        largest = np.maximum(largest, np.abs(d))
    return names, worst, largest


def rotation(v):
    """The rotation matrix of rotation vector v, and its quaternion (w, x, y, z)."""
    angle = float(np.linalg.norm(v))
    axis = np.asarray(v) / angle if angle > 0 else np.array([1.0, 0, 0])
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    return R, (np.cos(angle / 2), *(np.sin(angle / 2) * axis))


def floating_inverse_dynamics(path, samples=21, seconds=2.0):
    """Floating base, along the sine trajectory, the base turned (rotation
    vector r) and spinning (w_b, body axes; its origin's linear velocity 0, so
    DART's body-frame accelerations are the classical ones turned into the
    body). Prescribed: DART's computeInverseDynamics gives the base's six
    generalised forces (body axes, torque about the base's origin) and the
    efforts for base accelerations (alpha_b, a_b); Fulcrum's
    floating_base_inverse_dynamics with the same accelerations (world axes)
    gives its wrench and efforts. Free: DART's forward dynamics with Fulcrum's
    free-base efforts and no base force gives the base's accelerations and
    the joints' (which should be Fulcrum's, and the trajectory's).
    Returns the worst differences: efforts, wrench, base acceleration, joint
    acceleration; and the largest effort, wrench and acceleration."""
    skel, world, fw, robot = both_engines(path, floating=True)
    names = robot.joint_names
    n = len(names)
    idx = dart_dofs(skel, names)
    worst = np.zeros(4)
    largest = np.zeros(3)
    for t in np.linspace(0.0, seconds, samples):
        q, qd, qdd = sine(n, t)
        r = np.array([0.3 * np.sin(t), 0.2, -0.4 * np.cos(t)])
        R, quat = rotation(r)
        w_b = np.array([0.5, -0.8 * np.cos(t), 0.3])
        alpha_b, a_b = np.array([1.0, 0.4 * np.sin(2 * t), -0.7]), np.array([0.5, -1.2, 2.0 * np.cos(t)])
        base_position = np.array([0.2, -0.1, 0.5])
        positions = np.zeros(skel.getNumDofs())
        positions[:3], positions[3:6] = r, base_position
        velocities = np.zeros_like(positions)
        velocities[:3] = w_b
        accelerations = np.zeros_like(positions)
        accelerations[:3], accelerations[3:6] = alpha_b, a_b
        positions[idx], velocities[idx], accelerations[idx] = q, qd, qdd
        skel.setPositions(positions)
        skel.setVelocities(velocities)
        skel.setAccelerations(accelerations)
        skel.computeInverseDynamics(False, False, False)
        forces = np.array(skel.getForces())
        base = dict(base_position=base_position, base_orientation=quat, base_angular_velocity=R @ w_b)
        f = robot.floating_base_inverse_dynamics(q, qd, qdd, base_linear_acceleration=R @ a_b,
                                                  base_angular_acceleration=R @ alpha_b, damping=False,
                                                  friction=False, **base)
        wrench_dart = np.concatenate([R @ forces[3:6], R @ forces[:3]])
        wrench = np.concatenate([f["force"], f["torque"]])
        worst[0] = max(worst[0], np.abs(f["efforts"] - forces[idx]).max())
        worst[1] = max(worst[1], np.abs(wrench - wrench_dart).max())
        largest[0] = max(largest[0], np.abs(forces[idx]).max())
        largest[1] = max(largest[1], np.abs(wrench_dart).max())
        # Free: Fulcrum's base acceleration and efforts, then DART's forward dynamics with them.
        free = robot.floating_base_inverse_dynamics(q, qd, qdd, damping=False, friction=False, **base)
        applied = np.zeros_like(positions)
        applied[idx] = free["efforts"]
        skel.setForces(applied)
        skel.computeForwardDynamics()
        acc = np.array(skel.getAccelerations())
        base_dart = np.concatenate([R @ acc[3:6], R @ acc[:3]])
        base_fulcrum = np.concatenate([free["linear_acceleration"], free["angular_acceleration"]])
        worst[2] = max(worst[2], np.abs(base_fulcrum - base_dart).max())
        worst[3] = max(worst[3], np.abs(acc[idx] - qdd).max())
        largest[2] = max(largest[2], np.abs(base_dart).max(), np.abs(qdd).max())
    return worst, largest


def floating_copy(path, folder):
    """A copy of the URDF whose root is a link with mass: a root named 'world'
    (the fixed-base convention) and the joints from it are dropped, and a root
    without an inertial gets 2 kg (DART and Fulcrum give a missing inertial
    different defaults)."""
    tree = ET.parse(path)
    robot = tree.getroot()
    for joint in list(robot.iter("joint")):
        if joint.find("parent").get("link") == "world":
            robot.remove(joint)
    for link in list(robot.iter("link")):
        if link.get("name") == "world":
            robot.remove(link)
    children = {j.find("child").get("link") for j in robot.iter("joint")}
    for link in robot.iter("link"):
        if link.get("name") not in children and link.find("inertial") is None:
            inertial = ET.SubElement(link, "inertial")
            ET.SubElement(inertial, "mass", value="2")
            ET.SubElement(inertial, "inertia", ixx="0.02", iyy="0.03", izz="0.04", ixy="0", ixz="0", iyz="0")
    out = pathlib.Path(folder) / (path.stem + "_floating.urdf")
    tree.write(out)
    return out


def damped_copy(path, folder):
    """A copy of the URDF with joint damping 0.3 + 0.1 k on its k-th movable joint."""
    tree = ET.parse(path)
    k = 0
    for joint in tree.getroot().iter("joint"):
        if joint.get("type") in ("revolute", "continuous", "prismatic"):
            for e in joint.findall("dynamics"):
                joint.remove(e)
            ET.SubElement(joint, "dynamics", damping=f"{0.3 + 0.1 * k:g}")
            k += 1
    out = pathlib.Path(folder) / (path.stem + "_damped.urdf")
    tree.write(out)
    return out


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
        for damping in (False, True):
            names, worst, largest = inverse_dynamics(damped_copy(path, folder) if damping else path, damping=damping)
            print(f"{label}: inverse dynamics along a sine trajectory of every joint (41 samples over 2 s)"
                  f"{', joint damping 0.3 + 0.1 k' if damping else ''}: worst difference, and the largest effort (N m)")
            for n, w, big in zip(names, worst, largest):
                print(f"  {n:16s} worst difference {w:.2e}   largest effort {big:9.4f}   "
                      f"(relative to it {w / max(big, 1e-12):.1e}; to the robot's largest {w / largest.max():.1e})")
        worst, largest = floating_inverse_dynamics(floating_copy(path, folder))
        print(f"{label}: floating base (root with mass, turned and spinning), sine trajectory (21 samples): worst "
              f"difference / largest value")
        print(f"  prescribed base: efforts {worst[0]:.2e} / {largest[0]:.3g} N m; base wrench {worst[1]:.2e} / "
              f"{largest[1]:.3g}")
        print(f"  free base (DART's forward dynamics of Fulcrum's efforts): base acceleration {worst[2]:.2e}, "
              f"joint accelerations {worst[3]:.2e} / {largest[2]:.3g}")
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
