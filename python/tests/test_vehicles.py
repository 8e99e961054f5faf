"""Vehicles from Python (docs/vehicles.md): creation, input, state, scenes, errors."""
import pathlib

import pytest

import fulcrum

SCENES = pathlib.Path(__file__).resolve().parents[2] / "scenes"


def car_world():
    w = fulcrum.World(gravity=(0, -9.81, 0))
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static")
    chassis = w.create_body(shape=fulcrum.Box((0.9, 0.3, 2)), mass=1000, position=(0, 0.95, 0), name="car")
    wheels = [dict(position=(x, 0.65, z), steering=z > 0, driven=z < 0) for z in (1.3, -1.3) for x in (0.8, -0.8)]
    return w, chassis, wheels


def test_drives_and_brakes():
    w, chassis, wheels = car_world()
    car = w.create_vehicle(chassis=chassis, wheels=wheels, name="car")
    car.set_input(throttle=0.3)
    w.step(1 / 60, steps=120)
    assert car.speed > 3
    assert all(wh["in_contact"] for wh in car.wheels())
    car.set_input(brake=1)
    w.step(1 / 60, steps=240)
    assert abs(car.speed) < 0.05
    assert w.vehicles() and car.name == "car"


def test_negative_throttle_reverses_once_stopped():
    w, chassis, wheels = car_world()
    car = w.create_vehicle(chassis=chassis, wheels=wheels, name="car")
    car.set_input(throttle=-0.5)
    w.step(1 / 60, steps=180)
    assert car.gear == -1
    assert car.speed < -2


def test_scene_vehicles_follow_their_script():
    w = fulcrum.load_scene(str(SCENES / "car_lap.json"))
    (car,) = w.vehicles()
    w.step(1 / 60, steps=120)
    assert car.speed > 3


def test_bad_input_names_the_field():
    w, chassis, wheels = car_world()
    with pytest.raises(fulcrum.Error, match="chassis"):
        w.create_vehicle(chassis=None, wheels=wheels)
    bad = [dict(wheels[0], position=(5, 0.65, 0))] + wheels[1:]
    with pytest.raises(fulcrum.Error, match=r"wheels\[0\].position"):
        w.create_vehicle(chassis=chassis, wheels=bad)
    car = w.create_vehicle(chassis=chassis, wheels=wheels)
    with pytest.raises(fulcrum.Error, match="throttle"):
        car.set_input(throttle=float("nan"))
