// The largest size or coordinate a shape may have (kMaxShapeCoordinate,
// fulcrum/shape.hpp). Found by fuzz/snapshot_fuzz.cpp: a compound child at
// -3.4e38 m, a finite number, made the child's bounds infinite once its body
// turned (the rotation's intermediate terms overflow a float), deep inside a
// step. Every factory refuses such a shape with a message naming the field;
// the limit itself is checked to be safe: the largest legal box and compound
// child, turned by a rotation that mixes every axis, have finite bounds.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fulcrum/shape.hpp"
#include "test_util.hpp"

namespace fulcrum {
namespace {

using test::expectErrorContaining;

constexpr Real kBeyond = kMaxShapeCoordinate * 4;

bool finiteBox(const AABB& b) { return isFinite(b.min) && isFinite(b.max) && !b.isEmpty(); }

TEST(ShapeLimits, SizesBeyondTheLimitAreRefusedByEveryFactory) {
    expectErrorContaining([] { (void)Shape::sphere(kBeyond); }, "sphere: radius must be at most");
    expectErrorContaining([] { (void)Shape::box({1, kBeyond, 1}); }, "box: half_extents.y must be at most");
    expectErrorContaining([] { (void)Shape::capsule(1, kBeyond); }, "capsule: half_height must be at most");
    expectErrorContaining([] { (void)Shape::cylinder(kBeyond, 1); }, "cylinder: radius must be at most");
    expectErrorContaining([] { (void)Shape::plane({0, 2, 0}, 2 * kBeyond); }, "plane: offset must be at most");
    const std::vector<Vec3> hull{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, kBeyond}};
    expectErrorContaining([&] { (void)Shape::convexHull(hull); }, "convex_hull: points[3] has a coordinate beyond the limit");
    const std::vector<Vec3> v{{0, 0, 0}, {kBeyond, 0, 0}, {0, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}};
    expectErrorContaining([&] { (void)Shape::mesh(v, t); }, "mesh: vertices[1] has a coordinate beyond the limit");
    const std::vector<Real> heights{0, 0, 0, kBeyond};
    expectErrorContaining([&] { (void)Shape::heightField(2, 2, 1, 1, heights); }, "heightfield: heights[3] is beyond the limit");
    const std::vector<CompoundChild> far{{Shape::sphere(1), Transform{{Real(-3.4e38), 0, 0}, Quat{}}}};
    expectErrorContaining([&] { (void)Shape::compound(far); }, "compound: children[0] position is farther than");
}

TEST(ShapeLimits, TheLargestLegalShapesHaveFiniteBoundsWhenTurned) {
    const Real m = kMaxShapeCoordinate;
    const Quat turn = normalize(Quat{Real(0.3), Real(0.5), Real(-0.6), Real(0.55)});
    const Transform xf{{m, -m, m}, turn};
    EXPECT_TRUE(finiteBox(Shape::box({m, m, m}).bounds(xf)));
    EXPECT_TRUE(finiteBox(Shape::capsule(m, m).bounds(xf)));
    EXPECT_TRUE(finiteBox(Shape::cylinder(m, m).bounds(xf)));
    const std::vector<CompoundChild> children{{Shape::box({m, m, m}), Transform{{-m, m, -m}, turn}}};
    EXPECT_TRUE(finiteBox(Shape::compound(children).bounds(xf)));
    const std::vector<Vec3> hull{{-m, -m, -m}, {m, -m, -m}, {-m, m, -m}, {-m, -m, m}, {m, m, m}};
    EXPECT_TRUE(finiteBox(Shape::convexHull(hull).bounds(xf)));
}

}  // namespace
}  // namespace fulcrum
