"""The rest of the API through Python, each against what the physics or the
C++ API says: joints (motors, limits, springs, breaking), springs, queries,
events, ropes and cloths, energy and momentum, recordings."""
import math

import numpy as np
import pytest

import fulcrum

DT = 1 / 60


def test_hinge_motor_reaches_its_speed():
    # A free wheel (no gravity) driven by a strong motor spins at the motor's speed (1 %).
    w = fulcrum.World(gravity=(0, 0, 0), sleeping=False)
    wheel = w.create_body(shape=fulcrum.Cylinder(0.5, 0.1), mass=1)
    hinge = w.create_hinge_joint(None, wheel, anchor=(0, 0, 0), axis=(0, 1, 0), motor_speed=2.0, max_motor_force=100)
    w.step(DT, steps=60)
    assert wheel.angular_velocity[1] == pytest.approx(2.0, rel=0.01)
    assert hinge.position == pytest.approx(2.0 * w.time, abs=0.1)   # the angle grows at the motor speed
    hinge.set_motor(None)                                             # off: it keeps spinning freely
    w.step(DT, steps=10)
    assert wheel.angular_velocity[1] == pytest.approx(2.0, rel=0.01)


def test_slider_limit_stops_a_falling_body():
    w = fulcrum.World(sleeping=False)
    body = w.create_body(shape=fulcrum.Box((0.1, 0.1, 0.1)), mass=1, position=(0, 0, 0))
    slider = w.create_slider_joint(None, body, anchor=(0, 0, 0), axis=(0, 1, 0), limits=(-0.5, 0.5))
    w.step(DT, steps=120)
    assert body.position[1] == pytest.approx(-0.5, abs=0.01)
    assert slider.position == pytest.approx(-0.5, abs=0.01)
    assert abs(body.position[0]) < 1e-4 and abs(body.position[2]) < 1e-4   # stays on its axis
    # The joint holds the weight: the reaction on the body is m g upwards (2 %).
    assert slider.reaction_force[1] == pytest.approx(9.81, rel=0.02)


def test_hinge_spring_oscillates_at_its_frequency():
    # A rod on a hinge with a torsion spring k, no gravity: period 2 pi sqrt(I / k) (2 %).
    w = fulcrum.World(gravity=(0, 0, 0), sleeping=False, substeps=8)
    rod = w.create_body(shape=fulcrum.Sphere(0.2), mass=1, angular_velocity=(0, 0.5, 0))
    inertia = rod.inertia[1, 1]
    k = 1.0
    hinge = w.create_hinge_joint(None, rod, anchor=(0, 0, 0), axis=(0, 1, 0), spring_stiffness=k)
    crossings, prev = [], hinge.position
    for i in range(600):
        w.step(DT)
        now = hinge.position
        if prev < 0 <= now:
            crossings.append((i + prev / (prev - now)) * DT)
        prev = now
    period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    assert period == pytest.approx(2 * math.pi * math.sqrt(inertia / k), rel=0.02)


def test_joint_breaks_above_its_threshold():
    w = fulcrum.World(sleeping=False)
    heavy = w.create_body(shape=fulcrum.Box((0.2, 0.2, 0.2)), mass=10, position=(0, 1, 0), name="heavy")
    joint = w.create_fixed_joint(None, heavy, anchor=(0, 1, 0), break_force=50, name="weak")  # weight 98 N > 50 N
    w.step(DT)
    events = w.joint_break_events()
    assert joint.broken and not joint.enabled
    assert len(events) == 1 and events[0]["joint"] == joint and events[0]["body_b"] == heavy
    assert np.linalg.norm(events[0]["force"]) > 50
    w.step(DT, steps=30)
    assert heavy.linear_velocity[1] < -2   # falling freely now
    joint.enabled = True                     # mends it
    assert not joint.broken


def test_distance_joint_and_spring_conserve_momentum():
    # Internal forces only (no gravity): linear momentum is conserved (1e-5 relative, float rounding).
    w = fulcrum.World(gravity=(0, 0, 0), sleeping=False, integrator="verlet")
    a = w.create_body(mass=1, position=(0, 0, 0), linear_velocity=(1, 0, 0), name="a")
    b = w.create_body(mass=2, position=(3, 0, 0), linear_velocity=(0, 1, 0), name="b")
    w.create_spring(a, b, anchor_a=(0, 0, 0), anchor_b=(3, 0, 0), rest_length=2, stiffness=50, damping=1)
    p0 = w.linear_momentum()
    w.step(DT, steps=120)
    np.testing.assert_allclose(w.linear_momentum(), p0, atol=1e-5 * np.linalg.norm(p0))


