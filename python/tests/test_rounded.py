"""Rounded shapes: Box, Cylinder and ConvexHull take convex_radius (the shape
is its core swept by a sphere of that radius; box and cylinder keep their
outer size), a rounded box rests at its outer half height, rays hit the
rounded corner, bad radii name the field, and save_scene keeps the radius."""
import math

import numpy as np
import pytest

import fulcrum

DT = 1 / 60


def test_rounded_shapes_and_their_volume():
    box = fulcrum.Box((0.5, 0.3, 0.2), convex_radius=0.05)
    assert box.convex_radius == pytest.approx(0.05) and isinstance(box, fulcrum.Box)
    a, b, c, r = 0.45, 0.25, 0.15, 0.05
    v = 8 * a * b * c + 8 * r * (a * b + b * c + c * a) + 2 * math.pi * r * r * (a + b + c) + 4 / 3 * math.pi * r ** 3
    assert box.volume == pytest.approx(v, rel=1e-5)
    assert repr(box).endswith(", convex_radius=0.05)")
    assert fulcrum.Box((1, 1, 1)).convex_radius == 0
    assert fulcrum.Cylinder(0.5, 0.5, convex_radius=0.1).convex_radius == pytest.approx(0.1)
    hull = fulcrum.ConvexHull([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], convex_radius=0.1)
    lo, hi = hull.local_bounds()
    assert hi[0] == pytest.approx(1.1) and lo[1] == pytest.approx(-0.1)


@pytest.mark.parametrize("make, message", [
    (lambda: fulcrum.Box((0.5, 0.2, 0.5), convex_radius=0.3), "box: convex_radius"),
    (lambda: fulcrum.Box((0.5, 0.5, 0.5), convex_radius=-0.1), "box: convex_radius"),
    (lambda: fulcrum.Cylinder(0.5, 0.5, convex_radius=math.nan), "cylinder: convex_radius"),
    (lambda: fulcrum.ConvexHull(np.eye(4, 3), convex_radius=-1), "convex_hull: convex_radius"),
])
def test_bad_radius_names_the_field(make, message):
    with pytest.raises(fulcrum.Error, match=message):
        make()


def test_rests_rays_and_scenes(tmp_path):
    w = fulcrum.World()
    w.create_body(shape=fulcrum.Plane(), type="static")
    box = w.create_body(shape=fulcrum.Box((0.5, 0.25, 0.4), convex_radius=0.1), mass=1, position=(0, 0.5, 0))
    for _ in range(120):
        w.step(DT)
    assert box.position[1] == pytest.approx(0.25, abs=1e-3)
    # A ray down past the rounded corner (where the sharp box would be) misses it.
    x, _, z = box.position
    assert w.ray_cast((x + 0.49, 2, z + 0.39), (0, -1.5, 0)) is None
    hit = w.ray_cast((x, 2, z), (0, -3, 0))
    assert hit is not None and hit.body == box and hit.point[1] == pytest.approx(0.5, abs=1e-3)

    path = tmp_path / "rounded.json"
    w.save_scene(path)
    loaded = fulcrum.load_scene(path)
    assert loaded.bodies()[1].shape.convex_radius == pytest.approx(0.1)
    restored = fulcrum.load_snapshot(w.save_snapshot())
    assert restored.bodies()[1].shape.convex_radius == pytest.approx(0.1)
