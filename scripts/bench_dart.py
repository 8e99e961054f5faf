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
# Fulcrum's settings in the swing: its defaults, and joint rows stiffer than the default 60 Hz.
# (label, World settings, step)
FULCRUM_SETTINGS = [("Fulcrum", {}, DT), ("Fulcrum 250 Hz", {"joint_hertz": 250}, DT), ("Fulcrum 1/240 s", {}, 1 / 240)]


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


def swing(path, seconds, pitch=0.0):
    """Steps per second and energy drift of both engines, fixed base, drives and
    limits off; the base turned by `pitch` about y (the minitaur's legs hang
    still in its zero pose: turned nose down, they swing)."""
    steps = int(round(seconds / DT))
    skel = dart_skeleton(path, fixed=True)
    if pitch:
        turn = dart.math.Isometry3()
        c, s = np.cos(pitch), np.sin(pitch)
        turn.set_rotation(np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]))
        skel.getRootJoint().setTransformFromParentBodyNode(turn)
    world = dart.simulation.World()
    world.setGravity([0, 0, -9.81])
    world.setTimeStep(DT)
    world.addSkeleton(skel)
    e0, _ = dart_energy(skel)
    drift, kmax, e = 0.0, 0.0, e0
    start = time.perf_counter()
    for i in range(steps):
        world.step()
        if i % 10 == 9:
            e, k = dart_energy(skel)
            drift, kmax = max(drift, abs(e - e0)), max(kmax, k)
    results = [("DART", steps, time.perf_counter() - start, drift / max(kmax, 1e-12), (e - e0) / max(kmax, 1e-12), kmax)]

    for label, settings, dt in FULCRUM_SETTINGS:
        fulcrum_steps = int(round(seconds / dt))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fw = fulcrum.World(gravity=(0, 0, -9.81), **settings)
            robot = fulcrum.load_urdf(fw, path, fixed_base=True, orientation=(np.cos(pitch / 2), 0, np.sin(pitch / 2), 0))
        for n in robot.joint_names:
            robot.joint(n).set_limits(None)
        robot.disable_drives()
        e0 = fw.energy()["total"]
        drift, kmax, e = 0.0, 0.0, e0
        start = time.perf_counter()
        for i in range(fulcrum_steps):
            fw.step(dt)
            if dt < DT * 2 and i % 10 != 9:
                continue  # sampled every 10 ms, as DART's
            report = fw.energy()
            e = report["total"]
            drift, kmax = max(drift, abs(e - e0)), max(kmax, report["kinetic"])
        results.append((label, fulcrum_steps, time.perf_counter() - start, drift / max(kmax, 1e-12), (e - e0) / max(kmax, 1e-12),
                        kmax))
    return results, len(robot.link_names)


