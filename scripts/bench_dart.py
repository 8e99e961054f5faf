#!/usr/bin/env python3
"""Speed and energy drift of Fulcrum and DART (Debian's python3-dartpy) on the
same URDF robots, and a pile of 20 robots on the ground (docs/benchmarks.md,
"Robots beside DART"; docs/robots.md). Run by hand; not part of the test suite.

Usage: PYTHONPATH=build/release/python /usr/bin/python3 scripts/bench_dart.py ROBOTS_DIR [--seconds S]

ROBOTS_DIR holds kr5/, minitaur/ and r2d2/ (the public robot files); the
double pendulum comes from tests/robots/. Mesh elements are left out of every
file (the public copies have no meshes, and DART refuses a missing one), so
both engines see the same primitives.

Swing: each robot on a fixed base, from its zero pose, drives and limits off,
both engines at the same 1 ms step. Energy drift: the largest |E(t) - E(0)|
over the run, over the largest kinetic energy the robot reached (the energy
it trades). Pile: 20 copies of R2D2 (16 links each, boxes, cylinders and
spheres) dropped in four columns of five onto a ground, 5 s. Timings are wall
clock of one process on a shared machine: noisy; compare the ratio in one run.
"""
import argparse
import pathlib
import sys
import tempfile
import time
import warnings
import xml.etree.ElementTree as ET

import numpy as np

import dartpy as dart
import fulcrum

REPO = pathlib.Path(__file__).resolve().parents[1]
DT = 1e-3


def strip_meshes(path, folder, every_element=False):
    """A copy of the URDF without its mesh geometry (every visual and collision with every_element)."""
    tree = ET.parse(path)
    for link in tree.getroot().iter("link"):
        for tag in ("visual", "collision"):
            for e in link.findall(tag):
                if every_element or e.find("geometry/mesh") is not None:
                    link.remove(e)
    out = pathlib.Path(folder) / (path.stem + "_no_meshes.urdf")
    tree.write(out)
    return out


def dart_skeleton(path, fixed):
    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    options.mDefaultRootJointType = (dart.utils.DartLoaderRootJointType.FIXED if fixed
                                     else dart.utils.DartLoaderRootJointType.FLOATING)
    loader.setOptions(options)
    skel = loader.parseSkeleton(str(path))
    if skel is None:
        sys.exit(f"DART could not load {path}")
    return skel


def dart_energy(skel):
    return skel.computeKineticEnergy() + skel.computePotentialEnergy(), skel.computeKineticEnergy()


def swing(path, seconds):
    """Steps per second and energy drift of both engines, fixed base, drives and limits off."""
    steps = int(round(seconds / DT))
    skel = dart_skeleton(path, fixed=True)
    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    world.setTimeStep(DT)
    world.addSkeleton(skel)
    e0, _ = dart_energy(skel)
    drift, kmax = 0.0, 0.0
    start = time.perf_counter()
    for i in range(steps):
        world.step()
        if i % 10 == 9:
            e, k = dart_energy(skel)
            drift, kmax = max(drift, abs(e - e0)), max(kmax, k)
    dart_time = time.perf_counter() - start
    dart_drift = drift / max(kmax, 1e-12)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fw = fulcrum.World(gravity=(0, 0, -9.81))
        robot = fulcrum.load_urdf(fw, path, fixed_base=True)
    for n in robot.joint_names:
        robot.joint(n).set_limits(None)
    robot.disable_drives()
    e0 = fw.energy()["total"]
    drift, kmax = 0.0, 0.0
    start = time.perf_counter()
    for i in range(steps):
        fw.step(DT)
        if i % 10 == 9:
            e = fw.energy()
            drift, kmax = max(drift, abs(e["total"] - e0)), max(kmax, e["kinetic"])
    fulcrum_time = time.perf_counter() - start
    return steps, dart_time, dart_drift, fulcrum_time, drift / max(kmax, 1e-12), len(robot.link_names)


