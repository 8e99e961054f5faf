// Shape::scaled against analytic values. Mass properties: a scale S maps a
// solid's mass m to |det S| m, its centre of mass c to S c, and its central
// covariance C = tr(I)/2 E - I to |det S| S C S; the inertia is then
// tr(C) E - C. These are checked against the unscaled shape's own (analytic,
// tests/shapes/mass_test.cpp) properties and against closed forms, 1e-5 relative
// (float rounding). Also: kinds kept, mirrors, errors, a ray cast and closest
// points on a scaled mesh, and a scaled box resting on a plane.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "collision/shape_queries.hpp"
#include "fulcrum/fulcrum.hpp"
#include "test_util.hpp"

namespace fulcrum {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRel = 1e-5;

double maxAbs(const Mat3& m) {
    double r = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r = std::max(r, std::fabs(double(m(i, j))));
    return r;
}

void expectMatrixNear(const Mat3& a, const Mat3& b, double rel) {
    const double tol = rel * std::max(maxAbs(a), maxAbs(b));
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(a(i, j), b(i, j), tol) << "element (" << i << ", " << j << ")";
}

// The mass properties of the original solid mapped through diag(scale).
MassProperties expectedScaled(const MassProperties& mp, const Vec3& scale) {
    const double det = std::fabs(double(scale.x) * scale.y * scale.z);
    const Mat3 s = Mat3::diagonal(scale);
    const Mat3 c = Mat3::diagonal(trace(mp.inertia) / 2) - mp.inertia;
    const Mat3 cs = s * c * s * Real(det);
    MassProperties out;
    out.mass = mp.mass * Real(det);
    out.centerOfMass = mul(scale, mp.centerOfMass);
    out.inertia = Mat3::diagonal(trace(cs)) - cs;
    return out;
}

void expectMassNear(const MassProperties& got, const MassProperties& want) {
    EXPECT_NEAR(got.mass, want.mass, kRel * want.mass);
    const double size = std::sqrt(maxAbs(want.inertia) / want.mass);  // a length of the body's size
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(got.centerOfMass[i], want.centerOfMass[i], kRel * size);
    expectMatrixNear(got.inertia, want.inertia, kRel);
}

std::string errorOf(const Shape& s, const Vec3& scale) {
    try {
        (void)Shape::scaled(s, scale);
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an error for scale " << scale.x << ", " << scale.y << ", " << scale.z;
    return {};
}

std::vector<Vec3> boxCorners(const Vec3& h) {
    std::vector<Vec3> p;
    for (int k = 0; k < 8; ++k) p.push_back({(k & 1) ? h.x : -h.x, (k & 2) ? h.y : -h.y, (k & 4) ? h.z : -h.z});
    return p;
}

TEST(ScaledShape, BoxStaysABoxWithExactMass) {
    const Shape box = Shape::box({Real(0.5), Real(0.3), Real(0.7)});
    for (const Vec3 scale : {Vec3{2, Real(0.5), 3}, Vec3{-2, Real(0.5), 3}, Vec3{Real(1.5), Real(-1.5), Real(-1.5)}}) {
        const Shape s = Shape::scaled(box, scale);
        ASSERT_EQ(s.type(), ShapeType::Box);
        const Vec3 h = mul(box.halfExtents(), abs(scale));
        EXPECT_EQ(s.halfExtents(), h);
        // Closed form: m = rho 8 hx hy hz, I_x = m (hy^2 + hz^2) / 3.
        const double rho = 700, m = rho * 8 * double(h.x) * h.y * h.z;
        const MassProperties mp = s.massProperties(Real(rho));
        EXPECT_NEAR(mp.mass, m, kRel * m);
        expectMatrixNear(mp.inertia,
                         Mat3::diagonal(Vec3{Real(m * (h.y * h.y + h.z * h.z) / 3), Real(m * (h.x * h.x + h.z * h.z) / 3),
                                             Real(m * (h.x * h.x + h.y * h.y) / 3)}),
                         kRel);
        expectMassNear(mp, expectedScaled(box.massProperties(Real(rho)), scale));
    }
}

TEST(ScaledShape, SphereCapsuleCylinderKeepTheirKind) {
    const Shape sphere = Shape::scaled(Shape::sphere(Real(0.5)), Real(-3));
    ASSERT_EQ(sphere.type(), ShapeType::Sphere);
    EXPECT_NEAR(sphere.radius(), 1.5, 1e-6);

    const Shape capsule = Shape::scaled(Shape::capsule(Real(0.2), Real(0.4)), Vec3{2, -2, 2});
    ASSERT_EQ(capsule.type(), ShapeType::Capsule);
    EXPECT_NEAR(capsule.radius(), 0.4, 1e-6);
    EXPECT_NEAR(capsule.halfHeight(), 0.8, 1e-6);

    // Cylinder: x and z scale the radius, y the half height.
    const double r = 0.3, h = 0.5, sr = 2, sy = 3, rho = 900;
    const Shape cylinder = Shape::scaled(Shape::cylinder(Real(r), Real(h)), Vec3{Real(sr), Real(sy), Real(-sr)});
    ASSERT_EQ(cylinder.type(), ShapeType::Cylinder);
    EXPECT_NEAR(cylinder.radius(), r * sr, 1e-6);
    EXPECT_NEAR(cylinder.halfHeight(), h * sy, 1e-6);
    // m = rho pi R^2 H, I_y = m R^2 / 2, I_x = I_z = m (3 R^2 + H^2) / 12.
    const double R = r * sr, H = 2 * h * sy, m = rho * kPi * R * R * H;
    const MassProperties mp = cylinder.massProperties(Real(rho));
    EXPECT_NEAR(mp.mass, m, kRel * m);
    const double ix = m * (3 * R * R + H * H) / 12;
    expectMatrixNear(mp.inertia, Mat3::diagonal(Vec3{Real(ix), Real(m * R * R / 2), Real(ix)}), kRel);
}

TEST(ScaledShape, HullMassPropertiesFollowTheScale) {
    // An off-centre irregular hull: the centroid moves with the scale.
    test::Rng rng(7);
    std::vector<Vec3> points;
    for (int i = 0; i < 40; ++i) points.push_back(rng.inBall(1) + Vec3{Real(0.4), Real(-0.2), Real(0.9)});
    const Shape hull = Shape::convexHull(points);
    for (const Vec3 scale : {Vec3{2, Real(0.5), Real(1.25)}, Vec3{-1, 3, Real(0.7)}, Vec3::splat(Real(-0.5))}) {
        const Shape s = Shape::scaled(hull, scale);
        ASSERT_EQ(s.type(), ShapeType::ConvexHull);
        EXPECT_NEAR(s.volume(), hull.volume() * std::fabs(scale.x * scale.y * scale.z), kRel * s.volume());
        expectMassNear(s.massProperties(2), expectedScaled(hull.massProperties(2), scale));
        // Every face still points outward: the centroid is behind all of them.
        for (const HullFace& f : s.hull().faces) EXPECT_LT(dot(f.normal, s.hull().centroid), f.offset);
    }
    // The hull of a cube's corners scaled is the box.
    const Shape cube = Shape::convexHull(boxCorners(Vec3::splat(Real(0.5))));
    const Vec3 scale{3, Real(0.4), -2};
    expectMassNear(Shape::scaled(cube, scale).massProperties(1),
                   Shape::box(mul(Vec3::splat(Real(0.5)), abs(scale))).massProperties(1));
}

TEST(ScaledShape, CompoundScalesPositionsAndChildren) {
    // Two boxes side by side along x make one box: scaled, they make the scaled box.
    const Vec3 h{Real(0.25), Real(0.5), Real(0.5)};
    const CompoundChild halves[] = {{Shape::box(h), Transform({Real(-0.25), 0, 0}, Quat())},
                                    {Shape::box(h), Transform({Real(0.25), 0, 0}, Quat())}};
    const Shape pair = Shape::compound(halves);
    const Vec3 scale{2, Real(0.6), -3};
    const Shape scaled = Shape::scaled(pair, scale);
    ASSERT_EQ(scaled.type(), ShapeType::Compound);
    for (const CompoundChild& c : scaled.children()) EXPECT_EQ(c.shape.type(), ShapeType::Box);
    expectMassNear(scaled.massProperties(3), Shape::box(mul(Vec3{Real(0.5), Real(0.5), Real(0.5)}, abs(scale))).massProperties(3));
}

TEST(ScaledShape, RotatedChildrenAlignedOrShearedAreExact) {
    // Children rotated by 90 degrees stay their kind (the scale is permuted onto
    // their axes); a child at 45 degrees to a non-uniform scale becomes a hull.
    const Quat quarterZ = Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 2));
    const Quat eighthZ = Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 4));
    const Quat tilted = normalize(Quat::fromAxisAngle({1, 2, 3}, Real(0.7)));
    const CompoundChild children[] = {
        {Shape::box({Real(0.5), Real(0.2), Real(0.3)}), Transform({1, 0, 0}, quarterZ)},
        {Shape::cylinder(Real(0.2), Real(0.6)), Transform({0, 1, Real(0.5)}, quarterZ)},  // axis along x
        {Shape::box({Real(0.3), Real(0.1), Real(0.2)}), Transform({-1, Real(0.5), 0}, eighthZ)},
        {Shape::convexHull(boxCorners({Real(0.2), Real(0.3), Real(0.4)})), Transform({0, -1, Real(0.3)}, tilted)},
        {Shape::sphere(Real(0.3)), Transform({0, 0, -1}, tilted)},
    };
    const Shape compound = Shape::compound(children);
    const Vec3 scale{3, 2, 2};  // the tilted sphere would become an ellipsoid
    EXPECT_NE(errorOf(compound, scale).find("sphere"), std::string::npos);

    const Shape noSphere = Shape::compound(std::span(children, 4));
    for (const Vec3 s : {scale, Vec3{-3, 2, 2}}) {
        const Shape scaled = Shape::scaled(noSphere, s);
        const auto kids = scaled.children();
        ASSERT_EQ(kids.size(), 4u);
        EXPECT_EQ(kids[0].shape.type(), ShapeType::Box);
        EXPECT_EQ(kids[1].shape.type(), ShapeType::Cylinder);
        EXPECT_EQ(kids[2].shape.type(), ShapeType::ConvexHull);
        EXPECT_EQ(kids[3].shape.type(), ShapeType::ConvexHull);
        // The box rotated a quarter turn about z has its local x along world y.
        EXPECT_NEAR(kids[0].shape.halfExtents().x, 0.5 * 2, 1e-5);
        EXPECT_NEAR(kids[0].shape.halfExtents().y, 0.2 * 3, 1e-5);
        EXPECT_NEAR(kids[0].shape.halfExtents().z, 0.3 * 2, 1e-5);
        // The cylinder's axis is along world x: the half height takes sx, the radius sy == sz.
        EXPECT_NEAR(kids[1].shape.halfHeight(), 0.6 * 3, 1e-5);
        EXPECT_NEAR(kids[1].shape.radius(), 0.2 * 2, 1e-5);
        expectMassNear(scaled.massProperties(5), expectedScaled(noSphere.massProperties(5), s));
    }
}