def test_free_fall_conserves_energy():
    # tests/dynamics/forces_test.cpp, GravityEnergyIsConservedInFreeFall (verlet, 1e-5 relative).
    w = fulcrum.World(integrator="verlet", substeps=1)
    w.create_body(shape=fulcrum.Sphere(0.1), mass=2, position=(0, 10, 0))
    e = w.energy()
    assert e["potential"] == pytest.approx(2 * 9.81 * 10, abs=1e-3)
    w.step(DT, steps=60)
    assert w.energy()["total"] == pytest.approx(e["total"], rel=1e-5)


def test_queries_return_objects_in_the_documented_order():
    w = fulcrum.World()
    ground = w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", name="ground")
    ball = w.create_body(shape=fulcrum.Sphere(1), position=(0, 2, 0), name="ball")
    box = w.create_body(shape=fulcrum.Box((0.5, 0.5, 0.5)), position=(3, 2, 0), name="box")
    hit = w.ray_cast((0, 10, 0), (0, -20, 0))
    assert hit.body == ball and hit.fraction == pytest.approx(0.35, abs=1e-6)   # enters the sphere at y = 3
    np.testing.assert_allclose(hit.normal, (0, 1, 0), atol=1e-6)
    np.testing.assert_allclose(hit.point, (0, 3, 0), atol=1e-5)
    hits = w.ray_cast((0, 10, 0), (0, -20, 0), all=True)
    assert [h.body for h in hits] == [ball, ground] and hits[1].fraction == pytest.approx(0.5, abs=1e-6)
    assert w.ray_cast((0, 10, 0), (0, -20, 0), exclude=ball).body == ground
    assert w.ray_cast((10, 10, 10), (0, 1, 0)) is None
    assert w.overlap_sphere((1.5, 2, 0), 1.2) == [ball, box]
    assert w.overlap_aabb((2, 1, -1), (4, 3, 1)) == [box]
    assert w.overlap_box((0, 2, 0), (0.1, 0.1, 0.1)) == [ball]
    assert w.overlap_shape(fulcrum.Capsule(0.2, 1), (3, 2, 0)) == [box]
    cast = w.shape_cast(fulcrum.Sphere(0.5), (0, 10, 0), (0, -10, 0))
    assert cast.body == ball and cast.fraction == pytest.approx(0.65, abs=1e-3)   # touches at y = 3.5


def test_contact_events_after_a_step():
    w = fulcrum.World()
    ground = w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", name="ground")
    ball = w.create_body(shape=fulcrum.Sphere(0.5), position=(0, 0.7, 0), name="ball")
    began = []
    for _ in range(60):
        w.step(DT)
        began += w.contact_begin_events()
    assert began == [(ground, ball)]
    contacts = w.contacts()
    assert len(contacts) == 1 and contacts[0].body_a == ground and contacts[0].body_b == ball
    np.testing.assert_allclose(contacts[0].normal, (0, 1, 0), atol=1e-5)
    assert contacts[0].points.shape[1] == 3
    ball.position = (0, 5, 0)
    w.step(DT)
    assert w.contact_end_events() == [(ground, ball)]