def pile(path, count, seconds, fulcrum_dt):
    """Wall time of `count` robots dropped onto a ground, in four columns."""
    rng = np.random.default_rng(1)
    places = []
    for k in range(count):
        column, layer = k % 4, k // 4
        x, y = 0.8 * (column % 2) - 0.4, 0.8 * (column // 2) - 0.4  # apart: DART stalls on robots that start interpenetrating
        places.append((x, y, 0.6 + 1.1 * layer, rng.uniform(-np.pi, np.pi)))

    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    world.setTimeStep(DT)
    ground = dart.dynamics.Skeleton("ground")
    joint, body = ground.createWeldJointAndBodyNodePair()
    node = body.createShapeNode(dart.dynamics.BoxShape([20, 20, 1]))
    node.createCollisionAspect()
    node.createDynamicsAspect()
    below = dart.math.Isometry3()
    below.set_translation([0, 0, -0.5])
    joint.setTransformFromParentBodyNode(below)
    world.addSkeleton(ground)
    skels = []
    for k, (x, y, z, yaw) in enumerate(places):
        skel = dart_skeleton(path, fixed=False)
        skel.setName(f"r2d2_{k}")
        q = np.array(skel.getPositions())
        q[:6] = [0, 0, yaw, x, y, z]
        skel.setPositions(q)
        world.addSkeleton(skel)
        skels.append(skel)
    start = time.perf_counter()
    for _ in range(int(round(seconds / DT))):
        world.step()
    dart_time = time.perf_counter() - start
    dart_speed = max(np.abs(s.getVelocities()).max() for s in skels)
    dart_top = max(s.getCOM()[2] for s in skels)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fw = fulcrum.World(gravity=(0, 0, -9.81))
        fw.create_body(shape=fulcrum.Plane((0, 0, 1), 0), type="static", name="ground")
        robots = [fulcrum.load_urdf(fw, path, position=(x, y, z), orientation=(np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)))
                  for (x, y, z, yaw) in places]
    start = time.perf_counter()
    for _ in range(int(round(seconds / fulcrum_dt))):
        fw.step(fulcrum_dt)
    fulcrum_time = time.perf_counter() - start
    bodies = [r.body(n) for r in robots for n in r.link_names]
    fulcrum_speed = max(float(np.abs(b.linear_velocity).max()) for b in bodies)
    lowest = min(float(b.position[2]) for b in bodies)
    masses = [[(b.mass, np.array(b.center_of_mass)) for b in (r.body(n) for n in r.link_names)] for r in robots]
    fulcrum_top = max(sum(m * p for m, p in ms)[2] / sum(m for m, _ in ms) for ms in masses)
    return dart_time, dart_speed, dart_top, fulcrum_time, fulcrum_speed, fulcrum_top, lowest


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("robots", type=pathlib.Path)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    folder = tempfile.mkdtemp()
    cases = [("double pendulum", REPO / "tests" / "robots" / "double_pendulum.urdf"),
             ("KUKA KR5", strip_meshes(args.robots / "kr5" / "kr5_sixx_r650.urdf", folder, every_element=True)),
             ("minitaur", strip_meshes(args.robots / "minitaur" / "minitaur.urdf", folder))]
    print(f"Swing, fixed base, drives and limits off, {args.seconds:g} s at dt = {DT * 1e3:g} ms "
          "(Fulcrum: 5 sub-steps, joint rows 60 Hz; DART: its defaults)")
    print(f"{'robot':16s} {'links':>5s} {'DART steps/s':>13s} {'Fulcrum steps/s':>16s} {'ratio F/D':>10s} "
          f"{'DART drift':>11s} {'Fulcrum drift':>14s}")
    for label, path in cases:
        steps, dt_, dd, ft, fd, links = swing(path, args.seconds)
        print(f"{label:16s} {links:5d} {steps / dt_:13.0f} {steps / ft:16.0f} {dt_ / ft:10.2f} "
              f"{100 * dd:10.3f}% {100 * fd:13.3f}%")
    r2d2 = strip_meshes(args.robots / "r2d2" / "07-physics.urdf", folder)
    print("Pile: 20 R2D2 (meshes left out) dropped onto a ground, 5 s")
    for fulcrum_dt in (DT, 1 / 120):
        dt_, dv, dtop, ft, fv, ftop, lowest = pile(r2d2, 20, 5.0, fulcrum_dt)
        print(f"  DART dt 1 ms: {dt_:7.2f} s wall, fastest dof at the end {dv:.3f}, highest robot centre {dtop:.2f} m")
        print(f"  Fulcrum dt {fulcrum_dt * 1e3:.3g} ms: {ft:7.2f} s wall ({dt_ / ft:.1f}x DART's speed), fastest link "
              f"{fv:.3f} m/s, highest robot centre {ftop:.2f} m, lowest link origin {lowest:.3f} m")


if __name__ == "__main__":
    main()