TEST(ScaledShape, MirroredMeshKeepsItsFrontFacesOutward) {
    // A closed cube of 12 counter-clockwise triangles.
    const std::vector<Vec3> v = boxCorners(Vec3::splat(Real(0.5)));
    const std::vector<std::array<std::uint32_t, 3>> t = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                                                         {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
    const Shape cube = Shape::mesh(v, t);
    ASSERT_LT(closestPoint(cube, Transform::identity(), Vec3::zero()).distance, 0);  // the winding is outward
    for (const Vec3 scale : {Vec3{2, Real(0.5), 3}, Vec3{-2, Real(0.5), 3}}) {
        const Shape s = Shape::scaled(cube, scale);
        ASSERT_EQ(s.type(), ShapeType::Mesh);
        // A ray along -x from outside hits the face x = +|sx| / 2.
        const auto hit = rayCastShape(s, Transform::identity(), {10, Real(0.1), Real(0.2)}, {-20, 0, 0}, 1);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->point.x, 1.0, 1e-5);
        EXPECT_NEAR(hit->normal.x, 1.0, 1e-5);
        // Inside is inside (negative distance), and the nearest face is the thin y one.
        const PointQuery q = closestPoint(s, Transform::identity(), {Real(0.1), Real(0.05), 0});
        EXPECT_NEAR(q.distance, -0.2, 1e-5);
        EXPECT_NEAR(q.normal.y, 1.0, 1e-5);
    }
}

