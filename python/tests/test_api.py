"""The binding's contract: arrays, handles, pickle and snapshots, errors,
lifetimes, memory, threads."""
import gc
import math
import pickle
import resource
import threading

import numpy as np
import pytest

import fulcrum

DT = 1 / 60


def pile(n=10, threads=1):
    w = fulcrum.World(threads=threads)
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", name="ground")
    for i in range(n):
        w.create_body(shape=fulcrum.Box((0.5, 0.5, 0.5)) if i % 2 else fulcrum.Sphere(0.4), mass=1 + i,
                      position=(0.3 * (i % 3), 0.5 + 1.05 * i, 0.2 * (i % 2)), name=f"b{i}")
    return w


# ---- the names the public Python API fixes (docs/python.md)
def test_contract_example():
    w = fulcrum.World(gravity=(0, -9.81, 0), substeps=5, integrator="semi_implicit_euler", threads=1, sleeping=True)
    b = w.create_body(shape=fulcrum.Sphere(0.5), position=(0, 10, 0), type="dynamic", mass=1.0,
                      restitution=0.5, friction=0.6, linear_velocity=(0, 0, 0), name="ball")
    w.step(1 / 60)
    w.step(1 / 60, steps=600)
    assert b.position.shape == (3,) and b.orientation.shape == (4,)
    assert b.linear_velocity.dtype == np.float64 and b.angular_velocity.shape == (3,)
    assert w.find_body("ball") == b and w.find_body("nothing") is None
    assert w.positions().shape == (1, 3)
    assert w.step_count == 601 and w.time == pytest.approx(601 / 60, rel=1e-5)
    assert issubclass(fulcrum.Error, ValueError) and issubclass(fulcrum.NumericalError, fulcrum.Error)
    for shape in [fulcrum.Sphere(1), fulcrum.Box((1, 2, 3)), fulcrum.Capsule(0.5, 1), fulcrum.Cylinder(0.5, 1),
                  fulcrum.ConvexHull([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]), fulcrum.Plane((0, 1, 0), 0),
                  fulcrum.Mesh([(0, 0, 0), (1, 0, 0), (0, 0, 1)], [(0, 2, 1)]),
                  fulcrum.Compound([fulcrum.Sphere(1), (fulcrum.Box((1, 1, 1)), (2, 0, 0))])]:
        assert isinstance(shape, fulcrum.Shape) and repr(shape).startswith("fulcrum.")


def test_world_keywords_default_to_the_cpp_defaults():
    s = fulcrum.World().settings()
    assert s["substeps"] == 5 and s["solver_iterations"] == 1 and s["threads"] == 1 and s["sleeping"] is True
    assert s["integrator"] == "semi_implicit_euler" and s["parallel_min_bodies"] == 512
    np.testing.assert_array_equal(s["gravity"], np.array([0, -9.81, 0], dtype=fulcrum.real_dtype))
    w = fulcrum.World(contact_hertz=30, time_to_sleep=1.0, continuous_collision=False)
    assert w.settings()["contact_hertz"] == 30 and w.settings()["continuous_collision"] is False


# ---- bulk arrays
def test_arrays_shapes_dtypes_and_creation_order():
    w = pile(10)
    bodies = w.bodies()
    for name, array, cols in [("positions", w.positions(), 3), ("orientations", w.orientations(), 4),
                              ("linear_velocities", w.linear_velocities(), 3),
                              ("angular_velocities", w.angular_velocities(), 3)]:
        assert array.shape == (11, cols) and array.dtype == np.float64, name
        assert array.flags["C_CONTIGUOUS"]
    w.step(DT, steps=30)
    np.testing.assert_array_equal(w.positions(), np.array([b.position for b in bodies]))
    np.testing.assert_array_equal(w.orientations(), np.array([b.orientation for b in bodies]))
    np.testing.assert_array_equal(w.linear_velocities(), np.array([b.linear_velocity for b in bodies]))
    assert [b.name for b in bodies] == ["ground"] + [f"b{i}" for i in range(10)]
    # Destroying one keeps the others' order.
    w.destroy_body(bodies[3])
    assert [b.name for b in w.bodies()] == ["ground", "b0", "b1", "b3", "b4", "b5", "b6", "b7", "b8", "b9"]
    assert w.positions().shape == (10, 3)


