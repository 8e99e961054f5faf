// A small box beside a long hull face: one wall segment of Box3D's washer
// drum (bench/churn_scenes.hpp: a slab between radii 16 and 18 m, 20 m long
// in z, 12 degrees wide) and one of its 0.4 m cubes. When the contact normal
// is the wall's face axis, the wall's support along it is any vertex of that
// face; the midpoint of it and the cube's corner was a contact point 4 m from
// the cube (found in the washer: the solver's impulse there spun the cube and
// its speculative contact turned into a 16 cm overlap). Geometry is the
// reference: every point of the manifold lies within the cube's reach (its
// bounding radius plus the gap), and the deepest point's depth is the
// separation of the two shapes along the normal (their supports), to 1 mm.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"

using namespace fulcrum;

namespace {

// Segment i of the washer's drum wall, in the drum's frame.
Shape drumWallSegment(int i) {
    const double pi = 3.14159265358979323846, step = pi / 18;
    const double from = i * step - 0.1 * step, to = (i + 1) * step + 0.1 * step;
    std::vector<Vec3> points;
    for (const double z : {-10.0, 10.0}) {
        for (const double angle : {from, to}) {
            for (const double r : {16.0, 18.0}) {
                points.push_back({Real(r * std::cos(angle)), Real(r * std::sin(angle)), Real(z)});
            }
        }
    }
    return Shape::convexHull(points);
}

Quat aboutZ(Real angle) { return {std::cos(angle / 2), 0, 0, std::sin(angle / 2)}; }

}  // namespace

TEST(LongFacePoint, CubeBesideADrumWallGetsItsContactAtTheCube) {
    const Shape wall = drumWallSegment(20);
    const Shape cube = Shape::box(Vec3::splat(Real(0.2)));
    // The drum turned by 32 degrees (step 77 of washer(8)), the cube 8.4 cm
    // from the wall's inner face, then the same at other tilts of the cube.
    const Transform drum{{Real(0.001283), Real(20.99765), 0}, {Real(0.96106106), 0, 0, Real(0.2763364)}};
    const Real reach = length(Vec3::splat(Real(0.2)));
    const Real margin = Real(0.3);
    int checked = 0;
    for (int k = 0; k < 18; ++k) {
        const Transform box{{Real(-8.0523), Real(7.6273), Real(-2.4043)},
                            normalize(Quat{Real(0.9105), Real(0.0011), Real(-0.0032), Real(0.4135)} * aboutZ(Real(0.05) * Real(k)))};
        ManifoldBuffer out;
        collide(wall, drum, cube, box, margin, out);
        for (const Manifold& m : out) {
            ASSERT_GT(m.pointCount, 0u);
            const detail::ConvexShape a = detail::makeConvex(wall, drum), b = detail::makeConvex(cube, box);
            const Real separation = dot(b.support(-m.normal) - a.support(m.normal), m.normal);
            Real deepest = -1e30f;
            for (std::uint32_t p = 0; p < m.pointCount; ++p) {
                const ContactPoint& c = m.points[p];
                deepest = std::max(deepest, c.depth);
                // Before: 3.9 m from the cube's centre (the wall's far corner at z = -10 halfway in).
                EXPECT_LT(length(c.position - box.p), reach + std::fabs(c.depth) + Real(0.01)) << "tilt " << k << " point " << p;
            }
            EXPECT_NEAR(deepest, -separation, Real(1e-3)) << "tilt " << k;
            ++checked;
        }
    }
    EXPECT_GT(checked, 10);  // most tilts are within the margin
}
