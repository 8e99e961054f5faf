"""Robots from URDF files in Python (docs/robots.md): load_urdf, bulk drives
and read-outs as arrays, IMU samples, the scene entry and the command line.
The public robot files are read from the shared folder beside the checkout
(FULCRUM_ROBOTS_DIR overrides it); they are never copied into the project."""
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import fulcrum

REPO = pathlib.Path(__file__).resolve().parents[2]


def robots_dir():
    if "FULCRUM_ROBOTS_DIR" in os.environ:
        return pathlib.Path(os.environ["FULCRUM_ROBOTS_DIR"])
    for up in (REPO.parent, REPO.parent.parent):
        if (up / "shared" / "robots").is_dir():
            return up / "shared" / "robots"
    pytest.fail("the shared robot files are not beside the checkout (shared/robots); set FULCRUM_ROBOTS_DIR")


def z_up_world():
    world = fulcrum.World(gravity=(0, 0, -9.81))
    world.create_body(shape=fulcrum.Plane((0, 0, 1), 0), type="static", name="ground")
    return world


def test_kr5_held_by_drives_reads_as_arrays():
    world = fulcrum.World(gravity=(0, 0, -9.81))
    with pytest.warns(UserWarning, match=r"link 'base_link', collision: mesh 'meshes/base_link.STL' not found"):
        arm = fulcrum.load_urdf(world, robots_dir() / "kr5" / "kr5_sixx_r650.urdf", fixed_base=True)
    assert len(arm.joint_names) == 6
    n = len(arm.joint_names)
    arm.set_drive_gains(np.full(n, 3000.0), np.full(n, 100.0))
    target = np.array([0.2, 0.4, -0.3, 0.1, 0.3, 0.0])
    arm.set_position_targets(target)
    for _ in range(600):
        world.step(1 / 60)
    q, v, e = arm.joint_positions(), arm.joint_velocities(), arm.joint_efforts()
    assert q.shape == v.shape == e.shape == (n,)
    assert np.all(np.isfinite(q)) and np.all(np.isfinite(e))
    assert np.allclose(v, 0, atol=1e-3)
    # The stiff drives sag less than 0.02 rad under the arm's weight.
    assert np.allclose(q, target, atol=0.02)
    # The shoulder's pitch joint carries a real load; a joint handle reads the same.
    assert abs(e[1]) > 1
    assert arm.joint(arm.joint_names[1]).effort == pytest.approx(e[1])
    assert arm.body("base_link").type == "static" or arm.body("world").type == "static"
    f, w = arm.sample_imu()
    assert f.shape == (len(arm.link_names), 3) and w.shape == f.shape


def test_imu_of_a_free_fall_and_of_a_resting_link():
    world = fulcrum.World(gravity=(0, 0, -9.81))
    robot = fulcrum.load_urdf(world, REPO / "tests" / "robots" / "slider_load.urdf", fixed_base=True)
    robot.set_drive("lift", position=0.0, stiffness=20000, damping=400)
    for _ in range(300):
        world.step(1 / 60)
    robot.sample_imu()
    world.step(1 / 60)
    f, w = robot.sample_imu()
    # Both links at rest: the accelerometer reads +g up.
    assert f[:, 2] == pytest.approx([9.81, 9.81], abs=1e-2)
    assert robot.joint_efforts()[0] == pytest.approx(2.5 * 9.81, rel=5e-3)


def test_bad_files_raise_errors_naming_them(tmp_path):
    world = z_up_world()
    with pytest.raises(fulcrum.Error, match="invalid.urdf"):
        fulcrum.load_urdf(world, robots_dir() / "dart-tests" / "invalid.urdf")
    loop = tmp_path / "loop.urdf"
    loop.write_text("""<robot name="r">
      <link name="a"/><link name="b"/>
      <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
      <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>
    </robot>""")
    with pytest.raises(fulcrum.Error, match=r"loop.urdf.*loop"):
        fulcrum.load_urdf(world, loop)
    with pytest.raises(fulcrum.Error, match="no link named 'nope'"):
        fulcrum.load_urdf(world, REPO / "tests" / "robots" / "slider_load.urdf", fixed_base=True).body("nope")
    robot = fulcrum.load_urdf(world, REPO / "tests" / "robots" / "double_pendulum.urdf", fixed_base=True,
                              position=(5, 0, 0))
    with pytest.raises(fulcrum.Error, match="3 position targets for 2 actuated joints"):
        robot.set_position_targets([0, 0, 0])


