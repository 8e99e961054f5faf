// World::closestPoints / distance against analytic distances: spheres,
// boxes, a capsule, a plane, compounds, overlap depths, and refused shapes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;
using ::testing::HasSubstr;

namespace {

BodyId add(World& world, const Shape& shape, const Vec3& position, const Quat& q = {}, BodyType type = BodyType::Dynamic) {
    BodyDef d;
    d.shape = shape;
    d.position = position;
    d.orientation = q;
    d.type = type;
    return world.createBody(d);
}

constexpr Real kTol = Real(1e-4);

}  // namespace

TEST(ClosestPoints, SpheresApartAndOverlapping) {
    World world;
    const BodyId a = add(world, Shape::sphere(1), {0, 0, 0});
    const BodyId b = add(world, Shape::sphere(Real(0.5)), {3, 4, 0});  // centres 5 apart
    const ClosestPoints c = world.closestPoints(a, b);
    EXPECT_NEAR(c.distance, Real(3.5), kTol);
    EXPECT_NEAR(world.distanceBetween(a, b), Real(3.5), kTol);
    EXPECT_NEAR(length(c.normal - Vec3{Real(0.6), Real(0.8), 0}), 0, kTol);
    EXPECT_NEAR(length(c.pointA - Vec3{Real(0.6), Real(0.8), 0}), 0, kTol);
    EXPECT_NEAR(length(c.pointB - Vec3{3 - Real(0.3), 4 - Real(0.4), 0}), 0, kTol);
    // Reversed: the same distance, the normal the other way.
    const ClosestPoints r = world.closestPoints(b, a);
    EXPECT_NEAR(r.distance, Real(3.5), kTol);
    EXPECT_NEAR(dot(r.normal, c.normal), -1, kTol);
    // Overlapping by 0.25: a negative distance, the depth.
    world.setTransform(b, {Real(1.25), 0, 0}, Quat{});
    const ClosestPoints o = world.closestPoints(a, b);
    EXPECT_NEAR(o.distance, Real(-0.25), Real(1e-3));
    EXPECT_NEAR(o.normal.x, 1, Real(1e-3));
}

TEST(ClosestPoints, BoxesCapsulesAndPlanes) {
    World world;
    // Box corner to box face: a unit box rotated 45 deg about y presents an edge at x = sqrt(2) / 2.
    const BodyId a = add(world, Shape::box(Vec3::splat(Real(0.5))), {0, 0, 0}, Quat::fromAxisAngle({0, 1, 0}, Real(0.785398163)));
    const BodyId b = add(world, Shape::box(Vec3::splat(Real(0.5))), {3, 0, 0});
    EXPECT_NEAR(world.distanceBetween(a, b), Real(2.5) - std::sqrt(Real(0.5)), kTol);
    // A capsule lying along x above a plane y = -1: gap = height - radius + 1.
    const BodyId ground = add(world, Shape::plane({0, 1, 0}, -1), {}, {}, BodyType::Static);
    const BodyId cap = add(world, Shape::capsule(Real(0.2), 1), {0, 2, 5}, Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963)));
    const ClosestPoints c = world.closestPoints(ground, cap);
    EXPECT_NEAR(c.distance, 2 - Real(0.2) + 1, kTol);
    EXPECT_NEAR(c.normal.y, 1, kTol);
    EXPECT_NEAR(c.pointA.y, -1, kTol);
    EXPECT_NEAR(c.pointB.y, 2 - Real(0.2), kTol);
    EXPECT_NEAR(world.closestPoints(cap, ground).normal.y, -1, kTol);
    // A shape placed at a transform against a body.
    EXPECT_NEAR(world.closestPoints(Shape::sphere(Real(0.5)), Transform({0, 3, 0}, Quat{}), ground).distance, Real(3.5), kTol);
}

TEST(ClosestPoints, CompoundsUseTheirClosestChild) {
    World world;
    const CompoundChild parts[] = {{Shape::sphere(Real(0.5)), Transform({-2, 0, 0}, Quat{})},
                                   {Shape::box(Vec3::splat(Real(0.5))), Transform({2, 0, 0}, Quat{})}};
    const BodyId dumbbell = add(world, Shape::compound(parts), {0, 0, 0});
    const BodyId ball = add(world, Shape::sphere(Real(0.5)), {5, 0, 0});
    // The box child (face at x = 2.5) is nearest: 5 - 0.5 - 2.5 = 2.
    EXPECT_NEAR(world.distanceBetween(dumbbell, ball), 2, kTol);
    world.setTransform(ball, {-5, 0, 0}, Quat{});
    EXPECT_NEAR(world.distanceBetween(dumbbell, ball), 2, kTol);  // the sphere child: 5 - 0.5 - 2.5
}

TEST(ClosestPoints, RefusesMeshesHeightfieldsAndStaleBodies) {
    World world;
    const std::vector<Real> flat(9, 0);
    const BodyId field = add(world, Shape::heightField(3, 3, 1, 1, flat), {}, {}, BodyType::Static);
    const BodyId ball = add(world, Shape::sphere(1), {0, 3, 0});
    try {
        (void)world.closestPoints(field, ball);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_THAT(e.what(), HasSubstr("World::closestPoints"));
        EXPECT_THAT(e.what(), HasSubstr("heightfield"));
    }
    world.destroyBody(ball);
    EXPECT_THROW((void)world.distanceBetween(ball, field), Error);
    const BodyId other = add(world, Shape::sphere(1), {0, 3, 0});
    EXPECT_THROW((void)world.closestPoints(Shape::sphere(1), Transform({std::nanf(""), 0, 0}, Quat{}), other), Error);
}
