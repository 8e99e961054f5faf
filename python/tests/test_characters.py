"""Characters from Python (docs/characters.md): creation, input, state, scenes, errors."""
import os
import pathlib
import pickle

import pytest

import fulcrum

SCENES = pathlib.Path(__file__).resolve().parents[2] / "scenes"


def ground_world():
    w = fulcrum.World(gravity=(0, -9.81, 0))
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static")
    return w


def test_walks_by_its_input_and_stands():
    w = ground_world()
    c = w.create_character(position=(0, 0.91, 0), name="hero")
    c.set_input((1, 0, 0))
    w.step(1 / 60, steps=60)
    assert c.on_ground and c.ground_state == "on_ground"
    assert c.position[0] == pytest.approx(1.0, abs=0.03)
    assert c.ground_normal[1] == pytest.approx(1.0)
    assert c.body.type == "kinematic"
    assert w.characters() == [c]
    assert c.name == "hero"


def test_scene_characters_follow_their_script():
    w = fulcrum.load_scene(str(SCENES / "character_stairs.json"))
    (hero,) = w.characters()
    w.step(1 / 60, steps=270)
    assert hero.on_ground
    assert hero.position[1] - 0.9 == pytest.approx(1.0, abs=0.03)


def test_bad_input_names_the_field():
    w = ground_world()
    with pytest.raises(fulcrum.Error, match="radius"):
        w.create_character(position=(0, 1, 0), radius=0)
    with pytest.raises(fulcrum.Error, match="position"):
        w.create_character(position=(0, float("nan"), 0))
    c = w.create_character(position=(0, 0.91, 0))
    with pytest.raises(fulcrum.Error, match="velocity"):
        c.set_input((float("nan"), 0, 0))


def test_pickle_continues_bit_for_bit():
    w = ground_world()
    c = w.create_character(position=(0, 0.91, 0))
    c.set_input((1, 0, 0.5))
    w.step(1 / 60, steps=30)
    w2 = pickle.loads(pickle.dumps(w))
    w.step(1 / 60, steps=60)
    w2.step(1 / 60, steps=60)
    (c2,) = w2.characters()
    assert list(c.position) == list(c2.position)
