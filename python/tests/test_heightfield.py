"""fulcrum.HeightField: made from a 2-d array of heights and a spacing, bodies
rest on it, rays report the triangle hit, bad input names the field, and it
goes through save_scene and snapshots unchanged."""
import math

import numpy as np
import pytest

import fulcrum

DT = 1 / 60


def hills(rows=21, columns=17, dx=0.5, dz=0.25):
    z, x = np.meshgrid(np.arange(rows) * dz, np.arange(columns) * dx, indexing="ij")
    return 0.3 * np.sin(0.8 * x) + 0.2 * np.cos(1.0 * z), (dx, dz)  # a valley at local (5.9, 3.1)


def test_shape_from_a_2d_array():
    heights, spacing = hills()
    field = fulcrum.HeightField(heights, spacing, holes=[3, 7])
    assert isinstance(field, fulcrum.Shape) and field.type == "heightfield" and field.static_only
    assert field.rows == 21 and field.columns == 17 and field.spacing == pytest.approx(spacing)
    np.testing.assert_allclose(field.heights, heights, rtol=0, atol=1e-6)
    assert field.holes == [3, 7]
    assert repr(field) == "fulcrum.HeightField(<21 x 17 samples>, (0.5, 0.25))"
    lo, hi = field.local_bounds()
    assert lo[0] == 0 and hi[0] == pytest.approx(8) and hi[2] == pytest.approx(5)
    square = fulcrum.HeightField(np.zeros((3, 3)), 2.0)  # one number: the same spacing both ways
    assert square.spacing == (2.0, 2.0)


@pytest.mark.parametrize("heights, spacing, message", [
    (np.array([[0, 0], [0, math.nan]]), (1, 1), "heights[3] (row 1, column 1) is not finite"),
    (np.zeros((1, 5)), (1, 1), "rows must be between 2 and 4097"),
    (np.zeros((5, 1)), (1, 1), "columns must be between 2 and 4097"),
    (np.zeros((3, 3)), (0, 1), "spacing x must be a positive finite number"),
    (np.zeros((3, 3)), (1, -2), "spacing z must be a positive finite number"),
    (np.zeros((5000, 2)), (1, 1), "rows must be between 2 and 4097"),
])
def test_bad_input_names_the_field(heights, spacing, message):
    with pytest.raises(fulcrum.Error, match="heightfield: " + message.replace("[", r"\[").replace("]", r"\]")
                       .replace("(", r"\(").replace(")", r"\)")):
        fulcrum.HeightField(heights, spacing)


def test_wrong_types_are_type_errors():
    with pytest.raises(TypeError, match="heights"):
        fulcrum.HeightField([1, 2, 3], (1, 1))
    with pytest.raises(TypeError, match="spacing"):
        fulcrum.HeightField(np.zeros((3, 3)), (1, 2, 3))
    with pytest.raises(fulcrum.Error, match="holes"):
        fulcrum.HeightField(np.zeros((3, 3)), 1, holes=[4])
    with pytest.raises(fulcrum.Error):
        fulcrum.World().create_body(shape=fulcrum.HeightField(np.zeros((3, 3)), 1))  # dynamic


def test_bodies_rest_rays_hit_and_scenes_round_trip(tmp_path):
    heights, spacing = hills()
    w = fulcrum.World()
    terrain = w.create_body(shape=fulcrum.HeightField(heights, spacing), type="static", position=(-4, 0, -2.5))
    ball = w.create_body(shape=fulcrum.Sphere(0.3), mass=1, position=(1.5, 2, 0.5), linear_damping=1)
    for _ in range(240):
        w.step(DT)
    x, y, z = ball.position
    assert -4 < x < 4 and -2.5 < z < 2.5  # still over the field (it rolls into a valley)
    hit = w.ray_cast((x, 5, z), (0, -10, 0), exclude=ball)
    assert hit is not None and hit.body == terrain and hit.triangle is not None
    # At rest on the surface: the centre a radius above it (a little more on a slope, 1 / cos of it).
    assert 0.29 < y - hit.point[1] < 0.33
    assert np.linalg.norm(ball.linear_velocity) < 0.05

    path = tmp_path / "terrain.json"
    w.save_scene(path)
    loaded = fulcrum.load_scene(path)
    shape = loaded.bodies()[0].shape
    assert isinstance(shape, fulcrum.HeightField)
    np.testing.assert_array_equal(shape.heights, terrain.shape.heights)
    assert shape.spacing == terrain.shape.spacing
    restored = fulcrum.load_snapshot(w.save_snapshot())
    assert restored.bodies()[1].position == pytest.approx(ball.position)
    assert isinstance(restored.bodies()[0].shape, fulcrum.HeightField)


def test_closest_points_and_distance():
    w = fulcrum.World()
    a = w.create_body(shape=fulcrum.Sphere(1), position=(0, 0, 0))
    b = w.create_body(shape=fulcrum.Sphere(0.5), position=(3, 4, 0))
    c = w.closest_points(a, b)
    assert c["distance"] == pytest.approx(3.5, abs=1e-4) and w.distance(a, b) == pytest.approx(3.5, abs=1e-4)
    np.testing.assert_allclose(c["normal"], (0.6, 0.8, 0), atol=1e-4)
    np.testing.assert_allclose(c["point_a"], (0.6, 0.8, 0), atol=1e-4)
    ground = w.create_body(shape=fulcrum.Plane((0, 1, 0), -1), type="static")
    assert w.closest_points(fulcrum.Box((0.5, 0.5, 0.5)), ground, position=(0, 2, 0))["distance"] == pytest.approx(2.5, abs=1e-4)
    field = w.create_body(shape=fulcrum.HeightField(np.zeros((3, 3)), 1), type="static")
    with pytest.raises(fulcrum.Error, match="heightfield"):
        w.distance(field, a)
