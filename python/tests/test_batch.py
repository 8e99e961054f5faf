"""fulcrum.Batch (docs/python.md, "Batches"): each world of a batch gives bit for
bit its result alone, whatever the count and the threads; resets restore bit for
bit; arrays in and out have the documented shapes; bad input names itself."""
import copy

import numpy as np
import pytest

import fulcrum

DT = 1 / 60
STEPS = 40

SCENE = {
    "world": {"gravity": [0, -9.81, 0], "substeps": 4},
    "bodies": [
        {"name": "ground", "type": "static", "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "position": [0, -0.5, 0]},
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.25}, "mass": 1, "position": [2, 1.5, 0], "restitution": 0.5},
        {"name": "box0", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1, "position": [0, 0.5, 0]},
        {"name": "box1", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1, "position": [0.1, 1.5, 0]},
        {"name": "door", "shape": {"type": "box", "half_extents": [0.5, 1, 0.05]}, "mass": 10, "position": [-3, 3, 0]},
    ],
    "joints": [
        {"name": "hinge", "type": "hinge", "body_a": None, "body_b": "door", "anchor": [-3.5, 3, 0], "axis": [0, 1, 0],
         "motor": {"speed": 1.0, "max_force": 50}},
    ],
}


def overrides(i):
    return {"bodies[ball].restitution": 0.05 * (i % 20), "world.gravity": [0, -9.81 + 0.1 * i, 0]}


def edited(i):
    """The scene of world i written out by hand, as a user would without overrides."""
    scene = copy.deepcopy(SCENE)
    scene["bodies"][1]["restitution"] = 0.05 * (i % 20)
    scene["world"]["gravity"] = [0, -9.81 + 0.1 * i, 0]
    return scene


def alone(i, steps):
    world = fulcrum.load_scene(edited(i))
    world.step(DT, steps=steps)
    return world


@pytest.mark.parametrize("count", [1, 3, 17])
@pytest.mark.parametrize("threads", [1, 2, 3])
def test_each_world_equals_its_run_alone(count, threads):
    batch = fulcrum.Batch(SCENE, count=count, overrides=[overrides(i) for i in range(count)], threads=threads)
    batch.step(DT, steps=STEPS)
    p, q, v, w = batch.positions(), batch.orientations(), batch.linear_velocities(), batch.angular_velocities()
    assert p.shape == (count, 5, 3) and q.shape == (count, 5, 4) and p.dtype == np.float64
    for i in range(count):
        ref = alone(i, STEPS)
        assert p[i].tobytes() == ref.positions().tobytes(), i
        assert q[i].tobytes() == ref.orientations().tobytes(), i
        assert v[i].tobytes() == ref.linear_velocities().tobytes(), i
        assert w[i].tobytes() == ref.angular_velocities().tobytes(), i
    # The worlds moved, and differ: the comparison above compares something.
    assert p[0, 1, 1] < 1.0
    if count > 1:
        assert p[0, 1, 1] != p[1, 1, 1]


def test_reset_to_start_and_to_a_snapshot_bit_for_bit():
    batch = fulcrum.Batch(SCENE, count=2, overrides=[overrides(0), overrides(1)], threads=2)
    start = batch.positions()
    batch.step(DT, steps=10)
    snap, mid = batch.snapshot(1), batch.positions()
    batch.step(DT, steps=15)
    batch.reset(0)
    batch.reset(1, snap)
    now = batch.positions()
    assert now[0].tobytes() == start[0].tobytes()
    assert now[1].tobytes() == mid[1].tobytes()
    batch.step(DT, steps=STEPS - 10)
    now = batch.positions()
    assert now[0].tobytes() == alone(0, STEPS - 10).positions().tobytes()
    assert now[1].tobytes() == alone(1, STEPS).positions().tobytes()
    # A World's own snapshot works too.
    batch.reset(0, alone(1, 5).save_snapshot())
    assert batch.positions()[0].tobytes() == alone(1, 5).positions().tobytes()


def test_actions_from_arrays():
    batch = fulcrum.Batch(SCENE, count=2)
    ref = fulcrum.load_scene(SCENE)
    velocities = np.zeros((2, 5, 3))
    velocities[0, 1] = (3, 0, 0)
    forces = np.zeros((2, 5, 3))
    forces[1, 1] = (0, 50, 0)  # more than the ball's weight: it rises
    speeds = np.array([[-2.0], [1.0]])
    batch.set_linear_velocities(velocities)
    batch.apply_forces(forces)
    batch.set_joint_motor_speeds(speeds)
    batch.step(DT)
    ref.set_linear_velocities(np.zeros((4, 3)), indices=[1, 2, 3, 4])
    ref.find_body("ball").linear_velocity = (3, 0, 0)
    ref.joints()[0].set_motor(-2.0, max_force=50)
    ref.step(DT)
    assert batch.positions()[0].tobytes() == ref.positions().tobytes()
    assert batch.positions()[1, 1, 1] > 1.5
    assert batch.angular_velocities()[1, 4, 1] > 0 > batch.angular_velocities()[0, 4, 1]


def test_list_of_scenes_and_a_dict_for_every_world():
    other = {"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "mass": 2, "position": [0, 3, 0]}]}
    batch = fulcrum.Batch([other, other])
    batch.step(DT, steps=5)
    assert batch.positions()[1].tobytes() == alone_scene(other, 5).positions().tobytes()
    same = fulcrum.Batch(SCENE, count=3, overrides={"bodies[ball].mass": 4})
    assert len(same) == 3


def alone_scene(scene, steps):
    world = fulcrum.load_scene(scene)
    world.step(DT, steps=steps)
    return world


def test_bad_input_names_itself():
    batch = fulcrum.Batch(SCENE, count=2)
    with pytest.raises(fulcrum.Error, match=r"set_linear_velocities: expected an array of shape \(2, 5, 3\) .* got shape \(5, 3\)"):
        batch.set_linear_velocities(np.zeros((5, 3)))
    with pytest.raises(fulcrum.Error, match=r"set_joint_motor_speeds: expected an array of shape \(2, 1\)"):
        batch.set_joint_motor_speeds([1.0, 2.0])
    with pytest.raises(fulcrum.Error, match="world index 2 out of range"):
        batch.reset(2)
    with pytest.raises(fulcrum.SceneError, match=r"bodies\[bal\].mass: no element named 'bal'"):
        fulcrum.Batch(SCENE, overrides=[{"bodies[bal].mass": 1}])
    with pytest.raises(fulcrum.SceneError, match=r"bodies\[ball\].restitution: value -1 refused"):
        fulcrum.Batch(SCENE, overrides=[{}, {"bodies[ball].restitution": -1}])
    with pytest.raises(fulcrum.Error, match="2 overrides for count=3"):
        fulcrum.Batch(SCENE, count=3, overrides=[{}, {}])
    with pytest.raises(fulcrum.Error, match=r"world 1 has 1 bodies, world 0 has 5"):
        fulcrum.Batch([SCENE, {"bodies": [SCENE["bodies"][1]]}]).positions()
