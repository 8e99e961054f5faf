#pragma once
// Box3D's convex pile (bench/box3d_scenes.hpp) as a World: the ground, then
// one body per hull position of `pile` (their ids appended to `ids`), with
// WorldDef::pushOutGrownOverlaps as given. Shared by the hull-pile tests
// (tests/contacts/hull_pile_overlap_test.cpp, tests/solver/push_out_gate_test.cpp,
// tests/io/scene_world_test.cpp).
#include <vector>

#include "../../bench/box3d_scenes.hpp"
#include "fulcrum/fulcrum.hpp"

namespace fulcrum::test {

inline World hullPileWorld(const bench::HullPileSpec& pile, std::vector<BodyId>& ids, bool pushOut) {
    const auto vec = [](bench::V3 v) { return Vec3{Real(v.x), Real(v.y), Real(v.z)}; };
    WorldDef def;
    def.pushOutGrownOverlaps = pushOut;
    def.substeps = pile.substeps;
    def.gravity = vec(pile.gravity);
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box(vec(pile.groundHalf));
    ground.position = vec(pile.groundPosition);
    ground.friction = Real(pile.friction);
    world.createBody(ground);
    std::vector<Vec3> points;
    for (const bench::V3& p : pile.hullPoints) points.push_back(vec(p));
    const Shape hull = Shape::convexHull(points);
    for (const bench::V3& p : pile.positions) {
        BodyDef d;
        d.shape = hull;
        d.density = Real(pile.density);
        d.friction = Real(pile.friction);
        d.position = vec(p);
        ids.push_back(world.createBody(d));
    }
    return world;
}

}  // namespace fulcrum::test
