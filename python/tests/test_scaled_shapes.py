"""Shape.scaled: the scale is baked into a new shape of the same kind (a box
stays a box), mass properties follow it exactly, bad scales name the field,
and a scaled body rests at its scaled height."""
import math

import numpy as np
import pytest

import fulcrum

DT = 1 / 60


def test_kinds_and_mass_properties():
    box = fulcrum.Box((0.5, 0.3, 0.7)).scaled((2, -0.5, 3))
    assert isinstance(box, fulcrum.Box)
    np.testing.assert_allclose(box.half_extents, (1.0, 0.15, 2.1), rtol=1e-6)
    hx, hy, hz = box.half_extents
    m = 1000 * 8 * hx * hy * hz
    mp = box.mass_properties(1000)
    assert mp["mass"] == pytest.approx(m, rel=1e-5)
    assert mp["inertia"][0][0] == pytest.approx(m * (hy * hy + hz * hz) / 3, rel=1e-5)

    sphere = fulcrum.Sphere(0.5).scaled(3)
    assert isinstance(sphere, fulcrum.Sphere) and sphere.radius == pytest.approx(1.5)
    cylinder = fulcrum.Cylinder(0.2, 0.5).scaled((2, 3, 2))
    assert isinstance(cylinder, fulcrum.Cylinder)
    assert cylinder.radius == pytest.approx(0.4) and cylinder.half_height == pytest.approx(1.5)

    corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    hull = fulcrum.ConvexHull(corners).scaled((1, 2, 3))
    assert isinstance(hull, fulcrum.ConvexHull) and hull.volume == pytest.approx(8 * 6, rel=1e-5)
    compound = fulcrum.Compound([(fulcrum.Box((1, 1, 1)), (2, 0, 0))]).scaled((0.5, 1, 1))
    (child, position, _), = compound.children
    assert isinstance(child, fulcrum.Box) and position[0] == pytest.approx(1.0)


@pytest.mark.parametrize("shape, scale, message", [
    (fulcrum.Box((1, 1, 1)), (1, 0, 1), "scale.y must be a finite nonzero number"),
    (fulcrum.Box((1, 1, 1)), (math.nan, 1, 1), "scale.x must be a finite nonzero number"),
    (fulcrum.Sphere(1), (2, 1, 1), "of a sphere: a sphere only takes a uniform scale"),
    (fulcrum.Cylinder(1, 1), (1, 1, 2), "cylinder only takes a scale with"),
])
def test_bad_scales_name_the_field(shape, scale, message):
    with pytest.raises(fulcrum.Error, match=message.replace("(", r"\(").replace(")", r"\)")):
        shape.scaled(scale)


def test_scaled_box_rests_at_its_scaled_height(tmp_path):
    w = fulcrum.World()
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static")
    box = w.create_body(shape=fulcrum.Box((0.5, 0.5, 0.5)).scaled((1.6, 0.4, 2)), position=(0, 0.5, 0))
    for _ in range(120):
        w.step(DT)
    assert box.position[1] == pytest.approx(0.2, abs=0.005)
    path = tmp_path / "scaled.json"
    w.save_scene(path)  # the baked box: a plain box of the scaled size
    loaded = fulcrum.load_scene(path)  # (the world must outlive its bodies)
    shape = loaded.bodies()[1].shape
    np.testing.assert_allclose(shape.half_extents, (0.8, 0.2, 1.0), rtol=1e-6)


def l_shape_mesh():
    """An L of three unit cubes, (x, y) cells (0, 0), (1, 0), (0, 1), z in [0, 1]: a closed mesh."""
    outline = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    vertices = [(x, y, 0) for x, y in outline] + [(x, y, 1) for x, y in outline]
    front = [(0, 3, 1), (1, 3, 2), (0, 5, 3), (3, 5, 4)]
    back = [(a + 6, c + 6, b + 6) for a, b, c in front]
    sides = []
    for a in range(6):
        b = (a + 1) % 6
        sides += [(a, b, b + 6), (a, b + 6, a + 6)]
    return np.array(vertices, float), np.array(front + back + sides)


def test_convex_decomposition_of_an_l():
    vertices, triangles = l_shape_mesh()
    with pytest.raises(fulcrum.Error, match="Shape::convexDecomposition"):
        fulcrum.World().create_body(shape=fulcrum.Mesh(vertices, triangles))
    shape = fulcrum.Compound.from_mesh(vertices, triangles)
    assert isinstance(shape, fulcrum.Compound) and len(shape.children) == 2
    assert shape.volume == pytest.approx(3, rel=1e-5)
    assert all(isinstance(child, fulcrum.ConvexHull) for child, _, _ in shape.children)
    assert len(fulcrum.Compound.from_mesh(vertices, triangles, max_hulls=1).children) == 1
    with pytest.raises(fulcrum.Error, match="options.maxHulls"):
        fulcrum.Compound.from_mesh(vertices, triangles, max_hulls=0)
    w = fulcrum.World()
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static")
    body = w.create_body(shape=shape, position=(0, 0.5, 0))
    for _ in range(120):
        w.step(DT)
    assert body.position[1] == pytest.approx(0, abs=0.005)  # the L's foot (y = 0 in its frame) on the plane