def test_arrays_equal_the_per_body_getters_for_off_centre_shapes():
    # Bodies whose centre of mass is not their origin (hulls, compounds): the
    # arrays' fast path must give World::position's bits.
    w = pile(3)
    w.create_body(shape=fulcrum.ConvexHull([(0, 0, 0), (2, 0, 0), (0, 1, 0), (0, 0, 3)]), mass=1, position=(1, 3, 0),
                  angular_velocity=(1, 2, 3))
    w.create_body(shape=fulcrum.Compound([(fulcrum.Sphere(0.3), (1, 0, 0)), (fulcrum.Box((0.2, 0.2, 0.2)), (0, 0.5, 0))]),
                  mass=2, position=(-1, 4, 0), angular_velocity=(-2, 1, 0.5))
    w.step(DT, steps=7)
    assert np.any(w.centers_of_mass() != w.positions())
    np.testing.assert_array_equal(w.positions(), np.array([b.position for b in w.bodies()]))
    np.testing.assert_array_equal(w.centers_of_mass(), np.array([b.center_of_mass for b in w.bodies()]))


def test_bulk_setters_round_trip_and_match_per_body_calls():
    a, b = pile(10), pile(10)
    v = np.arange(33, dtype=np.float64).reshape(11, 3) * 0.1
    a.set_linear_velocities(v)
    np.testing.assert_array_equal(a.linear_velocities()[1:], v[1:].astype(fulcrum.real_dtype))   # static bodies keep 0
    for body, row in zip(b.bodies(), v):
        body.linear_velocity = row
    idx = np.array([2, 5, 7])
    f = np.array([[1, 2, 3], [4, 5, 6], [7, 8, 9]], dtype=np.float64)
    a.apply_forces(f, indices=idx)
    for i, row in zip(idx, f):
        b.bodies()[i].apply_force(row)
    a.set_angular_velocities(np.ones((2, 3)), indices=[1, -1])
    for i in (1, -1):
        b.bodies()[i].angular_velocity = (1, 1, 1)
    a.step(DT, steps=20)
    b.step(DT, steps=20)
    np.testing.assert_array_equal(a.positions(), b.positions())
    np.testing.assert_array_equal(a.angular_velocities(), b.angular_velocities())
    # Positions round trip exactly (values of the engine's Real in float64).
    p = a.positions()
    a.set_positions(p)
    np.testing.assert_array_equal(a.positions(), p)


def test_bulk_setters_reject_bad_input_without_changing_anything():
    w = pile(3)
    before = w.linear_velocities()
    with pytest.raises(fulcrum.Error, match="rows"):
        w.set_linear_velocities(np.zeros((3, 3)))
    bad = np.zeros((4, 3))
    bad[2, 1] = np.nan
    with pytest.raises(fulcrum.Error, match="finite"):
        w.set_linear_velocities(bad)
    with pytest.raises(TypeError, match="velocities"):
        w.set_linear_velocities(np.zeros((4, 2)))
    with pytest.raises(IndexError):
        w.apply_forces(np.zeros((1, 3)), indices=[99])
    np.testing.assert_array_equal(w.linear_velocities(), before)


# ---- pickle and snapshots
def test_pickle_continues_bit_for_bit():
    w = pile(10, threads=2)
    w.step(DT, steps=40)
    w2 = pickle.loads(pickle.dumps(w))
    w.step(DT, steps=80)
    w2.step(DT, steps=80)
    for get in ("positions", "orientations", "linear_velocities", "angular_velocities"):
        np.testing.assert_array_equal(getattr(w, get)(), getattr(w2, get)(), err_msg=get)
    assert w2.threads == 2 and w2.step_count == w.step_count
    assert [b.name for b in w2.bodies()] == [b.name for b in w.bodies()]


def test_snapshot_bytes_and_files(tmp_path):
    w = pile(5)
    w.step(DT, steps=10)
    blob = w.save_snapshot()
    assert isinstance(blob, bytes) and blob[:8] == b"FULCSNAP"
    w.save_snapshot(tmp_path / "w.snap")
    for copy in (fulcrum.load_snapshot(blob), fulcrum.load_snapshot(tmp_path / "w.snap")):
        copy.step(DT, steps=10)
        w2 = fulcrum.load_snapshot(blob)
        w2.step(DT, steps=10)
        np.testing.assert_array_equal(copy.positions(), w2.positions())
    with pytest.raises(fulcrum.Error, match="snapshot"):
        fulcrum.load_snapshot(blob[:100])