def pile_places(count):
    """Four columns, far enough apart that no two robots start interpenetrating
    (DART stalls on that), each robot 1.1 m above the one below, turned at random."""
    rng = np.random.default_rng(1)
    places = []
    for k in range(count):
        column, layer = k % 4, k // 4
        x, y = 0.8 * (column % 2) - 0.4, 0.8 * (column // 2) - 0.4
        places.append((x, y, 0.6 + 1.1 * layer, rng.uniform(-np.pi, np.pi)))
    return places


def dart_pile(path, count, seconds):
    """DART's wall time for `count` robots dropped onto a ground box; the
    fastest dof at the end and the highest robot's centre of mass."""
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
    for k, (x, y, z, yaw) in enumerate(pile_places(count)):
        skel = dart_skeleton(path, fixed=False)
        skel.setName(f"r2d2_{k}")
        q = np.array(skel.getPositions())
        q[:6] = [0, 0, yaw, x, y, z]
        skel.setPositions(q)
        world.addSkeleton(skel)
        skels.append(skel)
    start = time.perf_counter()
    for i in range(int(round(seconds / DT))):
        world.step()
        if i % 500 == 499:
            print(f"    DART pile: {(i + 1) * DT:.1f} s simulated, {time.perf_counter() - start:.1f} s wall", flush=True)
    wall = time.perf_counter() - start
    return wall, max(np.abs(s.getVelocities()).max() for s in skels), max(s.getCOM()[2] for s in skels)


def fulcrum_pile(path, count, seconds, dt):
    """The same in Fulcrum on a ground plane: wall time, the fastest link at the
    end, the highest robot's centre of mass and the lowest link origin."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fw = fulcrum.World(gravity=(0, 0, -9.81))
        fw.create_body(shape=fulcrum.Plane((0, 0, 1), 0), type="static", name="ground")
        robots = [fulcrum.load_urdf(fw, path, position=(x, y, z), orientation=(np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)))
                  for (x, y, z, yaw) in pile_places(count)]
    start = time.perf_counter()
    for _ in range(int(round(seconds / dt))):
        fw.step(dt)
    wall = time.perf_counter() - start
    links = [[r.body(n) for n in r.link_names] for r in robots]
    speed = max(float(np.abs(b.linear_velocity).max()) for bodies in links for b in bodies)
    lowest = min(float(b.position[2]) for bodies in links for b in bodies)
    top = max(sum(b.mass * np.array(b.center_of_mass) for b in bodies)[2] / sum(b.mass for b in bodies) for bodies in links)
    return wall, speed, top, lowest


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("robots", type=pathlib.Path)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--pile-seconds", type=float, default=5.0)
    parser.add_argument("--skip-swing", action="store_true")
    parser.add_argument("--skip-pile", action="store_true")
    args = parser.parse_args()
    folder = tempfile.mkdtemp()
    cases = [("double pendulum", REPO / "tests" / "robots" / "double_pendulum.urdf", 0.0),
             ("KUKA KR5", strip_meshes(args.robots / "kr5" / "kr5_sixx_r650.urdf", folder, every_element=True), 0.0),
             ("minitaur", strip_meshes(args.robots / "minitaur" / "minitaur.urdf", folder), np.pi / 2)]
    print(f"Swing, fixed base, drives and limits off, {args.seconds:g} s at dt = {DT * 1e3:g} ms "
          "(Fulcrum: 5 sub-steps, joint rows 60 Hz or 250 Hz; DART: its defaults). Drift: the largest |E - E0|, "
          "and E_end - E0, over the largest kinetic energy")
    for label, path, pitch in ([] if args.skip_swing else cases):
        results, links = swing(path, args.seconds, pitch)
        dart_time = results[0][2]
        print(f"{label} ({links} links)")
        for engine, steps, wall, drift, end, kmax in results:
            print(f"  {engine:15s} {steps / wall:8.0f} steps/s, {args.seconds / wall:7.1f} x real time "
                  f"({dart_time / wall:5.2f}x DART's)   drift {100 * drift:7.2f} %   at the end {100 * end:+7.2f} %"
                  f"   (largest kinetic energy {kmax:.3g} J)")
    r2d2 = strip_meshes(args.robots / "r2d2" / "07-physics.urdf", folder)
    if args.skip_pile:
        return
    print(f"Pile: 20 R2D2 (meshes left out) dropped onto a ground, {args.pile_seconds:g} s", flush=True)
    for dt in (DT, 1 / 120):
        wall, speed, top, lowest = fulcrum_pile(r2d2, 20, args.pile_seconds, dt)
        print(f"  Fulcrum dt {dt * 1e3:.3g} ms: {wall:7.2f} s wall ({args.pile_seconds / wall:.2f} x real time), "
              f"fastest link at the end {speed:.3f} m/s, highest robot centre {top:.2f} m, lowest link origin {lowest:.3f} m",
              flush=True)
    wall, speed, top = dart_pile(r2d2, 20, args.pile_seconds)
    print(f"  DART dt 1 ms: {wall:7.2f} s wall ({args.pile_seconds / wall:.2f} x real time), fastest dof at the end "
          f"{speed:.3f}, highest robot centre {top:.2f} m")

if __name__ == "__main__":
    main()