TEST(ScaledShape, PlaneAndHeightField) {
    const Shape plane = Shape::scaled(Shape::plane({0, 1, 0}, 1), Vec3{5, 2, 5});
    EXPECT_NEAR(plane.planeOffset(), 2, 1e-6);
    EXPECT_NEAR(plane.planeNormal().y, 1, 1e-6);

    const std::vector<Real> heights = {0, 1, 2, 3};
    const Shape field = Shape::heightField(2, 2, Real(0.5), 1, heights);
    const Shape s = Shape::scaled(field, Vec3{2, 3, 4});
    EXPECT_EQ(s.heightField().spacingX, 1);
    EXPECT_EQ(s.heightField().spacingZ, 4);
    EXPECT_EQ(s.heightField().heights[3], 9);
    EXPECT_NE(errorOf(field, {-1, 1, 1}).find("heightfield cannot be mirrored"), std::string::npos);
}

TEST(ScaledShape, BadScalesNameTheField) {
    const Shape box = Shape::box(Vec3::splat(1));
    EXPECT_NE(errorOf(box, {1, 0, 1}).find("scale.y must be a finite nonzero number"), std::string::npos);
    EXPECT_NE(errorOf(box, {Real(std::nan("")), 1, 1}).find("scale.x"), std::string::npos);
    EXPECT_NE(errorOf(box, {1, 1, Real(INFINITY)}).find("scale.z"), std::string::npos);
    const std::string sphere = errorOf(Shape::sphere(1), {2, 1, 1});
    EXPECT_NE(sphere.find("scale (2, 1, 1) of a sphere"), std::string::npos) << sphere;
    EXPECT_NE(sphere.find("uniform"), std::string::npos) << sphere;
    EXPECT_NE(errorOf(Shape::capsule(1, 1), {1, 2, 1}).find("capsule"), std::string::npos);
    const std::string cylinder = errorOf(Shape::cylinder(1, 1), {1, 2, 3});
    EXPECT_NE(cylinder.find("|x| == |z|"), std::string::npos) << cylinder;
    // A sphere in a compound: the child is named.
    const CompoundChild kids[] = {{Shape::box(Vec3::splat(1)), Transform()}, {Shape::sphere(1), Transform({2, 0, 0}, Quat())}};
    const std::string child = errorOf(Shape::compound(kids), {1, 1, 2});
    EXPECT_NE(child.find("children[1]"), std::string::npos) << child;
}

