"""The six-DOF joint, the cone-twist drive and contact forces per body from
Python (docs/joints.md, "Six-DOF" and "Cone-twist drive"; docs/robots.md)."""
import math

import numpy as np
import pytest

import fulcrum


def test_six_dof_spring_axis_oscillates_with_the_analytic_period():
    world = fulcrum.World(gravity=(0, 0, 0))
    box = world.create_body(shape=fulcrum.Box((0.1, 0.1, 0.1)), mass=2)
    joint = world.create_six_dof_joint(None, box, anchor=(0, 0, 0), axes={
        "x": {"spring": {"target": -0.1, "stiffness": 200}}})
    assert joint.type == "six_dof"
    xs = []
    for _ in range(120):
        world.step(1 / 60)
        xs.append(joint.axes["position"][0])
    xs = np.array(xs) + 0.1
    up = [i + xs[i] / (xs[i] - xs[i + 1]) for i in range(len(xs) - 1) if xs[i] < 0 <= xs[i + 1]]
    period = (up[-1] - up[0]) / (len(up) - 1) / 60
    assert period == pytest.approx(2 * math.pi * math.sqrt(2 / 200), rel=0.01)
    assert abs(box.position[1]) < 1e-4 and abs(box.position[2]) < 1e-4


def test_six_dof_axis_settings_and_errors():
    world = fulcrum.World(gravity=(0, 0, 0))
    box = world.create_body(shape=fulcrum.Box((0.1, 0.1, 0.1)), mass=1)
    joint = world.create_six_dof_joint(None, box, anchor=(0, 0, 0), axes={"rz": "free"})
    joint.set_axis("rz", {"motor": {"speed": 2, "max_force": 50}})
    for _ in range(60):
        world.step(1 / 60)
    assert joint.axes["velocity"][5] == pytest.approx(2, rel=0.01)
    with pytest.raises(fulcrum.Error, match="mode"):
        joint.set_axis("x", "free")  # created locked
    with pytest.raises(fulcrum.Error, match=r"axes\[x\]\.lower"):
        world.create_six_dof_joint(None, box, anchor=(0, 0, 0), axes={"y": {"limits": (1, 2)}, "x": {"limits": (0.5, -0.5)}})
    with pytest.raises(fulcrum.Error, match="not one of"):
        world.create_six_dof_joint(None, box, anchor=(0, 0, 0), axes={"w": "free"})


def test_cone_twist_drive_holds_a_lever_with_m_g_l():
    world = fulcrum.World(sleeping=False)  # a held lever would fall asleep, and a sleeping joint reports no reaction
    ball = world.create_body(shape=fulcrum.Sphere(0.05), mass=2, position=(0.8, 0, 0))
    joint = world.create_cone_twist_joint(None, ball, anchor=(0, 0, 0), axis=(1, 0, 0), swing_limit=math.pi,
                                          twist_limits=(-math.pi, math.pi))
    joint.set_drive((1, 0, 0, 0))
    for _ in range(120):
        world.step(1 / 60)
    assert joint.reaction_torque[2] == pytest.approx(2 * 9.81 * 0.8, rel=0.01)
    joint.set_drive(None)
    for _ in range(30):
        world.step(1 / 60)
    assert ball.position[1] < -0.05


def test_contact_force_of_a_resting_box_is_its_weight():
    world = fulcrum.World()
    world.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static")
    box = world.create_body(shape=fulcrum.Box((0.25, 0.25, 0.25)), mass=3, position=(0, 0.25, 0))
    for _ in range(120):
        world.step(1 / 60)
    assert world.contact_force(box)[1] == pytest.approx(3 * 9.81, rel=0.005)
    forces = world.contact_forces([box, box])
    assert forces.shape == (2, 3)
    assert forces[1][1] == pytest.approx(3 * 9.81, rel=0.005)


def test_robot_contact_forces_and_planar_joint(tmp_path):
    urdf = tmp_path / "planar.urdf"
    urdf.write_text(
        '<robot name="p"><link name="base"/>'
        '<link name="box"><inertial><mass value="2"/><inertia ixx="0.02" iyy="0.03" izz="0.04"/></inertial>'
        '<collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>'
        '<joint name="plane" type="planar"><parent link="base"/><child link="box"/>'
        '<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/></joint></robot>')
    world = fulcrum.World(gravity=(0, 0, -9.81))
    world.create_body(shape=fulcrum.Plane((0, 0, 1), 0), type="static")
    robot = fulcrum.load_urdf(world, urdf, fixed_base=True)
    for _ in range(120):
        world.step(1 / 60)
    forces = robot.contact_forces()
    assert forces.shape == (2, 3)
    assert forces[1][2] == pytest.approx(2 * 9.81, rel=0.005)
    assert world.joints()[0].type == "six_dof"


def test_cli_json_reports_six_dof_axes(cli, tmp_path):
    import json
    import subprocess
    scene = tmp_path / "six.json"
    scene.write_text(json.dumps({
        "world": {"gravity": [0, 0, 0]},
        "bodies": [{"name": "box", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "mass": 1,
                    "position": [0, 0, 0]}],
        "joints": [{"name": "six", "type": "six_dof", "body_b": "box", "anchor": [0, 0, 0], "axis": [1, 0, 0],
                    "axes": {"x": {"motor": {"speed": 0.5, "max_force": 100}}, "rz": "free"}}]}))
    r = subprocess.run([str(cli), "run", str(scene), "--steps", "60", "--json"], capture_output=True, text=True,
                       check=False)
    assert r.returncode == 0, r.stderr
    joint = json.loads(r.stdout)["joints"][0]
    assert len(joint["axis_positions"]) == 6 and len(joint["axis_efforts"]) == 6
    assert joint["axis_velocities"][0] == pytest.approx(0.5, rel=0.01)
    assert joint["axis_positions"][0] == pytest.approx(0.5, rel=0.05)
