// Piece recycling against a static mesh (contact.hpp, PiecePose;
// docs/narrow-phase.md, "Recycling a piece's mesh contacts"): a box or hull
// piece that moved little since its mesh manifolds were made keeps them,
// with refreshed depths, instead of running the narrow phase. Checked
// against the same worlds with recycling off (every piece collided every
// step), and against walls of triangles the recycled manifolds leave out.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

using namespace fulcrum;

namespace {

constexpr Real kDt = Real(1) / 60;

// A hexagonal prism of radius r (vertices on the circle) along z, a face down.
Shape hexLog(Real r, Real length) {
    std::vector<Vec3> points;
    for (int k = 0; k < 6; ++k) {
        const Real a = Real(k) * Real(3.14159265358979 / 3);
        for (const Real z : {-Real(0.5) * length, Real(0.5) * length}) points.push_back({r * std::cos(a), r * std::sin(a), z});
    }
    return Shape::convexHull(points);
}

// A static mesh: a flat grid of cells x cells of `cell` metres at y = 0,
// centred on the origin, and (wallX > 0) a wall of two triangles facing -x at
// x = wallX, from y = -1 to 3 and z = -4 to 4.
BodyId addMesh(World& world, int cells, Real cell, Real friction, Real wallX = 0) {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    const Real half = Real(0.5) * Real(cells) * cell;
    for (int i = 0; i <= cells; ++i) {
        for (int j = 0; j <= cells; ++j) vertices.push_back({Real(i) * cell - half, 0, Real(j) * cell - half});
    }
    const auto at = [cells](int i, int j) { return static_cast<std::uint32_t>(i * (cells + 1) + j); };
    for (int i = 0; i < cells; ++i) {
        for (int j = 0; j < cells; ++j) {
            triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            triangles.push_back({at(i + 1, j + 1), at(i + 1, j), at(i, j)});
        }
    }
    if (wallX > 0) {
        const auto w = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back({wallX, -1, -4});
        vertices.push_back({wallX, -1, 4});
        vertices.push_back({wallX, 3, 4});
        vertices.push_back({wallX, 3, -4});
        // Wound so the face normal points to -x (towards the bodies).
        triangles.push_back({w, w + 1, w + 2});
        triangles.push_back({w, w + 2, w + 3});
    }
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::mesh(vertices, triangles);
    g.friction = friction;
    return world.createBody(g);
}

std::uint64_t recycled(const World& world) { return detail::implOf(world).contactManager.recycledPieceCount(); }

void setRecycling(World& world, bool on) { detail::implOf(world).contactManager.setPieceRecycling(on); }

// The corners of a box body of half extents h.
std::array<Vec3, 8> corners(const World& world, BodyId b, const Vec3& h) {
    std::array<Vec3, 8> out;
    const Transform xf{world.position(b), world.orientation(b)};
    for (int k = 0; k < 8; ++k) {
        out[static_cast<std::size_t>(k)] = transformPoint(xf, Vec3{k & 1 ? h.x : -h.x, k & 2 ? h.y : -h.y, k & 4 ? h.z : -h.z});
    }
    return out;
}

// A box, a hex log and a two-box compound slide to rest on a flat mesh of
// 0.5 m cells (crossing triangles as they go), then rest.
struct Sliders {
    World world{WorldDef{}};
    std::vector<BodyId> bodies;
};

void buildSliders(Sliders& s) {
    addMesh(s.world, 24, Real(0.5), Real(0.6));
    BodyDef box;
    box.shape = Shape::box({Real(0.4), Real(0.25), Real(0.5)});
    box.position = {-3, Real(0.25), -2};
    box.linearVelocity = {Real(1.5), 0, Real(0.4)};
    s.bodies.push_back(s.world.createBody(box));
    BodyDef log;
    log.shape = hexLog(Real(0.3), 2);
    log.position = {2, Real(0.3) * std::sin(Real(3.14159265358979 / 3)), 1};
    log.linearVelocity = {Real(-0.2), 0, Real(1.2)};
    s.bodies.push_back(s.world.createBody(log));
    BodyDef pair;
    std::vector<CompoundChild> children;
    children.push_back({Shape::box({Real(0.3), Real(0.2), Real(0.3)}), Transform{Vec3{-Real(0.35), 0, 0}, Quat{}}});
    children.push_back({Shape::box({Real(0.3), Real(0.2), Real(0.3)}), Transform{Vec3{Real(0.35), 0, 0}, Quat{}}});
    pair.shape = Shape::compound(children);
    pair.position = {0, Real(0.2), 3};
    pair.linearVelocity = {Real(-0.8), 0, Real(-0.9)};
    pair.angularVelocity = {0, Real(0.6), 0};
    s.bodies.push_back(s.world.createBody(pair));
}

}  // namespace