def test_scene_round_trip(tmp_path):
    w = pile(4)
    w.create_hinge_joint(w.body("b0"), w.body("b1"), anchor=(0, 1, 0), axis=(0, 0, 1), limits=(-0.5, 0.5))
    w.step(DT, steps=5)
    w.save_scene(tmp_path / "s.json")
    w2 = fulcrum.load_scene(tmp_path / "s.json")
    np.testing.assert_array_equal(w2.positions(), w.positions())
    assert len(w2.joints()) == 1 and w2.joints()[0].type == "hinge"
    # A pickled world keeps its scene description.
    w3 = pickle.loads(pickle.dumps(w))
    assert w3.scene_json() == w.scene_json()
    # Dicts and JSON text.
    d = {"world": {"gravity": [0, -1.62, 0]}, "bodies": [{"name": "m", "shape": {"type": "sphere", "radius": 1}}]}
    assert fulcrum.load_scene(d).gravity[1] == pytest.approx(-1.62)
    assert fulcrum.load_scene('{"bodies": []}').body_count == 0


# ---- errors
def test_bad_values_raise_fulcrum_error_with_the_cpp_message():
    w = fulcrum.World()
    with pytest.raises(fulcrum.Error, match=r"mass must be positive.*got -1"):
        w.create_body(mass=-1, name="crate")
    with pytest.raises(fulcrum.Error, match="NaN|finite|nan"):
        w.create_body(position=(0, math.nan, 0))
    with pytest.raises(fulcrum.Error, match="substeps"):
        fulcrum.World(substeps=0)
    with pytest.raises(fulcrum.Error, match="integrator"):
        fulcrum.World(integrator="rk4")
    with pytest.raises(fulcrum.Error, match="type"):
        w.create_body(type="wobbly")
    with pytest.raises(fulcrum.Error, match="radius"):
        fulcrum.Sphere(-1)
    with pytest.raises(fulcrum.Error):
        fulcrum.ConvexHull([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    with pytest.raises(fulcrum.Error, match="no body named"):
        w.body("nobody")
    with pytest.raises(fulcrum.Error, match="steps"):
        w.step(DT, steps=-1)


def test_wrong_types_raise_type_error_naming_the_argument():
    w = fulcrum.World()
    with pytest.raises(TypeError, match="'position'"):
        w.create_body(position="up")
    with pytest.raises(TypeError, match="'position'"):
        w.create_body(position=(1, 2))
    with pytest.raises(TypeError, match="'shape'"):
        w.create_body(shape="sphere")
    with pytest.raises(TypeError, match="'mass'"):
        w.create_body(mass="heavy")
    with pytest.raises(TypeError, match="'substeps'"):
        fulcrum.World(substeps="many")
    with pytest.raises(TypeError, match="'radius'"):
        fulcrum.Sphere(None)
    with pytest.raises(TypeError, match="'max_motor_force'"):
        w.create_hinge_joint(None, w.create_body(), anchor=(0, 0, 0), motor_speed=1, max_motor_force="strong")
    with pytest.raises(TypeError, match="gravity"):
        fulcrum.World(gravity=None)
    with pytest.raises(TypeError, match="'body_b'"):
        w.create_ball_joint(None, "b", anchor=(0, 0, 0))
    with pytest.raises(TypeError, match="'dt'"):
        w.step("fast")
    with pytest.raises(TypeError, match="'steps'"):
        w.step(DT, steps=2.5)
    with pytest.raises(TypeError, match="Body.friction: expected float, got str"):
        w.create_body().friction = "rough"
    with pytest.raises(TypeError, match="World.substeps: expected int"):
        w.substeps = None
    with pytest.raises(TypeError, match="'callback'"):
        w.create_body().set_force_callback(42)


def test_scene_errors_name_the_file_path_and_reason(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"bodies": [{"name": "x", "shape": {"type": "sphere", "radius": 1}, "mass": -2}]}')
    with pytest.raises(fulcrum.SceneError, match=r"bad.json.*bodies\[0\]\.mass"):
        fulcrum.load_scene(bad)
    with pytest.raises(fulcrum.Error, match="missing.json"):
        fulcrum.load_scene(tmp_path / "missing.json")
    with pytest.raises(TypeError, match="source"):
        fulcrum.load_scene(42)


def test_numerical_error_when_the_state_goes_nan():
    w = fulcrum.World()
    b = w.create_body(name="ball")
    b.set_force_callback(lambda k: ((math.inf, 0, 0), (0, 0, 0)))
    with pytest.raises(fulcrum.NumericalError, match="ball"):
        w.step(DT)


def test_an_exception_in_a_force_callback_stops_step_and_is_raised():
    w = fulcrum.World()
    b = w.create_body()
    calls = []

    def boom(k):
        calls.append(k.time)
        raise KeyError("boom")

    b.set_force_callback(boom)
    with pytest.raises(KeyError, match="boom"):
        w.step(DT, steps=100)
    assert w.step_count == 1 and len(calls) == 1
    b.set_force_callback(None)
    w.step(DT)
    assert w.step_count == 2


# ---- handles and lifetimes
def test_stale_handles_raise():
    w = fulcrum.World()
    b = w.create_body(name="gone")
    j = w.create_ball_joint(None, b, anchor=(0, 1, 0))
    w.destroy_body(b)
    assert not b.valid and not j.valid
    for use in (lambda: b.position, lambda: b.apply_force((0, 1, 0)), lambda: setattr(b, "linear_velocity", (1, 0, 0)),
                lambda: j.reaction_force, lambda: w.destroy_body(b)):
        with pytest.raises(fulcrum.Error, match="stale|destroyed|does not exist"):
            use()
    assert "destroyed" in repr(b)


def test_a_body_outliving_its_world_raises():
    w = fulcrum.World()
    b = w.create_body()
    rope = w.create_rope(start=(0, 1, 0), end=(1, 1, 0), segments=4)
    del w
    gc.collect()
    with pytest.raises(fulcrum.Error, match="world no longer exists"):
        b.position
    with pytest.raises(fulcrum.Error, match="world no longer exists"):
        rope.positions()
    assert not b.valid and "deleted" in repr(b)


def test_handles_of_another_world_are_refused():
    w1, w2 = fulcrum.World(), fulcrum.World()
    b1 = w1.create_body()
    with pytest.raises(fulcrum.Error, match="another world"):
        w2.create_ball_joint(None, b1, anchor=(0, 0, 0))
    with pytest.raises(fulcrum.Error, match="another world"):
        w2.destroy_body(b1)


def rss_kib():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * resource.getpagesize() // 1024


def test_no_leak_over_ten_thousand_create_destroy_cycles():
    # Warm up (allocator pools, slot tables), then 10,000 cycles of a body with a
    # joint, a callback and handle objects. A leak of one body definition per
    # cycle (~200 bytes) would grow RSS by ~2 MiB; allow 1 MiB for the allocator.
    w = fulcrum.World()
    anchor = w.create_body(type="static", name="anchor")

    def cycle():
        b = w.create_body(shape=fulcrum.Box((0.1, 0.2, 0.3)), position=(0, 1, 0), name="temp")
        b.set_force_callback(lambda k: None)
        w.create_ball_joint(anchor, b, anchor=(0, 1, 0))
        _ = b.position, w.positions(), repr(b)
        w.destroy_body(b)

    for _ in range(2000):
        cycle()
    w.step(DT)
    gc.collect()
    before = rss_kib()
    for _ in range(10000):
        cycle()
    w.step(DT)
    gc.collect()
    grown = rss_kib() - before
    assert grown < 1024, f"RSS grew by {grown} KiB over 10,000 cycles"


def test_equality_and_hash():
    w = fulcrum.World()
    b = w.create_body(name="x")
    assert b == w.find_body("x") and hash(b) == hash(w.find_body("x"))
    assert len({b, w.find_body("x"), w.create_body()}) == 2


# ---- threads and the GIL
def test_step_releases_the_gil():
    w = pile(200)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)

    t = threading.Thread(target=count)
    t.start()
    try:
        w.step(DT, steps=200)
    finally:
        done.set()
        t.join()
    assert len(ticks) > 10   # the other thread ran while step() was in C++


def test_a_world_being_stepped_refuses_other_threads():
    w = pile(300)
    errors = []
    started = threading.Event()

    def stepper():
        started.set()
        w.step(DT, steps=400)

    t = threading.Thread(target=stepper)
    t.start()
    started.wait()
    for _ in range(200000):
        try:
            w.positions()
        except fulcrum.Error as e:
            errors.append(str(e))
            break
    t.join()
    assert errors and "another thread" in errors[0]


def test_same_bits_for_every_thread_count():
    results = []
    for threads in (1, 2, 4):
        w = pile(40, threads=threads)
        w.parallel_min_bodies = 0
        w.step(DT, steps=60)
        results.append(w.positions())
    np.testing.assert_array_equal(results[0], results[1])
    np.testing.assert_array_equal(results[0], results[2])


def test_force_callbacks_on_worker_threads_give_the_same_bits():
    # With threads > 1 the callbacks run on the pool's workers, each taking the GIL.
    results = []
    for threads in (1, 3):
        w = pile(60, threads=threads)
        w.parallel_min_bodies = 0
        for b in w.bodies()[1:]:
            b.set_force_callback(lambda k: ((0, 5.0 * k.mass * math.sin(3 * k.time), 0), (0, 0.1, 0)))
        w.step(DT, steps=30)
        results.append(w.positions())
    np.testing.assert_array_equal(results[0], results[1])