// Rounded shapes (core + ball): a uniform scale u maps the solid to u times
// it, so the mass goes as u^3 and the inertia as u^5 (the same formula as any
// shape), and the radius as u; any other scale would make the ball an
// ellipsoid, which is an error naming the rounding.
TEST(ScaledShape, RoundedShapesScaleUniformlyWithTheirRadius) {
    const Shape box = Shape::roundedBox({Real(0.5), Real(0.3), Real(0.7)}, Real(0.1));
    const Shape cylinder = Shape::roundedCylinder(Real(0.4), Real(0.6), Real(0.15));
    const std::vector<Vec3> core = boxCorners({Real(0.3), Real(0.2), Real(0.4)});
    const Shape hull = Shape::roundedConvexHull(core, Real(0.05));
    for (const Shape& s : {box, cylinder, hull}) {
        for (const Real u : {Real(2), Real(-1.5)}) {
            const Shape scaled = Shape::scaled(s, u);
            EXPECT_EQ(scaled.type(), s.type());
            EXPECT_NEAR(scaled.convexRadius(), s.convexRadius() * std::fabs(u), 1e-6);
            const Vec3 v = Vec3::splat(u);
            // The rounded hull's mass is its polyhedral stand-in's (0.5 %,
            // docs/shapes.md), rebuilt for the scaled core: compare loosely.
            const MassProperties got = scaled.massProperties(1), want = expectedScaled(s.massProperties(1), v);
            const double rel = s.type() == ShapeType::ConvexHull ? 5e-3 : kRel;
            EXPECT_NEAR(got.mass, want.mass, rel * want.mass) << toString(s.type());
            expectMatrixNear(got.inertia, want.inertia, rel);
        }
        const std::string e = errorOf(s, {1, 2, 1});
        EXPECT_NE(e.find("rounded"), std::string::npos) << e;
        EXPECT_NE(e.find("uniform"), std::string::npos) << e;
    }
    // A rotated rounded child of a compound: a uniform scale keeps it, a
    // non-uniform one is refused (its ball would shear).
    const CompoundChild kids[] = {{box, Transform({1, 0, 0}, Quat::fromAxisAngle({0, 1, 0}, Real(0.3)))}};
    const Shape compound = Shape::compound(kids);
    EXPECT_NEAR(Shape::scaled(compound, 3).massProperties(1).mass, 27 * compound.massProperties(1).mass,
                kRel * 27 * compound.massProperties(1).mass);
    EXPECT_NE(errorOf(compound, {1, 1, 2}).find("rounded"), std::string::npos);
}

TEST(ScaledShape, ScaledBoxRestsOnAPlaneAtItsScaledHalfHeight) {
    WorldDef wd;
    World world(wd);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    BodyDef box;
    box.shape = Shape::scaled(Shape::box(Vec3::splat(Real(0.5))), Vec3{Real(1.6), Real(0.4), Real(-2)});  // half height 0.2
    box.position = {0, Real(0.5), 0};
    const BodyId id = world.createBody(box);
    BodyDef hull = box;  // a scaled hull of the same box, beside it
    hull.shape = Shape::scaled(Shape::convexHull(boxCorners(Vec3::splat(Real(0.5)))), Vec3{Real(1.6), Real(0.4), Real(-2)});
    hull.position = {3, Real(0.5), 0};
    const BodyId hid = world.createBody(hull);
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    // Resting contact settles within the solver's few-millimetre penetration allowance.
    EXPECT_NEAR(world.position(id).y, 0.2, 0.005);
    EXPECT_NEAR(world.position(hid).y, 0.2, 0.005);
    EXPECT_LT(length(world.linearVelocity(id)), 1e-3);
    EXPECT_LT(length(world.linearVelocity(hid)), 1e-3);
}

}  // namespace
}  // namespace fulcrum