// With recycling the pieces slide and come to rest where the unrecycled run
// has them: within 1 cm and 1 degree after 4 s (they slide 0.2-1 m), and at
// the same resting height within 1 mm.
TEST(PieceRecycling, SlidingAndRestingPiecesAgreeWithTheUnrecycledPath) {
    Sliders on, off;
    buildSliders(on);
    buildSliders(off);
    setRecycling(off.world, false);
    for (int i = 0; i < 240; ++i) {
        on.world.step(kDt);
        off.world.step(kDt);
    }
    EXPECT_GT(recycled(on.world), 10u) << "the pieces' mesh contacts must be recycled in this scene";
    EXPECT_EQ(recycled(off.world), 0u);
    for (std::size_t k = 0; k < on.bodies.size(); ++k) {
        const Vec3 pOn = on.world.position(on.bodies[k]), pOff = off.world.position(off.bodies[k]);
        EXPECT_LT(length(pOn - pOff), Real(0.01)) << "body " << k;
        EXPECT_NEAR(pOn.y, pOff.y, Real(0.001)) << "body " << k;
        const Quat turn = conjugate(on.world.orientation(on.bodies[k])) * off.world.orientation(off.bodies[k]);
        const Real angle = 2 * std::asin(std::min(Real(1), length(Vec3{turn.x, turn.y, turn.z})));
        EXPECT_LT(angle, Real(3.14159265358979 / 180)) << "body " << k;
        EXPECT_LT(length(on.world.linearVelocity(on.bodies[k])), Real(0.01)) << "body " << k << " has not come to rest";
    }
}

// A box slides on a frictionless floor into a wall of two triangles at
// x = 3, at speeds from 0.2 m/s (its floor manifold recycled step after
// step) to 30 m/s (half a metre a step), and one falls on the floor at
// 25 m/s. The wall is in no manifold while the box is far from it: a
// recycled floor manifold must not let the box reach the wall unseen. Every
// step the box's corners stay out of the wall and the floor to within the
// depth the unrecycled run reaches plus 2 mm, and never deeper than 3 cm
// (the 30 m/s throw's stop at the wall leaves a step's end about 2 cm in
// with or without recycling in the double build, under 1 cm in the float
// one: the continuous pass's, not the recycling's).
TEST(PieceRecycling, AFastPieceIsNeverRecycledThroughATriangle) {
    const Vec3 half{Real(0.3), Real(0.2), Real(0.4)};
    constexpr Real kWall = 3;
    struct Throw {
        Vec3 position, velocity;
    };
    const std::vector<Throw> throws = {
        {{0, Real(0.2), 0}, {Real(0.2), 0, 0}},  {{0, Real(0.2), 0}, {Real(0.7), 0, Real(0.1)}},
        {{0, Real(0.2), 0}, {Real(2), 0, 0}},    {{-4, Real(0.2), 0}, {Real(8), 0, Real(-0.5)}},
        {{-5, Real(0.2), 0}, {30, 0, 0}},        {{0, 3, 0}, {0, -25, 0}},
    };
    std::uint64_t recycledAll = 0;
    for (std::size_t t = 0; t < throws.size(); ++t) {
        Real deepest[2] = {0, 0};
        for (int pass = 0; pass < 2; ++pass) {
            World world{WorldDef{}};
            setRecycling(world, pass == 0);
            addMesh(world, 24, Real(0.5), 0, kWall);
            BodyDef d;
            d.shape = Shape::box(half);
            d.friction = 0;
            d.position = throws[t].position;
            d.linearVelocity = throws[t].velocity;
            const BodyId box = world.createBody(d);
            const int steps = t == 0 ? 1000 : 300;
            for (int i = 0; i < steps; ++i) {
                world.step(kDt);
                for (const Vec3& c : corners(world, box, half)) {
                    deepest[pass] = std::max({deepest[pass], c.x - kWall, -c.y});
                }
            }
            if (pass == 0) recycledAll += recycled(world);
            EXPECT_LT(world.position(box).x, kWall) << "throw " << t << " went through the wall";
            EXPECT_GT(world.position(box).y, 0) << "throw " << t << " went through the floor";
        }
        EXPECT_LT(deepest[0], deepest[1] + Real(0.002)) << "throw " << t;
        EXPECT_LT(deepest[0], Real(0.03)) << "throw " << t;
    }
    EXPECT_GT(recycledAll, 500u) << "the slow throws must recycle their floor manifolds";
}
