"""World diagnostics from Python: the contact pair limit (WorldDef::maxContactPairs)
and the pairs the solver left overlapping (World::deepOverlaps), as in C++
(tests/contacts, tests/solver; docs/solver.md "Contact pair limit", "Mass ratios")."""
import pytest

import fulcrum

DT = 1 / 60


def crowd(limit, n=40):
    w = fulcrum.World(gravity=(0, 0, 0), max_contact_pairs=limit)
    for i in range(n):
        w.create_body(shape=fulcrum.Sphere(0.5), position=(0.01 * i, 0, 0), mass=1.0)
    return w


def test_pair_limit_holds_and_is_reported():
    w = crowd(60)
    assert w.max_contact_pairs == 60 and w.settings()["max_contact_pairs"] == 60
    w.step(DT)
    p = w.last_step_profile()
    # 40 coincident spheres make 780 pairs; the limit keeps at most 60 and says so once.
    assert p["contact_pair_limit"] == 60
    assert 0 < p["contact_pairs"] <= 60
    assert p["pairs_left_out"] > 0 and p["bodies_over_pair_limit"] > 0
    warnings = w.warnings()
    assert len(warnings) == 1 and warnings[0]["step"] == 1
    assert "contact pair limit" in warnings[0]["message"]
    w.step(DT, steps=5)
    assert len(w.warnings()) == 1  # each kind once per world


def test_automatic_limit_holds_every_pair_of_a_small_crowd():
    w = crowd(0)
    w.step(DT)
    p = w.last_step_profile()
    assert p["contact_pairs"] == 40 * 39 // 2  # all of them: far below 16 per body + 65536
    assert p["pairs_left_out"] == 0 and w.warnings() == []


@pytest.mark.parametrize("bad", [-1, 2**31])
def test_bad_pair_limit_raises(bad):
    with pytest.raises(fulcrum.Error, match="maxContactPairs"):
        fulcrum.World(max_contact_pairs=bad)


def stack(light, heavy, steps=300):
    w = fulcrum.World()
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static", name="ground")
    w.create_body(shape=fulcrum.Box((0.5, 0.5, 0.5)), position=(0, 0.5, 0), mass=light, name="light")
    w.create_body(shape=fulcrum.Box((0.5, 0.5, 0.5)), position=(0, 1.5, 0), mass=heavy, name="heavy")
    w.step(DT, steps=steps)
    return w


def test_deep_overlaps_name_a_heavy_box_sunk_into_a_light_one():
    # 1:10 holds (resting overlap of millimetres, far below 10 % of the 1 m box);
    # 1:10^6 is far beyond the ratio the solver holds (docs/solver.md): the heavy
    # box sinks into the light one and the pair is reported, deepest first.
    # Read half a second in, while it sinks: the light box's two overlaps were
    # driven in, so they keep the whole push-out speed (docs/solver.md, "Born
    # deep, driven deep"), and by 1.5 s it is squeezed out sideways, nothing
    # left overlapped (while they shared it, it stayed locked inside to the end).
    assert stack(1.0, 10.0).deep_overlaps() == []
    sunk_world = stack(1.0, 1e6, steps=30)  # kept alive: the bodies in the report refer to it
    sunk = sunk_world.deep_overlaps()
    assert sunk, "a 1:10^6 stack must be reported"
    names = {sunk[0]["body_a"].name, sunk[0]["body_b"].name}
    assert "heavy" in names
    assert sunk[0]["depth"] > 0.1 * sunk[0]["size"] and sunk[0]["size"] == pytest.approx(1.0)
    with pytest.raises(fulcrum.Error):
        stack(1.0, 10.0).deep_overlaps(fraction=0)