def test_contact_forces_hit_events_and_kinematic_targets():
    w = fulcrum.World(sleeping=False)
    w.create_body(shape=fulcrum.Box((5, 0.5, 5)), position=(0, -0.5, 0), type="static", name="ground")
    box = w.create_body(shape=fulcrum.Box((0.5, 0.5, 0.5)), position=(0, 0.5, 0), mass=2, name="box")
    for _ in range(120):
        w.step(DT)
    c = w.contacts()[0]
    sign = 1 if c.body_b == box else -1
    assert sign * c.force[1] == pytest.approx(2 * 9.81, rel=0.005)      # the ground carries m g
    assert c.normal_impulse == pytest.approx(sum(c.point_normal_impulses), rel=1e-5)
    assert len(c.point_normal_impulses) == len(c.points) and len(c.friction_impulse) == 3

    w = fulcrum.World(sleeping=False, hit_event_threshold=1.0)
    assert w.settings()["hit_event_threshold"] == 1.0
    w.create_body(shape=fulcrum.Box((5, 0.5, 5)), position=(0, -0.5, 0), type="static")
    w.create_body(shape=fulcrum.Sphere(0.25), position=(0, 2.25, 0))
    hits = []
    for _ in range(120):
        w.step(DT)
        hits += w.contact_hit_events()
    assert len(hits) == 1 and hits[0]["approach_speed"] == pytest.approx((2 * 9.81 * 2) ** 0.5, rel=0.01)
    assert set(hits[0]) == {"body_a", "body_b", "point", "normal", "approach_speed"}

    lift = w.create_body(shape=fulcrum.Box((1, 0.1, 1)), position=(3, 0, 0), type="kinematic", name="lift")
    lift.move_kinematic((3, 0.1, 0), (1, 0, 0, 0), DT)
    w.step(DT)
    np.testing.assert_allclose(lift.position, (3, 0.1, 0), atol=1e-5)
    with pytest.raises(fulcrum.Error, match="lift.*dt"):
        lift.move_kinematic((3, 0.1, 0), (1, 0, 0, 0), 0.0)
    ball = w.create_body(shape=fulcrum.Sphere(0.25), position=(-3, 0.25, 0), name="ball")
    with pytest.raises(fulcrum.Error, match="ball.*kinematic"):
        ball.move_kinematic((0, 0, 0), (1, 0, 0, 0), DT)


def test_ropes_and_cloths_as_arrays():
    w = fulcrum.World()
    rope = w.create_rope(start=(0, 5, 0), end=(2, 5, 0), segments=8, name="rope")
    start = rope.positions()
    assert start.shape == (9, 3) and start.dtype == np.float64
    np.testing.assert_allclose(start[:, 0], np.linspace(0, 2, 9), atol=1e-6)
    cloth = w.create_cloth(origin=(0, 3, 0), size=(5, 4), spacing=0.25, pinned=[(0, 0), (4, 0)], name="cloth")
    p = cloth.positions()
    assert cloth.size == (5, 4) and p.shape == (20, 3)
    i, j = 3, 2   # particle (i, j) is row j * columns + i, at origin + spacing (i u + j v)
    np.testing.assert_allclose(p[j * 5 + i], (0.75, 3, 0.5), atol=1e-6)
    w.step(DT, steps=60)
    assert rope.positions()[0] == pytest.approx(start[0])          # pinned start
    assert rope.positions()[-1][1] < 5                             # the free end fell
    np.testing.assert_allclose(cloth.positions()[[0, 4]], p[[0, 4]], atol=1e-6)   # pins held
    assert w.find_particle_system("cloth") == cloth and cloth.type == "cloth" and rope.type == "rope"
    assert cloth.report()["particles"] == 20


def test_recordings(tmp_path):
    w = fulcrum.World()
    w.create_body(shape=fulcrum.Plane(), type="static")
    w.create_body(shape=fulcrum.Box((0.2, 0.2, 0.2)), position=(0, 1, 0))
    rec = fulcrum.Recorder(w, title="drop")
    rec.capture()
    for _ in range(10):
        w.step(DT)
        rec.capture()
    assert rec.frame_count == 11
    rec.write(tmp_path / "drop.glb")
    rec.write(tmp_path / "drop.html")
    assert (tmp_path / "drop.glb").read_bytes()[:4] == b"glTF"
    assert "drop" in (tmp_path / "drop.html").read_text()
    with pytest.raises(fulcrum.Error, match="glb|html"):
        rec.write(tmp_path / "drop.txt")


def test_profile_and_settings():
    w = fulcrum.World()
    w.create_body()
    w.step(DT)
    p = w.last_step_profile()
    assert p["total"] >= 0 and p["awake_bodies"] == 1 and p["workers"] >= 1
    w.gravity = (0, -1.62, 0)
    w.integrator = "verlet"
    w.substeps = 3
    assert w.settings()["integrator"] == "verlet" and w.substeps == 3
    with pytest.raises(fulcrum.Error):
        w.substeps = 0