def test_scene_entry_with_drives_loads_and_holds():
    world = fulcrum.load_scene(REPO / "scenes" / "robot_arm.json")
    shoulder = next(j for j in world.joints() if j.name == "shoulder")
    for _ in range(300):
        world.step(1 / 60)
    assert shoulder.position == pytest.approx(0.7, abs=0.02)
    assert abs(shoulder.velocity) < 1e-2
    assert math.isfinite(shoulder.effort) and abs(shoulder.effort) > 1


def test_cli_runs_a_urdf_and_reports_joint_readouts(cli):
    r = subprocess.run([str(cli), "run", str(robots_dir() / "r2d2" / "07-physics.urdf"), "--steps", "60", "--json"],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    joints = {j["name"]: j for j in report["joints"]}
    assert "gripper_extension" in joints
    for key in ("position", "velocity", "torque"):
        assert key in joints["head_swivel"]
    assert "package://pr2_description" in r.stderr  # the missing meshes are warned about
    bad = subprocess.run([str(cli), "run", str(robots_dir() / "dart-tests" / "invalid.urdf")], capture_output=True, text=True,
                         check=False)
    assert bad.returncode == 2 and "invalid.urdf" in bad.stderr


def test_floating_joint_axes_are_driven_in_bulk(tmp_path):
    # A 2 kg box on a floating joint: every axis a dof, driven to a target;
    # the vertical one sags m g / k, and its effort reads m g (0.5 %).
    urdf = tmp_path / "floating.urdf"
    urdf.write_text(
        '<robot name="r"><link name="base"/>'
        '<link name="box"><inertial><mass value="2"/><inertia ixx="0.02" iyy="0.03" izz="0.04"/></inertial></link>'
        '<joint name="j" type="floating"><parent link="base"/><child link="box"/><origin xyz="0 0 1"/></joint></robot>')
    world = fulcrum.World(gravity=(0, 0, -9.81))
    robot = fulcrum.load_urdf(world, urdf, fixed_base=True)
    assert robot.joint_names == []
    assert robot.dof_names == ["j/x", "j/y", "j/z", "j/rx", "j/ry", "j/rz"]
    k = 20000.0
    robot.set_dof_drive_gains([k, k, k, 40, 40, 40], [400, 400, 400, 2.2, 2.2, 2.2])
    target = np.array([0.1, -0.2, 0.3, 0.2, -0.15, 0.3])
    robot.set_dof_position_targets(target)
    for _ in range(720):
        world.step(1 / 240)
    sag = 2 * 9.81 / k
    q = robot.dof_positions()
    assert q == pytest.approx(target - np.array([0, 0, sag, 0, 0, 0]), abs=1e-4)
    assert robot.dof_velocities() == pytest.approx(np.zeros(6), abs=1e-3)
    assert robot.dof_efforts()[2] == pytest.approx(2 * 9.81, rel=5e-3)
    with pytest.raises(fulcrum.Error, match="5 position targets for 6 degrees of freedom"):
        robot.set_dof_position_targets(np.zeros(5))


def test_inverse_dynamics_holds_the_double_pendulum():
    # Horizontal and still: the shoulder carries both rods (1 kg at 0.5 m and
    # at 1.5 m), the elbow the outer one; the default is gravity compensation
    # at the current pose.
    world = fulcrum.World(gravity=(0, 0, -9.81))
    robot = fulcrum.load_urdf(world, REPO / "tests" / "robots" / "double_pendulum.urdf", fixed_base=True)
    tau = robot.inverse_dynamics()
    assert tau == pytest.approx([-9.81 * 2.0, -9.81 * 0.5], rel=1e-5)
    # Swinging through the horizontal at rest with both joints accelerating:
    # M(0) qdd on top (M11 = 2/12 + 0.25 + 1 + 0.25 + 1, M12 = 1/12 + 0.25 + 0.5, M22 = 1/12 + 0.25).
    qdd = np.array([1.0, -2.0])
    m11, m12, m22 = 2 / 12 + 2.5, 1 / 12 + 0.75, 1 / 12 + 0.25
    expected = np.array([-19.62 + m11 * 1.0 + m12 * -2.0, -4.905 + m12 * 1.0 + m22 * -2.0])
    assert robot.inverse_dynamics([0, 0], [0, 0], qdd) == pytest.approx(expected, rel=1e-5)


def test_slider_friction_decelerates_a_sliding_body():
    # No gravity: a 2 kg body sliding at 3 m/s along a slider with 4 N of
    # friction slows at F / m = 2 m/s^2 and stops after 1.5 s.
    world = fulcrum.World(gravity=(0, 0, 0))
    body = world.create_body(shape=fulcrum.Sphere(0.1), mass=2.0)
    world.create_slider_joint(None, body, anchor=(0, 0, 0), axis=(1, 0, 0), friction_force=4.0)
    body.linear_velocity = (3.0, 0, 0)
    for _ in range(120):
        world.step(1 / 240)
    assert body.linear_velocity[0] == pytest.approx(3.0 - 2.0 * 0.5, rel=1e-2)
    for _ in range(360):
        world.step(1 / 240)
    assert abs(body.linear_velocity[0]) < 1e-4
    assert body.position[0] == pytest.approx(3.0 ** 2 / (2 * 2.0), rel=1e-2)


TWO_BODIES = """<robot name="two"><link name="base"><inertial><mass value="2"/>
<inertia ixx="0.03" iyy="0.04" izz="0.05"/></inertial></link>
<link name="arm"><inertial><origin xyz="0.4 0 0"/><mass value="1"/>
<inertia ixx="0.002" iyy="0.01" izz="0.01"/></inertial></link>
<joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
<dynamics damping="0.3" friction="0.7"/></joint></robot>"""


def test_inverse_dynamics_damping_friction_and_floating_base(tmp_path):
    path = tmp_path / "two.urdf"
    path.write_text(TWO_BODIES)
    world = fulcrum.World(gravity=(0, 0, -9.81))
    fixed = fulcrum.load_urdf(world, path, fixed_base=True)
    rigid = fixed.inverse_dynamics([0.2], [1.5], [2.0], damping=False, friction=False)
    assert rigid[0] == pytest.approx((0.01 + 0.16) * 2.0, rel=1e-5)
    assert fixed.inverse_dynamics([0.2], [1.5], [2.0])[0] - rigid[0] == pytest.approx(0.3 * 1.5 + 0.7, rel=1e-5)
    # Floating: the closed form of two bodies about a common axis (tests/robots/inverse_dynamics_test.cpp).
    world2 = fulcrum.World(gravity=(0, 0, -9.81))
    free = fulcrum.load_urdf(world2, path)
    m1, m2, i1, i2, L = 2.0, 1.0, 0.05, 0.01, 0.4
    J = i2 + m1 * m2 / (m1 + m2) * L * L
    d = free.floating_base_inverse_dynamics([0.3], [0.0], [2.0], base_angular_velocity=(0, 0, 0),
                                            damping=False, friction=False)
    assert d["efforts"][0] == pytest.approx(J * i1 * 2.0 / (i1 + J), rel=1e-5)
    assert d["angular_acceleration"][2] == pytest.approx(-J * 2.0 / (i1 + J), rel=1e-5)
    assert d["linear_acceleration"][2] == pytest.approx(-9.81, rel=1e-6)
    held = free.floating_base_inverse_dynamics([0.3], [0.0], [2.0], base_angular_velocity=(0, 0, 0),
                                               base_linear_acceleration=(0, 0, 0), damping=False, friction=False)
    assert held["torque"][2] == pytest.approx((i2 + m2 * L * L) * 2.0, rel=1e-5)
    assert held["force"][2] == pytest.approx((m1 + m2) * 9.81, rel=1e-5)


ARM = """<robot name="arm"><link name="base"/>
<link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>
<inertia ixx="0.001" iyy="0.001" izz="0.001"/></inertial></link>
<joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 1"/>
<axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="6" velocity="5"/></joint></robot>"""


def test_effort_limit_caps_the_position_drive(tmp_path):
    # m g l = 9.81 N m against an effort limit of 6: a stiff drive holding
    # the arm level gives way with (m g l - 6) / I; the bulk limit 20 holds it.
    path = tmp_path / "arm.urdf"
    path.write_text(ARM)
    inertia = 0.001 + 2 * 0.25
    for limit, held in ((None, False), (20.0, True)):
        world = fulcrum.World(gravity=(0, 0, -9.81))
        robot = fulcrum.load_urdf(world, path, fixed_base=True)
        robot.set_drive_gains([20000.0], [200.0])
        if limit is not None:
            robot.set_drive_max_forces([limit])
        # Measured from 0.05 s to 0.1 s, after the soft joint rows' first transient.
        for _ in range(12):
            world.step(1 / 240)
        w0 = robot.body("arm").angular_velocity[1]
        for _ in range(6):
            world.step(1 / 240)
        angle = robot.joint_positions()[0]
        for _ in range(6):
            world.step(1 / 240)
        if held:
            assert abs(robot.joint_positions()[0]) < 2e-3
        else:
            alpha = (robot.body("arm").angular_velocity[1] - w0) / 0.05
            assert alpha == pytest.approx((9.81 * math.cos(angle) - 6) / inertia, rel=0.01)
            assert abs(robot.joint_efforts()[0]) <= 6 * (1 + 1e-5)


def test_joint_spring_max_force():
    world = fulcrum.World(gravity=(0, -9.81, 0))
    box = world.create_body(shape=fulcrum.Box((0.1, 0.1, 0.1)), mass=3.0, position=(0, 0, 0))
    j = world.create_slider_joint(None, box, anchor=(0, 0, 0), axis=(0, 1, 0), spring_stiffness=1e5,
                                  spring_damping=500, spring_max_force=0.5 * 3 * 9.81)
    for _ in range(12):
        world.step(1 / 60)
    assert -box.linear_velocity[1] / 0.2 == pytest.approx(9.81 / 2, rel=0.01)
    j.set_spring(0, 1e5, 500, max_force=2 * 3 * 9.81)
    with pytest.raises(fulcrum.Error, match="spring.maxForce"):
        j.set_spring(0, 1e5, 500, max_force=-1)


def glb_json(path):
    data = pathlib.Path(path).read_bytes()
    length = int.from_bytes(data[12:16], "little")
    return json.loads(data[20:20 + length])


def test_recordings_draw_robot_visuals(tmp_path, cli):
    # load_urdf's links are drawn as their URDF visuals (docs/robots.md, "Visuals").
    world = z_up_world()
    fulcrum.load_urdf(world, REPO / "scenes" / "quadruped.urdf", position=(0, 0, 0.4))
    recorder = fulcrum.Recorder(world)
    for _ in range(3):
        world.step(1 / 60)
        recorder.capture()
    recorder.write(tmp_path / "quadruped.glb")
    names = [n.get("name", "") for n in glb_json(tmp_path / "quadruped.glb")["nodes"]]
    assert sum("_visual" in n for n in names) == 14
    # And the command line's: R2D2's page carries its visuals.
    page = tmp_path / "r2d2.html"
    r = subprocess.run([str(cli), "run", str(robots_dir() / "r2d2" / "07-physics.urdf"), "--steps", "10", "--record", str(page)],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    assert '"visuals":[{"color"' in page.read_text()
